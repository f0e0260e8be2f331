use csm_geometry::GeometryKind;
use csm_geometry::math::Point;
use csm_model::{
    ConditionId, ConditionIdx, Flag, ModelPart, NodeId, PartIdx, PropertiesId, ScalarVar,
    VectorVar, compute_unit_normals,
};

use super::*;
use crate::mapping::{normals_read, sides};

/// A unit slave square at z = 0 (normal +z, condition 1) and two master squares at z = gap
/// (normal −z): condition 2 over the slave (shifted by 0.25 in x), condition 3 far away.
fn scene(gap: f64) -> (ModelPart, PartIdx) {
    let mut m = ModelPart::new("Structure");
    let pts = [
        (1, 0.0, 0.0, 0.0),
        (2, 1.0, 0.0, 0.0),
        (3, 1.0, 1.0, 0.0),
        (4, 0.0, 1.0, 0.0),
        (5, 0.25, 0.0, gap),
        (6, 1.25, 0.0, gap),
        (7, 1.25, 1.0, gap),
        (8, 0.25, 1.0, gap),
        (9, 5.0, 0.0, gap),
        (10, 6.0, 0.0, gap),
        (11, 6.0, 1.0, gap),
        (12, 5.0, 1.0, gap),
    ];
    for (id, x, y, z) in pts {
        m.add_node(NodeId(id), Point::new(x, y, z)).unwrap();
    }
    let k = GeometryKind::Quadrilateral3D4;
    let p = PropertiesId(0);
    let s = m
        .add_condition(
            ConditionId(1),
            k,
            "c",
            &[NodeId(1), NodeId(2), NodeId(3), NodeId(4)],
            p,
        )
        .unwrap();
    let c2 = m
        .add_condition(
            ConditionId(2),
            k,
            "c",
            &[NodeId(5), NodeId(8), NodeId(7), NodeId(6)],
            p,
        )
        .unwrap();
    let c3 = m
        .add_condition(
            ConditionId(3),
            k,
            "c",
            &[NodeId(9), NodeId(12), NodeId(11), NodeId(10)],
            p,
        )
        .unwrap();
    let sub = m.create_part("Contact.ContactSub0").unwrap();
    let all_nodes: Vec<_> = (0..12).map(csm_model::NodeIdx).collect();
    m.add_nodes_to_part(sub, &all_nodes);
    m.add_conditions_to_part(sub, &[s, c2, c3]);
    for (i, n) in all_nodes.iter().enumerate() {
        let f = &mut m.nodes_mut().flags_mut()[n.index()];
        f.set(Flag::SLAVE, i < 4);
        f.set(Flag::MASTER, i >= 4);
    }
    for c in [s, c2, c3] {
        let f = &mut m.conditions_mut().flags_mut()[c.index()];
        f.set(Flag::SLAVE, c == s);
        f.set(Flag::MASTER, c != s);
    }
    unit_h_and_normals(&mut m, sub);
    m.index_map_mut(s).add_id(ConditionId(2));
    m.index_map_mut(s).add_id(ConditionId(3));
    (m, sub)
}

/// NODAL_H = 1 on every node, and the unit normals of `sub`.
fn unit_h_and_normals(m: &mut ModelPart, sub: PartIdx) {
    m.nodal_data_mut().add_scalar(ScalarVar::NodalH);
    m.nodal_data_mut()
        .scalar_mut(ScalarVar::NodalH, 0)
        .unwrap()
        .fill(1.0);
    compute_unit_normals(m, Some(sub), csm_model::NormalsMode::Once).unwrap();
}

/// [`scene`] with a gap of 0.01 and three nodes moved off their plane: warped
/// quadrilaterals, whose nodal normals differ from the centre's.
fn warped_scene() -> (ModelPart, PartIdx) {
    let (mut m, sub) = scene(0.01);
    for (node, dz) in [(2, 0.05), (6, -0.03), (7, 0.02)] {
        m.nodes_mut().coordinates_mut()[node].z += dz;
    }
    (m, sub)
}

/// Kratos mode; the mapping streams whatever the number of entries, so that these small
/// scenes run the streamed path (the search's tests and the fixtures run the defaults).
fn settings() -> MappingSettings {
    MappingSettings {
        mode: MortarMode::Kratos,
        distance_threshold: 1e24,
        inverted: false,
        dim: 3,
        tuning: MappingTuning {
            stream_min_entries: 0,
            ..MappingTuning::default()
        },
        ranks: None,
    }
}

#[test]
fn mapping_prunes_the_far_master_and_maps_the_gap() {
    let (mut m, sub) = scene(0.01);
    let r = normal_gap_process(&mut m, sub, &settings(), None).unwrap();
    assert_eq!(r.kept, 1);
    assert_eq!(r.removed.len(), 1);
    assert_eq!(r.removed[0].master, ConditionId(3));
    let keys: Vec<_> = m.index_map(ConditionIdx(0)).masters().collect();
    assert_eq!(keys, vec![ConditionId(2)]);
    assert!(r.iterations >= 1 && r.iterations <= MAPPER_MAX_ITERATIONS);
    let gap = m.nodal_data().scalar(ScalarVar::NormalGap, 0).unwrap();
    // Nodes 2 and 3 (x = 1) lie under the master; nodes 1 and 4 (x = 0) are covered only by
    // the dual basis' support: every slave node gets a mapped point (dual basis of a partial
    // overlap), with the gap of the flat interface.
    for (i, g) in gap[..4].iter().enumerate() {
        assert!(
            (g - 0.01).abs() < 1e-9 || *g == NORMAL_GAP_SENTINEL,
            "{i}: {g}"
        );
    }
    assert!((gap[1] - 0.01).abs() < 1e-9, "{}", gap[1]);
    // Master-side nodes get 0.
    assert!(gap[4..].iter().all(|g| *g == 0.0));
    let area = m.nodal_data().scalar(ScalarVar::NodalArea, 0).unwrap();
    assert!((area[..4].iter().sum::<f64>() - 0.75).abs() < 1e-12);
}

