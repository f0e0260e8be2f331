//! The contact search split across ranks (issue 29, `docs/distributed.md`): the recursive
//! coordinate bisection of the slave conditions ([`rcb`]) and each rank's part of the mesh
//! ([`split`], [`split_rank`]): its own slave conditions, two rings of slave conditions around
//! them, the master conditions within reach of these and their ring, the elements around their
//! nodes, and every node they use; one rank's search of its part with the values the ranks
//! share ([`search_rank`]), and the host-partitioned form ([`search_partitioned`]); the ranks
//! as threads ([`thread_ranks`]) or, with the feature `mpi`, as the processes of `mpirun`
//! (`MpiTransport`).
//!
//! **Architecture Invariant:** `csm-distributed` depends on `csm-search` and the layers below
//! it. A rank's part holds everything its owned values read; what it cannot hold (the global
//! sums and maxima, the ghost slave nodes' values between mapper iterations) the ranks
//! exchange in the serial order (`csm_model::Ranks`), so that every owned value is the
//! one-process value, bit for bit.

use std::collections::{BTreeMap, BTreeSet, HashMap, HashSet};

mod codec;
#[cfg(feature = "mpi")]
mod mpi;
mod partitioned;
mod run;
mod threads;

#[cfg(feature = "mpi")]
pub use mpi::MpiTransport;
pub use partitioned::search_partitioned;
pub use run::{
    DistributedPlan, RankTimes, RunError, distributed_plan, fail_rank, search_rank,
    search_rank_timed,
};
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
    /// Every rank holds every master condition, whatever the distance, and every node of the
    /// contact parts on no contact condition: for a search whose result depends on a tree
    /// over all the masters (Kratos' DirectCheck reads the ACTIVE flags its earlier
    /// candidates set, in the kd-tree's candidate order; the octree is refined around every
    /// master-side node).
    pub every_master: bool,
}

impl Reach {
    /// A reach that covers a search of `search_factor` (and `bounding_box_factor`) with a
    /// margin: `4 · max(search_factor, 1) + 2` slave radii.
    pub fn for_search_factor(search_factor: f64) -> Reach {
        Reach {
            factor: 4.0 * search_factor.max(1.0) + 2.0,
            every_master: false,
        }
    }

