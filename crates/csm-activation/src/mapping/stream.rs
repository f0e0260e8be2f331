//! The first two mapper iterations streamed with the segmentation (large interfaces).

use std::collections::VecDeque;

use csm_geometry::math::{Real, Vector};
use csm_model::{ConditionIdx, ModelPart, NodeIdx};

use super::iterate::{Residual, add_area};
use super::segment::{OperatorStore, Segmenting, SlaveMapping, kept_pairs, segment_slaves};
use super::sides::{Sides, SlavePositions};
use super::{AREA_TOLERANCE, MappingReport, RemovedEntry};
use crate::error::Error;
use crate::weighted_gap::KnownGap;

/// Slave conditions per batch of [`stream_first_iterations`].
pub(super) const SLAVES_PER_BATCH: usize = 8192;

/// What [`stream_first_iterations`] leaves for the iterations.
pub(super) struct FirstIterations {
    /// The residuals of the first two iterations (`VAUX`), by slave node.
    pub(super) vaux: [Vec<Vector>; 2],
    /// `NODAL_AREA`: `D`'s diagonal summed over the kept pairs, by slave node.
    pub(super) area: Vec<Real>,
    /// The weighted gap of the kept pairs, in slave order: each task's run.
    pub(super) gaps: Vec<Vec<KnownGap>>,
    /// The removed entries, in slave order: each task's run.
    pub(super) removed: Vec<Vec<RemovedEntry>>,
}

impl FirstIterations {
    /// Zero sums for `n_slaves` slave nodes.
    pub(super) fn zeros(n_slaves: usize) -> FirstIterations {
        FirstIterations {
            vaux: [
                csm_model::zero_vectors(n_slaves),
                csm_model::zero_vectors(n_slaves),
            ],
            area: vec![0.0; n_slaves],
            gaps: Vec::new(),
            removed: Vec::new(),
        }
    }

    /// Moves a batch mapping's reports out, in slave order: its kept count, the slave
    /// conditions of its standard-basis pairs and its lost projections into the run's
    /// (`report`, `standard`), its removed entries and weighted gaps (as runs) into `self`.
    pub(super) fn take_reports(
        &mut self,
        mapped: &mut SlaveMapping,
        (report, standard): (&mut MappingReport, &mut Vec<ConditionIdx>),
    ) {
        report.kept += mapped.kept.len();
        standard.append(&mut mapped.standard);
        report.lost_projections += mapped.lost_projections;
        self.removed.push(std::mem::take(&mut mapped.removed));
        self.gaps.push(std::mem::take(&mut mapped.gaps));
    }
}

/// Component `k` of node `n` (slave node position `j`) after the first iteration, as the
/// iterations compute it: `aux` the values before, `vaux0` and `area` the first iteration's
/// sums by slave node, `tolerance` the area up to which a node keeps its value.
pub(super) fn after_first(
    aux: &[Vector],
    (vaux0, area, tolerance): (&[Vector], &[Real], Real),
    (n, j): (NodeIdx, usize),
    k: usize,
) -> Real {
    let i = n.index();
    if area[j].abs() > tolerance {
        aux[i][k] + vaux0[j][k] / area[j]
    } else {
        aux[i][k]
    }
}

/// The mapped components of a store that streams (the master values' products).
pub(super) fn streamed_dim(store: OperatorStore) -> usize {
    match store {
        OperatorStore::MasterProducts { dim, .. } => dim,
        OperatorStore::Operators | OperatorStore::Relative { .. } => {
            unreachable!("streams only the master values' products")
        }
    }
}

/// INDEX_MAP entries from which the mapping streams its first iterations (below, keeping
/// every pair's operators costs little memory and saves the batches' passes).
pub(super) const STREAM_MIN_ENTRIES: usize = 1 << 16;

