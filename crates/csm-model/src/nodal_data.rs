//! Nodal variables: historical ones with a buffer of two steps (Kratos solution-step
//! variables) and plain ones (Kratos non-historical values).
//!
//! Storage is structure-of-arrays: one column per variable and buffer step, indexed by
//! [`crate::NodeIdx`]. A variable exists only once added ([`NodalData::add_scalar`],
//! [`NodalData::add_vector`]), as a Kratos model part has only the variables it was given
//! (`HasNodalSolutionStepVariable(VELOCITY)` decides whether dynamic search runs).

use std::collections::BTreeMap;

use csm_geometry::math::{Real, Vector};
use rayon::prelude::*;

use crate::write_at::par_clone;

/// `n` zero vectors, written in parallel on rayon's pool: `vec![Vector::zeros(); n]` writes
/// every value (a vector is no plain zero to the allocator) on one thread, and the first
/// touch of each fresh page with it.
pub fn zero_vectors(n: usize) -> Vec<Vector> {
    (0..n).into_par_iter().map(|_| Vector::zeros()).collect()
}

/// `n` zeros for a column that will be written (a current step), written in parallel on
/// rayon's pool where they are many: `vec![0.0; n]` takes pages the system zeroes at their
/// first touch, which would then come later, one page at a time, in whatever pass writes the
/// column first (a step's, on one thread or two contending).
fn zero_column(n: usize) -> Vec<Real> {
    /// Values from which the zeros are written in parallel.
    const PARALLEL_MIN: usize = 1 << 15;
    if n < PARALLEL_MIN {
        return vec![0.0; n];
    }
    (0..n).into_par_iter().map(|_| 0.0).collect()
}

/// Scalar nodal variables the pipeline uses, named as in Kratos.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ScalarVar {
    /// `WEIGHTED_GAP` (historical).
    WeightedGap,
    /// `LAGRANGE_MULTIPLIER_CONTACT_PRESSURE` (historical).
    LagrangeMultiplierContactPressure,
    /// `SCALAR_LAGRANGE_MULTIPLIER` (historical).
    ScalarLagrangeMultiplier,
    /// `NODAL_H` (historical).
    NodalH,
    /// `NORMAL_GAP` (plain).
    NormalGap,
    /// `NODAL_AREA` (plain).
    NodalArea,
}

/// Vector nodal variables the pipeline uses, named as in Kratos.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum VectorVar {
    /// `DISPLACEMENT` (historical).
    Displacement,
    /// `VELOCITY` (historical).
    Velocity,
    /// `ACCELERATION` (historical).
    Acceleration,
    /// `NORMAL` (historical).
    Normal,
    /// `VECTOR_LAGRANGE_MULTIPLIER` (historical).
    VectorLagrangeMultiplier,
    /// `DELTA_COORDINATES` (plain).
    DeltaCoordinates,
    /// `AUXILIAR_COORDINATES` (plain).
    AuxiliarCoordinates,
}

impl ScalarVar {
    /// True for variables Kratos keeps in the solution-step buffer.
    pub fn is_historical(self) -> bool {
        !matches!(self, ScalarVar::NormalGap | ScalarVar::NodalArea)
    }

    /// Kratos' name.
    pub fn name(self) -> &'static str {
        match self {
            ScalarVar::WeightedGap => "WEIGHTED_GAP",
            ScalarVar::LagrangeMultiplierContactPressure => "LAGRANGE_MULTIPLIER_CONTACT_PRESSURE",
            ScalarVar::ScalarLagrangeMultiplier => "SCALAR_LAGRANGE_MULTIPLIER",
            ScalarVar::NodalH => "NODAL_H",
            ScalarVar::NormalGap => "NORMAL_GAP",
            ScalarVar::NodalArea => "NODAL_AREA",
        }
    }
}

impl VectorVar {
    /// True for variables Kratos keeps in the solution-step buffer.
    pub fn is_historical(self) -> bool {
        !matches!(
            self,
            VectorVar::DeltaCoordinates | VectorVar::AuxiliarCoordinates
        )
    }

