//! 3D exact mortar segmentation of triangle/quadrilateral faces (Kratos
//! `ExactMortarIntegrationUtility<3, 3|4, false, 3|4>`, reference §10.2.1).

use std::cell::RefCell;

use super::cell::{MortarCell, Segmentation};
use super::face::{
    CLIPPING_TOLERANCE, DUPLICATE_POINT_TOLERANCE, MortarFace, MortarMode, ROBUST_AREA_FACTOR,
    SegmentationSettings,
};
use crate::geometry::PreparedSolver;
use crate::math::{EPS, Point, Real, Vector, cross_kratos, dot_kratos, norm_kratos};
use crate::projection::fast_project;
use crate::{Error, Geometry, GeometryKind, LocalCoordinatesSolver};

/// Robust mode: relative tolerance of the clipping denominator (× |e_slave|·|e_master|).
const ROBUST_PARALLEL_TOLERANCE: Real = 1e-14;
/// Robust mode: duplicate-point and edge-parameter tolerance on coordinates divided by the
/// slave size.
const ROBUST_POINT_TOLERANCE: Real = 1e-12;

/// The in-plane frame of the slave: centre `C`, tangents `t_ξ`, `t_η`, and the coordinate
/// scale (1 in Kratos mode; the slave size in robust mode).
#[derive(Debug)]
struct Frame {
    center: Point,
    t_xi: Vector,
    t_eta: Vector,
    scale: Real,
    mode: MortarMode,
}

impl Frame {
    /// `MortarUtilities::RotatePoint(…, false)`: Kratos keeps the offset,
    /// `C + ((p−C)·t_ξ, (p−C)·t_η, 0)`; robust mode uses `((p−C)·t_ξ, (p−C)·t_η, 0) / L`.
    fn rotate(&self, p: &Point) -> Point {
        let a = p - self.center;
        let x = dot_kratos(&self.t_xi, &a);
        let y = dot_kratos(&self.t_eta, &a);
        match self.mode {
            MortarMode::Kratos => Point::new(x + self.center.x, y + self.center.y, self.center.z),
            MortarMode::Robust => Point::new(x / self.scale, y / self.scale, 0.0),
        }
    }

    /// The inverse map (`RotatePoint(…, true)`), back to the plane through `C`.
    fn unrotate(&self, q: &Point) -> Point {
        match self.mode {
            MortarMode::Kratos => {
                let a = q - self.center;
                let (t, e) = (&self.t_xi, &self.t_eta);
                Point::new(
                    t.x * a.x + e.x * a.y + 0.0 * a.z + self.center.x,
                    t.y * a.x + e.y * a.y + 0.0 * a.z + self.center.y,
                    t.z * a.x + e.z * a.y + 0.0 * a.z + self.center.z,
                )
            }
            MortarMode::Robust => self.center + (self.t_xi * q.x + self.t_eta * q.y) * self.scale,
        }
    }

    /// The z of the rotated plane (intersection points get it).
    fn z_ref(&self) -> Real {
        match self.mode {
            MortarMode::Kratos => self.center.z,
            MortarMode::Robust => 0.0,
        }
    }

    fn duplicate_tolerance(&self) -> Real {
        match self.mode {
            MortarMode::Kratos => DUPLICATE_POINT_TOLERANCE,
            MortarMode::Robust => ROBUST_POINT_TOLERANCE,
        }
    }
}

/// The slave's share of [`clip_prepared`], the same for each of its masters: its robust
/// area, the frame, its nodes projected onto its plane and rotated, whether a node lies
/// farther than the distance threshold from that plane (quadrilateral slaves), the prepared
/// local-coordinates solvers of the rotated and of the local-coordinates geometry, and the
/// rotated slave's normal — or the first error computing them, which every pair reports at
/// the point where [`clip_prepared`] computes it.
#[derive(Debug)]
pub(super) struct ClipSlave(Result<ClipSlaveData, Error>, RefCell<PointMemo>);

