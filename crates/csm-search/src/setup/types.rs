//! Typed setup values.

use std::collections::BTreeMap;

use csm_geometry::math::{Point, Real, Vector};
use csm_model::VectorVar;

/// Which behaviour csm reproduces where Kratos is fragile (DESIGN.md §2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Compatibility {
    /// What Kratos 10.4.4 does, quirks included (the default).
    #[default]
    Kratos,
    /// Documented fixes of Kratos' fragilities.
    Robust,
}

impl Compatibility {
    /// The setup's spelling (`"kratos"`, `"robust"`).
    pub fn name(self) -> &'static str {
        match self {
            Compatibility::Kratos => "kratos",
            Compatibility::Robust => "robust",
        }
    }
}

/// The broad/narrow-phase combination (`type_search`, Kratos `SearchTreeType`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SearchTreeType {
    /// kd-tree radius query (`"InRadius"`, `"in_radius"`; also Kratos' fallback for unknown
    /// strings).
    KdtreeInRadius,
    /// kd-tree box query (`"InBox"`, `"in_box"`).
    KdtreeInBox,
    /// kd-tree radius query plus OBB test (`"InRadiusWithOBB"`, `"in_radius_with_obb"`).
    KdtreeInRadiusWithObb,
    /// kd-tree box query plus OBB test (`"InBoxWithOBB"`, `"in_box_with_obb"`).
    KdtreeInBoxWithObb,
    /// Octree with OBB test in the leaves (`"OctreeWithOBB"`, `"octree_with_obb"`).
    OctreeWithObb,
    /// csm's 18-DOP narrow phase after the kd-tree radius query (`"kdop_18"`; `"KDOP"` /
    /// `"kdop"` in `robust` mode). Kratos declares k-DOP but never implemented it.
    Kdop,
}

impl SearchTreeType {
    /// The Python-layer spelling of the value (`"in_radius_with_obb"`, …; `"kdop_18"`).
    pub fn name(self) -> &'static str {
        match self {
            SearchTreeType::KdtreeInRadius => "in_radius",
            SearchTreeType::KdtreeInBox => "in_box",
            SearchTreeType::KdtreeInRadiusWithObb => "in_radius_with_obb",
            SearchTreeType::KdtreeInBoxWithObb => "in_box_with_obb",
            SearchTreeType::OctreeWithObb => "octree_with_obb",
            SearchTreeType::Kdop => "kdop_18",
        }
    }
}

/// How candidate pairs are validated (`check_gap`, Kratos `CheckGap`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CheckGap {
    /// Pairs created without a gap check (`"NoCheck"`, `"no_check"`).
    NoCheck,
    /// Pairs kept when the nodal gap passes a direct projection check (`"DirectCheck"`,
    /// `"direct_check"`).
    DirectCheck,
    /// Pairs kept when the mortar mapping finds an overlap (`"MappingCheck"`,
    /// `"mapping_check"`; Kratos' fallback for any other string, the Python default
    /// `"check_mapping"` included).
    MappingCheck,
}

impl CheckGap {
    /// The Python-layer spelling of the value (`"no_check"`, `"direct_check"`,
    /// `"mapping_check"`).
    pub fn name(self) -> &'static str {
        match self {
            CheckGap::NoCheck => "no_check",
            CheckGap::DirectCheck => "direct_check",
            CheckGap::MappingCheck => "mapping_check",
        }
    }
}

/// The OBB intersection test (`OBB_intersection_type`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ObbIntersectionType {
    /// Separating-axis theorem (`"SeparatingAxisTheorem"`, the default).
    SeparatingAxisTheorem,
    /// Vertex inclusion and edge/face intersection (`"Direct"`).
    Direct,
}

impl ObbIntersectionType {
    /// Kratos' spelling (`"SeparatingAxisTheorem"`, `"Direct"`).
    pub fn name(self) -> &'static str {
        match self {
            ObbIntersectionType::SeparatingAxisTheorem => "SeparatingAxisTheorem",
            ObbIntersectionType::Direct => "Direct",
        }
    }
}

