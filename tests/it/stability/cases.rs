//! The cases of the stability suite: the fixture scenes under transforms, and extreme meshes
//! built in code (`scene.rs`).

use csm::model::ModelPart;
use csm::prelude::{Point, Real, Vector};
use serde_json::{Value, json};

use super::scene::{Scene, Sheet, linspace};

/// What a case's pairs are compared with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Oracle {
    /// The pairs whose projected overlap is at least 1e-9 of the slave's area (flat, close
    /// contact: every overlapping master is within reach and faces the slave).
    Overlap,
    /// The untransformed robust result (curved fixture scenes; pending the ground truth).
    RobustBaseline,
    /// None (the case must fail with an error).
    Error,
}

/// How a case spoils the model after reading it (coordinates a reader would refuse).
pub type Edit = fn(&mut ModelPart);

/// One case.
#[derive(Debug, Clone)]
pub struct Case {
    /// Its name in the report.
    pub name: &'static str,
    /// What it exercises.
    pub what: &'static str,
    /// The mesh, `.mdpa` text.
    pub mdpa: String,
    /// 2 or 3.
    pub dim: u8,
    /// The setup, without `compatibility` and `check_gap`.
    pub setup: Value,
    /// The `check_gap`s it runs.
    pub checks: &'static [&'static str],
    /// Whether it runs under the report's transforms.
    pub transforms: bool,
    /// The oracle of its pairs.
    pub oracle: Oracle,
    /// The exact normal gap where the scene is flat and parallel.
    pub analytic_gap: Option<Real>,
    /// The spoiling edit.
    pub edit: Option<Edit>,
    /// Part of the CI-size suite (else only in `cargo xtask stability`).
    pub ci: bool,
}

const MAPPING_DIRECT: &[&str] = &["mapping_check", "direct_check"];
const MAPPING: &[&str] = &["mapping_check"];

fn setup(extra_search: Value, extra: Value) -> Value {
    let mut s = json!({
        "contact_model_part": {"0": ["Slave", "Master"]},
        "assume_master_slave": {"0": ["Slave"]},
        "search_parameters": {},
    });
    if let Value::Object(m) = extra_search {
        for (k, v) in m {
            s["search_parameters"][k] = v;
        }
    }
    if let Value::Object(m) = extra {
        for (k, v) in m {
            s[k] = v;
        }
    }
    s
}

fn fixture_setup(scene: &str) -> Value {
    let mut s = json!({
        "contact_model_part": {"0": ["Parts_Slave", "Parts_Master"]},
        "assume_master_slave": {"0": ["Parts_Slave"]},
        "search_parameters": {},
    });
    if scene == "plane_cylinder_cpp" {
        // Kratos' C++ test (no elements): its C++ parameters, NODAL_H and DISTANCE_THRESHOLD
        // given (scaled with the mesh), as in `tests/fixtures/search/plane_cylinder_cpp/`.
        s = json!({
            "contact_model_part": {"0": ["Parts_Slave", "Parts_Master"]},
            "assume_master_slave": {"0": ["Parts_Slave"]},
            "cpp_search_parameters": {
                "simple_search": true,
                "search_factor": 3.5,
                "normal_orientation_threshold": 0.0,
                "type_search": "InRadiusWithOBB",
                "check_gap": "MappingCheck",
            },
            "nodal_h": 1.0,
            "process_info": {"STEP": 1, "NL_ITERATION_NUMBER": 1, "DELTA_TIME": 1.0,
                             "DISTANCE_THRESHOLD": 1.0},
        });
    }
    s
}

/// The master: a flat sheet in z = 0 facing up, `xs × ys`.
fn master(xs: &[Real], ys: &[Real]) -> Sheet {
    Sheet::flat(Point::origin(), Vector::x(), Vector::y(), xs, ys)
}

/// A slave: a flat sheet in z = `z` facing down, `xs × ys`.
fn slave(z: Real, xs: &[Real], ys: &[Real]) -> Sheet {
    Sheet::flat(Point::new(0.0, 0.0, z), Vector::x(), Vector::y(), xs, ys).flipped()
}

/// Two flat plates: a slave of 4 × 4 cells of size 1 shifted by a third of a cell over a master
/// of 5 × 5 cells (x, y in [−0.5, 4.5]), at gap `gap`.
pub fn plates(gap: Real) -> Scene {
    let s = linspace(1.0 / 3.0, 4.0 + 1.0 / 3.0, 4);
    let m = linspace(-0.5, 4.5, 5);
    Scene::new()
        .sheet(&slave(gap, &s, &s), true)
        .sheet(&master(&m, &m), false)
}

