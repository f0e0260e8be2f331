//! The octree type: parameters, cell arena, coordinate normalisation and keys.

use csm_geometry::math::{Point, Real};

use crate::aabb::Aabb;
use crate::error::{Error, ErrorKind, check_point};

/// The levels and the cell tolerance of an [`Octree`]; [`Default`] gives Kratos' values
/// (reference §8 and Appendix B: MAX/ROOT/MIN level 12/11/2, tolerance coefficient 0.001).
///
/// A cell of level `l` spans `2^l` integer keys per axis; the root (level `root_level`) spans
/// the whole root box, so the smallest cells (level `min_level`) are `2^(min_level −
/// root_level)` of the root box per axis (1/512 for Kratos).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OctreeParams {
    /// Kratos' `MAX_LEVEL` (12); only checked: `root_level < max_level <= 31`.
    pub max_level: u32,
    /// The level of the root cell (Kratos' `ROOT_LEVEL = MAX_LEVEL − 1 = 11`).
    pub root_level: u32,
    /// The level of the smallest cells, produced by [`Octree::insert_point`] (Kratos'
    /// `MIN_LEVEL`, 2).
    pub min_level: u32,
    /// The cell tolerance as a fraction of the smallest *normalised* cell size (Kratos'
    /// `ToleranceCoefficient`, 0.001); see [`OctreeParams::cell_tolerance`].
    pub tolerance_coefficient: Real,
}

impl Default for OctreeParams {
    fn default() -> OctreeParams {
        OctreeParams {
            max_level: 12,
            root_level: 11,
            min_level: 2,
            tolerance_coefficient: 0.001,
        }
    }
}

impl OctreeParams {
    /// The margin by which a leaf box is grown before the object test:
    /// `tolerance_coefficient · 2^min_level / 2^root_level` (≈ 1.95e-6 for Kratos).
    ///
    /// As in Kratos this value, computed in normalised units, is added to the leaf box **after**
    /// scaling it back to real coordinates, so it acts as an *absolute* length whatever the
    /// size of the root box (quirk Q17).
    pub fn cell_tolerance(&self) -> Real {
        self.tolerance_coefficient * (1u64 << self.min_level) as Real
            / (1u64 << self.root_level) as Real
    }

    fn validate(&self) -> Result<(), Error> {
        let levels_ok = self.min_level < self.root_level
            && self.root_level < self.max_level
            && self.max_level <= 31;
        if !levels_ok {
            return Err(Error::new(ErrorKind::InvalidLevels));
        }
        if !self.tolerance_coefficient.is_finite() {
            return Err(Error::non_finite("tolerance coefficient"));
        }
        Ok(())
    }
}

/// A leaf of an [`Octree`], as returned by [`Octree::intersected_leaves`]. Valid for the
/// octree that returned it until that octree is refined.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct LeafId(pub(crate) u32);

/// A cell: its lowest integer key per axis, its level, its children (8 consecutive cells in
/// the arena, Kratos' child order: bit 0 = x, bit 1 = y, bit 2 = z) and, for a leaf, the
/// objects stored in it, in insertion order.
#[derive(Debug, Clone)]
pub(crate) struct Cell<T> {
    pub(crate) min_key: [u32; 3],
    pub(crate) level: u32,
    pub(crate) children: Option<u32>,
    pub(crate) objects: Vec<T>,
}

/// An octree over a caller-given root box whose leaves hold objects (items with a box).
///
/// Items are opaque `Copy` ids (`T`); the octree knows nothing about what they are.
///
/// Use it as Kratos does (reference §8): create it over the root box, refine it with
/// [`Octree::insert_point`] around every point of interest (Kratos: every master node), then
/// [`Octree::insert`] every object (Kratos: every master condition) into all leaves it
/// overlaps, and finally ask which objects share a leaf with a query box
/// ([`Octree::query_aabb`], [`Octree::query_aabb_per_leaf`], [`Octree::intersected_leaves`]).
///
/// Coordinates are normalised to `[0, 1]` per axis by `(x − low) / (high − low)` and cells are
/// addressed by integer keys `floor(2^root_level · x̂)`. The leaf test uses the leaf box scaled
/// back to real coordinates and grown by the absolute [`OctreeParams::cell_tolerance`], so the
/// octree may report objects that do not quite touch the query (a superset of the exact
/// overlap); [`Octree::insert_with`] and [`Octree::intersected_leaves_with`] take the exact
/// object-vs-cell test of the caller (Kratos: triangle/box, segment/box) in place of the box
/// test.
#[derive(Debug, Clone)]
pub struct Octree<T> {
    pub(crate) cells: Vec<Cell<T>>,
    pub(crate) params: OctreeParams,
    root_aabb: Aabb,
    /// Kratos' `mScaleFactor`: `1 / (high − low)`.
    scale: [Real; 3],
    /// Kratos' `mOffset`: `−low`.
    offset: [Real; 3],
    pub(crate) n_objects: usize,
}