/// The contact formulation (`contact_type`), which selects the nodal variable set.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ContactType {
    /// `"Frictionless"`: LAGRANGE_MULTIPLIER_CONTACT_PRESSURE.
    Frictionless,
    /// `"FrictionlessComponents"`: VECTOR_LAGRANGE_MULTIPLIER.
    FrictionlessComponents,
    /// `"Frictional"` (Kratos appends `WithNormalUpdate`): VECTOR_LAGRANGE_MULTIPLIER.
    Frictional,
    /// `"FrictionalPureSlip"`: VECTOR_LAGRANGE_MULTIPLIER, `pure_slip` true.
    FrictionalPureSlip,
}

impl ContactType {
    /// True for the frictional formulations.
    pub fn is_frictional(self) -> bool {
        matches!(
            self,
            ContactType::Frictional | ContactType::FrictionalPureSlip
        )
    }
}

/// The Kratos contact process whose `Parameters` the setup holds: what it passes to the
/// search and what the search makes of the pairs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ContactProcess {
    /// `ALMContactProcess` (`alm_contact_process`), and `PenaltyContactProcess` and
    /// `ExplicitPenaltyContactProcess`, which derive from it: paired conditions.
    Alm,
    /// `MPCContactProcess` (`mpc_contact_process`): Kratos' `MPCContactSearchProcess`, the
    /// base search class (the base activation whatever `simple_search`, no pair
    /// properties), one `ContactMasterSlaveConstraint` per paired condition.
    Mpc,
    /// `MeshTyingProcess` (`mesh_tying_process`): parts in `mesh_tying_model_part`, paired
    /// `MeshTyingMortar` conditions; unlike the contact processes it keeps the condition ids.
    MeshTying,
}

impl ContactProcess {
    /// The process of a `python_module` name.
    pub fn of_module(module: &str) -> Option<ContactProcess> {
        match module {
            "alm_contact_process"
            | "penalty_contact_process"
            | "explicit_penalty_contact_process" => Some(ContactProcess::Alm),
            "mpc_contact_process" => Some(ContactProcess::Mpc),
            "mesh_tying_process" => Some(ContactProcess::MeshTying),
            _ => None,
        }
    }

    /// True when the process numbers every condition of the model 1..N in id order during
    /// its initialisation (`ALMFastInit`: the ALM, penalty and MPC processes).
    pub fn renumbers_conditions(self) -> bool {
        !matches!(self, ContactProcess::MeshTying)
    }
}

/// `octree_search_parameters`: the OBB and octree configuration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OctreeSearchParameters {
    /// Relative enlargement of the OBB half-lengths (times the maximum NODAL_H).
    pub bounding_box_factor: f64,
    /// Write the OBBs for debugging (accepted, no effect in csm).
    pub debug_obb: bool,
    /// SAT or Direct.
    pub obb_intersection_type: ObbIntersectionType,
    /// OBB from the AABB diagonal (true) or from the surface normal (false).
    pub build_from_bounding_box: bool,
    /// Octree only: extra extension of the lower corner of the octree box.
    pub lower_bounding_box_coefficient: f64,
    /// Octree only: extra extension of the upper corner of the octree box.
    pub higher_bounding_box_coefficient: f64,
}

