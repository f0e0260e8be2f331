//! The model part: nodes, elements, conditions, properties, process info, sub model parts
//! and nodal data.

use std::collections::{BTreeMap, BTreeSet, HashMap};

use csm_geometry::GeometryKind;
use csm_geometry::math::{Point, Real, Vector};

use crate::error::{EntityKind, Error, ErrorKind};
use crate::parts::{SubModelPart, merge_sorted};
use crate::write_at::par_clone;
use crate::{
    ConditionId, ConditionIdx, ElementId, ElementIdx, Entities, IndexMap, NodalData, NodeId,
    NodeIdx, Nodes, PartIdx, ProcessInfo, Properties, PropertiesId, ScalarVar, VectorVar,
};

/// The root model part (Kratos `ModelPart`, e.g. `Structure`): dense storage of every
/// entity, with the sub model parts as index sets into it.
#[derive(Debug, Default)]
pub struct ModelPart {
    name: String,
    nodes: Nodes,
    elements: Entities,
    conditions: Entities,
    properties: BTreeMap<PropertiesId, Properties>,
    process_info: ProcessInfo,
    parts: Vec<SubModelPart>,
    part_by_path: HashMap<String, PartIdx>,
    roots: Vec<PartIdx>,
    nodal_data: NodalData,
    index_maps: Vec<IndexMap>,
    condition_normals: Vec<Vector>,
    /// Renewed ([`crate::entities::fresh_stamp`]) by every access that can change the
    /// condition normals ([`ModelPart::condition_normals_mut`]); 0 before the first.
    condition_normals_stamp: u64,
}

/// A copy whose big columns (the nodes', the entities', the INDEX_MAPs, the condition
/// normals, the nodal data's and the parts' lists) are copied on rayon's pool.
impl Clone for ModelPart {
    fn clone(&self) -> ModelPart {
        let ModelPart {
            name,
            nodes,
            elements,
            conditions,
            properties,
            process_info,
            parts,
            part_by_path,
            roots,
            nodal_data,
            index_maps,
            condition_normals,
            condition_normals_stamp,
        } = self;
        ModelPart {
            name: name.clone(),
            nodes: nodes.clone(),
            elements: elements.clone(),
            conditions: conditions.clone(),
            properties: properties.clone(),
            process_info: process_info.clone(),
            parts: parts.clone(),
            part_by_path: part_by_path.clone(),
            roots: roots.clone(),
            nodal_data: nodal_data.clone(),
            index_maps: par_clone(index_maps),
            condition_normals: par_clone(condition_normals),
            condition_normals_stamp: *condition_normals_stamp,
        }
    }
}

/// [`ModelPart::geometry_stamp`]: equal stamps, equal node coordinates and condition
/// geometries.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct GeometryStamp([u64; 2]);

/// The most nodes of an element or condition kind (Hexahedra3D27).
const MAX_ENTITY_NODES: usize = 27;

impl ModelPart {
    /// An empty model part called `name`.
    pub fn new(name: &str) -> ModelPart {
        ModelPart {
            name: name.to_owned(),
            ..ModelPart::default()
        }
    }

    /// The name of the root model part.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The nodes.
    pub fn nodes(&self) -> &Nodes {
        &self.nodes
    }

    /// The nodes, mutable (coordinates and flags).
    pub fn nodes_mut(&mut self) -> &mut Nodes {
        &mut self.nodes
    }

    /// Part `idx` (read) beside the nodes (written): both borrows at once, so that a pass
    /// over a part's nodes writes their flags without copying the part's list first (a
    /// serial copy into fresh memory in every step).
    pub fn part_and_nodes_mut(&mut self, idx: PartIdx) -> (&SubModelPart, &mut Nodes) {
        (&self.parts[idx.index()], &mut self.nodes)
    }

    /// Part `idx` (read) beside the conditions (written), as [`ModelPart::part_and_nodes_mut`].
    pub fn part_and_conditions_mut(&mut self, idx: PartIdx) -> (&SubModelPart, &mut Entities) {
        (&self.parts[idx.index()], &mut self.conditions)
    }

