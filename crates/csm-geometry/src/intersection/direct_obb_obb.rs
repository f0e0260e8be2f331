//! Direct OBB–OBB test (Kratos `DirectHasIntersection`, reference §7.4): vertex inclusion both
//! ways, then boundary intersection (see the module doc of `intersection` for the primitive
//! tests used in the last step).

use super::segment_segment::segment_segment_intersect;
use super::triangle_triangle::triangle_triangle_intersect;
use crate::GeometryKind;
use crate::math::Point;
use crate::{Obb, Obb2};

/// Any vertex of `other` inside `obb` (Kratos `IsInside(other)`).
fn any_vertex_inside(obb: &Obb, other: &Obb) -> bool {
    let Some(inv) = obb.inverse_axes() else {
        return false;
    };
    other
        .vertices()
        .iter()
        .any(|p| obb.contains_point_with(&inv, p))
}

/// The two triangles of each of the 6 faces of the box, faces in Hexahedra3D8 order.
fn face_triangles(obb: &Obb) -> Vec<[Point; 3]> {
    let v = obb.vertices();
    let mut tris = Vec::with_capacity(12);
    for (_, f) in GeometryKind::Hexahedra3D8.faces() {
        tris.push([v[f[0]], v[f[1]], v[f[2]]]);
        tris.push([v[f[0]], v[f[2]], v[f[3]]]);
    }
    tris
}

/// Direct test between two 3D OBBs: (1) a vertex of `obb2` inside `obb1`, (2) a vertex of
/// `obb1` inside `obb2` (Kratos' point test with `ε`), (3) any face of one box intersecting any
/// face of the other (each face as two triangles, exact triangle–triangle test).
/// `true` = intersecting.
pub fn direct_obb_obb(obb1: &Obb, obb2: &Obb) -> bool {
    if any_vertex_inside(obb1, obb2) || any_vertex_inside(obb2, obb1) {
        return true;
    }
    let t1 = face_triangles(obb1);
    let t2 = face_triangles(obb2);
    t1.iter()
        .any(|a| t2.iter().any(|b| triangle_triangle_intersect(a, b)))
}

/// Direct test between two 2D OBBs: vertex inclusion both ways (Kratos' rotated point test),
/// then the 4 edges of each box pairwise (exact segment–segment test). `true` = intersecting.
pub fn direct_obb2_obb2(obb1: &Obb2, obb2: &Obb2) -> bool {
    let v1 = obb1.vertices();
    let v2 = obb2.vertices();
    if v2.iter().any(|p| obb1.contains_point(p)) || v1.iter().any(|p| obb2.contains_point(p)) {
        return true;
    }
    (0..4).any(|i| {
        (0..4)
            .any(|j| segment_segment_intersect(&v1[i], &v1[(i + 1) % 4], &v2[j], &v2[(j + 1) % 4]))
    })
}
