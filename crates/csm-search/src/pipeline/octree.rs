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
//! 4. A loop over the ContactSub conditions in ascending id order with ACTIVE defined:
//!    the leaves the condition meets (same test); for a SLAVE condition `MarkIfIntersected`
//!    (SELECTED on the slave and on every master of its leaves whose OBB — or, with `bbf ≤ 0`,
//!    whose geometry — meets the slave's); then, if the condition Is(SELECTED), every SELECTED
//!    master of its leaves, leaf by leaf in stored order: MappingCheck → `CheckGeometricalObject`
//!    and `INDEX_MAP.AddId`; No/DirectCheck → `AddPotentialPairing` with the master's unit
//!    normal at local (0,0,0), once per leaf (Q15).
//!
//! What only reads the model runs in parallel: each master's leaves before the masters are
//! stored (in ascending id order, so each leaf lists them as Kratos' insertions do), and each
//! slave's leaves and the answers of its `HasIntersection` calls, in the order the serial
//! `MarkIfIntersected` makes them (each master of its leaves at its first visit). The flags,
//! the pairings and the errors then follow the serial loop, condition by condition: the
//! result is Kratos' loop's for any thread count.
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
use std::sync::OnceLock;

use rayon::prelude::*;

use csm_geometry::math::{EPS, Point, Real, Vector};
use csm_geometry::{Geometry, GeometryKind, MAX_FACE_NODES, ObbIntersection, SatMode};
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
    /// The whole problem's largest NODAL_H, where given (`PairGlobals`).
    pub largest_nodal_h: Option<Real>,
    /// A distributed run: this rank's part in it (the largest NODAL_H is then the ranks').
    pub ranks: Option<&'a csm_model::Ranks>,
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
    /// The largest NODAL_H of the contact nodes (before the 1-below-ε rule), or the given one.
    pub hmax: Real,
    /// Number of leaves of the octree.
    pub n_leaves: usize,
}

/// The lowest and the highest corner of the points of every rank (`points` this rank's):
/// two points whose box is that of all of them, or none where no rank has a point.
fn whole_extent(points: &[Point], ranks: &csm_model::Ranks) -> Result<Vec<Point>, Error> {
    let mut low = [Real::INFINITY; 3];
    let mut high = [Real::NEG_INFINITY; 3];
    for p in points {
        for k in 0..3 {
            low[k] = low[k].min(p[k]);
            high[k] = high[k].max(p[k]);
        }
    }
    // Three maxima of the negated lows and three of the highs: one exchange each.
    for k in 0..3 {
        low[k] = -ranks.max(-low[k])?;
        high[k] = ranks.max(high[k])?;
    }
    if low.iter().zip(&high).any(|(l, h)| l > h) {
        return Ok(Vec::new());
    }
    Ok(vec![Point::from(low), Point::from(high)])
}

fn geometry_error(model: &ModelPart, c: ConditionIdx, message: String) -> Error {
    ErrorKind::Geometry {
        condition: model.conditions().ids()[c.index()],
        message,
    }
    .into()
}

fn tree_error(e: csm_trees::Error) -> Error {
    Error::tree("octree of the master conditions", e)
}

fn points_of(model: &ModelPart, c: ConditionIdx) -> Vec<Point> {
    let mut out = Vec::new();
    model.gather_points(model.conditions().nodes(c.index()), &mut out);
    out
}

/// The object-vs-leaf test of one condition.
enum CellTest<'p> {
    /// Kratos' `IsIntersected`: segment/box, triangle/box.
    Pieces(&'p [Piece]),
    /// Robust with OBBs: the AABB of the condition's OBB.
    Box(csm_geometry::Aabb),
}

impl CellTest<'_> {
    fn overlaps(&self, cell: &csm_geometry::Aabb) -> bool {
        match self {
            CellTest::Pieces(p) => overlaps_cell(p, cell),
            CellTest::Box(b) => cell.intersects(b),
        }
    }
}

/// The per-step state of the search: the octree and the conditions' pieces and boxes, each
/// computed on first use (a function of its condition alone, so which thread computes it
/// first does not matter).
struct Search<'a> {
    cx: &'a OctreeContext<'a>,
    octree: Octree<ConditionIdx>,
    bbf: Real,
    robust: bool,
    /// Linear pieces by condition index (`None` inside: not testable).
    pieces: Vec<OnceLock<Option<Vec<Piece>>>>,
    /// Whole-face OBBs by condition index, or the message of their build's error.
    bvs: Vec<OnceLock<Result<Bv, String>>>,
}

