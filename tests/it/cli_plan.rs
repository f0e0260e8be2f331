//! `csm plan`: the plan of a 2D static scene against a 3D dynamic one, the text (snapshots)
//! and JSON forms, and errors in `csm search`'s format.

use std::path::{Path, PathBuf};

use serde_json::Value;

use crate::{csm, repo_mesh};

const SETUP_2D_STATIC: &str = r#"{
    "contact_model_part": {"0": ["Parts_Slave", "Parts_Master"]},
    "assume_master_slave": {"0": ["Parts_Slave"]},
    "search_parameters": {"type_search": "in_radius_with_obb", "simple_search": true}
}"#;

const SETUP_3D_DYNAMIC: &str = r#"{
    "contact_model_part": {"0": ["Parts_Slave", "Parts_Master"]},
    "assume_master_slave": {"0": ["Parts_Slave"]},
    "search_parameters": {"type_search": "octree_with_obb", "dynamic_search": true,
                          "static_check_movement": true}
}"#;

fn write(name: &str, text: &str) -> PathBuf {
    crate::write_scratch(name, text)
}

/// The sphere-on-plate scene with a VELOCITY of −0.01 along z on every node of `Parts_Slave`
/// (the scene file itself has no velocities).
fn sphere_with_velocities() -> PathBuf {
    let text = std::fs::read_to_string(repo_mesh("scenes/sphere_on_plate_tri.mdpa")).unwrap();
    let slave = text
        .split("Begin SubModelPart Parts_Slave")
        .nth(1)
        .and_then(|rest| rest.split("Begin SubModelPartNodes").nth(1))
        .and_then(|rest| rest.split("End SubModelPartNodes").next())
        .expect("the slave part lists its nodes");
    let mut block = String::from("Begin NodalData VELOCITY\n");
    for id in slave.split_whitespace() {
        block += &format!(" {id} 0 [3] (0.0, 0.0, -0.01)\n");
    }
    block += "End NodalData\n";
    write("sphere_with_velocities.mdpa", &(text + &block))
}

