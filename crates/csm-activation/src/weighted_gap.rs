//! ComputeWeightedReaction: the explicit weighted gap of the paired conditions (§10.3).

use csm_geometry::math::Real;
use csm_geometry::{
    DualBasis, MortarIntegrationPoint, MortarMode, MortarOperators, OperatorSettings,
    SegmentationSettings, dual_basis_in, exact_segmentation, integration_points,
    integration_points_with_normals, mortar_operators,
};
use csm_geometry::{Geometry, MAX_MORTAR_FACE_NODES, MortarFace, Segmentation};
use csm_model::{ConditionIdx, ModelPart, PartIdx, ScalarVar};
use rayon::prelude::*;
use std::sync::atomic::Ordering::Relaxed;
use std::sync::atomic::{AtomicBool, AtomicUsize};

use crate::error::Error;
use crate::face::{FaceData, face_data, make_face};

/// A pair contributes only if `overlap area / slave area > WEIGHTED_GAP_AREA_RATIO`.
pub const WEIGHTED_GAP_AREA_RATIO: Real = 1e-5;

/// `ComputeWeightedReaction` for a frictionless setup: `WEIGHTED_GAP := 0` on the nodes of
/// `sub`, then every paired condition `(slave, master)` adds `−n_i · (D x_s − M x_m)_i` to
/// its slave nodes (dual basis, explicit operator settings, current coordinates, nodal
/// `NORMAL`; the slave normal is the slave condition's normal, the master normal the master
/// condition's). Returns, per pair, Kratos' condition flag ISOLATED: true where the pair
/// contributed nothing (no overlap above [`WEIGHTED_GAP_AREA_RATIO`] of the slave's area).
/// Nothing happens, and nothing is returned, when the model has no `WEIGHTED_GAP`.
///
/// Errors: a face the mortar routines refuse.
///
/// `known`: contributions the mapping already computed ([`crate::normal_gap_process_keeping`]
/// in a step whose coordinates did not move); a pair found there is not computed again.
pub fn compute_weighted_gap(
    model: &mut ModelPart,
    sub: PartIdx,
    pairs: &[(ConditionIdx, ConditionIdx)],
    (mode, distance_threshold): (MortarMode, Real),
    dim: usize,
    known: Option<KnownGaps>,
) -> Result<Vec<bool>, Error> {
    if !model.nodal_data().has_scalar(ScalarVar::WeightedGap) {
        return Ok(Vec::new());
    }
    let dim = dim.clamp(1, 3);
    let seg_settings = SegmentationSettings {
        mode,
        distance_threshold,
    };
    // Every pair's contribution, in pair order, looked up in parallel (the sums below then
    // only add); those the mapping did not compute are computed, in parallel too. Every
    // contribution is added below in pair order (Kratos' sums).
    let m = &*model;
    let known = known.unwrap_or_default();
    // (The pairs come mostly in key order: each task looks them up with its own cursor.)
    // The lookups also note whether a pair is not known and the first known error (the
    // smallest position: the same whatever the order of the notes).
    let (unknown, first_error) = (AtomicBool::new(false), AtomicUsize::new(usize::MAX));
    let looked: Vec<Option<&Contribution>> = (pairs.par_iter().enumerate())
        .map_init(
            || known.cursor(),
            |cursor, (k, &(sc, mc))| {
                let found = cursor.get(sc, mc);
                match found {
                    None => unknown.store(true, Relaxed),
                    Some(Err(_)) => {
                        first_error.fetch_min(k, Relaxed);
                    }
                    Some(Ok(_)) => {}
                }
                found
            },
        )
        .collect();
    // Only the pairs the mapping did not compute are listed, with their positions (usually
    // none: a list of every pair's possible contribution would be as long as the pairs'
    // contributions, all of them untouched memory to fault in).
    let computed: Vec<(usize, Contribution)> = if unknown.into_inner() {
        (pairs.par_iter().zip(&looked).enumerate())
            .filter(|(_, (_, known))| known.is_none())
            .map(|(k, (&(sc, mc), _))| (k, pair_weighted_gap(m, sc, mc, &seg_settings, dim)))
            .collect()
    } else {
        Vec::new()
    };
    let contribution = |k: usize| -> &Contribution {
        looked[k].unwrap_or_else(|| {
            let at = computed.binary_search_by_key(&k, |(k, _)| *k);
            &computed[at.expect("one contribution per pair, known or computed")].1
        })
    };
    // The first error in pair order, known or computed, before anything is written (the
    // model's values stay as they were on an error).
    let computed_error = computed.iter().find(|(_, c)| c.is_err()).map(|(k, _)| *k);
    let first = first_error
        .into_inner()
        .min(computed_error.unwrap_or(usize::MAX));
    if first < pairs.len()
        && let Err(e) = contribution(first)
    {
        return Err(e.clone());
    }
    // Summed in place: the sub's nodes start at zero, then every contribution in pair order.
    let mut isolated = Vec::with_capacity(pairs.len());
    model.with_scalar_mut(ScalarVar::WeightedGap, 0, |m, wg| {
        let nodes = m.part(sub).nodes();
        csm_model::write_at_ascending(wg, nodes.len(), |k| nodes[k].index(), |_, w| *w = 0.0);
        for (k, &(sc, _)) in pairs.iter().enumerate() {
            let contribution = contribution(k);
            // (No error is left: the first one was returned above.)
            debug_assert!(contribution.is_ok(), "an error reached the sums");
            let pair = contribution.as_ref().ok().and_then(Option::as_ref);
            isolated.push(pair.is_none());
            let Some(pair) = pair else {
                continue;
            };
            for (n, g) in m.conditions().nodes(sc.index()).iter().zip(pair.gaps()) {
                wg[n.index()] += g;
            }
        }
    });
    drop(looked);
    known.par_drop();
    Ok(isolated)
}

