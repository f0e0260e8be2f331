//! Stage 1 against Kratos' `GenerateInterfacePart` on the Kratos test meshes.

use csm_model::{Flag, ModelPart, PropertyValue};
use csm_search::{Compatibility, ErrorKind, InterfaceSettings, generate_interface_conditions};
use serde_json::{Value, json};

use crate::{build_model, fixture, ids, tri};

/// Every root condition as the fixture writes it.
fn conditions_json(m: &ModelPart) -> Vec<Value> {
    let c = m.conditions();
    (0..c.len())
        .map(|i| {
            let nodes: Vec<u32> = c
                .nodes(i)
                .iter()
                .map(|n| m.nodes().ids()[n.index()])
                .collect();
            json!({
                "geometry": c.kind(i).name(),
                "id": c.ids()[i],
                "master": tri(&c.flags()[i], Flag::MASTER),
                "nodes": nodes,
                "properties": c.properties(i).0,
                "slave": tri(&c.flags()[i], Flag::SLAVE),
            })
        })
        .collect()
}

fn properties_json(m: &ModelPart) -> Value {
    let mut out = serde_json::Map::new();
    for (id, p) in m.properties() {
        let mut vals = serde_json::Map::new();
        for (name, v) in &p.values {
            if let PropertyValue::Number(x) = v {
                vals.insert(name.clone(), json!(x));
            }
        }
        out.insert(id.0.to_string(), Value::Object(vals));
    }
    Value::Object(out)
}

#[track_caller]
fn check_mesh(name: &str) {
    let fx = fixture(&format!("interface/{name}.json"));
    for simplify in [false, true] {
        let mut m = build_model(&fx["input"]);
        let part = m.create_part(fx["part"].as_str().unwrap()).unwrap();
        let nodes: Vec<_> = ids(&fx["input"]["part_nodes"])
            .into_iter()
            .map(|id| m.nodes().index_of(id).unwrap())
            .collect();
        m.add_nodes_to_part(part, &nodes);
        let settings = InterfaceSettings {
            simplify_geometry: simplify,
            ..Default::default()
        };
        let report = generate_interface_conditions(&mut m, part, &settings).unwrap();
        let expect = &fx[format!("simplify_{simplify}")];
        assert_eq!(
            Value::Array(conditions_json(&m)),
            expect["conditions"],
            "{name}, simplify {simplify}"
        );
        let part_ids: Vec<u32> = m
            .part(part)
            .conditions()
            .iter()
            .map(|c| m.conditions().ids()[c.index()])
            .collect();
        assert_eq!(
            part_ids,
            ids(&expect["part_conditions"]),
            "{name}, simplify {simplify}"
        );
        assert_eq!(
            properties_json(&m),
            expect["properties"],
            "{name}, simplify {simplify}"
        );
        assert_eq!(
            report.created.len(),
            expect["part_conditions"].as_array().unwrap().len()
        );
    }
}

// See: Kratos ALM_frictionless_contact_test_3D/3D_contact_patch_nonmatching_test.
#[test]
fn nonmatching_patch_as_kratos() {
    check_mesh("3D_contact_patch_nonmatching_test");
}

// See: Kratos ALM_frictionless_contact_test_3D/3D_contact_simplest_patch_matching_triquad_test.
#[test]
fn triquad_patch_as_kratos() {
    check_mesh("3D_contact_simplest_patch_matching_triquad_test");
}

/// Kratos re-creates a fixed `contact_property_id` per element and fails on the second one,
/// after creating the first element's condition.
#[test]
fn fixed_contact_property_fails_as_kratos() {
    let fx = fixture("interface/contact_property_id.json");
    let base = fixture("interface/3D_contact_simplest_patch_matching_triquad_test.json");
    let mut m = build_model(&base["input"]);
    let part = m.create_part(fx["part"].as_str().unwrap()).unwrap();
    let nodes: Vec<_> = ids(&base["input"]["part_nodes"])
        .into_iter()
        .map(|id| m.nodes().index_of(id).unwrap())
        .collect();
    m.add_nodes_to_part(part, &nodes);
    let settings = InterfaceSettings {
        contact_property_id: fx["contact_property_id"].as_u64().unwrap() as u32,
        ..Default::default()
    };
    let e = generate_interface_conditions(&mut m, part, &settings).unwrap_err();
    assert!(matches!(e.kind(), ErrorKind::RejectedByKratos(_)), "{e}");
    assert_eq!(
        Value::Array(conditions_json(&m)),
        fx["result"]["conditions_before_error"]
    );
    // Robust mode: one property, every face.
    let mut m = build_model(&base["input"]);
    let part = m.create_part("P").unwrap();
    m.add_nodes_to_part(part, &nodes);
    let settings = InterfaceSettings {
        compatibility: Compatibility::Robust,
        ..settings
    };
    let r = generate_interface_conditions(&mut m, part, &settings).unwrap();
    assert_eq!(r.created.len(), 3);
}

/// Robust mode on the non-matching patch: no duplicates there, ids kept, so the conditions
/// are Kratos' except for the flag left undefined by Kratos.
#[test]
fn robust_mode_on_nonmatching_patch() {
    let fx = fixture("interface/3D_contact_patch_nonmatching_test.json");
    let mut m = build_model(&fx["input"]);
    let part = m.create_part("Contact_Part").unwrap();
    let nodes: Vec<_> = ids(&fx["input"]["part_nodes"])
        .into_iter()
        .map(|id| m.nodes().index_of(id).unwrap())
        .collect();
    m.add_nodes_to_part(part, &nodes);
    let settings = InterfaceSettings {
        compatibility: Compatibility::Robust,
        ..Default::default()
    };
    let r = generate_interface_conditions(&mut m, part, &settings).unwrap();
    let expect = fx["simplify_false"]["conditions"].as_array().unwrap();
    let got = conditions_json(&m);
    for (g, e) in got.iter().zip(expect).skip(64) {
        assert_eq!(g["id"], e["id"]);
        assert_eq!(g["nodes"], e["nodes"]);
        let slave = e["slave"] == json!(true);
        assert_eq!(g["slave"], json!(slave));
        assert_eq!(g["master"], json!(!slave));
    }
    assert_eq!(r.skipped_duplicates, 0);
}
