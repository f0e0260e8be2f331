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

/// The unit normals of many faces ([`face_unit_normals`]), stored flat: one centre normal per
/// face and the nodal normals only of faces whose normal varies over the face (affine faces —
/// Line2D2, Triangle3D3 — have one normal; [`FaceNormalsRef::node`] returns it for every node).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FaceNormals {
    conditions: Vec<ConditionIdx>,
    centres: Vec<Vector>,
    /// Per face, the end of its nodal normals in `nodes` (the start is the previous end).
    ends: Vec<u32>,
    nodes: Vec<Vector>,
}

/// One face of a [`FaceNormals`] table.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaceNormalsRef<'a> {
    /// The condition.
    pub condition: ConditionIdx,
    /// The unit normal at the local coordinates of the centre.
    pub centre: Vector,
    nodes: &'a [Vector],
}

impl FaceNormalsRef<'_> {
    /// The unit normal at the local coordinates of the face's node `k` (node order).
    pub fn node(&self, k: usize) -> Vector {
        self.nodes.get(k).copied().unwrap_or(self.centre)
    }
}

impl FaceNormals {
    /// The number of faces.
    pub fn len(&self) -> usize {
        self.conditions.len()
    }

    /// Whether the table has no face.
    pub fn is_empty(&self) -> bool {
        self.conditions.is_empty()
    }

    /// The faces, in the order they were given to [`face_unit_normals`].
    pub fn iter(&self) -> impl Iterator<Item = FaceNormalsRef<'_>> + '_ {
        (0..self.conditions.len()).map(move |i| {
            let start = if i == 0 { 0 } else { self.ends[i - 1] as usize };
            FaceNormalsRef {
                condition: self.conditions[i],
                centre: self.centres[i],
                nodes: &self.nodes[start..self.ends[i] as usize],
            }
        })
    }

    /// Per node of `model`, the sum of the nodal normals of its faces, added in the table's
    /// face order (Kratos' order), and the number of its faces (0: a node of no face).
    ///
    /// The nodes are split into one block of consecutive indices per thread, summed in
    /// parallel: each block scans every face in order and adds only to its own nodes, so every
    /// node's sum is the serial one, bit for bit, for any thread count.
    pub fn nodal_sums(&self, model: &ModelPart) -> (Vec<Vector>, Vec<u32>) {
        let n_nodes = model.nodes().len();
        let mut sums = vec![Vector::zeros(); n_nodes];
        let mut count = vec![0u32; n_nodes];
        let block = n_nodes.div_ceil(rayon::current_num_threads()).max(1);
        let conditions = model.conditions();
        sums.par_chunks_mut(block)
            .zip(count.par_chunks_mut(block))
            .enumerate()
            .for_each(|(b, (sums, count))| {
                let first = b * block;
                let range = first..first + sums.len();
                for face in self.iter() {
                    for (k, node) in conditions.nodes(face.condition.index()).iter().enumerate() {
                        if range.contains(&node.index()) {
                            sums[node.index() - first] += face.node(k);
                            count[node.index() - first] += 1;
                        }
                    }
                }
            });
        (sums, count)
    }

    /// Sets every face's condition normal ([`ModelPart::condition_normals`]) to its centre
    /// normal.
    pub fn set_condition_normals(&self, model: &mut ModelPart) {
        let condition_normals = model.condition_normals_mut();
        for face in self.iter() {
            condition_normals[face.condition.index()] = face.centre;
        }
    }

    fn push(&mut self, c: ConditionIdx, normals: &FaceUnitNormals) {
        self.conditions.push(c);
        self.centres.push(normals.centre);
        if !normals.is_uniform() {
            self.nodes.extend_from_slice(normals.nodes());
        }
        self.ends.push(self.nodes.len() as u32);
    }

    fn append(&mut self, other: FaceNormals) {
        let base = self.nodes.len() as u32;
        self.conditions.extend(other.conditions);
        self.centres.extend(other.centres);
        self.ends.extend(other.ends.into_iter().map(|e| e + base));
        self.nodes.extend(other.nodes);
    }
}

/// Faces per parallel task of [`face_unit_normals`].
const FACES_PER_TASK: usize = 4096;

/// The unit normals at the centre and at the nodes ([`Geometry::face_unit_normals`]) of every
/// face condition of `conditions` (other kinds are skipped), in the order given, computed in
/// parallel. Errors: the first condition (in the order given) whose normals cannot be
/// computed.
pub fn face_unit_normals(
    model: &ModelPart,
    conditions: &[ConditionIdx],
) -> Result<FaceNormals, Error> {
    let chunks: Vec<Result<FaceNormals, Error>> = conditions
        .par_chunks(FACES_PER_TASK)
        .map(|chunk| {
            let mut table = FaceNormals::default();
            let mut points = Vec::<Point>::new();
            for &c in chunk {
                let kind: GeometryKind = model.conditions().kind(c.index());
                if !kind.is_face() {
                    continue;
                }
                model.gather_points(model.conditions().nodes(c.index()), &mut points);
                let normals = Geometry::new(kind, &points)
                    .and_then(|g| g.face_unit_normals())
                    .map_err(|e| geometry_error(c, model, e))?;
                table.push(c, &normals);
            }
            Ok(table)
        })
        .collect();
    let mut table = FaceNormals::default();
    for chunk in chunks {
        table.append(chunk?);
    }
    Ok(table)
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
    // The per-face normals in parallel; the sums in condition order, as Kratos' serial loop
    // adds them (identical results for any thread count). `count`: how many faces a node
    // has — Kratos normalises it that often (Q38).
    let faces = face_unit_normals(model, &conditions)?;
    let (mut nodal, count) = faces.nodal_sums(model);
    // Normalise. Kratos' loop normalises node by node in condition order, a node once per
    // adjacent face; no other node's value enters, so each node is normalised `count` times
    // on its own, in parallel. Only the first normalisation can fail (afterwards the norm is
    // about 1): the node reported is the first failing one in Kratos' order.
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
    let result = match (failed, mode) {
        (false, _) => Ok(()),
        (true, NormalsMode::Kratos) => faces
            .iter()
            .flat_map(|face| model.conditions().nodes(face.condition.index()))
            .find(|n| nodal[n.index()].norm() <= EPS)
            .map_or(Ok(()), |n| Err(n.index())),
        (true, NormalsMode::Once) => (0..n_nodes)
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
    faces.set_condition_normals(model);
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
            column[i] = if count[i] > 0 {
                nodal[i]
            } else {
                Vector::zeros()
            };
        }
    }
    Ok(())
}

/// The nodal `NORMAL`s that [`compute_unit_normals`] wrote on a part, kept to be written again
/// when the normals were overwritten since (the mortar mapping's mean normals) but the
/// coordinates did not move: a second [`compute_unit_normals`] would write the same values.
///
/// Only the nodal values are kept: the condition normals that the mean normals write are the
/// same unit normals at the centres ([`face_unit_normals`]) that [`compute_unit_normals`]
/// writes. Which nodes are written again is decided by the part's conditions when the
/// snapshot is restored (the nodes [`compute_unit_normals`] resets).
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
        let nodal = model.nodal_data().vector(VectorVar::Normal, 0)?.to_vec();
        Some(UnitNormalsSnapshot { part, nodal })
    }

    /// The kept `NORMAL`, by node index (every node of the model).
    pub fn nodal(&self) -> &[Vector] {
        &self.nodal
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

#[cfg(test)]
mod tests;
