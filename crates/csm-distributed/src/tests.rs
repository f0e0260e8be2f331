use std::path::PathBuf;

use csm_model::ModelPart;
use std::sync::Arc;

use csm_search::{ContactSearch, PairGlobals, SearchResult, SearchSetup, parse_setup};

use super::*;

/// The scenes with parts `Parts_Slave` and `Parts_Master` (3D and 2D, triangles and
/// quadrilaterals, mortar-heavy and per face).
const SCENES: [&str; 5] = [
    "stacked_blocks.mdpa",
    "stacked_blocks_rotated.mdpa",
    "sphere_on_plate_tri.mdpa",
    "cylinder_on_plate_quads.mdpa",
    "cylinder_on_block_2d.mdpa",
];

fn scene(name: &str) -> MeshArrays {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/data/scenes")
        .join(name);
    csm_io::read_mesh(&path)
        .expect("the scene reads")
        .to_arrays()
}

/// The whole problem's values of each pair (`ContactSearch::globals`).
type Globals = BTreeMap<u32, PairGlobals>;

/// A search with the CLI's default setup for the parts `Parts_Slave` and `Parts_Master`, the
/// Simple or the Advanced activation and the search type `type_search`; with `globals`, those
/// of the whole problem. Returns the result and the values the search used.
fn search(
    mesh: &MeshArrays,
    (simple, type_search): (bool, &str),
    globals: Option<&Globals>,
) -> (SearchResult, Globals) {
    let setup = test_setup(simple, type_search, "kratos");
    let mut model = ModelPart::from_arrays("Structure", mesh).expect("the arrays make a model");
    let mut search = ContactSearch::initialize(&mut model, &setup).expect("initialize");
    if let Some(globals) = globals {
        search.set_globals(globals);
    }
    let result = search.step(&mut model).expect("search");
    (result, search.globals())
}

/// `search_parameters` for DirectCheck ([`setup_with`]).
const DIRECT_CHECK: &str = r#", "check_gap": "direct_check""#;

/// The CLI's default setup for the parts `Parts_Slave` and `Parts_Master` with the Simple or
/// the Advanced activation, the search type `type_search` and the compatibility mode.
fn test_setup(simple: bool, type_search: &str, compatibility: &str) -> SearchSetup {
    setup_with(simple, type_search, compatibility, "")
}

/// [`test_setup`] with more `search_parameters` (`more`: `, "key": value` pairs).
fn setup_with(simple: bool, type_search: &str, compatibility: &str, more: &str) -> SearchSetup {
    let text = format!(
        r#"{{"contact_model_part": {{"0": ["Parts_Slave", "Parts_Master"]}},
            "assume_master_slave": {{"0": ["Parts_Slave"]}},
            "compatibility": "{compatibility}",
            "search_parameters": {{"simple_search": {simple},
                                   "type_search": "{type_search}"{more}}}}}"#
    );
    parse_setup(&text, "<test setup>").expect("the setup parses")
}

/// `search_rank` on `ranks` threads, each with a pool of its own: rank 0's result (the other
/// ranks return none), or the error every rank returned (all the same).
fn on_threads(
    ranks: usize,
    mesh: &MeshArrays,
    setup: &SearchSetup,
) -> Result<SearchResult, RunError> {
    let inputs = vec![(mesh, setup); ranks];
    on_threads_each(&inputs)
}

/// `run(transport, rank)` on `ranks` ranks, each a thread with a pool of its own (a rank
/// blocked in an exchange blocks no other rank's work); the outcomes in rank order.
fn on_rank_threads<T: Send>(
    ranks: usize,
    run: impl Fn(Arc<dyn csm_model::Transport>, usize) -> T + Sync,
) -> Vec<T> {
    std::thread::scope(|scope| {
        let handles: Vec<_> = (thread_ranks(ranks).into_iter().enumerate())
            .map(|(rank, transport)| {
                let run = &run;
                scope.spawn(move || {
                    let pool = rayon::ThreadPoolBuilder::new()
                        .num_threads(1)
                        .build()
                        .expect("a pool");
                    pool.install(|| run(Arc::new(transport), rank))
                })
            })
            .collect();
        (handles.into_iter())
            .map(|h| h.join().expect("no rank panics"))
            .collect()
    })
}

