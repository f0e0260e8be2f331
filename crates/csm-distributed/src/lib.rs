//! The contact search split across ranks (issue 29, `docs/distributed.md`, "Partitioning"):
//! the recursive coordinate bisection of the slave conditions ([`rcb`]) and each rank's part
//! of the mesh ([`split`]): its own slave conditions, the slave conditions that share a node
//! with them, the master conditions within reach of any of these, the elements around their
//! nodes, and every node they use.
//!
//! No MPI here. A rank's part is an ordinary [`MeshArrays`]: the split is checked in one
//! process by searching every part, with the whole problem's values
//! (`csm_search::ContactSearch::set_globals`), and comparing its owned slaves' pairs and owned
//! nodes' results with the search of the whole mesh (the tests). The exchange of the parts
//! between ranks, the ghost values and the mapper's per-iteration global sum are the next steps
//! of the issue.
//!
//! **Architecture Invariant:** `csm-distributed` depends only on `csm-model` and
//! `csm-geometry` (its tests also read meshes and search them). A rank's part holds everything
//! its owned values read, except the global sums and maximum the ranks must share
//! (`docs/distributed.md`, "What exactly demands").

use std::collections::{BTreeMap, BTreeSet, HashMap};

mod codec;
#[cfg(feature = "mpi")]
mod mpi;
mod partitioned;
mod run;
mod threads;

#[cfg(feature = "mpi")]
pub use mpi::MpiTransport;
pub use partitioned::search_partitioned;
pub use run::{RankTimes, RunError, distributed_pair, fail_rank, search_rank, search_rank_timed};
pub use threads::{ThreadTransport, thread_ranks};

use csm_geometry::GeometryKind;
use csm_model::{EntityArrays, MeshArrays, PartArrays};

/// Why a mesh cannot be split.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SplitError {
    /// No rank to split for.
    NoRanks,
    /// A part named for the slaves or the contact faces is not in the mesh.
    UnknownPart(String),
    /// A condition names a node the mesh does not have.
    MissingNode { condition: u32, node: u32 },
    /// The slave parts hold no condition.
    NoSlaves,
}

impl std::fmt::Display for SplitError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SplitError::NoRanks => write!(f, "split: 0 ranks; give 1 or more"),
            SplitError::UnknownPart(p) => write!(f, "split: no part `{p}` in the mesh"),
            SplitError::MissingNode { condition, node } => {
                write!(
                    f,
                    "split: condition {condition} names node {node}, which is missing"
                )
            }
            SplitError::NoSlaves => write!(f, "split: the slave parts hold no condition"),
        }
    }
}

impl std::error::Error for SplitError {}

/// The rank (`0..ranks`) of each point by recursive coordinate bisection: each cut halves
/// the points (in proportion to the ranks on each side) along the longest side of their
/// bounding box, ordered by that coordinate and then by `key`, so the split depends on the
/// points and keys alone, not on their order.
pub fn rcb(points: &[([f64; 3], u32)], ranks: usize) -> Vec<u32> {
    let mut owner = vec![0; points.len()];
    let mut items: Vec<usize> = (0..points.len()).collect();
    bisect(points, &mut items, (ranks.max(1), 0), &mut owner);
    owner
}

fn bisect(
    points: &[([f64; 3], u32)],
    items: &mut [usize],
    (ranks, first): (usize, u32),
    owner: &mut [u32],
) {
    if ranks == 1 || items.len() <= 1 {
        for &i in items.iter() {
            owner[i] = first;
        }
        return;
    }
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for &i in items.iter() {
        for k in 0..3 {
            lo[k] = lo[k].min(points[i].0[k]);
            hi[k] = hi[k].max(points[i].0[k]);
        }
    }
    let axis = (0..3)
        .max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b])).then(b.cmp(&a)))
        .unwrap_or(0);
    items.sort_unstable_by(|&a, &b| {
        points[a].0[axis]
            .total_cmp(&points[b].0[axis])
            .then(points[a].1.cmp(&points[b].1))
    });
    let left = ranks / 2;
    let cut = items.len() * left / ranks;
    let (a, b) = items.split_at_mut(cut);
    bisect(points, a, (left, first), owner);
    bisect(points, b, (ranks - left, first + left as u32), owner);
}

