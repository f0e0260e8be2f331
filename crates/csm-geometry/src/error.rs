//! The error type of the geometry layer.

use std::fmt;

/// An error of a geometric computation: the input was degenerate or outside the domain of the
/// operation. Opaque; inspect it with [`Error::kind`].
#[derive(Debug, Clone, PartialEq)]
pub struct Error {
    kind: ErrorKind,
}

/// What went wrong in a geometric computation.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum ErrorKind {
    /// A coordinate or an argument was NaN or infinite.
    NonFinite,
    /// The geometry has no extent where one is needed (zero-length segment, zero-area face,
    /// zero-volume solid, coincident nodes, zero-norm direction).
    Degenerate(&'static str),
    /// The node list does not have the number of nodes the geometry kind needs.
    WrongNodeCount {
        /// The number the geometry kind needs.
        expected: usize,
        /// The number given.
        found: usize,
    },
    /// The operation is not defined for this geometry kind.
    Unsupported(&'static str),
    /// An iterative method (e.g. the Newton iteration of local coordinates) did not converge.
    NotConverged,
}

impl Error {
    /// Creates an error of the given kind.
    pub fn new(kind: ErrorKind) -> Error {
        Error { kind }
    }

    /// What went wrong.
    pub fn kind(&self) -> &ErrorKind {
        &self.kind
    }

    /// Shorthand for a [`ErrorKind::Degenerate`] error.
    pub fn degenerate(what: &'static str) -> Error {
        Error::new(ErrorKind::Degenerate(what))
    }
}

impl From<ErrorKind> for Error {
    fn from(kind: ErrorKind) -> Error {
        Error { kind }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.kind {
            ErrorKind::NonFinite => write!(f, "a coordinate or argument is NaN or infinite"),
            ErrorKind::Degenerate(what) => write!(f, "degenerate geometry: {what}"),
            ErrorKind::WrongNodeCount { expected, found } => {
                write!(f, "expected {expected} nodes, found {found}")
            }
            ErrorKind::Unsupported(what) => write!(f, "unsupported: {what}"),
            ErrorKind::NotConverged => write!(f, "iteration did not converge"),
        }
    }
}

impl std::error::Error for Error {}
