//! Inside test: local coordinates plus the reference-element test with tolerance (Kratos
//! `IsInside`, reference §17.1).

use super::Geometry;
use crate::math::{Point, Real, Vector};
use crate::{Error, ErrorKind, GeometryKind};

impl Geometry<'_> {
    /// Whether the local point `local` lies in the reference element enlarged by `tolerance`:
    /// lines `|ξ| ≤ 1 + tol`; triangles `ξ, η ≥ −tol`, `ξ + η ≤ 1 + tol`; quadrilaterals and
    /// hexahedra `|ξ_k| ≤ 1 + tol`; tetrahedra `ξ, η, ζ ≥ −tol`, `ξ + η + ζ ≤ 1 + tol`; prisms the
    /// triangle test on (ξ, η) and `−tol ≤ ζ ≤ 1 + tol`. Unused directions are ignored.
    pub fn is_inside_local(&self, local: &Point, tolerance: Real) -> bool {
        use GeometryKind as K;
        let (x, y, z) = (local.x, local.y, local.z);
        let lo = -tolerance;
        let hi = 1.0 + tolerance;
        match self.kind() {
            K::Line2D2 | K::Line2D3 => x.abs() <= hi,
            K::Triangle3D3 | K::Triangle3D6 | K::Triangle2D3 | K::Triangle2D6 => {
                x >= lo && y >= lo && x + y <= hi
            }
            K::Quadrilateral3D4
            | K::Quadrilateral3D8
            | K::Quadrilateral3D9
            | K::Quadrilateral2D4
            | K::Quadrilateral2D8
            | K::Quadrilateral2D9 => x.abs() <= hi && y.abs() <= hi,
            K::Hexahedra3D8 | K::Hexahedra3D20 | K::Hexahedra3D27 => {
                x.abs() <= hi && y.abs() <= hi && z.abs() <= hi
            }
            K::Tetrahedra3D4 | K::Tetrahedra3D10 => {
                x >= lo && y >= lo && z >= lo && x + y + z <= hi
            }
            K::Prism3D6 => x >= lo && y >= lo && x + y <= hi && z >= lo && z <= hi,
        }
    }

    /// Kratos `IsInside(p, local, tol)`: computes the local coordinates of `p`
    /// ([`point_local_coordinates`](Self::point_local_coordinates)) and returns them if they pass
    /// the reference-element test ([`is_inside_local`](Self::is_inside_local)). For faces the
    /// point is effectively projected onto the face (no out-of-plane check).
    ///
    /// A point whose local coordinates do not converge is reported as outside (`Ok(None)`),
    /// except for a Quadrilateral3D4, where, as in Kratos, the last iterate of the (Kratos-order)
    /// iteration is tested whatever the outcome.
    /// Errors: degenerate geometry or non-finite input or tolerance.
    pub fn is_inside(&self, p: &Point, tolerance: Real) -> Result<Option<Point>, Error> {
        self.inside_with(
            tolerance,
            || {
                self.point_local_coordinates_kratos_quadrilateral(p)
                    .map(|k| k.local)
            },
            || self.point_local_coordinates(p),
        )
    }

    /// The inside test on local coordinates from `kratos_last_iterate` (a Quadrilateral3D4:
    /// Kratos tests the last iterate whatever the iteration's outcome; a diverged or NaN
    /// iterate fails the test by itself) or `local` (every other kind; not converged is
    /// outside).
    pub(crate) fn inside_with(
        &self,
        tolerance: Real,
        kratos_last_iterate: impl FnOnce() -> Result<Point, Error>,
        local: impl FnOnce() -> Result<Point, Error>,
    ) -> Result<Option<Point>, Error> {
        if !tolerance.is_finite() {
            return Err(Error::new(ErrorKind::NonFinite));
        }
        let local = if self.kind() == GeometryKind::Quadrilateral3D4 {
            kratos_last_iterate()?
        } else {
            match local() {
                Ok(local) => local,
                Err(e) if *e.kind() == ErrorKind::NotConverged => return Ok(None),
                Err(e) => return Err(e),
            }
        };
        Ok(self.is_inside_local(&local, tolerance).then_some(local))
    }
}

