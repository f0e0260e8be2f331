//! Kratos `.mdpa` reader.

mod geometry_from_name;
mod read_mdpa;

pub use read_mdpa::read_mdpa;

#[cfg(test)]
mod tests;
