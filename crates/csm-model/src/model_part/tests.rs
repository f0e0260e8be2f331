use super::*;

fn p(x: f64, y: f64, z: f64) -> Point {
    Point::new(x, y, z)
}

fn square() -> ModelPart {
    let mut mp = ModelPart::new("Structure");
    for (i, (x, y)) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
        .iter()
        .enumerate()
    {
        mp.add_node(NodeId(10 + i as u32), p(*x, *y, 0.0)).unwrap();
    }
    mp
}

#[test]
fn ids_map_to_dense_indices() {
    let mut mp = square();
    let c = mp
        .add_condition(
            ConditionId(7),
            GeometryKind::Quadrilateral3D4,
            "SurfaceCondition3D4N",
            &[NodeId(10), NodeId(11), NodeId(12), NodeId(13)],
            PropertiesId(1),
        )
        .unwrap();
    assert_eq!(c, ConditionIdx(0));
    assert_eq!(mp.conditions().index_of(7), Some(0));
    assert_eq!(
        mp.conditions().nodes(0),
        &[NodeIdx(0), NodeIdx(1), NodeIdx(2), NodeIdx(3)]
    );
    assert_eq!(mp.conditions().name(0), "SurfaceCondition3D4N");
    assert_eq!(mp.conditions().max_id(), 7);
    assert_eq!(mp.nodes().index_of(12), Some(NodeIdx(2)));
}

#[test]
fn bad_entities_are_typed_errors() {
    let mut mp = square();
    let e = mp.add_node(NodeId(10), p(0.0, 0.0, 0.0)).unwrap_err();
    assert_eq!(
        e.kind(),
        &ErrorKind::DuplicateId {
            entity: EntityKind::Node,
            id: 10
        }
    );
    let e = mp.add_node(NodeId(99), p(f64::NAN, 0.0, 0.0)).unwrap_err();
    assert_eq!(e.kind(), &ErrorKind::NonFiniteCoordinate { node: 99 });
    let e = mp
        .add_element(
            ElementId(1),
            GeometryKind::Triangle2D3,
            "",
            &[NodeId(10), NodeId(11), NodeId(42)],
            PropertiesId(0),
        )
        .unwrap_err();
    assert_eq!(
        e.kind(),
        &ErrorKind::MissingNode {
            entity: EntityKind::Element,
            id: 1,
            node: 42
        }
    );
    let e = mp
        .add_element(
            ElementId(1),
            GeometryKind::Triangle2D3,
            "",
            &[NodeId(10)],
            PropertiesId(0),
        )
        .unwrap_err();
    assert!(matches!(
        e.kind(),
        ErrorKind::WrongNodeCount {
            expected: 3,
            found: 1,
            ..
        }
    ));
    assert!(e.to_string().contains("element 1 has 1 nodes"));
}

#[test]
fn sub_parts_are_addressed_by_full_path_and_propagate_to_ancestors() {
    let mut mp = square();
    let leaf = mp.create_part("Contact.ContactSub0").unwrap();
    let other = mp.create_part("Parts_Slave").unwrap();
    assert_eq!(mp.find_part("Contact/ContactSub0"), Some(leaf));
    mp.add_nodes_to_part(leaf, &[NodeIdx(3), NodeIdx(1)]);
    mp.add_nodes_to_part(other, &[NodeIdx(1)]);
    let contact = mp.find_part("Contact").unwrap();
    assert_eq!(mp.part(contact).nodes(), &[NodeIdx(1), NodeIdx(3)]);
    assert_eq!(mp.part(leaf).parent(), Some(contact));
    assert_eq!(mp.part(contact).children(), &[leaf]);
    assert_eq!(
        mp.part_paths(),
        vec!["Contact", "Contact.ContactSub0", "Parts_Slave"]
    );
    assert_eq!(mp.root_parts(), &[contact, other]);
    assert!(matches!(
        mp.get_part("Nope").unwrap_err().kind(),
        ErrorKind::UnknownPart(_)
    ));
    assert!(mp.create_part("A..B").is_err());
    assert!(mp.create_part("").is_err());
}

