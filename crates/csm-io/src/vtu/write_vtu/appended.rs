//! The binary form's appended block: each array's byte count (`UInt64`) and its values as
//! little-endian bytes, cut into tasks that rayon's pool encodes while one thread writes
//! ([`csm_model::write_in_order`]). The bytes are those of encoding every array in order on
//! one thread.

use std::io::Write;
use std::ops::Range;

use csm_model::{Entities, write_in_order};
use rayon::prelude::*;

use super::{DataArray, Value, VtuWriter, vtk_cell_type, vtk_permutation};

/// Values, points or cells per task (a few in the unit tests, to cross the boundaries).
#[cfg(not(test))]
const ITEMS_PER_TASK: usize = 1 << 14;
#[cfg(test)]
const ITEMS_PER_TASK: usize = 7;
/// Tasks per batch at least (see [`write_in_order`]).
const TASKS_PER_BATCH: usize = 8;

/// Encodes a range of an array's units.
type Encode<'s> = Box<dyn Fn(Range<usize>, &mut Vec<u8>) + Sync + 's>;

/// One array of the block: `items` units (values, points or cells) making `bytes` bytes,
/// encoded a range of units at a time.
pub(super) struct Array<'s> {
    pub(super) bytes: usize,
    items: usize,
    encode: Encode<'s>,
}

impl<'s> Array<'s> {
    fn new(
        items: usize,
        bytes: usize,
        encode: impl Fn(Range<usize>, &mut Vec<u8>) + Sync + 's,
    ) -> Array<'s> {
        Array {
            bytes,
            items,
            encode: Box::new(encode),
        }
    }

    /// `values`, padded to `len` values (NaN, −1).
    fn values<T: Value + Sync>(values: &'s [T], len: usize) -> Array<'s> {
        Array::new(len, len * T::SIZE, move |r, out| {
            for i in r {
                put(out, values.get(i).copied().unwrap_or(T::PAD));
            }
        })
    }

    /// `value(i)` for `i` in `0..len`, as `Int32` (`narrow`) or `Int64`.
    fn ints(len: usize, narrow: bool, value: impl Fn(usize) -> i64 + Sync + 's) -> Array<'s> {
        let size = if narrow { 4 } else { 8 };
        Array::new(len, len * size, move |r, out| {
            for i in r {
                put_int(out, value(i), narrow);
            }
        })
    }
}

fn put<T: Value>(out: &mut Vec<u8>, v: T) {
    let n = out.len();
    out.resize(n + T::SIZE, 0);
    v.bytes(&mut out[n..]);
}

fn put_int(out: &mut Vec<u8>, v: i64, narrow: bool) {
    if narrow {
        put(out, v as i32);
    } else {
        put(out, v);
    }
}

/// A cell: an element or condition (its entities, index and `entity_kind`: 0 or 1), or a
/// line cell.
enum Cell<'m> {
    Entity(&'m Entities, usize, i8),
    Line(usize),
}

/// The arrays' types, as the XML names them.
#[derive(Clone, Copy)]
pub(super) struct Narrow {
    /// Node ids `Int32`.
    pub(super) node_ids: bool,
    /// Entity ids `Int32`.
    pub(super) entity_ids: bool,
    /// Connectivity and offsets `Int32`.
    pub(super) indices: bool,
}

impl VtuWriter<'_> {
    fn cell(&self, i: usize) -> Cell<'_> {
        let (elements, conditions) = (self.model.elements(), self.model.conditions());
        if i < elements.len() {
            Cell::Entity(elements, i, 0)
        } else if i < elements.len() + conditions.len() {
            Cell::Entity(conditions, i - elements.len(), 1)
        } else {
            Cell::Line(i - elements.len() - conditions.len())
        }
    }

    /// The nodes of cell `i` (point indices), in VTK's order.
    fn cell_points(&self, i: usize, mut point: impl FnMut(usize)) {
        match self.cell(i) {
            Cell::Entity(e, k, _) => {
                let nodes = e.nodes(k);
                let p = vtk_permutation(e.kind(k)).filter(|p| p.len() == nodes.len());
                for j in 0..nodes.len() {
                    point(nodes[p.map_or(j, |p| p[j])].index());
                }
            }
            Cell::Line(l) => self.lines[l].iter().for_each(|&p| point(p)),
        }
    }

    fn cell_len(&self, i: usize) -> usize {
        match self.cell(i) {
            Cell::Entity(e, k, _) => e.nodes(k).len(),
            Cell::Line(_) => 2,
        }
    }

    /// The arrays of the appended block, in the XML's order: `node_id`, the point data,
    /// `entity_id`, `entity_kind`, the cell data, the points, `connectivity`, `offsets`,
    /// `types`.
    pub(super) fn appended_arrays(&self, narrow: &Narrow, n_conn: usize) -> Vec<Array<'_>> {
        let Narrow {
            node_ids: narrow_node_ids,
            entity_ids: narrow_entity_ids,
            indices: narrow_indices,
        } = *narrow;
        let (n_points, n_cells) = (self.n_points(), self.n_cells());
        let nodes = self.model.nodes();
        let n_nodes = nodes.len();
        let node_ids = nodes.ids();
        let mut arrays = vec![Array::ints(n_points, narrow_node_ids, move |i| {
            node_ids.get(i).map_or(-1, |&id| i64::from(id))
        })];
        arrays.extend(data(&self.point_data, n_points));
        arrays.push(Array::ints(
            n_cells,
            narrow_entity_ids,
            move |i| match self.cell(i) {
                Cell::Entity(e, k, _) => i64::from(e.ids()[k]),
                Cell::Line(l) => l as i64,
            },
        ));
        arrays.push(Array::new(n_cells, n_cells, move |r, out| {
            for i in r {
                let kind = match self.cell(i) {
                    Cell::Entity(.., kind) => kind,
                    Cell::Line(_) => 2,
                };
                put(out, kind);
            }
        }));
        arrays.extend(data(&self.cell_data, n_cells));
        let xyz = nodes.coordinates();
        arrays.push(Array::new(n_points, 24 * n_points, move |r, out| {
            for i in r {
                let p = if i < n_nodes {
                    &xyz[i]
                } else {
                    &self.extra_points[i - n_nodes]
                };
                for x in [p.x, p.y, p.z] {
                    put(out, x);
                }
            }
        }));
        let size = if narrow_indices { 4 } else { 8 };
        arrays.push(Array::new(n_cells, n_conn * size, move |r, out| {
            for i in r {
                self.cell_points(i, |p| put_int(out, p as i64, narrow_indices));
            }
        }));
        // Each task's first offset follows the node counts of the tasks before.
        let sums: Vec<usize> = (0..n_cells.div_ceil(ITEMS_PER_TASK))
            .into_par_iter()
            .map(|t| {
                let r = t * ITEMS_PER_TASK..((t + 1) * ITEMS_PER_TASK).min(n_cells);
                r.map(|i| self.cell_len(i)).sum()
            })
            .collect();
        let before: Vec<usize> = (sums.iter())
            .scan(0, |end, s| Some(std::mem::replace(end, *end + s)))
            .collect();
        arrays.push(Array::new(n_cells, n_cells * size, move |r, out| {
            let mut end = before[r.start / ITEMS_PER_TASK];
            for i in r {
                end += self.cell_len(i);
                put_int(out, end as i64, narrow_indices);
            }
        }));
        arrays.push(Array::new(n_cells, n_cells, move |r, out| {
            for i in r {
                let t = match self.cell(i) {
                    Cell::Entity(e, k, _) => vtk_cell_type(e.kind(k)),
                    Cell::Line(_) => 3,
                };
                put(out, t);
            }
        }));
        arrays
    }
}

