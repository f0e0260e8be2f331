//! The box type of the octree's objects and of the box searches: `csm_geometry::Aabb`, the
//! one bounding-box type of every layer, and what the trees need beside it.
//!
//! All tests on a box are **inclusive** (touching boxes overlap; a point on a face is inside),
//! as Kratos' `Collides` and kd-tree box test are. Boxes with `min == max` (points) are valid.

use csm_geometry::math::Point;

pub use csm_geometry::Aabb;

use crate::error::{Error, ErrorKind, check_point};

/// The smallest box containing all `points`; `None` when there are none.
pub fn bounds_of<'a>(points: impl IntoIterator<Item = &'a Point>) -> Option<Aabb> {
    let mut it = points.into_iter();
    let first = *it.next()?;
    let mut aabb = Aabb::new(first, first);
    for p in it {
        aabb.grow(p);
    }
    Some(aabb)
}

/// Checks that the corners are finite and `min <= max` on every axis.
pub(crate) fn validate(aabb: &Aabb) -> Result<(), Error> {
    check_point(&aabb.min, "box corner")?;
    check_point(&aabb.max, "box corner")?;
    if (0..3).all(|k| aabb.min[k] <= aabb.max[k]) {
        Ok(())
    } else {
        Err(Error::new(ErrorKind::InvertedBox))
    }
}
