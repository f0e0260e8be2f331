//! Stage 2: the normal check on solid elements (Kratos `NormalCheckProcess::Execute`,
//! reference §14), on the whole model:
//!
//! 1. unit normals of every condition and node ([`csm_model::compute_unit_normals`], Kratos'
//!    serial normalisation);
//! 2. the entities with MARKER defined are remembered; MARKER is reset (undefined) everywhere;
//! 3. pass 1, per element in container order (non-solid elements are skipped and reported):
//!    for **every** boundary face (Kratos' INTERFACE filter is ineffective, Q28),
//!    `p = face.Center() + length_proportion · face.Length() · face.UnitNormal(ξ(centre))`; if
//!    `element.IsInside(p, check_threshold)` the element and the face's nodes get MARKER;
//! 4. every condition gets MARKER = all its nodes MARKER; marked elements and conditions are
//!    inverted; normals recomputed (only when a condition was inverted: they depend on the
//!    conditions alone); MARKER reset on nodes, elements and conditions;
//! 5. pass 2, per solid element: every INTERFACE node gets MARKER when
//!    `X + length_proportion · element.Length() · NORMAL(node)` is inside the element; conditions
//!    with all nodes MARKER are inverted; MARKER reset on nodes and conditions; normals
//!    recomputed (again only after an inversion);
//! 6. the remembered entities get MARKER := **false**, whatever they had (Q28).
//!
//! The inside tests of linear solids first try [`Geometry::separated_along`] (the probe beyond
//! every node along the face normal or the nodal normal): a properly oriented element is
//! answered without the local-coordinates iteration, with the same answer; the iteration's
//! first-step error (a singular Jacobian) is still raised. Before that, a face probe of a
//! well-shaped triangle or quadrilateral face is decided from bounds on the face's normal and
//! length alone ([`Geometry::centre_probe_bound`], [`Geometry::separated_beyond`]): where the
//! bounded probe is separated, the exact probe is too, so neither the face's local
//! coordinates nor its Gauss-point area are computed.
//!
//! Kratos inverts by reversing the node list (`std::reverse`). That flips lines, triangles and
//! quadrilaterals, but it is an orientation-preserving renumbering of tetrahedra (Q41),
//! hexahedra and prisms (a 180° turn), so Kratos leaves inverted 3D solids inverted; it also
//! scrambles the corner/mid-node order of quadratic geometries.
//!
//! # Robust mode ([`Compatibility::Robust`])
//! * Inversion uses an orientation-reversing renumbering that keeps each kind's numbering
//!   valid ([`inversion_permutation`]): e.g. Tetrahedra3D4 `(0,2,1,3)`, Hexahedra3D8 bottom ↔
//!   top, Line2D3 `(1,0,2)`.
//! * MARKER is restored to the remembered values instead of false.

use csm_geometry::math::{Point, Vector};
use csm_geometry::{Geometry, GeometryKind};
use csm_model::{
    ConditionId, ElementId, EntityKind, FaceNormals, Flag, KeptFaceNormals, ModelPart, NodeIdx,
    NormalsMode, VectorVar, compute_unit_normals,
};
use rayon::prelude::*;

use crate::error::{Error, ErrorKind};
use crate::setup::Compatibility;

/// Settings of [`normal_check`] (Kratos' `{"length_proportion": 0.1, "check_threshold": 5e-7}`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NormalCheckSettings {
    /// Offset of the probe point, as a fraction of the face or element length.
    pub length_proportion: f64,
    /// Tolerance of the inside test in local coordinates.
    pub check_threshold: f64,
    /// Kratos' behaviour or the documented fixes (module docs).
    pub compatibility: Compatibility,
}

impl Default for NormalCheckSettings {
    fn default() -> NormalCheckSettings {
        NormalCheckSettings {
            length_proportion: 0.1,
            check_threshold: 5e-7,
            compatibility: Compatibility::Kratos,
        }
    }
}