/// The arrays of `list` (point or cell data), `n` tuples each (padded).
fn data(list: &[(String, DataArray)], n: usize) -> impl Iterator<Item = Array<'_>> {
    list.iter().map(move |(_, a)| {
        let len = n * a.components();
        with_values!(a, values => Array::values(values, len))
    })
}

/// Writes `arrays`: each one's byte count, then its values, in tasks of
/// [`ITEMS_PER_TASK`] units encoded in parallel and written in order.
pub(super) fn write_arrays(out: &mut dyn Write, arrays: &[Array<'_>]) -> std::io::Result<()> {
    let mut tasks: Vec<(usize, Range<usize>)> = Vec::new();
    for (a, array) in arrays.iter().enumerate() {
        let starts = (0..array.items.max(1)).step_by(ITEMS_PER_TASK);
        tasks.extend(starts.map(|s| (a, s..(s + ITEMS_PER_TASK).min(array.items))));
    }
    write_in_order(out, &tasks, TASKS_PER_BATCH, |_, (a, r)| {
        let array = &arrays[*a];
        let mut bytes = Vec::with_capacity(8 + array.bytes.min(32 * ITEMS_PER_TASK));
        if r.start == 0 {
            bytes.extend_from_slice(&(array.bytes as u64).to_le_bytes());
        }
        (array.encode)(r.clone(), &mut bytes);
        bytes
    })
}
