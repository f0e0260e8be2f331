//! The face data the mapping and the weighted gap read: a condition's points, normal and
//! nodal normals, and its mortar face.

use csm_geometry::math::{Point, Vector};
use csm_geometry::{Geometry, MAX_MORTAR_FACE_NODES, MortarFace};
use csm_model::{ConditionIdx, ModelPart, VectorVar};
use smallvec::SmallVec;

use crate::error::Error;

/// Geometry points, condition normal and nodal (historical) normals of a condition.
pub(crate) struct FaceData {
    pub points: PerNode<Point>,
    pub normal: Vector,
    pub nodal_normals: PerNode<Vector>,
}

/// One value per node of a condition: up to [`MAX_MORTAR_FACE_NODES`] in place (no allocation
/// for a mortar face), more on the heap (a face the mortar routines refuse).
pub(crate) type PerNode<T> = SmallVec<[T; MAX_MORTAR_FACE_NODES]>;

pub(crate) fn face_data(model: &ModelPart, c: ConditionIdx) -> FaceData {
    face_data_with(model, c, model.nodal_data().vector(VectorVar::Normal, 0))
}

/// [`face_data`] with the nodal normals taken from `normals` (by node index).
pub(crate) fn face_data_with(
    model: &ModelPart,
    c: ConditionIdx,
    normals: Option<&[Vector]>,
) -> FaceData {
    let coords = model.nodes().coordinates();
    let nodes = model.conditions().nodes(c.index());
    FaceData {
        points: nodes.iter().map(|n| coords[n.index()]).collect(),
        normal: model.condition_normals()[c.index()],
        nodal_normals: nodal_normals(model, c, normals),
    }
}

/// The nodal normals of condition `c` taken from `normals` (by node index; zero without).
pub(crate) fn nodal_normals(
    model: &ModelPart,
    c: ConditionIdx,
    normals: Option<&[Vector]>,
) -> PerNode<Vector> {
    let nodes = model.conditions().nodes(c.index()).iter();
    nodes
        .map(|n| normals.map_or(Vector::zeros(), |col| col[n.index()]))
        .collect()
}

pub(crate) fn make_face<'a>(
    model: &ModelPart,
    c: ConditionIdx,
    data: &'a FaceData,
) -> Result<MortarFace<'a>, Error> {
    let id = model.conditions().ids()[c.index()];
    let kind = model.conditions().kind(c.index());
    let wrap = |e: csm_geometry::Error| Error::condition("mortar face", id, &e);
    Geometry::new(kind, &data.points)
        .and_then(|g| MortarFace::new(g, data.normal))
        .and_then(|f| f.with_nodal_normals(&data.nodal_normals))
        .map_err(wrap)
}
