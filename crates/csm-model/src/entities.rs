//! Dense storage of nodes, elements and conditions, with the external ids beside it.

use std::collections::HashMap;
use std::sync::atomic::{AtomicU64, Ordering};

use csm_geometry::GeometryKind;
use csm_geometry::math::Point;
use rayon::prelude::*;

use crate::write_at::{par_clone, write_at_ascending};
use crate::{Flags, NodeIdx, PropertiesId};

/// A value no other change of any model's coordinates or connectivity in this process has
/// had ([`crate::ModelPart::geometry_stamp`]); never 0.
pub(crate) fn fresh_stamp() -> u64 {
    static NEXT: AtomicU64 = AtomicU64::new(1);
    NEXT.fetch_add(1, Ordering::Relaxed)
}

/// The nodes of a model part, structure-of-arrays: index `i` of every column is node
/// `NodeIdx(i)`.
#[derive(Debug, Default)]
pub struct Nodes {
    pub(crate) ids: Vec<u32>,
    pub(crate) initial: Vec<Point>,
    pub(crate) coordinates: Vec<Point>,
    pub(crate) flags: Vec<Flags>,
    pub(crate) by_id: IdIndex,
    /// Renewed ([`fresh_stamp`]) by every access that can change the coordinates.
    pub(crate) stamp: u64,
}

impl Nodes {
    /// Room for `additional` more nodes in every column.
    pub(crate) fn reserve(&mut self, additional: usize) {
        self.ids.reserve(additional);
        self.initial.reserve(additional);
        self.coordinates.reserve(additional);
        self.flags.reserve(additional);
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.ids.len()
    }

    /// True if there is no node.
    pub fn is_empty(&self) -> bool {
        self.ids.is_empty()
    }

    /// External ids, by index.
    pub fn ids(&self) -> &[u32] {
        &self.ids
    }

    /// Current coordinates, by index.
    pub fn coordinates(&self) -> &[Point] {
        &self.coordinates
    }

    /// Current coordinates, mutable (the initial coordinates are not touched). Renews the
    /// model's [`geometry_stamp`](crate::ModelPart::geometry_stamp), whether or not a
    /// coordinate is then changed.
    pub fn coordinates_mut(&mut self) -> &mut [Point] {
        self.stamp = fresh_stamp();
        &mut self.coordinates
    }

    /// Initial (reference) coordinates, as read from the file.
    pub fn initial_coordinates(&self) -> &[Point] {
        &self.initial
    }

    /// Tri-state flags, by index.
    pub fn flags(&self) -> &[Flags] {
        &self.flags
    }

    /// Tri-state flags, mutable.
    pub fn flags_mut(&mut self) -> &mut [Flags] {
        &mut self.flags
    }

    /// The dense index of the node with external id `id`.
    pub fn index_of(&self, id: u32) -> Option<NodeIdx> {
        self.by_id.get(id).map(NodeIdx)
    }
}

/// Entities in Kratos' container order, ascending external id ([`Entities::id_order`]): the
/// `k`-th is the dense index [`IdOrder::get`]`(k)`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct IdOrder {
    len: usize,
    /// The dense indices in id order, or `None` where that order is theirs (`get(k) == k`).
    sorted: Option<Vec<usize>>,
}

impl IdOrder {
    /// The dense index of the `k`-th entity in id order (`k < len()`).
    pub fn get(&self, k: usize) -> usize {
        self.sorted.as_ref().map_or(k, |sorted| sorted[k])
    }

    /// The number of entities.
    pub fn len(&self) -> usize {
        self.len
    }

    /// True when there is none.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The dense indices in id order.
    pub fn iter(&self) -> impl ExactSizeIterator<Item = usize> + '_ {
        (0..self.len).map(|k| self.get(k))
    }

    /// The dense indices in id order, on rayon's pool.
    pub fn par_iter(&self) -> impl rayon::iter::IndexedParallelIterator<Item = usize> + '_ {
        use rayon::prelude::*;
        (0..self.len).into_par_iter().map(|k| self.get(k))
    }
}

