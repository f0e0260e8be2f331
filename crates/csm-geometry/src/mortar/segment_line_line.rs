//! 2D exact mortar segmentation, Line2D2 slave against Line2D2 master (Kratos
//! `ExactMortarIntegrationUtility<2, 2, false>`, reference §10.2.1).

use super::cell::{MortarCell, Segmentation};
use super::face::{
    MortarFace, MortarMode, NEWTON_2D_MAX_ITERATIONS, NEWTON_2D_TOLERANCE, ROBUST_AREA_FACTOR,
    SegmentationSettings,
};
use crate::math::{EPS, Point, Real, Vector, dot_kratos, norm_kratos};
use crate::projection::fast_project_direction;
use crate::{Error, Geometry};

/// The 2D segmentation. Steps (Kratos order):
/// 1. each slave node `X_i` is projected onto the master line along `−n_i` (nodal normal);
///    a projection distance above the threshold rejects the pair (Q21); a projection inside the
///    master (tolerance 1e3·ε) marks the slave end (`ξ = −1` for node 0, `+1` for node 1);
/// 2. both ends marked → the whole slave;
/// 3. otherwise the master nodes are projected onto the slave by [`project_iterative_line`];
///    every converged projection is a "hit" (clamped to the slave ends, Q44);
/// 4. one end + one hit → `[end, hit]`; two hits → with an end the farther hit, else
///    `[min, max]`; anything else → no overlap ("not supposed to happen" in Kratos);
/// 5. a segment of local length `> ε` is the one cell.
pub(super) fn segment_line_line(
    slave: &MortarFace<'_>,
    master: &MortarFace<'_>,
    settings: &SegmentationSettings,
) -> Result<Option<Segmentation>, Error> {
    let sg = slave.geometry();
    let mg = master.geometry();
    sg.length()?;
    let tol = NEWTON_2D_TOLERANCE;
    let max_iter = match settings.mode {
        MortarMode::Kratos => NEWTON_2D_MAX_ITERATIONS,
        MortarMode::Robust => 5 * NEWTON_2D_MAX_ITERATIONS,
    };
    let master_ok = mg.length().is_ok();

    // Step 1: slave ends inside the master.
    let mut coords = [0.0, 0.0];
    let mut end = [false, false];
    for i in 0..2 {
        let x_i = sg.points()[i];
        let n_i = slave.nodal_normal(i);
        let (projected, distance) =
            fast_project_direction(&mg.points()[0], &x_i, &master.normal(), &(-n_i));
        if distance > settings.distance_threshold {
            return Ok(None);
        }
        // A zero-length master has NaN local coordinates in Kratos: never inside.
        let inside = master_ok && matches!(mg.is_inside(&projected, tol), Ok(Some(_)));
        if inside {
            end[i] = true;
            coords[i] = if i == 0 { -1.0 } else { 1.0 };
        }
    }

    let weight = if end[0] && end[1] {
        2.0
    } else {
        // Step 3: master nodes onto the slave.
        let mut hits: Vec<Real> = Vec::with_capacity(2);
        for j in 0..2 {
            let (xi0, dxi0) = if j == 0 { (-1.0, 0.5) } else { (1.0, -0.5) };
            if let Some(xi) = project_iterative_line(
                slave,
                &mg.points()[j],
                (xi0, dxi0),
                (tol, max_iter),
                settings.mode,
            ) {
                hits.push(xi);
            }
        }
        // Step 4.
        if hits.len() == 1 && (end[0] || end[1]) {
            if end[0] {
                coords[1] = hits[0];
            } else {
                coords[0] = hits[0];
            }
        } else if hits.len() == 2 {
            let (lo, hi) = if hits[0] < hits[1] {
                (hits[0], hits[1])
            } else {
                (hits[1], hits[0])
            };
            if end[0] {
                coords[1] = hi;
            } else if end[1] {
                coords[0] = lo;
            } else {
                coords = [lo, hi];
            }
        } else {
            return Ok(None);
        }
        coords[1] - coords[0]
    };

    // Kratos raises an error for weights outside [0, 2]; the clamping makes that unreachable.
    if !(0.0..=2.0).contains(&weight) {
        return Err(Error::degenerate("2D mortar segment outside the slave"));
    }
    let keep = weight > EPS
        && match settings.mode {
            MortarMode::Kratos => true,
            MortarMode::Robust => weight / 2.0 > ROBUST_AREA_FACTOR,
        };
    if !keep {
        return Ok(None);
    }
    let cell = MortarCell::new(
        sg,
        &[
            Point::new(coords[0], 0.0, 0.0),
            Point::new(coords[1], 0.0, 0.0),
        ],
    );
    Ok(Segmentation::new(vec![cell], settings.mode))
}

