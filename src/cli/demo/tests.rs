//! The demo scene: sizes, orientation of faces and solids, search on it.

use csm_geometry::GeometryKind;
use csm_geometry::math::{Point, Vector};
use csm_model::{ModelPart, NormalsMode, compute_unit_normals};

use super::demo_scene;
use crate::cli::{default_setup, run_search};

/// Six times the signed volume of the tetrahedron a, b, c, d: positive when the right-hand
/// normal of a-b-c points towards d.
fn volume6(a: Point, b: Point, c: Point, d: Point) -> f64 {
    (b - a).cross(&(c - a)).dot(&(d - a))
}

fn points(model: &ModelPart, e: usize) -> Vec<Point> {
    let xyz = model.nodes().coordinates();
    model
        .elements()
        .nodes(e)
        .iter()
        .map(|n| xyz[n.index()])
        .collect()
}

#[test]
fn sizes_and_parts() {
    let scene = demo_scene(2000).unwrap();
    // n = round(√1000) = 32, m = round(√500) = 22.
    assert_eq!(scene.n_master_faces, 32 * 32);
    assert_eq!(scene.n_slave_faces, 2 * 22 * 22);
    let m = &scene.model;
    assert_eq!(m.process_info().number("DOMAIN_SIZE"), Some(3.0));
    let part = |p: &str| m.part(m.get_part(p).unwrap());
    assert_eq!(part("master").conditions().len(), 32 * 32);
    assert_eq!(part("slave").conditions().len(), 2 * 22 * 22);
    assert_eq!(part("plate").elements().len(), 32 * 32 * 2);
    assert_eq!(part("sphere").elements().len(), 2 * 22 * 22);
    // Every node belongs to an element.
    let mut in_element = vec![false; m.nodes().len()];
    for e in 0..m.elements().len() {
        for n in m.elements().nodes(e) {
            in_element[n.index()] = true;
        }
    }
    assert!(in_element.iter().all(|&x| x));
    // The default is about 2e4 faces.
    let big = demo_scene(super::DEFAULT_FACES).unwrap();
    let total = big.n_master_faces + big.n_slave_faces;
    assert!((19_000..=21_000).contains(&total), "{total}");
    assert!(demo_scene(super::MAX_FACES + 1).is_err());
    assert!(demo_scene(0).is_ok());
}

#[test]
fn normals_point_out_of_each_body_and_solids_have_positive_volume() {
    let mut scene = demo_scene(800).unwrap();
    let m = &mut scene.model;
    compute_unit_normals(m, None, NormalsMode::Kratos).unwrap();
    let slave = m.get_part("slave").unwrap();
    let master = m.get_part("master").unwrap();
    let normals = m.condition_normals();
    for c in m.part(slave).conditions() {
        assert!(
            normals[c.index()].z < -0.8,
            "slave {:?}",
            normals[c.index()]
        );
    }
    for c in m.part(master).conditions() {
        let n: Vector = normals[c.index()];
        assert!((n - Vector::z()).norm() < 1e-12, "master {n:?}");
    }
    for e in 0..m.elements().len() {
        let p = points(m, e);
        match m.elements().kind(e) {
            GeometryKind::Hexahedra3D8 => {
                assert!(volume6(p[0], p[1], p[2], p[4]) > 0.0);
                assert!(volume6(p[0], p[2], p[3], p[6]) > 0.0);
            }
            GeometryKind::Prism3D6 => assert!(volume6(p[0], p[1], p[2], p[3]) > 0.0),
            k => panic!("unexpected element {k:?}"),
        }
    }
    // The sphere penetrates the plate (top at z = 0) by a tenth of the element size.
    let xyz = m.nodes().coordinates();
    let sphere = m.get_part("sphere").unwrap();
    let lowest = m
        .part(sphere)
        .nodes()
        .iter()
        .map(|n| xyz[n.index()].z)
        .fold(f64::INFINITY, f64::min);
    assert!(
        lowest < 0.0 && lowest >= -scene.penetration - 1e-12,
        "{lowest}"
    );
    assert!((scene.penetration - 0.1 * scene.element_size).abs() < 1e-15);
}

#[test]
fn the_default_search_finds_pairs_under_the_sphere() {
    let mut scene = demo_scene(2000).unwrap();
    let setup = default_setup(&scene.model).unwrap();
    let (result, _) = run_search(&mut scene.model, &setup, 0.0).unwrap();
    assert!(result.n_pairs() > 0);
    let text = super::demo_summary(&scene, &result, &crate::cli::Timings::default());
    assert!(text.contains("pairs"), "{text}");
}

/// The whole model of the smallest scene as text: every node (id, coordinates), element and
/// condition (id, kind, name, properties, node ids) and part (its nodes', elements' and
/// conditions' ids), in index order.
fn model_text(m: &ModelPart) -> String {
    use std::fmt::Write as _;
    let mut s = String::new();
    let node_ids = m.nodes().ids();
    let ids = |nodes: &[csm_model::NodeIdx]| -> Vec<u32> {
        nodes.iter().map(|n| node_ids[n.index()]).collect()
    };
    for (i, (id, x)) in node_ids.iter().zip(m.nodes().coordinates()).enumerate() {
        let x0 = m.nodes().initial_coordinates()[i];
        assert_eq!(*x, x0, "node {id}: current and initial coordinates differ");
        writeln!(s, "node {id} {:.9} {:.9} {:.9}", x.x, x.y, x.z).unwrap();
    }
    for (label, entities) in [("element", m.elements()), ("condition", m.conditions())] {
        for i in 0..entities.len() {
            writeln!(
                s,
                "{label} {} {:?} {} p{} {:?}",
                entities.ids()[i],
                entities.kind(i),
                entities.name(i),
                entities.properties(i).0,
                ids(entities.nodes(i))
            )
            .unwrap();
        }
    }
    for path in m.part_paths() {
        let part = m.part(m.get_part(path).unwrap());
        let elements: Vec<u32> = (part.elements().iter())
            .map(|e| m.elements().ids()[e.index()])
            .collect();
        let conditions: Vec<u32> = (part.conditions().iter())
            .map(|c| m.conditions().ids()[c.index()])
            .collect();
        writeln!(
            s,
            "part {path}: nodes {:?} elements {elements:?} conditions {conditions:?}",
            ids(part.nodes())
        )
        .unwrap();
    }
    s
}

/// The smallest scene (2 × 2 plate faces, 2 × 2 cap cells), entity by entity: the builder's
/// ids, order, connectivity and parts.
#[test]
fn the_smallest_scene_entity_by_entity() {
    let scene = demo_scene(8).unwrap();
    insta::assert_snapshot!(model_text(&scene.model));
}
