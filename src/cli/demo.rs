//! `csm demo`: an embedded scene, built in code, on which the search runs without any file.
//!
//! A sphere of radius [`DemoScene::radius`] pressed onto a plate, penetrating it by a tenth of
//! the element size:
//! - the plate: a structured block of `n × n × 2` Hexahedra3D8 elements (top face at z = 0),
//!   its top faces as Quadrilateral3D4 conditions, normals up: the part `master`;
//! - the sphere: its lower cap as a shell one element thick, `m × m` cells of a cube face
//!   projected on the sphere (the "cubed sphere"), each cell split into two Prism3D6
//!   elements, so that every node belongs to an element (Kratos gives NODAL_H = DBL_MAX to
//!   nodes outside elements); the outer faces are Triangle3D3 conditions, normals pointing
//!   out of the sphere (down): the part `slave`.
//!
//! `faces` ≈ the number of contact faces: `n² ≈ faces / 2` quadrilaterals and
//! `2 m² ≈ faces / 2` triangles. The plate's element size equals the size of the cap's cells
//! at the pole, so both sides are meshed alike. Parts: `plate`, `sphere` (elements and
//! nodes), `master`, `slave` (conditions and their nodes); ids are 1-based and consecutive,
//! plate first. `DOMAIN_SIZE` is 3.

use std::fmt::Write as _;

use csm_eval::{GroundTruth, Sample, Score, TruthOptions};
use csm_geometry::GeometryKind;
use csm_geometry::math::{Point, Real, Vector};
use csm_model::{ConditionIdx, ElementIdx, ModelPart, NodeIdx, PropertiesId};
use csm_search::{SearchResult, SearchSetup};
use rayon::prelude::*;

use crate::cli::Timings;

/// The default `--faces`.
pub const DEFAULT_FACES: usize = 20_000;
/// The largest `--faces` accepted.
pub const MAX_FACES: usize = 10_000_000;

/// The demo scene and its dimensions.
#[derive(Debug)]
pub struct DemoScene {
    /// The model `Structure` with the parts `plate`, `sphere`, `master`, `slave`.
    pub model: ModelPart,
    /// Quadrilateral faces on the plate's top (`master`).
    pub n_master_faces: usize,
    /// Triangular faces on the sphere's cap (`slave`).
    pub n_slave_faces: usize,
    /// The sphere's radius.
    pub radius: Real,
    /// The element size (plate edge; cap cell at the pole).
    pub element_size: Real,
    /// How far the sphere's lowest point lies below the plate's top.
    pub penetration: Real,
}

/// Entity records (`id, properties id, node ids…`, as [`ModelPart::add_entity_records`]
/// reads them) of `count` entities of `n` nodes, filled in parallel on rayon's pool: entity
/// `k` gets the id `first_id + k`, properties 0 and the node ids `fill(k, &mut ids)` writes.
fn records(
    count: usize,
    n: usize,
    first_id: u32,
    fill: impl Fn(usize, &mut [u32]) + Sync,
) -> Vec<u32> {
    /// Records per parallel task.
    const PER_TASK: usize = 4096;
    let width = n + 2;
    let mut out = vec![0u32; count * width];
    out.par_chunks_mut(PER_TASK * width)
        .enumerate()
        .for_each(|(task, chunk)| {
            for (j, r) in chunk.chunks_exact_mut(width).enumerate() {
                let k = task * PER_TASK + j;
                r[0] = first_id + k as u32;
                fill(k, &mut r[2..]);
            }
        });
    out
}

/// `a..b` as dense indices of the kind `T`.
fn indices<T>(range: std::ops::Range<usize>, make: impl Fn(u32) -> T) -> Vec<T> {
    range.map(|i| make(i as u32)).collect()
}

