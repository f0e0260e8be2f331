//! Time steps and prescribed nodal motion, with Kratos' solution-step buffer semantics.
//!
//! A multi-step run over a [`ModelPart`] does, between two searches, what Kratos' analysis stage
//! and solver do: [`ModelPart::advance_time_step`] (`STEP += 1`, `CloneTimeStep(TIME + dt)`:
//! the historical buffer shifts and the new current step starts as a copy of the previous one),
//! then the motion of the step, [`ModelPart::prescribe_motion`] (new coordinates, DISPLACEMENT,
//! VELOCITY and ACCELERATION of the current step). The search then reads the current and the
//! previous buffer step: the dynamic search VELOCITY at both and ACCELERATION at the previous
//! one, Advanced activation with `static_check_movement` WEIGHTED_GAP at the previous one.

use csm_geometry::math::{Point, Real, Vector};

use crate::{ModelPart, VectorVar};

impl ModelPart {
    /// Kratos' `STEP += 1; CloneTimeStep(TIME + delta_time)` with `DELTA_TIME := delta_time`:
    /// every historical variable's previous step becomes a copy of the current one (which keeps
    /// its values); `STEP` (1 if unset) and `TIME` (0 if unset) advance in the process info.
    pub fn advance_time_step(&mut self, delta_time: Real) {
        self.nodal_data_mut().clone_solution_step();
        let pi = self.process_info_mut();
        let step = pi.number("STEP").unwrap_or(1.0);
        let time = pi.number("TIME").unwrap_or(0.0);
        pi.set_number("STEP", step + 1.0);
        pi.set_number("TIME", time + delta_time);
        pi.set_number("DELTA_TIME", delta_time);
    }

    /// Moves every node to `positions[node index]` over a step of length `delta_time`, as a
    /// solver would leave the current step: with `d` the increment (new − old coordinates),
    /// `DISPLACEMENT += d`, `VELOCITY := d / dt`, `ACCELERATION := (VELOCITY − VELOCITY of the
    /// previous step) / dt`. The three variables are added (zero) where absent. The coordinates
    /// are set to the given positions exactly (not `old + d`).
    ///
    /// # Panics
    /// If `positions` does not have one entry per node (a caller's bug).
    pub fn prescribe_motion(&mut self, positions: &[Point], delta_time: Real) {
        let n = self.nodes().len();
        assert_eq!(positions.len(), n, "one position per node");
        let increments: Vec<Vector> = self
            .nodes()
            .coordinates()
            .iter()
            .zip(positions)
            .map(|(old, new)| new - old)
            .collect();
        self.nodes_mut()
            .coordinates_mut()
            .copy_from_slice(positions);
        let data = self.nodal_data_mut();
        for v in [
            VectorVar::Displacement,
            VectorVar::Velocity,
            VectorVar::Acceleration,
        ] {
            data.add_vector(v);
        }
        if let Some(u) = data.vector_mut(VectorVar::Displacement, 0) {
            for (u, d) in u.iter_mut().zip(&increments) {
                *u += d;
            }
        }
        let previous: Vec<Vector> = data
            .vector(VectorVar::Velocity, 1)
            .map_or_else(|| vec![Vector::zeros(); n], <[Vector]>::to_vec);
        let velocity: Vec<Vector> = increments.iter().map(|d| d / delta_time).collect();
        if let Some(v) = data.vector_mut(VectorVar::Velocity, 0) {
            v.copy_from_slice(&velocity);
        }
        if let Some(a) = data.vector_mut(VectorVar::Acceleration, 0) {
            for ((a, v), v_old) in a.iter_mut().zip(&velocity).zip(&previous) {
                *a = (v - v_old) / delta_time;
            }
        }
    }
}

#[cfg(test)]
mod tests;
