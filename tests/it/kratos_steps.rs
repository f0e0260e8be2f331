//! Multi-step runs and the dynamic search against Kratos 10.4.4 (`tests/fixtures/steps/`, made
//! by `cargo xtask fixtures` through `tools/kratos_fixtures_steps.py`): Kratos'
//! test_dynamic_search.py on its double-curvature meshes (reference §20.2) and multi-step
//! ALMContactProcess runs with `database_step_update`, the dynamic search,
//! `static_check_movement` and rigid motions.
//!
//! The `csm` binary runs each fixture's mesh and SETUP.json with `--threads 1` and `--threads 2`.
//! For every step (and the top level, = the last step): identical pair sets, ACTIVE flags and
//! paired-condition counts, NORMAL_GAP within 1e-9 relative (1e-12 absolute near 0), null
//! (never mapped, the 1e12 sentinel) where Kratos has null; and the two thread counts, and a
//! kd-tree refitted or rebuilt between steps (`refit_tree`), give the same RESULT.json but for
//! the timings.

use std::path::{Path, PathBuf};

use serde_json::Value;

use crate::{csm, scratch};

fn fixtures() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/steps");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("tests/fixtures/steps")
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    files
}

/// Runs `csm search` on the fixture's mesh and setup with `threads` worker threads; with
/// `rebuild`, the setup says `"refit_tree": false`.
fn run_csm(name: &str, fixture: &Value, threads: &str, rebuild: bool) -> Result<Value, String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mesh = root.join(fixture["mesh"].as_str().expect("mesh path"));
    let setup = scratch(&format!("steps_{name}_{threads}_{rebuild}_setup.json"));
    let mut text = fixture["setup"].clone();
    if rebuild {
        text.as_object_mut()
            .expect("setup object")
            .insert("refit_tree".to_owned(), Value::Bool(false));
    }
    std::fs::write(&setup, serde_json::to_string_pretty(&text).unwrap()).unwrap();
    let out = csm(&[
        "search",
        mesh.to_str().unwrap(),
        "--setup",
        setup.to_str().unwrap(),
        "--threads",
        threads,
        "--quiet",
    ]);
    if !out.status.success() {
        return Err(String::from_utf8_lossy(&out.stderr).into_owned());
    }
    serde_json::from_slice(&out.stdout).map_err(|e| format!("RESULT.json: {e}"))
}

fn without_timings(mut v: Value) -> Value {
    if let Some(m) = v.as_object_mut() {
        m.remove("timings_s");
        if let Some(Value::Array(steps)) = m.get_mut("steps") {
            for s in steps {
                if let Some(s) = s.as_object_mut() {
                    s.remove("timings_s");
                }
            }
        }
    }
    v
}

