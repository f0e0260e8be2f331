//! Stages 6–7 for one slave condition: the kd-tree query (reference §5.4) and the OBB narrow
//! phase (§5.3, §7), plus the order-independent parts of the stage-8 tests. Pure functions of
//! the step's data, so the slave loop can run them in parallel.

use csm_geometry::math::{EPS, Point, Real, Vector};
use std::sync::OnceLock;

use csm_geometry::{
    Geometry, Kdop18, MAX_FACE_NODES, Obb, Obb2, ObbIntersection, SatMode, fast_project_direction,
};
use csm_model::{ConditionIdx, ModelPart, NodeIdx};
use csm_trees::KdTree;

use super::filters::passes_orientation;
use super::step_jump::half_jump_center;
use crate::error::{Error, ErrorKind};
use crate::setup::{CheckGap, Compatibility, SearchParameters, SearchTreeType};

/// An oriented bounding box in 2D or 3D.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Bv {
    D2(Obb2),
    D3(Obb),
}

impl Bv {
    /// Kratos' construction (AABB diagonal, or the face normal with
    /// `build_from_bounding_box: false`); robust mode (Q1 fixed) builds a face's box on its
    /// normal (branch B) and a line's along the line, whatever `build_from_bounding_box`
    /// says, so that the box turns with the mesh (an axis-aligned face otherwise gets a box
    /// without thickness that grows once the mesh is rotated: pairs depended on the rotation).
    pub(crate) fn build(
        geometry: &Geometry<'_>,
        dim: usize,
        enlargement: Real,
        build_from_bounding_box: bool,
        compatibility: Compatibility,
    ) -> Result<Bv, csm_geometry::Error> {
        let robust = compatibility == Compatibility::Robust && !geometry.kind().is_solid();
        match (dim, robust) {
            (2, false) => Obb2::from_geometry(geometry, enlargement).map(Bv::D2),
            (2, true) => Obb2::build_from_segment(geometry, enlargement).map(Bv::D2),
            (_, false) => {
                Obb::from_geometry(geometry, enlargement, build_from_bounding_box).map(Bv::D3)
            }
            (_, true) => Obb::build_on_normal_first_edge(geometry, enlargement).map(Bv::D3),
        }
    }

    /// [`Bv::build`]'s errors without the box where they can be told apart cheaply (Kratos'
    /// boxes on the AABB diagonal, 2D and 3D, fail alike: [`Obb::check_build_from_aabb`]);
    /// `None` where only building tells.
    pub(crate) fn check(
        geometry: &Geometry<'_>,
        dim: usize,
        enlargement: Real,
        build_from_bounding_box: bool,
        compatibility: Compatibility,
    ) -> Option<Result<(), csm_geometry::Error>> {
        let robust = compatibility == Compatibility::Robust && !geometry.kind().is_solid();
        let on_diagonal = match (dim, robust) {
            (2, false) => true,
            (_, false) => build_from_bounding_box || geometry.kind().is_solid(),
            (_, true) => false,
        };
        on_diagonal.then(|| Obb::check_build_from_aabb(geometry, enlargement))
    }

    fn intersects(&self, other: &Bv, mode: SatMode) -> bool {
        match (self, other) {
            (Bv::D2(a), Bv::D2(b)) => a.intersects(b, ObbIntersection::Sat, mode),
            (Bv::D3(a), Bv::D3(b)) => a.intersects(b, ObbIntersection::Sat, mode),
            // Both boxes of one search have the same dimension.
            _ => true,
        }
    }
}

/// The function of a master condition and its node coordinates that [`PerMaster`] holds.
type MasterValue<'a, T> = Box<dyn Fn(ConditionIdx, &[Point]) -> T + Sync + 'a>;

/// Masters per block of [`PerMaster`] values.
const MASTERS_PER_BLOCK: usize = 64;

