//! The one scalar type and the concrete 3D aliases every csm crate uses.
//!
//! 2D problems keep three coordinates with z = 0, as Kratos does.

/// The scalar type of all geometry.
pub type Real = f64;
/// A point in space (2D points have z = 0).
pub type Point = nalgebra::Point3<Real>;
/// A vector in space.
pub type Vector = nalgebra::Vector3<Real>;
/// A 3×3 matrix.
pub type Matrix3 = nalgebra::Matrix3<Real>;

/// Kratos' `ZeroTolerance`: `std::numeric_limits<double>::epsilon()`.
pub const EPS: Real = f64::EPSILON;

/// Dot product evaluated as Kratos (`boost::ublas::inner_prod`) evaluates it:
/// `a0*b0 + a1*b1 + a2*b2`, left to right, no fused multiply-add.
#[inline]
pub fn dot_kratos(a: &Vector, b: &Vector) -> Real {
    a.x * b.x + a.y * b.y + a.z * b.z
}

/// Cross product evaluated as Kratos' `MathUtils::CrossProduct`:
/// `(a1*b2 - a2*b1, a2*b0 - a0*b2, a0*b1 - a1*b0)`.
#[inline]
pub fn cross_kratos(a: &Vector, b: &Vector) -> Vector {
    Vector::new(
        a.y * b.z - a.z * b.y,
        a.z * b.x - a.x * b.z,
        a.x * b.y - a.y * b.x,
    )
}

/// Euclidean norm evaluated as `boost::ublas::norm_2`: `sqrt(a0*a0 + a1*a1 + a2*a2)`.
#[inline]
pub fn norm_kratos(a: &Vector) -> Real {
    (a.x * a.x + a.y * a.y + a.z * a.z).sqrt()
}

/// True if every coordinate of `p` is finite.
#[inline]
pub fn is_finite_point(p: &Point) -> bool {
    p.x.is_finite() && p.y.is_finite() && p.z.is_finite()
}

/// True if every component of `v` is finite.
#[inline]
pub fn is_finite_vector(v: &Vector) -> bool {
    v.x.is_finite() && v.y.is_finite() && v.z.is_finite()
}
