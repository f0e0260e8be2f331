//! Running one case of the stability suite: the mesh (after a transform) and the setup in one
//! compatibility mode and one `check_gap`, with panics caught and NaN counted.

use std::collections::{BTreeMap, BTreeSet};
use std::panic::{AssertUnwindSafe, catch_unwind};

use csm::geometry::{
    Geometry, GeometryKind, MortarFace, MortarMode, SegmentationSettings, exact_segmentation,
};
use csm::model::{ModelPart, ScalarVar};
use csm::prelude::{Point, Real, Vector};
use csm::search::ContactSearch;
use serde_json::Value;

use super::scene::map_mdpa;

/// A pair (slave condition id, master condition id).
pub type Pair = (u32, u32);

/// A rigid motion or a uniform scaling of the mesh (and of the setup's lengths).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Transform {
    /// The mesh as built.
    Identity,
    /// `x ↦ s·x`; NODAL_H given in the setup (`nodal_h`, `process_info.DISTANCE_THRESHOLD`)
    /// is scaled too.
    Scale(Real),
    /// `x ↦ x + t`.
    Translate(Vector),
    /// `x ↦ R(axis, angle)·x` about the origin.
    Rotate(Vector, Real),
    /// `x ↦ s·R(axis, angle)·x + t`: a similarity (the property tests).
    Similarity {
        scale: Real,
        axis: Vector,
        angle: Real,
        offset: Vector,
    },
}

impl Transform {
    /// The transformed point.
    pub fn apply(&self, p: Point) -> Point {
        match *self {
            Transform::Identity => p,
            Transform::Scale(s) => p * s,
            Transform::Translate(t) => p + t,
            Transform::Rotate(axis, angle) => {
                let r = nalgebra_rotation(axis, angle);
                Point::from(r * p.coords)
            }
            Transform::Similarity {
                scale,
                axis,
                angle,
                offset,
            } => Point::from(nalgebra_rotation(axis, angle) * p.coords * scale + offset),
        }
    }

    /// The factor applied to lengths.
    pub fn length_factor(&self) -> Real {
        match *self {
            Transform::Scale(s) | Transform::Similarity { scale: s, .. } => s,
            _ => 1.0,
        }
    }

    /// The length of the translation part, `|t|`.
    pub fn offset(&self) -> Real {
        match *self {
            Transform::Translate(t) | Transform::Similarity { offset: t, .. } => t.norm(),
            _ => 0.0,
        }
    }

    /// A short label for the report.
    pub fn label(&self) -> String {
        match *self {
            Transform::Identity => "identity".into(),
            Transform::Scale(s) => format!("scale {s:e}"),
            Transform::Translate(t) => format!("translate ({:e}, {:e}, {:e})", t.x, t.y, t.z),
            Transform::Rotate(a, angle) => {
                format!("rotate {angle} rad about ({}, {}, {})", a.x, a.y, a.z)
            }
            Transform::Similarity {
                scale,
                axis: a,
                angle,
                offset: t,
            } => format!(
                "scale {scale:e}, rotate {angle} rad about ({}, {}, {}), translate ({:e}, {:e}, {:e})",
                a.x, a.y, a.z, t.x, t.y, t.z
            ),
        }
    }
}

/// Rodrigues' rotation matrix about the unit vector along `axis`.
fn nalgebra_rotation(axis: Vector, angle: Real) -> csm::geometry::math::Matrix3 {
    let k = axis.normalize();
    let kx = csm::geometry::math::Matrix3::new(0.0, -k.z, k.y, k.z, 0.0, -k.x, -k.y, k.x, 0.0);
    csm::geometry::math::Matrix3::identity() + kx * angle.sin() + kx * kx * (1.0 - angle.cos())
}

/// The number of transforms of the report.
pub const REPORT_TRANSFORMS: usize = 8;

