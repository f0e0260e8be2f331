//! NormalGapProcess and the explicit dual-mortar mapper (reference §10.1 a–b, §10.2).

use csm_geometry::math::{EPS, Point, Real, Vector, norm_kratos};
use csm_geometry::{Geometry, LargestArea, MAX_FACE_NODES, MAX_MORTAR_FACE_NODES};
use csm_geometry::{
    MortarFace, MortarMode, MortarOperators, OperatorSettings, Segmentation, SegmentationSettings,
    SlaveSegmentation, dual_basis, integration_points, mortar_operators,
};
use csm_model::{
    ConditionId, ConditionIdx, Flag, GATHER_BLOCK, GatheredPoints, KeptFaceNormals, KeptPositions,
    ModelPart, NodeIdx, PartIdx, ScalarVar, VectorVar,
};

use std::collections::VecDeque;

use rayon::prelude::*;

use crate::error::Error;
use crate::weighted_gap::{
    FirstPass, KnownGap, KnownGaps, PairGap, segmented_pair_gap, slave_area,
};

/// `NORMAL_GAP` before the mapping (CheckPairing step a): a slave node nothing was mapped onto
/// keeps it.
pub const NORMAL_GAP_SENTINEL: Real = 1e12;
/// The mapper's absolute convergence tolerance on `sqrt(Σ VAUX²) / n`.
pub const MAPPER_ABSOLUTE_TOLERANCE: Real = 1e-9;
/// The mapper's relative (to the first residual) and increment tolerance.
pub const MAPPER_RELATIVE_TOLERANCE: Real = 1e-4;
/// The mapper's iteration limit.
pub const MAPPER_MAX_ITERATIONS: usize = 10;
/// A slave node is updated only if `|NODAL_AREA| > AREA_TOLERANCE · ref_area`.
const AREA_TOLERANCE: Real = 1e-4;

/// Settings of [`normal_gap_process`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MappingSettings {
    /// Kratos' rules or the robust segmentation.
    pub mode: MortarMode,
    /// `ProcessInfo[DISTANCE_THRESHOLD]` (1e24 when absent).
    pub distance_threshold: Real,
    /// The search's `inverted_search` (the orientation of NormalGapProcess is `!inverted`).
    pub inverted: bool,
    /// The domain size (2 or 3): the number of mapped components.
    pub dim: usize,
}

/// An `INDEX_MAP` entry the mapping removed (no overlap).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RemovedEntry {
    /// The slave-side condition.
    pub slave: ConditionIdx,
    /// The master condition id (the key removed).
    pub master: ConditionId,
    /// The paired condition of the entry, if one existed (Kratos marks it TO_ERASE).
    pub paired: Option<ConditionId>,
}

/// What [`normal_gap_process`] did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MappingReport {
    /// The entries removed from the `INDEX_MAP`s, in slave id then master id order.
    pub removed: Vec<RemovedEntry>,
    /// The entries kept (pairs with an overlap).
    pub kept: usize,
    /// Mapper iterations run.
    pub iterations: usize,
}

/// The slave and master sides of a ContactSub (Kratos' `SlaveSubModelPart` /
/// `MasterSubModelPart`, §5.1): entities with `SLAVE != inverted`, resp. `MASTER != inverted`.
#[derive(Debug, Clone, Default)]
pub(crate) struct Sides {
    pub slave_conditions: Vec<ConditionIdx>,
    pub master_conditions: Vec<ConditionIdx>,
    pub slave_nodes: Vec<NodeIdx>,
    pub master_nodes: Vec<NodeIdx>,
}

pub(crate) fn sides(model: &ModelPart, sub: PartIdx, inverted: bool) -> Sides {
    let ids = model.conditions().ids();
    let mut conditions = model.part(sub).conditions().to_vec();
    conditions.sort_by_key(|c| ids[c.index()]);
    let cflags = model.conditions().flags();
    let nflags = model.nodes().flags();
    let nodes = model.part(sub).nodes();
    Sides {
        slave_conditions: conditions
            .iter()
            .copied()
            .filter(|c| cflags[c.index()].is(Flag::SLAVE) != inverted)
            .collect(),
        master_conditions: conditions
            .iter()
            .copied()
            .filter(|c| cflags[c.index()].is(Flag::MASTER) != inverted)
            .collect(),
        slave_nodes: nodes
            .iter()
            .copied()
            .filter(|n| nflags[n.index()].is(Flag::SLAVE) != inverted)
            .collect(),
        master_nodes: nodes
            .iter()
            .copied()
            .filter(|n| nflags[n.index()].is(Flag::MASTER) != inverted)
            .collect(),
    }
}

/// The Advanced search's `DISTANCE_THRESHOLD` (§10.1): `max(mean NODAL_H of the slave side,
/// mean NODAL_H of the master side)` of ContactSub `sub` (a side without nodes, or a model
/// without NODAL_H, counts 0). Reads the sides' nodes in the part's order, without listing
/// them.
pub fn mean_h(model: &ModelPart, sub: PartIdx, inverted: bool) -> Real {
    let Some(h) = model.nodal_data().scalar(ScalarVar::NodalH, 0) else {
        return 0.0;
    };
    let nflags = model.nodes().flags();
    let mean = |flag: Flag| -> Real {
        let side = || {
            let nodes = model.part(sub).nodes().iter();
            nodes.filter(|n| nflags[n.index()].is(flag) != inverted)
        };
        match side().count() {
            0 => 0.0,
            count => side().map(|n| h[n.index()]).sum::<Real>() / count as Real,
        }
    };
    mean(Flag::SLAVE).max(mean(Flag::MASTER))
}

/// Geometry points, condition normal and nodal (historical) normals of a condition.
pub(crate) struct FaceData {
    pub points: PerNode<Point>,
    pub normal: Vector,
    pub nodal_normals: PerNode<Vector>,
}

