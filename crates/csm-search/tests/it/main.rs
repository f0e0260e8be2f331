//! Integration tests of csm-search: stages checked against Kratos 10.4.4 fixtures
//! (`tests/fixtures/`, made by `tools/kratos_fixtures_interface.py`). The fixtures carry their
//! input models, so no mesh reader is needed (csm-search may not depend on csm-io).

mod interface_preprocess;
mod normal_check;

use std::path::PathBuf;

use csm_geometry::GeometryKind;
use csm_geometry::math::Point;
use csm_model::{
    ConditionId, ElementId, Flag, ModelPart, NodeId, Properties, PropertiesId, PropertyValue,
};
use serde_json::Value;

/// The parsed fixture `tests/fixtures/<rel>` of the workspace.
pub fn fixture(rel: &str) -> Value {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../tests/fixtures")
        .join(rel);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap()
}

pub fn kind(name: &str) -> GeometryKind {
    *GeometryKind::ALL
        .iter()
        .find(|k| k.name() == name)
        .unwrap_or_else(|| panic!("{name}"))
}

pub fn ids(v: &Value) -> Vec<u32> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_u64().unwrap() as u32)
        .collect()
}

pub fn flag(name: &str) -> Flag {
    match name {
        "INTERFACE" => Flag::INTERFACE,
        "SLAVE" => Flag::SLAVE,
        "MASTER" => Flag::MASTER,
        "MARKER" => Flag::MARKER,
        _ => panic!("{name}"),
    }
}

/// Rebuilds the model a fixture's `input` describes.
pub fn build_model(input: &Value) -> ModelPart {
    let mut m = ModelPart::new("Structure");
    m.process_info_mut()
        .set_number("DOMAIN_SIZE", input["domain_size"].as_f64().unwrap());
    for n in input["nodes"].as_array().unwrap() {
        let c: Vec<f64> = (1..4).map(|k| n[k].as_f64().unwrap()).collect();
        m.add_node(
            NodeId(n[0].as_u64().unwrap() as u32),
            Point::new(c[0], c[1], c[2]),
        )
        .unwrap();
    }
    for (id, flags) in input["node_flags"].as_object().unwrap() {
        let i = m.nodes().index_of(id.parse().unwrap()).unwrap();
        for (name, value) in flags.as_object().unwrap() {
            m.nodes_mut().flags_mut()[i.index()].set(flag(name), value.as_bool().unwrap());
        }
    }
    for (id, values) in input["properties"].as_object().unwrap() {
        let mut p = Properties::new(PropertiesId(id.parse().unwrap()));
        for (name, value) in values.as_object().unwrap() {
            p.values
                .insert(name.clone(), PropertyValue::Number(value.as_f64().unwrap()));
        }
        m.add_properties(p).unwrap();
    }
    for e in input["elements"].as_array().unwrap() {
        let nodes: Vec<NodeId> = ids(&e[3]).into_iter().map(NodeId).collect();
        let props = PropertiesId(e[2].as_u64().unwrap() as u32);
        m.add_element(
            ElementId(e[0].as_u64().unwrap() as u32),
            kind(e[1].as_str().unwrap()),
            "",
            &nodes,
            props,
        )
        .unwrap();
    }
    for c in input["conditions"].as_array().unwrap() {
        let nodes: Vec<NodeId> = ids(&c[3]).into_iter().map(NodeId).collect();
        let props = PropertiesId(c[2].as_u64().unwrap() as u32);
        m.add_condition(
            ConditionId(c[0].as_u64().unwrap() as u32),
            kind(c[1].as_str().unwrap()),
            "",
            &nodes,
            props,
        )
        .unwrap();
    }
    for (key, conditions) in [("element_flags", false), ("condition_flags", true)] {
        for (id, flags) in input[key].as_object().unwrap() {
            let id: u32 = id.parse().unwrap();
            let e = if conditions {
                m.conditions()
            } else {
                m.elements()
            };
            let i = e.index_of(id).unwrap();
            for (name, value) in flags.as_object().unwrap() {
                let e = if conditions {
                    m.conditions_mut()
                } else {
                    m.elements_mut()
                };
                e.flags_mut()[i].set(flag(name), value.as_bool().unwrap());
            }
        }
    }
    m
}

/// Kratos' tri-state flag as JSON (null = undefined).
pub fn tri(f: &csm_model::Flags, flag: Flag) -> Value {
    f.get(flag).map_or(Value::Null, Value::Bool)
}
