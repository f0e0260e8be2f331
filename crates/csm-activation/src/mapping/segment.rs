//! The segmentation of the INDEX_MAP entries: kept pairs, removed entries, the mapper's
//! operators (and, on request, the weighted gap of every kept pair).

use csm_geometry::math::{Real, Vector};
use csm_geometry::{
    MAX_FACE_NODES, MAX_MORTAR_FACE_NODES, MortarMode, MortarOperators, OperatorSettings,
    Segmentation, SegmentationSettings, SlaveSegmentation, dual_basis_in, integration_points,
    line_projections_lost_to_rounding, mortar_operators,
};
use csm_model::{ConditionId, ConditionIdx, IndexMap, ModelPart, Ranks};

use rayon::prelude::*;

use super::RemovedEntry;
use super::sides::{Sides, SlavePositions};
use crate::error::Error;
use crate::face::{FaceData, face_data, face_data_with, make_face, nodal_normals};
use crate::weighted_gap::{FirstPass, KnownGap, PairGap, segmented_pair_gap, slave_area};

/// Slave conditions per parallel task of the segmentation.
pub(super) const SLAVES_PER_TASK: usize = 64;

/// The entries of consecutive slave conditions' INDEX_MAPs after the segmentation.
#[derive(Default)]
pub(super) struct SlaveMapping {
    /// The kept (slave, master) pairs, in order.
    pub(super) kept: Vec<(ConditionIdx, ConditionIdx)>,
    /// Their operators, packed one pair after the other ([`MortarOperators::pack_into`]).
    pub(super) operators: Vec<Real>,
    pub(super) removed: Vec<RemovedEntry>,
    /// With [`WeightedGapInputs`]: the weighted-gap contribution of every kept pair.
    pub(super) gaps: Vec<KnownGap>,
    /// The slave condition of every kept pair whose `Me` was too ill-conditioned for the
    /// dual basis (the standard basis instead: `D` is not diagonal).
    pub(super) standard: Vec<ConditionIdx>,
    /// Kratos mode: master nodes of 2D pairs its projection dropped to rounding
    /// ([`line_projections_lost_to_rounding`]).
    pub(super) lost_projections: usize,
}

impl SlaveMapping {
    /// Its kept pairs and their operators only (the removed entries and the weighted gaps
    /// are reported and taken before).
    pub(super) fn kept_part(self) -> SlaveMapping {
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
pub(super) struct WeightedGapInputs<'a> {
    /// The nodal `NORMAL` the weighted gap will read, by node index.
    pub(super) unit_normals: &'a [Vector],
    pub(super) dim: usize,
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
    /// Robust mode's direct solve ([`super::iterate::solve_relative`]): per slave node `i`,
    /// the row sum of `D` (`∫ Φ_i` over the overlap: `D`'s diagonal for the dual basis, the
    /// lumped `D` for the standard one), then for each of the `dim` components the moments
    /// `Σ_m M_im (X_m − X_i)` of the master points relative to the slave node. Nothing absolute
    /// is summed, so the mapping is invariant under translations as it is assembled.
    Relative { dim: usize },
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
        full_operators: bool,
    ) -> OperatorStore {
        if full_operators || s.master_nodes.iter().any(|&n| slaves.get(n).is_some()) {
            OperatorStore::Operators
        } else {
            OperatorStore::MasterProducts { origin, dim }
        }
    }

    /// The number of values [`pack`](Self::pack) appends for `ns` slave and `nm` master
    /// nodes.
    pub(super) fn packed_len(self, ns: usize, nm: usize) -> usize {
        match self {
            OperatorStore::Operators => MortarOperators::packed_len(ns, nm),
            OperatorStore::MasterProducts { dim, .. } => {
                MortarOperators::packed_with_products_len(ns, dim)
            }
            OperatorStore::Relative { dim } => ns * (1 + dim),
        }
    }

