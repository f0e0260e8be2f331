//! From setup text to [`SearchSetup`]: Kratos' Python-path semantics (defaults, the keys it
//! forwards to C++, the ones it drops, its silent fallbacks) plus csm's own keys.

use std::collections::BTreeMap;

use serde_json::{Map, Value};

use super::defaults::{ALM_DEFAULTS, CONTACT_MODULES, CSM_KEYS, WRAPPER_DEFAULTS};
use super::motion::{nodal_values, steps};
use super::processes::{mesh_tying_as_alm, mpc_as_alm};
use super::types::{
    CheckGap, Compatibility, ContactProcess, ContactType, ObbIntersectionType,
    OctreeSearchParameters, PairSetup, SearchParameters, SearchSetup, SearchTreeType, SetupSource,
    line_of_key_path,
};
use super::validate::validate_and_fill;
use crate::error::{Error, ErrorKind};

/// The 1-based line of the first occurrence of `"key"` in `text` (the last segment of a
/// dotted path), used to point errors at the setup file.
fn line_of(text: &str, path: &str) -> Option<usize> {
    let key = path.rsplit('.').next().unwrap_or(path);
    let needle = format!("\"{key}\"");
    text.find(&needle)
        .map(|pos| text[..pos].matches('\n').count() + 1)
}

fn key_of(kind: &ErrorKind) -> Option<&str> {
    match kind {
        ErrorKind::UnknownKey { key } | ErrorKind::InvalidValue { key, .. } => Some(key),
        _ => None,
    }
}

pub(super) fn defaults(text: &str) -> Map<String, Value> {
    match serde_json::from_str(text) {
        Ok(Value::Object(map)) => map,
        // The defaults are constants of this crate, checked by a unit test.
        _ => Map::new(),
    }
}

pub(super) fn invalid(key: &str, expected: &str, found: &Value) -> Error {
    ErrorKind::InvalidValue {
        key: key.to_owned(),
        expected: expected.to_owned(),
        found: found.to_string(),
    }
    .into()
}

/// Finds the `Parameters` of the first contact process in a ProjectParameters tree.
fn find_contact_process(v: &Value) -> Option<(&Map<String, Value>, &'static str)> {
    match v {
        Value::Object(map) => {
            if let Some(Value::String(module)) = map.get("python_module") {
                let module = module.rsplit('.').next().unwrap_or(module);
                if let (Some(m), Some(Value::Object(params))) = (
                    CONTACT_MODULES.iter().find(|m| **m == module),
                    map.get("Parameters"),
                ) {
                    return Some((params, *m));
                }
            }
            map.values().find_map(find_contact_process)
        }
        Value::Array(items) => items.iter().find_map(find_contact_process),
        _ => None,
    }
}

struct Reader<'a> {
    map: &'a Map<String, Value>,
    path: &'a str,
}

impl Reader<'_> {
    fn key(&self, key: &str) -> String {
        if self.path.is_empty() {
            key.to_owned()
        } else {
            format!("{}.{key}", self.path)
        }
    }
    fn value(&self, key: &str) -> &Value {
        self.map.get(key).unwrap_or(&Value::Null)
    }
    fn bool(&self, key: &str) -> Result<bool, Error> {
        self.value(key)
            .as_bool()
            .ok_or_else(|| invalid(&self.key(key), "a boolean", self.value(key)))
    }
    fn f64(&self, key: &str) -> Result<f64, Error> {
        self.value(key)
            .as_f64()
            .ok_or_else(|| invalid(&self.key(key), "a number", self.value(key)))
    }
    fn positive(&self, key: &str) -> Result<f64, Error> {
        let x = self.f64(key)?;
        if x.is_finite() && x > 0.0 {
            Ok(x)
        } else {
            Err(invalid(
                &self.key(key),
                "a positive number",
                self.value(key),
            ))
        }
    }
    /// Kratos `GetInt` truncates a non-integral number; csm accepts only integers ≥ `min`.
    fn int(&self, key: &str, min: u64) -> Result<u64, Error> {
        let v = self.value(key);
        match v.as_f64() {
            Some(x) if x.fract() == 0.0 && x >= min as f64 && x <= u32::MAX as f64 => Ok(x as u64),
            _ => Err(invalid(&self.key(key), &format!("an integer ≥ {min}"), v)),
        }
    }
    fn str(&self, key: &str) -> Result<&str, Error> {
        self.value(key)
            .as_str()
            .ok_or_else(|| invalid(&self.key(key), "a string", self.value(key)))
    }
    fn obj(&self, key: &str) -> Result<&Map<String, Value>, Error> {
        self.value(key)
            .as_object()
            .ok_or_else(|| invalid(&self.key(key), "an object", self.value(key)))
    }
}

