//! The octree's box queries against the brute-force box-overlap oracle: for objects inside the
//! root box, every brute-force hit is found, and every extra object shares a leaf (grown by
//! the cell tolerance) with the query.

use csm_geometry::math::{Point, Real, Vector};
use csm_trees::{Aabb, LeafId, Octree, OctreeParams, brute_force};
use proptest::prelude::*;

use crate::generators::config;

/// A coordinate in `[-1, 1]`, often on a 1/8 grid so that faces coincide with cell faces.
fn coord() -> impl Strategy<Value = Real> {
    prop_oneof![-1.0..=1.0f64, (-8i32..=8).prop_map(|k| k as Real / 8.0),]
}

fn unit_point() -> impl Strategy<Value = Point> {
    prop::array::uniform3(coord()).prop_map(|c| Point::new(c[0], c[1], c[2]))
}

/// A box in `[-1, 1]^3`: a centre and half-extents in `[0, 0.4]` (some zero: flat boxes and
/// points).
fn unit_box() -> impl Strategy<Value = Aabb> {
    (
        unit_point(),
        prop::array::uniform3(prop_oneof![1 => Just(0.0), 3 => 0.0..0.4f64]),
    )
        .prop_map(|(c, h)| {
            let h = Vector::new(h[0], h[1], h[2]);
            let lo = Point::new(-1.0, -1.0, -1.0);
            let hi = Point::new(1.0, 1.0, 1.0);
            Aabb::new((c - h).sup(&lo), (c + h).inf(&hi))
        })
}

fn scaled(aabb: &Aabb, scale: Real, shift: &Vector) -> Aabb {
    Aabb::new(aabb.min * scale + shift, aabb.max * scale + shift)
}

/// Checks the three box queries of `octree` for `query` against the oracle over `objects`.
#[track_caller]
fn check_query(octree: &Octree<usize>, objects: &[(usize, Aabb)], query: &Aabb) {
    let mut expected = Vec::new();
    brute_force::aabb_overlap(objects, query, &mut expected);

    let mut found = vec![usize::MAX];
    octree.query_aabb(query, &mut found).unwrap();
    assert!(
        found.windows(2).all(|w| w[0] < w[1]),
        "not sorted and unique"
    );
    for item in &expected {
        assert!(
            found.binary_search(item).is_ok(),
            "object {item} {:?} overlaps {query:?} but was not found",
            objects[*item].1
        );
    }

    // The per-leaf listing: the same set, each object once per reached leaf holding it.
    let mut leaves: Vec<LeafId> = Vec::new();
    octree.intersected_leaves(query, &mut leaves).unwrap();
    let mut per_leaf = Vec::new();
    octree.query_aabb_per_leaf(query, &mut per_leaf).unwrap();
    let listed: usize = leaves.iter().map(|l| octree.leaf_items(*l).len()).sum();
    assert_eq!(per_leaf.len(), listed);
    let mut dedup = per_leaf.clone();
    dedup.sort_unstable();
    dedup.dedup();
    assert_eq!(dedup, found);

    // Every extra object shares a reached leaf (grown by the tolerance) with the query.
    let tolerance = octree.params().cell_tolerance();
    for item in &found {
        let object = &objects[*item].1;
        let shares = leaves.iter().any(|l| {
            octree.leaf_items(*l).contains(item)
                && octree
                    .leaf_aabb(*l)
                    .enlarged(2.0 * tolerance)
                    .intersects(object)
                && octree
                    .leaf_aabb(*l)
                    .enlarged(2.0 * tolerance)
                    .intersects(query)
        });
        assert!(
            shares,
            "object {item} {object:?} found without a shared leaf"
        );
    }
}

proptest! {
    #![proptest_config(config(256))]

    #[test]
    fn query_aabb_contains_every_overlapping_object(
        scale in prop_oneof![Just(1e-6), Just(1e-3), Just(1.0), Just(1e3), Just(1e6)],
        shift in prop::array::uniform3(-2.0..2.0f64),
        refine in prop::collection::vec(unit_point(), 0..12),
        objects in prop::collection::vec(unit_box(), 0..50),
        queries in prop::collection::vec(unit_box(), 1..6),
    ) {
        let shift = Vector::new(shift[0], shift[1], shift[2]) * scale;
        let root = scaled(
            &Aabb::new(Point::new(-1.0, -1.0, -1.0), Point::new(1.0, 1.0, 1.0)),
            scale,
            &shift,
        );
        let mut octree = Octree::new(root.min, root.max, OctreeParams::default()).unwrap();
        for p in &refine {
            octree.insert_point(&(p * scale + shift)).unwrap();
        }
        let objects: Vec<(usize, Aabb)> = objects
            .iter()
            .enumerate()
            .map(|(i, b)| (i, scaled(b, scale, &shift)))
            .collect();
        for (item, aabb) in &objects {
            octree.insert(*item, aabb).unwrap();
        }
        prop_assert_eq!(octree.n_objects(), objects.len());
        for query in &queries {
            check_query(&octree, &objects, &scaled(query, scale, &shift));
        }
        // Each object, queried with its own box, finds itself.
        for (item, aabb) in &objects {
            let mut found = Vec::new();
            octree.query_aabb(aabb, &mut found).unwrap();
            prop_assert!(found.contains(item));
        }
    }
}
