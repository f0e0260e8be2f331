//! The mortar operators `D` and `M` of one pair (Kratos `MortarOperator::
//! CalculateMortarOperators`, reference §10.2.2).

use super::dual_basis::DualBasis;
use super::face::MortarFace;
use super::face_matrix::{FaceMatrix, face_shape_values};
use super::integration_points::MortarIntegrationPoint;
use crate::math::Real;

/// The mortar operators of one slave–master pair (inline, no heap block).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MortarOperators {
    /// `D(i, j) = Σ w · Φ_i · N_s,j` (slave × slave; diagonal for the pair's own dual basis).
    pub d: FaceMatrix,
    /// `M(i, j) = Σ w · Φ_i · N_m,j` (slave × master).
    pub m: FaceMatrix,
}

impl MortarOperators {
    /// The mapper residual `R = M · v_master − D · v_slave` for one scalar component
    /// (values in node order), evaluated as ublas does `prod(M, V) − prod(D, S)`: each product
    /// summed in index order from 0, then the difference.
    pub fn residual(&self, master_values: &[Real], slave_values: &[Real]) -> Vec<Real> {
        let mut out = vec![0.0; self.d.nrows()];
        self.residual_into(master_values, slave_values, &mut out);
        out
    }

    /// [`residual`](Self::residual) written into `out` (one entry per slave node; entries
    /// beyond the slave nodes are left alone): the same arithmetic, no allocation.
    pub fn residual_into(&self, master_values: &[Real], slave_values: &[Real], out: &mut [Real]) {
        debug_assert!(
            master_values.len() == self.m.ncols() && slave_values.len() == self.d.ncols()
        );
        for (i, o) in out.iter_mut().enumerate().take(self.d.nrows()) {
            *o = row_residual(self.m.row(i), master_values, self.d.row(i), slave_values);
        }
    }

    /// The number of values [`pack_into`](Self::pack_into) appends for `slave_nodes` ×
    /// `master_nodes` operators.
    pub fn packed_len(slave_nodes: usize, master_nodes: usize) -> usize {
        slave_nodes * (slave_nodes + master_nodes)
    }

    /// Appends `D` then `M`, row by row, to `out`: the used entries only (a store of many
    /// pairs' operators without the fixed 4×4 blocks).
    pub fn pack_into(&self, out: &mut Vec<Real>) {
        for i in 0..self.d.nrows() {
            out.extend_from_slice(self.d.row(i));
        }
        for i in 0..self.m.nrows() {
            out.extend_from_slice(self.m.row(i));
        }
    }

    /// [`residual_into`](Self::residual_into) of the operators `packed` by
    /// [`pack_into`](Self::pack_into) (`slave_values.len()` slave and `master_values.len()`
    /// master nodes): bit for bit the same values.
    pub fn packed_residual_into(
        packed: &[Real],
        master_values: &[Real],
        slave_values: &[Real],
        out: &mut [Real],
    ) {
        let (ns, nm) = (slave_values.len(), master_values.len());
        debug_assert_eq!(packed.len(), MortarOperators::packed_len(ns, nm));
        let (d, m) = packed.split_at(ns * ns);
        for (i, o) in out.iter_mut().enumerate().take(ns) {
            let d_row = &d[i * ns..(i + 1) * ns];
            let m_row = &m[i * nm..(i + 1) * nm];
            *o = row_residual(m_row, master_values, d_row, slave_values);
        }
    }
}

impl MortarOperators {
    /// The number of values [`pack_with_products_into`](Self::pack_with_products_into)
    /// appends for `slave_nodes` and `components` components.
    pub fn packed_with_products_len(slave_nodes: usize, components: usize) -> usize {
        slave_nodes * (slave_nodes + components)
    }

    /// Appends `D`, row by row, then the products `M · v_k` of each component `k` of the master
    /// values `master_values[k]` (slave node order): for master values that do not change
    /// while the residual is evaluated again and again (the mapper's master side), the store
    /// of `M` is replaced by the one part of the residual it enters.
    pub fn pack_with_products_into(&self, master_values: &[&[Real]], out: &mut Vec<Real>) {
        for i in 0..self.d.nrows() {
            out.extend_from_slice(self.d.row(i));
        }
        for values in master_values {
            for i in 0..self.m.nrows() {
                out.push(row_product(self.m.row(i), values));
            }
        }
    }