struct Context {
    compatibility: Compatibility,
    strict: bool,
    warnings: Vec<String>,
    /// The pair whose parameters are being read, named in every warning about them.
    pair: Option<String>,
}

impl Context {
    /// A warning, prefixed with the pair being read.
    fn warn(&mut self, message: String) {
        let message = match &self.pair {
            Some(key) => format!("pair {key}: {message}"),
            None => message,
        };
        self.warnings.push(message);
    }

    /// A Kratos silent fallback: warned, or an error with `"strict": true`.
    fn fallback(&mut self, message: String) -> Result<(), Error> {
        if self.strict {
            let message = match &self.pair {
                Some(key) => format!("pair {key}: {message}"),
                None => message,
            };
            return Err(ErrorKind::Strict(message).into());
        }
        self.warn(message);
        Ok(())
    }
}

fn type_search(s: &str, key: &str, cx: &mut Context) -> Result<SearchTreeType, Error> {
    Ok(match s {
        "InRadius" | "in_radius" => SearchTreeType::KdtreeInRadius,
        "InBox" | "in_box" => SearchTreeType::KdtreeInBox,
        "InRadiusWithOBB" | "in_radius_with_obb" => SearchTreeType::KdtreeInRadiusWithObb,
        "InBoxWithOBB" | "in_box_with_obb" => SearchTreeType::KdtreeInBoxWithObb,
        "OctreeWithOBB" | "octree_with_obb" => SearchTreeType::OctreeWithObb,
        "kdop_18" => SearchTreeType::Kdop,
        "KDOP" | "kdop" => match cx.compatibility {
            Compatibility::Kratos => {
                return Err(ErrorKind::RejectedByKratos(format!(
                    "`{key}`: \"{s}\" fails in Kratos (\"KDOP contact search: Not yet \
                     implemented\"); use \"kdop_18\" or \"compatibility\": \"robust\" for csm's \
                     18-DOP search"
                ))
                .into());
            }
            Compatibility::Robust => {
                cx.warn(format!(
                    "`{key}`: \"{s}\" runs csm's 18-DOP search in robust mode (Kratos fails on it)"
                ));
                SearchTreeType::Kdop
            }
        },
        other => {
            cx.fallback(format!(
                "`{key}`: unknown type_search \"{other}\"; Kratos silently uses InRadius"
            ))?;
            SearchTreeType::KdtreeInRadius
        }
    })
}

fn check_gap(s: &str, key: &str, cx: &mut Context) -> Result<CheckGap, Error> {
    Ok(match s {
        "NoCheck" | "no_check" => CheckGap::NoCheck,
        "DirectCheck" | "direct_check" => CheckGap::DirectCheck,
        // "check_mapping" is the Python default; Kratos maps it through its fallback (Q11).
        "MappingCheck" | "mapping_check" | "check_mapping" => CheckGap::MappingCheck,
        other => {
            cx.fallback(format!(
                "`{key}`: unknown check_gap \"{other}\"; Kratos silently uses MappingCheck"
            ))?;
            CheckGap::MappingCheck
        }
    })
}