/// The parameters the C++ search process of one pair works with, after Kratos' Python layer
/// (or given verbatim with `cpp_search_parameters`).
#[derive(Debug, Clone, PartialEq)]
pub struct SearchParameters {
    /// Broad/narrow phase.
    pub type_search: SearchTreeType,
    /// Gap check.
    pub check_gap: CheckGap,
    /// Simple (true) or Advanced (false) activation.
    pub simple_search: bool,
    /// Radius or box factor of the kd-tree query.
    pub search_factor: f64,
    /// Cap of kd-tree results per query (`allocation_size` ← `max_number_results`).
    pub allocation_size: usize,
    /// kd-tree bucket size.
    pub bucket_size: usize,
    /// Search on the velocity-predicted configuration.
    pub dynamic_search: bool,
    /// Advanced activation: compare the weighted gap with the previous step.
    pub static_check_movement: bool,
    /// Advanced activation: gap threshold for nodes whose gap is not closing.
    pub consider_gap_threshold: bool,
    /// Minimum norm of the difference of two centre normals for a pair.
    pub normal_orientation_threshold: f64,
    /// Kratos' debug output (accepted, no effect in csm).
    pub debug_mode: bool,
    /// Build the tree on the slave side and query with masters.
    pub inverted_search: bool,
    /// Linear-regression prediction of the multipliers of newly active nodes.
    pub predict_correct_lagrange_multiplier: bool,
    /// Pure slip (frictional).
    pub pure_slip: bool,
    /// Whether master/slave roles are given (`assume_master_slave` non-empty).
    pub predefined_master_slave: bool,
    /// OBB and octree configuration.
    pub octree: OctreeSearchParameters,
    /// The pair key the process works on (`id_name`; `""` = the whole `Contact` part).
    pub id_name: String,
    /// Paired conditions are created (`condition_name` non-empty; always true on the Python
    /// path, false for C++ parameters without a condition name, Q18).
    pub create_auxiliar_conditions: bool,
}

/// One contact pair of the setup (a key `"0"`…`"9"` of `contact_model_part`).
#[derive(Debug, Clone, PartialEq)]
pub struct PairSetup {
    /// The user parts of the pair (full paths), in list order.
    pub parts: Vec<String>,
    /// The parts assumed slave (`assume_master_slave`); empty when roles are not predefined.
    pub slaves: Vec<String>,
    /// `contact_property_ids` of the pair (0: properties `100 + key` are created).
    pub property_id: u32,
    /// The C++ search parameters of this pair.
    pub search: SearchParameters,
}

/// A parsed setup: Kratos' contact-process parameters plus csm's own keys.
#[derive(Debug, Clone, PartialEq)]
pub struct SearchSetup {
    /// Name of the root model part (`model_part_name`, default `Structure`).
    pub model_part_name: String,
    /// The non-empty pairs, by key.
    pub pairs: BTreeMap<u32, PairSetup>,
    /// The contact formulation.
    pub contact_type: ContactType,
    /// `adapt_search`: scale search_factor and active_check_factor by h_max/h_min.
    pub adapt_search: bool,
    /// `active_check_factor` (ProcessInfo ACTIVE_CHECK_FACTOR).
    pub active_check_factor: f64,
    /// Steps between two searches.
    pub database_step_update: u32,
    /// Offset of the normal check point (`normal_check_proportion`).
    pub normal_check_proportion: f64,
    /// `zero_tolerance_factor` (ProcessInfo ZERO_TOLERANCE_FACTOR).
    pub zero_tolerance_factor: f64,
    /// Mortar integration order.
    pub integration_order: u32,
    /// `consider_tessellation`.
    pub consider_tessellation: bool,
    /// The time interval in which the search runs (`"End"` = 1e30).
    pub interval: (f64, f64),
    /// True when the setup came from an explicit penalty process (default `octree_with_obb`).
    pub explicit: bool,
    /// The contact process the setup is for.
    pub process: ContactProcess,
    /// Every `contact_model_part` list is empty: the contact faces are the skin of the mesh
    /// (pair 0, whose `parts` is empty until the skin part is made; `stages::detect_skin`).
    pub skin: bool,
    /// `"compatibility"`.
    pub compatibility: Compatibility,
    /// `"strict"`: silent fallbacks become errors.
    pub strict: bool,
    /// `"process_info"` overrides, by Kratos variable name.
    pub process_info: BTreeMap<String, f64>,
    /// `"nodal_h"`: a constant NODAL_H instead of FindNodalHProcess.
    pub nodal_h: Option<f64>,
    /// True when `"cpp_search_parameters"` gave the C++ parameters verbatim.
    pub cpp_search_parameters: bool,
    /// `"nodal_values"`: historical vector values set on the nodes of parts before the first
    /// step (e.g. the previous step's ACCELERATION of Kratos' dynamic-search test).
    pub nodal_values: Vec<NodalValueSetup>,
    /// `"steps"`: the steps of a multi-step run, each with its rigid increments; empty for a
    /// single search step without motion.
    pub steps: Vec<StepSetup>,
    /// `"refit_tree"` (default true): in a multi-step run the kd-tree of a pair is refitted
    /// to the moved condition centres instead of rebuilt (same pairs; `docs/steps.md`).
    /// `false` rebuilds it every step, as Kratos does.
    pub refit_tree: bool,
    /// The contact parts hold already the interface conditions stage 1 would generate from
    /// the elements ([`crate::generate_interfaces_first`], which a distributed run calls on the
    /// whole mesh before it splits it): stage 1 is left out. Not a SETUP.json key; false
    /// from [`crate::parse_setup`].
    pub interfaces_generated: bool,
    /// Silent fallbacks and dropped keys, in the order met.
    pub warnings: Vec<String>,
    /// The setup file's name and text, so that errors met later (an unknown part name, …)
    /// can point at the line.
    pub source: Option<SetupSource>,
}

