//! The nodal mean normals of the mapping (`ComputeNodesMeanNormalModelPart`).

use csm_geometry::math::{EPS, norm_kratos};
use csm_model::{ConditionIdx, KeptPositions, ModelPart, VectorVar};
use rayon::prelude::*;

use super::sides::Sides;
use crate::error::Error;

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
        col.par_iter_mut()
            .zip(&count)
            .filter(|&(_, &k)| k > 0)
            .for_each(|(v, _)| {
                let norm = norm_kratos(v);
                if norm > EPS {
                    *v /= norm;
                }
            });
    }
    Ok(())
}

/// By node index, the nodes whose NORMAL the mapping reads: those of the slave conditions
/// with an INDEX_MAP entry (their Gauss points' normals; ComputeNormalGap reads only nodes
/// that a kept pair maps to) and of the master conditions these entries name (their face
/// data carries nodal normals too, which no 3D computation reads today: cheap insurance).
pub(crate) fn normals_read(model: &ModelPart, s: &Sides) -> Vec<bool> {
    use std::sync::atomic::{AtomicBool, Ordering::Relaxed};
    // Marked in parallel: every mark is `true`, so the order of the writes does not matter.
    let read: Vec<AtomicBool> = (0..model.nodes().len())
        .into_par_iter()
        .map(|_| AtomicBool::new(false))
        .collect();
    let conditions = model.conditions();
    let mark = |c: usize| {
        for n in conditions.nodes(c) {
            read[n.index()].store(true, Relaxed);
        }
    };
    s.slave_conditions.par_iter().for_each(|&sc| {
        let map = model.index_map(sc);
        if map.is_empty() {
            return;
        }
        mark(sc.index());
        for (master, _) in map.iter() {
            if let Some(mc) = conditions.index_of(master.get()) {
                mark(mc);
            }
        }
    });
    read.into_par_iter().map(AtomicBool::into_inner).collect()
}
