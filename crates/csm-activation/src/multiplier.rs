//! The Lagrange-multiplier guesses of the activation (§10.6): Simple's penalty guess
//! `ε · A · g` and Advanced's predict/correct linear regression, and the SLIP rule.

use csm_geometry::math::{EPS, Real, Vector};
use csm_model::{Flag, ModelPart, NodeIdx, ScalarVar, VectorVar};

/// Kratos' `TypeSolution`, read from the nodal variables the model carries (reference §4.3
/// step 8): which multiplier the guesses write.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MultiplierKind {
    /// `VECTOR_LAGRANGE_MULTIPLIER` (frictionless components, frictional).
    Vector,
    /// `LAGRANGE_MULTIPLIER_CONTACT_PRESSURE` (ALM frictionless).
    NormalContactStress,
    /// `SCALAR_LAGRANGE_MULTIPLIER`.
    Scalar,
    /// No multiplier (penalty or other formulations): nothing is written.
    None,
}

impl MultiplierKind {
    /// The kind of `model`'s nodal data, in Kratos' order of precedence.
    pub fn of(model: &ModelPart) -> MultiplierKind {
        let data = model.nodal_data();
        if data
            .vector(VectorVar::VectorLagrangeMultiplier, 0)
            .is_some()
        {
            MultiplierKind::Vector
        } else if data
            .scalar(ScalarVar::LagrangeMultiplierContactPressure, 0)
            .is_some()
        {
            MultiplierKind::NormalContactStress
        } else if data
            .scalar(ScalarVar::ScalarLagrangeMultiplier, 0)
            .is_some()
        {
            MultiplierKind::Scalar
        } else {
            MultiplierKind::None
        }
    }
}

/// How the multipliers are guessed when nodes are activated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MultiplierSettings {
    /// Which multiplier is written.
    pub kind: MultiplierKind,
    /// `ProcessInfo[INITIAL_PENALTY]` (Simple's `ε = INITIAL_PENALTY / SCALE_FACTOR`); `None`
    /// when the process info has none.
    pub initial_penalty: Option<Real>,
    /// `ProcessInfo[SCALE_FACTOR]`; `None` when absent.
    pub scale_factor: Option<Real>,
    /// Advanced: `predict_correct_lagrange_multiplier` (a C++-only key).
    pub predict_correct: bool,
    /// The root model part is SLIP (frictional contact): activated nodes follow the SLIP rule.
    pub slip: bool,
    /// `pure_slip`.
    pub pure_slip: bool,
    /// Robust mode: an absent penalty or scale factor skips Simple's guess instead of writing
    /// NaN (Q25), and the regression needs two points with distinct weighted gaps (Q26).
    pub guarded: bool,
}

impl Default for MultiplierSettings {
    /// No multiplier, no penalty, no prediction, no SLIP, Kratos' (unguarded) arithmetic.
    fn default() -> MultiplierSettings {
        MultiplierSettings {
            kind: MultiplierKind::None,
            initial_penalty: None,
            scale_factor: None,
            predict_correct: false,
            slip: false,
            pure_slip: false,
            guarded: false,
        }
    }
}

/// Simple's `ε` (`INITIAL_PENALTY / SCALE_FACTOR`): NaN when either is absent (Kratos reads 0
/// for both, Q25), or `None` in guarded mode.
pub(crate) fn penalty(settings: &MultiplierSettings) -> Option<Real> {
    match (settings.initial_penalty, settings.scale_factor) {
        (Some(p), Some(s)) if !settings.guarded || (s != 0.0 && (p / s).is_finite()) => Some(p / s),
        _ if settings.guarded => None,
        (p, s) => Some(p.unwrap_or(0.0) / s.unwrap_or(0.0)),
    }
}

