//! The error of the activation layer.

use std::fmt;

/// A failure of the mapping or of the weighted gap. Opaque; inspect it with [`Error::kind`];
/// a geometry routine's error is its [`source`](std::error::Error::source).
#[derive(Debug, Clone, PartialEq)]
pub struct Error {
    kind: ErrorKind,
}

/// What went wrong in the activation layer.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum ErrorKind {
    /// A geometry routine refused a condition (unsupported kind, degenerate face, non-finite
    /// input).
    Condition {
        /// What was computed (`"mortar segmentation"`, `"unit normal"`, …).
        what: &'static str,
        /// External id of the condition.
        condition: u32,
        /// The geometry layer's error.
        source: csm_geometry::Error,
    },
    /// The model's data does not fit (a nodal variable of the wrong length, …).
    Data(String),
    /// A distributed run: another rank failed ([`csm_model::Aborted`]); the caller leaves
    /// through [`csm_model::Ranks::agree_on_failure`].
    Aborted,
}

impl Error {
    pub(crate) fn condition(what: &'static str, id: u32, source: &csm_geometry::Error) -> Error {
        Error {
            kind: ErrorKind::Condition {
                what,
                condition: id,
                source: source.clone(),
            },
        }
    }

    pub(crate) fn message_only(message: String) -> Error {
        Error {
            kind: ErrorKind::Data(message),
        }
    }

    pub(crate) fn aborted(_: csm_model::Aborted) -> Error {
        Error {
            kind: ErrorKind::Aborted,
        }
    }

    /// What went wrong.
    pub fn kind(&self) -> &ErrorKind {
        &self.kind
    }

    /// The message (the `Display` text).
    pub fn message(&self) -> String {
        self.to_string()
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.kind {
            ErrorKind::Condition {
                what,
                condition,
                source,
            } => write!(f, "{what} of condition {condition}: {source}"),
            ErrorKind::Data(message) => f.write_str(message),
            ErrorKind::Aborted => write!(f, "{}", csm_model::Aborted),
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match &self.kind {
            ErrorKind::Condition { source, .. } => Some(source),
            ErrorKind::Data(_) | ErrorKind::Aborted => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use std::error::Error as _;

    use super::{Error, ErrorKind};

    #[test]
    fn a_geometry_failure_is_the_source() {
        let refused = csm_geometry::Geometry::new(csm_geometry::GeometryKind::Triangle3D3, &[])
            .map(|_| ())
            .unwrap_err();
        let e = Error::condition("mortar face", 7, &refused);
        assert_eq!(
            e.to_string(),
            format!("mortar face of condition 7: {refused}")
        );
        assert!(matches!(
            e.kind(),
            ErrorKind::Condition { condition: 7, .. }
        ));
        let source = e.source().expect("a source");
        assert_eq!(source.downcast_ref::<csm_geometry::Error>(), Some(&refused));
    }
}