/// Whether the first two mapper iterations follow the segmentation
/// ([`stream_first_iterations`]): on enough entries (at least [`STREAM_MIN_ENTRIES`]) where
/// they can — the store keeps the products of the master values (which do not change), and
/// every node of a slave condition is a slave node (only those change, and every residual goes
/// to them).
pub(super) fn streams(
    m: &ModelPart,
    s: &Sides,
    slaves: &SlavePositions,
    store: OperatorStore,
    tuning: &super::MappingTuning,
) -> bool {
    if !matches!(store, OperatorStore::MasterProducts { .. }) {
        return false;
    }
    let least = tuning.stream_min_entries;
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
/// iterations and the reference area. Counts the kept entries in `report`, adds the slave
/// conditions of standard-basis pairs to `standard`, and keeps the tasks' removed entries
/// and weighted gaps in slave order in the result ([`FirstIterations::removed`],
/// [`FirstIterations::gaps`]).
pub(super) fn stream_first_iterations(
    m: &ModelPart,
    s: &Sides,
    tasks: &Segmenting<'_>,
    (aux, ref_area, slaves): (&[Vector], Real, &SlavePositions),
    (report, standard): (&mut MappingReport, &mut Vec<ConditionIdx>),
) -> Result<FirstIterations, Error> {
    if rayon::current_num_threads() >= tasks.gather_from_threads {
        return super::gather::gather_first_iterations(
            m,
            s,
            tasks,
            (aux, ref_area, slaves),
            (report, standard),
        );
    }
    let n_slaves = s.slave_nodes.len();
    let dim = streamed_dim(tasks.store);
    let batch = tasks.stream_batch;
    // By slave node: the number of slave conditions done when its last one is (every node
    // of a slave condition is a slave node).
    let position = |n: NodeIdx| slaves.get(n).expect("streams: a slave node");
    let mut done_with = vec![0; n_slaves];
    for (p, sc) in s.slave_conditions.iter().enumerate() {
        for &n in m.conditions().nodes(sc.index()) {
            done_with[position(n)] = p + 1;
        }
    }
    let mut first = FirstIterations::zeros(n_slaves);
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
    // A batch's sums (one serial pass over its pairs, in pair order): its first iteration,
    // then the second of the pairs whose slave nodes are done. `done`: the slave conditions
    // segmented once this batch is.
    let mut add_batch = |done: usize, segmented: Vec<SlaveMapping>| {
        for mut mapped in segmented {
            first.take_reports(&mut mapped, (&mut *report, &mut *standard));
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
        let first_value =
            |n: NodeIdx, k: usize| after_first(aux, (vaux0, area, tolerance), (n, position(n)), k);
        'pending: while let Some(mapped) = pending.front() {
            let pairs = kept_pairs(m, std::slice::from_ref(mapped), tasks.store).skip(next);
            for (sc, mc, packed) in pairs {
                let nodes = m.conditions().nodes(sc.index());
                if nodes.iter().any(|&n| done_with[position(n)] > done) {
                    break 'pending;
                }
                residual.add_with(m, (sc, mc, packed), vaux1, first_value);
                next += 1;
            }
            pending.pop_front();
            next = 0;
        }
    };
    // Pipelined: a batch's serial sums run beside the next batch's (parallel) segmentation,
    // whose tasks the summing thread joins when it is done. The sums still come batch after
    // batch, each in pair order, so the bits are the serial loop's; the first error is still
    // the first batch's (a batch that fails is never summed, nor is any after it).
    // On one thread, each batch is summed right after its segmentation, while its operators
    // are still in the caches.
    let batches: Vec<&[ConditionIdx]> = s.slave_conditions.chunks(batch).collect();
    if rayon::current_num_threads() == 1 {
        for (b, conditions) in batches.into_iter().enumerate() {
            add_batch(
                b * batch + conditions.len(),
                segment_slaves(m, conditions, tasks)?,
            );
        }
        debug_assert!(
            pending.is_empty(),
            "every node is done after the last batch"
        );
        return Ok(first);
    }
    let mut ready: Option<(usize, Vec<SlaveMapping>)> = None;
    for b in 0..=batches.len() {
        let segment = batches
            .get(b)
            .map(|conditions| (b * batch + conditions.len(), *conditions));
        let (segmented, ()) = rayon::join(
            || segment.map(|(done, conditions)| Ok((done, segment_slaves(m, conditions, tasks)?))),
            || {
                if let Some((done, segmented)) = ready.take() {
                    add_batch(done, segmented);
                }
            },
        );
        ready = segmented.transpose()?;
    }
    debug_assert!(
        pending.is_empty(),
        "every node is done after the last batch"
    );
    Ok(first)
}