    /// Appends the operators of the pair `(sc, mc)` to `out`.
    // The component `k` picks the coordinates of every node: no iterator of components.
    #[allow(clippy::needless_range_loop)]
    fn pack(
        self,
        model: &ModelPart,
        (sc, mc): (ConditionIdx, ConditionIdx),
        operators: &MortarOperators,
        out: &mut Vec<Real>,
    ) {
        match self {
            OperatorStore::Relative { dim } => {
                let coords = model.nodes().coordinates();
                let slave_nodes = model.conditions().nodes(sc.index());
                let master_nodes = model.conditions().nodes(mc.index());
                for i in 0..slave_nodes.len() {
                    out.push(operators.d.row(i).iter().sum());
                }
                for k in 0..dim {
                    for (i, s) in slave_nodes.iter().enumerate() {
                        let origin = coords[s.index()][k];
                        let mut moment = 0.0;
                        for (a, n) in operators.m.row(i).iter().zip(master_nodes) {
                            moment += a * (coords[n.index()][k] - origin);
                        }
                        out.push(moment);
                    }
                }
            }
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
pub(super) struct Segmenting<'a> {
    pub(super) seg: SegmentationSettings,
    pub(super) op: OperatorSettings,
    pub(super) store: OperatorStore,
    /// With it, the weighted gap of every kept pair as well.
    pub(super) weighted_gap: Option<WeightedGapInputs<'a>>,
    /// Slave conditions per streamed batch ([`super::MappingTuning::stream_batch`]).
    pub(super) stream_batch: usize,
    /// Gather the streamed sums by node from this many threads on
    /// ([`super::MappingTuning::gather_from_threads`]).
    pub(super) gather_from_threads: usize,
    /// A distributed run: the counts of the report (lost projections) take this rank's
    /// owned slave conditions only.
    pub(super) ranks: Option<&'a Ranks>,
}

/// Segments the INDEX_MAP entries of `slaves`, in parallel: their mappings in slave order,
/// [`SLAVES_PER_TASK`] slaves each. The first error in slave order.
pub(super) fn segment_slaves(
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
                let id = m.conditions().ids()[sc.index()];
                let counted = tasks.ranks.is_none_or(|r| r.owns_condition(id));
                map_slave(
                    m,
                    sc,
                    (&tasks.seg, &tasks.op),
                    (tasks.store, tasks.weighted_gap),
                    (&mut out, counted),
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
pub(super) fn kept_only(per_slave: Vec<SlaveMapping>) -> Vec<SlaveMapping> {
    per_slave
        .into_iter()
        .filter(|m| !m.kept.is_empty())
        .map(SlaveMapping::kept_part)
        .collect()
}

/// Every kept pair of `per_slave` with its packed operators, in order.
pub(super) fn kept_pairs<'a>(
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

/// Segments every INDEX_MAP entry of slave condition `sc`: entries without overlap are
/// removed; the others get the dual basis and the mapper's `D`, `M` operators (appended to
/// `out`; its lost projections where `counted`).
fn map_slave(
    model: &ModelPart,
    sc: ConditionIdx,
    (seg_settings, op_settings): (&SegmentationSettings, &OperatorSettings),
    (store, weighted_gap): (OperatorStore, Option<WeightedGapInputs<'_>>),
    (out, counted): (&mut SlaveMapping, bool),
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
        if seg_settings.mode == MortarMode::Kratos && counted {
            out.lost_projections += line_projections_lost_to_rounding(&slave, &master);
        }
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
        let basis = dual_basis_in(&slave, &gps, seg_settings.mode);
        if !basis.is_dual() {
            out.standard.push(sc);
        }
        let operators = mortar_operators(&slave, &master, &gps, Some(&basis));
        store.pack(model, (sc, mc), &operators, &mut out.operators);
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

/// Removed entries per task of [`remove_entries`], at least.
const REMOVALS_PER_TASK: usize = 4096;

/// Removes the `removed` entries from the INDEX_MAPs `maps` (every condition's, by index),
/// each map's in the list's order. Where the list's slave conditions ascend (a part's
/// conditions in index order, as usual), in parallel: the list is cut between two slaves'
/// entries and the maps at the first slave after the cut, so each task holds the maps it
/// changes, with no list of them to build; otherwise one pass in order.
pub(super) fn remove_entries(maps: &mut [IndexMap], removed: &[RemovedEntry]) {
    /// The entries `removed` from `maps`, whose first is condition `offset`'s map, in order.
    fn remove_serially(maps: &mut [IndexMap], offset: usize, removed: &[RemovedEntry]) {
        for r in removed {
            maps[r.slave.index() - offset].remove_id(r.master);
        }
    }
    /// The entries `removed` from `maps`, whose first is condition `offset`'s map.
    fn remove_in(maps: &mut [IndexMap], offset: usize, removed: &[RemovedEntry]) {
        let n = removed.len();
        let slave_at = |k: usize| removed[k].slave;
        // The cut: the middle moved on to the first entry of the next slave, or where one
        // slave's entries run to the end, back to the first of the middle's slave.
        let mut cut = n / 2;
        if n > REMOVALS_PER_TASK {
            while cut < n && slave_at(cut) == slave_at(cut - 1) {
                cut += 1;
            }
            if cut == n {
                cut = n / 2;
                while cut > 0 && slave_at(cut) == slave_at(cut - 1) {
                    cut -= 1;
                }
            }
        }
        if n <= REMOVALS_PER_TASK || cut == 0 {
            return remove_serially(maps, offset, removed);
        }
        let (left, right) = removed.split_at(cut);
        let (left_maps, right_maps) = maps.split_at_mut(right[0].slave.index() - offset);
        let split = offset + left_maps.len();
        rayon::join(
            || remove_in(left_maps, offset, left),
            || remove_in(right_maps, split, right),
        );
    }
    let ascending = |w: &[RemovedEntry]| w[0].slave <= w[1].slave;
    if removed.len() <= REMOVALS_PER_TASK || removed.par_windows(2).all(ascending) {
        remove_in(maps, 0, removed);
    } else {
        remove_serially(maps, 0, removed);
    }
}