/// Most points a [`PointMemo`] list holds: beyond, points are computed without being kept
/// (a linear search must stay cheaper than the work it saves).
const MEMO_CAPACITY: usize = 48;

/// What [`clip_prepared`] computes per point from the point and the slave alone, kept for the
/// slave's next masters: neighbouring masters share nodes, and a point's polygon appears in
/// every master it lies in. Keyed by the exact bits of the point, so a hit returns what the
/// computation would (it depends on nothing else).
#[derive(Debug, Default)]
struct PointMemo {
    /// Master nodes: the projection onto the slave plane, rotated; the distance from the plane;
    /// whether it lies inside the rotated slave (once asked).
    master: Vec<([u64; 3], MasterPoint)>,
    /// Polygon points (rotated): their slave local coordinates.
    slave_local: Vec<([u64; 3], Point)>,
}

#[derive(Clone, Copy, Debug)]
struct MasterPoint {
    rot: Point,
    distance: Real,
    inside: Option<bool>,
}

/// The exact bits of a point, a [`PointMemo`] key.
fn bits(p: &Point) -> [u64; 3] {
    [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()]
}

impl PointMemo {
    /// The master node `x`'s entry (its position in `master`), computed with `project` if new;
    /// `Err` with the computed entry where the memo is full and `x` not in it.
    fn master_slot(
        &mut self,
        x: &Point,
        project: impl FnOnce() -> MasterPoint,
    ) -> Result<usize, MasterPoint> {
        let key = bits(x);
        if let Some(i) = self.master.iter().position(|(k, _)| *k == key) {
            return Ok(i);
        }
        let value = project();
        if self.master.is_empty() {
            self.master.reserve_exact(MEMO_CAPACITY);
        }
        if self.master.len() < MEMO_CAPACITY {
            self.master.push((key, value));
            Ok(self.master.len() - 1)
        } else {
            Err(value)
        }
    }

    /// The slave local coordinates of the rotated point `p`, computed with `local` if new.
    fn slave_local(&mut self, p: &Point, local: impl FnOnce() -> Point) -> Point {
        let key = bits(p);
        if let Some((_, v)) = self.slave_local.iter().find(|(k, _)| *k == key) {
            return *v;
        }
        let value = local();
        if self.slave_local.is_empty() {
            self.slave_local.reserve_exact(MEMO_CAPACITY);
        }
        if self.slave_local.len() < MEMO_CAPACITY {
            self.slave_local.push((key, value));
        }
        value
    }
}

#[derive(Debug)]
struct ClipSlaveData {
    area: Real,
    frame: Frame,
    normal: Vector,
    flat: [Point; 4],
    rot: [Point; 4],
    far: bool,
    /// The rotated slave's solver, or the error building its geometry (raised after the
    /// master's projections, where the pair builds it).
    rot_solver: Result<PreparedSolver, Error>,
    /// The solver of the geometry the cells' local coordinates use (after the master's
    /// rotated geometry).
    local_solver: Result<PreparedSolver, Error>,
    /// The rotated slave's unit normal (raised where a pair fans at least three points).
    rot_normal: Result<Vector, Error>,
}

impl ClipSlave {
    /// Steps 1–2 of [`clip_prepared`] for the slave alone.
    pub(super) fn new(slave: &MortarFace<'_>, settings: &SegmentationSettings) -> ClipSlave {
        ClipSlave(
            ClipSlaveData::new(slave, settings),
            RefCell::new(PointMemo::default()),
        )
    }
}

