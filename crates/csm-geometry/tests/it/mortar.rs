//! Exact mortar segmentation and operators against oracles: Sutherland–Hodgman clipping of
//! the projected master (written here), interval intersection in 2D, invariance under rigid
//! motions and scaling, and exact mapping of constant and linear fields by `D⁻¹M`.

use crate::common::Rng;
use csm_geometry::math::{Point, Real, Vector};
use csm_geometry::{
    Geometry, GeometryKind, MortarFace, MortarMode, OperatorSettings, SegmentationSettings,
    SlaveSegmentation, dual_basis, exact_segmentation, integration_points, mortar_operators,
};

const MODES: [MortarMode; 2] = [MortarMode::Kratos, MortarMode::Robust];

/// A rigid motion `x ↦ R x + t` (Rodrigues rotation).
#[derive(Debug, Clone, Copy)]
struct Motion {
    axis: Vector,
    angle: Real,
    shift: Vector,
    scale: Real,
}

impl Motion {
    fn identity() -> Motion {
        Motion {
            axis: Vector::z(),
            angle: 0.0,
            shift: Vector::zeros(),
            scale: 1.0,
        }
    }

    fn random(rng: &mut Rng) -> Motion {
        Motion {
            axis: rng.unit_vector(),
            angle: rng.range(-3.0, 3.0),
            shift: rng.vector(-10.0, 10.0),
            scale: 1.0,
        }
    }

    fn rotate(&self, v: &Vector) -> Vector {
        let (s, c) = self.angle.sin_cos();
        let k = self.axis;
        v * c + k.cross(v) * s + k * (k.dot(v) * (1.0 - c))
    }

    fn apply(&self, p: &Point) -> Point {
        Point::from(self.rotate(&p.coords) * self.scale + self.shift)
    }
}

fn kind_of(n: usize) -> GeometryKind {
    match n {
        2 => GeometryKind::Line2D2,
        3 => GeometryKind::Triangle3D3,
        _ => GeometryKind::Quadrilateral3D4,
    }
}

/// A convex polygon (3 or 4 corners) inscribed in an ellipse, counter-clockwise in xy.
fn convex_polygon(rng: &mut Rng, n: usize, center: (Real, Real), size: Real) -> Vec<Point> {
    loop {
        let mut angles: Vec<Real> = (0..n)
            .map(|_| rng.range(0.0, std::f64::consts::TAU))
            .collect();
        angles.sort_by(|a, b| a.partial_cmp(b).unwrap());
        let gaps_ok = (0..n).all(|i| {
            let next = if i + 1 < n {
                angles[i + 1]
            } else {
                angles[0] + std::f64::consts::TAU
            };
            next - angles[i] > 0.3 && next - angles[i] < 3.0
        });
        if !gaps_ok {
            continue;
        }
        let (a, b) = (size * rng.range(0.6, 1.0), size * rng.range(0.6, 1.0));
        return angles
            .iter()
            .map(|t| Point::new(center.0 + a * t.cos(), center.1 + b * t.sin(), 0.0))
            .collect();
    }
}

/// Sutherland–Hodgman: `subject` clipped by the convex counter-clockwise `clip` (xy only).
fn clip_polygon(subject: &[(Real, Real)], clip: &[(Real, Real)]) -> Vec<(Real, Real)> {
    let mut out = subject.to_vec();
    for i in 0..clip.len() {
        let a = clip[i];
        let b = clip[(i + 1) % clip.len()];
        let side = |p: (Real, Real)| (b.0 - a.0) * (p.1 - a.1) - (b.1 - a.1) * (p.0 - a.0);
        let input = std::mem::take(&mut out);
        for j in 0..input.len() {
            let p = input[j];
            let q = input[(j + 1) % input.len()];
            let (sp, sq) = (side(p), side(q));
            if sp >= 0.0 {
                out.push(p);
            }
            if (sp >= 0.0) != (sq >= 0.0) {
                let t = sp / (sp - sq);
                out.push((p.0 + t * (q.0 - p.0), p.1 + t * (q.1 - p.1)));
            }
        }
        if out.is_empty() {
            break;
        }
    }
    out
}