/// Elements or conditions of a model part, structure-of-arrays: geometry kind, connectivity
/// (dense node indices, in the geometry's node order), properties and flags per entity.
#[derive(Debug, Default)]
pub struct Entities {
    pub(crate) ids: Vec<u32>,
    pub(crate) kinds: Vec<GeometryKind>,
    pub(crate) names: Vec<u16>,
    pub(crate) name_table: Vec<String>,
    pub(crate) offsets: Vec<u32>,
    pub(crate) connectivity: Vec<NodeIdx>,
    pub(crate) properties: Vec<PropertiesId>,
    pub(crate) flags: Vec<Flags>,
    pub(crate) by_id: IdIndex,
    /// Renewed ([`fresh_stamp`]) by every change of the kinds or the connectivity.
    pub(crate) stamp: u64,
}

impl Entities {
    /// Room for `additional` more entities of `nodes_each` nodes in every column.
    pub(crate) fn reserve(&mut self, additional: usize, nodes_each: usize) {
        self.ids.reserve(additional);
        self.kinds.reserve(additional);
        self.names.reserve(additional);
        self.offsets.reserve(additional);
        self.connectivity
            .reserve(additional.saturating_mul(nodes_each));
        self.properties.reserve(additional);
        self.flags.reserve(additional);
    }

    /// Number of entities.
    pub fn len(&self) -> usize {
        self.ids.len()
    }

    /// True if there is none.
    pub fn is_empty(&self) -> bool {
        self.ids.is_empty()
    }

    /// External ids, by index.
    pub fn ids(&self) -> &[u32] {
        &self.ids
    }

    /// Geometry kind of entity `i`.
    pub fn kind(&self, i: usize) -> GeometryKind {
        self.kinds[i]
    }

    /// Geometry kinds, by index.
    pub fn kinds(&self) -> &[GeometryKind] {
        &self.kinds
    }

    /// The Kratos name the entity was created with (e.g. `SurfaceCondition3D3N`), or `""`.
    pub fn name(&self, i: usize) -> &str {
        &self.name_table[self.names[i] as usize]
    }

    /// The nodes of entity `i`, in geometry order.
    pub fn nodes(&self, i: usize) -> &[NodeIdx] {
        let start = if i == 0 {
            0
        } else {
            self.offsets[i - 1] as usize
        };
        &self.connectivity[start..self.offsets[i] as usize]
    }

    /// Reverses the node order of entity `i` (Kratos `std::reverse` of the geometry's nodes,
    /// used to invert normals).
    pub fn reverse_nodes(&mut self, i: usize) {
        self.stamp = fresh_stamp();
        let start = if i == 0 {
            0
        } else {
            self.offsets[i - 1] as usize
        };
        self.connectivity[start..self.offsets[i] as usize].reverse();
    }

    /// Reorders the nodes of entity `i`: node `k` becomes the old node `permutation[k]`.
    /// Returns false (and changes nothing) unless `permutation` is a permutation of
    /// `0..n_nodes`.
    pub fn permute_nodes(&mut self, i: usize, permutation: &[usize]) -> bool {
        let start = if i == 0 {
            0
        } else {
            self.offsets[i - 1] as usize
        };
        let end = self.offsets[i] as usize;
        let n = end - start;
        let mut seen = vec![false; n];
        if permutation.len() != n
            || permutation
                .iter()
                .any(|&k| k >= n || std::mem::replace(&mut seen[k], true))
        {
            return false;
        }
        self.stamp = fresh_stamp();
        let old: Vec<NodeIdx> = self.connectivity[start..end].to_vec();
        for (k, &from) in permutation.iter().enumerate() {
            self.connectivity[start + k] = old[from];
        }
        true
    }

    /// Renumbers every entity: entity `i` gets external id `ids[i]`. Returns false (and
    /// changes nothing) when `ids` has the wrong length or repeats an id.
    pub fn set_ids(&mut self, ids: &[u32]) -> bool {
        if ids.len() != self.ids.len() {
            return false;
        }
        let mut by_id = IdIndex::default();
        for (i, &id) in ids.iter().enumerate() {
            if by_id.contains(id) {
                return false;
            }
            by_id.insert(id, i as u32);
        }
        self.ids.copy_from_slice(ids);
        self.by_id = by_id;
        true
    }

    /// Properties id of entity `i`.
    pub fn properties(&self, i: usize) -> PropertiesId {
        self.properties[i]
    }