/// Data of one step per master-side condition (the kd-tree's points), computed when a query
/// first asks for it, a block of [`MASTERS_PER_BLOCK`] consecutive masters at a time (the
/// blocks no slave query reaches cost nothing but their slots; the step lists the masters in
/// the kd-tree's order, so that a block lies in one region of space), and kept for the step: a slot
/// per condition index, the values only for the masters. A value is a function of its master
/// alone, so which query computes it first does not matter.
pub(crate) struct PerMaster<'a, T> {
    /// By condition index: the position in `masters`, or `u32::MAX`.
    slot: Vec<u32>,
    /// The masters, by position.
    masters: Vec<ConditionIdx>,
    /// The values of the masters, by block of positions.
    blocks: Vec<OnceLock<Box<[T]>>>,
    /// The model and the function of the values (none for [`PerMaster::none`]).
    source: Option<(&'a ModelPart, MasterValue<'a, T>)>,
}

impl<'a, T: Send + Sync> PerMaster<'a, T> {
    /// No master has a value.
    pub(crate) fn none() -> PerMaster<'a, T> {
        PerMaster {
            slot: Vec::new(),
            masters: Vec::new(),
            blocks: Vec::new(),
            source: None,
        }
    }

    /// `value(c, points)` for every master `c` of `model` in `masters` (`points`: its node
    /// coordinates), computed when first asked for.
    pub(crate) fn new(
        model: &'a ModelPart,
        masters: &[ConditionIdx],
        value: impl Fn(ConditionIdx, &[Point]) -> T + Sync + 'a,
    ) -> PerMaster<'a, T> {
        let mut slot = vec![u32::MAX; model.conditions().len()];
        for (i, c) in masters.iter().enumerate() {
            slot[c.index()] = i as u32;
        }
        PerMaster {
            slot,
            masters: masters.to_vec(),
            blocks: (0..masters.len().div_ceil(MASTERS_PER_BLOCK))
                .map(|_| OnceLock::new())
                .collect(),
            source: Some((model, Box::new(value))),
        }
    }

    /// Computes every master's value now, in parallel (in master order: where most masters
    /// will be asked for, this reads them in memory order).
    pub(crate) fn compute_all(&self) {
        use rayon::prelude::*;
        (0..self.blocks.len()).into_par_iter().for_each(|b| {
            self.block(b);
        });
    }

    /// The value of master `c`, if it has one.
    pub(crate) fn get(&self, c: ConditionIdx) -> Option<&T> {
        let i = *self.slot.get(c.index())? as usize;
        self.block(i / MASTERS_PER_BLOCK)
            .and_then(|values| values.get(i % MASTERS_PER_BLOCK))
    }

    /// The values of block `b`, computed on the first call.
    fn block(&self, b: usize) -> Option<&[T]> {
        let (model, value) = self.source.as_ref()?;
        let cell = self.blocks.get(b)?;
        Some(cell.get_or_init(|| {
            let end = ((b + 1) * MASTERS_PER_BLOCK).min(self.masters.len());
            let mut points = Vec::with_capacity(MAX_FACE_NODES);
            self.masters[b * MASTERS_PER_BLOCK..end]
                .iter()
                .map(|&c| {
                    model.gather_points(model.conditions().nodes(c.index()), &mut points);
                    value(c, &points)
                })
                .collect()
        }))
    }
}

/// The step's read-only data every slave query uses.
pub(crate) struct QueryContext<'a> {
    pub model: &'a ModelPart,
    pub params: &'a SearchParameters,
    /// The OBB narrow phase runs ([`crate::PairPlan::obb_test`]); `master_bvs` holds the
    /// master boxes.
    pub obb_test: bool,
    /// The 18-DOP narrow phase runs ([`crate::PairPlan::kdop`]); `master_kdops` holds the
    /// master 18-DOPs.
    pub kdop: bool,
    /// `bounding_box_factor × hmax`.
    pub bbf: Real,
    pub dim: usize,
    /// Nodes of a slave condition the search uses (6-node triangles searched as 3-node).
    pub slave_nodes: usize,
    pub compatibility: Compatibility,
    /// DELTA_COORDINATES when the search is dynamic.
    pub delta: Option<&'a [Vector]>,
    /// Historical nodal NORMAL.
    pub nodal_normals: &'a [Vector],
    pub nodal_h: &'a [Real],
    pub active_check_factor: Real,
    /// Master bounding boxes by condition index (`None`: not a point-list condition; empty
    /// without the OBB test).
    pub master_bvs: &'a PerMaster<'a, Result<Bv, csm_geometry::Error>>,
    /// Master 18-DOPs (enlarged by `bbf`) by condition index, for `kdop_18` (empty otherwise).
    pub master_kdops: &'a PerMaster<'a, Kdop18>,
}

