//! The Gmsh reader's entry point.

use csm_model::ModelPart;

use crate::cursor::Cursor;
use crate::error::Error;
use crate::msh::build_model::build_model;
use crate::msh::parse_msh::parse_msh;

/// Reads a Gmsh `.msh` file (MSH 2.2 or 4.1, ASCII or little-endian binary) from its bytes
/// into a model part named `Structure`. `file_name` is used in error messages only.
///
/// Sections read: `$MeshFormat`, `$PhysicalNames`, `$Entities` (4.1), `$Nodes`,
/// `$Elements`; any other `$Section` is skipped up to its `$EndSection`. See the crate
/// documentation for how cells become elements, conditions and sub model parts.
pub fn read_msh(bytes: &[u8], file_name: &str) -> Result<ModelPart, Error> {
    let mut cur = Cursor::new(bytes, file_name, false);
    let raw = parse_msh(&mut cur)?;
    build_model(&raw, &cur)
}
