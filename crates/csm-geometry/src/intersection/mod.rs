//! OBB–OBB intersection tests (Kratos `OrientedBoundingBox::HasIntersection`, reference §7.3,
//! §7.4) and the exact primitive tests the Direct test needs.
//!
//! * SAT ([`sat_obb_obb`], [`sat_obb2_obb2`]) in two modes ([`SatMode`]): `Kratos` reproduces
//!   Kratos' arithmetic literally (axis order, raw cross products, strict `>`, no epsilon — Q2);
//!   `Robust` normalises the axes, skips near-parallel cross-product axes
//!   ([`CROSS_AXIS_GUARD`]) and compares with a relative touching tolerance
//!   ([`TOUCH_TOLERANCE`]).
//! * Direct ([`direct_obb_obb`], [`direct_obb2_obb2`]): vertex inclusion both ways (Kratos'
//!   point-in-box tests with `ε`), then boundary intersection. Kratos' last step uses its own
//!   line–line and quadrilateral–quadrilateral routines, which the reference does not detail;
//!   here we use standard tests instead:
//!   - 2D: segment–segment intersection by orientation predicates
//!     ([`segment_segment_intersect`]; collinear overlap handled, touching counts);
//!   - 3D: each box face (quadrilateral, Hexahedra3D8 face order) split into two triangles
//!     (0,1,2), (0,2,3); each triangle pair by a separating-axis triangle–triangle test
//!     ([`triangle_triangle_intersect`]: the two normals, the 9 edge cross products and the 6
//!     in-plane edge normals, which makes the coplanar case exact; touching counts). It is exact
//!     in exact arithmetic; in floating point verdicts can only flip for configurations within
//!     rounding of touching.

mod direct_obb_obb;
mod mode;
mod sat_obb_obb;
mod segment_aabb;
mod segment_segment;
mod triangle_aabb;
mod triangle_triangle;

#[cfg(test)]
mod tests;

pub use direct_obb_obb::{direct_obb_obb, direct_obb2_obb2};
pub use mode::{CENTRE_ROUNDING_EPS, CROSS_AXIS_GUARD, ObbIntersection, SatMode, TOUCH_TOLERANCE};
pub use sat_obb_obb::{sat_obb_obb, sat_obb2_obb2};
pub use segment_aabb::segment_aabb_intersect;
pub use segment_segment::segment_segment_intersect;
pub use triangle_aabb::triangle_aabb_intersect;
pub use triangle_triangle::triangle_triangle_intersect;
