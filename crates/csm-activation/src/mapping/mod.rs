//! NormalGapProcess and the explicit dual-mortar mapper (reference §10.1 a–b, §10.2).
//!
//! - [`sides`]: the slave and master sides of a ContactSub, the mapper's slave-node numbering;
//! - [`mean_normals`]: the nodal mean normals the mapping writes first;
//! - [`segment`]: the exact segmentation of every INDEX_MAP entry, the kept pairs' operators;
//! - [`stream`]: the first two iterations streamed with the segmentation (large interfaces);
//! - [`gather`]: the same with the nodal sums gathered by slave node in parallel (many
//!   threads);
//! - [`iterate`]: Kratos' explicit iterations (residuals, nodal areas) and robust mode's
//!   direct solve;
//! - this module: the process itself, step by step, and `ComputeNormalGap`.

mod gather;
mod iterate;
mod mean_normals;
mod segment;
mod sides;
mod stream;

use csm_geometry::math::{EPS, Real, Vector, norm_kratos};
use csm_geometry::{LargestArea, MortarMode, OperatorSettings, SegmentationSettings};
use csm_model::{
    ConditionId, ConditionIdx, Flag, GATHER_BLOCK, GatheredPoints, KeptFaceNormals, ModelPart,
    PartIdx, Ranks, ScalarVar, VectorVar, write_at_ascending,
};

use rayon::prelude::*;

use crate::error::Error;
use crate::weighted_gap::KnownGaps;

pub(crate) use mean_normals::{mean_normals, normals_read};
pub(crate) use segment::OperatorStore;
pub(crate) use sides::{SlavePositions, sides};
pub use sides::{mean_h, mean_h_shared};

use iterate::{Segmented, kratos_iterations, solve_relative};
use segment::{Segmenting, WeightedGapInputs, kept_only, segment_slaves};
use stream::{SLAVES_PER_BATCH, STREAM_MIN_ENTRIES, stream_first_iterations, streams};

/// Conditions per parallel task of the reference area.
const CONDITIONS_PER_TASK: usize = 4096;

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
#[derive(Debug, Clone, PartialEq)]
pub struct MappingSettings {
    /// Kratos' rules or the robust segmentation.
    pub mode: MortarMode,
    /// `ProcessInfo[DISTANCE_THRESHOLD]` (1e24 when absent).
    pub distance_threshold: Real,
    /// The search's `inverted_search` (the orientation of NormalGapProcess is `!inverted`).
    pub inverted: bool,
    /// The domain size (2 or 3): the number of mapped components.
    pub dim: usize,
    /// How the work is organised ([`MappingTuning::default`] in production).
    pub tuning: MappingTuning,
    /// A distributed run: this rank's part of it (`None`: one process). The model is then the
    /// rank's part (`csm-distributed`): the mapping shares the reference area, the slave
    /// node count and every iteration's convergence sums with the other ranks, takes its ghost
    /// slave nodes' values from their owners after every iteration, and counts what it reports
    /// over the slave conditions and nodes it owns, so that every owned value is the one of
    /// the one-process run, bit for bit (`docs/distributed.md`).
    pub ranks: Option<Ranks>,
}

/// How the mapping organises its work in kratos mode. No choice changes a result — every
/// one gives the same bits (tested over every combination) —: they let the tests reach every
/// path on small models, and a caller trade memory for passes over the INDEX_MAPs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MappingTuning {
    /// From this many INDEX_MAP entries on, the first two iterations are streamed batch by
    /// batch instead of keeping every pair's operators (where they can be: module
    /// `mapping::stream`); `usize::MAX` never streams. Default 65,536.
    pub stream_min_entries: usize,
    /// Slave conditions per streamed batch. Default 8,192.
    pub stream_batch: usize,
    /// Keep each pair's `D` and `M` even where the products `M·v` of the fixed master values
    /// would do. Default false.
    pub full_operators: bool,
    /// From this many threads on (rayon's current pool), the streamed iterations gather
    /// their nodal sums by slave node in parallel (module `mapping::gather`) instead of one
    /// serial pass over the pairs; `usize::MAX` never, 1 always. Default
    /// [`GATHER_FROM_THREADS`].
    pub gather_from_threads: usize,
}