/// What [`normal_check`] did.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct NormalCheckReport {
    /// Non-solid (beam, shell, membrane) elements, assumed properly oriented.
    pub slender_elements: Vec<ElementId>,
    /// Elements inverted in pass 1 (a face normal pointed inside), in container order.
    pub inverted_elements: Vec<ElementId>,
    /// Conditions inverted in pass 1 (all their nodes on such a face).
    pub inverted_conditions: Vec<ConditionId>,
    /// Nodes whose normal pointed inside an element in pass 2, ascending id.
    pub inward_nodes: Vec<u32>,
    /// Conditions inverted in pass 2 (all their nodes had an inward normal).
    pub inverted_conditions_by_nodes: Vec<ConditionId>,
    /// Kratos mode: hexahedra and prisms with an INTERFACE node whose node probe
    /// (`length_proportion · √|det J(0)|`, a length to the power 1.5) is outside
    /// [`PROBE_RANGE`] times the element's size: too short, it drowns in the inside test's
    /// tolerance (at scale 5e-9 every node reads as inward); too long, it can pass through the
    /// element.
    pub misscaled_probes: usize,
}

/// The node probe's length, relative to the element's size, within which kratos mode's
/// normal check is trusted (a hexahedron of size 1 has 0.035 with the default proportion;
/// the bounds are reached at sizes of about 1e-5 and 1e3).
pub const PROBE_RANGE: (f64, f64) = (1e-4, 1.0);

impl NormalCheckReport {
    /// The warnings a user should read (kratos mode's misscaled probes).
    pub fn warnings(&self) -> Vec<String> {
        if self.misscaled_probes == 0 {
            return Vec::new();
        }
        vec![format!(
            "normal check: the node probes of {} hexahedra/prisms are scaled by Kratos' \
             Length() = sqrt|det J|, a length to the power 1.5: at this mesh scale they are \
             shorter than {:e} or longer than {} times the element, so the orientation test \
             is unreliable (every node reads as inward on meshes scaled to about 1e-8); \
             \"compatibility\": \"robust\" scales the probes with the element",
            self.misscaled_probes, PROBE_RANGE.0, PROBE_RANGE.1
        )]
    }
}

/// Stage 2: checks and fixes the orientation of elements and conditions (Kratos
/// `NormalCheckProcess`; module docs).
///
/// Errors: a degenerate face, element or condition (zero length/area/volume), or nodal
/// normals that cancel out (Kratos fails there too, e.g. with "Zero norm normal in INTERFACE
/// flagged node").
pub fn normal_check(
    model: &mut ModelPart,
    settings: &NormalCheckSettings,
) -> Result<NormalCheckReport, Error> {
    normal_check_with_normals(model, settings).map(|(report, _)| report)
}

/// Elements per parallel task of the element passes at most: the cost of an element varies
/// (most are tested once, some probed many times), and rayon splits a task only where it is
/// stolen, so a large task left at the end of a pass would run on one thread alone.
const ELEMENTS_PER_TASK: usize = 1024;

/// One element's face test: `None` for a slender element, else the local indices of the nodes
/// of its inward faces (empty: none).
type FaceTest = Result<Option<Vec<usize>>, Error>;