/// Builds the scene with about `faces` contact faces (at least 2 × 2 cells per side).
///
/// The nodes' positions and the entities' records are computed in parallel on rayon's pool
/// and added in bulk ([`ModelPart::add_nodes`], [`ModelPart::add_entity_records`]); the
/// model is the same for any thread count.
pub fn demo_scene(faces: usize) -> Result<DemoScene, String> {
    if faces > MAX_FACES {
        return Err(format!(
            "--faces {faces}: expected at most {MAX_FACES} faces"
        ));
    }
    // Plate: n × n top faces; cap: m × m cells, two triangles each.
    let n = ((faces as f64 / 2.0).sqrt().round() as usize).max(2);
    let m = ((faces as f64 / 4.0).sqrt().round() as usize).max(2);
    let nz = 2;
    let radius: Real = 1.0;
    // The cap is the cube face |u|, |v| ≤ A (on the plane at distance 1) projected on the
    // sphere: half-angle atan(A) ≈ 26.6° along the axes.
    const A: Real = 0.5;
    let h = radius * 2.0 * A / m as Real;
    let penetration = 0.1 * h;
    let mut model = ModelPart::new("Structure");
    model.ensure_properties(PropertiesId(0));
    model.process_info_mut().set_number("DOMAIN_SIZE", 3.0);
    let error = |(_, e): (usize, csm_model::Error)| e.to_string();

    // Node ids are 1-based and consecutive, node index + 1: the plate's (n + 1)² × (nz + 1)
    // nodes, layer by layer from the bottom, then the cap's outer and its inner nodes.
    // The plate, centred under the sphere, top at z = 0.
    let half = n as Real * h / 2.0;
    let row = n + 1;
    let n_plate = row * row * (nz + 1);
    let mut positions: Vec<[Real; 3]> = (0..n_plate)
        .into_par_iter()
        .map(|k| {
            let (i, j, l) = (k % row, (k / row) % row, k / (row * row));
            [
                -half + i as Real * h,
                -half + j as Real * h,
                (l as Real - nz as Real) * h,
            ]
        })
        .collect();
    // The sphere's cap: outer nodes on the sphere, inner nodes one element size inside.
    let centre = Point::new(0.0, 0.0, radius - penetration);
    let cap_row = m + 1;
    let n_outer = cap_row * cap_row;
    positions.par_extend((0..2 * n_outer).into_par_iter().map(|k| -> [Real; 3] {
        let (i, j) = ((k % n_outer) % cap_row, (k % n_outer) / cap_row);
        let u = -A + 2.0 * A * i as Real / m as Real;
        let v = -A + 2.0 * A * j as Real / m as Real;
        let d = Vector::new(u, v, -1.0).normalize();
        let r = if k < n_outer { radius } else { radius - h };
        (centre + r * d).coords.into()
    }));
    let ids: Vec<u32> = (1..=positions.len() as u32).collect();
    model.add_nodes(&ids, &positions).map_err(error)?;
    drop((ids, positions));
    let p = |i: usize, j: usize, k: usize| ((k * row + j) * row + i + 1) as u32;
    let o = |i: usize, j: usize| (n_plate + j * cap_row + i + 1) as u32;
    let q = |i: usize, j: usize| (n_plate + n_outer + j * cap_row + i + 1) as u32;

    // The plate's hexahedra, layer by layer; the cap's prisms, cell by cell, two each.
    let n_hexahedra = n * n * nz;
    let hexahedra = records(n_hexahedra, 8, 1, |e, r| {
        let (i, j, k) = (e % n, (e / n) % n, e / (n * n));
        // Bottom counter-clockwise seen from above, then the top: positive volume.
        r.copy_from_slice(&[
            p(i, j, k),
            p(i + 1, j, k),
            p(i + 1, j + 1, k),
            p(i, j + 1, k),
            p(i, j, k + 1),
            p(i + 1, j, k + 1),
            p(i + 1, j + 1, k + 1),
            p(i, j + 1, k + 1),
        ]);
    });
    let element = (GeometryKind::Hexahedra3D8, "SmallDisplacementElement3D8N");
    model
        .add_entity_records(false, element.0, element.1, &hexahedra)
        .map_err(error)?;
    drop(hexahedra);
    // Two triangles per cell, counter-clockwise seen from above (normal up, into the
    // sphere): the prisms' outer triangles, with the inner triangle above; the conditions
    // take them reversed, normal down and out of the sphere.
    let triangle = |t: usize| -> [(usize, usize); 3] {
        let (i, j) = ((t / 2) % m, t / 2 / m);
        if t.is_multiple_of(2) {
            [(i, j), (i + 1, j), (i + 1, j + 1)]
        } else {
            [(i, j), (i + 1, j + 1), (i, j + 1)]
        }
    };
    let n_triangles = 2 * m * m;
    let prisms = records(n_triangles, 6, 1 + n_hexahedra as u32, |t, r| {
        let [a, c, d] = triangle(t);
        r.copy_from_slice(&[
            o(a.0, a.1),
            o(c.0, c.1),
            o(d.0, d.1),
            q(a.0, a.1),
            q(c.0, c.1),
            q(d.0, d.1),
        ]);
    });
    let element = (GeometryKind::Prism3D6, "SmallDisplacementElement3D6N");
    model
        .add_entity_records(false, element.0, element.1, &prisms)
        .map_err(error)?;
    drop(prisms);

    // The plate's top faces, counter-clockwise seen from above (the normal points up, out of
    // the plate); the cap's outer triangles.
    let quadrilaterals = records(n * n, 4, 1, |f, r| {
        let (i, j) = (f % n, f / n);
        r.copy_from_slice(&[
            p(i, j, nz),
            p(i + 1, j, nz),
            p(i + 1, j + 1, nz),
            p(i, j + 1, nz),
        ]);
    });
    let condition = (GeometryKind::Quadrilateral3D4, "SurfaceCondition3D4N");
    model
        .add_entity_records(true, condition.0, condition.1, &quadrilaterals)
        .map_err(error)?;
    drop(quadrilaterals);
    let triangles = records(n_triangles, 3, 1 + (n * n) as u32, |t, r| {
        let [a, c, d] = triangle(t);
        r.copy_from_slice(&[o(a.0, a.1), o(d.0, d.1), o(c.0, c.1)]);
    });
    let condition = (GeometryKind::Triangle3D3, "SurfaceCondition3D3N");
    model
        .add_entity_records(true, condition.0, condition.1, &triangles)
        .map_err(error)?;
    drop(triangles);

    // The parts: every list is a range of dense indices (every plate node is a hexahedron's,
    // every top node a top face's, every cap node a prism's, every outer node a triangle's).
    let n_cap = 2 * n_outer;
    let top = row * row * nz..n_plate;
    let parts = [
        ("plate", 0..n_plate, 0..n_hexahedra, 0..0),
        (
            "sphere",
            n_plate..n_plate + n_cap,
            n_hexahedra..n_hexahedra + n_triangles,
            0..0,
        ),
        ("master", top, 0..0, 0..n * n),
        (
            "slave",
            n_plate..n_plate + n_outer,
            0..0,
            n * n..n * n + n_triangles,
        ),
    ];
    for (path, nodes, elements, conditions) in parts {
        let part = model.create_part(path).map_err(|e| e.to_string())?;
        model.add_nodes_to_part(part, &indices(nodes, NodeIdx));
        model.add_elements_to_part(part, &indices(elements, ElementIdx));
        model.add_conditions_to_part(part, &indices(conditions, ConditionIdx));
    }
    Ok(DemoScene {
        model,
        n_master_faces: n * n,
        n_slave_faces: n_triangles,
        radius,
        element_size: h,
        penetration,
    })
}