/// The regression `LM ≈ a + b · WEIGHTED_GAP` over the nodes `points` (those ACTIVE before the
/// activation loop): `y` = `LAGRANGE_MULTIPLIER_CONTACT_PRESSURE`, or
/// `VECTOR_LAGRANGE_MULTIPLIER · NORMAL`. Kratos divides by `n Σx² − (Σx)²` unguarded (NaN or
/// inf with fewer than two points, Q26); guarded mode returns `None` there.
pub(crate) fn regression(
    model: &ModelPart,
    points: &[NodeIdx],
    kind: MultiplierKind,
    guarded: bool,
) -> Option<(Real, Real)> {
    let data = model.nodal_data();
    let wg = data.scalar(ScalarVar::WeightedGap, 0);
    let y_of = |i: usize| -> Real {
        match kind {
            MultiplierKind::NormalContactStress => data
                .scalar(ScalarVar::LagrangeMultiplierContactPressure, 0)
                .map_or(0.0, |c| c[i]),
            _ => {
                let lm = data
                    .vector(VectorVar::VectorLagrangeMultiplier, 0)
                    .map_or_else(Vector::zeros, |c| c[i]);
                let n = data
                    .vector(VectorVar::Normal, 0)
                    .map_or_else(Vector::zeros, |c| c[i]);
                lm.dot(&n)
            }
        }
    };
    let (mut sx, mut sy, mut sxx, mut sxy) = (0.0, 0.0, 0.0, 0.0);
    for n in points {
        let i = n.index();
        let x = wg.map_or(0.0, |c| c[i]);
        let y = y_of(i);
        sx += x;
        sy += y;
        sxx += x * x;
        sxy += x * y;
    }
    let n = points.len() as Real;
    let den = n * sxx - sx * sx;
    if guarded && (points.len() < 2 || den.abs() <= EPS * (n * sxx).abs() || den == 0.0) {
        return None;
    }
    let a = (sy * sxx - sx * sxy) / den;
    let b = (n * sxy - sx * sy) / den;
    Some((a, b))
}

/// Simple's guess on an activated node `i` with gap `g < 0`: `ε · A · g` (times the historical
/// NORMAL for the vector multiplier).
pub(crate) fn penalty_guess(
    model: &mut ModelPart,
    i: usize,
    g: Real,
    eps: Real,
    kind: MultiplierKind,
) {
    let area = model
        .nodal_data()
        .scalar(ScalarVar::NodalArea, 0)
        .map_or(1.0, |c| c[i]);
    let value = eps * area * g;
    let normal = model
        .nodal_data()
        .vector(VectorVar::Normal, 0)
        .map_or_else(Vector::zeros, |c| c[i]);
    let data = model.nodal_data_mut();
    match kind {
        MultiplierKind::Vector => {
            if let Some(c) = data.vector_mut(VectorVar::VectorLagrangeMultiplier, 0) {
                c[i] = normal * value;
            }
        }
        MultiplierKind::NormalContactStress => {
            if let Some(c) = data.scalar_mut(ScalarVar::LagrangeMultiplierContactPressure, 0) {
                c[i] = value;
            }
        }
        MultiplierKind::Scalar => {
            if let Some(c) = data.scalar_mut(ScalarVar::ScalarLagrangeMultiplier, 0) {
                c[i] = value;
            }
        }
        MultiplierKind::None => {}
    }
}

/// Advanced's predict/correct on node `i`: `p = a + b · WEIGHTED_GAP`; the multiplier becomes
/// `p` (or `p · NORMAL`) where `p < 0`, else 0. Scalar and penalty formulations: nothing.
pub(crate) fn predict_correct(
    model: &mut ModelPart,
    i: usize,
    (a, b): (Real, Real),
    kind: MultiplierKind,
) {
    let data = model.nodal_data();
    let wg = data.scalar(ScalarVar::WeightedGap, 0).map_or(0.0, |c| c[i]);
    let normal = data
        .vector(VectorVar::Normal, 0)
        .map_or_else(Vector::zeros, |c| c[i]);
    let p = a + b * wg;
    let p = if p < 0.0 { p } else { 0.0 };
    let data = model.nodal_data_mut();
    match kind {
        MultiplierKind::NormalContactStress => {
            if let Some(c) = data.scalar_mut(ScalarVar::LagrangeMultiplierContactPressure, 0) {
                c[i] = p;
            }
        }
        MultiplierKind::Vector => {
            if let Some(c) = data.vector_mut(VectorVar::VectorLagrangeMultiplier, 0) {
                c[i] = normal * p;
            }
        }
        MultiplierKind::Scalar | MultiplierKind::None => {}
    }
}

/// The SLIP rule of `SetActiveNode` (§10.4, without the multiplier test): SLIP := true when the
/// node's friction coefficient is below ε (csm carries no nodal FRICTION_COEFFICIENT: 0) or
/// `pure_slip`; otherwise SLIP := false, but only where SLIP was undefined. Vector multipliers
/// only.
pub(crate) fn slip_rule(model: &mut ModelPart, i: usize, settings: &MultiplierSettings) {
    if !settings.slip || settings.kind != MultiplierKind::Vector {
        return;
    }
    let friction: Real = 0.0;
    let f = &mut model.nodes_mut().flags_mut()[i];
    if friction < EPS || settings.pure_slip {
        f.set(Flag::SLIP, true);
    } else if !f.is_defined(Flag::SLIP) {
        f.set(Flag::SLIP, false);
    }
}
