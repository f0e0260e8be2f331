//! Criterion benchmarks of the search's building blocks and of one whole search step
//! (`cargo bench --bench search`). Speed targets are checked here, never in tests.

use std::hint::black_box;
use std::path::Path;

use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use csm::geometry::math::{Point, Vector};
use csm::geometry::{Geometry, GeometryKind, Kdop18, Obb, ObbIntersection, SatMode};
use csm::trees::{Aabb, KdTree, Octree};

/// A deterministic cloud of `n` points in the unit cube (xorshift).
fn cloud(n: usize) -> Vec<(u32, Point)> {
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..n as u32)
        .map(|i| (i, Point::new(next(), next(), next())))
        .collect()
}

fn kdtree(c: &mut Criterion) {
    let points = cloud(100_000);
    c.bench_function("kdtree build 1e5", |b| {
        b.iter(|| KdTree::new(black_box(&points), 4).unwrap())
    });
    // The step's tree: subtrees of up to 1024 points built when a query first reaches them;
    // here queries in a corner of the cloud (the bodies touching in a small region).
    let corner: Vec<Point> = points
        .iter()
        .map(|(_, p)| p)
        .filter(|p| p.x < 0.1 && p.y < 0.1)
        .take(1000)
        .copied()
        .collect();
    c.bench_function("kdtree deferred build + 1e3 corner queries 1e5", |b| {
        let mut out = Vec::new();
        b.iter(|| {
            let tree = KdTree::new_deferred(black_box(&points), 4, 1024).unwrap();
            for q in &corner {
                tree.in_radius(q, 0.01, 1000, &mut out).unwrap();
            }
            black_box(out.len())
        })
    });
    // A multi-step run's tree update: the points translated and perturbed a little.
    let moved: Vec<Point> = points
        .iter()
        .map(|(i, p)| p + Vector::new(0.01, 0.002 * f64::from(i % 3), -0.01))
        .collect();
    c.bench_function("kdtree refit 1e5", |b| {
        let mut tree = KdTree::new(&points, 4).unwrap();
        b.iter(|| tree.refit(|i| moved[i as usize]).unwrap())
    });
    c.bench_function("kdtree rebuild_moved 1e5", |b| {
        let mut tree = KdTree::new(&points, 4).unwrap();
        b.iter(|| tree.rebuild_moved(|i| moved[i as usize]).unwrap())
    });
    let tree = KdTree::new(&points, 4).unwrap();
    let mut out = Vec::new();
    c.bench_function("kdtree in_radius 1e3 queries", |b| {
        b.iter(|| {
            for (_, q) in points.iter().take(1000) {
                tree.in_radius(q, 0.01, 1000, &mut out).unwrap();
                black_box(out.len());
            }
        })
    });
}

/// Small boxes around the points of `cloud(n)`, as the faces of a mesh of that many faces.
fn boxes(n: usize) -> Vec<(u32, Aabb)> {
    let h = 0.5 / (n as f64).cbrt();
    cloud(n)
        .into_iter()
        .map(|(i, p)| (i, Aabb::new(p - Vector::repeat(h), p + Vector::repeat(h))))
        .collect()
}

fn octree(c: &mut Criterion) {
    let points = cloud(10_000);
    let objects = boxes(10_000);
    let build = || {
        let mut octree =
            Octree::with_kratos_params(Point::new(0.0, 0.0, 0.0), Point::new(1.0, 1.0, 1.0))
                .unwrap();
        for (_, p) in &points {
            octree.insert_point(p).unwrap();
        }
        for (item, aabb) in &objects {
            octree.insert(*item, aabb).unwrap();
        }
        octree
    };
    c.bench_function("octree refine 1e4 points + insert 1e4 boxes", |b| {
        b.iter(|| black_box(build().n_leaves()))
    });
    let octree = build();
    let mut out = Vec::new();
    c.bench_function("octree query_aabb 1e3 boxes", |b| {
        b.iter(|| {
            for (_, aabb) in objects.iter().take(1000) {
                octree.query_aabb(aabb, &mut out).unwrap();
                black_box(out.len());
            }
        })
    });
}

