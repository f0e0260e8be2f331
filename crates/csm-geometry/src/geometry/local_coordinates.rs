//! Local coordinates of a global point (Kratos `PointLocalCoordinates`, reference §17.1).

use super::Geometry;
use super::quad_outside::QuadOutside;
use super::unit_normal::DEGENERATE_REL;
use crate::math::{Matrix3, Point, Real, Vector, dot_kratos, is_finite_point};
use crate::{Error, ErrorKind, GeometryKind};

/// Newton tolerance on the norm of the local-coordinate increment (Kratos: 1e-8).
pub const LOCAL_COORDINATES_TOLERANCE: Real = 1e-8;
/// Maximum number of Newton iterations (Kratos: 1000).
pub const LOCAL_COORDINATES_MAX_ITERATIONS: usize = 1000;

/// Runs `solve` on `geometry` and `p`; where it does not converge, runs it again on the points
/// and `p` relative to the first node (the local coordinates do not depend on a translation).
fn relative_fallback(
    geometry: &Geometry<'_>,
    p: &Point,
    solve: fn(&Geometry<'_>, &Point) -> Result<Point, Error>,
) -> Result<Point, Error> {
    match solve(geometry, p) {
        Err(e) if matches!(e.kind(), ErrorKind::NotConverged) => {
            let origin = geometry.points()[0];
            let shifted: Vec<Point> = geometry
                .points()
                .iter()
                .map(|q| Point::from(q - origin))
                .collect();
            let relative = Geometry::new(geometry.kind(), &shifted)?;
            solve(&relative, &Point::from(p - origin))
        }
        r => r,
    }
}

impl Geometry<'_> {
    /// The local coordinates `ξ` of the global point `p`.
    ///
    /// * Line2D2: the closed form `ξ = 2 ((p − x0)·(x1 − x0)) / |x1 − x0|² − 1` (projection onto
    ///   the line).
    /// * Quadrilateral3D4: Kratos' own Gauss–Newton iteration, reproduced operation for operation
    ///   (the crate-internal `point_local_coordinates_kratos_quadrilateral`),
    ///   so that local coordinates — and hence inside tests — of warped quadrilaterals agree with
    ///   Kratos bit for bit. It is the same mathematical iteration as the generic one below (start
    ///   at `ξ = 0`, least squares in the tangent plane); only the floating-point evaluation order
    ///   and the stopping rules are Kratos' (at most 500 iterations; a step longer than 300 stops
    ///   it). Kratos would return the last iterate of a non-converged iteration; this returns
    ///   [`ErrorKind::NotConverged`] instead, while [`is_inside`](Self::is_inside) tests that last
    ///   iterate exactly as Kratos' `IsInside` does.
    /// * Every other kind: [`point_local_coordinates_least_squares`](Self::point_local_coordinates_least_squares).
    ///
    /// Errors: [`ErrorKind::NonFinite`] for a non-finite `p`; [`ErrorKind::Degenerate`] when the
    /// Jacobian is singular (zero-length line, zero-area face, flat solid, coincident nodes);
    /// [`ErrorKind::NotConverged`] if the iteration does not converge.
    ///
    /// Far from the origin (a mesh translated by 1e6, or elements 1e-4 wide at 1e2) the
    /// residual `p − x(ξ)` is rounding noise larger than the tolerance allows, and the
    /// iteration in absolute coordinates cannot converge. Where it does not, the iteration is
    /// repeated on the points relative to the first node (translation-invariant; same result
    /// up to rounding). Results that converge in absolute coordinates — all of Kratos'
    /// fixtures — are unchanged (stability suite, `docs/stability.md`).
    pub fn point_local_coordinates(&self, p: &Point) -> Result<Point, Error> {
        relative_fallback(self, p, |g, q| g.point_local_coordinates_absolute(q))
    }

    fn point_local_coordinates_absolute(&self, p: &Point) -> Result<Point, Error> {
        if !is_finite_point(p) {
            return Err(Error::new(ErrorKind::NonFinite));
        }
        match self.kind() {
            GeometryKind::Line2D2 => {
                let pts = self.points();
                let d = pts[1] - pts[0];
                let l2 = dot_kratos(&d, &d);
                if l2.is_nan() || l2 <= 0.0 || l2.sqrt() <= DEGENERATE_REL * self.scale() {
                    return Err(Error::degenerate("zero-length line"));
                }
                let xi = 2.0 * dot_kratos(&(p - pts[0]), &d) / l2 - 1.0;
                finite(Point::new(xi, 0.0, 0.0))
            }
            GeometryKind::Triangle3D3 => self.point_local_coordinates_kratos_triangle(p),
            GeometryKind::Quadrilateral3D4 => {
                let newton = self.point_local_coordinates_kratos_quadrilateral(p)?;
                match newton.outcome {
                    NewtonOutcome::Converged => Ok(newton.local),
                    NewtonOutcome::Diverged | NewtonOutcome::MaxIterations => {
                        Err(Error::new(ErrorKind::NotConverged))
                    }
                }
            }
            _ => self.point_local_coordinates_least_squares_absolute(p),
        }
    }

    /// Kratos' `Triangle3D3::PointLocalCoordinates`, operation for operation: the point and the
    /// nodes are mapped about the centre `c` by the rows `t_ξ = (x1 − x0)/|x1 − x0|`,
    /// `t_η = (x2 − x0)/|x2 − x0|` (not orthogonal: an affine image of the plane, which leaves
    /// the local coordinates unchanged), then ξ, η come from the 2×2 closed form relative to
    /// node 0. A node gives exactly its reference coordinates, so a node shared by two faces is
    /// inside both with Kratos' tolerance ε, as in Kratos (DirectCheck on a self-contact
    /// surface activates the nodes a slave shares with its neighbours); the generic
    /// least-squares iteration is off by a few ulps there.
    fn point_local_coordinates_kratos_triangle(&self, p: &Point) -> Result<Point, Error> {
        let pts = self.points();
        let unit = |v: Vector| -> Result<Vector, Error> {
            let n = v.norm();
            if n.is_nan() || n <= DEGENERATE_REL * self.scale() {
                return Err(Error::degenerate("zero-length triangle edge"));
            }
            Ok(v / n)
        };
        let t_xi = unit(pts[1] - pts[0])?;
        let t_eta = unit(pts[2] - pts[0])?;
        let c = Point::from((pts[0].coords + pts[1].coords + pts[2].coords) / 3.0);
        let map = |q: &Point| -> (Real, Real) {
            let a = q - c;
            (
                t_xi.x * a.x + t_xi.y * a.y + t_xi.z * a.z + c.x,
                t_eta.x * a.x + t_eta.y * a.y + t_eta.z * a.z + c.y,
            )
        };
        let (dx, dy) = map(p);
        let r = [map(&pts[0]), map(&pts[1]), map(&pts[2])];
        let j00 = r[1].0 - r[0].0;
        let j01 = r[2].0 - r[0].0;
        let j10 = r[1].1 - r[0].1;
        let j11 = r[2].1 - r[0].1;
        let det = j00 * j11 - j01 * j10;
        if det.is_nan() || det.abs() <= DEGENERATE_REL * DEGENERATE_REL * self.scale().powi(2) {
            return Err(Error::degenerate("zero-area triangle"));
        }
        let eta = (j10 * (r[0].0 - dx) + j00 * (dy - r[0].1)) / det;
        let xi = (j11 * (dx - r[0].0) + j01 * (r[0].1 - dy)) / det;
        finite(Point::new(xi, eta, 0.0))
    }

    /// Generic Gauss–Newton on `x(ξ) = p` starting at the reference centre
    /// ([`reference_center`](Self::reference_center); Kratos starts at `ξ = 0`, which is the same
    /// point for lines, quadrilaterals and hexahedra, and gives the same result for affine
    /// simplices; for quadratic triangles/tetrahedra and prisms the centre start avoids converging
    /// to a spurious preimage outside the element), `Δξ = (JᵀJ)⁻¹ Jᵀ (p − x(ξ))`, stopping when
    /// `|Δξ| < 1e-8`, at most 1000 iterations. For solids `J` is square and this is Newton's
    /// method; for faces it solves in the tangent plane, i.e. an off-surface point is projected
    /// (the result does not depend on the offset along the normal of a flat face). Affine kinds
    /// (simplices, parallelograms) converge in one step.
    ///
    /// This is what [`point_local_coordinates`](Self::point_local_coordinates) uses for every
    /// kind except Line2D2 and Quadrilateral3D4; it is available for those too (for a
    /// Quadrilateral3D4 it agrees with the Kratos-order iteration to about 1e-8 relative, the
    /// convergence tolerance, but not bit for bit).
    ///
    /// Errors: as [`point_local_coordinates`](Self::point_local_coordinates).
    /// Like [`point_local_coordinates`](Self::point_local_coordinates), an iteration that does
    /// not converge in absolute coordinates is repeated relative to the first node.
    pub fn point_local_coordinates_least_squares(&self, p: &Point) -> Result<Point, Error> {
        relative_fallback(self, p, |g, q| {
            g.point_local_coordinates_least_squares_absolute(q)
        })
    }

    fn point_local_coordinates_least_squares_absolute(&self, p: &Point) -> Result<Point, Error> {
        self.least_squares_iterate(p, None)
    }

    /// The Gauss–Newton step's matrices at `ξ`: `J`, and `(JᵀJ)⁻¹` (unused directions padded
    /// with the identity) or the singular-Jacobian error.
    pub(crate) fn least_squares_step_matrices(
        &self,
        xi: &Point,
    ) -> (Matrix3, Result<Matrix3, Error>) {
        let d = self.kind().local_dim();
        let j = self.jacobian(xi);
        let mut jtj = j.transpose() * j;
        // Pad the unused local directions with the identity so the matrix is invertible
        // exactly when the used block is.
        for k in d..3 {
            jtj[(k, k)] = 1.0;
        }
        let det = jtj.determinant();
        let det_scale = self.scale().powi(2 * d as i32);
        if det.is_nan() || det <= (DEGENERATE_REL * DEGENERATE_REL) * det_scale {
            return (j, Err(Error::degenerate("singular Jacobian")));
        }
        match jtj.try_inverse() {
            Some(inv) => (j, Ok(inv)),
            None => (j, Err(Error::degenerate("singular Jacobian"))),
        }
    }

    /// The generic Gauss–Newton iteration; `affine` (the step matrices of a kind whose
    /// Jacobian does not depend on `ξ`, computed once by
    /// [`least_squares_step_matrices`](Self::least_squares_step_matrices)) replaces their
    /// computation in every iteration (the same bits).
    fn least_squares_iterate(
        &self,
        p: &Point,
        affine: Option<(&Matrix3, &Matrix3)>,
    ) -> Result<Point, Error> {
        if !is_finite_point(p) {
            return Err(Error::new(ErrorKind::NonFinite));
        }
        let d = self.kind().local_dim();
        let mut xi = self.reference_center();
        for _ in 0..LOCAL_COORDINATES_MAX_ITERATIONS {
            let x = self.global_coordinates(&xi);
            let r: Vector = p - x;
            let computed;
            let (j, inv) = match affine {
                Some(m) => m,
                None => {
                    computed = self.least_squares_step_matrices(&xi);
                    (&computed.0, computed.1.as_ref().map_err(Clone::clone)?)
                }
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

/// A geometry's local-coordinates solver with the work that does not depend on the point done
/// once, for many points on one geometry (the mortar integration points): the first step of
/// Kratos' quadrilateral iteration, the constant Jacobian and its normal-matrix inverse of the
/// linear simplices. Every answer is bit for bit the geometry's own
/// ([`Geometry::point_local_coordinates`]; tested).
#[derive(Clone, Debug)]
pub struct LocalCoordinatesSolver<'a> {
    geometry: Geometry<'a>,
    start: SolverStart,
}

/// A [`LocalCoordinatesSolver`]'s point-independent work, without its geometry.
#[derive(Clone, Debug)]
pub(crate) struct PreparedSolver(SolverStart);

#[derive(Clone, Debug)]
enum SolverStart {
    /// The first step, and the inside tests' certificate where it applies.
    Quadrilateral(QuadStart, Option<QuadOutside>),
    /// `J` and `(JᵀJ)⁻¹`; `None` for a singular Jacobian (the geometry's own path then gives
    /// the error).
    Affine(Matrix3, Option<Matrix3>),
    Other,
}

impl<'a> LocalCoordinatesSolver<'a> {
    /// Prepares the solver of `geometry`.
    pub fn new(geometry: Geometry<'a>) -> LocalCoordinatesSolver<'a> {
        let start = match geometry.kind() {
            GeometryKind::Quadrilateral3D4 => {
                SolverStart::Quadrilateral(geometry.kratos_quadrilateral_start(), None)
            }
            GeometryKind::Triangle2D3 | GeometryKind::Tetrahedra3D4 => {
                let xi = geometry.reference_center();
                let (j, inv) = geometry.least_squares_step_matrices(&xi);
                SolverStart::Affine(j, inv.ok())
            }
            _ => SolverStart::Other,
        };
        LocalCoordinatesSolver { geometry, start }
    }

    /// The solver with the certificate that lets [`is_inside`](Self::is_inside) skip the
    /// iteration for most points outside a plane quadrilateral (`quad_outside`): for a
    /// solver that will test several points (the same answers; it costs a little to make).
    pub(crate) fn with_outside_certificate(mut self) -> LocalCoordinatesSolver<'a> {
        if let SolverStart::Quadrilateral(_, certificate) = &mut self.start {
            *certificate = QuadOutside::new(self.geometry.points());
        }
        self
    }

    /// The geometry.
    pub fn geometry(&self) -> &Geometry<'a> {
        &self.geometry
    }

    /// The prepared work, to make the same solver again for a copy of the same points
    /// ([`from_prepared`](Self::from_prepared)).
    pub(crate) fn prepared(&self) -> PreparedSolver {
        PreparedSolver(self.start.clone())
    }

    /// The solver of `geometry` from the work `prepared` by a solver of the same kind and
    /// points (a copy of them, in another buffer): every answer is that solver's.
    pub(crate) fn from_prepared(
        geometry: Geometry<'a>,
        prepared: &PreparedSolver,
    ) -> LocalCoordinatesSolver<'a> {
        LocalCoordinatesSolver {
            geometry,
            start: prepared.0.clone(),
        }
    }

    /// [`Geometry::point_local_coordinates`] of `p` (same result, same errors).
    pub fn local_coordinates(&self, p: &Point) -> Result<Point, Error> {
        let g = &self.geometry;
        let absolute = match &self.start {
            SolverStart::Quadrilateral(s, _) => g
                .kratos_quadrilateral_iterate(p, Some(s))
                .and_then(|newton| match newton.outcome {
                    NewtonOutcome::Converged => Ok(newton.local),
                    NewtonOutcome::Diverged | NewtonOutcome::MaxIterations => {
                        Err(Error::new(ErrorKind::NotConverged))
                    }
                }),
            SolverStart::Affine(j, Some(inv)) => g.least_squares_iterate(p, Some((j, inv))),
            SolverStart::Affine(_, None) | SolverStart::Other => {
                return g.point_local_coordinates(p);
            }
        };
        match absolute {
            // The rare relative retry: the geometry's own path (it repeats the absolute
            // iteration, with the same outcome, then iterates relative to the first node).
            Err(e) if matches!(e.kind(), ErrorKind::NotConverged) => g.point_local_coordinates(p),
            r => r,
        }
    }

    /// [`Geometry::is_inside`] of `p` (same result, same errors). A plane quadrilateral skips
    /// the iteration for a point its certificate puts outside (`quad_outside`).
    pub fn is_inside(&self, p: &Point, tolerance: Real) -> Result<Option<Point>, Error> {
        if let SolverStart::Quadrilateral(start, Some(outside)) = &self.start
            && !start.singular
            && tolerance.is_finite()
            && outside.certainly_outside(p, tolerance)
        {
            return Ok(None);
        }
        self.geometry.inside_with(
            tolerance,
            || self.kratos_last_iterate(p),
            || self.local_coordinates(p),
        )
    }

    /// Kratos' quadrilateral iteration's last iterate whatever its outcome (the clipping's
    /// local coordinates in Kratos mode); [`LocalCoordinatesSolver::local_coordinates`] for
    /// other kinds.
    pub(crate) fn kratos_last_iterate(&self, p: &Point) -> Result<Point, Error> {
        match &self.start {
            SolverStart::Quadrilateral(s, _) => self
                .geometry
                .kratos_quadrilateral_iterate(p, Some(s))
                .map(|k| k.local),
            _ => self.local_coordinates(p),
        }
    }
}

/// Kratos' `Quadrilateral3D4` local-coordinates iteration: maximum number of iterations.
pub(crate) const KRATOS_QUADRILATERAL_MAX_ITERATIONS: usize = 500;
/// Kratos' `Quadrilateral3D4` local-coordinates iteration: an increment longer than this stops
/// the iteration (divergence).
pub(crate) const KRATOS_QUADRILATERAL_MAX_INCREMENT_NORM: Real = 300.0;

/// How Kratos' quadrilateral iteration stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum NewtonOutcome {
    /// `|Δξ| < 1e-8`.
    Converged,
    /// `|Δξ| > 300` (or not finite): Kratos stops and keeps the last iterate.
    Diverged,
    /// 500 iterations without either.
    MaxIterations,
}