/// [`on_threads`] where each rank has its own mesh and setup (`inputs[rank]`).
fn on_threads_each(inputs: &[(&MeshArrays, &SearchSetup)]) -> Result<SearchResult, RunError> {
    let ranks = inputs.len();
    let outcomes = on_rank_threads(ranks, |transport, rank| {
        let (mesh, setup) = inputs[rank];
        search_rank(transport, mesh, setup)
    });
    let mut results = Vec::new();
    let mut errors = Vec::new();
    for (rank, outcome) in outcomes.into_iter().enumerate() {
        match outcome {
            Ok(Some(r)) => results.push((rank, r)),
            Ok(None) => {}
            Err(e) => errors.push(e),
        }
    }
    if let Some(first) = errors.first() {
        assert_eq!(errors.len(), ranks, "every rank fails: {errors:?}");
        assert!(errors.iter().all(|e| e == first), "{errors:?}");
        return Err(first.clone());
    }
    assert_eq!(results.len(), 1, "rank 0 alone returns the result");
    assert_eq!(results[0].0, 0);
    Ok(results.pop().expect("one").1)
}

/// A distributed search on 1 to 4 ranks (threads of this process) gives the result of the
/// one-process search, all of it: pairs, pruned entries, every slave node's NORMAL_GAP bit
/// for bit and ACTIVE flag, paired conditions, Kratos' condition ids and warnings, on every
/// scene, Simple and Advanced activation, with and without the OBB test, in both modes.
#[test]
fn a_distributed_search_gives_the_one_process_result() {
    for name in SCENES {
        let mesh = scene(name);
        for (simple, type_search, mode, more) in [
            (true, "in_radius_with_obb", "kratos", ""),
            (false, "in_radius_with_obb", "kratos", ""),
            (false, "in_radius", "kratos", ""),
            (false, "in_box", "kratos", ""),
            (false, "in_box_with_obb", "kratos", ""),
            (false, "in_radius_with_obb", "robust", ""),
            (true, "kdop_18", "robust", ""),
            (
                false,
                "in_radius_with_obb",
                "robust",
                r#", "check_gap": "direct_check""#,
            ),
            (true, "in_box", "kratos", r#", "check_gap": "no_check""#),
            (true, "in_radius", "robust", r#", "check_gap": "no_check""#),
            // Kratos' DirectCheck: every rank holds every master (`Reach::every_master`).
            (false, "in_radius_with_obb", "kratos", DIRECT_CHECK),
            (true, "in_box", "kratos", DIRECT_CHECK),
            // The octree (robust mode): every master and the ranks' common root box.
            (false, "octree_with_obb", "robust", ""),
            (
                true,
                "octree_with_obb",
                "robust",
                r#", "check_gap": "no_check""#,
            ),
        ] {
            let setup = setup_with(simple, type_search, mode, more);
            let mut model = ModelPart::from_arrays("Structure", &mesh).expect("a model");
            let mut whole = ContactSearch::initialize(&mut model, &setup).expect("initialize");
            let serial = whole.step(&mut model).expect("search");
            for ranks in 1..=4 {
                let got = on_threads(ranks, &mesh, &setup).expect("the distributed search");
                let what =
                    format!("{name}, simple {simple}, {type_search}{more}, {mode}, {ranks} ranks");
                let differ: Vec<_> = (got.pairs["0"].iter())
                    .filter(|(id, m)| serial.pairs["0"].get(id) != Some(m))
                    .map(|(id, m)| (id, m, serial.pairs["0"].get(id)))
                    .collect();
                assert!(differ.is_empty(), "{what}: pairs (got, serial) {differ:?}");
                assert_eq!(got.pairs, serial.pairs, "{what}: pairs");
                assert_eq!(got.pruned, serial.pruned, "{what}: pruned");
                let bits = |r: &SearchResult| -> Vec<(u32, Option<u64>, bool)> {
                    (r.nodes.iter())
                        .map(|(id, n)| (*id, n.normal_gap.map(f64::to_bits), n.active))
                        .collect()
                };
                let (a, b) = (bits(&got), bits(&serial));
                let differ: Vec<_> = a.iter().zip(&b).filter(|(x, y)| x != y).collect();
                assert!(
                    differ.is_empty() && a.len() == b.len(),
                    "{what}: nodes {differ:?}"
                );
                assert_eq!(got.paired_conditions, serial.paired_conditions, "{what}");
                assert_eq!(
                    got.kratos_condition_ids, serial.kratos_condition_ids,
                    "{what}"
                );
                assert_eq!(got.warnings, serial.warnings, "{what}: warnings");
                assert_eq!(got, serial, "{what}: the rest");
            }
        }
    }
}

/// Robust mode's octree on ranks, with the plate as the slave side (each rank's slaves cover
/// a piece of it only): the one-process result on 2 to 4 ranks. (Its pairs are those whose
/// boxes meet, whatever the leaves; the ranks still build the one-process octree, with
/// every master and the common root box, so that the candidates come in its order too.)
#[test]
fn robust_octree_on_ranks_gives_the_one_process_result() {
    let mesh = scene("sphere_on_plate_tri.mdpa");
    for more in ["", r#", "check_gap": "no_check""#] {
        let text = format!(
            r#"{{"contact_model_part": {{"0": ["Parts_Slave", "Parts_Master"]}},
                "assume_master_slave": {{"0": ["Parts_Master"]}},
                "compatibility": "robust",
                "search_parameters": {{"type_search": "octree_with_obb"{more}}}}}"#
        );
        let setup = parse_setup(&text, "<test setup>").expect("the setup parses");
        let mut model = ModelPart::from_arrays("Structure", &mesh).expect("a model");
        let serial = (ContactSearch::initialize(&mut model, &setup))
            .and_then(|mut s| s.step(&mut model))
            .expect("the one-process search");
        assert!(
            !serial.pairs["0"].values().all(Vec::is_empty),
            "pairs found"
        );
        for ranks in 2..=4 {
            let got = on_threads(ranks, &mesh, &setup).expect("the distributed search");
            assert_eq!(got, serial, "{ranks} ranks{more}");
        }
    }
}