fn shoelace(poly: &[(Real, Real)]) -> Real {
    let mut a = 0.0;
    for i in 0..poly.len() {
        let (p, q) = (poly[i], poly[(i + 1) % poly.len()]);
        a += p.0 * q.1 - q.0 * p.1;
    }
    0.5 * a
}

/// CCW orientation of a polygon in xy.
fn ccw(poly: &[(Real, Real)]) -> Vec<(Real, Real)> {
    if shoelace(poly) < 0.0 {
        poly.iter().rev().copied().collect()
    } else {
        poly.to_vec()
    }
}

/// A random pair in the plane z = 0: slave (CCW, normal +z) and master (random winding,
/// corners lifted by up to `warp` in z), plus the oracle overlap area.
struct Pair {
    slave: Vec<Point>,
    master: Vec<Point>,
    oracle: Real,
}

fn random_pair(rng: &mut Rng, n_slave: usize, n_master: usize, warp: Real) -> Pair {
    let slave = convex_polygon(rng, n_slave, (0.0, 0.0), 1.0);
    let c = (rng.range(-1.5, 1.5), rng.range(-1.5, 1.5));
    let size = rng.range(0.2, 1.5);
    let mut master = convex_polygon(rng, n_master, c, size);
    if rng.unit() < 0.5 {
        master.reverse();
    }
    for q in &mut master {
        q.z = -0.05 + rng.range(-warp, warp);
    }
    let s2: Vec<_> = slave.iter().map(|q| (q.x, q.y)).collect();
    let m2: Vec<_> = master.iter().map(|q| (q.x, q.y)).collect();
    let clipped = clip_polygon(&ccw(&m2), &s2);
    let oracle = if clipped.len() < 3 {
        0.0
    } else {
        shoelace(&clipped).abs()
    };
    Pair {
        slave,
        master,
        oracle,
    }
}

/// Segmentation area (0 for none) with the slave normal `R·z` and master normal `−R·z`.
#[track_caller]
fn overlap(slave: &[Point], master: &[Point], motion: &Motion, mode: MortarMode) -> Option<Real> {
    let s: Vec<Point> = slave.iter().map(|p| motion.apply(p)).collect();
    let m: Vec<Point> = master.iter().map(|p| motion.apply(p)).collect();
    let n = motion.rotate(&Vector::z());
    let sf = MortarFace::new(Geometry::new(kind_of(s.len()), &s).unwrap(), n).unwrap();
    let mf = MortarFace::new(Geometry::new(kind_of(m.len()), &m).unwrap(), -n).unwrap();
    let settings = SegmentationSettings {
        mode,
        distance_threshold: 1e24,
    };
    exact_segmentation(&sf, &mf, &settings)
        .unwrap()
        .map(|seg| seg.overlap_area())
}

/// Kratos' Q49 configuration: a quadrilateral master entirely inside a triangle slave.
fn is_q49(pair: &Pair) -> bool {
    if pair.slave.len() != 3 || pair.master.len() != 4 {
        return false;
    }
    let s2: Vec<_> = pair.slave.iter().map(|q| (q.x, q.y)).collect();
    pair.master
        .iter()
        .all(|q| clip_polygon(&[(q.x, q.y), (q.x, q.y), (q.x, q.y)], &s2).len() == 3)
}

/// Kratos' quadrilateral `IsInside` tests the last Newton iterate whatever the outcome: for a
/// point far outside an irregular quadrilateral whose bilinear inverse does not converge, that
/// iterate can land inside, adding a spurious polygon vertex (Kratos mode only). True when some
/// node of one face has no converged local coordinates on the other.
fn kratos_newton_unreliable(pair: &Pair) -> bool {
    let flat =
        |pts: &[Point]| -> Vec<Point> { pts.iter().map(|p| Point::new(p.x, p.y, 0.0)).collect() };
    let (s, m) = (flat(&pair.slave), flat(&pair.master));
    let gs = Geometry::new(kind_of(s.len()), &s).unwrap();
    let gm = Geometry::new(kind_of(m.len()), &m).unwrap();
    m.iter().any(|p| gs.point_local_coordinates(p).is_err())
        || s.iter().any(|p| gm.point_local_coordinates(p).is_err())
}