    /// Part `idx` (read) beside the nodal variables (written), as
    /// [`ModelPart::part_and_nodes_mut`].
    pub fn part_and_nodal_data_mut(&mut self, idx: PartIdx) -> (&SubModelPart, &mut NodalData) {
        (&self.parts[idx.index()], &mut self.nodal_data)
    }

    /// The nodes (read) beside the nodal variables (written).
    pub fn nodes_and_nodal_data_mut(&mut self) -> (&Nodes, &mut NodalData) {
        (&self.nodes, &mut self.nodal_data)
    }

    /// The elements.
    pub fn elements(&self) -> &Entities {
        &self.elements
    }

    /// The elements, mutable (flags, node order, properties).
    pub fn elements_mut(&mut self) -> &mut Entities {
        &mut self.elements
    }

    /// The conditions.
    pub fn conditions(&self) -> &Entities {
        &self.conditions
    }

    /// The conditions, mutable (flags, node order, properties).
    pub fn conditions_mut(&mut self) -> &mut Entities {
        &mut self.conditions
    }

    /// The properties blocks, by id.
    pub fn properties(&self) -> &BTreeMap<PropertiesId, Properties> {
        &self.properties
    }

    /// The properties blocks, mutable.
    pub fn properties_mut(&mut self) -> &mut BTreeMap<PropertiesId, Properties> {
        &mut self.properties
    }

    /// The process info.
    pub fn process_info(&self) -> &ProcessInfo {
        &self.process_info
    }

    /// The process info, mutable.
    pub fn process_info_mut(&mut self) -> &mut ProcessInfo {
        &mut self.process_info
    }

    /// Nodal variables.
    pub fn nodal_data(&self) -> &NodalData {
        &self.nodal_data
    }

    /// Nodal variables, mutable.
    pub fn nodal_data_mut(&mut self) -> &mut NodalData {
        &mut self.nodal_data
    }

    /// Calls `f` with the model and the values of the vector variable `var` at buffer step
    /// `step` (by node index), to write them from what the rest of the model holds without
    /// a copy. Meanwhile the model's own values of `var` at `step` are absent (`f` has them).
    /// `None` (and `f` is not called) if the variable is absent or the step is not kept.
    pub fn with_vector_mut<R>(
        &mut self,
        var: VectorVar,
        step: usize,
        f: impl FnOnce(&ModelPart, &mut [Vector]) -> R,
    ) -> Option<R> {
        let mut values = self.nodal_data.take_vector(var, step)?;
        let result = f(self, &mut values);
        self.nodal_data.put_vector(var, step, values);
        Some(result)
    }

    /// Calls `f` with the model and the values of the scalar variable `var` at buffer step
    /// `step` (by node index), to write them from what the rest of the model holds without
    /// a copy ([`ModelPart::with_vector_mut`] for a scalar). Meanwhile the model's own values
    /// of `var` at `step` are absent (`f` has them). `None` (and `f` is not called) if the
    /// variable is absent or the step is not kept.
    pub fn with_scalar_mut<R>(
        &mut self,
        var: ScalarVar,
        step: usize,
        f: impl FnOnce(&ModelPart, &mut [Real]) -> R,
    ) -> Option<R> {
        let mut values = self.nodal_data.take_scalar(var, step)?;
        let result = f(self, &mut values);
        self.nodal_data.put_scalar(var, step, values);
        Some(result)
    }

    /// The `INDEX_MAP` of condition `c`.
    pub fn index_map(&self, c: ConditionIdx) -> &IndexMap {
        &self.index_maps[c.index()]
    }

    /// The `INDEX_MAP` of condition `c`, mutable.
    pub fn index_map_mut(&mut self, c: ConditionIdx) -> &mut IndexMap {
        &mut self.index_maps[c.index()]
    }

    /// Every condition's `INDEX_MAP`, by condition index, mutable: for updates of different
    /// conditions' maps in parallel.
    pub fn index_maps_mut(&mut self) -> &mut [IndexMap] {
        &mut self.index_maps
    }

