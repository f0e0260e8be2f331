//! The kd-tree type: storage, construction entry points and accessors.

use std::sync::OnceLock;

use csm_geometry::math::{Point, Real};
use rayon::prelude::*;

use crate::aabb::Aabb;
use crate::error::{Error, ErrorKind, check_point};

use super::build;

/// Kratos' default leaf size (`bucket_size`, reference Appendix B).
pub(crate) const KRATOS_BUCKET_SIZE: usize = 4;

/// A node of the tree, stored in one arena. Children of an inner node are never empty (with
/// `bucket_size >= 1` both halves of a split hold at least one point).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Node {
    /// A bucket: the entries `start..end` of the permuted entry arrays, in stored order.
    Leaf { start: u32, end: u32 },
    /// A split on `axis` at `cut`: points of `left` have coordinate `<= left_max`, those of
    /// `right` `>= right_min`. A build sets both bounds to `cut` (Kratos' tree, whose queries
    /// compare with the cut); [`KdTree::refit`] moves them to the subtrees' extents, which may
    /// then overlap. `cut` only decides which child a query visits first.
    Inner {
        axis: u8,
        cut: Real,
        left_max: Real,
        right_min: Real,
        left: u32,
        right: u32,
    },
    /// A subtree not built yet ([`KdTree::new_deferred`]) over the entries `start..end`, still
    /// in the order the split above left them: built as [`KdTree::deferred`]`[slot]` by the
    /// first query that reaches it, or in place by [`KdTree::settle`].
    Deferred { slot: u32, start: u32, end: u32 },
}

impl Node {
    /// The node of an arena appended at `nodes` over entries placed from `entries`: its
    /// child links and its entry range moved by those offsets.
    pub(crate) fn shifted(mut self, nodes: u32, entries: u32) -> Node {
        match &mut self {
            Node::Leaf { start, end } | Node::Deferred { start, end, .. } => {
                *start += entries;
                *end += entries;
            }
            Node::Inner { left, right, .. } => {
                *left += nodes;
                *right += nodes;
            }
        }
        self
    }
}

/// A deferred subtree once built: its entries (the range's, permuted by the build) and its
/// arena (root at 0; its leaves index its own entries).
#[derive(Debug, Clone)]
pub(crate) struct Subtree<T> {
    pub(crate) items: Vec<T>,
    pub(crate) points: Vec<Point>,
    pub(crate) nodes: Vec<Node>,
}

/// The arena and entries a query walks: the tree's own, or a deferred subtree's.
#[derive(Clone, Copy)]
pub(crate) struct Arena<'a, T> {
    pub(crate) nodes: &'a [Node],
    pub(crate) items: &'a [T],
    pub(crate) points: &'a [Point],
}

/// A bucketed kd-tree over `(item, point)` entries, built once and queried many times.
///
/// Items are opaque `Copy` ids (`T`); the tree knows nothing about what they are.
///
/// Construction follows Kratos (reference §6.1): a range of more than `bucket_size` points is
/// split on the axis of largest spread at its median (Kratos' Hoare quickselect, reproduced
/// literally, including the cut-value slip), so for the same input order the tree, and hence
/// the traversal order of the queries, is Kratos'. The entries are permuted internally, like
/// Kratos permutes the caller's point vector; [`KdTree::refit`] keeps that permutation between
/// builds, as Kratos does from one search step to the next (Q13); [`KdTree::refit`] keeps
/// the whole tree and only refits the split bounds to moved points.
///
/// Queries: [`KdTree::in_radius`] (strict, `|p − c| < r`) and [`KdTree::in_box`] (inclusive),
/// both with a result cap and a caller-owned output buffer.
///
/// A tree built by [`KdTree::new_deferred`] splits only its large ranges at once and builds
/// each small subtree when a query first reaches it: the queries, their results and their
/// order are the fully built tree's, and [`KdTree::settle`] makes it that tree, node for node.
#[derive(Debug, Clone)]
pub struct KdTree<T> {
    /// The items, in the tree's (permuted) order.
    pub(crate) items: Vec<T>,
    /// The points, parallel to `items`.
    pub(crate) points: Vec<Point>,
    /// The node arena.
    pub(crate) nodes: Vec<Node>,
    /// The root node; `None` for an empty tree.
    pub(crate) root: Option<u32>,
    /// The bounding box of all points (set with `root`): a query whose region misses it finds
    /// nothing without a descent.
    pub(crate) extent: Option<Aabb>,
    /// The maximum number of points in a leaf.
    pub(crate) bucket_size: usize,
    /// Ranges of more than `bucket_size` and at most this many points are deferred by a build
    /// (none where it is not above `bucket_size`).
    pub(crate) defer_max: usize,
    /// The deferred subtrees, by [`Node::Deferred`] slot; empty when none is left.
    pub(crate) deferred: Vec<OnceLock<Subtree<T>>>,
}