/// [`normal_check`], also returning the faces' unit normals it computed last (on the final
/// coordinates and node orders: [`csm_model::compute_unit_normals_from_kept`] takes them from
/// there while the geometry does not change).
pub fn normal_check_with_normals(
    model: &mut ModelPart,
    settings: &NormalCheckSettings,
) -> Result<(NormalCheckReport, KeptFaceNormals), Error> {
    let kratos = settings.compatibility == Compatibility::Kratos;
    let lp = settings.length_proportion;
    let tol = settings.check_threshold;
    let mut report = NormalCheckReport::default();
    let mut faces = compute_normals(model)?;

    // Backup of MARKER, then reset.
    let backup = MarkerBackup::take(model);
    reset_marker(model, true, true, true);

    // Pass 1: element faces. The geometric tests run in parallel; the flags are set after,
    // in id order (the tests read no flag).
    // Only the elements with something to record are kept (in id order): most have no
    // inward face, and a list of every element's outcome was a serial pass after.
    let order = model.elements().id_order();
    let tests: Vec<(usize, FaceTest)> = {
        let m = &*model;
        order
            .par_iter()
            .with_max_len(ELEMENTS_PER_TASK)
            .map_init(
                || (Vec::<Point>::new(), Vec::<Point>::new()),
                |(points, face_points), e| (e, inward_faces(m, e, lp, tol, points, face_points)),
            )
            .filter(|(_, test)| !matches!(test, Ok(Some(nodes)) if nodes.is_empty()))
            .collect()
    };
    for (e, test) in tests {
        match test? {
            None => report
                .slender_elements
                .push(ElementId(model.elements().ids()[e])),
            Some(nodes) if nodes.is_empty() => {}
            Some(nodes) => {
                for l in nodes {
                    let n = model.elements().nodes(e)[l];
                    model.nodes_mut().flags_mut()[n.index()].set(Flag::MARKER, true);
                }
                model.elements_mut().flags_mut()[e].set(Flag::MARKER, true);
                report
                    .inverted_elements
                    .push(ElementId(model.elements().ids()[e]));
            }
        }
    }
    report.inverted_conditions = mark_conditions(model);
    // The marked elements (most meshes have none), found in parallel, inverted in id order.
    let mut marked = with_marker(model.elements().flags());
    let ids = model.elements().ids();
    marked.sort_unstable_by_key(|&e| ids[e]);
    for e in marked {
        invert(model, EntityKind::Element, e, kratos);
    }
    invert_marked_conditions(model, kratos);
    // The unit normals depend on the conditions only (coordinates and node order): without an
    // inverted condition they are the ones just computed.
    if !report.inverted_conditions.is_empty() {
        faces = compute_normals(model)?;
    }
    reset_marker(model, true, true, true);

    // Pass 2: nodal normals.
    let normals: Vec<Vector> = model
        .nodal_data()
        .vector(VectorVar::Normal, 0)
        .map(|column| column.par_iter().copied().collect())
        .unwrap_or_default();
    let mut inward = vec![false; model.nodes().len()];
    let order = model.elements().id_order();
    let tests: Vec<Result<(Vec<NodeIdx>, bool), Error>> = {
        let m = &*model;
        order
            .par_iter()
            .with_max_len(ELEMENTS_PER_TASK)
            .map_init(Vec::<Point>::new, |points, e| {
                inward_nodes(m, e, &normals, (lp, tol, kratos), points)
            })
            .filter(|test| !matches!(test, Ok((nodes, false)) if nodes.is_empty()))
            .collect()
    };
    for test in tests {
        let (nodes, misscaled) = test?;
        report.misscaled_probes += usize::from(misscaled);
        for n in nodes {
            model.nodes_mut().flags_mut()[n.index()].set(Flag::MARKER, true);
            inward[n.index()] = true;
        }
    }
    let node_ids = model.nodes().ids();
    report.inward_nodes = (0..inward.len())
        .into_par_iter()
        .filter(|&i| inward[i])
        .map(|i| node_ids[i])
        .collect();
    report.inward_nodes.sort_unstable();
    report.inverted_conditions_by_nodes = mark_conditions(model);
    invert_marked_conditions(model, kratos);
    reset_marker(model, true, false, true);
    if !report.inverted_conditions_by_nodes.is_empty() {
        faces = compute_normals(model)?;
    }

    backup.restore(model, kratos);
    Ok((report, faces))
}

/// Stage 2 on a model without solid elements: what [`normal_check`] leaves behind there, at
/// a third of the cost. Both passes look only at solid elements, so nothing is inverted and
/// the check reduces to its unit normals (computed once instead of three times; the same
/// errors on a degenerate condition) and to the MARKER bookkeeping (every MARKER that was
/// defined becomes false in `kratos` mode and keeps its value in `robust` mode; every other
/// stays undefined). The report lists the non-solid elements, as [`normal_check`]'s does.
///
/// [`crate::Plan`] chooses this when [`count_solid_elements`] is 0.
pub fn normal_check_normals_only(
    model: &mut ModelPart,
    settings: &NormalCheckSettings,
) -> Result<NormalCheckReport, Error> {
    normal_check_normals_only_with_normals(model, settings).map(|(report, _)| report)
}