#[test]
fn overlap_area_matches_sutherland_hodgman() {
    let mut rng = Rng::new(0x4d4f_5254);
    let mut n_overlaps = 0;
    let mut n_kratos_skipped = 0;
    for case in 0..600 {
        let (ns, nm) = [(3, 3), (3, 4), (4, 3), (4, 4)][case % 4];
        let warp = if case % 8 < 4 { 0.0 } else { 0.02 };
        let pair = random_pair(&mut rng, ns, nm, warp);
        let motion = if case % 3 == 0 {
            Motion::identity()
        } else {
            Motion::random(&mut rng)
        };
        for mode in MODES {
            let got = overlap(&pair.slave, &pair.master, &motion, mode);
            if mode == MortarMode::Kratos && (is_q49(&pair) || kratos_newton_unreliable(&pair)) {
                n_kratos_skipped += 1;
                continue;
            }
            match got {
                Some(a) => {
                    assert!(
                        (a - pair.oracle).abs() <= 1e-9,
                        "case {case} {mode:?}: {a} vs oracle {}",
                        pair.oracle
                    );
                    n_overlaps += 1;
                }
                None => assert!(
                    pair.oracle <= 1e-9,
                    "case {case} {mode:?}: oracle {}",
                    pair.oracle
                ),
            }
        }
    }
    assert!(n_overlaps > 300, "too few overlapping cases: {n_overlaps}");
    assert!(
        n_kratos_skipped < 150,
        "Kratos comparisons skipped: {n_kratos_skipped}"
    );
}

#[test]
fn area_is_symmetric_for_coplanar_pairs() {
    let mut rng = Rng::new(7);
    for case in 0..200 {
        let (ns, nm) = [(3, 3), (3, 4), (4, 3), (4, 4)][case % 4];
        let pair = random_pair(&mut rng, ns, nm, 0.0);
        let master: Vec<Point> = pair
            .master
            .iter()
            .map(|q| Point::new(q.x, q.y, 0.0))
            .collect();
        // Swap the roles: the master (made CCW, normal +z) becomes the slave.
        let m2: Vec<_> = master.iter().map(|q| (q.x, q.y)).collect();
        let as_slave: Vec<Point> = if shoelace(&m2) < 0.0 {
            master.iter().rev().copied().collect()
        } else {
            master.clone()
        };
        let a = overlap(
            &pair.slave,
            &master,
            &Motion::identity(),
            MortarMode::Robust,
        );
        let b = overlap(
            &as_slave,
            &pair.slave,
            &Motion::identity(),
            MortarMode::Robust,
        );
        let (a, b) = (a.unwrap_or(0.0), b.unwrap_or(0.0));
        assert!((a - b).abs() <= 1e-9, "case {case}: {a} vs {b}");
    }
}

#[test]
fn robust_mode_is_invariant_under_uniform_scaling() {
    let mut rng = Rng::new(11);
    for case in 0..120 {
        let (ns, nm) = [(3, 3), (3, 4), (4, 3), (4, 4)][case % 4];
        let pair = random_pair(&mut rng, ns, nm, 0.01);
        let base = overlap(
            &pair.slave,
            &pair.master,
            &Motion::identity(),
            MortarMode::Robust,
        );
        for exp in [-6, -3, 3, 6] {
            let mut motion = Motion::random(&mut rng);
            motion.scale = 10f64.powi(exp);
            motion.shift *= motion.scale;
            let got = overlap(&pair.slave, &pair.master, &motion, MortarMode::Robust);
            match (base, got) {
                (Some(a), Some(b)) => {
                    let b = b / (motion.scale * motion.scale);
                    assert!((a - b).abs() <= 1e-9, "case {case} 1e{exp}: {a} vs {b}");
                }
                (None, None) => {}
                (a, b) => {
                    let (a, b) = (a.unwrap_or(0.0), b.unwrap_or(0.0) / motion.scale.powi(2));
                    assert!(a.max(b) <= 1e-9, "case {case} 1e{exp}: {a} vs {b}");
                }
            }
        }
    }
}