impl<T: Copy + Send> KdTree<T> {
    /// Builds the tree over `entries` with leaves of at most `bucket_size` points (Kratos'
    /// default is 4, see [`KdTree::with_kratos_bucket_size`]).
    ///
    /// Errors: [`ErrorKind::ZeroBucketSize`], [`ErrorKind::NonFinite`] for a NaN or infinite
    /// coordinate, [`ErrorKind::TooManyEntries`] beyond `u32::MAX / 2` entries. An empty slice
    /// gives an empty tree.
    pub fn new(entries: &[(T, Point)], bucket_size: usize) -> Result<KdTree<T>, Error> {
        KdTree::new_deferred(entries, bucket_size, 0)
    }

    /// [`KdTree::new`] that builds the subtrees of more than `bucket_size` and at most
    /// `defer_max` points only when a query first reaches one (each in the calling thread; a
    /// concurrent query waits for it). Where queries visit a small part of the points, most
    /// of the build is never done. Every query result, and its order, is [`KdTree::new`]'s;
    /// [`KdTree::settle`] builds the rest. Rebuilds defer likewise.
    ///
    /// Errors: those of [`KdTree::new`].
    pub fn new_deferred(
        entries: &[(T, Point)],
        bucket_size: usize,
        defer_max: usize,
    ) -> Result<KdTree<T>, Error> {
        let mut tree = KdTree::empty(bucket_size, defer_max)?;
        tree.rebuild(entries)?;
        Ok(tree)
    }

    /// [`KdTree::new_deferred`] over the entries `(items[i], points[i])`, taking the two
    /// lists as its own storage instead of copying them.
    ///
    /// Errors: those of [`KdTree::new`], and [`ErrorKind::LengthMismatch`] for lists of
    /// different lengths.
    pub fn from_parts(
        items: Vec<T>,
        points: Vec<Point>,
        bucket_size: usize,
        defer_max: usize,
    ) -> Result<KdTree<T>, Error> {
        if items.len() != points.len() {
            return Err(Error::new(ErrorKind::LengthMismatch));
        }
        let mut tree = KdTree::empty(bucket_size, defer_max)?;
        check_len(points.len())?;
        // (Checked in parallel: the error is the same for every point that is not finite.)
        if let Some(p) = (points.par_iter()).find_any(|p| check_point(p, "point").is_err()) {
            check_point(p, "point")?;
        }
        tree.items = items;
        tree.points = points;
        tree.build_in_place();
        Ok(tree)
    }

    /// An empty tree with these sizes.
    fn empty(bucket_size: usize, defer_max: usize) -> Result<KdTree<T>, Error> {
        let mut tree = KdTree {
            items: Vec::new(),
            points: Vec::new(),
            nodes: Vec::new(),
            root: None,
            extent: None,
            bucket_size: KRATOS_BUCKET_SIZE,
            defer_max,
            deferred: Vec::new(),
        };
        tree.set_bucket_size(bucket_size)?;
        Ok(tree)
    }

    /// [`KdTree::new`] with Kratos' default bucket size 4.
    pub fn with_kratos_bucket_size(entries: &[(T, Point)]) -> Result<KdTree<T>, Error> {
        KdTree::new(entries, KRATOS_BUCKET_SIZE)
    }