/// [`plates`] with the slave shifted by `shift` cells along x and y instead of a third.
pub fn plates_with_shift(gap: Real, shift: Real) -> Scene {
    let s = linspace(shift, 4.0 + shift, 4);
    let m = linspace(-0.5, 4.5, 5);
    Scene::new()
        .sheet(&slave(gap, &s, &s), true)
        .sheet(&master(&m, &m), false)
}

/// Quadrilateral slaves over a triangulated master, the interface plane at `z0` (gap `gap`):
/// many slaves overlap a master in a single triangular cell, whose `Me` is singular (the
/// standard basis in Kratos, the case that needs the mapper's iterations).
pub fn quads_over_triangles(z0: Real, gap: Real) -> Scene {
    let s = linspace(1.0 / 3.0, 4.0 + 1.0 / 3.0, 4);
    let m = linspace(-0.5, 4.5, 5);
    let scene = Scene::new()
        .sheet(&slave(gap, &s, &s), true)
        .sheet(&master(&m, &m).triangles(), false);
    scene.map_from(0, move |p| p + Vector::new(0.0, 0.0, z0))
}

/// Quadrilateral slaves over a master of equilateral triangles (side 1) at gap `gap`: each
/// master's three edge-aligned boxes tie.
pub fn over_equilateral_triangles(gap: Real) -> Scene {
    let s = linspace(1.0 / 3.0, 3.0 + 1.0 / 3.0, 3);
    let master_sheet = Sheet::flat(
        Point::new(-1.0, -0.5, 0.0),
        Vector::x(),
        Vector::new(-0.5, 3f64.sqrt() / 2.0, 0.0),
        &linspace(0.0, 7.0, 7),
        &linspace(0.0, 6.0, 6),
    )
    .triangles();
    Scene::new()
        .sheet(&slave(gap, &s, &s), true)
        .sheet(&master_sheet, false)
}

/// A cylindrical cap (radius 2, axis along y, ±30°) of 6 × 3 cells pressed 0.05 into a plate
/// of 5 × 4 triangulated cells: a small curved scene for the invariance properties.
pub fn cylinder_on_plate() -> Scene {
    let r = 2.0;
    let angles = linspace(-0.5, 0.5, 6);
    let ys = linspace(0.0, 3.0, 3);
    let grid = ys
        .iter()
        .map(|&y| {
            angles
                .iter()
                .map(|&a: &Real| Point::new(r * a.sin(), y, r - 0.05 - r * a.cos()))
                .collect()
        })
        .collect();
    let cap = Sheet {
        grid,
        out: -Vector::z(),
        thickness: 0.5,
        triangles: false,
    };
    let m = linspace(-1.5, 1.5, 5);
    let my = linspace(-0.5, 3.5, 4);
    Scene::new()
        .sheet(&cap, true)
        .sheet(&master(&m, &my).triangles(), false)
}

fn spoil_nan(model: &mut ModelPart) {
    model.nodes_mut().coordinates_mut()[0].x = Real::NAN;
}

fn spoil_inf(model: &mut ModelPart) {
    model.nodes_mut().coordinates_mut()[0].z = Real::INFINITY;
}

