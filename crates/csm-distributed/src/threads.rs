//! Ranks as threads of one process ([`thread_ranks`]): the transport the tests run every rank
//! with, without MPI, and a way to run a distributed search on one machine.

use std::sync::{Arc, Barrier, Mutex};

use csm_model::Transport;

/// The board the threads gather on: one slot per rank.
#[derive(Debug)]
struct Board {
    slots: Mutex<Vec<Vec<u8>>>,
    barrier: Barrier,
}

/// One rank of a group of threads ([`thread_ranks`]).
#[derive(Debug)]
pub struct ThreadTransport {
    rank: usize,
    ranks: usize,
    board: Arc<Board>,
}

/// The transports of `ranks` ranks that run as threads of this process: give each to its own
/// thread (every rank's calls block until every rank has made the same call).
pub fn thread_ranks(ranks: usize) -> Vec<ThreadTransport> {
    let ranks = ranks.max(1);
    let board = Arc::new(Board {
        slots: Mutex::new(vec![Vec::new(); ranks]),
        barrier: Barrier::new(ranks),
    });
    (0..ranks)
        .map(|rank| ThreadTransport {
            rank,
            ranks,
            board: Arc::clone(&board),
        })
        .collect()
}

impl Transport for ThreadTransport {
    fn rank(&self) -> usize {
        self.rank
    }

    fn ranks(&self) -> usize {
        self.ranks
    }

    fn all_gather(&self, bytes: &[u8]) -> Vec<Vec<u8>> {
        let slots = || self.board.slots.lock().unwrap_or_else(|e| e.into_inner());
        slots()[self.rank] = bytes.to_vec();
        // Every rank has written; every rank reads; no rank writes the next round before
        // every rank has read this one.
        self.board.barrier.wait();
        let all = slots().clone();
        self.board.barrier.wait();
        all
    }
}
