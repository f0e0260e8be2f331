//! The contact search of csm: stages 0–8 of the pipeline (contact model parts and flags,
//! interface conditions, normal check, master/slave flags, broad phase over every
//! `type_search`, OBB narrow phase, pair filters and pairing).
//!
//! **Status:** not implemented yet. This crate is an empty placeholder that fixes the
//! crate's place in the layering; it exports nothing and claims nothing.
//!
//! **Architecture Invariant:** `csm-search` depends on `csm-activation`, `csm-model`,
//! `csm-trees` and `csm-geometry`, never on `csm-io` or the facade: it works on a
//! `ModelPart` in memory and knows nothing of files.