/// A flat master patch covering [−0.5, 1.5]²: `n`×`n` cells with jittered interior nodes,
/// split into triangles (or kept as quadrilaterals), at height `z`.
fn master_patch(rng: &mut Rng, n: usize, quads: bool, z: Real) -> Vec<Vec<Point>> {
    let h = 2.0 / n as Real;
    let mut grid = vec![vec![Point::origin(); n + 1]; n + 1];
    for (i, row) in grid.iter_mut().enumerate() {
        for (j, q) in row.iter_mut().enumerate() {
            let interior = i > 0 && i < n && j > 0 && j < n;
            let jitter = if interior { 0.2 * h } else { 0.0 };
            *q = Point::new(
                -0.5 + i as Real * h + rng.range(-jitter, jitter),
                -0.5 + j as Real * h + rng.range(-jitter, jitter),
                z,
            );
        }
    }
    let mut faces = Vec::new();
    for i in 0..n {
        for j in 0..n {
            // Clockwise seen from +z: the master faces the slave below it… i.e. normal −z.
            let (a, b, c, d) = (
                grid[i][j],
                grid[i][j + 1],
                grid[i + 1][j + 1],
                grid[i + 1][j],
            );
            if quads {
                faces.push(vec![a, b, c, d]);
            } else if (i + j) % 2 == 0 {
                faces.push(vec![a, b, c]);
                faces.push(vec![a, c, d]);
            } else {
                faces.push(vec![a, b, d]);
                faces.push(vec![b, c, d]);
            }
        }
    }
    faces
}

/// Assembles `Σ D` and `Σ M·f(x_master)` over the master patch for one slave and solves for
/// the slave values; returns the maximum error against `f` at the slave nodes.
fn mapping_error(
    slave: &[Point],
    patch: &[Vec<Point>],
    mode: MortarMode,
    f: &dyn Fn(&Point) -> Real,
) -> Real {
    let n_s = slave.len();
    let sf = MortarFace::new(Geometry::new(kind_of(n_s), slave).unwrap(), Vector::z()).unwrap();
    let settings = SegmentationSettings {
        mode,
        distance_threshold: 1e24,
    };
    let mut d = nalgebra::DMatrix::<Real>::zeros(n_s, n_s);
    let mut rhs = nalgebra::DVector::<Real>::zeros(n_s);
    let mut covered = 0.0;
    for master in patch {
        let mf = MortarFace::new(
            Geometry::new(kind_of(master.len()), master).unwrap(),
            -Vector::z(),
        )
        .unwrap();
        let Some(seg) = exact_segmentation(&sf, &mf, &settings).unwrap() else {
            continue;
        };
        covered += seg.overlap_area();
        let gps = integration_points(&sf, &mf, &seg, &OperatorSettings::mapper()).unwrap();
        let basis = dual_basis(&sf, &gps);
        let ops = mortar_operators(&sf, &mf, &gps, Some(&basis));
        // Partition of unity of the pair: Σ_j M_ij = Σ_k D_ik.
        for i in 0..n_s {
            let sm: Real = ops.m.row(i).iter().sum();
            let sd: Real = ops.d.row(i).iter().sum();
            assert!((sm - sd).abs() <= 1e-12, "row sums {sm} vs {sd}");
            if basis.is_dual() {
                for k in 0..n_s {
                    if k != i {
                        assert!(ops.d[(i, k)].abs() <= 1e-12, "D not diagonal");
                    }
                }
            }
        }
        for i in 0..n_s {
            for k in 0..n_s {
                d[(i, k)] += ops.d[(i, k)];
            }
        }
        let fm: Vec<Real> = master.iter().map(f).collect();
        for i in 0..n_s {
            for (j, v) in fm.iter().enumerate() {
                rhs[i] += ops.m[(i, j)] * v;
            }
        }
    }
    let area = Geometry::new(kind_of(n_s), slave)
        .unwrap()
        .area_robust()
        .unwrap();
    assert!(
        (covered - area).abs() <= 1e-10,
        "covered {covered} of {area}"
    );
    let v = d.lu().solve(&rhs).expect("Σ D invertible");
    slave
        .iter()
        .zip(v.iter())
        .map(|(p, v)| (f(p) - v).abs())
        .fold(0.0, Real::max)
}

