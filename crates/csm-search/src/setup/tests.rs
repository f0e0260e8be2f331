use serde_json::Value;

use super::defaults::{ALM_DEFAULTS, WRAPPER_DEFAULTS};
use super::*;
use crate::ErrorKind;

const MINIMAL: &str = r#"{
    "contact_model_part": {"0": ["Parts_Slave", "Parts_Master"]},
    "assume_master_slave": {"0": ["Parts_Slave"]}
}"#;

#[track_caller]
fn parse(text: &str) -> SearchSetup {
    parse_setup(text, "setup.json").unwrap_or_else(|e| panic!("{e}"))
}

#[track_caller]
fn parse_err(text: &str) -> crate::Error {
    parse_setup(text, "setup.json").expect_err("the setup should be rejected")
}

/// A setup with `search_parameters` replaced by `sp` and extra top-level keys.
fn with(sp: &str, extra: &str) -> String {
    format!(
        r#"{{ "contact_model_part": {{"0": ["S", "M"]}}, "assume_master_slave": {{"0": ["S"]}},
             "search_parameters": {sp} {extra} }}"#
    )
}

fn shared(name: &str) -> String {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/data/kratos-tests/"
    );
    std::fs::read_to_string(format!("{path}{name}")).expect("shared test parameters")
}

#[test]
fn defaults_are_valid_json_objects() {
    for text in [ALM_DEFAULTS, WRAPPER_DEFAULTS] {
        assert!(serde_json::from_str::<Value>(text).unwrap().is_object());
    }
}

#[test]
fn python_defaults_reach_the_cpp_process() {
    let s = parse(MINIMAL);
    assert_eq!(s.model_part_name, "Structure");
    assert_eq!(s.compatibility, Compatibility::Kratos);
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    let pair = &s.pairs[&0];
    assert_eq!(pair.parts, ["Parts_Slave", "Parts_Master"]);
    assert_eq!(pair.slaves, ["Parts_Slave"]);
    let p = &pair.search;
    assert_eq!(p.type_search, SearchTreeType::KdtreeInRadiusWithObb);
    assert_eq!(
        p.check_gap,
        CheckGap::MappingCheck,
        "check_mapping falls back to MappingCheck"
    );
    assert_eq!(p.normal_orientation_threshold, 0.1);
    assert_eq!(
        (p.allocation_size, p.bucket_size, p.search_factor),
        (1000, 4, 3.5)
    );
    assert!(p.predefined_master_slave && p.create_auxiliar_conditions && !p.simple_search);
    assert_eq!(p.id_name, "0");
    assert_eq!(p.octree.bounding_box_factor, 0.1);
    assert_eq!(
        p.octree.obb_intersection_type,
        ObbIntersectionType::SeparatingAxisTheorem
    );
    assert_eq!(s.active_check_factor, 0.01);
    assert_eq!(s.database_step_update, 1);
    assert_eq!(s.interval, (0.0, 1e30));
}

