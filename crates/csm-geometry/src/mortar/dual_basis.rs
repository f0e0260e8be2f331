//! Popp's dual Lagrange-multiplier basis on the slave (Kratos
//! `DualLagrangeMultiplierOperators::CalculateAe`, reference §10.2.2).

use super::face::MortarFace;
use super::integration_points::MortarIntegrationPoint;
use crate::math::{EPS, Real};
use nalgebra::DMatrix;

/// The matrix `Ae` of the dual basis `Φ = Ae · N_s`, for one slave–master pair.
#[derive(Debug, Clone, PartialEq)]
pub struct DualBasis {
    ae: DMatrix<Real>,
    is_dual: bool,
}

impl DualBasis {
    /// The standard basis (`Ae = I`, `Φ = N_s`) for `n_nodes` slave nodes.
    pub fn identity(n_nodes: usize) -> DualBasis {
        DualBasis {
            ae: DMatrix::identity(n_nodes, n_nodes),
            is_dual: false,
        }
    }

    /// `Ae` (slave nodes × slave nodes).
    pub fn ae(&self) -> &DMatrix<Real> {
        &self.ae
    }

    /// Kratos' return flag: `false` when `Me` was (numerically) singular and `Ae` fell back to
    /// the identity. Kratos' mapper ignores it and uses whatever `Ae` came out.
    pub fn is_dual(&self) -> bool {
        self.is_dual
    }

    /// `Φ = Ae · N` for shape-function values `n` (one per slave node).
    pub fn phi(&self, n: &[Real]) -> Vec<Real> {
        (0..self.ae.nrows())
            .map(|i| (0..n.len()).map(|j| self.ae[(i, j)] * n[j]).sum())
            .collect()
    }
}

/// The dual basis of one pair from its Gauss points ([`integration_points`](super::
/// integration_points)): `De = Σ w·diag(N_s)`, `Me = Σ w·N_s N_sᵀ` (`w` = weight × detJ);
/// with `f = ‖Me‖_F`: if `f ≥ ε` and `|det(Me/f)| ≥ ε`, `Ae = (1/f) · De · (Me/f)⁻¹` (so that
/// `∫ Φ_i N_j = δ_ij ∫ N_j` over the pair's cells); otherwise the identity (flag false). No
/// Gauss points (all cells degenerate) gives the identity.
pub fn dual_basis(slave: &MortarFace<'_>, points: &[MortarIntegrationPoint]) -> DualBasis {
    let sg = slave.geometry();
    let n = sg.kind().n_nodes();
    let mut de = DMatrix::<Real>::zeros(n, n);
    let mut me = DMatrix::<Real>::zeros(n, n);
    for gp in points {
        let ns = sg.shape_functions(&gp.slave_local);
        for i in 0..n {
            de[(i, i)] += gp.weight * ns[i];
            for j in 0..n {
                me[(i, j)] += gp.weight * ns[i] * ns[j];
            }
        }
    }
    let f = me.norm();
    if f >= EPS {
        let scaled = &me / f;
        if scaled.clone().determinant().abs() >= EPS
            && let Some(inv) = scaled.try_inverse()
        {
            return DualBasis {
                ae: (de * inv) / f,
                is_dual: true,
            };
        }
    }
    DualBasis::identity(n)
}
