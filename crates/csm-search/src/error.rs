//! The error type of the search layer.

use std::fmt;

/// An error of the search layer. Opaque; inspect it with [`Error::kind`]. Its `Display` is
/// `<file>:<line>: <message>` when the position is known.
#[derive(Debug, Clone, PartialEq)]
pub struct Error {
    kind: ErrorKind,
    file: Option<String>,
    line: Option<usize>,
}

/// What went wrong in the search layer.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum ErrorKind {
    /// The setup is not valid JSON.
    Json(String),
    /// A setup key is unknown to Kratos (Kratos rejects it too), or unknown to csm.
    UnknownKey {
        /// Dotted path of the key, e.g. `search_parameters.serch_factor`.
        key: String,
    },
    /// A setup value has the wrong JSON type or an invalid value.
    InvalidValue {
        /// Dotted path of the key.
        key: String,
        /// What was expected.
        expected: String,
        /// What was found.
        found: String,
    },
    /// No contact process was found in a ProjectParameters file.
    NoContactProcess,
    /// Kratos fails on this setup (e.g. `"type_search": "KDOP"` in `kratos` mode); the
    /// message says how.
    RejectedByKratos(String),
    /// A silent fallback of Kratos that `"strict": true` turns into an error.
    Strict(String),
    /// A geometric computation on a condition failed (degenerate face, …).
    Geometry {
        /// External id of the condition.
        condition: u32,
        /// What failed.
        message: String,
    },
    /// The model does not fit the setup (missing parts, no slave or master conditions, …).
    Model(String),
    /// A model-layer operation failed; its error is the [`source`](std::error::Error::source).
    ModelData {
        /// What csm was doing (empty: the source says it all).
        context: String,
        /// The model layer's error.
        source: csm_model::Error,
    },
    /// A kd-tree or octree failed; its error is the source.
    Tree {
        /// Which tree.
        context: String,
        /// The tree layer's error.
        source: csm_trees::Error,
    },
    /// The mapping or the weighted gap failed; its error is the source.
    Activation(csm_activation::Error),
    /// A distributed run: another rank failed ([`csm_model::Aborted`]).
    Aborted,
}

impl Error {
    /// An error of the given kind with no position.
    pub fn new(kind: ErrorKind) -> Error {
        Error {
            kind,
            file: None,
            line: None,
        }
    }

    /// What went wrong.
    pub fn kind(&self) -> &ErrorKind {
        &self.kind
    }

    /// The file the error is about, if known.
    pub fn file(&self) -> Option<&str> {
        self.file.as_deref()
    }

    /// The 1-based line, if known.
    pub fn line(&self) -> Option<usize> {
        self.line
    }

    /// Sets the position.
    pub fn at(mut self, file: &str, line: Option<usize>) -> Error {
        self.file = Some(file.to_owned());
        self.line = line;
        self
    }
}

impl From<csm_model::Aborted> for Error {
    fn from(_: csm_model::Aborted) -> Error {
        Error::new(ErrorKind::Aborted)
    }
}

impl From<ErrorKind> for Error {
    fn from(kind: ErrorKind) -> Error {
        Error::new(kind)
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match (&self.file, self.line) {
            (Some(file), Some(line)) => write!(f, "{file}:{line}: ")?,
            (Some(file), None) => write!(f, "{file}: ")?,
            _ => {}
        }
        match &self.kind {
            ErrorKind::Json(msg) => write!(f, "expected a JSON setup, found invalid JSON: {msg}"),
            ErrorKind::UnknownKey { key } => write!(
                f,
                "expected a known setup key, found `{key}` (Kratos rejects it too: \"present in \
                 this Parameters but NOT in the default values\")"
            ),
            ErrorKind::InvalidValue {
                key,
                expected,
                found,
            } => {
                write!(f, "`{key}`: expected {expected}, found {found}")
            }
            ErrorKind::NoContactProcess => write!(
                f,
                "expected the Parameters of a contact process or a ProjectParameters file with \
                 one (python_module alm_contact_process, penalty_contact_process, …), found none"
            ),
            ErrorKind::RejectedByKratos(msg) => write!(f, "{msg}"),
            ErrorKind::Strict(msg) => write!(f, "{msg} (an error because \"strict\": true)"),
            ErrorKind::Geometry { condition, message } => {
                write!(f, "condition {condition}: {message}")
            }
            ErrorKind::Model(msg) => write!(f, "{msg}"),
            ErrorKind::ModelData { context, source } => with_context(f, context, source),
            ErrorKind::Tree { context, source } => with_context(f, context, source),
            ErrorKind::Activation(source) => write!(f, "{source}"),
            ErrorKind::Aborted => write!(f, "{}", csm_model::Aborted),
        }
    }
}

/// `<context>: <source>`, or the source alone without a context.
fn with_context(
    f: &mut fmt::Formatter<'_>,
    context: &str,
    source: &dyn fmt::Display,
) -> fmt::Result {
    if context.is_empty() {
        write!(f, "{source}")
    } else {
        write!(f, "{context}: {source}")
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match &self.kind {
            ErrorKind::ModelData { source, .. } => Some(source),
            ErrorKind::Tree { source, .. } => Some(source),
            ErrorKind::Activation(source) => Some(source),
            _ => None,
        }
    }
}

impl Error {
    /// A model-layer error, with what csm was doing (`""`: nothing to add).
    pub fn model_data(context: &str, source: csm_model::Error) -> Error {
        ErrorKind::ModelData {
            context: context.to_owned(),
            source,
        }
        .into()
    }

    /// Whether a distributed run stopped here because another rank failed (the caller leaves
    /// through [`csm_model::Ranks::agree_on_failure`]).
    pub fn is_aborted(&self) -> bool {
        match &self.kind {
            ErrorKind::Aborted => true,
            ErrorKind::Activation(e) => matches!(e.kind(), csm_activation::ErrorKind::Aborted),
            _ => false,
        }
    }

    /// A tree's error, naming the tree.
    pub fn tree(context: &str, source: csm_trees::Error) -> Error {
        ErrorKind::Tree {
            context: context.to_owned(),
            source,
        }
        .into()
    }
}

#[cfg(test)]
mod tests {
    use std::error::Error as _;

    use super::{Error, ErrorKind};

    /// A lower layer's error is kept whole: the message says what csm was doing and what the
    /// layer said, and `source()` gives the layer's typed error back.
    #[test]
    fn lower_layer_errors_keep_their_source() {
        let model = csm_model::ModelPart::new("Structure");
        let missing = model.get_part("Contact").unwrap_err();
        let e = Error::model_data("contact parts", missing.clone());
        assert_eq!(e.to_string(), format!("contact parts: {missing}"));
        let source = e.source().expect("a source");
        assert_eq!(source.downcast_ref::<csm_model::Error>(), Some(&missing));
        // Without a context the source's message alone, as before.
        assert_eq!(
            Error::model_data("", missing.clone()).to_string(),
            missing.to_string()
        );
        // The setup's own errors have none.
        assert!(Error::from(ErrorKind::NoContactProcess).source().is_none());
    }
}
