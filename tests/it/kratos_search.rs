//! The search against Kratos 10.4.4 on the fixture scenes (`tests/fixtures/search/`, made by
//! `cargo xtask fixtures` through `tools/kratos_fixtures_search.py`).
//!
//! Every check_gap: pair sets, ACTIVE flags and the number of paired conditions must be
//! identical. MappingCheck also compares NORMAL_GAP per slave node (relative 1e-9; null —
//! never mapped — must match null).
//! csm runs every fixture with one and with two threads, and the two results must be
//! identical.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde_json::Value;

fn fixture_files() -> Vec<PathBuf> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/search");
    let mut files = Vec::new();
    for scene in std::fs::read_dir(&root).into_iter().flatten().flatten() {
        for f in std::fs::read_dir(scene.path())
            .into_iter()
            .flatten()
            .flatten()
        {
            // `interface.json` files hold generated interface conditions, not results.
            if f.path().extension().is_some_and(|e| e == "json")
                && f.file_name() != "interface.json"
            {
                files.push(f.path());
            }
        }
    }
    files.sort();
    files
}

type Pairs = BTreeMap<String, BTreeMap<String, Vec<u64>>>;

fn pairs_of(v: &Value) -> Pairs {
    serde_json::from_value(v["pairs"].clone()).expect("pairs object")
}

fn active_of(v: &Value) -> BTreeMap<String, bool> {
    v["nodes"]
        .as_object()
        .expect("nodes object")
        .iter()
        .map(|(k, n)| (k.clone(), n["active"].as_bool().unwrap_or(false)))
        .collect()
}

/// csm's pairs with the condition ids Kratos gives them (RESULT.json `kratos_condition_ids`:
/// Kratos' contact process numbers every condition 1..N; csm keeps the file's ids).
fn pairs_in_kratos_ids(ours: &Value) -> Pairs {
    let renumbered: BTreeMap<String, u64> = ours
        .get("kratos_condition_ids")
        .map(|v| serde_json::from_value(v.clone()).expect("kratos_condition_ids object"))
        .unwrap_or_default();
    let id = |file: u64| renumbered.get(&file.to_string()).copied().unwrap_or(file);
    pairs_of(ours)
        .into_iter()
        .map(|(key, slaves)| {
            let slaves = slaves
                .into_iter()
                .map(|(s, masters)| {
                    let s = id(s.parse().expect("condition id")).to_string();
                    let mut masters: Vec<u64> = masters.into_iter().map(id).collect();
                    masters.sort_unstable();
                    (s, masters)
                })
                .collect();
            (key, slaves)
        })
        .collect()
}

/// (Kratos pairs csm lacks, csm pairs Kratos lacks).
fn pair_difference(kratos: &Pairs, ours: &Pairs) -> (usize, usize) {
    let flat = |p: &Pairs| -> std::collections::BTreeSet<(String, String, u64)> {
        p.iter()
            .flat_map(|(k, slaves)| {
                slaves
                    .iter()
                    .flat_map(move |(s, ms)| ms.iter().map(move |m| (k.clone(), s.clone(), *m)))
            })
            .collect()
    };
    let (a, b) = (flat(kratos), flat(ours));
    (a.difference(&b).count(), b.difference(&a).count())
}

/// The first node whose NORMAL_GAP differs (relative 1e-9, absolute 1e-12 near 0; null must
/// match null), or `None`. (Node 1332 of the quadrilateral double-curvature scene differed by
/// 5.8e-4 until the dual basis followed Kratos' rule: invert `Me/‖Me‖` unless its condition
/// number is too high, whatever its determinant — `csm-geometry::mortar::dual_basis`.)
fn normal_gap_difference(kratos: &Value, ours: &Value) -> Option<String> {
    let (k, o) = (kratos["nodes"].as_object()?, ours["nodes"].as_object()?);
    if k.len() != o.len() {
        return Some(format!("{} nodes (Kratos) vs {} (csm)", k.len(), o.len()));
    }
    for (id, kn) in k {
        let (kg, og) = (&kn["normal_gap"], &o.get(id)?["normal_gap"]);
        let same = match (kg.as_f64(), og.as_f64()) {
            (None, None) => kg.is_null() && og.is_null(),
            (Some(a), Some(b)) => (a - b).abs() <= 1e-9 * a.abs().max(b.abs()) + 1e-12,
            _ => false,
        };
        if !same {
            return Some(format!("node {id}: {kg} (Kratos) vs {og} (csm)"));
        }
    }
    None
}

