//! The octree path (`type_search = OctreeWithOBB`, Kratos `SearchUsingOcTree` with
//! `FindIntersectedGeometricalObjectsWithOBBContactSearchProcess`, reference §8).
//!
//! 1. `hmax` = max NODAL_H over the slave-part and master-part nodes (1.0 below ε);
//!    `bbf = bounding_box_factor · hmax`; BOUNDARY (OBB tests) iff `bbf > 0`.
//! 2. The root box over the slave-part and master-part nodes (`root_box::root_box`).
//! 3. The octree (Kratos' `OctreeBinary`, `csm_trees::Octree`) is refined around every master
//!    node, then every master condition (ascending id) is stored in every leaf whose box (grown
//!    by the absolute cell tolerance, Q17) meets its geometry (`pieces`: segment/box,
//!    triangle/box; other kinds never, Q16).
//! 4. A serial loop over the ContactSub conditions in ascending id order with ACTIVE defined:
//!    the leaves the condition meets (same test); for a SLAVE condition `MarkIfIntersected`
//!    (SELECTED on the slave and on every master of its leaves whose OBB — or, with `bbf ≤ 0`,
//!    whose geometry — meets the slave's); then, if the condition Is(SELECTED), every SELECTED
//!    master of its leaves, leaf by leaf in stored order: MappingCheck → `CheckGeometricalObject`
//!    and `INDEX_MAP.AddId`; No/DirectCheck → `AddPotentialPairing` with the master's unit
//!    normal at local (0,0,0), once per leaf (Q15).
//!
//! `compatibility: kratos` reproduces the quirks: every condition with ACTIVE defined enters
//! the loop, so a MASTER condition still SELECTED by an earlier slave pairs with the stale
//! SELECTED masters of its leaves (master–master pairs, Q14); a master met in several leaves
//! of a slave is paired once per leaf (duplicate pairs with No/DirectCheck, Q15); non-linear
//! faces are never inserted nor searched (Q16); the root box follows DOMAIN_SIZE and the
//! lower/higher coefficients (a flat interface lies on the box's lower face, Q17).
//! `compatibility: robust` fixes them: only slave conditions pair (the SELECTED flags they use
//! were all reset and recomputed for them), each master at most once per slave; with OBBs
//! (`bbf > 0`) masters are stored in, and slaves query, the leaves met by the AABB of their
//! OBB, and the root box covers every OBB — so every pair whose OBBs intersect shares a leaf
//! and is found (Kratos stores and queries the bare geometry, so faces a gap wider than the
//! local leaves apart are lost although their OBBs meet); quadratic faces are handled (by
//! their OBBs, or by their linear sub-pieces without OBBs, Q16); and a flat root box gets real
//! thickness around the interface instead of lying on its face.
//!
//! Faces Kratos cannot insert are reported as warnings in [`OctreeReport`] (the driver does not
//! collect them yet).

mod pieces;
mod root_box;

#[cfg(test)]
mod tests;

use std::collections::BTreeSet;

use csm_geometry::math::{EPS, Point, Real, Vector};
use csm_geometry::{Geometry, GeometryKind, ObbIntersection, SatMode};
use csm_model::{ConditionId, ConditionIdx, Flag, ModelPart, NodeIdx, PartIdx, ScalarVar};
use csm_trees::{LeafId, Octree};

use super::candidates::{Bv, PerMaster, QueryContext, direct_check_nodes, slave_search_nodes};
use super::filters::passes_orientation;
use super::pairing::direct_check_count;
use crate::error::{Error, ErrorKind};
use crate::setup::{CheckGap, Compatibility, ObbIntersectionType, SearchParameters};
use pieces::{Piece, linear_pieces, overlaps_cell, pieces_intersect};

/// What the octree search of one pair needs besides the model.
#[derive(Debug)]
pub(crate) struct OctreeContext<'a> {
    pub params: &'a SearchParameters,
    /// `Contact.ContactSub<key>`.
    pub sub: PartIdx,
    pub dim: usize,
    pub slave_nodes: usize,
    pub compatibility: Compatibility,
    pub domain_size: u32,
    /// Robust mode: the nodes ACTIVE before the pairing (`pairing::direct_check_count`).
    pub active_before: Option<Vec<bool>>,
}

