//! [`IdMap`]: the result's ordered maps (`SearchResult::pairs`, `pruned`, `nodes`) as one list
//! sorted by id.

use std::fmt;

/// An ordered map from ids to values, kept as one list of `(id, value)` sorted by id, each id
/// once: what a [`std::collections::BTreeMap`] gives a reader (lookup by id, iteration in
/// id order, equality, a map in JSON and `Debug`) for a map that is built once and then only
/// read. A search step writes its entries in parallel and takes the list as it is
/// ([`IdMap::from_sorted`]); a tree would be built on one thread, a node at a time, in fresh
/// memory (the result's maps of a 2e5-face scene took 3 ms of the two-thread step that way).
///
/// Lookups are binary searches (`O(log n)`); [`IdMap::insert`] and [`Extend`] keep the order
/// (an insert moves the entries after it: for building a small map, not a large one).
#[derive(Clone, PartialEq, Eq, Hash)]
pub struct IdMap<V> {
    entries: Vec<(u32, V)>,
}

impl<V> Default for IdMap<V> {
    fn default() -> Self {
        IdMap {
            entries: Vec::new(),
        }
    }
}

impl<V> IdMap<V> {
    /// An empty map.
    pub fn new() -> IdMap<V> {
        IdMap::default()
    }

    /// The map of `entries` as they are, where their ids ascend strictly (no copy, no
    /// sort); `entries` come back unchanged where they do not (two entries of one id, or out
    /// of order: collect them instead, [`FromIterator`]).
    pub fn from_sorted(entries: Vec<(u32, V)>) -> Result<IdMap<V>, Vec<(u32, V)>> {
        if entries.windows(2).all(|w| w[0].0 < w[1].0) {
            Ok(IdMap { entries })
        } else {
            Err(entries)
        }
    }

    /// [`IdMap::from_sorted`] where the caller has checked the order (debug builds check it
    /// again).
    pub(crate) fn from_sorted_unchecked(entries: Vec<(u32, V)>) -> IdMap<V> {
        debug_assert!(entries.windows(2).all(|w| w[0].0 < w[1].0));
        IdMap { entries }
    }

    /// The number of entries.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether the map has no entry.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// The position of `id`, or where it would go.
    fn position(&self, id: u32) -> Result<usize, usize> {
        self.entries.binary_search_by_key(&id, |(k, _)| *k)
    }

    /// The value of `id`.
    pub fn get(&self, id: &u32) -> Option<&V> {
        let k = self.position(*id).ok()?;
        Some(&self.entries[k].1)
    }

    /// The value of `id`, for writing.
    pub fn get_mut(&mut self, id: &u32) -> Option<&mut V> {
        let k = self.position(*id).ok()?;
        Some(&mut self.entries[k].1)
    }

    /// Whether `id` has an entry.
    pub fn contains_key(&self, id: &u32) -> bool {
        self.position(*id).is_ok()
    }

    /// Sets the value of `id`, returning the one it replaces.
    pub fn insert(&mut self, id: u32, value: V) -> Option<V> {
        match self.position(id) {
            Ok(k) => Some(std::mem::replace(&mut self.entries[k].1, value)),
            Err(k) => {
                self.entries.insert(k, (id, value));
                None
            }
        }
    }

    /// Removes the entry of `id`, returning its value.
    pub fn remove(&mut self, id: &u32) -> Option<V> {
        let k = self.position(*id).ok()?;
        Some(self.entries.remove(k).1)
    }

    /// Keeps only the entries for which `keep(id, value)` holds.
    pub fn retain(&mut self, mut keep: impl FnMut(&u32, &mut V) -> bool) {
        self.entries.retain_mut(|(k, v)| keep(k, v));
    }

