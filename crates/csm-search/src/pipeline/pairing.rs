//! Stage 8, the order-dependent part: INDEX_MAP updates (MappingCheck), ACTIVE flags and
//! pair creation (No/DirectCheck, `AddPotentialPairing` / `AddPairing`, reference §9–§10.5),
//! applied serially in slave order.

use csm_model::{ConditionId, ConditionIdx, Flag, ModelPart};

use super::candidates::{Candidate, slave_search_nodes};
use super::filters::same_stored_normal;
use crate::setup::{CheckGap, SearchParameters};

/// A pair created by the search (Kratos' paired condition in `ComputingContact`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PairedCondition {
    /// Id of the paired condition (after the largest condition id; csm numbers them in slave
    /// id order, then master id order — Kratos' ids follow its map order, DESIGN.md §2).
    pub id: ConditionId,
    /// The slave condition.
    pub slave: ConditionIdx,
    /// The master condition.
    pub master: ConditionIdx,
    /// ACTIVE flag of the paired condition.
    pub active: bool,
    /// ISOLATED flag: the weighted gap (ComputeWeightedReaction) found no overlap above
    /// 1e-5 of the slave's area. False at creation (Kratos' `Initialize` resets it) and left
    /// so where the weighted gap does not run (Simple activation, No/DirectCheck: nothing
    /// reads it there).
    pub isolated: bool,
}

/// What the serial pass needs besides the model.
pub(crate) struct PairingContext<'a> {
    pub params: &'a SearchParameters,
    pub inverted: bool,
    pub slave_nodes: usize,
}

/// Applies the candidates of slave `s` in order; returns the (slave, master) pairs created.
pub(crate) fn apply_candidates(
    model: &mut ModelPart,
    cx: &PairingContext<'_>,
    s: ConditionIdx,
    candidates: &[Candidate],
    created: &mut Vec<(ConditionIdx, ConditionIdx)>,
) {
    let p = cx.params;
    match p.check_gap {
        CheckGap::MappingCheck => {
            let slave_id = ConditionId(model.conditions().ids()[s.index()]);
            for c in candidates {
                let m = c.master;
                let master_flags = model.conditions().flags()[m.index()];
                // CheckCondition step 2: no reverse pair when the roles are not predefined or
                // the candidate is itself slave-side.
                if (!p.predefined_master_slave || master_flags.is(Flag::SLAVE) != cx.inverted)
                    && model.index_map(m).contains(slave_id)
                {
                    continue;
                }
                let normals = model.condition_normals();
                if same_stored_normal(&normals[s.index()], &normals[m.index()]) {
                    continue;
                }
                let master_id = ConditionId(model.conditions().ids()[m.index()]);
                model.index_map_mut(s).add_id(master_id);
            }
        }
        CheckGap::NoCheck | CheckGap::DirectCheck => {
            let nodes: Vec<_> = slave_search_nodes(model, s, cx.slave_nodes).to_vec();
            for c in candidates {
                let counted = match p.check_gap {
                    CheckGap::NoCheck => {
                        for n in &nodes {
                            model.nodes_mut().flags_mut()[n.index()].set(Flag::ACTIVE, true);
                        }
                        true
                    }
                    _ => {
                        let mut counted = false;
                        for (i, n) in nodes.iter().enumerate() {
                            let flags = &mut model.nodes_mut().flags_mut()[n.index()];
                            if flags.is(Flag::ACTIVE) {
                                counted = true;
                            } else if c.node_pass & (1 << i) != 0 {
                                flags.set(Flag::ACTIVE, true);
                                counted = true;
                            }
                        }
                        counted
                    }
                };
                if counted {
                    let master_id = ConditionId(model.conditions().ids()[c.master.index()]);
                    model.index_map_mut(s).add_id(master_id);
                    if p.create_auxiliar_conditions {
                        created.push((s, c.master));
                    }
                }
            }
        }
    }
}
