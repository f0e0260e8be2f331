//! The per-condition `INDEX_MAP`: candidate master conditions of a slave condition.

use std::collections::BTreeMap;

use crate::ConditionId;

/// Kratos' `IndexMap` of one slave condition: master condition id → id of the paired
/// condition created for the pair (`None` until it is created; Kratos stores 0).
///
/// Kept ordered by master id, so iteration and output are deterministic (Kratos iterates a
/// `std::unordered_map`; csm does not reproduce that order, DESIGN.md §2).
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct IndexMap {
    entries: BTreeMap<ConditionId, Option<ConditionId>>,
}

impl IndexMap {
    /// An empty map.
    pub fn new() -> IndexMap {
        IndexMap::default()
    }

    /// Adds `master` with no paired condition yet; returns false if it was already present
    /// (the entry is left unchanged).
    pub fn add_id(&mut self, master: ConditionId) -> bool {
        match self.entries.entry(master) {
            std::collections::btree_map::Entry::Occupied(_) => false,
            std::collections::btree_map::Entry::Vacant(v) => {
                v.insert(None);
                true
            }
        }
    }

    /// Records the paired condition created for `master` (Kratos `SetNewEntityId`); adds the
    /// entry if needed.
    pub fn set_new_entity_id(&mut self, master: ConditionId, paired: ConditionId) {
        self.entries.insert(master, Some(paired));
    }

    /// Removes `master`; returns true if it was present.
    pub fn remove_id(&mut self, master: ConditionId) -> bool {
        self.entries.remove(&master).is_some()
    }

    /// True if `master` is in the map.
    pub fn contains(&self, master: ConditionId) -> bool {
        self.entries.contains_key(&master)
    }

    /// The paired condition of `master`, if created.
    pub fn paired(&self, master: ConditionId) -> Option<ConditionId> {
        self.entries.get(&master).copied().flatten()
    }

    /// Number of masters.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// True if there is no master.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Removes every entry.
    pub fn clear(&mut self) {
        self.entries.clear();
    }

    /// Master ids in ascending order.
    pub fn masters(&self) -> impl Iterator<Item = ConditionId> + '_ {
        self.entries.keys().copied()
    }

    /// (master, paired) entries in ascending master order.
    pub fn iter(&self) -> impl Iterator<Item = (ConditionId, Option<ConditionId>)> + '_ {
        self.entries.iter().map(|(k, v)| (*k, *v))
    }
}
