//! `global_coordinates` → `point_local_coordinates` round trips for every kind (distorted and
//! curved geometries included), the inside test, and known normals.

use crate::common::Rng;
use csm_geometry::math::{Point, Vector};
use csm_geometry::{Geometry, GeometryKind, reference_node_coordinates};

/// A random interior local point of `kind`'s reference element.
fn interior_local(kind: GeometryKind, rng: &mut Rng) -> Point {
    use GeometryKind as K;
    let mut p = [0.0; 3];
    match kind {
        K::Triangle3D3 | K::Triangle3D6 | K::Triangle2D3 | K::Triangle2D6 => {
            let (a, b) = (rng.unit(), rng.unit());
            let (a, b) = if a + b > 1.0 {
                (1.0 - a, 1.0 - b)
            } else {
                (a, b)
            };
            p[0] = a * 0.98 + 0.005;
            p[1] = b * 0.98 + 0.005;
        }
        K::Tetrahedra3D4 | K::Tetrahedra3D10 => loop {
            let v = [rng.unit(), rng.unit(), rng.unit()];
            if v[0] + v[1] + v[2] < 0.98 {
                p = v;
                break;
            }
        },
        K::Prism3D6 => {
            let (a, b) = (rng.unit(), rng.unit());
            let (a, b) = if a + b > 1.0 {
                (1.0 - a, 1.0 - b)
            } else {
                (a, b)
            };
            p = [a * 0.98, b * 0.98, rng.range(0.01, 0.99)];
        }
        _ => {
            for c in p.iter_mut().take(kind.local_dim()) {
                *c = rng.range(-0.99, 0.99);
            }
        }
    }
    Point::new(p[0], p[1], p[2])
}

/// Reference nodes embedded in space: surfaces and lines get a rotation and a lift, every node
/// a jitter (distorted quads, curved quadratic faces), 2D kinds stay in z = 0.
fn embedded(kind: GeometryKind, rng: &mut Rng) -> Vec<Point> {
    let r = if kind.working_dim() == 2 {
        parry3d_f64::na::UnitQuaternion::from_scaled_axis(Vector::z() * rng.range(-3.0, 3.0))
    } else {
        rng.rotation()
    };
    let t = rng.vector(-3.0, 3.0);
    let scale = rng.range(0.5, 3.0);
    reference_node_coordinates(kind)
        .iter()
        .map(|a| {
            let mut v = Vector::new(a[0], a[1], a[2]) * scale;
            let j = rng.vector(-0.1, 0.1) * scale;
            v += if kind.working_dim() == 2 {
                Vector::new(j.x, j.y, 0.0)
            } else if kind.is_face() {
                // Keep the face roughly flat but warped/distorted.
                Vector::new(j.x, j.y, 0.5 * j.z)
            } else {
                j
            };
            Point::from(r * v + t)
        })
        .collect()
}

#[test]
fn round_trip_every_kind() {
    let mut rng = Rng::new(0x10CA1);
    for kind in GeometryKind::ALL {
        for _ in 0..20 {
            let pts = embedded(kind, &mut rng);
            let g = Geometry::new(kind, &pts).unwrap();
            for _ in 0..10 {
                let local = interior_local(kind, &mut rng);
                let x = g.global_coordinates(&local);
                let back = g.point_local_coordinates(&x).unwrap();
                assert!(
                    (back - local).norm() < 1e-7,
                    "{kind:?}: {local:?} -> {back:?}"
                );
                assert!(g.is_inside(&x, 1e-9).unwrap().is_some(), "{kind:?} inside");
            }
        }
    }
}

#[test]
fn faces_project_off_surface_points() {
    let mut rng = Rng::new(0xF1A7);
    for kind in [GeometryKind::Triangle3D3, GeometryKind::Quadrilateral3D4] {
        // Flat (undistorted) faces: the offset along the normal does not change ξ.
        let r = rng.rotation();
        let pts: Vec<Point> = reference_node_coordinates(kind)
            .iter()
            .map(|a| Point::from(r * Vector::new(a[0] * 2.0, a[1], 0.0)))
            .collect();
        let g = Geometry::new(kind, &pts).unwrap();
        let local = interior_local(kind, &mut rng);
        let n = g.unit_normal(&local).unwrap();
        let x = g.global_coordinates(&local) + n * 0.7;
        let back = g.point_local_coordinates(&x).unwrap();
        assert!((back - local).norm() < 1e-9, "{kind:?}");
    }
}

