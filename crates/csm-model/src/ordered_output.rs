//! Output formatted in parallel and written in order ([`write_in_order`]): the writers'
//! (RESULT.json, VTU) way of keeping one thread writing while the others format.

use std::io::Write;

use rayon::prelude::*;

/// Writes the bytes `format(k, &tasks[k])` gives for every task, in the tasks' order. The
/// tasks are formatted on rayon's pool in batches of at least `per_batch` (four per thread
/// where that is more); with several threads a batch is formatted while this thread writes
/// the one before. The output is that of the loop `for (k, t) in tasks.iter().enumerate() {
/// w.write_all(&format(k, t))? }`; an error stops the writing at the first failed write.
pub fn write_in_order<T: Sync>(
    w: &mut dyn Write,
    tasks: &[T],
    per_batch: usize,
    format: impl Fn(usize, &T) -> Vec<u8> + Sync,
) -> std::io::Result<()> {
    let threads = rayon::current_num_threads();
    let per_batch = per_batch.max(4 * threads).max(1);
    let format_batch = |b: usize, batch: &[T]| -> Vec<Vec<u8>> {
        (batch.par_iter().with_max_len(1).enumerate())
            .map(|(k, t)| format(b * per_batch + k, t))
            .collect()
    };
    let write_texts = |w: &mut dyn Write, texts: &[Vec<u8>]| -> std::io::Result<()> {
        texts.iter().try_for_each(|t| w.write_all(t))
    };
    let mut pending: Vec<Vec<u8>> = Vec::new();
    for (b, batch) in tasks.chunks(per_batch).enumerate() {
        if threads > 1 {
            let mut texts = Vec::new();
            let mut written = Ok(());
            rayon::in_place_scope(|scope| {
                scope.spawn(|_| texts = format_batch(b, batch));
                written = write_texts(w, &pending);
            });
            written?;
            pending = texts;
        } else {
            write_texts(w, &pending)?;
            pending = format_batch(b, batch);
        }
    }
    write_texts(w, &pending)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A writer that fails once it holds `limit` bytes.
    struct Limited {
        out: Vec<u8>,
        limit: usize,
    }

    impl Write for Limited {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            if self.out.len() + buf.len() > self.limit {
                return Err(std::io::Error::other("full"));
            }
            self.out.extend_from_slice(buf);
            Ok(buf.len())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    fn text(k: usize, t: &u32) -> Vec<u8> {
        format!("{k}:{t};").into_bytes()
    }

    #[test]
    fn tasks_are_written_in_order_on_any_pool() {
        let tasks: Vec<u32> = (0..1000).map(|k| k * 7 % 13).collect();
        let mut expected = Vec::new();
        for (k, t) in tasks.iter().enumerate() {
            expected.extend(text(k, t));
        }
        for (threads, per_batch) in [(1, 1), (2, 3), (3, 8), (2, 5000)] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut out = Vec::new();
            pool.install(|| write_in_order(&mut out, &tasks, per_batch, text))
                .unwrap();
            assert_eq!(out, expected, "{threads} threads, batches of {per_batch}");
        }
        let mut out = Vec::new();
        write_in_order(&mut out, &[] as &[u32], 4, text).unwrap();
        assert!(out.is_empty());
    }

    #[test]
    fn a_failed_write_is_the_error() {
        let tasks: Vec<u32> = (0..100).collect();
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut w = Limited {
                out: Vec::new(),
                limit: 50,
            };
            let r = pool.install(|| write_in_order(&mut w, &tasks, 2, text));
            assert_eq!(r.unwrap_err().to_string(), "full");
            assert!(w.out.len() <= 50);
        }
    }
}