/// The report's column headings of [`report_transforms`], in order.
pub const REPORT_HEADINGS: [&str; REPORT_TRANSFORMS] = [
    "scale 1e-9",
    "scale 1e-6",
    "scale 1e6",
    "along n 1e3",
    "along n 1e8",
    "in plane 1e8",
    "translate 1e6",
    "rotate",
];

/// The transforms of the report for a scene of dimension `dim` (2D: in the plane z = 0, the
/// contact normal along y; 3D: along z): scalings, translations along the contact normal and
/// in its plane (1e3 … 1e8), a general translation and a rotation.
pub fn report_transforms(dim: u8) -> [Transform; REPORT_TRANSFORMS] {
    let along = |d: Real| {
        if dim == 2 {
            Vector::new(0.0, d, 0.0)
        } else {
            Vector::new(0.0, 0.0, d)
        }
    };
    let (general, axis) = if dim == 2 {
        (Vector::new(1e6, -7e5, 0.0), Vector::z())
    } else {
        (Vector::new(1e6, -7e5, 3e5), Vector::new(1.0, 2.0, 3.0))
    };
    [
        Transform::Scale(1e-9),
        Transform::Scale(1e-6),
        Transform::Scale(1e6),
        Transform::Translate(along(1e3)),
        Transform::Translate(along(1e8)),
        Transform::Translate(Vector::new(1e8, 0.0, 0.0)),
        Transform::Translate(general),
        Transform::Rotate(axis, 0.7),
    ]
}

/// The size of a scene: `h`, the mean face size (square root of the mean area, or the mean
/// length of lines), and its extent, the largest `|x|` of a node.
pub fn scene_size(model: &ModelPart) -> (Real, Real) {
    let conds = model.conditions();
    let xyz = model.nodes().coordinates();
    let (mut sum, mut count, mut lines) = (0.0, 0usize, false);
    for i in 0..conds.len() {
        let pts: Vec<Point> = conds.nodes(i).iter().map(|n| xyz[n.index()]).collect();
        let Ok(g) = Geometry::new(conds.kind(i), &pts) else {
            continue;
        };
        let size = match g.kind() {
            GeometryKind::Line2D2 | GeometryKind::Line2D3 => {
                lines = true;
                g.length().ok()
            }
            _ => g.area_robust().ok(),
        };
        if let Some(v) = size.filter(|v| v.is_finite()) {
            sum += v;
            count += 1;
        }
    }
    let mean = sum / count.max(1) as Real;
    let h = if lines { mean } else { mean.sqrt() };
    let extent = xyz
        .iter()
        .map(|p| p.coords.norm())
        .filter(|v| v.is_finite())
        .fold(0.0, Real::max);
    (h, extent)
}

/// How a transformed run differs from the untransformed one in what users read.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Drift {
    /// Pairs missed and extra (overlaps below 1e-9 of the slave's area left out).
    pub missed: usize,
    pub extra: usize,
    /// Pairs that differ only by tiny overlaps.
    pub tiny: usize,
    /// Slave nodes whose ACTIVE flag differs.
    pub flips: usize,
    /// Nodes mapped in one run and not in the other.
    pub mapped: usize,
    /// Nodes whose mapped gap (`gap_t / s`) is off by more than the tolerance
    /// `1e-6·h + 64ε·(|t|/s + extent)`.
    pub gaps: usize,
    /// The largest `|gap_t / s − gap_0| / h`.
    pub worst_gap: Real,
}

impl Drift {
    /// Whether the runs agree.
    pub fn is_invariant(&self) -> bool {
        self.missed + self.extra + self.flips + self.mapped + self.gaps == 0
    }

    /// The report's cell: `=`, `= (k tiny)`, or what differs.
    pub fn cell(&self) -> String {
        if self.is_invariant() {
            return match self.tiny {
                0 => "=".into(),
                k => format!("= ({k} tiny)"),
            };
        }
        let mut parts = Vec::new();
        if self.missed + self.extra > 0 {
            parts.push(format!("−{} +{}", self.missed, self.extra));
        }
        if self.flips > 0 {
            parts.push(format!("{} flips", self.flips));
        }
        if self.mapped > 0 {
            parts.push(format!("{} (un)mapped", self.mapped));
        }
        if self.gaps > 0 {
            parts.push(format!("gap {:.0e} h", self.worst_gap));
        }
        parts.join("; ")
    }
}

