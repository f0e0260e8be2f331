//! `kratos` and `robust` compatibility side by side on the fixture scenes: where Kratos'
//! behaviour is a bug (reference §21) csm reproduces it in `kratos` mode (checked against the
//! Kratos fixtures in `kratos_search.rs`) and fixes it in `robust` mode; this snapshot pins the
//! robust results and shows how far the two modes differ.

use std::collections::BTreeSet;
use std::fmt::Write as _;
use std::path::Path;

use serde_json::Value;

const SCENES: [&str; 5] = [
    "sphere_on_plate_tri",
    "sphere_on_plate_mixed",
    "stacked_blocks",
    "stacked_blocks_pen",
    "cylinder_on_block_2d",
];

const SEARCHES: [(&str, &str); 7] = [
    ("in_radius", "no_check"),
    ("in_radius_with_obb", "no_check"),
    ("in_radius_with_obb", "direct_check"),
    ("in_box", "no_check"),
    ("in_box_with_obb", "no_check"),
    ("octree_with_obb", "no_check"),
    ("kdop_18", "no_check"),
];

fn run(scene: &str, type_search: &str, check_gap: &str, compat: &str) -> Value {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mesh = root.join(format!("tests/data/scenes/{scene}.mdpa"));
    let mut model = csm::io::read_mesh(&mesh).unwrap();
    let setup = serde_json::json!({
        "contact_model_part": {"0": ["Parts_Slave", "Parts_Master"]},
        "assume_master_slave": {"0": ["Parts_Slave"]},
        "compatibility": compat,
        "search_parameters": {"type_search": type_search, "check_gap": check_gap},
    });
    let setup = csm::cli::load_setup(&setup.to_string(), "snapshot").unwrap();
    let (result, _) = csm::cli::run_search(&mut model, &setup, 0.0).unwrap();
    result.to_json(&[])
}

fn pair_set(v: &Value) -> BTreeSet<(String, u64)> {
    let mut set = BTreeSet::new();
    for (slave, masters) in v["pairs"]["0"].as_object().unwrap() {
        for m in masters.as_array().unwrap() {
            set.insert((slave.clone(), m.as_u64().unwrap()));
        }
    }
    set
}

fn counts(v: &Value) -> String {
    let slaves = v["pairs"]["0"]
        .as_object()
        .unwrap()
        .values()
        .filter(|m| m != &&Value::Array(vec![]))
        .count();
    let active = v["nodes"]
        .as_object()
        .unwrap()
        .values()
        .filter(|n| n["active"] == true)
        .count();
    format!(
        "{slaves} slaves / {} pairs / {active} active",
        pair_set(v).len()
    )
}

#[test]
fn kratos_and_robust_modes_side_by_side() {
    let mut text = String::new();
    for scene in SCENES {
        for (type_search, check_gap) in SEARCHES {
            let kratos = run(scene, type_search, check_gap, "kratos");
            let robust = run(scene, type_search, check_gap, "robust");
            let (k, r) = (pair_set(&kratos), pair_set(&robust));
            let _ = writeln!(
                text,
                "{scene} {type_search} {check_gap}: kratos {} | robust {} | robust-only {}, kratos-only {}",
                counts(&kratos),
                counts(&robust),
                r.difference(&k).count(),
                k.difference(&r).count()
            );
        }
    }
    insta::assert_snapshot!(text);
}
