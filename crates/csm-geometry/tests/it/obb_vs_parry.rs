//! SAT (both modes) and Direct against `parry3d_f64::query::intersection_test` on random cuboid
//! pairs, including nearly parallel, exactly aligned and touching boxes.
//!
//! Measured (seeds 0x5A7.., 4 × 5000 pairs: generic, nearly parallel (10⁻¹²..10⁻⁶ rad), exactly
//! aligned, touching face-to-face with gap 0 or ±10⁻¹⁴..10⁻⁴; see
//! `kratos_mode_disagreement_rate`, run with `--nocapture`):
//!
//! | | compared (outside band) | in band |
//! |---|---|---|
//! | pairs | 16166 | 3834 (all "touching") |
//! | Kratos SAT ≠ parry | **0 (0 %)** | 329 (8.6 % of in-band pairs) |
//! | Kratos SAT(a,b) ≠ SAT(b,a) | 0 | 43 |
//! | Robust SAT ≠ parry | 0 (asserted) | not compared |
//! | Direct ≠ parry | 0 (asserted) | not compared |
//!
//! So the Kratos-literal SAT's noise verdicts (Q2) show up only for pairs within ~1e-8 · scale
//! of touching, where parry's own verdict is also at rounding level; there it disagrees with
//! parry in 8.6 % of the pairs and is argument-order dependent in 1.1 %.

use crate::common::{ALL_KINDS, BAND, PairKind, Rng, TestBox, parry, random_pair, sat_gap, scale};
use csm_geometry::math::{Point, Vector};
use csm_geometry::{
    Obb, Obb2, SatMode, direct_obb_obb, direct_obb2_obb2, sat_obb_obb, sat_obb2_obb2,
};
use parry3d_f64::na::UnitQuaternion;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};

/// `Some(parry verdict)` outside the touching band, `None` inside it. The band is symmetric:
/// pairs whose largest SAT gap (a lower bound of the distance when separated, minus the
/// penetration depth when overlapping) is within `BAND · scale` of zero, or that parry calls
/// separated at a distance below `BAND · scale`.
fn oracle(a: &TestBox, b: &TestBox) -> Option<bool> {
    let (hit, d) = parry(a, b);
    let band = BAND * scale(a, b);
    if sat_gap(a, b).abs() <= band || (!hit && d <= band) {
        None
    } else {
        Some(hit)
    }
}

#[derive(Default, Debug)]
struct Tally {
    compared: usize,
    in_band: usize,
    kratos_wrong: usize,
    kratos_wrong_near_parallel: usize,
    kratos_asymmetric: usize,
    kratos_asymmetric_outside_band: usize,
    kratos_wrong_in_band: usize,
    robust_wrong: usize,
    direct_wrong: usize,
}

fn run(kind: PairKind, seed: u64, n: usize, tally: &mut Tally) {
    let mut rng = Rng::new(seed);
    for _ in 0..n {
        let (a, b) = random_pair(&mut rng, kind);
        let (oa, ob) = (a.obb(), b.obb());
        let kratos = sat_obb_obb(&oa, &ob, SatMode::Kratos);
        let asymmetric = kratos != sat_obb_obb(&ob, &oa, SatMode::Kratos);
        if asymmetric {
            tally.kratos_asymmetric += 1;
        }
        let Some(expected) = oracle(&a, &b) else {
            tally.in_band += 1;
            if kratos != parry(&a, &b).0 {
                tally.kratos_wrong_in_band += 1;
            }
            continue;
        };
        if asymmetric {
            tally.kratos_asymmetric_outside_band += 1;
        }
        tally.compared += 1;
        if kratos != expected {
            tally.kratos_wrong += 1;
            if matches!(kind, PairKind::NearlyParallel | PairKind::Touching) {
                tally.kratos_wrong_near_parallel += 1;
            }
        }
        if sat_obb_obb(&oa, &ob, SatMode::Robust) != expected
            || sat_obb_obb(&ob, &oa, SatMode::Robust) != expected
        {
            tally.robust_wrong += 1;
            eprintln!("robust disagrees with parry: {a:?} {b:?} expected {expected}");
        }
        if direct_obb_obb(&oa, &ob) != expected {
            tally.direct_wrong += 1;
            eprintln!("direct disagrees with parry: {a:?} {b:?} expected {expected}");
        }
    }
}

