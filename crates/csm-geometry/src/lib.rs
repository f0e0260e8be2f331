//! Geometry layer of csm: the face and solid geometries of the contact pipeline, their shape
//! functions, centres, normals, local coordinates and projections, and the bounding volumes
//! used by the search (AABB, bounding sphere, OBB with the SAT and Direct tests).
//!
//! Main types: [`GeometryKind`] (which finite-element geometry a node list is), [`Geometry`]
//! (a validated view of one geometry's nodes), [`Aabb`], [`Obb`] / [`Obb2`]. All maths is
//! `f64` in three components, also in 2D (z = 0), see [`math`].
//!
//! **Architecture Invariant:** `csm-geometry` knows nothing about model parts, flags,
//! conditions or files. It depends on `nalgebra` only; every other csm crate may depend on it.
//!
//! **Architecture Invariant:** geometry is total: degenerate input (zero-length segment,
//! zero-area face, coincident nodes, NaN) gives an [`Error`], never a panic or a NaN result.
#![deny(missing_docs)]

mod bounding;
mod edges;
mod error;
mod faces;
mod geometry;
mod intersection;
mod kdop;
mod kind;
pub mod math;
mod mortar;
mod obb;
mod projection;
mod shape;
#[cfg(test)]
mod test_support;

pub use bounding::{Aabb, BoundingSphere};
pub use error::{Error, ErrorKind};
pub use geometry::{
    CentreProbeBound, FaceUnitNormals, Geometry, LOCAL_COORDINATES_MAX_ITERATIONS,
    LOCAL_COORDINATES_TOLERANCE, LargestArea, LocalCoordinatesSolver, MAX_FACE_NODES,
    TETRAHEDRON_LENGTH_FACTOR,
};
pub use intersection::{
    CENTRE_ROUNDING_EPS, CROSS_AXIS_GUARD, ObbIntersection, SatMode, TOUCH_TOLERANCE,
    direct_obb_obb, direct_obb2_obb2, sat_obb_obb, sat_obb2_obb2, segment_aabb_intersect,
    segment_segment_intersect, triangle_aabb_intersect, triangle_triangle_intersect,
};
pub use kdop::{KDOP18_DIRECTIONS, Kdop18};
pub use kind::GeometryKind;
pub use mortar::{
    CLIPPING_TOLERANCE, DUPLICATE_POINT_TOLERANCE, DualBasis, EXPLICIT_LENGTH_FACTOR, FaceMatrix,
    MAPPER_LENGTH_FACTOR, MAX_ME_CONDITION_NUMBER, MAX_MORTAR_FACE_NODES, MortarCell, MortarFace,
    MortarIntegrationPoint, MortarMode, MortarOperators, NEWTON_2D_MAX_ITERATIONS,
    NEWTON_2D_TOLERANCE, OperatorSettings, ROBUST_AREA_FACTOR, Segmentation, SegmentationSettings,
    SlaveSegmentation, dual_ae, dual_ae_in, dual_basis, dual_basis_in, exact_segmentation,
    integration_points, integration_points_with_normals, line_projections_lost_to_rounding,
    mortar_operators,
};
pub use obb::{Obb, Obb2};
pub use projection::{fast_project, fast_project_direction};
pub use shape::{
    MAX_NODES, ShapeDerivatives, ShapeValues, reference_node_coordinates, shape_derivatives,
    shape_functions,
};
