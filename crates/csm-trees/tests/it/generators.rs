//! Seeded proptest configuration and generators of point clouds and queries.

use csm_geometry::math::{Point, Real, Vector};
use proptest::prelude::*;
use proptest::test_runner::{Config, FileFailurePersistence, RngSeed};

/// The fixed seed of every property test (rstar `SEED_1` style).
pub const SEED: u64 = 0x00c5_7ee5_2024_0001;

/// A seeded configuration with `cases` cases; failures are persisted next to the test sources.
pub fn config(cases: u32) -> Config {
    Config {
        cases,
        rng_seed: RngSeed::Fixed(SEED),
        failure_persistence: Some(Box::new(FileFailurePersistence::SourceParallel(
            "proptest-regressions",
        ))),
        max_shrink_iters: 2_000,
        ..Config::default()
    }
}

/// The coordinate scales exercised: tiny, ordinary, huge.
pub fn scale() -> impl Strategy<Value = Real> {
    prop_oneof![Just(1e-12), Just(1e-3), Just(1.0), Just(1e3), Just(1e12)]
}

/// A point with coordinates in `[-1, 1]`, sometimes snapped to a coarse grid so that ties
/// (equal coordinates, points on box faces, exact distances) are common.
fn unit_point() -> impl Strategy<Value = Point> {
    prop_oneof![
        prop::array::uniform3(-1.0..=1.0f64).prop_map(|c| Point::new(c[0], c[1], c[2])),
        prop::array::uniform3(-4i32..=4).prop_map(|c| Point::new(
            c[0] as Real / 4.0,
            c[1] as Real / 4.0,
            c[2] as Real / 4.0
        )),
    ]
}

/// The shapes of point clouds.
#[derive(Debug, Clone, Copy)]
pub enum CloudKind {
    /// Independent points.
    Random,
    /// Points drawn from a handful of distinct positions (many duplicates).
    Duplicates,
    /// Points on one line.
    Collinear,
    /// Points in one plane (z = const or a tilted plane).
    Coplanar,
    /// All points identical.
    Identical,
}

fn cloud_kind() -> impl Strategy<Value = CloudKind> {
    prop_oneof![
        3 => Just(CloudKind::Random),
        2 => Just(CloudKind::Duplicates),
        2 => Just(CloudKind::Collinear),
        2 => Just(CloudKind::Coplanar),
        1 => Just(CloudKind::Identical),
    ]
}

/// A point cloud of `0..max_n` points of one of the [`CloudKind`]s, scaled by one of the
/// [`scale`]s and shifted by an offset of the same order.
pub fn cloud(max_n: usize) -> impl Strategy<Value = Vec<Point>> {
    (
        cloud_kind(),
        scale(),
        unit_point(),
        prop::collection::vec(unit_point(), 0..max_n),
        prop::collection::vec(0usize..5, 0..max_n),
        prop::collection::vec(-1.0..=1.0f64, 0..max_n),
        unit_point(),
        unit_point(),
        any::<bool>(),
    )
        .prop_map(
            |(kind, scale, offset, randoms, picks, params, dir1, dir2, flat)| {
                let n = randoms.len();
                let unit: Vec<Point> = match kind {
                    CloudKind::Random => randoms,
                    CloudKind::Duplicates => (0..n)
                        .map(|i| randoms[picks.get(i).copied().unwrap_or(0) % n])
                        .collect(),
                    CloudKind::Collinear => {
                        let d: Vector = dir1.coords;
                        (0..n)
                            .map(|i| offset + d * params.get(i).copied().unwrap_or(0.5))
                            .collect()
                    }
                    CloudKind::Coplanar => (0..n)
                        .map(|i| {
                            let mut p = randoms[i];
                            if flat {
                                p.z = offset.z;
                            } else {
                                // p = offset + s·dir1 + t·dir2
                                let (s, t) = (p.x, p.y);
                                p = offset + dir1.coords * s + dir2.coords * t;
                            }
                            p
                        })
                        .collect(),
                    CloudKind::Identical => vec![offset; n],
                };
                let shift = offset.coords * scale;
                unit.into_iter().map(|p| p * scale + shift).collect()
            },
        )
}

/// A query centre: one of the cloud points (often, to hit exact distances) or any point near
/// the cloud.
pub fn pick_point(cloud: &[Point], pick: usize, fallback: Point) -> Point {
    if cloud.is_empty() || pick.is_multiple_of(3) {
        fallback
    } else {
        cloud[pick % cloud.len()]
    }
}

/// The bounding scale of a cloud (1 for an empty or single-position cloud).
pub fn cloud_scale(cloud: &[Point]) -> Real {
    let m = cloud
        .iter()
        .flat_map(|p| p.coords.iter().map(|c| c.abs()))
        .fold(0.0, Real::max);
    if m > 0.0 { m } else { 1.0 }
}

/// Items of a cloud: their index.
pub fn entries(cloud: &[Point]) -> Vec<(usize, Point)> {
    cloud.iter().copied().enumerate().collect()
}