/// What one octree search saw, besides the pairs (for tests and warnings).
#[derive(Debug, Default, Clone)]
pub(crate) struct OctreeReport {
    /// Conditions the octree could not test (Kratos mode: non-linear faces, Q16).
    pub warnings: Vec<String>,
    /// The root box; `None` when no octree was built (a side without nodes).
    pub root: Option<(Point, Point)>,
    /// `bounding_box_factor · hmax`.
    pub bbf: Real,
    /// Number of leaves of the octree.
    pub n_leaves: usize,
}

fn geometry_error(model: &ModelPart, c: ConditionIdx, message: String) -> Error {
    ErrorKind::Geometry {
        condition: model.conditions().ids()[c.index()],
        message,
    }
    .into()
}

fn tree_error(e: csm_trees::Error) -> Error {
    ErrorKind::Model(format!("octree of the master conditions: {e}")).into()
}

fn points_of(model: &ModelPart, c: ConditionIdx) -> Vec<Point> {
    let mut out = Vec::new();
    model.gather_points(model.conditions().nodes(c.index()), &mut out);
    out
}

/// The object-vs-leaf test of one condition.
enum CellTest {
    /// Kratos' `IsIntersected`: segment/box, triangle/box.
    Pieces(Vec<Piece>),
    /// Robust with OBBs: the AABB of the condition's OBB.
    Box(csm_trees::Aabb),
}

impl CellTest {
    fn overlaps(&self, cell: &csm_trees::Aabb) -> bool {
        match self {
            CellTest::Pieces(p) => overlaps_cell(p, cell),
            CellTest::Box(b) => cell.intersects(b),
        }
    }
}

/// The per-step state of the serial loop.
struct Search<'a> {
    cx: &'a OctreeContext<'a>,
    octree: Octree<ConditionIdx>,
    bbf: Real,
    robust: bool,
    /// Linear pieces by condition index (`None`: not computed yet / not testable).
    pieces: Vec<Option<Option<Vec<Piece>>>>,
    /// Whole-face OBBs by condition index, built on first use.
    bvs: Vec<Option<Bv>>,
}

