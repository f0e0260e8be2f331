//! Popp's dual Lagrange-multiplier basis on the slave (Kratos
//! `DualLagrangeMultiplierOperators::CalculateAe`, reference §10.2.2), with Kratos' own
//! arithmetic: the accumulation order of `De` and `Me`, ublas' Frobenius norm, `MathUtils`'
//! closed-form inverse (`InvertMatrix2/3/4`, adjugate over its own determinant) and its
//! condition-number test `‖A‖_F·‖A⁻¹‖_F > 1e-4/ε`.
//!
//! Which pairs get the dual basis was settled against Kratos 10.4.4 (the mapper run on single
//! slave–master pairs of the double-curvature quadrilateral mesh in the dynamic-search set-up):
//! Kratos inverts `Me/‖Me‖` whatever its determinant and falls back to the standard basis only
//! when that condition number is too high. A pair whose Gauss points crowd one edge of a
//! quadrilateral slave has `det(Me/‖Me‖) ≈ 2e-17 < ε` but a condition number of 4e9 and gets
//! the dual basis; a one-triangle segmentation of a quadrilateral (rank-deficient `Me`,
//! condition number ≥ 1e20) gets the standard one. (The reference's "`|det(Me/f)| ≥ ε`" rule
//! gave the standard basis to the first kind and NODAL_AREA differences up to 1.7e-4.)

use super::face::{MortarFace, MortarMode};
use super::face_matrix::{FaceMatrix, MAX_MORTAR_FACE_NODES, face_shape_values};
use super::integration_points::MortarIntegrationPoint;
use crate::math::{EPS, Real};

/// The matrix `Ae` of the dual basis `Φ = Ae · N_s`, for one slave–master pair.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DualBasis {
    ae: FaceMatrix,
    is_dual: bool,
}

impl DualBasis {
    /// The standard basis (`Ae = I`, `Φ = N_s`) for `n_nodes` slave nodes (at most
    /// [`MAX_MORTAR_FACE_NODES`]; more are clamped).
    pub fn identity(n_nodes: usize) -> DualBasis {
        DualBasis {
            ae: FaceMatrix::identity(n_nodes.min(MAX_MORTAR_FACE_NODES)),
            is_dual: false,
        }
    }

    /// `Ae` (slave nodes × slave nodes).
    pub fn ae(&self) -> &FaceMatrix {
        &self.ae
    }

    /// Kratos' return flag: `false` when `Me` was too ill-conditioned (or zero) and `Ae` fell
    /// back to the identity. Kratos' mapper ignores it and uses whatever `Ae` came out.
    pub fn is_dual(&self) -> bool {
        self.is_dual
    }

    /// `Φ = Ae · N` for shape-function values `n` (one per slave node), each component summed
    /// in index order from 0 (ublas `prod`); entries beyond the slave nodes are 0.
    pub fn phi(&self, n: &[Real]) -> [Real; MAX_MORTAR_FACE_NODES] {
        let mut out = [0.0; MAX_MORTAR_FACE_NODES];
        for (i, o) in out.iter_mut().enumerate().take(self.ae.nrows()) {
            let row = self.ae.row(i);
            let mut t = 0.0;
            for (a, nj) in row.iter().zip(n) {
                t += a * nj;
            }
            *o = t;
        }
        out
    }
}

/// The dual basis of one pair from its Gauss points
/// ([`integration_points`](super::integration_points)): `De(i,i) += w·(detJ·N_i)`,
/// `Me(i,j) += (w·detJ)·(N_i·N_j)`; with
/// `f = ‖Me‖_F ≥ ε`, `inv = (Me/f)⁻¹` (closed form) and, unless the condition number
/// `‖Me/f‖_F·‖inv‖_F` exceeds `1e-4/ε`, `Ae = (1/f) · De · inv` (so that `∫ Φ_i N_j = δ_ij
/// ∫ N_j` over the pair's cells); otherwise the identity (flag false). No Gauss points (all cells
/// degenerate) gives the identity. See the module docs for the arithmetic and the rule.
pub fn dual_basis(slave: &MortarFace<'_>, points: &[MortarIntegrationPoint]) -> DualBasis {
    dual_basis_in(slave, points, MortarMode::Kratos)
}