fn octree(
    map: &Map<String, Value>,
    path: &str,
    cx: &mut Context,
) -> Result<OctreeSearchParameters, Error> {
    let r = Reader { map, path };
    let obb_key = r.key("OBB_intersection_type");
    let obb_intersection_type = match r.str("OBB_intersection_type")? {
        "SeparatingAxisTheorem" => ObbIntersectionType::SeparatingAxisTheorem,
        "Direct" => ObbIntersectionType::Direct,
        other => {
            cx.fallback(format!(
                "`{obb_key}`: unknown OBB_intersection_type \"{other}\"; Kratos uses \
                 SeparatingAxisTheorem"
            ))?;
            ObbIntersectionType::SeparatingAxisTheorem
        }
    };
    Ok(OctreeSearchParameters {
        bounding_box_factor: r.f64("bounding_box_factor")?,
        debug_obb: r.bool("debug_obb")?,
        obb_intersection_type,
        build_from_bounding_box: r.bool("build_from_bounding_box")?,
        lower_bounding_box_coefficient: r.f64("lower_bounding_box_coefficient")?,
        higher_bounding_box_coefficient: r.f64("higher_bounding_box_coefficient")?,
    })
}

fn contact_type(s: &str) -> Result<ContactType, Error> {
    let base = s.strip_suffix("WithNormalUpdate").unwrap_or(s);
    Ok(match base {
        "Frictionless" => ContactType::Frictionless,
        "FrictionlessComponents" => ContactType::FrictionlessComponents,
        "Frictional" => ContactType::Frictional,
        "FrictionalPureSlip" => ContactType::FrictionalPureSlip,
        _ => {
            return Err(invalid(
                "contact_type",
                "\"Frictionless\", \"FrictionlessComponents\", \"Frictional\" or \
                 \"FrictionalPureSlip\"",
                &Value::String(s.to_owned()),
            ));
        }
    })
}

fn string_list(v: &Value, key: &str) -> Result<Vec<String>, Error> {
    let items = v
        .as_array()
        .ok_or_else(|| invalid(key, "a list of part names", v))?;
    items
        .iter()
        .map(|s| {
            s.as_str()
                .map(str::to_owned)
                .ok_or_else(|| invalid(key, "a part name (string)", s))
        })
        .collect()
}

/// Parses a setup: the `Parameters` object of a Kratos contact process (`ALMContactProcess`,
/// Python-path semantics and defaults) or a whole `ProjectParameters.json` (its first contact
/// process is used), plus csm's keys `compatibility`, `strict`, `process_info`, `nodal_h`,
/// `cpp_search_parameters` (DESIGN.md §2), `nodal_values`, `steps` and `refit_tree`
/// (DESIGN.md §3, `docs/steps.md`). `file` names the setup in errors, which carry the
/// line of the offending key.
pub fn parse_setup(text: &str, file: &str) -> Result<SearchSetup, Error> {
    let source = SetupSource {
        file: file.to_owned(),
        text: text.to_owned(),
    };
    parse_inner(text)
        .map(|setup| SearchSetup {
            source: Some(source),
            ..setup
        })
        .map_err(|e| {
            let line = match e.kind() {
                ErrorKind::Json(_) => e.line(),
                kind => key_of(kind)
                    .and_then(|k| line_of_key_path(text, k).or_else(|| line_of(text, k))),
            };
            e.at(file, line)
        })
}

