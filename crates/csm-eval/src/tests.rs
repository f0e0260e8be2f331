//! The ground truth against oracles: the unfiltered all-pairs truth (the prefilter never drops
//! a true pair), the analytic gap of flat scenes, the full truth (samples), a fresh
//! initialization (`set_search_parameters`).

use csm_geometry::math::{Point, Real, Vector};
use csm_model::ModelPart;

use csm_search::scenes::{plates, plates_setup as setup};
use csm_search::{ContactSearch, SearchSetup, SearchTreeType};

use super::*;

const H: Real = 0.25;

fn truth(model: &ModelPart, s: &SearchSetup, prefilter: bool) -> GroundTruth {
    let options = TruthOptions {
        prefilter,
        sample: None,
    };
    GroundTruth::compute_with(model, s, 0, &options).unwrap()
}

/// A seeded deterministic perturbation: moves every node by up to `amplitude` per axis and
/// rotates the whole model by `angle` about a tilted axis (so the normals are oblique).
fn perturbed(mut model: ModelPart, seed: u64, amplitude: Real, angle: Real) -> ModelPart {
    let mut state = seed;
    let mut next = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        ((state >> 11) as Real / (1u64 << 53) as Real) * 2.0 - 1.0
    };
    // Rodrigues' rotation about a tilted unit axis.
    let k = Vector::new(1.0, 2.0, 0.5).normalize();
    let (sin, cos) = angle.sin_cos();
    let rotate = |v: Vector| v * cos + k.cross(&v) * sin + k * k.dot(&v) * (1.0 - cos);
    for p in model.nodes_mut().coordinates_mut() {
        let moved = Point::new(
            p.x + amplitude * next(),
            p.y + amplitude * next(),
            p.z + amplitude * next(),
        );
        *p = Point::from(rotate(moved.coords));
    }
    model
}

#[track_caller]
fn check_prefilter(model: &ModelPart, s: &SearchSetup) {
    let fast = truth(model, s, true);
    let slow = truth(model, s, false);
    assert!(fast.n_pairs() > 0, "the scene has true pairs");
    assert_eq!(fast.pairs, slow.pairs, "the prefilter dropped a true pair");
    assert_eq!(fast.nodes, slow.nodes);
    assert!(fast.overlap_tests <= slow.overlap_tests);
}