/// Runs csm on a fixture's mesh and setup with `threads` worker threads; `Err` carries csm's
/// message.
fn run_csm_threads(fixture: &Value, threads: usize) -> Result<Value, String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mesh = root.join(fixture["mesh"].as_str().expect("mesh path"));
    let mut model = csm::io::read_mesh(&mesh).map_err(|e| e.to_string())?;
    let setup = csm::cli::load_setup(&fixture["setup"].to_string(), "fixture setup")?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool");
    let (result, _) = pool.install(|| csm::cli::run_search(&mut model, &setup, 0.0))?;
    Ok(result.to_json(&[]))
}

/// Runs csm on a fixture with one and with two threads; the two results (timings aside) must be
/// identical, else `Err` says where they differ.
fn run_csm(fixture: &Value) -> Result<Value, String> {
    let one = run_csm_threads(fixture, 1)?;
    let two = run_csm_threads(fixture, 2)?;
    for key in ["pairs", "nodes", "paired_conditions", "warnings"] {
        if one[key] != two[key] {
            return Err(format!("`{key}` differs between 1 and 2 threads"));
        }
    }
    Ok(two)
}

fn check_gap(fixture: &Value) -> &'static str {
    let sp = &fixture["setup"]["search_parameters"]["check_gap"];
    let cpp = &fixture["setup"]["cpp_search_parameters"]["check_gap"];
    match sp.as_str().or(cpp.as_str()) {
        Some("no_check" | "NoCheck") => "no_check",
        Some("direct_check" | "DirectCheck") => "direct_check",
        _ => "mapping_check",
    }
}

/// DirectCheck fixtures of a self-contact surface, where a slave node lies exactly on a
/// vertex of the masters around it: whether Kratos counts the node depends on the last bits of
/// its local coordinates (and so on which pairs follow), which csm reproduces on most but not
/// all of them. Bounded, not exempted: a few slaves, a few flags, paired counts within 1 %.
const VERTEX_TIES: [&str; 4] = [
    "kratos_self_contact_nodes_only/auto_roles__in_radius__direct_check__advanced.json",
    "kratos_self_contact_nodes_only/auto_roles__in_radius__direct_check__simple.json",
    "kratos_self_contact_nodes_only/auto_roles__in_radius_with_obb__direct_check__advanced.json",
    "kratos_self_contact_nodes_only/auto_roles__in_radius_with_obb__direct_check__simple.json",
];

/// (slave conditions whose pair lists differ, ACTIVE flags that differ, relative difference of
/// the paired-condition counts).
fn tie_differences(kp: &Pairs, cp: &Pairs, fixture: &Value, ours: &Value) -> (usize, usize, f64) {
    let mut slaves = 0;
    for (key, k_slaves) in kp {
        let empty = BTreeMap::new();
        let c_slaves = cp.get(key).unwrap_or(&empty);
        let ids: std::collections::BTreeSet<&String> =
            k_slaves.keys().chain(c_slaves.keys()).collect();
        slaves += ids
            .into_iter()
            .filter(|s| k_slaves.get(*s) != c_slaves.get(*s))
            .count();
    }
    let (ka, ca) = (active_of(fixture), active_of(ours));
    let flags = ka
        .keys()
        .chain(ca.keys())
        .collect::<std::collections::BTreeSet<_>>()
        .into_iter()
        .filter(|n| ka.get(*n) != ca.get(*n))
        .count();
    let (a, b) = (
        fixture["paired_conditions"].as_f64().unwrap_or(0.0),
        ours["paired_conditions"].as_f64().unwrap_or(0.0),
    );
    (slaves, flags, (a - b).abs() / a.max(1.0))
}

