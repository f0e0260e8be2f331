//! `csm info`: counts per part, JSON contract, errors.

use serde_json::Value;

use crate::{csm, kratos_mesh, repo_mesh, scratch};

fn info_json(path: &std::path::Path) -> Value {
    let out = csm(&["info", path.to_str().unwrap(), "--json"]);
    assert!(
        out.status.success(),
        "csm info {} failed: {}",
        path.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("csm info --json prints JSON")
}

#[track_caller]
fn check_error(args: &[&str], expect_in_message: &str) {
    let out = csm(args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "expected failure for {args:?}");
    assert!(!stderr.contains("panicked"), "panic for {args:?}: {stderr}");
    assert!(
        stderr.starts_with("error: "),
        "unexpected stderr for {args:?}: {stderr}"
    );
    assert!(
        stderr.contains(expect_in_message),
        "stderr for {args:?} lacks `{expect_in_message}`: {stderr}"
    );
}

#[test]
fn kratos_patch_test_counts_per_part() {
    // SOURCES.md: 256 foundation + 8 punch hexahedra, 64 SurfaceLoadCondition3D4N,
    // Contact_Part lists 18 nodes only.
    let v = info_json(&kratos_mesh("3D_contact_patch_nonmatching_test.mdpa"));
    assert_eq!(v["elements"], 264);
    assert_eq!(v["conditions"], 64);
    assert_eq!(v["parts"]["Parts_Part_foundation"]["elements"], 256);
    assert_eq!(v["parts"]["Parts_Part_punch"]["elements"], 8);
    assert_eq!(v["parts"]["SurfaceLoad3D_SurfaceLoad"]["conditions"], 64);
    assert_eq!(v["parts"]["Contact_Part"]["nodes"], 18);
    assert_eq!(v["parts"]["Contact_Part"]["elements"], 0);
    assert_eq!(v["parts"]["Contact_Part"]["conditions"], 0);
}

#[test]
fn kratos_membrane_meshes_counts_per_part() {
    let v = info_json(&kratos_mesh(
        "test_double_curvature_integration_triangle.mdpa",
    ));
    assert_eq!(v["nodes"], 1437);
    assert_eq!(v["parts"]["Parts_Parts_Auto1"]["elements"], 1280);
    assert_eq!(v["parts"]["Parts_Parts_Auto1"]["nodes"], 724);
    assert_eq!(v["parts"]["Parts_Parts_Auto2"]["elements"], 1260);
    assert_eq!(v["parts"]["DISPLACEMENT_Displacement_Auto1"]["nodes"], 330);
    // CRLF line endings.
    let v = info_json(&kratos_mesh(
        "test_double_curvature_integration_quadrilateral.mdpa",
    ));
    assert_eq!(v["nodes"], 2016);
    assert_eq!(v["parts"]["Parts_Parts_Auto1"]["elements"], 935);
    assert_eq!(v["parts"]["Parts_Parts_Auto2"]["nodes"], 997);
}

#[test]
fn info_text_snapshot() {
    let path = kratos_mesh("3D_contact_simplest_patch_matching_triquad_test.mdpa");
    let out = csm(&["info", path.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    let text = text.replace(path.to_str().unwrap(), "MESH");
    insta::assert_snapshot!(text);
}

#[test]
fn only_one_part_and_unknown_parts() {
    let path = kratos_mesh("3D_contact_simplest_patch_matching_triquad_test.mdpa");
    let p = path.to_str().unwrap();
    let out = csm(&["info", p, "--json", "--part", "Parts_Parts_Auto1"]);
    assert!(out.status.success());
    let v: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["parts"].as_object().unwrap().len(), 1);
    assert_eq!(v["parts"]["Parts_Parts_Auto1"]["elements"], 1);
    check_error(
        &["info", p, "--json", "--part", "NoSuchPart"],
        "no sub model part `NoSuchPart`",
    );
}

/// The generated boxes mesh as `.mdpa` and as `.msh` 2.2/4.1 × ASCII/binary: the four `.msh`
/// give identical JSON; the `.mdpa` (written without the unnamed curve group) gives the same
/// totals and the same counts for every part it has.
#[test]
fn same_counts_from_mdpa_and_every_msh_flavour() {
    let mdpa = info_json(&repo_mesh("boxes.mdpa"));
    assert!(mdpa["conditions"].as_u64().unwrap() > 0);
    let msh = info_json(&repo_mesh("boxes_41_ascii.msh"));
    for flavour in ["41_bin", "22_ascii", "22_bin"] {
        let v = info_json(&repo_mesh(&format!("boxes_{flavour}.msh")));
        assert_eq!(v, msh, "{flavour} differs from 4.1 ASCII");
    }
    for key in ["nodes", "elements", "conditions"] {
        assert_eq!(mdpa[key], msh[key], "{key}");
    }
    let parts = mdpa["parts"].as_object().unwrap();
    assert!(parts.len() >= 4, "{parts:?}");
    for (path, counts) in parts {
        assert_eq!(&msh["parts"][path], counts, "part {path}");
    }
}

#[test]
fn bad_files_are_clear_errors_with_a_non_zero_exit() {
    check_error(&["info", "does/not/exist.mdpa"], "does/not/exist.mdpa");
    let empty = scratch("empty.msh");
    std::fs::write(&empty, "").unwrap();
    check_error(&["info", empty.to_str().unwrap()], "empty.msh");
    let text = std::fs::read_to_string(kratos_mesh(
        "3D_contact_simplest_patch_matching_triquad_test.mdpa",
    ))
    .unwrap();
    let truncated = scratch("truncated.mdpa");
    std::fs::write(&truncated, &text[..text.len() / 2]).unwrap();
    check_error(&["info", truncated.to_str().unwrap()], "truncated.mdpa:");
    let nan = scratch("nan.mdpa");
    std::fs::write(&nan, "Begin Nodes\n1 0.0 nan 0.0\nEnd Nodes\n").unwrap();
    check_error(&["info", nan.to_str().unwrap()], "nan.mdpa:2");
    let suffix = scratch("suffix.mdpa");
    std::fs::write(
        &suffix,
        "Begin Nodes\n1 0 0 0\n2 1 0 0\nEnd Nodes\nBegin Elements MyElement\n1 0 1 2\nEnd Elements\n",
    )
    .unwrap();
    check_error(&["info", suffix.to_str().unwrap()], "suffix.mdpa:5");
    let missing = scratch("missing_node.mdpa");
    std::fs::write(
        &missing,
        "Begin Nodes\n1 0 0 0\n2 1 0 0\nEnd Nodes\nBegin Conditions LineCondition2D2N\n1 0 1 3\nEnd Conditions\n",
    )
    .unwrap();
    check_error(&["info", missing.to_str().unwrap()], "missing_node.mdpa:6");
    let duplicate = scratch("duplicate.mdpa");
    std::fs::write(&duplicate, "Begin Nodes\n1 0 0 0\n1 1 0 0\nEnd Nodes\n").unwrap();
    check_error(&["info", duplicate.to_str().unwrap()], "duplicate.mdpa:3");
    let unknown_type = scratch("unknown_type.msh");
    std::fs::write(
        &unknown_type,
        "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n2\n1 0 0 0\n2 1 0 0\n$EndNodes\n\
         $Elements\n1\n1 7 0 1 2\n$EndElements\n",
    )
    .unwrap();
    check_error(
        &["info", unknown_type.to_str().unwrap()],
        "unknown_type.msh:11",
    );
    let binary = std::fs::read(repo_mesh("boxes_41_bin.msh")).unwrap();
    let wrong_endianness = scratch("wrong_endianness.msh");
    let mut flipped = binary.clone();
    let marker = flipped.windows(4).position(|w| w == [1, 0, 0, 0]).unwrap();
    flipped[marker..marker + 4].copy_from_slice(&[0, 0, 0, 1]);
    std::fs::write(&wrong_endianness, &flipped).unwrap();
    check_error(&["info", wrong_endianness.to_str().unwrap()], "endianness");
    let truncated_binary = scratch("truncated_binary.msh");
    std::fs::write(&truncated_binary, &binary[..binary.len() * 2 / 3]).unwrap();
    check_error(
        &["info", truncated_binary.to_str().unwrap()],
        "truncated_binary.msh",
    );
    check_error(&["info", "README.md"], "README.md");
}
