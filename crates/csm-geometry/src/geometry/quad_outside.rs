//! A cheap certificate that Kratos' quadrilateral iteration calls a point outside a plane
//! quadrilateral: the clipping's inside tests skip the iteration for most of the points they
//! test (a slave node against each of the masters around it).
//!
//! Write the bilinear map of a `Quadrilateral3D4` whose nodes lie in one plane `z = const` as
//! `x(u) = c + A u + h u₁u₂` (`u = (ξ, η)`; `c`, `A = [a b]`, `h` from the nodes), and let
//! `v = A⁻¹(p − c)` (the iteration's first iterate), `R = |v|`, `g = A⁻¹h`, `κ = |g|`. Where
//! `κR ≤ 1/8`, in exact arithmetic:
//!
//! * `x(u) = p` has exactly one root `u*` with `|u*| ≤ 2R` (the map `u ↦ v − g u₁u₂` sends that
//!   ball into itself and contracts by `2κR ≤ 1/4`), and `|u* − v| ≤ κ|u*|²/2 ≤ 0.79 κR²`
//!   (`|u*| ≤ 1.25 R`);
//! * in the plane Kratos' Gauss–Newton step is Newton's, and for this quadratic map its error
//!   obeys `e_{k+1} = J(u_k)⁻¹h · e_{k,1}e_{k,2}` with `|J(u)⁻¹h| = κ / |1 + (u₂, u₁)·g|`: from
//!   `u₀ = 0`, `|e₁| ≤ κ(1.25R)²/2 ≤ 0.1R`, and every later error is at most 1 % of the one
//!   before. So whatever step ends the iteration (converged, "diverged" past its increment
//!   limit, or the iteration limit), the last iterate is `v` itself (after one step) or lies
//!   within `|e₁| ≤ 0.79 κR²` of `u*`.
//!
//! Hence a component with `|v_i| − 1.6 κR² > 1 + tol + m` is beyond `1 + tol` in every iterate
//! the test can see: the point is outside. The margin `m` (`10⁻⁶` of the local coordinates,
//! plus `10⁻¹⁰` of the coordinates' magnitude over the element's size) covers the rounding of
//! the floating-point iteration, whose steps are the exact ones up to relative errors of a few
//! units in the last place of the coordinates (the out-of-plane row of Kratos' Jacobian is
//! such a rounding residue when the nodes and the point share their `z` bits).

use crate::math::{Point, Real};

/// The precomputed certificate of one quadrilateral (see the module documentation).
#[derive(Clone, Copy, Debug)]
pub(crate) struct QuadOutside {
    /// The plane's `z` bits (the nodes', and the point's for the test to apply).
    z: u64,
    c: [Real; 2],
    /// `A⁻¹`, row by row.
    inv: [[Real; 2]; 2],
    /// `κ = |A⁻¹h|`.
    kappa: Real,
    /// The largest coordinate magnitude of the nodes (and `z`).
    magnitude: Real,
    /// The element's smallest extent (`|det A| / max(|a|, |b|)`).
    size: Real,
}

/// The local-coordinates margin of the certificate.
const MARGIN: Real = 1e-6;
/// Its part per unit of coordinate magnitude over element size.
const ROUNDING_MARGIN: Real = 1e-10;
/// The largest `κR` the certificate accepts (the proof's `1/8`, less a rounding allowance).
const KAPPA_R_MAX: Real = 0.12;
/// The bound of `|u* − v| + |e₁|` in units of `κR²` (0.79 + 0.79, rounded up).
const ERROR_FACTOR: Real = 1.6;

impl QuadOutside {
    /// The certificate of the quadrilateral with nodes `x` (Kratos' node order), or `None`
    /// where it does not apply: nodes not in one plane `z = const` (bit for bit), a singular
    /// or badly conditioned map, or non-finite coordinates.
    pub(crate) fn new(x: &[Point]) -> Option<QuadOutside> {
        let [x0, x1, x2, x3] = x else {
            return None;
        };
        let z = x0.z.to_bits();
        if [x1, x2, x3].iter().any(|p| p.z.to_bits() != z) {
            return None;
        }
        let q = |f: fn(Real, Real, Real, Real) -> Real| {
            [f(x0.x, x1.x, x2.x, x3.x), f(x0.y, x1.y, x2.y, x3.y)]
        };
        let c = q(|p0, p1, p2, p3| 0.25 * (p0 + p1 + p2 + p3));
        let a = q(|p0, p1, p2, p3| 0.25 * (-p0 + p1 + p2 - p3));
        let b = q(|p0, p1, p2, p3| 0.25 * (-p0 - p1 + p2 + p3));
        let h = q(|p0, p1, p2, p3| 0.25 * (p0 - p1 + p2 - p3));
        let det = a[0] * b[1] - b[0] * a[1];
        let longest = Real::max(a[0] * a[0] + a[1] * a[1], b[0] * b[0] + b[1] * b[1]).sqrt();
        let size = det.abs() / longest;
        // A well-conditioned map only: its smallest extent at least 10⁻⁶ of its largest.
        if !(size.is_finite() && size > 1e-6 * longest) {
            return None;
        }
        let inv = [[b[1] / det, -b[0] / det], [-a[1] / det, a[0] / det]];
        let g = [
            inv[0][0] * h[0] + inv[0][1] * h[1],
            inv[1][0] * h[0] + inv[1][1] * h[1],
        ];
        let magnitude = x
            .iter()
            .flat_map(|p| [p.x.abs(), p.y.abs(), p.z.abs()])
            .fold(0.0, Real::max);
        let out = QuadOutside {
            z,
            c,
            inv,
            kappa: (g[0] * g[0] + g[1] * g[1]).sqrt(),
            magnitude,
            size,
        };
        let rounding = ROUNDING_MARGIN * magnitude / size;
        (out.kappa.is_finite() && rounding.is_finite()).then_some(out)
    }

    /// Whether Kratos' iteration certainly puts `p` outside the reference square enlarged by
    /// `tolerance` (`|ξ| > 1 + tol` or `|η| > 1 + tol` in its last iterate). False (no
    /// conclusion) for a point off the plane, a non-finite point and wherever the certificate
    /// does not decide.
    pub(crate) fn certainly_outside(&self, p: &Point, tolerance: Real) -> bool {
        if p.z.to_bits() != self.z {
            return false;
        }
        let d = [p.x - self.c[0], p.y - self.c[1]];
        let v = [
            self.inv[0][0] * d[0] + self.inv[0][1] * d[1],
            self.inv[1][0] * d[0] + self.inv[1][1] * d[1],
        ];
        let r = (v[0] * v[0] + v[1] * v[1]).sqrt();
        let kappa_r = self.kappa * r;
        if kappa_r.is_nan() || kappa_r > KAPPA_R_MAX {
            return false;
        }
        // The point's own magnitude enters the rounding too.
        let magnitude = self.magnitude.max(p.x.abs()).max(p.y.abs());
        let rounding = ROUNDING_MARGIN * magnitude / self.size;
        let bound =
            1.0 + tolerance + MARGIN * (1.0 + r) + rounding + ERROR_FACTOR * self.kappa * r * r;
        // NaN makes both comparisons false.
        v[0].abs() > bound || v[1].abs() > bound
    }
}