    /// The entries in id order.
    pub fn iter(&self) -> Iter<'_, V> {
        Iter {
            inner: self.entries.iter(),
        }
    }

    /// The entries in id order, the values writable.
    pub fn iter_mut(
        &mut self,
    ) -> impl DoubleEndedIterator<Item = (&u32, &mut V)> + ExactSizeIterator {
        self.entries.iter_mut().map(|(k, v)| (&*k, v))
    }

    /// The ids, ascending.
    pub fn keys(&self) -> impl DoubleEndedIterator<Item = &u32> + ExactSizeIterator + Clone {
        self.entries.iter().map(|(k, _)| k)
    }

    /// The values in id order.
    pub fn values(&self) -> impl DoubleEndedIterator<Item = &V> + ExactSizeIterator + Clone {
        self.entries.iter().map(|(_, v)| v)
    }

    /// The values in id order, writable.
    pub fn values_mut(&mut self) -> impl DoubleEndedIterator<Item = &mut V> + ExactSizeIterator {
        self.entries.iter_mut().map(|(_, v)| v)
    }

    /// The entry of the smallest id.
    pub fn first_key_value(&self) -> Option<(&u32, &V)> {
        self.entries.first().map(|(k, v)| (k, v))
    }

    /// The entry of the largest id.
    pub fn last_key_value(&self) -> Option<(&u32, &V)> {
        self.entries.last().map(|(k, v)| (k, v))
    }

    /// The entries, sorted by id (for passes over them in parallel).
    pub fn as_slice(&self) -> &[(u32, V)] {
        &self.entries
    }

    /// The entries as a list sorted by id.
    pub fn into_vec(self) -> Vec<(u32, V)> {
        self.entries
    }
}

/// The iterator of [`IdMap::iter`]: `(&id, &value)` in id order.
#[derive(Debug, Clone)]
pub struct Iter<'a, V> {
    inner: std::slice::Iter<'a, (u32, V)>,
}

impl<'a, V> Iterator for Iter<'a, V> {
    type Item = (&'a u32, &'a V);

    fn next(&mut self) -> Option<Self::Item> {
        self.inner.next().map(|(k, v)| (k, v))
    }

    fn size_hint(&self) -> (usize, Option<usize>) {
        self.inner.size_hint()
    }
}

impl<V> DoubleEndedIterator for Iter<'_, V> {
    fn next_back(&mut self) -> Option<Self::Item> {
        self.inner.next_back().map(|(k, v)| (k, v))
    }
}

impl<V> ExactSizeIterator for Iter<'_, V> {}

impl<'a, V> IntoIterator for &'a IdMap<V> {
    type Item = (&'a u32, &'a V);
    type IntoIter = Iter<'a, V>;

    fn into_iter(self) -> Iter<'a, V> {
        self.iter()
    }
}

impl<V> IntoIterator for IdMap<V> {
    type Item = (u32, V);
    type IntoIter = std::vec::IntoIter<(u32, V)>;

    fn into_iter(self) -> Self::IntoIter {
        self.entries.into_iter()
    }
}

impl<V> FromIterator<(u32, V)> for IdMap<V> {
    /// The map of the entries in any order; of two entries of one id the later stays (as a
    /// `BTreeMap` collects).
    fn from_iter<I: IntoIterator<Item = (u32, V)>>(iter: I) -> Self {
        let mut map = IdMap::new();
        map.extend(iter);
        map
    }
}

impl<V> Extend<(u32, V)> for IdMap<V> {
    /// Adds the entries; one whose id has an entry replaces its value (the later of two
    /// entries of one id stays).
    fn extend<I: IntoIterator<Item = (u32, V)>>(&mut self, iter: I) {
        let before = self.entries.len();
        self.entries.extend(iter);
        if self.entries[before..].windows(2).all(|w| w[0].0 < w[1].0)
            && (before == 0
                || self.entries.len() == before
                || self.entries[before - 1].0 < self.entries[before].0)
        {
            // Ascending after what was there (the usual case): nothing to sort.
            return;
        }
        // A stable sort keeps entries of one id in the order they came; the last stays.
        self.entries.sort_by_key(|(k, _)| *k);
        let mut kept: Vec<(u32, V)> = Vec::with_capacity(self.entries.len());
        for (k, v) in self.entries.drain(..) {
            match kept.last_mut() {
                Some(last) if last.0 == k => last.1 = v,
                _ => kept.push((k, v)),
            }
        }
        self.entries = kept;
    }
}

impl<V> std::ops::Index<&u32> for IdMap<V> {
    type Output = V;

    /// The value of `id`.
    ///
    /// # Panics
    /// If `id` has no entry.
    fn index(&self, id: &u32) -> &V {
        self.get(id).expect("IdMap: no entry for the id")
    }
}

impl<V: fmt::Debug> fmt::Debug for IdMap<V> {
    /// As a map: `{1: …, 4: …}`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_map().entries(self.iter()).finish()
    }
}

impl<V: serde::Serialize> serde::Serialize for IdMap<V> {
    /// As a map (in JSON, an object whose keys are the ids).
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_map(self.iter())
    }
}

