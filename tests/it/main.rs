//! Workspace-level integration tests: the `csm` binary as a user runs it.

mod cli_demo;
mod cli_info;
mod cli_plan;
mod cli_report;
mod cli_search;
mod cli_steps;
mod index_maps;
mod kratos_conformance;
mod kratos_search;
mod kratos_steps;
mod robust_snapshots;
mod seed_features;
mod stability;

use std::path::PathBuf;
use std::process::{Command, Output};

/// `../shared/data/kratos-tests/<name>` beside the clone (CI has it).
pub fn kratos_mesh(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../shared/data/kratos-tests")
        .join(name)
}

/// `tests/data/<name>` in the repository.
pub fn repo_mesh(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// Runs the `csm` binary with `args`.
pub fn csm(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_csm"))
        .args(args)
        .output()
        .expect("the csm binary runs")
}

/// Runs the `csm` binary with `args`, requires success and returns the RESULT.json it
/// printed on stdout.
pub fn csm_json(args: &[&str]) -> serde_json::Value {
    let out = csm(args);
    assert!(
        out.status.success(),
        "csm {args:?} failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("RESULT.json on stdout")
}

/// The top-level keys of a single-step RESULT.json, in the contract's order (DESIGN.md §3); a
/// multi-step one adds `steps`.
pub const RESULT_KEYS: [&str; 6] = [
    "format",
    "pairs",
    "nodes",
    "paired_conditions",
    "warnings",
    "timings_s",
];

/// The keys RESULT.json has only where they apply (DESIGN.md §3), after `paired_conditions`
/// in this order: the constraints of an MPC process, the ids Kratos gives conditions whose
/// file ids are not 1..N.
pub const OPTIONAL_RESULT_KEYS: [&str; 2] = ["master_slave_constraints", "kratos_condition_ids"];

/// The keys of the JSON object `v`, in order.
pub fn object_keys(v: &serde_json::Value) -> Vec<&str> {
    v.as_object()
        .expect("a JSON object")
        .keys()
        .map(String::as_str)
        .collect()
}

/// The top-level keys of RESULT.json `v`, in order, without the optional ones (which must
/// stand right after `paired_conditions`, in their order).
pub fn result_keys(v: &serde_json::Value) -> Vec<&str> {
    let all = object_keys(v);
    let optional: Vec<&str> = all
        .iter()
        .copied()
        .filter(|k| OPTIONAL_RESULT_KEYS.contains(k))
        .collect();
    if let Some(first) = optional.first() {
        let at = all.iter().position(|k| k == first).unwrap();
        assert_eq!(all[at - 1], "paired_conditions", "{all:?}");
        assert_eq!(&all[at..at + optional.len()], &optional[..], "{all:?}");
        let order: Vec<&str> = OPTIONAL_RESULT_KEYS
            .iter()
            .copied()
            .filter(|k| optional.contains(k))
            .collect();
        assert_eq!(optional, order, "{all:?}");
    }
    all.into_iter()
        .filter(|k| !OPTIONAL_RESULT_KEYS.contains(k))
        .collect()
}

/// A fresh scratch file path under the target directory's temp area.
pub fn scratch(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("it");
    std::fs::create_dir_all(&dir).expect("scratch dir");
    dir.join(name)
}

/// Writes `text` to the scratch file `name` and returns its path. The file is replaced whole
/// (written beside it, then renamed over it): tests that run at the same time and write the
/// same file never let a `csm` run of another read it half written or empty.
pub fn write_scratch(name: &str, text: &str) -> PathBuf {
    static WRITES: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let path = scratch(name);
    let n = WRITES.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let partial = scratch(&format!("{name}.{}.{n}.partial", std::process::id()));
    std::fs::write(&partial, text).expect("scratch file");
    std::fs::rename(&partial, &path).expect("scratch file in place");
    path
}