    /// Rebuilds the tree from scratch over `entries` (in their given order), reusing the
    /// allocations of the previous build. On error the tree is left unchanged.
    pub fn rebuild(&mut self, entries: &[(T, Point)]) -> Result<(), Error> {
        check_len(entries.len())?;
        for (_, p) in entries {
            check_point(p, "point")?;
        }
        self.items.clear();
        self.points.clear();
        self.items.extend(entries.iter().map(|(item, _)| *item));
        self.points.extend(entries.iter().map(|(_, p)| *p));
        self.build_in_place();
        Ok(())
    }

    /// Moves every stored point to `position(item)` and rebuilds the tree in place, keeping the
    /// current (permuted) entry order as the starting order, like Kratos' `UpdatePoint()` on
    /// the permuted point list followed by a new build (reference §6.1, Q13).
    ///
    /// Errors: [`ErrorKind::NonFinite`] if a new position is NaN or infinite; the tree is then
    /// left empty (every entry is dropped), so a failed rebuild can never be queried by mistake.
    pub fn rebuild_moved(&mut self, position: impl FnMut(T) -> Point) -> Result<(), Error> {
        self.settle();
        self.move_points(position)?;
        self.build_in_place();
        Ok(())
    }

    /// Moves every stored point to `position(item)` and **keeps the tree**: the leaves, their
    /// entries and the split axes stay, and each split's bounds are refitted to the extents of
    /// its two subtrees along its axis (one pass over the points, no sorting). Cheaper than a
    /// rebuild when only the coordinates changed between two search steps.
    ///
    /// The queries of a refitted tree find exactly the points a rebuilt tree finds (the
    /// bounds are exact); the traversal order, and hence the order of the results and which
    /// ones a result cap keeps, can differ from a rebuild's. A tree whose points moved far
    /// (a split's two subtrees overlapping widely) stays correct but gets slower: rebuild it.
    ///
    /// Errors: [`ErrorKind::NonFinite`] if a new position is NaN or infinite; the tree is then
    /// left empty (every entry is dropped), so a failed refit can never be queried by mistake.
    pub fn refit(&mut self, position: impl FnMut(T) -> Point) -> Result<(), Error> {
        self.settle();
        self.move_points(position)?;
        self.extent = self.root.map(|root| {
            let (lo, hi) = refit_node(&mut self.nodes, &self.points, root);
            Aabb::new(lo, hi)
        });
        Ok(())
    }

    /// Sets every stored point to `position(item)`; on a non-finite position the tree is
    /// emptied and an error returned.
    fn move_points(&mut self, mut position: impl FnMut(T) -> Point) -> Result<(), Error> {
        for (item, p) in self.items.iter().zip(self.points.iter_mut()) {
            *p = position(*item);
        }
        let all_finite = self
            .points
            .iter()
            .all(|p| p.coords.iter().all(|c| c.is_finite()));
        if !all_finite {
            self.items.clear();
            self.points.clear();
            self.nodes.clear();
            self.deferred.clear();
            self.root = None;
            self.extent = None;
            return Err(Error::non_finite("point"));
        }
        Ok(())
    }

    /// Changes the bucket size used by the next [`KdTree::rebuild`] or
    /// [`KdTree::rebuild_moved`] ([`KdTree::refit`] keeps the leaves).
    pub fn set_bucket_size(&mut self, bucket_size: usize) -> Result<(), Error> {
        if bucket_size == 0 {
            return Err(Error::new(ErrorKind::ZeroBucketSize));
        }
        self.bucket_size = bucket_size;
        Ok(())
    }

    fn build_in_place(&mut self) {
        self.nodes.clear();
        let (root, n_deferred, extent) = build::build(
            &mut self.items,
            &mut self.points,
            &mut self.nodes,
            self.bucket_size,
            self.defer_max,
        );
        self.root = root;
        self.deferred = (0..n_deferred).map(|_| OnceLock::new()).collect();
        self.extent = extent;
    }