/// The same entries as an ordered map of the standard library (for comparing with one).
impl<V: PartialEq> PartialEq<std::collections::BTreeMap<u32, V>> for IdMap<V> {
    fn eq(&self, other: &std::collections::BTreeMap<u32, V>) -> bool {
        self.len() == other.len() && self.iter().eq(other.iter())
    }
}

/// The same entries as an [`IdMap`].
impl<V: PartialEq> PartialEq<IdMap<V>> for std::collections::BTreeMap<u32, V> {
    fn eq(&self, other: &IdMap<V>) -> bool {
        other == self
    }
}

impl<V> From<std::collections::BTreeMap<u32, V>> for IdMap<V> {
    fn from(map: std::collections::BTreeMap<u32, V>) -> Self {
        IdMap::from_sorted_unchecked(map.into_iter().collect())
    }
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeMap;

    use super::*;

    /// Every operation against a `BTreeMap` fed the same entries: the oracle.
    #[test]
    fn behaves_as_an_ordered_map() {
        // Ids in a scrambled order with repeats (a small linear congruential sequence).
        let ids: Vec<u32> = (0..500u32).map(|i| (i * 7919 + 13) % 311).collect();
        let mut tree = BTreeMap::new();
        let mut map = IdMap::new();
        for (n, &id) in ids.iter().enumerate() {
            assert_eq!(map.insert(id, n), tree.insert(id, n));
        }
        let same = |map: &IdMap<usize>, tree: &BTreeMap<u32, usize>| {
            assert!(map.iter().eq(tree.iter()));
            assert!(map.iter().rev().eq(tree.iter().rev()));
            assert_eq!(map.len(), tree.len());
            assert!(map.keys().eq(tree.keys()) && map.values().eq(tree.values()));
            assert_eq!(map.first_key_value(), tree.first_key_value());
            assert_eq!(map.last_key_value(), tree.last_key_value());
            assert_eq!(format!("{map:?}"), format!("{tree:?}"));
            assert_eq!(
                serde_json::to_string(map).unwrap(),
                serde_json::to_string(tree).unwrap()
            );
            for id in 0..320 {
                assert_eq!(map.get(&id), tree.get(&id), "{id}");
                assert_eq!(map.contains_key(&id), tree.contains_key(&id));
            }
        };
        same(&map, &tree);
        // Collected and extended in any order: the later of two entries of one id stays.
        let entries: Vec<(u32, usize)> = ids.iter().enumerate().map(|(n, &i)| (i, n)).collect();
        let collected: IdMap<usize> = entries.iter().copied().collect();
        same(&collected, &entries.iter().copied().collect());
        let (head, tail) = entries.split_at(200);
        let mut extended: IdMap<usize> = head.iter().copied().collect();
        extended.extend(tail.iter().copied());
        same(&extended, &tree);
        // Ascending entries after the last id: appended as they are.
        let mut grown = IdMap::from_sorted(vec![(1, 10), (5, 50)]).unwrap();
        grown.extend([(6, 60), (9, 90)]);
        assert_eq!(grown.into_vec(), [(1, 10), (5, 50), (6, 60), (9, 90)]);
        // Removal, writing and indexing.
        for id in (0..320).step_by(3) {
            assert_eq!(map.remove(&id), tree.remove(&id));
        }
        for (v, w) in map.values_mut().zip(tree.values_mut()) {
            *v += 1;
            *w += 1;
        }
        if let (Some(v), Some(w)) = (map.get_mut(&2), tree.get_mut(&2)) {
            *v = 0;
            *w = 0;
        }
        map.retain(|id, v| id % 4 != 1 && *v % 3 != 0);
        tree.retain(|id, v| id % 4 != 1 && *v % 3 != 0);
        same(&map, &tree);
        let (&first, _) = map.first_key_value().unwrap();
        assert_eq!(map[&first], tree[&first]);
        assert_eq!(IdMap::from(tree.clone()), map);
        // Both ways round.
        assert!(map == tree);
        assert!(tree == map);
        tree.insert(1000, 0);
        assert!(map != tree);
        assert!(tree != map);
        tree.remove(&1000);
        assert!(map.clone().into_iter().eq(tree.into_iter()));
    }

    #[test]
    fn unsorted_entries_come_back() {
        for entries in [vec![(2, 'a'), (1, 'b')], vec![(1, 'a'), (1, 'b')]] {
            assert_eq!(IdMap::from_sorted(entries.clone()), Err(entries));
        }
        assert_eq!(IdMap::<u8>::from_sorted(Vec::new()), Ok(IdMap::new()));
    }
}