/// The result of [`Geometry::point_local_coordinates_kratos_quadrilateral`]: the last iterate
/// (what Kratos returns whatever the outcome) and how the iteration stopped.
#[derive(Clone, Copy, Debug)]
pub(crate) struct KratosNewton {
    pub(crate) local: Point,
    pub(crate) outcome: NewtonOutcome,
}

impl Geometry<'_> {
    /// Kratos 10.4.4 `Quadrilateral3D4::PointLocalCoordinatesImplementation`, evaluated in
    /// Kratos' order (checked bit for bit against the Kratos 10.4.4 binary on random warped
    /// quadrilaterals):
    ///
    /// * `ξ = (0, 0)`; per iteration, with `N`/`∂N` the bilinear shape functions and their local
    ///   derivatives at `ξ` (`N_0 = 0.25 (1 − ξ)(1 − η)`, `∂N_0/∂ξ = −0.25 (1 − η)`, …):
    /// * `x = Σ_i N_i X_i` (node order, per component), `r = p − x`;
    /// * `D = X ∂N` (3×2, sums over the nodes in order), `A = DᵀD`, `b = Dᵀ r` (sums over x, y, z
    ///   in order);
    /// * `det = A00 A11 − A01 A10`; the inverse entries `A11/det`, `−A10/det`, `−A01/det`,
    ///   `A00/det`; `Δξ = A⁻¹ b` (two products summed); `ξ += Δξ`;
    /// * stop when `|Δξ| > 300` (diverged) or `|Δξ| < 1e-8` (converged), at most 500 iterations.
    ///
    /// Kratos returns the last iterate whatever the outcome; so does this (the outcome says how
    /// it stopped). No projection is made first: the least-squares step solves in the tangent
    /// plane of the current iterate.
    ///
    /// Errors: [`ErrorKind::NonFinite`] for a non-finite `p`; [`ErrorKind::Degenerate`] when the
    /// quadrilateral's Jacobian at its centre is singular (where Kratos would divide by zero). A
    /// singular or non-finite step at a later iterate is reported as
    /// [`NewtonOutcome::Diverged`] (Kratos' iterate becomes NaN/∞ and fails every inside test).
    pub(crate) fn point_local_coordinates_kratos_quadrilateral(
        &self,
        p: &Point,
    ) -> Result<KratosNewton, Error> {
        self.kratos_quadrilateral_iterate(p, None)
    }

    /// The first step of Kratos' quadrilateral iteration at `ξ = (0, 0)`, which does not
    /// depend on the point: `x(0)`, `D(0)`, `det A(0)` and the inverse entries.
    fn kratos_quadrilateral_start(&self) -> QuadStart {
        let x_nodes = self.quadrilateral_nodes();
        let (x, d) = quadrilateral_x_d(&x_nodes, 0.0, 0.0);
        let (det, inv) = quadrilateral_inverse(&d);
        QuadStart {
            x,
            d,
            inv,
            singular: self.singular_start(det),
        }
    }

    /// Whether `det A` at the start of Kratos' quadrilateral iteration is singular (where
    /// Kratos would divide by zero): NaN or at most `1e-28 · scale⁴`.
    fn singular_start(&self, det: Real) -> bool {
        det.is_nan() || det <= (DEGENERATE_REL * DEGENERATE_REL) * self.scale().powi(4)
    }

    fn quadrilateral_nodes(&self) -> [[Real; 3]; 4] {
        let pts = self.points();
        [
            [pts[0].x, pts[0].y, pts[0].z],
            [pts[1].x, pts[1].y, pts[1].z],
            [pts[2].x, pts[2].y, pts[2].z],
            [pts[3].x, pts[3].y, pts[3].z],
        ]
    }

    /// Kratos' quadrilateral iteration; `start` (the same geometry's
    /// [`kratos_quadrilateral_start`](Self::kratos_quadrilateral_start)) replaces the first
    /// step's point-independent work by its stored values (the same bits).
    fn kratos_quadrilateral_iterate(
        &self,
        p: &Point,
        start: Option<&QuadStart>,
    ) -> Result<KratosNewton, Error> {
        if !is_finite_point(p) {
            return Err(Error::new(ErrorKind::NonFinite));
        }
        debug_assert_eq!(self.kind(), GeometryKind::Quadrilateral3D4);
        let x_nodes = self.quadrilateral_nodes();
        let target = [p.x, p.y, p.z];
        let (mut xi, mut eta) = (0.0, 0.0);
        let mut outcome = NewtonOutcome::MaxIterations;
        for k in 0..KRATOS_QUADRILATERAL_MAX_ITERATIONS {
            let (x, d, inv) = match (k, start) {
                (0, Some(s)) => {
                    if s.singular {
                        return Err(Error::degenerate("singular Jacobian"));
                    }
                    (s.x, s.d, s.inv)
                }
                _ => {
                    let (x, d) = quadrilateral_x_d(&x_nodes, xi, eta);
                    let (det, inv) = quadrilateral_inverse(&d);
                    if k == 0 && self.singular_start(det) {
                        return Err(Error::degenerate("singular Jacobian"));
                    }
                    (x, d, inv)
                }
            };
            let r = [target[0] - x[0], target[1] - x[1], target[2] - x[2]];
            let mut b = [0.0; 2];
            for (i, bi) in b.iter_mut().enumerate() {
                let mut t = 0.0;
                for (dc, rc) in d.iter().zip(&r) {
                    t += dc[i] * rc;
                }
                *bi = t;
            }
            let [inv00, inv10, inv01, inv11] = inv;
            let d_xi = inv00 * b[0] + inv01 * b[1];
            let d_eta = inv10 * b[0] + inv11 * b[1];
            xi += d_xi;
            eta += d_eta;
            let norm = (d_xi * d_xi + d_eta * d_eta).sqrt();
            if norm > KRATOS_QUADRILATERAL_MAX_INCREMENT_NORM || !norm.is_finite() {
                outcome = NewtonOutcome::Diverged;
                break;
            }
            if norm < LOCAL_COORDINATES_TOLERANCE {
                outcome = NewtonOutcome::Converged;
                break;
            }
        }
        Ok(KratosNewton {
            local: Point::new(xi, eta, 0.0),
            outcome,
        })
    }
}

