//! The pipeline stages, as functions over explicit data (STYLE.md 8). Each returns data a test
//! can print. Every stage module's public items are re-exported here (and from the crate root).

mod contact_parts;
mod dispatch;
mod interface_preprocess;
mod master_slave;
mod normal_check;
mod skin;

pub(crate) use contact_parts::user_part;
pub use contact_parts::{ContactParts, assign_contact_flags, transfer_to_contact};
pub use dispatch::{SearchInstance, dispatch};
pub(crate) use interface_preprocess::assign_generated_role;
pub use interface_preprocess::{
    GeneratedCondition, InterfaceReport, InterfaceSettings, generate_interface_conditions,
    interface_condition_name, simplify_split,
};
pub use master_slave::master_slave_from_nodes;
pub use normal_check::{
    NormalCheckReport, NormalCheckSettings, PROBE_RANGE, count_solid_elements,
    inversion_permutation, normal_check, normal_check_normals_only,
    normal_check_normals_only_with_normals, normal_check_with_normals,
};
pub use skin::{SKIN_PART, SkinReport, detect_skin};