/// Deterministic sweep; prints the Kratos-mode disagreement rate and asserts that the robust
/// SAT and the Direct test never disagree with parry outside the touching band.
#[test]
fn kratos_mode_disagreement_rate() {
    let n = 5000;
    let mut total = Tally::default();
    for (i, kind) in ALL_KINDS.into_iter().enumerate() {
        let mut t = Tally::default();
        run(kind, 0x5A7 + i as u64, n, &mut t);
        println!(
            "{kind:?}: compared {} in-band {} kratos-wrong {} (in band {}) kratos-asymmetric {} \
             robust-wrong {} direct-wrong {}",
            t.compared,
            t.in_band,
            t.kratos_wrong,
            t.kratos_wrong_in_band,
            t.kratos_asymmetric,
            t.robust_wrong,
            t.direct_wrong
        );
        total.compared += t.compared;
        total.in_band += t.in_band;
        total.kratos_wrong += t.kratos_wrong;
        total.kratos_wrong_near_parallel += t.kratos_wrong_near_parallel;
        total.kratos_asymmetric += t.kratos_asymmetric;
        total.kratos_asymmetric_outside_band += t.kratos_asymmetric_outside_band;
        total.kratos_wrong_in_band += t.kratos_wrong_in_band;
        total.robust_wrong += t.robust_wrong;
        total.direct_wrong += t.direct_wrong;
    }
    println!(
        "total: {total:?}; Kratos-mode disagreement rate {:.4} %",
        100.0 * total.kratos_wrong as f64 / total.compared as f64
    );
    assert_eq!(total.robust_wrong, 0);
    // Kratos' order-dependent (noise) verdicts exist, but only for touching pairs.
    assert_eq!(total.kratos_asymmetric_outside_band, 0);
    assert_eq!(total.direct_wrong, 0);
    assert!(
        total.compared > 15_000,
        "the band must not swallow the sample"
    );
}

fn config() -> Config {
    Config {
        cases: 256,
        rng_seed: RngSeed::Fixed(0xC5A1),
        ..Config::default()
    }
}

fn kind_strategy() -> impl Strategy<Value = PairKind> {
    prop_oneof![
        Just(PairKind::Generic),
        Just(PairKind::NearlyParallel),
        Just(PairKind::Aligned),
        Just(PairKind::Touching),
    ]
}

proptest! {
    #![proptest_config(config())]

    /// Robust SAT = parry outside the touching band, in both argument orders; Direct too.
    #[test]
    fn robust_sat_matches_parry(seed in any::<u64>(), kind in kind_strategy()) {
        let (a, b) = random_pair(&mut Rng::new(seed), kind);
        if let Some(expected) = oracle(&a, &b) {
            let (oa, ob) = (a.obb(), b.obb());
            prop_assert_eq!(sat_obb_obb(&oa, &ob, SatMode::Robust), expected);
            prop_assert_eq!(sat_obb_obb(&ob, &oa, SatMode::Robust), expected);
            prop_assert_eq!(direct_obb_obb(&oa, &ob), expected);
            prop_assert_eq!(direct_obb_obb(&ob, &oa), expected);
        }
    }

    /// Robust SAT is invariant under a rigid motion of both boxes (outside the band).
    #[test]
    fn robust_sat_is_rigid_motion_invariant(
        seed in any::<u64>(),
        kind in kind_strategy(),
        motion_seed in any::<u64>(),
    ) {
        let (a, b) = random_pair(&mut Rng::new(seed), kind);
        let mut rng = Rng::new(motion_seed);
        let r: UnitQuaternion<f64> = rng.rotation();
        let t = rng.vector(-10.0, 10.0);
        let (a2, b2) = (a.moved(&r, &t), b.moved(&r, &t));
        if oracle(&a, &b).is_some() && oracle(&a2, &b2).is_some() {
            prop_assert_eq!(
                sat_obb_obb(&a.obb(), &b.obb(), SatMode::Robust),
                sat_obb_obb(&a2.obb(), &b2.obb(), SatMode::Robust)
            );
        }
    }

    /// Direct and robust SAT agree on random pairs away from touching.
    #[test]
    fn direct_agrees_with_sat(seed in any::<u64>()) {
        let (a, b) = random_pair(&mut Rng::new(seed), PairKind::Generic);
        if oracle(&a, &b).is_some() {
            let (oa, ob) = (a.obb(), b.obb());
            prop_assert_eq!(direct_obb_obb(&oa, &ob), sat_obb_obb(&oa, &ob, SatMode::Robust));
        }
    }
}

