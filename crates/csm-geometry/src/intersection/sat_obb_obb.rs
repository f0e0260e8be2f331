//! Separating-axis test between two OBBs (Kratos `SeparatingAxisTheoremHasIntersection`,
//! reference §7.3; thesis eq. for `GetSeparatingPlane3D`/`GetSeparatingPlane2D`).
//!
//! Sign convention: the functions return **true when the boxes intersect** (no separating axis
//! found); touching boxes intersect.

use super::mode::{CENTRE_ROUNDING_EPS, CROSS_AXIS_GUARD, SatMode, TOUCH_TOLERANCE};
use crate::math::{EPS, Real, Vector, cross_kratos, dot_kratos};
use crate::{Obb, Obb2};

/// One box's axes and half-lengths, as slices so 2D and 3D share the code.
struct Frame<'a> {
    axes: &'a [Vector],
    half_lengths: &'a [Real],
}

/// Kratos `GetSeparatingPlane{2,3}D`: `|t·n| > Σ_k |(A1_k h1_k)·n| + Σ_k |(A2_k h2_k)·n|`,
/// evaluated left to right.
fn separates_kratos(t: &Vector, n: &Vector, f1: &Frame<'_>, f2: &Frame<'_>) -> bool {
    let lhs = dot_kratos(t, n).abs();
    let mut rhs = 0.0;
    let mut first = true;
    for f in [f1, f2] {
        for (a, h) in f.axes.iter().zip(f.half_lengths) {
            let term = dot_kratos(&(a * *h), n).abs();
            // Kratos writes the sum as `x0 + x1 + ...`; start from the first term (0 + x is
            // exact anyway, this only keeps the evaluation literally identical).
            rhs = if first { term } else { rhs + term };
            first = false;
        }
    }
    lhs > rhs
}

/// Robust separation along `n` (normalised here): gap beyond the touching tolerance.
fn separates_robust(t: &Vector, n: &Vector, f1: &Frame<'_>, f2: &Frame<'_>, tol: Real) -> bool {
    let nn = n.norm();
    if nn.is_nan() || nn <= 0.0 || nn.is_infinite() {
        return false;
    }
    let u = n / nn;
    let mut r = 0.0;
    for f in [f1, f2] {
        for (a, h) in f.axes.iter().zip(f.half_lengths) {
            r += h.abs() * a.dot(&u).abs();
        }
    }
    t.dot(&u).abs() - r > tol
}

/// The robust band: `TOUCH_TOLERANCE · (Σ h + |t|) + 16 ε · (|c1|∞ + |c2|∞)` (see
/// [`TOUCH_TOLERANCE`]).
fn band(t: &Vector, c1: &Vector, c2: &Vector, f1: &Frame<'_>, f2: &Frame<'_>) -> Real {
    let h: Real = f1
        .half_lengths
        .iter()
        .chain(f2.half_lengths)
        .map(|h| h.abs())
        .sum();
    TOUCH_TOLERANCE * (h + t.norm()) + CENTRE_ROUNDING_EPS * EPS * (c1.amax() + c2.amax())
}

/// The SAT on two frames with centres `c1`, `c2`.
fn sat(c1: &Vector, c2: &Vector, f1: &Frame<'_>, f2: &Frame<'_>, mode: SatMode) -> bool {
    let t = c2 - c1;
    match mode {
        SatMode::Kratos => {
            for a in f1.axes.iter().chain(f2.axes) {
                if separates_kratos(&t, a, f1, f2) {
                    return false;
                }
            }
            for a in f1.axes {
                for b in f2.axes {
                    if separates_kratos(&t, &cross_kratos(a, b), f1, f2) {
                        return false;
                    }
                }
            }
            true
        }
        SatMode::Robust => {
            let tol = band(&t, c1, c2, f1, f2);
            for a in f1.axes.iter().chain(f2.axes) {
                if separates_robust(&t, a, f1, f2, tol) {
                    return false;
                }
            }
            for a in f1.axes {
                for b in f2.axes {
                    let n = a.cross(b);
                    if n.norm() <= CROSS_AXIS_GUARD * a.norm() * b.norm() {
                        continue;
                    }
                    if separates_robust(&t, &n, f1, f2, tol) {
                        return false;
                    }
                }
            }
            true
        }
    }
}

/// SAT between two 3D OBBs: the 3 axes of `obb1`, the 3 of `obb2`, then the 9 cross products
/// `A1_i × A2_j` (i outer), first separating axis wins. `true` = intersecting. See [`SatMode`]
/// for the two arithmetic modes. Boxes that a common point proves intersecting
/// (`certainly_intersect`) answer `true` without the fifteen axes: the answer the axes give.
pub fn sat_obb_obb(obb1: &Obb, obb2: &Obb, mode: SatMode) -> bool {
    if certainly_intersect(obb1, obb2) {
        return true;
    }
    sat_obb_obb_axes(obb1, obb2, mode)
}