/// Where a setup came from.
#[derive(Debug, Clone, PartialEq)]
pub struct SetupSource {
    /// The name errors show.
    pub file: String,
    /// The setup text.
    pub text: String,
}

impl SetupSource {
    /// The 1-based line of the first occurrence of `needle` in the text.
    pub fn line_of(&self, needle: &str) -> Option<usize> {
        self.text
            .find(needle)
            .map(|pos| self.text[..pos].matches('\n').count() + 1)
    }

    /// The 1-based line of a key given by a path with list indices, e.g.
    /// `steps[1].move.Parts_Upper.rotate.axis` (csm's `steps` and `nodal_values` entries),
    /// followed object by object and index by index; `None` when the path has no index.
    pub fn line_of_indexed_key(&self, path: &str) -> Option<usize> {
        line_of_key_path(&self.text, path)
    }
}

/// The 1-based line of `path` in `text` when its first segment is `<list>[<i>]`: the list
/// entry is found by scanning the JSON tokens (strings, nesting), then every following segment
/// is searched as `"segment"` inside that entry, each after the previous one; the line of the
/// last one found (at least the entry's) is returned. `None` without an index or when the list
/// or entry is not in the text.
pub(crate) fn line_of_key_path(text: &str, path: &str) -> Option<usize> {
    let (head, rest) = path.split_once('.').unwrap_or((path, ""));
    let (list, index) = head.strip_suffix(']')?.split_once('[')?;
    let index: usize = index.parse().ok()?;
    let (start, end) = list_entry_span(text, list, index)?;
    let mut at = start;
    for segment in rest.split('.').filter(|s| !s.is_empty()) {
        let needle = format!("\"{segment}\"");
        match text[at..end].find(&needle) {
            Some(pos) => at += pos,
            None => break,
        }
    }
    Some(text[..at].matches('\n').count() + 1)
}

/// Byte span of entry `index` of the first JSON list under the key `"list"`.
fn list_entry_span(text: &str, list: &str, index: usize) -> Option<(usize, usize)> {
    let key = format!("\"{list}\"");
    let mut pos = text.find(&key)? + key.len();
    let bytes = text.as_bytes();
    while pos < bytes.len() && (bytes[pos].is_ascii_whitespace() || bytes[pos] == b':') {
        pos += 1;
    }
    if bytes.get(pos) != Some(&b'[') {
        return None;
    }
    pos += 1;
    let (mut depth, mut in_string, mut escaped) = (0usize, false, false);
    let (mut current, mut entry_start) = (0usize, None);
    for (i, &b) in bytes.iter().enumerate().skip(pos) {
        if in_string {
            match (escaped, b) {
                (true, _) => escaped = false,
                (false, b'\\') => escaped = true,
                (false, b'"') => in_string = false,
                _ => {}
            }
            continue;
        }
        match b {
            b'"' => {
                in_string = true;
                if depth == 0 && entry_start.is_none() {
                    entry_start = Some(i);
                }
            }
            b'{' | b'[' => {
                if depth == 0 && entry_start.is_none() {
                    entry_start = Some(i);
                }
                depth += 1;
            }
            b'}' | b']' if depth > 0 => depth -= 1,
            b']' | b',' if depth == 0 => {
                if current == index {
                    return entry_start.map(|s| (s, i));
                }
                if b == b']' {
                    return None;
                }
                current += 1;
                entry_start = None;
            }
            b if depth == 0 && !b.is_ascii_whitespace() && entry_start.is_none() => {
                entry_start = Some(i);
            }
            _ => {}
        }
    }
    None
}

