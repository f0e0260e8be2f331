//! Unit tests of the `shape` module.
use super::*;
use crate::GeometryKind;
use crate::math::Point;

fn sample_points(kind: GeometryKind) -> Vec<Point> {
    let d = kind.local_dim();
    let raw = [
        [0.1, 0.2, 0.3],
        [0.25, 0.05, 0.6],
        [-0.3, 0.7, 0.15],
        [0.6, 0.1, 0.9],
    ];
    raw.iter()
        .map(|r| {
            let mut p = Point::new(r[0], r[1], r[2]);
            for k in d..3 {
                p[k] = 0.0;
            }
            p
        })
        .collect()
}

#[test]
fn partition_of_unity_every_kind() {
    for kind in GeometryKind::ALL {
        for p in sample_points(kind) {
            let n = shape_functions(kind, &p);
            assert_eq!(n.len(), kind.n_nodes(), "{kind:?}");
            let s: f64 = n.iter().sum();
            assert!((s - 1.0).abs() < 1e-12, "{kind:?}: sum {s}");
            let dn = shape_derivatives(kind, &p);
            for k in 0..3 {
                let s: f64 = dn.rows().iter().map(|r| r[k]).sum();
                assert!(s.abs() < 1e-12, "{kind:?}: d/dxi_{k} sum {s}");
            }
        }
    }
}

#[test]
fn kronecker_at_nodes_every_kind() {
    for kind in GeometryKind::ALL {
        let nodes = reference_node_coordinates(kind);
        assert_eq!(nodes.len(), kind.n_nodes(), "{kind:?}");
        for (j, a) in nodes.iter().enumerate() {
            let n = shape_functions(kind, &Point::new(a[0], a[1], a[2]));
            for (i, v) in n.iter().enumerate() {
                let expected = if i == j { 1.0 } else { 0.0 };
                assert!(
                    (v - expected).abs() < 1e-14,
                    "{kind:?} N{i}(node {j}) = {v}"
                );
            }
        }
    }
}

#[test]
fn derivatives_match_finite_differences_every_kind() {
    let h = 1e-6;
    for kind in GeometryKind::ALL {
        for p in sample_points(kind) {
            let dn = shape_derivatives(kind, &p);
            assert_eq!(dn.local_dim(), kind.local_dim());
            for k in 0..kind.local_dim() {
                let mut pp = p;
                let mut pm = p;
                pp[k] += h;
                pm[k] -= h;
                let np = shape_functions(kind, &pp);
                let nm = shape_functions(kind, &pm);
                for i in 0..kind.n_nodes() {
                    let fd = (np[i] - nm[i]) / (2.0 * h);
                    assert!(
                        (fd - dn.get(i, k)).abs() < 1e-7,
                        "{kind:?} dN{i}/dxi{k}: fd {fd} vs {}",
                        dn.get(i, k)
                    );
                }
            }
        }
    }
}