#[test]
fn string_aliases_give_the_same_enums() {
    for (a, b, want) in [
        ("InRadius", "in_radius", SearchTreeType::KdtreeInRadius),
        ("InBox", "in_box", SearchTreeType::KdtreeInBox),
        (
            "InBoxWithOBB",
            "in_box_with_obb",
            SearchTreeType::KdtreeInBoxWithObb,
        ),
        (
            "OctreeWithOBB",
            "octree_with_obb",
            SearchTreeType::OctreeWithObb,
        ),
    ] {
        for name in [a, b] {
            let s = parse(&with(&format!(r#"{{"type_search": "{name}"}}"#), ""));
            assert_eq!(s.pairs[&0].search.type_search, want, "{name}");
        }
    }
    for (name, want) in [
        ("NoCheck", CheckGap::NoCheck),
        ("direct_check", CheckGap::DirectCheck),
    ] {
        let s = parse(&with(&format!(r#"{{"check_gap": "{name}"}}"#), ""));
        assert_eq!(s.pairs[&0].search.check_gap, want);
    }
}

#[test]
fn silent_fallbacks_are_warned_and_strict_makes_them_errors() {
    let s = parse(&with(
        r#"{"type_search": "in_sphere", "check_gap": "gap?"}"#,
        "",
    ));
    assert_eq!(
        s.pairs[&0].search.type_search,
        SearchTreeType::KdtreeInRadius
    );
    assert_eq!(s.pairs[&0].search.check_gap, CheckGap::MappingCheck);
    assert_eq!(s.warnings.len(), 2, "{:?}", s.warnings);
    assert!(s.warnings[0].contains("in_sphere"));
    let e = parse_err(&with(
        r#"{"type_search": "in_sphere"}"#,
        r#", "strict": true"#,
    ));
    assert!(matches!(e.kind(), ErrorKind::Strict(_)), "{e}");
}

#[test]
fn fallback_warnings_name_their_pair() {
    let s = parse(
        r#"{ "contact_model_part": {"0": ["S", "M"], "1": ["A", "B"]},
             "assume_master_slave": {"0": ["S"], "1": ["A"]},
             "search_parameters": {"check_gap": "gap?"} }"#,
    );
    assert_eq!(
        s.warnings,
        [
            "pair 0: `search_parameters.check_gap`: unknown check_gap \"gap?\"; Kratos silently \
             uses MappingCheck",
            "pair 1: `search_parameters.check_gap`: unknown check_gap \"gap?\"; Kratos silently \
             uses MappingCheck",
        ]
    );
    let e = parse_err(&with(r#"{"check_gap": "gap?"}"#, r#", "strict": true"#));
    assert!(e.to_string().contains("pair 0: "), "{e}");
}

#[test]
fn keys_kratos_rejects_are_errors_with_the_line() {
    let text = "{\n \"contact_model_part\": {\"0\": [\"S\"]},\n \"search_parameters\": {\n  \"serch_factor\": 2.0\n }\n}";
    let e = parse_err(text);
    assert_eq!(
        e.kind(),
        &ErrorKind::UnknownKey {
            key: "search_parameters.serch_factor".into()
        }
    );
    assert_eq!(e.line(), Some(4));
    assert!(
        e.to_string()
            .starts_with("setup.json:4: expected a known setup key"),
        "{e}"
    );
    let e = parse_err(&with(r#"{"search_factor": "big"}"#, ""));
    assert!(matches!(e.kind(), ErrorKind::InvalidValue { .. }), "{e}");
    let e = parse_err(r#"{"contact_model_part": {"10": ["S"]}}"#);
    assert!(
        matches!(e.kind(), ErrorKind::UnknownKey { .. }),
        "only keys 0..9, as Kratos"
    );
    let e = parse_err(&with(r#"{"bucket_size": 0}"#, ""));
    assert!(e.to_string().contains("an integer ≥ 1"), "{e}");
    let e = parse_err("{\n \"contact_model_part\": \n");
    assert!(
        matches!(e.kind(), ErrorKind::Json(_)) && e.line().is_some(),
        "{e}"
    );
}

#[test]
fn keys_the_python_layer_drops_are_ignored_in_kratos_mode_and_honoured_in_robust() {
    let sp = r#"{"predict_correct_lagrange_multiplier": true,
                 "octree_search_parameters": {"bounding_box_factor": 0.5}}"#;
    let s = parse(&with(sp, ""));
    assert!(!s.pairs[&0].search.predict_correct_lagrange_multiplier);
    assert_eq!(s.pairs[&0].search.octree.bounding_box_factor, 0.1);
    assert_eq!(s.warnings.len(), 2, "{:?}", s.warnings);
    let s = parse(&with(sp, r#", "compatibility": "robust""#));
    assert!(s.pairs[&0].search.predict_correct_lagrange_multiplier);
    assert_eq!(s.pairs[&0].search.octree.bounding_box_factor, 0.5);
    assert_eq!(s.warnings.len(), 2);
}

#[test]
fn kdop_fails_as_in_kratos_unless_robust_or_kdop_18() {
    let e = parse_err(&with(r#"{"type_search": "KDOP"}"#, ""));
    assert!(matches!(e.kind(), ErrorKind::RejectedByKratos(_)), "{e}");
    let s = parse(&with(
        r#"{"type_search": "kdop"}"#,
        r#", "compatibility": "robust""#,
    ));
    assert_eq!(s.pairs[&0].search.type_search, SearchTreeType::Kdop);
    let s = parse(&with(r#"{"type_search": "kdop_18"}"#, ""));
    assert_eq!(s.pairs[&0].search.type_search, SearchTreeType::Kdop);
}

#[test]
fn cpp_search_parameters_use_the_wrapper_defaults() {
    let s = parse(&with(
        "{}",
        r#", "cpp_search_parameters": {"inverted_search": true, "simple_search": true}"#,
    ));
    let p = &s.pairs[&0].search;
    assert!(s.cpp_search_parameters);
    assert_eq!(p.type_search, SearchTreeType::KdtreeInRadius);
    assert_eq!(p.normal_orientation_threshold, 1e-8, "Q5");
    assert!(p.inverted_search && p.simple_search && !p.create_auxiliar_conditions);
    assert_eq!(p.id_name, "");
}

#[test]
fn csm_keys() {
    let s = parse(&with(
        "{}",
        r#", "process_info": {"DISTANCE_THRESHOLD": 2.5}, "nodal_h": 0.25, "strict": false"#,
    ));
    assert_eq!(s.process_info["DISTANCE_THRESHOLD"], 2.5);
    assert_eq!(s.nodal_h, Some(0.25));
    let e = parse_err(&with("{}", r#", "compatibility": "loose""#));
    assert!(e.to_string().contains("\"kratos\" or \"robust\""), "{e}");
    let e = parse_err(&with("{}", r#", "nodal_h": -1"#));
    assert!(e.to_string().contains("positive"), "{e}");
    let e = parse_err(&with("{}", r#", "steps": []"#));
    assert!(e.to_string().contains("a non-empty list of steps"), "{e}");
    // Every list empty: skin detection (pair 0, no part named yet).
    let s = parse(r#"{"contact_model_part": {"0": []}, "assume_master_slave": {"0": ["S"]}}"#);
    assert!(s.skin);
    assert!(s.pairs[&0].parts.is_empty() && s.pairs[&0].slaves == ["S"]);
    assert!(!parse(&with("{}", "")).skin);
}

#[test]
fn project_parameters_of_kratos_tests() {
    let s = parse(&shared(
        "3D_contact_simplest_patch_matching_triquad_test_parameters.json",
    ));
    assert_eq!(s.pairs.len(), 1);
    assert_eq!(s.pairs[&0].parts, ["DISPLACEMENT_Displacement_Auto3"]);
    assert_eq!(s.pairs[&0].slaves, ["Parts_Parts_Auto2"]);
    let s = parse(&shared("3D_multi_contact_test_parameters.json"));
    assert_eq!(s.pairs.len(), 2);
    assert_eq!(
        s.pairs[&1].parts,
        ["GENERIC_BottomMiddle", "GENERIC_TopLower"]
    );
    assert_eq!(s.pairs[&1].search.id_name, "1");
    // The older format (contact_model_part a string, search keys at the top) is rejected by
    // Kratos 10.4.4's validation, and so by csm.
    let e = parse_err(&shared("3D_contact_patch_nonmatching_test_parameters.json"));
    assert!(
        matches!(
            e.kind(),
            ErrorKind::InvalidValue { .. } | ErrorKind::UnknownKey { .. }
        ),
        "{e}"
    );
    let e = parse_err(r#"{"problem_data": {}, "processes": {"list": []}}"#);
    assert_eq!(e.kind(), &ErrorKind::NoContactProcess);
}

#[test]
fn explicit_penalty_defaults_to_the_octree() {
    let text = r#"{"processes": {"contact_process_list": [{
        "python_module": "explicit_penalty_contact_process",
        "Parameters": {"contact_model_part": {"0": ["S", "M"]}, "assume_master_slave": {"0": ["S"]}}
    }]}}"#;
    let s = parse(text);
    assert!(s.explicit);
    assert_eq!(
        s.pairs[&0].search.type_search,
        SearchTreeType::OctreeWithObb
    );
}

/// `steps` (DESIGN.md §3): typed, part-name order, rotation axis kept as given, centre
/// optional; `nodal_values`.
#[test]
fn steps_and_nodal_values() {
    let s = parse(&with(
        "{}",
        r#", "steps": [
            {"delta_time": 0.5},
            {"delta_time": 0.25, "move": {
                "Upper": {"translate": [1, 2, 3]},
                "A": {"rotate": {"axis": [0, 0, 2], "angle_deg": 90}}}}],
           "nodal_values": [{"part": "S", "variable": "ACCELERATION", "buffer": 1,
                             "value": [-9.81, 0, 0]}]"#,
    ));
    assert_eq!(s.steps.len(), 2);
    assert_eq!(s.steps[0].delta_time, 0.5);
    assert!(s.steps[0].moves.is_empty());
    let parts: Vec<&str> = s.steps[1].moves.iter().map(|m| m.part.as_str()).collect();
    assert_eq!(parts, ["A", "Upper"]);
    let r = s.steps[1].moves[0].motion.rotate.unwrap();
    assert_eq!((r.axis.z, r.angle_deg, r.centre.x), (2.0, 90.0, 0.0));
    // A quarter turn about z moves (1, 0, 0) to (0, 1, 0).
    let p = s.steps[1].moves[0]
        .motion
        .apply(&csm_geometry::math::Point::new(1.0, 0.0, 0.0));
    assert!((p.x).abs() < 1e-15 && (p.y - 1.0).abs() < 1e-15, "{p:?}");
    assert_eq!(s.steps[1].moves[1].motion.translate.y, 2.0);
    assert_eq!(s.nodal_values.len(), 1);
    assert_eq!(s.nodal_values[0].buffer, 1);
    assert_eq!(s.nodal_values[0].value.x, -9.81);
}

/// Bad step input is an error at the line of the offending entry, never a panic.
#[test]
fn bad_steps_name_the_entry_and_its_line() {
    let text = |step2: &str| {
        format!(
            "{{\n \"contact_model_part\": {{\"0\": [\"S\", \"M\"]}},\n \
             \"assume_master_slave\": {{\"0\": [\"S\"]}},\n \"steps\": [\n  \
             {{\"delta_time\": 1.0}},\n  {step2}\n ]\n}}\n"
        )
    };
    let cases = [
        (
            r#"{"delta_time": 0}"#,
            "`steps[1].delta_time`: expected a positive finite number",
        ),
        (r#"{"delta_time": -1}"#, "positive finite number"),
        (r#"{"delta_time": "1"}"#, "positive finite number"),
        (r#"{"move": {}}"#, "`steps[1]`: expected a `delta_time`"),
        (
            r#"{"delta_time": 1, "mvoe": {}}"#,
            "`steps[1].mvoe`: expected one of the keys",
        ),
        (
            r#"{"delta_time": 1, "move": {"S": {"translate": [1, 2]}}}"#,
            "`steps[1].move.S.translate`: expected a list of 3 finite numbers",
        ),
        (
            r#"{"delta_time": 1, "move": {"S": {"rotate": {"axis": [0, 0, 0], "angle_deg": 1}}}}"#,
            "a non-zero axis",
        ),
        (
            r#"{"delta_time": 1, "move": {"S": {"rotate": {"axis": [0, 0, 1]}}}}"#,
            "`steps[1].move.S.rotate.angle_deg`: expected a finite number",
        ),
        (
            r#"{"delta_time": 1, "move": ["S"]}"#,
            "`steps[1].move`: expected an object",
        ),
        ("7", "`steps[1]`: expected an object"),
    ];
    for (step, expected) in cases {
        let e = parse_err(&text(step));
        let message = e.to_string();
        assert!(message.starts_with("setup.json:6: "), "{step}: {message}");
        assert!(message.contains(expected), "{step}: {message}");
    }
    // NaN is not JSON: the parser's error, with its line.
    let e = parse_err(&text(r#"{"delta_time": NaN}"#));
    assert!(e.to_string().starts_with("setup.json:6:"), "{e}");
    let e = parse_err(&with("{}", r#", "steps": {"delta_time": 1}"#));
    assert!(e.to_string().contains("a non-empty list of steps"), "{e}");
    let e = parse_err(&with(
        "{}",
        r#", "nodal_values": [{"part": "S", "variable": "NORMAL", "value": [0, 0, 1]}]"#,
    ));
    assert!(e.to_string().contains("`nodal_values[0].variable`"), "{e}");
}

#[test]
fn mpc_parameters_search_with_the_base_class() {
    let project = r#"{ "processes": { "contact_process_list": [{
        "python_module": "mpc_contact_process",
        "Parameters": { "contact_model_part": {"0": ["S", "M"]},
                        "assume_master_slave": {"0": ["S"]},
                        "contact_type": "MeshTying",
                        "update_condition_relation_step": true,
                        "search_parameters": {"simple_search": false} } }] } }"#;
    let s = parse(project);
    assert_eq!(s.process, ContactProcess::Mpc);
    // MPC's own default, not ALM's 1.0; and the wrapper drops simple_search.
    assert_eq!(s.zero_tolerance_factor, 100.0);
    assert!(s.pairs[&0].search.simple_search);
    assert!(s.process.renumbers_conditions());
    // The same Parameters as a bare object need csm's `process` key; ALM rejects MPC's keys.
    let bare = r#"{ "contact_model_part": {"0": ["S", "M"]}, "assume_master_slave": {"0": ["S"]},
                    "update_condition_relation_step": true }"#;
    assert!(matches!(
        parse_err(bare).kind(),
        ErrorKind::UnknownKey { .. }
    ));
    let with_key = bare.replacen('{', r#"{ "process": "mpc_contact_process","#, 1);
    assert_eq!(parse(&with_key).process, ContactProcess::Mpc);
    let e = parse_err(&bare.replacen('{', r#"{ "process": "mpc","#, 1));
    assert!(e.to_string().contains("mesh_tying_process"), "{e}");
}

#[test]
fn mesh_tying_parameters_keep_kratos_defaults_and_ids() {
    let s = parse(
        r#"{ "mesh_tying_model_part": {"0": ["S", "M"]}, "assume_master_slave": {"0": ["S"]} }"#,
    );
    assert_eq!(s.process, ContactProcess::MeshTying);
    assert!(!s.process.renumbers_conditions());
    assert_eq!(s.pairs[&0].parts, ["S", "M"]);
    // Its own search_parameters default: one search only.
    assert_eq!(s.database_step_update, 999_999_999);
    assert!(s.consider_tessellation);
    // A search_parameters object the user gives is completed by the base defaults (not
    // validated against the mesh tying's, whose keys it lacks).
    let s = parse(
        r#"{ "mesh_tying_model_part": {"0": ["S", "M"]}, "assume_master_slave": {"0": ["S"]},
             "search_parameters": {"simple_search": true} }"#,
    );
    assert_eq!(s.database_step_update, 1);
    assert!(s.pairs[&0].search.simple_search);
    let e =
        parse_err(r#"{ "mesh_tying_model_part": {"0": ["S"]}, "contact_type": "Frictionless" }"#);
    assert!(matches!(e.kind(), ErrorKind::UnknownKey { .. }), "{e}");
}