impl Search<'_> {
    fn pieces(&mut self, model: &ModelPart, c: ConditionIdx) -> Option<&[Piece]> {
        let slot = &mut self.pieces[c.index()];
        if slot.is_none() {
            let kind = model.conditions().kind(c.index());
            *slot = Some(linear_pieces(kind, &points_of(model, c), self.robust));
        }
        slot.as_ref().and_then(|p| p.as_deref())
    }

    /// How condition `c` is tested against a leaf box, and its bounding box: Kratos (and robust
    /// without OBBs) by its linear pieces within the AABB of its nodes; robust with OBBs by the
    /// AABB of its OBB. `None`: never in a leaf (Kratos: a non-linear face, Q16).
    fn cell_test(
        &mut self,
        model: &ModelPart,
        c: ConditionIdx,
    ) -> Result<Option<(CellTest, csm_trees::Aabb)>, Error> {
        if self.robust && self.bbf > 0.0 {
            let aabb = match self.bv(model, c)? {
                Bv::D2(o) => o.aabb(),
                Bv::D3(o) => o.aabb(),
            };
            let aabb = csm_trees::Aabb::new(aabb.min, aabb.max);
            return Ok(Some((CellTest::Box(aabb), aabb)));
        }
        let points = points_of(model, c);
        let Some(aabb) = csm_trees::Aabb::from_points(&points) else {
            return Ok(None);
        };
        Ok(self
            .pieces(model, c)
            .map(|p| (CellTest::Pieces(p.to_vec()), aabb)))
    }

    /// The leaves condition `c` meets (empty when it cannot be tested).
    fn leaves(
        &mut self,
        model: &ModelPart,
        c: ConditionIdx,
        out: &mut Vec<LeafId>,
    ) -> Result<(), Error> {
        out.clear();
        let Some((test, aabb)) = self.cell_test(model, c)? else {
            return Ok(());
        };
        self.octree
            .intersected_leaves_with(&aabb, |cell| test.overlaps(cell), out)
            .map_err(tree_error)
    }

    fn bv(&mut self, model: &ModelPart, c: ConditionIdx) -> Result<Bv, Error> {
        if let Some(bv) = self.bvs[c.index()] {
            return Ok(bv);
        }
        let points = points_of(model, c);
        let kind = model.conditions().kind(c.index());
        let bv = Geometry::new(kind, &points)
            .and_then(|g| {
                Bv::build(
                    &g,
                    self.cx.dim,
                    self.bbf,
                    self.cx.params.octree.build_from_bounding_box,
                    self.cx.compatibility,
                )
            })
            .map_err(|e| geometry_error(model, c, e.to_string()))?;
        self.bvs[c.index()] = Some(bv);
        Ok(bv)
    }

    /// Kratos' `HasIntersection(S, M)`: with BOUNDARY one OBB per whole face and the SAT or
    /// Direct test of `OBB_intersection_type`; without, the exact face–face test.
    fn has_intersection(
        &mut self,
        model: &ModelPart,
        s: ConditionIdx,
        m: ConditionIdx,
    ) -> Result<bool, Error> {
        if self.bbf > 0.0 {
            let (a, b) = (self.bv(model, s)?, self.bv(model, m)?);
            let kind = match self.cx.params.octree.obb_intersection_type {
                ObbIntersectionType::SeparatingAxisTheorem => ObbIntersection::Sat,
                ObbIntersectionType::Direct => ObbIntersection::Direct,
            };
            let mode = if self.robust {
                SatMode::Robust
            } else {
                SatMode::Kratos
            };
            Ok(match (a, b) {
                (Bv::D2(a), Bv::D2(b)) => a.intersects(&b, kind, mode),
                (Bv::D3(a), Bv::D3(b)) => a.intersects(&b, kind, mode),
                // Both boxes of one search have the same dimension.
                _ => true,
            })
        } else {
            let pa = self.pieces(model, s).map(<[Piece]>::to_vec);
            let pb = self.pieces(model, m);
            Ok(match (pa, pb) {
                (Some(pa), Some(pb)) => pieces_intersect(&pa, pb),
                _ => false,
            })
        }
    }

    /// `MarkIfIntersected` for a SLAVE condition `s` with leaves `leaves`.
    fn mark_if_intersected(
        &mut self,
        model: &mut ModelPart,
        s: ConditionIdx,
        leaves: &[LeafId],
    ) -> Result<(), Error> {
        model.conditions_mut().flags_mut()[s.index()].reset(Flag::SELECTED);
        for &leaf in leaves {
            let items = self.octree.leaf_items(leaf).to_vec();
            let flags = model.conditions_mut().flags_mut();
            for m in &items {
                if !flags[m.index()].is(Flag::VISITED) {
                    flags[m.index()].reset(Flag::SELECTED);
                }
            }
            for m in items {
                if model.conditions().flags()[m.index()].is(Flag::VISITED) {
                    continue;
                }
                if self.has_intersection(model, s, m)? {
                    let flags = model.conditions_mut().flags_mut();
                    flags[s.index()].set(Flag::SELECTED, true);
                    flags[m.index()].set(Flag::SELECTED, true);
                }
                model.conditions_mut().flags_mut()[m.index()].set(Flag::VISITED, true);
            }
        }
        for &leaf in leaves {
            for m in self.octree.leaf_items(leaf) {
                model.conditions_mut().flags_mut()[m.index()].reset(Flag::VISITED);
            }
        }
        Ok(())
    }
}

