//! `csm search`: the RESULT.json contract, determinism over thread counts, `--vtk`, errors.

use serde_json::Value;
use std::collections::BTreeMap;

use crate::{RESULT_KEYS, csm, csm_json, kratos_mesh, repo_mesh, result_keys, scratch};

/// What [`check_vtu`] read from a `.vtu` file.
#[derive(Debug, PartialEq)]
pub struct VtuSummary {
    pub n_points: usize,
    pub n_cells: usize,
    /// Every `<DataArray>` by section and name: its values.
    pub arrays: BTreeMap<(String, String), Vec<String>>,
}

impl VtuSummary {
    pub fn array(&self, section: &str, name: &str) -> &[String] {
        self.arrays
            .get(&(section.to_owned(), name.to_owned()))
            .unwrap_or_else(|| panic!("no {section} array {name}"))
    }

    /// How many cells have VTK type `t`.
    pub fn cells_of_type(&self, t: u8) -> usize {
        let t = t.to_string();
        self.array("Cells", "types")
            .iter()
            .filter(|x| **x == t)
            .count()
    }
}

/// [`check_vtu`] of the file at `path`, in either form: a binary file (raw appended data) is
/// read as the ASCII form it stands for (every array decoded from its offset, as text the way
/// the writer formats it).
#[track_caller]
pub fn check_vtu_file(path: &std::path::Path) -> VtuSummary {
    let bytes = std::fs::read(path).unwrap();
    let start = b"<AppendedData encoding=\"raw\">\n   _";
    let Some(at) = bytes.windows(start.len()).position(|w| w == start) else {
        return check_vtu(std::str::from_utf8(&bytes).expect("an ASCII VTU is text"));
    };
    let header = std::str::from_utf8(&bytes[..at]).expect("UTF-8 header");
    let data = &bytes[at + start.len()..];
    assert!(data.ends_with(b"\n  </AppendedData>\n</VTKFile>\n"));
    let mut xml = String::new();
    let mut rest = header;
    while let Some(i) = rest.find("<DataArray ") {
        xml.push_str(&rest[..i]);
        let end = rest[i..].find("/>").expect("an empty DataArray element") + i;
        let tag = &rest[i..end];
        let offset: usize = attribute(tag, "offset").unwrap().parse().unwrap();
        let len = u64::from_le_bytes(data[offset..offset + 8].try_into().unwrap()) as usize;
        let body = &data[offset + 8..offset + 8 + len];
        let ty = attribute(tag, "type").unwrap();
        let values: Vec<String> = match ty {
            "Float64" => body
                .chunks(8)
                .map(|c| {
                    let x = f64::from_le_bytes(c.try_into().unwrap());
                    if x.is_nan() {
                        "nan".to_owned()
                    } else if x.is_infinite() {
                        if x > 0.0 { "inf" } else { "-inf" }.to_owned()
                    } else {
                        format!("{x:e}")
                    }
                })
                .collect(),
            "Int64" => body
                .chunks(8)
                .map(|c| i64::from_le_bytes(c.try_into().unwrap()).to_string())
                .collect(),
            "Int32" => body
                .chunks(4)
                .map(|c| i32::from_le_bytes(c.try_into().unwrap()).to_string())
                .collect(),
            "Int8" => body.iter().map(|&b| (b as i8).to_string()).collect(),
            "UInt8" => body.iter().map(|b| b.to_string()).collect(),
            other => panic!("type {other}"),
        };
        let open = tag.replace(" format=\"appended\"", " format=\"ascii\"");
        let open = &open[..open.find(" offset=").unwrap()];
        xml.push_str(&format!("{open}>\n{}\n</DataArray>", values.join(" ")));
        rest = &rest[end + 2..];
    }
    xml.push_str(rest);
    xml.push_str("</VTKFile>\n");
    check_vtu(&xml)
}

fn attribute<'a>(tag: &'a str, name: &str) -> Option<&'a str> {
    let key = format!(" {name}=\"");
    let at = tag.find(&key)? + key.len();
    let end = tag[at..].find('"')? + at;
    Some(&tag[at..end])
}