/// The master nodes of a Line2D2 pair that [`MortarMode::Kratos`]' projection onto the slave
/// drops (no convergence in absolute coordinates) while the same projection relative to the
/// slave's first node converges: nodes lost to rounding far from the origin, so that Kratos'
/// segmentation of the pair loses overlap or the pair. 0 for other kinds.
pub fn line_projections_lost_to_rounding(slave: &MortarFace<'_>, master: &MortarFace<'_>) -> usize {
    let two_lines = |f: &MortarFace<'_>| f.geometry().kind() == crate::GeometryKind::Line2D2;
    if !(two_lines(slave) && two_lines(master)) {
        return 0;
    }
    let limits = (NEWTON_2D_TOLERANCE, NEWTON_2D_MAX_ITERATIONS);
    (0..2)
        .filter(|&j| {
            let start = if j == 0 { (-1.0, 0.5) } else { (1.0, -0.5) };
            let x = &master.geometry().points()[j];
            project_iterative_line(slave, x, start, limits, MortarMode::Kratos).is_none()
                && project_iterative_line(slave, x, start, limits, MortarMode::Robust).is_some()
        })
        .count()
}

/// Kratos `GeometricalProjectionUtilities::ProjectIterativeLine2D`: the local coordinate `ξ`
/// on the slave line whose interpolated, normalised nodal normal `n(ξ)` passes through
/// `x_master`. Each Newton step intersects the line `x_master + s·n(ξ)` with the plane through
/// the slave centre with the slave condition normal, solves the 1×1 normal equations of the
/// slave Jacobian (x, y only) for `Δξ`, and clamps `ξ` to `[−1, 1]`. Converged — and reported
/// as a hit — when `|Δξ − Δξ_old| < tol` (so a master node beyond a slave end converges to the
/// clamped end, Q44); `None` after `max_iter` steps (Kratos drops the node). NaN (zero
/// interpolated normal) never converges.
///
/// [`MortarMode::Kratos`] computes in absolute coordinates, as Kratos: the rounding of
/// `Δξ` grows as `ε·|X| / L` (`L` the slave's length), so once `|X| ≳ 1e3·L` it exceeds the
/// tolerance `1e3·ε`, the test may never pass and the master node is dropped (pairs with much
/// overlap are lost). [`MortarMode::Robust`]
/// computes relative to the slave's first node, so `Δξ` carries rounding of order `ε` only.
pub(super) fn project_iterative_line(
    slave: &MortarFace<'_>,
    x_master: &Point,
    (xi_init, delta_init): (Real, Real),
    (tol, max_iter): (Real, usize),
    mode: MortarMode,
) -> Option<Real> {
    let sg: &Geometry<'_> = slave.geometry();
    let origin = match mode {
        MortarMode::Kratos => Vector::zeros(),
        MortarMode::Robust => sg.points()[0].coords,
    };
    let x = [sg.points()[0] - origin, sg.points()[1] - origin];
    let x_master = &(x_master - origin);
    let normals = [slave.nodal_normal(0), slave.nodal_normal(1)];
    let n_s = slave.normal();
    let center = sg.center() - origin;
    let dn = [-0.5, 0.5];
    let dx = x[0].x * dn[0] + x[1].x * dn[1];
    let dy = x[0].y * dn[0] + x[1].y * dn[1];
    let j = dx * dx + dy * dy;
    let mut xi = xi_init;
    let mut delta = delta_init;
    for _ in 0..max_iter {
        let n0 = 0.5 * (1.0 - xi);
        let n1 = 0.5 * (1.0 + xi);
        let mut n_xi: Vector = normals[0] * n0 + normals[1] * n1;
        let norm = norm_kratos(&n_xi);
        n_xi /= norm;
        let current = x[0].coords * n0 + x[1].coords * n1;
        let distance = dot_kratos(&(center - x_master), &n_s) / dot_kratos(&(-n_xi), &n_s);
        let target = x_master.coords - n_xi * distance;
        let rhs = dx * (target.x - current.x) + dy * (target.y - current.y);
        let old = delta;
        delta = rhs / j;
        xi += delta;
        // NaN stays NaN (and never converges), as in Kratos.
        xi = xi.clamp(-1.0, 1.0);
        if (delta - old).abs() < tol {
            return Some(xi);
        }
    }
    None
}