#[test]
fn points_outside_are_outside() {
    let pts = [
        Point::new(0.0, 0.0, 0.0),
        Point::new(2.0, 0.0, 0.0),
        Point::new(2.5, 1.5, 0.0),
        Point::new(-0.2, 1.0, 0.0),
    ];
    let g = Geometry::new(GeometryKind::Quadrilateral3D4, &pts).unwrap();
    assert!(
        g.is_inside(&Point::new(3.0, 0.5, 0.0), 1e-6)
            .unwrap()
            .is_none()
    );
    assert!(
        g.is_inside(&Point::new(1.0, 0.5, 0.0), 0.0)
            .unwrap()
            .is_some()
    );
    // Distorted quad centre is not at (0, 0) but its corners are at (±1, ±1).
    let l = g.point_local_coordinates(&pts[2]).unwrap();
    assert!((l - Point::new(1.0, 1.0, 0.0)).norm() < 1e-9);
}

#[test]
fn known_normals() {
    // Counter-clockwise seen from +z → +z.
    let tri = [
        Point::new(0.0, 0.0, 1.0),
        Point::new(1.0, 0.0, 1.0),
        Point::new(0.0, 1.0, 1.0),
    ];
    let g = Geometry::new(GeometryKind::Triangle3D3, &tri).unwrap();
    assert_eq!(
        g.unit_normal(&Point::new(0.2, 0.2, 0.0)).unwrap(),
        Vector::z()
    );
    let quad = [
        Point::new(0.0, 0.0, 0.0),
        Point::new(0.0, 1.0, 0.0),
        Point::new(0.0, 1.0, 1.0),
        Point::new(0.0, 0.0, 1.0),
    ];
    let g = Geometry::new(GeometryKind::Quadrilateral3D4, &quad).unwrap();
    assert_eq!(g.unit_normal(&Point::origin()).unwrap(), Vector::x());
    // 2D line from (0,0) to (0,1): normal (t_y, -t_x) = +x.
    let line = [
        Point::new(0.0, 0.0, 0.0),
        Point::new(0.0, 1.0, 0.0),
        Point::new(0.0, 0.5, 0.0),
    ];
    let g = Geometry::new(GeometryKind::Line2D3, &line).unwrap();
    let n = g.unit_normal(&Point::new(0.3, 0.0, 0.0)).unwrap();
    assert!((n - Vector::x()).norm() < 1e-15);
    assert!((g.length().unwrap() - 1.0).abs() < 1e-14);
}

#[test]
fn warped_quadrilaterals_kratos_order_agrees_with_least_squares() {
    // Quadrilateral3D4 uses Kratos' evaluation order (bit-faithful to Kratos); it is the same
    // Gauss–Newton iteration as the generic least-squares solver, so converged results agree to
    // the convergence tolerance, and off-surface points give the same tangent-plane solution.
    let mut rng = Rng::new(0x0A4B);
    let kind = GeometryKind::Quadrilateral3D4;
    for _ in 0..50 {
        let pts = embedded(kind, &mut rng);
        let g = Geometry::new(kind, &pts).unwrap();
        for _ in 0..10 {
            let local = interior_local(kind, &mut rng);
            let n = g.unit_normal(&local).unwrap();
            let x = g.global_coordinates(&local) + n * rng.range(-0.05, 0.05);
            let kratos = g.point_local_coordinates(&x).unwrap();
            let lsq = g.point_local_coordinates_least_squares(&x).unwrap();
            assert!((kratos - lsq).norm() < 1e-8, "{kratos:?} vs {lsq:?}");
            assert_eq!(kratos.z, 0.0);
            let inside = g.is_inside(&x, 1e-6).unwrap();
            if local.x.abs() < 0.9 && local.y.abs() < 0.9 {
                assert_eq!(inside, Some(kratos));
            }
        }
    }
}

