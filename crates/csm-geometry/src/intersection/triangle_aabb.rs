//! Triangle–box overlap by separating axes (Akenine-Möller, "Fast 3D triangle-box overlap
//! testing", 2001), as Kratos' `Triangle3D3::HasIntersection(low, high)` / `TriBoxOverlap`
//! runs it for the octree (reference §8 step 4).

use crate::Aabb;
use crate::math::{Point, Real, Vector, cross_kratos, dot_kratos};

/// True if the closed triangle `tri` and the closed box `aabb` share a point (touching
/// counts).
///
/// The box is moved to its centre `c` with half sizes `h = |max − min| / 2`, then the 13 axes
/// of Akenine-Möller's test are tried in Kratos' order: the 9 cross products `e_i × a_k` of the
/// triangle edges (`v1 − v0`, `v2 − v1`, `v0 − v2`) with the box axes, the 3 box axes (the
/// triangle's bounding box against the box), and the triangle's plane (`PlaneBoxOverlap`). An
/// axis separates iff the projected intervals are disjoint (strict), so touching overlaps.
///
/// Each edge axis projects all three vertices (Akenine-Möller projects the two that differ,
/// the third coinciding in exact arithmetic), so the verdict is Kratos' in exact arithmetic and
/// can only differ within rounding of touching. Degenerate triangles (a segment or a point)
/// have a zero plane normal, which never separates: the edge and box axes then make the test
/// the exact segment/point–box test. An empty box (`min > max`) or a non-finite coordinate
/// gives `false`.
pub fn triangle_aabb_intersect(tri: &[Point; 3], aabb: &Aabb) -> bool {
    let finite = |x: &Point| x.iter().all(|c| c.is_finite());
    if aabb.is_empty() || !tri.iter().all(finite) || !finite(&aabb.min) || !finite(&aabb.max) {
        return false;
    }
    let center = aabb.center();
    let half: Vector = (aabb.max - aabb.min).map(Real::abs) * 0.5;
    let v = [tri[0] - center, tri[1] - center, tri[2] - center];
    let edges = [v[1] - v[0], v[2] - v[1], v[0] - v[2]];
    let axes = [Vector::x(), Vector::y(), Vector::z()];
    // 1. The nine edge × box-axis axes (Kratos: AxisTestX/Y/Z per edge).
    for e in &edges {
        for a in &axes {
            let n = cross_kratos(a, e);
            if separates(&n, &v, &half) {
                return false;
            }
        }
    }
    // 2. The box axes: the triangle's bounding box against the box.
    for k in 0..3 {
        let lo = v[0][k].min(v[1][k]).min(v[2][k]);
        let hi = v[0][k].max(v[1][k]).max(v[2][k]);
        if lo > half[k] || hi < -half[k] {
            return false;
        }
    }
    // 3. The triangle's plane (Kratos `PlaneBoxOverlap`).
    let normal = cross_kratos(&edges[0], &edges[1]);
    if normal.norm() <= DEGENERATE_NORMAL * edges[0].norm() * edges[1].norm() {
        // A (nearly) degenerate triangle: its computed normal is rounding noise, and the edge
        // and box axes already decide the segment (or point) it is.
        return true;
    }
    let distance = -dot_kratos(&normal, &v[0]);
    plane_box_overlap(&normal, distance, &half)
}

/// Relative size of the plane normal below which the triangle is treated as degenerate.
const DEGENERATE_NORMAL: Real = 1e-12;

/// True if axis `n` separates the triangle (vertices `v`, box-centred) from the box of half
/// sizes `half`. A zero axis never separates.
fn separates(n: &Vector, v: &[Vector; 3], half: &Vector) -> bool {
    let p = [
        dot_kratos(n, &v[0]),
        dot_kratos(n, &v[1]),
        dot_kratos(n, &v[2]),
    ];
    let lo = p[0].min(p[1]).min(p[2]);
    let hi = p[0].max(p[1]).max(p[2]);
    let radius = half.x * n.x.abs() + half.y * n.y.abs() + half.z * n.z.abs();
    lo > radius || hi < -radius
}

/// Akenine-Möller's `planeBoxOverlap`: the box corner farthest along `-normal` must not lie
/// above the plane `normal·x + distance = 0`, and the one farthest along `normal` must not lie
/// below it.
fn plane_box_overlap(normal: &Vector, distance: Real, half: &Vector) -> bool {
    let mut vmin = Vector::zeros();
    let mut vmax = Vector::zeros();
    for q in 0..3 {
        if normal[q] > 0.0 {
            vmin[q] = -half[q];
            vmax[q] = half[q];
        } else {
            vmin[q] = half[q];
            vmax[q] = -half[q];
        }
    }
    if dot_kratos(normal, &vmin) + distance > 0.0 {
        return false;
    }
    dot_kratos(normal, &vmax) + distance >= 0.0
}

#[cfg(test)]
mod tests;
