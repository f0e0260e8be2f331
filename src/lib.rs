//! csm: finite-element contact search (work in progress).