impl ClipSlaveData {
    fn new(
        slave: &MortarFace<'_>,
        settings: &SegmentationSettings,
    ) -> Result<ClipSlaveData, Error> {
        let mode = settings.mode;
        let sg = slave.geometry();
        let slave_is_quad = sg.kind() == GeometryKind::Quadrilateral3D4;
        let area = sg.area_robust()?;

        // 1. The frame.
        let center = sg.center();
        let mut n_s = slave.normal();
        let n_norm = norm_kratos(&n_s);
        if n_norm.is_nan() || n_norm <= EPS {
            return Err(Error::degenerate("zero-length slave normal"));
        }
        let sp = sg.points();
        let raw_t = if slave_is_quad {
            sp[2] - sp[0]
        } else {
            sp[1] - sp[0]
        };
        let mut t_xi = raw_t / norm_kratos(&raw_t);
        let scale = match mode {
            MortarMode::Kratos => 1.0,
            MortarMode::Robust => {
                n_s /= n_norm;
                t_xi -= n_s * dot_kratos(&t_xi, &n_s);
                let t_norm = norm_kratos(&t_xi);
                if t_norm.is_nan() || t_norm <= 1e-8 {
                    return Err(Error::degenerate("slave normal lies in the slave plane"));
                }
                t_xi /= t_norm;
                sg.scale()
            }
        };
        let t_norm = norm_kratos(&t_xi);
        if t_norm.is_nan() || t_norm <= 0.0 {
            return Err(Error::degenerate("zero-length slave edge"));
        }
        let t_eta = cross_kratos(&n_s, &t_xi);
        let frame = Frame {
            center,
            t_xi,
            t_eta,
            scale,
            mode,
        };

        // 2. The slave's projection (quadrilaterals) and rotation.
        let mut flat = [Point::origin(); 4]; // projected, not rotated (quadrilateral slave)
        let mut rot = [Point::origin(); 4];
        let mut far = false;
        for (i, x) in sp.iter().enumerate() {
            if slave_is_quad {
                let (p, distance) = fast_project(&center, x, &n_s);
                far |= distance > settings.distance_threshold;
                flat[i] = p;
                rot[i] = frame.rotate(&p);
            } else {
                flat[i] = *x;
                rot[i] = frame.rotate(x);
            }
        }
        let n = sp.len();
        let rot_geom = Geometry::new(sg.kind(), &rot[..n]);
        let rot_solver = rot_geom
            .as_ref()
            .map(|g| {
                LocalCoordinatesSolver::new(*g)
                    .with_outside_certificate()
                    .prepared()
            })
            .map_err(Clone::clone);
        // The rotated slave lies in a plane z = const: its unit normal is (0, 0, ±1).
        let rot_normal = rot_geom.and_then(|g| g.unit_normal(&g.reference_center()));
        // The geometry whose local coordinates the cells use: the original triangle, or the
        // projected quadrilateral (Kratos' `slave_geometry_not_rotated`).
        let local_solver = Geometry::new(sg.kind(), &flat[..n]).map(|flat_geom| {
            let local_geom = if slave_is_quad { flat_geom } else { *sg };
            LocalCoordinatesSolver::new(local_geom).prepared()
        });
        Ok(ClipSlaveData {
            area,
            frame,
            normal: n_s,
            flat,
            rot,
            far,
            rot_solver,
            local_solver,
            rot_normal,
        })
    }
}

