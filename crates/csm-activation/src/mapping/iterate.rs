//! The mapper's solution: Kratos' explicit iterations (residuals of the kept pairs, nodal
//! areas, Kratos' convergence tests) and robust mode's direct solve.

use csm_geometry::math::{Real, Vector};
use csm_geometry::{MAX_FACE_NODES, MortarOperators};
use csm_model::{ConditionIdx, ModelPart, NodeIdx};
use rayon::prelude::*;

use super::segment::{
    OperatorStore, Segmenting, SlaveMapping, kept_only, kept_pairs, segment_slaves,
};
use super::sides::{Sides, SlavePositions};
use super::stream::FirstIterations;
use super::{
    AREA_TOLERANCE, MAPPER_ABSOLUTE_TOLERANCE, MAPPER_MAX_ITERATIONS, MAPPER_RELATIVE_TOLERANCE,
};
use crate::error::Error;

/// One mapper iteration's residual of the kept pairs on the values `aux`, by slave node
/// (`slaves`).
pub(super) struct Residual<'a> {
    pub(super) store: OperatorStore,
    pub(super) dim: usize,
    pub(super) aux: &'a [Vector],
    pub(super) slaves: &'a SlavePositions,
}

impl Residual<'_> {
    /// Adds the residual of the pair `(sc, mc)` with the `packed` operators to its slave
    /// nodes in `vaux` (Kratos' `prod(M, V) − prod(D, S)`, component by component; by slave
    /// node: what the nodes of a slave condition that are not slave nodes get is never read).
    pub(super) fn add(
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
    pub(super) fn add_with(
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
                // Robust mode solves directly ([`solve_relative`]) and builds no residual.
                OperatorStore::Relative { .. } => {
                    unreachable!("the relative store is solved directly, never iterated")
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

/// Adds `D`'s diagonal of the pair of slave `sc` (`packed`: its first ns² values are `D`, row
/// by row) to the slave nodes' `area` (by slave node, as [`Residual::add`]).
pub(super) fn add_area(
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

/// How Kratos' explicit iterations ended.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(super) struct IterationsEnd {
    /// Iterations run.
    pub(super) iterations: usize,
    /// Whether Kratos' tests (absolute, relative, stagnation) declared every component
    /// converged (else the iteration limit stopped it).
    pub(super) converged: bool,
    /// The largest correction `|ΔAUX|` of a slave node in the last iteration (a length).
    pub(super) last_correction: Real,
}

/// The segmentation's results the iterations start from: the first two iterations' sums
/// where they were streamed, the kept pairs' operators where they were kept.
pub(super) struct Segmented {
    pub(super) first: Option<FirstIterations>,
    pub(super) per_slave: Option<Vec<SlaveMapping>>,
}

/// Kratos' explicit mapping iterations (`SimpleMortarMapperProcess`): `AUX += VAUX /
/// NODAL_AREA` on the slave nodes whose `|NODAL_AREA| > AREA_TOLERANCE · ref_area`, until
/// every component passes one of Kratos' tests on `sqrt(Σ VAUX²) / n` (absolute 1e-9,
/// relative to the first 1e-4, or a relative change below 1e-4: flags that stay set) or
/// [`MAPPER_MAX_ITERATIONS`]. `area` (by slave node) receives `NODAL_AREA`; `dim`: the mapped
/// components; `kept`: the number of kept pairs (none: converged at once).
pub(super) fn kratos_iterations(
    m: &ModelPart,
    (s, slaves): (&Sides, &SlavePositions),
    (tasks, segmented): (&Segmenting<'_>, Segmented),
    (aux, area): (&mut [Vector], &mut Vec<Real>),
    (dim, ref_area, kept): (usize, Real, usize),
) -> Result<IterationsEnd, Error> {
    let Segmented {
        mut first,
        mut per_slave,
    } = segmented;
    let ranks = tasks.ranks;
    let node_ids = m.nodes().ids();
    // A distributed run: which slave nodes this rank owns (it adds their terms to the sums)
    // and which it holds as ghosts (their values come from their owners).
    let owned: Vec<bool> = (s.slave_nodes.iter())
        .map(|n| ranks.is_none_or(|r| r.owns_node(node_ids[n.index()])))
        .collect();
    let n_slaves = match ranks {
        Some(r) => {
            let here = owned.iter().filter(|o| **o).count() as u64;
            r.sum_count(here).map_err(Error::aborted)? as usize
        }
        None => s.slave_nodes.len(),
    };
    let n_d = n_slaves.max(1) as Real;
    let mut r0: [Real; 3] = [0.0; 3];
    let mut r_prev: [Real; 3] = [0.0; 3];
    let mut end = IterationsEnd {
        converged: kept == 0,
        ..IterationsEnd::default()
    };
    // Kratos' per-component flags are sticky: a component converged once stays converged.
    let mut component_converged = [kept == 0; 3];
    // By slave node (Kratos' VAUX of the other nodes is never read).
    let mut vaux = Vec::new();
    while !end.converged && end.iterations < MAPPER_MAX_ITERATIONS {
        let iteration = end.iterations;
        match first.as_mut().filter(|_| iteration < 2) {
            // The streamed sums replace the previous iteration's.
            Some(first) => {
                std::mem::swap(&mut vaux, &mut first.vaux[iteration]);
                if iteration == 0 {
                    std::mem::swap(area, &mut first.area);
                }
            }
            None => {
                // After the streamed iterations: the operators again (the index maps now hold
                // the kept entries only; the weighted gap is known).
                if per_slave.is_none() {
                    let tasks = Segmenting {
                        weighted_gap: None,
                        ..*tasks
                    };
                    per_slave = Some(kept_only(segment_slaves(m, &s.slave_conditions, &tasks)?));
                }
                let per_slave = per_slave.as_deref().unwrap_or_default();
                vaux = csm_model::zero_vectors(s.slave_nodes.len());
                let residual = Residual {
                    store: tasks.store,
                    dim,
                    aux,
                    slaves,
                };
                for (sc, mc, packed) in kept_pairs(m, per_slave, tasks.store) {
                    residual.add(m, (sc, mc, packed), &mut vaux);
                    if iteration == 0 {
                        add_area(m, sc, packed, (area, slaves));
                    }
                }
            }
        }
        let tolerance = AREA_TOLERANCE * ref_area;
        let (mut sums, mut largest) = ([0.0; 3], 0.0);
        match ranks {
            None => (sums, largest) = update_one_process(s, (&vaux, area), tolerance, dim, aux),
            Some(r) => {
                // This rank's owned terms, added in the whole problem's order.
                let mut terms = Vec::new();
                for (j, n) in s.slave_nodes.iter().enumerate() {
                    let i = n.index();
                    if area[j].abs() > tolerance {
                        let correction = vaux[j] / area[j];
                        for k in 0..dim {
                            aux[i][k] += correction[k];
                        }
                        if owned[j] {
                            largest = largest.max(correction.norm());
                        }
                    }
                    if owned[j] {
                        let mut t = [0.0; 3];
                        for (k, t) in t.iter_mut().enumerate().take(dim) {
                            *t = vaux[j][k] * vaux[j][k];
                        }
                        terms.push((node_ids[i], t));
                    }
                }
                for (_, t) in r.terms(&terms).map_err(Error::aborted)? {
                    for (sum, t) in sums.iter_mut().zip(t).take(dim) {
                        *sum += t;
                    }
                }
                largest = r.max(largest).map_err(Error::aborted)?;
                exchange_ghosts(m, (s, &owned), r, aux)?;
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
        end.converged = component_converged[..dim].iter().all(|c| *c);
        end.last_correction = largest;
        end.iterations += 1;
    }
    Ok(end)
}

/// One iteration's update of a one-process run, in parallel: every slave node with an area
/// above `tolerance` moves by `vaux / area`; returns the sums of the squared residuals by
/// component and the largest correction. The same bits as the ordered pass over the slave
/// nodes: the nodes are independent, a maximum is one in any order, and the sums add the
/// nodes' non-zero terms in slave order (a term +0, all a node without pairs adds, leaves a
/// sum as it is; every sum starts at +0 and adds squares, so it is never −0).
fn update_one_process(
    s: &Sides,
    (vaux, area): (&[Vector], &[Real]),
    tolerance: Real,
    dim: usize,
    aux: &mut [Vector],
) -> ([Real; 3], Real) {
    let n = s.slave_nodes.len();
    let moves = |j: usize| area[j].abs() > tolerance;
    let at = |j: usize| s.slave_nodes[j].index();
    csm_model::write_at_ascending(aux, n, at, |j, a| {
        if moves(j) {
            let correction = vaux[j] / area[j];
            for k in 0..dim {
                a[k] += correction[k];
            }
        }
    });
    let largest = (0..n)
        .into_par_iter()
        .filter(|&j| moves(j))
        .map(|j| (vaux[j] / area[j]).norm())
        .reduce(|| 0.0, Real::max);
    // The squares summed in node order, as Kratos' serial loop adds them (one pass, no list:
    // the squares are never negative, so the zero ones change no sum).
    let mut sums = [0.0; 3];
    for v in &vaux[..n] {
        for (k, sum) in sums.iter_mut().enumerate().take(dim) {
            *sum += v[k] * v[k];
        }
    }
    (sums, largest)
}

/// A distributed run's ghost slave nodes (`owned[j]` false) take the values `aux` their owners
/// computed.
fn exchange_ghosts(
    m: &ModelPart,
    (s, owned): (&Sides, &[bool]),
    ranks: &csm_model::Ranks,
    aux: &mut [Vector],
) -> Result<(), Error> {
    let ids = m.nodes().ids();
    let mut mine = Vec::new();
    let mut ghosts = Vec::new();
    for (n, &o) in s.slave_nodes.iter().zip(owned) {
        if o {
            let v = aux[n.index()];
            mine.push((ids[n.index()], [v[0], v[1], v[2]]));
        } else {
            ghosts.push(*n);
        }
    }
    let wanted: Vec<u32> = ghosts.iter().map(|n| ids[n.index()]).collect();
    let values = ranks.values(&mine, &wanted).map_err(Error::aborted)?;
    for (n, v) in ghosts.iter().zip(values) {
        let v = v.ok_or_else(|| {
            Error::message_only(format!(
                "distributed mapping: no rank owns slave node {}",
                ids[n.index()]
            ))
        })?;
        aux[n.index()] = Vector::new(v[0], v[1], v[2]);
    }
    Ok(())
}

/// Robust mode's mapping, solved directly from the pairs of `per_slave` packed in the
/// [relative store](OperatorStore::Relative) of `dim` components:
/// by slave node, `NODAL_AREA = Σ ∫ Φ_i` over its kept pairs and the mapped point relative to
/// the node, `Σ_pairs Σ_m M_im (X_m − X_i) / NODAL_AREA` (`None` where `|NODAL_AREA| ≤
/// AREA_TOLERANCE · ref_area`: not mapped, as Kratos leaves such a node). With every `D`
/// diagonal (the dual basis, or the lumped standard one) this is the fixed point of Kratos'
/// iterations, reached without them, and nothing in it grows with the distance from the
/// origin. Pairs are summed in pair order (deterministic for any thread count).
pub(super) fn solve_relative(
    m: &ModelPart,
    slaves: &SlavePositions,
    (per_slave, dim): (&[SlaveMapping], usize),
    (n_slaves, ref_area): (usize, Real),
) -> (Vec<Real>, Vec<Option<Vector>>) {
    let store = OperatorStore::Relative { dim };
    let mut area = vec![0.0; n_slaves];
    let mut moment = csm_model::zero_vectors(n_slaves);
    for (sc, _, packed) in kept_pairs(m, per_slave, store) {
        let slave_nodes = m.conditions().nodes(sc.index());
        let ns = slave_nodes.len();
        for (i, &n) in slave_nodes.iter().enumerate() {
            let Some(j) = slaves.get(n) else { continue };
            area[j] += packed[i];
            for k in 0..dim {
                moment[j][k] += packed[ns * (1 + k) + i];
            }
        }
    }
    let tolerance = AREA_TOLERANCE * ref_area;
    let relative = area
        .iter()
        .zip(&moment)
        .map(|(&a, v)| (a.abs() > tolerance).then(|| v / a))
        .collect();
    (area, relative)
}

#[cfg(test)]
mod update_tests {
    use super::*;

    /// The ordered pass over the slave nodes that [`update_one_process`] replaces.
    fn ordered(
        s: &Sides,
        (vaux, area): (&[Vector], &[Real]),
        tolerance: Real,
        dim: usize,
        aux: &mut [Vector],
    ) -> ([Real; 3], Real) {
        let (mut sums, mut largest) = ([0.0; 3], 0.0);
        for (j, n) in s.slave_nodes.iter().enumerate() {
            if area[j].abs() > tolerance {
                let correction = vaux[j] / area[j];
                for k in 0..dim {
                    aux[n.index()][k] += correction[k];
                }
                largest = Real::max(largest, correction.norm());
            }
            for (k, sum) in sums.iter_mut().enumerate().take(dim) {
                *sum += vaux[j][k] * vaux[j][k];
            }
        }
        (sums, largest)
    }

    /// The parallel update gives the ordered pass's bits — sums, largest correction and every
    /// value — on 1 to 4 threads, with most nodes without pairs (zero residual), areas below
    /// the tolerance, negative zeros and a NaN residual, for 2 and 3 components.
    #[test]
    fn parallel_update_is_the_ordered_pass() {
        let n_nodes = 30_000;
        // Every third node is a slave node (ascending, as the sides list them).
        let slave_nodes: Vec<NodeIdx> = (0..n_nodes / 3).map(|j| NodeIdx(3 * j as u32)).collect();
        let s = Sides {
            slave_nodes,
            ..Sides::default()
        };
        let n = s.slave_nodes.len();
        // A fixed pseudo-random sequence (no dependency): values of every magnitude.
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as Real / (1u64 << 53) as Real
        };
        for nan in [false, true] {
            let vaux: Vec<Vector> = (0..n)
                .map(|j| match j % 7 {
                    0 | 3 => Vector::new(next() - 0.5, (next() - 0.5) * 1e-9, next() * 1e6),
                    5 => Vector::new(-0.0, 0.0, -0.0),
                    6 if nan && j == 6 * 301 => Vector::new(Real::NAN, 1.0, 2.0),
                    _ => Vector::zeros(),
                })
                .collect();
            let area: Vec<Real> = (0..n)
                .map(|j| if j % 11 == 0 { 1e-30 } else { next() + 0.1 })
                .collect();
            let aux0: Vec<Vector> = (0..n_nodes)
                .map(|_| Vector::new(next(), next(), next()))
                .collect();
            for dim in [2, 3] {
                let mut expected_aux = aux0.clone();
                let expected = ordered(&s, (&vaux, &area), 1e-20, dim, &mut expected_aux);
                for threads in 1..=4 {
                    let pool = rayon::ThreadPoolBuilder::new()
                        .num_threads(threads)
                        .build()
                        .unwrap();
                    let mut aux = aux0.clone();
                    let got = pool
                        .install(|| update_one_process(&s, (&vaux, &area), 1e-20, dim, &mut aux));
                    let bits = |(sums, largest): ([Real; 3], Real)| {
                        (sums.map(Real::to_bits), largest.to_bits())
                    };
                    assert_eq!(bits(got), bits(expected), "{threads} threads, dim {dim}");
                    let same = aux.iter().zip(&expected_aux).all(|(a, b)| {
                        a.iter()
                            .zip(b.iter())
                            .all(|(x, y)| x.to_bits() == y.to_bits())
                    });
                    assert!(same, "{threads} threads, dim {dim}: the values differ");
                }
            }
        }
    }
}
