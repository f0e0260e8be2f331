//! Kratos' `RecursivelyValidateAndAssignDefaults`: every given key must exist in the defaults
//! with a value of the same JSON type (all numbers are one type, as in Kratos), and missing
//! keys take the default.

use serde_json::{Map, Value};

use crate::error::{Error, ErrorKind};

fn type_name(v: &Value) -> &'static str {
    match v {
        Value::Null => "null",
        Value::Bool(_) => "a boolean",
        Value::Number(_) => "a number",
        Value::String(_) => "a string",
        Value::Array(_) => "an array",
        Value::Object(_) => "an object",
    }
}

fn same_type(a: &Value, b: &Value) -> bool {
    std::mem::discriminant(a) == std::mem::discriminant(b)
}

/// Kratos' `ValidateAndAssignDefaults` (no recursion): the top-level keys of `given` are
/// checked and completed; the values of object keys the user gave are kept as they are.
pub(crate) fn validate_top_level_and_fill(
    given: &mut Map<String, Value>,
    defaults: &Map<String, Value>,
) -> Result<(), Error> {
    for (key, value) in given.iter() {
        let Some(default) = defaults.get(key) else {
            return Err(ErrorKind::UnknownKey { key: key.clone() }.into());
        };
        if !same_type(value, default) {
            return Err(ErrorKind::InvalidValue {
                key: key.clone(),
                expected: type_name(default).to_owned(),
                found: format!("{} ({value})", type_name(value)),
            }
            .into());
        }
    }
    for (key, default) in defaults {
        given.entry(key.clone()).or_insert_with(|| default.clone());
    }
    Ok(())
}

/// Validates `given` against `defaults` and fills the missing keys, recursively. `path` is
/// the dotted prefix used in errors.
pub(crate) fn validate_and_fill(
    given: &mut Map<String, Value>,
    defaults: &Map<String, Value>,
    path: &str,
) -> Result<(), Error> {
    let join = |key: &str| {
        if path.is_empty() {
            key.to_owned()
        } else {
            format!("{path}.{key}")
        }
    };
    for (key, value) in given.iter_mut() {
        let Some(default) = defaults.get(key) else {
            return Err(ErrorKind::UnknownKey { key: join(key) }.into());
        };
        if !same_type(value, default) {
            return Err(ErrorKind::InvalidValue {
                key: join(key),
                expected: type_name(default).to_owned(),
                found: format!("{} ({value})", type_name(value)),
            }
            .into());
        }
        if let (Value::Object(inner), Value::Object(inner_defaults)) = (value, default) {
            validate_and_fill(inner, inner_defaults, &join(key))?;
        }
    }
    for (key, default) in defaults {
        if !given.contains_key(key) {
            given.insert(key.clone(), default.clone());
        }
    }
    Ok(())
}