/// The 3D segmentation (see [`exact_segmentation`](super::exact_segmentation)):
/// 1. frame: `C` = slave centre, `t_ξ` = unit `X1 − X0` (triangle slave) or `X2 − X0`
///    (quadrilateral slave), `t_η = n_s × t_ξ`;
/// 2. master nodes projected along `n_s` onto the plane through `C` (a distance above the
///    threshold rejects the pair; a quadrilateral slave paired with a triangle master also
///    checks its own nodes), quadrilateral slaves are projected too; all points rotated into
///    the frame;
/// 3. all master points inside the slave: shortcut cells (see the mode docs for `<3,3,4>`);
/// 4. otherwise the polygon points: master points inside the slave, slave points inside the
///    master, then the edge intersections, each dropped when closer than the duplicate
///    tolerance to one already listed;
/// 5. at least 3 points: back to the plane, slave and master local coordinates, sorted by the
///    angle around the first point, fanned into triangles `(0, k, k+1)`; a triangle whose
///    centroid is outside the slave or the master reference element (tolerance ε) is dropped.
///
/// The slave's share is `prepared` ([`ClipSlave::new`] of the same slave and settings).
pub(super) fn clip_prepared(
    slave: &MortarFace<'_>,
    prepared: &ClipSlave,
    master: &MortarFace<'_>,
    settings: &SegmentationSettings,
) -> Result<Option<Segmentation>, Error> {
    let mode = settings.mode;
    let sg = slave.geometry();
    let mg = master.geometry();
    let slave_is_quad = sg.kind() == GeometryKind::Quadrilateral3D4;
    let master_is_quad = mg.kind() == GeometryKind::Quadrilateral3D4;
    let data = prepared.0.as_ref().map_err(Clone::clone)?;
    let (frame, slave_area, n_s) = (&data.frame, data.area, &data.normal);

    // 2. Projections and rotation (the slave's are prepared).
    if slave_is_quad && !master_is_quad && data.far {
        return Ok(None);
    }
    let n_slave = sg.points().len();
    let n_master = mg.points().len();
    // The slave's memo of master nodes and polygon points (the same answers, kept).
    let mut memo = prepared.1.borrow_mut();
    let mut master_rot = [Point::origin(); 4];
    let mut slots: [Option<usize>; 4] = [None; 4];
    for (j, x) in mg.points().iter().enumerate() {
        let project = || {
            let (p, distance) = fast_project(&frame.center, x, n_s);
            MasterPoint {
                rot: frame.rotate(&p),
                distance,
                inside: None,
            }
        };
        let point = match memo.master_slot(x, project) {
            Ok(i) => {
                slots[j] = Some(i);
                memo.master[i].1
            }
            Err(point) => point,
        };
        if point.distance > settings.distance_threshold {
            return Ok(None);
        }
        master_rot[j] = point.rot;
    }
    let slave_rot_geom = Geometry::new(sg.kind(), &data.rot[..n_slave])?;
    let rot_prepared = data.rot_solver.as_ref().map_err(Clone::clone)?;
    let master_rot_geom = Geometry::new(mg.kind(), &master_rot[..n_master])?;
    let local_prepared = data.local_solver.as_ref().map_err(Clone::clone)?;
    let slave_local_geom = if slave_is_quad {
        Geometry::new(sg.kind(), &data.flat[..n_slave])?
    } else {
        *sg
    };
    let slave_rot = &data.rot;

    // Several points on each of these faces: the point-independent work once (the slave's
    // prepared for all its masters).
    let slave_rot_solver = LocalCoordinatesSolver::from_prepared(slave_rot_geom, rot_prepared);
    let master_rot_solver = LocalCoordinatesSolver::new(master_rot_geom).with_outside_certificate();
    let fan = FanSlave {
        frame,
        slave: sg,
        local_solver: LocalCoordinatesSolver::from_prepared(slave_local_geom, local_prepared),
        rot_normal: &data.rot_normal,
    };

    // 3. Master points inside the slave.
    let mut master_inside = [false; 4];
    for (j, p) in master_rot[..n_master].iter().enumerate() {
        let test = || inside(&slave_rot_solver, p, mode);
        master_inside[j] = match slots[j] {
            Some(i) => *memo.master[i].1.inside.get_or_insert_with(test),
            None => test(),
        };
    }
    let master_inside = &master_inside[..n_master];
    let tol_dup = frame.duplicate_tolerance();
    let mut points: Vec<Point> = Vec::with_capacity(16);
    let robust_min_area = ROBUST_AREA_FACTOR * slave_area;
    let finish = |cells: Vec<MortarCell>| -> Option<Segmentation> {
        let cells = match mode {
            MortarMode::Kratos => cells,
            MortarMode::Robust => cells
                .into_iter()
                .filter(|c| c.measure() > robust_min_area)
                .collect(),
        };
        Segmentation::new(cells, mode)
    };
    if master_inside.iter().all(|b| *b) {
        if !slave_is_quad {
            let mp = mg.points();
            let local: Vec<Point> = mp
                .iter()
                .map(|x| sg.point_local_coordinates(x))
                .collect::<Result<_, _>>()?;
            let mut cells = vec![MortarCell::new(sg, &local[0..3])];
            if master_is_quad {
                // Q49: Kratos emits (1,2,3), overlapping (0,1,2) and missing (0,2,3).
                let second = match mode {
                    MortarMode::Kratos => [local[1], local[2], local[3]],
                    MortarMode::Robust => [local[0], local[2], local[3]],
                };
                cells.push(MortarCell::new(sg, &second));
            }
            return Ok(finish(cells));
        }
        if !master_is_quad {
            let local: Vec<Point> = mg
                .points()
                .iter()
                .map(|x| local_coordinates(sg, x, mode))
                .collect::<Result<_, _>>()?;
            return Ok(finish(vec![MortarCell::new(sg, &local)]));
        }
        push_unique(&mut points, &master_rot[..n_master], master_inside, tol_dup);
        let cells = fan_cells(&mut points, &fan, &master_rot_solver, &mut memo)?;
        return Ok(finish(cells));
    }

    // 4. The polygon points.
    push_unique(&mut points, &master_rot[..n_master], master_inside, tol_dup);
    let mut slave_inside = [false; 4];
    for (flag, p) in slave_inside.iter_mut().zip(&slave_rot[..n_slave]) {
        *flag = inside(&master_rot_solver, p, mode);
    }
    push_unique(
        &mut points,
        &slave_rot[..n_slave],
        &slave_inside[..n_slave],
        tol_dup,
    );
    clipping_intersections(
        &mut points,
        &slave_rot[..n_slave],
        &master_rot[..n_master],
        frame,
    );

    // 5. The fan.
    let cells = fan_cells(&mut points, &fan, &master_rot_solver, &mut memo)?;
    Ok(finish(cells))
}