/// `x(ξ, η) = Σ N_i X_i` and `D = X ∂N` (3×2) of a bilinear quadrilateral, in Kratos' order.
fn quadrilateral_x_d(x_nodes: &[[Real; 3]; 4], xi: Real, eta: Real) -> ([Real; 3], [[Real; 2]; 3]) {
    let n = [
        0.25 * (1.0 - xi) * (1.0 - eta),
        0.25 * (1.0 + xi) * (1.0 - eta),
        0.25 * (1.0 + xi) * (1.0 + eta),
        0.25 * (1.0 - xi) * (1.0 + eta),
    ];
    let mut x = [0.0; 3];
    for (ni, xn) in n.iter().zip(x_nodes) {
        for c in 0..3 {
            x[c] += ni * xn[c];
        }
    }
    let dn = [
        [-0.25 * (1.0 - eta), -0.25 * (1.0 - xi)],
        [0.25 * (1.0 - eta), -0.25 * (1.0 + xi)],
        [0.25 * (1.0 + eta), 0.25 * (1.0 + xi)],
        [-0.25 * (1.0 + eta), 0.25 * (1.0 - xi)],
    ];
    let mut d = [[0.0; 2]; 3];
    for (c, row) in d.iter_mut().enumerate() {
        for (j, dcj) in row.iter_mut().enumerate() {
            let mut t = 0.0;
            for (xn, dni) in x_nodes.iter().zip(&dn) {
                t += xn[c] * dni[j];
            }
            *dcj = t;
        }
    }
    (x, d)
}

/// `A = DᵀD`, `det A` and the inverse entries `[A11/det, −A10/det, −A01/det, A00/det]`.
fn quadrilateral_inverse(d: &[[Real; 2]; 3]) -> (Real, [Real; 4]) {
    let mut a = [[0.0; 2]; 2];
    for (i, row) in a.iter_mut().enumerate() {
        for (j, aij) in row.iter_mut().enumerate() {
            let mut t = 0.0;
            for dc in d {
                t += dc[i] * dc[j];
            }
            *aij = t;
        }
    }
    let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
    (
        det,
        [a[1][1] / det, -a[1][0] / det, -a[0][1] / det, a[0][0] / det],
    )
}

/// The point-independent first step of Kratos' quadrilateral iteration.
#[derive(Clone, Copy, Debug)]
struct QuadStart {
    x: [Real; 3],
    d: [[Real; 2]; 3],
    inv: [Real; 4],
    /// `det A` is singular ([`Geometry::singular_start`]): the iteration fails at once.
    singular: bool,
}

fn finite(p: Point) -> Result<Point, Error> {
    if is_finite_point(&p) {
        Ok(p)
    } else {
        Err(Error::new(ErrorKind::NonFinite))
    }
}