/// The default [`MappingTuning::gather_from_threads`]: where the gather's extra passes cost
/// less than the serial pass they replace (measured, `docs/performance-analysis.md`).
pub const GATHER_FROM_THREADS: usize = 3;

impl Default for MappingTuning {
    fn default() -> MappingTuning {
        MappingTuning {
            stream_min_entries: STREAM_MIN_ENTRIES,
            stream_batch: SLAVES_PER_BATCH,
            full_operators: false,
            gather_from_threads: GATHER_FROM_THREADS,
        }
    }
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
    /// Mapper iterations run (robust mode: 1, its direct solve, or 0 without kept pairs).
    pub iterations: usize,
    /// Whether the mapping reached its end by Kratos' convergence tests rather than the
    /// iteration limit (robust mode's direct solve: always).
    pub converged: bool,
    /// The largest correction `|ΔAUXILIAR_COORDINATES|` of a slave node in the last
    /// iteration, a length (robust mode: 0). Far from the origin or with a standard-basis
    /// pair, what is left of the mapped points' error is of this order.
    pub last_correction: Real,
    /// Kept pairs whose `Me` was too ill-conditioned for the dual basis: their `D` is the
    /// standard basis' (not diagonal), so Kratos' explicit iterations are no longer one exact
    /// step (robust mode lumps that `D` and solves directly).
    pub standard_basis_pairs: usize,
    /// The slave nodes of the slave conditions of those pairs.
    pub standard_basis_nodes: usize,
    /// Kratos mode: slave nodes the mapper updated whose mapped point is within ε of the
    /// origin, so that Kratos' `|AUX| > ε` test reads them as not mapped (Q39: they keep the
    /// 1e12 sentinel and turn inactive). Robust mode tracks mapped nodes and has none.
    pub origin_nodes: usize,
    /// Kratos mode: master nodes of 2D pairs that Kratos' projection onto the slave dropped
    /// because its test on `Δξ`, computed from absolute coordinates, never passed, where the
    /// projection relative to the slave converges (far from the origin: the pairs lose overlap
    /// or are removed). Robust mode projects relative to the slave and has none.
    pub lost_projections: usize,
}