/// Whether the rotated point `p` lies in the rotated polygon `geometry`.
///
/// Kratos mode: Kratos `IsInside(p, local, ε)` (local coordinates, for a quadrilateral the last
/// Newton iterate whatever the outcome — which can call a point well outside an irregular
/// quadrilateral "inside"); a degenerate geometry (NaN local coordinates in Kratos) is
/// "outside". Robust mode: the 2D half-plane test against every edge of the (convex) polygon,
/// with tolerance [`ROBUST_POINT_TOLERANCE`] on the normalised coordinates.
fn inside(solver: &LocalCoordinatesSolver<'_>, p: &Point, mode: MortarMode) -> bool {
    match mode {
        MortarMode::Kratos => matches!(solver.is_inside(p, EPS), Ok(Some(_))),
        MortarMode::Robust => {
            let v = solver.geometry().points();
            let n = v.len();
            let mut twice_area = 0.0;
            for i in 0..n {
                let (a, b) = (v[i], v[(i + 1) % n]);
                twice_area += a.x * b.y - b.x * a.y;
            }
            if twice_area.is_nan() || twice_area == 0.0 {
                return false;
            }
            let sign = twice_area.signum();
            (0..n).all(|i| {
                let (a, b) = (v[i], v[(i + 1) % n]);
                let (ex, ey) = (b.x - a.x, b.y - a.y);
                let cross = ex * (p.y - a.y) - ey * (p.x - a.x);
                sign * cross >= -ROBUST_POINT_TOLERANCE * (ex * ex + ey * ey).sqrt()
            })
        }
    }
}

/// Local coordinates as Kratos computes them: for a Quadrilateral3D4 in Kratos mode the last
/// iterate of Kratos' Newton iteration whatever its outcome; otherwise
/// [`Geometry::point_local_coordinates`].
fn local_coordinates(geometry: &Geometry<'_>, p: &Point, mode: MortarMode) -> Result<Point, Error> {
    if mode == MortarMode::Kratos && geometry.kind() == GeometryKind::Quadrilateral3D4 {
        return geometry
            .point_local_coordinates_kratos_quadrilateral(p)
            .map(|k| k.local);
    }
    geometry.point_local_coordinates(p)
}

