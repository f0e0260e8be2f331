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

use csm_eval::{GroundTruth, Sample, Score};
use csm_geometry::GeometryKind;
use csm_geometry::math::{Point, Real, Vector};
use csm_model::{
    ConditionId, ConditionIdx, ElementId, ElementIdx, ModelPart, NodeId, NodeIdx, PropertiesId,
};
use csm_search::{SearchResult, SearchSetup};

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

/// Adds nodes with consecutive ids after the largest one.
struct Builder {
    model: ModelPart,
    next_node: u32,
    next_element: u32,
    next_condition: u32,
    props: PropertiesId,
}

impl Builder {
    fn node(&mut self, p: Point) -> Result<NodeIdx, String> {
        self.next_node += 1;
        self.model
            .add_node(NodeId(self.next_node), p)
            .map_err(|e| e.to_string())
    }

    fn element(
        &mut self,
        kind: GeometryKind,
        name: &str,
        nodes: &[NodeIdx],
    ) -> Result<ElementIdx, String> {
        self.next_element += 1;
        let ids: Vec<NodeId> = nodes.iter().map(|&n| self.id(n)).collect();
        self.model
            .add_element(ElementId(self.next_element), kind, name, &ids, self.props)
            .map_err(|e| e.to_string())
    }

    fn condition(
        &mut self,
        kind: GeometryKind,
        name: &str,
        nodes: &[NodeIdx],
    ) -> Result<ConditionIdx, String> {
        self.next_condition += 1;
        let ids: Vec<NodeId> = nodes.iter().map(|&n| self.id(n)).collect();
        self.model
            .add_condition(
                ConditionId(self.next_condition),
                kind,
                name,
                &ids,
                self.props,
            )
            .map_err(|e| e.to_string())
    }

    fn id(&self, n: NodeIdx) -> NodeId {
        NodeId(self.model.nodes().ids()[n.index()])
    }

    fn part(
        &mut self,
        path: &str,
        nodes: &[NodeIdx],
        elements: &[ElementIdx],
        conditions: &[ConditionIdx],
    ) -> Result<(), String> {
        let part = self.model.create_part(path).map_err(|e| e.to_string())?;
        let mut nodes = nodes.to_vec();
        nodes.sort_unstable();
        nodes.dedup();
        self.model.add_nodes_to_part(part, &nodes);
        self.model.add_elements_to_part(part, elements);
        self.model.add_conditions_to_part(part, conditions);
        Ok(())
    }
}

