//! NODAL_H: the characteristic mesh size at every node (Kratos `FindNodalHProcess`).
//!
//! Every node starts at `f64::MAX`; each element of the part lowers the values of its nodes
//! with the distances between its nodes. Conditions are ignored; nodes in no element keep
//! `f64::MAX` (reference Q33: that value then propagates into means and maxima).
//!
//! Kratos 10.4.4 (the pip build) keeps a true running minimum over every pair of nodes of
//! every element: `tests/fixtures/nodal_h` (made by `cargo xtask fixtures`) shows it bit for
//! bit on Kratos' own meshes. The reference's Q40 describes a stale read that keeps only the
//! last pair per node; that reading of the sources does not match 10.4.4 (precedence: the pip
//! build), and is kept as [`NodalHMode::StaleRead`] for the revisions that have it.

use csm_geometry::math::Real;
use rayon::prelude::*;

use crate::{ModelPart, NodeIdx, PartIdx, ScalarVar};

/// How NODAL_H is computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum NodalHMode {
    /// What Kratos 10.4.4 computes: the minimum distance from the node to any other node of
    /// any element containing it (all node pairs of the element, diagonals included), each
    /// distance `|X_l − X_k|` evaluated as `sqrt(dx·dx + dy·dy + dz·dz)`.
    #[default]
    Kratos,
    /// The reference's reading of the current Kratos sources (§17.3, Q40): node `k`'s value is
    /// read once before the loop over `l > k` and overwritten by `min(h_k_before, d_kl)`, so
    /// within one element only the pair `(k, n−1)` counts for `k`. Not what 10.4.4 does.
    StaleRead,
    /// The minimum length of the element edges containing the node (corner to corner along
    /// the geometry's edges; diagonals and interior pairs ignored) — the quantity NODAL_H is
    /// meant to be.
    MinimumEdge,
}

/// Computes NODAL_H for every node of `model` from the elements of `part` (the whole model
/// when `None`), by node index. Nodes in no element get `f64::MAX`.
pub fn compute_nodal_h(model: &ModelPart, part: Option<PartIdx>, mode: NodalHMode) -> Vec<Real> {
    compute_nodal_h_with(model, part, mode, PARALLEL_MIN_ELEMENTS)
}

/// Elements below which [`compute_nodal_h`] runs serially.
const PARALLEL_MIN_ELEMENTS: usize = 1 << 14;
/// The most per-worker arrays of the parallel minima (each holds every node's value).
const MAX_PARTIAL_ARRAYS: usize = 4;
/// Elements per chunk the workers of the parallel minima take in turn.
const ELEMENTS_PER_CHUNK: usize = 4096;

/// [`compute_nodal_h`]; the minima of [`NodalHMode::Kratos`] and [`NodalHMode::MinimumEdge`]
/// are taken over element chunks in parallel from `parallel_min` elements on (one array per
/// worker, at most [`MAX_PARTIAL_ARRAYS`], each taking chunks of [`ELEMENTS_PER_CHUNK`] in
/// turn; then the element-wise minimum: a minimum of the same distances in any grouping is
/// the same value), [`NodalHMode::StaleRead`] in
/// element order.
fn compute_nodal_h_with(
    model: &ModelPart,
    part: Option<PartIdx>,
    mode: NodalHMode,
    parallel_min: usize,
) -> Vec<Real> {
    let n_nodes = model.nodes().len();
    let order: Vec<usize> = match part {
        None => (0..model.elements().len()).collect(),
        Some(p) => model.part(p).elements().iter().map(|e| e.index()).collect(),
    };
    let workers = rayon::current_num_threads();
    if mode == NodalHMode::StaleRead || workers < 2 || order.len() < parallel_min.max(1) {
        let mut h = vec![Real::MAX; n_nodes];
        for &e in &order {
            lower_nodal_h(model, e, mode, &mut h);
        }
        return h;
    }
    // At most `MAX_PARTIAL_ARRAYS` arrays of `n_nodes` values at once, whatever the pool;
    // each array's task takes chunks of elements from a shared counter until none is left, so
    // a thread slowed down (or busy elsewhere) takes fewer chunks instead of holding the
    // others up.
    let arrays = workers.min(MAX_PARTIAL_ARRAYS);
    let chunks: Vec<&[usize]> = order.chunks(ELEMENTS_PER_CHUNK).collect();
    let next = std::sync::atomic::AtomicUsize::new(0);
    let mut partial: Vec<Vec<Real>> = (0..arrays)
        .into_par_iter()
        .map(|_| {
            let mut h: Option<Vec<Real>> = None;
            loop {
                let k = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let Some(elements) = chunks.get(k) else {
                    break;
                };
                let h = h.get_or_insert_with(|| vec![Real::MAX; n_nodes]);
                for &e in *elements {
                    lower_nodal_h(model, e, mode, h);
                }
            }
            h
        })
        .flatten()
        .collect();
    let mut h = partial.swap_remove(0);
    for other in &partial {
        h.par_iter_mut()
            .zip(other.par_iter())
            .for_each(|(a, b)| *a = a.min(*b));
    }
    h
}

/// Lowers the NODAL_H of the nodes of element `e` with the distances between them.
fn lower_nodal_h(model: &ModelPart, e: usize, mode: NodalHMode, h: &mut [Real]) {
    let coords = model.nodes().coordinates();
    let elements = model.elements();
    let distance = |a: NodeIdx, b: NodeIdx| {
        let d = coords[b.index()] - coords[a.index()];
        (d.x * d.x + d.y * d.y + d.z * d.z).sqrt()
    };
    let nodes = elements.nodes(e);
    match mode {
        NodalHMode::Kratos | NodalHMode::StaleRead => {
            for k in 0..nodes.len().saturating_sub(1) {
                let ik = nodes[k].index();
                let h_before = h[ik];
                for &nl in &nodes[k + 1..] {
                    let d = distance(nodes[k], nl);
                    let current = if mode == NodalHMode::Kratos {
                        h[ik]
                    } else {
                        h_before
                    };
                    h[ik] = current.min(d);
                    h[nl.index()] = h[nl.index()].min(d);
                }
            }
        }
        NodalHMode::MinimumEdge => {
            for [a, b] in elements.kind(e).edges() {
                let (na, nb) = (nodes[*a], nodes[*b]);
                let d = distance(na, nb);
                h[na.index()] = h[na.index()].min(d);
                h[nb.index()] = h[nb.index()].min(d);
            }
        }
    }
}

/// Computes NODAL_H (see [`compute_nodal_h`]) and stores it in the historical variable
/// `NODAL_H` (current step), adding the variable if needed.
pub fn assign_nodal_h(model: &mut ModelPart, part: Option<PartIdx>, mode: NodalHMode) {
    let h = compute_nodal_h(model, part, mode);
    // (One value per node: the list comes back only where it has not.)
    let _ = model.nodal_data_mut().set_scalar(ScalarVar::NodalH, h);
}

#[cfg(test)]
mod tests;