/// How far a slave's search reaches: `factor` × its radius (the largest distance from its
/// centre to a node) beyond its centre, plus the master's radius. It must cover every
/// search type's candidates (the tests check it against the whole mesh's search); a larger
/// factor only makes the halo larger.
#[derive(Debug, Clone, Copy)]
pub struct Reach {
    /// Slave radii.
    pub factor: f64,
}

impl Reach {
    /// A reach that covers a search of `search_factor` (and `bounding_box_factor`) with a
    /// margin: `4 · max(search_factor, 1) + 2` slave radii.
    pub fn for_search_factor(search_factor: f64) -> Reach {
        Reach {
            factor: 4.0 * search_factor.max(1.0) + 2.0,
        }
    }
}

/// One rank's part of the mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct RankPart {
    /// The mesh the rank searches (entities in the whole mesh's order, parts kept with the
    /// members it holds).
    pub mesh: MeshArrays,
    /// The slave conditions it owns (ids, ascending): their pairs are its result.
    pub owned_conditions: Vec<u32>,
    /// The slave nodes it owns (ids, ascending: a slave node belongs to the owner of its
    /// lowest-id slave condition): their nodal results are its result.
    pub owned_nodes: Vec<u32>,
}

/// Splits `mesh` for `ranks` ranks. The slave conditions are the conditions of the parts
/// `slaves` (full paths); the masters the other conditions of the parts `contact`. The slave
/// conditions are split by [`rcb`] of their centres (keyed by id); each rank's part holds
/// (`docs/distributed.md`):
/// 1. its slave conditions and every slave condition that shares a node with one (the ring
///    the nodal sums over slave nodes need);
/// 2. every master condition within `reach` of a slave condition it holds, and every master
///    condition that shares a node with one of these (the mean normals at a master node);
/// 3. every element with a node among its conditions' nodes, and every element with a node
///    among those elements' nodes (interface, normal check and NODAL_H read the elements
///    around a contact node, the normal check's probe point one layer further);
/// 4. every node these use.
pub fn split(
    mesh: &MeshArrays,
    roles: (&[&str], &[&str]),
    ranks: usize,
    reach: Reach,
) -> Result<Vec<RankPart>, SplitError> {
    parts_of(mesh, roles, (ranks, 0..ranks as u32), reach)
}

/// The part of rank `rank` of [`split`] alone (what each rank of a distributed run builds).
pub fn split_rank(
    mesh: &MeshArrays,
    roles: (&[&str], &[&str]),
    (ranks, rank): (usize, usize),
    reach: Reach,
) -> Result<RankPart, SplitError> {
    let mut parts = parts_of(mesh, roles, (ranks, rank as u32..rank as u32 + 1), reach)?;
    parts.pop().ok_or(SplitError::NoRanks)
}

