//! Unit tests of the kd-tree: construction invariants, Kratos' split and traversal order on
//! hand-traced inputs, boundary semantics, truncation and typed errors.

use csm_geometry::math::{Point, Real};

use super::tree::{KdTree, Node};
use crate::{ErrorKind, brute_force};

fn p(x: Real, y: Real, z: Real) -> Point {
    Point::new(x, y, z)
}

/// A deterministic pseudo-random cloud (64-bit LCG, fixed seed), coordinates in [-1, 1) on a
/// 1/16 grid so that ties are frequent.
fn lcg_cloud(n: usize, seed: u64) -> Vec<(usize, Point)> {
    let mut state = seed;
    let mut next = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((state >> 33) % 32) as Real / 16.0 - 1.0
    };
    (0..n).map(|i| (i, p(next(), next(), next()))).collect()
}

/// Walks the tree and checks: leaves are non-empty and hold at most `bucket_size` points,
/// they cover every entry exactly once, and every split's bounds hold its subtrees (a built
/// tree's bounds are its cut; a refitted tree's are the subtrees' exact extents).
#[track_caller]
fn check_invariants(tree: &KdTree<usize>) {
    fn walk(tree: &KdTree<usize>, node: u32, covered: &mut Vec<u32>) -> (Point, Point) {
        match tree.nodes[node as usize] {
            Node::Leaf { start, end } => {
                assert!(start < end, "empty leaf");
                assert!((end - start) as usize <= tree.bucket_size, "overfull leaf");
                covered.extend(start..end);
                let pts = &tree.points[start as usize..end as usize];
                let lo = pts.iter().fold(pts[0], |a, b| a.inf(b));
                let hi = pts.iter().fold(pts[0], |a, b| a.sup(b));
                (lo, hi)
            }
            Node::Inner {
                axis,
                left_max,
                right_min,
                left,
                right,
                ..
            } => {
                let (llo, lhi) = walk(tree, left, covered);
                let (rlo, rhi) = walk(tree, right, covered);
                let axis = axis as usize;
                assert!(lhi[axis] <= left_max, "left point beyond its bound");
                assert!(rlo[axis] >= right_min, "right point before its bound");
                (llo.inf(&rlo), lhi.sup(&rhi))
            }
            Node::Deferred { .. } => panic!("a deferred subtree in a settled tree"),
        }
    }
    let mut covered = Vec::new();
    if let Some(root) = tree.root {
        walk(tree, root, &mut covered);
    }
    covered.sort_unstable();
    let all: Vec<u32> = (0..tree.len() as u32).collect();
    assert_eq!(covered, all);
    let mut items: Vec<usize> = tree.items.clone();
    items.sort_unstable();
    assert_eq!(items, (0..tree.len()).collect::<Vec<_>>());
}

#[test]
fn construction_invariants_hold_for_every_bucket_size() {
    for n in [0, 1, 2, 3, 5, 17, 100, 333] {
        for bucket in 1..=6 {
            let entries = lcg_cloud(n, 0x5eed + n as u64);
            let tree = KdTree::new(&entries, bucket).unwrap();
            assert_eq!(tree.len(), n);
            check_invariants(&tree);
        }
    }
}

#[test]
fn identical_points_split_into_buckets() {
    let entries: Vec<(usize, Point)> = (0..50).map(|i| (i, p(1.0, 2.0, 3.0))).collect();
    let tree = KdTree::new(&entries, 4).unwrap();
    check_invariants(&tree);
    let mut out = Vec::new();
    tree.in_box(&p(1.0, 2.0, 3.0), &p(1.0, 2.0, 3.0), 100, &mut out)
        .unwrap();
    assert_eq!(out.len(), 50);
}

