use csm_geometry::GeometryKind;
use csm_geometry::math::Point;
use csm_model::{ConditionId, ConditionIdx, Flag, ModelPart, NodeId, NodeIdx, PropertiesId};

use super::*;
use crate::parse_setup;

/// Two triangles, one per part: `Slave` (nodes 1–3, condition 1) and `Master` (nodes 4–6,
/// condition 2), plus a node-only part `Loose` (node 7).
fn model() -> ModelPart {
    let mut mp = ModelPart::new("Structure");
    for i in 0..7u32 {
        mp.add_node(NodeId(i + 1), Point::new(f64::from(i), 0.0, 0.0))
            .unwrap();
    }
    let t = GeometryKind::Triangle3D3;
    mp.add_condition(
        ConditionId(1),
        t,
        "",
        &[NodeId(1), NodeId(2), NodeId(3)],
        PropertiesId(1),
    )
    .unwrap();
    mp.add_condition(
        ConditionId(2),
        t,
        "",
        &[NodeId(4), NodeId(5), NodeId(6)],
        PropertiesId(1),
    )
    .unwrap();
    for (name, nodes, cond) in [("Slave", 0..3, 0), ("Master", 3..6, 1)] {
        let p = mp.create_part(name).unwrap();
        let nodes: Vec<NodeIdx> = nodes.map(NodeIdx).collect();
        mp.add_nodes_to_part(p, &nodes);
        mp.add_conditions_to_part(p, &[ConditionIdx(cond)]);
    }
    let loose = mp.create_part("Loose").unwrap();
    mp.add_nodes_to_part(loose, &[NodeIdx(6)]);
    mp
}

fn setup(text: &str) -> SearchSetup {
    parse_setup(text, "setup.json").unwrap()
}

#[test]
fn predefined_roles_flag_slaves_and_masters() {
    let mut mp = model();
    let s = setup(
        r#"{"contact_model_part": {"0": ["Slave", "Master", "Loose"]},
            "assume_master_slave": {"0": ["Slave"]}}"#,
    );
    let parts = assign_contact_flags(&mut mp, &s).unwrap();
    let nf = mp.nodes().flags();
    for f in &nf[..3] {
        assert!(f.is(Flag::SLAVE | Flag::INTERFACE) && f.get(Flag::MASTER) == Some(false));
    }
    for f in &nf[3..7] {
        assert!(f.is(Flag::MASTER | Flag::INTERFACE) && f.get(Flag::SLAVE) == Some(false));
    }
    let cf = mp.conditions().flags();
    assert!(cf[0].is(Flag::SLAVE | Flag::INTERFACE));
    assert!(cf[1].is(Flag::MASTER | Flag::INTERFACE));
    assert_eq!(parts.properties[&0], PropertiesId(100));
    assert!(mp.properties().contains_key(&PropertiesId(100)));
    assert_eq!(mp.part(parts.subs[&0]).path(), "Contact.ContactSub0");
    assert!(
        mp.part(parts.contact).conditions().is_empty(),
        "not transferred yet"
    );

    transfer_to_contact(&mut mp, &s, &parts).unwrap();
    assert_eq!(
        mp.part(parts.subs[&0]).conditions(),
        &[ConditionIdx(0), ConditionIdx(1)]
    );
    assert_eq!(mp.part(parts.contact).nodes().len(), 7);
}

#[test]
fn without_predefined_roles_no_master_or_slave_flag_is_set() {
    let mut mp = model();
    let s = setup(
        r#"{"contact_model_part": {"3": ["Slave", "Master"]}, "contact_property_ids": {"3": 7}}"#,
    );
    let parts = assign_contact_flags(&mut mp, &s).unwrap();
    assert!(
        mp.nodes().flags()[..6]
            .iter()
            .all(|f| f.is(Flag::INTERFACE))
    );
    assert!(
        mp.nodes()
            .flags()
            .iter()
            .all(|f| !f.is_defined(Flag::MASTER) && !f.is_defined(Flag::SLAVE))
    );
    assert_eq!(parts.properties[&3], PropertiesId(7));
    assert_eq!(mp.part(parts.subs[&3]).path(), "Contact.ContactSub3");
}

#[test]
fn an_unknown_part_is_an_error_listing_the_parts() {
    let mut mp = model();
    let s = setup(r#"{"contact_model_part": {"0": ["Nope"]}}"#);
    let e = assign_contact_flags(&mut mp, &s).unwrap_err();
    let msg = e.to_string();
    assert!(msg.contains("\"Nope\"") && msg.contains("Slave"), "{msg}");
}
