//! Stage 3: master/slave flags of conditions from the nodal flags, when the `Contact` part
//! already exists (Kratos `MasterSlaveProcess`, reference §15).
//!
//! For every condition of the root model part: a node whose INTERFACE is defined-and-false
//! makes the condition a non-interface condition; a node whose INTERFACE is true but which is
//! not SLAVE makes it a non-slave condition; nodes with INTERFACE undefined are ignored — so a
//! condition none of whose nodes has INTERFACE defined is an interface *slave* condition
//! (Q30, reproduced). Interface conditions get SLAVE := true if slave, else MASTER := true
//! (the other flag is left as it was); every INTERFACE node and every interface condition is
//! added to `contact`.

use csm_model::{ConditionIdx, Flag, ModelPart, NodeIdx, PartIdx};

/// Assigns the condition flags from the nodal ones and fills `contact`.
pub fn master_slave_from_nodes(model: &mut ModelPart, contact: PartIdx) {
    let n_conditions = model.conditions().len();
    let mut interface_conditions = Vec::new();
    for c in 0..n_conditions {
        let (mut interface, mut slave) = (true, true);
        for n in model.conditions().nodes(c) {
            let f = model.nodes().flags()[n.index()];
            if !f.is_defined(Flag::INTERFACE) {
                continue;
            }
            if f.is_not(Flag::INTERFACE) {
                interface = false;
            } else if f.is_not(Flag::SLAVE) {
                slave = false;
            }
        }
        if interface {
            let flags = &mut model.conditions_mut().flags_mut()[c];
            flags.set(if slave { Flag::SLAVE } else { Flag::MASTER }, true);
            interface_conditions.push(ConditionIdx(c as u32));
        }
    }
    let interface_nodes: Vec<NodeIdx> = (0..model.nodes().len() as u32)
        .map(NodeIdx)
        .filter(|n| model.nodes().flags()[n.index()].is(Flag::INTERFACE))
        .collect();
    model.add_nodes_to_part(contact, &interface_nodes);
    model.add_conditions_to_part(contact, &interface_conditions);
}

#[cfg(test)]
mod tests;
