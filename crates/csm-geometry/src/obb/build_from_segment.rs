//! 2D OBB along the segment (robust mode's fix of quirk Q1).

use super::Obb2;
use super::build_from_aabb::check_enlargement;
use crate::math::{Point, Real, Vector};
use crate::{Error, Geometry};

impl Obb2 {
    /// The box of a line along its own direction (robust mode, Q1 fixed): `A_0` = the unit
    /// vector from the first to the second node, `A_1 = (A_0.y, −A_0.x, 0)`, centre = the mean
    /// of the end nodes, `h_0 = max_i |(X_i − c)·A_0| + f`, `h_1 = max_i |(X_i − c)·A_1| + f`
    /// (a quadratic line's middle node widens `h_1`). Unlike Kratos' AABB-diagonal axis, the box
    /// covers the whole segment whatever its direction, so it turns with the mesh.
    ///
    /// Errors: `Degenerate` for coincident end nodes; `NonFinite` for a non-finite
    /// `enlargement` or coordinates.
    pub fn build_from_segment(geometry: &Geometry<'_>, enlargement: Real) -> Result<Obb2, Error> {
        check_enlargement(enlargement)?;
        let pts = geometry.points();
        let d: Vector = pts[1] - pts[0];
        let len = d.norm();
        if !len.is_finite() {
            return Err(Error::new(crate::ErrorKind::NonFinite));
        }
        if len <= 0.0 {
            return Err(Error::degenerate("zero-length segment"));
        }
        let a0 = d / len;
        let a1 = Vector::new(a0.y, -a0.x, 0.0);
        let center = Point::from((pts[0].coords + pts[1].coords) * 0.5);
        let (mut h0, mut h1): (Real, Real) = (0.0, 0.0);
        for p in pts {
            let v = p - center;
            h0 = h0.max(v.dot(&a0).abs());
            h1 = h1.max(v.dot(&a1).abs());
        }
        Ok(Obb2::new(
            center,
            [a0, a1],
            [h0 + enlargement, h1 + enlargement],
        ))
    }
}