#[test]
fn removing_conditions_from_a_part_keeps_them_in_the_ancestors() {
    let mut mp = square();
    let ids = [NodeId(10), NodeId(11), NodeId(12)];
    let t = GeometryKind::Triangle3D3;
    let c0 = mp
        .add_condition(ConditionId(1), t, "", &ids, PropertiesId(0))
        .unwrap();
    let c1 = mp
        .add_condition(ConditionId(2), t, "", &ids, PropertiesId(0))
        .unwrap();
    let sub = mp.create_part("Contact.Sub").unwrap();
    let leaf = mp.create_part("Contact.Sub.Leaf").unwrap();
    mp.add_conditions_to_part(leaf, &[c0, c1]);
    mp.remove_conditions_from_part(sub, &[c0]);
    assert_eq!(mp.part(sub).conditions(), &[c1]);
    assert_eq!(mp.part(leaf).conditions(), &[c1]);
    let contact = mp.find_part("Contact").unwrap();
    assert_eq!(mp.part(contact).conditions(), &[c0, c1]);
}

#[test]
fn renumbering_and_permuting_conditions() {
    let mut mp = square();
    let ids = [NodeId(10), NodeId(11), NodeId(12)];
    let t = GeometryKind::Triangle3D3;
    mp.add_condition(ConditionId(5), t, "", &ids, PropertiesId(0))
        .unwrap();
    mp.add_condition(ConditionId(9), t, "", &ids, PropertiesId(0))
        .unwrap();
    assert!(!mp.conditions_mut().set_ids(&[1, 1]), "repeated id");
    assert!(!mp.conditions_mut().set_ids(&[1]), "wrong length");
    assert!(mp.conditions_mut().set_ids(&[1, 2]));
    assert_eq!(mp.conditions().index_of(2), Some(1));
    assert_eq!(mp.conditions().index_of(9), None);
    assert!(mp.conditions_mut().permute_nodes(0, &[0, 2, 1]));
    assert_eq!(
        mp.conditions().nodes(0),
        &[NodeIdx(0), NodeIdx(2), NodeIdx(1)]
    );
    assert!(
        !mp.conditions_mut().permute_nodes(0, &[0, 0, 1]),
        "not a permutation"
    );
    assert!(
        !mp.conditions_mut().permute_nodes(0, &[0, 1]),
        "wrong length"
    );
}

/// `with_scalar_mut` and `with_vector_mut` hand out the column (absent from the model
/// meanwhile) and put it back with what was written; `None` without the variable or step.
#[test]
fn with_column_mut_lends_the_column_and_puts_it_back() {
    let mut mp = square();
    assert_eq!(
        mp.with_scalar_mut(ScalarVar::WeightedGap, 0, |_, _| ()),
        None
    );
    mp.nodal_data_mut().add_scalar(ScalarVar::WeightedGap);
    assert_eq!(
        mp.with_scalar_mut(ScalarVar::WeightedGap, 3, |_, _| ()),
        None
    );
    let seen = mp.with_scalar_mut(ScalarVar::WeightedGap, 0, |m, col| {
        col[1] = 2.5;
        m.nodal_data()
            .scalar(ScalarVar::WeightedGap, 0)
            .map(<[f64]>::len)
    });
    assert_eq!(seen, Some(Some(0)));
    let col = mp.nodal_data().scalar(ScalarVar::WeightedGap, 0).unwrap();
    assert_eq!(col.len(), mp.nodes().len());
    assert_eq!(col[1], 2.5);
    mp.nodal_data_mut().add_vector(VectorVar::Normal);
    mp.with_vector_mut(VectorVar::Normal, 0, |_, col| col[2].x = 1.5);
    assert_eq!(
        mp.nodal_data().vector(VectorVar::Normal, 0).unwrap()[2].x,
        1.5
    );
}

