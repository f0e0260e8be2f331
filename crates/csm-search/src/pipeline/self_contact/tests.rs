//! Kratos' three `SelfContactUtilities` tests (reference §20.6): every condition's INDEX_MAP
//! holds every other condition, then `ComputeSelfContactPairing`. The expected roles depend
//! only on the connectivity, so the node positions here are arbitrary.

use csm_geometry::GeometryKind;
use csm_geometry::math::Point;
use csm_model::{ConditionId, ConditionIdx, Flag, ModelPart, NodeId, PartIdx, PropertiesId};

use super::{compute_self_contact_pairing, not_predefined_master_slave};

/// A `Contact` part of 4-node conditions with the given connectivity (ids 1..), nodes 1..=n.
fn quads(n_nodes: u32, conditions: &[[u32; 4]]) -> (ModelPart, PartIdx) {
    let mut mp = ModelPart::new("Structure");
    let nodes: Vec<_> = (1..=n_nodes)
        .map(|i| {
            mp.add_node(
                NodeId(i),
                Point::new(f64::from(i), 0.5 * f64::from(i % 3), 0.0),
            )
            .unwrap()
        })
        .collect();
    let part = mp.create_part("Contact").unwrap();
    mp.add_nodes_to_part(part, &nodes);
    let mut conds = Vec::new();
    for (k, c) in conditions.iter().enumerate() {
        let ids = c.map(NodeId);
        conds.push(
            mp.add_condition(
                ConditionId(k as u32 + 1),
                GeometryKind::Quadrilateral3D4,
                "SurfaceCondition3D4N",
                &ids,
                PropertiesId(0),
            )
            .unwrap(),
        );
    }
    mp.add_conditions_to_part(part, &conds);
    (mp, part)
}

/// FullAssignmentOfPairs: every condition gets every other one.
fn full_assignment(mp: &mut ModelPart, part: PartIdx) {
    let conds = mp.part(part).conditions().to_vec();
    for &a in &conds {
        for &b in &conds {
            if a != b {
                let id = ConditionId(mp.conditions().ids()[b.index()]);
                mp.index_map_mut(a).add_id(id);
            }
        }
    }
}

/// (SLAVE, MASTER, ACTIVE) of condition `id`, undefined as false.
fn roles(mp: &ModelPart, id: u32) -> Roles {
    let i = mp.conditions().index_of(id).unwrap();
    let f = mp.conditions().flags()[i];
    (f.is(Flag::SLAVE), f.is(Flag::MASTER), f.is(Flag::ACTIVE))
}

/// (SLAVE, MASTER, ACTIVE).
type Roles = (bool, bool, bool);

const ACTIVE_SLAVE: Roles = (true, false, true);
const ACTIVE_MASTER: Roles = (false, true, true);
const INACTIVE_MASTER: Roles = (false, true, false);

fn check(mp: &ModelPart, expected: &[(&[u32], Roles)]) {
    for (ids, role) in expected {
        for &id in *ids {
            assert_eq!(roles(mp, id), *role, "condition {id}");
        }
    }
}

#[test]
fn two_facing_plates_split_into_slave_and_master() {
    let (mut mp, part) = quads(
        18,
        &[
            [12, 5, 8, 15],
            [15, 8, 16, 18],
            [5, 2, 6, 8],
            [8, 6, 11, 16],
            [17, 14, 7, 13],
            [13, 7, 3, 9],
            [14, 10, 4, 7],
            [7, 4, 1, 3],
        ],
    );
    full_assignment(&mut mp, part);
    compute_self_contact_pairing(&mut mp, part).unwrap();
    check(
        &mp,
        &[
            (&[1, 2, 3, 4], ACTIVE_SLAVE),
            (&[5, 6, 7, 8], ACTIVE_MASTER),
        ],
    );
    // The masters' maps are cleared, the slaves keep theirs.
    for id in 5..=8 {
        let c = ConditionIdx(mp.conditions().index_of(id).unwrap() as u32);
        assert!(mp.index_map(c).is_empty(), "map of master {id}");
    }
    let c1 = ConditionIdx(mp.conditions().index_of(1).unwrap() as u32);
    assert!(!mp.index_map(c1).is_empty());
    // Every node of a slave plate is SLAVE, every node of the other MASTER.
    for (node, slave) in [(12, true), (2, true), (11, true), (17, false), (1, false)] {
        let i = mp.nodes().index_of(node).unwrap();
        let f = mp.nodes().flags()[i.index()];
        assert_eq!(
            (f.is(Flag::SLAVE), f.is(Flag::MASTER)),
            (slave, !slave),
            "node {node}"
        );
    }
}