/// The parts of the ranks `which` of a split for `ranks` ranks.
fn parts_of(
    mesh: &MeshArrays,
    (slaves, contact): (&[&str], &[&str]),
    (ranks, which): (usize, std::ops::Range<u32>),
    reach: Reach,
) -> Result<Vec<RankPart>, SplitError> {
    if ranks == 0 || which.end as usize > ranks {
        return Err(SplitError::NoRanks);
    }
    let point_of: HashMap<u32, [f64; 3]> = mesh
        .node_ids
        .iter()
        .copied()
        .zip(mesh.points.iter().copied())
        .collect();
    let conditions = index(&mesh.conditions);
    let part_conditions = |names: &[&str]| -> Result<BTreeSet<u32>, SplitError> {
        let mut out = BTreeSet::new();
        for name in names {
            let part = mesh
                .parts
                .get(*name)
                .ok_or_else(|| SplitError::UnknownPart((*name).to_owned()))?;
            out.extend(part.conditions.iter().copied());
        }
        Ok(out)
    };
    let slave_ids = part_conditions(slaves)?;
    let master_ids: Vec<u32> = part_conditions(contact)?
        .difference(&slave_ids)
        .copied()
        .collect();
    let slave_ids: Vec<u32> = slave_ids.into_iter().collect();
    if slave_ids.is_empty() {
        return Err(SplitError::NoSlaves);
    }
    // Centre (node mean) and radius of a condition.
    let shape = |id: u32| -> Result<([f64; 3], f64), SplitError> {
        let nodes = conditions[&id];
        let mut pts = Vec::with_capacity(nodes.len());
        for &n in nodes {
            let p = point_of.get(&n).ok_or(SplitError::MissingNode {
                condition: id,
                node: n,
            })?;
            pts.push(*p);
        }
        let mut centre = [0.0; 3];
        for p in &pts {
            for k in 0..3 {
                centre[k] += p[k] / pts.len() as f64;
            }
        }
        let radius = pts.iter().map(|p| distance(p, &centre)).fold(0.0, f64::max);
        Ok((centre, radius))
    };
    let slave_shapes: Vec<([f64; 3], f64)> = slave_ids
        .iter()
        .map(|&id| shape(id))
        .collect::<Result<_, _>>()?;
    let master_shapes: Vec<([f64; 3], f64)> = master_ids
        .iter()
        .map(|&id| shape(id))
        .collect::<Result<_, _>>()?;
    let largest_master_radius = master_shapes.iter().map(|s| s.1).fold(0.0, f64::max);
    let keyed: Vec<([f64; 3], u32)> = slave_shapes
        .iter()
        .zip(&slave_ids)
        .map(|((c, _), &id)| (*c, id))
        .collect();
    let owner = rcb(&keyed, ranks);
    // The contact parts' nodes on no contact condition (a part's node list may name more
    // nodes than its conditions use): split by their own bisection.
    let on_conditions: BTreeSet<u32> = (slave_ids.iter().chain(&master_ids))
        .flat_map(|id| conditions[id].iter().copied())
        .collect();
    let mut loose: BTreeSet<u32> = BTreeSet::new();
    for name in slaves.iter().chain(contact) {
        if let Some(part) = mesh.parts.get(*name) {
            loose.extend(part.nodes.iter().filter(|n| !on_conditions.contains(n)));
        }
    }
    let loose_nodes: Vec<([f64; 3], u32)> = loose
        .iter()
        .filter_map(|n| point_of.get(n).map(|p| (*p, *n)))
        .collect();
    let loose_owner = rcb(&loose_nodes, ranks);
    // Slave nodes: the slave conditions at each, ascending by id (the slave ids are).
    let mut at_node: BTreeMap<u32, Vec<usize>> = BTreeMap::new();
    for (s, id) in slave_ids.iter().enumerate() {
        for &n in conditions[id] {
            let list = at_node.entry(n).or_default();
            if list.last() != Some(&s) {
                list.push(s);
            }
        }
    }
    let mut masters_at_node: HashMap<u32, Vec<usize>> = HashMap::new();
    for (m, id) in master_ids.iter().enumerate() {
        for &n in conditions[id] {
            masters_at_node.entry(n).or_default().push(m);
        }
    }
    let mut parts = Vec::with_capacity(which.len());
    for rank in which {
        let owned: Vec<usize> = (0..slave_ids.len()).filter(|&s| owner[s] == rank).collect();
        // 1. The owned slaves and two rings around them: the nodal sums at an owned node
        // read every slave condition at it (the first ring), and those conditions' operators
        // read the mean normals of all their nodes, sums over the conditions at them (the
        // second ring).
        let mut held_slaves: BTreeSet<usize> = owned.iter().copied().collect();
        for _ in 0..2 {
            let inner: Vec<usize> = held_slaves.iter().copied().collect();
            for s in inner {
                for n in conditions[&slave_ids[s]] {
                    held_slaves.extend(at_node[n].iter().copied());
                }
            }
        }
        // 2. The masters within reach of a held slave.
        let held: Vec<([f64; 3], f64)> = held_slaves.iter().map(|&s| slave_shapes[s]).collect();
        let near = Near::new(&held, reach, largest_master_radius);
        let held_masters: Vec<usize> = (0..master_ids.len())
            .filter(|&m| near.reaches(master_shapes[m]))
            .collect();
        // The masters sharing a node with one of these (the mean normals at a master node
        // sum over every master condition at it).
        let mut ring: BTreeSet<usize> = held_masters.iter().copied().collect();
        for &m in &held_masters {
            for n in conditions[&master_ids[m]] {
                ring.extend(masters_at_node.get(n).into_iter().flatten().copied());
            }
        }
        let held_conditions: BTreeSet<u32> = held_slaves
            .iter()
            .map(|&s| slave_ids[s])
            .chain(ring.iter().map(|&m| master_ids[m]))
            .collect();
        let mut contact_nodes: BTreeSet<u32> = held_conditions
            .iter()
            .flat_map(|id| conditions[id].iter().copied())
            .collect();
        // The contact parts' nodes on no contact condition that this rank holds for the
        // largest and the mean NODAL_H (they count there as in the one-process run).
        contact_nodes.extend(
            (loose_nodes.iter().zip(&loose_owner))
                .filter(|(_, o)| **o == rank)
                .map(|(n, _)| n.1),
        );
        // 3. The elements around the contact nodes, two layers deep (the normal check's probe
        // point, a fraction of an element inside the body, can fall past the first layer);
        // 4. every node used.
        let first = filter_entities(&mesh.elements, |_, nodes| {
            nodes.iter().any(|n| contact_nodes.contains(n))
        });
        let first_nodes: BTreeSet<u32> = first
            .values()
            .flat_map(|a| a.connectivity.iter().copied())
            .collect();
        let elements = filter_entities(&mesh.elements, |_, nodes| {
            nodes.iter().any(|n| first_nodes.contains(n))
        });
        let conditions_kept =
            filter_entities(&mesh.conditions, |id, _| held_conditions.contains(&id));
        let mut used: BTreeSet<u32> = contact_nodes.clone();
        for arrays in elements.values() {
            used.extend(arrays.connectivity.iter().copied());
        }
        let (node_ids, points): (Vec<u32>, Vec<[f64; 3]>) = mesh
            .node_ids
            .iter()
            .zip(&mesh.points)
            .filter(|(id, _)| used.contains(id))
            .map(|(id, p)| (*id, *p))
            .unzip();
        let element_ids: BTreeSet<u32> = elements
            .values()
            .flat_map(|a| a.ids.iter().copied())
            .collect();
        let part_arrays = mesh
            .parts
            .iter()
            .map(|(path, p)| {
                let kept = PartArrays {
                    // Only the nodes whose elements are all held (their NODAL_H is whole).
                    nodes: p
                        .nodes
                        .iter()
                        .copied()
                        .filter(|n| contact_nodes.contains(n))
                        .collect(),
                    elements: p
                        .elements
                        .iter()
                        .copied()
                        .filter(|e| element_ids.contains(e))
                        .collect(),
                    conditions: p
                        .conditions
                        .iter()
                        .copied()
                        .filter(|c| held_conditions.contains(c))
                        .collect(),
                };
                (path.clone(), kept)
            })
            .collect();
        let mut owned_conditions: Vec<u32> = owned.iter().map(|&s| slave_ids[s]).collect();
        owned_conditions.sort_unstable();
        let owned_nodes: Vec<u32> = at_node
            .iter()
            .filter(|(_, at)| owner[at[0]] == rank)
            .map(|(n, _)| *n)
            .collect();
        parts.push(RankPart {
            mesh: MeshArrays {
                node_ids,
                points,
                elements,
                conditions: conditions_kept,
                parts: part_arrays,
                domain_size: mesh.domain_size,
            },
            owned_conditions,
            owned_nodes,
        });
    }
    Ok(parts)
}