/// Checks what ParaView needs of an ASCII VTU file: tags nest and close in the
/// VTKFile/UnstructuredGrid/Piece layout; every point (cell) data array has one tuple per
/// point (cell); 3 coordinates per point; offsets increase and end at the connectivity's
/// length; connectivity indices name points; one known cell type per cell with the node
/// count that type needs.
#[track_caller]
pub fn check_vtu(xml: &str) -> VtuSummary {
    assert!(xml.starts_with("<?xml version=\"1.0\"?>\n"));
    let mut stack: Vec<String> = Vec::new();
    let mut arrays = BTreeMap::new();
    let (mut n_points, mut n_cells) = (None, None);
    let mut rest = xml;
    while let Some(start) = rest.find('<') {
        let end = rest[start..].find('>').expect("unclosed tag") + start;
        let tag = &rest[start + 1..end];
        let after = &rest[end + 1..];
        if tag.starts_with('?') {
        } else if let Some(name) = tag.strip_prefix('/') {
            assert_eq!(stack.pop().as_deref(), Some(name), "mismatched </{name}>");
        } else {
            assert_eq!(tag.matches('"').count() % 2, 0, "quotes in <{tag}>");
            let name = tag.split_whitespace().next().unwrap().to_owned();
            let parent = stack.last().cloned().unwrap_or_default();
            let expected_parent = match name.as_str() {
                "VTKFile" => "",
                "UnstructuredGrid" => "VTKFile",
                "Piece" => "UnstructuredGrid",
                "PointData" | "CellData" | "Points" | "Cells" => "Piece",
                "DataArray" => parent.as_str(),
                other => panic!("unexpected element <{other}>"),
            };
            assert_eq!(parent, expected_parent, "<{name}> inside <{parent}>");
            match name.as_str() {
                "VTKFile" => assert_eq!(attribute(tag, "type"), Some("UnstructuredGrid")),
                "Piece" => {
                    n_points = attribute(tag, "NumberOfPoints").map(|x| x.parse().unwrap());
                    n_cells = attribute(tag, "NumberOfCells").map(|x| x.parse().unwrap());
                }
                "DataArray" => {
                    assert!(
                        ["PointData", "CellData", "Points", "Cells"].contains(&parent.as_str()),
                        "DataArray in <{parent}>"
                    );
                    assert_eq!(attribute(tag, "format"), Some("ascii"));
                    let ty = attribute(tag, "type").unwrap();
                    let types = ["Float64", "Int64", "Int32", "Int8", "UInt8"];
                    assert!(types.contains(&ty), "{ty}");
                    let array = attribute(tag, "Name").unwrap().to_owned();
                    let body = &after[..after.find("</DataArray>").unwrap()];
                    let values: Vec<String> = body.split_whitespace().map(str::to_owned).collect();
                    let components: usize = attribute(tag, "NumberOfComponents")
                        .unwrap()
                        .parse()
                        .unwrap();
                    let n = match parent.as_str() {
                        "PointData" | "Points" => n_points.unwrap(),
                        "CellData" => n_cells.unwrap(),
                        _ => values.len() / components,
                    };
                    assert_eq!(values.len(), n * components, "length of {parent}/{array}");
                    let old = arrays.insert((parent.clone(), array.clone()), values);
                    assert!(old.is_none(), "two arrays {parent}/{array}");
                }
                _ => {}
            }
            stack.push(name);
        }
        rest = after;
    }
    assert!(stack.is_empty(), "unclosed {stack:?}");
    let s = VtuSummary {
        n_points: n_points.expect("NumberOfPoints"),
        n_cells: n_cells.expect("NumberOfCells"),
        arrays,
    };
    assert_eq!(s.array("Points", "Points").len(), 3 * s.n_points);
    for x in s.array("Points", "Points") {
        let x: f64 = x.parse().unwrap();
        assert!(x.is_finite());
    }
    let num = |v: &[String]| -> Vec<usize> { v.iter().map(|x| x.parse().unwrap()).collect() };
    let offsets = num(s.array("Cells", "offsets"));
    let types = num(s.array("Cells", "types"));
    let conn = num(s.array("Cells", "connectivity"));
    assert_eq!(offsets.len(), s.n_cells);
    assert_eq!(types.len(), s.n_cells);
    assert_eq!(offsets.last().copied().unwrap_or(0), conn.len());
    assert!(
        conn.iter().all(|&i| i < s.n_points),
        "connectivity past the points"
    );
    let mut start = 0;
    for (&end, &t) in offsets.iter().zip(&types) {
        let nodes = match t {
            3 => 2,
            5 => 3,
            9 | 10 => 4,
            13 => 6,
            12 => 8,
            other => panic!("cell type {other} not expected here"),
        };
        assert_eq!(end - start, nodes, "cell of type {t}");
        start = end;
    }
    s
}