    /// Sets the properties id of entity `i`.
    pub fn set_properties(&mut self, i: usize, id: PropertiesId) {
        self.properties[i] = id;
    }

    /// Tri-state flags, by index.
    pub fn flags(&self) -> &[Flags] {
        &self.flags
    }

    /// Tri-state flags, mutable.
    pub fn flags_mut(&mut self) -> &mut [Flags] {
        &mut self.flags
    }

    /// The dense index of the entity with external id `id`.
    pub fn index_of(&self, id: u32) -> Option<usize> {
        self.by_id.get(id).map(|i| i as usize)
    }

    /// Kratos' container order (ascending external id) without a list where the ids ascend
    /// with the dense indices (a mesh written in id order, the usual case: checked in
    /// parallel); else the sorted list of [`Entities::indices_by_id`].
    pub fn id_order(&self) -> IdOrder {
        use rayon::prelude::*;
        let len = self.ids.len();
        if self.ids.par_windows(2).all(|w| w[0] < w[1]) {
            return IdOrder { len, sorted: None };
        }
        IdOrder {
            len,
            sorted: Some(self.indices_by_id()),
        }
    }

    /// Dense indices in Kratos' container order: ascending external id.
    pub fn indices_by_id(&self) -> Vec<usize> {
        use rayon::prelude::*;
        let mut order: Vec<usize> = (0..self.ids.len()).into_par_iter().collect();
        // A mesh written in id order (the usual case) is in that order already: checked in
        // parallel, no sort.
        if self.ids.par_windows(2).all(|w| w[0] < w[1]) {
            return order;
        }
        // Ids are unique: one order, whatever the sort (in parallel on rayon's pool).
        order.par_sort_unstable_by_key(|&i| self.ids[i]);
        order
    }

    /// The largest external id, or 0 when empty (Kratos `GetMaximumConditionsIds`).
    pub fn max_id(&self) -> u32 {
        self.ids.par_iter().copied().max().unwrap_or(0)
    }

    /// The columns but the ids and the connectivity (already there, with `by_id`) of the
    /// last `added` entities: all of `kind` and `name`, their properties the second id of
    /// each record of `records` (`width` ids each, from the first).
    pub(crate) fn extend_added(
        &mut self,
        added: usize,
        kind: GeometryKind,
        name: &str,
        records: &[u32],
        width: usize,
    ) {
        if added == 0 {
            return;
        }
        let name_idx = self.name_index(name);
        self.stamp = fresh_stamp();
        let n = kind.n_nodes();
        // Each column extended on rayon's pool (fresh pages, touched by the threads that
        // write them).
        self.kinds.par_extend(rayon::iter::repeat_n(kind, added));
        self.names
            .par_extend(rayon::iter::repeat_n(name_idx, added));
        let start = self.connectivity.len() - added * n;
        self.offsets
            .par_extend((1..=added).into_par_iter().map(|k| (start + k * n) as u32));
        self.properties.par_extend(
            (records.par_chunks_exact(width))
                .take(added)
                .map(|r| PropertiesId(r[1])),
        );
        self.flags
            .par_extend(rayon::iter::repeat_n(Flags::new(), added));
    }

    fn name_index(&mut self, name: &str) -> u16 {
        let i = match self.name_table.iter().position(|n| n == name) {
            Some(i) => i,
            None => {
                self.name_table.push(name.to_owned());
                self.name_table.len() - 1
            }
        };
        i as u16
    }

    pub(crate) fn push(
        &mut self,
        id: u32,
        kind: GeometryKind,
        name: &str,
        nodes: &[NodeIdx],
        properties: PropertiesId,
    ) {
        let name_idx = self.name_index(name);
        self.stamp = fresh_stamp();
        self.by_id.insert(id, self.ids.len() as u32);
        self.ids.push(id);
        self.kinds.push(kind);
        self.names.push(name_idx);
        self.connectivity.extend_from_slice(nodes);
        self.offsets.push(self.connectivity.len() as u32);
        self.properties.push(properties);
        self.flags.push(Flags::new());
    }
}

