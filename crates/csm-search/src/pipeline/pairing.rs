//! Stage 8, the order-dependent part: INDEX_MAP updates (MappingCheck), ACTIVE flags and
//! pair creation (No/DirectCheck, `AddPotentialPairing` / `AddPairing`, reference §9–§10.5),
//! applied serially in slave order.

use csm_model::{ConditionId, ConditionIdx, Flag, IndexMap, ModelPart};
use rayon::prelude::*;

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
    /// Robust mode: the nodes ACTIVE before this search's pairing (see [`direct_check_count`]);
    /// `None` in kratos mode.
    pub active_before: Option<&'a [bool]>,
}

/// The ACTIVE flags of every node, for [`direct_check_count`]'s robust rule.
pub(crate) fn active_snapshot(model: &ModelPart) -> Vec<bool> {
    model
        .nodes()
        .flags()
        .iter()
        .map(|f| f.is(Flag::ACTIVE))
        .collect()
}

/// DirectCheck's `AddPotentialPairing` count for one candidate master (reference §10.4): the
/// slave nodes in `node_pass` (they passed the geometric test against this master) become
/// ACTIVE, and the candidate pairs if one of them passed or a node counted as ACTIVE.
///
/// Kratos (`active_before` `None`) counts a node ACTIVE at the moment of the test, including
/// one that an earlier candidate of this very search activated: the pairs then depend on the
/// order of the candidates, which follows the tree and changes when the mesh is rotated or
/// moved (the stability suite found up to 20 pairs of one slave changing). Robust mode counts
/// only the nodes ACTIVE before the search's pairing began (`active_before`): the pairs are
/// the same in any order.
pub(crate) fn direct_check_count(
    flags: &mut [csm_model::Flags],
    nodes: &[csm_model::NodeIdx],
    node_pass: u32,
    active_before: Option<&[bool]>,
) -> bool {
    let mut counted = false;
    for (i, n) in nodes.iter().enumerate() {
        let f = &mut flags[n.index()];
        let was_active = match active_before {
            None => f.is(Flag::ACTIVE),
            Some(before) => before[n.index()],
        };
        if node_pass & (1 << i) != 0 {
            f.set(Flag::ACTIVE, true);
            counted = true;
        } else if was_active {
            counted = true;
        }
    }
    counted
}

/// Updates the INDEX_MAPs of the slaves of `entries` in parallel, each slave's map alone:
/// `entries` holds each slave's (`slave(entry)`) entries consecutively, and
/// `update(map, first, group)` gets a slave's map, the position of its first entry in
/// `entries` and its entries, in order.
pub(crate) fn update_index_maps<T: Sync>(
    model: &mut ModelPart,
    entries: &[T],
    slave: impl Fn(&T) -> ConditionIdx + Sync,
    update: impl Fn(&mut IndexMap, usize, &[T]) + Sync,
) {
    if entries.is_empty() {
        return;
    }
    let starts: Vec<usize> = (0..entries.len())
        .into_par_iter()
        .filter(|&k| k == 0 || slave(&entries[k]) != slave(&entries[k - 1]))
        .collect();
    // Each group's slave, by condition index.
    let mut at: Vec<(u32, usize)> = (starts.par_iter().enumerate())
        .map(|(g, &k)| (slave(&entries[k]).0, g))
        .collect();
    // (Usually in order already: ids and indices of a mesh read ascend together.)
    if !at.par_windows(2).all(|w| w[0].0 < w[1].0) {
        at.par_sort_unstable();
    }
    update_listed_maps(model, &at, |map, &g| {
        let end = starts.get(g + 1).copied().unwrap_or(entries.len());
        update(map, starts[g], &entries[starts[g]..end]);
    });
}

/// Calls `update(map, value)` on the INDEX_MAP of each condition of `at` (condition index and
/// a value, ascending and distinct indices), in parallel. The maps are taken in blocks of
/// consecutive conditions, and only the listed ones are visited: a step that updates a few
/// thousand maps does not walk every condition's.
pub(crate) fn update_listed_maps<V: Sync>(
    model: &mut ModelPart,
    at: &[(u32, V)],
    update: impl Fn(&mut IndexMap, &V) + Sync,
) {
    debug_assert!(at.windows(2).all(|w| w[0].0 < w[1].0));
    const MAPS: usize = 4096;
    (model.index_maps_mut().par_chunks_mut(MAPS))
        .enumerate()
        .for_each(|(b, maps)| {
            let first = b * MAPS;
            let from = at.partition_point(|(c, _)| (*c as usize) < first);
            let to = at.partition_point(|(c, _)| (*c as usize) < first + maps.len());
            for (c, value) in &at[from..to] {
                update(&mut maps[*c as usize - first], value);
            }
        });
}

/// MappingCheck's CheckCondition for the candidate master `m` of slave `s` (id `slave_id`):
/// no reverse pair (step 2: when the roles are not predefined or the candidate is itself
/// slave-side, a master whose INDEX_MAP already holds the slave), and not the same stored
/// normal. It reads `m`'s INDEX_MAP: the order of the slaves matters only where a candidate
/// is itself one of the slaves whose maps the pass writes.
pub(crate) fn mapping_check_keeps(
    model: &ModelPart,
    cx: &PairingContext<'_>,
    (s, slave_id): (ConditionIdx, ConditionId),
    m: ConditionIdx,
) -> bool {
    let p = cx.params;
    let master_flags = model.conditions().flags()[m.index()];
    if (!p.predefined_master_slave || master_flags.is(Flag::SLAVE) != cx.inverted)
        && model.index_map(m).contains(slave_id)
    {
        return false;
    }
    let normals = model.condition_normals();
    !same_stored_normal(&normals[s.index()], &normals[m.index()])
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
                if mapping_check_keeps(model, cx, (s, slave_id), c.master) {
                    let master_id = ConditionId(model.conditions().ids()[c.master.index()]);
                    model.index_map_mut(s).add_id(master_id);
                }
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
                    _ => direct_check_count(
                        model.nodes_mut().flags_mut(),
                        &nodes,
                        c.node_pass,
                        cx.active_before,
                    ),
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