/// [`local_coordinates`] through a solver prepared once for several points.
fn solver_local_coordinates(
    solver: &LocalCoordinatesSolver<'_>,
    p: &Point,
    mode: MortarMode,
) -> Result<Point, Error> {
    match mode {
        MortarMode::Kratos => solver.kratos_last_iterate(p),
        MortarMode::Robust => solver.local_coordinates(p),
    }
}

/// Kratos `CheckPoints`: `|a − b| < tol`.
fn same_point(a: &Point, b: &Point, tol: Real) -> bool {
    norm_kratos(&(b - a)) < tol
}

/// Kratos `PushBackPoints`: appends the flagged points that are not duplicates.
fn push_unique(list: &mut Vec<Point>, candidates: &[Point], flags: &[bool], tol: Real) {
    for (p, flag) in candidates.iter().zip(flags) {
        if *flag && !list.iter().any(|q| same_point(p, q, tol)) {
            list.push(*p);
        }
    }
}

/// Kratos `ComputeClippingIntersections` + `Clipping2D`: intersections of every slave edge
/// (outer loop) with every master edge (inner loop), appended unless duplicates.
fn clipping_intersections(list: &mut Vec<Point>, slave: &[Point], master: &[Point], frame: &Frame) {
    let tol_dup = frame.duplicate_tolerance();
    for i in 0..slave.len() {
        let ip = (i + 1) % slave.len();
        for j in 0..master.len() {
            let jp = (j + 1) % master.len();
            if let Some((x, y)) =
                clipping_2d(&slave[i], &slave[ip], &master[j], &master[jp], frame.mode)
            {
                let p = Point::new(x, y, frame.z_ref());
                if !list.iter().any(|q| same_point(&p, q, tol_dup)) {
                    list.push(p);
                }
            }
        }
    }
}

/// Kratos `Clipping2D`: the intersection of segments `o1–o2` and `d1–d2` in the xy plane.
fn clipping_2d(
    o1: &Point,
    o2: &Point,
    d1: &Point,
    d2: &Point,
    mode: MortarMode,
) -> Option<(Real, Real)> {
    let s12x = o2.x - o1.x;
    let s12y = o2.y - o1.y;
    let d12x = d2.x - d1.x;
    let d12y = d2.y - d1.y;
    let denom = s12x * d12y - d12x * s12y;
    let (parallel, tol) = match mode {
        MortarMode::Kratos => (denom.abs() < CLIPPING_TOLERANCE, CLIPPING_TOLERANCE),
        MortarMode::Robust => {
            let scale = (s12x * s12x + s12y * s12y).sqrt() * (d12x * d12x + d12y * d12y).sqrt();
            (
                denom.is_nan() || denom.abs() <= ROBUST_PARALLEL_TOLERANCE * scale,
                ROBUST_POINT_TOLERANCE,
            )
        }
    };
    if parallel {
        return None;
    }
    let so1d1x = o1.x - d1.x;
    let so1d1y = o1.y - d1.y;
    let s = (s12x * so1d1y - s12y * so1d1x) / denom;
    let t = (d12x * so1d1y - d12y * so1d1x) / denom;
    if s >= -tol && s <= 1.0 + tol && t >= -tol && t <= 1.0 + tol {
        Some((o1.x + t * s12x, o1.y + t * s12y))
    } else {
        None
    }
}

/// The slave's part of [`fan_cells`].
#[derive(Debug)]
struct FanSlave<'f> {
    frame: &'f Frame,
    /// The slave geometry (the cells' kind).
    slave: &'f Geometry<'f>,
    /// The solver of the geometry the cells' slave local coordinates use.
    local_solver: LocalCoordinatesSolver<'f>,
    /// The rotated slave's unit normal (the angles' axis).
    rot_normal: &'f Result<Vector, Error>,
}

