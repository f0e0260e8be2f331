//! The ranks of `mpirun` ([`MpiTransport`], feature `mpi`): rsmpi over the system's MPI.
//!
//! MPI is initialised, called and finalised on one thread of its own, which serves the
//! gathers the search asks for: the search's threads only send it requests (MPI's
//! `MPI_THREAD_FUNNELED` use, and no `unsafe` to share a communicator between threads).

use std::sync::Mutex;
use std::sync::mpsc::{Receiver, Sender, channel};
use std::thread::JoinHandle;

use csm_model::Transport;
use mpi::datatype::PartitionMut;
use mpi::traits::{Communicator, CommunicatorCollectives};

/// A gather asked of the MPI thread: this rank's bytes and where to send every rank's.
type Request = (Vec<u8>, Sender<Vec<Vec<u8>>>);

/// This process's rank in `MPI_COMM_WORLD`. Dropping it finalises MPI (after the last
/// gather); drop it before the process exits.
pub struct MpiTransport {
    rank: usize,
    ranks: usize,
    requests: Mutex<Option<Sender<Request>>>,
    thread: Mutex<Option<JoinHandle<()>>>,
}

impl std::fmt::Debug for MpiTransport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MpiTransport")
            .field("rank", &self.rank)
            .field("ranks", &self.ranks)
            .finish()
    }
}

impl MpiTransport {
    /// Whether this process was started by an MPI launcher (`mpirun`, `mpiexec`, `srun`):
    /// the variables Open MPI, PMI and PMIx set.
    pub fn launched() -> bool {
        ["OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"]
            .iter()
            .any(|v| std::env::var_os(v).is_some())
    }

    /// Initialises MPI on a thread of its own and returns this process's rank, or why MPI
    /// could not start.
    pub fn start() -> Result<MpiTransport, String> {
        let (ready_tx, ready_rx) = channel::<Result<(usize, usize), String>>();
        let (requests, served) = channel::<Request>();
        let thread = std::thread::Builder::new()
            .name("csm-mpi".to_owned())
            .spawn(move || serve(ready_tx, served))
            .map_err(|e| format!("MPI: cannot start its thread: {e}"))?;
        let (rank, ranks) = ready_rx
            .recv()
            .map_err(|_| "MPI: its thread stopped while starting".to_owned())??;
        Ok(MpiTransport {
            rank,
            ranks,
            requests: Mutex::new(Some(requests)),
            thread: Mutex::new(Some(thread)),
        })
    }
}

/// The MPI thread: initialise, report the rank, serve gathers until the transport is
/// dropped, finalise (when the universe goes).
fn serve(ready: Sender<Result<(usize, usize), String>>, requests: Receiver<Request>) {
    let Some(universe) = mpi::initialize() else {
        // Cannot fail to send: `start` waits for this answer.
        let _ = ready.send(Err("MPI: initialisation failed (or MPI was \
                                already initialised)"
            .to_owned()));
        return;
    };
    let world = universe.world();
    let (rank, size) = (world.rank(), world.size());
    let _ = ready.send(Ok((rank as usize, size as usize)));
    for (bytes, answer) in requests {
        let count = i32::try_from(bytes.len()).unwrap_or(i32::MAX);
        let mut counts = vec![0i32; size as usize];
        world.all_gather_into(&count, &mut counts[..]);
        let mut displs = Vec::with_capacity(counts.len());
        let mut total = 0i32;
        for c in &counts {
            displs.push(total);
            total += c;
        }
        let mut buf = vec![0u8; total as usize];
        // Every rank sees the same counts: where all are zero, every rank skips the gather
        // (Open MPI refuses a gather of nothing into an empty buffer, MPI_ERR_ARG).
        if total > 0 {
            let mut partition = PartitionMut::new(&mut buf[..], &counts[..], &displs[..]);
            world.all_gather_varcount_into(&bytes[..], &mut partition);
        }
        let all = counts
            .iter()
            .zip(&displs)
            .map(|(&c, &d)| buf[d as usize..(d + c) as usize].to_vec())
            .collect();
        // The asking thread waits for the answer.
        let _ = answer.send(all);
    }
    drop(universe);
}

impl Transport for MpiTransport {
    fn rank(&self) -> usize {
        self.rank
    }

    fn ranks(&self) -> usize {
        self.ranks
    }

    fn all_gather(&self, bytes: &[u8]) -> Vec<Vec<u8>> {
        let (answer, answered) = channel();
        let sent = self
            .requests
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .as_ref()
            .map(|r| r.send((bytes.to_vec(), answer)));
        match (sent, answered.recv()) {
            (Some(Ok(())), Ok(all)) => all,
            // The MPI thread is gone: nothing can be exchanged any more. The payload-less
            // answer reads as ranks out of step, which stops the run with an error.
            _ => vec![Vec::new(); self.ranks],
        }
    }
}

impl Drop for MpiTransport {
    fn drop(&mut self) {
        // Closing the channel ends the MPI thread's loop, which finalises MPI.
        self.requests
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .take();
        if let Some(thread) = self.thread.lock().unwrap_or_else(|e| e.into_inner()).take() {
            let _ = thread.join();
        }
    }
}
