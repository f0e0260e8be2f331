//! The streamed first two mapper iterations with their nodal sums gathered by slave node in
//! parallel ([`gather_first_iterations`]), for many threads.
//!
//! [`stream_first_iterations`](super::stream::stream_first_iterations) adds each pair's
//! residual to its slave nodes in one serial pass over the pairs: the order of the additions
//! (pair order) makes the sums bit for bit Kratos' serial ones. Here each slave node's sum is
//! computed whole by one task, which walks the node's own slave conditions in order, their
//! kept pairs in order, and adds the node's row of each pair's residual: the same additions
//! in the same order, so the same bits, with no serial pass over the pairs. A node's first
//! iteration is gathered in the batch that segments its last slave condition; its second in
//! the batch after which every node of its slave conditions has its first (its values after
//! the first iteration are then known). A batch's operators are dropped once every node of its
//! slave conditions has both.
//!
//! The walk reads each pair's operators once per slave node rather than once, and a node's
//! condition list is built first (integer passes): on few threads the serial pass costs less
//! ([`super::MappingTuning::gather_from_threads`]).
//!
//! A batch's gathers run beside the next batch's segmentation (as the serial pass's sums
//! do): the next batch's operators are alive beside the batches the gathers read.

use csm_geometry::MAX_FACE_NODES;
use csm_geometry::MortarOperators;
use csm_geometry::math::{Real, Vector};
use csm_model::{ConditionIdx, ModelPart, NodeIdx};
use rayon::prelude::*;

use super::segment::{OperatorStore, SLAVES_PER_TASK, Segmenting, SlaveMapping, segment_slaves};
use super::sides::{Sides, SlavePositions};
use super::stream::{FirstIterations, after_first, streamed_dim};
use super::{AREA_TOLERANCE, MappingReport};
use crate::error::Error;

/// Slave nodes per parallel task of a gather.
const NODES_PER_TASK: usize = 256;

/// By slave node (position): the positions of the slave conditions it belongs to, ascending.
struct NodeConditions {
    start: Vec<usize>,
    conditions: Vec<u32>,
}

impl NodeConditions {
    fn new(m: &ModelPart, s: &Sides, position: &impl Fn(NodeIdx) -> usize) -> NodeConditions {
        let n = s.slave_nodes.len();
        let mut start = vec![0usize; n + 1];
        for sc in &s.slave_conditions {
            for &node in m.conditions().nodes(sc.index()) {
                start[position(node) + 1] += 1;
            }
        }
        for j in 0..n {
            start[j + 1] += start[j];
        }
        let mut fill = start.clone();
        let mut conditions = vec![0u32; start[n]];
        for (p, sc) in s.slave_conditions.iter().enumerate() {
            let p = u32::try_from(p).expect("slave condition positions fit u32");
            for &node in m.conditions().nodes(sc.index()) {
                let j = position(node);
                conditions[fill[j]] = p;
                fill[j] += 1;
            }
        }
        NodeConditions { start, conditions }
    }

    fn of(&self, j: usize) -> &[u32] {
        &self.conditions[self.start[j]..self.start[j + 1]]
    }
}

/// The kept pairs of one slave condition in its batch: `kept[start..end]` of mapping
/// `mapping`, whose operators start at `offset`.
#[derive(Debug, Clone, Copy, Default)]
struct ConditionPairs {
    mapping: usize,
    start: usize,
    end: usize,
    offset: usize,
}

/// A segmented batch: its mappings' kept parts (the `k`-th holds its slave conditions
/// `k · SLAVES_PER_TASK…`, as [`segment_slaves`] cuts them) and, by slave condition, where
/// its pairs are.
struct Batch {
    first: usize,
    mappings: Vec<SlaveMapping>,
    pairs: Vec<ConditionPairs>,
}

impl Batch {
    fn new(
        m: &ModelPart,
        (first, conditions): (usize, &[ConditionIdx]),
        mappings: Vec<SlaveMapping>,
        store: OperatorStore,
    ) -> Batch {
        let per_mapping: Vec<Vec<ConditionPairs>> = mappings
            .par_iter()
            .zip(conditions.par_chunks(SLAVES_PER_TASK))
            .enumerate()
            .map(|(k, (mapped, chunk))| {
                let (mut p, mut offset) = (0, 0);
                chunk
                    .iter()
                    .map(|&sc| {
                        let start = p;
                        while p < mapped.kept.len() && mapped.kept[p].0 == sc {
                            p += 1;
                        }
                        let ns = m.conditions().nodes(sc.index()).len();
                        let pairs = ConditionPairs {
                            mapping: k,
                            start,
                            end: p,
                            offset,
                        };
                        // The master values' products: every pair of a slave condition packs
                        // the same length, whatever its master.
                        offset += (p - start) * store.packed_len(ns, 0);
                        pairs
                    })
                    .collect()
            })
            .collect();
        Batch {
            first,
            mappings,
            pairs: per_mapping.into_iter().flatten().collect(),
        }
    }
}

