//! Which OBB test runs and how the SAT evaluates its axes.

use crate::math::Real;

/// Kratos' `OBBHasIntersectionType`: which OBB–OBB test to run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum ObbIntersection {
    /// Separating-axis theorem (Kratos' default, `SeparatingAxisTheorem`).
    #[default]
    Sat,
    /// Vertex inclusion plus boundary intersection (Kratos `Direct`).
    Direct,
}

/// How the SAT evaluates its candidate axes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum SatMode {
    /// Literally as Kratos: axis order `A1_0..`, `A2_0..`, then the raw (un-normalised) cross
    /// products `A1_i × A2_j` (i outer); axis `n` separates iff
    /// `|t·n| > Σ|(A1_k h1_k)·n| + Σ|(A2_k h2_k)·n|` (strict, sums left to right, dot products
    /// `a0*b0 + a1*b1 + a2*b2`), no epsilon. Near-parallel axes compare rounding noise (Q2).
    #[default]
    Kratos,
    /// Numerically guarded: every axis is normalised; a cross-product axis with
    /// `|a × b| ≤` [`CROSS_AXIS_GUARD`]` · |a||b|` is skipped; an axis separates iff
    /// `|t·n̂| − (r1 + r2) > `[`TOUCH_TOLERANCE`]` · scale`.
    Robust,
}

/// Relative guard of the robust SAT for cross-product axes: `A1_i × A2_j` is skipped (treated
/// as non-separating) when `|A1_i × A2_j| ≤ 1e-10 · |A1_i| |A2_j|`, i.e. when the axes are
/// within 1e-10 rad of parallel.
///
/// Why this value: a cross product of unit vectors at angle θ carries an absolute rounding error
/// of about ε ≈ 2.2e-16 per component, so its *direction* is wrong by about ε/θ. Any direction
/// is a valid separating axis as long as the projections onto the *computed* (normalised) axis
/// are evaluated accurately, so a noisy direction cannot make a false "separated" verdict; the
/// guard only removes axes that are pure noise (θ ≲ 1e-10 means ≥ 1e-6 relative direction
/// error and, at θ → 0, a zero vector that cannot be normalised). Skipping is conservative
/// (it can only turn "separated" into "intersecting"): for θ below the guard, the face axes of
/// both boxes (which are complete for exactly parallel edges) detect any separation larger than
/// about `θ · (box size) ≤ 1e-10 · scale`, which is inside the documented band.
pub const CROSS_AXIS_GUARD: Real = 1e-10;

/// Relative touching tolerance of the robust SAT: an axis separates only if the gap between the
/// projected intervals exceeds `1e-9 · (Σ h1 + Σ h2 + |t|) + 16 ε · (max|c1| + max|c2|)`: a
/// band relative to the boxes' own size and distance, plus the rounding of `t = c2 − c1` and of
/// its projection (∞-norms of the centres; ε the machine epsilon). Boxes closer than that are
/// reported as intersecting (touching counts). The size part dominates the separation that a
/// skipped near-parallel cross axis can hide (~1e-10 · size); the centre part only covers
/// rounding, so the verdict does not depend on where the boxes are: a scene translated by 1e6
/// keeps its pairs (before, `1e-9 · max|c|` made the band 1e-3 wide there and added pairs —
/// found by the stability suite). The robust verdict can differ from the exact one only when
/// the exact separation distance is inside that band (the "touching band").
pub const TOUCH_TOLERANCE: Real = 1e-9;

/// The rounding factor of the centres in the robust SAT's band ([`TOUCH_TOLERANCE`]), in units
/// of the machine epsilon.
pub const CENTRE_ROUNDING_EPS: Real = 16.0;
