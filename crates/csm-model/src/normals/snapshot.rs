//! The unit normals a step wrote, kept to be written back after the mapping.

use csm_geometry::math::Vector;
use rayon::prelude::*;

use super::conditions_of;
use crate::{ModelPart, PartIdx, VectorVar};

/// The nodal `NORMAL`s that [`compute_unit_normals`](super::compute_unit_normals) wrote on a part, kept to be written again
/// when the normals were overwritten since (the mortar mapping's mean normals) but the
/// coordinates did not move: a second [`compute_unit_normals`](super::compute_unit_normals) would write the same values.
///
/// Only the nodal values are kept: the condition normals that the mean normals write are the
/// same unit normals at the centres ([`face_unit_normals`](super::face_unit_normals)) that [`compute_unit_normals`](super::compute_unit_normals)
/// writes. Which nodes are written again is decided by the part's conditions when the
/// snapshot is restored (the nodes [`compute_unit_normals`](super::compute_unit_normals) resets).
#[derive(Debug, Clone)]
pub struct UnitNormalsSnapshot {
    part: Option<PartIdx>,
    nodal: Vec<Vector>,
}

impl UnitNormalsSnapshot {
    /// The current nodal `NORMAL` of every node, to be restored on the nodes of the
    /// conditions of `part` (all conditions when `None`); `None` when the model has no
    /// `NORMAL`.
    pub fn take(model: &ModelPart, part: Option<PartIdx>) -> Option<UnitNormalsSnapshot> {
        // Copied in parallel: fresh memory's first touch spread over the threads.
        let nodal = (model.nodal_data().vector(VectorVar::Normal, 0)?.par_iter())
            .copied()
            .collect();
        Some(UnitNormalsSnapshot { part, nodal })
    }

    /// The kept `NORMAL`, by node index (every node of the model).
    pub fn nodal(&self) -> &[Vector] {
        &self.nodal
    }

    /// Puts the kept `NORMAL` back as the whole column (every node; no pass over the part):
    /// the same as [`UnitNormalsSnapshot::restore`] where, since the snapshot, `NORMAL` changed
    /// only on nodes of the part's conditions (e.g. the mapping's mean normals, which it
    /// writes on the nodes of the part's conditions only). Nothing happens if the model lost
    /// its `NORMAL`; where its nodes changed in number, this is [`UnitNormalsSnapshot::restore`].
    pub fn restore_all(self, model: &mut ModelPart) {
        let data = model.nodal_data_mut();
        let Some(replaced) = data.take_vector(VectorVar::Normal, 0) else {
            return;
        };
        if replaced.len() != self.nodal.len() {
            data.put_vector(VectorVar::Normal, 0, replaced);
            return self.restore(model);
        }
        // The kept list becomes the column (no copy of every node's value); the replaced
        // one is freed beside the work that follows (giving a large list back to the
        // system takes one thread a while).
        data.put_vector(VectorVar::Normal, 0, self.nodal);
        rayon::spawn(move || drop(replaced));
    }

    /// Writes the kept `NORMAL` of the nodes of the part's conditions back.
    pub fn restore(self, model: &mut ModelPart) {
        let mut written = vec![false; model.nodes().len()];
        for c in conditions_of(model, self.part) {
            for n in model.conditions().nodes(c.index()) {
                written[n.index()] = true;
            }
        }
        if let Some(column) = model.nodal_data_mut().vector_mut(VectorVar::Normal, 0) {
            for ((value, kept), w) in column.iter_mut().zip(&self.nodal).zip(&written) {
                if *w {
                    *value = *kept;
                }
            }
        }
    }
}