/// One value per node of a condition: up to [`MAX_MORTAR_FACE_NODES`] in place (no allocation
/// for a mortar face), more on the heap (a face the mortar routines refuse).
#[derive(Clone)]
pub(crate) struct PerNode<T> {
    inline: [T; MAX_MORTAR_FACE_NODES],
    len: usize,
    heap: Vec<T>,
}

impl<T: Copy> PerNode<T> {
    /// The values of `values` (`fill`: what the unused places hold).
    fn new(values: impl ExactSizeIterator<Item = T>, fill: T) -> PerNode<T> {
        let len = values.len();
        let mut out = PerNode {
            inline: [fill; MAX_MORTAR_FACE_NODES],
            len,
            heap: Vec::new(),
        };
        if len <= MAX_MORTAR_FACE_NODES {
            for (place, v) in out.inline.iter_mut().zip(values) {
                *place = v;
            }
        } else {
            out.heap.extend(values);
        }
        out
    }
}

impl<T> std::ops::Deref for PerNode<T> {
    type Target = [T];

    fn deref(&self) -> &[T] {
        if self.len <= MAX_MORTAR_FACE_NODES {
            &self.inline[..self.len]
        } else {
            &self.heap
        }
    }
}

pub(crate) fn face_data(model: &ModelPart, c: ConditionIdx) -> FaceData {
    face_data_with(model, c, model.nodal_data().vector(VectorVar::Normal, 0))
}

/// [`face_data`] with the nodal normals taken from `normals` (by node index).
pub(crate) fn face_data_with(
    model: &ModelPart,
    c: ConditionIdx,
    normals: Option<&[Vector]>,
) -> FaceData {
    let coords = model.nodes().coordinates();
    let nodes = model.conditions().nodes(c.index());
    FaceData {
        points: PerNode::new(nodes.iter().map(|n| coords[n.index()]), Point::origin()),
        normal: model.condition_normals()[c.index()],
        nodal_normals: nodal_normals(model, c, normals),
    }
}

/// The nodal normals of condition `c` taken from `normals` (by node index; zero without).
fn nodal_normals(
    model: &ModelPart,
    c: ConditionIdx,
    normals: Option<&[Vector]>,
) -> PerNode<Vector> {
    let nodes = model.conditions().nodes(c.index()).iter();
    PerNode::new(
        nodes.map(|n| normals.map_or(Vector::zeros(), |col| col[n.index()])),
        Vector::zeros(),
    )
}

pub(crate) fn make_face<'a>(
    model: &ModelPart,
    c: ConditionIdx,
    data: &'a FaceData,
) -> Result<MortarFace<'a>, Error> {
    let id = model.conditions().ids()[c.index()];
    let kind = model.conditions().kind(c.index());
    let wrap = |e: csm_geometry::Error| Error::condition("mortar face", id, &e);
    Geometry::new(kind, &data.points)
        .and_then(|g| MortarFace::new(g, data.normal))
        .and_then(|f| f.with_nodal_normals(&data.nodal_normals))
        .map_err(wrap)
}

/// `ComputeNodesMeanNormalModelPart` of one side: nodal NORMAL := 0 on the nodes of its
/// conditions, condition normal := unit normal at the centre, every node accumulates the unit
/// normal at its own local coordinates, then one normalisation (norm > eps).
/// `known`: the kept table of these faces' unit normals on the current coordinates, where the
/// caller has it ([`KeptFaceNormals::positions`]: its centre normals are the condition
/// normals already); computed here otherwise. With `known`, `wanted` (by node index) can
/// limit the nodes written to those it marks ([`normals_read`]).
pub(crate) fn mean_normals(
    model: &mut ModelPart,
    (conditions, wanted): (&[ConditionIdx], Option<&[bool]>),
    known: Option<&KeptPositions<'_>>,
) -> Result<(), Error> {
    model.nodal_data_mut().add_vector(VectorVar::Normal);
    // Summed into NORMAL itself, in the order of `conditions` (a node of none keeps its
    // value); every node of a face is written once, so the order of the writes does not
    // matter.
    let mut count = vec![0u32; model.nodes().len()];
    let summed = known.is_some_and(|kept| {
        model.with_vector_mut(VectorVar::Normal, 0, |m, normals| {
            kept.nodal_sums_into(m, (conditions, wanted), (normals, &mut count))
        }) == Some(true)
    });
    if !summed {
        let mut faces =
            csm_model::face_unit_normals(model, conditions).map_err(|e| match e.kind() {
                csm_model::ErrorKind::Geometry { id, source, .. } => {
                    Error::condition("unit normal", *id, source)
                }
                _ => Error::message_only(e.to_string()),
            })?;
        faces.set_condition_normals(model);
        model.with_vector_mut(VectorVar::Normal, 0, |m, normals| {
            faces.nodal_sums_into(m, normals, &mut count);
        });
    }
    if let Some(col) = model.nodal_data_mut().vector_mut(VectorVar::Normal, 0) {
        for (v, _) in col.iter_mut().zip(&count).filter(|&(_, &k)| k > 0) {
            let norm = norm_kratos(v);
            if norm > EPS {
                *v /= norm;
            }
        }
    }
    Ok(())
}

/// By node index, the nodes whose NORMAL the mapping reads: those of the slave conditions
/// with an INDEX_MAP entry (their Gauss points' normals; ComputeNormalGap reads only nodes
/// that a kept pair maps to) and of the master conditions these entries name (their face
/// data carries nodal normals too, which no 3D computation reads today: cheap insurance).
pub(crate) fn normals_read(model: &ModelPart, s: &Sides) -> Vec<bool> {
    let mut read = vec![false; model.nodes().len()];
    let conditions = model.conditions();
    let mut mark = |c: usize| {
        for n in conditions.nodes(c) {
            read[n.index()] = true;
        }
    };
    for &sc in &s.slave_conditions {
        let map = model.index_map(sc);
        if map.is_empty() {
            continue;
        }
        mark(sc.index());
        for (master, _) in map.iter() {
            if let Some(mc) = conditions.index_of(master.get()) {
                mark(mc);
            }
        }
    }
    read
}

