//! Unit tests of the `obb` module.
use crate::math::{Point, Vector};
use crate::{Error, ErrorKind, Geometry, GeometryKind, Obb, Obb2};

#[track_caller]
fn close_v(a: &Vector, b: [f64; 3], tol: f64) {
    for k in 0..3 {
        assert!((a[k] - b[k]).abs() <= tol, "{a:?} vs {b:?}");
    }
}

#[track_caller]
fn close(a: f64, b: f64, tol: f64) {
    assert!((a - b).abs() <= tol, "{a} vs {b}");
}

/// Slave 4 of reference §20.1: a 0.5 × 1 quadrilateral in the x–z plane.
fn slave4() -> [Point; 4] {
    [
        Point::new(1.5, 0.0, 0.0),
        Point::new(2.0, 0.0, 0.0),
        Point::new(2.0, 0.0, 1.0),
        Point::new(1.5, 0.0, 1.0),
    ]
}

// See: reference §7.2 / §20.4 (Kratos test_oriented_bounding_box.cpp, "3D complex" slave box).
#[test]
fn branch_a_reproduces_kratos_numbers() {
    let pts = slave4();
    let g = Geometry::new(GeometryKind::Quadrilateral3D4, &pts).unwrap();
    let obb = Obb::from_geometry(&g, 0.1, true).unwrap();
    assert_eq!(obb.center, Point::new(1.75, 0.0, 0.5));
    close_v(&obb.axes[0], [0.447214, 0.0, 0.894427], 1e-6);
    close_v(&obb.axes[1], [0.894427, 0.0, -0.447214], 1e-6);
    close_v(&obb.axes[2], [0.0, 1.0, 0.0], 1e-15);
    close(obb.half_lengths[0], 0.659017, 1e-6);
    close(obb.half_lengths[1], 0.547214, 1e-6);
    close(obb.half_lengths[2], 0.1, 1e-15);
    // Right-handed frame in branch A.
    close_v(&obb.axes[0].cross(&obb.axes[1]), [0.0, 1.0, 0.0], 1e-15);
}

#[test]
fn branch_b_uses_the_normal() {
    let pts = slave4();
    let g = Geometry::new(GeometryKind::Quadrilateral3D4, &pts).unwrap();
    let obb = Obb::from_geometry(&g, 0.1, false).unwrap();
    assert_eq!(obb.center, Point::new(1.75, 0.0, 0.5));
    close_v(&obb.axes[0], [0.0, -1.0, 0.0], 1e-15);
    close_v(&obb.axes[1], [0.447214, 0.0, 0.894427], 1e-6);
    close_v(&obb.axes[2], [0.894427, 0.0, -0.447214], 1e-6);
    close(obb.half_lengths[0], 0.1, 1e-15);
    close(obb.half_lengths[1], 0.659017, 1e-6);
    close(obb.half_lengths[2], 0.547214, 1e-6);
    // A solid always takes branch A.
    let tet = [
        Point::new(0.0, 0.0, 0.0),
        Point::new(1.0, 0.0, 0.0),
        Point::new(0.0, 1.0, 0.0),
        Point::new(0.0, 0.0, 1.0),
    ];
    let g = Geometry::new(GeometryKind::Tetrahedra3D4, &tet).unwrap();
    let a = Obb::from_geometry(&g, 0.0, false).unwrap();
    assert_eq!(a, Obb::build_from_aabb(&g, 0.0).unwrap());
}

// See: quirk Q1.
#[test]
fn obb2_uses_the_aabb_diagonal() {
    let pts = [Point::new(0.0, 1.0, 0.0), Point::new(1.0, 0.0, 0.0)];
    let g = Geometry::new(GeometryKind::Line2D2, &pts).unwrap();
    let obb = Obb2::from_geometry(&g, 0.1).unwrap();
    let s = 0.5f64.sqrt();
    close_v(&obb.axes[0], [s, s, 0.0], 1e-15);
    close_v(&obb.axes[1], [s, -s, 0.0], 1e-15);
    assert_eq!(obb.center, Point::new(0.5, 0.5, 0.0));
    close(obb.half_lengths[0], 0.5 * 2f64.sqrt() + 0.1, 1e-15);
    assert_eq!(obb.half_lengths[1], 0.1);
    // The segment's own end points are outside the box (only covered near the midpoint).
    assert!(!obb.contains_point(&pts[0]));
    assert!(obb.contains_point(&Point::new(0.5, 0.5, 0.0)));
}

// See: quirk Q12.
#[test]
fn zero_extent_is_the_kratos_zero_norm_error() {
    let pts = [Point::new(1.0, 2.0, 3.0); 3];
    let g = Geometry::new(GeometryKind::Triangle3D3, &pts).unwrap();
    for e in [
        Obb::from_geometry(&g, 0.1, true).unwrap_err(),
        Obb::from_geometry(&g, 0.1, false).unwrap_err(),
        Obb2::from_geometry(&g, 0.1).unwrap_err(),
    ] {
        assert!(matches!(e.kind(), ErrorKind::Degenerate(_)), "{e}");
    }
    let ok = slave4();
    let g = Geometry::new(GeometryKind::Quadrilateral3D4, &ok).unwrap();
    assert_eq!(
        *Obb::from_geometry(&g, f64::NAN, true).unwrap_err().kind(),
        ErrorKind::NonFinite
    );
}

