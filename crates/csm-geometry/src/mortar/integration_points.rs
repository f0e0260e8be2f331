//! Gauss points of the integration cells with slave and master local coordinates (the
//! kinematics of Kratos' mortar mapper and explicit contribution, reference §10.2.2).

use super::cell::Segmentation;
use super::face::{MortarFace, MortarMode};
use super::face_matrix::face_shape_values;
use crate::math::{EPS, Point, Real, Vector, norm_kratos};
use crate::projection::fast_project_direction;
use crate::{Error, ErrorKind, LocalCoordinatesSolver};

/// The mapper's degenerate-segment factor: a 2D cell shorter than `1e-6 · slave.Length()` is
/// skipped (`SimpleMortarMapperProcess`, Q45).
pub const MAPPER_LENGTH_FACTOR: Real = 1e-6;
/// The explicit weighted-gap contribution's factor: `1e-12 · slave.Length()` (Q45).
pub const EXPLICIT_LENGTH_FACTOR: Real = 1e-12;

/// How the cells are integrated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OperatorSettings {
    /// Kratos `integration_order` (`GI_GAUSS_n`): 1 or 2 are supported; 3..=5 give
    /// [`ErrorKind::Unsupported`]; any other value means 2, as in Kratos.
    pub integration_order: usize,
    /// Degenerate-segment factor of the 2D `LengthCheck` ([`MAPPER_LENGTH_FACTOR`] or
    /// [`EXPLICIT_LENGTH_FACTOR`]); 3D cells use Heron's test (`HeronCheck`) instead.
    pub length_factor: Real,
}

impl OperatorSettings {
    /// The mortar mapper of NormalGapProcess: order 2, length factor 1e-6.
    pub fn mapper() -> OperatorSettings {
        OperatorSettings {
            integration_order: 2,
            length_factor: MAPPER_LENGTH_FACTOR,
        }
    }

    /// The explicit weighted-gap contribution: order 2 (`INTEGRATION_ORDER_CONTACT` default),
    /// length factor 1e-12.
    pub fn explicit() -> OperatorSettings {
        OperatorSettings {
            integration_order: 2,
            length_factor: EXPLICIT_LENGTH_FACTOR,
        }
    }
}

impl Default for OperatorSettings {
    /// [`OperatorSettings::mapper`].
    fn default() -> OperatorSettings {
        OperatorSettings::mapper()
    }
}

/// One Gauss point of an integration cell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MortarIntegrationPoint {
    /// Index of the cell in [`Segmentation::cells`].
    pub cell: usize,
    /// Global position (interpolated on the cell, the "decomposition geometry").
    pub global: Point,
    /// Slave local coordinates (`PointLocalCoordinates` of `global` on the slave).
    pub slave_local: Point,
    /// The Gauss-point normal: normalised `Σ N_s,i · n_i` (nodal normals).
    pub normal: Vector,
    /// The point on the master plane reached from `global` along `−normal`
    /// (`FastProjectDirection` onto the plane through master node 0 with the master normal).
    pub master_global: Point,
    /// Master local coordinates of `master_global` (not checked to be inside).
    pub master_local: Point,
    /// Integration weight times the cell Jacobian determinant (`w · detJ`); the weights of a
    /// segmentation sum to its measure.
    pub weight: Real,
    /// The Gauss weight `w` of the cell's rule alone (Kratos multiplies it with `detJ` in
    /// different orders in different operators; see [`dual_basis`](super::dual_basis)).
    pub gauss_weight: Real,
    /// The cell's Jacobian determinant `detJ` alone.
    pub det_j: Real,
}

/// The Gauss points Kratos integrates the mortar operators on: for every cell that passes the
/// degenerate-shape test ([`MortarCell::is_bad_shape`](super::MortarCell::is_bad_shape) with
/// `length_factor · slave.Length()`), the Gauss rule of the cell geometry (Line2D2 or
/// Triangle3D3) with weight `w · detJ_cell` (`detJ` of a segment = length / 2; of a triangle
/// = 2 · area: Heron's area in [`MortarMode::Kratos`] as Kratos' `Triangle3D3`, the cross
/// product in robust mode), the slave local coordinates, the Gauss-point normal and the master
/// projection.
///
/// Errors: [`ErrorKind::Unsupported`] for integration orders 3..=5; [`ErrorKind::Degenerate`]
/// for a zero Gauss-point normal or a degenerate master; errors of the local-coordinate
/// iterations.
pub fn integration_points(
    slave: &MortarFace<'_>,
    master: &MortarFace<'_>,
    segmentation: &Segmentation,
    settings: &OperatorSettings,
) -> Result<Vec<MortarIntegrationPoint>, Error> {
    let sg = slave.geometry();
    let mg = master.geometry();
    let order = match settings.integration_order {
        1 => 1,
        3..=5 => {
            return Err(Error::new(ErrorKind::Unsupported(
                "mortar integration orders 3 to 5",
            )));
        }
        _ => 2,
    };
    let length_tolerance = if sg.kind().local_dim() == 1 {
        settings.length_factor * sg.length()?
    } else {
        0.0
    };
    let mut out = Vec::with_capacity(3 * segmentation.cells().len());
    // Many points on the same two faces: the point-independent work once.
    let slave_solver = LocalCoordinatesSolver::new(*sg);
    let master_solver = LocalCoordinatesSolver::new(*mg);
    for (cell_idx, cell) in segmentation.cells().iter().enumerate() {
        if cell.is_bad_shape(length_tolerance) {
            continue;
        }
        let g = cell.global_vertices();
        let rule = decomposition_rule(cell.is_segment(), order);
        let det_j = if cell.is_segment() {
            cell.measure() / 2.0
        } else {
            2.0 * match segmentation.mode() {
                MortarMode::Kratos => cell.measure_heron(),
                MortarMode::Robust => cell.measure(),
            }
        };
        for (n_cell, w) in rule {
            let mut x = Vector::zeros();
            for (nk, p) in n_cell.iter().zip(g) {
                x += p.coords * *nk;
            }
            let global = Point::from(x);
            let slave_local = slave_solver.local_coordinates(&global)?;
            let (normal, master_global, master_local) =
                master_side(slave, master, &master_solver, &global, &slave_local)?;
            out.push(MortarIntegrationPoint {
                cell: cell_idx,
                global,
                slave_local,
                normal,
                master_global,
                master_local,
                weight: w * det_j,
                gauss_weight: *w,
                det_j,
            });
        }
    }
    Ok(out)
}