/// One pair's weighted-gap contribution per slave node (in node order).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PairGap {
    len: usize,
    gaps: [Real; MAX_MORTAR_FACE_NODES],
}

impl PairGap {
    fn gaps(&self) -> &[Real] {
        &self.gaps[..self.len]
    }
}

/// Entries from which [`KnownGaps`] sorts, checks and frees its runs in parallel passes (a
/// parallel pass costs more than a few entries' work).
const PARALLEL_ENTRIES: usize = 1 << 14;

/// A pair's weighted-gap contribution: `None` without enough overlap (ISOLATED), or the error
/// its computation gave.
pub(crate) type Contribution = Result<Option<PairGap>, Error>;

/// One entry of [`KnownGaps`]: a (slave, master) pair and its contribution.
pub(crate) type KnownGap = ((ConditionIdx, ConditionIdx), Contribution);

/// Weighted-gap contributions computed by the mapping, by (slave, master) condition: the
/// contribution, `None` for a pair without enough overlap (ISOLATED), or the error its
/// computation gave (reported when the weighted gap reaches the pair, in pair order).
///
/// Kept as the runs the mapping's tasks wrote (one per task of slave conditions), not joined
/// into one list: a join would copy every entry on one thread, into fresh memory.
#[derive(Debug, Default)]
pub struct KnownGaps {
    /// Runs of entries, each sorted by key and not empty; every key of a run is below every
    /// key of the next.
    runs: Vec<Vec<KnownGap>>,
    /// The number of entries.
    len: usize,
}

impl KnownGaps {
    /// The entries of one list.
    #[cfg(test)]
    pub(crate) fn new(entries: Vec<KnownGap>) -> KnownGaps {
        KnownGaps::from_runs(vec![entries])
    }