/// [`normal_check_normals_only`], also returning the faces' unit normals it computed (as
/// [`normal_check_with_normals`]).
pub fn normal_check_normals_only_with_normals(
    model: &mut ModelPart,
    settings: &NormalCheckSettings,
) -> Result<(NormalCheckReport, KeptFaceNormals), Error> {
    let kratos = settings.compatibility == Compatibility::Kratos;
    let report = NormalCheckReport {
        slender_elements: model
            .elements()
            .id_order()
            .iter()
            .filter(|&e| !model.elements().kind(e).is_solid())
            .map(|e| ElementId(model.elements().ids()[e]))
            .collect(),
        ..NormalCheckReport::default()
    };
    debug_assert!(report.slender_elements.len() == model.elements().len());
    let faces = compute_normals(model)?;
    let backup = MarkerBackup::take(model);
    reset_marker(model, true, true, true);
    backup.restore(model, kratos);
    Ok((report, faces))
}

/// The number of solid elements (local dimension = working dimension) in the model: the
/// elements the normal check's passes look at.
pub fn count_solid_elements(model: &ModelPart) -> usize {
    (0..model.elements().len())
        .filter(|&e| model.elements().kind(e).is_solid())
        .count()
}

/// Pass 1 on element `e`: `None` for a non-solid element; otherwise the local indices of the
/// nodes of every face whose probe point lies inside the element (empty: properly oriented).
fn inward_faces(
    model: &ModelPart,
    e: usize,
    lp: f64,
    tol: f64,
    points: &mut Vec<Point>,
    face_points: &mut Vec<Point>,
) -> Result<Option<Vec<usize>>, Error> {
    let kind = model.elements().kind(e);
    if !kind.is_solid() {
        return Ok(None);
    }
    model.gather_points(model.elements().nodes(e), points);
    let element = Geometry::new(kind, points).map_err(|err| element_error(model, e, err))?;
    let mut inverted = Vec::new();
    let mut checked = false;
    for (face_kind, local) in kind.faces() {
        face_points.clear();
        face_points.extend(local.iter().map(|&l| points[l]));
        let face =
            Geometry::new(*face_kind, face_points).map_err(|err| element_error(model, e, err))?;
        if probe_certainly_outside(&element, &face, lp, tol) {
            first_outside(model, e, &element, &mut checked)?;
            continue;
        }
        let (probe, normal) = face_probe(&face, lp).map_err(|err| element_error(model, e, err))?;
        if probe_inside(model, e, &element, (&probe, &normal), tol, &mut checked)? {
            inverted.extend_from_slice(local);
        }
    }
    Ok(Some(inverted))
}

/// Pass 2 on element `e`: the INTERFACE nodes of a solid element whose normal, scaled by
/// `lp` times the element's length, points inside it, and whether that length is misscaled
/// ([`probe_length`]).
fn inward_nodes(
    model: &ModelPart,
    e: usize,
    normals: &[Vector],
    (lp, tol, kratos): (f64, f64, bool),
    points: &mut Vec<Point>,
) -> Result<(Vec<NodeIdx>, bool), Error> {
    let kind = model.elements().kind(e);
    if !kind.is_solid() {
        return Ok((Vec::new(), false));
    }
    let nodes = model.elements().nodes(e);
    let flags = model.nodes().flags();
    // Kratos computes the element's Length() for an INTERFACE node only: an element without
    // one is neither measured nor tested (pass 1 built its geometry already).
    if !nodes.iter().any(|n| flags[n.index()].is(Flag::INTERFACE)) {
        return Ok((Vec::new(), false));
    }
    model.gather_points(nodes, points);
    let element = Geometry::new(kind, points).map_err(|err| element_error(model, e, err))?;
    let (length, misscaled) =
        probe_length(&element, (lp, kratos)).map_err(|err| element_error(model, e, err))?;
    let mut inward = Vec::new();
    let mut checked = false;
    for (n, x) in nodes.iter().zip(points.iter()) {
        if !flags[n.index()].is(Flag::INTERFACE) {
            continue;
        }
        let normal = normals
            .get(n.index())
            .copied()
            .unwrap_or_else(Vector::zeros);
        let probe = x + normal * (lp * length);
        if probe_inside(model, e, &element, (&probe, &normal), tol, &mut checked)? {
            inward.push(*n);
        }
    }
    Ok((inward, misscaled))
}

