//! The error type of the I/O layer: what went wrong, in which file, and where.

use std::fmt;

/// Where in a file an error was found.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum Location {
    /// Nowhere in particular (e.g. the file could not be opened).
    None,
    /// A 1-based line of a text file (or of the text part of a Gmsh file).
    Line(usize),
    /// A byte offset in a binary section of a Gmsh file.
    Byte {
        /// Offset from the start of the file.
        offset: usize,
        /// The section, e.g. `$Nodes`.
        section: String,
    },
}

/// An error of the I/O layer. Opaque; inspect it with [`Error::kind`], [`Error::file`] and
/// [`Error::location`]. Displays as `<file>:<line>: <what was expected, what was found>`
/// (binary sections: `<file>: byte <offset> in <section>: …`).
#[derive(Debug, Clone, PartialEq)]
pub struct Error {
    file: String,
    location: Location,
    kind: ErrorKind,
}

/// What went wrong.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum ErrorKind {
    /// The file could not be read or written.
    Io(String),
    /// The file name has no extension csm can read (`.msh`, `.mdpa`).
    UnsupportedExtension(String),
    /// A format csm-io reads, but whose cargo feature (`msh`, `mdpa`) was off at build time.
    FormatNotCompiled(String),
    /// The file is empty (or holds only whitespace and comments).
    Empty,
    /// Something else was expected here.
    Expected {
        /// What the reader expected.
        expected: String,
        /// What it found (`end of file` on truncation).
        found: String,
    },
    /// An `.mdpa` block `Begin X` that csm does not know.
    UnknownBlock(String),
    /// A section or block that never ends (`$EndX` / `End X` missing).
    Unterminated(String),
    /// A Gmsh element type csm does not read.
    UnknownElementType(i64),
    /// An `.mdpa` element or condition name without a known geometry suffix.
    UnknownGeometryName(String),
    /// A Gmsh format version other than 2.x or 4.1.
    UnsupportedVersion(String),
    /// The model refused an entity (duplicate id, missing node, NaN coordinate, …).
    Model(csm_model::Error),
    /// A caller-supplied data array of the VTU writer has the wrong length.
    ArrayLength {
        /// The array's name.
        name: String,
        /// The length it needs.
        expected: usize,
        /// The length it has.
        found: usize,
    },
}

impl Error {
    /// An error of `kind` in `file` at `location`.
    pub fn new(file: &str, location: Location, kind: ErrorKind) -> Error {
        Error {
            file: file.to_owned(),
            location,
            kind,
        }
    }

    /// What went wrong.
    pub fn kind(&self) -> &ErrorKind {
        &self.kind
    }

    /// The file the error is about.
    pub fn file(&self) -> &str {
        &self.file
    }

    /// Where in the file.
    pub fn location(&self) -> &Location {
        &self.location
    }

    /// The 1-based line, for errors in text.
    pub fn line(&self) -> Option<usize> {
        match self.location {
            Location::Line(l) => Some(l),
            _ => None,
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.location {
            Location::None => write!(f, "{}: ", self.file)?,
            Location::Line(l) => write!(f, "{}:{}: ", self.file, l)?,
            Location::Byte { offset, section } => {
                write!(f, "{}: byte {} in binary {}: ", self.file, offset, section)?
            }
        }
        match &self.kind {
            ErrorKind::Io(msg) => write!(f, "cannot read or write the file: {msg}"),
            ErrorKind::UnsupportedExtension(ext) => write!(
                f,
                "expected a mesh file ending in .msh or .mdpa, found extension `{ext}`"
            ),
            ErrorKind::FormatNotCompiled(ext) => write!(
                f,
                "csm was built without the `{ext}` feature: it cannot read .{ext} files"
            ),
            ErrorKind::Empty => f.write_str("expected a mesh, found an empty file"),
            ErrorKind::Expected { expected, found } => {
                write!(f, "expected {expected}, found {found}")
            }
            ErrorKind::UnknownBlock(name) => write!(
                f,
                "expected a known block (ModelPartData, Properties, Nodes, Elements, Conditions, \
                 NodalData, ElementalData, ConditionalData, Table, SubModelPart…), found `Begin {name}`"
            ),
            ErrorKind::Unterminated(name) => {
                write!(f, "expected the end of {name}, found end of file")
            }
            ErrorKind::UnknownElementType(t) => write!(
                f,
                "expected a Gmsh element type csm reads (1-6, 8-12, 15-17), found type {t}"
            ),
            ErrorKind::UnknownGeometryName(name) => write!(
                f,
                "expected an element/condition name ending in a known geometry suffix \
                 (e.g. 3D4N, 2D3N), found `{name}`"
            ),
            ErrorKind::UnsupportedVersion(v) => {
                write!(
                    f,
                    "expected MSH format version 2.2 or 4.1, found version {v}"
                )
            }
            ErrorKind::Model(e) => write!(f, "{e}"),
            ErrorKind::ArrayLength {
                name,
                expected,
                found,
            } => write!(
                f,
                "expected {expected} values in data array `{name}`, found {found}"
            ),
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match &self.kind {
            ErrorKind::Model(e) => Some(e),
            _ => None,
        }
    }
}
