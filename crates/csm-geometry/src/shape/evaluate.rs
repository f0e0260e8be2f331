//! Evaluation of the shape functions and their local derivatives for every kind.

use super::reference::reference_node_coordinates;
use super::values::{ShapeDerivatives, ShapeValues};
use crate::GeometryKind;
use crate::math::{Point, Real};

/// Mid-node edges of the quadratic triangle (nodes 3, 4, 5).
const TRI6_EDGES: [(usize, usize); 3] = [(0, 1), (1, 2), (2, 0)];
/// Mid-node edges of the quadratic tetrahedron (nodes 4..10).
const TET10_EDGES: [(usize, usize); 6] = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)];

/// How the shape functions of a kind are built.
enum Family {
    /// Products of linear 1D functions `(1 + a x)/2` (Line2D2, quadrilateral 4, hexahedron 8).
    TensorLinear,
    /// Products of quadratic 1D Lagrange functions on {−1, 0, 1} (Line2D3, quad 9, hexa 27).
    TensorQuadratic,
    /// Serendipity (quadrilateral 8, hexahedron 20).
    Serendipity,
    /// Barycentric linear (triangle 3, tetrahedron 4).
    SimplexLinear,
    /// Barycentric quadratic with the given mid-node edges (triangle 6, tetrahedron 10).
    SimplexQuadratic(&'static [(usize, usize)]),
    /// Linear triangle × linear ζ ∈ [0, 1].
    Prism,
}

fn family(kind: GeometryKind) -> Family {
    use GeometryKind as K;
    match kind {
        K::Line2D2 | K::Quadrilateral3D4 | K::Quadrilateral2D4 | K::Hexahedra3D8 => {
            Family::TensorLinear
        }
        K::Line2D3 | K::Quadrilateral3D9 | K::Quadrilateral2D9 | K::Hexahedra3D27 => {
            Family::TensorQuadratic
        }
        K::Quadrilateral3D8 | K::Quadrilateral2D8 | K::Hexahedra3D20 => Family::Serendipity,
        K::Triangle3D3 | K::Triangle2D3 | K::Tetrahedra3D4 => Family::SimplexLinear,
        K::Triangle3D6 | K::Triangle2D6 => Family::SimplexQuadratic(&TRI6_EDGES),
        K::Tetrahedra3D10 => Family::SimplexQuadratic(&TET10_EDGES),
        K::Prism3D6 => Family::Prism,
    }
}

/// 1D quadratic Lagrange function on the nodes {−1, 0, 1} belonging to node `a`, and its
/// derivative.
fn lagrange2(x: Real, a: Real) -> (Real, Real) {
    if a < 0.0 {
        (0.5 * x * (x - 1.0), x - 0.5)
    } else if a > 0.0 {
        (0.5 * x * (x + 1.0), x + 0.5)
    } else {
        (1.0 - x * x, -2.0 * x)
    }
}

/// Barycentric coordinates `L_0..L_d` of a simplex and their (constant) local gradients.
fn barycentric(local_dim: usize, xi: &[Real; 3]) -> ([Real; 4], [[Real; 3]; 4]) {
    let mut l = [0.0; 4];
    let mut dl = [[0.0; 3]; 4];
    l[0] = 1.0 - xi[..local_dim].iter().sum::<Real>();
    for k in 0..local_dim {
        dl[0][k] = -1.0;
        l[k + 1] = xi[k];
        dl[k + 1][k] = 1.0;
    }
    (l, dl)
}

/// Shape-function values and local derivatives of `kind` at the local point `local`.
/// Always inlined: the callers want one of the two, and inlining lets the compiler drop the
/// other and build the result in place (a hot path of the mortar routines).
#[inline(always)]
fn evaluate(kind: GeometryKind, local: &Point) -> (ShapeValues, ShapeDerivatives) {
    let nodes = reference_node_coordinates(kind);
    let n = nodes.len();
    let d = kind.local_dim();
    let xi = [local.x, local.y, local.z];
    let mut values = ShapeValues::zeros(n);
    let mut derivs = ShapeDerivatives::zeros(n, d);
    match family(kind) {
        Family::TensorLinear | Family::TensorQuadratic => {
            let quadratic = matches!(family(kind), Family::TensorQuadratic);
            for (i, a) in nodes.iter().enumerate() {
                let mut f = [1.0; 3];
                let mut df = [0.0; 3];
                for k in 0..d {
                    (f[k], df[k]) = if quadratic {
                        lagrange2(xi[k], a[k])
                    } else {
                        (0.5 * (1.0 + a[k] * xi[k]), 0.5 * a[k])
                    };
                }
                values.set(i, f[0] * f[1] * f[2]);
                let mut row = [0.0; 3];
                for (k, r) in row.iter_mut().enumerate().take(d) {
                    let mut p = df[k];
                    for (m, fm) in f.iter().enumerate().take(d) {
                        if m != k {
                            p *= fm;
                        }
                    }
                    *r = p;
                }
                derivs.set(i, row);
            }
        }
        Family::Serendipity => {
            let scale = if d == 2 { 0.25 } else { 0.125 };
            for (i, a) in nodes.iter().enumerate() {
                let mid = (0..d).find(|&k| a[k] == 0.0);
                let mut row = [0.0; 3];
                match mid {
                    None => {
                        // Corner: scale · Π(1 + a_k x_k) · (Σ a_k x_k − (d − 1)).
                        let lin: Vec3 =
                            core::array::from_fn(|k| if k < d { 1.0 + a[k] * xi[k] } else { 1.0 });
                        let s: Real = (0..d).map(|k| a[k] * xi[k]).sum::<Real>() - (d - 1) as Real;
                        let prod = lin[0] * lin[1] * lin[2];
                        values.set(i, scale * prod * s);
                        for (k, r) in row.iter_mut().enumerate().take(d) {
                            let others: Real = (0..d).filter(|&m| m != k).map(|m| lin[m]).product();
                            *r = scale * others * a[k] * (s + lin[k]);
                        }
                    }
                    Some(m) => {
                        // Mid node: 2·scale · (1 − x_m²) · Π_{k≠m}(1 + a_k x_k).
                        let c = 2.0 * scale;
                        let bubble = 1.0 - xi[m] * xi[m];
                        let lin: Vec3 = core::array::from_fn(|k| {
                            if k < d && k != m {
                                1.0 + a[k] * xi[k]
                            } else {
                                1.0
                            }
                        });
                        let prod = lin[0] * lin[1] * lin[2];
                        values.set(i, c * bubble * prod);
                        for (k, r) in row.iter_mut().enumerate().take(d) {
                            *r = if k == m {
                                c * (-2.0 * xi[m]) * prod
                            } else {
                                let others: Real = (0..d)
                                    .filter(|&q| q != k && q != m)
                                    .map(|q| lin[q])
                                    .product();
                                c * bubble * a[k] * others
                            };
                        }
                    }
                }
                derivs.set(i, row);
            }
        }
        Family::SimplexLinear => {
            let (l, dl) = barycentric(d, &xi);
            for i in 0..n {
                values.set(i, l[i]);
                derivs.set(i, dl[i]);
            }
        }
        Family::SimplexQuadratic(edges) => {
            let (l, dl) = barycentric(d, &xi);
            for i in 0..=d {
                values.set(i, l[i] * (2.0 * l[i] - 1.0));
                let g = 4.0 * l[i] - 1.0;
                derivs.set(i, [dl[i][0] * g, dl[i][1] * g, dl[i][2] * g]);
            }
            for (e, &(p, q)) in edges.iter().enumerate() {
                let i = d + 1 + e;
                values.set(i, 4.0 * l[p] * l[q]);
                derivs.set(
                    i,
                    core::array::from_fn(|k| 4.0 * (dl[p][k] * l[q] + l[p] * dl[q][k])),
                );
            }
        }
        Family::Prism => {
            let (l, dl) = barycentric(2, &xi);
            let z = xi[2];
            for i in 0..3 {
                values.set(i, l[i] * (1.0 - z));
                values.set(i + 3, l[i] * z);
                derivs.set(i, [dl[i][0] * (1.0 - z), dl[i][1] * (1.0 - z), -l[i]]);
                derivs.set(i + 3, [dl[i][0] * z, dl[i][1] * z, l[i]]);
            }
        }
    }
    (values, derivs)
}

type Vec3 = [Real; 3];

/// Values `N_i(ξ)` of the shape functions of `kind` at the local point `local`
/// (unused local directions are ignored).
#[inline]
pub fn shape_functions(kind: GeometryKind, local: &Point) -> ShapeValues {
    evaluate(kind, local).0
}

/// Local derivatives `∂N_i/∂ξ_k` of the shape functions of `kind` at `local`.
#[inline]
pub fn shape_derivatives(kind: GeometryKind, local: &Point) -> ShapeDerivatives {
    evaluate(kind, local).1
}
