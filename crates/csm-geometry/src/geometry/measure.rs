//! Length, area, volume and domain size (Kratos `Length()`, `Area()`, `Volume()`,
//! `DomainSize()`, reference §14 and §17.1).

use super::Geometry;
use super::quadrature::for_each_gauss_point;
use super::unit_normal::DEGENERATE_REL;
use crate::math::{Point, Real, Vector, cross_kratos, norm_kratos};
use crate::{Error, ErrorKind, GeometryKind};

/// Kratos' tetrahedron length factor `(12/√2)^(1/3)`: the edge of a regular tetrahedron of
/// volume `V` is `factor · ∛V`.
pub const TETRAHEDRON_LENGTH_FACTOR: Real = 2.039_648_902_655_5;

/// The largest [`Geometry::area`] of many faces, bit for bit, with its errors, and with less
/// work per 3-node triangle (the mapper's reference area over every face of a contact pair).
///
/// Heron's area is `√r` with the radicand `r = s (s − a)(s − b)(s − c)`. The square root is
/// monotone (IEEE 754 rounds it correctly), so the largest area is the root of the largest
/// radicand: a triangle whose radicand is finite and clearly above the degeneracy floor of
/// [`Geometry::area`] (twice the square of `1e-14 · 3 · (longest edge)²`, which bounds that floor,
/// `1e-14 · (bounding-box diagonal)²`, from above) contributes its radicand, without the area's
/// own root and without the bounding box. Every other face — another kind, a non-finite point,
/// a near-degenerate or underflowing triangle — goes through [`Geometry::new`] and
/// [`Geometry::area`], which give its value or its error.
///
/// `==` compares the accumulated state (the short path's radicand and the other faces' area
/// apart), not only [`LargestArea::value`].
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct LargestArea {
    /// The largest radicand of the triangles taken by the short path (0 without).
    pub(super) radicand: Real,
    /// The largest area of the other faces (0 without).
    other: Real,
}

impl LargestArea {
    /// Takes the face of kind `kind` with the node coordinates `points`.
    ///
    /// Errors: those of [`Geometry::new`] and [`Geometry::area`] for this face.
    #[inline]
    pub fn add(&mut self, kind: GeometryKind, points: &[Point]) -> Result<(), Error> {
        if let (GeometryKind::Triangle3D3 | GeometryKind::Triangle2D3, [p0, p1, p2]) =
            (kind, points)
        {
            // `area_heron`'s operations, in its order, up to the last root.
            let squared = |d: Vector| d.x * d.x + d.y * d.y + d.z * d.z;
            let (a2, b2, c2) = (squared(p0 - p1), squared(p1 - p2), squared(p2 - p0));
            let (a, b, c) = (a2.sqrt(), b2.sqrt(), c2.sqrt());
            let s = (a + b + c) / 2.0;
            let r = s * (s - a) * (s - b) * (s - c);
            let t = DEGENERATE_REL * 3.0 * a2.max(b2).max(c2);
            let clear = 2.0 * (t * t);
            if clear.is_normal() && r.is_finite() && r > clear {
                self.radicand = self.radicand.max(r);
                return Ok(());
            }
        }
        let area = Geometry::new(kind, points)?.area()?;
        self.other = self.other.max(area);
        Ok(())
    }

    /// The larger of the two (the faces of both taken).
    pub fn merge(self, other: LargestArea) -> LargestArea {
        LargestArea {
            radicand: self.radicand.max(other.radicand),
            other: self.other.max(other.other),
        }
    }

    /// The largest area of the faces taken (0 without any): the maximum of their
    /// [`Geometry::area`] values.
    pub fn value(self) -> Real {
        self.radicand.sqrt().max(self.other)
    }
}