    /// The non-historical `NORMAL` of every condition (unit normal at the centre), by
    /// condition index; zero until computed (see [`crate::compute_unit_normals`]).
    pub fn condition_normals(&self) -> &[Vector] {
        &self.condition_normals
    }

    /// Mutable form of [`ModelPart::condition_normals`].
    pub fn condition_normals_mut(&mut self) -> &mut [Vector] {
        self.condition_normals_stamp = crate::entities::fresh_stamp();
        &mut self.condition_normals
    }

    /// A value that changes with every access that can change the condition normals
    /// ([`ModelPart::condition_normals_mut`]; conditions added keep it: their normals are
    /// appended, the others stay) and that no other model has (a clone shares it until one
    /// of them changes); 0 before the first.
    pub(crate) fn condition_normals_stamp(&self) -> u64 {
        self.condition_normals_stamp
    }

    /// Room for `additional` more nodes (a hint for readers that know how many will come:
    /// nothing observable changes, the arrays grow without intermediate copies).
    pub fn reserve_nodes(&mut self, additional: usize) {
        self.nodes.reserve(additional);
    }

    /// Room for `additional` more elements (`conditions == false`) or conditions of
    /// `nodes_each` nodes (a hint, as [`ModelPart::reserve_nodes`]).
    pub fn reserve_entities(&mut self, conditions: bool, additional: usize, nodes_each: usize) {
        if conditions {
            self.conditions.reserve(additional, nodes_each);
            self.index_maps.reserve(additional);
            self.condition_normals.reserve(additional);
        } else {
            self.elements.reserve(additional, nodes_each);
        }
    }

    /// A value that changes whenever the node coordinates or the conditions' kinds or
    /// connectivity may have changed (a node or condition added, [`Nodes::coordinates_mut`],
    /// [`Entities::reverse_nodes`], [`Entities::permute_nodes`]), and that no other model's
    /// geometry has in this process (a clone shares it until one of them changes): what is
    /// computed from the conditions' geometry alone stays valid while it is the same.
    pub fn geometry_stamp(&self) -> GeometryStamp {
        GeometryStamp([self.nodes.stamp, self.conditions.stamp])
    }

    /// Adds a node with external id `id`. Errors on a duplicate id or a non-finite
    /// coordinate.
    pub fn add_node(&mut self, id: NodeId, position: Point) -> Result<NodeIdx, Error> {
        if self.nodes.by_id.contains(id.0) {
            return Err(ErrorKind::DuplicateId {
                entity: EntityKind::Node,
                id: id.0,
            }
            .into());
        }
        if !position.iter().all(|x| x.is_finite()) {
            return Err(ErrorKind::NonFiniteCoordinate { node: id.0 }.into());
        }
        let idx = NodeIdx(self.nodes.ids.len() as u32);
        self.nodes.by_id.insert(id.0, idx.0);
        self.nodes.stamp = crate::entities::fresh_stamp();
        self.nodes.ids.push(id.0);
        self.nodes.initial.push(position);
        self.nodes.coordinates.push(position);
        self.nodes.flags.push(Default::default());
        self.nodal_data.resize(self.nodes.len());
        Ok(idx)
    }