/// Contact parts that list nodes only: the search generates their interface conditions from
/// the elements (stage 1). A distributed run generates them on the whole mesh before the
/// split (the ids, properties and roles of the one-process run) and gives the one-process
/// result, in both modes (kratos mode renumbers every condition first), with a degenerate
/// load condition far from the contact (the normal check stops there, on every rank).
#[test]
fn interfaces_generated_from_the_elements_give_the_one_process_result() {
    let cases = [
        ("stacked_blocks.mdpa", false),
        ("sphere_on_plate_tri.mdpa", false),
        ("stacked_blocks.mdpa", true),
    ];
    for (name, kept) in cases {
        // The scene without its contact conditions: the parts keep their nodes. `kept`: the
        // conditions stay in the mesh, in no part, their ids shifted by their count, so that
        // kratos mode renumbers them 1..N and gives the generated ones the ids they had; and
        // the slave part is the upper block's (its elements and nodes).
        let mut mesh = scene(name);
        let count: usize = mesh.conditions.values().map(|c| c.ids.len()).sum();
        if kept {
            for c in mesh.conditions.values_mut() {
                for id in &mut c.ids {
                    *id += count as u32;
                }
            }
        } else {
            mesh.conditions.clear();
        }
        for part in mesh.parts.values_mut() {
            part.conditions.clear();
        }
        for mode in ["kratos", "robust"] {
            let mut setup = test_setup(false, "in_radius_with_obb", mode);
            if kept {
                // The slave role from the upper block's part (as Kratos' patch tests do): the
                // generated slave conditions are in no slave part.
                setup.pairs.get_mut(&0).expect("pair 0").slaves = vec!["Parts_Upper".to_owned()];
            }
            let mut model = ModelPart::from_arrays("Structure", &mesh).expect("a model");
            let serial = (ContactSearch::initialize(&mut model, &setup))
                .and_then(|mut s| s.step(&mut model))
                .expect("the one-process search");
            assert!(serial.n_pairs() > 0, "{name}: pairs found");
            for ranks in 1..=3 {
                let got = on_threads(ranks, &mesh, &setup).expect("the distributed search");
                assert_eq!(got, serial, "{name} (kept {kept}), {mode}, {ranks} ranks");
            }
        }
    }
    // Roles decided automatically: the generated conditions are all MASTER (no node is
    // SLAVE), the ranks give them that role and hold the whole contact area.
    for name in ["stacked_blocks.mdpa", "sphere_on_plate_tri.mdpa"] {
        let mut mesh = scene(name);
        mesh.conditions.clear();
        for part in mesh.parts.values_mut() {
            part.conditions.clear();
        }
        for mode in ["kratos", "robust"] {
            let text = format!(
                r#"{{"contact_model_part": {{"0": ["Parts_Slave", "Parts_Master"]}},
                    "compatibility": "{mode}"}}"#
            );
            let setup = parse_setup(&text, "<setup>").expect("parses");
            let mut model = ModelPart::from_arrays("Structure", &mesh).expect("a model");
            let serial = (ContactSearch::initialize(&mut model, &setup))
                .and_then(|mut s| s.step(&mut model))
                .expect("the one-process search");
            assert!(serial.n_pairs() > 0, "{name}, automatic roles: pairs found");
            for ranks in 1..=3 {
                let got = on_threads(ranks, &mesh, &setup).expect("the distributed search");
                assert_eq!(
                    got, serial,
                    "{name}, automatic roles, {mode}, {ranks} ranks"
                );
            }
        }
    }
    // A load condition with every node at one point, on no contact part: the one-process
    // normal check stops at it, and so does every rank.
    let mut mesh = scene("stacked_blocks.mdpa");
    let node = mesh.node_ids[0];
    let loads = (mesh
        .conditions
        .entry(csm_geometry::GeometryKind::Triangle3D3))
    .or_default();
    loads.ids.push(999_999);
    loads.connectivity.extend([node; 3]);
    loads.properties.push(0);
    let setup = test_setup(false, "in_radius_with_obb", "kratos");
    let mut model = ModelPart::from_arrays("Structure", &mesh).expect("a model");
    let serial = (ContactSearch::initialize(&mut model, &setup))
        .and_then(|mut s| s.step(&mut model))
        .expect_err("a degenerate condition")
        .to_string();
    assert!(serial.contains("999999"), "{serial}");
    for ranks in 1..=3 {
        let got = on_threads(ranks, &mesh, &setup).expect_err("the same error");
        assert!(got.0.ends_with(&serial), "{ranks} ranks: {got} / {serial}");
    }
}

