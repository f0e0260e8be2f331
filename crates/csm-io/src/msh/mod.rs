//! Gmsh `.msh` reader (MSH 2.2 and 4.1, ASCII and binary).

mod build_model;
mod element_type;
mod parse_msh;
mod raw_mesh;
mod read_msh;
mod sections_v2;
mod sections_v4;

pub use read_msh::read_msh;

#[cfg(test)]
mod tests;
