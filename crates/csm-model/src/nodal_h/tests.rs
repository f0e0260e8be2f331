use csm_geometry::GeometryKind;
use csm_geometry::math::Point;

use super::*;
use crate::{ElementId, NodeId, PropertiesId};

/// One triangle with edges d01 = 3, d12 = 5, d02 = 4 (a 3-4-5 right triangle), plus a node
/// in no element.
fn triangle() -> ModelPart {
    let mut mp = ModelPart::new("Structure");
    mp.add_node(NodeId(1), Point::new(0.0, 0.0, 0.0)).unwrap();
    mp.add_node(NodeId(2), Point::new(3.0, 0.0, 0.0)).unwrap();
    mp.add_node(NodeId(3), Point::new(0.0, 4.0, 0.0)).unwrap();
    mp.add_node(NodeId(4), Point::new(9.0, 9.0, 0.0)).unwrap();
    let ids = [NodeId(1), NodeId(2), NodeId(3)];
    mp.add_element(
        ElementId(1),
        GeometryKind::Triangle2D3,
        "",
        &ids,
        PropertiesId(0),
    )
    .unwrap();
    mp
}

#[test]
fn stale_read_mode_keeps_only_the_last_pair_for_each_node_q40() {
    // Reference §17.3: h0 = d02 (d01 lost), h1 = min(d01, d12), h2 = min(d02, d12).
    let h = compute_nodal_h(&triangle(), None, NodalHMode::StaleRead);
    assert_eq!(h[0], 4.0, "d01 = 3 is lost for node 0 (Q40)");
    assert_eq!(h[1], 3.0);
    assert_eq!(h[2], 4.0);
    assert_eq!(h[3], f64::MAX, "node in no element keeps DBL_MAX");
}

#[test]
fn kratos_and_minimum_edge_modes_are_the_true_minimum_on_a_triangle() {
    for mode in [NodalHMode::Kratos, NodalHMode::MinimumEdge] {
        let h = compute_nodal_h(&triangle(), None, mode);
        assert_eq!(&h[..3], &[3.0, 3.0, 4.0], "{mode:?}");
        assert_eq!(h[3], f64::MAX);
    }
}

#[test]
fn minimum_edge_ignores_diagonals_of_a_distorted_quadrilateral() {
    // A kite whose diagonal 1–3 (length 0.2) is shorter than every edge (about 1.02).
    let mut mp = ModelPart::new("Structure");
    let pts = [(0.0, 0.0), (1.0, -0.1), (2.0, 0.0), (1.0, 0.1)];
    for (i, (x, y)) in pts.iter().enumerate() {
        mp.add_node(NodeId(i as u32 + 1), Point::new(*x, *y, 0.0))
            .unwrap();
    }
    let ids = [NodeId(1), NodeId(2), NodeId(3), NodeId(4)];
    mp.add_element(
        ElementId(1),
        GeometryKind::Quadrilateral2D4,
        "",
        &ids,
        PropertiesId(0),
    )
    .unwrap();
    let kratos = compute_nodal_h(&mp, None, NodalHMode::Kratos);
    let edge = compute_nodal_h(&mp, None, NodalHMode::MinimumEdge);
    assert!(
        (kratos[1] - 0.2).abs() < 1e-15,
        "Kratos counts the diagonal"
    );
    assert!(
        (edge[1] - (1.0f64 + 0.01).sqrt()).abs() < 1e-15,
        "edges only"
    );
}

#[test]
fn a_part_without_elements_leaves_every_node_at_max_and_assign_stores_it() {
    let mut mp = triangle();
    let part = mp.create_part("empty").unwrap();
    assign_nodal_h(&mut mp, Some(part), NodalHMode::Kratos);
    let h = mp.nodal_data().scalar(ScalarVar::NodalH, 0).unwrap();
    assert!(h.iter().all(|&x| x == f64::MAX));
    assign_nodal_h(&mut mp, None, NodalHMode::Kratos);
    assert_eq!(
        mp.nodal_data().scalar(ScalarVar::NodalH, 0).unwrap()[1],
        3.0
    );
}

/// The parallel minima (element chunks per worker, then the element-wise minimum) are the
/// serial ones bit for bit, for the whole model and for a part.
#[test]
fn parallel_minima_are_the_serial_ones() {
    let mut mp = ModelPart::new("Structure");
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    for i in 0..400u32 {
        let mut c = || (next() % 10_000) as f64 * 1e-3 + 0.1 * f64::from(i);
        mp.add_node(NodeId(i + 1), Point::new(c(), c(), c()))
            .unwrap();
    }
    for e in 0..900u32 {
        let ids: Vec<NodeId> = (0..4).map(|_| NodeId((next() % 400) as u32 + 1)).collect();
        mp.add_element(
            ElementId(e + 1),
            GeometryKind::Tetrahedra3D4,
            "",
            &ids,
            PropertiesId(0),
        )
        .unwrap();
    }
    let part = mp.create_part("Half").unwrap();
    let half: Vec<crate::ElementIdx> = (0..450).map(crate::ElementIdx).collect();
    mp.add_elements_to_part(part, &half);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(3)
        .build()
        .unwrap();
    for mode in [
        NodalHMode::Kratos,
        NodalHMode::MinimumEdge,
        NodalHMode::StaleRead,
    ] {
        for p in [None, Some(part)] {
            let serial = compute_nodal_h_with(&mp, p, mode, usize::MAX);
            let parallel = pool.install(|| compute_nodal_h_with(&mp, p, mode, 1));
            let bits = |h: &[f64]| h.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&parallel), bits(&serial), "{mode:?} {p:?}");
            assert!(serial.iter().any(|&x| x < f64::MAX));
        }
    }
}
