//! The values of the whole problem that a search takes from its own model: for a search of one
//! rank's part of a larger mesh (issue 29, `csm-distributed`), they must be the whole
//! problem's, not the part's. [`crate::ContactSearch::globals`] reports the ones a step used;
//! [`crate::ContactSearch::set_globals`] makes later steps use given ones.

use csm_geometry::math::Real;

/// One pair's values of the whole problem (`docs/distributed.md`, "What exactly demands").
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PairGlobals {
    /// The largest NODAL_H of the contact part's nodes: the OBB and 18-DOP tests enlarge the
    /// master boxes by `bounding_box_factor` times it (1 where it is below ε).
    pub largest_nodal_h: Option<Real>,
    /// The Advanced activation's DISTANCE_THRESHOLD: the mean NODAL_H of the slave side's
    /// nodes (`csm_activation::mean_h`).
    pub mean_nodal_h: Option<Real>,
}
