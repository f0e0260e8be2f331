//! The plan's values: a [`Plan`] for the model, a [`PairPlan`] per pair key, and the
//! [`Decision`] / [`Reason`] of every stage and structure.

use std::collections::BTreeMap;

use csm_model::{ScalarVar, VectorVar};

use crate::setup::{CheckGap, Compatibility, ObbIntersectionType, SearchTreeType};

/// Whether a stage runs (a structure is built, a variable allocated): `Used` with what it
/// does, or `LeftOut` with why.
#[derive(Debug, Clone, PartialEq)]
pub enum Decision<T> {
    /// It runs / is built, as `T` says.
    Used(T),
    /// It does not, for this reason.
    LeftOut(Reason),
}

impl<T> Decision<T> {
    /// True for [`Decision::Used`].
    pub fn is_used(&self) -> bool {
        matches!(self, Decision::Used(_))
    }

    /// What is done, if it is used.
    pub fn used(&self) -> Option<&T> {
        match self {
            Decision::Used(t) => Some(t),
            Decision::LeftOut(_) => None,
        }
    }

    /// Why it is left out, if it is.
    pub fn reason(&self) -> Option<&Reason> {
        match self {
            Decision::Used(_) => None,
            Decision::LeftOut(r) => Some(r),
        }
    }
}

/// Why a stage or structure is left out. Its `Display` is the sentence `csm plan` prints.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum Reason {
    /// The mesh has a `Contact` part, which Kratos reuses (no stage 0 or 1).
    ContactPartInMesh,
    /// The mesh has no `Contact` part: stage 0 sets the condition flags.
    NoContactPartInMesh,
    /// `cpp_search_parameters`: the C++ search process is driven directly, without the
    /// Python layer (no interface preprocessing, no normal check).
    CppSearchParameters,
    /// No solid element: the normal check's passes would look at nothing.
    NoSolidElements,
    /// `adapt_search` is false.
    AdaptSearchOff,
    /// The pair's `type_search` does not use it.
    TypeSearch(SearchTreeType),
    /// The pair's `check_gap` does not use it.
    CheckGap(CheckGap),
    /// `bounding_box_factor` ≤ 0: the octree tests the faces themselves, without OBBs.
    NoBoundingBoxFactor,
    /// `dynamic_search` is false.
    DynamicSearchOff,
    /// VELOCITY and ACCELERATION are zero (or absent) on every node of the pair: the
    /// predicted increment is zero and the prediction would change nothing.
    NoVelocities,
    /// `simple_search` is true: the Simple activation reads only NORMAL_GAP.
    SimpleActivation,
    /// The C++ parameters name no paired condition (`condition_name` empty, Q18).
    NoConditionName,
    /// No stage of csm reads it.
    NotRead,
    /// The setup has no `steps`: one search step.
    NoSteps,
    /// A Lagrange multiplier: csm has no solver to give it values, so the activation's guesses
    /// could only read and write zeros (a library user who adds the variable gets them).
    NoMultiplierValues,
    /// No pair has `dynamic_search`.
    NoDynamicPair,
    /// No pair runs the Advanced activation (MappingCheck with `simple_search` false).
    NoAdvancedActivation,
    /// No pair has `check_gap` MappingCheck.
    NoMappingCheck,
}

/// What the normal check (stage 2) does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NormalCheck {
    /// Both passes over the solid elements.
    Full {
        /// The solid elements the passes look at.
        solid_elements: usize,
    },
    /// No solid element: only the check's unit normals and MARKER bookkeeping
    /// ([`crate::normal_check_normals_only`]); `csm plan` shows it as left out.
    NormalsOnly,
}

/// What stage 1 does with one user part.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InterfaceAction {
    /// The part has no conditions: they are generated from the element faces.
    Generate,
    /// The part has conditions: only the properties check runs.
    CheckProperties {
        /// The part's conditions.
        conditions: usize,
    },
}

/// The multi-step run of the setup's `steps`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StepsPlan {
    /// Number of steps.
    pub count: usize,
    /// Full paths of the parts moved in some step.
    pub moved_parts: Vec<String>,
    /// The kd-trees are kept and refitted between steps (`refit_tree`; not for Kratos-mode
    /// DirectCheck, whose result depends on the candidate order).
    pub refit_tree: bool,
}

/// Where NODAL_H comes from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum NodalHSource {
    /// Kratos' FindNodalHProcess.
    FindNodalH,
    /// The setup's `nodal_h`, on every node.
    Constant(f64),
}

/// How a nodal variable is stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Storage {
    /// The current step only (a historical variable whose history no stage reads).
    Current,
    /// The current and the previous step (Kratos' buffer of two).
    WithHistory,
    /// A non-historical variable (one value per node).
    Plain,
    /// Already in the mesh: kept as read.
    FromMesh,
}

