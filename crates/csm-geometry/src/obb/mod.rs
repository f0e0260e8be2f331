//! Oriented bounding boxes (Kratos `OrientedBoundingBox<2|3>`, reference §7): the 3D [`Obb`]
//! and the 2D [`Obb2`], their construction from a geometry (AABB diagonal — branch A and the
//! 2D rule —, or face normal — branch B), with the enlargement factor, and their vertices.
//! The intersection tests live in `crate::intersection`.

mod build_first_edge;
mod build_from_aabb;
mod build_from_normal;
mod build_from_segment;
#[allow(clippy::module_inception)]
mod obb;
mod obb2;

#[cfg(test)]
mod tests;

pub use obb::Obb;
pub use obb2::Obb2;