/// Every case; `ci` marks those of the CI-size suite.
pub fn all() -> Vec<Case> {
    let mut cases = Vec::new();
    for (scene, dim, ci) in [
        ("plane_cylinder_cpp", 3, true),
        ("stacked_blocks_rotated", 3, true),
        ("cylinder_on_block_2d", 2, true),
        ("stacked_blocks", 3, false),
        ("stacked_blocks_pen", 3, false),
        ("sphere_on_plate_tri", 3, false),
        ("sphere_on_plate_mixed", 3, false),
        ("cylinder_on_plate_quads", 3, false),
    ] {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join(format!("tests/data/scenes/{scene}.mdpa"));
        let mdpa = std::fs::read_to_string(&path).expect("fixture scene");
        cases.push(Case {
            name: scene,
            what: "fixture scene",
            mdpa,
            dim,
            setup: fixture_setup(scene),
            checks: MAPPING_DIRECT,
            transforms: true,
            oracle: Oracle::RobustBaseline,
            analytic_gap: None,
            edit: None,
            ci,
        });
    }
    let built = |name, what, scene: Scene, oracle, gap| Case {
        name,
        what,
        mdpa: scene.to_mdpa(),
        dim: 3,
        setup: setup(json!({}), json!({})),
        checks: MAPPING_DIRECT,
        transforms: true,
        oracle,
        analytic_gap: gap,
        edit: None,
        ci: true,
    };
    cases.push(built(
        "flat_gap",
        "two flat non-matching plates, gap 0.05 h (reference case)",
        plates(0.05),
        Oracle::Overlap,
        Some(0.05),
    ));
    cases.push(built(
        "cylinder_on_plate",
        "small curved scene built in code (cylindrical cap on a triangulated plate)",
        cylinder_on_plate(),
        Oracle::RobustBaseline,
        None,
    ));
    // Slivers: cells 1 × 1e-4 split into triangles (aspect ratio 1e4 and more) over quads of
    // 1 × 2e-4.
    let sx = linspace(1.0 / 3.0, 4.0 + 1.0 / 3.0, 4);
    let sy = linspace(0.0, 4e-4, 4);
    let mx = linspace(-0.5, 4.5, 5);
    let my = linspace(-2e-4, 6e-4, 4);
    cases.push(built(
        "sliver_triangles",
        "slave triangles of aspect ratio ≥ 1e4 over quadrilaterals of aspect ratio 5e3, gap 1e-5",
        Scene::new()
            .sheet(&slave(1e-5, &sx, &sy).triangles().thick(1e-4), true)
            .sheet(&master(&mx, &my).thick(1e-4), false),
        Oracle::Overlap,
        Some(1e-5),
    ));
    // Nearly parallel: the slave tilted by 1e-12 rad about y, the master by 1e-12 about x.
    let tilt = |axis: Vector, angle: Real| {
        let r = csm::geometry::math::Matrix3::identity() + {
            let k = axis;
            csm::geometry::math::Matrix3::new(0.0, -k.z, k.y, k.z, 0.0, -k.x, -k.y, k.x, 0.0)
        } * angle;
        move |p: Point| Point::from(r * p.coords)
    };
    let s = linspace(1.0 / 3.0, 4.0 + 1.0 / 3.0, 4);
    let m = linspace(-0.5, 4.5, 5);
    let master_part = Scene::new()
        .sheet(&master(&m, &m), false)
        .map_from(0, tilt(Vector::x(), -1e-12));
    let first_slave_node = master_part.n_nodes();
    let parallel = master_part
        .sheet(&slave(1e-3, &s, &s), true)
        .map_from(first_slave_node, tilt(Vector::y(), 1e-12));
    cases.push(built(
        "nearly_parallel",
        "plates at gap 1e-3 h, tilted by 1e-12 rad against each other (SAT cross axes within 1e-12)",
        parallel,
        Oracle::Overlap,
        Some(1e-3),
    ));
    let s = linspace(0.0, 4.0, 4);
    cases.push(built(
        "coincident_matching",
        "matching plates at gap exactly 0 (mesh tying)",
        Scene::new()
            .sheet(&slave(0.0, &s, &s), true)
            .sheet(&master(&s, &s), false),
        Oracle::Overlap,
        Some(0.0),
    ));
    cases.push(built(
        "coincident_nonmatching",
        "non-matching plates at gap exactly 0",
        plates(0.0),
        Oracle::Overlap,
        Some(0.0),
    ));
    cases.push(built(
        "deep_penetration",
        "plates penetrating by half an element (gap −0.5 h)",
        plates(-0.5),
        Oracle::Overlap,
        Some(-0.5),
    ));
    let s = linspace(4.0, 8.0, 4);
    let m = linspace(0.0, 4.0, 4);
    cases.push(built(
        "grazing_edge",
        "coplanar plates (gap 0) that touch only along the edge x = 4",
        Scene::new()
            .sheet(&slave(0.0, &s, &m), true)
            .sheet(&master(&m, &m), false),
        Oracle::Overlap,
        None,
    ));
    // Graded master: 10 cells from size 1 down to 1e-3 (geometric), under a uniform slave.
    let ratio = (1e-3_f64).powf(1.0 / 9.0);
    let mut gx = vec![0.0];
    for k in 0..10 {
        gx.push(gx[k] + ratio.powi(k as i32));
    }
    let len = gx[10];
    let sx = linspace(0.1, len - 0.1, 3);
    let sy = linspace(0.1, 2.9, 3);
    let my = linspace(0.0, 3.0, 3);
    let graded = Scene::new()
        .sheet(&slave(0.01, &sx, &sy), true)
        .sheet(&master(&gx, &my), false);
    cases.push(built(
        "graded",
        "master cells graded from h to 1e-3 h under a uniform slave, gap 0.01",
        graded.clone(),
        Oracle::Overlap,
        Some(0.01),
    ));
    let mut adapt = built(
        "graded_adapt_search",
        "the graded scene with adapt_search",
        graded,
        Oracle::Overlap,
        Some(0.01),
    );
    adapt.setup = setup(json!({"adapt_search": true}), json!({}));
    cases.push(adapt);
    for (name, z0) in [
        ("quads_over_triangles_z1", 1.0),
        ("quads_over_triangles_z1e3", 1e3),
        ("quads_over_triangles_z1e6", 1e6),
    ] {
        cases.push(built(
            name,
            "quadrilateral slaves over triangle masters (single-triangle overlaps: Kratos' standard basis), interface plane off the origin, gap 0.05",
            quads_over_triangles(z0, 0.05),
            Oracle::Overlap,
            Some(0.05),
        ));
    }
    cases.push(built(
        "equilateral_masters",
        "quadrilateral slaves over equilateral-triangle masters (three tied OBB rectangles each), gap 0.05",
        over_equilateral_triangles(0.05),
        Oracle::Overlap,
        Some(0.05),
    ));
    let s = linspace(-2.0, 2.0, 4);
    cases.push(built(
        "node_over_origin",
        "matching plates at gap 0.05 with a slave node mapped onto the master node at the origin (Kratos reads |AUX| ≤ ε as not mapped)",
        Scene::new()
            .sheet(&slave(0.05, &s, &s), true)
            .sheet(&master(&s, &s), false),
        Oracle::Overlap,
        Some(0.05),
    ));
    let zx = [1.0 / 3.0, 4.0 / 3.0, 4.0 / 3.0, 7.0 / 3.0, 13.0 / 3.0];
    let s = linspace(1.0 / 3.0, 4.0 + 1.0 / 3.0, 4);
    let m = linspace(-0.5, 4.5, 5);
    // Not yet handled: a zero-area face has no normal; both modes stop with a typed error
    // naming the condition (documented in docs/stability.md).
    let mut zero = built(
        "zero_area_faces",
        "a column of zero-area slave faces (two coincident node pairs each), gap 0.05",
        Scene::new()
            .sheet(&slave(0.05, &zx, &s), true)
            .sheet(&master(&m, &m), false),
        Oracle::Error,
        Some(0.05),
    );
    zero.transforms = false;
    cases.push(zero);
    let left = linspace(1.0 / 3.0, 2.0 + 1.0 / 3.0, 2);
    let right = linspace(2.0 + 1.0 / 3.0, 4.0 + 1.0 / 3.0, 2);
    cases.push(built(
        "duplicate_nodes",
        "a slave of two sheets whose seam nodes are duplicated (same coordinates, other ids)",
        Scene::new()
            .sheet(&slave(0.05, &left, &s), true)
            .sheet(&slave(0.05, &right, &s), true)
            .sheet(&master(&m, &m), false),
        Oracle::Overlap,
        Some(0.05),
    ));
    for (name, what, edit) in [
        (
            "nan_coordinates",
            "a NaN coordinate on a node (in memory; the .mdpa reader refuses it)",
            spoil_nan as Edit,
        ),
        (
            "inf_coordinates",
            "an infinite coordinate on a node (in memory)",
            spoil_inf as Edit,
        ),
    ] {
        let mut c = built(name, what, plates(0.05), Oracle::Error, None);
        c.edit = Some(edit);
        c.transforms = false;
        cases.push(c);
    }
    let mut stiff = built(
        "stiff_penalty",
        "Simple activation, INITIAL_PENALTY 1e12: the guess ε·A·g on plates penetrating by 0.01",
        plates(-0.01),
        Oracle::Overlap,
        Some(-0.01),
    );
    stiff.setup = setup(
        json!({"simple_search": true}),
        json!({"process_info": {"INITIAL_PENALTY": 1e12, "SCALE_FACTOR": 1.0}}),
    );
    stiff.checks = MAPPING;
    cases.push(stiff);
    let mut regression = built(
        "regression_no_active_node",
        "Advanced activation with predict_correct_lagrange_multiplier (C++ parameters): the regression over the nodes active before the step (none)",
        plates(-0.01),
        Oracle::Overlap,
        Some(-0.01),
    );
    regression.setup = json!({
        "contact_model_part": {"0": ["Slave", "Master"]},
        "assume_master_slave": {"0": ["Slave"]},
        "cpp_search_parameters": {
            "type_search": "InRadiusWithOBB",
            "check_gap": "MappingCheck",
            "simple_search": false,
            "predict_correct_lagrange_multiplier": true,
        },
    });
    regression.checks = MAPPING;
    cases.push(regression);
    cases
}