/// Hand trace of Kratos' build on x = [3, 1, 2] with bucket 1 (reference §6.1): the
/// quickselect gives [1, 2, 3] with the median 2 at position 1; the cut slip gives cut = 2 at
/// the root and cut = 3 in the right subtree. A radius query from x = 2.6 visits the right
/// subtree first (2.6 − 2 >= 0), within it the left leaf first (2.6 − 3 < 0).
#[test]
fn split_and_traversal_order_follow_kratos() {
    let entries = [
        (0, p(3.0, 0.0, 0.0)),
        (1, p(1.0, 0.0, 0.0)),
        (2, p(2.0, 0.0, 0.0)),
    ];
    let tree = KdTree::new(&entries, 1).unwrap();
    let stored: Vec<usize> = tree.iter().map(|(i, _)| *i).collect();
    assert_eq!(stored, [1, 2, 0]);
    match tree.nodes[tree.root.unwrap() as usize] {
        Node::Inner { axis, cut, .. } => assert_eq!((axis, cut), (0, 2.0)),
        _ => panic!("root should be a split"),
    }
    let mut out = Vec::new();
    tree.in_radius(&p(2.6, 0.0, 0.0), 10.0, 10, &mut out)
        .unwrap();
    assert_eq!(out, [2, 0, 1]);
    tree.in_box(&p(0.0, -1.0, -1.0), &p(5.0, 1.0, 1.0), 10, &mut out)
        .unwrap();
    assert_eq!(out, [1, 2, 0]);
}

/// The spread ties go to the lowest axis; a larger spread on z wins.
#[test]
fn split_axis_is_the_widest() {
    let square = [
        (0, p(0.0, 0.0, 0.0)),
        (1, p(1.0, 1.0, 0.0)),
        (2, p(1.0, 0.0, 0.0)),
    ];
    let tree = KdTree::new(&square, 1).unwrap();
    assert!(matches!(tree.nodes[0], Node::Inner { axis: 0, .. }));
    let tall = [
        (0, p(0.0, 0.0, 0.0)),
        (1, p(1.0, 1.0, 5.0)),
        (2, p(1.0, 0.0, 2.0)),
    ];
    let tree = KdTree::new(&tall, 1).unwrap();
    assert!(matches!(tree.nodes[0], Node::Inner { axis: 2, .. }));
}

#[test]
fn radius_is_strict_and_box_is_inclusive() {
    let entries = [
        (0, p(1.0, 0.0, 0.0)),
        (1, p(0.0, 0.0, 0.0)),
        (2, p(0.5, 0.5, 0.0)),
    ];
    let tree = KdTree::new(&entries, 1).unwrap();
    let mut out = Vec::new();
    tree.in_radius(&p(0.0, 0.0, 0.0), 1.0, 10, &mut out)
        .unwrap();
    out.sort_unstable();
    assert_eq!(
        out,
        [1, 2],
        "the point at distance exactly 1 is not inside radius 1"
    );
    tree.in_radius(&p(0.0, 0.0, 0.0), 0.0, 10, &mut out)
        .unwrap();
    assert!(
        out.is_empty(),
        "radius 0 finds nothing, not even the centre"
    );
    tree.in_box(&p(0.5, 0.0, 0.0), &p(1.0, 0.5, 0.0), 10, &mut out)
        .unwrap();
    out.sort_unstable();
    assert_eq!(out, [0, 2], "points on the faces are inside");
    tree.in_box(&p(0.5, 0.5, 0.0), &p(0.5, 0.5, 0.0), 10, &mut out)
        .unwrap();
    assert_eq!(
        out,
        [2],
        "a box with min == max finds the point at that corner"
    );
    tree.in_box(&p(1.0, 0.0, 0.0), &p(0.0, 1.0, 1.0), 10, &mut out)
        .unwrap();
    assert!(out.is_empty(), "an inverted box finds nothing");
}

