//! Unit tests of the `intersection` module.
use super::sat_obb_obb::{certainly_intersect, sat_obb_obb_axes};
use super::*;
use crate::math::{Point, Vector};
use crate::{Obb, Obb2};

const MODES: [SatMode; 2] = [SatMode::Kratos, SatMode::Robust];

/// All three tests (SAT in both modes, Direct), both argument orders, must give `expected`.
#[track_caller]
fn check3(a: &Obb, b: &Obb, expected: bool) {
    for mode in MODES {
        assert_eq!(sat_obb_obb(a, b, mode), expected, "SAT {mode:?}");
        assert_eq!(sat_obb_obb(b, a, mode), expected, "SAT {mode:?} swapped");
    }
    assert_eq!(direct_obb_obb(a, b), expected, "Direct");
    assert_eq!(direct_obb_obb(b, a), expected, "Direct swapped");
}

#[track_caller]
fn check2(a: &Obb2, b: &Obb2, expected: bool) {
    for mode in MODES {
        assert_eq!(sat_obb2_obb2(a, b, mode), expected, "SAT {mode:?}");
        assert_eq!(sat_obb2_obb2(b, a, mode), expected, "SAT {mode:?} swapped");
    }
    assert_eq!(direct_obb2_obb2(a, b), expected, "Direct");
    assert_eq!(direct_obb2_obb2(b, a), expected, "Direct swapped");
}

fn v(x: f64, y: f64, z: f64) -> Vector {
    Vector::new(x, y, z)
}

// See: Kratos test_oriented_bounding_box.cpp, 2D simple / crossed (reference §20.4).
#[test]
fn kratos_2d_cases() {
    let s = 0.5f64.sqrt();
    let b1 = Obb2::new(
        Point::new(0.5, 0.5, 0.0),
        [v(s, s, 0.0), v(-s, s, 0.0)],
        [s, 0.1],
    );
    let mut b2 = Obb2::new(Point::origin(), [Vector::x(), Vector::y()], [0.5, 0.1]);
    check2(&b1, &b2, true);
    b2.center.y = 0.5;
    check2(&b1, &b2, true);
    let thin_x = Obb2::new(Point::origin(), [Vector::x(), Vector::y()], [1.0, 0.1]);
    let thin_y = Obb2::new(Point::origin(), [Vector::y(), -Vector::x()], [1.0, 0.1]);
    check2(&thin_x, &thin_y, true);
    // Far apart.
    b2.center = Point::new(3.0, 0.0, 0.0);
    check2(&b1, &b2, false);
}

// See: Kratos test_oriented_bounding_box.cpp, 3D cases (reference §20.4). The rounded axis
// values (0.7071, …) are Kratos' test data, kept as written.
#[test]
#[allow(clippy::approx_constant)]
fn kratos_3d_cases() {
    let s = 0.5f64.sqrt();
    let b1 = Obb::new(
        Point::new(0.5, 0.5, 0.0),
        [v(s, s, 0.0), v(-s, s, 0.0), Vector::z()],
        [s, 0.1, 0.1],
    );
    let mut b2 = Obb::new(
        Point::origin(),
        [Vector::x(), Vector::y(), Vector::z()],
        [0.5, 0.1, 0.1],
    );
    check3(&b1, &b2, true);
    b2.center.y = 0.5;
    check3(&b1, &b2, true);

    let r3 = 3f64.sqrt();
    let diag = Obb::new(
        Point::new(0.5, 0.5, 0.1),
        [
            v(1.0 / r3, 1.0 / r3, 1.0 / r3),
            v(0.8165, -0.4082, -0.4082),
            v(0.0, 0.7071, -0.7071),
        ],
        [r3 / 3.0, 0.1, 0.1],
    );
    let mut origin_box = Obb::new(
        Point::origin(),
        [Vector::x(), Vector::y(), Vector::z()],
        [0.5, 0.1, 0.1],
    );
    check3(&diag, &origin_box, false);
    origin_box.center.y = 0.5;
    check3(&diag, &origin_box, true);

    let slave4 = Obb::new(
        Point::new(1.75, 0.0, 0.5),
        [
            v(0.447214, 0.0, 0.894427),
            v(0.894427, 0.0, -0.447214),
            v(0.0, 1.0, 0.0),
        ],
        [0.659017, 0.547214, 0.1],
    );
    let master13 = Obb::new(
        Point::new(1.74078, 0.261432, 0.5),
        [
            v(0.349731, 0.10609, 0.930824),
            v(0.93685, -0.039604, -0.347482),
            v(0.0, 0.993568, -0.113241),
        ],
        [0.637159, 0.447482, 0.213241],
    );
    check3(&slave4, &master13, true);
    let master11 = Obb::new(
        Point::new(0.97685, 0.0833096, 0.5),
        [
            v(0.360587, 0.0595331, 0.930824),
            v(0.932726, -0.0230152, -0.359852),
            v(0.0, 0.997961, -0.0638271),
        ],
        [0.637159, 0.459852, 0.163827],
    );
    check3(&slave4, &master11, true);
}

#[test]
fn exactly_parallel_and_touching_boxes() {
    let axes = [Vector::x(), Vector::y(), Vector::z()];
    let a = Obb::new(Point::origin(), axes, [1.0, 1.0, 1.0]);
    // Face contact: exactly touching counts as intersecting in every test.
    let b = Obb::new(Point::new(2.0, 0.0, 0.0), axes, [1.0, 1.0, 1.0]);
    check3(&a, &b, true);
    let c = Obb::new(Point::new(2.0 + 1e-6, 0.0, 0.0), axes, [1.0, 1.0, 1.0]);
    check3(&a, &c, false);
    // Robust: a gap below the touching tolerance counts as touching.
    let d = Obb::new(Point::new(2.0 + 1e-12, 0.0, 0.0), axes, [1.0, 1.0, 1.0]);
    assert!(sat_obb_obb(&a, &d, SatMode::Robust));
    assert!(!sat_obb_obb(&a, &d, SatMode::Kratos));
}