/// How `moved` (the run under `t`) differs from `base` (untransformed; `model0` its mesh,
/// `(h, extent)` its [`scene_size`]).
pub fn drift(
    model0: Option<&ModelPart>,
    (h, extent): (Real, Real),
    base: &Run,
    moved: &Run,
    t: Transform,
) -> Drift {
    let (missed, extra) = match model0 {
        Some(m) => differences(m, &base.pairs, &moved.pairs),
        None => (
            base.pairs.difference(&moved.pairs).copied().collect(),
            moved.pairs.difference(&base.pairs).copied().collect(),
        ),
    };
    let tiny = base.pairs.symmetric_difference(&moved.pairs).count() - missed.len() - extra.len();
    let flips = base
        .node_active
        .iter()
        .filter(|(id, a)| moved.node_active.get(id) != Some(a))
        .count();
    let s = t.length_factor();
    let tolerance = 1e-6 * h + 64.0 * Real::EPSILON * (t.offset() / s + extent);
    let mut d = Drift {
        missed: missed.len(),
        extra: extra.len(),
        tiny,
        flips,
        ..Drift::default()
    };
    let ids: BTreeSet<u32> = base
        .node_gaps
        .keys()
        .chain(moved.node_gaps.keys())
        .copied()
        .collect();
    for id in ids {
        match (base.node_gaps.get(&id), moved.node_gaps.get(&id)) {
            (Some(g0), Some(gt)) => {
                let err = (gt / s - g0).abs();
                if err.is_nan() || err > tolerance {
                    d.gaps += 1;
                    d.worst_gap = d.worst_gap.max(err / h);
                }
            }
            _ => d.mapped += 1,
        }
    }
    d
}

/// What one search gave.
#[derive(Debug, Clone, PartialEq)]
pub struct Run {
    /// The final pairs of pair key "0".
    pub pairs: BTreeSet<Pair>,
    /// Non-finite NORMAL_GAP, WEIGHTED_GAP or Lagrange multipliers on any node.
    pub non_finite: usize,
    /// The range of the mapped NORMAL_GAP over slave nodes (the 1e12 sentinel left out).
    pub gap: Option<(Real, Real)>,
    /// The range of `LAGRANGE_MULTIPLIER_CONTACT_PRESSURE` over the nodes where it is not 0.
    pub lm: Option<(Real, Real)>,
    /// Nodes whose multiplier differs from Simple's `ε·A·g` (relative 1e-9), with `ε` given.
    pub lm_mismatch: Option<usize>,
    /// Active slave nodes.
    pub active: usize,
    /// The mapped NORMAL_GAP per node (the 1e12 sentinel left out).
    pub node_gaps: BTreeMap<u32, Real>,
    /// The ACTIVE flag per slave node.
    pub node_active: BTreeMap<u32, bool>,
    /// The search's warnings.
    pub warnings: Vec<String>,
}

/// The mesh of a case: the `.mdpa` text (transformed by [`map_mdpa`]).
pub fn transformed(mdpa: &str, t: Transform) -> String {
    if t == Transform::Identity {
        mdpa.to_owned()
    } else {
        map_mdpa(mdpa, |p| t.apply(p))
    }
}