/// [`sat_obb_obb`] by its fifteen axes alone.
pub(super) fn sat_obb_obb_axes(obb1: &Obb, obb2: &Obb, mode: SatMode) -> bool {
    let f1 = Frame {
        axes: &obb1.axes,
        half_lengths: &obb1.half_lengths,
    };
    let f2 = Frame {
        axes: &obb2.axes,
        half_lengths: &obb2.half_lengths,
    };
    sat(&obb1.center.coords, &obb2.center.coords, &f1, &f2, mode)
}

/// The relative margin of [`certainly_intersect`]'s common point (of the boxes' size).
const WITNESS_MARGIN: Real = 1e-9;
/// Its part for the rounding of coordinates far from the origin, in units of `ε · |c|∞`.
const WITNESS_ROUNDING_EPS: Real = 64.0;
/// How far from orthonormal the axes of the box a point is tested in may be.
const WITNESS_ORTHONORMAL: Real = 1e-12;

/// Whether a point lies inside both boxes by a margin `m` (see [`witness`]): then no axis `n`
/// separates them. With `q − c1 = Σ s_k A1_k`, `|s_k| ≤ h1_k − m`, and `c2 − q = Σ r_j A2_j`,
/// `|r_j| ≤ h2_j − m` (orthonormal `A2`), `|t·n| ≤ Σ h1_k |A1_k·n| + Σ h2_j |A2_j·n| − m|n|`,
/// and `m` (`10⁻⁹` of the boxes' size plus `64 ε` of the centres' magnitude) is far above the
/// rounding of either mode's evaluation of both sides, which scales with `|n|` too. So the
/// SAT's answer is `true` in both modes, for every axis, the cross products included.
pub(super) fn certainly_intersect(obb1: &Obb, obb2: &Obb) -> bool {
    witness(obb1, obb2) || witness(obb2, obb1)
}

/// [`certainly_intersect`] with the point `q`: `obb2`'s centre clamped into `obb1` shrunk by
/// the margin (`q − c1 = Σ s_k A1_k` by construction), then tested inside `obb2` shrunk by it
/// (its axes orthonormal within `10⁻¹²`). False for a degenerate box, non-orthonormal axes of
/// `obb2` and anything not finite.
fn witness(obb1: &Obb, obb2: &Obb) -> bool {
    let (c1, c2) = (&obb1.center.coords, &obb2.center.coords);
    let t = c2 - c1;
    let size: Real =
        t.norm() + obb1.half_lengths.iter().sum::<Real>() + obb2.half_lengths.iter().sum::<Real>();
    let m = WITNESS_MARGIN * size + WITNESS_ROUNDING_EPS * EPS * c1.amax().max(c2.amax());
    let mut q = *c1;
    for (a, h) in obb1.axes.iter().zip(&obb1.half_lengths) {
        let limit = h - m;
        if limit.is_nan() || limit <= 0.0 {
            return false;
        }
        q += a * t.dot(a).clamp(-limit, limit);
    }
    let d = q - c2;
    let a2 = &obb2.axes;
    let inside = a2
        .iter()
        .zip(&obb2.half_lengths)
        .all(|(a, h)| d.dot(a).abs() <= h - m);
    // The proof needs `obb2`'s axes orthonormal (checked last: most points that are not
    // inside never need it).
    inside && orthonormal(a2)
}

/// Whether `axes` are orthonormal within [`WITNESS_ORTHONORMAL`] (false for NaN).
fn orthonormal(axes: &[Vector; 3]) -> bool {
    for i in 0..3 {
        for j in i..3 {
            let target = if i == j { 1.0 } else { 0.0 };
            let deviation = (axes[i].dot(&axes[j]) - target).abs();
            if deviation.is_nan() || deviation > WITNESS_ORTHONORMAL {
                return false;
            }
        }
    }
    true
}

/// SAT between two 2D OBBs: `A1_0, A1_1, A2_0, A2_1`, then the 4 cross products (parallel to
/// z; for planar data they never separate, as in Kratos). `true` = intersecting.
pub fn sat_obb2_obb2(obb1: &Obb2, obb2: &Obb2, mode: SatMode) -> bool {
    let f1 = Frame {
        axes: &obb1.axes,
        half_lengths: &obb1.half_lengths,
    };
    let f2 = Frame {
        axes: &obb2.axes,
        half_lengths: &obb2.half_lengths,
    };
    sat(&obb1.center.coords, &obb2.center.coords, &f1, &f2, mode)
}