/// What a model holds of its nodes and entities, for comparing two ways of building it.
fn entity_summary(mp: &ModelPart) -> String {
    let mut s = format!(
        "nodes {:?} {:?} {:?}\n",
        mp.nodes().ids(),
        mp.nodes().coordinates(),
        mp.nodes().initial_coordinates()
    );
    for e in [mp.elements(), mp.conditions()] {
        s += &format!("{:?} {:?}\n", e.ids(), e.kinds());
        for i in 0..e.len() {
            s += &format!(
                "{} {:?} {:?} {:?}\n",
                e.name(i),
                e.nodes(i),
                e.properties(i),
                e.flags()[i]
            );
        }
    }
    s + &format!(
        "properties {:?}; {} index maps; {} normals",
        mp.properties().keys().collect::<Vec<_>>(),
        (0..mp.conditions().len())
            .filter(|&i| mp.index_map(ConditionIdx(i as u32)).is_empty())
            .count(),
        mp.condition_normals().len()
    )
}

/// `add_nodes` and `add_entity_records` against `add_node`, `add_element` and
/// `add_condition` one by one (the oracle): the same model and the same first error, over
/// more records than one parallel task holds, with a bad record early, late or nowhere.
#[test]
fn bulk_insertion_is_one_by_one_insertion() {
    let n_nodes = 10_000u32;
    let ids: Vec<u32> = (1..=n_nodes).collect();
    let positions: Vec<[f64; 3]> = ids.iter().map(|&i| [i as f64, 0.5, -1.0]).collect();
    // Triangles over consecutive nodes, properties changing every 1000 records.
    let records = |count: u32| -> Vec<u32> {
        (1..=count)
            .flat_map(|i| [i, i / 1000, i, i + 1, i + 2])
            .collect()
    };
    let spoil = |mut r: Vec<u32>, at: Option<(usize, usize, u32)>| {
        if let Some((record, word, value)) = at {
            r[5 * record + word] = value;
        }
        r
    };
    for at in [
        None,
        Some((0, 3, 99_999)),     // a missing node in the first record
        Some((9_000, 2, 99_999)), // … deep in a later task
        Some((9_000, 0, 17)),     // a duplicate id
        Some((5_000, 4, 99_999)),
    ] {
        let recs = spoil(records(9_990), at);
        let oracle = {
            let mut mp = ModelPart::new("S");
            for (&id, x) in ids.iter().zip(&positions) {
                mp.add_node(NodeId(id), Point::from(*x)).unwrap();
            }
            let mut first = None;
            for conditions in [false, true] {
                for (k, r) in recs.chunks(5).enumerate() {
                    mp.ensure_properties(PropertiesId(r[1]));
                    let nodes: Vec<NodeId> = r[2..].iter().map(|&n| NodeId(n)).collect();
                    let added = if conditions {
                        mp.add_condition(
                            ConditionId(r[0]),
                            GeometryKind::Triangle3D3,
                            "C",
                            &nodes,
                            PropertiesId(r[1]),
                        )
                        .map(|_| ())
                    } else {
                        mp.add_element(
                            ElementId(r[0]),
                            GeometryKind::Triangle3D3,
                            "E",
                            &nodes,
                            PropertiesId(r[1]),
                        )
                        .map(|_| ())
                    };
                    if let Err(e) = added {
                        first.get_or_insert((conditions, k, e.to_string()));
                        break;
                    }
                }
            }
            (entity_summary(&mp), first)
        };
        let bulk = {
            let mut mp = ModelPart::new("S");
            mp.add_nodes(&ids, &positions).unwrap();
            let mut first = None;
            for conditions in [false, true] {
                let name = if conditions { "C" } else { "E" };
                if let Err((k, e)) =
                    mp.add_entity_records(conditions, GeometryKind::Triangle3D3, name, &recs)
                {
                    first.get_or_insert((conditions, k, e.to_string()));
                }
            }
            (entity_summary(&mp), first)
        };
        assert_eq!(bulk.1, oracle.1, "{at:?}");
        assert!(bulk.0 == oracle.0, "{at:?}: the models differ");
    }
    // Records that do not fill whole records: the short one is refused, never a panic.
    let mut mp = ModelPart::new("S");
    mp.add_nodes(&ids, &positions).unwrap();
    let (k, e) = mp
        .add_entity_records(true, GeometryKind::Triangle3D3, "C", &[1, 0, 1, 2, 3, 2, 0])
        .unwrap_err();
    assert_eq!(k, 1, "{e}");
    assert_eq!(mp.conditions().len(), 1);
    // Nodes: a duplicate and a non-finite coordinate, each after some nodes were added.
    for (ids, x) in [
        (vec![1, 2, 3, 2], [0.0; 3]),
        (vec![1, 2, 3, 4], [f64::NAN, 0.0, 0.0]),
    ] {
        let mut positions = vec![[0.0; 3]; 4];
        positions[3] = x;
        let mut one = ModelPart::new("S");
        let err_one = ids
            .iter()
            .zip(&positions)
            .enumerate()
            .find_map(|(k, (&id, p))| {
                one.add_node(NodeId(id), Point::from(*p))
                    .err()
                    .map(|e| (k, e.to_string()))
            });
        let mut bulk = ModelPart::new("S");
        let err_bulk = bulk
            .add_nodes(&ids, &positions)
            .err()
            .map(|(k, e)| (k, e.to_string()));
        assert_eq!(err_bulk, err_one);
        assert_eq!(entity_summary(&bulk), entity_summary(&one));
    }
}