#[test]
fn dual_mortar_maps_constant_and_linear_fields_exactly() {
    let mut rng = Rng::new(3);
    let constant = |_: &Point| 2.5;
    let linear = |p: &Point| 1.0 + 2.0 * p.x - 3.0 * p.y;
    let tri = vec![
        Point::new(0.1, 0.05, 0.0),
        Point::new(0.95, 0.2, 0.0),
        Point::new(0.3, 0.9, 0.0),
    ];
    let quad = vec![
        Point::new(0.0, 0.0, 0.0),
        Point::new(1.0, 0.1, 0.0),
        Point::new(0.9, 1.0, 0.0),
        Point::new(0.05, 0.85, 0.0),
    ];
    // Matching: the slave itself as the only master (reversed).
    for slave in [&tri, &quad] {
        let rev: Vec<Point> = slave
            .iter()
            .rev()
            .map(|p| Point::new(p.x, p.y, -0.01))
            .collect();
        for mode in MODES {
            for f in [&constant as &dyn Fn(&Point) -> Real, &linear] {
                let e = mapping_error(slave, std::slice::from_ref(&rev), mode, f);
                assert!(e <= 1e-12, "matching {mode:?}: {e}");
            }
        }
    }
    // Non-matching patches (triangles in both modes; quadrilaterals in robust mode, since
    // Kratos' Q49 cells are wrong for a quadrilateral master inside a triangle slave).
    for round in 0..6 {
        let n = 3 + round % 3;
        let tris = master_patch(&mut rng, n, false, -0.02);
        let quads = master_patch(&mut rng, n, true, -0.02);
        for slave in [&tri, &quad] {
            for f in [&constant as &dyn Fn(&Point) -> Real, &linear] {
                for mode in MODES {
                    let e = mapping_error(slave, &tris, mode, f);
                    assert!(e <= 1e-10, "triangles {mode:?} n={n}: {e}");
                }
                let e = mapping_error(slave, &quads, MortarMode::Robust, f);
                assert!(e <= 1e-10, "quadrilaterals n={n}: {e}");
            }
        }
    }
}

#[test]
fn segments_2d_match_interval_intersection() {
    let mut rng = Rng::new(2024);
    let mut n_overlaps = 0;
    for case in 0..400 {
        let a = rng.range(-1.0, 1.0);
        let b = a + rng.range(0.2, 2.0);
        let c = rng.range(-2.0, 2.0);
        let d = c + rng.range(0.2, 2.0);
        let gap = rng.range(-0.05, 0.05);
        let oracle = (b.min(d) - a.max(c)).max(0.0);
        // Slave along +x with normal (0,−1); master along −x below, normal (0, 1); whole
        // configuration rotated in the xy plane.
        let angle = rng.range(-3.0, 3.0);
        let (sn, cs) = angle.sin_cos();
        let rot = |x: Real, y: Real| Point::new(cs * x - sn * y, sn * x + cs * y, 0.0);
        let rotv = |x: Real, y: Real| Vector::new(cs * x - sn * y, sn * x + cs * y, 0.0);
        let slave = [rot(a, 0.0), rot(b, 0.0)];
        let master = [rot(d, -gap), rot(c, -gap)];
        let s_n = [rotv(0.0, -1.0); 2];
        let m_n = [rotv(0.0, 1.0); 2];
        let sf = MortarFace::new(
            Geometry::new(GeometryKind::Line2D2, &slave).unwrap(),
            s_n[0],
        )
        .unwrap()
        .with_nodal_normals(&s_n)
        .unwrap();
        let mf = MortarFace::new(
            Geometry::new(GeometryKind::Line2D2, &master).unwrap(),
            m_n[0],
        )
        .unwrap()
        .with_nodal_normals(&m_n)
        .unwrap();
        for mode in MODES {
            let settings = SegmentationSettings {
                mode,
                distance_threshold: 1e24,
            };
            let got = exact_segmentation(&sf, &mf, &settings).unwrap();
            match got {
                Some(seg) => {
                    let l = seg.overlap_area();
                    assert!(
                        (l - oracle).abs() <= 1e-9,
                        "case {case} {mode:?}: {l} vs {oracle}"
                    );
                    let w: Real = integration_points(&sf, &mf, &seg, &OperatorSettings::explicit())
                        .unwrap()
                        .iter()
                        .map(|g| g.weight)
                        .sum();
                    assert!((w - oracle).abs() <= 1e-9, "weights {w} vs {oracle}");
                    n_overlaps += 1;
                }
                None => assert!(oracle <= 1e-9, "case {case} {mode:?}: missed {oracle}"),
            }
        }
    }
    assert!(n_overlaps > 200, "{n_overlaps}");
}