#[test]
fn truncation_keeps_the_first_hits_and_reports_it() {
    let entries: Vec<(usize, Point)> = lcg_cloud(40, 7);
    let tree = KdTree::new(&entries, 4).unwrap();
    let mut all = Vec::new();
    tree.in_radius(&p(0.0, 0.0, 0.0), 3.0, usize::MAX, &mut all)
        .unwrap();
    assert_eq!(all.len(), 40);
    let mut out = Vec::new();
    for cap in [0, 1, 5, 39, 40, 41] {
        let status = tree
            .in_radius(&p(0.0, 0.0, 0.0), 3.0, cap, &mut out)
            .unwrap();
        assert_eq!(out.len(), cap.min(40));
        assert_eq!(status.truncated, cap < 40);
        assert_eq!(
            out[..],
            all[..out.len()],
            "the first hits in traversal order"
        );
    }
}

#[test]
fn rebuild_moved_starts_from_the_permuted_order() {
    let entries = lcg_cloud(60, 99);
    let mut refitted = KdTree::new(&entries, 3).unwrap();
    let permuted: Vec<(usize, Point)> = refitted.iter().map(|(i, q)| (*i, *q)).collect();
    let rebuilt = KdTree::new(&permuted, 3).unwrap();
    refitted.rebuild_moved(|i| entries[i].1).unwrap();
    let order = |t: &KdTree<usize>| t.iter().map(|(i, _)| *i).collect::<Vec<_>>();
    assert_eq!(order(&refitted), order(&rebuilt));
    check_invariants(&refitted);
}

#[test]
fn rebuild_reuses_and_replaces() {
    let mut tree = KdTree::new(&lcg_cloud(100, 1), 4).unwrap();
    let fewer = lcg_cloud(10, 2);
    tree.rebuild(&fewer).unwrap();
    assert_eq!(tree.len(), 10);
    check_invariants(&tree);
    let mut out = Vec::new();
    let mut expected = Vec::new();
    tree.in_radius(&p(0.0, 0.0, 0.0), 0.9, usize::MAX, &mut out)
        .unwrap();
    brute_force::in_radius(&fewer, &p(0.0, 0.0, 0.0), 0.9, &mut expected);
    out.sort_unstable();
    assert_eq!(out, expected);
}

/// Coordinates near `Real::MAX`: the cut value must not overflow to infinity.
#[test]
fn extreme_coordinates_keep_valid_cuts() {
    let big = Real::MAX / 1.5;
    let entries: Vec<(usize, Point)> = (0..9)
        .map(|i| (i, p(big / 2.0 * (i % 3) as Real + big / 4.0, 0.0, -big)))
        .collect();
    let tree = KdTree::new(&entries, 1).unwrap();
    check_invariants(&tree);
    let mut out = Vec::new();
    tree.in_box(
        &p(-Real::MAX, -1.0, -Real::MAX),
        &p(Real::MAX, 1.0, Real::MAX),
        100,
        &mut out,
    )
    .unwrap();
    assert_eq!(out.len(), 9);
}

#[test]
fn degenerate_input_gives_typed_errors() {
    let good = [(0usize, p(0.0, 0.0, 0.0))];
    let err = KdTree::new(&good, 0).unwrap_err();
    assert_eq!(err.kind(), &ErrorKind::ZeroBucketSize);
    assert!(!err.to_string().is_empty());

    let nan = [(0usize, p(0.0, Real::NAN, 0.0))];
    assert!(matches!(
        KdTree::new(&nan, 4).unwrap_err().kind(),
        ErrorKind::NonFinite { .. }
    ));
    let inf = [(0usize, p(Real::INFINITY, 0.0, 0.0))];
    assert!(KdTree::new(&inf, 4).is_err());
    // The lists taken as they are: checked in parallel, one bad point among many.
    let mut points: Vec<Point> = (0..5000).map(|i| p(i as Real, 0.0, 1.0)).collect();
    points[3210].z = Real::NAN;
    assert!(matches!(
        KdTree::from_parts(vec![0u32; 5000], points, 4, 0)
            .unwrap_err()
            .kind(),
        ErrorKind::NonFinite { .. }
    ));

    let mut tree = KdTree::new(&good, 4).unwrap();
    assert!(tree.rebuild(&nan).is_err());
    assert_eq!(tree.len(), 1, "a failed rebuild leaves the tree unchanged");
    assert!(tree.set_bucket_size(0).is_err());

    let mut out = vec![7];
    let origin = p(0.0, 0.0, 0.0);
    let bad = p(Real::NAN, 0.0, 0.0);
    assert!(tree.in_radius(&bad, 1.0, 10, &mut out).is_err());
    assert!(out.is_empty(), "the buffer is cleared even on error");
    assert!(tree.in_radius(&origin, Real::NAN, 10, &mut out).is_err());
    assert_eq!(
        tree.in_radius(&origin, -1.0, 10, &mut out)
            .unwrap_err()
            .kind(),
        &ErrorKind::NegativeRadius
    );
    assert!(tree.in_box(&bad, &origin, 10, &mut out).is_err());
    assert!(tree.in_box(&origin, &bad, 10, &mut out).is_err());

    assert!(tree.refit(|_| bad).is_err());
    assert!(tree.is_empty(), "a failed refit empties the tree");
    let mut tree = KdTree::new(&lcg_cloud(20, 5), 4).unwrap();
    assert!(tree.rebuild_moved(|_| bad).is_err());
    assert!(tree.is_empty(), "a failed rebuild_moved empties the tree");
}

