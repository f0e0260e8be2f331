//! Small inline matrices and shape-function values of mortar faces (at most four nodes): the
//! per-pair arithmetic of the operators without heap blocks.

use std::ops::{Index, IndexMut};

use crate::GeometryKind;
use crate::math::{Point, Real};

/// The most nodes of a mortar face (`Quadrilateral3D4`).
pub const MAX_MORTAR_FACE_NODES: usize = 4;

/// A dense `rows × cols` matrix of at most [`MAX_MORTAR_FACE_NODES`] rows and columns, stored inline:
/// the dual basis `Ae` and the mortar operators `D`, `M` of one pair. Indexed by
/// `(row, column)`; an index beyond `rows × cols` panics, as a slice index does.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaceMatrix {
    entries: [[Real; MAX_MORTAR_FACE_NODES]; MAX_MORTAR_FACE_NODES],
    rows: usize,
    cols: usize,
}

impl FaceMatrix {
    /// The zero matrix. The sizes are the node counts of mortar faces
    /// ([`MortarFace`](super::MortarFace) admits no other); larger ones are clamped.
    pub(crate) fn zeros(rows: usize, cols: usize) -> FaceMatrix {
        debug_assert!(rows <= MAX_MORTAR_FACE_NODES && cols <= MAX_MORTAR_FACE_NODES);
        FaceMatrix {
            entries: [[0.0; MAX_MORTAR_FACE_NODES]; MAX_MORTAR_FACE_NODES],
            rows: rows.min(MAX_MORTAR_FACE_NODES),
            cols: cols.min(MAX_MORTAR_FACE_NODES),
        }
    }

    /// The `n × n` identity.
    pub(crate) fn identity(n: usize) -> FaceMatrix {
        let mut a = FaceMatrix::zeros(n, n);
        for i in 0..a.rows {
            a.entries[i][i] = 1.0;
        }
        a
    }

    /// The number of rows.
    pub fn nrows(&self) -> usize {
        self.rows
    }

    /// The number of columns.
    pub fn ncols(&self) -> usize {
        self.cols
    }

    /// Row `i` (`ncols` entries).
    pub fn row(&self, i: usize) -> &[Real] {
        &self.entries[..self.rows][i][..self.cols]
    }

    /// The entries, row by row.
    pub fn iter(&self) -> impl Iterator<Item = &Real> + '_ {
        self.entries[..self.rows]
            .iter()
            .flat_map(move |r| r[..self.cols].iter())
    }

    /// `f` applied to every entry.
    pub(crate) fn map(&self, f: impl Fn(Real) -> Real) -> FaceMatrix {
        let mut out = *self;
        for row in &mut out.entries[..self.rows] {
            for x in &mut row[..self.cols] {
                *x = f(*x);
            }
        }
        out
    }
}

impl Index<(usize, usize)> for FaceMatrix {
    type Output = Real;
    fn index(&self, (i, j): (usize, usize)) -> &Real {
        &self.entries[..self.rows][i][..self.cols][j]
    }
}

impl IndexMut<(usize, usize)> for FaceMatrix {
    fn index_mut(&mut self, (i, j): (usize, usize)) -> &mut Real {
        &mut self.entries[..self.rows][i][..self.cols][j]
    }
}

/// The shape-function values of a mortar face kind at `local` (entries beyond the node count
/// are 0): bit for bit [`Geometry::shape_functions`](crate::Geometry::shape_functions), without
/// its 27-value container and the derivatives (tested).
#[inline]
pub(crate) fn face_shape_values(
    kind: GeometryKind,
    local: &Point,
) -> [Real; MAX_MORTAR_FACE_NODES] {
    let (x, y) = (local.x, local.y);
    match kind {
        GeometryKind::Line2D2 => [0.5 * (1.0 - x), 0.5 * (1.0 + x), 0.0, 0.0],
        GeometryKind::Triangle3D3 | GeometryKind::Triangle2D3 => [1.0 - (x + y), x, y, 0.0],
        GeometryKind::Quadrilateral3D4 | GeometryKind::Quadrilateral2D4 => [
            (0.5 * (1.0 - x)) * (0.5 * (1.0 - y)),
            (0.5 * (1.0 + x)) * (0.5 * (1.0 - y)),
            (0.5 * (1.0 + x)) * (0.5 * (1.0 + y)),
            (0.5 * (1.0 - x)) * (0.5 * (1.0 + y)),
        ],
        other => {
            let mut out = [0.0; MAX_MORTAR_FACE_NODES];
            let n = crate::shape_functions(other, local);
            for (o, v) in out.iter_mut().zip(n.iter()) {
                *o = *v;
            }
            out
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #[test]
        fn face_shape_values_are_the_shape_functions_bit_for_bit(
            x in -1.5f64..1.5,
            y in -1.5f64..1.5,
            tiny in prop_oneof![Just(0.0), Just(-0.0), Just(1e-300), Just(-1e-17)],
        ) {
            use GeometryKind as K;
            for kind in [K::Line2D2, K::Triangle3D3, K::Triangle2D3, K::Quadrilateral3D4, K::Quadrilateral2D4] {
                for p in [Point::new(x, y, 0.0), Point::new(tiny, y, 0.0), Point::new(x, tiny, 0.0), Point::new(tiny, tiny, 0.0)] {
                    let fast = face_shape_values(kind, &p);
                    let general = crate::shape_functions(kind, &p);
                    for (i, v) in general.iter().enumerate() {
                        prop_assert_eq!(fast[i].to_bits(), v.to_bits(), "{:?} node {}", kind, i);
                    }
                    prop_assert!(fast[general.len()..].iter().all(|v| *v == 0.0));
                }
            }
        }
    }

    #[test]
    fn indices_stay_within_the_sizes() {
        let mut a = FaceMatrix::zeros(2, 3);
        a[(1, 2)] = 5.0;
        assert_eq!(a.row(1), &[0.0, 0.0, 5.0]);
        assert_eq!(a.iter().count(), 6);
        assert_eq!(FaceMatrix::identity(3).iter().sum::<Real>(), 3.0);
        assert!(std::panic::catch_unwind(|| a[(2, 0)]).is_err());
        assert!(std::panic::catch_unwind(|| a[(0, 3)]).is_err());
    }
}
