//! Brute-force radius search.

use csm_geometry::math::{Point, Real};

use crate::kdtree::distance2;

/// Collects into `out` (cleared first), in input order, every item of `entries` whose point
/// satisfies `|p − center|² < radius²` (strict; the squared distance computed exactly as
/// [`crate::KdTree::in_radius`] computes it).
pub fn in_radius<T: Copy>(entries: &[(T, Point)], center: &Point, radius: Real, out: &mut Vec<T>) {
    out.clear();
    let radius2 = radius * radius;
    out.extend(
        entries
            .iter()
            .filter(|(_, p)| distance2(p, center) < radius2)
            .map(|(item, _)| *item),
    );
}