/// [`dual_basis`] under the rules of `mode`: [`MortarMode::Kratos`] as Kratos ([`dual_ae`]),
/// [`MortarMode::Robust`] without the absolute floor on `‖Me‖_F` ([`dual_ae_in`]), so that a
/// scaled mesh gets the dual basis wherever the unscaled one does.
pub fn dual_basis_in(
    slave: &MortarFace<'_>,
    points: &[MortarIntegrationPoint],
    mode: MortarMode,
) -> DualBasis {
    let sg = slave.geometry();
    let n = sg.kind().n_nodes();
    let mut de = FaceMatrix::zeros(n, n);
    let mut me = FaceMatrix::zeros(n, n);
    for gp in points {
        let ns = face_shape_values(sg.kind(), &gp.slave_local);
        let w_det = gp.gauss_weight * gp.det_j;
        for i in 0..n {
            de[(i, i)] += gp.gauss_weight * (gp.det_j * ns[i]);
            for j in 0..n {
                me[(i, j)] += w_det * (ns[i] * ns[j]);
            }
        }
    }
    match dual_ae_in(&de, &me, mode) {
        Some(ae) => DualBasis { ae, is_dual: true },
        None => DualBasis::identity(n),
    }
}

/// The largest condition number `‖Me/f‖_F · ‖(Me/f)⁻¹‖_F` for which the dual basis is used:
/// `10⁻⁴ / ε` (Kratos' `MathUtils::CheckConditionNumber`: "at least 4 significant digits").
pub const MAX_ME_CONDITION_NUMBER: Real = 1.0e-4 / EPS;

/// `Ae = (1/f) · De · (Me/f)⁻¹` with `f = ‖Me‖_F` (so that `∫ Φ_i N_j = δ_ij ∫ N_j` over the
/// pair's cells), in Kratos' arithmetic, or `None` — the standard basis — when `f < ε`, when
/// the sizes differ or have no closed-form inverse, or when the condition number exceeds
/// [`MAX_ME_CONDITION_NUMBER`] (whatever the determinant; see the module docs). An exactly
/// singular `Me/f` (determinant 0.0, so a 0/0 inverse) has a NaN condition number, which is not
/// "too high" for Kratos: it keeps the NaN inverse and the NaN reaches NORMAL_GAP. csm does
/// not: a non-finite inverse also gives the standard basis, in both modes (a NaN is never a
/// result; docs/conformance.md). No fixture pair has an exactly singular `Me`.
pub fn dual_ae(de: &FaceMatrix, me: &FaceMatrix) -> Option<FaceMatrix> {
    dual_ae_in(de, me, MortarMode::Kratos)
}

/// [`dual_ae`] under the rules of `mode`. [`MortarMode::Kratos`] refuses `‖Me‖_F < ε`, an
/// absolute floor on an area: below a scale of about 1e-8 every pair gets the standard basis.
/// [`MortarMode::Robust`] refuses only `‖Me‖_F` that is zero or not finite; the condition
/// number, which decides the rest, is scale-free (`Me/f`).
pub fn dual_ae_in(de: &FaceMatrix, me: &FaceMatrix, mode: MortarMode) -> Option<FaceMatrix> {
    let n = me.nrows();
    if de.nrows() != n || de.ncols() != n {
        return None;
    }
    let f = frobenius(me);
    let refused = match mode {
        MortarMode::Kratos => f.is_nan() || f < EPS,
        MortarMode::Robust => !(f.is_finite() && f > 0.0),
    };
    if refused {
        return None;
    }
    let scaled = me.map(|x| x / f);
    let inv = invert_kratos(&scaled)?;
    if inv.iter().any(|x| !x.is_finite()) {
        return None;
    }
    if frobenius(&scaled) * frobenius(&inv) > MAX_ME_CONDITION_NUMBER {
        return None;
    }
    let scale = 1.0 / f;
    let mut ae = FaceMatrix::zeros(n, n);
    for i in 0..n {
        for j in 0..n {
            let mut t = 0.0;
            for k in 0..n {
                t += de[(i, k)] * inv[(k, j)];
            }
            ae[(i, j)] = scale * t;
        }
    }
    Some(ae)
}