impl MappingReport {
    /// What a user should know of this mapping's accuracy, as `RESULT.json` warnings. In
    /// [`MortarMode::Kratos`]: where some kept pair fell back to the standard basis (then
    /// Kratos' explicit iterations are no longer one exact step, and what they leave is a
    /// fraction of the mapped coordinates, so it grows with the distance from the origin), or
    /// where the iterations stopped at their limit. [`MortarMode::Robust`] solves the mapping
    /// directly and has nothing to report.
    pub fn warnings(&self, mode: MortarMode) -> Vec<String> {
        if mode == MortarMode::Robust {
            return Vec::new();
        }
        let mut warnings = Vec::new();
        if self.origin_nodes > 0 {
            warnings.push(format!(
                "NORMAL_GAP: {} slave node(s) were mapped onto the origin, which Kratos' \
                 |AUXILIAR_COORDINATES| > eps test reads as not mapped: they keep the 1e12 \
                 sentinel and are inactive (Q39); \"compatibility\": \"robust\" knows which \
                 nodes are mapped",
                self.origin_nodes
            ));
        }
        if self.lost_projections > 0 {
            warnings.push(format!(
                "2D mortar segmentation: {} master-node projection(s) did not converge in \
                 Kratos' absolute coordinates (they do relative to the slave), so those nodes \
                 were dropped and their pairs lost overlap or were removed (MappingCheck); \
                 \"compatibility\": \"robust\" projects relative to the slave",
                self.lost_projections
            ));
        }
        if self.converged && self.standard_basis_pairs == 0 {
            return warnings;
        }
        let how = if self.converged {
            format!(
                "stopped after {} iteration(s) by Kratos' tests",
                self.iterations
            )
        } else {
            format!("stopped at its limit of {MAPPER_MAX_ITERATIONS} iterations without converging")
        };
        let basis = if self.standard_basis_pairs > 0 {
            format!(
                "{} mapped pair(s) ({} slave node(s)) fell back to the standard mortar basis \
                 (an ill-conditioned overlap), so Kratos' explicit mapper is not exact in one \
                 step there; it ",
                self.standard_basis_pairs, self.standard_basis_nodes
            )
        } else {
            "the mortar mapper ".to_owned()
        };
        warnings.push(format!(
            "NORMAL_GAP: {basis}{how}, the last correction of a mapped point being {:.3e}; the \
             mapped gap may be off by a fraction of the coordinates' distance from the origin \
             (Kratos computes the same); \"compatibility\": \"robust\" solves the mapping \
             directly, relative to each slave node",
            self.last_correction
        ));
        warnings
    }
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
        let (part, data) = model.part_and_nodal_data_mut(sub);
        let sub_nodes = part.nodes();
        data.add_scalar(ScalarVar::NormalGap);
        data.add_scalar(ScalarVar::NodalArea);
        // AUXILIAR_COORDINATES: computed below and moved in at the end (no column of zeros
        // to write first and copy into afterwards).
        if let Some(col) = data.scalar_mut(ScalarVar::NormalGap, 0) {
            let at = |k: usize| sub_nodes[k].index();
            write_at_ascending(col, sub_nodes.len(), at, |_, g| *g = NORMAL_GAP_SENTINEL);
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
    // Origin side: the coordinates (or 0 when inverted); destination side: 0 (whatever the
    // origin side wrote, Kratos' destination reset); other nodes keep their value. Written
    // in parallel from each node's side.
    let coords = model.nodes().coordinates();
    let (master_side, slave_side) = (1u8, 2u8);
    let mut side = vec![0u8; n_nodes];
    for (nodes, mark) in [(&s.master_nodes, master_side), (&s.slave_nodes, slave_side)] {
        write_at_ascending(
            &mut side,
            nodes.len(),
            |k| nodes[k].index(),
            |_, v| *v |= mark,
        );
    }
    let before = model.nodal_data().vector(VectorVar::AuxiliarCoordinates, 0);
    let mut aux: Vec<Vector> = (0..n_nodes)
        .into_par_iter()
        .map(|i| match side[i] {
            0 => before.map_or_else(Vector::zeros, |b| b[i]),
            m if m == master_side && o => coords[i].coords,
            _ => Vector::zeros(),
        })
        .collect();
    drop(side);
    let slaves = SlavePositions::new(&s, n_nodes);
    // By slave node.
    let mut area = vec![0.0; s.slave_nodes.len()];
    let m = &*model;
    // The largest area per task (the maximum in any grouping is the serial one), and the
    // first error in condition order (master side, then slave side; no joined copy of the
    // two lists).
    let areas: Vec<Result<LargestArea, Error>> = (s.master_conditions)
        .par_chunks(CONDITIONS_PER_TASK)
        .chain(s.slave_conditions.par_chunks(CONDITIONS_PER_TASK))
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
    let ref_area = match &settings.ranks {
        Some(ranks) => ranks.max(largest.value()).map_err(Error::aborted)?,
        None => largest.value(),
    };
    // 3. Segmentation of every INDEX_MAP entry, with the first two mapper iterations where
    // they can follow it (`streamed`). Robust mode keeps each pair's moments relative to its
    // slave nodes instead, for the direct solve.
    let robust = settings.mode == MortarMode::Robust;
    let tasks = Segmenting {
        seg: SegmentationSettings {
            mode: settings.mode,
            distance_threshold: settings.distance_threshold,
        },
        op: OperatorSettings::mapper(),
        store: if robust {
            OperatorStore::Relative { dim }
        } else {
            OperatorStore::for_sides(&s, &slaves, o, dim, settings.tuning.full_operators)
        },
        weighted_gap,
        stream_batch: settings.tuning.stream_batch.max(1),
        gather_from_threads: settings.tuning.gather_from_threads,
        ranks: settings.ranks.as_ref(),
    };
    let mut report = MappingReport::default();
    let mut standard = Vec::new();
    let m = &*model;
    // A rank's streamed second iteration would read its ghost slave nodes' values before
    // their owners computed them: a distributed run iterates over the kept operators.
    let streamed =
        settings.ranks.is_none() && streams(m, &s, &slaves, tasks.store, &settings.tuning);
    let (segmented, gaps, removed) = if streamed {
        let mut first = stream_first_iterations(
            m,
            &s,
            &tasks,
            (&aux, ref_area, &slaves),
            (&mut report, &mut standard),
        )?;
        let gaps = std::mem::take(&mut first.gaps);
        let removed = std::mem::take(&mut first.removed);
        let segmented = Segmented {
            first: Some(first),
            per_slave: None,
        };
        (segmented, gaps, removed)
    } else {
        let mut per_slave = segment_slaves(m, &s.slave_conditions, &tasks)?;
        let mut gaps = Vec::with_capacity(per_slave.len());
        let mut removed = Vec::with_capacity(per_slave.len());
        for mapped in &mut per_slave {
            report.kept += mapped.kept.len();
            removed.push(std::mem::take(&mut mapped.removed));
            gaps.push(std::mem::take(&mut mapped.gaps));
            standard.append(&mut mapped.standard);
            report.lost_projections += mapped.lost_projections;
        }
        let segmented = Segmented {
            first: None,
            per_slave: Some(kept_only(per_slave)),
        };
        (segmented, gaps, removed)
    };
    report.removed = csm_model::concat_parts_with(&removed, |r| *r);
    drop(removed);
    let known = KnownGaps::from_runs(gaps);
    segment::remove_entries(model.index_maps_mut(), &report.removed);
    let m = &*model;
    match &settings.ranks {
        None => {
            report.standard_basis_pairs = standard.len();
            report.standard_basis_nodes =
                count_slave_nodes(m, &standard, (&slaves, s.slave_nodes.len()));
        }
        Some(ranks) => {
            globalize_counts(m, (&s, &slaves), ranks, (&mut report, standard))
                .map_err(Error::aborted)?;
        }
    }
    // 4. The mapping: Kratos' explicit iterations, or robust mode's direct solve (relative to
    // each slave node: `relative[j]` is the mapped point minus the node, `None` where the
    // node is not mapped).
    let m = &*model;
    let relative = if robust {
        let per_slave = segmented.per_slave.as_deref().unwrap_or_default();
        let (nodal_area, relative) = solve_relative(
            m,
            &slaves,
            (per_slave, dim),
            (s.slave_nodes.len(), ref_area),
        );
        area = nodal_area;
        // Kratos' inverted mapping maps zeros (its origin side holds no coordinates), so no
        // slave node is mapped; robust mode keeps that outcome.
        let relative: Vec<Option<Vector>> = if o { relative } else { vec![None; area.len()] };
        for (n, r) in s.slave_nodes.iter().zip(&relative) {
            if let Some(r) = r {
                aux[n.index()] = coords_of(m, *n) + r;
            }
        }
        report.iterations = usize::from(report.kept > 0);
        report.converged = true;
        Some(relative)
    } else {
        let end = kratos_iterations(
            m,
            (&s, &slaves),
            (&tasks, segmented),
            (&mut aux, &mut area),
            (dim, ref_area, report.kept),
        )?;
        let origin = |n: &csm_model::NodeIdx, a: &Real| {
            a.abs() > AREA_TOLERANCE * ref_area && norm_kratos(&aux[n.index()]) <= EPS
        };
        report.iterations = end.iterations;
        report.converged = end.converged;
        report.last_correction = end.last_correction;
        if o {
            let ids = m.nodes().ids();
            let owned = |n: &csm_model::NodeIdx| {
                (settings.ranks.as_ref()).is_none_or(|r| r.owns_node(ids[n.index()]))
            };
            let origin_nodes = (s.slave_nodes.iter().zip(&area))
                .filter(|(n, a)| owned(n) && origin(n, a))
                .count();
            report.origin_nodes = match &settings.ranks {
                Some(ranks) => ranks
                    .sum_count(origin_nodes as u64)
                    .map_err(Error::aborted)? as usize,
                None => origin_nodes,
            };
        }
        None
    };
    // 5. ComputeNormalGap (master side, then slave side): a node on both sides takes its
    // slave-side value, the last written. Each side's values are written in parallel from
    // their node's own inputs (NORMAL, the flags, the coordinates, AUXILIAR_COORDINATES, none
    // of them written here), so the column is the one ordered pass over both sides writes.
    // Kratos takes a node as mapped when `|AUX| > ε` (Q39: a point mapped onto the origin is
    // not); robust mode knows which are.
    let (nodes, data) = model.nodes_and_nodal_data_mut();
    let (column, normals) =
        data.scalar_mut_and_vector((ScalarVar::NormalGap, VectorVar::Normal), 0);
    if let Some(col) = column {
        let normal = |i: usize| normals.map_or_else(Vector::zeros, |col| col[i]);
        let (nflags, coords) = (nodes.flags(), nodes.coordinates());
        // The new value of node `n`, `None` where it keeps its value.
        let value = |n: &csm_model::NodeIdx| -> Option<Real> {
            let i = n.index();
            if nflags[i].is(Flag::SLAVE) != o {
                Some(0.0)
            } else if let Some(relative) = &relative {
                // (aux − X)·n, without forming aux.
                let r = slaves.get(*n).and_then(|j| relative[j])?;
                Some(r.dot(&normal(i)))
            } else if norm_kratos(&aux[i]) > EPS {
                Some((coords[i].coords - aux[i]).dot(&(-normal(i))))
            } else {
                None
            }
        };
        for side in [&s.master_nodes, &s.slave_nodes] {
            let at = |k: usize| side[k].index();
            write_at_ascending(col, side.len(), at, |k, g| {
                if let Some(v) = value(&side[k]) {
                    *g = v;
                }
            });
        }
    }
    let data = model.nodal_data_mut();
    if let Some(col) = data.scalar_mut(ScalarVar::NodalArea, 0) {
        let at = |j: usize| s.slave_nodes[j].index();
        write_at_ascending(col, s.slave_nodes.len(), at, |j, a| *a = area[j]);
    }
    data.set_vector(VectorVar::AuxiliarCoordinates, aux)
        .map_err(|_| Error::message_only("AUXILIAR_COORDINATES: not one value per node".into()))?;
    Ok((report, known))
}

/// A distributed run's report counts over the whole problem: the kept entries of the owned
/// slave conditions (what the iterations start from), their standard-basis pairs
/// (`standard`: the slave condition of each such pair on this rank) and the distinct slave
/// nodes of these, and the lost projections (counted over the owned conditions already).
fn globalize_counts(
    m: &ModelPart,
    (s, slaves): (&sides::Sides, &SlavePositions),
    ranks: &Ranks,
    (report, standard): (&mut MappingReport, Vec<ConditionIdx>),
) -> Result<(), csm_model::Aborted> {
    let ids = m.conditions().ids();
    let owned = |c: &ConditionIdx| ranks.owns_condition(ids[c.index()]);
    let kept: usize = (s.slave_conditions.iter())
        .filter(|c| owned(c))
        .map(|&c| m.index_map(c).len())
        .sum();
    report.kept = ranks.sum_count(kept as u64)? as usize;
    let standard: Vec<ConditionIdx> = standard.into_iter().filter(owned).collect();
    report.standard_basis_pairs = ranks.sum_count(standard.len() as u64)? as usize;
    let node_ids = m.nodes().ids();
    let nodes: Vec<(u32, [Real; 3])> = standard
        .iter()
        .flat_map(|c| m.conditions().nodes(c.index()))
        .filter(|&&n| slaves.get(n).is_some())
        .map(|n| (node_ids[n.index()], [0.0; 3]))
        .collect();
    report.standard_basis_nodes = ranks.terms(&nodes)?.len();
    report.lost_projections = ranks.sum_count(report.lost_projections as u64)? as usize;
    Ok(())
}

/// The number of distinct slave nodes (`slaves`, `n_slaves` of them) of the conditions
/// `listed`.
fn count_slave_nodes(
    m: &ModelPart,
    listed: &[ConditionIdx],
    (slaves, n_slaves): (&SlavePositions, usize),
) -> usize {
    let mut seen = vec![false; if listed.is_empty() { 0 } else { n_slaves }];
    let mut count = 0;
    for &n in listed.iter().flat_map(|c| m.conditions().nodes(c.index())) {
        if let Some(j) = slaves.get(n)
            && !std::mem::replace(&mut seen[j], true)
        {
            count += 1;
        }
    }
    count
}

/// The coordinates of node `n` as a vector.
fn coords_of(m: &ModelPart, n: csm_model::NodeIdx) -> Vector {
    m.nodes().coordinates()[n.index()].coords
}

#[cfg(test)]
mod tests;