/// One `SlaveSegmentation` reused for many masters gives, for each, what a fresh
/// `exact_segmentation` gives (the slave's share carries nothing from one master to the
/// next): cells and `None`s, masters beyond the distance threshold (which a quadrilateral
/// slave's own warp can exceed), degenerate masters, and the errors of a degenerate slave.
#[test]
fn a_prepared_slave_segments_each_master_as_a_fresh_one() {
    let mut rng = Rng::new(0x5E6_AE17);
    let mut with_cells = 0;
    for round in 0..120 {
        let mode = MODES[round % 2];
        let n_slave = 3 + round % 2;
        let motion = Motion::random(&mut rng);
        let mut slave = convex_polygon(&mut rng, n_slave, (0.0, 0.0), 1.0);
        for q in &mut slave {
            q.z = rng.range(-0.05, 0.05);
        }
        if round % 17 == 0 {
            // A degenerate slave: every pair reports its error.
            slave[1] = slave[0];
        }
        let s: Vec<Point> = slave.iter().map(|p| motion.apply(p)).collect();
        let n = motion.rotate(&Vector::z());
        let sf = MortarFace::new(Geometry::new(kind_of(n_slave), &s).unwrap(), n).unwrap();
        let settings = SegmentationSettings {
            mode,
            distance_threshold: [1e24, 0.2, 0.04][round % 3],
        };
        let prepared = SlaveSegmentation::new(&sf, &settings);
        for k in 0..12 {
            let n_master = 3 + (k + round) % 2;
            let c = (rng.range(-1.5, 1.5), rng.range(-1.5, 1.5));
            let size = rng.range(0.2, 1.5);
            let mut master = convex_polygon(&mut rng, n_master, c, size);
            for q in &mut master {
                q.z = rng.range(-0.3, 0.1);
            }
            if k == 5 {
                master[2] = master[1];
            }
            let m: Vec<Point> = master.iter().map(|p| motion.apply(p)).collect();
            let mf = MortarFace::new(Geometry::new(kind_of(n_master), &m).unwrap(), -n).unwrap();
            let fresh = exact_segmentation(&sf, &mf, &settings);
            let reused = prepared.segment(&mf);
            assert_eq!(fresh, reused, "round {round}, master {k}");
            with_cells += usize::from(matches!(fresh, Ok(Some(ref g)) if !g.cells().is_empty()));
        }
    }
    assert!(with_cells > 200, "{with_cells}");
}

/// A prepared slave keeps what it computed for each master node and polygon point for its next
/// masters: on a master grid whose faces share nodes (quadrilaterals and triangles, a slave
/// whose own nodes lie on master nodes and edges, masters visited in random order and more
/// than once, a grid with more nodes than the slave keeps), every master still gets what a
/// fresh `exact_segmentation` gives, bit for bit.
#[test]
fn a_prepared_slave_segments_masters_sharing_nodes_as_fresh_ones() {
    let mut rng = Rng::new(0x0A11_CE11);
    let mut with_cells = 0;
    for round in 0..40 {
        let mode = MODES[round % 2];
        let motion = if round % 3 == 0 {
            Motion::identity()
        } else {
            Motion::random(&mut rng)
        };
        // A (2k+1)² node grid of spacing 0.5 around the origin, slightly warped, in a plane.
        let k: i32 = if round % 4 == 3 { 6 } else { 3 };
        let side = (2 * k + 1) as usize;
        let warp = [0.0, 0.05][round % 2];
        let grid: Vec<Point> = (-k..=k)
            .flat_map(|j| (-k..=k).map(move |i| (i, j)))
            .map(|(i, j)| {
                let (x, y) = (0.5 * f64::from(i), 0.5 * f64::from(j));
                Point::new(
                    x + warp * rng.range(-1.0, 1.0),
                    y + warp * rng.range(-1.0, 1.0),
                    -0.02 + warp * rng.range(-0.1, 0.1),
                )
            })
            .collect();
        let node = |i: usize, j: usize| motion.apply(&grid[j * side + i]);
        let mut masters: Vec<Vec<Point>> = Vec::new();
        for j in 0..side - 1 {
            for i in 0..side - 1 {
                let quad = [
                    node(i, j),
                    node(i + 1, j),
                    node(i + 1, j + 1),
                    node(i, j + 1),
                ];
                if (i + j + round) % 5 == 0 {
                    masters.push(vec![quad[0], quad[1], quad[2]]);
                    masters.push(vec![quad[0], quad[2], quad[3]]);
                } else {
                    masters.push(quad.to_vec());
                }
            }
        }
        // The slave: a quadrilateral or triangle over the middle, with a node on a master node
        // and one on a master edge.
        let mut slave = vec![
            Point::new(-0.5, -0.5, 0.0),
            Point::new(0.25, -0.6, 0.01),
            Point::new(0.7, 0.55, -0.01),
            Point::new(-0.6, 0.4, 0.0),
        ];
        if round % 5 == 4 {
            slave.pop();
        }
        let s: Vec<Point> = slave.iter().map(|p| motion.apply(p)).collect();
        let n = motion.rotate(&Vector::z());
        let sf = MortarFace::new(Geometry::new(kind_of(s.len()), &s).unwrap(), n).unwrap();
        let settings = SegmentationSettings {
            mode,
            distance_threshold: [1e24, 0.025][round % 2],
        };
        let prepared = SlaveSegmentation::new(&sf, &settings);
        for _ in 0..3 * masters.len() {
            let m = &masters[(rng.unit() * masters.len() as f64) as usize];
            let mf = MortarFace::new(Geometry::new(kind_of(m.len()), m).unwrap(), -n).unwrap();
            let fresh = exact_segmentation(&sf, &mf, &settings);
            assert_eq!(fresh, prepared.segment(&mf), "round {round}");
            with_cells += usize::from(matches!(fresh, Ok(Some(ref g)) if !g.cells().is_empty()));
        }
    }
    assert!(with_cells > 500, "{with_cells}");
}

