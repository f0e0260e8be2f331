//! OBB construction from the face normal: Kratos' 3D branch B (§7.2).

use super::Obb;
use super::build_from_aabb::{
    check_enlargement, div, half_lengths, hughes_moller_basis, unit_cross,
};
use crate::math::{Real, Vector, dot_kratos, norm_kratos};
use crate::{Error, Geometry};

impl Obb {
    /// Kratos' 3D branch B (§7.2, used for faces when `build_from_bounding_box` is false):
    /// centre `c` = [`Geometry::center`]; `A_0` = unit normal at the local coordinates of `c`;
    /// temporary `(A_1, A_2)` = Hughes–Möller completion of `A_0`; the farthest node in the
    /// tangent plane (in-plane distance `sqrt(((X_i−c)·A_1)² + ((X_i−c)·A_2)²)`, first strictly
    /// larger wins, starting from node 0); `v = c − X_far`;
    /// `A_1 = ((v·A_1) A_1 + (v·A_2) A_2)/|…|`; `A_2 = (A_1 × A_0)/|A_1 × A_0|` (note the order:
    /// the frame is left-handed, as in Kratos); `h_k = max_i |(X_i − c)·A_k| + f`.
    ///
    /// Errors: whatever [`Geometry::point_local_coordinates`] / [`Geometry::unit_normal`] report
    /// for a degenerate face; `Degenerate` where Kratos would divide by zero (all nodes at the
    /// centre in the tangent plane).
    pub fn build_from_normal(geometry: &Geometry<'_>, enlargement: Real) -> Result<Obb, Error> {
        check_enlargement(enlargement)?;
        let center = geometry.center();
        let local = geometry.point_local_coordinates(&center)?;
        let a0 = geometry.unit_normal(&local)?;
        let (t1, t2) = hughes_moller_basis(&a0)?;

        let mut distance = 0.0;
        let mut far = 0;
        for (i, p) in geometry.points().iter().enumerate() {
            // Kratos `MortarUtilities::RotatePoint(p, c, A_1, A_2, false)` then
            // `norm_2(rotated − c)`: the in-plane coordinates are shifted by `c` and back, with
            // the same rounding.
            let v = p - center;
            let rotated = Vector::new(
                dot_kratos(&v, &t1) + center.x,
                dot_kratos(&v, &t2) + center.y,
                0.0 + center.z,
            );
            let d = norm_kratos(&(rotated - center.coords));
            if distance < d {
                far = i;
                distance = d;
            }
        }
        let v = center - geometry.points()[far];
        let (s1, s2) = (dot_kratos(&v, &t1), dot_kratos(&v, &t2));
        let a1_raw = Vector::new(
            s1 * t1.x + s2 * t2.x,
            s1 * t1.y + s2 * t2.y,
            s1 * t1.z + s2 * t2.z,
        );
        let n1 = norm_kratos(&a1_raw);
        if n1.is_nan() || n1 <= 0.0 {
            return Err(Error::degenerate(
                "zero in-plane extent in OrientedBoundingBox",
            ));
        }
        let a1 = div(&a1_raw, n1);
        let a2 = unit_cross(&a1, &a0)?;
        let axes = [a0, a1, a2];
        let h = half_lengths(geometry.points(), &center, &axes, enlargement);
        Ok(Obb::new(center, axes, h))
    }
}