/// The setup with `compatibility`, `check_gap` and the lengths scaled by `t`.
pub fn setup_for(base: &Value, compatibility: &str, check_gap: &str, t: Transform) -> Value {
    let mut s = base.clone();
    s["compatibility"] = compatibility.into();
    if s.get("cpp_search_parameters").is_some() {
        let cpp = match check_gap {
            "direct_check" => "DirectCheck",
            "no_check" => "NoCheck",
            _ => "MappingCheck",
        };
        s["cpp_search_parameters"]["check_gap"] = cpp.into();
    } else {
        s["search_parameters"]["check_gap"] = check_gap.into();
    }
    let f = t.length_factor();
    if let Some(h) = s.get("nodal_h").and_then(Value::as_f64) {
        s["nodal_h"] = (h * f).into();
    }
    if let Some(d) = s
        .pointer("/process_info/DISTANCE_THRESHOLD")
        .and_then(Value::as_f64)
    {
        s["process_info"]["DISTANCE_THRESHOLD"] = (d * f).into();
    }
    s
}

/// Reads `mdpa`, optionally spoils it (`edit`), runs initialize + one step with `setup`.
/// `Err`: csm's error message, or `panic: …`.
pub fn run(
    mdpa: &str,
    setup: &Value,
    edit: Option<&dyn Fn(&mut ModelPart)>,
) -> Result<(Run, ModelPart), String> {
    let outcome = catch_unwind(AssertUnwindSafe(|| -> Result<(Run, ModelPart), String> {
        let mut model = csm::io::read_mdpa(mdpa, "scene.mdpa").map_err(|e| e.to_string())?;
        if let Some(edit) = edit {
            edit(&mut model);
        }
        let setup = csm::cli::load_setup(&setup.to_string(), "SETUP.json")?;
        let mut search =
            ContactSearch::initialize(&mut model, &setup).map_err(|e| e.to_string())?;
        let result = search.step(&mut model).map_err(|e| e.to_string())?;
        let pairs = result
            .pairs
            .get("0")
            .into_iter()
            .flatten()
            .flat_map(|(s, ms)| ms.iter().map(move |m| (*s, *m)))
            .collect();
        let data = model.nodal_data();
        let mut non_finite = 0;
        for var in [
            ScalarVar::NormalGap,
            ScalarVar::WeightedGap,
            ScalarVar::LagrangeMultiplierContactPressure,
        ] {
            if let Some(c) = data.scalar(var, 0) {
                non_finite += c.iter().filter(|x| !x.is_finite()).count();
            }
        }
        let gaps: Vec<Real> = result
            .nodes
            .values()
            .filter_map(|n| n.normal_gap)
            .filter(|g| g.abs() < 1e11)
            .collect();
        let range = |v: &[Real]| {
            (!v.is_empty()).then(|| {
                v.iter()
                    .fold((Real::INFINITY, Real::NEG_INFINITY), |(a, b), &x| {
                        (a.min(x), b.max(x))
                    })
            })
        };
        let lm_col = data.scalar(ScalarVar::LagrangeMultiplierContactPressure, 0);
        let lms: Vec<Real> = lm_col
            .map(|c| c.iter().copied().filter(|&x| x != 0.0).collect())
            .unwrap_or_default();
        let eps = match (
            model.process_info().number("INITIAL_PENALTY"),
            model.process_info().number("SCALE_FACTOR"),
        ) {
            (Some(p), Some(s)) => Some(p / s),
            _ => None,
        };
        let lm_mismatch = match (eps, lm_col, data.scalar(ScalarVar::NormalGap, 0)) {
            (Some(eps), Some(lm), Some(g)) => {
                let area = data.scalar(ScalarVar::NodalArea, 0);
                Some(
                    (0..lm.len())
                        .filter(|&i| lm[i] != 0.0)
                        .filter(|&i| {
                            let want = eps * area.map_or(1.0, |a| a[i]) * g[i];
                            (lm[i] - want).abs() > 1e-9 * want.abs() || lm[i].is_nan()
                        })
                        .count(),
                )
            }
            _ => None,
        };
        let active = result.nodes.values().filter(|n| n.active).count();
        let node_gaps = result
            .nodes
            .iter()
            .filter_map(|(id, n)| n.normal_gap.filter(|g| g.abs() < 1e11).map(|g| (*id, g)))
            .collect();
        let node_active = result.nodes.iter().map(|(id, n)| (*id, n.active)).collect();
        let run = Run {
            node_active,
            pairs,
            non_finite,
            gap: range(&gaps),
            lm: range(&lms),
            lm_mismatch,
            active,
            node_gaps,
            warnings: result.warnings.clone(),
        };
        Ok((run, model))
    }));
    match outcome {
        Ok(r) => r,
        Err(p) => {
            let msg = p
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| p.downcast_ref::<&str>().map(|s| (*s).to_owned()))
                .unwrap_or_default();
            Err(format!("panic: {msg}"))
        }
    }
}