fn without_timings(mut v: Value) -> Value {
    v.as_object_mut().unwrap().remove("timings_s");
    v
}

#[track_caller]
fn assert_sorted_ids<'a>(keys: impl Iterator<Item = &'a String>) {
    let ids: Vec<u64> = keys.map(|k| k.parse().expect("numeric id")).collect();
    assert!(
        ids.windows(2).all(|w| w[0] < w[1]),
        "ids not ascending: {ids:?}"
    );
}

#[test]
fn result_json_follows_the_contract() {
    let mesh = repo_mesh("boxes_41_ascii.msh");
    let path = scratch("boxes_result.json");
    let out = csm(&[
        "search",
        mesh.to_str().unwrap(),
        "-o",
        path.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        out.stdout.is_empty() && out.stderr.is_empty(),
        "--quiet prints nothing"
    );
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert_eq!(result_keys(&v), RESULT_KEYS);
    assert_eq!(v["format"], "csm-result/1");
    let timing_keys = crate::object_keys(&v["timings_s"]);
    assert_eq!(timing_keys, ["read", "initialize", "search", "total"]);
    let pairs = v["pairs"].as_object().unwrap();
    assert_eq!(pairs.keys().collect::<Vec<_>>(), ["0"]);
    let slaves = pairs["0"].as_object().unwrap();
    assert!(!slaves.is_empty());
    assert_sorted_ids(slaves.keys());
    let mut n_pairs = 0;
    for masters in slaves.values() {
        let m: Vec<u64> = masters
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_u64().unwrap())
            .collect();
        assert!(m.windows(2).all(|w| w[0] < w[1]), "{m:?}");
        n_pairs += m.len();
    }
    assert!(n_pairs > 0);
    assert_sorted_ids(v["nodes"].as_object().unwrap().keys());
    for node in v["nodes"].as_object().unwrap().values() {
        assert!(node["active"].is_boolean());
        assert!(node["normal_gap"].is_null() || node["normal_gap"].is_number());
    }
    assert!(v["paired_conditions"].is_u64());
    assert!(v["warnings"].is_array());
}

#[test]
fn same_result_for_any_thread_count() {
    let mesh = repo_mesh("boxes_41_ascii.msh");
    let m = mesh.to_str().unwrap();
    let one = csm_json(&["search", m, "--threads", "1", "--quiet"]);
    let two = csm_json(&["search", m, "--threads", "2", "--quiet"]);
    assert_eq!(
        serde_json::to_string_pretty(&without_timings(one)).unwrap(),
        serde_json::to_string_pretty(&without_timings(two)).unwrap()
    );
}

