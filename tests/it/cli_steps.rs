//! `csm search` with SETUP.json `steps` (DESIGN.md §3): the RESULT.json `steps` contract,
//! determinism over thread counts, motion, and clear errors for bad step input.

use serde_json::Value;

use crate::{RESULT_KEYS, csm, csm_json, repo_mesh, result_keys};

fn write_setup(name: &str, text: &str) -> std::path::PathBuf {
    crate::write_scratch(name, text)
}

/// The boxes mesh (`slave` quads on `master` triangles) with `steps` moving `block_upper`.
fn boxes_setup(name: &str, steps: &str) -> std::path::PathBuf {
    write_setup(
        name,
        &format!(
            "{{\n  \"contact_model_part\": {{\"0\": [\"slave\", \"master\"]}},\n  \
             \"assume_master_slave\": {{\"0\": [\"slave\"]}},\n  \"steps\": [\n{steps}\n  ]\n}}\n"
        ),
    )
}

fn search(setup: &std::path::Path, extra: &[&str]) -> Value {
    let mesh = repo_mesh("boxes_41_ascii.msh");
    let mut args = vec![
        "search",
        mesh.to_str().unwrap(),
        "--setup",
        setup.to_str().unwrap(),
        "--quiet",
    ];
    args.extend_from_slice(extra);
    csm_json(&args)
}

fn without_timings(mut v: Value) -> Value {
    let m = v.as_object_mut().unwrap();
    m.remove("timings_s");
    if let Some(Value::Array(steps)) = m.get_mut("steps") {
        for s in steps {
            s.as_object_mut().unwrap().remove("timings_s");
        }
    }
    v
}

/// Pairs, nodes and paired conditions of a step entry or of the top level.
fn state(v: &Value) -> Value {
    serde_json::json!({
        "pairs": v["pairs"], "nodes": v["nodes"], "paired_conditions": v["paired_conditions"]
    })
}

const AWAY_AND_BACK: &str = r#"    {"delta_time": 0.5},
    {"delta_time": 0.5, "move": {"block_upper": {"translate": [0, 0, 10]}}},
    {"delta_time": 0.25, "move": {"block_upper": {"translate": [0, 0, -10]}}}"#;

#[test]
fn steps_result_follows_the_contract() {
    let setup = boxes_setup("steps_contract.json", AWAY_AND_BACK);
    let v = search(&setup, &[]);
    let mut expected = RESULT_KEYS.to_vec();
    expected.push("steps");
    assert_eq!(result_keys(&v), expected);
    let steps = v["steps"].as_array().unwrap();
    assert_eq!(steps.len(), 3);
    for (k, s) in steps.iter().enumerate() {
        let keys: Vec<&str> = s.as_object().unwrap().keys().map(String::as_str).collect();
        assert_eq!(
            keys,
            ["step", "pairs", "nodes", "paired_conditions", "timings_s"]
        );
        assert_eq!(s["step"], k + 1);
        assert!(s["timings_s"]["search"].as_f64().unwrap() >= 0.0);
    }
    assert_eq!(state(&v), state(&steps[2]), "top level = last step");
    let timing_keys: Vec<&str> = v["timings_s"]
        .as_object()
        .unwrap()
        .keys()
        .map(String::as_str)
        .collect();
    assert_eq!(timing_keys, ["read", "initialize", "search", "total"]);
    // Step 1 without motion is the plain single-step search.
    let plain = search(
        &write_setup(
            "steps_plain.json",
            "{\"contact_model_part\": {\"0\": [\"slave\", \"master\"]}, \
             \"assume_master_slave\": {\"0\": [\"slave\"]}}",
        ),
        &[],
    );
    assert_eq!(state(&steps[0]), state(&plain));
    let n_pairs = |s: &Value| -> usize {
        s["pairs"]["0"]
            .as_object()
            .unwrap()
            .values()
            .map(|m| m.as_array().unwrap().len())
            .sum()
    };
    assert!(n_pairs(&steps[0]) > 0);
    // Lifted 10 away: the mapping removes every pair, no node is active.
    assert_eq!(n_pairs(&steps[1]), 0);
    assert!(
        steps[1]["nodes"]
            .as_object()
            .unwrap()
            .values()
            .all(|n| n["active"] == false)
    );
    // Back in place: the first step's pairs, gaps and flags again.
    assert_eq!(steps[2]["pairs"], steps[0]["pairs"]);
    assert_eq!(steps[2]["nodes"], steps[0]["nodes"]);
}