    /// Kratos' name.
    pub fn name(self) -> &'static str {
        match self {
            VectorVar::Displacement => "DISPLACEMENT",
            VectorVar::Velocity => "VELOCITY",
            VectorVar::Acceleration => "ACCELERATION",
            VectorVar::Normal => "NORMAL",
            VectorVar::VectorLagrangeMultiplier => "VECTOR_LAGRANGE_MULTIPLIER",
            VectorVar::DeltaCoordinates => "DELTA_COORDINATES",
            VectorVar::AuxiliarCoordinates => "AUXILIAR_COORDINATES",
        }
    }
}

/// The number of solution steps kept for historical variables (Kratos buffer size 2).
pub const BUFFER_SIZE: usize = 2;

/// The nodal variables of a model part. Step 0 is the current step, step 1 the previous.
#[derive(Debug, Default)]
pub struct NodalData {
    n_nodes: usize,
    scalars: BTreeMap<ScalarVar, Vec<Vec<Real>>>,
    vectors: BTreeMap<VectorVar, Vec<Vec<Vector>>>,
    /// Per vector variable, renewed ([`crate::entities::fresh_stamp`]) by every access that can
    /// change its values ([`NodalData::vector_stamp`]).
    vector_stamps: BTreeMap<VectorVar, u64>,
}

/// A copy of a variable's steps, each on rayon's pool where it is long.
fn steps<T: Clone + Send + Sync>(columns: &[Vec<T>]) -> Vec<Vec<T>> {
    columns.iter().map(|c| par_clone(c)).collect()
}

/// A copy whose columns are copied on rayon's pool where they are long.
impl Clone for NodalData {
    fn clone(&self) -> NodalData {
        let NodalData {
            n_nodes,
            scalars,
            vectors,
            vector_stamps,
        } = self;
        NodalData {
            n_nodes: *n_nodes,
            scalars: scalars.iter().map(|(k, v)| (*k, steps(v))).collect(),
            vectors: vectors.iter().map(|(k, v)| (*k, steps(v))).collect(),
            vector_stamps: vector_stamps.clone(),
        }
    }
}

impl NodalData {
    fn steps_of(historical: bool) -> usize {
        if historical { BUFFER_SIZE } else { 1 }
    }

    /// Adds `var` (zero on every node) if absent.
    pub fn add_scalar(&mut self, var: ScalarVar) {
        let n = self.n_nodes;
        // Each column zeroed on its own (`vec![column; steps]` would copy the first's zeros
        // into the others, touching every page); the current step's pages touched now, in
        // parallel, the others' when a step first writes them.
        self.scalars.entry(var).or_insert_with(|| {
            (0..Self::steps_of(var.is_historical()))
                .map(|step| {
                    if step == 0 {
                        zero_column(n)
                    } else {
                        vec![0.0; n]
                    }
                })
                .collect()
        });
    }

    /// Adds `var` (zero on every node) if absent.
    pub fn add_vector(&mut self, var: VectorVar) {
        if !self.vectors.contains_key(&var) {
            let steps = Self::steps_of(var.is_historical());
            self.insert_vector(var, steps);
        }
    }

    /// Adds `var` with `steps` zero columns.
    fn insert_vector(&mut self, var: VectorVar, steps: usize) {
        self.vectors.insert(
            var,
            (0..steps).map(|_| zero_vectors(self.n_nodes)).collect(),
        );
        self.renew(var);
    }

    /// Renews `var`'s stamp ([`NodalData::vector_stamp`]).
    fn renew(&mut self, var: VectorVar) {
        self.vector_stamps
            .insert(var, crate::entities::fresh_stamp());
    }

    /// A value that changes with every access that can change the values of the vector
    /// variable `var` (its mutable accesses, adding it, resizing, advancing the buffer) and
    /// that no other model has (a clone shares it until one of them changes); 0 while `var`
    /// is absent.
    pub fn vector_stamp(&self, var: VectorVar) -> u64 {
        self.vector_stamps.get(&var).copied().unwrap_or(0)
    }

