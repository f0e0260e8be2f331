//! The plan of a search: which stages run and which structures are built or allocated for a
//! model and a setup, and why each other one is left out (`csm plan`).
//!
//! [`Plan::new`] decides from the model as read and the setup, before anything runs;
//! [`crate::ContactSearch`] makes the same plan at the start of `initialize` and follows it
//! (stage 2, the nodal variables, the broad and narrow phases, the step jump, the weighted
//! gap), so the plan is what runs, not a separate guess. Only the step jump depends on data
//! that can change between steps (the velocities): every step decides it again with
//! [`step_jump`] and records it in [`crate::ContactSearch::plan`].
//!
//! A decision is a [`Decision`]: `Used` with what is done, or `LeftOut` with a [`Reason`].
//! Leaving something out never changes a result: each reason says why the stage or structure
//! could not have had an effect.

mod decide;
mod render;
mod types;

pub use decide::step_jump;
pub(crate) use decide::{contact_sub_path, missing_contact_sub, pair_plan};
pub use types::{
    Activation, Decision, InterfaceAction, KdQuery, NodalHSource, NodalVariable, NormalCheck,
    PairPlan, Plan, Reason, StepJump, StepsPlan, Storage, VariablePlan,
};

#[cfg(test)]
mod tests;
