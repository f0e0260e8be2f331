//! Typed setup values.

use std::collections::BTreeMap;

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
}
