//! The mortar overlap of one slave–master pair as [`normal_gap_process`](crate::normal_gap_process)
//! sees it, for callers that decide pairs themselves (the ground truth of `csm-search`).

use csm_geometry::math::Real;
use csm_geometry::{SegmentationSettings, exact_segmentation};
use csm_model::{ConditionIdx, ModelPart, PartIdx};

use crate::error::Error;
use crate::face::{face_data, make_face};
use crate::mapping::{mean_normals, sides};

/// Step 2 of [`normal_gap_process`](crate::normal_gap_process) alone: the nodal mean normals
/// and the condition normals (unit normal at the centre) of the master side, then of the slave
/// side of ContactSub `sub` — the normals the mapping segments with.
///
/// Errors: a face whose unit normal cannot be computed (degenerate geometry).
pub fn mapping_normals(model: &mut ModelPart, sub: PartIdx, inverted: bool) -> Result<(), Error> {
    let s = sides(model, sub, inverted);
    mean_normals(model, (&s.master_conditions, None), None)?;
    mean_normals(model, (&s.slave_conditions, None), None)
}

/// The overlap measure (area in 3D, length in 2D) of the exact mortar segmentation of
/// `master` onto `slave` with the model's current normals (call [`mapping_normals`] first to
/// get the mapping's), or `None` where the segmentation finds no overlap (which is what makes
/// the mapping remove the pair). Also returns the slave's own measure.
///
/// Errors: a face the mortar routines refuse (unsupported kind, degenerate slave).
pub fn overlap_measure(
    model: &ModelPart,
    slave: ConditionIdx,
    master: ConditionIdx,
    settings: &SegmentationSettings,
) -> Result<(Option<Real>, Real), Error> {
    let slave_id = model.conditions().ids()[slave.index()];
    let sdata = face_data(model, slave);
    let sface = make_face(model, slave, &sdata)?;
    let slave_measure = sface
        .geometry()
        .area()
        .map_err(|e| Error::condition("area", slave_id, &e))?;
    let mdata = face_data(model, master);
    let mface = make_face(model, master, &mdata)?;
    let seg = exact_segmentation(&sface, &mface, settings)
        .map_err(|e| Error::condition("mortar segmentation", slave_id, &e))?;
    Ok((seg.map(|s| s.overlap_area()), slave_measure))
}