/// The held slaves (centre, radius) bucketed in a grid whose cells are as wide as the
/// farthest reach, so that a master's reaching slaves lie in the 27 cells around it.
struct Near<'a> {
    slaves: &'a [([f64; 3], f64)],
    reach: Reach,
    cell: f64,
    cells: HashMap<[i64; 3], Vec<usize>>,
}

impl<'a> Near<'a> {
    fn new(slaves: &'a [([f64; 3], f64)], reach: Reach, largest_master_radius: f64) -> Near<'a> {
        let farthest = slaves
            .iter()
            .map(|s| reach.factor * s.1)
            .fold(0.0, f64::max);
        let cell = farthest + largest_master_radius;
        let cell = if cell.is_finite() && cell > 0.0 {
            cell
        } else {
            1.0
        };
        let mut cells: HashMap<[i64; 3], Vec<usize>> = HashMap::new();
        for (k, (c, _)) in slaves.iter().enumerate() {
            cells.entry(cell_of(c, cell)).or_default().push(k);
        }
        Near {
            slaves,
            reach,
            cell,
            cells,
        }
    }

    /// Whether a master (centre, radius) is within reach of some slave: `distance ≤ factor ·
    /// slave radius + master radius`.
    fn reaches(&self, (cm, rm): ([f64; 3], f64)) -> bool {
        let at = cell_of(&cm, self.cell);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let key = [at[0] + dx, at[1] + dy, at[2] + dz];
                    let Some(list) = self.cells.get(&key) else {
                        continue;
                    };
                    if list.iter().any(|&k| {
                        let (cs, rs) = self.slaves[k];
                        distance(&cs, &cm) <= self.reach.factor * rs + rm
                    }) {
                        return true;
                    }
                }
            }
        }
        false
    }
}

