//! The INDEX_MAP contents (slave condition → master conditions, sorted) pinned by insta, in
//! both modes, so that a reviewer sees every pair a change adds or removes: on each Kratos
//! fixture scene (its `in_radius` MappingCheck Advanced setup, Kratos' default check) and on
//! each stability scene (`stability_index_maps` in `stability/mod.rs`). The Kratos fixtures
//! check kratos mode against Kratos; these pin robust mode too, and both against the last
//! reviewed state (`cargo insta review`).

use std::fmt::Write as _;
use std::path::Path;

use serde_json::Value;

/// The pairs of `result` as text: per pair key, one line per slave condition with its masters.
pub fn index_map_text(result: &Value) -> String {
    let mut text = String::new();
    for (key, slaves) in result["pairs"].as_object().expect("pairs object") {
        let _ = writeln!(text, "pair {key}:");
        for (slave, masters) in slaves.as_object().expect("slaves object") {
            let masters: Vec<String> = masters
                .as_array()
                .expect("masters list")
                .iter()
                .map(|m| m.to_string())
                .collect();
            let _ = writeln!(text, "  {slave}: {}", masters.join(" "));
        }
    }
    text
}

/// Runs `setup` (with `compatibility` set) on `mesh`: the INDEX_MAP text, or the error.
fn maps(mesh: &Path, setup: &Value, compatibility: &str) -> String {
    let mut setup = setup.clone();
    setup["compatibility"] = compatibility.into();
    let run = || -> Result<Value, String> {
        let mut model = csm::io::read_mesh(mesh).map_err(|e| e.to_string())?;
        let setup = csm::cli::load_setup(&setup.to_string(), "fixture setup")?;
        let (result, _) = csm::cli::run_search(&mut model, &setup, 0.0)?;
        Ok(result.to_json(&[]))
    };
    match run() {
        Ok(v) => index_map_text(&v),
        Err(e) => format!("error: {}\n", e.lines().next().unwrap_or("")),
    }
}

#[test]
fn fixture_index_maps() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    insta::glob!(
        "../fixtures/search",
        "*/*in_radius__mapping_check__advanced.json",
        |path| {
            let fixture: Value =
                serde_json::from_str(&std::fs::read_to_string(path).expect("fixture"))
                    .expect("JSON");
            let mesh = root.join(fixture["mesh"].as_str().expect("mesh path"));
            let mut text = String::new();
            for mode in ["kratos", "robust"] {
                let _ = writeln!(text, "## {mode}");
                text += &maps(&mesh, &fixture["setup"], mode);
            }
            insta::assert_snapshot!(text);
        }
    );
}