fn parse_inner(text: &str) -> Result<SearchSetup, Error> {
    let root: Value = serde_json::from_str(text)
        .map_err(|e| Error::new(ErrorKind::Json(e.to_string())).at("", Some(e.line())))?;
    let Value::Object(mut root) = root else {
        return Err(invalid("<setup>", "a JSON object", &root));
    };
    let mut csm: Map<String, Value> = Map::new();
    for key in CSM_KEYS {
        if let Some(v) = root.remove(key) {
            csm.insert(key.to_owned(), v);
        }
    }
    let project = ["problem_data", "solver_settings", "processes"]
        .iter()
        .any(|k| root.contains_key(*k));
    let (mut params, module) = if project {
        let tree = Value::Object(root);
        let (params, module) = find_contact_process(&tree).ok_or(ErrorKind::NoContactProcess)?;
        (params.clone(), module)
    } else {
        (root, "alm_contact_process")
    };
    for key in CSM_KEYS {
        if let Some(v) = params.remove(key) {
            csm.entry(key.to_owned()).or_insert(v);
        }
    }
    let explicit = module == "explicit_penalty_contact_process";
    // The process: the ProjectParameters' module, csm's `process` key, or for a bare
    // `Parameters` object the keys it has (`mesh_tying_model_part` is the mesh tying's own).
    let process = match csm.get("process") {
        Some(Value::String(m)) => ContactProcess::of_module(m).ok_or_else(|| {
            invalid(
                "process",
                "a contact process module: \"alm_contact_process\", \"penalty_contact_process\", \
                 \"explicit_penalty_contact_process\", \"mpc_contact_process\" or \
                 \"mesh_tying_process\"",
                &Value::String(m.clone()),
            )
        })?,
        Some(v) => return Err(invalid("process", "a module name (string)", v)),
        None if project => ContactProcess::of_module(module).unwrap_or(ContactProcess::Alm),
        None if params.contains_key("mesh_tying_model_part") => ContactProcess::MeshTying,
        None => ContactProcess::Alm,
    };
    let explicit = explicit
        || csm.get("process").and_then(Value::as_str) == Some("explicit_penalty_contact_process");
    // MPC and mesh tying: validated against their own defaults as Kratos does, then read as
    // the ALM parameters they share the search keys with.
    match process {
        ContactProcess::Mpc => params = mpc_as_alm(params)?,
        ContactProcess::MeshTying => params = mesh_tying_as_alm(params)?,
        ContactProcess::Alm => {}
    }

    // csm's own keys.
    let csm_reader = Reader {
        map: &csm,
        path: "",
    };
    let compatibility = match csm.get("compatibility") {
        None => Compatibility::Kratos,
        Some(Value::String(s)) if s == "kratos" => Compatibility::Kratos,
        Some(Value::String(s)) if s == "robust" => Compatibility::Robust,
        Some(v) => return Err(invalid("compatibility", "\"kratos\" or \"robust\"", v)),
    };
    let strict = if csm.contains_key("strict") {
        csm_reader.bool("strict")?
    } else {
        false
    };
    let mut process_info = BTreeMap::new();
    if csm.contains_key("process_info") {
        for (k, v) in csm_reader.obj("process_info")? {
            let x = v.as_f64().filter(|x| x.is_finite());
            let x = x.ok_or_else(|| invalid(&format!("process_info.{k}"), "a finite number", v))?;
            process_info.insert(k.clone(), x);
        }
    }
    let nodal_h = if csm.contains_key("nodal_h") {
        Some(csm_reader.positive("nodal_h")?)
    } else {
        None
    };
    let steps = match csm.get("steps") {
        Some(v) => steps(v)?,
        None => Vec::new(),
    };
    let refit_tree = if csm.contains_key("refit_tree") {
        csm_reader.bool("refit_tree")?
    } else {
        true
    };
    let nodal_values = match csm.get("nodal_values") {
        Some(v) => nodal_values(v)?,
        None => Vec::new(),
    };
    let mut cx = Context {
        compatibility,
        strict,
        warnings: Vec::new(),
        pair: None,
    };

    // What the user wrote in search_parameters, before defaults are filled.
    let written: Map<String, Value> = params
        .get("search_parameters")
        .and_then(Value::as_object)
        .cloned()
        .unwrap_or_default();
    let mut alm = defaults(ALM_DEFAULTS);
    if let (true, Some(Value::Object(sp))) = (explicit, alm.get_mut("search_parameters")) {
        sp.insert(
            "type_search".to_owned(),
            Value::String("octree_with_obb".to_owned()),
        );
    }
    validate_and_fill(&mut params, &alm, "")?;
    let top = Reader {
        map: &params,
        path: "",
    };
    let sp_map = top.obj("search_parameters")?;
    let sp = Reader {
        map: sp_map,
        path: "search_parameters",
    };

    let contact_type = contact_type(top.str("contact_type")?)?;
    let interval = {
        let v = top.value("interval");
        let items = v
            .as_array()
            .filter(|a| a.len() == 2)
            .ok_or_else(|| invalid("interval", "[start, end]", v))?;
        let bound = |x: &Value| match x {
            Value::String(s) if s == "End" => Ok(1e30),
            x => x
                .as_f64()
                .ok_or_else(|| invalid("interval", "numbers or \"End\"", x)),
        };
        (bound(&items[0])?, bound(&items[1])?)
    };

    // The keys Kratos' Python layer drops (Q8): same results in kratos mode, honoured in
    // robust mode, warned either way when the user set them.
    let wrapper = defaults(WRAPPER_DEFAULTS);
    let default_octree = octree(
        wrapper
            .get("octree_search_parameters")
            .and_then(Value::as_object)
            .unwrap_or(&Map::new()),
        "octree_search_parameters",
        &mut cx,
    )?;
    let written_octree = octree(
        sp.obj("octree_search_parameters")?,
        "search_parameters.octree_search_parameters",
        &mut cx,
    )?;
    let written_predict = sp.bool("predict_correct_lagrange_multiplier")?;
    let honour = compatibility == Compatibility::Robust;
    for key in [
        "octree_search_parameters",
        "predict_correct_lagrange_multiplier",
    ] {
        let changed = match key {
            "octree_search_parameters" => {
                written.contains_key(key) && written_octree != default_octree
            }
            _ => written.contains_key(key) && written_predict,
        };
        if changed {
            cx.warnings.push(if honour {
                format!("`search_parameters.{key}` is dropped by Kratos' Python layer; honoured in robust mode")
            } else {
                format!(
                    "`search_parameters.{key}` is dropped by Kratos' Python layer and ignored, as in \
                     Kratos; use \"cpp_search_parameters\" or \"compatibility\": \"robust\""
                )
            });
        }
    }

    // Pairs.
    let cmp = top.obj("contact_model_part")?;
    let ams = top.obj("assume_master_slave")?;
    let cpi = top.obj("contact_property_ids")?;
    let cpp = match csm.get("cpp_search_parameters") {
        None => None,
        Some(Value::Object(m)) => {
            let mut m = m.clone();
            validate_and_fill(&mut m, &wrapper, "cpp_search_parameters")?;
            Some(m)
        }
        Some(v) => return Err(invalid("cpp_search_parameters", "an object", v)),
    };
    let mut pairs = BTreeMap::new();
    // Every list empty: Kratos detects the skin into pair "0" (`__detect_skin`), with that
    // pair's roles and properties; the pair's part list stays empty here (`skin`).
    let mut skin = true;
    for (key, parts) in cmp {
        skin &= string_list(parts, &format!("contact_model_part.{key}"))?.is_empty();
    }
    for (key, parts) in cmp {
        let parts = string_list(parts, &format!("contact_model_part.{key}"))?;
        if parts.is_empty() && !(skin && key == "0") {
            continue;
        }
        let slaves = string_list(&ams[key], &format!("assume_master_slave.{key}"))?;
        cx.pair = Some(key.clone());
        let property_id = Reader {
            map: cpi,
            path: "contact_property_ids",
        }
        .int(key, 0)? as u32;
        let search = match &cpp {
            Some(m) => cpp_parameters(m, &mut cx)?,
            None => SearchParameters {
                type_search: type_search(
                    sp.str("type_search")?,
                    "search_parameters.type_search",
                    &mut cx,
                )?,
                check_gap: check_gap(sp.str("check_gap")?, "search_parameters.check_gap", &mut cx)?,
                simple_search: sp.bool("simple_search")?,
                search_factor: sp.positive("search_factor")?,
                allocation_size: sp.int("max_number_results", 1)? as usize,
                bucket_size: sp.int("bucket_size", 1)? as usize,
                dynamic_search: sp.bool("dynamic_search")?,
                static_check_movement: sp.bool("static_check_movement")?,
                consider_gap_threshold: sp.bool("consider_gap_threshold")?,
                normal_orientation_threshold: sp.f64("normal_orientation_threshold")?,
                debug_mode: sp.bool("debug_mode")?,
                inverted_search: false,
                predict_correct_lagrange_multiplier: honour && written_predict,
                pure_slip: contact_type == ContactType::FrictionalPureSlip,
                predefined_master_slave: !slaves.is_empty(),
                octree: if honour {
                    written_octree
                } else {
                    default_octree
                },
                id_name: key.clone(),
                create_auxiliar_conditions: true,
            },
        };
        let key_number: u32 = key.parse().map_err(|_| {
            invalid(
                "contact_model_part",
                "keys \"0\"…\"9\"",
                &Value::String(key.clone()),
            )
        })?;
        pairs.insert(
            key_number,
            PairSetup {
                parts,
                slaves,
                property_id,
                search,
            },
        );
    }
    cx.pair = None;
    // MPCContactSearchProcess is the base search class: the wrapper drops `simple_search`,
    // and the base activation is the Simple one (without the multiplier guesses, which
    // change no pair, flag or gap).
    if process == ContactProcess::Mpc {
        for pair in pairs.values_mut() {
            pair.search.simple_search = true;
        }
    }
    if pairs.is_empty() {
        // Only a `contact_model_part` without the key "0" gets here.
        return Err(invalid(
            "contact_model_part",
            "lists of part names under the keys \"0\"…\"9\"",
            &Value::Object(cmp.clone()),
        ));
    }
    let consider_tessellation = top.bool("consider_tessellation")?;
    if consider_tessellation {
        cx.warn(
            "`consider_tessellation`: Kratos triangulates each 3D overlap polygon by Delaunay \
             (delaunator or Triangle, whichever its build has), csm by Kratos' fan: the mapped \
             NORMAL_GAP can differ by about 1e-9 relative (docs/conformance.md)"
                .to_owned(),
        );
    }

    Ok(SearchSetup {
        model_part_name: top.str("model_part_name")?.to_owned(),
        pairs,
        contact_type,
        adapt_search: sp.bool("adapt_search")?,
        active_check_factor: sp.f64("active_check_factor")?,
        database_step_update: sp.int("database_step_update", 1)? as u32,
        normal_check_proportion: top.f64("normal_check_proportion")?,
        zero_tolerance_factor: top.f64("zero_tolerance_factor")?,
        integration_order: top.int("integration_order", 1)? as u32,
        consider_tessellation,
        skin,
        interval,
        explicit,
        process,
        compatibility,
        strict,
        process_info,
        nodal_h,
        cpp_search_parameters: cpp.is_some(),
        nodal_values,
        steps,
        refit_tree,
        interfaces_generated: false,
        warnings: cx.warnings,
        source: None,
    })
}

