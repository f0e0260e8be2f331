//! OBB of a face on its normal with the smallest in-plane rectangle (robust mode, Q1 fixed).

use super::Obb;
use super::build_from_aabb::{check_enlargement, half_lengths, unit_cross};
use crate::math::{Real, Vector};
use crate::{Error, Geometry, GeometryKind};

impl Obb {
    /// The box of a face on its own normal whose in-plane rectangle is the smallest one with a
    /// side along an edge of the face (robust mode; Q1 fixed): `A_0` = the unit normal at the
    /// local coordinates of the centre (as branch B), `A_1` = the direction of the corner edge
    /// (projected into the tangent plane) whose rectangle `max|(X_i − c)·A_1| ·
    /// max|(X_i − c)·A_2|` is smallest (first strictly smaller wins), `A_2 = A_0 × A_1`,
    /// `h_k = max_i |(X_i − c)·A_k| + f`.
    ///
    /// Branch B takes `A_1` towards the node farthest from the centre, a choice that flips
    /// between nodes at (nearly) equal distance — every corner of a rectangle — with the
    /// rounding of a rotation, translation or scaling, and with it the box (a rectangle's box
    /// along a diagonal is twice as large): pairs changed under rigid motions. The smallest
    /// edge-aligned rectangle (the minimum-area rectangle of a convex polygon has a side on an
    /// edge) is the same box whichever of equal candidates wins for rectangles, and it is
    /// tighter.
    ///
    /// Errors: as [`build_from_normal`](Self::build_from_normal); `Degenerate` when no edge
    /// has an in-plane direction.
    pub fn build_on_normal_min_area(
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
        let extent = |axis: &Vector| -> Real {
            points
                .iter()
                .map(|p| (p - center).dot(axis).abs())
                .fold(0.0, Real::max)
        };
        let mut best: Option<(Real, Vector, Vector)> = None;
        for i in 0..corners {
            let e: Vector = points[(i + 1) % corners] - points[i];
            let t = e - a0 * e.dot(&a0);
            let n = t.norm();
            if !(n.is_finite() && n > 0.0) {
                continue;
            }
            let a1 = t / n;
            let Ok(a2) = unit_cross(&a0, &a1) else {
                continue;
            };
            let area = extent(&a1) * extent(&a2);
            if best.as_ref().is_none_or(|(b, _, _)| area < *b) {
                best = Some((area, a1, a2));
            }
        }
        let (_, a1, a2) =
            best.ok_or_else(|| Error::degenerate("no in-plane edge direction for the box"))?;
        let axes = [a0, a1, a2];
        let h = half_lengths(points, &center, &axes, enlargement);
        Ok(Obb::new(center, axes, h))
    }
}
