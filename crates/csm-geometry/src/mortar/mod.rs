//! Exact mortar segmentation and the dual mortar operators (Kratos
//! `ExactMortarIntegrationUtility<TDim, TNumNodes, false, TNumNodesMaster>`, `MortarOperator`
//! and `DualLagrangeMultiplierOperators`, reference §10.2.1–§10.2.2).
//!
//! [`exact_segmentation`] clips a master face against a slave face and returns the integration
//! cells (segments in 2D, triangles in 3D, in the slave's local coordinates) or `None` when the
//! pair has no overlap within the distance threshold: exactly the decision that removes a pair
//! from `INDEX_MAP` in MappingCheck. [`integration_points`], [`dual_basis`] and
//! [`mortar_operators`] integrate over the cells; the iterated mapper of §10.2 is built on top of
//! them elsewhere.
//!
//! [`MortarMode::Kratos`] reproduces Kratos' absolute tolerances and quirks (Q21, Q44, Q45,
//! Q48, Q49); [`MortarMode::Robust`] uses scale-relative tolerances and fixes Q48/Q49.

mod cell;
mod clip_face_face;
mod dual_basis;
mod face;
mod face_matrix;
mod integration_points;
mod operators;
mod segment_line_line;
mod segmentation;

#[cfg(test)]
mod tests;

pub use cell::{MortarCell, Segmentation};
pub use dual_basis::{
    DualBasis, MAX_ME_CONDITION_NUMBER, dual_ae, dual_ae_in, dual_basis, dual_basis_in,
};
pub use face::{
    CLIPPING_TOLERANCE, DUPLICATE_POINT_TOLERANCE, MortarFace, MortarMode,
    NEWTON_2D_MAX_ITERATIONS, NEWTON_2D_TOLERANCE, ROBUST_AREA_FACTOR, SegmentationSettings,
};
pub use face_matrix::{FaceMatrix, MAX_MORTAR_FACE_NODES};
pub use integration_points::{
    EXPLICIT_LENGTH_FACTOR, MAPPER_LENGTH_FACTOR, MortarIntegrationPoint, OperatorSettings,
    integration_points, integration_points_with_normals,
};
pub use operators::{MortarOperators, mortar_operators};
pub use segment_line_line::line_projections_lost_to_rounding;
pub use segmentation::{SlaveSegmentation, exact_segmentation};
