//! [`Geometry`]: a validated view of one finite-element geometry's node coordinates, with its
//! shape functions, centre, normals, local coordinates, inside test and measures (Kratos'
//! `Geometry` API as the contact search uses it, reference §17).

#[allow(clippy::module_inception)]
mod geometry;
mod is_inside;
mod local_coordinates;
mod measure;
mod probe_bound;
mod quad_outside;
mod quadrature;
mod unit_normal;
pub use unit_normal::{FaceUnitNormals, MAX_FACE_NODES};

#[cfg(test)]
mod tests;

pub use geometry::Geometry;
pub(crate) use local_coordinates::PreparedSolver;
pub use local_coordinates::{
    LOCAL_COORDINATES_MAX_ITERATIONS, LOCAL_COORDINATES_TOLERANCE, LocalCoordinatesSolver,
};
pub use measure::{LargestArea, TETRAHEDRON_LENGTH_FACTOR};
pub use probe_bound::CentreProbeBound;
