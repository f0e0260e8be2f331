//! Dynamic search: the predicted displacement increment of every node (Kratos
//! `ContactUtilities::ComputeStepJump`, half jump, reference §11) and the half-jump centre.

use csm_geometry::math::{Point, Real, Vector};
use csm_model::{ModelPart, NodeIdx, VectorVar};

/// Half-jump coefficients (velocity, acceleration): the search calls ComputeStepJump with
/// its default `HalfJump = true` (§11).
const HALF_JUMP: (Real, Real) = (0.25, 0.125);

/// `Δ = c_v·dt·(v_n + v_{n−1}) + c_a·dt²·a_{n−1}` for every node in `nodes` (zero elsewhere).
/// Kratos zeroes the components whose displacement DoF is fixed; csm has no DoFs, so nothing
/// is fixed.
pub(crate) fn compute_step_jump(model: &ModelPart, nodes: &[NodeIdx], dt: Real) -> Vec<Vector> {
    let data = model.nodal_data();
    let mut delta = vec![Vector::zeros(); model.nodes().len()];
    let (cv, ca) = HALF_JUMP;
    let zero = Vector::zeros();
    // An absent column reads as zero.
    let at = |column: Option<&[Vector]>, i: usize| column.map_or(zero, |c| c[i]);
    let v0 = data.vector(VectorVar::Velocity, 0);
    let v1 = data.vector(VectorVar::Velocity, 1);
    let a1 = data.vector(VectorVar::Acceleration, 1);
    for n in nodes {
        let i = n.index();
        delta[i] = (at(v0, i) + at(v1, i)) * (cv * dt) + at(a1, i) * (ca * dt * dt);
    }
    delta
}

/// `GetHalfJumpCenter`: the centre plus the shape-function interpolation of the nodal
/// increments at the centre's local coordinates (only the first `dim` components).
pub(crate) fn half_jump_center(
    center: &Point,
    shape_at_center: &[Real],
    nodes: &[NodeIdx],
    delta: &[Vector],
    dim: usize,
) -> Point {
    let mut c = *center;
    for (n, w) in nodes.iter().zip(shape_at_center) {
        for k in 0..dim {
            c[k] += w * delta[n.index()][k];
        }
    }
    c
}
