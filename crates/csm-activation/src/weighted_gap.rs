//! ComputeWeightedReaction: the explicit weighted gap of the paired conditions (§10.3).

use csm_geometry::Geometry;
use csm_geometry::math::Real;
use csm_geometry::{
    MortarMode, OperatorSettings, SegmentationSettings, dual_basis, exact_segmentation,
    integration_points, mortar_operators,
};
use csm_model::{ConditionIdx, ModelPart, PartIdx, ScalarVar};
use rayon::prelude::*;

use crate::error::Error;
use crate::mapping::{face_data, make_face};

/// A pair contributes only if `overlap area / slave area > WEIGHTED_GAP_AREA_RATIO`.
pub const WEIGHTED_GAP_AREA_RATIO: Real = 1e-5;

/// `ComputeWeightedReaction` for a frictionless setup: `WEIGHTED_GAP := 0` on the nodes of
/// `sub`, then every paired condition `(slave, master)` adds `−n_i · (D x_s − M x_m)_i` to
/// its slave nodes (dual basis, explicit operator settings, current coordinates, nodal
/// `NORMAL`; the slave normal is the slave condition's normal, the master normal the master
/// condition's). Returns, per pair, Kratos' condition flag ISOLATED: true where the pair
/// contributed nothing (no overlap above [`WEIGHTED_GAP_AREA_RATIO`] of the slave's area).
/// Nothing happens, and nothing is returned, when the model has no `WEIGHTED_GAP`.
///
/// Errors: a face the mortar routines refuse.
pub fn compute_weighted_gap(
    model: &mut ModelPart,
    sub: PartIdx,
    pairs: &[(ConditionIdx, ConditionIdx)],
    mode: MortarMode,
    distance_threshold: Real,
    dim: usize,
) -> Result<Vec<bool>, Error> {
    if !model.nodal_data().has_scalar(ScalarVar::WeightedGap) {
        return Ok(Vec::new());
    }
    let dim = dim.clamp(1, 3);
    let sub_nodes = model.part(sub).nodes().to_vec();
    let n_nodes = model.nodes().len();
    let mut wg = model
        .nodal_data()
        .scalar(ScalarVar::WeightedGap, 0)
        .map_or_else(|| vec![0.0; n_nodes], <[Real]>::to_vec);
    for n in &sub_nodes {
        wg[n.index()] = 0.0;
    }
    let seg_settings = SegmentationSettings {
        mode,
        distance_threshold,
    };
    let op_settings = OperatorSettings::explicit();
    // Every pair's contribution in parallel, added below in pair order (Kratos' sums).
    let m = &*model;
    let contributions: Vec<Result<Option<PairGap>, Error>> = pairs
        .par_iter()
        .map(|&(sc, mc)| pair_weighted_gap(m, sc, mc, &seg_settings, &op_settings, dim))
        .collect();
    let mut isolated = Vec::with_capacity(pairs.len());
    for contribution in contributions {
        let contribution = contribution?;
        isolated.push(contribution.is_none());
        let Some(pair) = contribution else {
            continue;
        };
        for (n, g) in model
            .conditions()
            .nodes(pair.slave.index())
            .iter()
            .zip(&pair.gaps)
        {
            wg[n.index()] += g;
        }
    }
    if let Some(col) = model.nodal_data_mut().scalar_mut(ScalarVar::WeightedGap, 0) {
        col.copy_from_slice(&wg);
    }
    Ok(isolated)
}

/// One pair's weighted-gap contribution per slave node (in node order).
struct PairGap {
    slave: ConditionIdx,
    gaps: Vec<Real>,
}

/// The contribution of the pair `(sc, mc)`, `None` when it has no overlap above
/// [`WEIGHTED_GAP_AREA_RATIO`] of the slave's area.
fn pair_weighted_gap(
    model: &ModelPart,
    sc: ConditionIdx,
    mc: ConditionIdx,
    seg_settings: &SegmentationSettings,
    op_settings: &OperatorSettings,
    dim: usize,
) -> Result<Option<PairGap>, Error> {
    let slave_id = model.conditions().ids()[sc.index()];
    let sdata = face_data(model, sc);
    let mdata = face_data(model, mc);
    let slave = make_face(model, sc, &sdata)?;
    let master = make_face(model, mc, &mdata)?;
    let wrap =
        |what: &'static str| move |e: csm_geometry::Error| Error::condition(what, slave_id, &e);
    let Some(seg) =
        exact_segmentation(&slave, &master, seg_settings).map_err(wrap("mortar segmentation"))?
    else {
        return Ok(None);
    };
    let slave_area = Geometry::new(model.conditions().kind(sc.index()), &sdata.points)
        .and_then(|g| g.area())
        .map_err(wrap("area"))?;
    if seg.cells().is_empty() || seg.overlap_area() / slave_area <= WEIGHTED_GAP_AREA_RATIO {
        return Ok(None);
    }
    let gps = integration_points(&slave, &master, &seg, op_settings)
        .map_err(wrap("mortar integration"))?;
    let basis = dual_basis(&slave, &gps);
    let ops = mortar_operators(&slave, &master, &gps, Some(&basis));
    // Kratos: `D_x1_M_x2 = prod(D, x1) − prod(M, x2)`, then
    // `WEIGHTED_GAP_i += inner_prod(row_i, −n_i)` (sums in index order from 0).
    let gaps = (0..sdata.points.len())
        .map(|i| {
            let normal = sdata.nodal_normals[i];
            let mut g = 0.0;
            for k in 0..dim {
                let mut dx = 0.0;
                for (j, p) in sdata.points.iter().enumerate() {
                    dx += ops.d[(i, j)] * p[k];
                }
                let mut mx = 0.0;
                for (j, p) in mdata.points.iter().enumerate() {
                    mx += ops.m[(i, j)] * p[k];
                }
                g += (dx - mx) * -normal[k];
            }
            g
        })
        .collect();
    Ok(Some(PairGap { slave: sc, gaps }))
}