    /// Adds the nodes `ids` at `positions` (one each) in order: the same model and the same
    /// first error as [`ModelPart::add_node`] node by node (the nodes before a refused one are
    /// added), the columns extended once. The error comes with the refused node's position.
    pub fn add_nodes(
        &mut self,
        ids: &[u32],
        positions: &[[Real; 3]],
    ) -> Result<(), (usize, Error)> {
        use rayon::prelude::*;
        let count = ids.len().min(positions.len());
        self.nodes.reserve(count);
        let duplicate = |id| ErrorKind::DuplicateId {
            entity: EntityKind::Node,
            id,
        };
        let finite = |x: &[Real; 3]| x.iter().all(|v| v.is_finite());
        // The nodes before the first non-finite position, in one parallel pass where their
        // ids ascend from above every id present (no duplicate is then possible); else one
        // by one.
        let bad = positions[..count].par_iter().position_first(|x| !finite(x));
        let clean = bad.unwrap_or(count);
        let first = self.nodes.ids.len() as u32;
        let (added, refused) = if self.nodes.by_id.insert_ascending(clean, |k| ids[k], first) {
            self.nodes.ids.par_extend(ids[..clean].par_iter().copied());
            let refused = bad.map(|k| match self.nodes.by_id.contains(ids[k]) {
                true => (k, duplicate(ids[k])),
                false => (k, ErrorKind::NonFiniteCoordinate { node: ids[k] }),
            });
            (clean, refused)
        } else {
            let mut refused = None;
            let mut added = 0;
            for (k, (&id, x)) in ids.iter().zip(positions).enumerate() {
                if self.nodes.by_id.contains(id) {
                    refused = Some((k, duplicate(id)));
                    break;
                }
                if !finite(x) {
                    refused = Some((k, ErrorKind::NonFiniteCoordinate { node: id }));
                    break;
                }
                self.nodes.by_id.insert(id, self.nodes.ids.len() as u32);
                self.nodes.ids.push(id);
                added += 1;
            }
            (added, refused)
        };
        if added > 0 {
            let points = || positions[..added].par_iter().map(|&x| Point::from(x));
            self.nodes.initial.par_extend(points());
            self.nodes.coordinates.par_extend(points());
            let len = self.nodes.ids.len();
            let more = len - self.nodes.flags.len();
            (self.nodes.flags).par_extend(rayon::iter::repeat_n(crate::Flags::default(), more));
            self.nodes.stamp = crate::entities::fresh_stamp();
            self.nodal_data.resize(len);
        }
        match refused {
            Some((k, e)) => Err((k, e.into())),
            None => Ok(()),
        }
    }

    /// Adds an element. `name` is the Kratos name it was read as (may be empty). Errors on a
    /// duplicate id, a missing node or a node count that does not fit `kind`.
    pub fn add_element(
        &mut self,
        id: ElementId,
        kind: GeometryKind,
        name: &str,
        nodes: &[NodeId],
        properties: PropertiesId,
    ) -> Result<ElementIdx, Error> {
        let idx = ElementIdx(self.elements.len() as u32);
        let mut buffer = [NodeIdx(0); MAX_ENTITY_NODES];
        let conn = self.resolve(EntityKind::Element, id.0, kind, nodes, &mut buffer)?;
        if self.elements.by_id.contains(id.0) {
            return Err(ErrorKind::DuplicateId {
                entity: EntityKind::Element,
                id: id.0,
            }
            .into());
        }
        self.elements.push(id.0, kind, name, conn, properties);
        Ok(idx)
    }

    /// Adds a condition. As [`ModelPart::add_element`].
    pub fn add_condition(
        &mut self,
        id: ConditionId,
        kind: GeometryKind,
        name: &str,
        nodes: &[NodeId],
        properties: PropertiesId,
    ) -> Result<ConditionIdx, Error> {
        let idx = ConditionIdx(self.conditions.len() as u32);
        let mut buffer = [NodeIdx(0); MAX_ENTITY_NODES];
        let conn = self.resolve(EntityKind::Condition, id.0, kind, nodes, &mut buffer)?;
        if self.conditions.by_id.contains(id.0) {
            return Err(ErrorKind::DuplicateId {
                entity: EntityKind::Condition,
                id: id.0,
            }
            .into());
        }
        self.conditions.push(id.0, kind, name, conn, properties);
        self.index_maps.push(IndexMap::new());
        self.condition_normals.push(Vector::zeros());
        Ok(idx)
    }