/// External id → dense index. Ids of a mesh are mostly contiguous from 1, so they are kept in
/// a dense table (id → index + 1, 0 for none) while it stays within twice the entry count;
/// ids beyond it go to a hash map.
#[derive(Debug, Default)]
pub(crate) struct IdIndex {
    dense: Vec<u32>,
    sparse: HashMap<u32, u32>,
    len: usize,
    /// The largest id present.
    max: Option<u32>,
}

impl IdIndex {
    /// The slack of the dense table beyond twice the entry count.
    const DENSE_SLACK: usize = 1024;

    pub(crate) fn get(&self, id: u32) -> Option<u32> {
        match self.dense.get(id as usize) {
            Some(&v) if v != 0 => Some(v - 1),
            _ if self.sparse.is_empty() => None,
            _ => self.sparse.get(&id).copied(),
        }
    }

    pub(crate) fn contains(&self, id: u32) -> bool {
        self.get(id).is_some()
    }

    /// Adds `id → index`; `id` must not be present.
    pub(crate) fn insert(&mut self, id: u32, index: u32) {
        debug_assert!(!self.contains(id));
        self.len += 1;
        self.max = Some(self.max.map_or(id, |m| m.max(id)));
        let i = id as usize;
        if i < self.dense.len() {
            self.dense[i] = index + 1;
        } else if i < 2 * self.len + Self::DENSE_SLACK {
            self.dense.resize(i + 1, 0);
            self.dense[i] = index + 1;
        } else {
            self.sparse.insert(id, index);
        }
    }

    /// Adds `id(k) → first + k` for every `k` in `0..n` in one parallel pass, where the ids ascend
    /// strictly from above every id present and the dense table holds them (kept within the
    /// bound [`IdIndex::insert`] keeps it in); returns false, adding nothing, where not. Lookups
    /// then answer as after inserting the ids one by one.
    pub(crate) fn insert_ascending(
        &mut self,
        n: usize,
        id: impl Fn(usize) -> u32 + Sync,
        first: u32,
    ) -> bool {
        if n == 0 {
            return true;
        }
        let (low, high) = (id(0), id(n - 1));
        let end = high as usize + 1;
        let fits = end <= 2 * (self.len + n) + Self::DENSE_SLACK;
        if !fits
            || self.max.is_some_and(|m| low <= m)
            || !(1..n).into_par_iter().all(|k| id(k - 1) < id(k))
        {
            return false;
        }
        if self.dense.len() < end {
            let more = end - self.dense.len();
            self.dense.par_extend(rayon::iter::repeat_n(0, more));
        }
        let at = |k: usize| id(k) as usize;
        write_at_ascending(&mut self.dense, n, at, |k, v| *v = first + k as u32 + 1);
        self.len += n;
        self.max = Some(high);
        true
    }
}

// The columns of a big model are copied in parallel ([`par_clone`]); the copy shares the
// stamps (its geometry is the same until one of them changes).

impl Clone for Nodes {
    fn clone(&self) -> Nodes {
        let Nodes {
            ids,
            initial,
            coordinates,
            flags,
            by_id,
            stamp,
        } = self;
        Nodes {
            ids: par_clone(ids),
            initial: par_clone(initial),
            coordinates: par_clone(coordinates),
            flags: par_clone(flags),
            by_id: by_id.clone(),
            stamp: *stamp,
        }
    }
}

impl Clone for Entities {
    fn clone(&self) -> Entities {
        let Entities {
            ids,
            kinds,
            names,
            name_table,
            offsets,
            connectivity,
            properties,
            flags,
            by_id,
            stamp,
        } = self;
        Entities {
            ids: par_clone(ids),
            kinds: par_clone(kinds),
            names: par_clone(names),
            name_table: name_table.clone(),
            offsets: par_clone(offsets),
            connectivity: par_clone(connectivity),
            properties: par_clone(properties),
            flags: par_clone(flags),
            by_id: by_id.clone(),
            stamp: *stamp,
        }
    }
}

impl Clone for IdIndex {
    fn clone(&self) -> IdIndex {
        let IdIndex {
            dense,
            sparse,
            len,
            max,
        } = self;
        IdIndex {
            dense: par_clone(dense),
            sparse: sparse.clone(),
            len: *len,
            max: *max,
        }
    }
}
