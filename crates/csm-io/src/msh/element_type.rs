//! Gmsh element types: node counts, dimensions, the Kratos geometry each becomes, and the
//! node permutation from Gmsh's order to Kratos'.
//!
//! Gmsh and Kratos agree on the node order of every linear cell and of the 3-node line,
//! 6-node triangle and 8/9-node quadrilaterals (corners, then edge mid nodes 01, 12, 23, 30,
//! then the centre). They differ for:
//! - the 10-node tetrahedron: Gmsh's mid nodes 8 and 9 are on edges 2-3 and 1-3, Kratos'
//!   on 1-3 and 2-3 (swap them);
//! - the 20-node hexahedron: Gmsh numbers the edges 01, 03, 04, 12, 15, 23, 26, 37, 45, 47,
//!   56, 67; Kratos 01, 12, 23, 30, 04, 15, 26, 37, 45, 56, 67, 74;
//! - the 27-node hexahedron: edges as the 20-node one, then the face centres (Gmsh: bottom,
//!   front 0154, left 0473, right 1265, back 2376, top; Kratos: bottom, 0154, 1265, 2376,
//!   3047, top), then the centre.

use csm_geometry::GeometryKind;

/// Number of nodes of Gmsh element type `t` (a known type).
pub(crate) fn n_nodes(t: i64) -> Option<usize> {
    Some(match t {
        1 => 2,
        2 => 3,
        3 => 4,
        4 => 4,
        5 => 8,
        6 => 6,
        8 => 3,
        9 => 6,
        10 => 9,
        11 => 10,
        12 => 27,
        15 => 1,
        16 => 8,
        17 => 20,
        _ => return None,
    })
}

/// Dimension of Gmsh element type `t` (0 points, 1 lines, 2 surfaces, 3 volumes).
pub(crate) fn dim(t: i64) -> usize {
    match t {
        15 => 0,
        1 | 8 => 1,
        2 | 3 | 9 | 10 | 16 => 2,
        _ => 3,
    }
}

/// What a Gmsh cell becomes in the model.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Role {
    /// An element of this geometry.
    Element(GeometryKind),
    /// A condition of this geometry.
    Condition(GeometryKind),
    /// Only its nodes go into its physical groups' parts.
    NodesOnly,
}

/// The role of Gmsh type `t` in a model of dimension `model_dim` (`planar`: every node has
/// z = 0 and `model_dim` ≤ 2).
pub(crate) fn role(t: i64, model_dim: usize, planar: bool) -> Role {
    use GeometryKind as G;
    let d = dim(t);
    if planar {
        // 2D model: surfaces are elements, lines conditions (lines only: elements).
        let kind = match t {
            1 => G::Line2D2,
            8 => G::Line2D3,
            2 => G::Triangle2D3,
            9 => G::Triangle2D6,
            3 => G::Quadrilateral2D4,
            16 => G::Quadrilateral2D8,
            10 => G::Quadrilateral2D9,
            _ => return Role::NodesOnly,
        };
        return if d == model_dim {
            Role::Element(kind)
        } else if d + 1 == model_dim {
            Role::Condition(kind)
        } else {
            Role::NodesOnly
        };
    }
    let kind = match t {
        2 => G::Triangle3D3,
        9 => G::Triangle3D6,
        3 => G::Quadrilateral3D4,
        16 => G::Quadrilateral3D8,
        10 => G::Quadrilateral3D9,
        4 => G::Tetrahedra3D4,
        11 => G::Tetrahedra3D10,
        5 => G::Hexahedra3D8,
        17 => G::Hexahedra3D20,
        12 => G::Hexahedra3D27,
        6 => G::Prism3D6,
        // Lines in space and points: no Kratos face geometry csm uses.
        _ => return Role::NodesOnly,
    };
    if d == model_dim {
        Role::Element(kind)
    } else if d + 1 == model_dim {
        Role::Condition(kind)
    } else {
        Role::NodesOnly
    }
}

/// `kratos[i] = gmsh[perm[i]]` for the types whose orders differ; `None` when they agree.
pub(crate) fn permutation(t: i64) -> Option<&'static [usize]> {
    const TET10: [usize; 10] = [0, 1, 2, 3, 4, 5, 6, 7, 9, 8];
    const HEX20: [usize; 20] = [
        0, 1, 2, 3, 4, 5, 6, 7, 8, 11, 13, 9, 10, 12, 14, 15, 16, 18, 19, 17,
    ];
    const HEX27: [usize; 27] = [
        0, 1, 2, 3, 4, 5, 6, 7, 8, 11, 13, 9, 10, 12, 14, 15, 16, 18, 19, 17, 20, 21, 23, 24, 22,
        25, 26,
    ];
    match t {
        11 => Some(&TET10),
        17 => Some(&HEX20),
        12 => Some(&HEX27),
        _ => None,
    }
}
