//! The order of the parallel slave queries (a Morton curve of the slave centres) and the test
//! that puts a slave far from every master. Only the order of work depends on them, never a
//! result.

use super::*;

/// The positions in `slaves` ordered along a Morton (Z-order) curve of the slave centres
/// (node means, quantised to 21 bits per axis in their bounding box); ties by position, so the
/// order is deterministic. Only the order of the parallel queries depends on it, never a result.
#[cfg(test)]
pub(crate) fn morton_order(model: &ModelPart, slaves: &[ConditionIdx]) -> Vec<usize> {
    let centres: Vec<(usize, Point)> = slaves
        .par_iter()
        .enumerate()
        .map(|(k, c)| (k, reach(model, *c).0))
        .collect();
    morton_order_of(&centres)
}

/// The centre of condition `c` (its node mean) and the largest distance from it to a node.
pub(crate) fn reach(model: &ModelPart, c: ConditionIdx) -> (Point, Real) {
    let coords = model.nodes().coordinates();
    let nodes = model.conditions().nodes(c.index());
    let sum = nodes
        .iter()
        .fold(Vector::zeros(), |acc, n| acc + coords[n.index()].coords);
    let centre = Point::from(sum / nodes.len().max(1) as Real);
    let radius = nodes
        .iter()
        .map(|n| (coords[n.index()] - centre).norm())
        .fold(0.0, Real::max);
    (centre, radius)
}

/// Which slave queries stay far from the kd-tree's points (and end at its root): an estimate
/// of the queries' reach, which only decides the order of the queries, never a result.
pub(crate) struct Far {
    bounds: Option<Aabb>,
    /// How far a query reaches, in slave radii (twice the search factor, at least 2).
    factor: Real,
}

impl Far {
    pub(crate) fn new(bounds: Option<Aabb>, search_factor: Real) -> Far {
        Far {
            bounds,
            factor: 2.0 * search_factor.max(1.0),
        }
    }

    /// Whether the query of a slave of centre `centre` and radius `radius` (see [`reach`]) is
    /// taken to stay far from the tree's points.
    pub(crate) fn is_far(&self, centre: &Point, radius: Real) -> bool {
        self.bounds.is_some_and(|b| {
            let outside = (b.min - centre)
                .sup(&(centre - b.max))
                .sup(&Vector::zeros());
            outside.norm() > self.factor * radius
        })
    }
}

/// The positions of `centres` (position, centre) ordered along a Morton curve of the centres
/// (see [`morton_order`]).
#[cfg(test)]
pub(super) fn morton_order_of(centres: &[(usize, Point)]) -> Vec<usize> {
    morton_order_of_parts(&[centres])
}

/// [`morton_order_of`] the centres of `parts`, one part after the other, in parallel passes:
/// their bounding box, their keys (written into one list, no part joined on one thread), the
/// sort and the positions.
pub(super) fn morton_order_of_parts<P>(parts: &[P]) -> Vec<usize>
where
    P: AsRef<[(usize, Point)]> + Sync,
{
    let empty = (
        Vector::repeat(Real::INFINITY),
        Vector::repeat(Real::NEG_INFINITY),
    );
    let (lo, hi) = (parts.par_iter())
        .map(|part| {
            (part.as_ref().iter()).fold(empty, |(lo, hi), (_, p)| {
                (lo.inf(&p.coords), hi.sup(&p.coords))
            })
        })
        .reduce(|| empty, |(lo, hi), (l, h)| (lo.inf(&l), hi.sup(&h)));
    let cells = Real::from((1u32 << 21) - 1);
    let quantise = |x: Real, k: usize| -> u64 {
        let span = hi[k] - lo[k];
        if span.is_nan() || span <= 0.0 || !x.is_finite() {
            return 0;
        }
        (((x - lo[k]) / span * cells).clamp(0.0, cells)) as u64
    };
    let spread = |mut v: u64| -> u64 {
        // Insert two zero bits between the 21 low bits of `v`.
        v &= 0x1f_ffff;
        v = (v | v << 32) & 0x1f_0000_0000_ffff;
        v = (v | v << 16) & 0x1f_0000_ff00_00ff;
        v = (v | v << 8) & 0x100f_00f0_0f00_f00f;
        v = (v | v << 4) & 0x10c3_0c30_c30c_30c3;
        v = (v | v << 2) & 0x1249_2492_4924_9249;
        v
    };
    let mut keyed: Vec<(u64, usize)> = csm_model::concat_parts_with(parts, |&(i, p)| {
        let code = spread(quantise(p.x, 0))
            | spread(quantise(p.y, 1)) << 1
            | spread(quantise(p.z, 2)) << 2;
        (code, i)
    });
    // The positions are unique: one order, whatever the sort.
    keyed.par_sort_unstable();
    keyed.into_par_iter().map(|(_, i)| i).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The curve of centres given in parts is the curve of the parts joined: parts of many
    /// sizes (empty ones among them) on pools of 1–3 threads, against the one-list order.
    #[test]
    fn the_curve_of_parts_is_the_curve_of_their_list() {
        // A scattered cloud of 10,000 centres, positions in a shuffled order.
        let centres: Vec<(usize, Point)> = (0..10_000usize)
            .map(|k| {
                let t = k as Real;
                let at = Point::new((t * 0.37).sin() * 5.0, (t * 0.11).cos() * 3.0, t * 1e-3);
                ((k * 7919) % 10_000, at)
            })
            .collect();
        let whole = morton_order_of(&centres);
        assert_ne!(whole, (0..10_000).collect::<Vec<_>>());
        let mut parts: Vec<&[(usize, Point)]> = Vec::new();
        let (mut start, mut size) = (0, 0);
        while start < centres.len() {
            let end = (start + size).min(centres.len());
            parts.push(&centres[start..end]);
            (start, size) = (end, size * 2 + 1);
        }
        for threads in [1, 2, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            assert_eq!(pool.install(|| morton_order_of_parts(&parts)), whole);
        }
    }
}
