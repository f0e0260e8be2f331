//! The kd-tree's radius and box queries against the brute-force oracles.

use csm_geometry::math::{Point, Real};
use csm_trees::{KdTree, brute_force};
use proptest::prelude::*;

use crate::generators::{cloud, cloud_scale, config, entries, pick_point};

/// How the radius of a query is chosen.
#[derive(Debug, Clone, Copy)]
enum RadiusKind {
    Zero,
    /// Exactly the distance from the centre to a cloud point (tests the strict `<`).
    ToPoint(usize),
    /// A fraction of the cloud scale.
    Fraction(Real),
}

fn radius_kind() -> impl Strategy<Value = RadiusKind> {
    prop_oneof![
        1 => Just(RadiusKind::Zero),
        2 => any::<usize>().prop_map(RadiusKind::ToPoint),
        3 => (0.0..3.0f64).prop_map(RadiusKind::Fraction),
    ]
}

/// How the box of a query is chosen.
#[derive(Debug, Clone, Copy)]
enum BoxKind {
    /// `min == max ==` a cloud point.
    Degenerate(usize),
    /// The box spanned by two cloud points (faces through cloud points: tests inclusiveness).
    Spanned(usize, usize),
    /// A box around the centre with half-extents given as fractions of the cloud scale
    /// (negative fractions give inverted boxes).
    Around([Real; 3]),
}

fn box_kind() -> impl Strategy<Value = BoxKind> {
    prop_oneof![
        1 => any::<usize>().prop_map(BoxKind::Degenerate),
        2 => (any::<usize>(), any::<usize>()).prop_map(|(a, b)| BoxKind::Spanned(a, b)),
        3 => prop::array::uniform3(-0.2..1.5f64).prop_map(BoxKind::Around),
    ]
}

fn radius_of(kind: RadiusKind, cloud: &[Point], center: &Point) -> Real {
    match kind {
        RadiusKind::Zero => 0.0,
        RadiusKind::ToPoint(i) if !cloud.is_empty() => (cloud[i % cloud.len()] - center).norm(),
        RadiusKind::ToPoint(_) => 1.0,
        RadiusKind::Fraction(f) => f * cloud_scale(cloud),
    }
}

fn box_of(kind: BoxKind, cloud: &[Point], center: &Point) -> (Point, Point) {
    match kind {
        BoxKind::Degenerate(i) if !cloud.is_empty() => {
            let p = cloud[i % cloud.len()];
            (p, p)
        }
        BoxKind::Spanned(a, b) if !cloud.is_empty() => {
            let (a, b) = (cloud[a % cloud.len()], cloud[b % cloud.len()]);
            (a.inf(&b), a.sup(&b))
        }
        BoxKind::Degenerate(_) | BoxKind::Spanned(..) => (*center, *center),
        BoxKind::Around(h) => {
            let s = cloud_scale(cloud);
            let h = csm_geometry::math::Vector::new(h[0] * s, h[1] * s, h[2] * s);
            (center - h, center + h)
        }
    }
}

fn sorted(mut v: Vec<usize>) -> Vec<usize> {
    v.sort_unstable();
    v
}

/// Checks one radius query: the uncapped result equals the oracle, and the result capped at
/// `cap` has `min(cap, true count)` distinct items, all from the true set, with `truncated`
/// set exactly when hits were dropped.
#[track_caller]
fn check_in_radius(
    tree: &KdTree<usize>,
    entries: &[(usize, Point)],
    center: &Point,
    radius: Real,
    cap: usize,
) {
    let mut expected = Vec::new();
    brute_force::in_radius(entries, center, radius, &mut expected);
    let expected = sorted(expected);

    let mut found = vec![usize::MAX; 3]; // Stale content must be cleared.
    let status = tree
        .in_radius(center, radius, usize::MAX, &mut found)
        .unwrap();
    assert!(!status.truncated);
    assert_eq!(
        sorted(found.clone()),
        expected,
        "radius {radius:e} around {center:?}"
    );

    let status = tree.in_radius(center, radius, cap, &mut found).unwrap();
    check_capped(&found, &expected, cap, status.truncated);
}

/// Checks one box query like [`check_in_radius`].
#[track_caller]
fn check_in_box(
    tree: &KdTree<usize>,
    entries: &[(usize, Point)],
    min: &Point,
    max: &Point,
    cap: usize,
) {
    let mut expected = Vec::new();
    brute_force::in_box(entries, min, max, &mut expected);
    let expected = sorted(expected);

    let mut found = vec![usize::MAX; 3];
    let status = tree.in_box(min, max, usize::MAX, &mut found).unwrap();
    assert!(!status.truncated);
    assert_eq!(sorted(found.clone()), expected, "box {min:?} – {max:?}");

    let status = tree.in_box(min, max, cap, &mut found).unwrap();
    check_capped(&found, &expected, cap, status.truncated);
}