/// A model whose conditions, added in index order, have the ids `ids`, all in one part.
fn conditions_numbered(ids: &[u32]) -> (ModelPart, PartIdx) {
    let mut model = square();
    let nodes: Vec<NodeId> = model.nodes().ids()[..3]
        .iter()
        .map(|&i| NodeId(i))
        .collect();
    let kind = GeometryKind::Triangle3D3;
    let added: Vec<ConditionIdx> = (ids.iter())
        .map(|&id| {
            let c = model.add_condition(ConditionId(id), kind, "c", &nodes, PropertiesId(0));
            c.unwrap()
        })
        .collect();
    let part = model.create_part("Numbered").unwrap();
    model.add_conditions_to_part(part, &added);
    (model, part)
}

#[test]
fn a_part_in_id_order_is_lent_and_another_sorted() {
    let (model, part) = conditions_numbered(&[103, 105, 109, 112]);
    let listed = model.part_conditions_by_id(part);
    assert!(matches!(listed, std::borrow::Cow::Borrowed(_)));
    assert_eq!(*listed, *model.part(part).conditions());
    let (model, part) = conditions_numbered(&[109, 103, 112, 105]);
    let listed = model.part_conditions_by_id(part);
    assert!(matches!(listed, std::borrow::Cow::Owned(_)));
    let ids: Vec<u32> = (listed.iter())
        .map(|c| model.conditions().ids()[c.index()])
        .collect();
    assert_eq!(ids, [103, 105, 109, 112]);
}

/// Everything a model holds, as text (the nodes and entities, their id lookups, the parts,
/// the INDEX_MAPs, the condition normals, the nodal data), but its stamps.
fn whole_model(mp: &ModelPart) -> String {
    let mut s = entity_summary(mp);
    s += &format!(
        "\nnode flags {:?}\nlookups {:?} {:?} {:?}\n",
        mp.nodes().flags(),
        (0..60_005)
            .map(|id| mp.nodes().index_of(id))
            .collect::<Vec<_>>(),
        (0..60_005)
            .map(|id| mp.elements().index_of(id))
            .collect::<Vec<_>>(),
        (0..60_005)
            .map(|id| mp.conditions().index_of(id))
            .collect::<Vec<_>>(),
    );
    for path in mp.part_paths() {
        let part = mp.part(mp.get_part(path).unwrap());
        s += &format!(
            "part {path} {:?} {:?} {:?}\n",
            part.nodes(),
            part.elements(),
            part.conditions()
        );
    }
    for c in 0..mp.conditions().len() {
        s += &format!("{:?} ", mp.index_map(ConditionIdx(c as u32)));
    }
    s += &format!(
        "\n{:?}\n{:?} {:?}",
        mp.condition_normals(),
        mp.nodal_data().scalar(ScalarVar::NodalH, 0),
        mp.nodal_data().vector(VectorVar::Normal, 0),
    );
    s
}

