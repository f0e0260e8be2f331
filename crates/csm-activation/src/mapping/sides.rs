//! The slave and master sides of a ContactSub and the mapper's slave-node numbering.

use csm_geometry::math::Real;
use csm_model::{ConditionIdx, Flag, ModelPart, NodeIdx, PartIdx, ScalarVar};
use rayon::prelude::*;

/// The slave and master sides of a ContactSub (Kratos' `SlaveSubModelPart` /
/// `MasterSubModelPart`, §5.1): entities with `SLAVE != inverted`, resp. `MASTER != inverted`.
#[derive(Debug, Clone, Default)]
pub(crate) struct Sides {
    pub slave_conditions: Vec<ConditionIdx>,
    pub master_conditions: Vec<ConditionIdx>,
    pub slave_nodes: Vec<NodeIdx>,
    pub master_nodes: Vec<NodeIdx>,
}

pub(crate) fn sides(model: &ModelPart, sub: PartIdx, inverted: bool) -> Sides {
    let cflags = model.conditions().flags();
    let nflags = model.nodes().flags();
    let nodes = model.part(sub).nodes();
    // Each side keeps the order of its list (a filter in parallel, collected in order). The
    // four lists are filtered side by side: each collect ends in a copy on one thread.
    let conditions_with = |conditions: &[ConditionIdx], flag: Flag| -> Vec<ConditionIdx> {
        conditions
            .par_iter()
            .copied()
            .filter(|c| cflags[c.index()].is(flag) != inverted)
            .collect()
    };
    let nodes_with = |flag: Flag| -> Vec<NodeIdx> {
        nodes
            .par_iter()
            .copied()
            .filter(|n| nflags[n.index()].is(flag) != inverted)
            .collect()
    };
    let ((slave_conditions, master_conditions), (slave_nodes, master_nodes)) = rayon::join(
        || {
            let conditions = model.part_conditions_by_id(sub);
            rayon::join(
                || conditions_with(&conditions, Flag::SLAVE),
                || conditions_with(&conditions, Flag::MASTER),
            )
        },
        || rayon::join(|| nodes_with(Flag::SLAVE), || nodes_with(Flag::MASTER)),
    );
    Sides {
        slave_conditions,
        master_conditions,
        slave_nodes,
        master_nodes,
    }
}

/// The Advanced search's `DISTANCE_THRESHOLD` (§10.1): `max(mean NODAL_H of the slave side,
/// mean NODAL_H of the master side)` of ContactSub `sub` (a side without nodes, or a model
/// without NODAL_H, counts 0). Reads the sides' nodes in the part's order, without listing
/// them.
pub fn mean_h(model: &ModelPart, sub: PartIdx, inverted: bool) -> Real {
    let Some(h) = model.nodal_data().scalar(ScalarVar::NodalH, 0) else {
        return 0.0;
    };
    let nflags = model.nodes().flags();
    // The side's values are gathered in parallel (in the part's order), then summed in that
    // order: the bits of the one ordered pass.
    let mean = |flag: Flag| -> Real {
        let values: Vec<Real> = (model.part(sub).nodes().par_iter())
            .filter(|n| nflags[n.index()].is(flag) != inverted)
            .map(|n| h[n.index()])
            .collect();
        match values.len() {
            0 => 0.0,
            count => values.iter().sum::<Real>() / count as Real,
        }
    };
    mean(Flag::SLAVE).max(mean(Flag::MASTER))
}

/// [`mean_h`] of a rank's part in a distributed run: each side's NODAL_H summed over the
/// whole problem's nodes, in ascending id order (the one-process run's order where the nodes
/// are numbered in their order), every node once.
pub fn mean_h_shared(
    model: &ModelPart,
    sub: PartIdx,
    inverted: bool,
    ranks: &csm_model::Ranks,
) -> Result<Real, crate::Error> {
    let h = model.nodal_data().scalar(ScalarVar::NodalH, 0);
    let nflags = model.nodes().flags();
    let ids = model.nodes().ids();
    let mut means = [0.0; 2];
    for (mean, flag) in means.iter_mut().zip([Flag::SLAVE, Flag::MASTER]) {
        let terms: Vec<(u32, [Real; 3])> = match h {
            Some(h) => (model.part(sub).nodes().iter())
                .filter(|n| nflags[n.index()].is(flag) != inverted)
                .map(|n| (ids[n.index()], [h[n.index()], 0.0, 0.0]))
                .collect(),
            None => Vec::new(),
        };
        let all = ranks.terms(&terms).map_err(crate::Error::aborted)?;
        if !all.is_empty() {
            *mean = all.iter().map(|t| t.1[0]).sum::<Real>() / all.len() as Real;
        }
    }
    Ok(means[0].max(means[1]))
}

/// The positions of the slave nodes in [`Sides::slave_nodes`] by node index: the mapper's
/// arrays by slave node.
pub(crate) struct SlavePositions(Vec<u32>);

impl SlavePositions {
    /// Not a slave node.
    const NONE: u32 = u32::MAX;

    pub(crate) fn new(s: &Sides, n_nodes: usize) -> SlavePositions {
        let mut positions = vec![SlavePositions::NONE; n_nodes];
        // (Positions below `n_nodes`, which a u32 index holds.)
        let at = |j: usize| s.slave_nodes[j].index();
        csm_model::write_at_ascending(&mut positions, s.slave_nodes.len(), at, |j, p| {
            *p = j as u32;
        });
        SlavePositions(positions)
    }

    /// The position of node `n` among the slave nodes, if it is one.
    pub(super) fn get(&self, n: NodeIdx) -> Option<usize> {
        let j = self.0[n.index()];
        (j != SlavePositions::NONE).then_some(j as usize)
    }
}