/// Slave conditions per parallel task of the segmentation.
const SLAVES_PER_TASK: usize = 64;
/// Conditions per parallel task of the reference area.
const CONDITIONS_PER_TASK: usize = 4096;

/// The entries of consecutive slave conditions' INDEX_MAPs after the segmentation.
#[derive(Default)]
struct SlaveMapping {
    /// The kept (slave, master) pairs, in order.
    kept: Vec<(ConditionIdx, ConditionIdx)>,
    /// Their operators, packed one pair after the other ([`MortarOperators::pack_into`]).
    operators: Vec<Real>,
    removed: Vec<RemovedEntry>,
    /// With [`WeightedGapInputs`]: the weighted-gap contribution of every kept pair.
    gaps: Vec<KnownGap>,
}

impl SlaveMapping {
    /// Its kept pairs and their operators only (the removed entries and the weighted gaps
    /// are reported and taken before).
    fn kept_part(self) -> SlaveMapping {
        SlaveMapping {
            kept: self.kept,
            operators: self.operators,
            ..SlaveMapping::default()
        }
    }
}

/// What the mapping needs to compute the weighted gap of its kept pairs as well
/// ([`normal_gap_process_keeping`]).
#[derive(Clone, Copy)]
struct WeightedGapInputs<'a> {
    /// The nodal `NORMAL` the weighted gap will read, by node index.
    unit_normals: &'a [Vector],
    dim: usize,
}

/// How the mapping keeps a pair's operators for its iterations.
#[derive(Clone, Copy, Debug)]
pub(crate) enum OperatorStore {
    /// `D` and `M` ([`MortarOperators::pack_into`]).
    Operators,
    /// `D` and the products `M · v_k` of the master values of the `dim` components
    /// ([`MortarOperators::pack_with_products_into`]): where no master node is a slave node,
    /// the master values (`AUXILIAR_COORDINATES`: the coordinates, or zero when `!origin`)
    /// do not change during the iterations, and the residual's `M · v` part is the same in
    /// every iteration, bit for bit.
    MasterProducts { origin: bool, dim: usize },
}

impl OperatorStore {
    /// The store of a mapping between the sides `s` (`slaves`: their slave nodes' positions;
    /// `origin`: not inverted; `dim` components): the master values stay as the mapping sets
    /// them through the iterations unless a master node is also a slave node (the iterations
    /// update the slave nodes).
    pub(crate) fn for_sides(
        s: &Sides,
        slaves: &SlavePositions,
        origin: bool,
        dim: usize,
    ) -> OperatorStore {
        #[cfg(test)]
        if crate::tests::FORCE_OPERATORS.with(std::cell::Cell::get) {
            return OperatorStore::Operators;
        }
        if s.master_nodes.iter().any(|&n| slaves.get(n).is_some()) {
            OperatorStore::Operators
        } else {
            OperatorStore::MasterProducts { origin, dim }
        }
    }

    /// The number of values [`pack`](Self::pack) appends for `ns` slave and `nm` master
    /// nodes.
    fn packed_len(self, ns: usize, nm: usize) -> usize {
        match self {
            OperatorStore::Operators => MortarOperators::packed_len(ns, nm),
            OperatorStore::MasterProducts { dim, .. } => {
                MortarOperators::packed_with_products_len(ns, dim)
            }
        }
    }

    /// Appends the operators of the pair with master `mc` to `out`.
    fn pack(
        self,
        model: &ModelPart,
        mc: ConditionIdx,
        operators: &MortarOperators,
        out: &mut Vec<Real>,
    ) {
        match self {
            OperatorStore::Operators => operators.pack_into(out),
            OperatorStore::MasterProducts { origin, dim } => {
                let coords = model.nodes().coordinates();
                let mut values = [[0.0; MAX_FACE_NODES]; 3];
                let nodes = model.conditions().nodes(mc.index());
                for (k, component) in values.iter_mut().enumerate().take(dim) {
                    for (v, n) in component.iter_mut().zip(nodes) {
                        *v = if origin { coords[n.index()][k] } else { 0.0 };
                    }
                }
                let nm = nodes.len();
                let rows = [&values[0][..nm], &values[1][..nm], &values[2][..nm]];
                operators.pack_with_products_into(&rows[..dim], out);
            }
        }
    }
}

/// What the segmentation of the INDEX_MAP entries computes and keeps.
#[derive(Clone, Copy)]
struct Segmenting<'a> {
    seg: SegmentationSettings,
    op: OperatorSettings,
    store: OperatorStore,
    /// With it, the weighted gap of every kept pair as well.
    weighted_gap: Option<WeightedGapInputs<'a>>,
}

/// Segments the INDEX_MAP entries of `slaves`, in parallel: their mappings in slave order,
/// [`SLAVES_PER_TASK`] slaves each. The first error in slave order.
fn segment_slaves(
    m: &ModelPart,
    slaves: &[ConditionIdx],
    tasks: &Segmenting<'_>,
) -> Result<Vec<SlaveMapping>, Error> {
    let per_slave: Vec<Result<SlaveMapping, Error>> = slaves
        .par_chunks(SLAVES_PER_TASK)
        .map(|chunk| {
            // Room for every entry (the kept ones are at most these): no copies as the lists
            // grow; the rest is given back after.
            let mut out = SlaveMapping::default();
            let (mut entries, mut values) = (0, 0);
            for &sc in chunk {
                let map = m.index_map(sc);
                let ns = m.conditions().nodes(sc.index()).len();
                entries += map.len();
                values += map.len() * MortarOperators::packed_len(ns, MAX_MORTAR_FACE_NODES);
            }
            out.kept.reserve_exact(entries);
            out.operators.reserve_exact(values);
            if tasks.weighted_gap.is_some() {
                out.gaps.reserve_exact(entries);
            }
            for &sc in chunk {
                map_slave(
                    m,
                    sc,
                    (&tasks.seg, &tasks.op),
                    (tasks.store, tasks.weighted_gap),
                    &mut out,
                )?;
            }
            out.kept.shrink_to_fit();
            out.operators.shrink_to_fit();
            out.gaps.shrink_to_fit();
            Ok(out)
        })
        .collect();
    per_slave.into_iter().collect()
}

