//! A host code whose mesh is already split across its ranks calls csm on each rank with its
//! piece (`search_partitioned`), here with the ranks as threads of one process:
//!
//! ```text
//! cargo run -p csm-distributed --example partitioned -- tests/data/scenes/sphere_on_plate_tri.mdpa 3
//! ```
//!
//! With MPI, each rank passes `csm_distributed::MpiTransport::start()?` instead (feature `mpi`,
//! run under `mpirun`): nothing else changes.

use std::sync::Arc;

use csm_distributed::{search_partitioned, sub_mesh, thread_ranks};
use csm_model::MeshArrays;
use csm_search::parse_setup;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let path = args
        .next()
        .unwrap_or_else(|| "tests/data/scenes/sphere_on_plate_tri.mdpa".to_owned());
    let ranks: usize = args.next().map_or(Ok(3), |n| n.parse())?;
    let mesh = csm_io::read_mesh(std::path::Path::new(&path))?.to_arrays();
    let setup = parse_setup(
        r#"{"contact_model_part": {"0": ["Parts_Slave", "Parts_Master"]},
            "assume_master_slave": {"0": ["Parts_Slave"]}}"#,
        "<example setup>",
    )?;
    // The host's pieces: the conditions and elements of ids `rank` modulo `ranks`.
    let pieces: Vec<MeshArrays> = (0..ranks).map(|r| piece(&mesh, ranks, r)).collect();
    let results = std::thread::scope(|scope| {
        let handles: Vec<_> = thread_ranks(ranks)
            .into_iter()
            .zip(&pieces)
            .map(|(transport, local)| {
                let setup = &setup;
                scope.spawn(move || search_partitioned(Arc::new(transport), local, setup))
            })
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().expect("a rank panicked"))
            .collect::<Vec<_>>()
    });
    for (rank, result) in results.into_iter().enumerate() {
        let result = result?;
        println!(
            "rank {rank}: {} of its conditions are slaves, with {} pairs; {} of its nodes are \
             slave nodes, {} active",
            result.pairs.values().map(|m| m.len()).sum::<usize>(),
            result.n_pairs(),
            result.nodes.len(),
            result.nodes.values().filter(|n| n.active).count()
        );
    }
    Ok(())
}

/// Piece `rank` of `ranks`: the entities whose id is `rank` modulo `ranks`, their nodes, the
/// parts restricted to them.
fn piece(mesh: &MeshArrays, ranks: usize, rank: usize) -> MeshArrays {
    let mine = |id: u32| id as usize % ranks == rank;
    sub_mesh(mesh, mine, mine)
}