#[test]
fn rcb_halves_along_the_longest_side_and_ignores_the_input_order() {
    // A 8 × 2 row of points: two ranks cut it across its long side (x).
    let points: Vec<([f64; 3], u32)> = (0..16)
        .map(|i| ([f64::from(i % 8), f64::from(i / 8), 0.0], i as u32))
        .collect();
    let two = rcb(&points, 2);
    for (p, r) in points.iter().zip(&two) {
        assert_eq!(*r, u32::from(p.0[0] >= 4.0), "{p:?}");
    }
    // Three ranks: 5, 5 and 6 points (the first cut gives one rank a third).
    let three = rcb(&points, 3);
    let count = |r: u32| three.iter().filter(|&&o| o == r).count();
    assert_eq!((count(0), count(1), count(2)), (5, 5, 6));
    // Reversed input, the same owner per key; ties (equal x) broken by key.
    let reversed: Vec<_> = points.iter().rev().copied().collect();
    let again = rcb(&reversed, 3);
    for (k, p) in reversed.iter().enumerate() {
        assert_eq!(again[k], three[p.1 as usize], "key {}", p.1);
    }
    assert_eq!(rcb(&points, 1), vec![0; 16]);
}

#[test]
fn bad_splits_are_refused() {
    let mesh = scene("stacked_blocks.mdpa");
    let reach = Reach::for_search_factor(3.5);
    let slaves = (&["Parts_Slave"][..], &["Parts_Slave", "Parts_Master"][..]);
    assert_eq!(
        split(&mesh, slaves, 0, reach).unwrap_err(),
        SplitError::NoRanks
    );
    let err = split(&mesh, (&["Nope"], &["Parts_Master"]), 2, reach).unwrap_err();
    assert_eq!(err, SplitError::UnknownPart("Nope".to_owned()));
    assert_eq!(err.to_string(), "split: no part `Nope` in the mesh");
}

