//! OBB of a face on its normal with the smallest in-plane rectangle (robust mode, Q1 fixed).

use super::Obb;
use super::build_from_aabb::{check_enlargement, half_lengths, unit_cross};
use crate::math::{EPS, Real, Vector};
use crate::{Error, Geometry, GeometryKind};

/// The relative difference below which two in-plane rectangles of
/// [`Obb::build_on_normal_min_area`] tie (the first edge in node order wins).
pub const OBB_TIE_TOLERANCE: Real = 1e-9;

impl Obb {
    /// The box of a face on its own normal whose in-plane rectangle is the smallest one with a
    /// side along an edge of the face (robust mode; Q1 fixed): `A_0` = the unit normal at the
    /// local coordinates of the centre (as branch B), `A_1` = the direction of the corner edge
    /// (projected into the tangent plane) whose rectangle `max|(X_i − c)·A_1| ·
    /// max|(X_i − c)·A_2|` is smallest, `A_2 = A_0 × A_1`, `h_k = max_i |(X_i − c)·A_k| + f`.
    /// Rectangles within [`OBB_TIE_TOLERANCE`] (relative) of the smallest, plus the rounding
    /// of the coordinates (`64·ε·|c| / L`, `L` the largest extent), tie, and of those the
    /// first edge in the face's node order wins: an equilateral triangle's three rectangles
    /// are equal, and without the rule the rounding of a motion picked one of its three boxes
    /// (SAT verdicts changed with margins of 1e-3 h).
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
        // The candidates in node order: (area, A_1, A_2, largest extent).
        let mut candidates = [(0.0, Vector::zeros(), Vector::zeros(), 0.0); 4];
        let mut count = 0;
        for i in 0..corners.min(candidates.len()) {
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
            let (e1, e2) = (extent(&a1), extent(&a2));
            candidates[count] = (e1 * e2, a1, a2, e1.max(e2));
            count += 1;
        }
        let candidates = &candidates[..count];
        let smallest = candidates
            .iter()
            .map(|c| c.0)
            .fold(Real::INFINITY, Real::min);
        let size = candidates.iter().map(|c| c.3).fold(0.0, Real::max);
        let tie = OBB_TIE_TOLERANCE + 64.0 * EPS * center.coords.norm() / size;
        let (_, a1, a2, _) = candidates
            .iter()
            .find(|c| c.0 <= smallest * (1.0 + tie))
            .copied()
            .ok_or_else(|| Error::degenerate("no in-plane edge direction for the box"))?;
        let axes = [a0, a1, a2];
        let h = half_lengths(points, &center, &axes, enlargement);
        Ok(Obb::new(center, axes, h))
    }
}
