//! Reads a mesh file of any supported format, chosen by extension.

use std::path::Path;

use csm_model::ModelPart;

use crate::error::{Error, ErrorKind, Location};

/// Reads the mesh at `path` into a model part named `Structure`: `.msh` with `read_msh`,
/// `.mdpa` with `read_mdpa` (extensions compared case-insensitively). A format whose cargo
/// feature (`msh`, `mdpa`) is off gives [`ErrorKind::FormatNotCompiled`].
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
    if (ext == "msh" && !cfg!(feature = "msh")) || (ext == "mdpa" && !cfg!(feature = "mdpa")) {
        return Err(Error::new(
            &file,
            Location::None,
            ErrorKind::FormatNotCompiled(ext),
        ));
    }
    let bytes = std::fs::read(path)
        .map_err(|e| Error::new(&file, Location::None, ErrorKind::Io(e.to_string())))?;
    read_bytes(&ext, &bytes, &file)
}

#[cfg(all(feature = "msh", feature = "mdpa"))]
fn read_bytes(ext: &str, bytes: &[u8], file: &str) -> Result<ModelPart, Error> {
    if ext == "msh" {
        crate::read_msh(bytes, file)
    } else {
        crate::mdpa::read_mdpa_bytes(bytes, file)
    }
}

#[cfg(all(feature = "msh", not(feature = "mdpa")))]
fn read_bytes(_ext: &str, bytes: &[u8], file: &str) -> Result<ModelPart, Error> {
    crate::read_msh(bytes, file)
}

#[cfg(all(feature = "mdpa", not(feature = "msh")))]
fn read_bytes(_ext: &str, bytes: &[u8], file: &str) -> Result<ModelPart, Error> {
    crate::mdpa::read_mdpa_bytes(bytes, file)
}

#[cfg(not(any(feature = "msh", feature = "mdpa")))]
fn read_bytes(ext: &str, _bytes: &[u8], file: &str) -> Result<ModelPart, Error> {
    Err(Error::new(
        file,
        Location::None,
        ErrorKind::FormatNotCompiled(ext.to_owned()),
    ))
}

#[cfg(test)]
mod tests;