/// The C++ wrapper's parameters, used verbatim (wrapper defaults already filled).
fn cpp_parameters(m: &Map<String, Value>, cx: &mut Context) -> Result<SearchParameters, Error> {
    let r = Reader {
        map: m,
        path: "cpp_search_parameters",
    };
    Ok(SearchParameters {
        type_search: type_search(
            r.str("type_search")?,
            "cpp_search_parameters.type_search",
            cx,
        )?,
        check_gap: check_gap(r.str("check_gap")?, "cpp_search_parameters.check_gap", cx)?,
        simple_search: r.bool("simple_search")?,
        search_factor: r.positive("search_factor")?,
        allocation_size: r.int("allocation_size", 1)? as usize,
        bucket_size: r.int("bucket_size", 1)? as usize,
        dynamic_search: r.bool("dynamic_search")?,
        static_check_movement: r.bool("static_check_movement")?,
        consider_gap_threshold: r.bool("consider_gap_threshold")?,
        normal_orientation_threshold: r.f64("normal_orientation_threshold")?,
        debug_mode: r.bool("debug_mode")?,
        inverted_search: r.bool("inverted_search")?,
        predict_correct_lagrange_multiplier: r.bool("predict_correct_lagrange_multiplier")?,
        pure_slip: r.bool("pure_slip")?,
        predefined_master_slave: r.bool("predefined_master_slave")?,
        octree: octree(
            r.obj("octree_search_parameters")?,
            "cpp_search_parameters.octree_search_parameters",
            cx,
        )?,
        id_name: r.str("id_name")?.to_owned(),
        create_auxiliar_conditions: !r.str("condition_name")?.is_empty(),
    })
}
