//! Orthogonal and directional projection of a point onto a plane `(origin, normal)`.

use crate::math::{EPS, Point, Real, Vector, dot_kratos, norm_kratos};

/// Kratos `FastProject`: projects `p` onto the plane through `origin` with (unit) `normal`.
/// Returns `(projected, distance)` with `distance = (p − origin)·n` (positive on the side the
/// normal points to) and `projected = p − n · distance`.
///
/// `normal` is expected to be unit length; it is not normalised. Finite input gives finite
/// output.
pub fn fast_project(origin: &Point, p: &Point, normal: &Vector) -> (Point, Real) {
    let distance = dot_kratos(&(p - origin), normal);
    let projected = Point::new(
        p.x - normal.x * distance,
        p.y - normal.y * distance,
        p.z - normal.z * distance,
    );
    (projected, distance)
}

/// Kratos `FastProjectDirection`: projects `p` onto the plane `(origin, normal)` along
/// `direction`. Returns `(projected, distance)` where `projected = p + direction · distance`:
///
/// * regular case (`|direction · normal| > ε`): `distance = ((origin − p)·n) / (direction·n)`,
///   so `projected` lies on the plane (`distance` is measured in units of `|direction|`);
/// * `|direction| < ε` but `|normal| > ε`: Kratos falls back to
///   `distance = ((origin − p)·n)/|n|` and still moves along the (near-zero) direction, so
///   `projected ≈ p`;
/// * direction parallel to the plane (`|direction · normal| ≤ ε`): Kratos returns
///   **distance 0** and `projected = p` (it only logs a warning); reproduced here.
///
/// `ε` is `f64::EPSILON` (Kratos' `ZeroTolerance`). Finite input gives finite output.
pub fn fast_project_direction(
    origin: &Point,
    p: &Point,
    normal: &Vector,
    direction: &Vector,
) -> (Point, Real) {
    let to_origin = origin - p;
    let distance = if norm_kratos(direction) < EPS && norm_kratos(normal) > EPS {
        dot_kratos(&to_origin, normal) / norm_kratos(normal)
    } else {
        let dn = dot_kratos(direction, normal);
        if dn.abs() > EPS {
            dot_kratos(&to_origin, normal) / dn
        } else {
            return (*p, 0.0);
        }
    };
    let projected = Point::new(
        p.x + direction.x * distance,
        p.y + direction.y * distance,
        p.z + direction.z * distance,
    );
    (projected, distance)
}