#[test]
fn vtk_output_has_the_mesh_the_flags_and_the_pairs() {
    let mesh = repo_mesh("boxes_41_ascii.msh");
    let vtu = scratch("boxes_search.vtu");
    let v = csm_json(&[
        "search",
        mesh.to_str().unwrap(),
        "--vtk",
        vtu.to_str().unwrap(),
        "--quiet",
    ]);
    let s = check_vtu_file(&vtu);
    // The ASCII form holds the same arrays.
    let ascii = scratch("boxes_search_ascii.vtu");
    csm_json(&[
        "search",
        mesh.to_str().unwrap(),
        "--vtk",
        ascii.to_str().unwrap(),
        "--vtk-ascii",
        "--quiet",
    ]);
    assert!(std::fs::read(&vtu).unwrap().len() < std::fs::read(&ascii).unwrap().len());
    assert_eq!(check_vtu(&std::fs::read_to_string(&ascii).unwrap()), s);
    // boxes_41_ascii.msh: 169 nodes, 266 elements, 60 conditions (`csm info`).
    let slaves = v["pairs"]["0"].as_object().unwrap();
    let n_pairs: usize = slaves.values().map(|m| m.as_array().unwrap().len()).sum();
    assert_eq!(s.n_cells, 266 + 60 + n_pairs);
    assert_eq!(s.cells_of_type(3), n_pairs);
    assert_eq!(s.cells_of_type(10) + s.cells_of_type(12), 266);
    assert_eq!(s.cells_of_type(5) + s.cells_of_type(9), 60);
    // One centre point per condition in a pair, after the nodes.
    let mut in_pairs: std::collections::BTreeSet<u64> = std::collections::BTreeSet::new();
    for (slave, masters) in slaves {
        if !masters.as_array().unwrap().is_empty() {
            in_pairs.insert(slave.parse().unwrap());
        }
        in_pairs.extend(
            masters
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_u64().unwrap()),
        );
    }
    assert_eq!(s.n_points, 169 + in_pairs.len());
    for name in [
        "node_id",
        "SLAVE",
        "MASTER",
        "ACTIVE",
        "INTERFACE",
        "normal_gap",
    ] {
        s.array("PointData", name);
    }
    let kinds = s.array("CellData", "entity_kind");
    assert_eq!(kinds.iter().filter(|k| *k == "2").count(), n_pairs);
    // The pairs' cell data name the slave and the master as in RESULT.json.
    let cond = s.array("CellData", "condition_id");
    let master = s.array("CellData", "master_id");
    let mut from_vtu: Vec<(u64, u64)> = Vec::new();
    for i in 0..s.n_cells {
        if kinds[i] == "2" {
            from_vtu.push((cond[i].parse().unwrap(), master[i].parse().unwrap()));
        }
    }
    let from_json: Vec<(u64, u64)> = slaves
        .iter()
        .flat_map(|(s, ms)| {
            let s: u64 = s.parse().unwrap();
            ms.as_array()
                .unwrap()
                .iter()
                .map(move |m| (s, m.as_u64().unwrap()))
        })
        .collect();
    assert_eq!(from_vtu, from_json);
    // Slave conditions carry SLAVE = 1, elements −1.
    let slave_flag = s.array("CellData", "SLAVE");
    assert_eq!(slave_flag[0], "-1");
    let ids = s.array("CellData", "entity_id");
    for i in 0..s.n_cells {
        if kinds[i] == "1" && slaves.contains_key(&ids[i]) {
            assert_eq!(slave_flag[i], "1", "condition {}", ids[i]);
        }
    }
    // Deterministic: a second run writes the same bytes.
    let again = scratch("boxes_search_again.vtu");
    csm_json(&[
        "search",
        mesh.to_str().unwrap(),
        "--vtk",
        again.to_str().unwrap(),
        "--quiet",
        "--threads",
        "1",
    ]);
    assert_eq!(std::fs::read(&again).unwrap(), std::fs::read(&vtu).unwrap());
}

#[track_caller]
fn check_error(args: &[&str], expect_in_message: &str) {
    let out = csm(args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "expected failure for {args:?}");
    assert!(!stderr.contains("panicked"), "panic for {args:?}: {stderr}");
    assert!(
        stderr.starts_with("error: "),
        "stderr for {args:?}: {stderr}"
    );
    assert!(
        stderr.contains(expect_in_message),
        "stderr for {args:?} lacks `{expect_in_message}`: {stderr}"
    );
}

fn write_setup(name: &str, text: &str) -> std::path::PathBuf {
    crate::write_scratch(name, text)
}

#[test]
fn bad_setups_are_clear_errors() {
    let mesh = repo_mesh("boxes_41_ascii.msh");
    let m = mesh.to_str().unwrap();
    check_error(
        &["search", m, "--setup", "does/not/exist.json"],
        "does/not/exist.json: cannot read",
    );
    let bad = write_setup(
        "bad_setup.json",
        "{\n  \"contact_model_part\": {\"0\": [\"slave\", \"master\"]},\n  oops\n}\n",
    );
    check_error(
        &["search", m, "--setup", bad.to_str().unwrap()],
        &format!("{}:3:", bad.display()),
    );
    let unknown = write_setup(
        "unknown_part.json",
        "{\n  \"contact_model_part\": {\"0\": [\"slave\", \"no_such_part\"]},\n  \
         \"assume_master_slave\": {\"0\": [\"slave\"]}\n}\n",
    );
    check_error(
        &["search", m, "--setup", unknown.to_str().unwrap()],
        &format!("{}:2: `contact_model_part.0`", unknown.display()),
    );
    check_error(
        &["search", m, "--setup", unknown.to_str().unwrap()],
        "found \"no_such_part\"",
    );
    // Without --setup, a mesh without `slave`/`master` parts says so.
    let other = kratos_mesh("3D_contact_simplest_patch_matching_triquad_test.mdpa");
    check_error(
        &["search", other.to_str().unwrap()],
        "no part named `slave` (any case)",
    );
}