impl<T> Octree<T> {
    /// An octree with a single (root) leaf over the box `root_min`–`root_max`.
    ///
    /// Errors: [`ErrorKind::NonFinite`] for a NaN/infinite corner, [`ErrorKind::EmptyRootBox`]
    /// when `root_max[k] <= root_min[k]` on some axis (or the extent overflows),
    /// [`ErrorKind::InvalidLevels`].
    pub fn new(root_min: Point, root_max: Point, params: OctreeParams) -> Result<Octree<T>, Error> {
        params.validate()?;
        check_point(&root_min, "root box corner")?;
        check_point(&root_max, "root box corner")?;
        let mut scale = [0.0; 3];
        let mut offset = [0.0; 3];
        for k in 0..3 {
            let extent = root_max[k] - root_min[k];
            scale[k] = 1.0 / extent;
            offset[k] = -root_min[k];
            let ok = extent > 0.0 && extent.is_finite() && scale[k].is_finite();
            if !ok {
                return Err(Error::new(ErrorKind::EmptyRootBox));
            }
        }
        Ok(Octree {
            cells: vec![Cell {
                min_key: [0; 3],
                level: params.root_level,
                children: None,
                objects: Vec::new(),
            }],
            params,
            root_aabb: Aabb::new(root_min, root_max),
            scale,
            offset,
            n_objects: 0,
        })
    }

    /// [`Octree::new`] with Kratos' parameters ([`OctreeParams::default`]).
    pub fn with_kratos_params(root_min: Point, root_max: Point) -> Result<Octree<T>, Error> {
        Octree::new(root_min, root_max, OctreeParams::default())
    }

    /// The root box given at construction.
    pub fn root_aabb(&self) -> Aabb {
        self.root_aabb
    }

    /// The parameters given at construction.
    pub fn params(&self) -> &OctreeParams {
        &self.params
    }

    /// The number of objects inserted (each counted once, whatever the number of its leaves).
    pub fn n_objects(&self) -> usize {
        self.n_objects
    }

    /// The number of cells (inner cells and leaves).
    pub fn n_cells(&self) -> usize {
        self.cells.len()
    }

    /// The number of leaves.
    pub fn n_leaves(&self) -> usize {
        self.cells.iter().filter(|c| c.children.is_none()).count()
    }

    /// The objects stored in `leaf`, in insertion order.
    pub fn leaf_items(&self, leaf: LeafId) -> &[T] {
        &self.cells[leaf.0 as usize].objects
    }

    /// The level of `leaf` (`min_level ..= root_level`).
    pub fn leaf_level(&self, leaf: LeafId) -> u32 {
        self.cells[leaf.0 as usize].level
    }

    /// The box of `leaf` in real coordinates (without the cell tolerance).
    pub fn leaf_aabb(&self, leaf: LeafId) -> Aabb {
        let (low, high) = self.cell_box_normalized(leaf.0);
        Aabb::new(self.scale_back(low), self.scale_back(high))
    }

    /// Kratos' `NormalizeCoordinates`: `(x + offset) · scale` per axis.
    pub(crate) fn normalize(&self, p: &Point) -> [Real; 3] {
        std::array::from_fn(|k| (p[k] + self.offset[k]) * self.scale[k])
    }

    /// Kratos' `ScaleBackToOriginalCoordinate`: `x̂ / scale − offset` per axis.
    pub(crate) fn scale_back(&self, x: [Real; 3]) -> Point {
        Point::new(
            x[0] / self.scale[0] - self.offset[0],
            x[1] / self.scale[1] - self.offset[1],
            x[2] / self.scale[2] - self.offset[2],
        )
    }

    /// The integer key of a normalised coordinate, `floor(2^root_level · x̂)`, clamped to the
    /// root cell (`0 ..= 2^root_level − 1`). Kratos does not clamp: a coordinate outside
    /// `[0, 1]` is undefined behaviour there and `x̂ = 1` falls into the *lowest* child; the
    /// clamp only matters for boxes touching or leaving the root box.
    pub(crate) fn key(&self, x: Real) -> u32 {
        let n = (1u32 << self.params.root_level) as Real;
        let k = (n * x.clamp(0.0, 1.0)) as u32;
        k.min((1u32 << self.params.root_level) - 1)
    }

    /// The normalised box of cell `cell`: `[key · s, key · s + 2^level · s]`, `s = 2^−root`.
    pub(crate) fn cell_box_normalized(&self, cell: u32) -> ([Real; 3], [Real; 3]) {
        let cell = &self.cells[cell as usize];
        let unit = 1.0 / (1u32 << self.params.root_level) as Real;
        let size = (1u32 << cell.level) as Real * unit;
        let low: [Real; 3] = std::array::from_fn(|k| cell.min_key[k] as Real * unit);
        let high: [Real; 3] = std::array::from_fn(|k| low[k] + size);
        (low, high)
    }

    /// The position (0..8) among the children of a cell of level `level` of the child
    /// containing the keys `keys` (Kratos' `GetChildIndex`).
    pub(crate) fn child_index(level: u32, keys: [u32; 3]) -> u32 {
        let bit = level - 1;
        ((keys[0] >> bit) & 1) | (((keys[1] >> bit) & 1) << 1) | (((keys[2] >> bit) & 1) << 2)
    }

    /// Splits the leaf `cell` into 8 children of the next level (no-op when it already has
    /// children or is at level 0).
    pub(crate) fn subdivide(&mut self, cell: u32) {
        let c = &self.cells[cell as usize];
        if c.children.is_some() || c.level == 0 {
            return;
        }
        let level = c.level - 1;
        let min_key = c.min_key;
        // Fits: a tree with 2^32 cells would need hundreds of GiB.
        let first = self.cells.len() as u32;
        for i in 0..8u32 {
            self.cells.push(Cell {
                min_key: [
                    min_key[0] | ((i & 1) << level),
                    min_key[1] | (((i >> 1) & 1) << level),
                    min_key[2] | (((i >> 2) & 1) << level),
                ],
                level,
                children: None,
                objects: Vec::new(),
            });
        }
        self.cells[cell as usize].children = Some(first);
    }
}
