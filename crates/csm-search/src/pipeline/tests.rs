//! Tests of the driver on scenes built in code, against brute-force oracles.

use std::collections::BTreeMap;

use csm_geometry::math::Point;
use csm_geometry::{Geometry, GeometryKind};
use csm_model::{ConditionIdx, ModelPart, NodeId, NodeIdx};

use super::candidates::Bv;
use super::*;
use crate::scenes::{plates, plates_setup as setup};
use crate::{ErrorKind, parse_setup};

const H: f64 = 0.25;

fn run(model: &mut ModelPart, s: &crate::SearchSetup) -> SearchResult {
    let mut search = ContactSearch::initialize(model, s).unwrap();
    search.step(model).unwrap()
}

fn pairs(r: &SearchResult) -> &crate::IdMap<Vec<u32>> {
    &r.pairs["0"]
}

fn points_of(model: &ModelPart, c: usize) -> Vec<Point> {
    model
        .conditions()
        .nodes(c)
        .iter()
        .map(|n| model.nodes().coordinates()[n.index()])
        .collect()
}

/// Brute force: every master whose centre is strictly inside the slave's search sphere.
fn radius_oracle(model: &ModelPart, search_factor: f64) -> BTreeMap<u32, Vec<u32>> {
    let ids = model.conditions().ids();
    let slave = model.find_part("Slave").unwrap();
    let master = model.find_part("Master").unwrap();
    let mut out = BTreeMap::new();
    for s in model.part(slave).conditions() {
        let sp = points_of(model, s.index());
        let g = Geometry::new(GeometryKind::Triangle3D3, &sp).unwrap();
        let (c, r) = (g.center(), search_factor * g.bounding_sphere().radius);
        let mut masters: Vec<u32> = model
            .part(master)
            .conditions()
            .iter()
            .filter(|m| {
                let mg = points_of(model, m.index());
                let mc = Geometry::new(GeometryKind::Triangle3D3, &mg)
                    .unwrap()
                    .center();
                (mc - c).norm_squared() < r * r
            })
            .map(|m| ids[m.index()])
            .collect();
        masters.sort_unstable();
        out.insert(ids[s.index()], masters);
    }
    out
}

#[test]
fn no_check_in_radius_equals_the_brute_force_radius_query() {
    let mut model = plates(6, 0.01, false);
    let r = run(
        &mut model,
        &setup(
            r#"{"type_search": "in_radius", "check_gap": "no_check"}"#,
            "",
        ),
    );
    assert_eq!(pairs(&r), &radius_oracle(&model, 3.5));
    assert_eq!(r.paired_conditions, r.n_pairs());
    assert!(
        r.nodes.values().all(|n| n.active && n.normal_gap.is_none()),
        "NoCheck activates"
    );
}

#[test]
fn obb_filter_keeps_a_subset_whose_boxes_intersect() {
    let mut model = plates(6, 0.01, false);
    let s = setup(
        r#"{"type_search": "in_radius_with_obb", "check_gap": "no_check"}"#,
        "",
    );
    let r = run(&mut model, &s);
    let oracle = radius_oracle(&model, 3.5);
    let mut total = 0;
    for (slave, masters) in pairs(&r) {
        let s_idx = model.conditions().index_of(*slave).unwrap();
        let sb = Bv::build(
            &Geometry::new(GeometryKind::Triangle3D3, &points_of(&model, s_idx)).unwrap(),
            3,
            0.1 * H,
            true,
            crate::Compatibility::Kratos,
        )
        .unwrap();
        for m in masters {
            assert!(oracle[slave].contains(m));
            let m_idx = model.conditions().index_of(*m).unwrap();
            let mb = Bv::build(
                &Geometry::new(GeometryKind::Triangle3D3, &points_of(&model, m_idx)).unwrap(),
                3,
                0.1 * H,
                true,
                crate::Compatibility::Kratos,
            )
            .unwrap();
            assert!(
                matches!((sb, mb), (Bv::D3(a), Bv::D3(b)) if a.intersects(&b, csm_geometry::ObbIntersection::Sat, csm_geometry::SatMode::Kratos))
            );
            total += 1;
        }
    }
    let radius_total: usize = oracle.values().map(Vec::len).sum();
    assert!(
        total > 0 && total < radius_total,
        "{total} of {radius_total}"
    );
}