    /// This reach, holding every master condition ([`Reach::every_master`]).
    pub fn with_every_master(self) -> Reach {
        Reach {
            every_master: true,
            ..self
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
    // Nodes by index (their position in the mesh); sets of nodes are flags by index.
    let n_nodes = mesh.node_ids.len();
    let node_index = NodeIndex::new(&mesh.node_ids);
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
    // A condition's nodes by index.
    let nodes_of = |id: u32| -> Result<Vec<u32>, SplitError> {
        let nodes = conditions.get(&id).copied().unwrap_or_default();
        (nodes.iter())
            .map(|&n| {
                (node_index.get(n)).ok_or(SplitError::MissingNode {
                    condition: id,
                    node: n,
                })
            })
            .collect()
    };
    let slave_nodes: Vec<Vec<u32>> =
        (slave_ids.iter().map(|&id| nodes_of(id))).collect::<Result<_, _>>()?;
    let master_nodes: Vec<Vec<u32>> =
        (master_ids.iter().map(|&id| nodes_of(id))).collect::<Result<_, _>>()?;
    // Centre (node mean) and radius of a condition.
    let shape = |nodes: &Vec<u32>| -> ([f64; 3], f64) {
        let pts: Vec<[f64; 3]> = nodes.iter().map(|&n| mesh.points[n as usize]).collect();
        let mut centre = [0.0; 3];
        for p in &pts {
            for k in 0..3 {
                centre[k] += p[k] / pts.len() as f64;
            }
        }
        let radius = pts.iter().map(|p| distance(p, &centre)).fold(0.0, f64::max);
        (centre, radius)
    };
    let slave_shapes: Vec<([f64; 3], f64)> = slave_nodes.iter().map(shape).collect();
    let master_shapes: Vec<([f64; 3], f64)> = master_nodes.iter().map(shape).collect();
    let largest_master_radius = master_shapes.iter().map(|s| s.1).fold(0.0, f64::max);
    let keyed: Vec<([f64; 3], u32)> = slave_shapes
        .iter()
        .zip(&slave_ids)
        .map(|((c, _), &id)| (*c, id))
        .collect();
    let owner = rcb(&keyed, ranks);
    // The contact parts' nodes on no contact condition (a part's node list may name more
    // nodes than its conditions use): split by their own bisection.
    let mut on_conditions = vec![false; n_nodes];
    for &n in slave_nodes.iter().chain(&master_nodes).flatten() {
        on_conditions[n as usize] = true;
    }
    let mut loose: BTreeSet<u32> = BTreeSet::new();
    for name in slaves.iter().chain(contact) {
        if let Some(part) = mesh.parts.get(*name) {
            loose.extend(
                (part.nodes.iter())
                    .filter_map(|&n| node_index.get(n))
                    .filter(|&i| !on_conditions[i as usize]),
            );
        }
    }
    drop(on_conditions);
    let loose: Vec<u32> = loose.into_iter().collect();
    let loose_keyed: Vec<([f64; 3], u32)> = (loose.iter())
        .map(|&i| (mesh.points[i as usize], mesh.node_ids[i as usize]))
        .collect();
    let loose_owner = rcb(&loose_keyed, ranks);
    // The slave conditions at each node (positions, ascending: the slave ids are), the master
    // conditions at each node.
    let at_node = Incidence::new(n_nodes, &slave_nodes);
    let masters_at_node = Incidence::new(n_nodes, &master_nodes);
    // The elements' nodes by index (`u32::MAX`: a node the mesh lacks), in the mesh's order.
    let element_nodes: Vec<Vec<u32>> = (mesh.elements.iter())
        .flat_map(|(kind, a)| a.connectivity.chunks(kind.n_nodes().max(1)))
        .map(|nodes| {
            (nodes.iter())
                .map(|&n| node_index.get(n).unwrap_or(u32::MAX))
                .collect()
        })
        .collect();
    let flagged = |flags: &[bool], n: u32| flags.get(n as usize).copied().unwrap_or(false);
    let mut parts = Vec::with_capacity(which.len());
    for rank in which {
        let owned: Vec<usize> = (0..slave_ids.len()).filter(|&s| owner[s] == rank).collect();
        // 1. The owned slaves and two rings around them: the nodal sums at an owned node
        // read every slave condition at it (the first ring), and those conditions' operators
        // read the mean normals of all their nodes, sums over the conditions at them (the
        // second ring).
        let mut held_slave = vec![false; slave_ids.len()];
        let mut held: Vec<usize> = owned.clone();
        for &s in &owned {
            held_slave[s] = true;
        }
        for _ in 0..2 {
            for k in 0..held.len() {
                for &n in &slave_nodes[held[k]] {
                    for &t in at_node.of(n) {
                        if !std::mem::replace(&mut held_slave[t as usize], true) {
                            held.push(t as usize);
                        }
                    }
                }
            }
        }
        held.sort_unstable();
        // 2. The masters within reach of a held slave, and the masters sharing a node with
        // one of these (the mean normals at a master node sum over every master condition at
        // it).
        let shapes: Vec<([f64; 3], f64)> = held.iter().map(|&s| slave_shapes[s]).collect();
        let near = Near::new(&shapes, reach, largest_master_radius);
        let mut held_master = vec![false; master_ids.len()];
        for m in 0..master_ids.len() {
            if reach.every_master || near.reaches(master_shapes[m]) {
                held_master[m] = true;
                for &n in &master_nodes[m] {
                    for &t in masters_at_node.of(n) {
                        held_master[t as usize] = true;
                    }
                }
            }
        }
        let held_conditions = IdSet::new(
            (held.iter().map(|&s| slave_ids[s])).chain(
                (0..master_ids.len())
                    .filter(|&m| held_master[m])
                    .map(|m| master_ids[m]),
            ),
        );
        let mut contact_node = vec![false; n_nodes];
        let held_masters = (0..master_ids.len()).filter(|&m| held_master[m]);
        for nodes in held
            .iter()
            .map(|&s| &slave_nodes[s])
            .chain(held_masters.map(|m| &master_nodes[m]))
        {
            for &n in nodes {
                contact_node[n as usize] = true;
            }
        }
        // The contact parts' nodes on no contact condition that this rank holds for the
        // largest and the mean NODAL_H (they count there as in the one-process run).
        // Holding every master, a rank holds every such node too (the octree is refined
        // around every master-side node).
        for (&n, _) in
            (loose.iter().zip(&loose_owner)).filter(|(_, o)| reach.every_master || **o == rank)
        {
            contact_node[n as usize] = true;
        }
        // 3. The elements around the contact nodes, two layers deep (the normal check's probe
        // point, a fraction of an element inside the body, can fall past the first layer);
        // 4. every node used.
        let mut first_node = vec![false; n_nodes];
        for nodes in &element_nodes {
            if nodes.iter().any(|&n| flagged(&contact_node, n)) {
                for &n in nodes.iter().filter(|&&n| n != u32::MAX) {
                    first_node[n as usize] = true;
                }
            }
        }
        let kept_element: Vec<bool> = (element_nodes.iter())
            .map(|nodes| nodes.iter().any(|&n| flagged(&first_node, n)))
            .collect();
        drop(first_node);
        let mut used = contact_node.clone();
        for (nodes, _) in element_nodes.iter().zip(&kept_element).filter(|(_, k)| **k) {
            for &n in nodes.iter().filter(|&&n| n != u32::MAX) {
                used[n as usize] = true;
            }
        }
        let mut next = 0;
        let elements = filter_entities(&mesh.elements, |_, _| {
            next += 1;
            kept_element[next - 1]
        });
        let element_ids = IdSet::new(elements.values().flat_map(|a| a.ids.iter().copied()));
        let conditions_kept =
            filter_entities(&mesh.conditions, |id, _| held_conditions.contains(id));
        let (node_ids, points): (Vec<u32>, Vec<[f64; 3]>) = (0..n_nodes)
            .filter(|&i| used[i])
            .map(|i| (mesh.node_ids[i], mesh.points[i]))
            .unzip();
        let is_contact_node = |id: &u32| {
            node_index
                .get(*id)
                .is_some_and(|i| contact_node[i as usize])
        };
        let part_arrays = mesh
            .parts
            .iter()
            .map(|(path, p)| {
                let kept = PartArrays {
                    // Only the nodes whose elements are all held (their NODAL_H is whole).
                    nodes: p.nodes.iter().copied().filter(is_contact_node).collect(),
                    elements: (p.elements.iter().copied())
                        .filter(|&e| element_ids.contains(e))
                        .collect(),
                    conditions: (p.conditions.iter().copied())
                        .filter(|&c| held_conditions.contains(c))
                        .collect(),
                };
                (path.clone(), kept)
            })
            .collect();
        let mut owned_conditions: Vec<u32> = owned.iter().map(|&s| slave_ids[s]).collect();
        owned_conditions.sort_unstable();
        // A slave node belongs to the owner of its lowest-id slave condition.
        let mut owned_nodes: Vec<u32> = (0..n_nodes as u32)
            .filter(|&n| {
                at_node
                    .of(n)
                    .first()
                    .is_some_and(|&s| owner[s as usize] == rank)
            })
            .map(|n| mesh.node_ids[n as usize])
            .collect();
        owned_nodes.sort_unstable();
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

/// A set of entity ids: flags by id where the ids are dense enough (their largest at most
/// four times their count, plus 1024), else a hash set. A split asks it once per entity of
/// the whole mesh: a hash set's probes into a table of 1e6 ids were half of the split's time.
enum IdSet {
    Dense(Vec<bool>),
    Sparse(HashSet<u32>),
}

impl IdSet {
    fn new(ids: impl Iterator<Item = u32> + Clone) -> IdSet {
        let (count, largest) = ids
            .clone()
            .fold((0usize, 0u32), |(n, m), id| (n + 1, m.max(id)));
        if largest as usize <= 4 * count + 1024 {
            let mut flags = vec![false; largest as usize + 1];
            for id in ids {
                flags[id as usize] = true;
            }
            IdSet::Dense(flags)
        } else {
            IdSet::Sparse(ids.collect())
        }
    }

    fn contains(&self, id: u32) -> bool {
        match self {
            IdSet::Dense(flags) => flags.get(id as usize).copied().unwrap_or(false),
            IdSet::Sparse(set) => set.contains(&id),
        }
    }
}

/// Node positions by id: a table where the ids are dense enough, else a hash map.
enum NodeIndex {
    Dense(Vec<u32>),
    Sparse(HashMap<u32, u32>),
}

impl NodeIndex {
    fn new(ids: &[u32]) -> NodeIndex {
        let largest = ids.iter().copied().max().unwrap_or(0) as usize;
        if largest <= 4 * ids.len() + 1024 {
            let mut table = vec![u32::MAX; largest + 1];
            for (i, &id) in ids.iter().enumerate() {
                table[id as usize] = i as u32;
            }
            NodeIndex::Dense(table)
        } else {
            NodeIndex::Sparse(
                ids.iter()
                    .enumerate()
                    .map(|(i, &id)| (id, i as u32))
                    .collect(),
            )
        }
    }

    fn get(&self, id: u32) -> Option<u32> {
        match self {
            NodeIndex::Dense(table) => table.get(id as usize).copied().filter(|&i| i != u32::MAX),
            NodeIndex::Sparse(map) => map.get(&id).copied(),
        }
    }
}

/// The conditions at each node, as positions in a list of conditions (ascending, each once):
/// compressed rows by node index.
struct Incidence {
    start: Vec<u32>,
    items: Vec<u32>,
}

impl Incidence {
    fn new(n_nodes: usize, condition_nodes: &[Vec<u32>]) -> Incidence {
        let mut count = vec![0u32; n_nodes + 1];
        for nodes in condition_nodes {
            for &n in nodes {
                count[n as usize + 1] += 1;
            }
        }
        for i in 0..n_nodes {
            count[i + 1] += count[i];
        }
        let mut fill = count.clone();
        let mut items = vec![u32::MAX; count[n_nodes] as usize];
        for (c, nodes) in condition_nodes.iter().enumerate() {
            for &n in nodes {
                let at = &mut fill[n as usize];
                items[*at as usize] = c as u32;
                *at += 1;
            }
        }
        // A condition that names a node twice is listed once.
        let mut start = vec![0u32; n_nodes + 1];
        let mut kept = Vec::with_capacity(items.len());
        for i in 0..n_nodes {
            let row = &items[count[i] as usize..count[i + 1] as usize];
            for (k, &c) in row.iter().enumerate() {
                if k == 0 || row[k - 1] != c {
                    kept.push(c);
                }
            }
            start[i + 1] = kept.len() as u32;
        }
        Incidence { start, items: kept }
    }

    fn of(&self, n: u32) -> &[u32] {
        let n = n as usize;
        &self.items[self.start[n] as usize..self.start[n + 1] as usize]
    }
}

/// The held slaves (centre, radius) bucketed in a grid whose cells are as wide as the
/// farthest reach, so that a master's reaching slaves lie in the 27 cells around it; each
/// cell keeps the box of its slaves' centres and their farthest reach, to skip it whole.
struct Near<'a> {
    slaves: &'a [([f64; 3], f64)],
    reach: Reach,
    cell: f64,
    cells: HashMap<[i64; 3], Cell>,
}

/// A grid cell of [`Near`]: its slaves, the box of their centres, their farthest reach.
#[derive(Default)]
struct Cell {
    slaves: Vec<usize>,
    lo: [f64; 3],
    hi: [f64; 3],
    farthest: f64,
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
        let mut cells: HashMap<[i64; 3], Cell> = HashMap::new();
        for (k, (c, r)) in slaves.iter().enumerate() {
            let entry = cells.entry(cell_of(c, cell)).or_insert_with(|| Cell {
                lo: *c,
                hi: *c,
                ..Cell::default()
            });
            entry.slaves.push(k);
            for (d, x) in c.iter().enumerate() {
                entry.lo[d] = entry.lo[d].min(*x);
                entry.hi[d] = entry.hi[d].max(*x);
            }
            entry.farthest = entry.farthest.max(reach.factor * r);
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
                    let Some(cell) = self.cells.get(&key) else {
                        continue;
                    };
                    // The distance from the master's centre to the box of the centres.
                    let outside: f64 = (0..3)
                        .map(|d| {
                            (cell.lo[d] - cm[d])
                                .max(cm[d] - cell.hi[d])
                                .max(0.0)
                                .powi(2)
                        })
                        .sum();
                    if outside > (cell.farthest + rm).powi(2) {
                        continue;
                    }
                    if cell.slaves.iter().any(|&k| {
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

/// The part of `mesh` a host code's rank might hold: the elements and the conditions whose
/// ids `keep_element` and `keep_condition` keep, every node they use, the parts restricted to
/// these (what [`search_partitioned`] takes as a rank's piece).
pub fn sub_mesh(
    mesh: &MeshArrays,
    keep_element: impl Fn(u32) -> bool,
    keep_condition: impl Fn(u32) -> bool,
) -> MeshArrays {
    let elements = filter_entities(&mesh.elements, |id, _| keep_element(id));
    let conditions = filter_entities(&mesh.conditions, |id, _| keep_condition(id));
    let used: HashSet<u32> = (elements.values().chain(conditions.values()))
        .flat_map(|a| a.connectivity.iter().copied())
        .collect();
    let (node_ids, points) = (mesh.node_ids.iter().zip(&mesh.points))
        .filter(|(id, _)| used.contains(id))
        .map(|(id, p)| (*id, *p))
        .unzip();
    let parts = (mesh.parts.iter())
        .map(|(name, p)| {
            let part = PartArrays {
                nodes: p
                    .nodes
                    .iter()
                    .copied()
                    .filter(|n| used.contains(n))
                    .collect(),
                elements: (p.elements.iter().copied())
                    .filter(|&e| keep_element(e))
                    .collect(),
                conditions: (p.conditions.iter().copied())
                    .filter(|&c| keep_condition(c))
                    .collect(),
            };
            (name.clone(), part)
        })
        .collect();
    MeshArrays {
        node_ids,
        points,
        elements,
        conditions,
        parts,
        domain_size: mesh.domain_size,
    }
}

fn distance(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// The conditions' nodes by condition id: a table by id where the ids are dense enough (as
/// [`IdSet`]), else a hash map.
enum ById<'a> {
    Dense(Vec<Option<&'a [u32]>>),
    Sparse(HashMap<u32, &'a [u32]>),
}

impl<'a> ById<'a> {
    fn get(&self, id: &u32) -> Option<&&'a [u32]> {
        match self {
            ById::Dense(table) => table.get(*id as usize).and_then(Option::as_ref),
            ById::Sparse(map) => map.get(id),
        }
    }
}

fn index(by_kind: &BTreeMap<GeometryKind, EntityArrays>) -> ById<'_> {
    let entries = || {
        by_kind.iter().flat_map(|(&kind, arrays)| {
            let n = kind.n_nodes();
            (arrays.ids.iter().enumerate())
                .map(move |(k, &id)| (id, &arrays.connectivity[k * n..(k + 1) * n]))
        })
    };
    let (count, largest) = entries().fold((0usize, 0u32), |(c, m), (id, _)| (c + 1, m.max(id)));
    if largest as usize <= 4 * count + 1024 {
        let mut table = vec![None; largest as usize + 1];
        for (id, nodes) in entries() {
            table[id as usize] = Some(nodes);
        }
        ById::Dense(table)
    } else {
        ById::Sparse(entries().collect())
    }
}

/// The entities `keep(id, nodes)` holds, in their order, by kind (kinds left empty dropped).
fn filter_entities(
    by_kind: &BTreeMap<GeometryKind, EntityArrays>,
    mut keep: impl FnMut(u32, &[u32]) -> bool,
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
