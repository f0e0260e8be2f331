//! The error of the activation layer.

use std::fmt;

/// A failure of the mapping or of the weighted gap: a geometry routine refused a condition
/// (unsupported kind, degenerate face, non-finite input).
#[derive(Debug, Clone, PartialEq)]
pub struct Error {
    message: String,
}

impl Error {
    pub(crate) fn condition(what: &str, id: u32, source: &csm_geometry::Error) -> Error {
        Error {
            message: format!("{what} of condition {id}: {source}"),
        }
    }

    pub(crate) fn message_only(message: String) -> Error {
        Error { message }
    }

    /// The message.
    pub fn message(&self) -> &str {
        &self.message
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for Error {}