/// A clone of a model past the parallel copy's size, made on pools of 1–3 threads, holds
/// everything the model holds, and its stamps.
#[test]
fn a_big_model_is_cloned_whole_on_any_pool() {
    let n = 50_000u32;
    let mut mp = ModelPart::new("Structure");
    let ids: Vec<u32> = (1..=n).collect();
    let positions: Vec<[f64; 3]> = ids.iter().map(|&i| [i as f64, 0.5, -1.0]).collect();
    mp.add_nodes(&ids, &positions).unwrap();
    // A sparse id, in the hash part of the lookup.
    mp.add_node(NodeId(60_000), p(1.0, 2.0, 3.0)).unwrap();
    let triangles: Vec<u32> = (1..n - 2).flat_map(|i| [i, 1, i, i + 1, i + 2]).collect();
    mp.add_entity_records(true, GeometryKind::Triangle3D3, "C", &triangles)
        .unwrap();
    mp.add_entity_records(false, GeometryKind::Triangle3D3, "E", &triangles)
        .unwrap();
    let part = mp.create_part("a.b").unwrap();
    let some: Vec<NodeIdx> = (0..n / 2).map(NodeIdx).collect();
    mp.add_nodes_to_part(part, &some);
    let conditions: Vec<ConditionIdx> = (0..n - 3).step_by(2).map(ConditionIdx).collect();
    mp.add_conditions_to_part(part, &conditions);
    mp.index_map_mut(ConditionIdx(7)).add_id(ConditionId(9));
    mp.condition_normals_mut()[3] = Vector::new(0.0, 0.0, 1.0);
    let column = (0..mp.nodes().len()).map(|i| i as f64).collect();
    mp.nodal_data_mut()
        .set_scalar(ScalarVar::NodalH, column)
        .unwrap();
    let expected = whole_model(&mp);
    for threads in [1, 2, 3] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let copy = pool.install(|| mp.clone());
        assert_eq!(whole_model(&copy), expected, "{threads} threads");
        assert_eq!(copy.geometry_stamp(), mp.geometry_stamp());
        assert_eq!(copy.condition_normals_stamp(), mp.condition_normals_stamp());
    }
}