/// [`stream_first_iterations`](super::stream::stream_first_iterations), its sums gathered by
/// slave node in parallel (module docs): the same results, bit for bit. Only for the master
/// values' products ([`OperatorStore::MasterProducts`]) and slave conditions whose nodes are
/// all slave nodes, as the stream.
pub(super) fn gather_first_iterations(
    m: &ModelPart,
    s: &Sides,
    tasks: &Segmenting<'_>,
    (aux, ref_area, slaves): (&[Vector], Real, &SlavePositions),
    (report, standard): (&mut MappingReport, &mut Vec<ConditionIdx>),
) -> Result<FirstIterations, Error> {
    let n_slaves = s.slave_nodes.len();
    let dim = streamed_dim(tasks.store);
    let batch = tasks.stream_batch;
    let n_batches = s.slave_conditions.len().div_ceil(batch);
    let position = |n: NodeIdx| slaves.get(n).expect("streams: a slave node");
    let node_conditions = NodeConditions::new(m, s, &position);
    // By slave node: the batch of its first iteration (that of its last slave condition;
    // none without one: its sums stay zero, as the serial pass leaves them).
    let first_at: Vec<Option<usize>> = (0..n_slaves)
        .into_par_iter()
        .map(|j| node_conditions.of(j).last().map(|&c| c as usize / batch))
        .collect();
    // By slave condition: the batch after which every node of it has its first iteration.
    let condition_done: Vec<usize> = s
        .slave_conditions
        .par_iter()
        .map(|sc| {
            m.conditions()
                .nodes(sc.index())
                .iter()
                .filter_map(|&n| first_at[position(n)])
                .max()
                .unwrap_or(0)
        })
        .collect();
    // By slave node: the batch of its second iteration.
    let second_at: Vec<Option<usize>> = (0..n_slaves)
        .into_par_iter()
        .map(|j| {
            let of = node_conditions.of(j);
            of.iter().map(|&c| condition_done[c as usize]).max()
        })
        .collect();
    // By batch: the last batch whose second iterations read its operators.
    let keep_until: Vec<usize> = s
        .slave_conditions
        .par_chunks(batch)
        .map(|chunk| {
            chunk
                .iter()
                .flat_map(|sc| m.conditions().nodes(sc.index()))
                .filter_map(|&n| second_at[position(n)])
                .max()
                .unwrap_or(0)
        })
        .collect();
    let mut firsts = vec![Vec::new(); n_batches];
    let mut seconds = vec![Vec::new(); n_batches];
    for j in 0..n_slaves {
        if let (Some(a), Some(b)) = (first_at[j], second_at[j]) {
            firsts[a].push(j);
            seconds[b].push(j);
        }
    }
    let mut first = FirstIterations::zeros(n_slaves);
    let tolerance = AREA_TOLERANCE * ref_area;
    let mut batches: Vec<Option<Batch>> = (0..n_batches).map(|_| None).collect();
    // Pipelined: a batch's gathers run beside the next batch's segmentation, so that neither
    // waits for the other's last tasks (nor for the serial writes of the sums). The gathers
    // of batch `b` read only the batches up to `b`; the batches are still taken in order, so
    // the reports and the first error are the loop's.
    let conditions_of: Vec<&[ConditionIdx]> = s.slave_conditions.chunks(batch).collect();
    let mut segmented = match conditions_of.first() {
        Some(conditions) => Some(segment_slaves(m, conditions, tasks)?),
        None => None,
    };
    for (b, &conditions) in conditions_of.iter().enumerate() {
        let mut mapped = segmented
            .take()
            .expect("a batch is segmented before its turn");
        for mapped in &mut mapped {
            first.take_reports(mapped, (&mut *report, &mut *standard));
        }
        let mappings = mapped.into_iter().map(SlaveMapping::kept_part).collect();
        batches[b] = Some(Batch::new(
            m,
            (b * batch, conditions),
            mappings,
            tasks.store,
        ));
        let gather = Gather {
            m,
            batches: &batches,
            batch,
            node_conditions: &node_conditions,
            slaves,
            store: tasks.store,
            dim,
        };
        let first = &mut first;
        let gathers = || {
            // The first iteration of the nodes whose last slave condition is in this batch.
            let sums: Vec<(Vector, Real)> = firsts[b]
                .par_iter()
                .with_min_len(NODES_PER_TASK)
                .map(|&j| gather.node(j, |n, k| aux[n.index()][k], true))
                .collect();
            for (&j, (v, a)) in firsts[b].iter().zip(sums) {
                first.vaux[0][j] = v;
                first.area[j] = a;
            }
            // The second of the nodes whose slave conditions' nodes all have their first.
            let (vaux0, area) = (&first.vaux[0], &first.area);
            let first_value = |n: NodeIdx, k: usize| {
                after_first(aux, (vaux0, area, tolerance), (n, position(n)), k)
            };
            let sums: Vec<(Vector, Real)> = seconds[b]
                .par_iter()
                .with_min_len(NODES_PER_TASK)
                .map(|&j| gather.node(j, first_value, false))
                .collect();
            for (&j, (v, _)) in seconds[b].iter().zip(sums) {
                first.vaux[1][j] = v;
            }
        };
        let next = conditions_of.get(b + 1);
        let (next_segmented, ()) = rayon::join(
            || next.map(|conditions| segment_slaves(m, conditions, tasks)),
            gathers,
        );
        segmented = next_segmented.transpose()?;
        for (kept, until) in batches.iter_mut().zip(&keep_until).take(b + 1) {
            if *until <= b {
                *kept = None;
            }
        }
    }
    debug_assert!(
        batches.iter().all(Option::is_none),
        "every batch is dropped after the last"
    );
    Ok(first)
}

