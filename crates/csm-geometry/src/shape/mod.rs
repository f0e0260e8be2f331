//! Shape functions of the reference elements, in Kratos' node numbering.
//!
//! Reference elements: lines ξ ∈ [−1, 1]; triangles and tetrahedra ξ, η (, ζ) ≥ 0 with
//! ξ + η (+ ζ) ≤ 1; quadrilaterals and hexahedra [−1, 1]^d; prisms a triangle in (ξ, η) times
//! ζ ∈ [0, 1] (Kratos' `Prism3D6`).

mod evaluate;
mod reference;
mod values;

#[cfg(test)]
mod tests;

pub use evaluate::{shape_derivatives, shape_functions};
pub use reference::reference_node_coordinates;
pub use values::{MAX_NODES, ShapeDerivatives, ShapeValues};