/// [`Obb::check_build_from_aabb`] fails exactly where [`Obb::build_from_aabb`] and
/// [`Obb2::from_geometry`] fail, with the same error: random triangles and quadrilaterals over
/// many scales, with nodes coincident, on a line, a diagonal at the ε threshold, and
/// non-finite enlargements.
#[test]
fn the_aabb_box_check_fails_where_the_build_fails() {
    let mut uniform = crate::test_support::uniform(0x2545_F491_4F6C_DD1D);
    let mut next = move || uniform() + 0.5;
    let (mut failures, mut builds) = (0, 0);
    for case in 0..4000 {
        let scale = 10f64.powi((case % 40) - 20);
        let n = if case % 2 == 0 { 3 } else { 4 };
        let mut pts: Vec<Point> = (0..n)
            .map(|_| Point::new(next() * scale, next() * scale, next() * scale))
            .collect();
        match case % 5 {
            // All nodes at one point.
            1 => {
                let p0 = pts[0];
                pts.iter_mut().for_each(|p| *p = p0);
            }
            // Spread along one axis by about ε.
            2 => {
                let p0 = pts[0];
                for (k, p) in pts.iter_mut().enumerate() {
                    *p = p0 + Vector::new(k as f64 * 0.5 * f64::EPSILON, 0.0, 0.0);
                }
            }
            // On a line.
            3 => {
                let (p0, d) = (pts[0], pts[1] - pts[0]);
                for (k, p) in pts.iter_mut().enumerate() {
                    *p = p0 + d * k as f64;
                }
            }
            _ => {}
        }
        let kind = if n == 3 {
            GeometryKind::Triangle3D3
        } else {
            GeometryKind::Quadrilateral3D4
        };
        let g = Geometry::new(kind, &pts).unwrap();
        for enlargement in [0.0, 0.1 * scale, f64::NAN, f64::INFINITY] {
            let built = Obb::build_from_aabb(&g, enlargement).map(|_| ());
            let built_2d = Obb2::from_geometry(&g, enlargement).map(|_| ());
            let checked = Obb::check_build_from_aabb(&g, enlargement);
            for built in [&built, &built_2d] {
                assert_eq!(
                    built.as_ref().map_err(Error::kind),
                    checked.as_ref().map_err(Error::kind),
                    "case {case}, enlargement {enlargement}: {pts:?}"
                );
            }
            if built.is_err() {
                failures += 1;
            } else {
                builds += 1;
            }
        }
    }
    assert!(
        failures > 2000 && builds > 4000,
        "{failures} failures, {builds} builds"
    );
}

#[test]
fn vertices_follow_the_hexahedron_order() {
    let obb = Obb::new(
        Point::new(1.0, 2.0, 3.0),
        [Vector::x(), Vector::y(), Vector::z()],
        [1.0, 2.0, 3.0],
    );
    let v = obb.vertices();
    assert_eq!(v[0], Point::new(0.0, 0.0, 0.0));
    assert_eq!(v[6], Point::new(2.0, 4.0, 6.0));
    assert_eq!(v[3], Point::new(0.0, 4.0, 0.0));
    for p in v {
        assert!(obb.contains_point(&p));
    }
    assert!(!obb.contains_point(&Point::new(2.0 + 1e-9, 2.0, 3.0)));
    let b = obb.aabb();
    assert_eq!((b.min, b.max), (v[0], v[6]));
}

/// Rodrigues' rotation of `v` about the unit `axis` by `angle`.
fn rotate(v: Vector, axis: Vector, angle: f64) -> Vector {
    let k = axis.normalize();
    v * angle.cos() + k.cross(&v) * angle.sin() + k * k.dot(&v) * (1.0 - angle.cos())
}

// See: issue 24, cause 6 (the three rectangles of an equilateral triangle tie to rounding,
// and those of near-equilateral ones nearly tie).
#[test]
fn first_edge_box_of_an_equilateral_triangle_follows_every_motion() {
    let h = 3f64.sqrt() / 2.0;
    // Equilateral, and its rectangles 1e-8 apart (the third node raised by 1e-8 h).
    for top in [h, h * (1.0 + 1e-8)] {
        check_first_edge_box([
            Point::new(0.0, 0.0, 0.0),
            Point::new(1.0, 0.0, 0.0),
            Point::new(0.5, top, 0.0),
        ]);
    }
}

#[track_caller]
fn check_first_edge_box(tri: [Point; 3]) {
    let box0 = Obb::build_on_normal_first_edge(
        &Geometry::new(GeometryKind::Triangle3D3, &tri).unwrap(),
        0.0,
    )
    .unwrap();
    // The first edge in node order is the box's first in-plane axis.
    assert!(box0.axes[1].x.abs() > 1.0 - 1e-12, "{:?}", box0.axes);
    let motions: [(f64, Vector, f64, Vector); 5] = [
        (1.0, Vector::z(), 0.0, Vector::new(0.0, 0.0, 1e8)),
        (1.0, Vector::z(), 0.0, Vector::new(1e8, -7e7, 3e3)),
        (1e-9, Vector::z(), 0.0, Vector::zeros()),
        (1.0, Vector::new(1.0, 2.0, 3.0), 0.7, Vector::zeros()),
        (
            1e3,
            Vector::new(-0.3, 0.2, 1.0),
            2.1,
            Vector::new(5e5, 1e6, -2e6),
        ),
    ];
    for (s, axis, angle, t) in motions {
        let moved: Vec<Point> = tri
            .iter()
            .map(|p| Point::from(rotate(p.coords, axis, angle) * s + t))
            .collect();
        let b = Obb::build_on_normal_first_edge(
            &Geometry::new(GeometryKind::Triangle3D3, &moved).unwrap(),
            0.0,
        )
        .unwrap();
        for k in 0..3 {
            let want = rotate(box0.axes[k], axis, angle);
            let cos = b.axes[k].dot(&want).abs();
            assert!(
                cos > 1.0 - 1e-9,
                "axis {k} under ({s}, {angle}, {t:?}): {cos}"
            );
            close(b.half_lengths[k] / s, box0.half_lengths[k], 1e-6);
        }
    }
}