#[test]
fn without_masters_every_slave_node_keeps_the_sentinel() {
    let (mut m, sub) = scene(0.01);
    m.index_map_mut(ConditionIdx(0)).remove_id(ConditionId(2));
    let r = normal_gap_process(&mut m, sub, &settings(), None).unwrap();
    assert_eq!(r.kept, 0);
    let gap = m.nodal_data().scalar(ScalarVar::NormalGap, 0).unwrap();
    assert!(gap[..4].iter().all(|g| *g == NORMAL_GAP_SENTINEL));
}

#[test]
fn simple_activation_uses_the_gap_threshold_and_zeroes_inactive_gaps() {
    let act = ActivationSettings {
        rule: ActivationRule::Simple,
        inverted: false,
        keep_gap_on_inactive: false,
        multiplier: MultiplierSettings::default(),
    };
    // Penetration: active, gap kept.
    let (mut m, sub) = scene(-0.01);
    normal_gap_process(&mut m, sub, &settings(), None).unwrap();
    compute_active_inactive_nodes(&mut m, sub, &act);
    assert!(m.nodes().flags()[1].is(Flag::ACTIVE));
    assert!(m.nodes().flags()[1].is(Flag::MARKER));
    let gap = m.nodal_data().scalar(ScalarVar::NormalGap, 0).unwrap();
    assert!((gap[1] + 0.01).abs() < 1e-9);
    // Open gap 0.01 > 2e-3 · 1: inactive, gap 0 (Q24); robust keeps it.
    let (mut m, sub) = scene(0.01);
    normal_gap_process(&mut m, sub, &settings(), None).unwrap();
    compute_active_inactive_nodes(&mut m, sub, &act);
    assert!(!m.nodes().flags()[1].is(Flag::ACTIVE));
    assert_eq!(
        m.nodal_data().scalar(ScalarVar::NormalGap, 0).unwrap()[1],
        0.0
    );
    let (mut m, sub) = scene(0.01);
    normal_gap_process(&mut m, sub, &settings(), None).unwrap();
    let robust = ActivationSettings {
        keep_gap_on_inactive: true,
        ..act
    };
    compute_active_inactive_nodes(&mut m, sub, &robust);
    assert!((m.nodal_data().scalar(ScalarVar::NormalGap, 0).unwrap()[1] - 0.01).abs() < 1e-9);
}

#[test]
fn advanced_activation_uses_distance_threshold_times_active_check_factor() {
    let rule = |dt: f64| ActivationSettings {
        rule: ActivationRule::Advanced {
            static_check_movement: false,
            consider_gap_threshold: false,
            distance_threshold: dt,
            active_check_factor: 0.01,
        },
        inverted: false,
        keep_gap_on_inactive: false,
        multiplier: MultiplierSettings::default(),
    };
    // L = 0.1 · 0.01 = 0.001 < 0.005: inactive.
    let (mut m, sub) = scene(0.005);
    normal_gap_process(&mut m, sub, &settings(), None).unwrap();
    compute_active_inactive_nodes(&mut m, sub, &rule(0.1));
    assert!(!m.nodes().flags()[1].is(Flag::ACTIVE));
    // L = 1 · 0.01 > 0.005: active.
    let (mut m, sub) = scene(0.005);
    normal_gap_process(&mut m, sub, &settings(), None).unwrap();
    assert_eq!(
        compute_active_inactive_nodes(&mut m, sub, &rule(1.0)).active,
        4
    );
    assert!(m.nodes().flags()[1].is(Flag::ACTIVE));
}

#[test]
fn weighted_gap_of_a_flat_pair_is_gap_times_area() {
    let (mut m, sub) = scene(0.01);
    m.nodal_data_mut().add_scalar(ScalarVar::WeightedGap);
    let isolated = compute_weighted_gap(
        &mut m,
        sub,
        &[
            (ConditionIdx(0), ConditionIdx(1)),
            (ConditionIdx(0), ConditionIdx(2)),
        ],
        (MortarMode::Kratos, 1e24),
        3,
        None,
    )
    .unwrap();
    // The far master (condition 3) overlaps nothing: ISOLATED.
    assert_eq!(isolated, [false, true]);
    let wg = m.nodal_data().scalar(ScalarVar::WeightedGap, 0).unwrap();
    // Σ_i wg_i = gap · overlap area for a flat interface (D, M rows sum to the overlap).
    assert!(
        (wg[..4].iter().sum::<f64>() - 0.01 * 0.75).abs() < 1e-12,
        "{wg:?}"
    );
}