/// One gather's view of the batches kept.
struct Gather<'a> {
    m: &'a ModelPart,
    batches: &'a [Option<Batch>],
    batch: usize,
    node_conditions: &'a NodeConditions,
    slaves: &'a SlavePositions,
    store: OperatorStore,
    dim: usize,
}

impl Gather<'_> {
    /// Slave node `j`'s residual sum over its kept pairs on the slave values
    /// `slave_value(node, component)`, in pair order (with `area`, also `D`'s diagonal).
    // The component `k` picks the slave values and the sum: no iterator of `sum`.
    #[allow(clippy::needless_range_loop)]
    fn node(
        &self,
        j: usize,
        slave_value: impl Fn(NodeIdx, usize) -> Real,
        area: bool,
    ) -> (Vector, Real) {
        let (mut sum, mut nodal_area) = (Vector::zeros(), 0.0);
        let mut previous = None;
        for &c in self.node_conditions.of(j) {
            // A node listed twice by one condition: its rows are all taken below, once.
            if previous == Some(c) {
                continue;
            }
            previous = Some(c);
            let c = c as usize;
            let batch = self.batches[c / self.batch]
                .as_ref()
                .expect("the batch of a node's slave condition is kept");
            let pairs = batch.pairs[c - batch.first];
            let mapped = &batch.mappings[pairs.mapping];
            for (q, p) in (pairs.start..pairs.end).enumerate() {
                let (sc, _) = mapped.kept[p];
                let nodes = self.m.conditions().nodes(sc.index());
                let ns = nodes.len();
                let len = self.store.packed_len(ns, 0);
                let packed = &mapped.operators[pairs.offset + q * len..][..len];
                let mut rows = [false; MAX_FACE_NODES];
                for (row, &n) in rows.iter_mut().zip(nodes) {
                    *row = self.slaves.get(n) == Some(j);
                }
                for k in 0..self.dim {
                    let mut sv = [0.0; MAX_FACE_NODES];
                    for (v, &n) in sv.iter_mut().zip(nodes) {
                        *v = slave_value(n, k);
                    }
                    for i in (0..ns).filter(|&i| rows[i]) {
                        sum[k] += MortarOperators::packed_products_residual_row(
                            packed,
                            (k, self.dim),
                            &sv[..ns],
                            i,
                        );
                    }
                }
                if area {
                    for i in (0..ns).filter(|&i| rows[i]) {
                        nodal_area += packed[i * ns + i];
                    }
                }
            }
        }
        (sum, nodal_area)
    }
}
