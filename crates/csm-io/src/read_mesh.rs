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
    let bytes = read_file(path)
        .map_err(|e| Error::new(&file, Location::None, ErrorKind::Io(e.to_string())))?;
    let model = read_bytes(&ext, &bytes, &file);
    free_in_background(bytes);
    model
}

/// Gives the file's bytes back: on rayon's pool where it has several threads (the `mdpa`
/// feature), without waiting. Unmapping a large buffer takes one thread milliseconds (the
/// 67 MB of a 2e5-face `.mdpa`: 4.5 ms) that the caller's next work need not wait for.
fn free_in_background(bytes: Vec<u8>) {
    #[cfg(feature = "mdpa")]
    if rayon::current_num_threads() > 1 {
        rayon::spawn(move || drop(bytes));
        return;
    }
    drop(bytes);
}

/// The bytes of the file at `path`. A large file is read in pieces in parallel where rayon is
/// compiled in (the `mdpa` feature) and has more than one thread: most of its read time is
/// the copy out of the page cache and the first touch of the buffer's pages, which then
/// share the work. The same bytes as [`std::fs::read`], which reads everything else (and a
/// file whose length changes while it is read).
fn read_file(path: &Path) -> std::io::Result<Vec<u8>> {
    #[cfg(all(unix, feature = "mdpa"))]
    if let Some(bytes) = read_file_in_pieces(path)? {
        return Ok(bytes);
    }
    std::fs::read(path)
}

/// [`read_file`]'s parallel read: `None` where it does not apply (a small file, one thread,
/// a length that changed).
#[cfg(all(unix, feature = "mdpa"))]
fn read_file_in_pieces(path: &Path) -> std::io::Result<Option<Vec<u8>>> {
    use rayon::prelude::*;
    use std::os::unix::fs::FileExt;
    /// The bytes of one piece.
    const PIECE: usize = 4 << 20;
    let file = std::fs::File::open(path)?;
    let Ok(len) = usize::try_from(file.metadata()?.len()) else {
        return Ok(None);
    };
    if len < 2 * PIECE || rayon::current_num_threads() < 2 {
        return Ok(None);
    }
    let mut bytes = vec![0u8; len];
    let read = bytes
        .par_chunks_mut(PIECE)
        .enumerate()
        .try_for_each(|(i, piece)| file.read_exact_at(piece, (i * PIECE) as u64));
    // A file that got shorter (an early end) or longer (a byte after `len`) meanwhile.
    let mut more = [0u8; 1];
    if read.is_err() || file.read_at(&mut more, len as u64)? != 0 {
        return Ok(None);
    }
    Ok(Some(bytes))
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