/// A pair whose contribution cannot be computed (a flat slave face) is the weighted gap's
/// error, the first in pair order, and the nodal values stay as they were.
#[test]
fn weighted_gap_error_is_the_first_in_pair_order_and_leaves_the_values() {
    let (mut m, sub) = scene(0.01);
    // A flat quadrilateral on nodes 9 and 10, with the first condition's normals.
    let mut add_flat = |id: u32, nodes: [u32; 4]| {
        let c = m
            .add_condition(
                ConditionId(id),
                GeometryKind::Quadrilateral3D4,
                "c",
                &nodes.map(NodeId),
                PropertiesId(0),
            )
            .unwrap();
        let unit_normals = m.condition_normals()[0];
        m.condition_normals_mut()[c.index()] = unit_normals;
        c
    };
    let flat = add_flat(4, [9, 10, 10, 9]);
    // A second flat face with a larger id, listed first: the error is the first in pair
    // order, not the smallest id nor the last.
    let flat_first = add_flat(5, [10, 9, 9, 10]);
    m.nodal_data_mut().add_scalar(ScalarVar::WeightedGap);
    m.nodal_data_mut()
        .scalar_mut(ScalarVar::WeightedGap, 0)
        .unwrap()
        .fill(7.0);
    let settings = (MortarMode::Kratos, 1e24);
    let pairs = [
        (ConditionIdx(0), ConditionIdx(1)),
        (flat_first, ConditionIdx(1)),
        (flat, ConditionIdx(1)),
        (ConditionIdx(0), ConditionIdx(2)),
    ];
    let e = compute_weighted_gap(&mut m, sub, &pairs, settings, 3, None).unwrap_err();
    assert!(e.to_string().contains("condition 5"), "{e}");
    let e = compute_weighted_gap(&mut m, sub, &pairs[2..], settings, 3, None).unwrap_err();
    assert!(e.to_string().contains("condition 4"), "{e}");
    let unchanged = |m: &ModelPart| {
        let wg = m.nodal_data().scalar(ScalarVar::WeightedGap, 0).unwrap();
        assert!(wg.iter().all(|&w| w == 7.0), "{wg:?}");
    };
    unchanged(&m);
    // An error the mapping recorded for a pair (known) is reported too, with no computed
    // one, and nothing is written.
    let good = [pairs[0], pairs[3]];
    let known = crate::weighted_gap::KnownGaps::new(vec![(good[1], Err(e.clone()))]);
    let again = compute_weighted_gap(&mut m, sub, &good, settings, 3, Some(known)).unwrap_err();
    assert_eq!(again.to_string(), e.to_string());
    unchanged(&m);
    // Recorded and computed errors together: the first in pair order, whichever it is, and
    // of two recorded ones the first in pair order, not in key order.
    let known_with = |errors: &[((ConditionIdx, ConditionIdx), &str)]| {
        let entries = errors
            .iter()
            .map(|&(key, message)| (key, Err(Error::message_only(message.to_string()))));
        Some(crate::weighted_gap::KnownGaps::new(entries.collect()))
    };
    let mut first = |pairs: &[(ConditionIdx, ConditionIdx)], known| {
        let e = compute_weighted_gap(&mut m, sub, pairs, settings, 3, known).unwrap_err();
        e.to_string()
    };
    let before_computed = known_with(&[(pairs[0], "recorded 0"), (pairs[3], "recorded 3")]);
    assert!(first(&pairs, before_computed).contains("recorded 0"));
    let after_computed = known_with(&[(pairs[3], "recorded 3")]);
    assert!(first(&pairs, after_computed).contains("condition 5"));
    let reversed = [pairs[3], pairs[0]];
    let both = known_with(&[(pairs[0], "recorded 0"), (pairs[3], "recorded 3")]);
    assert!(first(&reversed, both).contains("recorded 3"));
    unchanged(&m);
    // Without the flat faces and the recorded error, the same pairs give values.
    compute_weighted_gap(&mut m, sub, &good, settings, 3, None).unwrap();
    let wg = m.nodal_data().scalar(ScalarVar::WeightedGap, 0).unwrap();
    assert!(wg[..4].iter().all(|&w| w != 7.0), "{wg:?}");
}

#[test]
fn advanced_distance_threshold_is_the_larger_mean_nodal_h() {
    let (mut m, sub) = scene(0.01);
    let h = m.nodal_data_mut().scalar_mut(ScalarVar::NodalH, 0).unwrap();
    h[..4].fill(2.0);
    assert_eq!(mean_h(&m, sub, false), 2.0);
}

fn simple_with(multiplier: MultiplierSettings) -> ActivationSettings {
    ActivationSettings {
        rule: ActivationRule::Simple,
        inverted: false,
        keep_gap_on_inactive: false,
        multiplier,
    }
}

fn contact_pressure_scene(gap: f64) -> (ModelPart, PartIdx) {
    let (mut m, sub) = scene(gap);
    m.nodal_data_mut()
        .add_scalar(ScalarVar::LagrangeMultiplierContactPressure);
    normal_gap_process(&mut m, sub, &settings(), None).unwrap();
    (m, sub)
}

#[test]
fn simple_activation_guesses_the_multiplier_from_the_penalty() {
    let (mut m, sub) = contact_pressure_scene(-0.01);
    assert_eq!(MultiplierKind::of(&m), MultiplierKind::NormalContactStress);
    let ms = MultiplierSettings {
        kind: MultiplierKind::of(&m),
        initial_penalty: Some(1.0e3),
        scale_factor: Some(2.0),
        ..MultiplierSettings::default()
    };
    let r = compute_active_inactive_nodes(&mut m, sub, &simple_with(ms));
    assert!(r.warnings.is_empty(), "{:?}", r.warnings);
    let data = m.nodal_data();
    let lm = data
        .scalar(ScalarVar::LagrangeMultiplierContactPressure, 0)
        .unwrap();
    let gap = data.scalar(ScalarVar::NormalGap, 0).unwrap();
    let area = data.scalar(ScalarVar::NodalArea, 0).unwrap();
    // Node 2 (index 1) penetrates by 0.01 with a positive nodal area: ε · A · g = 500 · A · g.
    assert!(gap[1] < 0.0 && area[1] > 0.0);
    assert!(
        (lm[1] - 500.0 * area[1] * gap[1]).abs() < 1e-12,
        "{}",
        lm[1]
    );
    assert!(lm[1] < 0.0);
    // Masters are not touched.
    assert!(lm[4..].iter().all(|v| *v == 0.0));
}

