//! ComputeActiveInactiveNodes (§10.6): Simple and Advanced activation.

use csm_geometry::math::{EPS, Real, Vector};
use csm_model::{Flag, ModelPart, PartIdx, ScalarVar, VectorVar};
use rayon::prelude::*;

use crate::multiplier::{
    MultiplierKind, MultiplierSettings, penalty, penalty_guess, predict_correct, regression,
    slip_rule,
};

/// The base (and Simple) gap threshold factor: active iff `NORMAL_GAP < 2e-3 · NODAL_H`.
pub const GAP_THRESHOLD: Real = 2.0e-3;
/// The Advanced minimum length with `consider_gap_threshold`.
pub const ADVANCED_GAP_THRESHOLD: Real = 2.0e-4;
/// The relative tolerance of Advanced's `static_check_movement`.
const STATIC_CHECK_TOLERANCE: Real = 1e-3;

/// Which search class activates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ActivationRule {
    /// `SimpleContactSearch` (the base rule): `NORMAL_GAP < 2e-3 · NODAL_H`.
    Simple,
    /// `AdvancedContactSearch`: `NORMAL_GAP < L || (ACTIVE && WEIGHTED_GAP / NODAL_AREA < L)`
    /// with `L = DISTANCE_THRESHOLD · ACTIVE_CHECK_FACTOR` (raised to 2e-4 by
    /// `static_check_movement` + `consider_gap_threshold` on a node that does not close).
    Advanced {
        /// `static_check_movement`.
        static_check_movement: bool,
        /// `consider_gap_threshold`.
        consider_gap_threshold: bool,
        /// `ProcessInfo[DISTANCE_THRESHOLD]` (as set by the Advanced CheckPairing).
        distance_threshold: Real,
        /// `ProcessInfo[ACTIVE_CHECK_FACTOR]`.
        active_check_factor: Real,
    },
}

/// Settings of [`compute_active_inactive_nodes`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ActivationSettings {
    /// Simple or Advanced.
    pub rule: ActivationRule,
    /// `inverted_search`: the nodes activated are those with `SLAVE == !inverted`.
    pub inverted: bool,
    /// Robust mode: `SetInactiveNode` keeps the mapped gap instead of writing 0 (Q24).
    pub keep_gap_on_inactive: bool,
    /// The multiplier guesses and the SLIP rule.
    pub multiplier: MultiplierSettings,
}

/// What [`compute_active_inactive_nodes`] did.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ActivationReport {
    /// Nodes activated.
    pub active: usize,
    /// Advanced predict/correct: the regression `LM ≈ a + b · WEIGHTED_GAP` used, `None` when it
    /// was not run or (guarded) had fewer than two distinct points.
    pub regression: Option<(Real, Real)>,
    /// What the caller should tell the user: NaN multipliers written in Kratos' arithmetic
    /// (Q25, Q26) or guesses skipped by the guards.
    pub warnings: Vec<String>,
}

