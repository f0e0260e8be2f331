use csm_geometry::math::Point;
use csm_geometry::{Geometry, GeometryKind, reference_node_coordinates};
use csm_model::{ElementId, Flag, ModelPart, NodeId, PropertiesId};

use super::*;

const CUBE: [(f64, f64, f64); 8] = [
    (0., 0., 0.),
    (1., 0., 0.),
    (1., 1., 0.),
    (0., 1., 0.),
    (0., 0., 1.),
    (1., 0., 1.),
    (1., 1., 1.),
    (0., 1., 1.),
];

fn cube(conn: [u32; 8]) -> ModelPart {
    let points: Vec<Point> = CUBE.iter().map(|&(x, y, z)| Point::new(x, y, z)).collect();
    one_solid(
        GeometryKind::Hexahedra3D8,
        "Element3D8N",
        &points,
        &conn,
        true,
    )
}

/// A model of the nodes `points` (ids from 1, INTERFACE as given) and one element of `kind`
/// on the node ids `conn`.
fn one_solid(
    kind: GeometryKind,
    name: &str,
    points: &[Point],
    conn: &[u32],
    interface: bool,
) -> ModelPart {
    let mut m = ModelPart::new("Main");
    for (i, p) in points.iter().enumerate() {
        m.add_node(NodeId(i as u32 + 1), *p).unwrap();
        m.nodes_mut().flags_mut()[i].set(Flag::INTERFACE, interface);
    }
    let ids: Vec<NodeId> = conn.iter().map(|&n| NodeId(n)).collect();
    m.add_element(ElementId(1), kind, name, &ids, PropertiesId(1))
        .unwrap();
    m
}

fn element_nodes(m: &ModelPart) -> Vec<u32> {
    m.elements()
        .nodes(0)
        .iter()
        .map(|n| m.nodes().ids()[n.index()])
        .collect()
}

/// Observed with Kratos 10.4.4 on one unit cube: a mirrored hexahedron is detected and reversed
/// (which leaves it mirrored); a reversed one is not detected.
#[test]
fn single_hexahedron_as_kratos() {
    let mut m = cube([5, 6, 7, 8, 1, 2, 3, 4]);
    let r = normal_check(&mut m, &NormalCheckSettings::default()).unwrap();
    assert_eq!(r.inverted_elements, vec![ElementId(1)]);
    assert_eq!(element_nodes(&m), vec![4, 3, 2, 1, 8, 7, 6, 5]);
    let mut m = cube([8, 7, 6, 5, 4, 3, 2, 1]);
    let r = normal_check(&mut m, &NormalCheckSettings::default()).unwrap();
    assert!(r.inverted_elements.is_empty());
    assert_eq!(element_nodes(&m), vec![8, 7, 6, 5, 4, 3, 2, 1]);
}

#[test]
fn robust_mode_really_reorients_and_restores_marker() {
    let mut m = cube([5, 6, 7, 8, 1, 2, 3, 4]);
    m.nodes_mut().flags_mut()[0].set(Flag::MARKER, true);
    let settings = NormalCheckSettings {
        compatibility: Compatibility::Robust,
        ..Default::default()
    };
    let r = normal_check(&mut m, &settings).unwrap();
    assert_eq!(r.inverted_elements, vec![ElementId(1)]);
    assert_eq!(
        element_nodes(&m),
        vec![1, 2, 3, 4, 5, 6, 7, 8],
        "bottom and top swapped"
    );
    assert_eq!(m.nodes().flags()[0].get(Flag::MARKER), Some(true));
    let again = normal_check(&mut m, &settings).unwrap();
    assert!(
        again.inverted_elements.is_empty(),
        "the element is now positively oriented"
    );
    let mut m = cube([1, 2, 3, 4, 5, 6, 7, 8]);
    m.nodes_mut().flags_mut()[0].set(Flag::MARKER, true);
    normal_check(&mut m, &NormalCheckSettings::default()).unwrap();
    assert_eq!(m.nodes().flags()[0].get(Flag::MARKER), Some(false));
    assert_eq!(m.nodes().flags()[1].get(Flag::MARKER), None);
}