/// SearchUsingOcTree (§8): fills the slaves' INDEX_MAPs (MappingCheck) or pushes the created
/// (slave, master) pairs (No/DirectCheck); returns what it saw (warnings, root box, bbf).
pub(crate) fn search_octree_report(
    model: &mut ModelPart,
    cx: &OctreeContext<'_>,
    created: &mut Vec<(ConditionIdx, ConditionIdx)>,
) -> Result<OctreeReport, Error> {
    let p = cx.params;
    if p.inverted_search {
        return Err(ErrorKind::RejectedByKratos(
            "the octree search does not support inverted_search (Kratos errors too)".to_owned(),
        )
        .into());
    }
    let robust = cx.compatibility == Compatibility::Robust;
    let mut report = OctreeReport::default();

    // SetOriginDestinationModelParts: the slave and master sides of ContactSub.
    let ids = model.conditions().ids();
    let mut conditions = model.part(cx.sub).conditions().to_vec();
    conditions.sort_by_key(|c| ids[c.index()]);
    let node_flags = model.nodes().flags();
    let side_nodes = |flag: Flag| -> Vec<NodeIdx> {
        let mut v: Vec<NodeIdx> = model
            .part(cx.sub)
            .nodes()
            .iter()
            .copied()
            .filter(|n| node_flags[n.index()].is(flag))
            .collect();
        v.sort_by_key(|n| model.nodes().ids()[n.index()]);
        v
    };
    let slave_nodes = side_nodes(Flag::SLAVE);
    let master_nodes = side_nodes(Flag::MASTER);
    let masters: Vec<ConditionIdx> = conditions
        .iter()
        .copied()
        .filter(|c| model.conditions().flags()[c.index()].is(Flag::MASTER))
        .collect();
    if slave_nodes.is_empty() || master_nodes.is_empty() {
        // Kratos builds no octree without slave nodes; the caller rejects empty sides.
        return Ok(report);
    }

    // 1. hmax and the OBB enlargement.
    let h = model
        .nodal_data()
        .scalar(ScalarVar::NodalH, 0)
        .unwrap_or(&[]);
    let hmax = slave_nodes
        .iter()
        .chain(&master_nodes)
        .map(|n| h.get(n.index()).copied().unwrap_or(0.0))
        .fold(0.0, Real::max);
    let hmax = if hmax < EPS { 1.0 } else { hmax };
    let bbf = p.octree.bounding_box_factor * hmax;
    report.bbf = bbf;

    // 2. The root box. Robust with OBBs: it also covers the OBB of every slave-side and
    // master condition, so every point two OBBs share lies in a leaf.
    let mut search = Search {
        cx,
        octree: Octree::with_kratos_params(Point::origin(), Point::new(1.0, 1.0, 1.0))
            .map_err(tree_error)?,
        bbf,
        robust,
        pieces: vec![None; model.conditions().len()],
        bvs: vec![None; model.conditions().len()],
    };
    let coords = model.nodes().coordinates();
    let mut box_points: Vec<Point> = slave_nodes
        .iter()
        .chain(&master_nodes)
        .map(|n| coords[n.index()])
        .collect();
    if robust && bbf > 0.0 {
        for &c in &conditions {
            let f = model.conditions().flags()[c.index()];
            if f.is(Flag::MASTER) || (f.is(Flag::SLAVE) && f.is_defined(Flag::ACTIVE)) {
                let aabb = match search.bv(model, c)? {
                    Bv::D2(o) => o.aabb(),
                    Bv::D3(o) => o.aabb(),
                };
                box_points.extend([aabb.min, aabb.max]);
            }
        }
    }
    let Some((low, high)) = root_box::root_box(
        &box_points,
        bbf,
        &p.octree,
        cx.domain_size,
        cx.compatibility,
    ) else {
        return Ok(report);
    };
    report.root = Some((low, high));

    // 3. Refine around the master nodes, then store the master conditions.
    search.octree = Octree::with_kratos_params(low, high).map_err(tree_error)?;
    for n in &master_nodes {
        search
            .octree
            .insert_point(&model.nodes().coordinates()[n.index()])
            .map_err(tree_error)?;
    }
    let mut untestable: BTreeSet<GeometryKind> = BTreeSet::new();
    for &m in &masters {
        let Some((test, aabb)) = search.cell_test(model, m)? else {
            untestable.insert(model.conditions().kind(m.index()));
            continue;
        };
        search
            .octree
            .insert_with(m, &aabb, |cell| test.overlaps(cell))
            .map_err(tree_error)?;
    }
    for kind in &untestable {
        report.warnings.push(format!(
            "octree_with_obb: {} conditions are never stored in the octree nor searched \
             (Kratos' octree only tests Line2D2, Triangle3D3 and Quadrilateral3D4, Q16); use \
             `compatibility: robust` to search them through their linear sub-pieces",
            kind.name()
        ));
    }
    report.n_leaves = search.octree.n_leaves();

    // 4. The serial loop.
    let nodal_h = h.to_vec();
    let acf = model
        .process_info()
        .number("ACTIVE_CHECK_FACTOR")
        .unwrap_or(0.0);
    let mut leaves = Vec::new();
    let mut paired: Vec<ConditionIdx> = Vec::new();
    for &c in &conditions {
        let flags = model.conditions().flags()[c.index()];
        if !flags.is_defined(Flag::ACTIVE) {
            continue;
        }
        let is_slave = flags.is(Flag::SLAVE);
        // Robust: only slaves pair (Q14). Kratos: a non-slave condition only matters when it
        // is (stale) SELECTED; its leaves have no other effect.
        if !is_slave && (robust || !flags.is(Flag::SELECTED)) {
            continue;
        }
        search.leaves(model, c, &mut leaves)?;
        if is_slave {
            search.mark_if_intersected(model, c, &leaves)?;
        }
        if !model.conditions().flags()[c.index()].is(Flag::SELECTED) {
            continue;
        }
        paired.clear();
        let slave_id = ConditionId(model.conditions().ids()[c.index()]);
        for &leaf in &leaves {
            for &m in search.octree.leaf_items(leaf) {
                if !model.conditions().flags()[m.index()].is(Flag::SELECTED) {
                    continue;
                }
                if robust {
                    // Q15: each master once per slave.
                    if paired.contains(&m) {
                        continue;
                    }
                    paired.push(m);
                }
                let master_id = ConditionId(model.conditions().ids()[m.index()]);
                match p.check_gap {
                    CheckGap::MappingCheck => {
                        // CheckGeometricalObject: not itself, not facing the same way, not
                        // already in the map.
                        let normals = model.condition_normals();
                        if passes_orientation(
                            slave_id.get(),
                            master_id.get(),
                            &normals[c.index()],
                            &normals[m.index()],
                            p.normal_orientation_threshold,
                        ) && !model.index_map(c).contains(master_id)
                        {
                            model.index_map_mut(c).add_id(master_id);
                        }
                    }
                    CheckGap::NoCheck | CheckGap::DirectCheck => {
                        let node_pass = match p.check_gap {
                            CheckGap::DirectCheck => {
                                let n_c = master_unit_normal(model, m)?;
                                let qcx = QueryContext {
                                    model,
                                    params: p,
                                    obb_test: false,
                                    kdop: false,
                                    bbf,
                                    dim: cx.dim,
                                    slave_nodes: cx.slave_nodes,
                                    compatibility: cx.compatibility,
                                    delta: None,
                                    nodal_normals: &[],
                                    nodal_h: &nodal_h,
                                    active_check_factor: acf,
                                    master_bvs: &PerMaster::none(),
                                    master_kdops: &PerMaster::none(),
                                };
                                direct_check_nodes(&qcx, c, m, &n_c)?
                            }
                            _ => 0,
                        };
                        if add_potential_pairing(model, cx, c, node_pass) {
                            model.index_map_mut(c).add_id(master_id);
                            if p.create_auxiliar_conditions {
                                created.push((c, m));
                            }
                        }
                    }
                }
            }
        }
    }
    Ok(report)
}

