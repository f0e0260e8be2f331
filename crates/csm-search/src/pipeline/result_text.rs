//! RESULT.json's text, written with the big maps (`pairs`, `nodes`) formatted in parallel:
//! the same bytes as `serde_json::to_writer_pretty` of the result's serde view (tested
//! against it), in batches of entries formatted by rayon's pool and written in order.
//!
//! serde_json's pretty form indents by two spaces, puts every map entry and array item on a
//! line of its own, writes an empty map or array as `{}` / `[]`, map keys as JSON strings
//! (integers quoted) and numbers as its own formatter does (reused here for every float).
//! A JSON string never holds a raw line end, so a value pretty-printed at the top level is
//! moved to another depth by indenting every line after its first.

use std::collections::BTreeMap;
use std::io::Write;

use serde::Serialize;

use super::IdMap;
use super::result::{NodeResult, SearchResult, StepResult};

/// Map entries formatted by one task (a few in the unit tests, to cross the boundaries).
#[cfg(not(test))]
const ENTRIES_PER_TASK: usize = 4096;
#[cfg(test)]
const ENTRIES_PER_TASK: usize = 3;
/// Tasks per batch at least (the text of a batch is held at once; four per thread where
/// that is more). Small batches: the first batch's formatting is the one no write overlaps.
#[cfg(not(test))]
const TASKS_PER_BATCH: usize = 8;
#[cfg(test)]
const TASKS_PER_BATCH: usize = 2;

fn indent(out: &mut Vec<u8>, level: usize) {
    out.extend(std::iter::repeat_n(b' ', 2 * level));
}

/// Ends a map or array at depth `level` that has entries: a line end, the indentation and
/// the closing `bracket`.
fn close(w: &mut impl Write, level: usize, bracket: u8) -> std::io::Result<()> {
    let mut out = vec![b'\n'];
    indent(&mut out, level);
    out.push(bracket);
    w.write_all(&out)
}

/// `value` pretty-printed as it would be at depth `level`.
fn pretty_at(out: &mut Vec<u8>, value: &impl Serialize, level: usize) -> std::io::Result<()> {
    let text = serde_json::to_vec_pretty(value).map_err(std::io::Error::from)?;
    for (k, line) in text.split(|&b| b == b'\n').enumerate() {
        if k > 0 {
            out.push(b'\n');
            indent(out, level);
        }
        out.extend_from_slice(line);
    }
    Ok(())
}

/// Writes a map at depth `level` whose entries `format` writes (key and value, from the
/// entry's indentation on), formatted in parallel: the map's list is cut into tasks of
/// [`ENTRIES_PER_TASK`] entries each, batches of at least [`TASKS_PER_BATCH`] tasks written
/// in order. With several threads a batch is formatted while this thread writes the one
/// before.
fn write_map<V: Sync>(
    w: &mut impl Write,
    map: &IdMap<V>,
    level: usize,
    format: impl Fn(&mut Vec<u8>, u32, &V) + Sync,
) -> std::io::Result<()> {
    if map.is_empty() {
        return w.write_all(b"{}");
    }
    w.write_all(b"{")?;
    let tasks: Vec<&[(u32, V)]> = map.as_slice().chunks(ENTRIES_PER_TASK).collect();
    csm_model::write_in_order(w, &tasks, TASKS_PER_BATCH, |t, entries| {
        let mut out = Vec::new();
        for (k, (key, value)) in entries.iter().enumerate() {
            // The first task starts at the first key: every other entry follows one.
            if t > 0 || k > 0 {
                out.push(b',');
            }
            out.push(b'\n');
            indent(&mut out, level + 1);
            format(&mut out, *key, value);
        }
        out
    })?;
    close(w, level, b'}')
}

/// An integer as serde_json writes it (its integer formatter, no allocation).
fn int(out: &mut Vec<u8>, v: u32) {
    let _ = serde_json::to_writer(&mut *out, &v);
}

/// `"id": ` (a map key: the integer quoted).
fn id_key(out: &mut Vec<u8>, id: u32) {
    out.push(b'"');
    int(out, id);
    out.extend_from_slice(b"\": ");
}

