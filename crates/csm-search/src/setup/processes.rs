//! The Parameters of the contact processes other than ALM (MPCContactProcess,
//! MeshTyingProcess), validated as Kratos validates them and read as the ALM parameters they
//! share the search keys with.

use serde_json::{Map, Value};

use super::defaults::{MESH_TYING_DEFAULTS, MPC_DEFAULTS};
use super::parse::defaults;
use super::validate::{validate_and_fill, validate_top_level_and_fill};
use crate::error::Error;

/// The keys `SearchBaseProcess` takes from a contact process (`base_process_settings`), besides
/// the part lists and property ids.
const BASE_KEYS: [&str; 7] = [
    "model_part_name",
    "assume_master_slave",
    "interval",
    "zero_tolerance_factor",
    "integration_order",
    "consider_tessellation",
    "normal_check_proportion",
];

/// `MPCContactProcess`' parameters: validated recursively against its defaults (unknown keys
/// rejected as Kratos does), then the keys the search reads, as ALM parameters. Its
/// `contact_type` `"MeshTying"` (mesh tying through constraints) searches as frictionless.
pub(super) fn mpc_as_alm(mut params: Map<String, Value>) -> Result<Map<String, Value>, Error> {
    validate_and_fill(&mut params, &defaults(MPC_DEFAULTS), "")?;
    let mut alm = Map::new();
    for key in BASE_KEYS.iter().chain(&[
        "contact_model_part",
        "contact_property_ids",
        "search_parameters",
    ]) {
        if let Some(v) = params.remove(*key) {
            alm.insert((*key).to_owned(), v);
        }
    }
    let contact_type = match params.remove("contact_type") {
        Some(Value::String(t)) if t == "MeshTying" => Value::String("Frictionless".to_owned()),
        Some(v) => v,
        None => Value::String("Frictionless".to_owned()),
    };
    alm.insert("contact_type".to_owned(), contact_type);
    Ok(alm)
}

/// `MeshTyingProcess`' parameters: validated against its defaults without recursion, as
/// Kratos does (a `search_parameters` object the user gives is kept whole; the ALM
/// validation then completes it with the base defaults), then read as ALM parameters:
/// `mesh_tying_model_part` and `mesh_tying_property_ids` are the part lists and property ids.
pub(super) fn mesh_tying_as_alm(
    mut params: Map<String, Value>,
) -> Result<Map<String, Value>, Error> {
    validate_top_level_and_fill(&mut params, &defaults(MESH_TYING_DEFAULTS))?;
    let mut alm = Map::new();
    for key in BASE_KEYS.iter().chain(&["search_parameters"]) {
        if let Some(v) = params.remove(*key) {
            alm.insert((*key).to_owned(), v);
        }
    }
    if let Some(v) = params.remove("mesh_tying_model_part") {
        alm.insert("contact_model_part".to_owned(), v);
    }
    if let Some(v) = params.remove("mesh_tying_property_ids") {
        alm.insert("contact_property_ids".to_owned(), v);
    }
    alm.insert(
        "contact_type".to_owned(),
        Value::String("Frictionless".to_owned()),
    );
    Ok(alm)
}