/// Kratos `TriangleIntersections` after the clipping: converts the (rotated) polygon points to
/// slave and master local coordinates, sorts them by angle around the first point and fans
/// them; drops triangles whose centroid is outside either reference element.
fn fan_cells(
    points: &mut [Point],
    fan: &FanSlave<'_>,
    master_solver: &LocalCoordinatesSolver<'_>,
    memo: &mut PointMemo,
) -> Result<Vec<MortarCell>, Error> {
    let (frame, slave) = (fan.frame, fan.slave);
    let master_rot = master_solver.geometry();
    let n = points.len();
    if n < 3 {
        return Ok(Vec::new());
    }
    let nan = Point::new(Real::NAN, Real::NAN, Real::NAN);
    let mut master_local = Vec::with_capacity(n);
    for p in points.iter_mut() {
        master_local.push(solver_local_coordinates(master_solver, p, frame.mode).unwrap_or(nan));
        *p = memo.slave_local(p, || {
            let global = frame.unrotate(p);
            solver_local_coordinates(&fan.local_solver, &global, frame.mode).unwrap_or(nan)
        });
    }
    let normal = fan.rot_normal.as_ref().map_err(Clone::clone)?;
    let order = angle_order(points, normal);
    let mut cells = Vec::with_capacity(n - 2);
    for k in 0..n - 2 {
        let ids = [0, order[k] + 1, order[k + 1] + 1];
        let s = [points[ids[0]], points[ids[1]], points[ids[2]]];
        let m = [
            master_local[ids[0]],
            master_local[ids[1]],
            master_local[ids[2]],
        ];
        let sc = (
            1.0 / 3.0 * (s[0].x + s[1].x + s[2].x),
            1.0 / 3.0 * (s[0].y + s[1].y + s[2].y),
        );
        let mc = (
            1.0 / 3.0 * (m[0].x + m[1].x + m[2].x),
            1.0 / 3.0 * (m[0].y + m[1].y + m[2].y),
        );
        if center_is_inside(sc, slave.kind()) && center_is_inside(mc, master_rot.kind()) {
            cells.push(MortarCell::new(slave, &s));
        }
    }
    Ok(cells)
}

/// Kratos `CheckCenterIsInside` (tolerance ε).
fn center_is_inside((x, y): (Real, Real), kind: GeometryKind) -> bool {
    if kind == GeometryKind::Triangle3D3 {
        (-EPS..=1.0 + EPS).contains(&x) && (-EPS..=1.0 + EPS).contains(&y) && x + y <= 1.0 + EPS
    } else {
        x.abs() <= 1.0 + EPS && y.abs() <= 1.0 + EPS
    }
}

/// Kratos `ComputeAnglesIndexes` + `SortIndexes`: the order of points `1..n` by the angle
/// around point 0, measured from the direction to point 1 and re-based (all earlier angles
/// shifted) whenever a negative angle appears. A stable sort, like libstdc++'s insertion sort
/// for these short lists.
fn angle_order(points: &[Point], normal: &Vector) -> Vec<usize> {
    let p0 = points[0];
    let unit = |p: &Point| {
        let v = p - p0;
        v / norm_kratos(&v)
    };
    let mut v = unit(&points[1]);
    let mut w = cross_kratos(normal, &v);
    let mut angles = vec![0.0; points.len() - 1];
    for e in 1..points.len() {
        let a = angle_points(&p0, &points[e], &v, &w);
        angles[e - 1] = a;
        if a < 0.0 {
            v = unit(&points[e]);
            w = cross_kratos(normal, &v);
            for angle in &mut angles[..e] {
                *angle -= a;
            }
        }
    }
    let mut idx: Vec<usize> = (0..angles.len()).collect();
    idx.sort_by(|&i, &j| {
        angles[i]
            .partial_cmp(&angles[j])
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    idx
}

/// Kratos `AnglePoints`: `atan2(axis2·e, axis1·e)` of the unit edge `e = p2 − p1`.
fn angle_points(p1: &Point, p2: &Point, axis1: &Vector, axis2: &Vector) -> Real {
    let mut e = p2 - p1;
    let norm = norm_kratos(&e);
    if norm > 0.0 {
        e /= norm;
    }
    dot_kratos(axis2, &e).atan2(dot_kratos(axis1, &e))
}
