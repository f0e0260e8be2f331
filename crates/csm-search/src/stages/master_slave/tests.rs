use csm_geometry::GeometryKind;
use csm_geometry::math::Point;
use csm_model::{ConditionId, NodeId, PropertiesId};

use super::*;

#[test]
fn condition_flags_follow_the_nodes_q30_included() {
    let mut mp = ModelPart::new("Structure");
    for i in 1..=8u32 {
        mp.add_node(NodeId(i), Point::new(f64::from(i), 0.0, 0.0))
            .unwrap();
    }
    let line = GeometryKind::Line2D2;
    for (id, a, b) in [(1, 1, 2), (2, 3, 4), (3, 5, 6), (4, 7, 8)] {
        mp.add_condition(
            ConditionId(id),
            line,
            "",
            &[NodeId(a), NodeId(b)],
            PropertiesId(0),
        )
        .unwrap();
    }
    let nf = mp.nodes_mut().flags_mut();
    // Condition 1: both nodes interface slaves → slave.
    for f in &mut nf[0..2] {
        f.set(Flag::INTERFACE, true);
        f.set(Flag::SLAVE, true);
    }
    // Condition 2: interface, one node not slave → master.
    nf[2].set(Flag::INTERFACE, true);
    nf[2].set(Flag::SLAVE, true);
    nf[3].set(Flag::INTERFACE, true);
    // Condition 3: a node with INTERFACE false → not an interface condition.
    nf[4].set(Flag::INTERFACE, false);
    nf[5].set(Flag::INTERFACE, true);
    // Condition 4: no INTERFACE defined at all → interface slave (Q30).
    let contact = mp.create_part("Contact").unwrap();
    master_slave_from_nodes(&mut mp, contact);
    let cf = mp.conditions().flags();
    assert!(cf[0].is(Flag::SLAVE) && !cf[0].is_defined(Flag::MASTER));
    assert!(cf[1].is(Flag::MASTER) && !cf[1].is_defined(Flag::SLAVE));
    assert!(!cf[2].is_defined(Flag::MASTER) && !cf[2].is_defined(Flag::SLAVE));
    assert!(
        cf[3].is(Flag::SLAVE),
        "Q30: nodes without INTERFACE make an interface slave"
    );
    let part = mp.part(contact);
    assert_eq!(
        part.conditions(),
        &[ConditionIdx(0), ConditionIdx(1), ConditionIdx(3)]
    );
    assert_eq!(
        part.nodes(),
        &[NodeIdx(0), NodeIdx(1), NodeIdx(2), NodeIdx(3), NodeIdx(5)]
    );
}