impl Geometry<'_> {
    /// Whether `p` lies certainly outside this linear solid (Tetrahedra3D4, Prism3D6,
    /// Hexahedra3D8) enlarged by `tolerance` in local coordinates
    /// ([`is_inside_local`](Self::is_inside_local)), seen along `direction`: `direction · p`
    /// exceeds `direction · x` of every node by more than a margin. The map of these kinds is
    /// affine in each factor of the reference element (simplex × interval), so the image of the
    /// enlarged reference element lies in the convex hull of the images of its corners, which
    /// reach at most `(3t + 4t²) · range` beyond the nodes' range along `direction`; the margin
    /// also covers the convergence tolerance of the local coordinates (`10⁻⁶` of the
    /// bounding-box diagonal, a hundred times `LOCAL_COORDINATES_TOLERANCE` times the Jacobian's
    /// size) and rounding far from the origin.
    ///
    /// Where it returns true, [`is_inside`](Self::is_inside) gives `Ok(None)` for every
    /// iteration that converges (and a non-converged one is outside too). The one answer it
    /// does not give is an error of the iteration: a singular Jacobian at the start, which
    /// [`check_local_coordinates`](Self::check_local_coordinates) reports, or at a later
    /// iterate on the way to the (outside) point, which only a badly distorted element can
    /// reach and which a caller skipping the iteration reads as "outside". False (no
    /// conclusion) for every other kind and for a zero or non-finite direction, point or
    /// tolerance. A cheap exact pre-test for the normal check's probes.
    pub fn separated_along(&self, p: &Point, direction: &Vector, tolerance: Real) -> bool {
        let Some(range) = self.range_along(direction, tolerance) else {
            return false;
        };
        let probe = range.along(p);
        // NaN anywhere makes the comparison false.
        probe > range.hi + range.margin(probe.abs())
    }

    /// Whether [`separated_along`](Self::separated_along)`(base + s·u, direction, tolerance)`
    /// holds, in exact arithmetic and with an allowance for its rounding, for **every**
    /// offset `s ≥ min_offset` and unit vector `u` with `direction · u ≥ cos_floor`
    /// (`direction` a unit vector): the normal check's probes whose offset and direction are
    /// known only by bounds ([`Geometry::centre_probe_bound`]). Along `direction` such a probe
    /// lies at least `direction · base + s · cos_floor` and at most `|direction · base| + s`
    /// from the origin, and the margin grows by `1e-12` per unit of `s` while the probe gains
    /// `cos_floor`, so the smallest offset decides. False (no conclusion) for a `min_offset`
    /// or `cos_floor` that is not positive, and wherever `separated_along` gives false.
    pub fn separated_beyond(
        &self,
        base: &Point,
        direction: &Vector,
        min_offset: Real,
        cos_floor: Real,
        tolerance: Real,
    ) -> bool {
        if !(min_offset > 0.0 && cos_floor > 0.0 && cos_floor <= 1.0) {
            return false;
        }
        let Some(range) = self.range_along(direction, tolerance) else {
            return false;
        };
        let start = range.along(base);
        let farthest = start.abs() + min_offset;
        // The margin at the farthest the probe can be, plus as much again for the rounding
        // of this evaluation.
        let slack = 1e-12 * (range.magnitude + farthest);
        start + min_offset * cos_floor > range.hi + range.margin(farthest) + slack
    }

    /// The nodes' extent along `direction` for [`separated_along`](Self::separated_along):
    /// `None` for a kind it does not decide or a tolerance that is negative or not finite.
    fn range_along(&self, direction: &Vector, tolerance: Real) -> Option<RangeAlong> {
        use GeometryKind as K;
        if !matches!(
            self.kind(),
            K::Tetrahedra3D4 | K::Prism3D6 | K::Hexahedra3D8
        ) || !tolerance.is_finite()
            || tolerance < 0.0
        {
            return None;
        }
        let mut range = RangeAlong {
            direction: *direction,
            lo: Real::INFINITY,
            hi: Real::NEG_INFINITY,
            magnitude: 0.0,
            fixed_margin: 0.0,
        };
        for x in self.points() {
            let a = range.along(x);
            range.lo = range.lo.min(a);
            range.hi = range.hi.max(a);
            range.magnitude = Real::max(range.magnitude, a.abs());
        }
        let d = direction.norm();
        range.fixed_margin = (3.0 * tolerance + 4.0 * tolerance * tolerance)
            * (range.hi - range.lo)
            + 1e-6 * d * self.scale();
        // A zero or non-finite direction, or non-finite points: no conclusion.
        (d > 0.0 && range.fixed_margin.is_finite() && range.magnitude.is_finite()).then_some(range)
    }

    /// The error the local-coordinates iteration of a solid or face raises in its first step,
    /// if any: a singular Jacobian at the reference centre ([`ErrorKind::Degenerate`]).
    /// Callers that skip [`is_inside`](Self::is_inside) on [`separated_along`](
    /// Self::separated_along) report it with this.
    pub fn check_local_coordinates(&self) -> Result<(), Error> {
        self.least_squares_step_matrices(&self.reference_center())
            .1
            .map(|_| ())
    }
}

/// The nodes of a linear solid seen along a direction ([`Geometry::separated_along`]).
struct RangeAlong {
    direction: Vector,
    lo: Real,
    hi: Real,
    /// The largest `|direction · x|` over the nodes.
    magnitude: Real,
    /// The margin's part that does not depend on the probe.
    fixed_margin: Real,
}

impl RangeAlong {
    fn along(&self, x: &Point) -> Real {
        self.direction.x * x.x + self.direction.y * x.y + self.direction.z * x.z
    }

    /// How far beyond `hi` a probe at `|direction · p| = probe` must lie: the enlarged
    /// reference element's reach `(3t + 4t²) · range`, the convergence tolerance of the local
    /// coordinates, and rounding far from the origin.
    fn margin(&self, probe: Real) -> Real {
        self.fixed_margin + 1e-12 * Real::max(self.magnitude, probe)
    }
}
