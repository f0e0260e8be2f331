//! Unit normal of a face geometry at local coordinates (Kratos `UnitNormal`, reference §17.1).

use super::Geometry;
use crate::math::{Point, Real, Vector, cross_kratos, is_finite_vector, norm_kratos};
use crate::{Error, ErrorKind};

/// Relative size below which a tangent or normal vector counts as zero: `|v| ≤ 1e-14 · L^d`
/// with `L` the bounding-box diagonal and `d` the local dimension.
pub(crate) const DEGENERATE_REL: Real = 1e-14;

impl Geometry<'_> {
    /// The non-normalised normal of a face at `local`: for a 2D line, `(t_y, −t_x, 0)` with
    /// `t = ∂x/∂ξ` (pointing to the right of the direction 0 → 1); for a surface,
    /// `∂x/∂ξ × ∂x/∂η` (triangle: `(x1−x0)×(x2−x0)`). Its length is the area (length) element.
    ///
    /// Errors: [`ErrorKind::Unsupported`] for solids.
    pub fn normal(&self, local: &Point) -> Result<Vector, Error> {
        if !self.kind().is_face() {
            return Err(Error::new(ErrorKind::Unsupported(
                "normal of a non-face geometry",
            )));
        }
        let j = self.jacobian(local);
        let t0: Vector = j.column(0).into_owned();
        Ok(if self.kind().local_dim() == 1 {
            Vector::new(t0.y, -t0.x, 0.0)
        } else {
            let t1: Vector = j.column(1).into_owned();
            cross_kratos(&t0, &t1)
        })
    }

    /// The unit normal of a face at `local` (Kratos conventions, see [`normal`](Self::normal)),
    /// normalised by division by its norm.
    ///
    /// Errors: [`ErrorKind::Degenerate`] where the normal has zero (or rounding-noise) length,
    /// e.g. zero-length lines, zero-area faces, coincident nodes — never NaN;
    /// [`ErrorKind::Unsupported`] for solids; [`ErrorKind::NonFinite`] for a non-finite `local`.
    pub fn unit_normal(&self, local: &Point) -> Result<Vector, Error> {
        if !(local.x.is_finite() && local.y.is_finite() && local.z.is_finite()) {
            return Err(Error::new(ErrorKind::NonFinite));
        }
        let n = self.normal(local)?;
        let norm = norm_kratos(&n);
        let scale = self.scale().powi(self.kind().local_dim() as i32);
        if norm.is_nan() || norm <= DEGENERATE_REL * scale || norm.is_infinite() {
            return Err(Error::degenerate("zero-length normal"));
        }
        let u = Vector::new(n.x / norm, n.y / norm, n.z / norm);
        debug_assert!(is_finite_vector(&u));
        Ok(u)
    }
}
