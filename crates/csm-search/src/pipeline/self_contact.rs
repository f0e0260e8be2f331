//! Roles decided automatically (`assume_master_slave` empty, `predefined_master_slave: false`;
//! reference §12): Kratos' `SelfContactUtilities::ComputeSelfContactPairing`, which turns the
//! INDEX_MAPs of a pre-search over every condition into SLAVE/MASTER/ACTIVE flags, and
//! `NotPredefinedMasterSlave`, which flags both sides of the maps the main search left.
//!
//! Both only read and write flags and INDEX_MAPs of the conditions of one part (`ContactSub`)
//! and the flags of their nodes. Their results depend only on the connectivity and the maps,
//! never on coordinates or map order (reference §20.6).

use std::collections::HashMap;

use csm_model::{ConditionId, ConditionIdx, Flag, ModelPart, PartIdx};

use crate::error::{Error, ErrorKind};

/// The conditions of `sub` in container (id) order.
fn conditions_in_order(model: &ModelPart, sub: PartIdx) -> Vec<ConditionIdx> {
    let ids = model.conditions().ids();
    let mut conditions = model.part(sub).conditions().to_vec();
    conditions.sort_by_key(|c| ids[c.index()]);
    conditions
}

/// The boundary entities of a condition as sorted node-id lists, in Kratos'
/// `GenerateBoundariesEntities` order: a triangle's edges (1,2),(2,0),(0,1) (each opposite
/// its node, as Kratos' `GenerateEdges`; the reference's (0,1),(1,2),(2,0) gives another walk
/// and, on Kratos' self-contact mesh, other roles), a quadrilateral's (0,1),(1,2),(2,3),(3,0),
/// a line's two end points. Quadratic faces by their corners (their mid nodes come with them).
fn boundaries(model: &ModelPart, c: ConditionIdx) -> Vec<Vec<u32>> {
    const TRIANGLE: [[usize; 2]; 3] = [[1, 2], [2, 0], [0, 1]];
    const QUADRILATERAL: [[usize; 2]; 4] = [[0, 1], [1, 2], [2, 3], [3, 0]];
    let conditions = model.conditions();
    let kind = conditions.kind(c.index());
    let node_ids = model.nodes().ids();
    let nodes = conditions.nodes(c.index());
    let id = |local: usize| node_ids[nodes[local].index()];
    if kind.local_dim() == 1 {
        return vec![vec![id(0)], vec![id(1)]];
    }
    let edges: &[[usize; 2]] = if kind.edges().len() == 3 {
        &TRIANGLE
    } else {
        &QUADRILATERAL
    };
    edges
        .iter()
        .map(|&[a, b]| {
            let (a, b) = (id(a), id(b));
            vec![a.min(b), a.max(b)]
        })
        .collect()
}

/// The walk order of [`compute_self_contact_pairing`] (positions in `conditions`): from the
/// first condition, each next one is the first not yet placed neighbour (sharing a boundary
/// entity) of the condition placed k-th, or else the first not yet placed in container order.
fn adjacency_order(model: &ModelPart, conditions: &[ConditionIdx]) -> Vec<usize> {
    let n = conditions.len();
    if n == 0 {
        return Vec::new();
    }
    // Every condition but the first is entered, in container order.
    let mut by_boundary: HashMap<Vec<u32>, Vec<usize>> = HashMap::new();
    for (k, &c) in conditions.iter().enumerate().skip(1) {
        for b in boundaries(model, c) {
            by_boundary.entry(b).or_default().push(k);
        }
    }
    let mut placed = vec![false; n];
    let mut order = Vec::with_capacity(n);
    order.push(0);
    placed[0] = true;
    let mut next_unplaced = 1;
    let mut k = 0;
    while order.len() < n {
        let current = conditions[order[k]];
        let neighbour = boundaries(model, current).iter().find_map(|b| {
            by_boundary
                .get(b)
                .and_then(|list| list.iter().copied().find(|&o| !placed[o]))
        });
        let chosen = match neighbour {
            Some(o) => o,
            None => {
                while placed[next_unplaced] {
                    next_unplaced += 1;
                }
                next_unplaced
            }
        };
        placed[chosen] = true;
        order.push(chosen);
        k += 1;
    }
    order
}

/// Sets `flag := value` and `other := !value` on a condition and its nodes.
fn set_role(model: &mut ModelPart, c: ConditionIdx, slave: bool) {
    let (on, off) = if slave {
        (Flag::SLAVE, Flag::MASTER)
    } else {
        (Flag::MASTER, Flag::SLAVE)
    };
    let f = &mut model.conditions_mut().flags_mut()[c.index()];
    f.set(on, true);
    f.set(off, false);
    let nodes = model.conditions().nodes(c.index()).to_vec();
    let node_flags = model.nodes_mut().flags_mut();
    for n in nodes {
        node_flags[n.index()].set(on, true);
        node_flags[n.index()].set(off, false);
    }
}

