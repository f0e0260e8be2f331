//! Cheap, certain bounds on a face's centre unit normal and length (the normal check's face
//! probe `Center() + lp · Length() · UnitNormal(ξ(Center()))`) without computing them.

use super::Geometry;
use crate::GeometryKind;
use crate::math::{Real, Vector};

/// What [`Geometry::centre_probe_bound`] guarantees about a face's exact
/// [`centre_unit_normal`](Geometry::centre_unit_normal) `n` and [`length`](Geometry::length)
/// `L`: both succeed, `direction · n ≥ cos_floor` and `L ≥ length_floor`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CentreProbeBound {
    /// A unit vector next to the centre unit normal (the normal at the reference centre).
    pub direction: Vector,
    /// A lower bound of `direction · n` (positive).
    pub cos_floor: Real,
    /// A lower bound of `L` (positive).
    pub length_floor: Real,
}

/// The smallest `|normal at the centre| / scale²` [`Geometry::centre_probe_bound`] accepts:
/// far above every degeneracy threshold, so that the exact computations certainly succeed
/// and the rounding bounds below stay small.
const MIN_SHAPE: Real = 1e-3;
/// Relative slack on the length bound: covers the rounding of Heron's formula on a face of
/// shape at least [`MIN_SHAPE`] (relative error below 1e-7) and of the Gauss sum.
const LENGTH_SLACK: Real = 1e-6;
/// Unit roundoff of `f64`.
const UNIT_ROUNDOFF: Real = Real::EPSILON / 2.0;

impl Geometry<'_> {
    /// Bounds on this face's exact centre unit normal and length (what Kratos' normal check
    /// multiplies into its face probe), computed from the normal at the reference centre
    /// only; `None` (no conclusion) unless it is a Triangle3D3 or a Quadrilateral3D4 with
    /// finite points whose normal at the centre is at least `1e-3 · scale²` long.
    ///
    /// Why the bounds hold, with `A` the normal `∂x/∂ξ × ∂x/∂η` at the reference centre:
    /// * Triangle3D3: the normal is constant; [`centre_unit_normal`](Self::centre_unit_normal)
    ///   is `A/|A|` up to rounding, and `Length() = sqrt(2 · Heron area)`, with Heron's
    ///   relative error below 1e-7 on such a triangle (every `s − a` is at least `7e-8 · scale`), so `L ≥ sqrt(|A| (1 − 1e-6))`.
    /// * Quadrilateral3D4: the normal is linear in the local coordinates,
    ///   `n(ξ, η) = A + ξ B + η C` (`B = e₁ × e₃`, `C = e₃ × e₂`, with `e₁`, `e₂` the tangents at
    ///   the centre and `e₃` the bilinear term). The 2×2 Gauss area is `Σ |n(g)| ≥ |Σ n(g)| =
    ///   4 |A|` (the points are symmetric), so `L = sqrt(area) ≥ sqrt(4 |A| (1 − 1e-6))`. Kratos'
    ///   iteration for the centre's local coordinates starts at 0 with the residual
    ///   `Center() − x(0)`, which is rounding only (`|r| ≤ 64 u R √3`, `R` the largest
    ///   coordinate); its step is at most `δ = 2 |r| |D|_F / |A|` (the smaller singular value
    ///   of the tangents `D` is at least `|A| / |D|_F`). When `δ < 1e-9` it converges in that
    ///   step (below the 1e-8 tolerance), and the normal there is within `ρ = δ (|B| + |C|)`
    ///   of `A`, so `direction · n ≥ 1 − 2ρ/|A|` (less a rounding allowance). The condition
    ///   `δ < 1e-9` also bounds the largest coordinate to about 1e4 face sizes, which keeps the
    ///   rounding of the exact Jacobians (proportional to `u R`) far inside the length and
    ///   cosine allowances: a mesh farther from its origin than that takes the exact probe.
    ///
    /// In both cases the degeneracy tests of the local coordinates (`det ≤ 1e-28 · scale⁴`),
    /// of the normal (`≤ 1e-14 · scale²`) and of the length are far from reached.
    pub fn centre_probe_bound(&self) -> Option<CentreProbeBound> {
        let p = self.points();
        // Finite points whose mean overflows: the exact centre is not finite.
        if p.iter().any(|x| !crate::math::is_finite_point(x))
            || !crate::math::is_finite_point(&self.center())
        {
            return None;
        }
        let scale = self.scale();
        let (a, norm, cos_floor, area_floor) = match self.kind() {
            GeometryKind::Triangle3D3 => {
                let a = (p[1] - p[0]).cross(&(p[2] - p[0]));
                let norm = a.norm();
                (a, norm, 1.0 - 1e-12, norm * (1.0 - LENGTH_SLACK))
            }
            GeometryKind::Quadrilateral3D4 => {
                let e1 = 0.25 * ((p[1] - p[0]) + (p[2] - p[3]));
                let e2 = 0.25 * ((p[3] - p[0]) + (p[2] - p[1]));
                let e3 = 0.25 * ((p[0] - p[1]) + (p[2] - p[3]));
                let a = e1.cross(&e2);
                let norm = a.norm();
                let largest = p
                    .iter()
                    .flat_map(|x| x.coords.iter().map(|c| c.abs()))
                    .fold(0.0, Real::max);
                let residual = 64.0 * UNIT_ROUNDOFF * largest * Real::sqrt(3.0);
                let d_frobenius = (e1.norm_squared() + e2.norm_squared()).sqrt();
                let step = 2.0 * residual * d_frobenius / norm;
                // (NaN: no conclusion.)
                if step.is_nan() || step >= 1e-9 {
                    return None;
                }
                let rho = step * (e1.cross(&e3).norm() + e3.cross(&e2).norm());
                (
                    a,
                    norm,
                    1.0 - 2.0 * rho / norm - 1e-12,
                    4.0 * norm * (1.0 - LENGTH_SLACK),
                )
            }
            _ => return None,
        };
        let shaped = norm >= MIN_SHAPE * scale * scale && norm.is_finite();
        // NaN fails both comparisons: no conclusion.
        if !shaped || cos_floor.is_nan() || cos_floor <= 0.5 {
            return None;
        }
        Some(CentreProbeBound {
            direction: a / norm,
            cos_floor,
            length_floor: area_floor.sqrt(),
        })
    }
}