    /// Adds the entity records `records` in order, as elements (`conditions == false`) or
    /// conditions of `kind` named `name`: each record is `kind.n_nodes() + 2` ids — the id,
    /// the properties id, the node ids. The same model and the same first error as
    /// [`ModelPart::ensure_properties`] then [`ModelPart::add_element`] /
    /// [`ModelPart::add_condition`] record by record (the records before a refused one are
    /// added), with the node ids resolved in parallel (rayon's pool) and the columns extended
    /// once. The error comes with the refused record's position.
    pub fn add_entity_records(
        &mut self,
        conditions: bool,
        kind: GeometryKind,
        name: &str,
        records: &[u32],
    ) -> Result<(), (usize, Error)> {
        use rayon::prelude::*;
        /// Records per parallel task.
        const RECORDS_PER_TASK: usize = 4096;
        let n = kind.n_nodes();
        let width = n + 2;
        let entity = if conditions {
            EntityKind::Condition
        } else {
            EntityKind::Element
        };
        if n == 0 || n > MAX_ENTITY_NODES || !records.len().is_multiple_of(width) {
            // Every record is refused the same way one by one: the first says how.
            for (k, r) in records.chunks(width).enumerate() {
                // (A short last record reads its missing properties id as 0.)
                let properties = PropertiesId(r.get(1).copied().unwrap_or(0));
                self.ensure_properties(properties);
                let nodes: Vec<NodeId> = r.iter().skip(2).map(|&id| NodeId(id)).collect();
                let id = r[0];
                let added = if conditions {
                    self.add_condition(ConditionId(id), kind, name, &nodes, properties)
                        .map(|_| ())
                } else {
                    self.add_element(ElementId(id), kind, name, &nodes, properties)
                        .map(|_| ())
                };
                added.map_err(|e| (k, e))?;
            }
            return Ok(());
        }
        let count = records.len() / width;
        let target = if conditions {
            &mut self.conditions
        } else {
            &mut self.elements
        };
        target.reserve(count, n);
        // The node indices, written in place, and per task the first record naming a
        // missing node.
        let start = target.connectivity.len();
        target.connectivity.resize(start + count * n, NodeIdx(0));
        let nodes = &self.nodes;
        let missing = target.connectivity[start..]
            .par_chunks_mut(RECORDS_PER_TASK * n)
            .zip(records.par_chunks(RECORDS_PER_TASK * width))
            .enumerate()
            .map(|(task, (out, recs))| {
                let pairs = out.chunks_exact_mut(n).zip(recs.chunks_exact(width));
                for (k, (slots, r)) in pairs.enumerate() {
                    for (slot, &node) in slots.iter_mut().zip(&r[2..]) {
                        match nodes.index_of(node) {
                            Some(idx) => *slot = idx,
                            None => return Some((task * RECORDS_PER_TASK + k, node)),
                        }
                    }
                }
                None
            })
            .find_first(Option::is_some)
            .flatten();
        let usable = missing.map_or(count, |(k, _)| k);
        let mut refused = None;
        let first = target.ids.len() as u32;
        let id_of = |k: usize| records[k * width];
        // In one parallel pass where the ids ascend from above every id present (no duplicate
        // is then possible); else record by record.
        let added = if target.by_id.insert_ascending(usable, id_of, first) {
            target
                .ids
                .par_extend((0..usable).into_par_iter().map(id_of));
            // The properties named, each once (per task the runs of one id are skipped).
            let named = (records.par_chunks_exact(width))
                .take(usable)
                .fold(
                    || (BTreeSet::new(), None),
                    |(mut set, last), r| {
                        if last != Some(r[1]) {
                            set.insert(r[1]);
                        }
                        (set, Some(r[1]))
                    },
                )
                .map(|(set, _)| set)
                .reduce(BTreeSet::new, |mut a, mut b| {
                    a.append(&mut b);
                    a
                });
            for p in named {
                (self.properties)
                    .entry(PropertiesId(p))
                    .or_insert_with(|| Properties::new(PropertiesId(p)));
            }
            usable
        } else {
            let mut last_properties = None;
            let mut added = 0;
            for (k, r) in records.chunks_exact(width).take(usable).enumerate() {
                if last_properties != Some(r[1]) {
                    self.properties
                        .entry(PropertiesId(r[1]))
                        .or_insert_with(|| Properties::new(PropertiesId(r[1])));
                    last_properties = Some(r[1]);
                }
                if target.by_id.contains(r[0]) {
                    refused = Some((k, ErrorKind::DuplicateId { entity, id: r[0] }));
                    break;
                }
                target.by_id.insert(r[0], target.ids.len() as u32);
                target.ids.push(r[0]);
                added += 1;
            }
            added
        };
        // The other columns of the records added; the connectivity of the others goes.
        target.connectivity.truncate(start + added * n);
        target.extend_added(added, kind, name, records, width);
        if conditions {
            // Written in parallel (fresh memory: its first touch is much of the cost).
            let new = self.index_maps.len()..self.conditions.len();
            self.index_maps
                .par_extend(new.into_par_iter().map(|_| IndexMap::new()));
            let new = self.condition_normals.len()..self.conditions.len();
            self.condition_normals
                .par_extend(new.into_par_iter().map(|_| Vector::zeros()));
        }
        if let Some((k, e)) = refused {
            return Err((k, e.into()));
        }
        if let Some((k, node)) = missing {
            let r = &records[k * width..(k + 1) * width];
            self.ensure_properties(PropertiesId(r[1]));
            return Err((
                k,
                ErrorKind::MissingNode {
                    entity,
                    id: r[0],
                    node,
                }
                .into(),
            ));
        }
        Ok(())
    }

