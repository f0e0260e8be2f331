//! Integration tests of csm-io: the project's Gmsh meshes (every MSH variant gives the same
//! model, and the `.mdpa` twin the same parts), Kratos' contact test meshes, the VTU writer,
//! and a fuzz proptest (mutated real files never panic a reader).

mod fuzz;
mod gmsh_meshes;
mod kratos_meshes;
mod vtu;

use std::path::PathBuf;

/// A file of the project's generated meshes (`tests/data/`).
pub fn data(name: &str) -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/data")).join(name)
}

/// A file of Kratos' test meshes (`shared/data/kratos-tests/`, beside the repository).
pub fn kratos(name: &str) -> PathBuf {
    PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/data/kratos-tests"
    ))
    .join(name)
}
