//! The edges of every geometry kind, as pairs of corner nodes (mid-edge nodes of quadratic
//! kinds are not edge ends: a quadratic edge is listed by its two corners).

use crate::GeometryKind;

type Edges = &'static [[usize; 2]];

const LINE: Edges = &[[0, 1]];
const TRIANGLE: Edges = &[[0, 1], [1, 2], [2, 0]];
const QUADRILATERAL: Edges = &[[0, 1], [1, 2], [2, 3], [3, 0]];
const TETRAHEDRON: Edges = &[[0, 1], [1, 2], [2, 0], [0, 3], [1, 3], [2, 3]];
const HEXAHEDRON: Edges = &[
    [0, 1],
    [1, 2],
    [2, 3],
    [3, 0],
    [4, 5],
    [5, 6],
    [6, 7],
    [7, 4],
    [0, 4],
    [1, 5],
    [2, 6],
    [3, 7],
];
const PRISM: Edges = &[
    [0, 1],
    [1, 2],
    [2, 0],
    [3, 4],
    [4, 5],
    [5, 3],
    [0, 3],
    [1, 4],
    [2, 5],
];

impl GeometryKind {
    /// The edges of the geometry as pairs of corner-node indices, in a fixed order.
    pub fn edges(self) -> &'static [[usize; 2]] {
        use GeometryKind as K;
        match self {
            K::Line2D2 | K::Line2D3 => LINE,
            K::Triangle3D3 | K::Triangle3D6 | K::Triangle2D3 | K::Triangle2D6 => TRIANGLE,
            K::Quadrilateral3D4
            | K::Quadrilateral3D8
            | K::Quadrilateral3D9
            | K::Quadrilateral2D4
            | K::Quadrilateral2D8
            | K::Quadrilateral2D9 => QUADRILATERAL,
            K::Tetrahedra3D4 | K::Tetrahedra3D10 => TETRAHEDRON,
            K::Hexahedra3D8 | K::Hexahedra3D20 | K::Hexahedra3D27 => HEXAHEDRON,
            K::Prism3D6 => PRISM,
        }
    }
}