    /// [`residual_into`](Self::residual_into) of component `k` from the operators packed by
    /// [`pack_with_products_into`](Self::pack_with_products_into) (`slave_values.len()` slave
    /// nodes, `components` components): bit for bit the residual of the master values packed.
    pub fn packed_products_residual_into(
        packed: &[Real],
        (k, components): (usize, usize),
        slave_values: &[Real],
        out: &mut [Real],
    ) {
        let ns = slave_values.len();
        debug_assert_eq!(
            packed.len(),
            MortarOperators::packed_with_products_len(ns, components)
        );
        for (i, o) in out.iter_mut().enumerate().take(ns) {
            *o = MortarOperators::packed_products_residual_row(
                packed,
                (k, components),
                slave_values,
                i,
            );
        }
    }

    /// Row `i` alone of [`packed_products_residual_into`](Self::packed_products_residual_into):
    /// bit for bit its `out[i]` (for a caller that sums the residual node by node).
    pub fn packed_products_residual_row(
        packed: &[Real],
        (k, components): (usize, usize),
        slave_values: &[Real],
        i: usize,
    ) -> Real {
        let ns = slave_values.len();
        debug_assert_eq!(
            packed.len(),
            MortarOperators::packed_with_products_len(ns, components)
        );
        let (d, products) = packed.split_at(ns * ns);
        products[k * ns + i] - row_product(&d[i * ns..(i + 1) * ns], slave_values)
    }
}

/// `Σ_j a_j v_j` in index order from 0 (one row of a ublas `prod`).
fn row_product(row: &[Real], values: &[Real]) -> Real {
    let mut sum = 0.0;
    for (a, v) in row.iter().zip(values) {
        sum += a * v;
    }
    sum
}

/// One row of the mapper residual, `Σ_j M_ij v_j − Σ_j D_ij s_j`, each sum in index order
/// from 0 (ublas' `prod(M, V) − prod(D, S)`).
fn row_residual(
    m_row: &[Real],
    master_values: &[Real],
    d_row: &[Real],
    slave_values: &[Real],
) -> Real {
    row_product(m_row, master_values) - row_product(d_row, slave_values)
}

/// `D` and `M` integrated over the Gauss points of one pair with `Φ = Ae · N_s` (`basis`) or
/// `Φ = N_s` (`None`, the standard mortar basis). `N_s` at the slave local coordinates, `N_m`
/// at the master local coordinates of each point.
pub fn mortar_operators(
    slave: &MortarFace<'_>,
    master: &MortarFace<'_>,
    points: &[MortarIntegrationPoint],
    basis: Option<&DualBasis>,
) -> MortarOperators {
    let sg = slave.geometry();
    let mg = master.geometry();
    let ns_count = sg.kind().n_nodes();
    let nm_count = mg.kind().n_nodes();
    let mut d = FaceMatrix::zeros(ns_count, ns_count);
    let mut m = FaceMatrix::zeros(ns_count, nm_count);
    for gp in points {
        let ns = face_shape_values(sg.kind(), &gp.slave_local);
        let nm = face_shape_values(mg.kind(), &gp.master_local);
        let phi = match basis {
            Some(b) => b.phi(&ns[..ns_count]),
            None => ns,
        };
        // Kratos `MortarOperator::CalculateMortarOperators`:
        // `D += (detJ·w) · outer(Φ, N_s)`, `M += (detJ·w) · outer(Φ, N_m)`.
        let w_det = gp.det_j * gp.gauss_weight;
        for i in 0..ns_count {
            for j in 0..ns_count {
                d[(i, j)] += w_det * (phi[i] * ns[j]);
            }
            for j in 0..nm_count {
                m[(i, j)] += w_det * (phi[i] * nm[j]);
            }
        }
    }
    MortarOperators { d, m }
}
