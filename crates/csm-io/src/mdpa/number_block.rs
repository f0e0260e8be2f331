//! Blocks of plain numbers (`Nodes`, `Elements`, `Conditions`, the id lists of sub model
//! parts) parsed in parallel.
//!
//! The word-by-word cursor handles every form a file may take (comments anywhere, records
//! split over lines, odd whitespace); most files have none of that inside their big blocks.
//! When the body of such a block holds nothing but number characters, spaces, tabs and line
//! ends up to its `End`, it is cut at line ends into windows of a few MiB, each window into one
//! chunk per worker, and the chunks are tokenised and parsed in parallel (ids digit by digit,
//! coordinates with the standard library's `parse` that the cursor's nom parser ends in: the
//! same values on every word of number characters, tested); the records are then used in file
//! order, so the model is the one the cursor would build. A chunk whose words do not make whole records
//! of the expected kinds makes the caller go on with the cursor from the start of its window
//! (nothing of that window has been used yet), so every error — a bad word, a record split
//! over a chunk boundary, a missing `End` — is the cursor's own.

use rayon::prelude::*;

/// The bytes a window of a block holds (cut at a line end); its chunks are parsed in parallel.
/// Bounds the parsed records held at once.
pub(crate) const WINDOW_BYTES: usize = 4 << 20;

/// The whitespace of a plain body (the cursor's `multispace1`).
fn is_plain_space(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\r' | b'\n')
}

/// The end of the plain body of a block that starts at `start`: the offset of the word `End`
/// that closes it, if every byte before it is a number character (`0-9 + - . e E`) or plain
/// whitespace. `None` otherwise (a comment, a name, another whitespace byte, no `End`).
pub(crate) fn plain_body_end(data: &[u8], start: usize) -> Option<usize> {
    plain_body_end_with(data, start, SCAN_BYTES)
}

/// [`plain_body_end`], scanned in slices of `scan` bytes, a group of them (one per worker) in
/// parallel, group after group, so that little is scanned beyond the block's end.
fn plain_body_end_with(data: &[u8], start: usize, scan: usize) -> Option<usize> {
    let scan = scan.max(1);
    let workers = rayon::current_num_threads().max(1);
    let mut group = start;
    while group < data.len() {
        let group_end = group
            .saturating_add(workers.saturating_mul(scan))
            .min(data.len());
        let stops: Vec<Option<Stop>> = (group..group_end)
            .step_by(scan)
            .collect::<Vec<_>>()
            .into_par_iter()
            .map(|a| first_stop(data, start, (a, a.saturating_add(scan).min(group_end))))
            .collect();
        match stops.into_iter().flatten().next() {
            Some(Stop::End(i)) => return Some(i),
            Some(Stop::NotPlain) => return None,
            None => group = group_end,
        }
    }
    None
}

/// The bytes one worker scans in [`plain_body_end`].
const SCAN_BYTES: usize = 1 << 20;

/// Where the scan of a plain body stops.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Stop {
    /// The closing `End` at this offset.
    End(usize),
    /// A byte a plain body cannot hold (or another word starting with `E`).
    NotPlain,
}

/// The first stop in `data[a..b]` of the scan of a plain body starting at `start`.
fn first_stop(data: &[u8], start: usize, (a, b): (usize, usize)) -> Option<Stop> {
    for i in a..b {
        match data[i] {
            b'0'..=b'9' | b'+' | b'-' | b'.' | b'e' => {}
            c if is_plain_space(c) => {}
            b'E' => {
                if i == start || is_plain_space(data[i - 1]) {
                    let end = i + 3;
                    let ends_word = end == data.len()
                        || data.get(end).is_some_and(|&c| c.is_ascii_whitespace());
                    return Some(if data[i..].starts_with(b"End") && ends_word {
                        Stop::End(i)
                    } else {
                        Stop::NotPlain
                    });
                }
            }
            _ => return Some(Stop::NotPlain),
        }
    }
    None
}

/// The end of the window that starts at `at` in a body ending at `end`: just past the first
/// line end at or after `at + bytes`, or `end`.
pub(crate) fn window_end(data: &[u8], at: usize, end: usize, bytes: usize) -> usize {
    let target = at.saturating_add(bytes);
    if target >= end {
        return end;
    }
    data[target..end]
        .iter()
        .position(|&b| b == b'\n')
        .map_or(end, |k| target + k + 1)
}