/// The [kept parts](SlaveMapping::kept_part) of the mappings with kept pairs: most slave
/// conditions have none on a large interface with a small contact zone.
fn kept_only(per_slave: Vec<SlaveMapping>) -> Vec<SlaveMapping> {
    per_slave
        .into_iter()
        .filter(|m| !m.kept.is_empty())
        .map(SlaveMapping::kept_part)
        .collect()
}

/// Every kept pair of `per_slave` with its packed operators, in order.
fn kept_pairs<'a>(
    m: &'a ModelPart,
    per_slave: &'a [SlaveMapping],
    store: OperatorStore,
) -> impl Iterator<Item = (ConditionIdx, ConditionIdx, &'a [Real])> + 'a {
    per_slave.iter().flat_map(move |mapped| {
        let mut rest = mapped.operators.as_slice();
        mapped.kept.iter().map(move |&(sc, mc)| {
            let ns = m.conditions().nodes(sc.index()).len();
            let nm = m.conditions().nodes(mc.index()).len();
            let (packed, next) = rest.split_at(store.packed_len(ns, nm));
            rest = next;
            (sc, mc, packed)
        })
    })
}

/// One mapper iteration's residual of the kept pairs on the values `aux`, by slave node
/// (`slaves`).
struct Residual<'a> {
    store: OperatorStore,
    dim: usize,
    aux: &'a [Vector],
    slaves: &'a SlavePositions,
}

impl Residual<'_> {
    /// Adds the residual of the pair `(sc, mc)` with the `packed` operators to its slave
    /// nodes in `vaux` (Kratos' `prod(M, V) − prod(D, S)`, component by component; by slave
    /// node: what the nodes of a slave condition that are not slave nodes get is never read).
    fn add(
        &self,
        m: &ModelPart,
        (sc, mc, packed): (ConditionIdx, ConditionIdx, &[Real]),
        vaux: &mut [Vector],
    ) {
        self.add_with(m, (sc, mc, packed), vaux, |n, k| self.aux[n.index()][k]);
    }

    /// [`add`](Self::add) with the slave values `slave_value(node, component)`.
    // The component `k` also picks the slave values and the products: no iterator of `vaux`.
    #[allow(clippy::needless_range_loop)]
    fn add_with(
        &self,
        m: &ModelPart,
        (sc, mc, packed): (ConditionIdx, ConditionIdx, &[Real]),
        vaux: &mut [Vector],
        slave_value: impl Fn(NodeIdx, usize) -> Real,
    ) {
        let slave_nodes = m.conditions().nodes(sc.index());
        let master_nodes = m.conditions().nodes(mc.index());
        let (nm, ns) = (master_nodes.len(), slave_nodes.len());
        for k in 0..self.dim {
            let mut sv = [0.0; MAX_FACE_NODES];
            let mut r = [0.0; MAX_FACE_NODES];
            for (v, &n) in sv.iter_mut().zip(slave_nodes) {
                *v = slave_value(n, k);
            }
            match self.store {
                OperatorStore::Operators => {
                    let mut mv = [0.0; MAX_FACE_NODES];
                    for (v, n) in mv.iter_mut().zip(master_nodes) {
                        *v = self.aux[n.index()][k];
                    }
                    MortarOperators::packed_residual_into(
                        packed,
                        &mv[..nm],
                        &sv[..ns],
                        &mut r[..ns],
                    );
                }
                OperatorStore::MasterProducts { .. } => {
                    MortarOperators::packed_products_residual_into(
                        packed,
                        (k, self.dim),
                        &sv[..ns],
                        &mut r[..ns],
                    );
                }
            }
            for (i, &n) in slave_nodes.iter().enumerate() {
                if let Some(j) = self.slaves.get(n) {
                    vaux[j][k] += r[i];
                }
            }
        }
    }
}

/// The positions of the slave nodes in [`Sides::slave_nodes`] by node index: the mapper's
/// arrays by slave node.
pub(crate) struct SlavePositions(Vec<u32>);

impl SlavePositions {
    /// Not a slave node.
    const NONE: u32 = u32::MAX;

    pub(crate) fn new(s: &Sides, n_nodes: usize) -> SlavePositions {
        let mut positions = vec![SlavePositions::NONE; n_nodes];
        for (j, n) in s.slave_nodes.iter().enumerate() {
            positions[n.index()] = u32::try_from(j).expect("node positions fit u32");
        }
        SlavePositions(positions)
    }

    /// The position of node `n` among the slave nodes, if it is one.
    fn get(&self, n: NodeIdx) -> Option<usize> {
        let j = self.0[n.index()];
        (j != SlavePositions::NONE).then_some(j as usize)
    }
}

/// Adds `D`'s diagonal of the pair of slave `sc` (`packed`: its first ns² values are `D`, row
/// by row) to the slave nodes' `area` (by slave node, as [`Residual::add`]).
fn add_area(
    m: &ModelPart,
    sc: ConditionIdx,
    packed: &[Real],
    (area, slaves): (&mut [Real], &SlavePositions),
) {
    let slave_nodes = m.conditions().nodes(sc.index());
    let ns = slave_nodes.len();
    for (i, &n) in slave_nodes.iter().enumerate() {
        if let Some(j) = slaves.get(n) {
            area[j] += packed[i * ns + i];
        }
    }
}

/// Slave conditions per batch of [`stream_first_iterations`].
const SLAVES_PER_BATCH: usize = 8192;