#[test]
fn segment_and_triangle_primitives() {
    let p = |x: f64, y: f64| Point::new(x, y, 0.0);
    assert!(segment_segment_intersect(
        &p(0.0, 0.0),
        &p(1.0, 1.0),
        &p(0.0, 1.0),
        &p(1.0, 0.0)
    ));
    assert!(segment_segment_intersect(
        &p(0.0, 0.0),
        &p(2.0, 0.0),
        &p(1.0, 0.0),
        &p(3.0, 0.0)
    ));
    assert!(!segment_segment_intersect(
        &p(0.0, 0.0),
        &p(1.0, 0.0),
        &p(2.0, 0.0),
        &p(3.0, 0.0)
    ));
    assert!(segment_segment_intersect(
        &p(0.0, 0.0),
        &p(1.0, 0.0),
        &p(1.0, 0.0),
        &p(1.0, 5.0)
    ));
    assert!(!segment_segment_intersect(
        &p(0.0, 0.0),
        &p(1.0, 0.0),
        &p(0.0, 0.1),
        &p(1.0, 0.1)
    ));
    let t1 = [
        Point::new(0.0, 0.0, 0.0),
        Point::new(1.0, 0.0, 0.0),
        Point::new(0.0, 1.0, 0.0),
    ];
    // Piercing.
    let t2 = [
        Point::new(0.2, 0.2, -1.0),
        Point::new(0.2, 0.2, 1.0),
        Point::new(0.3, 0.4, 1.0),
    ];
    assert!(triangle_triangle_intersect(&t1, &t2));
    // Coplanar overlapping and coplanar disjoint.
    let t3 = [
        Point::new(0.4, 0.4, 0.0),
        Point::new(1.0, 1.0, 0.0),
        Point::new(0.0, 2.0, 0.0),
    ];
    assert!(triangle_triangle_intersect(&t1, &t3));
    let t4 = [
        Point::new(0.6, 0.6, 0.0),
        Point::new(1.0, 1.0, 0.0),
        Point::new(0.6, 2.0, 0.0),
    ];
    assert!(!triangle_triangle_intersect(&t1, &t4));
    // Parallel planes.
    let t5 = t1.map(|q| q + Vector::z() * 0.1);
    assert!(!triangle_triangle_intersect(&t1, &t5));
}

/// A box pair that a common point proves intersecting is one the fifteen axes call
/// intersecting, in both modes and both orders: overlapping, touching, nearly touching and
/// separated boxes, rotated, thin (zero and tiny half-lengths), with parallel axes, far from
/// the origin, with axes that are not orthonormal; and the common point is found for most
/// (four in five) of the intersecting ones.
#[test]
fn a_common_point_proves_what_the_axes_find() {
    use crate::math::Matrix3;
    let mut next = crate::test_support::uniform(0x00B0_B5A7);
    let (mut proven, mut intersecting, mut pairs) = (0, 0, 0);
    for case in 0..20_000 {
        let offset = [0.0, 1e3, -2e6][case % 3];
        let scale = [1.0, 1e-3, 50.0][case % 5 % 3];
        let mut rotation = || {
            let axis = v(next(), next(), next());
            let angle = if case % 7 == 0 { 0.0 } else { 6.0 * next() };
            nalgebra::Rotation3::new(axis.normalize() * angle).into_inner()
        };
        let (r1, mut r2): (Matrix3, Matrix3) = (rotation(), rotation());
        if case % 11 == 0 {
            // Axes that are not orthonormal.
            r2[(0, 1)] += 1e-6;
        }
        let half = |k: usize, next: &mut dyn FnMut() -> f64| -> [f64; 3] {
            let mut h = [0.0; 3];
            for (i, h) in h.iter_mut().enumerate() {
                *h = scale * (0.5 + next()).abs();
                if case % 13 == 0 && i == k {
                    *h = [0.0, 1e-12 * scale][case % 2];
                }
            }
            h
        };
        let h1 = half(0, &mut next);
        let h2 = half(2, &mut next);
        let c1 = v(offset, offset, offset) + v(next(), next(), next()) * scale;
        // The second centre from near the first (overlap) to a box length away (touching or
        // apart).
        let reach = [0.3, 1.0, 2.5][case % 3 % 3] * scale;
        let c2 = c1 + v(next(), next(), next()) * reach;
        let axes = |r: &Matrix3| {
            [
                r.column(0).into_owned(),
                r.column(1).into_owned(),
                r.column(2).into_owned(),
            ]
        };
        let a = Obb::new(Point::from(c1), axes(&r1), h1);
        let b = Obb::new(Point::from(c2), axes(&r2), h2);
        pairs += 1;
        let certain = certainly_intersect(&a, &b);
        for mode in MODES {
            let by_axes = sat_obb_obb_axes(&a, &b, mode);
            if certain {
                assert!(by_axes, "case {case}, {mode:?}: {a:?} {b:?}");
                assert!(
                    sat_obb_obb_axes(&b, &a, mode),
                    "case {case}, {mode:?}, swapped"
                );
            }
            assert_eq!(sat_obb_obb(&a, &b, mode), by_axes, "case {case}, {mode:?}");
        }
        if sat_obb_obb_axes(&a, &b, SatMode::Kratos) {
            intersecting += 1;
            proven += usize::from(certain);
        }
    }
    assert_eq!(pairs, 20_000);
    assert!(
        proven * 5 > intersecting * 4,
        "{proven} of {intersecting} intersecting pairs proven"
    );
}
