use csm_geometry::GeometryKind;
use csm_geometry::math::Point;
use csm_model::{ConditionId, ConditionIdx, Flag, ModelPart, NodeId, PropertiesId};

use super::*;

/// One slave and one master condition of the given kinds, all in `Contact`.
fn model(slave: GeometryKind, master: GeometryKind) -> (ModelPart, PartIdx) {
    let mut mp = ModelPart::new("Structure");
    for i in 0..20u32 {
        mp.add_node(NodeId(i + 1), Point::new(f64::from(i), 0.0, 0.0))
            .unwrap();
    }
    let ids = |from: u32, n: usize| (from..from + n as u32).map(NodeId).collect::<Vec<_>>();
    mp.add_condition(
        ConditionId(1),
        slave,
        "",
        &ids(1, slave.n_nodes()),
        PropertiesId(0),
    )
    .unwrap();
    mp.add_condition(
        ConditionId(2),
        master,
        "",
        &ids(11, master.n_nodes()),
        PropertiesId(0),
    )
    .unwrap();
    mp.conditions_mut().flags_mut()[0].set(Flag::SLAVE, true);
    mp.conditions_mut().flags_mut()[1].set(Flag::MASTER, true);
    let contact = mp.create_part("Contact").unwrap();
    mp.add_conditions_to_part(contact, &[ConditionIdx(0), ConditionIdx(1)]);
    (mp, contact)
}

#[test]
fn instances_follow_the_wrapper() {
    use GeometryKind::*;
    for (slave, master, dim, suffix) in [
        (Triangle3D3, Triangle3D3, 3, "3D3N"),
        (Quadrilateral3D4, Quadrilateral3D4, 3, "3D4N"),
        (Triangle3D3, Quadrilateral3D4, 3, "3D3N4N"),
        (Quadrilateral3D4, Triangle3D3, 3, "3D4N3N"),
        (Triangle3D6, Triangle3D6, 3, "3D3N"),
        (Line2D2, Line2D2, 2, "2D2N"),
        (Line2D3, Line2D3, 2, "2D2N"),
    ] {
        let (mp, contact) = model(slave, master);
        let inst = dispatch(&mp, contact, dim, true).unwrap();
        assert_eq!(inst.suffix(), suffix, "{slave:?}/{master:?}");
    }
}

#[test]
fn unsupported_combinations_are_errors_not_crashes() {
    let (mp, contact) = model(
        GeometryKind::Quadrilateral3D8,
        GeometryKind::Quadrilateral3D8,
    );
    let e = dispatch(&mp, contact, 3, true).unwrap_err();
    assert!(e.to_string().contains("8 nodes"), "{e}");
    let (mp, contact) = model(GeometryKind::Triangle3D3, GeometryKind::Quadrilateral3D4);
    let inst = dispatch(&mp, contact, 3, false).unwrap();
    assert_eq!(
        inst.suffix(),
        "3D3N",
        "not predefined: the first condition decides both"
    );
}
