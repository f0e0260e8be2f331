//! Stage 8 candidate filters (reference §9): `CheckGeometricalObject` and the map-dependent
//! parts of `CheckCondition`.

use csm_geometry::math::{Real, Vector};

/// `CheckGeometricalObject`'s order-independent part: a condition never pairs with itself, and
/// two faces whose centre normals differ by less than `1e-16 + normal_orientation_threshold`
/// (`|n_A − n_B|`) look the same way and cannot be in contact.
pub fn passes_orientation(
    slave_id: u32,
    master_id: u32,
    slave_normal: &Vector,
    master_normal: &Vector,
    threshold: Real,
) -> bool {
    if slave_id == master_id {
        return false;
    }
    (slave_normal - master_normal).norm() >= 1e-16 + threshold
}

/// `CheckCondition` step 3: the stored condition normals are identical up to 1e-16 (Q46:
/// exactly parallel, same direction only).
pub(crate) fn same_stored_normal(a: &Vector, b: &Vector) -> bool {
    (a - b).norm() < 1e-16
}
