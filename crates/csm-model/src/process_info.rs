//! Process info (Kratos `ProcessInfo`): global values of the current step.

use std::collections::BTreeMap;

use crate::PropertyValue;

/// Global values of the simulation state, by Kratos variable name (`DOMAIN_SIZE`, `STEP`,
/// `TIME`, `DELTA_TIME`, `DISTANCE_THRESHOLD`, …).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ProcessInfo {
    values: BTreeMap<String, PropertyValue>,
}

impl ProcessInfo {
    /// An empty process info.
    pub fn new() -> ProcessInfo {
        ProcessInfo::default()
    }

    /// Sets a numeric value.
    pub fn set_number(&mut self, name: &str, value: f64) {
        self.values
            .insert(name.to_owned(), PropertyValue::Number(value));
    }

    /// Sets any value.
    pub fn set(&mut self, name: &str, value: PropertyValue) {
        self.values.insert(name.to_owned(), value);
    }

    /// The numeric value of `name`, if set and a number.
    pub fn number(&self, name: &str) -> Option<f64> {
        match self.values.get(name) {
            Some(PropertyValue::Number(x)) => Some(*x),
            _ => None,
        }
    }

    /// The value of `name`, if set.
    pub fn get(&self, name: &str) -> Option<&PropertyValue> {
        self.values.get(name)
    }

    /// True if `name` is set.
    pub fn has(&self, name: &str) -> bool {
        self.values.contains_key(name)
    }

    /// All values, in name order.
    pub fn iter(&self) -> impl Iterator<Item = (&str, &PropertyValue)> {
        self.values.iter().map(|(k, v)| (k.as_str(), v))
    }
}
