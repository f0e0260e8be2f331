//! Axis-aligned bounding boxes and bounding spheres.

mod aabb;
mod bounding_sphere;

#[cfg(test)]
mod tests;

pub use aabb::Aabb;
pub use bounding_sphere::BoundingSphere;