/// `separated_along` is an exact pre-test of the inside test: wherever it says "separated",
/// `is_inside` says outside — on points all around distorted linear solids, on points exactly
/// on the enlarged reference element's boundary (never separated) — and it does answer for
/// the normal check's probes (0.1 · face length outside each face, along the face normal).
#[test]
fn separated_along_implies_outside() {
    use GeometryKind as K;
    let mut rng = Rng::new(0x5E9A);
    let tol = 5e-7;
    for kind in [K::Tetrahedra3D4, K::Prism3D6, K::Hexahedra3D8] {
        let (mut probes, mut separated_probes, mut separated_points) = (0, 0, 0);
        for _ in 0..100 {
            let pts = embedded(kind, &mut rng);
            let g = Geometry::new(kind, &pts).unwrap();
            g.check_local_coordinates().unwrap();
            // Random points around the element, random directions (and the axes).
            for _ in 0..40 {
                let local = interior_local(kind, &mut rng);
                let spread = Vector::new(
                    rng.range(-0.6, 0.6),
                    rng.range(-0.6, 0.6),
                    rng.range(-0.6, 0.6),
                );
                let x = g.global_coordinates(&(local + spread));
                let inside = g.is_inside(&x, tol).unwrap().is_some();
                for d in [rng.unit_vector(), Vector::x(), -Vector::z()] {
                    if g.separated_along(&x, &d, tol) {
                        separated_points += 1;
                        assert!(!inside, "{kind:?}: {x:?} separated along {d:?} but inside");
                    }
                }
            }
            // Points on the enlarged boundary are inside: never separated.
            let corner = match kind {
                K::Hexahedra3D8 => Point::new(1.0 + tol, -1.0 - tol, 1.0 + tol),
                K::Prism3D6 => Point::new(-tol, 1.0 + 2.0 * tol, 1.0 + tol),
                _ => Point::new(-tol, -tol, 1.0 + 3.0 * tol),
            };
            let x = g.global_coordinates(&corner);
            for _ in 0..20 {
                assert!(!g.separated_along(&x, &rng.unit_vector(), tol), "{kind:?}");
            }
            // The normal check's probes of a properly oriented element.
            for (face_kind, local) in kind.faces() {
                let face_points: Vec<Point> = local.iter().map(|&l| pts[l]).collect();
                let face = Geometry::new(*face_kind, &face_points).unwrap();
                let centre = face.center();
                let n = face
                    .unit_normal(&face.point_local_coordinates(&centre).unwrap())
                    .unwrap();
                let probe = centre + n * (0.1 * face.length().unwrap());
                probes += 1;
                if g.separated_along(&probe, &n, tol) {
                    separated_probes += 1;
                    assert!(g.is_inside(&probe, tol).unwrap().is_none(), "{kind:?}");
                }
            }
        }
        assert!(separated_points > 100, "{kind:?}: {separated_points}");
        assert!(
            separated_probes * 10 >= probes * 9,
            "{kind:?}: {separated_probes} of {probes} probes separated"
        );
    }
    // Other kinds: no conclusion.
    let tri = [
        Point::new(0.0, 0.0, 0.0),
        Point::new(1.0, 0.0, 0.0),
        Point::new(0.0, 1.0, 0.0),
    ];
    let g = Geometry::new(K::Triangle3D3, &tri).unwrap();
    assert!(!g.separated_along(&Point::new(0.0, 0.0, 5.0), &Vector::z(), tol));
}

/// A face of `kind` (Triangle3D3 or Quadrilateral3D4) for the probe bounds: distorted and
/// warped, often stretched into a sliver, sometimes far from the origin.
fn probe_face(kind: GeometryKind, rng: &mut Rng) -> Vec<Point> {
    let mut pts = embedded(kind, rng);
    let squash = [1.0, 1.0, 0.3, 1e-2, 1e-4, 1e-7][(rng.unit() * 6.0) as usize % 6];
    let axis = rng.unit_vector();
    let far = [0.0, 0.0, 1e3, 1e7, 1e12][(rng.unit() * 5.0) as usize % 5];
    let shift = rng.unit_vector() * far;
    for p in &mut pts {
        let a = p.coords.dot(&axis);
        *p -= axis * (a * (1.0 - squash));
        *p += shift;
    }
    pts
}