/// The projected overlap area (length in 2D) of master `m` on slave `s` in `model`, by the
/// robust exact mortar segmentation (no distance threshold), and the slave's area; `None`
/// when the pair cannot be segmented (a degenerate slave).
pub fn overlap(model: &ModelPart, s: u32, m: u32) -> Option<(Real, Real)> {
    let conds = model.conditions();
    let idx = |id: u32| conds.ids().iter().position(|&c| c == id);
    let (si, mi) = (idx(s)?, idx(m)?);
    let xyz = model.nodes().coordinates();
    let pts = |i: usize| -> Vec<Point> { conds.nodes(i).iter().map(|n| xyz[n.index()]).collect() };
    let (sp, mp) = (pts(si), pts(mi));
    let sg = Geometry::new(conds.kind(si), &sp).ok()?;
    let mg = Geometry::new(conds.kind(mi), &mp).ok()?;
    let centre = |k: GeometryKind| match k {
        GeometryKind::Triangle3D3 => Point::new(1.0 / 3.0, 1.0 / 3.0, 0.0),
        _ => Point::origin(),
    };
    let sn = sg.unit_normal(&centre(sg.kind())).ok()?;
    let mn = mg.unit_normal(&centre(mg.kind())).ok()?;
    let area = match sg.kind() {
        GeometryKind::Line2D2 => (sp[1] - sp[0]).norm(),
        _ => sg.area_robust().ok()?,
    };
    let sf = MortarFace::new(sg, sn).ok()?;
    let mf = MortarFace::new(mg, mn).ok()?;
    let settings = SegmentationSettings {
        mode: MortarMode::Robust,
        distance_threshold: 1e300,
    };
    let seg = exact_segmentation(&sf, &mf, &settings).ok()?;
    Some((seg.map_or(0.0, |s| s.overlap_area()), area))
}

/// Pairs of `a` and `b` that differ, leaving out those whose overlap area (on `model`) is
/// below `1e-9` of the slave's area: (in `a` only, in `b` only).
pub fn differences(
    model: &ModelPart,
    a: &BTreeSet<Pair>,
    b: &BTreeSet<Pair>,
) -> (Vec<Pair>, Vec<Pair>) {
    let keep = |p: &&Pair| match overlap(model, p.0, p.1) {
        Some((o, area)) => o >= 1e-9 * area,
        None => true,
    };
    (
        a.difference(b).filter(keep).copied().collect(),
        b.difference(a).filter(keep).copied().collect(),
    )
}

/// Every (slave, master) whose projected overlap is at least `1e-9` of the slave's area,
/// and master faces facing the slave (normals within 90°): the pairs of a flat, close contact.
pub fn overlapping_pairs(model: &ModelPart) -> BTreeSet<Pair> {
    let part_conditions = |name: &str| -> Vec<u32> {
        model
            .find_part(name)
            .map(|p| {
                model
                    .part(p)
                    .conditions()
                    .iter()
                    .map(|c| model.conditions().ids()[c.index()])
                    .collect()
            })
            .unwrap_or_default()
    };
    let (slaves, masters) = (part_conditions("Slave"), part_conditions("Master"));
    let mut out = BTreeSet::new();
    for &s in &slaves {
        for &m in &masters {
            if let Some((o, area)) = overlap(model, s, m)
                && o >= 1e-9 * area
                && o > 0.0
            {
                out.insert((s, m));
            }
        }
    }
    out
}