/// The summary `csm demo` prints.
pub fn demo_summary(scene: &DemoScene, result: &SearchResult, timings: &Timings) -> String {
    let mut s = String::new();
    let active = result.nodes.values().filter(|n| n.active).count();
    // Writing to a String cannot fail.
    let _ = writeln!(
        s,
        "csm demo: a sphere (radius {}) pressed {:.2e} into a plate (element size {:.2e})",
        scene.radius, scene.penetration, scene.element_size
    );
    let _ = writeln!(
        s,
        "  faces:      {} slave (sphere, Triangle3D3), {} master (plate, Quadrilateral3D4)",
        scene.n_slave_faces, scene.n_master_faces
    );
    let _ = writeln!(
        s,
        "  candidates: {} pairs over {} slave conditions, {} paired conditions, {} active nodes",
        result.n_pairs(),
        result
            .pairs
            .values()
            .flat_map(|m| m.values())
            .filter(|v| !v.is_empty())
            .count(),
        result.paired_conditions,
        active
    );
    let _ = writeln!(
        s,
        "  time:       build {:.3} s, initialize {:.3} s, search {:.3} s (total {:.3} s, {} threads)",
        timings.read,
        timings.initialize,
        timings.search,
        timings.total,
        rayon::current_num_threads()
    );
    if result.warnings.is_empty() {
        let _ = writeln!(s, "  warnings:   none");
    } else {
        for w in &result.warnings {
            let _ = writeln!(s, "  warning:    {w}");
        }
    }
    s
}

/// The default search of the demo against the ground truth ([`demo_truth`]).
#[derive(Debug, Clone, PartialEq)]
pub struct DemoTruth {
    /// The ground truth of the setup's first pair key.
    pub truth: GroundTruth,
    /// The demo's search result against it.
    pub score: Score,
    /// Wall time of the ground truth, seconds.
    pub seconds: f64,
}

impl DemoTruth {
    /// The line `csm demo` prints.
    pub fn line(&self) -> String {
        let sc = &self.score;
        let gap = sc
            .max_gap_error
            .map_or_else(|| "—".to_owned(), |e| format!("{e:.2e}"));
        format!(
            "  truth:      {} true pairs ({}, {:.3} s); the search missed {} ({:.2}%)\n              {} spurious candidates before the mortar pruning, {} wrong ACTIVE flags, gap \
             error {gap} (`csm demo --report` compares every strategy)\n",
            sc.true_pairs,
            if self.truth.sampled {
                format!("a sample of {} slave faces", self.truth.pairs.len())
            } else {
                "exhaustive".to_owned()
            },
            self.seconds,
            sc.missed,
            sc.missed_percent(),
            sc.spurious_candidates,
            sc.wrong_active
        )
    }
}

/// The demo's summary against the ground truth: the exact pairs and gaps of `setup`'s first
/// pair key on `model` (the scene before the search, which the ground truth searches and
/// drops: no copy; a sample of 2,000 slave faces above 20,000 faces per side) and the score
/// of `result`, the demo's search.
pub fn demo_truth(
    model: ModelPart,
    setup: &SearchSetup,
    result: &SearchResult,
) -> Result<DemoTruth, String> {
    let key = *setup
        .pairs
        .keys()
        .next()
        .ok_or_else(|| "the setup has no contact pair".to_owned())?;
    let faces = model.conditions().len();
    let sample = (faces > 2 * 20_000).then_some(Sample {
        size: 2_000,
        seed: 1,
    });
    let start = std::time::Instant::now();
    let options = TruthOptions {
        prefilter: true,
        sample,
    };
    let truth =
        GroundTruth::compute_owned(model, setup, key, &options).map_err(|e| e.to_string())?;
    let seconds = start.elapsed().as_secs_f64();
    let score = truth.score(result);
    Ok(DemoTruth {
        truth,
        score,
        seconds,
    })
}

#[cfg(test)]
mod tests;
