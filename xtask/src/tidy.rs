//! Tidy checks, run by plain `cargo test`: the layering of `docs/ARCHITECTURE.md` (from
//! `cargo metadata`) and the documentation of every source file.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Command;

use super::workspace_root;

/// The csm crates each crate may depend on (normal, build and dev dependencies alike).
/// DESIGN.md §1: geometry ← trees; geometry ← model ← io; {geometry, model} ← activation;
/// {geometry, trees, model, activation} ← search ← eval; everything ← facade ← python;
/// {geometry, model, search} ← distributed ← facade (its tests also read meshes: io).
fn allowed() -> BTreeMap<&'static str, BTreeSet<&'static str>> {
    let all = [
        "csm-geometry",
        "csm-trees",
        "csm-model",
        "csm-io",
        "csm-search",
        "csm-activation",
        "csm-eval",
        "csm-chart",
        "csm-distributed",
    ];
    BTreeMap::from([
        ("csm-geometry", BTreeSet::new()),
        ("csm-trees", BTreeSet::from(["csm-geometry"])),
        ("csm-model", BTreeSet::from(["csm-geometry"])),
        ("csm-io", BTreeSet::from(["csm-geometry", "csm-model"])),
        (
            "csm-activation",
            BTreeSet::from(["csm-geometry", "csm-model"]),
        ),
        (
            "csm-search",
            BTreeSet::from(["csm-geometry", "csm-trees", "csm-model", "csm-activation"]),
        ),
        (
            "csm-eval",
            BTreeSet::from([
                "csm-geometry",
                "csm-trees",
                "csm-model",
                "csm-activation",
                "csm-search",
            ]),
        ),
        ("csm-chart", BTreeSet::new()),
        // The search split across ranks: over the mesh arrays and the search.
        (
            "csm-distributed",
            BTreeSet::from(["csm-geometry", "csm-model", "csm-io", "csm-search"]),
        ),
        ("csm", BTreeSet::from(all)),
        // The Python binding: over the facade only.
        ("csm-python", BTreeSet::from(["csm"])),
    ])
}

fn metadata() -> serde_json::Value {
    let out = Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_owned()))
        .args([
            "metadata",
            "--format-version",
            "1",
            "--no-deps",
            "--offline",
        ])
        .current_dir(workspace_root())
        .output()
        .expect("cargo metadata runs");
    assert!(
        out.status.success(),
        "cargo metadata failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("cargo metadata prints JSON")
}

#[test]
fn layers_depend_only_downwards() {
    let meta = metadata();
    let allowed = allowed();
    let packages = meta["packages"].as_array().expect("packages array");
    let mut seen = BTreeSet::new();
    let mut violations = Vec::new();
    for package in packages {
        let name = package["name"].as_str().expect("package name");
        seen.insert(name.to_owned());
        if name == "xtask" {
            continue;
        }
        let Some(ok) = allowed.get(name) else {
            violations.push(format!(
                "{name}: not in the layering allow-list of xtask/src/tidy.rs"
            ));
            continue;
        };
        for dep in package["dependencies"]
            .as_array()
            .expect("dependencies array")
        {
            let dep_name = dep["name"].as_str().expect("dependency name");
            let is_layer = dep_name == "csm" || dep_name.starts_with("csm-");
            if is_layer && !ok.contains(dep_name) {
                violations.push(format!(
                    "{name} -> {dep_name} is a back-edge or a skipped layer"
                ));
            }
        }
    }
    assert!(
        violations.is_empty(),
        "layering violations:\n{}",
        violations.join("\n")
    );
    for name in allowed.keys() {
        assert!(
            seen.contains(*name),
            "crate {name} of the design card is missing"
        );
    }
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// Every library source file opens with a `//!` doc (STYLE.md 3), except test side files.
#[test]
fn every_source_file_opens_with_a_doc() {
    let root = workspace_root();
    let mut files = Vec::new();
    rust_files(&root.join("src"), &mut files);
    rust_files(&root.join("xtask/src"), &mut files);
    for krate in std::fs::read_dir(root.join("crates"))
        .expect("crates dir")
        .flatten()
    {
        rust_files(&krate.path().join("src"), &mut files);
    }
    assert!(files.len() > 10, "found only {} source files", files.len());
    let missing: Vec<String> = files
        .iter()
        .filter(|f| !f.ends_with("tests.rs"))
        .filter(|f| {
            let text = std::fs::read_to_string(f).unwrap_or_default();
            !text.trim_start().starts_with("//!")
        })
        .map(|f| f.strip_prefix(&root).unwrap_or(f).display().to_string())
        .collect();
    assert!(
        missing.is_empty(),
        "files without a leading `//!` doc:\n{}",
        missing.join("\n")
    );
}

/// Every layer's `lib.rs` states its architecture invariant.
#[test]
fn every_layer_states_its_invariant() {
    let root = workspace_root();
    for krate in std::fs::read_dir(root.join("crates"))
        .expect("crates dir")
        .flatten()
    {
        let lib = krate.path().join("src/lib.rs");
        let text = std::fs::read_to_string(&lib).unwrap_or_default();
        assert!(
            text.contains("**Architecture Invariant:**"),
            "{} has no `**Architecture Invariant:**` line",
            lib.display()
        );
    }
}