    /// Adds `var` (zero on every node) if absent, keeping only the current step even when
    /// Kratos keeps the variable's history: for runs in which no stage reads step 1
    /// (`scalar(var, 1)` is then `None`, and [`NodalData::clone_solution_step`] leaves it).
    pub fn add_scalar_current(&mut self, var: ScalarVar) {
        let n = self.n_nodes;
        self.scalars
            .entry(var)
            .or_insert_with(|| vec![zero_column(n)]);
    }

    /// [`NodalData::add_scalar_current`] for a vector variable.
    pub fn add_vector_current(&mut self, var: VectorVar) {
        if !self.vectors.contains_key(&var) {
            self.insert_vector(var, 1);
        }
    }

    /// The number of steps kept for `var` (0 if absent; 1 for plain variables and for
    /// historical ones added without history).
    pub fn scalar_steps(&self, var: ScalarVar) -> usize {
        self.scalars.get(&var).map_or(0, Vec::len)
    }

    /// [`NodalData::scalar_steps`] for a vector variable.
    pub fn vector_steps(&self, var: VectorVar) -> usize {
        self.vectors.get(&var).map_or(0, Vec::len)
    }

    /// True if `var` was added.
    pub fn has_scalar(&self, var: ScalarVar) -> bool {
        self.scalars.contains_key(&var)
    }

    /// True if `var` was added.
    pub fn has_vector(&self, var: VectorVar) -> bool {
        self.vectors.contains_key(&var)
    }

    /// The values of `var` at buffer step `step` (0 = current), by node index; `None` if the
    /// variable is absent or the step is not kept.
    pub fn scalar(&self, var: ScalarVar, step: usize) -> Option<&[Real]> {
        self.scalars.get(&var)?.get(step).map(Vec::as_slice)
    }

    /// Mutable form of [`NodalData::scalar`].
    pub fn scalar_mut(&mut self, var: ScalarVar, step: usize) -> Option<&mut [Real]> {
        self.scalars
            .get_mut(&var)?
            .get_mut(step)
            .map(Vec::as_mut_slice)
    }

    /// [`NodalData::scalar_mut`] of `scalar` beside [`NodalData::vector`] of `vector`, both at
    /// buffer step `step`: one column written from another.
    pub fn scalar_mut_and_vector(
        &mut self,
        (scalar, vector): (ScalarVar, VectorVar),
        step: usize,
    ) -> (Option<&mut [Real]>, Option<&[Vector]>) {
        let written = (self.scalars.get_mut(&scalar))
            .and_then(|columns| columns.get_mut(step))
            .map(Vec::as_mut_slice);
        let read = (self.vectors.get(&vector))
            .and_then(|columns| columns.get(step))
            .map(Vec::as_slice);
        (written, read)
    }

    /// The values of `var` at buffer step `step` (0 = current), by node index.
    pub fn vector(&self, var: VectorVar, step: usize) -> Option<&[Vector]> {
        self.vectors.get(&var)?.get(step).map(Vec::as_slice)
    }

    /// Mutable form of [`NodalData::vector`].
    pub fn vector_mut(&mut self, var: VectorVar, step: usize) -> Option<&mut [Vector]> {
        self.column_mut(var, step).map(Vec::as_mut_slice)
    }

    /// The column of `var` at `step`, for writing: `var`'s stamp is renewed.
    fn column_mut(&mut self, var: VectorVar, step: usize) -> Option<&mut Vec<Vector>> {
        if self.vectors.contains_key(&var) {
            self.renew(var);
        }
        self.vectors.get_mut(&var)?.get_mut(step)
    }

    /// [`NodalData::set_vector`] of a scalar variable.
    pub fn set_scalar(&mut self, var: ScalarVar, values: Vec<Real>) -> Result<(), Vec<Real>> {
        if values.len() != self.n_nodes {
            return Err(values);
        }
        // (An absent variable's current step is `values`: no column of zeros written first;
        // the other steps are zeroed when a step first writes them.)
        let n = self.n_nodes;
        let steps = Self::steps_of(var.is_historical());
        let columns = self.scalars.entry(var).or_insert_with(|| {
            let mut columns = vec![Vec::new()];
            columns.resize_with(steps, || vec![0.0; n]);
            columns
        });
        columns[0] = values;
        Ok(())
    }