/// A nodal variable.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NodalVariable {
    /// A scalar one.
    Scalar(ScalarVar),
    /// A vector one.
    Vector(VectorVar),
}

impl NodalVariable {
    /// Kratos' name.
    pub fn name(self) -> &'static str {
        match self {
            NodalVariable::Scalar(v) => v.name(),
            NodalVariable::Vector(v) => v.name(),
        }
    }
}

/// One nodal variable of the emulated Python state.
#[derive(Debug, Clone, PartialEq)]
pub struct VariablePlan {
    /// The variable.
    pub variable: NodalVariable,
    /// How it is stored, or why it is not allocated.
    pub storage: Decision<Storage>,
    /// What reads it (shown when it is allocated).
    pub readers: &'static str,
}

/// The kd-tree query of a pair.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KdQuery {
    /// Radius query around the slave centre.
    Radius,
    /// Box query around the slave's bounding box.
    Box,
}

/// The dynamic search's step jump (half-jump prediction) of a pair.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct StepJump {
    /// Nodes of the pair with a non-zero velocity or acceleration.
    pub moving_nodes: usize,
    /// MappingCheck moves the nodes to the predicted positions for the search (and back);
    /// No/DirectCheck only shift the query centres.
    pub moves_nodes: bool,
}

/// The activation (stage 9) of a MappingCheck pair.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Activation {
    /// `simple_search` true: NORMAL_GAP against a fraction of NODAL_H.
    Simple,
    /// `simple_search` false: NORMAL_GAP and the weighted gap against DISTANCE_THRESHOLD ×
    /// ACTIVE_CHECK_FACTOR (DISTANCE_THRESHOLD = the mean NODAL_H of the slave side).
    Advanced {
        /// Compares the weighted gap with the previous step's.
        static_check_movement: bool,
    },
}

/// The plan of one pair key (one Kratos search process).
#[derive(Debug, Clone, PartialEq)]
pub struct PairPlan {
    /// The pair key.
    pub key: u32,
    /// The parts assumed slave (`assume_master_slave`; empty: roles not predefined).
    pub slave_parts: Vec<String>,
    /// The other parts of the pair.
    pub master_parts: Vec<String>,
    /// `type_search`.
    pub type_search: SearchTreeType,
    /// `check_gap`.
    pub check_gap: CheckGap,
    /// `inverted_search`: the tree holds the slave side, masters query it.
    pub inverted_search: bool,
    /// The half-jump prediction of the dynamic search.
    pub step_jump: Decision<StepJump>,
    /// The kd-tree over the master-side condition centres.
    pub kd_tree: Decision<KdQuery>,
    /// The octree over the master-side conditions.
    pub octree: Decision<()>,
    /// The OBB narrow phase (OBBs of the candidate masters, SAT or Direct).
    pub obb_test: Decision<ObbIntersectionType>,
    /// The 18-DOP narrow phase.
    pub kdop: Decision<()>,
    /// The mortar mapping (NormalGapProcess: NORMAL_GAP, pruning of pairs without overlap).
    pub mortar_mapping: Decision<()>,
    /// The paired conditions (Kratos' ComputingContact conditions).
    pub paired_conditions: Decision<()>,
    /// The weighted gap (ComputeWeightedReaction).
    pub weighted_gap: Decision<()>,
    /// The activation (ComputeActiveInactiveNodes).
    pub activation: Decision<Activation>,
}

/// The plan of a search: see the module docs.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// DOMAIN_SIZE (2 or 3) the search runs with.
    pub domain_size: u32,
    /// `compatibility`.
    pub compatibility: Compatibility,
    /// Stage 0: the `Contact` part, its sub parts and the INTERFACE/MASTER/SLAVE flags.
    pub contact_parts: Decision<()>,
    /// Stage 1, for every (pair key, user part) in the order it runs.
    pub interface: Decision<Vec<(u32, String, InterfaceAction)>>,
    /// Stage 2.
    pub normal_check: Decision<NormalCheck>,
    /// Stage 3: MASTER/SLAVE condition flags from the nodal ones.
    pub master_slave_from_nodes: Decision<()>,
    /// NODAL_H.
    pub nodal_h: NodalHSource,
    /// `adapt_search`: search_factor and active_check_factor scaled by h_max/h_min.
    pub adapt_search: Decision<()>,
    /// The setup's `steps` (DESIGN.md §3): how many, and the parts their rigid motions move
    /// (sorted, each once).
    pub steps: Decision<StepsPlan>,
    /// The nodal variables of the emulated Python state.
    pub variables: Vec<VariablePlan>,
    /// The pairs, by key.
    pub pairs: BTreeMap<u32, PairPlan>,
}

impl Plan {
    /// The plan of a variable, by Kratos name.
    pub fn variable(&self, name: &str) -> Option<&VariablePlan> {
        self.variables.iter().find(|v| v.variable.name() == name)
    }
}