/// `centre_probe_bound` bounds what it claims: wherever it answers, the exact centre unit
/// normal and length succeed, the normal is within `cos_floor` of `direction` and the length
/// at least `length_floor` — on distorted, warped, sliver and far-away faces. On well-shaped
/// faces near the origin it answers, tightly; on degenerate ones it does not.
#[test]
fn centre_probe_bound_bounds_the_exact_normal_and_length() {
    use GeometryKind as K;
    let mut rng = Rng::new(0xB0D);
    for kind in [K::Triangle3D3, K::Quadrilateral3D4] {
        let (mut answered, mut tried) = (0, 0);
        for _ in 0..4000 {
            let pts = probe_face(kind, &mut rng);
            let face = Geometry::new(kind, &pts).unwrap();
            tried += 1;
            let Some(b) = face.centre_probe_bound() else {
                continue;
            };
            answered += 1;
            let n = face.centre_unit_normal().unwrap();
            let length = face.length().unwrap();
            assert!((b.direction.norm() - 1.0).abs() < 1e-12);
            assert!(b.direction.dot(&n) >= b.cos_floor, "{kind:?} {pts:?}");
            assert!(length >= b.length_floor, "{kind:?} {pts:?}");
            assert!(b.cos_floor > 0.5 && b.length_floor > 0.0);
        }
        assert!(answered * 3 >= tried, "{kind:?}: {answered} of {tried}");
        // Well shaped near the origin: answered, and tight.
        let square = [
            Point::new(0.0, 0.0, 0.0),
            Point::new(2.0, 0.0, 0.0),
            Point::new(2.0, 2.0, 0.0),
            Point::new(0.0, 2.0, 0.0),
        ];
        let n = kind.n_nodes();
        let face = Geometry::new(kind, &square[..n]).unwrap();
        let b = face.centre_probe_bound().unwrap();
        assert!(b.cos_floor > 1.0 - 1e-9);
        assert!(b.length_floor > 0.999 * face.length().unwrap());
        assert!((b.direction - Vector::z()).norm() < 1e-15);
        // Degenerate: coincident nodes, a needle, non-finite points.
        let mut flat = square;
        flat[2] = flat[1];
        if kind == K::Triangle3D3 {
            flat[2] = Point::new(1.0, 1e-9, 0.0);
        } else {
            flat[3] = flat[0];
        }
        assert!(
            Geometry::new(kind, &flat[..n])
                .unwrap()
                .centre_probe_bound()
                .is_none()
        );
        let mut bad = square;
        bad[0].x = f64::NAN;
        // (`Geometry::new` refuses it already.)
        assert!(Geometry::new(kind, &bad[..n]).map_or(true, |g| g.centre_probe_bound().is_none()));
    }
    // Other kinds: no conclusion.
    let line = [Point::new(0.0, 0.0, 0.0), Point::new(1.0, 0.0, 0.0)];
    assert!(
        Geometry::new(K::Line2D2, &line)
            .unwrap()
            .centre_probe_bound()
            .is_none()
    );
}

