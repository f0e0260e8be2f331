//! The error type of the trees layer.

use std::fmt;

/// An error of a tree construction or query: the input was degenerate (NaN or infinite
/// coordinates, zero bucket size, empty root box, …). Opaque; inspect it with [`Error::kind`].
#[derive(Debug, Clone, PartialEq)]
pub struct Error {
    kind: ErrorKind,
}

/// What went wrong in a tree construction or query.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum ErrorKind {
    /// A coordinate or scalar argument was NaN or infinite; `what` names the argument.
    NonFinite {
        /// The argument that was not finite (`"point"`, `"center"`, `"radius"`, …).
        what: &'static str,
    },
    /// A radius was negative.
    NegativeRadius,
    /// The kd-tree bucket size was zero (Kratos would build empty children and crash).
    ZeroBucketSize,
    /// More entries than the tree can index (`u32::MAX / 2`).
    TooManyEntries,
    /// An axis-aligned box had `min > max` on some axis where a proper box is needed.
    InvertedBox,
    /// The octree root box has zero, negative or unrepresentably small/large extent on some
    /// axis.
    EmptyRootBox,
    /// The octree levels are inconsistent (`min_level < root_level < max_level <= 31` is
    /// required).
    InvalidLevels,
    /// A point to refine the octree around lies outside the root box.
    OutsideRootBox,
    /// The octree was refined after objects had been inserted (refine first, then insert,
    /// as Kratos inserts nodes before conditions).
    RefineAfterInsert,
    /// A tree was given item and point lists of different lengths.
    LengthMismatch,
    /// An octree leaf id is not a leaf of the octree it was given to (another octree's, or
    /// one from before a refinement).
    NotALeaf,
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

    /// Shorthand for a [`ErrorKind::NonFinite`] error.
    pub(crate) fn non_finite(what: &'static str) -> Error {
        Error::new(ErrorKind::NonFinite { what })
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
            ErrorKind::NonFinite { what } => write!(f, "{what} is NaN or infinite"),
            ErrorKind::NegativeRadius => write!(f, "the search radius is negative"),
            ErrorKind::ZeroBucketSize => write!(f, "the kd-tree bucket size must be at least 1"),
            ErrorKind::TooManyEntries => {
                write!(f, "too many entries for a tree (max u32::MAX / 2)")
            }
            ErrorKind::InvertedBox => write!(f, "the box has min > max on some axis"),
            ErrorKind::EmptyRootBox => {
                write!(f, "the octree root box has no extent on some axis")
            }
            ErrorKind::InvalidLevels => write!(
                f,
                "invalid octree levels (need min_level < root_level < max_level <= 31)"
            ),
            ErrorKind::OutsideRootBox => write!(f, "the point lies outside the octree root box"),
            ErrorKind::LengthMismatch => {
                write!(f, "the item and point lists differ in length")
            }
            ErrorKind::NotALeaf => write!(f, "the cell is not a leaf of this octree"),
            ErrorKind::RefineAfterInsert => {
                write!(
                    f,
                    "the octree cannot be refined after objects were inserted"
                )
            }
        }
    }
}

impl std::error::Error for Error {}

/// Checks that every coordinate of `p` is finite.
pub(crate) fn check_point(p: &csm_geometry::math::Point, what: &'static str) -> Result<(), Error> {
    if p.coords.iter().all(|c| c.is_finite()) {
        Ok(())
    } else {
        Err(Error::non_finite(what))
    }
}
