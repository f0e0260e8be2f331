//! Gauss rules used by the measures (area, volume): `(local point, weight)` visited in order.

use crate::GeometryKind;
use crate::math::Real;

const G2: Real = 0.577_350_269_189_625_8; // 1/sqrt(3)
const G3: Real = 0.774_596_669_241_483_4; // sqrt(3/5)

fn gauss_1d(order: usize) -> &'static [(Real, Real)] {
    const TWO: [(Real, Real); 2] = [(-G2, 1.0), (G2, 1.0)];
    const THREE: [(Real, Real); 3] = [(-G3, 5.0 / 9.0), (0.0, 8.0 / 9.0), (G3, 5.0 / 9.0)];
    if order <= 2 { &TWO } else { &THREE }
}

/// Calls `f(point, weight)` for every point of a Gauss rule for `kind`'s reference element
/// (no allocation): 2 points per direction for linear kinds,
/// 3 for quadratic ones; triangles the 3-point rule (degree 2), tetrahedra the 4-point rule
/// (degree 2), prisms triangle (3) × Gauss (2) on ζ ∈ [0, 1].
pub(crate) fn for_each_gauss_point(kind: GeometryKind, mut f: impl FnMut([Real; 3], Real)) {
    use GeometryKind as K;
    let quadratic = matches!(
        kind,
        K::Line2D3
            | K::Quadrilateral3D8
            | K::Quadrilateral3D9
            | K::Quadrilateral2D8
            | K::Quadrilateral2D9
            | K::Hexahedra3D20
            | K::Hexahedra3D27
    );
    let g = gauss_1d(if quadratic { 3 } else { 2 });
    const TRI: [([Real; 2], Real); 3] = [
        ([1.0 / 6.0, 1.0 / 6.0], 1.0 / 6.0),
        ([2.0 / 3.0, 1.0 / 6.0], 1.0 / 6.0),
        ([1.0 / 6.0, 2.0 / 3.0], 1.0 / 6.0),
    ];
    match kind {
        K::Line2D2 | K::Line2D3 => {
            for &(x, w) in g {
                f([x, 0.0, 0.0], w);
            }
        }
        K::Triangle3D3 | K::Triangle3D6 | K::Triangle2D3 | K::Triangle2D6 => {
            for &(p, w) in &TRI {
                f([p[0], p[1], 0.0], w);
            }
        }
        K::Quadrilateral3D4
        | K::Quadrilateral3D8
        | K::Quadrilateral3D9
        | K::Quadrilateral2D4
        | K::Quadrilateral2D8
        | K::Quadrilateral2D9 => {
            for &(y, wy) in g {
                for &(x, wx) in g {
                    f([x, y, 0.0], wx * wy);
                }
            }
        }
        K::Hexahedra3D8 | K::Hexahedra3D20 | K::Hexahedra3D27 => {
            for &(z, wz) in g {
                for &(y, wy) in g {
                    for &(x, wx) in g {
                        f([x, y, z], wx * wy * wz);
                    }
                }
            }
        }
        K::Tetrahedra3D4 | K::Tetrahedra3D10 => {
            let a = 0.585_410_196_624_968_5;
            let b = 0.138_196_601_125_010_5;
            let w = 1.0 / 24.0;
            for p in [[b, b, b], [a, b, b], [b, a, b], [b, b, a]] {
                f(p, w);
            }
        }
        K::Prism3D6 => {
            for &(z, wz) in gauss_1d(2) {
                for &(p, w) in &TRI {
                    f([p[0], p[1], 0.5 + 0.5 * z], w * 0.5 * wz);
                }
            }
        }
    }
}