/// A random 2D box: centre in [−2, 2]², angle, half-lengths.
fn random_obb2(rng: &mut Rng) -> Obb2 {
    let angle = rng.range(-3.2, 3.2);
    let a0 = Vector::new(angle.cos(), angle.sin(), 0.0);
    let a1 = Vector::new(-a0.y, a0.x, 0.0);
    Obb2::new(
        Point::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0), 0.0),
        [a0, a1],
        [rng.range(0.02, 1.5), rng.range(0.02, 1.5)],
    )
}

/// Largest gap over the 4 edge normals of two 2D boxes (complete for rectangles).
fn gap2(a: &Obb2, b: &Obb2) -> f64 {
    let t = b.center - a.center;
    a.axes
        .iter()
        .chain(&b.axes)
        .map(|n| {
            let r: f64 = (0..2)
                .map(|k| {
                    a.half_lengths[k] * a.axes[k].dot(n).abs()
                        + b.half_lengths[k] * b.axes[k].dot(n).abs()
                })
                .sum();
            t.dot(n).abs() - r
        })
        .fold(f64::NEG_INFINITY, f64::max)
}

proptest! {
    #![proptest_config(config())]

    /// Kratos-mode SAT = parry outside the touching band (measured 0 disagreements there).
    #[test]
    fn kratos_sat_matches_parry_outside_band(seed in any::<u64>(), kind in kind_strategy()) {
        let (a, b) = random_pair(&mut Rng::new(seed), kind);
        if let Some(expected) = oracle(&a, &b) {
            prop_assert_eq!(sat_obb_obb(&a.obb(), &b.obb(), SatMode::Kratos), expected);
            prop_assert_eq!(sat_obb_obb(&b.obb(), &a.obb(), SatMode::Kratos), expected);
        }
    }

    /// 2D SAT (both modes) and 2D Direct agree with the exact 2D gap, in both orders, and with
    /// the 3D SAT on the boxes extruded along z.
    #[test]
    fn obb2_tests_agree(seed in any::<u64>()) {
        let mut rng = Rng::new(seed);
        let a = random_obb2(&mut rng);
        let b = random_obb2(&mut rng);
        let g = gap2(&a, &b);
        prop_assume!(g.abs() > 1e-9);
        let expected = g < 0.0;
        for mode in [SatMode::Kratos, SatMode::Robust] {
            prop_assert_eq!(sat_obb2_obb2(&a, &b, mode), expected);
            prop_assert_eq!(sat_obb2_obb2(&b, &a, mode), expected);
        }
        prop_assert_eq!(direct_obb2_obb2(&a, &b), expected);
        prop_assert_eq!(direct_obb2_obb2(&b, &a), expected);
        let extrude = |o: &Obb2| Obb::new(
            o.center,
            [o.axes[0], o.axes[1], Vector::z()],
            [o.half_lengths[0], o.half_lengths[1], 1.0],
        );
        prop_assert_eq!(sat_obb_obb(&extrude(&a), &extrude(&b), SatMode::Robust), expected);
    }
}
