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

use csm_geometry::math::{EPS, Point, Vector};
use csm_geometry::{FaceUnitNormals, Geometry, GeometryKind};
use rayon::prelude::*;

use crate::error::{EntityKind, Error, ErrorKind};
use crate::{ConditionIdx, Flag, ModelPart, PartIdx, VectorVar};

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
fn conditions_of(model: &ModelPart, part: Option<PartIdx>) -> Vec<ConditionIdx> {
    match part {
        Some(p) => model.part(p).conditions().to_vec(),
        None => (0..model.conditions().len() as u32)
            .map(ConditionIdx)
            .collect(),
    }
}

fn geometry_error(c: ConditionIdx, model: &ModelPart, source: csm_geometry::Error) -> Error {
    ErrorKind::Geometry {
        entity: EntityKind::Condition,
        id: model.conditions().ids()[c.index()],
        source,
    }
    .into()
}

/// The unit normals at the centre and at the nodes ([`Geometry::face_unit_normals`]) of every
/// face condition of `conditions` (other kinds are skipped), in the order given, computed in
/// parallel. Errors: the first condition (in the order given) whose normals cannot be
/// computed.
pub fn face_unit_normals(
    model: &ModelPart,
    conditions: &[ConditionIdx],
) -> Result<Vec<(ConditionIdx, FaceUnitNormals)>, Error> {
    let per_face: Vec<Option<Result<FaceUnitNormals, csm_geometry::Error>>> = conditions
        .par_iter()
        .map_init(Vec::<Point>::new, |points, &c| {
            let kind: GeometryKind = model.conditions().kind(c.index());
            if !kind.is_face() {
                return None;
            }
            model.gather_points(model.conditions().nodes(c.index()), points);
            Some(Geometry::new(kind, points).and_then(|g| g.face_unit_normals()))
        })
        .collect();
    conditions
        .iter()
        .zip(per_face)
        .filter_map(|(&c, r)| r.map(|r| r.map(|n| (c, n)).map_err(|e| geometry_error(c, model, e))))
        .collect()
}

/// Computes the unit normals of the conditions of `part` (all conditions when `None`) and
/// of their nodes: condition normals go to [`ModelPart::condition_normals`], nodal normals to
/// the historical variable `NORMAL` (current step), which is added if needed.
pub fn compute_unit_normals(
    model: &mut ModelPart,
    part: Option<PartIdx>,
    mode: NormalsMode,
) -> Result<(), Error> {
    let conditions = conditions_of(model, part);
    model.nodal_data_mut().add_vector(VectorVar::Normal);
    let n_nodes = model.nodes().len();
    let mut nodal = vec![Vector::zeros(); n_nodes];
    let mut touched = vec![false; n_nodes];
    // The per-face normals in parallel; the sums below in condition order, as Kratos' serial
    // loop adds them (identical results for any thread count).
    let faces = face_unit_normals(model, &conditions)?;
    let mut cond_normals = Vec::with_capacity(faces.len());
    for (c, normals) in faces {
        cond_normals.push((c, normals.centre));
        let nodes = model.conditions().nodes(c.index());
        for (node, n) in nodes.iter().zip(normals.nodes()) {
            nodal[node.index()] += n;
            touched[node.index()] = true;
        }
    }
    // Normalise.
    let mut normalise = |i: usize| -> Result<(), usize> {
        let norm = nodal[i].norm();
        if norm <= EPS {
            return Err(i);
        }
        nodal[i] /= norm;
        Ok(())
    };
    let result = match mode {
        NormalsMode::Kratos => cond_normals.iter().try_for_each(|(c, _)| {
            model
                .conditions()
                .nodes(c.index())
                .iter()
                .try_for_each(|n| normalise(n.index()))
        }),
        NormalsMode::Once => (0..n_nodes)
            .filter(|&i| touched[i])
            .try_for_each(&mut normalise),
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
    for (c, n) in cond_normals {
        model.condition_normals_mut()[c.index()] = n;
    }
    // Step 1 resets NORMAL on every node of the part's conditions; the face nodes then get
    // their normalised sums.
    let mut reset = vec![false; n_nodes];
    for &c in &conditions {
        for n in model.conditions().nodes(c.index()) {
            reset[n.index()] = true;
        }
    }
    if let Some(column) = model.nodal_data_mut().vector_mut(VectorVar::Normal, 0) {
        for i in (0..n_nodes).filter(|&i| reset[i]) {
            column[i] = if touched[i] {
                nodal[i]
            } else {
                Vector::zeros()
            };
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests;