#[test]
fn a_missing_penalty_gives_kratos_nan_or_a_robust_skip_with_a_warning() {
    // Kratos: INITIAL_PENALTY / SCALE_FACTOR read as 0 / 0 → NaN multipliers (Q25).
    let (mut m, sub) = contact_pressure_scene(-0.01);
    let ms = MultiplierSettings {
        kind: MultiplierKind::NormalContactStress,
        ..MultiplierSettings::default()
    };
    let r = compute_active_inactive_nodes(&mut m, sub, &simple_with(ms));
    assert_eq!(r.warnings.len(), 1, "{:?}", r.warnings);
    assert!(r.warnings[0].contains("NaN"), "{}", r.warnings[0]);
    let lm = m
        .nodal_data()
        .scalar(ScalarVar::LagrangeMultiplierContactPressure, 0)
        .unwrap();
    assert!(lm[1].is_nan());
    // Guarded: skipped, nothing NaN, one warning.
    let (mut m, sub) = contact_pressure_scene(-0.01);
    let guarded = MultiplierSettings {
        guarded: true,
        ..ms
    };
    let r = compute_active_inactive_nodes(&mut m, sub, &simple_with(guarded));
    assert_eq!(r.warnings.len(), 1, "{:?}", r.warnings);
    assert!(r.warnings[0].contains("skipped"), "{}", r.warnings[0]);
    let lm = m
        .nodal_data()
        .scalar(ScalarVar::LagrangeMultiplierContactPressure, 0)
        .unwrap();
    assert!(lm.iter().all(|v| *v == 0.0), "{lm:?}");
}

fn advanced_predicting(guarded: bool) -> ActivationSettings {
    ActivationSettings {
        rule: ActivationRule::Advanced {
            static_check_movement: false,
            consider_gap_threshold: false,
            distance_threshold: 1.0,
            active_check_factor: 0.01,
        },
        inverted: false,
        keep_gap_on_inactive: false,
        multiplier: MultiplierSettings {
            kind: MultiplierKind::NormalContactStress,
            predict_correct: true,
            guarded,
            ..MultiplierSettings::default()
        },
    }
}

/// Nodes 1 and 2 (indices 0, 1) ACTIVE before with (WEIGHTED_GAP, LM) = (1, −3) and (2, −5):
/// the regression is LM = −1 − 2 · WEIGHTED_GAP.
fn regression_scene(active_before: &[usize]) -> (ModelPart, PartIdx) {
    let (mut m, sub) = contact_pressure_scene(0.005);
    m.nodal_data_mut().add_scalar(ScalarVar::WeightedGap);
    let data = m.nodal_data_mut();
    let wg = data.scalar_mut(ScalarVar::WeightedGap, 0).unwrap();
    wg[..4].copy_from_slice(&[1.0, 2.0, -1.0, 0.25]);
    let lm = data
        .scalar_mut(ScalarVar::LagrangeMultiplierContactPressure, 0)
        .unwrap();
    lm[..2].copy_from_slice(&[-3.0, -5.0]);
    for &i in active_before {
        m.nodes_mut().flags_mut()[i].set(Flag::ACTIVE, true);
    }
    (m, sub)
}

#[test]
fn advanced_predict_correct_sets_the_multiplier_from_the_regression() {
    let (mut m, sub) = regression_scene(&[0, 1]);
    let r = compute_active_inactive_nodes(&mut m, sub, &advanced_predicting(true));
    let (a, b) = r.regression.expect("two distinct points");
    assert!(
        (a + 1.0).abs() < 1e-12 && (b + 2.0).abs() < 1e-12,
        "{a} {b}"
    );
    assert!(r.warnings.is_empty(), "{:?}", r.warnings);
    assert_eq!(r.active, 4);
    let lm = m
        .nodal_data()
        .scalar(ScalarVar::LagrangeMultiplierContactPressure, 0)
        .unwrap();
    // p = −1 − 2·wg where negative, else 0: wg = −1 gives p = 1 > 0 → 0.
    let expected = [-3.0, -5.0, 0.0, -1.5];
    for (i, e) in expected.iter().enumerate() {
        assert!((lm[i] - e).abs() < 1e-12, "{i}: {} vs {e}", lm[i]);
    }
}

#[test]
fn the_regression_with_one_active_node_is_nan_in_kratos_and_guarded_in_robust() {
    // Kratos: 1·x² − x² = 0 → 0/0 (Q26): predicted multipliers come out as 0 (NaN < 0 is false).
    let (mut m, sub) = regression_scene(&[0]);
    let r = compute_active_inactive_nodes(&mut m, sub, &advanced_predicting(false));
    let (a, b) = r.regression.unwrap();
    assert!(!a.is_finite() || !b.is_finite());
    assert_eq!(r.warnings.len(), 1, "{:?}", r.warnings);
    let lm = m
        .nodal_data()
        .scalar(ScalarVar::LagrangeMultiplierContactPressure, 0)
        .unwrap();
    assert!(lm[..4].iter().all(|v| *v == 0.0), "{lm:?}");
    // Robust: no regression, the multipliers are left as they were.
    let (mut m, sub) = regression_scene(&[0]);
    let r = compute_active_inactive_nodes(&mut m, sub, &advanced_predicting(true));
    assert_eq!(r.regression, None);
    assert!(
        r.warnings[0].contains("two active nodes"),
        "{}",
        r.warnings[0]
    );
    let lm = m
        .nodal_data()
        .scalar(ScalarVar::LagrangeMultiplierContactPressure, 0)
        .unwrap();
    assert_eq!(&lm[..2], &[-3.0, -5.0]);
    assert!(lm.iter().all(|v| v.is_finite()));
}

