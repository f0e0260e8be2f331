//! Local coordinates of a global point (Kratos `PointLocalCoordinates`, reference §17.1).

use super::Geometry;
use super::unit_normal::DEGENERATE_REL;
use crate::math::{Matrix3, Point, Real, Vector, dot_kratos, is_finite_point};
use crate::{Error, ErrorKind, GeometryKind};

/// Newton tolerance on the norm of the local-coordinate increment (Kratos: 1e-8).
pub const LOCAL_COORDINATES_TOLERANCE: Real = 1e-8;
/// Maximum number of Newton iterations (Kratos: 1000).
pub const LOCAL_COORDINATES_MAX_ITERATIONS: usize = 1000;

impl Geometry<'_> {
    /// The local coordinates `ξ` of the global point `p`.
    ///
    /// * Line2D2: the closed form `ξ = 2 ((p − x0)·(x1 − x0)) / |x1 − x0|² − 1` (projection onto
    ///   the line).
    /// * Every other kind: Gauss–Newton on `x(ξ) = p` starting at the reference centre
    ///   ([`reference_center`](Self::reference_center); Kratos starts at `ξ = 0`, which is the
    ///   same point for lines, quadrilaterals and hexahedra, and gives the same result for affine
    ///   simplices; for quadratic triangles/tetrahedra and prisms the centre start avoids
    ///   converging to a spurious preimage outside the element),
    ///   `Δξ = (JᵀJ)⁻¹ Jᵀ (p − x(ξ))`, stopping when `|Δξ| < 1e-8`, at most 1000 iterations. For
    ///   solids `J` is square and this is Newton's method; for faces it solves in the tangent
    ///   plane, i.e. an off-surface point is projected (the result does not depend on the offset
    ///   along the normal of a flat face). Affine kinds (simplices, parallelograms) converge in
    ///   one step.
    ///
    /// Kratos projects a quadrilateral into a tangent frame before its 2D Newton iteration; for
    /// flat faces that is the same solution, for warped quadrilaterals the two may differ at the
    /// 1e-8 level.
    ///
    /// Errors: [`ErrorKind::NonFinite`] for a non-finite `p`; [`ErrorKind::Degenerate`] when the
    /// Jacobian is singular (zero-length line, zero-area face, flat solid, coincident nodes);
    /// [`ErrorKind::NotConverged`] if the iteration does not converge.
    pub fn point_local_coordinates(&self, p: &Point) -> Result<Point, Error> {
        if !is_finite_point(p) {
            return Err(Error::new(ErrorKind::NonFinite));
        }
        if self.kind() == GeometryKind::Line2D2 {
            let pts = self.points();
            let d = pts[1] - pts[0];
            let l2 = dot_kratos(&d, &d);
            if l2.is_nan() || l2 <= 0.0 || l2.sqrt() <= DEGENERATE_REL * self.scale() {
                return Err(Error::degenerate("zero-length line"));
            }
            let xi = 2.0 * dot_kratos(&(p - pts[0]), &d) / l2 - 1.0;
            return finite(Point::new(xi, 0.0, 0.0));
        }
        let d = self.kind().local_dim();
        let scale = self.scale();
        let mut xi = self.reference_center();
        for _ in 0..LOCAL_COORDINATES_MAX_ITERATIONS {
            let x = self.global_coordinates(&xi);
            let r: Vector = p - x;
            let j = self.jacobian(&xi);
            let mut jtj = j.transpose() * j;
            // Pad the unused local directions with the identity so the matrix is invertible
            // exactly when the used block is.
            for k in d..3 {
                jtj[(k, k)] = 1.0;
            }
            let det = jtj.determinant();
            let det_scale = scale.powi(2 * d as i32);
            if det.is_nan() || det <= (DEGENERATE_REL * DEGENERATE_REL) * det_scale {
                return Err(Error::degenerate("singular Jacobian"));
            }
            let inv: Matrix3 = match jtj.try_inverse() {
                Some(m) => m,
                None => return Err(Error::degenerate("singular Jacobian")),
            };
            let mut delta = inv * (j.transpose() * r);
            for k in d..3 {
                delta[k] = 0.0;
            }
            xi += delta;
            if !is_finite_point(&xi) {
                return Err(Error::new(ErrorKind::NotConverged));
            }
            if delta.norm() < LOCAL_COORDINATES_TOLERANCE {
                return Ok(xi);
            }
        }
        Err(Error::new(ErrorKind::NotConverged))
    }
}

fn finite(p: Point) -> Result<Point, Error> {
    if is_finite_point(&p) {
        Ok(p)
    } else {
        Err(Error::new(ErrorKind::NonFinite))
    }
}