#[test]
fn degenerate_element_is_an_error_not_a_panic() {
    let mut m = ModelPart::new("Main");
    for i in 0..8 {
        m.add_node(NodeId(i + 1), Point::new(0.0, 0.0, 0.0))
            .unwrap();
    }
    let ids: Vec<NodeId> = (1..=8).map(NodeId).collect();
    m.add_element(
        ElementId(1),
        GeometryKind::Hexahedra3D8,
        "",
        &ids,
        PropertiesId(1),
    )
    .unwrap();
    assert!(normal_check(&mut m, &NormalCheckSettings::default()).is_err());
}

/// A hexahedron flattened to its square base: its base face is well shaped, so pass 1 decides
/// that face's probe from the bounds — and still reports the element's singular Jacobian,
/// as the exact probe's inside test does.
#[test]
fn a_flat_element_is_an_error_when_the_bounds_decide_its_face() {
    let points: Vec<Point> = CUBE
        .iter()
        .map(|&(x, y, _)| Point::new(x, y, 0.0))
        .collect();
    let base = Geometry::new(GeometryKind::Quadrilateral3D4, &points[..4]).unwrap();
    assert!(base.centre_probe_bound().is_some());
    let mut m = one_solid(
        GeometryKind::Hexahedra3D8,
        "Element3D8N",
        &points,
        &[1, 2, 3, 4, 5, 6, 7, 8],
        true,
    );
    let err = normal_check(&mut m, &NormalCheckSettings::default()).unwrap_err();
    let message = err.to_string();
    assert!(message.contains("singular Jacobian"), "{message}");
    assert!(message.contains('1'), "{message}");
}

/// The robust permutations reverse the orientation of every kind (solids: sign of det J at the
/// reference centre; faces: direction of the normal) and keep mid nodes between their corners.
#[test]
fn inversion_permutations_reverse_orientation() {
    for kind in GeometryKind::ALL {
        let perm = inversion_permutation(kind);
        let reference: Vec<Point> = reference_node_coordinates(kind)
            .iter()
            .map(|a| Point::new(a[0], a[1], a[2]))
            .collect();
        // Embed 2D kinds in the xy plane, lines along x.
        let permuted: Vec<Point> = perm.iter().map(|&p| reference[p]).collect();
        let g = Geometry::new(kind, &reference).unwrap();
        let h = Geometry::new(kind, &permuted).unwrap();
        let c = g.reference_center();
        if kind.is_face() && kind.working_dim() == 3 || kind.local_dim() == 1 {
            let n0 = g.normal(&c).unwrap();
            let n1 = h.normal(&c).unwrap();
            assert!(n0.dot(&n1) < 0.0, "{kind:?}");
        } else {
            let d0 = g.jacobian(&c).determinant();
            let d1 = h.jacobian(&c).determinant();
            let (d0, d1) = if kind.local_dim() == 2 {
                let j0 = g.jacobian(&c);
                let j1 = h.jacobian(&c);
                (
                    j0[(0, 0)] * j0[(1, 1)] - j0[(0, 1)] * j0[(1, 0)],
                    j1[(0, 0)] * j1[(1, 1)] - j1[(0, 1)] * j1[(1, 0)],
                )
            } else {
                (d0, d1)
            };
            assert!(d0 * d1 < 0.0, "{kind:?}");
        }
        // A valid numbering: the permuted nodes are an affine image of the reference nodes
        // (fitted on the corners 0 and the neighbours of 0 along each local axis).
        let axes: &[usize] = match kind.local_dim() {
            1 => &[1],
            _ if matches!(reference.len(), 4 | 8 | 9) && kind.local_dim() == 2 => &[1, 3],
            2 => &[1, 2],
            _ if matches!(
                kind,
                GeometryKind::Hexahedra3D8
                    | GeometryKind::Hexahedra3D20
                    | GeometryKind::Hexahedra3D27
            ) =>
            {
                &[1, 3, 4]
            }
            _ => &[1, 2, 3],
        };
        let mut r = csm_geometry::math::Matrix3::identity();
        let mut q = csm_geometry::math::Matrix3::identity();
        for (k, &a) in axes.iter().enumerate() {
            r.set_column(k, &(reference[a] - reference[0]));
            q.set_column(k, &(permuted[a] - permuted[0]));
        }
        let m = q * r.try_inverse().unwrap_or_else(|| panic!("{}", kind.name()));
        for (i, p) in permuted.iter().enumerate() {
            let x = permuted[0] + m * (reference[i] - reference[0]);
            assert!((x - p).norm() < 1e-12, "{kind:?} node {i}");
        }
    }
}