/// Bulk insertion in one parallel pass (ids ascending from above every id present) or one by
/// one (any other order, a jump past the dense table) gives the model and the first error
/// that inserting node by node and record by record gives, on pools of 1–3 threads.
#[test]
fn bulk_insertion_in_any_id_order_is_one_by_one_insertion() {
    let n = 5_000u32;
    let ascending: Vec<u32> = (1..=n).collect();
    let descending: Vec<u32> = (1..=n).rev().collect();
    let jump: Vec<u32> = (1..=n).map(|i| if i == n { 1 << 30 } else { i }).collect();
    let later: Vec<u32> = (n + 1..=2 * n).collect();
    let overlapping: Vec<u32> = (n - 10..2 * n - 10).collect();
    // Node batches (ids, index of a NaN position) and, per batch, triangle records over the
    // batch's nodes with the same ids.
    let cases: Vec<Vec<(&[u32], Option<usize>)>> = vec![
        vec![(&ascending, None)],
        vec![(&descending, None)],
        vec![(&jump, None)],
        vec![(&ascending, None), (&later, None)],
        vec![(&ascending, None), (&overlapping, None)],
        vec![(&ascending, Some(4_000))],
        vec![(&ascending, None), (&later, Some(0))],
        vec![(&ascending, None), (&overlapping, Some(20))],
    ];
    let position = |id: u32, nan: bool| {
        let x = if nan { f64::NAN } else { id as f64 };
        [x, 0.5, -1.0]
    };
    let records = |ids: &[u32]| -> Vec<u32> {
        let max = ids.len() - 2;
        (ids.iter().take(max).enumerate())
            .flat_map(|(k, &id)| [id, id % 3, ids[k], ids[k + 1], ids[k + 2]])
            .collect()
    };
    for batches in &cases {
        let one_by_one = {
            let mut mp = ModelPart::new("S");
            let mut errors = Vec::new();
            for &(ids, nan) in batches {
                let first = ids.iter().enumerate().find_map(|(k, &id)| {
                    let p = Point::from(position(id, nan == Some(k)));
                    mp.add_node(NodeId(id), p).err().map(|e| (k, e.to_string()))
                });
                errors.push(first);
                let recs = records(ids);
                let first = recs.chunks(5).enumerate().find_map(|(k, r)| {
                    mp.ensure_properties(PropertiesId(r[1]));
                    let nodes: Vec<NodeId> = r[2..].iter().map(|&i| NodeId(i)).collect();
                    (mp.add_condition(
                        ConditionId(r[0]),
                        GeometryKind::Triangle3D3,
                        "C",
                        &nodes,
                        PropertiesId(r[1]),
                    ))
                    .err()
                    .map(|e| (k, e.to_string()))
                });
                errors.push(first);
            }
            (whole_model(&mp), errors)
        };
        for threads in [1, 2, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let bulk = pool.install(|| {
                let mut mp = ModelPart::new("S");
                let mut errors = Vec::new();
                for &(ids, nan) in batches {
                    let positions: Vec<[f64; 3]> = (ids.iter().enumerate())
                        .map(|(k, &id)| position(id, nan == Some(k)))
                        .collect();
                    let added = mp.add_nodes(ids, &positions);
                    errors.push(added.err().map(|(k, e)| (k, e.to_string())));
                    let recs = records(ids);
                    let added = mp.add_entity_records(true, GeometryKind::Triangle3D3, "C", &recs);
                    errors.push(added.err().map(|(k, e)| (k, e.to_string())));
                }
                (whole_model(&mp), errors)
            });
            assert_eq!(bulk.1, one_by_one.1, "{threads} threads");
            assert!(
                bulk.0 == one_by_one.0,
                "{threads} threads: the models differ"
            );
        }
    }
}

/// The id order: the dense indices themselves where the ids ascend with them (no list
/// kept), else the sorted list; serial and parallel walks give the same order, on conditions
/// added in ascending, descending and mixed id order.
#[test]
fn the_id_order_is_the_sorted_indices() {
    use rayon::prelude::*;
    let mut mp = ModelPart::new("S");
    let n = 3_000u32;
    let ids: Vec<u32> = (1..=n).collect();
    let positions: Vec<[Real; 3]> = (0..n).map(|i| [f64::from(i), 0.0, 0.0]).collect();
    mp.add_nodes(&ids, &positions).unwrap();
    let cases: Vec<Vec<u32>> = vec![
        (1..=1_000).collect(),
        (1..=1_000).rev().collect(),
        (1..=1_000).map(|i| (i * 7_919) % 1_009 + 1).collect(),
        Vec::new(),
    ];
    for (case, cids) in cases.iter().enumerate() {
        let mut mp = mp.clone();
        for &c in cids {
            let nodes = [NodeId(c), NodeId(c + 1), NodeId(c + 2)];
            let kind = GeometryKind::Triangle3D3;
            mp.add_condition(ConditionId(c), kind, "", &nodes, PropertiesId(0))
                .unwrap();
        }
        let order = mp.conditions().id_order();
        let sorted = mp.conditions().indices_by_id();
        assert_eq!(order.len(), sorted.len(), "case {case}");
        assert_eq!(order.is_empty(), sorted.is_empty(), "case {case}");
        assert_eq!(order.iter().collect::<Vec<_>>(), sorted, "case {case}");
        assert_eq!(order.par_iter().collect::<Vec<_>>(), sorted, "case {case}");
        let by_id: Vec<u32> = order.iter().map(|k| mp.conditions().ids()[k]).collect();
        assert!(by_id.windows(2).all(|w| w[0] < w[1]), "case {case}");
        // Ascending ids: the dense order, no list.
        if case == 0 || case == 3 {
            assert!(format!("{order:?}").contains("sorted: None"), "{order:?}");
            assert!((0..order.len()).all(|k| order.get(k) == k));
        }
    }
}