    /// The entries of `runs` (the mapping's tasks', in the order of its slave conditions):
    /// each run sorted (in parallel from [`PARALLEL_ENTRIES`] entries). Where the runs' keys
    /// then interleave (slave conditions out of index order), every entry is merged into one
    /// sorted run.
    pub(crate) fn from_runs(mut runs: Vec<Vec<KnownGap>>) -> KnownGaps {
        runs.retain(|run| !run.is_empty());
        // Keys are unique: an unstable sort gives the same order, without a buffer.
        let sort = |run: &mut Vec<KnownGap>| run.sort_unstable_by_key(|(key, _)| *key);
        let last = |run: &[KnownGap]| run[run.len() - 1].0;
        let before = |w: &[Vec<KnownGap>]| last(&w[0]) < w[1][0].0;
        let len = runs.iter().map(Vec::len).sum();
        let ordered = if len >= PARALLEL_ENTRIES {
            runs.par_iter_mut().for_each(sort);
            runs.par_windows(2).all(before)
        } else {
            runs.iter_mut().for_each(sort);
            runs.windows(2).all(before)
        };
        if !ordered {
            let mut all: Vec<KnownGap> = runs.into_iter().flatten().collect();
            all.sort_unstable_by_key(|(key, _)| *key);
            runs = vec![all];
        }
        KnownGaps { runs, len }
    }

    /// The number of pairs.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether no pair is known.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The run that holds `key` if any run does: the first whose last key is not below it
    /// (`runs.len()` when none is).
    fn run_of(&self, key: (ConditionIdx, ConditionIdx)) -> usize {
        (self.runs).partition_point(|run| run[run.len() - 1].0 < key)
    }

    /// The contribution of the pair `(slave, master)`, if known (the oracle of
    /// [`KnownGapsCursor::get`]).
    #[cfg(test)]
    pub(crate) fn get(&self, slave: ConditionIdx, master: ConditionIdx) -> Option<&Contribution> {
        let key = (slave, master);
        let run = self.runs.get(self.run_of(key))?;
        let k = run.binary_search_by_key(&key, |(key, _)| *key).ok()?;
        Some(&run[k].1)
    }

    /// Every entry, by key.
    #[cfg(test)]
    pub(crate) fn entries(&self) -> Vec<&KnownGap> {
        self.runs.iter().flatten().collect()
    }

    /// The number of runs kept.
    #[cfg(test)]
    pub(crate) fn n_runs(&self) -> usize {
        self.runs.len()
    }

    /// A cursor for many lookups ([`KnownGapsCursor::get`]).
    pub(crate) fn cursor(&self) -> KnownGapsCursor<'_> {
        KnownGapsCursor {
            gaps: self,
            run: 0,
            position: 0,
        }
    }

    /// Frees the entries, the runs in parallel from [`PARALLEL_ENTRIES`] entries (each
    /// entry's drop reads it: on one thread, a pass over all of them).
    pub(crate) fn par_drop(self) {
        if self.len >= PARALLEL_ENTRIES {
            self.runs.into_par_iter().for_each(drop);
        }
    }
}

/// Lookups in a [`KnownGaps`] that start from the previous one's position: pairs asked in key
/// order are found by a short forward search instead of a binary search over every entry
/// (a cache miss per step on a large table).
pub(crate) struct KnownGapsCursor<'a> {
    gaps: &'a KnownGaps,
    /// The run where the previous lookup ended, and its position there (the entry found, or
    /// where it would be).
    run: usize,
    position: usize,
}

