//! Integration tests of `csm-geometry`: shape-function and local-coordinate round trips over
//! every kind, outward faces of solids, and the OBB tests against `parry3d-f64` as an oracle.

mod common;
mod degenerate;
mod faces;
mod local_coordinates;
mod mortar;
mod obb_vs_parry;
