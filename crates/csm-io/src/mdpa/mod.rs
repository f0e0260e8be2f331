//! Kratos `.mdpa` reader.

mod geometry_from_name;
mod number_block;
mod read_mdpa;

pub use read_mdpa::read_mdpa;
pub(crate) use read_mdpa::read_mdpa_bytes;
#[cfg(test)]
use read_mdpa::{Parallel, read_mdpa_with};

#[cfg(test)]
mod tests;