impl<'a> KnownGapsCursor<'a> {
    /// The contribution of the pair `(slave, master)`, if known: the same answer as a binary
    /// search over every entry, for any sequence of lookups.
    pub(crate) fn get(
        &mut self,
        slave: ConditionIdx,
        master: ConditionIdx,
    ) -> Option<&'a Contribution> {
        let runs = &self.gaps.runs;
        let key = (slave, master);
        // In the run of the previous lookup, from its position: a short search forward
        // (lookups in key order) or back (a slave's masters by id need not be in index
        // order). The runs' key ranges do not overlap, so a key inside this run's range and
        // not found in it is not known.
        if let Some(entries) = runs.get(self.run)
            && entries[0].0 <= key
        {
            let found = match entries.get(self.position) {
                Some((k, _)) if *k <= key => gallop(entries, self.position, key),
                _ => entries[..self.position].binary_search_by_key(&key, |(k, _)| *k),
            };
            match found {
                Ok(i) => {
                    self.position = i;
                    return Some(&entries[i].1);
                }
                Err(i) if i < entries.len() => {
                    self.position = i;
                    return None;
                }
                // (Past the run's last key: a later run's.)
                Err(_) => {}
            }
        }
        // The next run, or the one whose range would hold the key (a binary search of the
        // runs), searched whole.
        let next = self.run + 1;
        let r = if runs
            .get(next)
            .is_some_and(|run| run[0].0 <= key && key <= run[run.len() - 1].0)
        {
            next
        } else {
            self.gaps.run_of(key)
        };
        self.run = r;
        let Some(entries) = runs.get(r) else {
            self.position = 0;
            return None;
        };
        match entries.binary_search_by_key(&key, |(k, _)| *k) {
            Ok(i) => {
                self.position = i;
                Some(&entries[i].1)
            }
            Err(i) => {
                self.position = i;
                None
            }
        }
    }
}

/// The position of `key` in `entries` (sorted by key), or where it would be, by a search
/// forward from `start`, whose key is at most `key`: galloping, then a binary search.
fn gallop(
    entries: &[KnownGap],
    start: usize,
    key: (ConditionIdx, ConditionIdx),
) -> Result<usize, usize> {
    // `entries[low]` is at most the key, `entries[high]` (if any) above it.
    let (mut low, mut step) = (start, 1);
    let mut high = start + 1;
    while high < entries.len() && entries[high].0 <= key {
        low = high;
        step *= 2;
        high = low + step;
    }
    let high = high.min(entries.len());
    match entries[low..high].binary_search_by_key(&key, |(k, _)| *k) {
        Ok(i) => Ok(low + i),
        Err(i) => Err(low + i),
    }
}

/// The contribution of the pair `(sc, mc)`, `None` when it has no overlap above
/// [`WEIGHTED_GAP_AREA_RATIO`] of the slave's area.
fn pair_weighted_gap(
    model: &ModelPart,
    sc: ConditionIdx,
    mc: ConditionIdx,
    seg_settings: &SegmentationSettings,
    dim: usize,
) -> Result<Option<PairGap>, Error> {
    let slave_id = model.conditions().ids()[sc.index()];
    let sdata = face_data(model, sc);
    let mdata = face_data(model, mc);
    let slave = make_face(model, sc, &sdata)?;
    let master = make_face(model, mc, &mdata)?;
    let Some(seg) = exact_segmentation(&slave, &master, seg_settings)
        .map_err(|e| Error::condition("mortar segmentation", slave_id, &e))?
    else {
        return Ok(None);
    };
    let slave_area = slave_area(model, sc, &sdata)?;
    segmented_pair_gap(
        model,
        sc,
        (&sdata, &slave, slave_area),
        (&mdata, &master),
        (&seg, None),
        dim,
    )
}

/// The area of slave condition `sc` (points `sdata`), the reference of the overlap ratio.
pub(crate) fn slave_area(
    model: &ModelPart,
    sc: ConditionIdx,
    sdata: &FaceData,
) -> Result<Real, Error> {
    Geometry::new(model.conditions().kind(sc.index()), &sdata.points)
        .and_then(|g| g.area())
        .map_err(|e| Error::condition("area", model.conditions().ids()[sc.index()], &e))
}

/// The mapper's work on a pair that [`segmented_pair_gap`] reuses.
#[derive(Clone, Copy)]
pub(crate) struct FirstPass<'a> {
    /// The mapper's Gauss points.
    pub points: &'a [MortarIntegrationPoint],
    /// The mapper's dual basis.
    pub basis: &'a DualBasis,
    /// The mapper's operators, where the weighted gap's slave nodal normals are the mapper's.
    pub operators: Option<&'a MortarOperators>,
}

