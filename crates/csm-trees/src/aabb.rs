//! A minimal axis-aligned box, the object type of the octree and the query type of the box
//! searches.

use csm_geometry::math::{Point, Real};

use crate::error::{Error, ErrorKind, check_point};

/// An axis-aligned bounding box given by its corners, `mins[k] <= maxs[k]` expected.
///
/// All tests on it are **inclusive** (touching boxes overlap; a point on a face is inside), as
/// Kratos' `Collides` and kd-tree box test are. Boxes with `mins == maxs` (points) are valid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    /// The lowest corner.
    pub mins: Point,
    /// The highest corner.
    pub maxs: Point,
}

impl Aabb {
    /// The box with corners `mins` and `maxs` (not checked; see [`Aabb::validate`]).
    pub fn new(mins: Point, maxs: Point) -> Aabb {
        Aabb { mins, maxs }
    }

    /// The smallest box containing all `points`; `None` when there are none.
    pub fn from_points<'a>(points: impl IntoIterator<Item = &'a Point>) -> Option<Aabb> {
        let mut it = points.into_iter();
        let first = *it.next()?;
        let mut aabb = Aabb::new(first, first);
        for p in it {
            aabb.mins = aabb.mins.inf(p);
            aabb.maxs = aabb.maxs.sup(p);
        }
        Some(aabb)
    }

    /// Checks that the corners are finite and `mins <= maxs` on every axis.
    pub fn validate(&self) -> Result<(), Error> {
        check_point(&self.mins, "box corner")?;
        check_point(&self.maxs, "box corner")?;
        if (0..3).all(|k| self.mins[k] <= self.maxs[k]) {
            Ok(())
        } else {
            Err(Error::new(ErrorKind::InvertedBox))
        }
    }

    /// Whether the two boxes overlap or touch (inclusive on every axis; symmetric).
    pub fn intersects(&self, other: &Aabb) -> bool {
        (0..3).all(|k| self.mins[k] <= other.maxs[k] && other.mins[k] <= self.maxs[k])
    }

    /// Whether `p` lies in the box, faces included: `mins[k] <= p[k] <= maxs[k]` for all `k`.
    pub fn contains_point(&self, p: &Point) -> bool {
        (0..3).all(|k| self.mins[k] <= p[k] && p[k] <= self.maxs[k])
    }

    /// The box grown by `margin` on every side (shrunk when `margin < 0`).
    pub fn loosened(&self, margin: Real) -> Aabb {
        let m = csm_geometry::math::Vector::repeat(margin);
        Aabb::new(self.mins - m, self.maxs + m)
    }
}