// See: issue 24, cause 5 (the 2D projection's test on Δξ from absolute coordinates never
// passes far from the origin, and the master node is dropped).
/// Robust mode segments 2D line pairs far from the origin as near it: the overlap of
/// non-matching flat lines translated by 1e3 … 1e8 is the interval intersection, up to the
/// rounding of the translated coordinates.
#[test]
fn robust_2d_segments_keep_their_overlap_far_from_the_origin() {
    let mut rng = Rng::new(0xFA2_0261);
    let mut n_overlaps = 0;
    for case in 0..300 {
        let a = rng.range(-1.0, 1.0) * 0.01;
        let b = a + rng.range(0.2, 2.0) * 0.01;
        let c = rng.range(-2.0, 2.0) * 0.01;
        let d = c + rng.range(0.2, 2.0) * 0.01;
        let gap = rng.range(-0.05, 0.05) * 0.01;
        let oracle = (b.min(d) - a.max(c)).max(0.0);
        let offset = Vector::new(
            10f64.powf(rng.range(3.0, 8.0)),
            10f64.powf(rng.range(3.0, 8.0)),
            0.0,
        );
        let at = |x: Real, y: Real| Point::new(x, y, 0.0) + offset;
        let slave = [at(a, 0.0), at(b, 0.0)];
        let master = [at(d, -gap), at(c, -gap)];
        let s_n = [Vector::new(0.0, -1.0, 0.0); 2];
        let m_n = [Vector::new(0.0, 1.0, 0.0); 2];
        fn face<'a>(pts: &'a [Point; 2], n: &'a [Vector; 2]) -> MortarFace<'a> {
            MortarFace::new(Geometry::new(GeometryKind::Line2D2, pts).unwrap(), n[0])
                .unwrap()
                .with_nodal_normals(n)
                .unwrap()
        }
        let (sf, mf) = (face(&slave, &s_n), face(&master, &m_n));
        let settings = SegmentationSettings {
            mode: MortarMode::Robust,
            distance_threshold: 1e24,
        };
        let tolerance = 1e-9 * 0.01 + 64.0 * Real::EPSILON * offset.norm();
        match exact_segmentation(&sf, &mf, &settings).unwrap() {
            Some(seg) => {
                let l = seg.overlap_area();
                assert!(
                    (l - oracle).abs() <= tolerance,
                    "case {case}: {l} vs {oracle}"
                );
                n_overlaps += 1;
            }
            None => assert!(oracle <= tolerance, "case {case}: missed {oracle}"),
        }
    }
    assert!(n_overlaps > 150, "{n_overlaps}");
}