/// ublas `norm_frobenius`.
fn frobenius(a: &FaceMatrix) -> Real {
    let mut sum = 0.0;
    for i in 0..a.nrows() {
        for j in 0..a.ncols() {
            let u = a[(i, j)].abs();
            sum += u * u;
        }
    }
    sum.sqrt()
}

/// The determinant `MathUtils::InvertMatrix4` divides by (the literal expression of `Det4`).
fn det4(a: &FaceMatrix) -> Real {
    let r = |i: usize, j: usize| a[(i, j)];
    r(0, 1) * r(1, 3) * r(2, 2) * r(3, 0)
        - r(0, 1) * r(1, 2) * r(2, 3) * r(3, 0)
        - r(0, 0) * r(1, 3) * r(2, 2) * r(3, 1)
        + r(0, 0) * r(1, 2) * r(2, 3) * r(3, 1)
        - r(0, 1) * r(1, 3) * r(2, 0) * r(3, 2)
        + r(0, 0) * r(1, 3) * r(2, 1) * r(3, 2)
        + r(0, 1) * r(1, 0) * r(2, 3) * r(3, 2)
        - r(0, 0) * r(1, 1) * r(2, 3) * r(3, 2)
        + r(0, 3)
            * (r(1, 2) * r(2, 1) * r(3, 0)
                - r(1, 1) * r(2, 2) * r(3, 0)
                - r(1, 2) * r(2, 0) * r(3, 1)
                + r(1, 0) * r(2, 2) * r(3, 1)
                + r(1, 1) * r(2, 0) * r(3, 2)
                - r(1, 0) * r(2, 1) * r(3, 2))
        + (r(0, 1) * r(1, 2) * r(2, 0) - r(0, 0) * r(1, 2) * r(2, 1) - r(0, 1) * r(1, 0) * r(2, 2)
            + r(0, 0) * r(1, 1) * r(2, 2))
            * r(3, 3)
        + r(0, 2)
            * (-(r(1, 3) * r(2, 1) * r(3, 0))
                + r(1, 1) * r(2, 3) * r(3, 0)
                + r(1, 3) * r(2, 0) * r(3, 1)
                - r(1, 0) * r(2, 3) * r(3, 1)
                - r(1, 1) * r(2, 0) * r(3, 3)
                + r(1, 0) * r(2, 1) * r(3, 3))
}

