//! OBB of a face on its normal along its first edge (robust mode, Q1 fixed).

use super::Obb;
use super::build_from_aabb::{check_enlargement, half_lengths, unit_cross};
use crate::math::{Real, Vector};
use crate::{Error, Geometry, GeometryKind};

impl Obb {
    /// The box of a face on its own normal with a side along its first edge (robust mode;
    /// Q1 fixed): `A_0` = the unit normal at the local coordinates of the centre (as branch B),
    /// `A_1` = the direction of the first corner edge in the face's node order (`X_1 − X_0`,
    /// or the next edge where that one has no in-plane direction), projected into the tangent
    /// plane, `A_2 = A_0 × A_1`, `h_k = max_i |(X_i − c)·A_k| + f`.
    ///
    /// The choice is combinatorial, so no rigid motion or scaling changes it, and the box
    /// follows the face exactly (up to the rounding of its coordinates). Every rule that picks
    /// among the edges by a measured quantity flips with rounding somewhere: Kratos' branch B
    /// (towards the farthest node) between the corners of a rectangle, and the smallest
    /// edge-aligned rectangle — tried before — between the nearly equal rectangles of
    /// near-equilateral triangles (a gmsh sphere translated by 1e6 changed 16 candidate pairs
    /// even with ties within the coordinates' rounding broken by node order). On rectangles
    /// the first edge gives the smallest box; on other faces the box can be larger than the
    /// smallest (never smaller than needed: it contains the face).
    ///
    /// Errors: as [`build_from_normal`](Self::build_from_normal); `Degenerate` when no edge
    /// has an in-plane direction.
    pub fn build_on_normal_first_edge(
        geometry: &Geometry<'_>,
        enlargement: Real,
    ) -> Result<Obb, Error> {
        check_enlargement(enlargement)?;
        let center = geometry.center();
        let local = geometry.point_local_coordinates(&center)?;
        let a0 = geometry.unit_normal(&local)?;
        let points = geometry.points();
        let corners = match geometry.kind() {
            GeometryKind::Triangle3D3 | GeometryKind::Triangle3D6 => 3,
            GeometryKind::Quadrilateral3D4
            | GeometryKind::Quadrilateral3D8
            | GeometryKind::Quadrilateral3D9 => 4,
            _ => points.len(),
        };
        let (a1, a2) = (0..corners)
            .find_map(|i| {
                let e: Vector = points[(i + 1) % corners] - points[i];
                let t = e - a0 * e.dot(&a0);
                let n = t.norm();
                if !(n.is_finite() && n > 0.0) {
                    return None;
                }
                let a1 = t / n;
                unit_cross(&a0, &a1).ok().map(|a2| (a1, a2))
            })
            .ok_or_else(|| Error::degenerate("no in-plane edge direction for the box"))?;
        let axes = [a0, a1, a2];
        let h = half_lengths(points, &center, &axes, enlargement);
        Ok(Obb::new(center, axes, h))
    }
}
