//! The box type of the octree's objects and of the box searches: `csm_geometry::Aabb`, the
//! one bounding-box type of every layer, and what the trees need beside it.
//!
//! All tests on a box are **inclusive** (touching boxes overlap; a point on a face is inside),
//! as Kratos' `Collides` and kd-tree box test are. Boxes with `min == max` (points) are valid.

use csm_geometry::math::Point;
use rayon::prelude::*;

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

/// [`bounds_of`] a list, found in parallel blocks where it is long. The box is the same: a
/// minimum and a maximum are exact in any grouping (up to the sign of a zero, which no
/// comparison and no spread sees).
pub fn par_bounds_of(points: &[Point]) -> Option<Aabb> {
    bounds_in_blocks(points, 0)
}

/// [`par_bounds_of`], on one thread below `parallel_min` points.
pub(crate) fn bounds_in_blocks(points: &[Point], parallel_min: usize) -> Option<Aabb> {
    const BLOCK: usize = 4096;
    // Compared coordinate by coordinate (faster than `Aabb::grow`'s `min`/`max`, which
    // handle NaN; the points are finite).
    let serial = |points: &[Point]| {
        let (mut lo, mut hi) = (points[0], points[0]);
        for p in &points[1..] {
            for k in 0..3 {
                if p[k] < lo[k] {
                    lo[k] = p[k];
                }
                if p[k] > hi[k] {
                    hi[k] = p[k];
                }
            }
        }
        Aabb::new(lo, hi)
    };
    if points.is_empty() {
        None
    } else if points.len() < parallel_min.max(2 * BLOCK) {
        Some(serial(points))
    } else {
        (points.par_chunks(BLOCK).map(serial)).reduce_with(|a, b| a.union(&b))
    }
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
