use super::*;

/// Two hexahedra-free solids and faces of two kinds, entities of mixed kinds interleaved in
/// id order, a nested part.
fn sample() -> ModelPart {
    let mut m = ModelPart::new("Structure");
    for (i, x) in [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 1.0, 0.0],
    ]
    .into_iter()
    .enumerate()
    {
        m.add_node(NodeId(10 + i as u32), Point::from(x)).unwrap();
    }
    let tet = GeometryKind::Tetrahedra3D4;
    m.ensure_properties(PropertiesId(1));
    m.add_element(
        ElementId(1),
        tet,
        "",
        &[NodeId(10), NodeId(11), NodeId(12), NodeId(13)],
        PropertiesId(1),
    )
    .unwrap();
    let (tri, quad) = (GeometryKind::Triangle3D3, GeometryKind::Quadrilateral3D4);
    m.add_condition(
        ConditionId(3),
        tri,
        "",
        &[NodeId(10), NodeId(12), NodeId(11)],
        PropertiesId(0),
    )
    .unwrap();
    m.add_condition(
        ConditionId(5),
        quad,
        "",
        &[NodeId(10), NodeId(11), NodeId(14), NodeId(12)],
        PropertiesId(2),
    )
    .unwrap();
    m.add_condition(
        ConditionId(7),
        tri,
        "",
        &[NodeId(11), NodeId(14), NodeId(12)],
        PropertiesId(0),
    )
    .unwrap();
    let p = m.create_part("Contact.Slave").unwrap();
    let nodes: Vec<_> = [10, 11, 12]
        .map(|id| m.nodes().index_of(id).unwrap())
        .into();
    m.add_nodes_to_part(p, &nodes);
    m.add_conditions_to_part(p, &[ConditionIdx(0), ConditionIdx(2)]);
    let solid = m.create_part("Solid").unwrap();
    m.add_elements_to_part(solid, &[ElementIdx(0)]);
    m
}

use csm_geometry::math::Point;

#[test]
fn every_kind_is_found_by_its_name() {
    for kind in GeometryKind::ALL {
        assert_eq!(GeometryKind::from_name(kind.name()), Some(kind));
    }
    assert_eq!(GeometryKind::from_name("Triangle3D4"), None);
}

#[test]
fn round_trip_gives_the_same_mesh_in_the_same_order() {
    let m = sample();
    let arrays = m.to_arrays();
    assert_eq!(arrays.node_ids, vec![10, 11, 12, 13, 14]);
    let tris = &arrays.conditions[&GeometryKind::Triangle3D3];
    assert_eq!(tris.ids, vec![3, 7]);
    assert_eq!(tris.connectivity, vec![10, 12, 11, 11, 14, 12]);
    assert_eq!(arrays.parts["Contact"].conditions, vec![3, 7]);
    assert_eq!(arrays.parts["Contact.Slave"].nodes, vec![10, 11, 12]);
    assert_eq!(arrays.domain_size, None);
    let back = ModelPart::from_arrays("Structure", &arrays).unwrap();
    let with_domain = MeshArrays {
        domain_size: Some(3),
        ..arrays.clone()
    };
    assert_eq!(back.to_arrays(), with_domain);
    // The conditions of two kinds keep their interleaved id order.
    assert_eq!(back.conditions().ids(), m.conditions().ids());
    assert_eq!(back.conditions().kinds(), m.conditions().kinds());
    assert_eq!(back.part_paths(), m.part_paths());
    assert!(back.properties().contains_key(&PropertiesId(2)));
    // No DOMAIN_SIZE given: 3 with a 3D geometry, 2 when every geometry is 2D.
    assert_eq!(back.process_info().number("DOMAIN_SIZE"), Some(3.0));
    let mut planar = MeshArrays {
        domain_size: None,
        ..arrays.clone()
    };
    planar.elements.clear();
    planar.conditions.clear();
    planar.conditions.insert(
        GeometryKind::Line2D2,
        EntityArrays {
            ids: vec![1],
            connectivity: vec![10, 11],
            properties: vec![0],
        },
    );
    planar.parts.clear();
    let planar = ModelPart::from_arrays("Structure", &planar).unwrap();
    assert_eq!(planar.process_info().number("DOMAIN_SIZE"), Some(2.0));
    assert_eq!(planar.to_arrays().domain_size, Some(2));
}

#[test]
fn bad_arrays_are_refused_with_what_is_wrong() {
    let good = sample().to_arrays();
    let message = |f: &dyn Fn(&mut MeshArrays)| {
        let mut a = good.clone();
        f(&mut a);
        ModelPart::from_arrays("Structure", &a)
            .expect_err("refused")
            .to_string()
    };
    assert_eq!(
        message(&|a| {
            a.points.pop();
        }),
        "points: 4 values, expected 5"
    );
    assert_eq!(
        message(&|a| a.points[2][1] = f64::NAN),
        "node 12 has a NaN or infinite coordinate"
    );
    assert_eq!(
        message(&|a| a.domain_size = Some(1)),
        "DOMAIN_SIZE 1: 2 or 3"
    );
    assert_eq!(message(&|a| a.node_ids[1] = 10), "duplicate node id 10");
    let tri = GeometryKind::Triangle3D3;
    assert_eq!(
        message(&|a| {
            a.conditions.get_mut(&tri).unwrap().connectivity.pop();
        }),
        "conditions Triangle3D3: connectivity: 5 values, expected 6"
    );
    assert_eq!(
        message(&|a| a.conditions.get_mut(&tri).unwrap().connectivity[4] = 99),
        "condition 7 refers to node 99, which does not exist"
    );
    assert_eq!(
        message(&|a| a.parts.get_mut("Solid").unwrap().elements.push(4)),
        "sub model part `Solid` lists element 4, which does not exist"
    );
    assert_eq!(
        message(&|a| {
            a.parts.insert("A..B".to_owned(), PartArrays::default());
        }),
        "invalid sub model part name `A..B` (empty, or a segment contains `.` or `/`)"
    );
}