/// The length the node probes of a solid element are scaled by. Kratos takes `Length()`,
/// which for hexahedra and prisms is `√|det J(0)|`, a length to the power 1.5: under a scaling
/// by `s` the probe moves `s^1.5` instead of `s`, and below `s ≈ 5e-9` every probe lands inside
/// (every condition taken as inverted). Robust mode takes a true length there, `2 ∛|det J(0)|`
/// (the edge of a cube, the size of a parallelepiped); tetrahedra and 2D solids keep Kratos'
/// length, proportional already. The
/// flag: kratos mode's probe `lp · length` of a hexahedron or prism is outside
/// [`PROBE_RANGE`] times the element's size.
fn probe_length(
    element: &Geometry<'_>,
    (lp, kratos): (f64, bool),
) -> Result<(f64, bool), csm_geometry::Error> {
    use csm_geometry::GeometryKind as K;
    match element.kind() {
        K::Hexahedra3D8 | K::Hexahedra3D20 | K::Hexahedra3D27 | K::Prism3D6 if kratos => {
            // `length = √|det J(0)|`; a parallelepiped's volume is `8 |det J(0)|`, so its size
            // is `2 ∛(length²)` and the probe relative to it is `r = lp · length / (2
            // ∛(length²))`, compared through `r³ = lp³ · length / 8` (no volume integral, no
            // cube root in kratos mode).
            let length = element.length()?;
            let cubed = lp * lp * lp * length / 8.0;
            let (lo, hi) = PROBE_RANGE;
            let off = !(lo * lo * lo..=hi * hi * hi).contains(&cubed);
            Ok((length, off))
        }
        // The size of the same parallelepiped, `2 ∛|det J(0)|`: proportional to the element
        // under any scaling, without a volume integral.
        K::Hexahedra3D8 | K::Hexahedra3D20 | K::Hexahedra3D27 | K::Prism3D6 => {
            let length = element.length()?;
            Ok((2.0 * (length * length).cbrt(), false))
        }
        _ => Ok((element.length()?, false)),
    }
}

/// `face.Center() + lp · face.Length() · face.UnitNormal(ξ(centre))`, in Kratos' order, and
/// that unit normal.
fn face_probe(face: &Geometry<'_>, lp: f64) -> Result<(Point, Vector), csm_geometry::Error> {
    let centre = face.center();
    let normal = face.centre_unit_normal()?;
    let length = face.length()?;
    Ok((centre + normal * (lp * length), normal))
}

/// Whether the face probe of `face` ([`face_probe`]) is certainly outside `element`, known
/// from bounds on the face's normal and length alone ([`Geometry::centre_probe_bound`],
/// [`Geometry::separated_beyond`]): where this is true, [`face_probe`] succeeds and
/// [`probe_inside`] answers false (apart from the iteration error `separated_along`'s docs
/// describe, which only a badly distorted element reaches), so neither is computed. The
/// bounds need a positive `lp`.
fn probe_certainly_outside(element: &Geometry<'_>, face: &Geometry<'_>, lp: f64, tol: f64) -> bool {
    if lp.is_nan() || lp <= 0.0 {
        return false;
    }
    face.centre_probe_bound().is_some_and(|b| {
        element.separated_beyond(
            &face.center(),
            &b.direction,
            lp * b.length_floor,
            b.cos_floor,
            tol,
        )
    })
}