/// The master normal of the octree's `AddPotentialPairing`: `UnitNormal` at local (0,0,0).
fn master_unit_normal(model: &ModelPart, m: ConditionIdx) -> Result<Vector, Error> {
    let points = points_of(model, m);
    Geometry::new(model.conditions().kind(m.index()), &points)
        .and_then(|g| g.unit_normal(&Point::origin()))
        .map_err(|e| geometry_error(model, m, e.to_string()))
}

/// `AddPotentialPairing`'s activation (reference §10.4), as the kd-tree path applies it:
/// NoCheck activates every slave node and pairs; DirectCheck counts the nodes already ACTIVE
/// and activates those in `node_pass`, and pairs when one counted. Returns whether to pair.
fn add_potential_pairing(
    model: &mut ModelPart,
    cx: &OctreeContext<'_>,
    s: ConditionIdx,
    node_pass: u32,
) -> bool {
    let nodes: Vec<NodeIdx> = slave_search_nodes(model, s, cx.slave_nodes).to_vec();
    let flags = model.nodes_mut().flags_mut();
    match cx.params.check_gap {
        CheckGap::DirectCheck => {
            direct_check_count(flags, &nodes, node_pass, cx.active_before.as_deref())
        }
        _ => {
            for n in &nodes {
                flags[n.index()].set(Flag::ACTIVE, true);
            }
            true
        }
    }
}
