//! The contact search of csm: stages 0–8 of the pipeline (contact model parts and flags,
//! interface conditions, normal check, master/slave flags, broad phase over every
//! `type_search`, OBB narrow phase, pair filters and pairing).
//!
//! **Status:** [`parse_setup`] turns the `Parameters` of a Kratos contact process (or a whole
//! `ProjectParameters.json`) into a typed [`SearchSetup`] with Kratos' defaults, aliases,
//! fallbacks and dropped keys (DESIGN.md §2). [`ContactSearch`] runs Kratos' life cycle over
//! the stages: contact parts and flags (stage 0, [`assign_contact_flags`]), interface
//! conditions ([`generate_interface_conditions`], stage 1), the normal check
//! ([`normal_check`], stage 2), [`master_slave_from_nodes`] (stage 3), [`dispatch`] (stage 4),
//! the life cycle with `database_step_update` (stage 5), the kd-tree broad phase (`in_radius`,
//! `in_box`), the OBB and 18-DOP narrow phases (stages 6–7), the candidate filters and the
//! No/Direct/MappingCheck pairing (stage 8) with the mortar pruning, gap and activation of
//! `csm-activation`, dynamic and inverted search, the octree path, and multi-step runs
//! ([`ContactSearch::advance`]: the time step and the rigid motions of SETUP.json `steps`,
//! `docs/steps.md`), roles decided automatically (self-contact) and the skin when no part is
//! named (robust mode).
//!
//! The evaluation layer (`csm-eval`: the exact ground truth and the scores) drives a search
//! through [`ContactSearch::step_with_pairs`], [`TruthScene`] and [`passes_orientation`].
//!
//! [`Plan`] says which stages run and which structures are built for a model and a setup, and
//! why each other one is left out (`csm plan`); [`ContactSearch`] makes the same plan and
//! follows it, so nothing a scene or setup does not need is run or allocated.
//!
//! **Architecture Invariant:** `csm-search` depends on `csm-activation`, `csm-model`,
//! `csm-trees` and `csm-geometry`, never on `csm-io` or the facade: it works on a
//! `ModelPart` in memory and knows nothing of files (the setup text is given to it).
#![deny(missing_docs)]

mod error;
mod setup;
mod stages;

pub use error::{Error, ErrorKind};
pub use setup::{
    CheckGap, Compatibility, ContactProcess, ContactType, NodalValueSetup, ObbIntersectionType,
    OctreeSearchParameters, PairSetup, PartMotion, RigidMotion, Rotation, SearchParameters,
    SearchSetup, SearchTreeType, SetupSource, StepSetup, parse_setup,
};
pub use stages::{
    ContactParts, GeneratedCondition, InterfaceReport, InterfaceSettings, NormalCheckReport,
    NormalCheckSettings, PROBE_RANGE, SKIN_PART, SearchInstance, SkinReport, assign_contact_flags,
    count_solid_elements, detect_skin, dispatch, generate_interface_conditions,
    interface_condition_name, inversion_permutation, master_slave_from_nodes, normal_check,
    normal_check_normals_only, normal_check_normals_only_with_normals, normal_check_with_normals,
    simplify_split, transfer_to_contact,
};
mod pipeline;
mod plan;
pub mod scenes;
mod trace;
pub use pipeline::{
    ContactSearch, GENERATED_CONDITIONS_PART, IdMap, MappingTuning, NodeResult, PairGlobals,
    PairedCondition, QueryOrder, SearchResult, SearchTuning, StepResult, TruthScene,
    generate_interfaces_first, kratos_renumbering, passes_orientation,
};
pub use plan::{
    Activation, Decision, InterfaceAction, KdQuery, NodalHSource, NodalVariable, NormalCheck,
    PairPlan, Plan, Reason, StepJump, StepsPlan, Storage, VariablePlan, step_jump,
};
pub use trace::{Usage, minor_faults, process_cpu_seconds};