/// Every rank's part, searched alone with the whole problem's values given
/// (`set_globals`: the largest and the mean NODAL_H, taken from the search of the whole mesh)
/// and no other rank to share with, gives its owned slave conditions the pairs of the search
/// of the whole mesh, and every slave condition and slave node is owned once: for 1 to 4 ranks
/// on every scene, Simple and Advanced activation, with and without the OBB test. On one rank
/// the owned nodes' NORMAL_GAP and ACTIVE are the whole search's, bit for bit (the halo holds
/// what they read); on more, the mapper's iterations need the other ranks
/// ([`a_distributed_search_gives_the_one_process_result`]).
#[test]
fn every_rank_finds_the_pairs_of_the_whole_search() {
    for name in SCENES {
        let mesh = scene(name);
        for (simple, type_search) in [
            (true, "in_radius_with_obb"),
            (false, "in_radius_with_obb"),
            (false, "in_radius"),
        ] {
            let (whole, globals) = search(&mesh, (simple, type_search), None);
            let pairs = &whole.pairs["0"];
            for ranks in 1..=4 {
                let parts = split(
                    &mesh,
                    (&["Parts_Slave"], &["Parts_Slave", "Parts_Master"]),
                    ranks,
                    Reach::for_search_factor(3.5),
                )
                .unwrap();
                let mut owned_conditions: Vec<u32> = Vec::new();
                let mut owned_nodes: Vec<u32> = Vec::new();
                for part in &parts {
                    let (local, _) = search(&part.mesh, (simple, type_search), Some(&globals));
                    for id in &part.owned_conditions {
                        assert_eq!(
                            local.pairs["0"].get(id),
                            pairs.get(id),
                            "{name}, simple {simple}, {type_search}, {ranks} ranks: slave {id}"
                        );
                    }
                    // One rank holds every slave node and so sums what the whole search
                    // sums: the same bits.
                    for id in part.owned_nodes.iter().filter(|_| ranks == 1) {
                        let (a, b) = (&local.nodes[id], &whole.nodes[id]);
                        let same = a.active == b.active
                            && a.normal_gap.map(f64::to_bits) == b.normal_gap.map(f64::to_bits);
                        assert!(same, "{name}, one rank: node {id}: {a:?} against {b:?}");
                    }
                    owned_conditions.extend(&part.owned_conditions);
                    owned_nodes.extend(&part.owned_nodes);
                }
                owned_conditions.sort_unstable();
                owned_nodes.sort_unstable();
                let all: Vec<u32> = pairs.keys().copied().collect();
                assert_eq!(owned_conditions, all, "{name}: every slave owned once");
                let slave_nodes: Vec<u32> = whole.nodes.keys().copied().collect();
                assert_eq!(
                    owned_nodes, slave_nodes,
                    "{name}: every slave node owned once"
                );
            }
        }
    }
}

/// A rank that fails stops every rank with the same message, that of the lowest failed rank,
/// whether it fails before the others start to share values (a part name its setup does not
/// find) or while they wait for it (a NaN coordinate on a slave node it owns): no rank hangs.
#[test]
fn one_rank_failing_stops_every_rank_with_its_message() {
    let mesh = scene("stacked_blocks.mdpa");
    let setup = test_setup(false, "in_radius_with_obb", "kratos");
    let text = r#"{"contact_model_part": {"0": ["Parts_Nope", "Parts_Master"]},
                  "assume_master_slave": {"0": ["Parts_Nope"]}}"#;
    let bad_setup = parse_setup(text, "<bad setup>").expect("parses");
    let err = on_threads_each(&[(&mesh, &setup), (&mesh, &bad_setup), (&mesh, &setup)])
        .expect_err("rank 1 fails");
    assert_eq!(
        err.0,
        "rank 1 of 3: split: no part `Parts_Nope` in the mesh"
    );
    // A slave node of rank 2's part, NaN on rank 2 alone: the others are in the search.
    let parts = split(
        &mesh,
        (&["Parts_Slave"], &["Parts_Slave", "Parts_Master"]),
        3,
        Reach::for_search_factor(3.5),
    )
    .unwrap();
    let node = parts[2].owned_nodes[0];
    let mut broken = mesh.clone();
    let at = broken.node_ids.iter().position(|&n| n == node).unwrap();
    broken.points[at][2] = f64::NAN;
    let err = on_threads_each(&[(&mesh, &setup), (&mesh, &setup), (&broken, &setup)])
        .expect_err("rank 2 fails");
    assert!(err.0.starts_with("rank 2 of 3: "), "{err}");
    // Both fail: the lower rank's message.
    let err = on_threads_each(&[(&mesh, &setup), (&broken, &setup), (&mesh, &bad_setup)])
        .expect_err("ranks 1 and 2 fail");
    assert!(err.0.starts_with("rank 1 of 3: "), "{err}");
}

/// A setup without a contact pair is refused, on every rank.
#[test]
fn a_setup_without_pairs_is_refused() {
    let mesh = scene("stacked_blocks.mdpa");
    let mut none = test_setup(false, "in_radius", "robust");
    none.pairs.clear();
    let err = on_threads(2, &mesh, &none).expect_err("refused");
    assert_eq!(
        err.0,
        "rank 0 of 2: a distributed run does not support a setup without contact pairs yet"
    );
}

/// The one-process search of `mesh`, its steps as `csm search` runs them, with the steps'
/// wall times zeroed (as [`without_times`]).
fn one_process_of(mesh: &MeshArrays, setup: &SearchSetup) -> Result<SearchResult, String> {
    let mut model = ModelPart::from_arrays("Structure", mesh).map_err(|e| e.to_string())?;
    let mut search = ContactSearch::initialize(&mut model, setup).map_err(|e| e.to_string())?;
    if setup.steps.is_empty() {
        return search.step(&mut model).map_err(|e| e.to_string());
    }
    (search.run_steps(&mut model, &setup.steps, |_, _, _| {}))
        .map(without_times)
        .map_err(|e| e.to_string())
}