/// The Gauss-point normal (normalised `Σ N_s,i · n_i` of the slave's nodal normals at
/// `slave_local`), the point on the master plane along `−normal` from `global` and its master
/// local coordinates.
fn master_side(
    slave: &MortarFace<'_>,
    master: &MortarFace<'_>,
    master_solver: &LocalCoordinatesSolver<'_>,
    global: &Point,
    slave_local: &Point,
) -> Result<(Vector, Point, Point), Error> {
    let sg = slave.geometry();
    let n_s = face_shape_values(sg.kind(), slave_local);
    let mut normal = Vector::zeros();
    for (i, ni) in n_s.iter().enumerate().take(sg.kind().n_nodes()) {
        normal += slave.nodal_normal(i) * *ni;
    }
    let norm = norm_kratos(&normal);
    if norm.is_nan() || norm <= EPS {
        return Err(Error::degenerate("zero Gauss-point normal"));
    }
    normal /= norm;
    let mg = master.geometry();
    let (master_global, _) =
        fast_project_direction(&mg.points()[0], global, &master.normal(), &(-normal));
    let master_local = master_solver.local_coordinates(&master_global)?;
    Ok((normal, master_global, master_local))
}

/// The Gauss points of `points` — [`integration_points`] of a pair whose slave has the
/// geometry of `slave` — again with the nodal normals of `slave` and the master `master`:
/// the cells, positions, slave local coordinates and weights are kept (they depend on the
/// slave geometry and the cells only), the Gauss-point normal, the master projection and the
/// master local coordinates computed anew. Bit for bit [`integration_points`]`(slave, master,
/// segmentation, settings)` when `points` came from the same segmentation with the same
/// `settings` (in 3D the cell test does not depend on them; tested), without the slave's
/// local-coordinate iterations. Errors: those of the master side of [`integration_points`].
pub fn integration_points_with_normals(
    slave: &MortarFace<'_>,
    master: &MortarFace<'_>,
    points: &[MortarIntegrationPoint],
) -> Result<Vec<MortarIntegrationPoint>, Error> {
    let master_solver = LocalCoordinatesSolver::new(*master.geometry());
    // Room for every point at once (a collect through `Result` would grow the list).
    let mut out = Vec::with_capacity(points.len());
    for gp in points {
        let (normal, master_global, master_local) =
            master_side(slave, master, &master_solver, &gp.global, &gp.slave_local)?;
        out.push(MortarIntegrationPoint {
            normal,
            master_global,
            master_local,
            ..*gp
        });
    }
    Ok(out)
}

/// Gauss rule of a cell as (shape-function values of the cell at the point, weight): Line2D2
/// Gauss–Legendre on [−1, 1]; Triangle3D3 `GI_GAUSS_1` (centroid, ½) and `GI_GAUSS_2`
/// (1/6, 1/6), (2/3, 1/6), (1/6, 2/3) with weights 1/6.
fn decomposition_rule(segment: bool, order: usize) -> &'static [([Real; 3], Real)] {
    const G: Real = 0.577_350_269_189_625_8;
    const SEGMENT_1: [([Real; 3], Real); 1] = [([0.5 * (1.0 - 0.0), 0.5 * (1.0 + 0.0), 0.0], 2.0)];
    const SEGMENT_2: [([Real; 3], Real); 2] = [
        ([0.5 * (1.0 - -G), 0.5 * (1.0 + -G), 0.0], 1.0),
        ([0.5 * (1.0 - G), 0.5 * (1.0 + G), 0.0], 1.0),
    ];
    const fn tri(xi: Real, eta: Real, w: Real) -> ([Real; 3], Real) {
        ([1.0 - xi - eta, xi, eta], w)
    }
    const TRIANGLE_1: [([Real; 3], Real); 1] = [tri(1.0 / 3.0, 1.0 / 3.0, 0.5)];
    const TRIANGLE_2: [([Real; 3], Real); 3] = [
        tri(1.0 / 6.0, 1.0 / 6.0, 1.0 / 6.0),
        tri(2.0 / 3.0, 1.0 / 6.0, 1.0 / 6.0),
        tri(1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0),
    ];
    match (segment, order) {
        (true, 1) => &SEGMENT_1,
        (true, _) => &SEGMENT_2,
        (false, 1) => &TRIANGLE_1,
        (false, _) => &TRIANGLE_2,
    }
}
