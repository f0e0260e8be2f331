//! The result of the segmentation: integration cells in slave local coordinates.

use super::face::MortarMode;
use crate::Geometry;
use crate::math::{Point, Real, cross_kratos, norm_kratos};

/// One integration cell: a segment (2D) or a triangle (3D), stored by its vertices in the
/// slave's local coordinates and, mapped through the (original) slave geometry, in global
/// coordinates — the "decomposition geometry" Kratos integrates on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MortarCell {
    local: [Point; 3],
    global: [Point; 3],
    len: usize,
}

impl MortarCell {
    /// A cell from its vertices in slave local coordinates (2 or 3 of them).
    pub(crate) fn new(slave: &Geometry<'_>, local: &[Point]) -> MortarCell {
        debug_assert!(local.len() == 2 || local.len() == 3);
        let mut cell = MortarCell {
            local: [Point::origin(); 3],
            global: [Point::origin(); 3],
            len: local.len(),
        };
        for (k, p) in local.iter().enumerate() {
            cell.local[k] = *p;
            cell.global[k] = slave.global_coordinates(p);
        }
        cell
    }

    /// The vertices in the slave's local coordinates (2 for a segment, 3 for a triangle).
    pub fn local_vertices(&self) -> &[Point] {
        &self.local[..self.len]
    }

    /// The vertices in global coordinates (the slave's `GlobalCoordinates` of the local ones).
    pub fn global_vertices(&self) -> &[Point] {
        &self.global[..self.len]
    }

    /// True for a 2-vertex (2D) cell.
    pub fn is_segment(&self) -> bool {
        self.len == 2
    }

    /// The measure of the cell in global coordinates: the length `sqrt(Δx² + Δy²)` of a
    /// segment (Kratos `Line2D2::Length`, z ignored), the area `½|(x1−x0)×(x2−x0)|` of a
    /// triangle.
    pub fn measure(&self) -> Real {
        let g = &self.global;
        if self.len == 2 {
            let dx = g[1].x - g[0].x;
            let dy = g[1].y - g[0].y;
            (dx * dx + dy * dy).sqrt()
        } else {
            0.5 * norm_kratos(&cross_kratos(&(g[1] - g[0]), &(g[2] - g[0])))
        }
    }

    /// Kratos' measure: the length for a segment, Heron's formula for a triangle (`Triangle3D3::
    /// Area`, Q45). Where Kratos' radicand is negative (a sliver; Kratos gets NaN) this returns 0.
    pub fn measure_heron(&self) -> Real {
        if self.len == 2 {
            return self.measure();
        }
        let g = &self.global;
        let a = norm_kratos(&(g[0] - g[1]));
        let b = norm_kratos(&(g[1] - g[2]));
        let c = norm_kratos(&(g[2] - g[0]));
        let s = (a + b + c) / 2.0;
        let r = s * (s - a) * (s - b) * (s - c);
        if r > 0.0 { r.sqrt() } else { 0.0 }
    }

    /// Kratos' degenerate-cell test of the mortar integration: a segment is bad if its length
    /// (x, y only) is below `length_tolerance` (`MortarUtilities::LengthCheck`); a triangle is bad
    /// if Heron's radicand `s(s−a)(s−b)(s−c)` is `≤ 0` (`MortarUtilities::HeronCheck`;
    /// `length_tolerance` is unused in 3D).
    pub fn is_bad_shape(&self, length_tolerance: Real) -> bool {
        if self.len == 2 {
            let length = self.measure();
            return length.is_nan() || length < length_tolerance;
        }
        let g = &self.global;
        let a = norm_kratos(&(g[0] - g[1]));
        let b = norm_kratos(&(g[1] - g[2]));
        let c = norm_kratos(&(g[2] - g[0]));
        let s = 0.5 * (a + b + c);
        let radicand = s * (s - a) * (s - b) * (s - c);
        radicand.is_nan() || radicand <= 0.0
    }
}

/// The integration cells of one slave–master pair (never empty: "no overlap" is `None`).
#[derive(Debug, Clone, PartialEq)]
pub struct Segmentation {
    cells: Vec<MortarCell>,
    mode: MortarMode,
}

impl Segmentation {
    pub(crate) fn new(cells: Vec<MortarCell>, mode: MortarMode) -> Option<Segmentation> {
        (!cells.is_empty()).then_some(Segmentation { cells, mode })
    }

    /// The cells, in Kratos' order (fan order around the first polygon point in 3D).
    pub fn cells(&self) -> &[MortarCell] {
        &self.cells
    }

    /// The mode the segmentation was computed in.
    pub fn mode(&self) -> MortarMode {
        self.mode
    }

    /// The overlap measure: the sum of the cell measures (Kratos `GetTotalArea`): Heron's
    /// formula in [`MortarMode::Kratos`] ([`MortarCell::measure_heron`]), the cross product in
    /// [`MortarMode::Robust`] ([`MortarCell::measure`]); segment lengths in 2D. Note that in
    /// Kratos mode the `<3,3,4>` master-inside cells overlap (Q49), so this can exceed the
    /// true overlap.
    pub fn overlap_area(&self) -> Real {
        self.cells
            .iter()
            .map(|c| match self.mode {
                MortarMode::Kratos => c.measure_heron(),
                MortarMode::Robust => c.measure(),
            })
            .sum()
    }
}
