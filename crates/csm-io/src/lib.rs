//! I/O layer of csm: mesh readers and the VTU writer.
//!
//! - [`read_mesh`] reads a mesh by extension: Gmsh `.msh` ([`read_msh`]: MSH 2.2 and 4.1,
//!   ASCII and binary) and Kratos `.mdpa` ([`read_mdpa`]), both parsed with `nom`, into a
//!   [`csm_model::ModelPart`] named `Structure`.
//! - [`VtuWriter`] writes a model part as a VTK XML UnstructuredGrid (`.vtu`; [`VtuFormat`]:
//!   raw binary appended data, what ParaView reads fastest, or ASCII, diff-friendly) with
//!   caller-supplied point and cell data and extra line cells (the contact pairs).
//! - [`Error`] (with [`ErrorKind`] and [`Location`]) says what went wrong and where:
//!   `file:line: expected …, found …` for text, the byte offset and section for binary
//!   Gmsh data. A truncated or garbled file gives an error, never a panic.
//!
//! Cargo features (all on by default): `msh` ([`read_msh`]), `mdpa` ([`read_mdpa`]), `vtu`
//! ([`VtuWriter`]); [`read_mesh`] reads the formats that are compiled in and names the
//! missing feature for the others.
//!
//! **Architecture Invariant:** `csm-io` depends only on `csm-model` and `csm-geometry`
//! (and `nom`; `rayon` for the parallel parsing of `.mdpa` blocks). It knows nothing of the search: it fills a model part and writes one.
#![deny(missing_docs)]

#[cfg(any(feature = "msh", feature = "mdpa"))]
mod cursor;
mod error;
#[cfg(feature = "mdpa")]
mod mdpa;
#[cfg(feature = "msh")]
mod msh;
mod read_mesh;
#[cfg(feature = "vtu")]
mod vtu;

pub use error::{Error, ErrorKind, Location};
#[cfg(feature = "mdpa")]
pub use mdpa::read_mdpa;
#[cfg(feature = "msh")]
pub use msh::read_msh;
pub use read_mesh::read_mesh;
#[cfg(feature = "vtu")]
pub use vtu::{DataArray, VtuFormat, VtuWriter, vtk_cell_type};