/// Builds the scene with about `faces` contact faces (at least 2 × 2 cells per side).
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
    let mut b = Builder {
        model: ModelPart::new("Structure"),
        next_node: 0,
        next_element: 0,
        next_condition: 0,
        props: PropertiesId(0),
    };
    b.model.ensure_properties(b.props);
    b.model.process_info_mut().set_number("DOMAIN_SIZE", 3.0);

    // The plate, centred under the sphere, top at z = 0.
    let half = n as Real * h / 2.0;
    let mut plate_nodes = Vec::with_capacity((n + 1) * (n + 1) * (nz + 1));
    for k in 0..=nz {
        for j in 0..=n {
            for i in 0..=n {
                let p = Point::new(
                    -half + i as Real * h,
                    -half + j as Real * h,
                    (k as Real - nz as Real) * h,
                );
                plate_nodes.push(b.node(p)?);
            }
        }
    }
    let p = |i: usize, j: usize, k: usize| plate_nodes[(k * (n + 1) + j) * (n + 1) + i];
    let mut plate_elements = Vec::with_capacity(n * n * nz);
    for k in 0..nz {
        for j in 0..n {
            for i in 0..n {
                // Bottom counter-clockwise seen from above, then the top: positive volume.
                let nodes = [
                    p(i, j, k),
                    p(i + 1, j, k),
                    p(i + 1, j + 1, k),
                    p(i, j + 1, k),
                    p(i, j, k + 1),
                    p(i + 1, j, k + 1),
                    p(i + 1, j + 1, k + 1),
                    p(i, j + 1, k + 1),
                ];
                plate_elements.push(b.element(
                    GeometryKind::Hexahedra3D8,
                    "SmallDisplacementElement3D8N",
                    &nodes,
                )?);
            }
        }
    }
    let mut master = Vec::with_capacity(n * n);
    let mut master_nodes = Vec::with_capacity((n + 1) * (n + 1));
    for j in 0..n {
        for i in 0..n {
            // Counter-clockwise seen from above: the normal points up, out of the plate.
            let nodes = [
                p(i, j, nz),
                p(i + 1, j, nz),
                p(i + 1, j + 1, nz),
                p(i, j + 1, nz),
            ];
            master.push(b.condition(
                GeometryKind::Quadrilateral3D4,
                "SurfaceCondition3D4N",
                &nodes,
            )?);
            master_nodes.extend(nodes);
        }
    }

    // The sphere's cap: outer nodes on the sphere, inner nodes one element size inside.
    let centre = Point::new(0.0, 0.0, radius - penetration);
    let mut outer = Vec::with_capacity((m + 1) * (m + 1));
    let mut inner = Vec::with_capacity((m + 1) * (m + 1));
    for j in 0..=m {
        for i in 0..=m {
            let u = -A + 2.0 * A * i as Real / m as Real;
            let v = -A + 2.0 * A * j as Real / m as Real;
            let d = Vector::new(u, v, -1.0).normalize();
            outer.push(centre + radius * d);
            inner.push(centre + (radius - h) * d);
        }
    }
    let mut sphere_nodes = Vec::with_capacity(2 * outer.len());
    for &x in &outer {
        sphere_nodes.push(b.node(x)?);
    }
    for &x in &inner {
        sphere_nodes.push(b.node(x)?);
    }
    let n_outer = outer.len();
    let o = |i: usize, j: usize| sphere_nodes[j * (m + 1) + i];
    let q = |i: usize, j: usize| sphere_nodes[n_outer + j * (m + 1) + i];
    let mut sphere_elements = Vec::with_capacity(2 * m * m);
    let mut slave = Vec::with_capacity(2 * m * m);
    let mut slave_nodes = Vec::with_capacity(n_outer);
    for j in 0..m {
        for i in 0..m {
            // Two triangles counter-clockwise seen from above (normal up, into the sphere):
            // the prisms' outer triangles, with the inner triangle above; the conditions take
            // them reversed, normal down and out of the sphere.
            for [a, c, d] in [
                [(i, j), (i + 1, j), (i + 1, j + 1)],
                [(i, j), (i + 1, j + 1), (i, j + 1)],
            ] {
                let prism = [
                    o(a.0, a.1),
                    o(c.0, c.1),
                    o(d.0, d.1),
                    q(a.0, a.1),
                    q(c.0, c.1),
                    q(d.0, d.1),
                ];
                sphere_elements.push(b.element(
                    GeometryKind::Prism3D6,
                    "SmallDisplacementElement3D6N",
                    &prism,
                )?);
                let face = [o(a.0, a.1), o(d.0, d.1), o(c.0, c.1)];
                slave.push(b.condition(
                    GeometryKind::Triangle3D3,
                    "SurfaceCondition3D3N",
                    &face,
                )?);
                slave_nodes.extend(face);
            }
        }
    }
    b.part("plate", &plate_nodes, &plate_elements, &[])?;
    b.part("sphere", &sphere_nodes, &sphere_elements, &[])?;
    b.part("master", &master_nodes, &[], &master)?;
    b.part("slave", &slave_nodes, &[], &slave)?;
    Ok(DemoScene {
        model: b.model,
        n_master_faces: master.len(),
        n_slave_faces: slave.len(),
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
/// pair key on `model` (the scene before the search; a sample of 2,000 slave faces above
/// 20,000 faces per side) and the score of `result`, the demo's search.
pub fn demo_truth(
    model: &ModelPart,
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
    let truth = GroundTruth::compute(model, setup, key, sample).map_err(|e| e.to_string())?;
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