/// `"id": [masters…]` at depth `level`.
fn slave_entry(out: &mut Vec<u8>, id: u32, masters: &[u32], level: usize) {
    id_key(out, id);
    if masters.is_empty() {
        out.extend_from_slice(b"[]");
        return;
    }
    out.push(b'[');
    for (k, m) in masters.iter().enumerate() {
        if k > 0 {
            out.push(b',');
        }
        out.push(b'\n');
        indent(out, level + 1);
        int(out, *m);
    }
    out.push(b'\n');
    indent(out, level);
    out.push(b']');
}

/// `"id": {"normal_gap": …, "active": …}` at depth `level`.
fn node_entry(out: &mut Vec<u8>, id: u32, node: &NodeResult, level: usize) {
    id_key(out, id);
    out.extend_from_slice(b"{\n");
    indent(out, level + 1);
    out.extend_from_slice(b"\"normal_gap\": ");
    match node.normal_gap.filter(|g| g.is_finite()) {
        // serde_json's own float text.
        Some(g) => {
            let _ = serde_json::to_writer(&mut *out, &g);
        }
        None => out.extend_from_slice(b"null"),
    }
    out.extend_from_slice(b",\n");
    indent(out, level + 1);
    out.extend_from_slice(if node.active {
        b"\"active\": true\n"
    } else {
        b"\"active\": false\n"
    });
    indent(out, level);
    out.push(b'}');
}

/// Writes the pairs map (`pair key → slave map`) at depth `level`.
fn write_pairs(
    w: &mut impl Write,
    pairs: &BTreeMap<String, IdMap<Vec<u32>>>,
    level: usize,
) -> std::io::Result<()> {
    if pairs.is_empty() {
        return w.write_all(b"{}");
    }
    w.write_all(b"{")?;
    for (k, (key, slaves)) in pairs.iter().enumerate() {
        let mut head = Vec::new();
        if k > 0 {
            head.push(b',');
        }
        head.push(b'\n');
        indent(&mut head, level + 1);
        serde_json::to_writer(&mut head, key).map_err(std::io::Error::from)?;
        head.extend_from_slice(b": ");
        w.write_all(&head)?;
        write_map(w, slaves, level + 1, |out, id, masters| {
            slave_entry(out, id, masters, level + 2);
        })?;
    }
    close(w, level, b'}')
}

/// The timings map (`json!(f64)`: a non-finite value is null).
fn timings_map(timings: &[(&str, f64)]) -> serde_json::Map<String, serde_json::Value> {
    timings
        .iter()
        .map(|(k, v)| ((*k).to_owned(), serde_json::json!(v)))
        .collect()
}

/// Writes `"key": ` at depth `level` after a separator (`first`: none).
fn key(w: &mut impl Write, name: &str, level: usize, first: bool) -> std::io::Result<()> {
    let mut head = Vec::new();
    if !first {
        head.push(b',');
    }
    head.push(b'\n');
    indent(&mut head, level);
    let _ = write!(head, "\"{name}\": ");
    w.write_all(&head)
}

/// A small value at depth `level`.
fn small(w: &mut impl Write, value: &impl Serialize, level: usize) -> std::io::Result<()> {
    let mut out = Vec::new();
    pretty_at(&mut out, value, level)?;
    w.write_all(&out)
}