#[test]
fn twelve_facet_cylinder() {
    let (mut mp, part) = quads(
        24,
        &[
            [23, 24, 21, 19],
            [19, 21, 17, 15],
            [15, 17, 13, 11],
            [11, 13, 9, 7],
            [7, 9, 5, 3],
            [3, 5, 2, 1],
            [1, 2, 6, 4],
            [4, 6, 10, 8],
            [8, 10, 14, 12],
            [12, 14, 18, 16],
            [16, 18, 22, 20],
            [20, 22, 24, 23],
        ],
    );
    full_assignment(&mut mp, part);
    compute_self_contact_pairing(&mut mp, part).unwrap();
    check(
        &mp,
        &[
            (&[1, 2, 12], ACTIVE_SLAVE),
            (&[3, 11], INACTIVE_MASTER),
            (&[4, 5, 6, 7, 8, 9, 10], ACTIVE_MASTER),
        ],
    );
}

#[test]
fn twenty_facet_cylinder_in_two_rings() {
    let (mut mp, part) = quads(
        30,
        &[
            [30, 29, 25, 27],
            [26, 24, 29, 30],
            [20, 18, 24, 26],
            [14, 12, 18, 20],
            [8, 6, 12, 14],
            [3, 2, 6, 8],
            [9, 7, 2, 3],
            [15, 13, 7, 9],
            [21, 19, 13, 15],
            [27, 25, 19, 21],
            [29, 28, 23, 25],
            [24, 22, 28, 29],
            [18, 16, 22, 24],
            [12, 10, 16, 18],
            [6, 4, 10, 12],
            [2, 1, 4, 6],
            [7, 5, 1, 2],
            [13, 11, 5, 7],
            [19, 17, 11, 13],
            [25, 23, 17, 19],
        ],
    );
    full_assignment(&mut mp, part);
    compute_self_contact_pairing(&mut mp, part).unwrap();
    check(
        &mp,
        &[
            (&[1, 2, 10, 11, 12, 20], ACTIVE_SLAVE),
            (&[3, 9, 13, 19], INACTIVE_MASTER),
            (&[4, 5, 6, 7, 8, 14, 15, 16, 17, 18], ACTIVE_MASTER),
        ],
    );
}

#[test]
fn not_predefined_flags_both_sides_of_the_maps() {
    let (mut mp, part) = quads(18, &[[12, 5, 8, 15], [17, 14, 7, 13], [5, 2, 6, 8]]);
    let c = |mp: &ModelPart, id: u32| ConditionIdx(mp.conditions().index_of(id).unwrap() as u32);
    let c1 = c(&mp, 1);
    mp.index_map_mut(c1).add_id(ConditionId(2));
    not_predefined_master_slave(&mut mp, part);
    assert!(roles(&mp, 1).0);
    assert!(roles(&mp, 2).1);
    // Condition 3 has no map and is no one's master: no flag set.
    let f3 = mp.conditions().flags()[c(&mp, 3).index()];
    assert!(!f3.is_defined(Flag::SLAVE) && !f3.is_defined(Flag::MASTER));
    // Nodes of condition 1 SLAVE, of condition 2 MASTER; node 6 (only in 3) neither.
    let node = |id: u32| mp.nodes().flags()[mp.nodes().index_of(id).unwrap().index()];
    assert!(node(12).is(Flag::SLAVE) && node(17).is(Flag::MASTER));
    assert!(!node(6).is_defined(Flag::SLAVE) && !node(6).is_defined(Flag::MASTER));
}
