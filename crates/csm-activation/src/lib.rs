//! The gap and activation layer of csm (stage 9): mortar NormalGap mapping (the MappingCheck
//! narrow phase), weighted gap, Simple and Advanced activation.
//!
//! **Status:** not implemented yet. This crate is an empty placeholder that fixes the
//! crate's place in the layering; it exports nothing and claims nothing.
//!
//! **Architecture Invariant:** `csm-activation` depends only on `csm-model` and
//! `csm-geometry`; it never sees trees, the search configuration or files.