/// Whether `probe` is inside element `e` (`element`), the probe lying off a face or node
/// along `direction`. A probe beyond every node along `direction` is outside: the inside
/// test's answer without its iteration (exact, `Geometry::separated_along`); the first such
/// answer of an element (`checked`) still raises the error of the iteration's first step.
fn probe_inside(
    model: &ModelPart,
    e: usize,
    element: &Geometry<'_>,
    (probe, direction): (&Point, &Vector),
    tol: f64,
    checked: &mut bool,
) -> Result<bool, Error> {
    if element.separated_along(probe, direction, tol) {
        first_outside(model, e, element, checked)?;
        return Ok(false);
    }
    Ok(element
        .is_inside(probe, tol)
        .map_err(|err| element_error(model, e, err))?
        .is_some())
}

/// An "outside" answer of element `e` found without the inside test's iteration: the first
/// one (`checked`) raises the error of the iteration's first step, as the iteration would.
fn first_outside(
    model: &ModelPart,
    e: usize,
    element: &Geometry<'_>,
    checked: &mut bool,
) -> Result<(), Error> {
    if !*checked {
        element
            .check_local_coordinates()
            .map_err(|err| element_error(model, e, err))?;
        *checked = true;
    }
    Ok(())
}

/// The renumbering that inverts a geometry of `kind` in robust mode: new node `i` is old node
/// `perm[i]`. Orientation-reversing and valid for the kind's numbering (corners first, then
/// mid-edge nodes in Kratos' edge order).
pub fn inversion_permutation(kind: GeometryKind) -> &'static [usize] {
    use GeometryKind as K;
    match kind {
        K::Line2D2 => &[1, 0],
        K::Line2D3 => &[1, 0, 2],
        K::Triangle3D3 | K::Triangle2D3 => &[2, 1, 0],
        K::Triangle3D6 | K::Triangle2D6 => &[2, 1, 0, 4, 3, 5],
        K::Quadrilateral3D4 | K::Quadrilateral2D4 => &[3, 2, 1, 0],
        K::Quadrilateral3D8 | K::Quadrilateral2D8 => &[3, 2, 1, 0, 6, 5, 4, 7],
        K::Quadrilateral3D9 | K::Quadrilateral2D9 => &[3, 2, 1, 0, 6, 5, 4, 7, 8],
        K::Tetrahedra3D4 => &[0, 2, 1, 3],
        K::Tetrahedra3D10 => &[0, 2, 1, 3, 6, 5, 4, 7, 9, 8],
        K::Prism3D6 => &[3, 4, 5, 0, 1, 2],
        K::Hexahedra3D8 => &[4, 5, 6, 7, 0, 1, 2, 3],
        K::Hexahedra3D20 => &[
            4, 5, 6, 7, 0, 1, 2, 3, 16, 17, 18, 19, 12, 13, 14, 15, 8, 9, 10, 11,
        ],
        K::Hexahedra3D27 => &[
            4, 5, 6, 7, 0, 1, 2, 3, 16, 17, 18, 19, 12, 13, 14, 15, 8, 9, 10, 11, 25, 21, 22, 23,
            24, 20, 26,
        ],
    }
}

fn invert(model: &mut ModelPart, entity: EntityKind, i: usize, kratos: bool) {
    let kind = match entity {
        EntityKind::Element => model.elements().kind(i),
        _ => model.conditions().kind(i),
    };
    let entities = match entity {
        EntityKind::Element => model.elements_mut(),
        _ => model.conditions_mut(),
    };
    // `inversion_permutation` is a permutation of the kind's nodes (unit-tested), so
    // `permute_nodes` applies it.
    if kratos || !entities.permute_nodes(i, inversion_permutation(kind)) {
        entities.reverse_nodes(i);
    }
}

/// Every condition: MARKER := all its nodes MARKER. Returns the marked ones' ids (by dense
/// index). The tests run in parallel (they read node flags only).
fn mark_conditions(model: &mut ModelPart) -> Vec<ConditionId> {
    let all: Vec<bool> = {
        let (conditions, node_flags) = (model.conditions(), model.nodes().flags());
        (0..conditions.len())
            .into_par_iter()
            .map(|c| {
                conditions
                    .nodes(c)
                    .iter()
                    .all(|n| node_flags[n.index()].is(Flag::MARKER))
            })
            .collect()
    };
    model
        .conditions_mut()
        .flags_mut()
        .par_iter_mut()
        .zip(&all)
        .for_each(|(f, &a)| f.set(Flag::MARKER, a));
    let ids = model.conditions().ids();
    (0..all.len())
        .into_par_iter()
        .filter(|&c| all[c])
        .map(|c| ConditionId(ids[c]))
        .collect()
}