#[test]
fn slip_rule_marks_frictionless_activated_nodes_slip() {
    let (mut m, sub) = scene(-0.01);
    m.nodal_data_mut()
        .add_vector(VectorVar::VectorLagrangeMultiplier);
    normal_gap_process(&mut m, sub, &settings(), None).unwrap();
    let ms = MultiplierSettings {
        kind: MultiplierKind::of(&m),
        slip: true,
        initial_penalty: Some(1.0),
        scale_factor: Some(1.0),
        ..MultiplierSettings::default()
    };
    assert_eq!(ms.kind, MultiplierKind::Vector);
    compute_active_inactive_nodes(&mut m, sub, &simple_with(ms));
    let f = m.nodes().flags()[1];
    assert!(f.is(Flag::ACTIVE) && f.is(Flag::SLIP));
    // The vector guess points along the node's normal.
    let lm = m
        .nodal_data()
        .vector(VectorVar::VectorLagrangeMultiplier, 0)
        .unwrap()[1];
    assert!(lm.z.abs() > 0.0 && lm.x == 0.0 && lm.y == 0.0, "{lm:?}");
}

/// The mapping with the step's kept face normals ([`csm_model::FaceNormals::keep`]) does what
/// it does computing them itself, bit for bit (report, NORMAL_GAP, NODAL_AREA,
/// AUXILIAR_COORDINATES, nodal and condition normals), on warped quadrilaterals (their nodal
/// normals differ from the centre's); a kept table whose condition normals changed since is
/// not used.
#[test]
fn kept_face_normals_map_as_computed_ones() {
    let (base, sub) = warped_scene();
    let state = |m: &ModelPart| {
        let data = m.nodal_data();
        (
            data.scalar(ScalarVar::NormalGap, 0).unwrap().to_vec(),
            data.scalar(ScalarVar::NodalArea, 0).unwrap().to_vec(),
            data.vector(VectorVar::AuxiliarCoordinates, 0)
                .unwrap()
                .to_vec(),
            data.vector(VectorVar::Normal, 0).unwrap().to_vec(),
            m.condition_normals().to_vec(),
        )
    };
    for changed in [false, true] {
        let mut with = base.clone();
        let kept = compute_unit_normals(&mut with, Some(sub), csm_model::NormalsMode::Once)
            .unwrap()
            .keep();
        if changed {
            with.condition_normals_mut()[0].y += 1e-3;
        }
        let mut without = with.clone();
        let a = normal_gap_process(&mut with, sub, &settings(), Some(kept)).unwrap();
        let b = normal_gap_process(&mut without, sub, &settings(), None).unwrap();
        assert_eq!(a, b, "changed: {changed}");
        assert_eq!(a.kept, 1);
        assert_eq!(state(&with), state(&without), "changed: {changed}");
        // The warped faces' nodal mean normals are not all the centre normal.
        let normals = state(&with).3;
        assert!(normals[0] != normals[2], "{normals:?}");
    }
}

/// The known gaps' cursor finds what a map of every entry finds, for lookups in key order
/// (its fast path), backwards, at random, repeated and absent; with the entries in one run,
/// in runs of many sizes (the mapping's tasks'), and in runs whose keys interleave (merged).
#[test]
fn known_gaps_cursor_answers_as_a_map_of_the_entries() {
    use crate::weighted_gap::{KnownGap, KnownGaps};
    use std::collections::BTreeMap;
    let key = |i: u32| (ConditionIdx(i / 5), ConditionIdx(i % 5 * 3));
    // Every third key of 0..3n is known, each with its own value (an error naming it): few
    // entries (their runs taken on one thread) and many (in parallel passes).
    let entry = |i: u32| -> KnownGap { (key(3 * i), Err(Error::message_only(format!("{i}")))) };
    for n in [1000u32, 20_000] {
        let oracle: BTreeMap<_, _> = (0..n).map(|i| (key(3 * i), entry(i).1)).collect();
        // Runs in key order, each entered out of order: sizes 1, 2, 3, … (then what is left),
        // and an empty one.
        let mut in_runs = Vec::new();
        let (mut next, mut size) = (0u32, 1u32);
        while next < n {
            let end = (next + size).min(n);
            in_runs.push((next..end).rev().map(entry).collect::<Vec<_>>());
            (next, size) = (end, size + 1);
        }
        in_runs.insert(3, Vec::new());
        // Seven runs whose keys interleave: entry `i` in run `i % 7`.
        let interleaved: Vec<Vec<KnownGap>> = (0..7u32)
            .map(|r| (0..n).filter(|i| i % 7 == r).map(entry).collect())
            .collect();
        let one_run = vec![(0..n).rev().map(entry).collect::<Vec<_>>()];
        let end = 3 * n + 100;
        let mut state = 0x853C_49E6_748F_EA9Bu64;
        let mut random = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % u64::from(end)) as u32
        };
        let ascending: Vec<u32> = (0..end).collect();
        let descending: Vec<u32> = (0..end).rev().collect();
        let scattered: Vec<u32> = (0..end * 5 / 3).map(|_| random()).collect();
        let repeated = vec![42, 42, 43, 0, 0, 2999, 3099, 3];
        // Within each slave, its masters backwards (ids need not follow indices).
        let slave_backwards: Vec<u32> = (0..end).map(|q| q / 5 * 5 + 4 - q % 5).collect();
        let n_in_runs = in_runs.len() - 1;
        for (runs, kept) in [(one_run, 1), (in_runs, n_in_runs), (interleaved, 1)] {
            let known = KnownGaps::from_runs(runs);
            assert_eq!(known.len(), n as usize);
            // The runs in key order are kept as runs (not the empty one); the interleaved
            // ones are merged.
            assert_eq!(known.n_runs(), kept);
            let (mut hits, mut misses) = (0, 0);
            for queries in [
                &ascending,
                &descending,
                &scattered,
                &repeated,
                &slave_backwards,
            ] {
                let mut cursor = known.cursor();
                for &q in queries {
                    let (s, m) = key(q);
                    let expected = oracle.get(&(s, m));
                    let got = cursor.get(s, m);
                    assert_eq!(got, expected, "{q}");
                    assert_eq!(known.get(s, m), expected, "{q}");
                    if got.is_some() {
                        hits += 1;
                    } else {
                        misses += 1;
                    }
                }
            }
            assert!(
                hits > 3 * n && misses > 6 * n,
                "{hits} hits, {misses} misses"
            );
            let entries: Vec<_> = known.entries().into_iter().map(|(k, _)| *k).collect();
            assert_eq!(entries, oracle.keys().copied().collect::<Vec<_>>());
            known.par_drop();
        }
    }
}

