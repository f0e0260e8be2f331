//! Unit normals of conditions and nodes (Kratos `NormalCalculationUtils::CalculateUnitNormals`,
//! reference §17.2).
//!
//! 1. The historical nodal `NORMAL` of every node of the part's conditions is reset to zero.
//! 2. Every face condition (lines in 2D, surfaces in 3D) gets the unit normal at the local
//!    coordinates of its centre.
//! 3. Every node of every face condition accumulates the condition's unit normal at that
//!    node's local coordinates (not area weighted).
//! 4. Nodal normals are normalised. Kratos' serial branch normalises a node once per adjacent
//!    condition (Q38: repeated division by a number within a few ulp of 1, which can change
//!    last bits); [`NormalsMode::Kratos`] does the same, [`NormalsMode::Once`] normalises once.
//!
//! A condition of zero area or a node whose summed normal vanishes (opposite faces cancel) is
//! an error here; Kratos produces NaN or raises for INTERFACE nodes.

//!
//! Files: this module computes; `face_normals.rs` holds [`FaceNormals`], the flat table of many
//! faces' normals; `kept.rs` the face-normal cache ([`KeptFaceNormals`]) and when it is valid;
//! `node_sums.rs` the blocked nodal sums; `snapshot.rs` the unit normals kept across the
//! mapping ([`UnitNormalsSnapshot`]).

mod face_normals;
mod kept;
mod node_sums;
mod snapshot;

use csm_geometry::Geometry;
use csm_geometry::math::{EPS, Vector};
use rayon::prelude::*;

pub use face_normals::{FaceNormals, FaceNormalsRef};
pub use kept::{KeptFaceNormals, KeptPositions};
pub use snapshot::UnitNormalsSnapshot;

use crate::error::{EntityKind, Error, ErrorKind};
use crate::{ConditionIdx, Flag, GATHER_BLOCK, GatheredPoints, ModelPart, PartIdx, VectorVar};

/// How nodal normals are normalised.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum NormalsMode {
    /// Once per adjacent condition, in condition order, as Kratos' serial branch (Q38).
    #[default]
    Kratos,
    /// Once per node.
    Once,
}

/// The conditions of `part`, or of the whole model when `None`, in ascending index order.
pub(super) fn conditions_of(model: &ModelPart, part: Option<PartIdx>) -> Vec<ConditionIdx> {
    match part {
        Some(p) => model.part(p).conditions().to_vec(),
        None => (0..model.conditions().len() as u32)
            .into_par_iter()
            .map(ConditionIdx)
            .collect(),
    }
}

pub(super) fn geometry_error(
    c: ConditionIdx,
    model: &ModelPart,
    source: csm_geometry::Error,
) -> Error {
    ErrorKind::Geometry {
        entity: EntityKind::Condition,
        id: model.conditions().ids()[c.index()],
        source,
    }
    .into()
}

/// Faces per parallel task of [`face_unit_normals`].
pub(super) const FACES_PER_TASK: usize = 4096;

/// The unit normals at the centre and at the nodes ([`Geometry::face_unit_normals`]) of every
/// face condition of `conditions` (other kinds are skipped), in the order given, computed in
/// parallel. Errors: the first condition (in the order given) whose normals cannot be
/// computed.
pub fn face_unit_normals(
    model: &ModelPart,
    conditions: &[ConditionIdx],
) -> Result<FaceNormals, Error> {
    let kinds = model.conditions();
    let faces: Vec<ConditionIdx> = conditions
        .par_iter()
        .copied()
        .filter(|c| kinds.kind(c.index()).is_face())
        .collect();
    // Centres and per-face counts of nodal normals written in place; the nodal normals of
    // the (few) non-affine faces per task, joined afterwards.
    let mut centres = crate::zero_vectors(faces.len());
    let mut ends = vec![0u32; faces.len()];
    let chunks: Vec<Result<Vec<Vector>, Error>> = faces
        .par_chunks(FACES_PER_TASK)
        .zip(centres.par_chunks_mut(FACES_PER_TASK))
        .zip(ends.par_chunks_mut(FACES_PER_TASK))
        .map(|((faces, centres), counts)| {
            let mut nodes = Vec::new();
            let mut gathered = GatheredPoints::default();
            for ((faces, centres), counts) in faces
                .chunks(GATHER_BLOCK)
                .zip(centres.chunks_mut(GATHER_BLOCK))
                .zip(counts.chunks_mut(GATHER_BLOCK))
            {
                gathered.gather(model, faces.iter().copied());
                for (k, ((&c, centre), count)) in faces.iter().zip(centres).zip(counts).enumerate()
                {
                    let before = nodes.len();
                    *centre = Geometry::new(kinds.kind(c.index()), gathered.points(k))
                        .and_then(|g| g.face_unit_normals_into(&mut nodes))
                        .map_err(|e| geometry_error(c, model, e))?;
                    *count = (nodes.len() - before) as u32;
                }
            }
            Ok(nodes)
        })
        .collect();
    let chunks = chunks.into_iter().collect::<Result<Vec<_>, _>>()?;
    // Joined in parallel into one zeroed list.
    let mut nodes = crate::zero_vectors(chunks.iter().map(Vec::len).sum());
    crate::copy_parts_into(&mut nodes, &chunks);
    let mut end = 0u32;
    for e in &mut ends {
        end += *e;
        *e = end;
    }
    Ok(FaceNormals {
        conditions: faces,
        centres,
        ends,
        nodes,
        stamp: model.geometry_stamp(),
        normals_stamp: 0,
        nodal_written: None,
    })
}

