//! The mapping's minimal reproductions of issue 24: robust mode's direct solve against Kratos'
//! iterations, far from the origin, at tiny scales and on a point mapped onto the origin.

use csm_geometry::GeometryKind;
use csm_geometry::math::{Point, Real};
use csm_model::{
    ConditionId, ConditionIdx, Flag, ModelPart, NodeId, NodeIdx, PartIdx, PropertiesId, ScalarVar,
    compute_unit_normals,
};

use super::*;

/// One unit quadrilateral slave (condition 1, normal +z) at height `z0`, and a master below
/// it at `z0 − gap` (normal −z: the bodies overlap by `gap`, NORMAL_GAP = −gap) made of
/// `masters` (x, y corners, counter-clockwise seen from
/// below); every master in the slave's INDEX_MAP. Every length is multiplied by `scale`.
fn scene(z0: Real, gap: Real, scale: Real, masters: &[&[(Real, Real)]]) -> (ModelPart, PartIdx) {
    let mut m = ModelPart::new("Structure");
    let mut id = 0;
    let mut node = |m: &mut ModelPart, x: Real, y: Real, z: Real| {
        id += 1;
        m.add_node(NodeId(id), Point::new(x, y, z) * scale).unwrap();
        NodeId(id)
    };
    let slave_nodes: Vec<NodeId> = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
        .iter()
        .map(|&(x, y)| node(&mut m, x, y, z0))
        .collect();
    let p = PropertiesId(0);
    let slave = m
        .add_condition(
            ConditionId(1),
            GeometryKind::Quadrilateral3D4,
            "c",
            &slave_nodes,
            p,
        )
        .unwrap();
    let mut conditions = vec![slave];
    for (k, corners) in masters.iter().enumerate() {
        let nodes: Vec<NodeId> = corners
            .iter()
            .map(|&(x, y)| node(&mut m, x, y, z0 - gap))
            .collect();
        let kind = match nodes.len() {
            3 => GeometryKind::Triangle3D3,
            _ => GeometryKind::Quadrilateral3D4,
        };
        let c = m
            .add_condition(ConditionId(2 + k as u32), kind, "c", &nodes, p)
            .unwrap();
        conditions.push(c);
    }
    let sub = m.create_part("Contact.ContactSub0").unwrap();
    let nodes: Vec<NodeIdx> = (0..m.nodes().len() as u32).map(NodeIdx).collect();
    m.add_nodes_to_part(sub, &nodes);
    m.add_conditions_to_part(sub, &conditions);
    for (i, n) in nodes.iter().enumerate() {
        let f = &mut m.nodes_mut().flags_mut()[n.index()];
        f.set(Flag::SLAVE, i < 4);
        f.set(Flag::MASTER, i >= 4);
    }
    for (k, c) in conditions.iter().enumerate() {
        let f = &mut m.conditions_mut().flags_mut()[c.index()];
        f.set(Flag::SLAVE, k == 0);
        f.set(Flag::MASTER, k > 0);
    }
    compute_unit_normals(&mut m, Some(sub), csm_model::NormalsMode::Once).unwrap();
    for k in 0..masters.len() {
        m.index_map_mut(slave).add_id(ConditionId(2 + k as u32));
    }
    (m, sub)
}

/// Two master triangles under the slave's right half (x from 0.5 to 1.5): the slave overlaps
/// each in one triangular cell (3 Gauss points for 4 shape functions: `Me` is singular and
/// Kratos falls back to the standard basis).
const TWO_TRIANGLES: [&[(Real, Real)]; 2] = [
    &[(0.5, 0.0), (0.5, 1.0), (1.5, 0.0)],
    &[(1.5, 0.0), (0.5, 1.0), (1.5, 1.0)],
];

fn map(model: &mut ModelPart, sub: PartIdx, mode: MortarMode) -> (MappingReport, Vec<Real>) {
    let settings = MappingSettings {
        mode,
        distance_threshold: 1e24,
        inverted: false,
        dim: 3,
        tuning: MappingTuning::default(),
        ranks: None,
    };
    let report = normal_gap_process(model, sub, &settings, None).unwrap();
    let gaps = model.nodal_data().scalar(ScalarVar::NormalGap, 0).unwrap()[..4].to_vec();
    (report, gaps)
}