/// What [`stream_first_iterations`] leaves for the iterations.
struct FirstIterations {
    /// The residuals of the first two iterations (`VAUX`), by slave node.
    vaux: [Vec<Vector>; 2],
    /// `NODAL_AREA`: `D`'s diagonal summed over the kept pairs, by slave node.
    area: Vec<Real>,
    /// The weighted gap of the kept pairs, in slave order.
    gaps: Vec<KnownGap>,
}

/// INDEX_MAP entries from which the mapping streams its first iterations (below, keeping
/// every pair's operators costs little memory and saves the batches' passes).
const STREAM_MIN_ENTRIES: usize = 1 << 16;

/// Whether the first two mapper iterations follow the segmentation
/// ([`stream_first_iterations`]): on enough entries (at least [`STREAM_MIN_ENTRIES`]) where
/// they can — the store keeps the products of the master values (which do not change), and
/// every node of a slave condition is a slave node (only those change, and every residual goes
/// to them).
fn streams(m: &ModelPart, s: &Sides, slaves: &SlavePositions, store: OperatorStore) -> bool {
    #[cfg(test)]
    if crate::tests::FORCE_STORED.with(std::cell::Cell::get) {
        return false;
    }
    if !matches!(store, OperatorStore::MasterProducts { .. }) {
        return false;
    }
    // (The tests stream whatever the number of entries.)
    let least = if cfg!(test) { 0 } else { STREAM_MIN_ENTRIES };
    let entries: usize = s
        .slave_conditions
        .iter()
        .map(|&c| m.index_map(c).len())
        .sum();
    entries >= least
        && s.slave_conditions.iter().all(|c| {
            m.conditions()
                .nodes(c.index())
                .iter()
                .all(|&n| slaves.get(n).is_some())
        })
}

/// The segmentation of every INDEX_MAP entry ([`segment_slaves`], batch after batch of
/// [`SLAVES_PER_BATCH`] slaves) with the first two mapper iterations' residuals, computed as
/// the pairs come, so that no pair's operators are kept longer than those iterations need
/// them (where [`streams`]): the first iteration's residual and `D`'s diagonal of a pair are
/// added as its batch is done; its second iteration's residual once every slave condition of
/// its slave nodes is done (their values after the first iteration are then known), in pair
/// order, after which its operators are dropped. Each node's sums are those of the iterations
/// in pair order, bit for bit: the values after the first iteration are computed as the
/// iteration computes them, and what the iterations do with the sums of the first two
/// (`aux` update, convergence) is left to them. `(aux, ref_area)`: the values before the
/// iterations and the reference area. Counts the kept entries in `report` and adds the
/// removed ones in slave order.
fn stream_first_iterations(
    m: &ModelPart,
    s: &Sides,
    tasks: &Segmenting<'_>,
    (aux, ref_area, slaves): (&[Vector], Real, &SlavePositions),
    report: &mut MappingReport,
) -> Result<FirstIterations, Error> {
    let n_slaves = s.slave_nodes.len();
    let dim = match tasks.store {
        OperatorStore::MasterProducts { dim, .. } => dim,
        OperatorStore::Operators => unreachable!("streams only the master values' products"),
    };
    let batch = batch_size();
    // By slave node: the number of slave conditions done when its last one is (every node
    // of a slave condition is a slave node).
    let position = |n: NodeIdx| slaves.get(n).expect("streams: a slave node");
    let mut done_with = vec![0; n_slaves];
    for (p, sc) in s.slave_conditions.iter().enumerate() {
        for &n in m.conditions().nodes(sc.index()) {
            done_with[position(n)] = p + 1;
        }
    }
    let mut first = FirstIterations {
        vaux: [
            vec![Vector::zeros(); n_slaves],
            vec![Vector::zeros(); n_slaves],
        ],
        area: vec![0.0; n_slaves],
        gaps: Vec::new(),
    };
    let residual = Residual {
        store: tasks.store,
        dim,
        aux,
        slaves,
    };
    let tolerance = AREA_TOLERANCE * ref_area;
    // The mappings whose pairs' second iteration is not done yet, the first from pair `next`.
    let mut pending: VecDeque<SlaveMapping> = VecDeque::new();
    let mut next = 0;
    for (b, conditions) in s.slave_conditions.chunks(batch).enumerate() {
        let done = b * batch + conditions.len();
        for mut mapped in segment_slaves(m, conditions, tasks)? {
            report.kept += mapped.kept.len();
            report.removed.append(&mut mapped.removed);
            first.gaps.append(&mut mapped.gaps);
            if mapped.kept.is_empty() {
                continue;
            }
            for (sc, mc, packed) in kept_pairs(m, std::slice::from_ref(&mapped), tasks.store) {
                residual.add(m, (sc, mc, packed), &mut first.vaux[0]);
                add_area(m, sc, packed, (&mut first.area, slaves));
            }
            pending.push_back(mapped.kept_part());
        }
        // The second iteration of the pairs whose slave nodes are done, in order.
        let [vaux0, vaux1] = &mut first.vaux;
        let (vaux0, area) = (&*vaux0, &first.area);
        // A slave node's value after the first iteration, as the iterations compute it.
        let after_first = |n: NodeIdx, k: usize| {
            let (i, j) = (n.index(), position(n));
            if area[j].abs() > tolerance {
                aux[i][k] + vaux0[j][k] / area[j]
            } else {
                aux[i][k]
            }
        };
        'pending: while let Some(mapped) = pending.front() {
            let pairs = kept_pairs(m, std::slice::from_ref(mapped), tasks.store).skip(next);
            for (sc, mc, packed) in pairs {
                let nodes = m.conditions().nodes(sc.index());
                if nodes.iter().any(|&n| done_with[position(n)] > done) {
                    break 'pending;
                }
                residual.add_with(m, (sc, mc, packed), vaux1, after_first);
                next += 1;
            }
            pending.pop_front();
            next = 0;
        }
    }
    debug_assert!(
        pending.is_empty(),
        "every node is done after the last batch"
    );
    Ok(first)
}

