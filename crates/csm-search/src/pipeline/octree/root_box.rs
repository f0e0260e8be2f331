//! The octree's root box (Kratos `FindIntersectedGeometricalObjectsWithOBBContactSearchProcess::
//! SetOctreeBoundingBox`, reference §8 step 3).

use csm_geometry::math::{EPS, Point, Real};

use crate::setup::{Compatibility, OctreeSearchParameters};

/// The root box of the octree over `points` (the slave-part and master-part nodes), or `None`
/// without points.
///
/// Both modes start from the nodes' AABB, padded per axis `k` exactly as Kratos does:
/// `low −= |high − low|·1e-3 + ε`, then `high += |high − low|·1e-3 + ε` — the second line uses
/// the already lowered `low`.
///
/// * Kratos mode: then, when `bbf > 0`, every axis `k < domain_size` (DOMAIN_SIZE; 0 when
///   unset → nothing, Q17) with `|high − low| < bbf` gets `low −= lower_coefficient · bbf`,
///   `high += higher_coefficient · bbf` (defaults 0 and 1: a flat interface lies on the lower
///   face of the box).
/// * Robust mode: every axis (whatever DOMAIN_SIZE) thinner than
///   `t = max(bbf, 1e-3 · largest extent)` becomes `[mid − t, mid + t]` around its middle, so a
///   flat interface lies in the middle of a box of real thickness; the lower/higher
///   coefficients are not used.
pub(super) fn root_box<'a>(
    points: impl IntoIterator<Item = &'a Point>,
    bbf: Real,
    octree: &OctreeSearchParameters,
    domain_size: u32,
    compatibility: Compatibility,
) -> Option<(Point, Point)> {
    let mut it = points.into_iter();
    let first = *it.next()?;
    let (mut low, mut high) = (first, first);
    for p in it {
        for k in 0..3 {
            low[k] = if p[k] < low[k] { p[k] } else { low[k] };
            high[k] = if p[k] > high[k] { p[k] } else { high[k] };
        }
    }
    for k in 0..3 {
        low[k] -= (high[k] - low[k]).abs() * 1e-3 + EPS;
        high[k] += (high[k] - low[k]).abs() * 1e-3 + EPS;
    }
    match compatibility {
        Compatibility::Kratos => {
            if bbf > 0.0 {
                for k in 0..(domain_size as usize).min(3) {
                    if (high[k] - low[k]).abs() < bbf {
                        low[k] -= octree.lower_bounding_box_coefficient * bbf;
                        high[k] += octree.higher_bounding_box_coefficient * bbf;
                    }
                }
            }
        }
        Compatibility::Robust => {
            let largest = (0..3).map(|k| high[k] - low[k]).fold(0.0, Real::max);
            let thickness = bbf.max(1e-3 * largest);
            for k in 0..3 {
                if high[k] - low[k] < thickness {
                    let mid = 0.5 * (low[k] + high[k]);
                    low[k] = mid - thickness;
                    high[k] = mid + thickness;
                }
            }
        }
    }
    Some((low, high))
}