// See: issue 24, cause 1 ("one quadrilateral slave over two master triangles at z = 1 gives
// +10.55 instead of −0.001").
#[test]
fn robust_mapping_of_a_standard_basis_pair_is_exact_anywhere() {
    for z0 in [0.0, 1.0, 1e3, 1e6, 1e8] {
        let (mut m, sub) = scene(z0, 0.001, 1.0, &TWO_TRIANGLES);
        let (report, gaps) = map(&mut m, sub, MortarMode::Robust);
        assert_eq!(report.kept, 2);
        assert!(report.standard_basis_pairs > 0, "{report:?}");
        assert!(report.converged && report.warnings(MortarMode::Robust).is_empty());
        let tolerance = 1e-9 * 0.001 + 64.0 * Real::EPSILON * z0;
        for (i, g) in gaps.iter().enumerate() {
            assert!((g + 0.001).abs() <= tolerance, "z0 {z0}, node {i}: {g}");
        }
    }
}

#[test]
fn kratos_mapping_warns_where_its_iterations_are_not_one_exact_step() {
    let (mut m, sub) = scene(1.0, 0.001, 1.0, &TWO_TRIANGLES);
    let (report, gaps) = map(&mut m, sub, MortarMode::Kratos);
    assert_eq!(report.standard_basis_pairs, 1, "{report:?}");
    assert_eq!(report.standard_basis_nodes, 4);
    let warnings = report.warnings(MortarMode::Kratos);
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(warnings[0].contains("1 mapped pair(s) (4 slave node(s))"));
    assert!(warnings[0].contains("\"compatibility\": \"robust\""));
    // Kratos' iterations leave a gap off by far more than the rounding (the reproduction).
    let worst = gaps.iter().map(|g| (g + 0.001).abs()).fold(0.0, Real::max);
    assert!(worst > 1e-6, "{gaps:?}");
    // Dual-basis pairs near the origin: no warning.
    let quad: [&[(Real, Real)]; 1] = [&[(0.5, 0.0), (0.5, 1.0), (1.5, 1.0), (1.5, 0.0)]];
    let (mut m, sub) = scene(0.0, 0.001, 1.0, &quad);
    let (report, _) = map(&mut m, sub, MortarMode::Kratos);
    assert_eq!(report.standard_basis_pairs, 0);
    assert!(report.warnings(MortarMode::Kratos).is_empty(), "{report:?}");
}

// See: issue 24, cause 2 (the dual basis' floor ‖Me‖ ≥ ε is an area).
#[test]
fn robust_mapping_keeps_the_dual_basis_and_the_gap_at_tiny_scales() {
    let quad: [&[(Real, Real)]; 1] = [&[(0.25, 0.0), (0.25, 1.0), (1.25, 1.0), (1.25, 0.0)]];
    let (mut m, sub) = scene(0.0, 0.01, 1.0, &quad);
    let (base, gaps0) = map(&mut m, sub, MortarMode::Robust);
    assert_eq!(base.standard_basis_pairs, 0);
    for scale in [1e-6, 1e-9, 1e-12, 1e6] {
        let (mut m, sub) = scene(0.0, 0.01, scale, &quad);
        let (report, gaps) = map(&mut m, sub, MortarMode::Robust);
        assert_eq!(report.standard_basis_pairs, 0, "scale {scale}");
        for (g, g0) in gaps.iter().zip(&gaps0) {
            assert!(
                (g / scale - g0).abs() <= 1e-12,
                "scale {scale}: {g} vs {g0}"
            );
        }
    }
    // Kratos falls back to the standard basis once ‖Me‖ (an area) is below ε.
    let (mut m, sub) = scene(0.0, 0.01, 1e-9, &quad);
    assert_eq!(
        map(&mut m, sub, MortarMode::Kratos).0.standard_basis_pairs,
        1
    );
}

// See: issue 24, cause 4 ("was this node mapped?" is |AUX| > ε in Kratos).
#[test]
fn robust_mapping_knows_a_point_mapped_onto_the_origin_is_mapped() {
    // The slave's first node maps onto the master node at the origin.
    let quad: [&[(Real, Real)]; 1] = [&[(0.0, 0.0), (0.0, 1.0), (1.0, 1.0), (1.0, 0.0)]];
    let (mut m, sub) = scene(0.05, 0.05, 1.0, &quad);
    let (_, gaps) = map(&mut m, sub, MortarMode::Robust);
    for g in &gaps {
        assert!((g + 0.05).abs() < 1e-12, "{gaps:?}");
    }
    let aux = m
        .nodal_data()
        .vector(csm_model::VectorVar::AuxiliarCoordinates, 0)
        .unwrap();
    assert!(aux[0].norm() < 1e-12, "{:?}", aux[0]);
    let (mut m, sub) = scene(0.05, 0.05, 1.0, &quad);
    let (report, gaps) = map(&mut m, sub, MortarMode::Kratos);
    assert_eq!(gaps[0], NORMAL_GAP_SENTINEL, "{gaps:?}");
    assert_eq!(report.origin_nodes, 1);
    let warnings = report.warnings(MortarMode::Kratos);
    assert!(
        warnings.len() == 1 && warnings[0].contains("1 slave node(s) were mapped onto the origin"),
        "{warnings:?}"
    );
}

