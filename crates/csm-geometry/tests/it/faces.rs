//! Faces of solids: Kratos' node order gives outward normals on positively oriented solids,
//! and quadratic faces carry their mid nodes in the face kind's numbering.

use crate::common::Rng;
use csm_geometry::math::{Point, Vector};
use csm_geometry::{Geometry, GeometryKind, reference_node_coordinates};
use parry3d_f64::na::UnitQuaternion;

fn solids() -> impl Iterator<Item = GeometryKind> {
    GeometryKind::ALL.into_iter().filter(|k| k.is_solid())
}

/// The reference element's nodes, mapped by `x ↦ R (S x) + T` with positive scales (2D kinds
/// are rotated about z only), optionally jittered (corners only for linear kinds).
fn placed(kind: GeometryKind, rng: Option<&mut Rng>) -> Vec<Point> {
    let nodes = reference_node_coordinates(kind);
    let Some(rng) = rng else {
        return nodes.iter().map(|a| Point::new(a[0], a[1], a[2])).collect();
    };
    let s = rng.vector(0.5, 2.0);
    let r = if kind.working_dim() == 2 {
        UnitQuaternion::from_scaled_axis(Vector::z() * rng.range(-3.0, 3.0))
    } else {
        rng.rotation()
    };
    let t = rng.vector(-5.0, 5.0);
    nodes
        .iter()
        .map(|a| {
            let mut local = Vector::new(a[0] * s.x, a[1] * s.y, a[2] * s.z);
            if kind.n_nodes() <= 8 {
                let j = rng.vector(-0.05, 0.05);
                local += if kind.working_dim() == 2 {
                    Vector::new(j.x, j.y, 0.0)
                } else {
                    j
                };
            }
            Point::from(r * local + t)
        })
        .collect()
}

fn check_outward(kind: GeometryKind, pts: &[Point]) {
    let solid = Geometry::new(kind, pts).unwrap();
    let c = solid.center();
    assert!(!kind.faces().is_empty(), "{kind:?} has faces");
    for (face_kind, idx) in kind.faces() {
        assert_eq!(idx.len(), face_kind.n_nodes(), "{kind:?}");
        let face_pts: Vec<Point> = idx.iter().map(|&i| pts[i]).collect();
        let face = Geometry::new(*face_kind, &face_pts).unwrap();
        let n = face.unit_normal(&face.reference_center()).unwrap();
        let out = (face.center() - c).dot(&n);
        assert!(
            out > 0.0,
            "{kind:?} face {idx:?}: normal {n:?} points inwards"
        );
    }
}

#[test]
fn faces_point_outwards_on_reference_solids() {
    for kind in solids() {
        check_outward(kind, &placed(kind, None));
    }
}

#[test]
fn faces_point_outwards_on_moved_distorted_solids() {
    let mut rng = Rng::new(0xFACE);
    for _ in 0..20 {
        for kind in solids() {
            check_outward(kind, &placed(kind, Some(&mut rng)));
        }
    }
}

#[test]
fn every_face_is_a_boundary_face_and_faces_cover_the_corners() {
    for kind in solids() {
        let mut seen = vec![false; kind.n_nodes()];
        for (_, idx) in kind.faces() {
            for &i in *idx {
                seen[i] = true;
            }
        }
        let interior = match kind {
            GeometryKind::Quadrilateral2D9 => vec![8],
            GeometryKind::Hexahedra3D27 => vec![26],
            _ => vec![],
        };
        for (i, s) in seen.iter().enumerate() {
            assert_eq!(*s, !interior.contains(&i), "{kind:?} node {i}");
        }
    }
}

/// The face's quadratic nodes sit where the face kind's numbering expects them.
#[test]
fn quadratic_faces_use_the_face_numbering() {
    for kind in solids() {
        let pts = placed(kind, None);
        for (face_kind, idx) in kind.faces() {
            let linear = match face_kind {
                GeometryKind::Line2D3 => GeometryKind::Line2D2,
                GeometryKind::Triangle3D6 => GeometryKind::Triangle3D3,
                GeometryKind::Quadrilateral3D8 | GeometryKind::Quadrilateral3D9 => {
                    GeometryKind::Quadrilateral3D4
                }
                _ => continue,
            };
            let face_pts: Vec<Point> = idx.iter().map(|&i| pts[i]).collect();
            let corners = &face_pts[..linear.n_nodes()];
            let g = Geometry::new(linear, corners).unwrap();
            for (j, a) in reference_node_coordinates(*face_kind).iter().enumerate() {
                let expected = g.global_coordinates(&Point::new(a[0], a[1], a[2]));
                assert!(
                    (expected - face_pts[j]).norm() < 1e-14,
                    "{kind:?} face {idx:?} node {j}"
                );
            }
        }
    }
}

/// The face order and node order of every linear solid equal Kratos 10.4.4's, as observed
/// through `InterfacePreprocessCondition` (fixture made by `cargo xtask fixtures`).
#[test]
fn faces_match_kratos_fixture() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../tests/fixtures/faces.json"
    );
    let text = std::fs::read_to_string(path).expect("faces fixture");
    let fixture: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    let kinds = [
        GeometryKind::Tetrahedra3D4,
        GeometryKind::Hexahedra3D8,
        GeometryKind::Prism3D6,
        GeometryKind::Triangle2D3,
        GeometryKind::Quadrilateral2D4,
    ];
    for kind in kinds {
        let expected: Vec<Vec<usize>> =
            serde_json::from_value(fixture["faces"][kind.name()].clone()).expect("face lists");
        let ours: Vec<Vec<usize>> = kind
            .faces()
            .iter()
            .map(|(_, nodes)| nodes.to_vec())
            .collect();
        assert_eq!(ours, expected, "{}", kind.name());
    }
}

/// Every edge joins two distinct nodes of the geometry, and the corner edges of every face of
/// a solid are edges of the solid.
#[test]
fn edges_are_consistent_with_faces() {
    for kind in GeometryKind::ALL {
        let edges = kind.edges();
        assert!(!edges.is_empty(), "{kind:?}");
        for [a, b] in edges {
            assert!(
                a != b && *a < kind.n_nodes() && *b < kind.n_nodes(),
                "{kind:?}"
            );
        }
        let has = |a: usize, b: usize| edges.iter().any(|e| *e == [a, b] || *e == [b, a]);
        for (face, nodes) in kind.faces() {
            let corners = face
                .edges()
                .iter()
                .flat_map(|e| e.iter())
                .max()
                .map_or(0, |m| m + 1);
            for [a, b] in face.edges() {
                assert!(*a < corners && *b < corners);
                assert!(
                    has(nodes[*a], nodes[*b]),
                    "{kind:?} face {nodes:?} edge {a}-{b}"
                );
            }
        }
    }
}
