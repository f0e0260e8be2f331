//! ComputeActiveInactiveNodes (§10.6): Simple and Advanced activation.

use csm_geometry::math::{Real, Vector};
use csm_model::{Flag, ModelPart, PartIdx, ScalarVar, VectorVar};

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
}

/// Kratos' `ComputeActiveInactiveNodes` on the nodes of `sub` with `SLAVE == !inverted`:
/// `SetActiveNode` (ACTIVE, MARKER) or `SetInactiveNode` (on non-MARKER nodes: ACTIVE := false
/// with the Lagrange multiplier zeroed, and `NORMAL_GAP := 0`, Q24). Returns the number of
/// active nodes.
pub fn compute_active_inactive_nodes(
    model: &mut ModelPart,
    sub: PartIdx,
    settings: &ActivationSettings,
) -> usize {
    let o = !settings.inverted;
    let nodes: Vec<_> = model
        .part(sub)
        .nodes()
        .iter()
        .copied()
        .filter(|n| model.nodes().flags()[n.index()].is(Flag::SLAVE) == o)
        .collect();
    let data = model.nodal_data();
    let gap = data.scalar(ScalarVar::NormalGap, 0).map(<[Real]>::to_vec);
    let h = data.scalar(ScalarVar::NodalH, 0).map(<[Real]>::to_vec);
    let area = data.scalar(ScalarVar::NodalArea, 0).map(<[Real]>::to_vec);
    let wg = data.scalar(ScalarVar::WeightedGap, 0).map(<[Real]>::to_vec);
    let wg_old = data.scalar(ScalarVar::WeightedGap, 1).map(<[Real]>::to_vec);
    let mut inactive = Vec::new();
    let mut n_active = 0;
    for n in nodes {
        let i = n.index();
        let flags = model.nodes().flags()[i];
        let g = gap.as_ref().map_or(0.0, |c| c[i]);
        let active = match settings.rule {
            ActivationRule::Simple => g < GAP_THRESHOLD * h.as_ref().map_or(0.0, |c| c[i]),
            ActivationRule::Advanced {
                static_check_movement,
                consider_gap_threshold,
                distance_threshold,
                active_check_factor,
            } => {
                let mut l = distance_threshold * active_check_factor;
                let has_wg = wg.is_some();
                let w = wg.as_ref().map_or(0.0, |c| c[i]);
                let a = area.as_ref().map_or(1.0, |c| c[i]);
                let aux = flags.is(Flag::ACTIVE) && has_wg && w / a < l;
                if static_check_movement && has_wg {
                    let old = wg_old.as_ref().map_or(0.0, |c| c[i]);
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
        let f = &mut model.nodes_mut().flags_mut()[i];
        if active {
            f.set(Flag::ACTIVE, true);
            f.set(Flag::MARKER, true);
            n_active += 1;
        } else if !f.is(Flag::MARKER) {
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
    n_active
}
