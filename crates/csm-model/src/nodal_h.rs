//! NODAL_H: the characteristic mesh size at every node (Kratos `FindNodalHProcess`).
//!
//! Every node starts at `f64::MAX`; each element of the part lowers the values of its nodes
//! with the distances between its nodes. Conditions are ignored; nodes in no element keep
//! `f64::MAX` (reference Q33: that value then propagates into means and maxima).

use csm_geometry::math::Real;

use crate::{ModelPart, NodeIdx, PartIdx, ScalarVar};

/// How NODAL_H is computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum NodalHMode {
    /// Kratos 10.4.4 literally (reference §17.3, Q40): for node `k` of an element, its value
    /// is read once before the loop over the later nodes `l > k` and overwritten by
    /// `min(h_k_before, d_kl)` at each `l`, so within one element only the pair `(k, n−1)`
    /// counts for `k`; node `l` keeps a correct running minimum.
    #[default]
    Kratos,
    /// The true minimum edge (node-to-node) distance over every element containing the node.
    MinimumDistance,
}

/// Computes NODAL_H for every node of `model` from the elements of `part` (the whole model
/// when `None`), by node index. Nodes in no element get `f64::MAX`.
pub fn compute_nodal_h(model: &ModelPart, part: Option<PartIdx>, mode: NodalHMode) -> Vec<Real> {
    let coords = model.nodes().coordinates();
    let mut h = vec![Real::MAX; coords.len()];
    let elements = model.elements();
    let mut visit = |nodes: &[NodeIdx]| {
        let n = nodes.len();
        for k in 0..n.saturating_sub(1) {
            let ik = nodes[k].index();
            let h_before = h[ik];
            for &nl in &nodes[k + 1..] {
                let il = nl.index();
                let d = (coords[il] - coords[ik]).norm();
                h[ik] = match mode {
                    NodalHMode::Kratos => h_before.min(d),
                    NodalHMode::MinimumDistance => h[ik].min(d),
                };
                h[il] = h[il].min(d);
            }
        }
    };
    match part {
        None => (0..elements.len()).for_each(|e| visit(elements.nodes(e))),
        Some(p) => model
            .part(p)
            .elements()
            .iter()
            .for_each(|e| visit(elements.nodes(e.index()))),
    }
    h
}

/// Computes NODAL_H (see [`compute_nodal_h`]) and stores it in the historical variable
/// `NODAL_H` (current step), adding the variable if needed.
pub fn assign_nodal_h(model: &mut ModelPart, part: Option<PartIdx>, mode: NodalHMode) {
    let h = compute_nodal_h(model, part, mode);
    let data = model.nodal_data_mut();
    data.add_scalar(ScalarVar::NodalH);
    if let Some(col) = data.scalar_mut(ScalarVar::NodalH, 0) {
        col.copy_from_slice(&h);
    }
}

#[cfg(test)]
mod tests;
