//! OBB construction from the AABB diagonal: Kratos' 2D rule (§7.1) and 3D branch A (§7.2).

use super::{Obb, Obb2};
use crate::math::{EPS, Point, Real, Vector, cross_kratos, dot_kratos, norm_kratos};
use crate::{Error, ErrorKind, Geometry};

pub(crate) const ZERO_NORM: &str = "Zero norm on OrientedBoundingBox direction";

pub(crate) fn check_enlargement(enlargement: Real) -> Result<(), Error> {
    if enlargement.is_finite() {
        Ok(())
    } else {
        Err(Error::new(ErrorKind::NonFinite))
    }
}

/// Divides every component by `d` (ublas `v /= d`).
pub(crate) fn div(v: &Vector, d: Real) -> Vector {
    Vector::new(v.x / d, v.y / d, v.z / d)
}

/// Kratos' `MathUtils::UnitCrossProduct(c, a, b)`: `c = (a × b)/|a × b|`; error for a zero
/// cross product.
pub(crate) fn unit_cross(a: &Vector, b: &Vector) -> Result<Vector, Error> {
    let c = cross_kratos(a, b);
    let n = norm_kratos(&c);
    if n.is_nan() || n <= 0.0 {
        return Err(Error::degenerate(ZERO_NORM));
    }
    Ok(div(&c, n))
}

/// The Hughes–Möller orthonormal completion of the unit vector `a0` (Kratos'
/// `MathUtils::OrthonormalBasis(a0, a1, a2)`): `b = (a0.y, −a0.x, 0)` if `|a0.x| > |a0.z|`,
/// else `(0, a0.z, −a0.y)`; `a2 = b/|b|`; `a1 = (a2 × a0)/|a2 × a0|`. Returns `(a1, a2)`.
pub(crate) fn hughes_moller_basis(a0: &Vector) -> Result<(Vector, Vector), Error> {
    let b = if a0.x.abs() > a0.z.abs() {
        Vector::new(a0.y, -a0.x, 0.0)
    } else {
        Vector::new(0.0, a0.z, -a0.y)
    };
    let nb = norm_kratos(&b);
    if nb.is_nan() || nb <= 0.0 {
        return Err(Error::degenerate(ZERO_NORM));
    }
    let a2 = div(&b, nb);
    let a1 = unit_cross(&a2, a0)?;
    Ok((a1, a2))
}

/// `h_k = max_i |(X_i − c)·A_k| + f` (max starting at 0), as Kratos computes it.
pub(crate) fn half_lengths(
    points: &[Point],
    center: &Point,
    axes: &[Vector; 3],
    f: Real,
) -> [Real; 3] {
    let mut d = [0.0_f64; 3];
    for p in points {
        let v = p - center;
        for k in 0..3 {
            d[k] = d[k].max(dot_kratos(&v, &axes[k]).abs());
        }
    }
    [d[0] + f, d[1] + f, d[2] + f]
}

/// `(hi − lo, |hi − lo|)` of the node AABB, or the "Zero norm" error when `|hi − lo| ≤ ε`.
fn aabb_diagonal(geometry: &Geometry<'_>) -> Result<(Point, Point, Vector, Real), Error> {
    let b = geometry.aabb();
    let d = b.max - b.min;
    let norm = norm_kratos(&d);
    if norm.is_nan() || norm <= EPS {
        return Err(Error::degenerate(ZERO_NORM));
    }
    Ok((b.min, b.max, d, norm))
}

impl Obb {
    /// What [`Obb::build_from_aabb`] (and [`Obb2::from_geometry`]) of `geometry` with
    /// `enlargement` returns, less the box: its errors (a non-finite `enlargement`, a zero AABB
    /// diagonal) at a fraction of the cost, for a caller that needs the box only sometimes but
    /// its errors always. (The rest of the construction cannot fail on the finite points of a
    /// [`Geometry`]: the diagonal's Hughes–Möller completion is exactly perpendicular to it;
    /// tested.)
    pub fn check_build_from_aabb(geometry: &Geometry<'_>, enlargement: Real) -> Result<(), Error> {
        check_enlargement(enlargement)?;
        aabb_diagonal(geometry).map(|_| ())
    }

    /// Kratos' 3D branch A (§7.2): `A_0` = normalised AABB diagonal `(hi − lo)/|hi − lo|`,
    /// `(A_1, A_2)` its Hughes–Möller completion, centre = [`Geometry::center`] (node mean, not
    /// the AABB centre), `h_k = max_i |(X_i − c)·A_k| + f`.
    ///
    /// Errors: `Degenerate("Zero norm on OrientedBoundingBox direction")` when `|hi − lo| ≤ ε`
    /// (all nodes coincident, Q12); `NonFinite` for a non-finite `enlargement`.
    pub fn build_from_aabb(geometry: &Geometry<'_>, enlargement: Real) -> Result<Obb, Error> {
        check_enlargement(enlargement)?;
        let (_, _, d, norm) = aabb_diagonal(geometry)?;
        let a0 = div(&d, norm);
        let (a1, a2) = hughes_moller_basis(&a0)?;
        let center = geometry.center();
        let axes = [a0, a1, a2];
        let half_lengths = half_lengths(geometry.points(), &center, &axes, enlargement);
        Ok(Obb::new(center, axes, half_lengths))
    }
}

impl Obb2 {
    /// Kratos' 2D construction (§7.1; `build_from_bounding_box` is ignored in 2D): `A_0` =
    /// normalised AABB diagonal (non-negative components, quirk Q1), `A_1 = (A_0.y, −A_0.x, 0)`,
    /// centre = AABB centre `0.5 · (lo + hi)`, `h_0 = |hi − lo|/2 + f`, `h_1 = f`.
    ///
    /// Errors: `Degenerate("Zero norm on OrientedBoundingBox direction")` when `|hi − lo| ≤ ε`;
    /// `NonFinite` for a non-finite `enlargement`.
    pub fn from_geometry(geometry: &Geometry<'_>, enlargement: Real) -> Result<Obb2, Error> {
        check_enlargement(enlargement)?;
        let (lo, hi, d, norm) = aabb_diagonal(geometry)?;
        let a0 = div(&d, norm);
        let a1 = Vector::new(a0.y, -a0.x, 0.0);
        let s = lo.coords + hi.coords;
        let center = Point::new(0.5 * s.x, 0.5 * s.y, 0.5 * s.z);
        Ok(Obb2::new(
            center,
            [a0, a1],
            [0.5 * norm + enlargement, enlargement],
        ))
    }
}
