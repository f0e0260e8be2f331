//! Which finite-element geometry a node list describes.

/// The finite-element geometries csm knows, named as in Kratos. Faces (what contact
/// conditions are made of) and solids (what elements are made of, needed for interface
/// generation, the normal check and NODAL_H).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum GeometryKind {
    /// 2-node line in the xy plane (2D contact face).
    Line2D2,
    /// 3-node quadratic line (Kratos order: ends 0, 1, mid node 2).
    Line2D3,
    /// 3-node triangle in space.
    Triangle3D3,
    /// 6-node quadratic triangle in space (corners 0..3, then mid nodes of edges 01, 12, 20).
    Triangle3D6,
    /// 4-node bilinear quadrilateral in space.
    Quadrilateral3D4,
    /// 8-node serendipity quadrilateral in space (corners, then mid nodes of 01, 12, 23, 30).
    Quadrilateral3D8,
    /// 9-node Lagrange quadrilateral in space (as 3D8 plus the centre node).
    Quadrilateral3D9,
    /// 3-node triangle as a 2D solid.
    Triangle2D3,
    /// 4-node quadrilateral as a 2D solid.
    Quadrilateral2D4,
    /// 4-node tetrahedron.
    Tetrahedra3D4,
    /// 8-node hexahedron.
    Hexahedra3D8,
    /// 6-node prism (wedge).
    Prism3D6,
    /// 6-node quadratic triangle as a 2D solid (read from meshes; stored, not searched).
    Triangle2D6,
    /// 8-node serendipity quadrilateral as a 2D solid (read from meshes; stored, not searched).
    Quadrilateral2D8,
    /// 9-node quadrilateral as a 2D solid (read from meshes; stored, not searched).
    Quadrilateral2D9,
    /// 10-node quadratic tetrahedron (read from meshes; stored, not searched).
    Tetrahedra3D10,
    /// 20-node serendipity hexahedron (read from meshes; stored, not searched).
    Hexahedra3D20,
    /// 27-node hexahedron (read from meshes; stored, not searched).
    Hexahedra3D27,
}

impl GeometryKind {
    /// Every kind, in declaration order.
    pub const ALL: [GeometryKind; 18] = [
        GeometryKind::Line2D2,
        GeometryKind::Line2D3,
        GeometryKind::Triangle3D3,
        GeometryKind::Triangle3D6,
        GeometryKind::Quadrilateral3D4,
        GeometryKind::Quadrilateral3D8,
        GeometryKind::Quadrilateral3D9,
        GeometryKind::Triangle2D3,
        GeometryKind::Quadrilateral2D4,
        GeometryKind::Tetrahedra3D4,
        GeometryKind::Hexahedra3D8,
        GeometryKind::Prism3D6,
        GeometryKind::Triangle2D6,
        GeometryKind::Quadrilateral2D8,
        GeometryKind::Quadrilateral2D9,
        GeometryKind::Tetrahedra3D10,
        GeometryKind::Hexahedra3D20,
        GeometryKind::Hexahedra3D27,
    ];

    /// Kratos' name of the geometry.
    pub fn name(self) -> &'static str {
        match self {
            GeometryKind::Line2D2 => "Line2D2",
            GeometryKind::Line2D3 => "Line2D3",
            GeometryKind::Triangle3D3 => "Triangle3D3",
            GeometryKind::Triangle3D6 => "Triangle3D6",
            GeometryKind::Quadrilateral3D4 => "Quadrilateral3D4",
            GeometryKind::Quadrilateral3D8 => "Quadrilateral3D8",
            GeometryKind::Quadrilateral3D9 => "Quadrilateral3D9",
            GeometryKind::Triangle2D3 => "Triangle2D3",
            GeometryKind::Quadrilateral2D4 => "Quadrilateral2D4",
            GeometryKind::Tetrahedra3D4 => "Tetrahedra3D4",
            GeometryKind::Hexahedra3D8 => "Hexahedra3D8",
            GeometryKind::Prism3D6 => "Prism3D6",
            GeometryKind::Triangle2D6 => "Triangle2D6",
            GeometryKind::Quadrilateral2D8 => "Quadrilateral2D8",
            GeometryKind::Quadrilateral2D9 => "Quadrilateral2D9",
            GeometryKind::Tetrahedra3D10 => "Tetrahedra3D10",
            GeometryKind::Hexahedra3D20 => "Hexahedra3D20",
            GeometryKind::Hexahedra3D27 => "Hexahedra3D27",
        }
    }

    /// The kind Kratos names `name` ([`name`](Self::name)), if csm knows it.
    pub fn from_name(name: &str) -> Option<GeometryKind> {
        GeometryKind::ALL.into_iter().find(|k| k.name() == name)
    }

    /// Number of nodes of the geometry.
    pub fn n_nodes(self) -> usize {
        match self {
            GeometryKind::Line2D2 => 2,
            GeometryKind::Line2D3 | GeometryKind::Triangle3D3 | GeometryKind::Triangle2D3 => 3,
            GeometryKind::Quadrilateral3D4
            | GeometryKind::Quadrilateral2D4
            | GeometryKind::Tetrahedra3D4 => 4,
            GeometryKind::Triangle3D6 | GeometryKind::Prism3D6 | GeometryKind::Triangle2D6 => 6,
            GeometryKind::Quadrilateral3D8
            | GeometryKind::Hexahedra3D8
            | GeometryKind::Quadrilateral2D8 => 8,
            GeometryKind::Quadrilateral3D9 | GeometryKind::Quadrilateral2D9 => 9,
            GeometryKind::Tetrahedra3D10 => 10,
            GeometryKind::Hexahedra3D20 => 20,
            GeometryKind::Hexahedra3D27 => 27,
        }
    }

    /// Dimension of the reference element (1 for lines, 2 for surfaces, 3 for volumes).
    pub fn local_dim(self) -> usize {
        match self {
            GeometryKind::Line2D2 | GeometryKind::Line2D3 => 1,
            GeometryKind::Triangle3D3
            | GeometryKind::Triangle3D6
            | GeometryKind::Quadrilateral3D4
            | GeometryKind::Quadrilateral3D8
            | GeometryKind::Quadrilateral3D9
            | GeometryKind::Triangle2D3
            | GeometryKind::Quadrilateral2D4
            | GeometryKind::Triangle2D6
            | GeometryKind::Quadrilateral2D8
            | GeometryKind::Quadrilateral2D9 => 2,
            GeometryKind::Tetrahedra3D4
            | GeometryKind::Hexahedra3D8
            | GeometryKind::Prism3D6
            | GeometryKind::Tetrahedra3D10
            | GeometryKind::Hexahedra3D20
            | GeometryKind::Hexahedra3D27 => 3,
        }
    }

    /// Dimension of the space the geometry lives in (2 for the `…2D…` kinds, else 3).
    pub fn working_dim(self) -> usize {
        match self {
            GeometryKind::Line2D2
            | GeometryKind::Line2D3
            | GeometryKind::Triangle2D3
            | GeometryKind::Quadrilateral2D4
            | GeometryKind::Triangle2D6
            | GeometryKind::Quadrilateral2D8
            | GeometryKind::Quadrilateral2D9 => 2,
            _ => 3,
        }
    }

    /// True for solids (local dimension = working dimension): the kinds elements are made of.
    pub fn is_solid(self) -> bool {
        self.local_dim() == self.working_dim()
    }

    /// True for faces (local dimension = working dimension − 1): the kinds contact
    /// conditions are made of.
    pub fn is_face(self) -> bool {
        self.local_dim() + 1 == self.working_dim()
    }
}
