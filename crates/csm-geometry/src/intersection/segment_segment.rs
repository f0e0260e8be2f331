//! Segment–segment intersection in the xy plane by orientation predicates.

use crate::math::{Point, Real};

fn orient(a: &Point, b: &Point, c: &Point) -> Real {
    (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x)
}

/// `c` lies in the axis-aligned box of `a`–`b` (used for collinear points).
fn on_segment(a: &Point, b: &Point, c: &Point) -> bool {
    c.x >= a.x.min(b.x) && c.x <= a.x.max(b.x) && c.y >= a.y.min(b.y) && c.y <= a.y.max(b.y)
}

/// True if the closed segments `p1–p2` and `q1–q2` (xy components; z ignored) share a point:
/// proper crossings, an endpoint on the other segment, and collinear overlaps all count.
/// Exact in exact arithmetic (floating-point orientation predicates, no tolerance).
pub fn segment_segment_intersect(p1: &Point, p2: &Point, q1: &Point, q2: &Point) -> bool {
    let d1 = orient(q1, q2, p1);
    let d2 = orient(q1, q2, p2);
    let d3 = orient(p1, p2, q1);
    let d4 = orient(p1, p2, q2);
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    (d1 == 0.0 && on_segment(q1, q2, p1))
        || (d2 == 0.0 && on_segment(q1, q2, p2))
        || (d3 == 0.0 && on_segment(p1, p2, q1))
        || (d4 == 0.0 && on_segment(p1, p2, q2))
}