/// `result` with its steps' wall times zeroed.
fn without_times(mut result: SearchResult) -> SearchResult {
    for step in &mut result.steps {
        step.search_s = 0.0;
    }
    result
}

/// Moving bodies (the steps fixtures of the repository's scenes), `adapt_search` and
/// `inverted_search`: every rank searches the whole mesh, and the result, step by step, is
/// the one-process result on 1 to 3 ranks.
#[test]
fn steps_adapt_search_and_inverted_search_give_the_one_process_result() {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut cases: Vec<(String, MeshArrays, SearchSetup)> = Vec::new();
    for name in [
        "cylinder_on_block_2d__simple_rolling",
        "sphere_on_plate_tri__dynamic_static_check",
        "stacked_blocks__database_step_update_2",
        "stacked_blocks__static_check_movement",
    ] {
        let path = root.join(format!("tests/fixtures/steps/{name}.json"));
        let text = std::fs::read_to_string(&path).expect("the fixture reads");
        let json: serde_json::Value = serde_json::from_str(&text).expect("the fixture parses");
        let mesh = csm_io::read_mesh(&root.join(json["mesh"].as_str().expect("a mesh")))
            .expect("the scene reads")
            .to_arrays();
        let setup = parse_setup(&json["setup"].to_string(), name).expect("the setup parses");
        assert!(!setup.steps.is_empty(), "{name}: steps");
        cases.push((name.to_owned(), mesh, setup));
    }
    let mesh = scene("stacked_blocks.mdpa");
    let mut adapt = test_setup(false, "in_radius_with_obb", "kratos");
    adapt.adapt_search = true;
    cases.push(("adapt_search".to_owned(), mesh.clone(), adapt));
    for mode in ["kratos", "robust"] {
        let mut inverted = test_setup(false, "in_radius", mode);
        for pair in inverted.pairs.values_mut() {
            pair.search.inverted_search = true;
        }
        cases.push((format!("inverted_search, {mode}"), mesh.clone(), inverted));
    }
    for (what, mesh, setup) in &cases {
        assert!(
            distributed_plan(setup).is_ok_and(|p| p.whole_area.is_some()),
            "{what}"
        );
        let serial = one_process_of(mesh, setup);
        assert!(
            serial.as_ref().is_ok_and(|r| r.n_pairs() > 0),
            "{what}: {:?}",
            serial.as_ref().err()
        );
        for ranks in 1..=3 {
            let got = on_threads(ranks, mesh, setup).map(without_times);
            match (&got, &serial) {
                (Ok(got), Ok(serial)) => assert_eq!(got, serial, "{what}, {ranks} ranks"),
                _ => panic!("{what}, {ranks} ranks: {got:?} against {serial:?}"),
            }
        }
    }
}

/// The setups whose pairs depend on a decision over the whole contact area (Kratos'
/// octree loop, roles decided automatically, several pairs): every rank searches the whole
/// mesh, owning the contact conditions of its bisection, and the result is the one-process
/// result (or its error), on 1 to 4 ranks.
#[test]
fn whole_area_setups_give_the_one_process_result() {
    let automatic = r#"{"contact_model_part": {"0": ["Parts_Slave", "Parts_Master"]}}"#;
    // A second pair searches the paired conditions the first one made too (rank 0's).
    let two_pairs = r#"{"contact_model_part": {"0": ["Parts_Slave", "Parts_Master"],
                                                "1": ["Parts_Master", "Parts_Slave"]},
                        "assume_master_slave": {"0": ["Parts_Slave"], "1": ["Parts_Master"]}}"#;
    let mut checked = 0;
    for name in [
        "stacked_blocks.mdpa",
        "sphere_on_plate_tri.mdpa",
        "cylinder_on_block_2d.mdpa",
    ] {
        let mesh = scene(name);
        let setups = [
            (
                "kratos octree",
                test_setup(false, "octree_with_obb", "kratos"),
            ),
            (
                "kratos octree, no check",
                setup_with(
                    true,
                    "octree_with_obb",
                    "kratos",
                    r#", "check_gap": "no_check""#,
                ),
            ),
            (
                "automatic roles",
                parse_setup(automatic, "<setup>").expect("parses"),
            ),
            (
                "two pairs",
                parse_setup(two_pairs, "<setup>").expect("parses"),
            ),
        ];
        for (what, setup) in setups {
            assert!(
                distributed_plan(&setup).is_ok_and(|p| p.whole_area.is_some()),
                "{what}"
            );
            let mut model = ModelPart::from_arrays("Structure", &mesh).expect("a model");
            let serial = (ContactSearch::initialize(&mut model, &setup))
                .and_then(|mut s| s.step(&mut model))
                .map_err(|e| e.to_string());
            if serial
                .as_ref()
                .is_ok_and(|r| r.pairs.values().any(|m| !m.is_empty()))
            {
                checked += 1;
            }
            for ranks in 1..=4 {
                let got = on_threads(ranks, &mesh, &setup);
                match (&got, &serial) {
                    (Ok(got), Ok(serial)) => {
                        assert_eq!(got, serial, "{name}, {what}, {ranks} ranks")
                    }
                    (Err(got), Err(serial)) => assert!(
                        got.0.ends_with(serial.as_str()),
                        "{name}, {what}, {ranks} ranks: {got} against {serial}"
                    ),
                    _ => panic!("{name}, {what}, {ranks} ranks: {got:?} against {serial:?}"),
                }
            }
        }
    }
    // Most of them find pairs (not only the same error).
    assert!(checked >= 6, "{checked} setups with pairs");
}

