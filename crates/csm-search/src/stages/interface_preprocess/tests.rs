use csm_geometry::GeometryKind;
use csm_geometry::math::Point;
use csm_model::{ElementId, Flag, ModelPart, NodeId, PropertiesId};

use super::*;

/// Reference §20.5, 2D: four triangles, INTERFACE on the nodes with y = 0 → 2 conditions.
fn two_d_model() -> (ModelPart, PartIdx) {
    let mut m = ModelPart::new("Main");
    m.process_info_mut().set_number("DOMAIN_SIZE", 2.0);
    let pts = [(0., 0.), (1., 0.), (1., 1.), (0., 1.), (2., 0.), (2., 1.)];
    for (i, (x, y)) in pts.iter().enumerate() {
        m.add_node(NodeId(i as u32 + 1), Point::new(*x, *y, 0.0))
            .unwrap();
    }
    m.ensure_properties(PropertiesId(1));
    let tris = [[1, 2, 3], [1, 3, 4], [2, 5, 3], [5, 6, 3]];
    for (i, t) in tris.iter().enumerate() {
        let ids: Vec<NodeId> = t.iter().map(|&n| NodeId(n)).collect();
        m.add_element(
            ElementId(i as u32 + 1),
            GeometryKind::Triangle2D3,
            "Element2D3N",
            &ids,
            PropertiesId(1),
        )
        .unwrap();
    }
    let part = m.create_part("Interface").unwrap();
    for n in 0..m.nodes().len() {
        let on = m.nodes().coordinates()[n].y == 0.0;
        m.nodes_mut().flags_mut()[n].set(Flag::INTERFACE, on);
    }
    let idx: Vec<_> = [1u32, 2, 5]
        .iter()
        .map(|&i| m.nodes().index_of(i).unwrap())
        .collect();
    m.add_nodes_to_part(part, &idx);
    (m, part)
}

#[track_caller]
fn check(settings: InterfaceSettings, expect: &[(u32, &str, &[u32])]) {
    let (mut m, part) = two_d_model();
    let report = generate_interface_conditions(&mut m, part, &settings).unwrap();
    let got: Vec<(u32, &str, Vec<u32>)> = report
        .created
        .iter()
        .map(|c| (c.id.0, c.name, c.nodes.iter().map(|n| n.0).collect()))
        .collect();
    let expect: Vec<(u32, &str, Vec<u32>)> = expect
        .iter()
        .map(|(i, n, v)| (*i, *n, v.to_vec()))
        .collect();
    assert_eq!(got, expect);
    assert_eq!(m.part(part).conditions().len(), expect.len());
}

#[test]
fn kratos_2d_test_gives_two_edges() {
    check(
        InterfaceSettings::default(),
        &[
            (1, "LineCondition2D2N", &[1, 2]),
            (2, "LineCondition2D2N", &[2, 5]),
        ],
    );
}

#[test]
fn masters_have_slave_undefined_in_kratos_mode_and_false_in_robust_mode() {
    for compatibility in [Compatibility::Kratos, Compatibility::Robust] {
        let (mut m, part) = two_d_model();
        let settings = InterfaceSettings {
            compatibility,
            ..Default::default()
        };
        let r = generate_interface_conditions(&mut m, part, &settings).unwrap();
        let f = m.conditions().flags()[r.created[0].idx.index()];
        assert!(f.is(Flag::MASTER));
        let expect = (compatibility == Compatibility::Robust).then_some(false);
        assert_eq!(f.get(Flag::SLAVE), expect);
    }
}

#[test]
fn fixed_property_fails_on_the_second_element_in_kratos_mode_only() {
    let (mut m, part) = two_d_model();
    let settings = InterfaceSettings {
        contact_property_id: 7,
        ..Default::default()
    };
    let e = generate_interface_conditions(&mut m, part, &settings).unwrap_err();
    assert!(matches!(e.kind(), ErrorKind::RejectedByKratos(_)), "{e}");
    let (mut m, part) = two_d_model();
    let settings = InterfaceSettings {
        contact_property_id: 7,
        compatibility: Compatibility::Robust,
        ..Default::default()
    };
    let r = generate_interface_conditions(&mut m, part, &settings).unwrap();
    assert!(r.created.iter().all(|c| c.properties == PropertiesId(7)));
}

#[test]
fn robust_splits_cover_the_reference_faces_once() {
    // Every split triangle is positively oriented in the reference element and the areas sum
    // to the reference area.
    use csm_geometry::reference_node_coordinates;
    for (kind, area) in [
        (GeometryKind::Triangle3D6, 0.5),
        (GeometryKind::Quadrilateral3D8, 4.0),
        (GeometryKind::Quadrilateral3D9, 4.0),
    ] {
        let r = reference_node_coordinates(kind);
        let table = simplify_split(kind.n_nodes(), false, Compatibility::Robust).unwrap();
        let mut sum = 0.0;
        for t in table {
            let (a, b, c) = (r[t[0]], r[t[1]], r[t[2]]);
            let cross = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
            assert!(cross > 0.0, "{kind:?} {t:?}");
            sum += 0.5 * cross;
        }
        assert!((sum - area).abs() < 1e-12, "{kind:?}");
    }
}

#[test]
fn no_nodes_is_an_error() {
    let (mut m, _) = two_d_model();
    let empty = m.create_part("Empty").unwrap();
    assert!(generate_interface_conditions(&mut m, empty, &InterfaceSettings::default()).is_err());
}