#[track_caller]
fn plan(mesh: &Path, setup: &Path, json: bool) -> String {
    let mut args = vec![
        "plan",
        mesh.to_str().unwrap(),
        "--setup",
        setup.to_str().unwrap(),
    ];
    if json {
        args.push("--json");
    }
    let out = csm(&args);
    assert!(
        out.status.success(),
        "csm plan failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

fn plan_json(mesh: &Path, setup: &Path) -> Value {
    serde_json::from_str(&plan(mesh, setup, true)).expect("csm plan --json prints JSON")
}

/// `(used, what or why)` of the item `id` of a JSON section.
#[track_caller]
fn item(section: &Value, id: &str) -> (bool, String) {
    let i = section
        .as_array()
        .unwrap()
        .iter()
        .find(|i| i["id"] == id)
        .unwrap_or_else(|| panic!("no item {id} in {section}"));
    let text = i.get("what").or_else(|| i.get("why")).unwrap();
    (i["used"] == true, text.as_str().unwrap().to_owned())
}

/// The issue's check: a 2D static scene (kd-tree, Simple activation) against a 3D dynamic one
/// (octree, Advanced activation with static_check_movement, velocities on the slave side).
#[test]
fn plan_of_a_2d_static_scene_against_a_3d_dynamic_one() {
    let p2 = plan_json(
        &repo_mesh("scenes/cylinder_on_block_2d.mdpa"),
        &write("plan_2d_static.json", SETUP_2D_STATIC),
    );
    let p3 = plan_json(
        &sphere_with_velocities(),
        &write("plan_3d_dynamic.json", SETUP_3D_DYNAMIC),
    );
    assert_eq!(p2["format"], "csm-plan/1");
    assert_eq!(
        (p2["domain_size"].as_u64(), p3["domain_size"].as_u64()),
        (Some(2), Some(3))
    );
    let (s2, s3) = (&p2["pairs"]["0"]["stages"], &p3["pairs"]["0"]["stages"]);

    // Dynamic search: the step jump runs only in 3D, where the slave side moves.
    assert_eq!(
        item(s2, "step_jump"),
        (false, "skipped — dynamic_search false".to_owned())
    );
    let (used, what) = item(s3, "step_jump");
    assert!(used && what.contains("moving nodes"), "{what}");
    let (v2, v3) = (&p2["variables"], &p3["variables"]);
    assert_eq!(
        item(v2, "VELOCITY"),
        (
            false,
            "not allocated — no pair has dynamic_search".to_owned()
        )
    );
    assert_eq!(
        item(v3, "VELOCITY"),
        (true, "as read from the mesh".to_owned())
    );
    assert!(!item(v2, "ACCELERATION").0 && item(v3, "ACCELERATION").0);

    // Trees: each scene builds only the one its type_search uses.
    assert!(item(s2, "kd_tree").0 && item(s3, "octree").0);
    assert_eq!(
        item(s2, "octree"),
        (
            false,
            "not built — type_search in_radius_with_obb".to_owned()
        )
    );
    assert_eq!(
        item(s3, "kd_tree"),
        (false, "not built — type_search octree_with_obb".to_owned())
    );

    // Activation: Simple needs no weighted gap; Advanced with static_check_movement needs it
    // with its history.
    let (used, why) = item(s2, "weighted_gap");
    assert!(!used && why.contains("simple_search true"), "{why}");
    assert!(item(s3, "weighted_gap").0);
    assert!(!item(v2, "WEIGHTED_GAP").0);
    assert!(
        item(v3, "WEIGHTED_GAP")
            .1
            .starts_with("current and previous step")
    );

    // Both scenes have solid elements (2D triangles and quadrilaterals, 3D tetrahedra), so
    // both run the normal check; neither needs DISPLACEMENT or the Lagrange multipliers.
    for p in [&p2, &p3] {
        assert!(item(&p["initialize"], "normal_check").0);
        assert!(!item(&p["variables"], "DISPLACEMENT").0);
        assert!(!item(&p["variables"], "LAGRANGE_MULTIPLIER_CONTACT_PRESSURE").0);
        assert!(
            item(&p["variables"], "NORMAL")
                .1
                .starts_with("current step only")
        );
    }
}

/// The same 3D dynamic setup on the scene as committed (no velocities): the step jump is
/// planned out, because the predicted increment is zero on every node.
#[test]
fn a_dynamic_search_without_velocities_plans_no_step_jump() {
    let p = plan_json(
        &repo_mesh("scenes/sphere_on_plate_tri.mdpa"),
        &write("plan_3d_dynamic_still.json", SETUP_3D_DYNAMIC),
    );
    let (used, why) = item(&p["pairs"]["0"]["stages"], "step_jump");
    assert!(!used && why.starts_with("skipped — no velocities"), "{why}");
    // VELOCITY is still allocated: a library user may set it between steps.
    assert!(item(&p["variables"], "VELOCITY").0);
}

#[test]
fn plan_text_snapshots() {
    let text_2d = plan(
        &repo_mesh("scenes/cylinder_on_block_2d.mdpa"),
        &write("plan_2d_static_text.json", SETUP_2D_STATIC),
        false,
    );
    insta::assert_snapshot!("plan_2d_static", text_2d);
    let text_3d = plan(
        &sphere_with_velocities(),
        &write("plan_3d_dynamic_text.json", SETUP_3D_DYNAMIC),
        false,
    );
    insta::assert_snapshot!("plan_3d_dynamic", text_3d);
}

/// Errors come in `csm search`'s format, pointing at the setup's line.
#[test]
fn plan_errors_name_the_file_and_line() {
    let setup = write(
        "plan_bad_part.json",
        "{\n  \"contact_model_part\": {\"0\": [\"Parts_Slave\", \"Nowhere\"]}\n}\n",
    );
    let mesh = repo_mesh("scenes/cylinder_on_block_2d.mdpa");
    let out = csm(&[
        "plan",
        mesh.to_str().unwrap(),
        "--setup",
        setup.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(
        stderr.starts_with(&format!("error: {}:2: ", setup.display())),
        "{stderr}"
    );
    assert!(stderr.contains("\"Nowhere\""), "{stderr}");
    let search = csm(&[
        "search",
        mesh.to_str().unwrap(),
        "--setup",
        setup.to_str().unwrap(),
    ]);
    assert_eq!(
        String::from_utf8_lossy(&search.stderr),
        stderr,
        "same error"
    );
    // A mesh error too.
    let bad = write("plan_bad.mdpa", "Begin Nodes\n 1 0.0 0.0\nEnd Nodes\n");
    let out = csm(&["plan", bad.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.starts_with(&format!("error: {}:", bad.display())),
        "{stderr}"
    );
}
