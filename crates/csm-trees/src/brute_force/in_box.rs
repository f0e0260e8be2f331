//! Brute-force box search.

use csm_geometry::math::Point;

use crate::aabb::Aabb;

/// Collects into `out` (cleared first), in input order, every item of `entries` whose point
/// satisfies `min[k] <= p[k] <= max[k]` on every axis (inclusive).
pub fn in_box<T: Copy>(entries: &[(T, Point)], min: &Point, max: &Point, out: &mut Vec<T>) {
    out.clear();
    let aabb = Aabb::new(*min, *max);
    out.extend(
        entries
            .iter()
            .filter(|(_, p)| aabb.contains(p))
            .map(|(item, _)| *item),
    );
}