#[test]
fn pairs_match_kratos_on_every_fixture() {
    let files = fixture_files();
    assert!(
        files.len() >= 40,
        "expected the search fixtures, found {}",
        files.len()
    );
    let mut failures = Vec::new();
    let mut summary = BTreeMap::<&str, (usize, usize)>::new();
    for file in &files {
        let name = file
            .strip_prefix(env!("CARGO_MANIFEST_DIR"))
            .unwrap_or(file)
            .display()
            .to_string();
        let fixture: Value =
            serde_json::from_str(&std::fs::read_to_string(file).unwrap()).expect("fixture JSON");
        let gap = check_gap(&fixture);
        let entry = summary.entry(gap).or_default();
        entry.0 += 1;
        let ours = run_csm(&fixture);
        if let Some(kratos_error) = fixture.get("error") {
            match ours {
                Err(_) => entry.1 += 1,
                Ok(_) => failures.push(format!(
                    "{name}: Kratos fails ({kratos_error}), csm does not"
                )),
            }
            continue;
        }
        let ours = match ours {
            Ok(v) => v,
            Err(e) => {
                failures.push(format!("{name}: csm failed: {e}"));
                continue;
            }
        };
        let (kp, cp) = (pairs_of(&fixture), pairs_in_kratos_ids(&ours));
        let ok = match gap {
            "mapping_check" => {
                let same_pairs = kp == cp;
                let same_count = fixture["paired_conditions"] == ours["paired_conditions"];
                let same_active = active_of(&fixture) == active_of(&ours);
                let gap_diff = normal_gap_difference(&fixture, &ours);
                if !same_pairs {
                    let (missing, extra) = pair_difference(&kp, &cp);
                    failures.push(format!(
                        "{name}: pair sets differ ({missing} Kratos pairs missing, {extra} extra)"
                    ));
                }
                if !same_count {
                    failures.push(format!(
                        "{name}: paired conditions {} (Kratos) vs {} (csm)",
                        fixture["paired_conditions"], ours["paired_conditions"]
                    ));
                }
                // MPCContactProcess: the constraints it made (absent for the others).
                let same_constraints =
                    fixture.get("master_slave_constraints") == ours.get("master_slave_constraints");
                if !same_constraints {
                    failures.push(format!(
                        "{name}: master-slave constraints {:?} (Kratos) vs {:?} (csm)",
                        fixture.get("master_slave_constraints"),
                        ours.get("master_slave_constraints")
                    ));
                }
                if !same_active {
                    failures.push(format!("{name}: ACTIVE flags differ"));
                }
                if let Some(d) = &gap_diff {
                    failures.push(format!("{name}: NORMAL_GAP differs: {d}"));
                }
                same_pairs && same_count && same_constraints && same_active && gap_diff.is_none()
            }
            _ if VERTEX_TIES.iter().any(|t| name.ends_with(t)) => {
                // DirectCheck on a self-contact surface: a slave node on a vertex of a
                // neighbouring master (docs/conformance.md, "DirectCheck at shared vertices").
                let (slaves, flags, count) = tie_differences(&kp, &cp, &fixture, &ours);
                let ok = slaves <= 10 && flags <= 5 && count <= 0.01;
                if !ok {
                    failures.push(format!(
                        "{name}: beyond the vertex ties: {slaves} slaves with other pairs, {flags} \
                         ACTIVE flags, paired conditions {:.2} % apart",
                        count * 100.0
                    ));
                }
                ok
            }
            _ => {
                let same_pairs = kp == cp;
                let same_active = active_of(&fixture) == active_of(&ours);
                let same_count = fixture["paired_conditions"] == ours["paired_conditions"];
                if !same_pairs {
                    failures.push(format!("{name}: pair sets differ"));
                }
                if !same_active {
                    failures.push(format!("{name}: ACTIVE flags differ"));
                }
                if !same_count {
                    failures.push(format!(
                        "{name}: paired conditions {} (Kratos) vs {} (csm)",
                        fixture["paired_conditions"], ours["paired_conditions"]
                    ));
                }
                same_pairs && same_active && same_count
            }
        };
        entry.1 += usize::from(ok);
    }
    for (gap, (n, ok)) in &summary {
        eprintln!("{gap}: {ok} of {n} fixtures conform");
    }
    assert!(
        failures.is_empty(),
        "{} non-conforming:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// csm's robust 18-DOP search loses none of the pairs that Kratos' most complete search keeps
/// (in_radius, Simple MappingCheck: DISTANCE_THRESHOLD 1e24), on every 3D and 2D fixture scene,
/// while the OBB variant (Kratos' default) does lose some on curved scenes
/// (`docs/kdop.md` has the figures).
#[test]
fn robust_kdop_keeps_every_pair_of_the_kratos_radius_search() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let scenes = [
        "sphere_on_plate_tri",
        "sphere_on_plate_mixed",
        "stacked_blocks",
        "cylinder_on_block_2d",
    ];
    for scene in scenes {
        let fixture: Value = serde_json::from_str(
            &std::fs::read_to_string(root.join(format!(
                "tests/fixtures/search/{scene}/in_radius__mapping_check__simple.json"
            )))
            .unwrap(),
        )
        .unwrap();
        let kratos = pairs_of(&fixture);
        let mut setup = fixture["setup"].clone();
        setup["search_parameters"]["type_search"] = "kdop_18".into();
        setup["compatibility"] = "robust".into();
        let mut with_kdop = fixture.clone();
        with_kdop["setup"] = setup;
        let ours = pairs_of(&run_csm(&with_kdop).unwrap());
        let (mut kept, mut total) = (0, 0);
        for (s, masters) in &kratos["0"] {
            for m in masters {
                total += 1;
                kept += usize::from(ours["0"].get(s).is_some_and(|v| v.contains(m)));
            }
        }
        assert!(total > 0, "{scene}");
        assert_eq!(
            kept,
            total,
            "{scene}: robust kdop_18 lost {} of {total} pairs",
            total - kept
        );
    }
}

/// The interface conditions the search generates from element faces (stage 1, inside
/// `ContactSearch::initialize`) equal Kratos' on its own test meshes: ids, node order and the
/// tri-state SLAVE/MASTER flags. Where Kratos fails later in its ExecuteInitialize (the
/// normal check of the patch test), csm fails too.
#[test]
fn generated_interface_conditions_match_kratos() {
    use csm::model::Flag;
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut checked = 0;
    for dir in std::fs::read_dir(root.join("tests/fixtures/search"))
        .unwrap()
        .flatten()
    {
        let path = dir.path().join("interface.json");
        let Ok(text) = std::fs::read_to_string(&path) else {
            continue;
        };
        let fixture: Value = serde_json::from_str(&text).unwrap();
        let mut model = csm::io::read_mesh(&root.join(fixture["mesh"].as_str().unwrap())).unwrap();
        let setup = csm::cli::load_setup(&fixture["setup"].to_string(), "fixture").unwrap();
        let result = csm::search::ContactSearch::initialize(&mut model, &setup);
        if fixture.get("error").is_some() {
            assert!(
                result.is_err(),
                "{}: Kratos fails, csm does not",
                path.display()
            );
            checked += 1;
            continue;
        }
        result.unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let sub = model.find_part("Contact.ContactSub0").unwrap();
        let conditions = model.conditions();
        let mut ours: Vec<Value> = model
            .part(sub)
            .conditions()
            .iter()
            .map(|c| {
                let i = c.index();
                let nodes: Vec<u32> = conditions
                    .nodes(i)
                    .iter()
                    .map(|n| model.nodes().ids()[n.index()])
                    .collect();
                let f = conditions.flags()[i];
                serde_json::json!({
                    "id": conditions.ids()[i], "nodes": nodes,
                    "slave": f.get(Flag::SLAVE), "master": f.get(Flag::MASTER),
                })
            })
            .collect();
        ours.sort_by_key(|v| v["id"].as_u64());
        assert_eq!(
            &Value::Array(ours),
            &fixture["conditions"],
            "{}",
            path.display()
        );
        checked += 1;
    }
    assert!(
        checked >= 4,
        "expected the interface fixtures of the Kratos meshes, found {checked}"
    );
}

/// The expectations of Kratos' C++ unit tests `test_search_process.cpp` (reference §20.1),
/// written out here from the test rather than read from the fixture: the INDEX_MAP of every
/// slave of the plane–cylinder strip for InRadius and for the OBB variants, and — from the
/// fixture calibration — exactly the two slave nodes 1 and 2 active, with NORMAL_GAP
/// −0.0011945660046527.
#[test]
fn plane_cylinder_unit_test_expectations() {
    let dir =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/search/plane_cylinder_cpp");
    let radius: [&[u64]; 8] = [
        &[9, 10],
        &[10, 11],
        &[11, 12],
        &[12, 13, 14],
        &[14, 15],
        &[15, 16],
        &[],
        &[],
    ];
    let obb: [&[u64]; 8] = [
        &[9, 10],
        &[10, 11],
        &[11, 12],
        &[12, 13, 14],
        &[14],
        &[],
        &[],
        &[],
    ];
    for (file, expected) in [
        ("cpp_in_radius.json", radius),
        ("cpp_in_radius_with_obb.json", obb),
        ("cpp_octree_with_obb.json", obb),
    ] {
        let fixture: Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join(file)).unwrap()).unwrap();
        let ours = run_csm(&fixture).unwrap_or_else(|e| panic!("{file}: {e}"));
        let pairs = &ours["pairs"]["0"];
        for (slave, masters) in expected.iter().enumerate() {
            let got: Vec<u64> = pairs[(slave + 1).to_string()]
                .as_array()
                .unwrap_or_else(|| panic!("{file}: slave {} missing", slave + 1))
                .iter()
                .map(|m| m.as_u64().unwrap())
                .collect();
            assert_eq!(&got, masters, "{file}: slave {}", slave + 1);
        }
        let active: Vec<(&String, f64)> = ours["nodes"]
            .as_object()
            .unwrap()
            .iter()
            .filter(|(_, n)| n["active"] == true)
            .map(|(id, n)| (id, n["normal_gap"].as_f64().unwrap()))
            .collect();
        assert_eq!(active.len(), 2, "{file}: {active:?}");
        for (id, gap) in active {
            assert!(id == "1" || id == "2", "{file}: node {id} active");
            let expected = -0.0011945660046527;
            assert!(
                (gap - expected).abs() <= 1e-9 * expected.abs(),
                "{file}: node {id}: {gap}"
            );
        }
    }
}