    /// Builds every deferred subtree that no query has built yet and puts them all in place:
    /// the tree is then [`KdTree::new`]'s, node for node and entry for entry. Nothing to do
    /// on a tree without deferred subtrees.
    pub fn settle(&mut self) {
        let (Some(root), false) = (self.root, self.deferred.is_empty()) else {
            return;
        };
        let deferred = std::mem::take(&mut self.deferred);
        let old = std::mem::take(&mut self.nodes);
        let mut nodes = Vec::with_capacity(old.len());
        let mut settle = Settle {
            old: &old,
            deferred,
            items: &mut self.items,
            points: &mut self.points,
            bucket_size: self.bucket_size,
            nodes: &mut nodes,
        };
        self.root = Some(settle.node(root));
        self.nodes = nodes;
    }

    /// The deferred subtree `slot` over the entries `start..end`, built now if no query did.
    pub(crate) fn subtree(&self, slot: u32, start: u32, end: u32) -> &Subtree<T> {
        self.deferred[slot as usize].get_or_init(|| {
            let range = start as usize..end as usize;
            build_subtree(
                self.items[range.clone()].to_vec(),
                self.points[range].to_vec(),
                self.bucket_size,
            )
        })
    }
}

/// Builds the whole tree over `items`/`points` (more than `bucket_size` of them).
fn build_subtree<T: Copy + Send>(
    mut items: Vec<T>,
    mut points: Vec<Point>,
    bucket_size: usize,
) -> Subtree<T> {
    let mut nodes = Vec::new();
    build::build(&mut items, &mut points, &mut nodes, bucket_size, 0);
    Subtree {
        items,
        points,
        nodes,
    }
}

impl<T> Subtree<T> {
    /// Its arena and entries.
    pub(crate) fn arena(&self) -> Arena<'_, T> {
        Arena {
            nodes: &self.nodes,
            items: &self.items,
            points: &self.points,
        }
    }
}

/// The walk of [`KdTree::settle`]: copies the arena in pre-order into `nodes`, with every
/// deferred subtree's arena in the place of its node.
struct Settle<'a, T> {
    old: &'a [Node],
    deferred: Vec<OnceLock<Subtree<T>>>,
    items: &'a mut [T],
    points: &'a mut [Point],
    bucket_size: usize,
    nodes: &'a mut Vec<Node>,
}

impl<T: Copy + Send> Settle<'_, T> {
    /// Copies the subtree `node` of the old arena; returns its index in the new one.
    fn node(&mut self, node: u32) -> u32 {
        let index = self.nodes.len() as u32;
        match self.old[node as usize] {
            leaf @ Node::Leaf { .. } => self.nodes.push(leaf),
            inner @ Node::Inner { left, right, .. } => {
                // Its links are the old arena's until its children are copied.
                self.nodes.push(inner);
                let new_left = self.node(left);
                let new_right = self.node(right);
                if let Node::Inner { left, right, .. } = &mut self.nodes[index as usize] {
                    (*left, *right) = (new_left, new_right);
                }
            }
            Node::Deferred { slot, start, end } => {
                let range = start as usize..end as usize;
                let sub = std::mem::take(&mut self.deferred[slot as usize])
                    .into_inner()
                    .unwrap_or_else(|| {
                        build_subtree(
                            self.items[range.clone()].to_vec(),
                            self.points[range.clone()].to_vec(),
                            self.bucket_size,
                        )
                    });
                self.items[range.clone()].copy_from_slice(&sub.items);
                self.points[range].copy_from_slice(&sub.points);
                self.nodes
                    .extend(sub.nodes.into_iter().map(|node| node.shifted(index, start)));
            }
        }
        index
    }
}

impl<T> KdTree<T> {
    /// The number of entries.
    pub fn len(&self) -> usize {
        self.items.len()
    }

    /// Whether the tree holds no entry.
    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    /// The maximum number of points in a leaf.
    pub fn bucket_size(&self) -> usize {
        self.bucket_size
    }