/// The weighted gap of the standard-basis scene in `mode`, by slave node, with the interface
/// at height `z0`.
fn weighted_gaps(z0: Real, mode: MortarMode) -> Vec<Real> {
    let (mut m, sub) = scene(z0, 0.001, 1.0, &TWO_TRIANGLES);
    m.nodal_data_mut().add_scalar(ScalarVar::WeightedGap);
    let pairs = [
        (ConditionIdx(0), ConditionIdx(1)),
        (ConditionIdx(0), ConditionIdx(2)),
    ];
    crate::compute_weighted_gap(&mut m, sub, &pairs, (mode, 1e24), 3, None).unwrap();
    m.nodal_data().scalar(ScalarVar::WeightedGap, 0).unwrap()[..4].to_vec()
}

// See: issue 24 (the weighted gap subtracts two sums of absolute coordinates).
#[test]
fn robust_weighted_gap_is_the_same_far_from_the_origin() {
    let near = weighted_gaps(0.0, MortarMode::Robust);
    // Σ_i wg_i = −0.001 · the overlap area (0.5) of the flat interface.
    let total: Real = near.iter().sum();
    assert!((total + 0.0005).abs() < 1e-15, "{near:?}");
    for z0 in [1e3, 1e6, 1e8] {
        let far = weighted_gaps(z0, MortarMode::Robust);
        for (f, n) in far.iter().zip(&near) {
            assert!(
                (f - n).abs() <= 64.0 * Real::EPSILON * 1e-3 * z0,
                "z0 {z0}: {far:?}"
            );
        }
    }
    // Kratos' arithmetic at 1e8: the cancellation of the absolute sums is of order ε·1e8.
    let kratos = weighted_gaps(1e8, MortarMode::Kratos);
    let worst = kratos
        .iter()
        .zip(&near)
        .map(|(k, n)| (k - n).abs())
        .fold(0.0, Real::max);
    assert!(worst > 1e-10, "{kratos:?}");
}

/// The removals in parallel leave every INDEX_MAP as the serial loop over the list does: slave
/// conditions ascending (cut between slaves; one slave's entries where the middle cuts fall,
/// so that the cut moves to its end or back to its start; maps without removals between),
/// and out of order (the serial pass), on pools of 1–3 threads.
#[test]
fn removals_in_parallel_leave_the_maps_of_the_serial_loop() {
    // 3,000 conditions, condition c with masters 1..=(c % 9 + 1), and condition 1,500 with
    // 20,000 (more than a task's removals alone).
    let maps: Vec<csm_model::IndexMap> = (0..3000u32)
        .map(|c| {
            let mut map = csm_model::IndexMap::new();
            let n = if c == 1500 { 20_000 } else { c % 9 + 1 };
            for master in 1..=n {
                map.add_id(ConditionId(master));
            }
            map
        })
        .collect();
    // Every third condition loses its odd masters (and a master it does not hold), in
    // descending master order for a few; condition 1,500 loses every odd one.
    let mut ascending = Vec::new();
    for c in (0..3000u32).filter(|c| c % 3 == 0 || *c == 1500) {
        let n = if c == 1500 { 20_000 } else { c % 9 + 1 };
        let mut masters: Vec<u32> = (1..=n + 1).filter(|m| m % 2 == 1).collect();
        if c % 4 == 0 {
            masters.reverse();
        }
        ascending.extend(masters.into_iter().map(|m| RemovedEntry {
            slave: ConditionIdx(c),
            master: ConditionId(m),
            paired: None,
        }));
    }
    // Two slaves' entries swapped (the list no longer ascends): the maps lose the same
    // entries, so they end as the ascending list's.
    let mut scrambled = ascending.clone();
    scrambled.swap(10, 12_000);
    assert_ne!(scrambled[10].slave, scrambled[12_000].slave);
    let serial = |removed: &[RemovedEntry]| {
        let mut maps = maps.clone();
        for r in removed {
            maps[r.slave.index()].remove_id(r.master);
        }
        maps
    };
    let expected = serial(&ascending);
    assert!(serial(&scrambled) == expected);
    for removed in [&ascending, &scrambled] {
        assert!(expected.iter().zip(&maps).filter(|(a, b)| a != b).count() > 900);
        for threads in [1, 2, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut got = maps.clone();
            pool.install(|| segment::remove_entries(&mut got, removed));
            assert!(got == expected, "{threads} threads");
        }
    }
}
