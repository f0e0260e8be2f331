//! Brute-force box-overlap search.

use crate::aabb::Aabb;

/// Collects into `out` (cleared first), in input order, every item of `objects` whose box
/// overlaps or touches `query` ([`Aabb::intersects`], inclusive).
pub fn aabb_overlap<T: Copy>(objects: &[(T, Aabb)], query: &Aabb, out: &mut Vec<T>) {
    out.clear();
    out.extend(
        objects
            .iter()
            .filter(|(_, aabb)| aabb.intersects(query))
            .map(|(item, _)| *item),
    );
}