/// The records a body of `body_bytes` likely holds when its first window of `window_bytes`
/// held `records` (for reserving room; a few more than the proportion).
pub(crate) fn estimate_records(records: usize, window_bytes: usize, body_bytes: usize) -> usize {
    if window_bytes == 0 {
        return records;
    }
    let estimate = records as f64 * (body_bytes as f64 / window_bytes as f64) * 1.01;
    (estimate as usize).saturating_add(16)
}

/// What the words of a record are.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Record {
    /// A node: an id and three finite coordinates.
    Node,
    /// `n` ids (32 bits each).
    Ids(usize),
}

/// The parsed records of a window, in file order.
#[derive(Debug, Default, PartialEq)]
pub(crate) struct Parsed {
    /// The ids: one per node, or `n` per record of [`Record::Ids`].
    pub(crate) ids: Vec<u32>,
    /// The coordinates of the nodes (empty for [`Record::Ids`]).
    pub(crate) coordinates: Vec<[f64; 3]>,
}

impl Parsed {
    /// The parts one after the other: each list concatenated in parallel ([`concat`]).
    fn concat(parts: Vec<Parsed>) -> Parsed {
        let (ids, coordinates): (Vec<_>, Vec<_>) =
            parts.into_iter().map(|p| (p.ids, p.coordinates)).unzip();
        let (ids, coordinates) = rayon::join(|| concat(ids), || concat(coordinates));
        Parsed { ids, coordinates }
    }
}

/// `parts` one after the other. A single part is moved; several are copied in parallel into
/// one zeroed list (the allocator's zero pages: each part's pages are first touched by the
/// thread that copies it, not by one thread for all).
fn concat<T: Copy + Default + Send + Sync>(mut parts: Vec<Vec<T>>) -> Vec<T> {
    if parts.len() <= 1 {
        return parts.pop().unwrap_or_default();
    }
    let total = parts.iter().map(Vec::len).sum();
    let mut out = vec![T::default(); total];
    csm_model::copy_parts_into(&mut out, &parts);
    out
}

/// Parses the window `data[at..end]` (whole lines of a plain body) in parallel, in eight
/// chunks per worker (at least `min_chunk` bytes each; one chunk on one thread); `None` when a
/// chunk does not hold whole records of the kind `record`.
pub(crate) fn parse_window(
    data: &[u8],
    (at, end): (usize, usize),
    record: Record,
    min_chunk: usize,
) -> Option<Parsed> {
    let workers = rayon::current_num_threads().max(1);
    let bounds = piece_bounds(data, (at, end), workers, min_chunk);
    if let [(from, to)] = bounds[..] {
        return parse_chunk(&data[from..to], record);
    }
    // Every piece a task of its own (rayon's own split would leave a thread that joins late
    // nothing to take: its halves are only split again where they are stolen).
    let parts: Option<Vec<Parsed>> = bounds
        .into_par_iter()
        .with_max_len(1)
        .map(|(from, to)| parse_chunk(&data[from..to], record))
        .collect();
    Some(Parsed::concat(parts?))
}

/// The pieces `parse_window` parses `data[at..end]` in, each ending after a line end (or at
/// `end`), at least `min_chunk` bytes: eight per worker where there are several, one on one
/// thread. The window is parsed while another thread inserts the last one
/// (`parallel_records`); that thread, once done, takes the pieces still waiting. One thread
/// parses the window whole, and its list is moved without a copy.
fn piece_bounds(
    data: &[u8],
    (at, end): (usize, usize),
    workers: usize,
    min_chunk: usize,
) -> Vec<(usize, usize)> {
    let pieces = if workers > 1 { workers * 8 } else { 1 };
    let chunk = ((end - at) / pieces).max(min_chunk.max(1));
    let mut bounds = Vec::with_capacity(pieces + 1);
    let mut from = at;
    while from < end {
        let to = window_end(data, from, end, chunk);
        bounds.push((from, to));
        from = to;
    }
    bounds
}

/// The words of `chunk` as records of kind `record`, or `None`.
fn parse_chunk(chunk: &[u8], record: Record) -> Option<Parsed> {
    let mut out = Parsed::default();
    // A plain body is ASCII, so the chunk is text; its whitespace is ASCII whitespace without
    // form feeds (see `plain_body_end`), which is what `split_ascii_whitespace` splits at.
    let mut words = std::str::from_utf8(chunk).ok()?.split_ascii_whitespace();
    let coordinate = |w: Option<&str>| w.and_then(parse_coordinate);
    match record {
        Record::Node => {
            while let Some(w) = words.next() {
                out.ids.push(parse_id(w.as_bytes())?);
                let x = coordinate(words.next())?;
                let y = coordinate(words.next())?;
                let z = coordinate(words.next())?;
                out.coordinates.push([x, y, z]);
            }
        }
        Record::Ids(n) => {
            let mut count = 0usize;
            for w in words {
                out.ids.push(parse_id(w.as_bytes())?);
                count += 1;
            }
            if n == 0 || !count.is_multiple_of(n) {
                return None;
            }
        }
    }
    Some(out)
}