/// Computes the unit normals of the conditions of `part` (all conditions when `None`) and
/// of their nodes: condition normals go to [`ModelPart::condition_normals`], nodal normals to
/// the historical variable `NORMAL` (current step), which is added if needed. Returns the
/// faces' own normals ([`face_unit_normals`] of the part's conditions), for callers that need
/// them again on the same coordinates ([`FaceNormals::keep`], [`KeptFaceNormals::subset`]).
pub fn compute_unit_normals(
    model: &mut ModelPart,
    part: Option<PartIdx>,
    mode: NormalsMode,
) -> Result<FaceNormals, Error> {
    compute_unit_normals_reusing(model, part, mode, None)
}

/// [`compute_unit_normals`], with the faces' own normals taken from `known` (the kept table of
/// an earlier [`compute_unit_normals`] of these faces or more) where the model's geometry and
/// condition normals have not changed since ([`KeptFaceNormals::current_subset`]): the same
/// results, without computing them again.
pub fn compute_unit_normals_reusing(
    model: &mut ModelPart,
    part: Option<PartIdx>,
    mode: NormalsMode,
    known: Option<&KeptFaceNormals>,
) -> Result<FaceNormals, Error> {
    unit_normals_with(model, part, mode, |model, conditions| {
        known.and_then(|k| k.current_subset(model, conditions))
    })
}

/// [`compute_unit_normals`] with the faces' own normals from `known(model, conditions)` where
/// it has them.
pub(super) fn unit_normals_with(
    model: &mut ModelPart,
    part: Option<PartIdx>,
    mode: NormalsMode,
    known: impl FnOnce(&ModelPart, &[ConditionIdx]) -> Option<FaceNormals>,
) -> Result<FaceNormals, Error> {
    let conditions = conditions_of(model, part);
    model.nodal_data_mut().add_vector(VectorVar::Normal);
    // The per-face normals in parallel; the sums in condition order, as Kratos' serial loop
    // adds them (identical results for any thread count).
    let mut faces = match known(model, &conditions) {
        Some(faces) => faces,
        None => face_unit_normals(model, &conditions)?,
    };
    let sums = faces.nodal_sums(model);
    let nodal = normalised(model, &conditions, mode, sums)?;
    faces.set_condition_normals(model);
    write_nodal_normals(model, &conditions, nodal);
    faces.nodal_written = Some((model.nodal_data().vector_stamp(VectorVar::Normal), mode));
    Ok(faces)
}

/// [`compute_unit_normals`] from the faces' own normals in `known` (the kept table of an
/// earlier [`compute_unit_normals`] of these faces or more), without building their table:
/// where the model's geometry and condition normals have not changed since
/// ([`KeptFaceNormals::current_subset`]) and the table has every face of the part, writes
/// what [`compute_unit_normals`] writes (the condition normals hold the table's centre
/// normals already, so `known` stays current) and returns true; false, with nothing done,
/// otherwise. Where `known` is the table of a [`compute_unit_normals`] over exactly these
/// conditions in this mode and `NORMAL` has not been written since (its
/// [`NodalData::vector_stamp`](crate::NodalData::vector_stamp)), `NORMAL` already holds the
/// result: nothing is computed.
pub fn compute_unit_normals_from_kept(
    model: &mut ModelPart,
    part: Option<PartIdx>,
    mode: NormalsMode,
    known: &KeptFaceNormals,
) -> Result<bool, Error> {
    if !known.is_current(model) || !known.holds_centres(model) {
        return Ok(false);
    }
    let conditions = conditions_of(model, part);
    // The table's own computation over exactly these conditions, in this mode, with `NORMAL`
    // untouched since: it holds what this one would write.
    let written = model.nodal_data().vector_stamp(VectorVar::Normal);
    if known.nodal_written == Some((written, mode)) && conditions == known.conditions {
        return Ok(true);
    }
    let Some(positions) = known.positions_checked(model) else {
        return Ok(false);
    };
    let n_nodes = model.nodes().len();
    let mut sums = (crate::zero_vectors(n_nodes), vec![0u32; n_nodes]);
    if !positions.nodal_sums_into(model, (&conditions, None), (&mut sums.0, &mut sums.1)) {
        return Ok(false);
    }
    model.nodal_data_mut().add_vector(VectorVar::Normal);
    let nodal = normalised(model, &conditions, mode, sums)?;
    write_nodal_normals(model, &conditions, nodal);
    Ok(true)
}

