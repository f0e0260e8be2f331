//! `csm search --vtk OUT.vtu` (and `csm demo`): the mesh, the contact flags and the pairs of
//! a search as one VTK UnstructuredGrid for ParaView.
//!
//! - Points: the nodes (current coordinates), then one point per condition that takes part in
//!   a pair, at its centre (the mean of its nodes).
//! - Cells: the elements, the conditions, then one line cell per (slave, master) pair from the
//!   slave condition's centre to the master's, in pair key, slave id, master id order.
//! - Point data: `SLAVE`, `MASTER`, `ACTIVE`, `INTERFACE` as 1 (true), 0 (false) or −1
//!   (undefined, Kratos' tri-state flags; `Int8`, as the cell data's flags), `normal_gap` (NaN where RESULT.json has null);
//!   centre points get −1 and NaN. Built-in: `node_id`.
//! - Cell data: `SLAVE`, `MASTER`, `ACTIVE` of the conditions (−1 on elements and pairs),
//!   `condition_id` (the condition's id; the slave's on a pair; −1 on elements),
//!   `master_id` (the master's id on a pair, else −1), `pair_key` (on pairs, else −1).
//!   Built-in: `entity_kind` (0 element, 1 condition, 2 pair) and `entity_id`.

use std::collections::BTreeMap;
use std::path::Path;

use csm_geometry::math::{Point, Vector};
use csm_io::{DataArray, VtuFormat, VtuWriter};
use csm_model::{Flag, Flags, ModelPart};
use csm_search::SearchResult;

/// 1, 0 or −1 (undefined).
fn tri_state(flags: &Flags, flag: Flag) -> i8 {
    if !flags.is_defined(flag) {
        -1
    } else if flags.is(flag) {
        1
    } else {
        0
    }
}

fn ints(values: Vec<i64>) -> DataArray {
    DataArray::I64 {
        components: 1,
        values,
    }
}

/// Tri-state flags (`Int8`).
fn flags(values: Vec<i8>) -> DataArray {
    DataArray::I8 {
        components: 1,
        values,
    }
}

/// The pairs of `result` as (key, slave condition index, master condition index), in key,
/// slave id, master id order; pairs naming a condition the model does not have are skipped.
fn pair_list(model: &ModelPart, result: &SearchResult) -> Vec<(i64, usize, usize)> {
    let conditions = model.conditions();
    let mut out = Vec::new();
    for (key, slaves) in &result.pairs {
        let key = key.parse::<i64>().unwrap_or(-1);
        for (&slave, masters) in slaves {
            let Some(s) = conditions.index_of(slave) else {
                continue;
            };
            for &master in masters {
                if let Some(m) = conditions.index_of(master) {
                    out.push((key, s, m));
                }
            }
        }
    }
    out
}

fn centre(model: &ModelPart, condition: usize) -> Point {
    let xyz = model.nodes().coordinates();
    let nodes = model.conditions().nodes(condition);
    let sum: Vector = nodes.iter().map(|n| xyz[n.index()].coords).sum();
    Point::from(sum / nodes.len().max(1) as f64)
}

/// A writer of `model` with the flags, gaps and pairs of `result` (see the module doc).
pub fn search_vtu<'a>(model: &'a ModelPart, result: &SearchResult) -> VtuWriter<'a> {
    let n_nodes = model.nodes().len();
    let pairs = pair_list(model, result);
    // One centre point per condition in a pair, in condition index order.
    let mut centre_of: BTreeMap<usize, usize> = BTreeMap::new();
    for &(_, s, m) in &pairs {
        centre_of.insert(s, 0);
        centre_of.insert(m, 0);
    }
    let mut centres = Vec::with_capacity(centre_of.len());
    for (k, (&c, point)) in centre_of.iter_mut().enumerate() {
        *point = n_nodes + k;
        centres.push(centre(model, c));
    }
    let lines: Vec<[usize; 2]> = pairs
        .iter()
        .map(|&(_, s, m)| [centre_of[&s], centre_of[&m]])
        .collect();

    let mut w = VtuWriter::new(model);
    w.extra_points(&centres).point_line_cells(&lines);

    let node_flags = model.nodes().flags();
    for (name, flag) in [
        ("SLAVE", Flag::SLAVE),
        ("MASTER", Flag::MASTER),
        ("ACTIVE", Flag::ACTIVE),
        ("INTERFACE", Flag::INTERFACE),
    ] {
        w.point_data(
            name,
            flags(node_flags.iter().map(|f| tri_state(f, flag)).collect()),
        );
    }
    let mut gap = vec![f64::NAN; n_nodes];
    for (&id, node) in &result.nodes {
        if let (Some(i), Some(g)) = (model.nodes().index_of(id), node.normal_gap) {
            gap[i.index()] = g;
        }
    }
    w.point_data(
        "normal_gap",
        DataArray::F64 {
            components: 1,
            values: gap,
        },
    );

    let n_elements = model.elements().len();
    let n_pairs = pairs.len();
    let undefined = |n: usize| std::iter::repeat_n(-1i64, n);
    let cond_flags = model.conditions().flags();
    for (name, flag) in [
        ("SLAVE", Flag::SLAVE),
        ("MASTER", Flag::MASTER),
        ("ACTIVE", Flag::ACTIVE),
    ] {
        let values = std::iter::repeat_n(-1, n_elements)
            .chain(cond_flags.iter().map(|f| tri_state(f, flag)))
            .chain(std::iter::repeat_n(-1, n_pairs))
            .collect();
        w.cell_data(name, flags(values));
    }
    let cond_ids = model.conditions().ids();
    let id = |i: usize| i64::from(cond_ids[i]);
    let condition_id = undefined(n_elements)
        .chain(cond_ids.iter().map(|&i| i64::from(i)))
        .chain(pairs.iter().map(|&(_, s, _)| id(s)))
        .collect();
    w.cell_data("condition_id", ints(condition_id));
    let master_id = undefined(n_elements + cond_ids.len())
        .chain(pairs.iter().map(|&(_, _, m)| id(m)))
        .collect();
    w.cell_data("master_id", ints(master_id));
    let pair_key = undefined(n_elements + cond_ids.len())
        .chain(pairs.iter().map(|&(k, _, _)| k))
        .collect();
    w.cell_data("pair_key", ints(pair_key));
    w
}

/// Writes [`search_vtu`] to `path` in `format`.
pub fn write_search_vtu(
    model: &ModelPart,
    result: &SearchResult,
    path: &Path,
    format: VtuFormat,
) -> Result<(), String> {
    search_vtu(model, result)
        .write_file(path, format)
        .map_err(|e| e.to_string())
}