/// The mapping that keeps the master values' products in place of `M` maps as the one that
/// keeps `M`, bit for bit (report, NORMAL_GAP, NODAL_AREA, AUXILIAR_COORDINATES), on warped
/// faces, not inverted and inverted (master values zero); a master node that is also a slave
/// node makes it keep `M`.
#[test]
fn master_products_map_as_the_operators() {
    let (mut base, sub) = warped_scene();
    let bits = |m: &ModelPart| {
        let data = m.nodal_data();
        let scalars = [ScalarVar::NormalGap, ScalarVar::NodalArea].map(|v| {
            data.scalar(v, 0)
                .unwrap()
                .iter()
                .map(|x| x.to_bits())
                .collect::<Vec<_>>()
        });
        let aux: Vec<[u64; 3]> = data
            .vector(VectorVar::AuxiliarCoordinates, 0)
            .unwrap()
            .iter()
            .map(|v| [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()])
            .collect();
        (scalars, aux)
    };
    for inverted in [false, true] {
        let mut model = base.clone();
        if inverted {
            // The inverted slave side (condition 2) searched condition 1.
            model
                .index_map_mut(ConditionIdx(0))
                .remove_id(ConditionId(2));
            model
                .index_map_mut(ConditionIdx(0))
                .remove_id(ConditionId(3));
            model.index_map_mut(ConditionIdx(1)).add_id(ConditionId(1));
        }
        let settings = MappingSettings {
            inverted,
            ..settings()
        };
        let s = crate::mapping::sides(&model, sub, inverted);
        assert!(matches!(
            crate::mapping::OperatorStore::for_sides(
                &s,
                &crate::mapping::SlavePositions::new(&s, model.nodes().len()),
                !inverted,
                3,
                false
            ),
            crate::mapping::OperatorStore::MasterProducts { .. }
        ));
        let mut with_products = model.clone();
        let a = normal_gap_process(&mut with_products, sub, &settings, None).unwrap();
        let full = MappingSettings {
            tuning: MappingTuning {
                full_operators: true,
                ..settings.tuning
            },
            ..settings.clone()
        };
        let b = normal_gap_process(&mut model, sub, &full, None).unwrap();
        assert_eq!(a, b, "inverted: {inverted}");
        assert_eq!(a.kept, 1, "inverted: {inverted}");
        assert_eq!(bits(&with_products), bits(&model), "inverted: {inverted}");
    }
    // Node 5 on both sides.
    base.nodes_mut().flags_mut()[4].set(Flag::SLAVE, true);
    let s = crate::mapping::sides(&base, sub, false);
    assert!(matches!(
        crate::mapping::OperatorStore::for_sides(
            &s,
            &crate::mapping::SlavePositions::new(&s, base.nodes().len()),
            true,
            3,
            false
        ),
        crate::mapping::OperatorStore::Operators
    ));
}