/// `RUST_LOG` drives the log through `tracing`: the phases at `info`, the stage trace of the
/// search layer at `csm::stages=debug`; the default (`warn`) prints neither.
#[test]
fn rust_log_selects_phases_and_the_stage_trace() {
    let mesh = repo_mesh("boxes_41_ascii.msh");
    let run = |rust_log: Option<&str>| {
        let mut cmd = std::process::Command::new(env!("CARGO_BIN_EXE_csm"));
        cmd.args(["search", mesh.to_str().unwrap(), "-o"])
            .arg(scratch("rust_log_result.json"))
            .arg("--quiet")
            .env_remove("RUST_LOG");
        if let Some(v) = rust_log {
            cmd.env("RUST_LOG", v);
        }
        let out = cmd.output().expect("csm runs");
        assert!(out.status.success());
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    assert_eq!(run(None), "");
    let info = run(Some("info"));
    assert!(
        info.contains("INFO initialize:") && !info.contains("stage "),
        "{info}"
    );
    let stages = run(Some("csm::stages=debug"));
    assert!(
        stages.contains("DEBUG stage normal check") && !stages.contains("INFO"),
        "{stages}"
    );
}

/// `--profile` writes every phase with its stages, whatever `RUST_LOG` says; the stages of a
/// phase add up to it, and RESULT.json is the one of a run without it.
#[test]
fn profile_has_every_phase_and_stage() {
    let mesh = repo_mesh("boxes_41_ascii.msh");
    let (result, profile) = (scratch("profile_result.json"), scratch("profile.json"));
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_csm"))
        .args([
            "search",
            mesh.to_str().unwrap(),
            "--threads",
            "2",
            "--quiet",
        ])
        .arg("-o")
        .arg(&result)
        .arg("--profile")
        .arg(&profile)
        .env_remove("RUST_LOG")
        .output()
        .expect("csm runs");
    assert!(out.status.success() && out.stderr.is_empty());
    let p: Value = serde_json::from_str(&std::fs::read_to_string(&profile).unwrap()).unwrap();
    assert_eq!(p["format"], "csm-profile/1");
    assert_eq!(p["threads"], 2);
    let phases = crate::object_keys(&p["phases"]);
    assert_eq!(phases, ["read", "initialize", "search", "write", "total"]);
    let stages = p["stages"].as_array().unwrap();
    let named = |phase: &str| -> Vec<&str> {
        stages
            .iter()
            .filter(|s| s["phase"] == phase)
            .map(|s| s["stage"].as_str().unwrap())
            .collect()
    };
    assert_eq!(named("read"), ["read"]);
    for stage in [
        "plan",
        "interface",
        "normal check",
        "nodal h",
        "search set-up",
    ] {
        assert!(named("initialize").contains(&stage), "{stage}: {stages:?}");
    }
    for stage in ["slave queries", "mapping", "activation", "result"] {
        assert!(named("search").contains(&stage), "{stage}: {stages:?}");
    }
    assert_eq!(named("write")[0], "RESULT.json");
    assert_phases_add_up(&p, &["read", "initialize", "search", "write"]);
    // Linux counts every stage's page faults; reading the mesh touches fresh memory.
    if cfg!(target_os = "linux") {
        assert!(stages.iter().all(|s| s["faults"].is_u64()), "{stages:?}");
        assert!(stages[0]["faults"].as_u64() > Some(0), "{stages:?}");
    }
    let plain = csm_json(&["search", mesh.to_str().unwrap(), "--quiet"]);
    let with: Value = serde_json::from_str(&std::fs::read_to_string(&result).unwrap()).unwrap();
    assert_eq!(without_timings(with), without_timings(plain));
}

/// `tools/scaling_runs.sh`, what a lent many-core machine runs without a toolchain: a gzipped
/// mesh is unpacked once; every thread count and round gets its profile, its time and the
/// checksum of its RESULT.json without timings, and the checksums agree.
#[test]
fn the_scaling_script_makes_every_run() {
    use std::process::Command;
    let out = scratch("scaling_runs");
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(&out).unwrap();
    let mesh = repo_mesh("boxes_41_ascii.msh");
    let gz = out.join("boxes.msh.gz");
    let zipped = Command::new("sh")
        .arg("-c")
        .arg(format!("gzip -c '{}' > '{}'", mesh.display(), gz.display()))
        .status()
        .expect("sh runs");
    assert!(zipped.success());
    let script = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tools/scaling_runs.sh");
    let run = Command::new("sh")
        .arg(&script)
        .arg(env!("CARGO_BIN_EXE_csm"))
        .arg(&out)
        .args(["1,2", "2"])
        .arg(&gz)
        .arg("demo:300")
        .output()
        .expect("sh runs");
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    assert!(
        !std::fs::read_to_string(out.join("machine.txt"))
            .unwrap()
            .trim()
            .is_empty()
    );
    let dir = out.join("boxes");
    check_scaling_runs(&dir, |_| {});
    assert!(
        !dir.join("result.json").exists(),
        "the last result is removed"
    );
    // `demo:300`: `csm demo --profile`, its phases adding up, the same result each run.
    let dir = out.join("demo_300");
    check_scaling_runs(&dir, |p| {
        let phases = crate::object_keys(&p["phases"]);
        assert_eq!(
            phases,
            ["read", "initialize", "search", "truth", "write", "total"]
        );
        assert_phases_add_up(p, &["read", "initialize", "search", "truth", "write"]);
        let stages = p["stages"].as_array().unwrap();
        let named: Vec<&str> = stages
            .iter()
            .filter(|s| s["phase"] == "write")
            .map(|s| s["stage"].as_str().unwrap())
            .collect();
        assert_eq!(named[..2], ["RESULT.json", "VTU"]);
    });
    assert!(!dir.join("demo").exists(), "the demo's files are removed");
}

/// In the profile `p`, each of `phases` is the sum of its stages.
fn assert_phases_add_up(p: &Value, phases: &[&str]) {
    let stages = p["stages"].as_array().unwrap();
    for phase in phases {
        let sum: f64 = stages
            .iter()
            .filter(|s| s["phase"] == *phase)
            .map(|s| s["seconds"].as_f64().unwrap())
            .sum();
        let total = p["phases"][*phase].as_f64().unwrap();
        assert!(
            (sum - total).abs() <= 1e-9 * total.max(1.0),
            "{phase}: {sum} vs {total}"
        );
    }
}

/// The runs of one scene of `tools/scaling_runs.sh` with threads 1, 2 and rounds 1, 2: each
/// has its profile (of its thread count, checked further by `check_profile`), its time, and
/// the checksum of its RESULT.json, the same for all.
fn check_scaling_runs(dir: &std::path::Path, check_profile: impl Fn(&Value)) {
    let mut sums = Vec::new();
    for t in [1, 2] {
        for r in [1, 2] {
            let base = dir.join(format!("t{t}_r{r}"));
            let read = |ext: &str| {
                std::fs::read_to_string(base.with_extension(ext))
                    .unwrap_or_else(|e| panic!("{}.{ext}: {e}", base.display()))
            };
            let profile: Value = serde_json::from_str(&read("profile.json")).unwrap();
            assert_eq!(profile["threads"], t);
            check_profile(&profile);
            let wall: f64 = read("time.txt")
                .split_whitespace()
                .next()
                .unwrap()
                .parse()
                .unwrap();
            assert!(wall >= 0.0);
            sums.push(read("result.sha256").trim().to_owned());
        }
    }
    assert_eq!(sums[0].len(), 64, "{sums:?}");
    assert!(sums.iter().all(|s| *s == sums[0]), "{sums:?}");
}
