//! `csm demo`: a small scene end to end (files, summary, errors).

use serde_json::Value;

use crate::cli_search::{check_vtu, check_vtu_file};
use crate::{csm, scratch};

#[test]
fn small_demo_writes_both_files_and_a_summary() {
    let dir = scratch("demo_small");
    let _ = std::fs::remove_dir_all(&dir);
    let out = csm(&["demo", "--faces", "2000", "-o", dir.to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("pairs"), "{stdout}");
    assert!(stdout.contains("968 slave"), "{stdout}");
    assert!(stdout.contains("1024 master"), "{stdout}");
    let v: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("RESULT.json")).unwrap()).unwrap();
    assert_eq!(v["format"], "csm-result/1");
    let slaves = v["pairs"]["0"].as_object().unwrap();
    // Every slave face is listed; those under the sphere's pole have pairs.
    assert_eq!(slaves.len(), 968);
    let n_pairs: usize = slaves.values().map(|m| m.as_array().unwrap().len()).sum();
    assert!(n_pairs > 0);
    assert!(stdout.contains(&format!("{n_pairs} pairs")), "{stdout}");
    let s = check_vtu_file(&dir.join("demo.vtu"));
    // `--vtk-ascii` writes the same arrays as text.
    let ascii = scratch("demo_small_ascii");
    let _ = std::fs::remove_dir_all(&ascii);
    let out = csm(&[
        "demo",
        "--faces",
        "2000",
        "-o",
        ascii.to_str().unwrap(),
        "--vtk-ascii",
        "--quiet",
    ]);
    assert!(out.status.success());
    let text = std::fs::read_to_string(ascii.join("demo.vtu")).unwrap();
    assert_eq!(check_vtu(&text), s);
    // 32 × 32 × 2 hexahedra, 2 × 22 × 22 prisms, the faces, the pairs.
    assert_eq!(s.cells_of_type(12), 2048);
    assert_eq!(s.cells_of_type(13), 968);
    assert_eq!(s.cells_of_type(9), 1024);
    assert_eq!(s.cells_of_type(5), 968);
    assert_eq!(s.cells_of_type(3), n_pairs);
}

#[test]
fn quiet_demo_prints_nothing_and_bad_sizes_are_errors() {
    let dir = scratch("demo_quiet");
    let out = csm(&[
        "demo",
        "--faces",
        "200",
        "-o",
        dir.to_str().unwrap(),
        "--quiet",
        "--threads",
        "1",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.stdout.is_empty() && out.stderr.is_empty());
    assert!(dir.join("RESULT.json").is_file() && dir.join("demo.vtu").is_file());
    let out = csm(&[
        "demo",
        "--faces",
        "99999999999",
        "-o",
        dir.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success());
    assert!(stderr.starts_with("error: --faces"), "{stderr}");
}
