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

/// The largest condition number `‖Me/f‖_F · ‖(Me/f)⁻¹‖_F` for which the dual basis is used:
/// `10⁻⁴ / ε` (Kratos' `MathUtils::CheckConditionNumber`: "at least 4 significant digits").
pub const MAX_ME_CONDITION_NUMBER: Real = 1.0e-4 / EPS;

/// The dual basis of one pair from its Gauss points ([`integration_points`](super::
/// integration_points)): `De = Σ w·diag(N_s)`, `Me = Σ w·N_s N_sᵀ` (`w` = weight × detJ),
/// then [`dual_ae`]. No Gauss points (all cells degenerate) gives the identity.
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
    match dual_ae(&de, &me) {
        Some(ae) => DualBasis { ae, is_dual: true },
        None => DualBasis::identity(n),
    }
}

/// `Ae = (1/f) · De · (Me/f)⁻¹` with `f = ‖Me‖_F` (so that `∫ Φ_i N_j = δ_ij ∫ N_j` over the
/// pair's cells), or `None` — the standard basis — when `f < ε`, when `Me/f` has no finite
/// inverse, or when its condition number `‖Me/f‖_F · ‖(Me/f)⁻¹‖_F` exceeds
/// [`MAX_ME_CONDITION_NUMBER`].
///
/// The condition-number rule is what Kratos 10.4.4 does, established against its results:
/// `|det(Me/f)| ≥ ε` (the rule of older Kratos sources and of the reference §10.2.2) would
/// refuse the dual basis of a two-cell corner pair of the quadrilateral double-curvature mesh
/// (det 3.3e-17, condition number ≈ 10⁹) whose dual `D` Kratos' `NODAL_AREA` contains, and
/// no determinant threshold reproduces every fixture while this rule does (docs/conformance.md).
pub fn dual_ae(de: &DMatrix<Real>, me: &DMatrix<Real>) -> Option<DMatrix<Real>> {
    let f = me.norm();
    if f.is_nan() || f < EPS {
        return None;
    }
    let scaled = me / f;
    let inv = scaled.clone().try_inverse()?;
    let condition = scaled.norm() * inv.norm();
    if !condition.is_finite() || condition > MAX_ME_CONDITION_NUMBER {
        return None;
    }
    Some((de * inv) / f)
}