/// Kratos' `ComputeActiveInactiveNodes` on the nodes of `sub` with `SLAVE == !inverted`:
/// `SetActiveNode` (ACTIVE, MARKER, the SLIP rule; Simple also guesses the multiplier
/// `ε · A · g` on penetrating nodes; Advanced with predict/correct sets it from the regression
/// over the nodes that were ACTIVE before) or `SetInactiveNode` (on non-MARKER nodes:
/// ACTIVE := false with the Lagrange multiplier zeroed, and `NORMAL_GAP := 0`, Q24).
pub fn compute_active_inactive_nodes(
    model: &mut ModelPart,
    sub: PartIdx,
    settings: &ActivationSettings,
) -> ActivationReport {
    let mut report = ActivationReport::default();
    let ms = &settings.multiplier;
    let predicting = matches!(settings.rule, ActivationRule::Advanced { .. }) && ms.predict_correct;
    if predicting {
        // Over all ContactSub nodes ACTIVE before this loop.
        let before: Vec<_> = model
            .part(sub)
            .nodes()
            .iter()
            .copied()
            .filter(|n| model.nodes().flags()[n.index()].is(Flag::ACTIVE))
            .collect();
        report.regression = regression(model, &before, ms.kind, ms.guarded);
        match report.regression {
            None => report.warnings.push(format!(
                "predict_correct_lagrange_multiplier: the regression needs two active nodes with \
                 distinct weighted gaps ({} active): the multipliers are left as they are (robust \
                 guard of Q26)",
                before.len()
            )),
            Some((a, b)) if !(a.is_finite() && b.is_finite()) => report.warnings.push(format!(
                "predict_correct_lagrange_multiplier: the regression over {} active node(s) is \
                 not finite (Kratos' unguarded division, Q26); the predicted multipliers are 0",
                before.len()
            )),
            Some(_) => {}
        }
    }
    let simple_penalty = if settings.rule == ActivationRule::Simple {
        penalty(ms)
    } else {
        None
    };
    let mut penalty_nan_reported = false;
    let o = !settings.inverted;
    let nodes: Vec<_> = model
        .part(sub)
        .nodes()
        .par_iter()
        .copied()
        .filter(|n| model.nodes().flags()[n.index()].is(Flag::SLAVE) == o)
        .collect();
    // Every node's decision reads the values before any node is changed: a node changes only
    // its own flags and values, after its decision. So the decisions come first, read in
    // place (no copies of the nodal columns), and the changes after.
    let decisions: Vec<(bool, Real)> = {
        let data = model.nodal_data();
        let gap = data.scalar(ScalarVar::NormalGap, 0);
        let h = data.scalar(ScalarVar::NodalH, 0);
        let area = data.scalar(ScalarVar::NodalArea, 0);
        let wg = data.scalar(ScalarVar::WeightedGap, 0);
        let wg_old = data.scalar(ScalarVar::WeightedGap, 1);
        let flags = model.nodes().flags();
        nodes
            .par_iter()
            .map(|n| {
                let i = n.index();
                let g = gap.map_or(0.0, |c| c[i]);
                let active = match settings.rule {
                    ActivationRule::Simple => g < GAP_THRESHOLD * h.map_or(0.0, |c| c[i]),
                    ActivationRule::Advanced {
                        static_check_movement,
                        consider_gap_threshold,
                        distance_threshold,
                        active_check_factor,
                    } => {
                        let mut l = distance_threshold * active_check_factor;
                        let has_wg = wg.is_some();
                        let w = wg.map_or(0.0, |c| c[i]);
                        let a = area.map_or(1.0, |c| c[i]);
                        let aux = flags[i].is(Flag::ACTIVE) && has_wg && w / a < l;
                        if static_check_movement && has_wg {
                            let old = wg_old.map_or(0.0, |c| c[i]);
                            if w - old > -w.abs() * STATIC_CHECK_TOLERANCE
                                && consider_gap_threshold
                                && l < ADVANCED_GAP_THRESHOLD
                            {
                                l = ADVANCED_GAP_THRESHOLD;
                            }
                        }
                        g < l || aux
                    }
                };
                (active, g)
            })
            .collect()
    };
    let mut inactive = Vec::new();
    let mut n_active = 0;
    for (n, (active, g)) in nodes.into_iter().zip(decisions) {
        let i = n.index();
        if active {
            n_active += 1;
            if let Some(ab) = report.regression.filter(|_| predicting) {
                // Advanced predict/correct: "correct" an active node, "predict" a new one.
                model.nodes_mut().flags_mut()[i].set(Flag::ACTIVE, true);
                if ms.slip && ms.kind == MultiplierKind::Vector {
                    let lm = model
                        .nodal_data()
                        .vector(VectorVar::VectorLagrangeMultiplier, 0)
                        .map_or(0.0, |c| c[i].norm());
                    if lm < EPS {
                        slip_rule(model, i, ms);
                    }
                } else {
                    predict_correct(model, i, ab, ms.kind);
                }
                model.nodes_mut().flags_mut()[i].set(Flag::MARKER, true);
                continue;
            }
            let f = &mut model.nodes_mut().flags_mut()[i];
            f.set(Flag::ACTIVE, true);
            f.set(Flag::MARKER, true);
            slip_rule(model, i, ms);
            if settings.rule == ActivationRule::Simple && g < 0.0 && ms.kind != MultiplierKind::None
            {
                match simple_penalty {
                    Some(eps) => {
                        if eps.is_nan() && !penalty_nan_reported {
                            penalty_nan_reported = true;
                            report.warnings.push(
                                "Simple activation: INITIAL_PENALTY or SCALE_FACTOR is not in the \
                                 process info, so Kratos' multiplier guess ε·A·g is NaN (Q25)"
                                    .to_owned(),
                            );
                        }
                        penalty_guess(model, i, g, eps, ms.kind);
                    }
                    None if !penalty_nan_reported => {
                        penalty_nan_reported = true;
                        report.warnings.push(
                            "Simple activation: no usable INITIAL_PENALTY / SCALE_FACTOR in the \
                             process info (csm does not emulate Kratos' \
                             ALMVariablesCalculationProcess; set them in `process_info`): the \
                             multiplier guess ε·A·g is skipped"
                                .to_owned(),
                        );
                    }
                    None => {}
                }
            }
            continue;
        }
        let f = &mut model.nodes_mut().flags_mut()[i];
        if !f.is(Flag::MARKER) {
            if f.is(Flag::ACTIVE) {
                f.set(Flag::ACTIVE, false);
                inactive.push(n);
            }
            if !settings.keep_gap_on_inactive
                && let Some(col) = model.nodal_data_mut().scalar_mut(ScalarVar::NormalGap, 0)
            {
                col[i] = 0.0;
            }
        }
    }
    let data = model.nodal_data_mut();
    if let Some(col) = data.scalar_mut(ScalarVar::LagrangeMultiplierContactPressure, 0) {
        for n in &inactive {
            col[n.index()] = 0.0;
        }
    }
    if let Some(col) = data.vector_mut(VectorVar::VectorLagrangeMultiplier, 0) {
        for n in &inactive {
            col[n.index()] = Vector::zeros();
        }
    }
    if let Some(col) = data.scalar_mut(ScalarVar::ScalarLagrangeMultiplier, 0) {
        for n in &inactive {
            col[n.index()] = 0.0;
        }
    }
    report.active = n_active;
    report
}