#[test]
fn kratos_bucket_size_is_four() {
    let tree = KdTree::with_kratos_bucket_size(&lcg_cloud(10, 3)).unwrap();
    assert_eq!(tree.bucket_size(), 4);
    assert!(tree.n_nodes() >= 3);
    assert!(tree.bounds().is_some());
}

#[test]
fn refit_keeps_the_tree_and_tightens_the_bounds() {
    let entries = lcg_cloud(200, 7);
    let mut tree = KdTree::new(&entries, 4).unwrap();
    let order: Vec<usize> = tree.iter().map(|(i, _)| *i).collect();
    let n_nodes = tree.n_nodes();
    // A rigid translation and a small perturbation of each point.
    let moved = |i: usize| {
        let q = entries[i].1;
        p(q.x + 10.0 + 0.01 * (i % 7) as Real, q.y - 3.0, q.z * 1.5)
    };
    tree.refit(moved).unwrap();
    assert_eq!(tree.n_nodes(), n_nodes);
    assert_eq!(tree.iter().map(|(i, _)| *i).collect::<Vec<_>>(), order);
    check_invariants(&tree);
    // Every point is at its new position and is found by a radius query around it.
    let mut out = Vec::new();
    for (i, _) in &entries {
        tree.in_radius(&moved(*i), 1e-9, usize::MAX, &mut out)
            .unwrap();
        assert!(out.contains(i), "point {i} not found after the refit");
    }
}

/// A cloud of distinct, irregular coordinates (no ties) in [-1, 1)³.
fn irregular_cloud(n: usize) -> Vec<(usize, Point)> {
    let f = |i: usize, k: f64| ((i as f64 + 1.0) * k).sin();
    (0..n)
        .map(|i| (i, p(f(i, 12.9898), f(i, 78.233), f(i, 37.719))))
        .collect()
}

#[test]
fn parallel_halves_build_the_serial_arena() {
    for (cloud, bucket) in [(lcg_cloud(3000, 7), 4), (irregular_cloud(2500), 3)] {
        let build = |parallel_min: usize| {
            let mut items: Vec<usize> = cloud.iter().map(|(i, _)| *i).collect();
            let mut points: Vec<Point> = cloud.iter().map(|(_, x)| *x).collect();
            let mut nodes = Vec::new();
            let root = super::build::build_with(
                &mut items,
                &mut points,
                &mut nodes,
                (bucket, parallel_min, 0),
            );
            (root, items, points, nodes)
        };
        let serial = build(usize::MAX);
        for parallel_min in [1, 2, 64, 1000] {
            assert_eq!(
                build(parallel_min),
                serial,
                "parallel halves from {parallel_min} points"
            );
        }
    }
}