/// `ComputeSelfContactPairing` (reference §12.2) on the conditions of `sub`, whose INDEX_MAPs
/// hold the candidates of the pre-search:
/// 1. SLAVE and MASTER are reset (undefined) on every node and condition, ACTIVE on every
///    condition;
/// 2. the conditions are walked in adjacency order; a MASTER condition's map is cleared; a
///    condition with candidates makes each candidate master whose nodes are all MASTER or
///    undefined (its map cleared), drops the candidates that cannot be (some node already
///    slave), keeps those that share a node with it or are already master, and becomes SLAVE
///    if any candidate is left;
/// 3. a condition whose nodes are all SLAVE or all MASTER becomes ACTIVE; any other becomes
///    inactive MASTER (it shares slave and master nodes).
///
/// Fails when a condition has more SLAVE and MASTER nodes together than nodes (Kratos' "The
/// MASTER/SLAVE flags are inconsistent"; the walk above never produces that).
pub(crate) fn compute_self_contact_pairing(
    model: &mut ModelPart,
    sub: PartIdx,
) -> Result<(), Error> {
    let conditions = conditions_in_order(model, sub);
    // 1. Reset.
    for n in model.part(sub).nodes().to_vec() {
        let f = &mut model.nodes_mut().flags_mut()[n.index()];
        f.reset(Flag::SLAVE);
        f.reset(Flag::MASTER);
    }
    for &c in &conditions {
        let f = &mut model.conditions_mut().flags_mut()[c.index()];
        f.reset(Flag::SLAVE);
        f.reset(Flag::MASTER);
        f.reset(Flag::ACTIVE);
    }
    // 2. The walk.
    let node_ids = model.nodes().ids().to_vec();
    for k in adjacency_order(model, &conditions) {
        let c = conditions[k];
        if model.conditions().flags()[c.index()].is(Flag::MASTER) {
            model.index_map_mut(c).clear();
            continue;
        }
        if model.index_map(c).is_empty() {
            continue;
        }
        let own: Vec<u32> = model
            .conditions()
            .nodes(c.index())
            .iter()
            .map(|n| node_ids[n.index()])
            .collect();
        let candidates: Vec<ConditionId> = model.index_map(c).masters().collect();
        let mut dropped = Vec::new();
        for m_id in candidates {
            let Some(m) = model
                .conditions()
                .index_of(m_id.get())
                .map(|i| ConditionIdx(i as u32))
            else {
                return Err(ErrorKind::Model(format!(
                    "self-contact: condition {m_id} in the INDEX_MAP of condition {} does not \
                     exist",
                    model.conditions().ids()[c.index()]
                ))
                .into());
            };
            if model.conditions().flags()[m.index()].is(Flag::MASTER) {
                continue;
            }
            let m_nodes = model.conditions().nodes(m.index());
            if m_nodes.iter().any(|n| own.contains(&node_ids[n.index()])) {
                continue;
            }
            let can_be_master = m_nodes
                .iter()
                .all(|n| model.nodes().flags()[n.index()].get(Flag::MASTER) != Some(false));
            if can_be_master {
                model.index_map_mut(m).clear();
                set_role(model, m, false);
            } else {
                dropped.push(m_id);
            }
        }
        let map = model.index_map_mut(c);
        for m_id in dropped {
            map.remove_id(m_id);
        }
        if !map.is_empty() {
            set_role(model, c, true);
        }
    }
    // 3. Isolate the conditions with mixed nodes.
    for &c in &conditions {
        let nodes = model.conditions().nodes(c.index());
        let node_flags = model.nodes().flags();
        let masters = nodes
            .iter()
            .filter(|n| node_flags[n.index()].is(Flag::MASTER))
            .count();
        let slaves = nodes
            .iter()
            .filter(|n| node_flags[n.index()].is(Flag::SLAVE))
            .count();
        if masters + slaves > nodes.len() {
            return Err(ErrorKind::Model(format!(
                "self-contact: condition {} has {slaves} SLAVE and {masters} MASTER nodes out of \
                 {} (\"The MASTER/SLAVE flags are inconsistent\")",
                model.conditions().ids()[c.index()],
                nodes.len()
            ))
            .into());
        }
        let uniform = slaves == nodes.len() || masters == nodes.len();
        let f = &mut model.conditions_mut().flags_mut()[c.index()];
        if uniform {
            f.set(Flag::ACTIVE, true);
        } else {
            f.set(Flag::ACTIVE, false);
            f.set(Flag::SLAVE, false);
            f.set(Flag::MASTER, true);
        }
    }
    Ok(())
}

/// `NotPredefinedMasterSlave` (reference §12.3), after the main search: every condition of
/// `sub` with a non-empty INDEX_MAP becomes SLAVE, every master in those maps MASTER, then
/// the nodes of SLAVE conditions SLAVE and the nodes of MASTER conditions MASTER. Flags are
/// only ever set true here.
pub(crate) fn not_predefined_master_slave(model: &mut ModelPart, sub: PartIdx) {
    let conditions = conditions_in_order(model, sub);
    let mut masters = Vec::new();
    for &c in &conditions {
        if !model.index_map(c).is_empty() {
            model.conditions_mut().flags_mut()[c.index()].set(Flag::SLAVE, true);
            masters.extend(model.index_map(c).masters());
        }
    }
    masters.sort_unstable();
    masters.dedup();
    for m in masters {
        if let Some(i) = model.conditions().index_of(m.get()) {
            model.conditions_mut().flags_mut()[i].set(Flag::MASTER, true);
        }
    }
    for &c in &conditions {
        let f = model.conditions().flags()[c.index()];
        let nodes = model.conditions().nodes(c.index()).to_vec();
        let node_flags = model.nodes_mut().flags_mut();
        for n in nodes {
            if f.is(Flag::SLAVE) {
                node_flags[n.index()].set(Flag::SLAVE, true);
            }
            if f.is(Flag::MASTER) {
                node_flags[n.index()].set(Flag::MASTER, true);
            }
        }
    }
}

#[cfg(test)]
mod tests;