    /// Sets the current values (buffer step 0) of `var` to `values`, by node index, moving
    /// them in; the variable is added first if absent (its other buffer steps zero).
    /// `values` comes back, and nothing changes, if it does not hold one value per node.
    pub fn set_vector(&mut self, var: VectorVar, values: Vec<Vector>) -> Result<(), Vec<Vector>> {
        if values.len() != self.n_nodes {
            return Err(values);
        }
        let n = self.n_nodes;
        let steps = Self::steps_of(var.is_historical());
        let columns = self.vectors.entry(var).or_insert_with(|| {
            let mut columns = vec![Vec::new()];
            columns.resize_with(steps, || zero_vectors(n));
            columns
        });
        columns[0] = values;
        self.renew(var);
        Ok(())
    }

    /// Takes the values of `var` at `step` out (leaving none), for
    /// [`ModelPart::with_scalar_mut`](crate::ModelPart::with_scalar_mut), which puts them back.
    pub(crate) fn take_scalar(&mut self, var: ScalarVar, step: usize) -> Option<Vec<Real>> {
        column_of(&mut self.scalars, var, step).map(std::mem::take)
    }

    /// Puts back what [`NodalData::take_scalar`] took.
    pub(crate) fn put_scalar(&mut self, var: ScalarVar, step: usize, values: Vec<Real>) {
        if let Some(column) = column_of(&mut self.scalars, var, step) {
            *column = values;
        }
    }

    /// Takes the values of `var` at `step` out (leaving none), for
    /// [`ModelPart::with_vector_mut`](crate::ModelPart::with_vector_mut), which puts them back.
    pub(crate) fn take_vector(&mut self, var: VectorVar, step: usize) -> Option<Vec<Vector>> {
        self.column_mut(var, step).map(std::mem::take)
    }

    /// Puts back what [`NodalData::take_vector`] took.
    pub(crate) fn put_vector(&mut self, var: VectorVar, step: usize, values: Vec<Vector>) {
        if let Some(column) = column_of(&mut self.vectors, var, step) {
            *column = values;
        }
    }

    /// Advances the buffer of every historical variable (Kratos `CloneSolutionStep`): the
    /// previous step becomes a copy of the current one, and the current one keeps its values.
    pub fn clone_solution_step(&mut self) {
        for cols in self.scalars.values_mut() {
            if cols.len() == BUFFER_SIZE {
                let (cur, prev) = cols.split_at_mut(1);
                prev[0].copy_from_slice(&cur[0]);
            }
        }
        for cols in self.vectors.values_mut() {
            if cols.len() == BUFFER_SIZE {
                let (cur, prev) = cols.split_at_mut(1);
                prev[0].copy_from_slice(&cur[0]);
            }
        }
        self.renew_all();
    }

    /// Renews every vector variable's stamp.
    fn renew_all(&mut self) {
        for stamp in self.vector_stamps.values_mut() {
            *stamp = crate::entities::fresh_stamp();
        }
    }

    /// The variables present, scalars then vectors, in declaration order.
    pub fn variable_names(&self) -> Vec<&'static str> {
        let mut v: Vec<&'static str> = self.scalars.keys().map(|k| k.name()).collect();
        v.extend(self.vectors.keys().map(|k| k.name()));
        v
    }

    pub(crate) fn resize(&mut self, n_nodes: usize) {
        self.n_nodes = n_nodes;
        for cols in self.scalars.values_mut() {
            for c in cols {
                c.resize(n_nodes, 0.0);
            }
        }
        for cols in self.vectors.values_mut() {
            for c in cols {
                c.resize(n_nodes, Vector::zeros());
            }
        }
        self.renew_all();
    }
}

#[cfg(test)]
mod tests;

/// The column of `var` at buffer step `step` in `columns` (by variable, then step), as is.
fn column_of<K: Ord, T>(
    columns: &mut BTreeMap<K, Vec<Vec<T>>>,
    var: K,
    step: usize,
) -> Option<&mut Vec<T>> {
    columns.get_mut(&var)?.get_mut(step)
}