/// `separated_beyond` claims only what `separated_along` confirms: every probe
/// `base + s·u` with `s ≥ min_offset` and `u · direction ≥ cos_floor` is separated (so
/// outside), and its claims stop short of probes that are not.
#[test]
fn separated_beyond_implies_separated_along_every_probe() {
    use GeometryKind as K;
    let mut rng = Rng::new(0xBE70);
    let tol = 5e-7;
    for kind in [K::Tetrahedra3D4, K::Prism3D6, K::Hexahedra3D8] {
        let (mut claims, mut refusals) = (0, 0);
        for _ in 0..200 {
            let pts = embedded(kind, &mut rng);
            let g = Geometry::new(kind, &pts).unwrap();
            let base = g.global_coordinates(&interior_local(kind, &mut rng));
            let direction = rng.unit_vector();
            let min_offset = rng.range(0.01, 3.0);
            let cos_floor = rng.range(0.3, 1.0);
            if !g.separated_beyond(&base, &direction, min_offset, cos_floor, tol) {
                refusals += 1;
                continue;
            }
            claims += 1;
            for _ in 0..30 {
                let s = min_offset * rng.range(1.0, 10.0);
                // A unit vector at cosine c ≥ cos_floor from `direction`.
                let c = rng.range(cos_floor, 1.0);
                let side = rng.unit_vector();
                let perp = side - direction * side.dot(&direction);
                let u = if perp.norm() > 1e-6 {
                    direction * c + perp.normalize() * (1.0 - c * c).sqrt()
                } else {
                    direction
                };
                let probe = base + u * s;
                assert!(g.separated_along(&probe, &direction, tol), "{kind:?}");
                // Outside; far probes may meet the iteration error `separated_along`
                // describes on the way (a distorted element), never an inside answer.
                assert!(!matches!(g.is_inside(&probe, tol), Ok(Some(_))), "{kind:?}");
            }
            // At the bound exactly, straight along `direction`: separated too.
            let probe = base + direction * min_offset;
            assert!(g.separated_along(&probe, &direction, tol), "{kind:?}");
        }
        assert!(
            claims > 20 && refusals > 20,
            "{kind:?}: {claims} claims, {refusals} refusals"
        );
        // No conclusion without a positive offset or cosine.
        let pts = embedded(kind, &mut rng);
        let g = Geometry::new(kind, &pts).unwrap();
        let far = Point::new(100.0, 0.0, 0.0);
        assert!(g.separated_beyond(&far, &Vector::x(), 1.0, 1.0, tol));
        assert!(!g.separated_beyond(&far, &Vector::x(), 0.0, 1.0, tol));
        assert!(!g.separated_beyond(&far, &Vector::x(), 1.0, 0.0, tol));
        assert!(!g.separated_beyond(&far, &Vector::x(), f64::NAN, 1.0, tol));
    }
}

/// The normal check's face probes decided by the bounds agree with the exact probes: a
/// face whose bounded probe is separated has its exact probe outside the element; on
/// properly oriented elements almost every face is decided that way, and on inverted ones
/// (the probe pointing inside) none is.
#[test]
fn bounded_face_probes_agree_with_the_exact_probes() {
    use GeometryKind as K;
    let mut rng = Rng::new(0xFACE);
    let tol = 5e-7;
    let lp = 0.1;
    for kind in [K::Tetrahedra3D4, K::Prism3D6, K::Hexahedra3D8] {
        let (mut faces, mut decided, mut decided_inverted) = (0, 0, 0);
        for k in 0..300 {
            let mut pts = embedded(kind, &mut rng);
            let inverted = k % 2 == 1;
            if inverted {
                // A mirror image: the same element with its faces turned inside.
                for p in &mut pts {
                    p.x = -p.x;
                }
            }
            let g = Geometry::new(kind, &pts).unwrap();
            for (face_kind, local) in kind.faces() {
                let face_points: Vec<Point> = local.iter().map(|&l| pts[l]).collect();
                let face = Geometry::new(*face_kind, &face_points).unwrap();
                let centre = face.center();
                let n = face.centre_unit_normal().unwrap();
                let probe = centre + n * (lp * face.length().unwrap());
                let exact_inside = g.is_inside(&probe, tol).unwrap().is_some();
                assert_eq!(exact_inside, inverted, "{kind:?}");
                faces += 1;
                let Some(b) = face.centre_probe_bound() else {
                    continue;
                };
                if g.separated_beyond(&centre, &b.direction, lp * b.length_floor, b.cos_floor, tol)
                {
                    assert!(!exact_inside, "{kind:?}: decided outside, but inside");
                    if inverted {
                        decided_inverted += 1;
                    } else {
                        decided += 1;
                    }
                }
            }
        }
        assert_eq!(decided_inverted, 0, "{kind:?}");
        assert!(
            decided * 2 * 10 >= faces * 9,
            "{kind:?}: {decided} of {} faces",
            faces / 2
        );
    }
}