#[track_caller]
fn check_capped(found: &[usize], expected_sorted: &[usize], cap: usize, truncated: bool) {
    assert_eq!(found.len(), cap.min(expected_sorted.len()), "cap {cap}");
    assert_eq!(truncated, expected_sorted.len() > cap, "cap {cap}");
    let found = sorted(found.to_vec());
    assert!(found.windows(2).all(|w| w[0] < w[1]), "duplicate items");
    assert!(
        found
            .iter()
            .all(|i| expected_sorted.binary_search(i).is_ok()),
        "capped result not a subset of the true set"
    );
}

proptest! {
    #![proptest_config(config(1024))]

    #[test]
    fn in_radius_matches_brute_force(
        cloud in cloud(120),
        bucket in 1usize..=8,
        pick in any::<usize>(),
        fallback in prop::array::uniform3(-1.5..1.5f64),
        radius in radius_kind(),
        cap in 0usize..40,
    ) {
        let entries = entries(&cloud);
        let tree = KdTree::new(&entries, bucket).unwrap();
        prop_assert_eq!(tree.len(), cloud.len());
        let s = cloud_scale(&cloud);
        let fallback = Point::new(fallback[0] * s, fallback[1] * s, fallback[2] * s);
        let center = pick_point(&cloud, pick, fallback);
        let r = radius_of(radius, &cloud, &center);
        check_in_radius(&tree, &entries, &center, r, cap);
    }

    #[test]
    fn in_box_matches_brute_force(
        cloud in cloud(120),
        bucket in 1usize..=8,
        pick in any::<usize>(),
        fallback in prop::array::uniform3(-1.5..1.5f64),
        kind in box_kind(),
        cap in 0usize..40,
    ) {
        let entries = entries(&cloud);
        let tree = KdTree::new(&entries, bucket).unwrap();
        let s = cloud_scale(&cloud);
        let fallback = Point::new(fallback[0] * s, fallback[1] * s, fallback[2] * s);
        let center = pick_point(&cloud, pick, fallback);
        let (min, max) = box_of(kind, &cloud, &center);
        check_in_box(&tree, &entries, &min, &max, cap);
    }

    /// `refit` (new positions, the tree kept), `rebuild_moved` (new positions, Kratos'
    /// persistent permutation) and `rebuild` (fresh order) all answer as the oracle on the
    /// moved points.
    #[test]
    fn refit_and_rebuild_match_brute_force(
        cloud in cloud(80),
        moved in cloud(80),
        bucket in 1usize..=6,
        pick in any::<usize>(),
        radius in radius_kind(),
        kind in box_kind(),
    ) {
        let mut tree = KdTree::new(&entries(&cloud), bucket).unwrap();
        // Move point i to moved[i] (or keep it when `moved` is shorter).
        let new_position = |i: usize| moved.get(i).copied().unwrap_or(cloud[i]);
        tree.refit(new_position).unwrap();
        let moved_entries: Vec<(usize, Point)> =
            (0..cloud.len()).map(|i| (i, new_position(i))).collect();
        let center = pick_point(&moved_entries.iter().map(|e| e.1).collect::<Vec<_>>(), pick, Point::origin());
        let moved_cloud: Vec<Point> = moved_entries.iter().map(|e| e.1).collect();
        let r = radius_of(radius, &moved_cloud, &center);
        let (min, max) = box_of(kind, &moved_cloud, &center);
        check_in_radius(&tree, &moved_entries, &center, r, 7);
        check_in_box(&tree, &moved_entries, &min, &max, 7);

        let mut again = KdTree::new(&entries(&cloud), bucket).unwrap();
        again.rebuild_moved(new_position).unwrap();
        check_in_radius(&again, &moved_entries, &center, r, 7);
        check_in_box(&again, &moved_entries, &min, &max, 7);

        tree.rebuild(&moved_entries).unwrap();
        check_in_radius(&tree, &moved_entries, &center, r, 7);
        check_in_box(&tree, &moved_entries, &min, &max, 7);
    }
}

/// Every query on the empty tree finds nothing and reports no truncation.
#[test]
fn empty_tree_finds_nothing() {
    let tree = KdTree::<usize>::new(&[], 4).unwrap();
    assert!(tree.is_empty());
    let mut out = vec![1, 2];
    let status = tree
        .in_radius(&Point::origin(), 1e300, 10, &mut out)
        .unwrap();
    assert!(out.is_empty() && !status.truncated);
    let p = Point::new(1e300, 1e300, 1e300);
    let status = tree.in_box(&(-p), &p, 10, &mut out).unwrap();
    assert!(out.is_empty() && !status.truncated);
}
