//! The plan's decisions on small models built in code. That the pipeline follows the plan is
//! tested in `pipeline/tests.rs`; the plans of the fixture scenes in the facade's
//! `tests/it/cli_plan.rs`.

use csm_geometry::GeometryKind;
use csm_geometry::math::{Point, Vector};
use csm_model::{ConditionId, ModelPart, NodeId, NodeIdx, PropertiesId, VectorVar};

use super::*;
use crate::{CheckGap, ErrorKind, ObbIntersectionType, SearchTreeType, parse_setup};

/// Two facing triangles 0.1 apart, the parts `Slave` (above, facing down) and `Master`; no
/// elements.
fn triangles() -> ModelPart {
    let mut m = ModelPart::new("Structure");
    let corners = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)];
    for (k, z) in [0.1, 0.0].into_iter().enumerate() {
        for (i, (x, y)) in corners.iter().enumerate() {
            m.add_node(NodeId((3 * k + i + 1) as u32), Point::new(*x, *y, z))
                .unwrap();
        }
    }
    for (k, (name, nodes)) in [("Slave", [1, 3, 2]), ("Master", [4, 5, 6])]
        .into_iter()
        .enumerate()
    {
        let part = m.create_part(name).unwrap();
        let ids: Vec<NodeId> = nodes.iter().map(|&n| NodeId(n)).collect();
        let c = m
            .add_condition(
                ConditionId(k as u32 + 1),
                GeometryKind::Triangle3D3,
                "SurfaceCondition3D3N",
                &ids,
                PropertiesId(0),
            )
            .unwrap();
        let nodes: Vec<NodeIdx> = nodes
            .iter()
            .map(|&n| m.nodes().index_of(n).unwrap())
            .collect();
        m.add_nodes_to_part(part, &nodes);
        m.add_conditions_to_part(part, &[c]);
    }
    m
}

fn setup(search_parameters: &str) -> crate::SearchSetup {
    let text = format!(
        r#"{{"contact_model_part": {{"0": ["Slave", "Master"]}},
            "assume_master_slave": {{"0": ["Slave"]}},
            "search_parameters": {search_parameters}}}"#
    );
    parse_setup(&text, "setup.json").unwrap()
}

#[track_caller]
fn check(search_parameters: &str) -> Plan {
    Plan::new(&triangles(), &setup(search_parameters)).unwrap()
}

#[test]
fn defaults_use_the_kd_tree_with_obbs_and_the_advanced_mapping() {
    let plan = check("{}");
    assert_eq!(plan.domain_size, 3);
    assert_eq!(plan.contact_parts, Decision::Used(()));
    assert_eq!(
        plan.normal_check,
        Decision::Used(NormalCheck::NormalsOnly),
        "no solid elements"
    );
    assert_eq!(
        plan.master_slave_from_nodes,
        Decision::LeftOut(Reason::NoContactPartInMesh)
    );
    let p = &plan.pairs[&0];
    assert_eq!(p.slave_parts, ["Slave"]);
    assert_eq!(p.master_parts, ["Master"]);
    assert_eq!(p.kd_tree, Decision::Used(KdQuery::Radius));
    assert_eq!(
        p.octree,
        Decision::LeftOut(Reason::TypeSearch(SearchTreeType::KdtreeInRadiusWithObb))
    );
    assert_eq!(
        p.obb_test,
        Decision::Used(ObbIntersectionType::SeparatingAxisTheorem)
    );
    assert_eq!(p.step_jump, Decision::LeftOut(Reason::DynamicSearchOff));
    assert!(p.mortar_mapping.is_used() && p.weighted_gap.is_used());
    assert_eq!(
        p.activation,
        Decision::Used(Activation::Advanced {
            static_check_movement: false
        })
    );
    let storage = |name: &str| plan.variable(name).unwrap().storage.clone();
    assert_eq!(storage("DISPLACEMENT"), Decision::LeftOut(Reason::NotRead));
    assert_eq!(
        storage("VELOCITY"),
        Decision::LeftOut(Reason::NoDynamicPair)
    );
    assert_eq!(storage("NORMAL"), Decision::Used(Storage::Current));
    assert_eq!(storage("WEIGHTED_GAP"), Decision::Used(Storage::Current));
    assert_eq!(storage("NORMAL_GAP"), Decision::Used(Storage::Plain));
    assert_eq!(
        storage("LAGRANGE_MULTIPLIER_CONTACT_PRESSURE"),
        Decision::LeftOut(Reason::NoMultiplierValues)
    );
}