/// Every difference between Kratos' state (`kratos`) and csm's (`ours`) of one step, each
/// prefixed with `at`.
fn differences(at: &str, kratos: &Value, ours: &Value) -> Vec<String> {
    let mut out = Vec::new();
    if kratos["pairs"] != ours["pairs"] {
        let flat = |v: &Value| -> std::collections::BTreeSet<(String, u64)> {
            v["pairs"]["0"]
                .as_object()
                .into_iter()
                .flatten()
                .flat_map(|(s, ms)| {
                    ms.as_array()
                        .into_iter()
                        .flatten()
                        .map(move |m| (s.clone(), m.as_u64().unwrap_or(0)))
                })
                .collect()
        };
        let (k, o) = (flat(kratos), flat(ours));
        out.push(format!(
            "{at}: pair sets differ ({} Kratos pairs missing, {} extra; e.g. missing {:?}, extra \
             {:?})",
            k.difference(&o).count(),
            o.difference(&k).count(),
            k.difference(&o).next(),
            o.difference(&k).next()
        ));
    }
    if kratos["paired_conditions"] != ours["paired_conditions"] {
        out.push(format!(
            "{at}: paired conditions {} (Kratos) vs {} (csm)",
            kratos["paired_conditions"], ours["paired_conditions"]
        ));
    }
    let (Some(kn), Some(on)) = (kratos["nodes"].as_object(), ours["nodes"].as_object()) else {
        out.push(format!("{at}: no nodes object"));
        return out;
    };
    if kn.len() != on.len() || kn.keys().ne(on.keys()) {
        out.push(format!(
            "{at}: node sets differ ({} Kratos, {} csm)",
            kn.len(),
            on.len()
        ));
        return out;
    }
    let (mut active, mut gaps, mut worst) = (Vec::new(), Vec::new(), 0.0_f64);
    for (id, k) in kn {
        let o = &on[id];
        if k["active"] != o["active"] {
            active.push(id.clone());
        }
        let same = match (k["normal_gap"].as_f64(), o["normal_gap"].as_f64()) {
            (None, None) => k["normal_gap"].is_null() && o["normal_gap"].is_null(),
            (Some(a), Some(b)) => {
                let d = (a - b).abs();
                worst = worst.max(d / a.abs().max(b.abs()).max(1e-300));
                d <= 1e-9 * a.abs().max(b.abs()) + 1e-12
            }
            _ => false,
        };
        if !same {
            gaps.push(format!("{id}: {} vs {}", k["normal_gap"], o["normal_gap"]));
        }
    }
    if !active.is_empty() {
        out.push(format!(
            "{at}: ACTIVE differs on {} nodes (e.g. {:?})",
            active.len(),
            &active[..active.len().min(5)]
        ));
    }
    if !gaps.is_empty() {
        out.push(format!(
            "{at}: NORMAL_GAP differs on {} nodes (largest relative difference {worst:.2e}; e.g. \
             {:?})",
            gaps.len(),
            &gaps[..gaps.len().min(3)]
        ));
    }
    out
}

#[test]
fn steps_and_dynamic_search_match_kratos() {
    let files = fixtures();
    assert!(
        files.len() >= 5,
        "expected the step fixtures, found {}",
        files.len()
    );
    let mut failures = Vec::new();
    for file in &files {
        let name = file.file_stem().unwrap().to_string_lossy().into_owned();
        let fixture: Value =
            serde_json::from_str(&std::fs::read_to_string(file).unwrap()).expect("fixture JSON");
        let one = match run_csm(&name, &fixture, "1", false) {
            Ok(v) => v,
            Err(e) => {
                failures.push(format!("{name}: csm failed: {e}"));
                continue;
            }
        };
        failures.extend(differences(&name, &fixture, &one));
        match (fixture["steps"].as_array(), one["steps"].as_array()) {
            (None, None) => {}
            (Some(k), Some(o)) if k.len() == o.len() => {
                for (ks, os) in k.iter().zip(o) {
                    assert_eq!(ks["step"], os["step"], "{name}");
                    failures.extend(differences(&format!("{name} step {}", ks["step"]), ks, os));
                }
            }
            (k, o) => failures.push(format!(
                "{name}: {} Kratos steps, {} csm steps",
                k.map_or(0, Vec::len),
                o.map_or(0, Vec::len)
            )),
        }
        match run_csm(&name, &fixture, "2", false) {
            Ok(two) => {
                if without_timings(two) != without_timings(one.clone()) {
                    failures.push(format!("{name}: --threads 2 differs from --threads 1"));
                }
            }
            Err(e) => failures.push(format!("{name}: csm failed with 2 threads: {e}")),
        }
        // The kd-tree refitted between steps (the default) and rebuilt every step (Kratos)
        // give the same RESULT.json.
        match run_csm(&name, &fixture, "1", true) {
            Ok(rebuilt) => {
                if without_timings(rebuilt) != without_timings(one) {
                    failures.push(format!("{name}: \"refit_tree\": false differs"));
                }
            }
            Err(e) => failures.push(format!("{name}: csm failed with refit_tree false: {e}")),
        }
    }
    assert!(
        failures.is_empty(),
        "{} differences from Kratos:\n{}",
        failures.len(),
        failures.join("\n")
    );
}
