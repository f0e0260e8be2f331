//! The seed's features beyond a predefined pair of named parts: skin detection (robust mode),
//! roles decided automatically, the condition ids Kratos gives, and the warnings of several
//! pairs. The Kratos fixtures of `kratos_search` check the results against Kratos; these
//! tests check what Kratos cannot be asked (it loses the skin) and the RESULT.json fields.

use serde_json::Value;

use crate::{csm, csm_json, repo_mesh, write_scratch};

fn setup(name: &str, text: &str) -> String {
    write_scratch(name, text).display().to_string()
}

fn run(mesh: &str, setup_name: &str, setup_text: &str) -> Value {
    let mesh = repo_mesh(mesh).display().to_string();
    let setup = setup(setup_name, setup_text);
    csm_json(&[
        "search",
        &mesh,
        "--setup",
        &setup,
        "--quiet",
        "--threads",
        "2",
    ])
}

/// Robust skin detection finds exactly the faces of the elements that no other element has:
/// on Kratos' simplest patch (two separate hexahedra) they are all twelve faces, the faces
/// Kratos' own interface generation makes from a part listing every node. The two runs give
/// the same RESULT.json (pairs, flags and gaps bit for bit); the all-nodes run in kratos mode
/// is a Kratos fixture (`kratos_simplest_patch_all_nodes`).
#[test]
fn robust_skin_detection_equals_listing_every_node() {
    for search in [
        r#"{"type_search": "in_radius"}"#,
        r#"{"type_search": "in_radius_with_obb", "check_gap": "direct_check"}"#,
    ] {
        let skin = run(
            "kratos/3D_contact_simplest_patch_matching_test.mdpa",
            "skin_robust.json",
            &format!(
                r#"{{"contact_type": "Frictionless", "compatibility": "robust",
                    "search_parameters": {search}}}"#
            ),
        );
        let listed = run(
            "kratos/simplest_patch_all_nodes.mdpa",
            "skin_listed.json",
            &format!(
                r#"{{"contact_model_part": {{"0": ["All_Nodes"]}}, "contact_type": "Frictionless",
                    "compatibility": "robust", "search_parameters": {search}}}"#
            ),
        );
        for key in ["pairs", "nodes", "paired_conditions"] {
            assert_eq!(skin[key], listed[key], "{search}: {key}");
        }
        let pairs: usize = skin["pairs"]["0"]
            .as_object()
            .unwrap()
            .values()
            .map(|m| m.as_array().unwrap().len())
            .sum();
        assert!(pairs > 0, "{search}: the skin faces pair");
    }
}

/// Kratos 10.4.4 loses the skin (it goes to `Structure.ContactSub0`): kratos mode refuses
/// with Kratos' own error and says what to change.
#[test]
fn kratos_mode_refuses_skin_detection_as_kratos_does() {
    let mesh = repo_mesh("kratos/3D_contact_simplest_patch_matching_test.mdpa")
        .display()
        .to_string();
    let s = setup("skin_kratos.json", r#"{"contact_type": "Frictionless"}"#);
    let out = csm(&["search", &mesh, "--setup", &s, "--quiet"]);
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("mPointListDestination not initialized")
            && stderr.contains("\"compatibility\": \"robust\""),
        "{stderr}"
    );
}

/// Conditions 10 and 20 of the mesh are 1 and 2 for Kratos: RESULT.json keeps 10 and 20 and
/// maps them; a mesh tying process (which does not renumber) writes no map.
#[test]
fn kratos_condition_ids_map_the_file_ids() {
    let alm = run(
        "kratos/condition_ids_10_20.mdpa",
        "ids_alm.json",
        r#"{"contact_model_part": {"0": ["Parts_Slave", "Parts_Master"]},
            "assume_master_slave": {"0": ["Parts_Slave"]}, "contact_type": "Frictionless"}"#,
    );
    assert_eq!(alm["pairs"]["0"]["10"], serde_json::json!([20]));
    assert_eq!(
        alm["kratos_condition_ids"],
        serde_json::json!({"10": 1, "20": 2})
    );
    let tying = run(
        "kratos/condition_ids_10_20.mdpa",
        "ids_tying.json",
        r#"{"mesh_tying_model_part": {"0": ["Parts_Slave", "Parts_Master"]},
            "assume_master_slave": {"0": ["Parts_Slave"]}}"#,
    );
    assert_eq!(tying["pairs"]["0"]["10"], serde_json::json!([20]));
    assert!(tying.get("kratos_condition_ids").is_none(), "{tying}");
    assert!(tying.get("master_slave_constraints").is_none());
    let mpc = run(
        "kratos/condition_ids_10_20.mdpa",
        "ids_mpc.json",
        r#"{"process": "mpc_contact_process",
            "contact_model_part": {"0": ["Parts_Slave", "Parts_Master"]},
            "assume_master_slave": {"0": ["Parts_Slave"]}}"#,
    );
    assert_eq!(mpc["master_slave_constraints"], serde_json::json!(1));
    assert_eq!(mpc["kratos_condition_ids"], alm["kratos_condition_ids"]);
}

/// A setup with two pairs and a fallback in the shared search parameters warns once per pair,
/// each warning naming its pair.
#[test]
fn warnings_of_two_pairs_name_their_pair() {
    let v = run(
        "kratos/condition_ids_10_20.mdpa",
        "two_pairs.json",
        r#"{"contact_model_part": {"0": ["Parts_Slave", "Parts_Master"],
                                   "1": ["Parts_Parts_Auto1", "Parts_Parts_Auto2"]},
            "assume_master_slave": {"0": ["Parts_Slave"], "1": ["Parts_Parts_Auto2"]},
            "contact_type": "Frictionless",
            "search_parameters": {"check_gap": "gap?"}}"#,
    );
    let warnings: Vec<&str> = v["warnings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|w| w.as_str().unwrap())
        .collect();
    assert!(
        warnings.iter().any(|w| w.starts_with("pair 0: ")),
        "{warnings:?}"
    );
    assert!(
        warnings.iter().any(|w| w.starts_with("pair 1: ")),
        "{warnings:?}"
    );
}

/// Robust mode decides the roles even where Kratos refuses (contact parts with conditions of
/// their own, which Kratos leaves without MASTER flags): on the stacked blocks the self-contact
/// pairing finds the slave and master blocks of the predefined setup, and the same pairs,
/// flags and gaps.
#[test]
fn robust_automatic_roles_find_the_predefined_ones() {
    let parts = r#""contact_model_part": {"0": ["Parts_Slave", "Parts_Master"]},
                   "contact_type": "Frictionless", "compatibility": "robust""#;
    let auto = run(
        "scenes/stacked_blocks.mdpa",
        "roles_auto.json",
        &format!("{{{parts}}}"),
    );
    let predefined = run(
        "scenes/stacked_blocks.mdpa",
        "roles_predefined.json",
        &format!(r#"{{{parts}, "assume_master_slave": {{"0": ["Parts_Slave"]}}}}"#),
    );
    for key in ["pairs", "nodes", "paired_conditions"] {
        assert_eq!(auto[key], predefined[key], "{key}");
    }
    // Kratos mode refuses, as Kratos does, and says what to change.
    let mesh = repo_mesh("scenes/stacked_blocks.mdpa")
        .display()
        .to_string();
    let s = setup(
        "roles_kratos.json",
        r#"{"contact_model_part": {"0": ["Parts_Slave", "Parts_Master"]}}"#,
    );
    let out = csm(&["search", &mesh, "--setup", &s, "--quiet"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        stderr.contains("mPointListDestination not initialized")
            && stderr.contains("assume_master_slave"),
        "{stderr}"
    );
}