/// A slave grid of `n`×`n` warped unit-spaced quadrilaterals (normal about +z) and a master
/// grid of `n + 1`×`n + 1` quadrilaterals of spacing `pitch` at `z = gap` (normal about −z),
/// shifted by `shift` in x and y; the condition ids of each side are scrambled, so that the
/// slave conditions in id order visit the grid out of place. Every slave condition's
/// INDEX_MAP holds the masters whose boxes come within 0.5 of its own, some of which do not
/// overlap it, and every master's the slaves whose own hold it.
fn grid_scene(n: usize, (pitch, shift, gap): (f64, f64, f64)) -> (ModelPart, PartIdx) {
    let mut m = ModelPart::new("Structure");
    let warp = |x: f64, y: f64| 0.02 * (1.3 * x).sin() * (0.7 * y).cos();
    let mut next_node = 1;
    let mut grid = |m: &mut ModelPart, cells: usize, pitch: f64, offset: f64, z: f64| {
        let first = next_node;
        for j in 0..=cells {
            for i in 0..=cells {
                let (x, y) = (offset + pitch * i as f64, offset + pitch * j as f64);
                m.add_node(NodeId(next_node), Point::new(x, y, z + warp(x, y)))
                    .unwrap();
                next_node += 1;
            }
        }
        move |i: usize, j: usize| NodeId(first + (j * (cells + 1) + i) as u32)
    };
    let slave_node = grid(&mut m, n, 1.0, 0.0, 0.0);
    let master_node = grid(&mut m, n + 1, pitch, shift, gap);
    let n_nodes = m.nodes().len();
    let add_quad = |m: &mut ModelPart, id: ConditionId, nodes: &[NodeId]| {
        let kind = GeometryKind::Quadrilateral3D4;
        m.add_condition(id, kind, "c", nodes, PropertiesId(0))
            .unwrap()
    };
    // A permutation of 1..=count by a multiplier prime to it.
    let scrambled = |k: usize, count: usize| ConditionId((k * 7919 % count + 1) as u32);
    let mut slaves = Vec::new();
    for k in 0..n * n {
        let (i, j) = (k % n, k / n);
        let nodes = [
            slave_node(i, j),
            slave_node(i + 1, j),
            slave_node(i + 1, j + 1),
            slave_node(i, j + 1),
        ];
        let c = add_quad(&mut m, scrambled(k, n * n), &nodes);
        slaves.push((c, [i as f64, j as f64]));
    }
    let cells = n + 1;
    let mut masters = Vec::new();
    for k in 0..cells * cells {
        let (i, j) = (k % cells, k / cells);
        let nodes = [
            master_node(i, j),
            master_node(i, j + 1),
            master_node(i + 1, j + 1),
            master_node(i + 1, j),
        ];
        let id = ConditionId((n * n + 1) as u32 + scrambled(k, cells * cells).get());
        let c = add_quad(&mut m, id, &nodes);
        let corner = [shift + pitch * i as f64, shift + pitch * j as f64];
        masters.push((c, id, corner));
    }
    let sub = m.create_part("Contact.ContactSub0").unwrap();
    let all_nodes: Vec<_> = (0..n_nodes as u32).map(csm_model::NodeIdx).collect();
    m.add_nodes_to_part(sub, &all_nodes);
    let all_conditions: Vec<_> = slaves
        .iter()
        .map(|s| s.0)
        .chain(masters.iter().map(|m| m.0))
        .collect();
    m.add_conditions_to_part(sub, &all_conditions);
    let n_slave_nodes = (n + 1) * (n + 1);
    for (i, f) in m.nodes_mut().flags_mut().iter_mut().enumerate() {
        f.set(Flag::SLAVE, i < n_slave_nodes);
        f.set(Flag::MASTER, i >= n_slave_nodes);
    }
    for &(c, _) in &slaves {
        m.conditions_mut().flags_mut()[c.index()].set(Flag::SLAVE, true);
    }
    for &(c, _, _) in &masters {
        m.conditions_mut().flags_mut()[c.index()].set(Flag::MASTER, true);
    }
    unit_h_and_normals(&mut m, sub);
    // Both ways: the inverted mapping's slave side is the master side.
    let slave_ids = m.conditions().ids().to_vec();
    for &(c, [x, y]) in &slaves {
        for &(mc, id, [mx, my]) in &masters {
            let near = |a: f64, b: f64, size: f64| b < a + 1.0 + 0.5 && a < b + size + 0.5;
            if near(x, mx, pitch) && near(y, my, pitch) {
                m.index_map_mut(c).add_id(id);
                m.index_map_mut(mc)
                    .add_id(ConditionId(slave_ids[c.index()]));
            }
        }
    }
    (m, sub)
}

/// The state the mapping leaves, bit for bit: NORMAL_GAP, NODAL_AREA, AUXILIAR_COORDINATES,
/// NORMAL, and the INDEX_MAPs.
fn mapped_bits(m: &ModelPart) -> Vec<u64> {
    mapped_bits_of(m, &[VectorVar::AuxiliarCoordinates, VectorVar::Normal])
}

/// [`mapped_bits`] with the vector variables `vectors`.
fn mapped_bits_of(m: &ModelPart, vectors: &[VectorVar]) -> Vec<u64> {
    let data = m.nodal_data();
    let mut bits = Vec::new();
    for v in [ScalarVar::NormalGap, ScalarVar::NodalArea] {
        bits.extend(data.scalar(v, 0).unwrap().iter().map(|x| x.to_bits()));
    }
    for &v in vectors {
        for x in data.vector(v, 0).unwrap() {
            bits.extend(x.iter().map(|c| c.to_bits()));
        }
    }
    for c in 0..m.conditions().len() {
        let map = m.index_map(ConditionIdx(c as u32));
        bits.extend(map.masters().map(|id| u64::from(id.get())));
        bits.push(u64::MAX);
    }
    bits
}

/// The weighted-gap variant with the step's kept face normals writes the mean normals only
/// where the mapping reads them (its caller writes its unit normals back after it): every
/// result is the full mapping's, bit for bit, NORMAL included on the nodes read; the others
/// keep the unit normals they had. Inverted and not, on grids that overlap widely, at a
/// corner, and not at all.
#[test]
fn the_keeping_mapping_writes_only_the_mean_normals_it_reads() {
    let normal_bits = |m: &ModelPart| -> Vec<[u64; 3]> {
        let col = m.nodal_data().vector(VectorVar::Normal, 0).unwrap();
        col.iter()
            .map(|v| [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()])
            .collect()
    };
    let mut skipped = 0;
    for layout in [(0.83, -0.2, 0.01), (0.5, 6.9, 0.01), (0.9, 40.0, 0.01)] {
        let (base, sub) = grid_scene(7, layout);
        for inverted in [false, true] {
            let settings = MappingSettings {
                inverted,
                ..settings()
            };
            let mut lean = base.clone();
            let kept = compute_unit_normals(&mut lean, Some(sub), csm_model::NormalsMode::Kratos)
                .unwrap()
                .keep();
            let unit_normals = lean
                .nodal_data()
                .vector(VectorVar::Normal, 0)
                .unwrap()
                .to_vec();
            let before = normal_bits(&lean);
            let read = normals_read(&lean, &sides(&lean, sub, inverted));
            let mut full = lean.clone();
            let a =
                normal_gap_process_keeping(&mut lean, sub, &settings, Some(kept), &unit_normals)
                    .unwrap();
            let b =
                normal_gap_process_keeping(&mut full, sub, &settings, None, &unit_normals).unwrap();
            let what = format!("layout {layout:?}, inverted {inverted}");
            assert_eq!(a.0, b.0, "{what}");
            assert_eq!(
                format!("{:?}", a.1.entries()),
                format!("{:?}", b.1.entries())
            );
            let others = [VectorVar::AuxiliarCoordinates];
            assert!(
                mapped_bits_of(&lean, &others) == mapped_bits_of(&full, &others),
                "{what}"
            );
            let (lean, full) = (normal_bits(&lean), normal_bits(&full));
            for i in 0..read.len() {
                if read[i] {
                    assert_eq!(lean[i], full[i], "{what}: node {i}");
                } else {
                    assert_eq!(lean[i], before[i], "{what}: node {i}");
                    skipped += usize::from(full[i] != before[i]);
                }
            }
        }
    }
    // The full mapping wrote mean normals the lean one left out.
    assert!(skipped > 20, "{skipped}");
}

