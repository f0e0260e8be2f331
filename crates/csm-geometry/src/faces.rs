//! The boundary entities (faces) of the solid kinds, in Kratos' order and node order
//! (`GenerateFaces` in 3D, `GenerateEdges` in 2D, i.e. `GenerateBoundariesEntities`).
//!
//! With these node orders the face normals ([`Geometry::unit_normal`](crate::Geometry::unit_normal))
//! of a positively oriented solid point outwards. The linear orders are Kratos 10.4.4's,
//! observed through `InterfacePreprocessCondition` (fixture `tests/fixtures/faces.json`, made by
//! `cargo xtask fixtures`); the quadratic ones follow the same corner order. 2D edges use the
//! normal `(t_y, −t_x)` (right of the direction 0 → 1) on counter-clockwise polygons; 3D faces are ordered counter-clockwise
//! seen from outside, so `∂x/∂ξ × ∂x/∂η` points out.

use crate::GeometryKind;

type Faces = &'static [(GeometryKind, &'static [usize])];

const TRI_EDGES: Faces = &[
    (GeometryKind::Line2D2, &[1, 2]),
    (GeometryKind::Line2D2, &[2, 0]),
    (GeometryKind::Line2D2, &[0, 1]),
];
const TRI6_EDGES: Faces = &[
    (GeometryKind::Line2D3, &[1, 2, 4]),
    (GeometryKind::Line2D3, &[2, 0, 5]),
    (GeometryKind::Line2D3, &[0, 1, 3]),
];
const QUAD_EDGES: Faces = &[
    (GeometryKind::Line2D2, &[0, 1]),
    (GeometryKind::Line2D2, &[1, 2]),
    (GeometryKind::Line2D2, &[2, 3]),
    (GeometryKind::Line2D2, &[3, 0]),
];
const QUAD8_EDGES: Faces = &[
    (GeometryKind::Line2D3, &[0, 1, 4]),
    (GeometryKind::Line2D3, &[1, 2, 5]),
    (GeometryKind::Line2D3, &[2, 3, 6]),
    (GeometryKind::Line2D3, &[3, 0, 7]),
];
const TET4_FACES: Faces = &[
    (GeometryKind::Triangle3D3, &[2, 3, 1]),
    (GeometryKind::Triangle3D3, &[0, 3, 2]),
    (GeometryKind::Triangle3D3, &[0, 1, 3]),
    (GeometryKind::Triangle3D3, &[0, 2, 1]),
];
const TET10_FACES: Faces = &[
    (GeometryKind::Triangle3D6, &[2, 3, 1, 9, 8, 5]),
    (GeometryKind::Triangle3D6, &[0, 3, 2, 7, 9, 6]),
    (GeometryKind::Triangle3D6, &[0, 1, 3, 4, 8, 7]),
    (GeometryKind::Triangle3D6, &[0, 2, 1, 6, 5, 4]),
];
const HEXA8_FACES: Faces = &[
    (GeometryKind::Quadrilateral3D4, &[3, 2, 1, 0]),
    (GeometryKind::Quadrilateral3D4, &[0, 1, 5, 4]),
    (GeometryKind::Quadrilateral3D4, &[2, 6, 5, 1]),
    (GeometryKind::Quadrilateral3D4, &[7, 6, 2, 3]),
    (GeometryKind::Quadrilateral3D4, &[7, 3, 0, 4]),
    (GeometryKind::Quadrilateral3D4, &[4, 5, 6, 7]),
];
const HEXA20_FACES: Faces = &[
    (GeometryKind::Quadrilateral3D8, &[3, 2, 1, 0, 10, 9, 8, 11]),
    (GeometryKind::Quadrilateral3D8, &[0, 1, 5, 4, 8, 13, 16, 12]),
    (GeometryKind::Quadrilateral3D8, &[2, 6, 5, 1, 14, 17, 13, 9]),
    (
        GeometryKind::Quadrilateral3D8,
        &[7, 6, 2, 3, 18, 14, 10, 15],
    ),
    (
        GeometryKind::Quadrilateral3D8,
        &[7, 3, 0, 4, 15, 11, 12, 19],
    ),
    (
        GeometryKind::Quadrilateral3D8,
        &[4, 5, 6, 7, 16, 17, 18, 19],
    ),
];
const HEXA27_FACES: Faces = &[
    (
        GeometryKind::Quadrilateral3D9,
        &[3, 2, 1, 0, 10, 9, 8, 11, 20],
    ),
    (
        GeometryKind::Quadrilateral3D9,
        &[0, 1, 5, 4, 8, 13, 16, 12, 21],
    ),
    (
        GeometryKind::Quadrilateral3D9,
        &[2, 6, 5, 1, 14, 17, 13, 9, 22],
    ),
    (
        GeometryKind::Quadrilateral3D9,
        &[7, 6, 2, 3, 18, 14, 10, 15, 23],
    ),
    (
        GeometryKind::Quadrilateral3D9,
        &[7, 3, 0, 4, 15, 11, 12, 19, 24],
    ),
    (
        GeometryKind::Quadrilateral3D9,
        &[4, 5, 6, 7, 16, 17, 18, 19, 25],
    ),
];
const PRISM6_FACES: Faces = &[
    (GeometryKind::Triangle3D3, &[0, 2, 1]),
    (GeometryKind::Triangle3D3, &[3, 4, 5]),
    (GeometryKind::Quadrilateral3D4, &[1, 2, 5, 4]),
    (GeometryKind::Quadrilateral3D4, &[0, 3, 5, 2]),
    (GeometryKind::Quadrilateral3D4, &[0, 1, 4, 3]),
];

impl GeometryKind {
    /// The boundary entities of a solid, in Kratos' order and node order
    /// (`GenerateBoundariesEntities`): for each, the face kind and the indices of its nodes in
    /// this geometry's node list. Empty for the face kinds.
    ///
    /// 2D solids give their edges (Line2D2, or Line2D3 for the quadratic ones); tetrahedra,
    /// hexahedra and prisms give triangles/quadrilaterals in Kratos' `GenerateFaces` order, e.g.
    /// Tetrahedra3D4: (2,3,1), (0,3,2), (0,1,3), (0,2,1); Triangle2D3: (1,2), (2,0), (0,1);
    /// Hexahedra3D8: (3,2,1,0), (0,1,5,4),
    /// (2,6,5,1), (7,6,2,3), (7,3,0,4), (4,5,6,7); Prism3D6: (0,2,1), (3,4,5), (1,2,5,4),
    /// (0,3,5,2), (0,1,4,3). On a positively oriented solid every face normal points outwards.
    pub fn faces(self) -> &'static [(GeometryKind, &'static [usize])] {
        use GeometryKind as K;
        match self {
            K::Triangle2D3 => TRI_EDGES,
            K::Triangle2D6 => TRI6_EDGES,
            K::Quadrilateral2D4 => QUAD_EDGES,
            K::Quadrilateral2D8 | K::Quadrilateral2D9 => QUAD8_EDGES,
            K::Tetrahedra3D4 => TET4_FACES,
            K::Tetrahedra3D10 => TET10_FACES,
            K::Hexahedra3D8 => HEXA8_FACES,
            K::Hexahedra3D20 => HEXA20_FACES,
            K::Hexahedra3D27 => HEXA27_FACES,
            K::Prism3D6 => PRISM6_FACES,
            K::Line2D2
            | K::Line2D3
            | K::Triangle3D3
            | K::Triangle3D6
            | K::Quadrilateral3D4
            | K::Quadrilateral3D8
            | K::Quadrilateral3D9 => &[],
        }
    }
}