/// Writes the result (or a `steps` entry, `step`) as a map at depth `level`.
fn write_result(
    w: &mut impl Write,
    r: &SearchResult,
    timings: &[(&str, f64)],
    step: Option<u32>,
    level: usize,
) -> std::io::Result<()> {
    let inner = level + 1;
    w.write_all(b"{")?;
    match step {
        None => {
            key(w, "format", inner, true)?;
            w.write_all(b"\"csm-result/1\"")?;
            key(w, "pairs", inner, false)?;
        }
        Some(s) => {
            key(w, "step", inner, true)?;
            write!(w, "{s}")?;
            key(w, "pairs", inner, false)?;
        }
    }
    write_pairs(w, &r.pairs, inner)?;
    key(w, "nodes", inner, false)?;
    write_map(w, &r.nodes, inner, |out, id, node| {
        node_entry(out, id, node, inner + 1);
    })?;
    key(w, "paired_conditions", inner, false)?;
    write!(w, "{}", r.paired_conditions)?;
    if step.is_none() {
        if let Some(n) = r.master_slave_constraints {
            key(w, "master_slave_constraints", inner, false)?;
            write!(w, "{n}")?;
        }
        if !r.kratos_condition_ids.is_empty() {
            key(w, "kratos_condition_ids", inner, false)?;
            small(w, &r.kratos_condition_ids, inner)?;
        }
        key(w, "warnings", inner, false)?;
        small(w, &r.warnings, inner)?;
    }
    key(w, "timings_s", inner, false)?;
    small(w, &timings_map(timings), inner)?;
    if step.is_none() && !r.steps.is_empty() {
        key(w, "steps", inner, false)?;
        write_steps(w, &r.steps, inner)?;
    }
    close(w, level, b'}')
}

fn write_steps(w: &mut impl Write, steps: &[StepResult], level: usize) -> std::io::Result<()> {
    w.write_all(b"[")?;
    for (k, s) in steps.iter().enumerate() {
        let mut head = Vec::new();
        if k > 0 {
            head.push(b',');
        }
        head.push(b'\n');
        indent(&mut head, level + 1);
        w.write_all(&head)?;
        write_result(
            w,
            &s.result,
            &[("search", s.search_s)],
            Some(s.step),
            level + 1,
        )?;
    }
    close(w, level, b']')
}

/// RESULT.json's text of `r` with `timings`, followed by a line end.
pub(super) fn write_result_json(
    r: &SearchResult,
    timings: &[(&str, f64)],
    mut w: impl Write,
) -> std::io::Result<()> {
    write_result(&mut w, r, timings, None, 0)?;
    w.write_all(b"\n")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A result with many entries (over several tasks and batches), repeated masters, empty
    /// lists, gaps of every kind, several pair keys and steps.
    fn big(steps: bool) -> SearchResult {
        let mut r = SearchResult::default();
        for key in ["0", "1", "a\"b"] {
            let slaves: IdMap<Vec<u32>> = (0..47u32)
                .map(|i| (i * 7 + 1, (0..i % 4).map(|k| 1000 + i + k / 3).collect()))
                .collect();
            r.pairs.insert(key.to_owned(), slaves);
        }
        r.pairs.insert("empty".to_owned(), IdMap::new());
        for i in 0..31u32 {
            let normal_gap = match i % 5 {
                0 => None,
                1 => Some(f64::NAN),
                2 => Some(-1.25e-7 * f64::from(i)),
                3 => Some(1e300),
                _ => Some(f64::from(i) / 3.0),
            };
            r.nodes.insert(
                i * 3,
                NodeResult {
                    normal_gap,
                    active: i % 2 == 0,
                },
            );
        }
        r.paired_conditions = 99;
        r.warnings = vec!["pair 0: x".into(), "ü \n".into()];
        r.kratos_condition_ids = [(10, 1), (20, 2)].into_iter().collect();
        if steps {
            r.master_slave_constraints = Some(99);
            r.steps = vec![
                StepResult {
                    step: 1,
                    result: big(false),
                    search_s: 0.25,
                },
                StepResult {
                    step: 2,
                    result: SearchResult::default(),
                    search_s: f64::NAN,
                },
            ];
        }
        r
    }

    #[test]
    fn the_parallel_text_is_serde_json_pretty() {
        for (steps, threads) in [(false, 1), (false, 2), (true, 1), (true, 2), (true, 3)] {
            let r = big(steps);
            let timings = [("read", 0.5), ("search", f64::INFINITY), ("total", 1e-9)];
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut text = Vec::new();
            pool.install(|| write_result_json(&r, &timings, &mut text))
                .unwrap();
            let tree = serde_json::to_string_pretty(&r.to_json(&timings)).unwrap() + "\n";
            assert_eq!(String::from_utf8(text).unwrap(), tree, "steps {steps}");
        }
    }
}
