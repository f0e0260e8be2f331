//! Stage 0: the `Contact` model part, one `Contact.ContactSub<key>` per pair, and the
//! INTERFACE / MASTER / SLAVE flags (Kratos `SearchBaseProcess.ExecuteInitialize`, reference
//! §1.3, the path where `Contact` does not exist yet).
//!
//! For every listed part P of pair `key`, in list order: when roles are predefined, P's nodes
//! (and conditions, if any) become MASTER (SLAVE false), then the nodes (and conditions) of
//! every part in `assume_master_slave[key]` become SLAVE (MASTER false) — the net effect is
//! that listed slave parts are slave and everything else master; without predefined roles no
//! MASTER/SLAVE flag is set at all. INTERFACE is set on P's nodes, and on P's conditions when
//! it has any. The pair properties are `contact_property_ids[key]`, or a properties block
//! `100 + key` created if missing.

use std::collections::BTreeMap;

use csm_model::{Flag, ModelPart, PartIdx, PropertiesId};

use crate::error::{Error, ErrorKind};
use crate::setup::SearchSetup;

/// The contact parts built by stage 0.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactParts {
    /// `Contact`.
    pub contact: PartIdx,
    /// `Contact.ContactSub<key>`, by pair key.
    pub subs: BTreeMap<u32, PartIdx>,
    /// The properties of each pair, by pair key.
    pub properties: BTreeMap<u32, PropertiesId>,
}

pub(crate) fn user_part(model: &ModelPart, path: &str, key: u32) -> Result<PartIdx, Error> {
    model.find_part(path).ok_or_else(|| {
        ErrorKind::InvalidValue {
            key: format!("contact_model_part.{key}"),
            expected: format!(
                "names of parts of the mesh ({})",
                model.part_paths().join(", ")
            ),
            found: format!("\"{path}\""),
        }
        .into()
    })
}

fn set_part_flag(model: &mut ModelPart, part: PartIdx, flag: Flag, value: bool, conditions: bool) {
    let nodes = model.part(part).nodes().to_vec();
    let node_flags = model.nodes_mut().flags_mut();
    for n in nodes {
        node_flags[n.index()].set(flag, value);
    }
    if conditions {
        let conds = model.part(part).conditions().to_vec();
        let cond_flags = model.conditions_mut().flags_mut();
        for c in conds {
            cond_flags[c.index()].set(flag, value);
        }
    }
}

/// Creates `Contact` and `Contact.ContactSub<key>` for every pair and sets the flags of the
/// user parts. The user parts are not transferred yet (stage 1 may first generate their
/// conditions); see [`transfer_to_contact`].
pub fn assign_contact_flags(
    model: &mut ModelPart,
    setup: &SearchSetup,
) -> Result<ContactParts, Error> {
    // Every named part must exist before anything is created.
    for (&key, pair) in &setup.pairs {
        for path in pair.parts.iter().chain(&pair.slaves) {
            user_part(model, path, key)?;
        }
    }
    let contact = model.create_part("Contact").map_err(model_error)?;
    let mut subs = BTreeMap::new();
    let mut properties = BTreeMap::new();
    for (&key, pair) in &setup.pairs {
        let sub = model
            .create_part(&format!("Contact.ContactSub{key}"))
            .map_err(model_error)?;
        subs.insert(key, sub);
        let predefined = !pair.slaves.is_empty();
        let slaves = pair
            .slaves
            .iter()
            .map(|s| user_part(model, s, key))
            .collect::<Result<Vec<_>, _>>()?;
        for path in &pair.parts {
            let part = user_part(model, path, key)?;
            let has_conditions = !model.part(part).conditions().is_empty();
            if predefined {
                set_part_flag(model, part, Flag::SLAVE, false, has_conditions);
                set_part_flag(model, part, Flag::MASTER, true, has_conditions);
                for &slave in &slaves {
                    let slave_has_conditions = !model.part(slave).conditions().is_empty();
                    set_part_flag(model, slave, Flag::SLAVE, true, slave_has_conditions);
                    set_part_flag(model, slave, Flag::MASTER, false, slave_has_conditions);
                }
            }
            set_part_flag(model, part, Flag::INTERFACE, true, has_conditions);
        }
        let id = if pair.property_id != 0 {
            PropertiesId(pair.property_id)
        } else {
            PropertiesId(100 + key)
        };
        model.ensure_properties(id);
        properties.insert(key, id);
    }
    Ok(ContactParts {
        contact,
        subs,
        properties,
    })
}

/// Transfers the nodes and conditions of every user part of each pair into its
/// `Contact.ContactSub<key>` (and so into `Contact`), as Kratos'
/// `FastTransferBetweenModelPartsProcess` (NODESANDCONDITIONS) does after stage 1.
pub fn transfer_to_contact(
    model: &mut ModelPart,
    setup: &SearchSetup,
    parts: &ContactParts,
) -> Result<(), Error> {
    for (&key, pair) in &setup.pairs {
        let sub = parts.subs[&key];
        for path in &pair.parts {
            let part = user_part(model, path, key)?;
            let nodes = model.part(part).nodes().to_vec();
            let conditions = model.part(part).conditions().to_vec();
            model.add_nodes_to_part(sub, &nodes);
            model.add_conditions_to_part(sub, &conditions);
        }
    }
    Ok(())
}

fn model_error(e: csm_model::Error) -> Error {
    ErrorKind::RejectedByKratos(e.to_string()).into()
}

#[cfg(test)]
mod tests;