/// Bounding volumes of 1e3 triangles: Kratos' OBB (both branches) and the 18-DOP.
fn bounding_volumes(c: &mut Criterion) {
    let corners = cloud(3000);
    let triangles: Vec<[Point; 3]> = corners
        .chunks(3)
        .map(|t| [t[0].1, t[1].1, t[2].1])
        .collect();
    for from_aabb in [true, false] {
        c.bench_function(
            &format!("obb build 1e3 triangles (from AABB: {from_aabb})"),
            |b| {
                b.iter(|| {
                    for t in &triangles {
                        let g = Geometry::new(GeometryKind::Triangle3D3, t).unwrap();
                        black_box(Obb::from_geometry(&g, 0.01, from_aabb).unwrap());
                    }
                })
            },
        );
    }
    c.bench_function("kdop18 build + test 1e3 triangles", |b| {
        let first = Kdop18::from_points(&triangles[0]).enlarged(0.01);
        b.iter(|| {
            let mut hits = 0;
            for t in &triangles {
                hits += usize::from(Kdop18::from_points(t).enlarged(0.01).intersects(&first));
            }
            black_box(hits)
        })
    });
}

fn sat(c: &mut Criterion) {
    let a = Obb::new(
        Point::new(0.0, 0.0, 0.0),
        [Vector::x(), Vector::y(), Vector::z()],
        [1.0, 0.5, 0.1],
    );
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let b = Obb::new(
        Point::new(1.2, 0.3, 0.05),
        [Vector::new(s, s, 0.0), Vector::new(-s, s, 0.0), Vector::z()],
        [0.8, 0.4, 0.1],
    );
    for mode in [SatMode::Kratos, SatMode::Robust] {
        c.bench_function(&format!("sat obb-obb {mode:?}"), |bench| {
            bench.iter(|| black_box(&a).intersects(black_box(&b), ObbIntersection::Sat, mode))
        });
    }
}

fn search_step(c: &mut Criterion) {
    let mesh =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/scenes/sphere_on_plate_tri.mdpa");
    let model = csm::io::read_mesh(&mesh).unwrap();
    let setup = csm::cli::load_setup(
        r#"{"contact_model_part": {"0": ["Parts_Slave", "Parts_Master"]},
            "assume_master_slave": {"0": ["Parts_Slave"]}}"#,
        "bench",
    )
    .unwrap();
    // The model's copy is made outside the timing.
    c.bench_function("search step sphere_on_plate_tri (736 slave faces)", |b| {
        b.iter_batched(
            || model.clone(),
            |mut m| csm::cli::run_search(&mut m, &setup, 0.0).unwrap(),
            BatchSize::LargeInput,
        )
    });
}

/// RESULT.json of a result the size of the 2e5 sphere's (2e5 slave conditions, a few
/// thousand with masters, 1e5 nodes), written with 1 and 2 threads.
fn result_json(c: &mut Criterion) {
    use csm::search::{NodeResult, SearchResult};
    let mut r = SearchResult::default();
    let slaves = (1..=200_000u32)
        .map(|i| {
            let masters = if i % 60 == 0 {
                vec![i + 7, i + 9]
            } else {
                Vec::new()
            };
            (i, masters)
        })
        .collect();
    r.pairs.insert("0".to_owned(), slaves);
    r.nodes = (1..=100_000u32)
        .map(|i| {
            let normal_gap = (i % 3 == 0).then(|| -1e-3 * f64::from(i).sqrt());
            (
                i,
                NodeResult {
                    normal_gap,
                    active: i % 7 == 0,
                },
            )
        })
        .collect();
    let timings = [("read", 0.5), ("total", 1.0)];
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let mut out = Vec::with_capacity(32 << 20);
        c.bench_function(
            &format!("RESULT.json 2e5 slaves, {threads} thread(s)"),
            |b| {
                b.iter(|| {
                    out.clear();
                    pool.install(|| r.write_json(&timings, &mut out)).unwrap();
                    black_box(out.len())
                })
            },
        );
    }
}

criterion_group!(
    benches,
    kdtree,
    octree,
    bounding_volumes,
    sat,
    search_step,
    result_json
);
criterion_main!(benches);