#[test]
fn the_octree_search_builds_no_kd_tree() {
    let p = &check(r#"{"type_search": "octree_with_obb"}"#).pairs[&0];
    assert_eq!(
        p.kd_tree,
        Decision::LeftOut(Reason::TypeSearch(SearchTreeType::OctreeWithObb))
    );
    assert!(p.octree.is_used() && p.obb_test.is_used());
    // The Python layer drops `octree_search_parameters`; the C++ parameters keep them.
    let text = r#"{"contact_model_part": {"0": ["Slave", "Master"]},
        "assume_master_slave": {"0": ["Slave"]},
        "cpp_search_parameters": {"type_search": "OctreeWithOBB",
            "octree_search_parameters": {"bounding_box_factor": 0.0}}}"#;
    let plan = Plan::new(&triangles(), &parse_setup(text, "setup.json").unwrap()).unwrap();
    let p = &plan.pairs[&0];
    assert_eq!(p.obb_test, Decision::LeftOut(Reason::NoBoundingBoxFactor));
    assert_eq!(
        plan.interface,
        Decision::LeftOut(Reason::CppSearchParameters)
    );
    assert_eq!(
        plan.normal_check,
        Decision::LeftOut(Reason::CppSearchParameters)
    );
}

#[test]
fn no_check_leaves_out_mapping_weighted_gap_and_activation() {
    let plan = check(r#"{"check_gap": "no_check", "type_search": "in_box"}"#);
    let p = &plan.pairs[&0];
    let gap = Decision::LeftOut(Reason::CheckGap(CheckGap::NoCheck));
    assert_eq!(p.mortar_mapping, gap);
    assert_eq!(p.weighted_gap, gap.clone());
    assert_eq!(
        p.activation,
        Decision::LeftOut(Reason::CheckGap(CheckGap::NoCheck))
    );
    assert_eq!(p.kd_tree, Decision::Used(KdQuery::Box));
    assert_eq!(
        p.obb_test,
        Decision::LeftOut(Reason::TypeSearch(SearchTreeType::KdtreeInBox))
    );
    assert_eq!(
        plan.variable("NORMAL_GAP").unwrap().storage,
        Decision::LeftOut(Reason::NoMappingCheck)
    );
    assert_eq!(
        plan.variable("WEIGHTED_GAP").unwrap().storage,
        Decision::LeftOut(Reason::NoAdvancedActivation)
    );
}

#[test]
fn the_simple_activation_needs_no_weighted_gap() {
    let plan = check(r#"{"simple_search": true}"#);
    let p = &plan.pairs[&0];
    assert_eq!(p.weighted_gap, Decision::LeftOut(Reason::SimpleActivation));
    assert_eq!(p.activation, Decision::Used(Activation::Simple));
    assert!(!plan.variable("WEIGHTED_GAP").unwrap().storage.is_used());
    let plan = check(r#"{"static_check_movement": true}"#);
    assert_eq!(
        plan.variable("WEIGHTED_GAP").unwrap().storage,
        Decision::Used(Storage::WithHistory)
    );
}

#[test]
fn the_step_jump_needs_dynamic_search_and_velocities() {
    let dynamic = setup(r#"{"dynamic_search": true}"#);
    let params = &dynamic.pairs[&0].search;
    let mut model = triangles();
    let nodes: Vec<NodeIdx> = (0..6).map(NodeIdx).collect();
    assert_eq!(
        step_jump(params, &model, &nodes),
        Decision::LeftOut(Reason::NoVelocities),
        "no VELOCITY at all"
    );
    model.nodal_data_mut().add_vector(VectorVar::Velocity);
    model.nodal_data_mut().add_vector(VectorVar::Acceleration);
    assert_eq!(
        step_jump(params, &model, &nodes),
        Decision::LeftOut(Reason::NoVelocities),
        "zero VELOCITY"
    );
    // The current acceleration is not read; the previous one is.
    model
        .nodal_data_mut()
        .vector_mut(VectorVar::Acceleration, 0)
        .unwrap()[4] = Vector::new(1.0, 0.0, 0.0);
    assert!(!step_jump(params, &model, &nodes).is_used());
    model
        .nodal_data_mut()
        .vector_mut(VectorVar::Acceleration, 1)
        .unwrap()[4] = Vector::new(1.0, 0.0, 0.0);
    model
        .nodal_data_mut()
        .vector_mut(VectorVar::Velocity, 0)
        .unwrap()[1] = Vector::new(0.0, 0.0, -1.0);
    assert_eq!(
        step_jump(params, &model, &nodes),
        Decision::Used(StepJump {
            moving_nodes: 2,
            moves_nodes: true
        })
    );
    assert!(
        !step_jump(params, &model, &nodes[2..4]).is_used(),
        "only the pair's nodes count"
    );
    let static_setup = setup("{}");
    assert_eq!(
        step_jump(&static_setup.pairs[&0].search, &model, &nodes),
        Decision::LeftOut(Reason::DynamicSearchOff)
    );
}

#[test]
fn an_unknown_part_is_the_error_the_search_gives() {
    let text = r#"{"contact_model_part": {"0": ["Slave", "Nowhere"]}}"#;
    let s = parse_setup(text, "setup.json").unwrap();
    let e = Plan::new(&triangles(), &s).unwrap_err();
    assert!(matches!(e.kind(), ErrorKind::InvalidValue { .. }), "{e}");
    assert_eq!(e.file(), Some("setup.json"));
    assert_eq!(e.line(), Some(1));
    let mut model = triangles();
    let search_error = crate::ContactSearch::initialize(&mut model, &s).unwrap_err();
    assert_eq!(e, search_error);
}

#[test]
fn text_and_json_say_the_same() {
    let plan = check(r#"{"type_search": "octree_with_obb", "check_gap": "direct_check"}"#);
    let text = plan.to_string();
    assert!(
        text.contains("  - kd-tree: not built — type_search octree_with_obb\n"),
        "{text}"
    );
    assert!(text.contains("  - normal check (stage 2): skipped — no solid elements"));
    let json = plan.to_json();
    assert_eq!(json["format"], "csm-plan/1");
    let stages = json["pairs"]["0"]["stages"].as_array().unwrap();
    let kd = stages.iter().find(|s| s["id"] == "kd_tree").unwrap();
    assert_eq!(kd["used"], false);
    assert_eq!(kd["why"], "not built — type_search octree_with_obb");
    let octree = stages.iter().find(|s| s["id"] == "octree").unwrap();
    assert_eq!(octree["used"], true);
    assert!(octree["what"].is_string());
    // Every item of the JSON is a line of the text.
    for section in [
        &json["initialize"],
        &json["variables"],
        &json["pairs"]["0"]["stages"],
    ] {
        for i in section.as_array().unwrap() {
            let sign = if i["used"] == true { '+' } else { '-' };
            let said = i.get("what").or_else(|| i.get("why")).unwrap();
            let line = format!(
                "  {sign} {}: {}\n",
                i["name"].as_str().unwrap(),
                said.as_str().unwrap()
            );
            assert!(text.contains(&line), "{line:?} not in\n{text}");
        }
    }
}

/// `steps` move parts: the plan lists them, and DISPLACEMENT, VELOCITY and ACCELERATION are
/// kept with history even without a dynamic pair; without steps they are left out.
#[test]
fn steps_allocate_the_motion_variables() {
    let text = r#"{"contact_model_part": {"0": ["Slave", "Master"]},
        "assume_master_slave": {"0": ["Slave"]},
        "steps": [{"delta_time": 1, "move": {"Slave": {"translate": [0, 0, -0.01]}}},
                  {"delta_time": 1, "move": {"Slave": {"translate": [0, 0, -0.01]}}
                   }]}"#;
    let s = parse_setup(text, "setup.json").unwrap();
    let plan = Plan::new(&triangles(), &s).unwrap();
    assert_eq!(
        plan.steps,
        Decision::Used(StepsPlan {
            count: 2,
            moved_parts: vec!["Slave".to_owned()],
            refit_tree: true,
        })
    );
    for name in ["DISPLACEMENT", "VELOCITY", "ACCELERATION"] {
        assert_eq!(
            plan.variable(name).unwrap().storage,
            Decision::Used(Storage::WithHistory),
            "{name}"
        );
    }
    assert!(
        plan.to_string()
            .contains("2 search steps; rigid motions of `Slave`")
    );
    assert!(plan.to_string().contains("kd-trees refitted between steps"));
    let rebuilt = text.replacen('{', r#"{"refit_tree": false, "#, 1);
    let plan = Plan::new(&triangles(), &parse_setup(&rebuilt, "setup.json").unwrap()).unwrap();
    assert!(plan.to_string().contains("kd-trees rebuilt every step"));
    let plan = check("{}");
    assert_eq!(plan.steps, Decision::LeftOut(Reason::NoSteps));
    assert_eq!(
        plan.variable("DISPLACEMENT").unwrap().storage,
        Decision::LeftOut(Reason::NotRead)
    );
}