fn cell_of(p: &[f64; 3], cell: f64) -> [i64; 3] {
    p.map(|x| (x / cell).floor() as i64)
}

fn distance(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// The conditions' nodes by condition id.
fn index(by_kind: &BTreeMap<GeometryKind, EntityArrays>) -> HashMap<u32, &[u32]> {
    let mut out = HashMap::new();
    for (&kind, arrays) in by_kind {
        let n = kind.n_nodes();
        for (k, &id) in arrays.ids.iter().enumerate() {
            out.insert(id, &arrays.connectivity[k * n..(k + 1) * n]);
        }
    }
    out
}

/// The entities `keep(id, nodes)` holds, in their order, by kind (kinds left empty dropped).
fn filter_entities(
    by_kind: &BTreeMap<GeometryKind, EntityArrays>,
    keep: impl Fn(u32, &[u32]) -> bool,
) -> BTreeMap<GeometryKind, EntityArrays> {
    let mut out = BTreeMap::new();
    for (&kind, arrays) in by_kind {
        let n = kind.n_nodes();
        let mut kept = EntityArrays::default();
        for (k, &id) in arrays.ids.iter().enumerate() {
            let nodes = &arrays.connectivity[k * n..(k + 1) * n];
            if keep(id, nodes) {
                kept.ids.push(id);
                kept.connectivity.extend_from_slice(nodes);
                kept.properties.push(arrays.properties[k]);
            }
        }
        if !kept.ids.is_empty() {
            out.insert(kind, kept);
        }
    }
    out
}

#[cfg(test)]
mod tests;