/// A shell (Quadrilateral3D4 element, not solid) under two triangle conditions, with MARKER
/// defined on some entities.
fn shell_model() -> ModelPart {
    let mut m = ModelPart::new("Main");
    for (i, (x, y)) in [(0., 0.), (1., 0.), (1., 1.), (0., 1.)].iter().enumerate() {
        m.add_node(NodeId(i as u32 + 1), Point::new(*x, *y, 0.0))
            .unwrap();
    }
    let ids = |v: &[u32]| v.iter().map(|&n| NodeId(n)).collect::<Vec<_>>();
    m.add_element(
        ElementId(1),
        GeometryKind::Quadrilateral3D4,
        "ShellThinElement3D4N",
        &ids(&[1, 2, 3, 4]),
        PropertiesId(1),
    )
    .unwrap();
    for (id, nodes) in [(1, [1, 2, 3]), (2, [1, 3, 4])] {
        m.add_condition(
            csm_model::ConditionId(id),
            GeometryKind::Triangle3D3,
            "SurfaceCondition3D3N",
            &ids(&nodes),
            PropertiesId(1),
        )
        .unwrap();
    }
    m.nodes_mut().flags_mut()[0].set(Flag::MARKER, true);
    m.nodes_mut().flags_mut()[1].set(Flag::MARKER, false);
    m.elements_mut().flags_mut()[0].set(Flag::MARKER, true);
    m.conditions_mut().flags_mut()[1].set(Flag::MARKER, true);
    m
}

/// Without solid elements the short path leaves the model exactly as the full check does
/// (flags, connectivity, condition and nodal normals) and reports the same, in both modes.
#[test]
fn normals_only_equals_the_full_check_without_solids() {
    for compatibility in [Compatibility::Kratos, Compatibility::Robust] {
        let settings = NormalCheckSettings {
            compatibility,
            ..NormalCheckSettings::default()
        };
        let mut full = shell_model();
        let mut short = shell_model();
        assert_eq!(count_solid_elements(&full), 0);
        let r_full = normal_check(&mut full, &settings).unwrap();
        let r_short = normal_check_normals_only(&mut short, &settings).unwrap();
        assert_eq!(r_full, r_short);
        assert_eq!(r_short.slender_elements, vec![ElementId(1)]);
        assert_eq!(full.nodes().flags(), short.nodes().flags());
        assert_eq!(full.elements().flags(), short.elements().flags());
        assert_eq!(full.conditions().flags(), short.conditions().flags());
        assert_eq!(full.condition_normals(), short.condition_normals());
        assert_eq!(
            full.nodal_data().vector(VectorVar::Normal, 0),
            short.nodal_data().vector(VectorVar::Normal, 0)
        );
        for c in 0..2 {
            assert_eq!(full.conditions().nodes(c), short.conditions().nodes(c));
        }
    }
}

#[test]
fn solid_elements_are_counted() {
    assert_eq!(count_solid_elements(&cube([1, 2, 3, 4, 5, 6, 7, 8])), 1);
}

/// Kratos measures an element in pass 2 only for an INTERFACE node: a prism whose Jacobian is
/// singular at its first corner (where its Length() is taken) but not at its centre passes the
/// check without INTERFACE nodes and fails it with one.
#[test]
fn pass_2_measures_only_elements_with_interface_nodes() {
    let g = [
        Point::new(0.0, 0.0, 0.0),
        Point::new(1.0, 0.0, 0.0),
        Point::new(0.0, 1.0, 0.0),
        Point::new(0.3, 0.3, 0.0),
        Point::new(1.0, 0.0, 1.0),
        Point::new(0.0, 1.0, 1.0),
    ];
    let prism = |interface| {
        one_solid(
            GeometryKind::Prism3D6,
            "",
            &g,
            &[1, 2, 3, 4, 5, 6],
            interface,
        )
    };
    assert!(
        Geometry::new(GeometryKind::Prism3D6, &g)
            .unwrap()
            .length()
            .is_err()
    );
    assert!(normal_check(&mut prism(false), &NormalCheckSettings::default()).is_ok());
    let e = normal_check(&mut prism(true), &NormalCheckSettings::default()).unwrap_err();
    assert!(e.to_string().contains("zero length"), "{e}");
}