#[test]
fn mapping_check_rejects_masters_facing_the_same_way() {
    let mut model = plates(4, 0.01, true);
    let r = run(&mut model, &setup(r#"{"type_search": "in_radius"}"#, ""));
    assert!(pairs(&r).values().all(Vec::is_empty));
    assert!(r.warnings.is_empty(), "{:?}", r.warnings);
    let mut model = plates(4, 0.01, false);
    let r = run(&mut model, &setup(r#"{"type_search": "in_radius"}"#, ""));
    assert!(r.n_pairs() > 0);
    assert_eq!(
        r.paired_conditions,
        r.n_pairs(),
        "MappingCheck creates one paired condition per surviving pair"
    );
    // Gap 0.01 > 2e-3 · NODAL_H: every node is inactive, and Kratos' SetInactiveNode writes
    // NORMAL_GAP = 0 (Q24); robust mode keeps the mapped gap, 0.01 on flat, parallel plates.
    let gaps =
        |r: &SearchResult| -> Vec<f64> { r.nodes.values().filter_map(|n| n.normal_gap).collect() };
    assert!(r.nodes.values().all(|n| !n.active));
    assert!(!gaps(&r).is_empty() && gaps(&r).iter().all(|g| *g == 0.0));
    let mut model = plates(4, 0.01, false);
    let r = run(
        &mut model,
        &setup(
            r#"{"type_search": "in_radius"}"#,
            r#", "compatibility": "robust""#,
        ),
    );
    assert!(r.nodes.values().all(|n| !n.active));
    let g = gaps(&r);
    assert!(
        !g.is_empty() && g.iter().all(|g| (g - 0.01).abs() < 1e-12),
        "{g:?}"
    );
}

#[test]
fn direct_check_needs_the_gap_below_the_active_check_length() {
    // Gap 0.01 > NODAL_H · active_check_factor = 0.0025: nothing; a penetration: pairs.
    let sp = r#"{"type_search": "in_radius", "check_gap": "direct_check"}"#;
    let mut model = plates(4, 0.01, false);
    let r = run(&mut model, &setup(sp, ""));
    assert_eq!(r.n_pairs(), 0);
    assert!(r.nodes.values().all(|n| !n.active));
    let mut model = plates(4, -0.01, false);
    let r = run(&mut model, &setup(sp, ""));
    assert!(r.n_pairs() > 0);
    assert!(r.nodes.values().filter(|n| n.active).count() > 0);
}

/// Runs `f` in a rayon pool of `threads` threads.
pub(crate) fn in_pool<R: Send>(threads: usize, f: impl FnOnce() -> R + Send) -> R {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

#[test]
fn results_are_identical_for_any_thread_count() {
    let s = setup(
        r#"{"type_search": "in_radius_with_obb", "check_gap": "direct_check"}"#,
        "",
    );
    let run_with = |threads: usize| {
        in_pool(threads, || {
            let mut model = plates(8, -0.005, false);
            run(&mut model, &s)
        })
    };
    let one = run_with(1);
    assert!(one.n_pairs() > 0);
    assert_eq!(one, run_with(2));
    assert_eq!(one, run_with(3));
}

/// MappingCheck's INDEX_MAP updates run in parallel on several threads where the slaves'
/// order cannot matter, and serially otherwise: the slave plate half off the master (half the
/// slaves without candidates), with predefined roles and with roles decided automatically
/// (robust mode: every condition is then a slave, and candidates are slaves).
#[test]
fn mapping_check_pairs_are_identical_for_any_thread_count() {
    let predefined = setup("{}", "");
    let automatic = parse_setup(
        r#"{"contact_model_part": {"0": ["Slave", "Master"]},
            "assume_master_slave": {"0": []}, "compatibility": "robust"}"#,
        "test",
    )
    .unwrap();
    for s in [&predefined, &automatic] {
        let run_with = |threads: usize| {
            in_pool(threads, || {
                let mut model = plates(8, -0.005, false);
                let slave = model.find_part("Slave").unwrap();
                let nodes = model.part(slave).nodes().to_vec();
                for n in nodes {
                    model.nodes_mut().coordinates_mut()[n.index()].x += 4.0 * H;
                }
                run(&mut model, s)
            })
        };
        let one = run_with(1);
        let paired = pairs(&one).values().filter(|m| !m.is_empty()).count();
        assert!(
            paired > 0 && paired < pairs(&one).len(),
            "{paired} slaves paired"
        );
        assert_eq!(one, run_with(2));
        assert_eq!(one, run_with(3));
    }
}

#[test]
fn robust_kdop_keeps_pairs_that_deep_penetration_makes_the_obbs_lose() {
    // Penetration 0.2 > 2 · bounding_box_factor · NODAL_H = 0.05.
    let deep = -0.2;
    let obb = {
        let mut model = plates(4, deep, false);
        run(
            &mut model,
            &setup(
                r#"{"type_search": "in_radius_with_obb", "check_gap": "no_check"}"#,
                "",
            ),
        )
    };
    assert_eq!(obb.n_pairs(), 0, "Q42: the OBBs are too thin");
    let kdop = |compat: &str| {
        let mut model = plates(4, deep, false);
        let s = setup(
            r#"{"type_search": "kdop_18", "check_gap": "no_check"}"#,
            &format!(r#", "compatibility": "{compat}""#),
        );
        run(&mut model, &s)
    };
    assert_eq!(
        kdop("kratos").n_pairs(),
        0,
        "unswept 18-DOPs are as thin as the OBBs"
    );
    let robust = kdop("robust");
    let mut model = plates(4, deep, false);
    let radius = run(
        &mut model,
        &setup(
            r#"{"type_search": "in_radius", "check_gap": "no_check"}"#,
            "",
        ),
    );
    assert!(robust.n_pairs() > 0 && robust.n_pairs() <= radius.n_pairs());
}

#[test]
fn inverted_search_queries_from_the_master_side() {
    let mut model = plates(4, 0.01, false);
    let s = setup(
        "{}",
        r#", "cpp_search_parameters": {"inverted_search": true, "check_gap": "NoCheck",
            "condition_name": "ALMFrictionlessMortarContact", "normal_orientation_threshold": 0.1}"#,
    );
    let r = run(&mut model, &s);
    let master = model.find_part("Master").unwrap();
    let master_ids: Vec<u32> = model
        .part(master)
        .conditions()
        .iter()
        .map(|c| model.conditions().ids()[c.index()])
        .collect();
    assert_eq!(pairs(&r).keys().copied().collect::<Vec<_>>(), master_ids);
    assert!(r.n_pairs() > 0);
}

#[test]
fn a_degenerate_slave_is_an_error_naming_it() {
    let mut model = plates(2, 0.01, false);
    // Collapse slave condition 1 onto a line.
    let c = model.conditions().index_of(1).unwrap();
    let nodes: Vec<NodeIdx> = model.conditions().nodes(c).to_vec();
    let p0 = model.nodes().coordinates()[nodes[0].index()];
    model.nodes_mut().coordinates_mut()[nodes[1].index()] = p0;
    model.nodes_mut().coordinates_mut()[nodes[2].index()] = p0;
    let s = setup(
        r#"{"type_search": "in_radius", "check_gap": "no_check"}"#,
        "",
    );
    let e = ContactSearch::initialize(&mut model, &s)
        .and_then(|mut search| search.step(&mut model))
        .unwrap_err();
    assert!(
        matches!(e.kind(), ErrorKind::Model(_) | ErrorKind::Geometry { .. }),
        "{e}"
    );
    assert!(e.to_string().contains("condition 1:"), "{e}");
}

#[test]
fn pairs_sharing_conditions_get_clones_with_their_own_maps() {
    let mut model = plates(3, 0.01, false);
    let n = model.conditions().len() as u32;
    let text = r#"{"contact_model_part": {"0": ["Slave", "Master"], "1": ["Slave", "Master"]},
            "assume_master_slave": {"0": ["Slave"], "1": ["Slave"]},
            "search_parameters": {"type_search": "in_radius", "check_gap": "no_check"}}"#;
    let s = parse_setup(text, "test").unwrap();
    let r = run(&mut model, &s);
    assert_eq!(
        model.conditions().len() as u32,
        2 * n,
        "every condition cloned once"
    );
    let (p0, p1) = (&r.pairs["0"], &r.pairs["1"]);
    assert_eq!(p0.len(), p1.len());
    assert!(p0.keys().all(|&id| id <= n) && p1.keys().all(|&id| id > n));
    // The clone of condition k is T + (its rank in id order) = n + k here (dense ids).
    for (slave, masters) in p0 {
        let cloned: Vec<u32> = masters.iter().map(|m| m + n).collect();
        assert_eq!(p1[&(slave + n)], cloned);
    }
    assert_eq!(
        r.paired_conditions,
        2 * r.pairs["0"].values().map(Vec::len).sum::<usize>()
    );
}

#[test]
fn an_existing_contact_part_is_reused_with_flags_from_the_nodes() {
    let s = setup(
        r#"{"type_search": "in_radius", "check_gap": "no_check"}"#,
        "",
    );
    let reference = run(&mut plates(3, 0.01, false), &s);
    // The same scene with `Contact` already there, as after a restart: the nodal flags decide
    // which conditions are slave (stage 3).
    let mut model = plates(3, 0.01, false);
    let contact = model.create_part("Contact").unwrap();
    assert!(
        ContactSearch::initialize(&mut model.clone(), &s).is_err(),
        "no ContactSub0"
    );
    let sub = model.create_part("Contact.ContactSub0").unwrap();
    for (name, slave) in [("Slave", true), ("Master", false)] {
        let part = model.find_part(name).unwrap();
        let nodes = model.part(part).nodes().to_vec();
        let conditions = model.part(part).conditions().to_vec();
        for n in &nodes {
            let f = &mut model.nodes_mut().flags_mut()[n.index()];
            f.set(csm_model::Flag::INTERFACE, true);
            f.set(csm_model::Flag::SLAVE, slave);
        }
        model.add_nodes_to_part(sub, &nodes);
        model.add_conditions_to_part(sub, &conditions);
    }
    assert!(!model.part(contact).conditions().is_empty());
    let r = run(&mut model, &s);
    assert_eq!(r.pairs, reference.pairs);
}

/// Robust mode runs the octree from the master side too (Kratos refuses): with NoCheck the
/// pairs are exactly the transpose of the direct search's, as the robust octree finds every
/// pair whose OBBs intersect and that test is symmetric.
#[test]
fn robust_inverted_octree_is_the_transpose_of_the_direct_one() {
    let octree = |inverted: bool, compat: &str| {
        let mut model = plates(4, 0.01, false);
        let s = setup(
            "{}",
            &format!(
                r#", "compatibility": "{compat}", "cpp_search_parameters": {{
                    "type_search": "OctreeWithOBB", "check_gap": "NoCheck",
                    "inverted_search": {inverted}, "normal_orientation_threshold": 0.1,
                    "condition_name": "ALMFrictionlessMortarContact"}}"#
            ),
        );
        ContactSearch::initialize(&mut model, &s).and_then(|mut search| search.step(&mut model))
    };
    assert!(
        octree(true, "kratos").is_err(),
        "Kratos refuses an inverted octree search"
    );
    let direct = octree(false, "robust").unwrap();
    let inverted = octree(true, "robust").unwrap();
    let mut transpose: BTreeMap<u32, Vec<u32>> = BTreeMap::new();
    for (s, masters) in pairs(&direct) {
        for m in masters {
            transpose.entry(*m).or_default().push(*s);
        }
    }
    let found: BTreeMap<u32, Vec<u32>> = pairs(&inverted)
        .iter()
        .filter(|(_, v)| !v.is_empty())
        .map(|(k, v)| (*k, v.clone()))
        .collect();
    assert!(!found.is_empty());
    assert_eq!(found, transpose);
}

/// Dynamic search (§11): the kd query is centred on the half-jump centre, `Δ = 0.25·dt·(v_n +
/// v_{n−1}) + 0.125·dt²·a_{n−1}`. Plates 1.0 apart find nothing statically; a slave velocity
/// of −2 along z over dt = 1 moves the query centre by −1 onto the master. With NoCheck Kratos
/// then subtracts Δ from the (never moved) nodes (Q9); robust mode does not.
#[test]
fn dynamic_search_queries_from_the_predicted_position() {
    use csm_geometry::math::Vector;
    use csm_model::VectorVar;
    let sp = r#"{"type_search": "in_radius", "check_gap": "no_check", "dynamic_search": true}"#;
    let run_dynamic = |compat: &str, velocity: f64| {
        let mut model = plates(3, 1.0, false);
        let s = setup(sp, &format!(r#", "compatibility": "{compat}""#));
        let mut search = ContactSearch::initialize(&mut model, &s).unwrap();
        let slave = model.find_part("Slave").unwrap();
        let nodes = model.part(slave).nodes().to_vec();
        for step in 0..2 {
            let v = model
                .nodal_data_mut()
                .vector_mut(VectorVar::Velocity, step)
                .unwrap();
            for n in &nodes {
                v[n.index()] = Vector::new(0.0, 0.0, velocity);
            }
        }
        let z_before = model.nodes().coordinates()[nodes[0].index()].z;
        let r = search.step(&mut model).unwrap();
        let z_after = model.nodes().coordinates()[nodes[0].index()].z;
        (r.n_pairs(), z_after - z_before)
    };
    assert_eq!(run_dynamic("kratos", 0.0).0, 0, "static: too far");
    let (pairs, shift) = run_dynamic("kratos", -2.0);
    assert!(pairs > 0, "the half-jump centre reaches the master");
    assert!(
        (shift - 1.0).abs() < 1e-12,
        "Q9: X -= Δ with Δ = −1, got {shift}"
    );
    let (robust_pairs, robust_shift) = run_dynamic("robust", -2.0);
    assert_eq!((robust_pairs, robust_shift), (pairs, 0.0));
}

/// `database_step_update` (§1.4, Q36): with 2, the search runs at step 1 and 3; at step 2
/// every Contact node and condition is set inactive and the pairs of step 1 stay.
#[test]
fn database_step_update_skips_steps_and_deactivates() {
    let mut model = plates(3, 0.01, false);
    let s = setup(
        r#"{"type_search": "in_radius", "check_gap": "no_check", "database_step_update": 2}"#,
        "",
    );
    let mut search = ContactSearch::initialize(&mut model, &s).unwrap();
    let first = search.step(&mut model).unwrap();
    assert!(first.n_pairs() > 0 && first.nodes.values().all(|n| n.active));
    search.finalize_step(&mut model).unwrap();
    model.process_info_mut().set_number("STEP", 2.0);
    let skipped = search.step(&mut model).unwrap();
    assert!(
        skipped.nodes.values().all(|n| !n.active),
        "Q36: deactivated in a skipped step"
    );
    search.finalize_step(&mut model).unwrap();
    model.process_info_mut().set_number("STEP", 3.0);
    let third = search.step(&mut model).unwrap();
    assert_eq!(third.pairs, first.pairs);
    assert!(third.nodes.values().all(|n| n.active));
}

/// `adapt_search` multiplies search_factor and active_check_factor by h_max / h_min over all
/// nodes (§16.2); a node outside every element makes it infinite (Q33), an error here.
#[test]
fn adapt_search_scales_by_the_mesh_size_ratio() {
    let mut model = plates(3, 0.01, false);
    // Master twice as coarse: h = 2H there.
    let master = model.find_part("Master").unwrap();
    let mut to_scale: Vec<NodeIdx> = model.part(master).nodes().to_vec();
    for e in 0..model.elements().len() {
        if model
            .elements()
            .nodes(e)
            .iter()
            .any(|n| to_scale.contains(n))
        {
            to_scale.extend_from_slice(model.elements().nodes(e));
        }
    }
    to_scale.sort_unstable();
    to_scale.dedup();
    for n in to_scale {
        let p = &mut model.nodes_mut().coordinates_mut()[n.index()];
        p.coords *= 2.0;
    }
    let s = setup(r#"{"adapt_search": true, "check_gap": "no_check"}"#, "");
    let search = ContactSearch::initialize(&mut model, &s).unwrap();
    assert_eq!(search.setup().pairs[&0].search.search_factor, 7.0);
    assert_eq!(search.setup().active_check_factor, 0.02);
    let mut model = plates(2, 0.01, false);
    model
        .add_node(NodeId(9999), Point::new(9.0, 9.0, 9.0))
        .unwrap();
    let e = ContactSearch::initialize(&mut model, &s).unwrap_err();
    assert!(e.to_string().contains("Q33"), "{e}");
}

/// A multi-step run through [`ContactSearch::advance`]: the first step keeps STEP 1 and sets
/// DELTA_TIME; later steps advance STEP and TIME and shift the buffer; the motion gives
/// DISPLACEMENT, VELOCITY and ACCELERATION as a solver would (DESIGN.md §3).
#[test]
fn advance_moves_the_parts_with_kratos_buffer_semantics() {
    use csm_model::VectorVar;
    let mut model = plates(3, 0.01, false);
    let s = setup(
        "{}",
        r#", "steps": [
            {"delta_time": 0.5, "move": {"Slave": {"translate": [0, 0, -0.002]}}},
            {"delta_time": 0.25, "move": {"Slave": {"translate": [0, 0, -0.004]}}}]"#,
    );
    let slave = model.find_part("Slave").unwrap();
    let node = model.part(slave).nodes()[0].index();
    let master_node = model.part(model.find_part("Master").unwrap()).nodes()[0].index();
    let z0 = model.nodes().coordinates()[node].z;
    let mut search = ContactSearch::initialize(&mut model, &s).unwrap();
    let z = |var, step, m: &ModelPart| m.nodal_data().vector(var, step).unwrap()[node].z;
    search.advance(&mut model, &s.steps[0]).unwrap();
    let pi = model.process_info();
    assert_eq!(
        (
            pi.number("STEP"),
            pi.number("TIME"),
            pi.number("DELTA_TIME")
        ),
        (Some(1.0), Some(1.0), Some(0.5))
    );
    assert!((model.nodes().coordinates()[node].z - (z0 - 0.002)).abs() < 1e-15);
    assert!((z(VectorVar::Velocity, 0, &model) + 0.004).abs() < 1e-12);
    search.step(&mut model).unwrap();
    search.finalize_step(&mut model).unwrap();
    search.advance(&mut model, &s.steps[1]).unwrap();
    let pi = model.process_info();
    assert_eq!(
        (
            pi.number("STEP"),
            pi.number("TIME"),
            pi.number("DELTA_TIME")
        ),
        (Some(2.0), Some(1.25), Some(0.25))
    );
    assert!((z(VectorVar::Displacement, 0, &model) + 0.006).abs() < 1e-12);
    assert!((z(VectorVar::Velocity, 1, &model) + 0.004).abs() < 1e-12);
    assert!((z(VectorVar::Velocity, 0, &model) + 0.016).abs() < 1e-12);
    assert!((z(VectorVar::Acceleration, 0, &model) + 0.048).abs() < 1e-12);
    let still = model.nodal_data().vector(VectorVar::Velocity, 0).unwrap()[master_node];
    assert_eq!(
        still,
        csm_geometry::math::Vector::zeros(),
        "unmoved nodes get a zero increment"
    );
    assert!(search.step(&mut model).unwrap().n_pairs() > 0);
}

/// Parts named in `steps` must exist and, within a step, share no node.
#[test]
fn step_parts_must_exist_and_be_disjoint() {
    let mut model = plates(2, 0.01, false);
    let s = setup(
        "{}",
        r#", "steps": [{"delta_time": 1, "move": {"Nope": {"translate": [0, 0, 1]}}}]"#,
    );
    let e = ContactSearch::initialize(&mut model, &s).unwrap_err();
    assert!(
        matches!(e.kind(), ErrorKind::InvalidValue { key, .. } if key == "steps[0].move.Nope"),
        "{e}"
    );
    let mut model = plates(2, 0.01, false);
    let slave = model.find_part("Slave").unwrap();
    let nodes = model.part(slave).nodes().to_vec();
    let both = model.create_part("Both").unwrap();
    model.add_nodes_to_part(both, &nodes[..1]);
    let s = setup(
        "{}",
        r#", "steps": [{"delta_time": 1, "move": {"Both": {}, "Slave": {}}}]"#,
    );
    let e = ContactSearch::initialize(&mut model, &s).unwrap_err();
    assert!(
        e.to_string().contains("`Both` and `Slave` share node"),
        "{e}"
    );
}

/// C++ parameters without `condition_name` create no paired conditions: Kratos'
/// ResetContactOperators then fails on the INDEX_MAP entries at the end of the first step
/// (Q18, "Condition index not found: 0." with Kratos 10.4.4); robust mode drops the entries.
#[test]
fn a_second_step_without_paired_conditions_fails_as_in_kratos() {
    for (compat, fails) in [("kratos", true), ("robust", false)] {
        let mut model = plates(3, 0.01, false);
        let s = setup(
            "{}",
            &format!(
                r#", "cpp_search_parameters": {{"type_search": "InRadius"}},
                     "compatibility": "{compat}""#
            ),
        );
        let mut search = ContactSearch::initialize(&mut model, &s).unwrap();
        assert!(search.step(&mut model).unwrap().n_pairs() > 0);
        let r = search.finalize_step(&mut model);
        assert_eq!(r.is_err(), fails, "{compat}: {r:?}");
        if let Err(e) = r {
            assert!(e.to_string().contains("Q18"), "{e}");
        } else {
            model.advance_time_step(1.0);
            assert!(search.step(&mut model).unwrap().n_pairs() > 0);
        }
    }
}

/// The search follows the plan made from the model as read: `plan()` equals [`crate::Plan::new`]
/// on the model before `initialize`, and the nodal variables are those it allocates — no
/// DISPLACEMENT, no Lagrange multipliers, NORMAL and NODAL_H without history, VELOCITY and
/// ACCELERATION only with `dynamic_search`, WEIGHTED_GAP only for the Advanced activation.
#[test]
fn the_search_follows_its_plan() {
    use crate::{Decision, Plan, Reason};
    use csm_model::{ScalarVar, VectorVar};
    for (sp, dynamic, advanced) in [
        (r#"{"type_search": "in_radius_with_obb"}"#, false, true),
        (
            r#"{"simple_search": true, "dynamic_search": true, "type_search": "octree_with_obb"}"#,
            true,
            false,
        ),
        (
            r#"{"check_gap": "no_check", "type_search": "kdop_18"}"#,
            false,
            false,
        ),
    ] {
        let mut model = plates(3, 0.01, false);
        let s = setup(sp, "");
        let plan = Plan::new(&model, &s).unwrap();
        let mut search = ContactSearch::initialize(&mut model, &s).unwrap();
        assert_eq!(search.plan(), &plan, "{sp}");
        search.step(&mut model).unwrap();
        assert_eq!(search.plan(), &plan, "zero velocities: no step jump ({sp})");
        if dynamic {
            assert_eq!(
                plan.pairs[&0].step_jump,
                Decision::LeftOut(Reason::NoVelocities)
            );
        }
        let data = model.nodal_data();
        assert!(!data.has_vector(VectorVar::Displacement));
        assert!(!data.has_scalar(ScalarVar::LagrangeMultiplierContactPressure));
        assert_eq!(data.vector_steps(VectorVar::Normal), 1);
        assert_eq!(data.scalar_steps(ScalarVar::NodalH), 1);
        let history = if dynamic { 2 } else { 0 };
        assert_eq!(data.vector_steps(VectorVar::Velocity), history, "{sp}");
        assert_eq!(data.vector_steps(VectorVar::Acceleration), history, "{sp}");
        assert_eq!(data.has_scalar(ScalarVar::WeightedGap), advanced, "{sp}");
    }
}

/// With velocities set after `initialize`, the step decides the step jump again and records
/// it in the plan.
#[test]
fn the_step_jump_is_decided_again_every_step() {
    use csm_geometry::math::Vector;
    use csm_model::VectorVar;
    let mut model = plates(3, 1.0, false);
    let s = setup(
        r#"{"type_search": "in_radius", "dynamic_search": true}"#,
        "",
    );
    let mut search = ContactSearch::initialize(&mut model, &s).unwrap();
    assert!(!search.plan().pairs[&0].step_jump.is_used());
    let slave = model.find_part("Slave").unwrap();
    let nodes = model.part(slave).nodes().to_vec();
    let v = model
        .nodal_data_mut()
        .vector_mut(VectorVar::Velocity, 0)
        .unwrap();
    v[nodes[0].index()] = Vector::new(0.0, 0.0, -1.0);
    search.step(&mut model).unwrap();
    let jump = search.plan().pairs[&0].step_jump.used().copied().unwrap();
    assert_eq!(jump.moving_nodes, 1);
    assert!(jump.moves_nodes, "MappingCheck moves the nodes");
}

/// The Morton order of the slave queries is a permutation, deterministic, and walks the
/// centres of a regular grid in Z order (the quadrant of the first half comes first).
#[test]
fn morton_order_is_a_deterministic_z_curve_permutation() {
    let model = plates(4, 0.01, false);
    let slave = model.find_part("Slave").unwrap();
    let slaves = model.part(slave).conditions().to_vec();
    let order = morton_order(&model, &slaves);
    let mut sorted = order.clone();
    sorted.sort_unstable();
    assert_eq!(sorted, (0..slaves.len()).collect::<Vec<_>>());
    assert_eq!(order, morton_order(&model, &slaves));
    // Z order: the first quarter of the curve lies in the lower-left quadrant of the plate.
    let coords = model.nodes().coordinates();
    let centre = |k: usize| {
        let nodes = model.conditions().nodes(slaves[k].index());
        let n = nodes.len() as f64;
        let (x, y) = nodes.iter().fold((0.0, 0.0), |(x, y), i| {
            (x + coords[i.index()].x, y + coords[i.index()].y)
        });
        (x / n, y / n)
    };
    let (xs, ys): (Vec<f64>, Vec<f64>) = (0..slaves.len()).map(centre).unzip();
    let mid = |v: &[f64]| {
        (v.iter().cloned().fold(f64::INFINITY, f64::min)
            + v.iter().cloned().fold(f64::NEG_INFINITY, f64::max))
            / 2.0
    };
    let (mx, my) = (mid(&xs), mid(&ys));
    for &k in &order[..slaves.len() / 4] {
        assert!(xs[k] < mx && ys[k] < my, "{k}: ({}, {})", xs[k], ys[k]);
    }
}

/// The step's results do not depend on which slave queries run first (those taken to stay far
/// from the masters, in slave order) and which along the Morton curve: every query taken as
/// far, none, or the estimate, on plates whose slave half is lifted far away (the estimate
/// then splits the slaves).
#[test]
fn the_order_of_the_slave_queries_does_not_change_the_step() {
    let mut model = plates(8, -0.005, false);
    let slave = model.find_part("Slave").unwrap();
    let slave_nodes = model.part(slave).nodes().len();
    let mid = 4.0 * H + H / 3.0;
    // Both layers of the slave plate's prisms (the first 2 · 81 nodes) beyond the middle.
    for i in 0..2 * 81 {
        let p = &mut model.nodes_mut().coordinates_mut()[i];
        if p.x > mid {
            p.z += 50.0 * H;
        }
    }
    assert_eq!(slave_nodes, 81);
    let s = setup(r#"{"type_search": "in_radius_with_obb"}"#, "");
    let step = |query_order: QueryOrder| {
        let mut m = model.clone();
        let mut search = ContactSearch::initialize(&mut m, &s).unwrap();
        search.set_tuning(SearchTuning {
            query_order,
            ..SearchTuning::default()
        });
        search.step(&mut m).unwrap()
    };
    let estimated = step(QueryOrder::Estimate);
    assert!(estimated.n_pairs() > 0);
    assert_eq!(
        step(QueryOrder::AllFirst),
        estimated,
        "every query first, in slave order"
    );
    assert_eq!(
        step(QueryOrder::AllAlongCurve),
        estimated,
        "every query along the curve"
    );
    // The estimate splits the slaves: some far from the masters' centres, some near.
    let master = model.find_part("Master").unwrap();
    let centres: Vec<Point> = model
        .part(master)
        .conditions()
        .iter()
        .map(|c| {
            let nodes = model.conditions().nodes(c.index());
            let sum = nodes.iter().fold(Point::origin().coords, |a, n| {
                a + model.nodes().coordinates()[n.index()].coords
            });
            Point::from(sum / nodes.len() as f64)
        })
        .collect();
    let bounds = csm_trees::bounds_of(&centres);
    let far = super::search::Far::new(bounds, 1.0);
    let (mut n_far, mut n_near) = (0, 0);
    for &c in model.part(slave).conditions() {
        let (centre, radius) = super::search::reach(&model, c);
        if far.is_far(&centre, radius) {
            n_far += 1;
        } else {
            n_near += 1;
        }
    }
    assert!(n_far > 20 && n_near > 20, "{n_far} far, {n_near} near");
}

/// One static step of the default search on plates bent into a bump: curved faces, so the
/// mapping's mean normals and Kratos' unit normals differ.
fn curved_plates_step() -> (ModelPart, SearchResult) {
    plates_step(true)
}

/// One static step of the default search on the plates, bent into a bump (`curved`) or flat
/// (the mapping's mean normals and Kratos' unit normals are then the same bits).
fn plates_step(curved: bool) -> (ModelPart, SearchResult) {
    let s = setup(r#"{"type_search": "in_radius_with_obb"}"#, "");
    let mut model = plates(8, -0.005, false);
    if curved {
        for p in model.nodes_mut().coordinates_mut() {
            p.z += 0.05 * (1.3 * p.x).sin() * (0.7 * p.y + 0.2).cos();
        }
    }
    let mut search = ContactSearch::initialize(&mut model, &s).unwrap();
    let result = search.step(&mut model).unwrap();
    (model, result)
}

#[test]
fn the_unit_normals_after_the_mapping_are_those_calculate_unit_normals_writes() {
    // Curved plates, so that the mapping's mean normals (normalised once) and Kratos' unit
    // normals (normalised once per adjacent face) differ: a static step keeps the unit
    // normals of its start instead of computing them again after the mapping.
    let (model, result) = curved_plates_step();
    assert!(result.n_pairs() > 0);
    let sub = model.find_part("Contact.ContactSub0").unwrap();
    let mut again = model.clone();
    csm_model::compute_unit_normals(&mut again, Some(sub), csm_model::NormalsMode::Kratos).unwrap();
    let normal = |m: &ModelPart| {
        m.nodal_data()
            .vector(csm_model::VectorVar::Normal, 0)
            .unwrap()
            .to_vec()
    };
    assert_eq!(normal(&model), normal(&again), "nodal NORMAL");
    assert_eq!(model.condition_normals(), again.condition_normals());
}

#[test]
fn the_weighted_gap_computed_by_the_mapping_is_the_weighted_gap_of_the_pairs() {
    // Curved plates: the mapping's nodal normals (mean normals) differ from the weighted
    // gap's (Kratos' unit normals); flat plates: they are the same bits, and the mapping
    // takes its own Gauss points and operators. A static step computes the weighted gap of
    // every kept pair in the mapping from the mapping's segmentation; here it is computed
    // again on its own, pair by pair in the step's pair order (slave id, master id), and
    // must agree bit for bit.
    for curved in [true, false] {
        weighted_gap_of_the_pairs(curved);
    }
}

fn weighted_gap_of_the_pairs(curved: bool) {
    let (model, result) = plates_step(curved);
    let index = |id: u32| ConditionIdx(model.conditions().index_of(id).unwrap() as u32);
    let paired: Vec<(ConditionIdx, ConditionIdx)> = pairs(&result)
        .iter()
        .flat_map(|(s, masters)| masters.iter().map(|m| (index(*s), index(*m))))
        .collect();
    assert!(paired.len() > 10);
    let sub = model.find_part("Contact.ContactSub0").unwrap();
    let threshold = model.process_info().number("DISTANCE_THRESHOLD").unwrap();
    let mut again = model.clone();
    let isolated = csm_activation::compute_weighted_gap(
        &mut again,
        sub,
        &paired,
        (csm_activation::MortarMode::Kratos, threshold),
        3,
        None,
    )
    .unwrap();
    assert!(isolated.iter().any(|i| !i));
    let wg = |m: &ModelPart| {
        m.nodal_data()
            .scalar(csm_model::ScalarVar::WeightedGap, 0)
            .unwrap()
            .to_vec()
    };
    let (stepped, recomputed) = (wg(&model), wg(&again));
    assert!(stepped.iter().any(|g| *g != 0.0), "curved: {curved}");
    let bits = |v: &[f64]| v.iter().map(|g| g.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&stepped), bits(&recomputed), "curved: {curved}");
}

/// The pruned entries of a result, grouped by slave, are what inserting them one by one and
/// sorting each slave's masters gives, in any input order and with repeated entries.
#[test]
fn pruned_entries_group_by_slave_with_ascending_masters() {
    let entries = [(7, 3), (2, 9), (7, 1), (2, 9), (5, 4), (2, 1), (7, 2)];
    let mut naive: std::collections::BTreeMap<u32, Vec<u32>> = Default::default();
    for &(s, m) in &entries {
        naive.entry(s).or_default().push(m);
    }
    for masters in naive.values_mut() {
        masters.sort_unstable();
    }
    assert_eq!(super::by_slave(&entries), naive);
    let mut reversed = entries;
    reversed.reverse();
    assert_eq!(super::by_slave(&reversed), naive);
    assert_eq!(naive[&2], [1, 9, 9]);
    assert!(super::by_slave(&[]).is_empty());
    // Many entries, in order (as the mapping reports them) and shuffled, on pools of 1–3
    // threads.
    let many: Vec<(u32, u32)> = (0..50_000u32)
        .map(|k| ((k / 3) * 7 % 10_007, (k * 31) % 97))
        .collect();
    let mut naive: std::collections::BTreeMap<u32, Vec<u32>> = Default::default();
    for &(s, m) in &many {
        naive.entry(s).or_default().push(m);
    }
    for masters in naive.values_mut() {
        masters.sort_unstable();
    }
    let mut in_order = many.clone();
    in_order.sort_unstable();
    for threads in [1, 2, 3] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        for list in [&many, &in_order] {
            assert_eq!(pool.install(|| super::by_slave(list)), naive, "{threads}");
        }
    }
}

/// A refitted kd-tree whose queries reach the result cap is rebuilt from the masters in id
/// order, so every step finds what a step with a freshly built tree finds (and without the
/// cap the refitted tree finds the same pairs).
#[test]
fn a_capped_refitted_tree_gives_the_rebuilt_trees_pairs() {
    for cap in [2, 1000] {
        let steps = |refit: bool| {
            let mut model = plates(6, 0.01, false);
            let s = setup(
                &format!(r#"{{"max_number_results": {cap}, "search_factor": 6.0}}"#),
                &format!(
                    r#", "refit_tree": {refit}, "steps": [
                    {{"delta_time": 1, "move": {{"Slave": {{"translate": [0.01, 0, -0.002]}}}}}},
                    {{"delta_time": 1, "move": {{"Slave": {{"translate": [0.02, 0.01, -0.002]}}}}}}]"#
                ),
            );
            let mut search = ContactSearch::initialize(&mut model, &s).unwrap();
            let mut all = Vec::new();
            for step in &s.steps {
                search.advance(&mut model, step).unwrap();
                let r = search.step(&mut model).unwrap();
                all.push(r.pairs.clone());
                search.finalize_step(&mut model).unwrap();
            }
            all
        };
        let (refitted, rebuilt) = (steps(true), steps(false));
        assert!(refitted.iter().all(|p| !p["0"].is_empty()), "cap {cap}");
        assert_eq!(refitted, rebuilt, "cap {cap}");
    }
}