#[test]
fn queries_missing_the_extent_find_nothing_and_agree_with_brute_force() {
    let cloud = irregular_cloud(500);
    let tree = KdTree::new(&cloud, 4).unwrap();
    let extent = tree.bounds().unwrap();
    assert_eq!(
        Some(extent),
        crate::bounds_of(cloud.iter().map(|(_, x)| x)),
        "the stored extent is the points' box"
    );
    let (mut got, mut want) = (Vec::new(), Vec::new());
    // The point closest to a face of the box, and centres at, just inside and just outside
    // the radius that reaches it.
    for axis in 0..3 {
        let nearest = cloud
            .iter()
            .min_by(|a, b| a.1[axis].total_cmp(&b.1[axis]))
            .unwrap()
            .1;
        for offset in [0.5, 1e-3] {
            let mut center = nearest;
            center[axis] -= offset;
            let exact = super::query::in_radius::box_distance2(&extent, &center).sqrt();
            for radius in [
                exact * (1.0 - 1e-12),
                exact,
                exact * (1.0 + 1e-12),
                exact + 0.3,
            ] {
                tree.in_radius(&center, radius, 1000, &mut got).unwrap();
                brute_force::in_radius(&cloud, &center, radius, &mut want);
                got.sort_unstable();
                want.sort_unstable();
                assert_eq!(got, want, "radius {radius} around {center:?}");
            }
            let mut hi = center;
            for radius in [offset * 0.5, offset, offset * 2.0] {
                hi[axis] = center[axis] + radius;
                tree.in_box(&center, &hi, 1000, &mut got).unwrap();
                brute_force::in_box(&cloud, &center, &hi, &mut want);
                got.sort_unstable();
                want.sort_unstable();
                assert_eq!(got, want, "box {center:?} – {hi:?}");
            }
        }
    }
    tree.in_radius(&p(5.0, 0.0, 0.0), 3.9, 1000, &mut got)
        .unwrap();
    assert!(got.is_empty(), "a sphere short of the box finds nothing");
    tree.in_radius(&p(5.0, 0.0, 0.0), 6.5, 1000, &mut got)
        .unwrap();
    assert_eq!(got.len(), 500, "a sphere around the box finds every point");
}

