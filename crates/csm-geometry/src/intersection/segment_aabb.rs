//! Segment–box overlap by the slab method (Kratos `Line2D2::HasIntersection(low, high)`, the
//! octree's test for 2D lines, reference §8 step 4).

use crate::Aabb;
use crate::math::Point;

/// True if the closed segment `p`–`q` and the closed box `aabb` share a point (touching
/// counts), in all three components (2D data has z = 0 on both).
///
/// Slab method: the segment `p + t (q − p)`, `t ∈ [0, 1]`, is clipped against the three slabs
/// `min[k] ≤ x[k] ≤ max[k]`; a component with `q[k] = p[k]` only checks that `p[k]` lies in its
/// slab. Exact up to the rounding of the parameters `t` (within rounding of touching). An empty
/// box or a non-finite coordinate gives `false`.
pub fn segment_aabb_intersect(p: &Point, q: &Point, aabb: &Aabb) -> bool {
    let finite = |x: &Point| x.iter().all(|c| c.is_finite());
    if aabb.is_empty() || !finite(p) || !finite(q) || !finite(&aabb.min) || !finite(&aabb.max) {
        return false;
    }
    let d = q - p;
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for k in 0..3 {
        let (lo, hi) = (aabb.min[k], aabb.max[k]);
        if d[k] == 0.0 {
            if p[k] < lo || p[k] > hi {
                return false;
            }
            continue;
        }
        let a = (lo - p[k]) / d[k];
        let b = (hi - p[k]) / d[k];
        let (enter, exit) = if a <= b { (a, b) } else { (b, a) };
        t0 = t0.max(enter);
        t1 = t1.min(exit);
        if t0 > t1 {
            return false;
        }
    }
    true
}

#[cfg(test)]
mod tests;