/// [`SLAVES_PER_BATCH`], or the tests' own.
fn batch_size() -> usize {
    #[cfg(test)]
    if let Some(n) = crate::tests::STREAM_BATCH.with(std::cell::Cell::get) {
        return n;
    }
    SLAVES_PER_BATCH
}

/// Segments every INDEX_MAP entry of slave condition `sc`: entries without overlap are
/// removed; the others get the dual basis and the mapper's `D`, `M` operators (appended to
/// `out`).
fn map_slave(
    model: &ModelPart,
    sc: ConditionIdx,
    (seg_settings, op_settings): (&SegmentationSettings, &OperatorSettings),
    (store, weighted_gap): (OperatorStore, Option<WeightedGapInputs<'_>>),
    out: &mut SlaveMapping,
) -> Result<(), Error> {
    let entries: Vec<(ConditionId, Option<ConditionId>)> = model.index_map(sc).iter().collect();
    if entries.is_empty() {
        return Ok(());
    }
    let sdata = face_data(model, sc);
    let slave = make_face(model, sc, &sdata)?;
    let segmentation = SlaveSegmentation::new(&slave, seg_settings);
    let slave_id = model.conditions().ids()[sc.index()];
    // With the weighted gap: the slave's face data with its nodal normals, its area, and
    // whether those nodal normals are the mapper's, bit for bit (then so are the weighted
    // gap's Gauss points and operators: `FirstPass`).
    let mut slave_for_gap: Option<(FaceData, Result<Real, Error>, bool)> = None;
    for (master_id, paired) in entries {
        let Some(mc) = model
            .conditions()
            .index_of(master_id.get())
            .map(|i| ConditionIdx(u32::try_from(i).expect("condition index fits u32")))
        else {
            continue;
        };
        let mdata = face_data(model, mc);
        let master = make_face(model, mc, &mdata)?;
        let seg = segmentation
            .segment(&master)
            .map_err(|e| Error::condition("mortar segmentation", slave_id, &e))?;
        let Some(seg) = seg.filter(|g| !g.cells().is_empty()) else {
            out.removed.push(RemovedEntry {
                slave: sc,
                master: master_id,
                paired,
            });
            continue;
        };
        let gps = integration_points(&slave, &master, &seg, op_settings)
            .map_err(|e| Error::condition("mortar integration", slave_id, &e))?;
        let basis = dual_basis(&slave, &gps);
        let operators = mortar_operators(&slave, &master, &gps, Some(&basis));
        store.pack(model, mc, &operators, &mut out.operators);
        out.kept.push((sc, mc));
        // The weighted gap's segmentation of a face pair would be this one: it depends on
        // the coordinates and the slave's condition normal only (not on the nodal normals,
        // which differ), and both are the same then. Lines (2D) project along nodal normals.
        if let Some(inputs) = weighted_gap
            && slave.geometry().kind().local_dim() == 2
        {
            let (slave_u, area, same_normals) = slave_for_gap.get_or_insert_with(|| {
                let (data, area) = slave_gap_data(model, sc, &sdata, inputs.unit_normals);
                let same = same_bits(&data.nodal_normals, &sdata.nodal_normals);
                (data, area, same)
            });
            let first = FirstPass {
                points: &gps,
                basis: &basis,
                operators: same_normals.then_some(&operators),
            };
            let gap = kept_pair_gap(model, (sc, mc), (&seg, first), (slave_u, area), inputs);
            out.gaps.push(((sc, mc), gap));
        }
    }
    Ok(())
}

/// The weighted-gap contribution of the kept 3D pair `(sc, mc)` whose segmentation is `seg`
/// and whose mapper Gauss points and dual basis are `gps`, `basis`: the faces with the
/// weighted gap's nodal normals.
fn kept_pair_gap(
    model: &ModelPart,
    (sc, mc): (ConditionIdx, ConditionIdx),
    (seg, first): (&Segmentation, FirstPass<'_>),
    (sdata, slave_area): (&FaceData, &Result<Real, Error>),
    inputs: WeightedGapInputs<'_>,
) -> Result<Option<PairGap>, Error> {
    let mdata = face_data_with(model, mc, Some(inputs.unit_normals));
    let slave = make_face(model, sc, sdata)?;
    let master = make_face(model, mc, &mdata)?;
    // The weighted gap's order: both faces, then the area.
    let slave_area = slave_area.clone()?;
    segmented_pair_gap(
        model,
        sc,
        (sdata, &slave, slave_area),
        (&mdata, &master),
        (seg, Some(first)),
        inputs.dim,
    )
}

/// Whether `a` and `b` hold the same vectors, bit for bit.
fn same_bits(a: &[Vector], b: &[Vector]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(u, v)| {
            u.iter()
                .zip(v.iter())
                .all(|(x, y)| x.to_bits() == y.to_bits())
        })
}

/// The slave's face data with the weighted gap's nodal normals (`sdata` with other nodal
/// normals), and its area.
fn slave_gap_data(
    model: &ModelPart,
    sc: ConditionIdx,
    sdata: &FaceData,
    unit_normals: &[Vector],
) -> (FaceData, Result<Real, Error>) {
    let data = FaceData {
        points: sdata.points.clone(),
        normal: sdata.normal,
        nodal_normals: nodal_normals(model, sc, Some(unit_normals)),
    };
    let area = slave_area(model, sc, &data);
    (data, area)
}

/// Kratos' `NormalGapProcess` (§10.1 a–b, §10.2) on ContactSub `sub`, after the search filled
/// the slave side's `INDEX_MAP`s:
///
/// 1. `NORMAL_GAP := 1e12` on every node of `sub`; `AUXILIAR_COORDINATES` := coordinates on the
///    master side (0 on the slave side; the other way round when inverted);
/// 2. nodal mean normals (master side, then slave side: shared nodes take the slave value) —
///    this overwrites the historical `NORMAL` and the condition normals (Q23);
/// 3. the exact segmentation of every `INDEX_MAP` entry: entries without overlap are removed
///    (MappingCheck's narrow phase); dual basis and `D`, `M` operators for the others;
/// 4. the explicit mapping iterations of `AUXILIAR_COORDINATES` (`NODAL_AREA` from the first);
/// 5. `ComputeNormalGap`: on nodes with `SLAVE == !inverted`, `NORMAL_GAP = (X − AUX)·(−n)`
///    where `|AUX| > eps` (else the sentinel stays, Q39); the other side's nodes get 0.
///
/// `face_normals`: where the caller has them, the unit normals of the faces of `sub` on the
/// current coordinates (the table [`csm_model::compute_unit_normals`] returns, kept), which
/// step 2 then does not compute again; `None` computes them.
///
/// Errors: a face the mortar routines refuse (unsupported kind, degenerate geometry).
pub fn normal_gap_process(
    model: &mut ModelPart,
    sub: PartIdx,
    settings: &MappingSettings,
    face_normals: Option<KeptFaceNormals>,
) -> Result<MappingReport, Error> {
    normal_gap_process_inner(model, sub, settings, face_normals, None).map(|(report, _)| report)
}

/// [`normal_gap_process`] that also computes the weighted gap
/// ([`crate::compute_weighted_gap`]) of every pair it keeps, from the same segmentation, for a
/// step in which the coordinates do not move before the weighted gap: `unit_normals` (by node
/// index) are the nodal `NORMAL` the weighted gap will read (the unit normals the caller
/// writes back after the mapping). Face pairs only (3D); the weighted gap computes the others.
/// `face_normals` as for [`normal_gap_process`]; with them, the mean normals are written only
/// on the nodes whose NORMAL the mapping reads (the others keep theirs, which the caller
/// overwrites anyway).
pub fn normal_gap_process_keeping(
    model: &mut ModelPart,
    sub: PartIdx,
    settings: &MappingSettings,
    face_normals: Option<KeptFaceNormals>,
    unit_normals: &[Vector],
) -> Result<(MappingReport, KnownGaps), Error> {
    let inputs = WeightedGapInputs {
        unit_normals,
        dim: settings.dim.clamp(1, 3),
    };
    normal_gap_process_inner(model, sub, settings, face_normals, Some(inputs))
}

fn normal_gap_process_inner(
    model: &mut ModelPart,
    sub: PartIdx,
    settings: &MappingSettings,
    face_normals: Option<KeptFaceNormals>,
    weighted_gap: Option<WeightedGapInputs<'_>>,
) -> Result<(MappingReport, KnownGaps), Error> {
    let o = !settings.inverted;
    let dim = settings.dim.clamp(1, 3);
    let s = sides(model, sub, settings.inverted);
    let n_nodes = model.nodes().len();
    // 1. Sentinel and AUXILIAR_COORDINATES.
    {
        let sub_nodes = model.part(sub).nodes().to_vec();
        let data = model.nodal_data_mut();
        data.add_scalar(ScalarVar::NormalGap);
        data.add_scalar(ScalarVar::NodalArea);
        // AUXILIAR_COORDINATES: computed below and moved in at the end (no column of zeros
        // to write first and copy into afterwards).
        if let Some(col) = data.scalar_mut(ScalarVar::NormalGap, 0) {
            for n in &sub_nodes {
                col[n.index()] = NORMAL_GAP_SENTINEL;
            }
        }
    }
    // 2. Mean normals: origin (master side) first, destination (slave side) second.
    // Both sides' faces from the kept table (one check, one position table).
    let positions = face_normals.as_ref().and_then(|kept| kept.positions(model));
    // The caller of the weighted-gap variant writes its unit normals back after the mapping:
    // only the mean normals the mapping reads are needed there.
    let wanted = weighted_gap.map(|_| normals_read(model, &s));
    for conditions in [&s.master_conditions, &s.slave_conditions] {
        mean_normals(model, (conditions, wanted.as_deref()), positions.as_ref())?;
    }
    // The kept table is not read again: its memory (the quadrilaterals' nodal normals) goes
    // before the segmentation's.
    drop((wanted, positions));
    drop(face_normals);
    // AUXILIAR_COORDINATES (after the mean normals, which do not read it).
    let coords = model.nodes().coordinates();
    let mut aux = model
        .nodal_data()
        .vector(VectorVar::AuxiliarCoordinates, 0)
        .map_or_else(|| vec![Vector::zeros(); n_nodes], <[Vector]>::to_vec);
    for n in &s.master_nodes {
        aux[n.index()] = if o {
            coords[n.index()].coords
        } else {
            Vector::zeros()
        };
    }
    for n in &s.slave_nodes {
        aux[n.index()] = if o {
            Vector::zeros()
        } else {
            coords[n.index()].coords
        };
    }
    // Destination reset.
    for n in &s.slave_nodes {
        aux[n.index()] = Vector::zeros();
    }
    let slaves = SlavePositions::new(&s, n_nodes);
    // By slave node.
    let mut area = vec![0.0; s.slave_nodes.len()];
    let all: Vec<ConditionIdx> = s
        .master_conditions
        .iter()
        .chain(&s.slave_conditions)
        .copied()
        .collect();
    let m = &*model;
    // The largest area per task (the maximum in any grouping is the serial one), and the
    // first error in condition order.
    let areas: Vec<Result<LargestArea, Error>> = all
        .par_chunks(CONDITIONS_PER_TASK)
        .map(|chunk| {
            let mut gathered = GatheredPoints::default();
            let mut largest = LargestArea::default();
            for block in chunk.chunks(GATHER_BLOCK) {
                gathered.gather(m, block.iter().copied());
                for (k, &c) in block.iter().enumerate() {
                    largest
                        .add(m.conditions().kind(c.index()), gathered.points(k))
                        .map_err(|e| {
                            Error::condition("area", m.conditions().ids()[c.index()], &e)
                        })?;
                }
            }
            Ok(largest)
        })
        .collect();
    let mut largest = LargestArea::default();
    for a in areas {
        largest = largest.merge(a?);
    }
    let ref_area = largest.value();
    // 3. Segmentation of every INDEX_MAP entry, with the first two mapper iterations where
    // they can follow it (`streamed`).
    let tasks = Segmenting {
        seg: SegmentationSettings {
            mode: settings.mode,
            distance_threshold: settings.distance_threshold,
        },
        op: OperatorSettings::mapper(),
        store: OperatorStore::for_sides(&s, &slaves, o, dim),
        weighted_gap,
    };
    let mut report = MappingReport::default();
    let m = &*model;
    let (mut first, mut per_slave, gaps) = if streams(m, &s, &slaves, tasks.store) {
        let mut first =
            stream_first_iterations(m, &s, &tasks, (&aux, ref_area, &slaves), &mut report)?;
        let gaps = std::mem::take(&mut first.gaps);
        (Some(first), None, gaps)
    } else {
        let mut per_slave = segment_slaves(m, &s.slave_conditions, &tasks)?;
        let mut gaps = Vec::with_capacity(per_slave.iter().map(|m| m.gaps.len()).sum());
        for mapped in &mut per_slave {
            report.kept += mapped.kept.len();
            report.removed.append(&mut mapped.removed);
            gaps.append(&mut mapped.gaps);
        }
        (None, Some(kept_only(per_slave)), gaps)
    };
    let known = KnownGaps::new(gaps);
    for r in &report.removed {
        model.index_map_mut(r.slave).remove_id(r.master);
    }
    // 4. The explicit mapping iterations.
    let m = &*model;
    let n_d = s.slave_nodes.len().max(1) as Real;
    let mut r0: [Real; 3] = [0.0; 3];
    let mut r_prev: [Real; 3] = [0.0; 3];
    let mut iteration = 0;
    // Kratos' per-component flags are sticky: a component converged once stays converged.
    let mut component_converged = [report.kept == 0; 3];
    let mut converged = report.kept == 0;
    // By slave node (Kratos' VAUX of the other nodes is never read).
    let mut vaux = Vec::new();
    while !converged && iteration < MAPPER_MAX_ITERATIONS {
        match first.as_mut().filter(|_| iteration < 2) {
            // The streamed sums replace the previous iteration's.
            Some(first) => {
                std::mem::swap(&mut vaux, &mut first.vaux[iteration]);
                if iteration == 0 {
                    std::mem::swap(&mut area, &mut first.area);
                }
            }
            None => {
                // After the streamed iterations: the operators again (the index maps now hold
                // the kept entries only; the weighted gap is known).
                if per_slave.is_none() {
                    let tasks = Segmenting {
                        weighted_gap: None,
                        ..tasks
                    };
                    per_slave = Some(kept_only(segment_slaves(m, &s.slave_conditions, &tasks)?));
                }
                let per_slave = per_slave.as_deref().unwrap_or_default();
                vaux.clear();
                vaux.resize(s.slave_nodes.len(), Vector::zeros());
                let residual = Residual {
                    store: tasks.store,
                    dim,
                    aux: &aux,
                    slaves: &slaves,
                };
                for (sc, mc, packed) in kept_pairs(m, per_slave, tasks.store) {
                    residual.add(m, (sc, mc, packed), &mut vaux);
                    if iteration == 0 {
                        add_area(m, sc, packed, (&mut area, &slaves));
                    }
                }
            }
        }
        let mut sums = [0.0; 3];
        for (j, n) in s.slave_nodes.iter().enumerate() {
            let i = n.index();
            if area[j].abs() > AREA_TOLERANCE * ref_area {
                for k in 0..dim {
                    aux[i][k] += vaux[j][k] / area[j];
                }
            }
            for (k, sum) in sums.iter_mut().enumerate().take(dim) {
                *sum += vaux[j][k] * vaux[j][k];
            }
        }
        for k in 0..dim {
            let r = sums[k].sqrt() / n_d;
            if iteration == 0 {
                r0[k] = r;
            }
            let ok = r < MAPPER_ABSOLUTE_TOLERANCE
                || r / r0[k] < MAPPER_RELATIVE_TOLERANCE
                || (iteration > 0
                    && ((r - r_prev[k]) / r_prev[k]).abs() < MAPPER_RELATIVE_TOLERANCE);
            r_prev[k] = r;
            component_converged[k] |= ok;
        }
        converged = component_converged[..dim].iter().all(|c| *c);
        iteration += 1;
    }
    report.iterations = iteration;
    // 5. ComputeNormalGap (master side, then slave side): the new values (in that order; a
    // node on both sides takes its last), then written.
    let gaps: Vec<(usize, Real)> = {
        let normals = model.nodal_data().vector(VectorVar::Normal, 0);
        let nflags = model.nodes().flags();
        let coords = model.nodes().coordinates();
        s.master_nodes
            .iter()
            .chain(&s.slave_nodes)
            .filter_map(|n| {
                let i = n.index();
                if nflags[i].is(Flag::SLAVE) != o {
                    Some((i, 0.0))
                } else if norm_kratos(&aux[i]) > EPS {
                    let normal = normals.map_or_else(Vector::zeros, |col| col[i]);
                    Some((i, (coords[i].coords - aux[i]).dot(&(-normal))))
                } else {
                    None
                }
            })
            .collect()
    };
    let data = model.nodal_data_mut();
    if let Some(col) = data.scalar_mut(ScalarVar::NormalGap, 0) {
        for (i, g) in gaps {
            col[i] = g;
        }
    }
    if let Some(col) = data.scalar_mut(ScalarVar::NodalArea, 0) {
        for (j, n) in s.slave_nodes.iter().enumerate() {
            col[n.index()] = area[j];
        }
    }
    data.set_vector(VectorVar::AuxiliarCoordinates, aux)
        .map_err(|_| Error::message_only("AUXILIAR_COORDINATES: not one value per node".into()))?;
    Ok((report, known))
}