/// One entry of `"nodal_values"`: `{"part": "<path>", "variable": "ACCELERATION", "buffer": 1,
/// "value": [x, y, z]}` sets the historical vector variable at that buffer index (0 = current
/// step, 1 = previous step) on every node of the part.
#[derive(Debug, Clone, PartialEq)]
pub struct NodalValueSetup {
    /// Full path of the part.
    pub part: String,
    /// `DISPLACEMENT`, `VELOCITY` or `ACCELERATION`.
    pub variable: VectorVar,
    /// Buffer index: 0 (current step) or 1 (previous step).
    pub buffer: usize,
    /// The value.
    pub value: Vector,
}

/// One step of a multi-step run (`"steps"` entry `{"delta_time": dt, "move": {...}}`).
#[derive(Debug, Clone, PartialEq)]
pub struct StepSetup {
    /// `delta_time` (> 0): ProcessInfo DELTA_TIME of the step; TIME advances by it.
    pub delta_time: Real,
    /// The rigid increment of each named part, in part-name order (a node in no named part
    /// does not move).
    pub moves: Vec<PartMotion>,
}

/// The rigid increment of one part in one step.
#[derive(Debug, Clone, PartialEq)]
pub struct PartMotion {
    /// Full path of the part.
    pub part: String,
    /// The increment.
    pub motion: RigidMotion,
}

/// A rigid increment: an optional rotation about an axis through a centre, then a translation
/// (`{"translate": [x, y, z], "rotate": {"axis": [x, y, z], "angle_deg": a, "centre": [x, y, z]}}`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidMotion {
    /// Translation, applied after the rotation.
    pub translate: Vector,
    /// Rotation, applied first.
    pub rotate: Option<Rotation>,
}

/// A rotation by `angle_deg` degrees about the axis through `centre` (right-hand rule).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rotation {
    /// The axis as given (non-zero; normalised when applied).
    pub axis: Vector,
    /// The angle in degrees.
    pub angle_deg: Real,
    /// A point on the axis.
    pub centre: Point,
}

impl RigidMotion {
    /// The new position of `p`: `c + (v cos a + (k × v) sin a + k (k · v)(1 − cos a)) + t`
    /// with `v = p − c` and `k` the unit axis (Rodrigues), evaluated component by component in
    /// this exact order (`tools/kratos_fixtures_steps.py` computes the Kratos side the same way,
    /// so both codes see bit-identical coordinates).
    pub fn apply(&self, p: &Point) -> Point {
        let (mut x, mut y, mut z) = (p.x, p.y, p.z);
        if let Some(r) = &self.rotate {
            let (a0, a1, a2) = (r.axis.x, r.axis.y, r.axis.z);
            let n = (a0 * a0 + a1 * a1 + a2 * a2).sqrt();
            let (k0, k1, k2) = (a0 / n, a1 / n, a2 / n);
            let (c0, c1, c2) = (r.centre.x, r.centre.y, r.centre.z);
            let angle = r.angle_deg * (std::f64::consts::PI / 180.0);
            let (cos, sin) = (angle.cos(), angle.sin());
            let (v0, v1, v2) = (x - c0, y - c1, z - c2);
            let (w0, w1, w2) = (k1 * v2 - k2 * v1, k2 * v0 - k0 * v2, k0 * v1 - k1 * v0);
            let f = (k0 * v0 + k1 * v1 + k2 * v2) * (1.0 - cos);
            x = c0 + (v0 * cos + w0 * sin + k0 * f);
            y = c1 + (v1 * cos + w1 * sin + k1 * f);
            z = c2 + (v2 * cos + w2 * sin + k2 * f);
        }
        Point::new(
            x + self.translate.x,
            y + self.translate.y,
            z + self.translate.z,
        )
    }
}
