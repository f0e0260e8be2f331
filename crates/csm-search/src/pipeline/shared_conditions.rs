//! `CheckContactModelParts` (reference §4.1): a condition shared by several contact pairs gets
//! its own copy in every pair after the first, so that each pair has its own INDEX_MAP.
//!
//! Pairs are initialised in key order. Walking the conditions of `ContactSub<key>` in id
//! order, a condition already MARKER (taken by an earlier pair) is replaced by a clone (same
//! geometry, properties and flags, MARKER true, a fresh empty INDEX_MAP) and the original is
//! removed from `ContactSub<key>` and its children; a condition not MARKER just becomes MARKER.
//! Kratos numbers the clones `T + 1, T + 2, …` in the order made, `T` being the number of
//! conditions of the root: with non-dense ids these can collide with existing ids (Q27), which
//! csm reports as an error in `kratos` mode; `robust` mode numbers them after the largest id.

use csm_model::{ConditionId, ConditionIdx, Flag, ModelPart, NodeId, PartIdx};

use crate::error::{Error, ErrorKind};
use crate::setup::Compatibility;

/// Clones the conditions of `sub` that an earlier pair already took; returns the clones.
pub(crate) fn check_contact_model_parts(
    model: &mut ModelPart,
    sub: PartIdx,
    compatibility: Compatibility,
) -> Result<Vec<ConditionIdx>, Error> {
    let count = model.conditions().len() as u32;
    let max_id = model.conditions().max_id();
    let mut conditions = model.part(sub).conditions().to_vec();
    let ids = model.conditions().ids().to_vec();
    conditions.sort_by_key(|c| ids[c.index()]);
    let mut originals = Vec::new();
    let mut clones = Vec::new();
    for c in conditions {
        let flags = model.conditions().flags()[c.index()];
        if !flags.is(Flag::MARKER) {
            model.conditions_mut().flags_mut()[c.index()].set(Flag::MARKER, true);
            continue;
        }
        let base = match compatibility {
            Compatibility::Kratos => count,
            Compatibility::Robust => max_id,
        };
        let id = base + clones.len() as u32 + 1;
        let kind = model.conditions().kind(c.index());
        let name = model.conditions().name(c.index()).to_owned();
        let properties = model.conditions().properties(c.index());
        let node_ids: Vec<NodeId> = model
            .conditions()
            .nodes(c.index())
            .iter()
            .map(|n| NodeId(model.nodes().ids()[n.index()]))
            .collect();
        let clone = model
            .add_condition(ConditionId(id), kind, &name, &node_ids, properties)
            .map_err(|e| {
                Error::from(ErrorKind::Model(format!(
                    "cloning condition {} shared by several contact pairs as id {id}: {e} \
                     (Kratos numbers clones after the condition count, which collides with \
                     non-dense ids, Q27; \"compatibility\": \"robust\" numbers them after the \
                     largest id)",
                    ids[c.index()]
                )))
            })?;
        model.conditions_mut().flags_mut()[clone.index()] = flags;
        model.conditions_mut().flags_mut()[clone.index()].set(Flag::MARKER, true);
        originals.push(c);
        clones.push(clone);
    }
    if !originals.is_empty() {
        model.remove_conditions_from_part(sub, &originals);
        model.add_conditions_to_part(sub, &clones);
    }
    Ok(clones)
}
