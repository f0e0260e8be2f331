//! VTK cell types and the node permutation from Kratos' order to VTK's.
//!
//! Kratos and VTK agree on lines (3, quadratic edge 21), triangles (5, 22), quadrilaterals
//! (9, 23, biquadratic 28), tetrahedra (10, 24) and the linear hexahedron (12). They differ:
//! - wedge (13): Kratos' triangle 0-1-2 faces the triangle 3-4-5 (right-hand rule), VTK's
//!   points away from it: VTK gets nodes 0, 2, 1, 3, 5, 4. This follows VTK's documentation
//!   and its face definitions (ParaView's extracted surfaces then have outward normals); VTK
//!   9.7's volume measures (Cell Size, Mesh Quality) disagree with both and report such
//!   wedges with a negative volume — a known VTK inconsistency, not an inverted mesh;
//! - quadratic hexahedron (25): Kratos' mid nodes are bottom edges 8-11, vertical edges
//!   12-15, top edges 16-19; VTK's bottom, top, vertical;
//! - triquadratic hexahedron (29): as 25, then VTK's face centres are x-, x+, y-, y+, z-, z+
//!   (Kratos: z- 20, y- 21, x+ 22, y+ 23, x- 24, z+ 25), then the centre.

use csm_geometry::GeometryKind;

/// The VTK cell type of a geometry kind.
pub fn vtk_cell_type(kind: GeometryKind) -> u8 {
    use GeometryKind as G;
    match kind {
        G::Line2D2 => 3,
        G::Line2D3 => 21,
        G::Triangle3D3 | G::Triangle2D3 => 5,
        G::Triangle3D6 | G::Triangle2D6 => 22,
        G::Quadrilateral3D4 | G::Quadrilateral2D4 => 9,
        G::Quadrilateral3D8 | G::Quadrilateral2D8 => 23,
        G::Quadrilateral3D9 | G::Quadrilateral2D9 => 28,
        G::Tetrahedra3D4 => 10,
        G::Tetrahedra3D10 => 24,
        G::Hexahedra3D8 => 12,
        G::Hexahedra3D20 => 25,
        G::Hexahedra3D27 => 29,
        G::Prism3D6 => 13,
    }
}

/// `vtk[i] = kratos[perm[i]]` where the orders differ.
pub(crate) fn vtk_permutation(kind: GeometryKind) -> Option<&'static [usize]> {
    const WEDGE: [usize; 6] = [0, 2, 1, 3, 5, 4];
    const HEX20: [usize; 20] = [
        0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 16, 17, 18, 19, 12, 13, 14, 15,
    ];
    const HEX27: [usize; 27] = [
        0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 16, 17, 18, 19, 12, 13, 14, 15, 24, 22, 21, 23, 20,
        25, 26,
    ];
    match kind {
        GeometryKind::Prism3D6 => Some(&WEDGE),
        GeometryKind::Hexahedra3D20 => Some(&HEX20),
        GeometryKind::Hexahedra3D27 => Some(&HEX27),
        _ => None,
    }
}