/// The mapping that follows the segmentation with its first two iterations (keeping no
/// pair's operators longer than they need) maps as the one that keeps them all, bit for bit
/// (report, nodal values, INDEX_MAPs, weighted gaps), for batches of one slave condition up
/// to all of them, on grids that converge in one, two and more iterations (the last goes on
/// with the operators computed again), inverted and not.
#[test]
fn streamed_mapping_maps_as_the_stored_one() {
    let mut iterations = Vec::new();
    // (pitch, shift, gap): two non-matching grids over each other; master grids that touch
    // the slave grid's corner cell only (a node with too small an area: three iterations),
    // or by a sliver (converged after the first); a far one (no kept pair).
    let layouts = [
        (0.83, -0.2, 0.01),
        (1.1, -0.37, 0.002),
        (0.5, 6.9, 0.01),
        (1.0, 6.9999, 0.01),
        (0.9, 40.0, 0.01),
    ];
    for (l, &layout) in layouts.iter().enumerate() {
        let (base, sub) = grid_scene(7, layout);
        let unit_normals = base
            .nodal_data()
            .vector(VectorVar::Normal, 0)
            .unwrap()
            .to_vec();
        for inverted in [false, true] {
            let settings = MappingSettings {
                inverted,
                ..settings()
            };
            let run = |stored: bool, batch: Option<usize>, gather: bool| {
                let mut m = base.clone();
                let tuned = MappingSettings {
                    tuning: MappingTuning {
                        stream_min_entries: if stored { usize::MAX } else { 0 },
                        stream_batch: batch.unwrap_or(settings.tuning.stream_batch),
                        gather_from_threads: if gather { 1 } else { usize::MAX },
                        ..settings.tuning
                    },
                    ..settings.clone()
                };
                let r = normal_gap_process_keeping(&mut m, sub, &tuned, None, &unit_normals);
                let (report, known) = r.unwrap();
                let gaps = format!("{:?}", known.entries());
                (report, mapped_bits(&m), gaps)
            };
            let stored = run(true, None, false);
            for batch in [1, 3, 10, 1000] {
                for gather in [false, true] {
                    let streamed = three_threads(|| run(false, Some(batch), gather));
                    assert!(
                        streamed == stored,
                        "layout {l}, inverted {inverted}, batch {batch}, gather {gather}"
                    );
                }
            }
            iterations.push(stored.0.iterations);
            if l < 2 {
                assert!(
                    stored.0.kept > 50 && !stored.0.removed.is_empty(),
                    "layout {l}"
                );
            }
        }
    }
    // Every case the iterations distinguish is covered: none, one, two, more.
    for covered in [0, 1, 2, 3] {
        assert!(
            iterations.iter().any(|&i| i.min(3) == covered),
            "{iterations:?}"
        );
    }
}

/// Runs `f` in a pool of three threads (the gather's tasks split unevenly).
fn three_threads<T: Send>(f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(3)
        .build()
        .unwrap()
        .install(f)
}

/// The gathered sums (module `mapping::gather`) on a grid of more slave conditions than one
/// segmentation task holds, so that a batch has several mappings and a node's conditions
/// lie in different ones and in different batches: the serial pass's bits, with 1 and 3
/// threads, and both as the stored mapping.
#[test]
fn gathered_mapping_maps_as_the_serial_pass() {
    let (base, sub) = grid_scene(24, (0.83, -0.2, 0.01));
    let unit_normals = base
        .nodal_data()
        .vector(VectorVar::Normal, 0)
        .unwrap()
        .to_vec();
    let run = |min_entries: usize, batch: usize, gather: usize| {
        let mut m = base.clone();
        let tuned = MappingSettings {
            tuning: MappingTuning {
                stream_min_entries: min_entries,
                stream_batch: batch,
                gather_from_threads: gather,
                ..MappingTuning::default()
            },
            ..settings()
        };
        let r = normal_gap_process_keeping(&mut m, sub, &tuned, None, &unit_normals);
        let (report, known) = r.unwrap();
        (report, mapped_bits(&m), format!("{:?}", known.entries()))
    };
    let stored = run(usize::MAX, 1, usize::MAX);
    assert!(
        stored.0.kept > 500 && stored.0.iterations >= 2,
        "{:?}",
        stored.0
    );
    for batch in [50, 130, 100_000] {
        let serial = run(0, batch, usize::MAX);
        assert!(serial == stored, "serial, batch {batch}");
        // The serial pass pipelined beside the segmentation (several threads) or not (one).
        let serial_three = three_threads(|| run(0, batch, usize::MAX));
        assert!(serial_three == stored, "serial on 3 threads, batch {batch}");
        let serial_one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap()
            .install(|| run(0, batch, usize::MAX));
        assert!(serial_one == stored, "serial on 1 thread, batch {batch}");
        let one = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .unwrap()
            .install(|| run(0, batch, 1));
        assert!(one == stored, "gathered on 1 thread, batch {batch}");
        let three = three_threads(|| run(0, batch, 1));
        assert!(three == stored, "gathered on 3 threads, batch {batch}");
        // The default gathers from three threads on: the serial pass on one.
        let default = three_threads(|| run(0, batch, GATHER_FROM_THREADS));
        assert!(default == stored, "default on 3 threads, batch {batch}");
    }
}