    /// The number of nodes (leaves and inner nodes) built so far: a deferred subtree counts
    /// as one node until it is built and settled ([`KdTree::settle`]).
    pub fn n_nodes(&self) -> usize {
        self.nodes.len()
    }

    /// The items in their stored order, which groups them in space: a settled tree's leaves
    /// left to right; the items of a subtree not built yet ([`KdTree::new_deferred`]) are
    /// together, in the order the split above it left them. ([`KdTree::iter`] gives the
    /// settled order, building the deferred subtrees.)
    pub fn stored_items(&self) -> &[T] {
        &self.items
    }

    /// Whether some subtree is still deferred ([`KdTree::new_deferred`]).
    pub fn has_deferred(&self) -> bool {
        !self.deferred.is_empty()
    }
}

impl<T: Copy + Send> KdTree<T> {
    /// The entries in the tree's internal (permuted) order: leaves left to right, each bucket
    /// in stored order. A deferred subtree is built for it (it holds the order of its range).
    pub fn iter(&self) -> impl Iterator<Item = (&T, &Point)> + '_ {
        let mut pieces = Vec::new();
        let mut at = 0;
        for (slot, start, end) in self.deferred_ranges() {
            let sub = self.subtree(slot, start, end);
            pieces.push((
                &self.items[at..start as usize],
                &self.points[at..start as usize],
            ));
            pieces.push((&sub.items[..], &sub.points[..]));
            at = end as usize;
        }
        pieces.push((&self.items[at..], &self.points[at..]));
        pieces
            .into_iter()
            .flat_map(|(items, points)| items.iter().zip(points))
    }

    /// The deferred nodes' `(slot, start, end)`, in entry order.
    fn deferred_ranges(&self) -> Vec<(u32, u32, u32)> {
        if self.deferred.is_empty() {
            return Vec::new();
        }
        let mut ranges: Vec<(u32, u32, u32)> = self
            .nodes
            .iter()
            .filter_map(|node| match *node {
                Node::Deferred { slot, start, end } => Some((slot, start, end)),
                _ => None,
            })
            .collect();
        ranges.sort_unstable_by_key(|r| r.1);
        ranges
    }
}

impl<T> KdTree<T> {
    /// The arena and entries of the tree itself (a query's start).
    pub(crate) fn arena(&self) -> Arena<'_, T> {
        Arena {
            nodes: &self.nodes,
            items: &self.items,
            points: &self.points,
        }
    }

    /// The bounding box of all points; `None` for an empty tree.
    pub fn bounds(&self) -> Option<Aabb> {
        self.extent
    }
}

/// Refits the bounds of the subtree `node` to `points` and returns its extent `(min, max)`.
fn refit_node(nodes: &mut [Node], points: &[Point], node: u32) -> (Point, Point) {
    match nodes[node as usize] {
        // A refit settles the tree first; a deferred range's extent is its points' anyway.
        Node::Leaf { start, end } | Node::Deferred { start, end, .. } => {
            let pts = &points[start as usize..end as usize];
            let lo = pts.iter().fold(pts[0], |a, b| a.inf(b));
            let hi = pts.iter().fold(pts[0], |a, b| a.sup(b));
            (lo, hi)
        }
        Node::Inner {
            axis, left, right, ..
        } => {
            let (llo, lhi) = refit_node(nodes, points, left);
            let (rlo, rhi) = refit_node(nodes, points, right);
            if let Node::Inner {
                left_max,
                right_min,
                ..
            } = &mut nodes[node as usize]
            {
                *left_max = lhi[axis as usize];
                *right_min = rlo[axis as usize];
            }
            (llo.inf(&rlo), lhi.sup(&rhi))
        }
    }
}

/// Checks that `n` entries and their `< 2n` nodes can be indexed with `u32`.
fn check_len(n: usize) -> Result<(), Error> {
    if n <= (u32::MAX / 2) as usize {
        Ok(())
    } else {
        Err(Error::new(ErrorKind::TooManyEntries))
    }
}
