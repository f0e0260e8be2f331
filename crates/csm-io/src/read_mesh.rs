//! Reads a mesh file of any supported format, chosen by extension.

use std::path::Path;

use csm_model::ModelPart;

use crate::error::{Error, ErrorKind, Location};
use crate::{read_mdpa, read_msh};

/// Reads the mesh at `path` into a model part named `Structure`: `.msh` with [`read_msh`],
/// `.mdpa` with [`read_mdpa`] (extensions compared case-insensitively).
pub fn read_mesh(path: &Path) -> Result<ModelPart, Error> {
    let file = path.display().to_string();
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    if ext != "msh" && ext != "mdpa" {
        return Err(Error::new(
            &file,
            Location::None,
            ErrorKind::UnsupportedExtension(ext),
        ));
    }
    let bytes = std::fs::read(path)
        .map_err(|e| Error::new(&file, Location::None, ErrorKind::Io(e.to_string())))?;
    if ext == "msh" {
        read_msh(&bytes, &file)
    } else {
        let text = String::from_utf8_lossy(&bytes);
        read_mdpa(&text, &file)
    }
}
