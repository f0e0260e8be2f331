//! Projections onto a plane (Kratos `GeometricalProjectionUtilities::FastProject` and
//! `FastProjectDirection`, reference §17.1).

mod fast_project;

#[cfg(test)]
mod tests;

pub use fast_project::{fast_project, fast_project_direction};