/// Kratos `MathUtils::InvertMatrix2/3/4`: the adjugate (literal expressions) divided by the
/// determinant computed as those functions do; `None` for other sizes.
fn invert_kratos(a: &FaceMatrix) -> Option<FaceMatrix> {
    let r = |i: usize, j: usize| a[(i, j)];
    let n = a.nrows();
    if a.ncols() != n {
        return None;
    }
    let mut inv = FaceMatrix::zeros(n, n);
    let det = match n {
        1 => {
            inv[(0, 0)] = 1.0 / r(0, 0);
            return Some(inv);
        }
        2 => {
            inv[(0, 0)] = r(1, 1);
            inv[(0, 1)] = -r(0, 1);
            inv[(1, 0)] = -r(1, 0);
            inv[(1, 1)] = r(0, 0);
            r(0, 0) * r(1, 1) - r(0, 1) * r(1, 0)
        }
        3 => {
            inv[(0, 0)] = r(1, 1) * r(2, 2) - r(1, 2) * r(2, 1);
            inv[(1, 0)] = -r(1, 0) * r(2, 2) + r(1, 2) * r(2, 0);
            inv[(2, 0)] = r(1, 0) * r(2, 1) - r(1, 1) * r(2, 0);
            inv[(0, 1)] = -r(0, 1) * r(2, 2) + r(0, 2) * r(2, 1);
            inv[(1, 1)] = r(0, 0) * r(2, 2) - r(0, 2) * r(2, 0);
            inv[(2, 1)] = -r(0, 0) * r(2, 1) + r(0, 1) * r(2, 0);
            inv[(0, 2)] = r(0, 1) * r(1, 2) - r(0, 2) * r(1, 1);
            inv[(1, 2)] = -r(0, 0) * r(1, 2) + r(0, 2) * r(1, 0);
            inv[(2, 2)] = r(0, 0) * r(1, 1) - r(0, 1) * r(1, 0);
            r(0, 0) * inv[(0, 0)] + r(0, 1) * inv[(1, 0)] + r(0, 2) * inv[(2, 0)]
        }
        4 => {
            inv[(0, 0)] = -(r(1, 3) * r(2, 2) * r(3, 1))
                + r(1, 2) * r(2, 3) * r(3, 1)
                + r(1, 3) * r(2, 1) * r(3, 2)
                - r(1, 1) * r(2, 3) * r(3, 2)
                - r(1, 2) * r(2, 1) * r(3, 3)
                + r(1, 1) * r(2, 2) * r(3, 3);
            inv[(0, 1)] = r(0, 3) * r(2, 2) * r(3, 1)
                - r(0, 2) * r(2, 3) * r(3, 1)
                - r(0, 3) * r(2, 1) * r(3, 2)
                + r(0, 1) * r(2, 3) * r(3, 2)
                + r(0, 2) * r(2, 1) * r(3, 3)
                - r(0, 1) * r(2, 2) * r(3, 3);
            inv[(0, 2)] = -(r(0, 3) * r(1, 2) * r(3, 1))
                + r(0, 2) * r(1, 3) * r(3, 1)
                + r(0, 3) * r(1, 1) * r(3, 2)
                - r(0, 1) * r(1, 3) * r(3, 2)
                - r(0, 2) * r(1, 1) * r(3, 3)
                + r(0, 1) * r(1, 2) * r(3, 3);
            inv[(0, 3)] = r(0, 3) * r(1, 2) * r(2, 1)
                - r(0, 2) * r(1, 3) * r(2, 1)
                - r(0, 3) * r(1, 1) * r(2, 2)
                + r(0, 1) * r(1, 3) * r(2, 2)
                + r(0, 2) * r(1, 1) * r(2, 3)
                - r(0, 1) * r(1, 2) * r(2, 3);
            inv[(1, 0)] = r(1, 3) * r(2, 2) * r(3, 0)
                - r(1, 2) * r(2, 3) * r(3, 0)
                - r(1, 3) * r(2, 0) * r(3, 2)
                + r(1, 0) * r(2, 3) * r(3, 2)
                + r(1, 2) * r(2, 0) * r(3, 3)
                - r(1, 0) * r(2, 2) * r(3, 3);
            inv[(1, 1)] = -(r(0, 3) * r(2, 2) * r(3, 0))
                + r(0, 2) * r(2, 3) * r(3, 0)
                + r(0, 3) * r(2, 0) * r(3, 2)
                - r(0, 0) * r(2, 3) * r(3, 2)
                - r(0, 2) * r(2, 0) * r(3, 3)
                + r(0, 0) * r(2, 2) * r(3, 3);
            inv[(1, 2)] = r(0, 3) * r(1, 2) * r(3, 0)
                - r(0, 2) * r(1, 3) * r(3, 0)
                - r(0, 3) * r(1, 0) * r(3, 2)
                + r(0, 0) * r(1, 3) * r(3, 2)
                + r(0, 2) * r(1, 0) * r(3, 3)
                - r(0, 0) * r(1, 2) * r(3, 3);
            inv[(1, 3)] = -(r(0, 3) * r(1, 2) * r(2, 0))
                + r(0, 2) * r(1, 3) * r(2, 0)
                + r(0, 3) * r(1, 0) * r(2, 2)
                - r(0, 0) * r(1, 3) * r(2, 2)
                - r(0, 2) * r(1, 0) * r(2, 3)
                + r(0, 0) * r(1, 2) * r(2, 3);
            inv[(2, 0)] = -(r(1, 3) * r(2, 1) * r(3, 0))
                + r(1, 1) * r(2, 3) * r(3, 0)
                + r(1, 3) * r(2, 0) * r(3, 1)
                - r(1, 0) * r(2, 3) * r(3, 1)
                - r(1, 1) * r(2, 0) * r(3, 3)
                + r(1, 0) * r(2, 1) * r(3, 3);
            inv[(2, 1)] = r(0, 3) * r(2, 1) * r(3, 0)
                - r(0, 1) * r(2, 3) * r(3, 0)
                - r(0, 3) * r(2, 0) * r(3, 1)
                + r(0, 0) * r(2, 3) * r(3, 1)
                + r(0, 1) * r(2, 0) * r(3, 3)
                - r(0, 0) * r(2, 1) * r(3, 3);
            inv[(2, 2)] = -(r(0, 3) * r(1, 1) * r(3, 0))
                + r(0, 1) * r(1, 3) * r(3, 0)
                + r(0, 3) * r(1, 0) * r(3, 1)
                - r(0, 0) * r(1, 3) * r(3, 1)
                - r(0, 1) * r(1, 0) * r(3, 3)
                + r(0, 0) * r(1, 1) * r(3, 3);
            inv[(2, 3)] = r(0, 3) * r(1, 1) * r(2, 0)
                - r(0, 1) * r(1, 3) * r(2, 0)
                - r(0, 3) * r(1, 0) * r(2, 1)
                + r(0, 0) * r(1, 3) * r(2, 1)
                + r(0, 1) * r(1, 0) * r(2, 3)
                - r(0, 0) * r(1, 1) * r(2, 3);
            inv[(3, 0)] = r(1, 2) * r(2, 1) * r(3, 0)
                - r(1, 1) * r(2, 2) * r(3, 0)
                - r(1, 2) * r(2, 0) * r(3, 1)
                + r(1, 0) * r(2, 2) * r(3, 1)
                + r(1, 1) * r(2, 0) * r(3, 2)
                - r(1, 0) * r(2, 1) * r(3, 2);
            inv[(3, 1)] = -(r(0, 2) * r(2, 1) * r(3, 0))
                + r(0, 1) * r(2, 2) * r(3, 0)
                + r(0, 2) * r(2, 0) * r(3, 1)
                - r(0, 0) * r(2, 2) * r(3, 1)
                - r(0, 1) * r(2, 0) * r(3, 2)
                + r(0, 0) * r(2, 1) * r(3, 2);
            inv[(3, 2)] = r(0, 2) * r(1, 1) * r(3, 0)
                - r(0, 1) * r(1, 2) * r(3, 0)
                - r(0, 2) * r(1, 0) * r(3, 1)
                + r(0, 0) * r(1, 2) * r(3, 1)
                + r(0, 1) * r(1, 0) * r(3, 2)
                - r(0, 0) * r(1, 1) * r(3, 2);
            inv[(3, 3)] = -(r(0, 2) * r(1, 1) * r(2, 0))
                + r(0, 1) * r(1, 2) * r(2, 0)
                + r(0, 2) * r(1, 0) * r(2, 1)
                - r(0, 0) * r(1, 2) * r(2, 1)
                - r(0, 1) * r(1, 0) * r(2, 2)
                + r(0, 0) * r(1, 1) * r(2, 2);
            det4(a)
        }
        _ => return None,
    };
    Some(inv.map(|x| x / det))
}
