//! Triangle–triangle intersection by separating axes.

use crate::math::{Point, Real, Vector};

fn interval(tri: &[Point; 3], n: &Vector) -> (Real, Real) {
    let a = tri[0].coords.dot(n);
    let b = tri[1].coords.dot(n);
    let c = tri[2].coords.dot(n);
    (a.min(b).min(c), a.max(b).max(c))
}

/// True if the closed triangles `t1` and `t2` share a point (touching counts).
///
/// Separating-axis test with the candidate axes: both normals, the 9 edge cross products
/// `e1_i × e2_j`, and the 6 in-plane edge normals `n1 × e1_i`, `n2 × e2_j` (these make the
/// coplanar case exact). An axis separates iff the projected intervals are disjoint (strict);
/// zero axes are skipped. Exact in exact arithmetic; degenerate triangles (segments, points)
/// are handled as the corresponding flat sets.
pub fn triangle_triangle_intersect(t1: &[Point; 3], t2: &[Point; 3]) -> bool {
    let e1 = [t1[1] - t1[0], t1[2] - t1[1], t1[0] - t1[2]];
    let e2 = [t2[1] - t2[0], t2[2] - t2[1], t2[0] - t2[2]];
    let n1 = e1[0].cross(&e1[1]);
    let n2 = e2[0].cross(&e2[1]);
    let mut axes: Vec<Vector> = Vec::with_capacity(17);
    axes.push(n1);
    axes.push(n2);
    for a in &e1 {
        for b in &e2 {
            axes.push(a.cross(b));
        }
    }
    for a in &e1 {
        axes.push(n1.cross(a));
    }
    for b in &e2 {
        axes.push(n2.cross(b));
    }
    // Degenerate (flat) triangles: add edge-perpendicular axes within the edge planes.
    for a in e1.iter().chain(&e2) {
        for b in e1.iter().chain(&e2) {
            axes.push(a.cross(&a.cross(b)));
        }
    }
    for n in &axes {
        if *n == Vector::zeros() {
            continue;
        }
        let (min1, max1) = interval(t1, n);
        let (min2, max2) = interval(t2, n);
        if max1 < min2 || max2 < min1 {
            return false;
        }
    }
    true
}
