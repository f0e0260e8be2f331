//! Degenerate and random inputs: errors, never panics or NaN.

use csm_geometry::math::Point;
use csm_geometry::{Geometry, GeometryKind, Obb, Obb2};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};

fn coordinate() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => -2.0..2.0f64,
        1 => Just(0.0),
        1 => Just(1.0),
        1 => Just(f64::NAN),
    ]
}

fn kind() -> impl Strategy<Value = GeometryKind> {
    proptest::sample::select(GeometryKind::ALL.to_vec())
}

fn config() -> Config {
    Config {
        cases: 512,
        rng_seed: RngSeed::Fixed(0xDE6E),
        ..Config::default()
    }
}

proptest! {
    #![proptest_config(config())]

    /// Any geometry, possibly with NaN or coincident nodes (a pool of 3 points reused), and
    /// any query: every operation returns a finite value or an error.
    #[test]
    fn every_operation_is_total(
        kind in kind(),
        pool in proptest::collection::vec((coordinate(), coordinate(), coordinate()), 3),
        picks in proptest::collection::vec(0usize..3, 27),
        jitter in proptest::collection::vec(-1.0..1.0f64, 27),
        jitter_on in any::<bool>(),
        q in (-2.0..2.0f64, -2.0..2.0f64, -2.0..2.0f64),
    ) {
        let pts: Vec<Point> = (0..kind.n_nodes())
            .map(|i| {
                let (x, y, z) = pool[picks[i]];
                let j = if jitter_on { jitter[i] } else { 0.0 };
                let z = if kind.working_dim() == 2 { 0.0 } else { z + j };
                Point::new(x + j, y, z)
            })
            .collect();
        let Ok(g) = Geometry::new(kind, &pts) else { return Ok(()) };
        let q = Point::new(q.0, q.1, if kind.working_dim() == 2 { 0.0 } else { q.2 });
        let finite = |v: f64| v.is_finite();
        if let Ok(v) = g.length() { prop_assert!(finite(v) && v > 0.0) }
        if let Ok(v) = g.area() { prop_assert!(finite(v) && v > 0.0) }
        if let Ok(v) = g.area_robust() { prop_assert!(finite(v) && v > 0.0) }
        if let Ok(v) = g.volume() { prop_assert!(finite(v) && v > 0.0) }
        if let Ok(v) = g.domain_size() { prop_assert!(finite(v) && v > 0.0) }
        if let Ok(n) = g.unit_normal(&g.reference_center()) {
            prop_assert!((n.norm() - 1.0).abs() < 1e-12);
        }
        if let Ok(l) = g.point_local_coordinates(&q) {
            prop_assert!(l.coords.iter().all(|c| c.is_finite()));
        }
        let _ = g.is_inside(&q, 1e-8);
        prop_assert!(g.center().coords.iter().all(|c| c.is_finite()));
        prop_assert!(g.bounding_sphere().radius.is_finite());
        for bfb in [true, false] {
            if let Ok(obb) = Obb::from_geometry(&g, 0.1, bfb) {
                prop_assert!(obb.half_lengths.iter().all(|h| h.is_finite()));
                prop_assert!(obb.axes.iter().all(|a| (a.norm() - 1.0).abs() < 1e-12));
            }
        }
        if let Ok(obb) = Obb2::from_geometry(&g, 0.1) {
            prop_assert!(obb.half_lengths.iter().all(|h| h.is_finite()));
        }
    }
}
