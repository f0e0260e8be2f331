//! The node coordinates of many conditions, gathered a run at a time.

use csm_geometry::math::Point;

use crate::{ConditionIdx, ModelPart};

/// Conditions per [`GatheredPoints::gather`] that a per-condition loop over a large mesh
/// gathers at a time.
pub const GATHER_BLOCK: usize = 64;

/// The node coordinates of a run of conditions, gathered in one tight loop before they are
/// used.
///
/// The coordinates of a large mesh are not in cache: gathered inside a long per-condition
/// computation, each condition's loads wait on their own, whereas a tight loop over many
/// conditions overlaps them. A per-condition loop therefore gathers [`GATHER_BLOCK`]
/// conditions, then works on their points.
#[derive(Debug, Clone, Default)]
pub struct GatheredPoints {
    points: Vec<Point>,
    /// Per condition, the end of its points (the start is the previous end).
    ends: Vec<usize>,
}

impl GatheredPoints {
    /// Gathers the node coordinates of the conditions `conditions` of `model`, replacing the
    /// previous ones.
    pub fn gather(
        &mut self,
        model: &ModelPart,
        conditions: impl IntoIterator<Item = ConditionIdx>,
    ) {
        self.points.clear();
        self.ends.clear();
        let coordinates = model.nodes().coordinates();
        for c in conditions {
            let nodes = model.conditions().nodes(c.index());
            self.points
                .extend(nodes.iter().map(|n| coordinates[n.index()]));
            self.ends.push(self.points.len());
        }
    }

    /// The number of conditions gathered.
    pub fn len(&self) -> usize {
        self.ends.len()
    }

    /// Whether no condition was gathered.
    pub fn is_empty(&self) -> bool {
        self.ends.is_empty()
    }

    /// The node coordinates of the `k`-th condition gathered, in node order.
    ///
    /// # Panics
    ///
    /// If `k` is not below [`len`](Self::len).
    pub fn points(&self, k: usize) -> &[Point] {
        let start = if k == 0 { 0 } else { self.ends[k - 1] };
        &self.points[start..self.ends[k]]
    }
}

#[cfg(test)]
mod tests {
    use csm_geometry::GeometryKind;

    use super::*;
    use crate::{ConditionId, NodeId, PropertiesId};

    #[test]
    fn gathered_points_are_each_conditions_points_in_order() {
        let mut mp = ModelPart::new("Structure");
        for (i, (x, y)) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
            .iter()
            .enumerate()
        {
            mp.add_node(NodeId(10 + i as u32), Point::new(*x, *y, 0.5 * x))
                .unwrap();
        }
        let kinds = [
            (GeometryKind::Quadrilateral3D4, &[10, 11, 12, 13][..]),
            (GeometryKind::Triangle3D3, &[12, 10, 13][..]),
            (GeometryKind::Line2D2, &[13, 11][..]),
        ];
        for (i, (kind, nodes)) in kinds.iter().enumerate() {
            let ids: Vec<NodeId> = nodes.iter().map(|&n| NodeId(n)).collect();
            mp.add_condition(ConditionId(i as u32 + 1), *kind, "", &ids, PropertiesId(0))
                .unwrap();
        }
        let mut gathered = GatheredPoints::default();
        assert!(gathered.is_empty());
        for order in [vec![0, 1, 2], vec![2, 0], vec![1, 1]] {
            gathered.gather(&mp, order.iter().map(|&c| ConditionIdx(c)));
            assert_eq!(gathered.len(), order.len());
            for (k, &c) in order.iter().enumerate() {
                let mut one = Vec::new();
                mp.gather_points(mp.conditions().nodes(c as usize), &mut one);
                assert_eq!(gathered.points(k), &one[..], "{order:?}, condition {k}");
            }
        }
        gathered.gather(&mp, []);
        assert!(gathered.is_empty());
    }
}
