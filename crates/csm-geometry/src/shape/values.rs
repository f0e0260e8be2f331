//! Small fixed-capacity containers for shape-function values and derivatives.

use crate::math::Real;

/// The largest node count of any [`GeometryKind`](crate::GeometryKind) (Hexahedra3D27).
pub const MAX_NODES: usize = 27;

/// Values `N_i(ξ)` of the shape functions at one local point, one per node, in node order.
/// Dereferences to a slice of length `n_nodes`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShapeValues {
    values: [Real; MAX_NODES],
    len: usize,
}

impl ShapeValues {
    pub(crate) fn zeros(len: usize) -> ShapeValues {
        debug_assert!(len <= MAX_NODES);
        ShapeValues {
            values: [0.0; MAX_NODES],
            len,
        }
    }

    pub(crate) fn set(&mut self, i: usize, value: Real) {
        self.values[i] = value;
    }

    /// The values as a slice (length = number of nodes).
    pub fn as_slice(&self) -> &[Real] {
        &self.values[..self.len]
    }
}

impl std::ops::Deref for ShapeValues {
    type Target = [Real];
    fn deref(&self) -> &[Real] {
        self.as_slice()
    }
}

/// Local derivatives `∂N_i/∂ξ_k` of the shape functions at one local point: one row per node
/// (node order), one column per local direction `k < local_dim` (ξ, η, ζ). Columns at and
/// beyond `local_dim` are zero.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShapeDerivatives {
    rows: [[Real; 3]; MAX_NODES],
    len: usize,
    local_dim: usize,
}

impl ShapeDerivatives {
    pub(crate) fn zeros(len: usize, local_dim: usize) -> ShapeDerivatives {
        debug_assert!(len <= MAX_NODES && local_dim <= 3);
        ShapeDerivatives {
            rows: [[0.0; 3]; MAX_NODES],
            len,
            local_dim,
        }
    }

    pub(crate) fn set(&mut self, i: usize, row: [Real; 3]) {
        self.rows[i] = row;
    }

    /// Number of nodes (rows).
    pub fn n_nodes(&self) -> usize {
        self.len
    }

    /// Number of local directions (meaningful columns).
    pub fn local_dim(&self) -> usize {
        self.local_dim
    }

    /// `∂N_node/∂ξ_k`. Panics if `node ≥ n_nodes()` or `k ≥ 3` (plain slice indexing).
    pub fn get(&self, node: usize, k: usize) -> Real {
        self.rows[..self.len][node][k]
    }

    /// All rows `[∂N_i/∂ξ, ∂N_i/∂η, ∂N_i/∂ζ]`, node order.
    pub fn rows(&self) -> &[[Real; 3]] {
        &self.rows[..self.len]
    }
}
