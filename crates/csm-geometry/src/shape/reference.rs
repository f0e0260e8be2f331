//! Local coordinates of the nodes of each reference element (Kratos' numbering).

use crate::GeometryKind;
use crate::math::Real;

const LINE2: [[Real; 3]; 2] = [[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0]];
const LINE3: [[Real; 3]; 3] = [[-1.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]];
const TRI3: [[Real; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
const TRI6: [[Real; 3]; 6] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.5, 0.0, 0.0],
    [0.5, 0.5, 0.0],
    [0.0, 0.5, 0.0],
];
const QUAD9: [[Real; 3]; 9] = [
    [-1.0, -1.0, 0.0],
    [1.0, -1.0, 0.0],
    [1.0, 1.0, 0.0],
    [-1.0, 1.0, 0.0],
    [0.0, -1.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [-1.0, 0.0, 0.0],
    [0.0, 0.0, 0.0],
];
const TET10: [[Real; 3]; 10] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
    [0.5, 0.0, 0.0],
    [0.5, 0.5, 0.0],
    [0.0, 0.5, 0.0],
    [0.0, 0.0, 0.5],
    [0.5, 0.0, 0.5],
    [0.0, 0.5, 0.5],
];
const PRISM6: [[Real; 3]; 6] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
    [1.0, 0.0, 1.0],
    [0.0, 1.0, 1.0],
];
/// Corners (0–7), edge mid nodes 01, 12, 23, 30, 04, 15, 26, 37, 45, 56, 67, 74 (8–19),
/// face centres z = −1, y = −1, x = +1, y = +1, x = −1, z = +1 (20–25), centre (26).
const HEXA27: [[Real; 3]; 27] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
    [0.0, -1.0, -1.0],
    [1.0, 0.0, -1.0],
    [0.0, 1.0, -1.0],
    [-1.0, 0.0, -1.0],
    [-1.0, -1.0, 0.0],
    [1.0, -1.0, 0.0],
    [1.0, 1.0, 0.0],
    [-1.0, 1.0, 0.0],
    [0.0, -1.0, 1.0],
    [1.0, 0.0, 1.0],
    [0.0, 1.0, 1.0],
    [-1.0, 0.0, 1.0],
    [0.0, 0.0, -1.0],
    [0.0, -1.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [-1.0, 0.0, 0.0],
    [0.0, 0.0, 1.0],
    [0.0, 0.0, 0.0],
];

/// Local coordinates `[ξ, η, ζ]` of the nodes of `kind`'s reference element, in node order
/// (unused directions are 0). The Hexahedra3D27 face-centre order (20–25) follows the order
/// of Kratos' `GenerateFaces` for that geometry.
pub fn reference_node_coordinates(kind: GeometryKind) -> &'static [[Real; 3]] {
    use GeometryKind as K;
    match kind {
        K::Line2D2 => &LINE2,
        K::Line2D3 => &LINE3,
        K::Triangle3D3 | K::Triangle2D3 => &TRI3,
        K::Triangle3D6 | K::Triangle2D6 => &TRI6,
        K::Quadrilateral3D4 | K::Quadrilateral2D4 => &QUAD9[..4],
        K::Quadrilateral3D8 | K::Quadrilateral2D8 => &QUAD9[..8],
        K::Quadrilateral3D9 | K::Quadrilateral2D9 => &QUAD9,
        K::Tetrahedra3D4 => &TET10[..4],
        K::Tetrahedra3D10 => &TET10,
        K::Hexahedra3D8 => &HEXA27[..8],
        K::Hexahedra3D20 => &HEXA27[..20],
        K::Hexahedra3D27 => &HEXA27,
        K::Prism3D6 => &PRISM6,
    }
}
