//! The linear pieces (segments, triangles) the octree tests a condition with: Kratos'
//! `IsIntersected` (object vs leaf box, reference §8 step 4) and the exact face–face test
//! `Geometry::HasIntersection` used when `bounding_box_factor ≤ 0`.

use csm_geometry::math::Point;
use csm_geometry::{
    GeometryKind, segment_aabb_intersect, segment_segment_intersect, triangle_aabb_intersect,
    triangle_triangle_intersect,
};

/// A straight segment or a flat triangle of a condition's geometry.
#[derive(Debug, Clone, Copy)]
pub(super) enum Piece {
    Segment(Point, Point),
    Triangle([Point; 3]),
}

/// The pieces of a condition of kind `kind` with nodes `points`; `None` when the octree cannot
/// test it.
///
/// Both modes: Line2D2 → the segment; Triangle3D3 → the triangle; Quadrilateral3D4 → the
/// triangles (0,1,2), (2,3,0) (Kratos' split). Kratos mode: any other kind → `None` — Kratos'
/// base `Geometry::HasIntersection(low, high)` warns and answers "no intersection", so such a
/// condition is never inserted nor finds a leaf (Q16). Robust mode: the quadratic faces are
/// tested through the linear sub-segments / sub-triangles through all their nodes (Line2D3:
/// (0,2), (2,1); Triangle3D6: the 3 corner triangles and the middle one; Quadrilateral3D8: the 4
/// corner triangles and the middle quadrilateral of the mid nodes; Quadrilateral3D9: the 4
/// sub-quadrilaterals around the centre node), so a curved face is found wherever its piecewise
/// linear interpolant is.
pub(super) fn linear_pieces(
    kind: GeometryKind,
    points: &[Point],
    robust: bool,
) -> Option<Vec<Piece>> {
    use GeometryKind as K;
    if points.len() != kind.n_nodes() {
        return None;
    }
    let tri = |a: usize, b: usize, c: usize| Piece::Triangle([points[a], points[b], points[c]]);
    let quad = |a: usize, b: usize, c: usize, d: usize| [tri(a, b, c), tri(c, d, a)];
    let seg = |a: usize, b: usize| Piece::Segment(points[a], points[b]);
    let pieces = match kind {
        K::Line2D2 => vec![seg(0, 1)],
        K::Triangle3D3 => vec![tri(0, 1, 2)],
        K::Quadrilateral3D4 => quad(0, 1, 2, 3).to_vec(),
        _ if !robust => return None,
        K::Line2D3 => vec![seg(0, 2), seg(2, 1)],
        K::Triangle3D6 => vec![tri(0, 3, 5), tri(3, 1, 4), tri(5, 4, 2), tri(3, 4, 5)],
        K::Quadrilateral3D8 => {
            let mut v = vec![tri(0, 4, 7), tri(4, 1, 5), tri(5, 2, 6), tri(6, 3, 7)];
            v.extend(quad(4, 5, 6, 7));
            v
        }
        K::Quadrilateral3D9 => [
            quad(0, 4, 8, 7),
            quad(4, 1, 5, 8),
            quad(8, 5, 2, 6),
            quad(7, 8, 6, 3),
        ]
        .concat(),
        _ => return None,
    };
    Some(pieces)
}

/// Kratos' `IsIntersected`: does any piece meet the leaf box `cell` (real coordinates, already
/// grown by the cell tolerance)? Segment/box by slabs, triangle/box by Akenine-Möller.
pub(super) fn overlaps_cell(pieces: &[Piece], cell: &csm_geometry::Aabb) -> bool {
    let aabb = csm_geometry::Aabb::new(cell.min, cell.max);
    pieces.iter().any(|piece| match piece {
        Piece::Segment(a, b) => segment_aabb_intersect(a, b, &aabb),
        Piece::Triangle(t) => triangle_aabb_intersect(t, &aabb),
    })
}

/// The exact face–face test (`Geometry::HasIntersection(other)`, used without OBBs): any pair
/// of pieces shares a point. Segments in 2D by orientation predicates, triangles by the
/// separating-axis triangle–triangle test (a segment against a triangle as a degenerate
/// triangle).
pub(super) fn pieces_intersect(a: &[Piece], b: &[Piece]) -> bool {
    let as_triangle = |p: &Piece| match p {
        Piece::Segment(x, y) => [*x, *y, *y],
        Piece::Triangle(t) => *t,
    };
    a.iter().any(|pa| {
        b.iter().any(|pb| match (pa, pb) {
            (Piece::Segment(p1, p2), Piece::Segment(q1, q2)) => {
                segment_segment_intersect(p1, p2, q1, q2)
            }
            _ => triangle_triangle_intersect(&as_triangle(pa), &as_triangle(pb)),
        })
    })
}