/// The weighted-gap contribution of a pair from its segmentation `seg` (explicit operator
/// settings; the faces carry the nodal normals the weighted gap uses; `slave_area` from
/// [`slave_area`]), `None` when the overlap is not above [`WEIGHTED_GAP_AREA_RATIO`] of the
/// slave's area.
///
/// `first_pass`: the Gauss points and dual basis of the mapper on the same faces and
/// segmentation, in 3D (the same cells: the degenerate-cell test of triangles does not depend
/// on the operator settings). The points are then only moved to the new nodal normals
/// ([`integration_points_with_normals`]) and the basis is kept (it depends on the slave side
/// only): bit for bit the values computed afresh. With the mapper's operators as well (given
/// where the slave's nodal normals are the mapper's, bit for bit — flat faces), the points do
/// not move at all (their normals, master projections and master local coordinates are
/// computed from the same bits), so the operators are the mapper's and are used as they are.
pub(crate) fn segmented_pair_gap(
    model: &ModelPart,
    sc: ConditionIdx,
    (sdata, slave, slave_area): (&FaceData, &MortarFace<'_>, Real),
    (mdata, master): (&FaceData, &MortarFace<'_>),
    (seg, first_pass): (&Segmentation, Option<FirstPass<'_>>),
    dim: usize,
) -> Result<Option<PairGap>, Error> {
    let slave_id = model.conditions().ids()[sc.index()];
    let wrap =
        |what: &'static str| move |e: csm_geometry::Error| Error::condition(what, slave_id, &e);
    if seg.cells().is_empty() || seg.overlap_area() / slave_area <= WEIGHTED_GAP_AREA_RATIO {
        return Ok(None);
    }
    let ops = match first_pass {
        Some(FirstPass {
            operators: Some(operators),
            ..
        }) => *operators,
        Some(FirstPass { points, basis, .. }) => {
            let gps = integration_points_with_normals(slave, master, points)
                .map_err(wrap("mortar integration"))?;
            mortar_operators(slave, master, &gps, Some(basis))
        }
        None => {
            let gps = integration_points(slave, master, seg, &OperatorSettings::explicit())
                .map_err(wrap("mortar integration"))?;
            let basis = dual_basis_in(slave, &gps, seg.mode());
            mortar_operators(slave, master, &gps, Some(&basis))
        }
    };
    // Kratos: `D_x1_M_x2 = prod(D, x1) − prod(M, x2)`, then
    // `WEIGHTED_GAP_i += inner_prod(row_i, −n_i)` (sums in index order from 0). Robust mode
    // takes every point relative to the slave node `i`: the same value in exact arithmetic
    // (`Σ_j D_ij = Σ_m M_im`, the shape functions sum to one), without the cancellation of two
    // sums of absolute coordinates far from the origin.
    // `slave` is a mortar face of these points: it has at most four nodes.
    debug_assert!(sdata.points.len() <= MAX_MORTAR_FACE_NODES);
    let relative = seg.mode() == MortarMode::Robust;
    let mut out = PairGap {
        len: sdata.points.len(),
        gaps: [0.0; MAX_MORTAR_FACE_NODES],
    };
    for (i, gap) in out.gaps[..out.len].iter_mut().enumerate() {
        let normal = sdata.nodal_normals[i];
        let mut g = 0.0;
        for k in 0..dim {
            let origin = if relative { sdata.points[i][k] } else { 0.0 };
            let mut dx = 0.0;
            for (j, p) in sdata.points.iter().enumerate() {
                dx += ops.d[(i, j)] * (p[k] - origin);
            }
            let mut mx = 0.0;
            for (j, p) in mdata.points.iter().enumerate() {
                mx += ops.m[(i, j)] * (p[k] - origin);
            }
            g += (dx - mx) * -normal[k];
        }
        *gap = g;
    }
    Ok(Some(out))
}