impl Search<'_> {
    fn pieces(&self, model: &ModelPart, c: ConditionIdx) -> Option<&[Piece]> {
        self.pieces[c.index()]
            .get_or_init(|| {
                let kind = model.conditions().kind(c.index());
                linear_pieces(kind, &points_of(model, c), self.robust)
            })
            .as_deref()
    }

    /// How condition `c` is tested against a leaf box, and its bounding box: Kratos (and robust
    /// without OBBs) by its linear pieces within the AABB of its nodes; robust with OBBs by the
    /// AABB of its OBB. `None`: never in a leaf (Kratos: a non-linear face, Q16).
    fn cell_test(
        &self,
        model: &ModelPart,
        c: ConditionIdx,
    ) -> Result<Option<(CellTest<'_>, csm_geometry::Aabb)>, Error> {
        if self.robust && self.bbf > 0.0 {
            let aabb = match self.bv(model, c)? {
                Bv::D2(o) => o.aabb(),
                Bv::D3(o) => o.aabb(),
            };
            return Ok(Some((CellTest::Box(aabb), aabb)));
        }
        let coords = model.nodes().coordinates();
        let nodes = model.conditions().nodes(c.index());
        let Some(aabb) = csm_trees::bounds_of(nodes.iter().map(|n| &coords[n.index()])) else {
            return Ok(None);
        };
        Ok(self.pieces(model, c).map(|p| (CellTest::Pieces(p), aabb)))
    }

    /// The leaves condition `c` meets (empty when it cannot be tested).
    fn leaves(
        &self,
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

    fn bv(&self, model: &ModelPart, c: ConditionIdx) -> Result<Bv, Error> {
        self.bvs[c.index()]
            .get_or_init(|| {
                let points = points_of(model, c);
                let kind = model.conditions().kind(c.index());
                Geometry::new(kind, &points)
                    .and_then(|g| {
                        Bv::build(
                            &g,
                            self.cx.dim,
                            self.bbf,
                            self.cx.params.octree.build_from_bounding_box,
                            self.cx.compatibility,
                        )
                    })
                    .map_err(|e| e.to_string())
            })
            .clone()
            .map_err(|message| geometry_error(model, c, message))
    }

    /// Kratos' `HasIntersection(S, M)`: with BOUNDARY one OBB per whole face and the SAT or
    /// Direct test of `OBB_intersection_type`; without, the exact face–face test.
    fn has_intersection(
        &self,
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
            Ok(match (self.pieces(model, s), self.pieces(model, m)) {
                (Some(pa), Some(pb)) => pieces_intersect(pa, pb),
                _ => false,
            })
        }
    }

    /// The read-only half of `MarkIfIntersected` for a SLAVE condition `s`: its leaves into
    /// `leaves`, and into `outcomes` the answers of `HasIntersection(s, m)` for each master
    /// `m` at its first visit (leaf by leaf, in stored order), in that order: the calls the
    /// serial `MarkIfIntersected` makes, whose answers [`replay_mark`] then applies. `scratch`:
    /// the visits, reused.
    fn mark_outcomes(
        &self,
        model: &ModelPart,
        s: ConditionIdx,
        leaves: &mut Vec<LeafId>,
        outcomes: &mut Vec<bool>,
        scratch: &mut Vec<(ConditionIdx, u32)>,
    ) -> Result<(), Error> {
        self.leaves(model, s, leaves)?;
        // Every visit (master, position); a master's first visit is its lowest position.
        scratch.clear();
        let mut position = 0u32;
        for &leaf in leaves.iter() {
            for &m in self.octree.leaf_items(leaf) {
                scratch.push((m, position));
                position += 1;
            }
        }
        scratch.sort_unstable();
        scratch.dedup_by_key(|(m, _)| *m);
        scratch.sort_unstable_by_key(|&(_, position)| position);
        for &(m, _) in scratch.iter() {
            outcomes.push(self.has_intersection(model, s, m)?);
        }
        Ok(())
    }
}

/// `MarkIfIntersected` for a SLAVE condition `s` with leaves `leaves`, the answers of its
/// `HasIntersection` calls taken in order from `outcomes` ([`Search::mark_outcomes`]): SELECTED
/// is reset on the slave and on every master of its leaves at its first visit, and set on
/// both where the answer is yes; VISITED marks the visited masters meanwhile (it is clear
/// before and after).
fn replay_mark(
    model: &mut ModelPart,
    octree: &Octree<ConditionIdx>,
    s: ConditionIdx,
    leaves: &[LeafId],
    outcomes: &[bool],
) {
    let flags = model.conditions_mut().flags_mut();
    flags[s.index()].reset(Flag::SELECTED);
    let mut answers = outcomes.iter();
    for &leaf in leaves {
        let items = octree.leaf_items(leaf);
        for m in items {
            if !flags[m.index()].is(Flag::VISITED) {
                flags[m.index()].reset(Flag::SELECTED);
            }
        }
        for m in items {
            if flags[m.index()].is(Flag::VISITED) {
                continue;
            }
            // `mark_outcomes` answered every first visit.
            if answers.next().copied().unwrap_or(false) {
                flags[s.index()].set(Flag::SELECTED, true);
                flags[m.index()].set(Flag::SELECTED, true);
            }
            flags[m.index()].set(Flag::VISITED, true);
        }
    }
    debug_assert!(answers.next().is_none());
    for &leaf in leaves {
        for m in octree.leaf_items(leaf) {
            flags[m.index()].reset(Flag::VISITED);
        }
    }
}