/// Piece `rank` of `ranks` of a mesh as a host code might hold it: the elements and the
/// conditions whose id is `rank` modulo `ranks` (scattered, the hardest case for the
/// exchange), every node they use, the parts restricted to these.
fn piece(mesh: &MeshArrays, (ranks, rank): (u32, u32)) -> MeshArrays {
    sub_mesh(mesh, |id| id % ranks == rank, |id| id % ranks == rank)
}

/// A host code's mesh already split across 1 to 4 ranks (threads), each rank passing its
/// piece: each gets the pairs of its conditions and the results of its nodes of the
/// one-process search of the whole mesh, bit for bit, with the whole run's warnings.
#[test]
fn a_partitioned_mesh_gets_the_one_process_result_of_its_pieces() {
    for name in ["sphere_on_plate_tri.mdpa", "cylinder_on_block_2d.mdpa"] {
        let mesh = scene(name);
        let setup = test_setup(false, "in_radius_with_obb", "kratos");
        let mut model = ModelPart::from_arrays("Structure", &mesh).expect("a model");
        let mut whole = ContactSearch::initialize(&mut model, &setup).expect("initialize");
        let serial = whole.step(&mut model).expect("search");
        for ranks in 1..=4u32 {
            let pieces: Vec<MeshArrays> = (0..ranks).map(|r| piece(&mesh, (ranks, r))).collect();
            let results = on_rank_threads(ranks as usize, |transport, rank| {
                search_partitioned(transport, &pieces[rank], &setup)
            });
            let mut seen_nodes = BTreeSet::new();
            for (local, got) in pieces.iter().zip(results) {
                let got = got.expect("the partitioned search");
                let what = format!("{name}, {ranks} ranks");
                for (id, masters) in &got.pairs["0"] {
                    assert_eq!(
                        Some(masters),
                        serial.pairs["0"].get(id),
                        "{what}: slave {id}"
                    );
                }
                let slaves_here = (serial.pairs["0"].keys())
                    .filter(|id| local.conditions.values().any(|a| a.ids.contains(id)))
                    .count();
                assert_eq!(
                    got.pairs["0"].len(),
                    slaves_here,
                    "{what}: every local slave"
                );
                for (id, n) in &got.nodes {
                    let s = serial.nodes[id];
                    assert_eq!(
                        n.normal_gap.map(f64::to_bits),
                        s.normal_gap.map(f64::to_bits)
                    );
                    assert_eq!(n.active, s.active, "{what}: node {id}");
                    seen_nodes.insert(*id);
                }
                assert_eq!(got.warnings, serial.warnings, "{what}");
                assert_eq!(got.paired_conditions, serial.paired_conditions, "{what}");
            }
            let all: BTreeSet<u32> = serial.nodes.keys().copied().collect();
            assert_eq!(
                seen_nodes, all,
                "{name}, {ranks} ranks: every slave node somewhere"
            );
        }
    }
}

