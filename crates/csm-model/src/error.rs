//! The error type of the model layer.

use std::fmt;

/// Which kind of entity an error is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EntityKind {
    /// A node.
    Node,
    /// An element.
    Element,
    /// A condition.
    Condition,
    /// A properties block.
    Properties,
}

impl fmt::Display for EntityKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            EntityKind::Node => "node",
            EntityKind::Element => "element",
            EntityKind::Condition => "condition",
            EntityKind::Properties => "properties",
        })
    }
}

/// An error of the model layer. Opaque; inspect it with [`Error::kind`].
#[derive(Debug, Clone, PartialEq)]
pub struct Error {
    kind: ErrorKind,
}

/// What went wrong in the model layer.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum ErrorKind {
    /// An entity id was given twice.
    DuplicateId {
        /// The entity kind.
        entity: EntityKind,
        /// The repeated id.
        id: u32,
    },
    /// An entity refers to a node id that does not exist.
    MissingNode {
        /// The entity kind that refers to the node.
        entity: EntityKind,
        /// The id of the referring entity.
        id: u32,
        /// The missing node id.
        node: u32,
    },
    /// A referenced entity id does not exist.
    MissingEntity {
        /// The entity kind.
        entity: EntityKind,
        /// The missing id.
        id: u32,
    },
    /// An entity has the wrong number of nodes for its geometry.
    WrongNodeCount {
        /// The entity kind.
        entity: EntityKind,
        /// The entity id.
        id: u32,
        /// Nodes the geometry needs.
        expected: usize,
        /// Nodes given.
        found: usize,
    },
    /// A node coordinate is NaN or infinite.
    NonFiniteCoordinate {
        /// The node id.
        node: u32,
    },
    /// No sub model part has this full path.
    UnknownPart(String),
    /// A sub model part name is empty or contains a path separator.
    InvalidPartName(String),
    /// A geometric computation on an entity failed.
    Geometry {
        /// The entity kind.
        entity: EntityKind,
        /// The entity id.
        id: u32,
        /// The geometric error.
        source: csm_geometry::Error,
    },
    /// An array of [`MeshArrays`](crate::MeshArrays) has the wrong length.
    ArrayLength {
        /// Which array (`points`, `elements Triangle3D3: connectivity`, …).
        what: String,
        /// The length it must have.
        expected: usize,
        /// Its length.
        found: usize,
    },
    /// A `DOMAIN_SIZE` other than 2 or 3.
    InvalidDomainSize(u32),
    /// A sub model part of [`MeshArrays`](crate::MeshArrays) lists an entity that does not
    /// exist.
    MissingPartMember {
        /// The part's full path.
        part: String,
        /// The entity kind.
        entity: EntityKind,
        /// The missing id.
        id: u32,
    },
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
}

impl From<ErrorKind> for Error {
    fn from(kind: ErrorKind) -> Error {
        Error { kind }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.kind {
            ErrorKind::DuplicateId { entity, id } => write!(f, "duplicate {entity} id {id}"),
            ErrorKind::MissingNode { entity, id, node } => {
                write!(
                    f,
                    "{entity} {id} refers to node {node}, which does not exist"
                )
            }
            ErrorKind::MissingEntity { entity, id } => write!(f, "{entity} {id} does not exist"),
            ErrorKind::WrongNodeCount {
                entity,
                id,
                expected,
                found,
            } => write!(
                f,
                "{entity} {id} has {found} nodes, its geometry needs {expected}"
            ),
            ErrorKind::NonFiniteCoordinate { node } => {
                write!(f, "node {node} has a NaN or infinite coordinate")
            }
            ErrorKind::UnknownPart(path) => write!(f, "no sub model part named `{path}`"),
            ErrorKind::InvalidPartName(name) => write!(
                f,
                "invalid sub model part name `{name}` (empty, or a segment contains `.` or `/`)"
            ),
            ErrorKind::Geometry { entity, id, source } => write!(f, "{entity} {id}: {source}"),
            ErrorKind::ArrayLength {
                what,
                expected,
                found,
            } => write!(f, "{what}: {found} values, expected {expected}"),
            ErrorKind::InvalidDomainSize(d) => write!(f, "DOMAIN_SIZE {d}: 2 or 3"),
            ErrorKind::MissingPartMember { part, entity, id } => write!(
                f,
                "sub model part `{part}` lists {entity} {id}, which does not exist"
            ),
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match &self.kind {
            ErrorKind::Geometry { source, .. } => Some(source),
            _ => None,
        }
    }
}
