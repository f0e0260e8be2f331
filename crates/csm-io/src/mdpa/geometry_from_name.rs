//! The geometry of an `.mdpa` element or condition, from its name.
//!
//! The name ends in `<d>D<n>N` (working dimension, node count). Conditions are faces:
//! `2D2N` Line2D2, `2D3N` Line2D3, `3D3N` Triangle3D3, `3D4N` Quadrilateral3D4, `3D6N`
//! Triangle3D6, `3D8N` Quadrilateral3D8, `3D9N` Quadrilateral3D9. Elements are solids:
//! `2D3N` Triangle2D3, `2D4N` Quadrilateral2D4, `2D6N` Triangle2D6, `2D8N` Quadrilateral2D8,
//! `2D9N` Quadrilateral2D9, `3D4N` Tetrahedra3D4, `3D6N` Prism3D6, `3D8N` Hexahedra3D8,
//! `3D10N` Tetrahedra3D10, `3D20N` Hexahedra3D20, `3D27N` Hexahedra3D27 — except that an
//! element whose name contains `Membrane` or `Shell` (any case) is a surface in space
//! (`3D3N` Triangle3D3, `3D4N` Quadrilateral3D4, `3D6N`, `3D8N`, `3D9N` as for conditions),
//! and `3D3N`/`3D9N` elements, which cannot be solids, are always surfaces. Elements
//! `2D2N`/`2D3N`… lines in a 2D model are not solids and are refused like any other suffix
//! without a geometry here.

use csm_geometry::GeometryKind;

/// `(working dimension, node count)` of a name ending in `<d>D<n>N`.
fn suffix(name: &str) -> Option<(u32, u32)> {
    let s = name.strip_suffix('N')?;
    let digits = s.len() - s.trim_end_matches(|c: char| c.is_ascii_digit()).len();
    let n: u32 = s[s.len() - digits..].parse().ok()?;
    let s = s[..s.len() - digits].strip_suffix('D')?;
    let d = s.chars().last()?.to_digit(10)?;
    Some((d, n))
}

/// The geometry of an element (`is_element`) or condition named `name`.
pub(crate) fn geometry_from_name(name: &str, is_element: bool) -> Option<GeometryKind> {
    use GeometryKind as G;
    let (d, n) = suffix(name)?;
    let lower = name.to_ascii_lowercase();
    let surface = !is_element || lower.contains("membrane") || lower.contains("shell");
    Some(match (d, n, is_element, surface) {
        (2, 2, false, _) => G::Line2D2,
        (2, 3, false, _) => G::Line2D3,
        (2, 3, true, _) => G::Triangle2D3,
        (2, 4, true, _) => G::Quadrilateral2D4,
        (2, 6, true, _) => G::Triangle2D6,
        (2, 8, true, _) => G::Quadrilateral2D8,
        (2, 9, true, _) => G::Quadrilateral2D9,
        (3, 3, _, _) => G::Triangle3D3,
        (3, 9, _, _) => G::Quadrilateral3D9,
        (3, 4, _, true) => G::Quadrilateral3D4,
        (3, 6, _, true) => G::Triangle3D6,
        (3, 8, _, true) => G::Quadrilateral3D8,
        (3, 4, true, false) => G::Tetrahedra3D4,
        (3, 6, true, false) => G::Prism3D6,
        (3, 8, true, false) => G::Hexahedra3D8,
        (3, 10, true, false) => G::Tetrahedra3D10,
        (3, 20, true, false) => G::Hexahedra3D20,
        (3, 27, true, false) => G::Hexahedra3D27,
        _ => return None,
    })
}