/// Slaves per task of the parallel half of the loop.
const MARK_CHUNK: usize = 256;

/// The read-only half of the loop for a run of slaves, flat: slave `j`'s leaves and answers
/// are the next `spans[j]` entries of `leaves` and `outcomes`, or its error.
#[derive(Default)]
struct MarkChunk {
    leaves: Vec<LeafId>,
    outcomes: Vec<bool>,
    spans: Vec<Result<(usize, usize), Error>>,
}

/// SearchUsingOcTree (§8): fills the slaves' INDEX_MAPs (MappingCheck) or pushes the created
/// (slave, master) pairs (No/DirectCheck); returns what it saw (warnings, root box, bbf).
///
/// The octree's storage and the slaves' leaves and intersection tests run in parallel (they
/// only read the model); the flags, the pairing and every error come in Kratos' serial order
/// afterwards, so the result is the serial loop's for any thread count.
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
    // 1. hmax (before any rank can leave: the ranks take their largest together).
    let h = model
        .nodal_data()
        .scalar(ScalarVar::NodalH, 0)
        .unwrap_or(&[]);
    let hmax = match cx.largest_nodal_h {
        Some(h) => h,
        None => {
            let here = (slave_nodes.iter().chain(&master_nodes))
                .map(|n| h.get(n.index()).copied().unwrap_or(0.0))
                .fold(0.0, Real::max);
            match cx.ranks {
                Some(ranks) => ranks.max(here)?,
                None => here,
            }
        }
    };
    if slave_nodes.is_empty() || master_nodes.is_empty() {
        // Kratos builds no octree without slave nodes; the caller rejects empty sides.
        return Ok(report);
    }

    // The OBB enlargement.
    report.hmax = hmax;
    let hmax = if hmax < EPS { 1.0 } else { hmax };
    let bbf = p.octree.bounding_box_factor * hmax;
    report.bbf = bbf;

    // 2. The root box. Robust with OBBs: it also covers the OBB of every slave-side and
    // master condition, so every point two OBBs share lies in a leaf.
    let n_conditions = model.conditions().len();
    let mut search = Search {
        cx,
        octree: Octree::with_kratos_params(Point::origin(), Point::new(1.0, 1.0, 1.0))
            .map_err(tree_error)?,
        bbf,
        robust,
        pieces: (0..n_conditions).map(|_| OnceLock::new()).collect(),
        bvs: (0..n_conditions).map(|_| OnceLock::new()).collect(),
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
    // A distributed run: the box of the whole problem's points (every rank holds a part of
    // them; a minimum and a maximum in any grouping are the one-process ones).
    if let Some(ranks) = cx.ranks {
        box_points = whole_extent(&box_points, ranks)?;
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

    // 3. Refine around the master nodes, then store the master conditions in ascending id
    // order: each master's leaves found in parallel, then stored in that order.
    search.octree = Octree::with_kratos_params(low, high).map_err(tree_error)?;
    for n in &master_nodes {
        search
            .octree
            .insert_point(&model.nodes().coordinates()[n.index()])
            .map_err(tree_error)?;
    }
    let walks: Vec<Result<Option<Vec<LeafId>>, Error>> = {
        let (search, model) = (&search, &*model);
        masters
            .par_iter()
            .map(|&m| {
                let Some((test, aabb)) = search.cell_test(model, m)? else {
                    return Ok(None);
                };
                let mut leaves = Vec::new();
                search
                    .octree
                    .intersected_leaves_with(&aabb, |cell| test.overlaps(cell), &mut leaves)
                    .map_err(tree_error)?;
                Ok(Some(leaves))
            })
            .collect()
    };
    let mut untestable: BTreeSet<GeometryKind> = BTreeSet::new();
    for (&m, walk) in masters.iter().zip(walks) {
        match walk? {
            Some(leaves) => search
                .octree
                .insert_in_leaves(m, &leaves)
                .map_err(tree_error)?,
            None => {
                untestable.insert(model.conditions().kind(m.index()));
            }
        }
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

    // DirectCheck's NODAL_H, read while the pairings change the model.
    let nodal_h = match p.check_gap {
        CheckGap::DirectCheck => h.to_vec(),
        _ => Vec::new(),
    };
    // 4. The loop over the conditions in ascending id order. Its read-only half first, in
    // parallel: every slave's leaves and the answers of its intersection tests. VISITED is
    // the marking's own scratch flag, clear between two slaves (a step that failed inside a
    // marking may have left it set).
    for &m in &masters {
        model.conditions_mut().flags_mut()[m.index()].reset(Flag::VISITED);
    }
    let loop_slaves: Vec<ConditionIdx> = conditions
        .iter()
        .copied()
        .filter(|c| {
            let f = model.conditions().flags()[c.index()];
            f.is_defined(Flag::ACTIVE) && f.is(Flag::SLAVE)
        })
        .collect();
    let marks: Vec<MarkChunk> = {
        let (search, model) = (&search, &*model);
        loop_slaves
            .par_chunks(MARK_CHUNK)
            .map_init(
                || (Vec::new(), Vec::new()),
                |(visits, own), chunk| {
                    let mut out = MarkChunk::default();
                    for &s in chunk {
                        let o0 = out.outcomes.len();
                        let done = search.mark_outcomes(model, s, own, &mut out.outcomes, visits);
                        out.spans.push(match done {
                            Ok(()) => {
                                out.leaves.extend_from_slice(own);
                                Ok((own.len(), out.outcomes.len() - o0))
                            }
                            Err(e) => {
                                out.outcomes.truncate(o0);
                                Err(e)
                            }
                        });
                    }
                    out
                },
            )
            .collect()
    };

    // The serial half, in Kratos' order: each slave's marking applied to the flags, then
    // the pairings.
    let mut marked = MarkCursor::new(&marks);
    let acf = model
        .process_info()
        .number("ACTIVE_CHECK_FACTOR")
        .unwrap_or(0.0);
    let mut other_leaves = Vec::new();
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
        let leaves: &[LeafId] = if is_slave {
            let (leaves, outcomes) = marked.next()?;
            replay_mark(model, &search.octree, c, leaves, outcomes);
            leaves
        } else {
            search.leaves(model, c, &mut other_leaves)?;
            &other_leaves
        };
        if !model.conditions().flags()[c.index()].is(Flag::SELECTED) {
            continue;
        }
        paired.clear();
        let slave_id = ConditionId(model.conditions().ids()[c.index()]);
        for &leaf in leaves {
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

/// Walks the slaves of the parallel half in order.
struct MarkCursor<'m> {
    chunks: &'m [MarkChunk],
    chunk: usize,
    span: usize,
    leaf: usize,
    outcome: usize,
}

impl<'m> MarkCursor<'m> {
    fn new(chunks: &'m [MarkChunk]) -> MarkCursor<'m> {
        MarkCursor {
            chunks,
            chunk: 0,
            span: 0,
            leaf: 0,
            outcome: 0,
        }
    }

    /// The next slave's leaves and answers, or its error.
    fn next(&mut self) -> Result<(&'m [LeafId], &'m [bool]), Error> {
        while self
            .chunks
            .get(self.chunk)
            .is_some_and(|c| self.span == c.spans.len())
        {
            (self.chunk, self.span, self.leaf, self.outcome) = (self.chunk + 1, 0, 0, 0);
        }
        let Some(chunk) = self.chunks.get(self.chunk) else {
            return Err(
                ErrorKind::Model("octree search: a slave without its marking".to_owned()).into(),
            );
        };
        let span = chunk.spans[self.span].clone()?;
        self.span += 1;
        let (nl, no) = span;
        let leaves = &chunk.leaves[self.leaf..self.leaf + nl];
        let outcomes = &chunk.outcomes[self.outcome..self.outcome + no];
        self.leaf += nl;
        self.outcome += no;
        Ok((leaves, outcomes))
    }
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
    // Copied out (the node flags change below), on the stack.
    let mut copy = [NodeIdx(0); MAX_FACE_NODES];
    let search_nodes = slave_search_nodes(model, s, cx.slave_nodes);
    debug_assert!(search_nodes.len() <= MAX_FACE_NODES);
    let n = search_nodes.len().min(MAX_FACE_NODES);
    copy[..n].copy_from_slice(&search_nodes[..n]);
    let nodes = &copy[..n];
    let flags = model.nodes_mut().flags_mut();
    match cx.params.check_gap {
        CheckGap::DirectCheck => {
            direct_check_count(flags, nodes, node_pass, cx.active_before.as_deref())
        }
        _ => {
            for n in nodes {
                flags[n.index()].set(Flag::ACTIVE, true);
            }
            true
        }
    }
}
