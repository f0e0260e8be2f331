//! Skin detection: the contact faces when no contact part is named (every
//! `contact_model_part` list empty; Kratos `SearchBaseProcess.__detect_skin`, reference §1.3
//! step 2).
//!
//! Kratos 10.4.4 runs `SkinDetectionProcess` on the main model part with
//! `name_auxiliar_model_part` `"ContactSub0"`, which creates the part at the root
//! (`Structure.ContactSub0`), not under `Contact`: `Contact` stays empty and the search raises
//! "mPointListDestination not initialized". csm reproduces that refusal in kratos mode; robust
//! mode puts the skin where the search looks for it ([`detect_skin`] here, then the usual
//! contact parts with the skin part as the only listed part).
//!
//! The skin is every element face (an edge in 2D) that belongs to one element only, matched
//! by its set of nodes. Kratos numbers its skin conditions in hash-set order; csm creates them
//! in element id order, each element's faces in Kratos' `GenerateFaces` order
//! ([`csm_geometry::GeometryKind::faces`]), with the ids after the largest condition id, the
//! face's node order (outward normal on a positively oriented solid) and the element's
//! properties. Conditions and nodes get `INTERFACE`.

use std::collections::HashMap;

use csm_model::{ConditionId, Flag, ModelPart, NodeId, NodeIdx, PartIdx};

use super::interface_preprocess::interface_condition_name;
use crate::error::{Error, ErrorKind};

/// The part Kratos creates for the skin (at the root of the model).
pub const SKIN_PART: &str = "ContactSub0";

/// What [`detect_skin`] made.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SkinReport {
    /// The part holding the skin conditions and their nodes.
    pub part: PartIdx,
    /// The ids of the skin conditions, in creation order.
    pub conditions: Vec<ConditionId>,
}

/// Creates the skin conditions of every element of `model` in a new root part [`SKIN_PART`]
/// (module docs). Fails when the part already exists or the elements have no face (a mesh of
/// surface elements only) — there is then no skin to search.
pub fn detect_skin(model: &mut ModelPart) -> Result<SkinReport, Error> {
    if model.find_part(SKIN_PART).is_some() {
        return Err(ErrorKind::Model(format!(
            "skin detection: the mesh already has a part `{SKIN_PART}`, where the skin goes; \
             rename it or name the contact parts in `contact_model_part`"
        ))
        .into());
    }
    let elements = model.elements();
    let mut order: Vec<usize> = (0..elements.len()).collect();
    order.sort_by_key(|&e| elements.ids()[e]);
    let node_ids = model.nodes().ids();
    // Every face, keyed by its sorted node ids: how many elements have it.
    let key_of = |nodes: &[NodeIdx]| -> Vec<u32> {
        let mut key: Vec<u32> = nodes.iter().map(|n| node_ids[n.index()]).collect();
        key.sort_unstable();
        key
    };
    let mut count: HashMap<Vec<u32>, u32> = HashMap::new();
    let mut faces = Vec::new();
    for &e in &order {
        let element_nodes = elements.nodes(e);
        for (kind, local) in elements.kind(e).faces() {
            let nodes: Vec<NodeIdx> = local.iter().map(|&l| element_nodes[l]).collect();
            let key = key_of(&nodes);
            *count.entry(key.clone()).or_default() += 1;
            faces.push((key, *kind, nodes, elements.properties(e)));
        }
    }
    if faces.is_empty() {
        return Err(ErrorKind::Model(
            "skin detection: no element has a face (only surface elements or no elements); \
             name the contact parts in `contact_model_part`"
                .to_owned(),
        )
        .into());
    }
    let part = model
        .create_part(SKIN_PART)
        .map_err(|e| Error::model_data("", e))?;
    let mut next = model.conditions().max_id();
    let mut conditions = Vec::new();
    let mut skin_nodes = Vec::new();
    for (key, kind, nodes, properties) in faces {
        if count[&key] != 1 {
            continue;
        }
        next += 1;
        let id = ConditionId(next);
        let ids: Vec<NodeId> = nodes
            .iter()
            .map(|n| NodeId(model.nodes().ids()[n.index()]))
            .collect();
        let name = interface_condition_name(nodes.len(), kind.local_dim() == 1);
        let idx = model
            .add_condition(id, kind, name, &ids, properties)
            .map_err(|e| Error::model_data("", e))?;
        model.add_conditions_to_part(part, &[idx]);
        model.conditions_mut().flags_mut()[idx.index()].set(Flag::INTERFACE, true);
        skin_nodes.extend(nodes);
        conditions.push(id);
    }
    skin_nodes.sort_unstable();
    skin_nodes.dedup();
    for n in &skin_nodes {
        model.nodes_mut().flags_mut()[n.index()].set(Flag::INTERFACE, true);
    }
    model.add_nodes_to_part(part, &skin_nodes);
    Ok(SkinReport { part, conditions })
}

#[cfg(test)]
mod tests;