/// Two pieces that give one node different coordinates: every rank stops with the same
/// error, which names the node.
#[test]
fn pieces_that_disagree_are_refused_on_every_rank() {
    let mesh = scene("stacked_blocks.mdpa");
    let setup = test_setup(false, "in_radius", "kratos");
    let mut b = mesh.clone();
    b.points[0][0] += 1.0;
    let node = b.node_ids[0];
    let results = on_rank_threads(2, |transport, rank| {
        search_partitioned(transport, [&mesh, &b][rank], &setup)
    });
    let errors: Vec<RunError> = results
        .into_iter()
        .map(|r| r.expect_err("refused"))
        .collect();
    assert_eq!(errors[0], errors[1]);
    assert!(
        errors[0]
            .0
            .starts_with(&format!("rank 0 of 2: node {node}: rank 1 gives")),
        "{}",
        errors[0]
    );
}

/// The collective operations between ranks (threads): a maximum and a count of every rank's
/// values; sum terms merged in ascending id order with each id once, whichever rank gave it;
/// ghost values from their owners; and ranks out of step (each in another operation) both
/// stopped with the same message instead of a wrong value or a hang.
#[test]
fn ranks_share_exactly_and_stop_together_when_out_of_step() {
    let outcomes = on_rank_threads(3, |transport, rank| {
        let ranks = csm_model::Ranks::new(transport, &[rank as u32], &[]);
        let r = rank as f64;
        let max = ranks.max(r * 2.0).unwrap();
        let count = ranks.sum_count(rank as u64 + 1).unwrap();
        // Rank k gives node ids k, k + 1 (so 1 and 2 come twice, the same values).
        let terms: Vec<(u32, [f64; 3])> = [rank as u32, rank as u32 + 1]
            .iter()
            .map(|&id| (id, [f64::from(id), 0.0, 0.0]))
            .collect();
        let merged = ranks.terms(&terms).unwrap();
        let owned = [(rank as u32, [r, r, r])];
        let ghosts = ranks.values(&owned, &[(rank as u32 + 1) % 3, 7]).unwrap();
        (max, count, merged, ghosts)
    });
    for (rank, (max, count, merged, ghosts)) in outcomes.into_iter().enumerate() {
        assert_eq!((max, count), (4.0, 6), "rank {rank}");
        let ids: Vec<u32> = merged.iter().map(|t| t.0).collect();
        assert_eq!(ids, [0, 1, 2, 3], "rank {rank}");
        assert!(merged.iter().all(|(id, v)| v[0] == f64::from(*id)));
        let next = ((rank + 1) % 3) as f64;
        assert_eq!(ghosts, [Some([next; 3]), None], "rank {rank}");
    }
    // Rank 1 asks for a count where the others ask for a maximum.
    let stopped = on_rank_threads(3, |transport, rank| {
        let ranks = csm_model::Ranks::new(transport, &[], &[]);
        let step = if rank == 1 {
            ranks.sum_count(1).map(|_| ())
        } else {
            ranks.max(1.0).map(|_| ())
        };
        step.map_err(|_| ranks.agree_on_failure(None))
    });
    for outcome in stopped {
        assert_eq!(outcome, Err("the ranks went out of step".to_owned()));
    }
}

/// The split's id lookups answer the same by table (dense ids) and by hash (sparse ids):
/// every id asked, present or not, past the largest too.
#[test]
fn id_lookups_are_the_same_dense_and_sparse() {
    let dense_ids: Vec<u32> = (1..=3000).filter(|i| i % 3 != 0).collect();
    let sparse_ids: Vec<u32> = dense_ids.iter().map(|i| i * 1000).collect();
    for ids in [&dense_ids, &sparse_ids] {
        let set = IdSet::new(ids.iter().copied());
        let dense = matches!(set, IdSet::Dense(_));
        assert_eq!(
            dense,
            ids == &dense_ids,
            "the table is taken for dense ids only"
        );
        let wanted: std::collections::HashSet<u32> = ids.iter().copied().collect();
        let largest = *ids.last().unwrap();
        for id in (0..=largest + 5).step_by(if dense { 1 } else { 500 }) {
            assert_eq!(set.contains(id), wanted.contains(&id), "id {id}");
        }
        // Condition nodes by id: one kind, two nodes each.
        let mut arrays = EntityArrays::default();
        for &id in ids.iter() {
            arrays.ids.push(id);
            arrays.connectivity.extend([id, id + 1]);
            arrays.properties.push(0);
        }
        let by_kind = BTreeMap::from([(csm_geometry::GeometryKind::Line2D2, arrays)]);
        let by_id = index(&by_kind);
        assert_eq!(matches!(by_id, ById::Dense(_)), dense);
        for id in (0..=largest + 5).step_by(if dense { 1 } else { 500 }) {
            let expected = wanted.contains(&id).then(|| vec![id, id + 1]);
            assert_eq!(by_id.get(&id).map(|n| n.to_vec()), expected, "id {id}");
        }
    }
}