#[test]
fn prefilter_never_drops_a_true_pair_on_plates() {
    for simple in [true, false] {
        let s = setup(&format!(r#"{{"simple_search": {simple}}}"#), "");
        for gap in [0.05, 0.0, -0.05, -0.3] {
            check_prefilter(&plates(4, gap, false), &s);
        }
    }
}

#[test]
fn prefilter_never_drops_a_true_pair_on_random_meshes() {
    for seed in 0..6 {
        for simple in [true, false] {
            let s = setup(&format!(r#"{{"simple_search": {simple}}}"#), "");
            let gap = [0.02, -0.04, 0.1][seed as usize % 3];
            let model = perturbed(plates(3, gap, false), seed, 0.03, 0.4 * seed as Real);
            check_prefilter(&model, &s);
        }
    }
}

#[test]
fn the_prefilter_prunes() {
    let s = setup("{}", "");
    let model = plates(6, 0.01, false);
    let fast = truth(&model, &s, true);
    let slow = truth(&model, &s, false);
    assert!(
        fast.overlap_tests * 4 < slow.overlap_tests,
        "{} vs {}",
        fast.overlap_tests,
        slow.overlap_tests
    );
}

/// Flat parallel plates `gap` apart: every mapped slave node has the analytic gap, and every
/// slave node whose projection lies inside the master is mapped.
#[test]
fn the_exact_gap_of_flat_plates_is_the_analytic_gap() {
    let n = 4;
    for gap in [0.1, 0.0, -0.02] {
        let model = plates(n, gap, false);
        let t = truth(&model, &setup("{}", ""), true);
        let extent = n as Real * H;
        let mut mapped = 0;
        for (id, node) in &t.nodes {
            let idx = model.nodes().index_of(*id).unwrap();
            let p = model.nodes().coordinates()[idx.index()];
            let inside = p.x < extent - 1e-9 && p.y < extent - 1e-9;
            match node.normal_gap {
                Some(g) => {
                    assert!((g - gap).abs() < 1e-12, "node {id}: {g} vs {gap}");
                    mapped += 1;
                }
                None => assert!(!inside, "node {id} inside the master is not mapped"),
            }
        }
        assert!(mapped >= n * n, "{mapped}");
    }
}

/// A sample's pairs and gaps are those of the full ground truth on the sampled faces.
#[test]
fn a_sample_agrees_with_the_full_truth() {
    let model = perturbed(plates(5, 0.02, false), 7, 0.02, 0.3);
    for simple in [true, false] {
        let s = setup(&format!(r#"{{"simple_search": {simple}}}"#), "");
        let full = GroundTruth::compute(&model, &s, 0, None).unwrap();
        let sample = Sample { size: 9, seed: 3 };
        let part = GroundTruth::compute(&model, &s, 0, Some(sample)).unwrap();
        assert!(part.sampled && !full.sampled);
        assert_eq!(part.pairs.len(), 9);
        assert_eq!(
            part,
            GroundTruth::compute(&model, &s, 0, Some(sample)).unwrap(),
            "seeded"
        );
        for (slave, masters) in &part.pairs {
            assert_eq!(&full.pairs[slave], masters, "slave {slave}");
        }
        for (id, node) in &part.nodes {
            let exact = full.nodes[id];
            assert_eq!(node.active, exact.active, "node {id}");
            match (node.normal_gap, exact.normal_gap) {
                (Some(a), Some(b)) => assert!((a - b).abs() < 1e-12, "node {id}: {a} vs {b}"),
                (a, b) => assert_eq!(a, b, "node {id}"),
            }
        }
    }
}

/// The default (robust) MappingCheck search finds every true pair of the plates, and scores
/// itself as such.
#[test]
fn the_default_robust_search_finds_every_true_pair_of_the_plates() {
    for simple in [true, false] {
        let s = setup(
            &format!(r#"{{"simple_search": {simple}}}"#),
            r#", "compatibility": "robust""#,
        );
        for gap in [0.02, -0.02] {
            let model = perturbed(plates(4, gap, false), 11, 0.01, 0.2);
            let t = GroundTruth::compute(&model, &s, 0, None).unwrap();
            let mut m = model.clone();
            let mut search = ContactSearch::initialize(&mut m, &s).unwrap();
            let result = search.step(&mut m).unwrap();
            let score = t.score(&result);
            assert_eq!(score.missed, 0, "{score:?}");
            assert_eq!(score.extra_pairs, 0, "{score:?}");
            assert_eq!(score.wrong_active, 0, "{score:?}");
            // Penetrating plates have active nodes (whose gaps are compared).
            assert_eq!(score.max_gap_error.is_some(), gap < 0.0, "{score:?}");
            assert!(score.max_gap_error.is_none_or(|e| e < 1e-9), "{score:?}");
            assert_eq!(score.true_pairs, t.n_pairs());
        }
    }
}

/// A search with a tiny search factor misses pairs, and the score counts them.
#[test]
fn the_score_counts_missed_pairs_and_pruned_candidates() {
    let model = plates(4, 0.01, false);
    let s = setup(
        r#"{"search_factor": 0.3}"#,
        r#", "compatibility": "robust""#,
    );
    let t = GroundTruth::compute(&model, &s, 0, None).unwrap();
    let mut m = model.clone();
    let mut search = ContactSearch::initialize(&mut m, &s).unwrap();
    let small = t.score(&search.step(&mut m).unwrap());
    assert!(small.missed > 0, "{small:?}");
    let s = setup(
        r#"{"search_factor": 6.0}"#,
        r#", "compatibility": "robust""#,
    );
    let mut m = model.clone();
    let mut search = ContactSearch::initialize(&mut m, &s).unwrap();
    let result = search.step(&mut m).unwrap();
    let large = t.score(&result);
    assert_eq!(large.missed, 0, "{large:?}");
    let pruned: usize = result.pruned["0"].values().map(Vec::len).sum();
    assert!(pruned > 0);
    assert_eq!(large.spurious_candidates, pruned, "{large:?}");
}

/// `set_search_parameters` after one initialization gives what a fresh initialization with
/// those parameters gives.
#[test]
fn set_search_parameters_equals_a_fresh_initialize() {
    let model = perturbed(plates(4, 0.01, false), 5, 0.01, 0.3);
    for compat in ["kratos", "robust"] {
        let base = setup("{}", &format!(r#", "compatibility": "{compat}""#));
        let mut m0 = model.clone();
        let search0 = ContactSearch::initialize(&mut m0, &base).unwrap();
        for t in [
            "in_radius",
            "in_box",
            "in_radius_with_obb",
            "in_box_with_obb",
            "octree_with_obb",
            "kdop_18",
        ] {
            for (sf, bbf) in [(1.0, 0.1), (2.5, 0.3)] {
                let sp = format!(
                    r#"{{"type_search": "{t}", "search_factor": {sf},
                        "octree_search_parameters": {{"bounding_box_factor": {bbf}}}}}"#
                );
                let fresh_setup = setup(&sp, &format!(r#", "compatibility": "{compat}""#));
                let mut m1 = model.clone();
                let mut fresh = ContactSearch::initialize(&mut m1, &fresh_setup).unwrap();
                let expected = fresh.step(&mut m1).unwrap();
                let mut m2 = m0.clone();
                let mut reused = search0.clone();
                let params = &fresh_setup.pairs[&0].search;
                assert_eq!(
                    params.type_search.name(),
                    SearchTreeType::name(params.type_search)
                );
                reused.set_search_parameters(&m2, 0, params).unwrap();
                let mut got = reused.step(&mut m2).unwrap();
                // The fresh setup warns about the keys Kratos' Python layer drops.
                got.warnings = expected.warnings.clone();
                assert_eq!(got, expected, "{compat} {t} {sf} {bbf}");
            }
        }
    }
}

#[test]
fn set_search_parameters_refuses_other_changes() {
    let model = plates(2, 0.01, false);
    let base = setup("{}", "");
    let mut m = model.clone();
    let mut search = ContactSearch::initialize(&mut m, &base).unwrap();
    let mut p = base.pairs[&0].search.clone();
    p.simple_search = !p.simple_search;
    assert!(search.set_search_parameters(&m, 0, &p).is_err());
    let mut p = base.pairs[&0].search.clone();
    p.search_factor = Real::NAN;
    assert!(search.set_search_parameters(&m, 0, &p).is_err());
    assert!(
        search
            .set_search_parameters(&m, 9, &base.pairs[&0].search)
            .is_err()
    );
}