#[test]
fn steps_give_the_same_result_for_any_thread_count() {
    let setup = boxes_setup(
        "steps_threads.json",
        r#"    {"delta_time": 0.1, "move": {"block_upper": {"translate": [0.05, 0.02, 0]}}},
    {"delta_time": 0.1, "move": {"block_upper": {"rotate": {"axis": [0, 0, 1], "angle_deg": 3, "centre": [0.5, 0.5, 0]}}}}"#,
    );
    let one = search(&setup, &["--threads", "1"]);
    let two = search(&setup, &["--threads", "2"]);
    assert_eq!(
        serde_json::to_string_pretty(&without_timings(one)).unwrap(),
        serde_json::to_string_pretty(&without_timings(two)).unwrap()
    );
}

#[track_caller]
fn check_error(setup: &std::path::Path, expect: &[&str]) {
    let mesh = repo_mesh("boxes_41_ascii.msh");
    let out = csm(&[
        "search",
        mesh.to_str().unwrap(),
        "--setup",
        setup.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "expected failure: {stderr}");
    assert!(!stderr.contains("panicked"), "panic: {stderr}");
    assert!(stderr.starts_with("error: "), "{stderr}");
    for e in expect {
        assert!(stderr.contains(e), "stderr lacks `{e}`: {stderr}");
    }
}

/// Bad step input: `error: <file>:<line>: …` naming the entry, never a panic. The steps list
/// starts on line 5 of these setups; the second entry is on line 6.
#[test]
fn bad_steps_are_clear_errors_with_the_line() {
    let first = r#"    {"delta_time": 1},"#;
    let cases: &[(&str, &[&str])] = &[
        (
            r#"    {"delta_time": 1, "move": {"no_such_part": {"translate": [1, 0, 0]}}}"#,
            &[
                ":6: `steps[1].move.no_such_part`",
                "expected a sub model part of the mesh",
            ],
        ),
        (
            r#"    {"delta_time": 1, "move": {"interface": {}, "slave": {}}}"#,
            &[":6: `steps[1].move.slave`", "share node"],
        ),
        (
            r#"    {"delta_time": 0}"#,
            &[":6: `steps[1].delta_time`: expected a positive finite number"],
        ),
        (
            r#"    {"delta_time": -0.5}"#,
            &[":6: `steps[1].delta_time`"],
        ),
        (
            r#"    {"delta_time": "fast"}"#,
            &[":6: `steps[1].delta_time`"],
        ),
        (r#"    {"delta_time": NaN}"#, &[":6:", "invalid JSON"]),
        (
            r#"    {"delta_time": 1, "move": {"slave": {"translate": [1, "x", 0]}}}"#,
            &[":6: `steps[1].move.slave.translate`"],
        ),
        (
            r#"    {"delta_time": 1, "move": {"slave": {"rotate": {"axis": [0, 0, 0], "angle_deg": 5}}}}"#,
            &[":6: `steps[1].move.slave.rotate.axis`", "non-zero"],
        ),
        (
            r#"    {"delta_time": 1, "speed": 2}"#,
            &[":6: `steps[1].speed`"],
        ),
    ];
    for (i, (step, expect)) in cases.iter().enumerate() {
        let setup = boxes_setup(&format!("bad_steps_{i}.json"), &format!("{first}\n{step}"));
        check_error(&setup, expect);
    }
}