/// A deferred tree answers every query as the fully built tree does, results in the same order
/// and truncated alike, whichever subtrees earlier queries built; settled, it is that tree node
/// for node (arena, entry order, extent), and its entry order is the same before settling.
#[test]
fn deferred_subtrees_give_the_built_tree() {
    let clouds = [
        (lcg_cloud(3000, 11), 4),
        (irregular_cloud(2500), 3),
        (lcg_cloud(700, 5), 1),
    ];
    for (cloud, bucket) in clouds {
        let full = KdTree::new(&cloud, bucket).unwrap();
        for defer_max in [0, bucket, bucket + 1, 7, 64, 500, 10_000] {
            let mut tree = KdTree::new_deferred(&cloud, bucket, defer_max).unwrap();
            assert_eq!(
                tree.has_deferred(),
                defer_max > bucket && cloud.len() > bucket,
                "defer_max {defer_max}"
            );
            let (mut got, mut want) = (Vec::new(), Vec::new());
            // Queries of every size, some capped, in an order that builds subtrees piecemeal.
            for (k, (_, x)) in cloud.iter().enumerate().step_by(97) {
                let radius = [0.01, 0.1, 0.4, 3.0][k % 4];
                let cap = [1000, 3, 10_000][k % 3];
                let s1 = tree.in_radius(x, radius, cap, &mut got).unwrap();
                let s2 = full.in_radius(x, radius, cap, &mut want).unwrap();
                assert_eq!((&got, s1), (&want, s2), "radius {radius} at {x:?}");
                let lo = p(x[0] - radius, x[1] - radius, x[2]);
                let hi = p(x[0] + radius, x[1], x[2] + radius);
                let s1 = tree.in_box(&lo, &hi, cap, &mut got).unwrap();
                let s2 = full.in_box(&lo, &hi, cap, &mut want).unwrap();
                assert_eq!((&got, s1), (&want, s2), "box {lo:?} – {hi:?}");
            }
            let entries = |t: &KdTree<usize>| t.iter().map(|(i, x)| (*i, *x)).collect::<Vec<_>>();
            assert_eq!(entries(&tree), entries(&full), "order before settling");
            // Stored order: the built tree's, except within each deferred range (same set).
            let mut stored = tree.stored_items().to_vec();
            let mut settled = full.stored_items().to_vec();
            for node in &tree.nodes {
                if let Node::Deferred { start, end, .. } = *node {
                    stored[start as usize..end as usize].sort_unstable();
                    settled[start as usize..end as usize].sort_unstable();
                }
            }
            assert_eq!(stored, settled, "stored order, defer_max {defer_max}");
            tree.settle();
            assert_eq!(tree.stored_items(), full.stored_items());
            assert!(!tree.has_deferred());
            assert_eq!(
                (
                    &tree.nodes,
                    &tree.items,
                    &tree.points,
                    tree.root,
                    tree.extent
                ),
                (
                    &full.nodes,
                    &full.items,
                    &full.points,
                    full.root,
                    full.extent
                ),
                "settled tree, defer_max {defer_max}"
            );
            check_invariants(&tree);
        }
        // The owning constructor is the copying one.
        let (items, points): (Vec<usize>, Vec<Point>) = cloud.iter().copied().unzip();
        let mut owned = KdTree::from_parts(items.clone(), points.clone(), bucket, 64).unwrap();
        owned.settle();
        assert_eq!((&owned.nodes, &owned.items), (&full.nodes, &full.items));
        let short = KdTree::from_parts(items[1..].to_vec(), points, bucket, 64);
        assert_eq!(short.unwrap_err().kind(), &ErrorKind::LengthMismatch);
        // Settling without a query builds every subtree; a rebuild of moved points and a
        // refit start from the settled order, as the built tree's do.
        let mut tree = KdTree::new_deferred(&cloud, bucket, 64).unwrap();
        let mut built = full.clone();
        let moved = |i: usize| cloud[(i * 7 + 3) % cloud.len()].1;
        tree.rebuild_moved(moved).unwrap();
        built.rebuild_moved(moved).unwrap();
        tree.settle();
        assert_eq!((&tree.nodes, &tree.items), (&built.nodes, &built.items));
        let mut tree = KdTree::new_deferred(&cloud, bucket, 64).unwrap();
        let mut built = full.clone();
        tree.refit(moved).unwrap();
        built.refit(moved).unwrap();
        assert!(!tree.has_deferred());
        assert_eq!((&tree.nodes, &tree.items), (&built.nodes, &built.items));
    }
}