/// One candidate master that survived the order-independent tests.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Candidate {
    pub master: ConditionIdx,
    /// DirectCheck: bit `i` set when slave node `i` passes one of the two projection tests.
    pub node_pass: u32,
}

fn geometry_error(model: &ModelPart, c: ConditionIdx, e: &csm_geometry::Error) -> Error {
    ErrorKind::Geometry {
        condition: model.conditions().ids()[c.index()],
        message: e.to_string(),
    }
    .into()
}

/// The buffers of the slave queries of one worker, reused from query to query (no
/// allocation per query once they have grown).
#[derive(Debug, Default)]
pub(crate) struct QueryScratch {
    /// The candidates of the last query, in kd-tree result order.
    pub candidates: Vec<Candidate>,
    /// The kd-tree's hits.
    found: Vec<u32>,
    /// The slave's node coordinates.
    points: Vec<Point>,
}

/// The candidates of slave `s` in `tree` (the master-side condition centres), in kd-tree
/// result order (Kratos' traversal order), into `scratch.candidates`. Returns whether the
/// kd-tree query reached the result cap (`max_number_results`).
pub(crate) fn slave_candidates(
    cx: &QueryContext<'_>,
    tree: &KdTree<u32>,
    s: ConditionIdx,
    scratch: &mut QueryScratch,
) -> Result<bool, Error> {
    let QueryScratch {
        candidates: out,
        found,
        points,
    } = scratch;
    out.clear();
    let model = cx.model;
    let conditions = model.conditions();
    let nodes = conditions.nodes(s.index());
    points.clear();
    points.extend(nodes.iter().map(|n| model.nodes().coordinates()[n.index()]));
    let points = &points[..];
    let kind = conditions.kind(s.index());
    let geometry = Geometry::new(kind, points).map_err(|e| geometry_error(model, s, &e))?;
    let p = cx.params;
    // Q12: the slave box is always built, even without OBB filtering, and fails on a
    // zero-extent bounding box: that failure here, the box itself only for a slave with
    // candidates to test ([`Bv::check`]).
    let build_slave_bv = || {
        Bv::build(
            &geometry,
            cx.dim,
            cx.bbf,
            p.octree.build_from_bounding_box,
            cx.compatibility,
        )
        .map_err(|e| geometry_error(model, s, &e))
    };
    let check = Bv::check(
        &geometry,
        cx.dim,
        cx.bbf,
        p.octree.build_from_bounding_box,
        cx.compatibility,
    );
    let mut slave_bv = match check {
        Some(checked) => {
            checked.map_err(|e| geometry_error(model, s, &e))?;
            None
        }
        None => Some(build_slave_bv()?),
    };
    let mut query_radius = 0.0;
    let tree_error = |e: csm_trees::Error| {
        Error::from(ErrorKind::Geometry {
            condition: conditions.ids()[s.index()],
            message: format!("kd-tree query: {e}"),
        })
    };
    let status = match p.type_search {
        SearchTreeType::KdtreeInRadius
        | SearchTreeType::KdtreeInRadiusWithObb
        | SearchTreeType::Kdop
        | SearchTreeType::OctreeWithObb => {
            let center = geometry.center();
            let radius = p.search_factor * geometry.bounding_sphere().radius;
            query_radius = radius;
            let query = match cx.delta {
                Some(delta) => {
                    let local = geometry
                        .point_local_coordinates(&center)
                        .map_err(|e| geometry_error(model, s, &e))?;
                    let shape = geometry.shape_functions(&local);
                    half_jump_center(&center, &shape, nodes, delta, cx.dim)
                }
                None => center,
            };
            tree.in_radius(&query, radius, p.allocation_size, found)
                .map_err(tree_error)?
        }
        SearchTreeType::KdtreeInBox | SearchTreeType::KdtreeInBoxWithObb => {
            let length = geometry
                .length()
                .map_err(|e| geometry_error(model, s, &e))?;
            let l = p.search_factor * length;
            let aabb = geometry.aabb();
            let shifted = |corner: &Point| -> Result<Point, Error> {
                // Q6: the corner is moved along the interpolated nodal normal at its
                // (extrapolated) local coordinates.
                let local = geometry
                    .point_local_coordinates(corner)
                    .map_err(|e| geometry_error(model, s, &e))?;
                let shape = geometry.shape_functions(&local);
                let mut n = Vector::zeros();
                for (node, w) in nodes.iter().zip(shape.iter()) {
                    n += cx.nodal_normals[node.index()] * *w;
                }
                let norm = n.norm();
                if norm <= EPS {
                    return Err(ErrorKind::Geometry {
                        condition: conditions.ids()[s.index()],
                        message: "the interpolated normal at a corner of the search box is zero"
                            .to_owned(),
                    }
                    .into());
                }
                Ok(corner + n * (l / norm))
            };
            let (lo, hi) = match cx.compatibility {
                Compatibility::Kratos => (shifted(&aabb.min)?, shifted(&aabb.max)?),
                // Robust (Q6 fixed): the slave's bounding box inflated by L on every side, so
                // the box always has volume and holds every master centre within L of it.
                Compatibility::Robust => {
                    let margin = Vector::new(l, l, l);
                    (aabb.min - margin, aabb.max + margin)
                }
            };
            tree.in_box(&lo, &hi, p.allocation_size, found)
                .map_err(tree_error)?
        }
    };
    let mode = match cx.compatibility {
        Compatibility::Kratos => SatMode::Kratos,
        Compatibility::Robust => SatMode::Robust,
    };
    if found.is_empty() {
        return Ok(status.truncated);
    }
    let slave_id = conditions.ids()[s.index()];
    let slave_normal = model.condition_normals()[s.index()];
    // kdop_18: the slave's 18-DOP enlarged like the OBBs; in robust mode first swept along
    // the slave normal over the query radius, so a master up to that far in front of or
    // behind the face (penetration) is not lost.
    let slave_kdop = cx.kdop.then(|| {
        let k = match cx.compatibility {
            Compatibility::Kratos => Kdop18::from_points(points),
            Compatibility::Robust => Kdop18::swept(points, &slave_normal, query_radius),
        };
        k.enlarged(cx.bbf)
    });
    for &c in found.iter() {
        let master = ConditionIdx(c);
        if let Some(kdop) = &slave_kdop {
            match cx.master_kdops.get(master) {
                Some(m) if kdop.intersects(m) => {}
                _ => continue,
            }
        }
        if cx.obb_test {
            let bv = match cx.master_bvs.get(master) {
                Some(Ok(bv)) => bv,
                Some(Err(e)) => return Err(geometry_error(model, master, e)),
                None => continue,
            };
            let slave_bv = match &mut slave_bv {
                Some(built) => &*built,
                empty => empty.insert(build_slave_bv()?),
            };
            if !slave_bv.intersects(bv, mode) {
                continue;
            }
        }
        let mut node_pass = 0u32;
        match p.check_gap {
            CheckGap::MappingCheck => {
                let master_normal = model.condition_normals()[master.index()];
                let master_id = conditions.ids()[master.index()];
                if !passes_orientation(
                    slave_id,
                    master_id,
                    &slave_normal,
                    &master_normal,
                    p.normal_orientation_threshold,
                ) {
                    continue;
                }
            }
            CheckGap::NoCheck => {}
            CheckGap::DirectCheck => {
                let n_c = model.condition_normals()[master.index()];
                node_pass = direct_check_nodes(cx, s, master, &n_c)?;
            }
        }
        out.push(Candidate { master, node_pass });
    }
    Ok(status.truncated)
}