    /// The dense indices of `nodes`, into `out` (the first `nodes.len()` entries).
    fn resolve<'b>(
        &self,
        entity: EntityKind,
        id: u32,
        kind: GeometryKind,
        nodes: &[NodeId],
        out: &'b mut [NodeIdx; MAX_ENTITY_NODES],
    ) -> Result<&'b [NodeIdx], Error> {
        if nodes.len() != kind.n_nodes() || nodes.len() > MAX_ENTITY_NODES {
            return Err(ErrorKind::WrongNodeCount {
                entity,
                id,
                expected: kind.n_nodes(),
                found: nodes.len(),
            }
            .into());
        }
        for (slot, n) in out.iter_mut().zip(nodes) {
            *slot = self.nodes.index_of(n.0).ok_or_else(|| {
                Error::from(ErrorKind::MissingNode {
                    entity,
                    id,
                    node: n.0,
                })
            })?;
        }
        Ok(&out[..nodes.len()])
    }

    /// Adds a properties block; errors if its id exists.
    pub fn add_properties(&mut self, properties: Properties) -> Result<(), Error> {
        if self.properties.contains_key(&properties.id) {
            return Err(ErrorKind::DuplicateId {
                entity: EntityKind::Properties,
                id: properties.id.0,
            }
            .into());
        }
        self.properties.insert(properties.id, properties);
        Ok(())
    }

    /// Adds a properties block with no value if `id` does not exist yet.
    pub fn ensure_properties(&mut self, id: PropertiesId) {
        self.properties
            .entry(id)
            .or_insert_with(|| Properties::new(id));
    }

    /// The sub model parts, by index.
    pub fn parts(&self) -> &[SubModelPart] {
        &self.parts
    }

    /// The sub model part `idx`.
    pub fn part(&self, idx: PartIdx) -> &SubModelPart {
        &self.parts[idx.index()]
    }

    /// The conditions of part `idx` in Kratos' container order (ascending external id). A
    /// mesh numbered in its own order (the usual case) lists them so already: that list is
    /// lent (checked in parallel), not copied.
    pub fn part_conditions_by_id(&self, idx: PartIdx) -> std::borrow::Cow<'_, [ConditionIdx]> {
        use rayon::prelude::*;
        let conditions = self.part(idx).conditions();
        let ids = self.conditions.ids();
        if (conditions.par_windows(2)).all(|w| ids[w[0].index()] < ids[w[1].index()]) {
            return std::borrow::Cow::Borrowed(conditions);
        }
        let mut v: Vec<ConditionIdx> = conditions.par_iter().copied().collect();
        // Ids are unique: one order, whatever the sort.
        v.par_sort_unstable_by_key(|c| ids[c.index()]);
        std::borrow::Cow::Owned(v)
    }

    /// The parts directly under the root, in creation order.
    pub fn root_parts(&self) -> &[PartIdx] {
        &self.roots
    }

    /// The part at full path `path` (segments separated by `.` or `/`).
    pub fn find_part(&self, path: &str) -> Option<PartIdx> {
        self.part_by_path.get(&normalize_path(path)).copied()
    }

    /// The part at `path`, or [`ErrorKind::UnknownPart`].
    pub fn get_part(&self, path: &str) -> Result<PartIdx, Error> {
        self.find_part(path)
            .ok_or_else(|| ErrorKind::UnknownPart(path.to_owned()).into())
    }

    /// Full paths of every part, sorted.
    pub fn part_paths(&self) -> Vec<&str> {
        let mut v: Vec<&str> = self.parts.iter().map(|p| p.path.as_str()).collect();
        v.sort_unstable();
        v
    }

    /// Returns the part at full path `path`, creating it and any missing ancestor.
    pub fn create_part(&mut self, path: &str) -> Result<PartIdx, Error> {
        let normalized = normalize_path(path);
        if normalized.is_empty() || normalized.split('.').any(|s| s.is_empty()) {
            return Err(ErrorKind::InvalidPartName(path.to_owned()).into());
        }
        let mut parent: Option<PartIdx> = None;
        let mut current = String::new();
        for segment in normalized.split('.') {
            if !current.is_empty() {
                current.push('.');
            }
            current.push_str(segment);
            let idx = match self.part_by_path.get(&current) {
                Some(&idx) => idx,
                None => {
                    let idx = PartIdx(self.parts.len() as u32);
                    self.parts.push(SubModelPart {
                        name: segment.to_owned(),
                        path: current.clone(),
                        parent,
                        ..SubModelPart::default()
                    });
                    self.part_by_path.insert(current.clone(), idx);
                    match parent {
                        Some(p) => self.parts[p.index()].children.push(idx),
                        None => self.roots.push(idx),
                    }
                    idx
                }
            };
            parent = Some(idx);
        }
        // The loop ran at least once: `normalized` is non-empty.
        parent.ok_or_else(|| ErrorKind::InvalidPartName(path.to_owned()).into())
    }

    /// Adds nodes to `part` and its ancestors.
    pub fn add_nodes_to_part(&mut self, part: PartIdx, nodes: &[NodeIdx]) {
        let mut p = Some(part);
        while let Some(idx) = p {
            let sp = &mut self.parts[idx.index()];
            merge_sorted(&mut sp.nodes, nodes);
            p = sp.parent;
        }
    }

    /// Adds elements to `part` and its ancestors. Only the elements are added, as in Kratos'
    /// mdpa reader; add their nodes with [`ModelPart::add_nodes_to_part`].
    pub fn add_elements_to_part(&mut self, part: PartIdx, elements: &[ElementIdx]) {
        let mut p = Some(part);
        while let Some(idx) = p {
            let sp = &mut self.parts[idx.index()];
            merge_sorted(&mut sp.elements, elements);
            p = sp.parent;
        }
    }

    /// Adds conditions to `part` and its ancestors.
    pub fn add_conditions_to_part(&mut self, part: PartIdx, conditions: &[ConditionIdx]) {
        let mut p = Some(part);
        while let Some(idx) = p {
            let sp = &mut self.parts[idx.index()];
            merge_sorted(&mut sp.conditions, conditions);
            p = sp.parent;
        }
    }

    /// Removes conditions from `part` and from every part below it (Kratos'
    /// `RemoveConditions` on a sub model part); the conditions stay in the root and in the
    /// part's ancestors.
    pub fn remove_conditions_from_part(&mut self, part: PartIdx, conditions: &[ConditionIdx]) {
        let mut sorted = conditions.to_vec();
        sorted.sort_unstable();
        let mut stack = vec![part];
        while let Some(idx) = stack.pop() {
            let sp = &mut self.parts[idx.index()];
            sp.conditions.retain(|c| sorted.binary_search(c).is_err());
            stack.extend(sp.children.iter().copied());
        }
    }

    /// The coordinates of the nodes of `nodes`, gathered into `out` (cleared first).
    pub fn gather_points(&self, nodes: &[NodeIdx], out: &mut Vec<Point>) {
        out.clear();
        out.extend(nodes.iter().map(|n| self.nodes.coordinates[n.index()]));
    }
}

/// Accepts `/` as a separator too; returns the `.`-separated form.
fn normalize_path(path: &str) -> String {
    path.trim().replace('/', ".")
}

#[cfg(test)]
mod tests;
