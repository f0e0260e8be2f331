//! Properties blocks (Kratos `Properties`): material values shared by entities.

use std::collections::BTreeMap;

use crate::PropertiesId;

/// One value of a properties block or of the process info.
#[derive(Debug, Clone, PartialEq)]
pub enum PropertyValue {
    /// A number.
    Number(f64),
    /// A vector or list of numbers.
    Vector(Vec<f64>),
    /// A string (or any value csm keeps verbatim).
    Text(String),
}

/// A properties block: an id and named values (e.g. `YOUNG_MODULUS`).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Properties {
    /// The id, as in the file.
    pub id: PropertiesId,
    /// Values by variable name, in name order.
    pub values: BTreeMap<String, PropertyValue>,
}

impl Properties {
    /// An empty properties block.
    pub fn new(id: PropertiesId) -> Properties {
        Properties {
            id,
            values: BTreeMap::new(),
        }
    }

    /// The numeric value of `name`, if present and a number.
    pub fn number(&self, name: &str) -> Option<f64> {
        match self.values.get(name) {
            Some(PropertyValue::Number(x)) => Some(*x),
            _ => None,
        }
    }

    /// True if `name` has a value.
    pub fn has(&self, name: &str) -> bool {
        self.values.contains_key(name)
    }
}