/// The nodal normals from the sums of their faces' normals and the faces' count per node
/// ([`FaceNormals::nodal_sums`]): normalised as Kratos' loop does — node by node in
/// condition order, a node once per adjacent face (Q38; once in [`NormalsMode::Once`]). No
/// other node's value enters, so each node is normalised on its own, in parallel. Only the
/// first normalisation can fail (afterwards the norm is about 1): the node reported is the
/// first failing one in Kratos' order (the face conditions of `conditions`, node by node).
pub(super) fn normalised(
    model: &ModelPart,
    conditions: &[ConditionIdx],
    mode: NormalsMode,
    (mut nodal, count): (Vec<Vector>, Vec<u32>),
) -> Result<(Vec<Vector>, Vec<u32>), Error> {
    let times = |i: usize| match mode {
        NormalsMode::Kratos => count[i],
        NormalsMode::Once => count[i].min(1),
    };
    let failed = nodal
        .par_iter_mut()
        .enumerate()
        .map(|(i, v)| {
            for _ in 0..times(i) {
                let norm = v.norm();
                if norm <= EPS {
                    return true;
                }
                *v /= norm;
            }
            false
        })
        .filter(|&f| f)
        .count()
        > 0;
    let kinds = model.conditions();
    let result = match (failed, mode) {
        (false, _) => Ok(()),
        (true, NormalsMode::Kratos) => conditions
            .iter()
            .filter(|c| kinds.kind(c.index()).is_face())
            .flat_map(|c| kinds.nodes(c.index()))
            .find(|n| nodal[n.index()].norm() <= EPS)
            .map_or(Ok(()), |n| Err(n.index())),
        (true, NormalsMode::Once) => (0..nodal.len())
            .find(|&i| count[i] > 0 && nodal[i].norm() <= EPS)
            .map_or(Ok(()), Err),
    };
    if let Err(i) = result {
        let what = if model.nodes().flags()[i].is(Flag::INTERFACE) {
            "the unit normals of the conditions around this interface node cancel out"
        } else {
            "the unit normals of the conditions around this node cancel out"
        };
        return Err(ErrorKind::Geometry {
            entity: EntityKind::Node,
            id: model.nodes().ids()[i],
            source: csm_geometry::Error::degenerate(what),
        }
        .into());
    }
    Ok((nodal, count))
}

/// Writes the [`normalised`] nodal normals: step 1 resets NORMAL on every node of the
/// conditions; the face nodes then get their normalised sums.
pub(super) fn write_nodal_normals(
    model: &mut ModelPart,
    conditions: &[ConditionIdx],
    (nodal, count): (Vec<Vector>, Vec<u32>),
) {
    use std::sync::atomic::{AtomicBool, Ordering};
    let n_nodes = model.nodes().len();
    // Marked in parallel: every mark is `true`, so the order of the writes does not matter.
    let reset: Vec<AtomicBool> = (0..n_nodes)
        .into_par_iter()
        .map(|_| AtomicBool::new(false))
        .collect();
    conditions.par_iter().for_each(|&c| {
        for n in model.conditions().nodes(c.index()) {
            reset[n.index()].store(true, Ordering::Relaxed);
        }
    });
    if let Some(column) = model.nodal_data_mut().vector_mut(VectorVar::Normal, 0) {
        column
            .par_iter_mut()
            .zip(&reset)
            .enumerate()
            .filter(|(_, (_, r))| r.load(Ordering::Relaxed))
            .for_each(|(i, (v, _))| {
                *v = if count[i] > 0 {
                    nodal[i]
                } else {
                    Vector::zeros()
                };
            });
    }
}

#[cfg(test)]
mod tests;