impl Geometry<'_> {
    /// Checks a measure of dimension `dim` against the node-cloud scale.
    fn check_measure(&self, value: Real, dim: i32, what: &'static str) -> Result<Real, Error> {
        let floor = DEGENERATE_REL * self.scale().powi(dim);
        if value.is_nan() || value <= floor || value.is_infinite() {
            Err(Error::degenerate(what))
        } else {
            Ok(value)
        }
    }

    /// `∫ |∂x/∂ξ|` (lines), `∫ |∂x/∂ξ × ∂x/∂η|` (2D elements) or `∫ det J` (3D) by the Gauss rule
    /// of the kind; the absolute value of the sum for solids.
    fn integrate_measure(&self) -> Real {
        let mut sum = 0.0;
        for_each_gauss_point(self.kind(), |xi, w| {
            sum += w * self.jacobian_measure(&Point::new(xi[0], xi[1], xi[2]));
        });
        sum.abs()
    }

    /// The Jacobian "determinant" at `local`: tangent norm (lines), normal norm (2D
    /// elements), signed `det J` (3D solids).
    pub fn jacobian_measure(&self, local: &Point) -> Real {
        let j = self.jacobian(local);
        let c0: Vector = j.column(0).into_owned();
        match self.kind().local_dim() {
            1 => norm_kratos(&c0),
            2 => norm_kratos(&cross_kratos(&c0, &j.column(1).into_owned())),
            _ => j.determinant(),
        }
    }

    /// Kratos `Length()` per kind (a characteristic length for non-lines):
    /// * Line2D2: `sqrt(Δx² + Δy²)` (z ignored, as Kratos); Line2D3: arc length (3-point Gauss);
    /// * triangles: `sqrt(2 · Area())` (Heron's area for Triangle3D3/2D3);
    /// * Quadrilateral3D4/2D4: `sqrt(|Area()|)`; quadratic quadrilaterals:
    ///   `sqrt(|det J(0, 0)|)` (Kratos' Quadrilateral3D8 definition);
    /// * tetrahedra: `(12/√2)^(1/3) · ∛|Volume()|`;
    /// * hexahedra and prisms: `sqrt(|det J|)` at the local origin (Kratos evaluates
    ///   `DeterminantOfJacobian(PointType())`, i.e. at ξ = 0: the centre of a hexahedron, node 0
    ///   of a prism).
    ///
    /// Errors: [`ErrorKind::Degenerate`] for a zero (or non-finite) result.
    pub fn length(&self) -> Result<Real, Error> {
        use GeometryKind as K;
        let value = match self.kind() {
            K::Line2D2 => {
                let p = self.points();
                let dx = p[1].x - p[0].x;
                let dy = p[1].y - p[0].y;
                (dx * dx + dy * dy).sqrt()
            }
            K::Line2D3 => self.integrate_measure(),
            K::Triangle3D3 | K::Triangle3D6 | K::Triangle2D3 | K::Triangle2D6 => {
                (2.0 * self.area()?).sqrt()
            }
            K::Quadrilateral3D4 | K::Quadrilateral2D4 => self.area()?.abs().sqrt(),
            K::Quadrilateral3D8
            | K::Quadrilateral3D9
            | K::Quadrilateral2D8
            | K::Quadrilateral2D9 => self.jacobian_measure(&Point::origin()).abs().sqrt(),
            K::Tetrahedra3D4 | K::Tetrahedra3D10 => {
                TETRAHEDRON_LENGTH_FACTOR * self.volume()?.abs().cbrt()
            }
            K::Hexahedra3D8 | K::Hexahedra3D20 | K::Hexahedra3D27 | K::Prism3D6 => {
                self.jacobian_measure(&Point::origin()).abs().sqrt()
            }
        };
        self.check_measure(value, 1, "zero length")
    }

    /// Kratos `Area()`:
    /// * lines: their length (as Kratos' Line2D2);
    /// * Triangle3D3 / Triangle2D3: **Heron's formula** on the edge lengths `a = |x0−x1|`,
    ///   `b = |x1−x2|`, `c = |x2−x0|`, `s = (a+b+c)/2`, `sqrt(s(s−a)(s−b)(s−c))`, literally as
    ///   Kratos (quirk Q45: a sliver can give the square root of a tiny negative number — here an
    ///   error instead of NaN). See [`area_robust`](Self::area_robust) for the cross-product
    ///   variant;
    /// * quadratic triangles and quadrilaterals: Gauss integration of the area element
    ///   (2×2 points for 4-node quadrilaterals — Kratos' default rule —, 3×3 for quadratic ones,
    ///   3 points for triangles).
    ///
    /// Errors: [`ErrorKind::Unsupported`] for 3D solids; [`ErrorKind::Degenerate`] for a zero,
    /// NaN or rounding-noise area.
    pub fn area(&self) -> Result<Real, Error> {
        use GeometryKind as K;
        let value = match self.kind() {
            K::Line2D2 | K::Line2D3 => return self.length(),
            K::Triangle3D3 | K::Triangle2D3 => self.area_heron(),
            K::Tetrahedra3D4
            | K::Tetrahedra3D10
            | K::Hexahedra3D8
            | K::Hexahedra3D20
            | K::Hexahedra3D27
            | K::Prism3D6 => {
                return Err(Error::new(ErrorKind::Unsupported("area of a 3D solid")));
            }
            _ => self.integrate_measure(),
        };
        self.check_measure(value, 2, "zero area")
    }

    /// Heron's formula, Kratos' evaluation order (no checks; may be NaN).
    fn area_heron(&self) -> Real {
        let p = self.points();
        let a = norm_kratos(&(p[0] - p[1]));
        let b = norm_kratos(&(p[1] - p[2]));
        let c = norm_kratos(&(p[2] - p[0]));
        let s = (a + b + c) / 2.0;
        (s * (s - a) * (s - b) * (s - c)).sqrt()
    }

    /// The robust area: for 3-node triangles `½ |(x1 − x0) × (x2 − x0)|` (accurate for slivers,
    /// never NaN); for every other kind the same as [`area`](Self::area). Prefer it wherever
    /// bit-compatibility with Kratos' Heron area is not required (Q45).
    pub fn area_robust(&self) -> Result<Real, Error> {
        match self.kind() {
            GeometryKind::Triangle3D3 | GeometryKind::Triangle2D3 => {
                let p = self.points();
                let value = 0.5 * norm_kratos(&cross_kratos(&(p[1] - p[0]), &(p[2] - p[0])));
                self.check_measure(value, 2, "zero area")
            }
            _ => self.area(),
        }
    }

    /// The volume of a 3D solid: `|det J| / 6` for Tetrahedra3D4, otherwise `|Σ w det J|` by
    /// Gauss integration (2×2×2 for hexahedra, 4 points for tetrahedra, 3×2 for prisms; exact
    /// for straight-sided elements).
    ///
    /// Errors: [`ErrorKind::Unsupported`] for non-3D-solids; [`ErrorKind::Degenerate`] for zero
    /// volume.
    pub fn volume(&self) -> Result<Real, Error> {
        if !(self.kind().is_solid() && self.kind().local_dim() == 3) {
            return Err(Error::new(ErrorKind::Unsupported(
                "volume of a non-3D-solid",
            )));
        }
        let value = if self.kind() == GeometryKind::Tetrahedra3D4 {
            self.jacobian(&Point::origin()).determinant().abs() / 6.0
        } else {
            self.integrate_measure()
        };
        self.check_measure(value, 3, "zero volume")
    }

    /// Kratos `DomainSize()`: [`length`](Self::length) for lines, [`area`](Self::area) for
    /// surfaces and 2D solids, [`volume`](Self::volume) for 3D solids.
    pub fn domain_size(&self) -> Result<Real, Error> {
        match self.kind().local_dim() {
            1 => self.length(),
            2 => self.area(),
            _ => self.volume(),
        }
    }
}