/// An id word: what the cursor's `parse_u64` accepts (decimal digits only) and `u32` holds.
fn parse_id(w: &[u8]) -> Option<u32> {
    if w.is_empty() {
        return None;
    }
    let mut v: u32 = 0;
    for &b in w {
        if !b.is_ascii_digit() {
            return None;
        }
        v = v.checked_mul(10)?.checked_add(u32::from(b - b'0'))?;
    }
    Some(v)
}

/// A finite coordinate word. On a plain word (number characters only) the cursor's
/// `parse_f64` recognises the same decimal grammar (sign, digits, point, exponent) and then
/// converts with the standard library's correctly rounded `parse`, which is called here
/// directly (tested against it).
fn parse_coordinate(w: &str) -> Option<f64> {
    w.parse::<f64>().ok().filter(|x| x.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cursor::{parse_f64, parse_u64};
    use proptest::prelude::*;

    proptest! {
        /// The plain-word parsers are the cursor's on every word of number characters.
        #[test]
        fn word_parsers_are_the_cursors(w in "[0-9eE.+-]{1,12}") {
            let cursor_id = parse_u64(&w).and_then(|v| u32::try_from(v).ok());
            prop_assert_eq!(parse_id(w.as_bytes()), cursor_id);
            let cursor_x = parse_f64(&w).filter(|x| x.is_finite());
            prop_assert_eq!(parse_coordinate(&w).map(f64::to_bits), cursor_x.map(f64::to_bits));
        }

        #[test]
        fn numeric_words_parse_like_the_cursor(
            x in any::<f64>().prop_filter("finite", |x| x.is_finite()),
            digits in 0usize..20,
            id in any::<u64>(),
        ) {
            for w in [format!("{x}"), format!("{x:e}"), format!("{x:E}"), format!("{x:+.digits$e}"), format!("{x:.digits$}")] {
                prop_assert_eq!(
                    parse_coordinate(&w).map(f64::to_bits),
                    parse_f64(&w).filter(|x| x.is_finite()).map(f64::to_bits),
                    "{}", w
                );
            }
            for w in [id.to_string(), (id % 5_000_000_000).to_string(), format!("00{}", id % 1000)] {
                prop_assert_eq!(parse_id(w.as_bytes()), parse_u64(&w).and_then(|v| u32::try_from(v).ok()));
            }
        }
    }

    /// The parts' lists one after the other, empty parts included, on 1 and 3 threads; a
    /// single part as it is.
    #[test]
    fn parts_are_concatenated_in_order() {
        let parts: Vec<Vec<u32>> = vec![vec![1, 2, 3], vec![], vec![4], (5..5000).collect()];
        let serial: Vec<u32> = parts.concat();
        for threads in [1, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            assert_eq!(
                pool.install(|| concat(parts.clone())),
                serial,
                "{threads} threads"
            );
        }
        let points = vec![
            vec![[1.0, 2.0, 3.0]],
            vec![[4.0, 5.0, 6.0], [7.0, 8.0, 9.0]],
        ];
        assert_eq!(concat(points.clone()), points.concat());
        assert_eq!(concat(vec![vec![7u32, 8]]), [7, 8]);
        assert!(concat(Vec::<Vec<u32>>::new()).is_empty());
    }
    #[test]
    fn the_plain_body_ends_at_its_end_word() {
        let text = b"Begin Nodes\n 1 1.5e-3 -2E+1 3\nEnd Nodes\n";
        let start = "Begin Nodes".len();
        let end = plain_body_end(text, start).unwrap();
        assert_eq!(&text[end..end + 9], b"End Nodes");
        // An exponent `E` inside a number is not the end.
        assert_eq!(plain_body_end(b" 1 2E5 3 4\nEnd", 0), Some(11));
        // Comments, names, form feeds, a missing `End` or an `Ending` word: not plain.
        let not_plain = [
            &b" 1 0 0 0 // c\nEnd Nodes"[..],
            b" 1 0 0 0 /* c */\nEnd Nodes",
            b" 1 0 0 nan\nEnd Nodes",
            b" 1 0 0\x0c0\nEnd Nodes",
            b" 1 0 0 0\n",
            b" 1 0 0 0\nEnding",
            b"E 1",
        ];
        for text in not_plain {
            assert_eq!(
                plain_body_end(text, 0),
                None,
                "{:?}",
                String::from_utf8_lossy(text)
            );
        }
        // Any slicing of the scan gives the same answer.
        let plain = [&b" 1 2E5 3 4\nEnd"[..], b" 1 0 0 0\n 2 1 1 1\nEnd Nodes\n"];
        for text in plain.into_iter().chain(not_plain) {
            for scan in 1..8 {
                assert_eq!(
                    plain_body_end_with(text, 0, scan),
                    plain_body_end_with(text, 0, usize::MAX)
                );
            }
        }
    }

    #[test]
    fn windows_end_after_a_line_end() {
        let text = b"1 2\n3 4\n5 6\nEnd";
        assert_eq!(window_end(text, 0, 12, 1), 4);
        assert_eq!(window_end(text, 4, 12, 4), 12);
        assert_eq!(window_end(text, 0, 12, 100), 12);
    }

    #[test]
    fn the_estimate_scales_the_first_window_to_the_body() {
        assert!((100..=120).contains(&estimate_records(10, 100, 1000)));
        assert_eq!(estimate_records(7, 0, 1000), 7);
        // Absurd sizes saturate instead of overflowing.
        assert!(estimate_records(usize::MAX, 1, usize::MAX) > 0);
    }

    #[test]
    fn a_window_is_cut_in_eight_pieces_per_worker_or_kept_whole() {
        let text = "1 0 0 0\n".repeat(1000).into_bytes();
        let whole = (0, text.len());
        for workers in [2, 3] {
            let bounds = piece_bounds(&text, whole, workers, 1);
            assert!(bounds.len() >= 8 * workers, "{workers}: {}", bounds.len());
            assert!(
                bounds.len() <= 8 * workers + 1,
                "{workers}: {}",
                bounds.len()
            );
            // Consecutive, covering the window, each ending after a line end.
            assert_eq!((bounds[0].0, bounds[bounds.len() - 1].1), whole);
            for w in bounds.windows(2) {
                assert_eq!(w[0].1, w[1].0);
                assert_eq!(text[w[0].1 - 1], b'\n');
            }
        }
        assert_eq!(piece_bounds(&text, whole, 1, 1), [whole]);
        // No piece below `min_chunk` (but the last).
        assert_eq!(piece_bounds(&text, whole, 2, text.len()), [whole]);
    }

    #[test]
    fn chunks_parse_to_the_records_of_the_window() {
        let text = b"1 0 0 0\n2 1.5 -2 3e2\n3 4 5 6\n";
        for min_chunk in [1, 5, 1000] {
            let p = parse_window(text, (0, text.len()), Record::Node, min_chunk).unwrap();
            assert_eq!(p.ids, [1, 2, 3]);
            assert_eq!(p.coordinates[1], [1.5, -2.0, 300.0]);
        }
        let ids = b"7 1 1 2 3\n8 1 2 3 4\n";
        let p = parse_window(ids, (0, ids.len()), Record::Ids(5), 1).unwrap();
        assert_eq!(p.ids, [7, 1, 1, 2, 3, 8, 1, 2, 3, 4]);
        assert!(p.coordinates.is_empty());
    }

    #[test]
    fn a_chunk_without_whole_valid_records_gives_up() {
        // A record split over two lines, which become two chunks.
        let split = b"1 0 0\n0\n";
        assert!(parse_window(split, (0, split.len()), Record::Node, 1).is_none());
        assert!(parse_window(split, (0, split.len()), Record::Node, 100).is_some());
        let ids = b"7 1 1\n2 3\n";
        assert!(parse_window(ids, (0, ids.len()), Record::Ids(5), 1).is_none());
        // Words that are not what the record needs.
        for bad in [
            &b"1 0 0 1e999\n"[..],
            b"1.5 0 0 0\n",
            b"4294967296 0 0 0\n",
            b"1 0 0\n",
        ] {
            assert!(parse_window(bad, (0, bad.len()), Record::Node, 1).is_none());
        }
        assert!(parse_window(b"1 -2\n", (0, 5), Record::Ids(1), 1).is_none());
    }
}
