//! The per-condition `INDEX_MAP`: candidate master conditions of a slave condition.

use crate::ConditionId;

/// Kratos' `IndexMap` of one slave condition: master condition id → id of the paired
/// condition created for the pair (`None` until it is created; Kratos stores 0).
///
/// Kept ordered by master id, so iteration and output are deterministic (Kratos iterates a
/// `std::unordered_map`; csm does not reproduce that order, DESIGN.md §2). A sorted list:
/// a slave has a handful of masters, so a binary search in one allocation beats a tree's
/// nodes (the stacked blocks add 1.5e6 entries in one step). An entry added or removed moves
/// the entries after it: `k` masters added out of order cost O(k²) moves, a few hundred µs
/// for the 1,000 of Kratos' result buffer.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct IndexMap {
    entries: Vec<(ConditionId, Option<ConditionId>)>,
}

impl IndexMap {
    /// An empty map.
    pub fn new() -> IndexMap {
        IndexMap::default()
    }

    /// Where `master` is (`Ok`) or would go (`Err`).
    fn find(&self, master: ConditionId) -> Result<usize, usize> {
        self.entries.binary_search_by_key(&master, |(m, _)| *m)
    }

    /// Room for `additional` more entries without a new allocation (for a caller that knows
    /// how many it will add).
    pub fn reserve(&mut self, additional: usize) {
        self.entries.reserve(additional);
    }

    /// Adds `master` with no paired condition yet; returns false if it was already present
    /// (the entry is left unchanged).
    pub fn add_id(&mut self, master: ConditionId) -> bool {
        match self.find(master) {
            Ok(_) => false,
            Err(at) => {
                self.entries.insert(at, (master, None));
                true
            }
        }
    }

    /// Records the paired condition created for `master` (Kratos `SetNewEntityId`); adds the
    /// entry if needed.
    pub fn set_new_entity_id(&mut self, master: ConditionId, paired: ConditionId) {
        match self.find(master) {
            Ok(at) => self.entries[at].1 = Some(paired),
            Err(at) => self.entries.insert(at, (master, Some(paired))),
        }
    }

    /// Removes `master`; returns true if it was present.
    pub fn remove_id(&mut self, master: ConditionId) -> bool {
        match self.find(master) {
            Ok(at) => {
                self.entries.remove(at);
                true
            }
            Err(_) => false,
        }
    }

    /// True if `master` is in the map.
    pub fn contains(&self, master: ConditionId) -> bool {
        self.find(master).is_ok()
    }

    /// The paired condition of `master`, if created.
    pub fn paired(&self, master: ConditionId) -> Option<ConditionId> {
        self.find(master).ok().and_then(|at| self.entries[at].1)
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
        self.entries.iter().map(|(m, _)| *m)
    }

    /// (master, paired) entries in ascending master order.
    pub fn iter(&self) -> impl Iterator<Item = (ConditionId, Option<ConditionId>)> + '_ {
        self.entries.iter().copied()
    }
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeMap;

    use super::*;

    /// Random operations against a `BTreeMap` (the oracle): same answers, same ordered
    /// entries after every operation.
    #[test]
    fn index_map_answers_as_an_ordered_map() {
        let mut state = 0x1dea_u64;
        let mut next = move |n: u64| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state % n
        };
        let mut map = IndexMap::new();
        let mut oracle: BTreeMap<ConditionId, Option<ConditionId>> = BTreeMap::new();
        let (mut added, mut removed) = (0, 0);
        for step in 0..20_000 {
            let master = ConditionId(next(40) as u32 + 1);
            match next(10) {
                0..=3 => {
                    let new = !oracle.contains_key(&master);
                    if new {
                        oracle.insert(master, None);
                        added += 1;
                    }
                    assert_eq!(map.add_id(master), new, "step {step}");
                }
                4..=6 => {
                    let was = oracle.remove(&master).is_some();
                    removed += usize::from(was);
                    assert_eq!(map.remove_id(master), was, "step {step}");
                }
                7 | 8 => {
                    let paired = ConditionId(next(1000) as u32 + 1);
                    oracle.insert(master, Some(paired));
                    map.set_new_entity_id(master, paired);
                }
                _ if next(50) == 0 => {
                    oracle.clear();
                    map.clear();
                }
                _ => {}
            }
            assert_eq!(map.contains(master), oracle.contains_key(&master));
            assert_eq!(map.paired(master), oracle.get(&master).copied().flatten());
            assert_eq!(map.len(), oracle.len());
            assert_eq!(map.is_empty(), oracle.is_empty());
            assert!(
                map.iter().eq(oracle.iter().map(|(k, v)| (*k, *v))),
                "step {step}"
            );
            assert!(map.masters().eq(oracle.keys().copied()));
        }
        assert!(added > 1_000 && removed > 1_000, "{added} {removed}");
    }
}