/// Robust DirectCheck's inside tolerance in local coordinates (Kratos: ε): well above the
/// rounding of local coordinates far from the origin (a mesh translated by 1e6 moves a node's
/// local coordinates by ~1e-9 on 0.1-wide faces), so a node on an edge or vertex stays inside
/// every master around it.
const ROBUST_INSIDE_TOLERANCE: Real = 1e-6;

/// DirectCheck's geometric test (reference §10.4) for every slave node: project the node onto
/// the master's plane along `v` (the slave normal: csm never sets the non-historical nodal
/// NORMAL, Q20) and along `−n_C`; a node passes if, for either direction, the distance is at
/// most `NODAL_H · ACTIVE_CHECK_FACTOR` and the projection lies inside the master (tolerance
/// ε). A direction parallel to the master plane gives distance 0 (Kratos' behaviour).
/// `n_c` is the master normal the caller's path uses (kd-tree: the condition NORMAL; octree:
/// the unit normal at local (0,0,0)).
pub(crate) fn direct_check_nodes(
    cx: &QueryContext<'_>,
    s: ConditionIdx,
    master: ConditionIdx,
    n_c: &Vector,
) -> Result<u32, Error> {
    let model = cx.model;
    let conditions = model.conditions();
    let master_nodes = conditions.nodes(master.index());
    // On the stack, no allocation per candidate (a face has at most MAX_FACE_NODES nodes;
    // a longer list, which no face kind has, is gathered as before).
    let mut buffer = [Point::origin(); MAX_FACE_NODES];
    let n = master_nodes.len();
    let mut master_points = Vec::new();
    let master_points: &[Point] = if n <= MAX_FACE_NODES {
        for (p, node) in buffer.iter_mut().zip(master_nodes) {
            *p = model.nodes().coordinates()[node.index()];
        }
        &buffer[..n]
    } else {
        model.gather_points(master_nodes, &mut master_points);
        &master_points
    };
    let master_geometry = Geometry::new(conditions.kind(master.index()), master_points)
        .map_err(|e| geometry_error(model, master, &e))?;
    let n_s = model.condition_normals()[s.index()];
    let n_c = *n_c;
    let origin = master_points[0];
    // Robust mode: a node on the edge between two masters is inside both (local tolerance
    // 1e-6 instead of ε), so that rounding — e.g. after a rotation of the mesh — cannot move
    // it from one master to the other (stability suite).
    let inside_tolerance = match cx.compatibility {
        Compatibility::Kratos => EPS,
        Compatibility::Robust => ROBUST_INSIDE_TOLERANCE,
    };
    let mut pass = 0u32;
    for (i, node) in conditions
        .nodes(s.index())
        .iter()
        .take(cx.slave_nodes)
        .enumerate()
    {
        let p = model.nodes().coordinates()[node.index()];
        let limit = cx.nodal_h[node.index()] * cx.active_check_factor;
        for v in [n_s, -n_c] {
            let (projected, d) = fast_project_direction(&origin, &p, &n_c, &v);
            if d <= limit {
                let inside = master_geometry
                    .is_inside(&projected, inside_tolerance)
                    .map_err(|e| geometry_error(model, master, &e))?;
                if inside.is_some() {
                    pass |= 1 << i;
                    break;
                }
            }
        }
    }
    Ok(pass)
}

/// The nodes of slave `s` that the search considers (the first `n`).
pub(crate) fn slave_search_nodes(model: &ModelPart, s: ConditionIdx, n: usize) -> &[NodeIdx] {
    let nodes = model.conditions().nodes(s.index());
    &nodes[..n.min(nodes.len())]
}