/// The block-listing quickselect makes Kratos' swaps: the same permutation as the scalar
/// quickselect for every target position, on inputs with many ties, sorted, reversed,
/// constant runs and rows in grid order (lopsided passes), of sizes around the scan block, with
/// block bounds kept from the first lopsided pass of any range, of 64 positions on and of
/// the default size on.
#[test]
fn block_select_is_the_scalar_quickselect() {
    use super::build::{Entries, select_blocks, select_blocks_with};
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = move |k: u64| {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 33) % k
    };
    let mut cases: Vec<Vec<Real>> = Vec::new();
    for n in [
        1, 2, 3, 4, 5, 7, 63, 64, 65, 127, 128, 129, 200, 1000, 3001, 5000,
    ] {
        for levels in [2, 5, 1000, 1 << 30] {
            cases.push((0..n).map(|_| next(levels) as Real).collect());
        }
        cases.push((0..n).map(|i| i as Real).collect());
        cases.push((0..n).map(|i| -(i as Real)).collect());
        cases.push(vec![1.5; n]);
        cases.push((0..n).map(|i| ((i * 37) % 11) as Real).collect());
        for row in [7, 70, 71] {
            cases.push(
                (0..n)
                    .map(|i| (i % row) as Real + (i / row) as Real * 1e-3)
                    .collect(),
            );
            cases.push((0..n).map(|i| ((i % row) * 3 % row) as Real).collect());
        }
    }
    for values in cases {
        let n = values.len();
        let targets: Vec<usize> = if n <= 130 {
            (0..n).collect()
        } else {
            vec![0, 1, n / 3, n / 2, n - 2, n - 1]
        };
        for m in targets {
            for axis in [0, 2] {
                // 0: the scalar oracle; 1: the default; 2, 3: bounds from 1 and 64 positions.
                let run = |how: usize| {
                    let mut items: Vec<usize> = (0..n).collect();
                    let mut points: Vec<Point> = values
                        .iter()
                        .map(|&v| {
                            let mut x = p(0.0, 0.0, 0.0);
                            x[axis] = v;
                            x
                        })
                        .collect();
                    let mut entries = Entries {
                        items: &mut items,
                        points: &mut points,
                        base: 0,
                    };
                    match how {
                        0 => select(&mut entries, m, axis),
                        1 => select_blocks(&mut entries, m, axis),
                        2 => select_blocks_with(&mut entries, m, axis, 1),
                        _ => select_blocks_with(&mut entries, m, axis, 64),
                    }
                    (items, points)
                };
                let oracle = run(0);
                for how in 1..=3 {
                    assert_eq!(run(how), oracle, "n {n}, m {m}, {how}, values {values:?}");
                }
            }
        }
    }
}

/// Kratos' Hoare-style quickselect on `axis` over the whole range: afterwards position `m` holds the
/// value it would hold in sorted order, everything before it is `<=` and everything after it
/// `>=` (reference §6.1): Kratos' loop as written, the oracle of `select_blocks`.
fn select<T>(entries: &mut super::build::Entries<'_, T>, m: usize, axis: usize) {
    let mut left = 0;
    let mut right = entries.len() - 1;
    while left < right {
        let mut i = left;
        if entries.v(i, axis) > entries.v(right, axis) {
            entries.swap(i, right);
        }
        let pivot = entries.v(i, axis);
        let mut j = right;
        loop {
            // `v(right) >= pivot` stops `i` at `right` at the latest, `v(left) == pivot`
            // stops `j` at `left` at the latest.
            loop {
                i += 1;
                if entries.v(i, axis) >= pivot {
                    break;
                }
            }
            loop {
                j -= 1;
                if entries.v(j, axis) <= pivot {
                    break;
                }
            }
            if i < j {
                entries.swap(i, j);
            } else {
                break;
            }
        }
        entries.swap(left, j);
        if j > m {
            right = j - 1;
        } else if j < m {
            left = j + 1;
        } else {
            break;
        }
    }
}

/// The box of a range, found in parallel blocks, is the one pass's box, for any thread count;
/// the tree's extent is its points' box.
#[test]
fn the_parallel_box_is_the_serial_one() {
    for (n, seed) in [(3, 1), (8191, 2), (8192, 3), (40_000, 4)] {
        let cloud = lcg_cloud(n, seed);
        let points: Vec<Point> = cloud.iter().map(|(_, x)| *x).collect();
        let serial = crate::bounds_of(points.iter()).unwrap();
        for threads in [1, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            for parallel_min in [1, usize::MAX] {
                let aabb = pool.install(|| super::build::bounds(&points, parallel_min));
                assert_eq!((aabb.min, aabb.max), (serial.min, serial.max), "{n} points");
            }
            let public = pool.install(|| crate::par_bounds_of(&points)).unwrap();
            assert_eq!((public.min, public.max), (serial.min, serial.max));
        }
        let items: Vec<usize> = (0..n).collect();
        let tree = KdTree::from_parts(items, points, 4, 64).unwrap();
        assert_eq!(tree.bounds(), Some(serial));
    }
    assert_eq!(crate::par_bounds_of(&[]), None);
}