/// The indices whose flags hold MARKER, ascending, found in parallel.
fn with_marker(flags: &[csm_model::Flags]) -> Vec<usize> {
    (0..flags.len())
        .into_par_iter()
        .filter(|&i| flags[i].is(Flag::MARKER))
        .collect()
}

/// Inverts the MARKER conditions (most meshes have none: found in parallel), in index order.
fn invert_marked_conditions(model: &mut ModelPart, kratos: bool) {
    for c in with_marker(model.conditions().flags()) {
        invert(model, EntityKind::Condition, c, kratos);
    }
}

/// Kratos `VariableUtils().ResetFlag(MARKER, …)`: MARKER becomes undefined (in parallel).
fn reset_marker(model: &mut ModelPart, nodes: bool, elements: bool, conditions: bool) {
    let reset = |flags: &mut [csm_model::Flags]| {
        flags.par_iter_mut().for_each(|f| f.reset(Flag::MARKER));
    };
    if nodes {
        reset(model.nodes_mut().flags_mut());
    }
    if elements {
        reset(model.elements_mut().flags_mut());
    }
    if conditions {
        reset(model.conditions_mut().flags_mut());
    }
}

/// The MARKER values defined before the check, by dense index.
struct MarkerBackup {
    nodes: Vec<(usize, bool)>,
    elements: Vec<(usize, bool)>,
    conditions: Vec<(usize, bool)>,
}

impl MarkerBackup {
    /// The defined MARKERs (most entities have none), found in parallel, in index order.
    fn take(model: &ModelPart) -> MarkerBackup {
        let defined = |flags: &[csm_model::Flags]| -> Vec<(usize, bool)> {
            flags
                .par_iter()
                .enumerate()
                .filter_map(|(i, f)| f.get(Flag::MARKER).map(|v| (i, v)))
                .collect()
        };
        let (nodes, (elements, conditions)) = rayon::join(
            || defined(model.nodes().flags()),
            || {
                rayon::join(
                    || defined(model.elements().flags()),
                    || defined(model.conditions().flags()),
                )
            },
        );
        MarkerBackup {
            nodes,
            elements,
            conditions,
        }
    }

    /// Kratos sets MARKER false on every remembered entity (Q28); robust mode restores the
    /// remembered value.
    fn restore(&self, model: &mut ModelPart, kratos: bool) {
        let value = |v: bool| v && !kratos;
        for &(i, v) in &self.nodes {
            model.nodes_mut().flags_mut()[i].set(Flag::MARKER, value(v));
        }
        for &(i, v) in &self.elements {
            model.elements_mut().flags_mut()[i].set(Flag::MARKER, value(v));
        }
        for &(i, v) in &self.conditions {
            model.conditions_mut().flags_mut()[i].set(Flag::MARKER, value(v));
        }
    }
}

/// The unit normals of every condition; the faces' own normals kept (without the centre
/// normals, which the condition normals hold).
fn compute_normals(model: &mut ModelPart) -> Result<KeptFaceNormals, Error> {
    compute_unit_normals(model, None, NormalsMode::Kratos)
        .map(FaceNormals::keep)
        .map_err(|e| match e.kind() {
            csm_model::ErrorKind::Geometry {
                entity: EntityKind::Condition,
                id,
                source,
            } => ErrorKind::Geometry {
                condition: *id,
                message: source.to_string(),
            }
            .into(),
            _ => Error::model_data("", e),
        })
}

fn element_error(model: &ModelPart, e: usize, err: csm_geometry::Error) -> Error {
    ErrorKind::Model(format!(
        "normal check: element {}: {err}",
        model.elements().ids()[e]
    ))
    .into()
}

#[cfg(test)]
mod tests;
