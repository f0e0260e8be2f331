//! What the ranks of a distributed run share (issue 29, `docs/distributed.md`): a
//! [`Transport`] that gathers every rank's bytes on every rank (MPI, or threads in one
//! process), and [`Ranks`], the handle a rank's search holds: the slave nodes and conditions
//! the rank owns, and the collective operations the stages need, each exact in the serial
//! order (a maximum; sums of terms keyed by node id, added in ascending id order as the
//! one-process run adds them; the values of ghost nodes from their owners).
//!
//! **Failure.** Every operation is one gather round in which each rank also says whether it
//! has failed. A rank that fails calls [`Ranks::agree_on_failure`]; the others see the
//! failure in their next round and return [`Aborted`], and their callers then join it: every
//! rank leaves with the same message, that of the lowest failed rank, and none waits on a
//! rank that has stopped.

use std::collections::{BTreeMap, HashSet};
use std::fmt;
use std::sync::Arc;

/// How the ranks exchange bytes: one collective call, made by every rank the same number of
/// times in the same order. A transport that can no longer exchange returns empty messages.
pub trait Transport: Send + Sync + fmt::Debug {
    /// This rank, from 0.
    fn rank(&self) -> usize;
    /// The number of ranks.
    fn ranks(&self) -> usize;
    /// Every rank's `bytes`, in rank order, on every rank.
    fn all_gather(&self, bytes: &[u8]) -> Vec<Vec<u8>>;
}

/// Another rank failed: the operation has no result, and the caller must leave through
/// [`Ranks::agree_on_failure`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Aborted;

impl fmt::Display for Aborted {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "another rank failed")
    }
}

impl std::error::Error for Aborted {}

/// One gather round's kind, sent with its payload: every rank must be in the same kind of
/// round, or the ranks are out of step (a defect, reported as an error).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
enum Round {
    Failed = 0,
    Max = 1,
    Count = 2,
    Terms = 3,
    Values = 4,
    Bytes = 5,
}

/// A rank's part in a distributed run: its [`Transport`] and what it owns. Cloned cheaply
/// (shared); two handles are equal when they share their state.
#[derive(Clone)]
pub struct Ranks {
    transport: Arc<dyn Transport>,
    owned_nodes: Arc<HashSet<u32>>,
    owned_conditions: Arc<HashSet<u32>>,
    /// Where set, the conditions of the mesh: those the search makes (paired conditions, skin
    /// conditions) are rank 0's.
    listed_conditions: Option<Arc<HashSet<u32>>>,
}

impl fmt::Debug for Ranks {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Ranks")
            .field("rank", &self.rank())
            .field("ranks", &self.ranks())
            .field("owned_nodes", &self.owned_nodes.len())
            .field("owned_conditions", &self.owned_conditions.len())
            .finish()
    }
}

impl PartialEq for Ranks {
    fn eq(&self, other: &Ranks) -> bool {
        Arc::ptr_eq(&self.owned_nodes, &other.owned_nodes)
    }
}

impl Ranks {
    /// The handle of a rank that owns the slave nodes `owned_nodes` and the slave conditions
    /// `owned_conditions` (ids): their values are its results, and only it adds them to the
    /// global sums.
    pub fn new(
        transport: Arc<dyn Transport>,
        owned_nodes: &[u32],
        owned_conditions: &[u32],
    ) -> Ranks {
        Ranks {
            transport,
            owned_nodes: Arc::new(owned_nodes.iter().copied().collect()),
            owned_conditions: Arc::new(owned_conditions.iter().copied().collect()),
            listed_conditions: None,
        }
    }

    /// This handle, where every rank holds the same whole model: the conditions that are not
    /// in `listed` (the mesh's condition ids) — those the search makes — are rank 0's.
    pub fn with_made_conditions_on_first(self, listed: &[u32]) -> Ranks {
        Ranks {
            listed_conditions: Some(Arc::new(listed.iter().copied().collect())),
            ..self
        }
    }

    /// This rank, from 0.
    pub fn rank(&self) -> usize {
        self.transport.rank()
    }

    /// The number of ranks.
    pub fn ranks(&self) -> usize {
        self.transport.ranks()
    }

    /// Whether this rank owns the slave node `id`.
    pub fn owns_node(&self, id: u32) -> bool {
        self.owned_nodes.contains(&id)
    }

    /// Whether this rank owns the slave condition `id`.
    pub fn owns_condition(&self, id: u32) -> bool {
        self.owned_conditions.contains(&id)
            || (self.listed_conditions.as_ref())
                .is_some_and(|listed| self.rank() == 0 && !listed.contains(&id))
    }

    /// One round: every rank's payload, or [`Aborted`] where some rank has failed.
    fn round(&self, kind: Round, payload: &[u8]) -> Result<Vec<Vec<u8>>, Aborted> {
        let mut bytes = Vec::with_capacity(payload.len() + 1);
        bytes.push(kind as u8);
        bytes.extend_from_slice(payload);
        let all = self.transport.all_gather(&bytes);
        if all.iter().any(|b| b.first() != Some(&(kind as u8))) {
            // A failed rank, or ranks out of step (then this rank fails as well).
            return Err(Aborted);
        }
        Ok(all.into_iter().map(|mut b| b.split_off(1)).collect())
    }

    /// The largest of every rank's `x` (exact in any order).
    pub fn max(&self, x: f64) -> Result<f64, Aborted> {
        let all = self.round(Round::Max, &x.to_le_bytes())?;
        Ok(all.iter().map(|b| f64_at(b, 0)).fold(x, f64::max))
    }

    /// The sum of every rank's `n`.
    pub fn sum_count(&self, n: u64) -> Result<u64, Aborted> {
        let all = self.round(Round::Count, &n.to_le_bytes())?;
        Ok(all.iter().map(|b| u64_at(b, 0)).sum())
    }

    /// Every rank's terms `(node id, value)` together, ascending by id, each id once (a term
    /// given by several ranks is the same value: the first rank's is kept): the terms of a sum
    /// over nodes in the order the one-process run adds them (nodes in ascending id order).
    pub fn terms(&self, terms: &[(u32, [f64; 3])]) -> Result<Vec<(u32, [f64; 3])>, Aborted> {
        let all = self.round(Round::Terms, &encode_terms(terms))?;
        let mut merged: BTreeMap<u32, [f64; 3]> = BTreeMap::new();
        for bytes in &all {
            for term in decode_terms(bytes) {
                merged.entry(term.0).or_insert(term.1);
            }
        }
        Ok(merged.into_iter().collect())
    }

    /// The values of the nodes `wanted` (ids) from the ranks that give them in `owned`
    /// (`None` where no rank does).
    pub fn values(
        &self,
        owned: &[(u32, [f64; 3])],
        wanted: &[u32],
    ) -> Result<Vec<Option<[f64; 3]>>, Aborted> {
        let all = self.round(Round::Values, &encode_terms(owned))?;
        let mut by_id: std::collections::HashMap<u32, [f64; 3]> = std::collections::HashMap::new();
        for bytes in &all {
            by_id.extend(decode_terms(bytes));
        }
        Ok(wanted.iter().map(|id| by_id.get(id).copied()).collect())
    }

    /// Every rank's `bytes`, in rank order.
    pub fn gather_bytes(&self, bytes: &[u8]) -> Result<Vec<Vec<u8>>, Aborted> {
        self.round(Round::Bytes, bytes)
    }

    /// Leaves a failed run together: this rank failed with `message` (`None`: it saw another
    /// rank fail). Takes part in rounds until every rank has failed or seen the failure, and
    /// returns the message of the lowest rank that failed with one — the same on every rank.
    pub fn agree_on_failure(&self, message: Option<&str>) -> String {
        let mut payload = vec![Round::Failed as u8];
        payload.extend_from_slice(message.unwrap_or_default().as_bytes());
        loop {
            let all = self.transport.all_gather(&payload);
            // Every message has its kind: an empty one is a transport that can no longer
            // exchange anything.
            if all.iter().any(Vec::is_empty) {
                return format!(
                    "rank {}: the ranks can no longer exchange data",
                    self.rank()
                );
            }
            if all
                .iter()
                .all(|b| b.first() == Some(&(Round::Failed as u8)))
            {
                let first = all
                    .iter()
                    .enumerate()
                    .find(|(_, b)| b.len() > 1)
                    .map(|(rank, b)| {
                        format!(
                            "rank {rank} of {}: {}",
                            self.ranks(),
                            String::from_utf8_lossy(&b[1..])
                        )
                    });
                return first.unwrap_or_else(|| "the ranks went out of step".to_owned());
            }
        }
    }
}

fn f64_at(b: &[u8], at: usize) -> f64 {
    f64::from_le_bytes(b[at..at + 8].try_into().expect("8 bytes"))
}

fn u64_at(b: &[u8], at: usize) -> u64 {
    u64::from_le_bytes(b[at..at + 8].try_into().expect("8 bytes"))
}

/// Terms as bytes: per term the id (4 bytes) and three values (8 bytes each).
const TERM_BYTES: usize = 4 + 3 * 8;

fn encode_terms(terms: &[(u32, [f64; 3])]) -> Vec<u8> {
    let mut out = Vec::with_capacity(terms.len() * TERM_BYTES);
    for (id, v) in terms {
        out.extend_from_slice(&id.to_le_bytes());
        for x in v {
            out.extend_from_slice(&x.to_le_bytes());
        }
    }
    out
}

fn decode_terms(bytes: &[u8]) -> impl Iterator<Item = (u32, [f64; 3])> + '_ {
    bytes.chunks_exact(TERM_BYTES).map(|t| {
        let id = u32::from_le_bytes(t[..4].try_into().expect("4 bytes"));
        (id, [f64_at(t, 4), f64_at(t, 12), f64_at(t, 20)])
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One rank alone: every operation returns its own input.
    #[derive(Debug)]
    struct Alone;

    impl Transport for Alone {
        fn rank(&self) -> usize {
            0
        }
        fn ranks(&self) -> usize {
            1
        }
        fn all_gather(&self, bytes: &[u8]) -> Vec<Vec<u8>> {
            vec![bytes.to_vec()]
        }
    }

    #[test]
    fn one_rank_gets_its_own_values_back_in_id_order() {
        let ranks = Ranks::new(Arc::new(Alone), &[3], &[7]);
        assert!(ranks.owns_node(3) && !ranks.owns_node(4));
        assert!(ranks.owns_condition(7) && !ranks.owns_condition(3));
        // Rank 0 owns the conditions that are not the mesh's (the search made them).
        let whole = ranks.clone().with_made_conditions_on_first(&[3, 7]);
        assert!(whole.owns_condition(7) && !whole.owns_condition(3) && whole.owns_condition(8));
        assert_eq!(ranks.max(-2.5), Ok(-2.5));
        assert_eq!(ranks.sum_count(41), Ok(41));
        let terms = [(9, [1.0, 2.0, 3.0]), (2, [4.0, 5.0, 6.0]), (9, [7.0; 3])];
        assert_eq!(
            ranks.terms(&terms),
            Ok(vec![(2, [4.0, 5.0, 6.0]), (9, [1.0, 2.0, 3.0])])
        );
        assert_eq!(
            ranks.values(&terms[..2], &[2, 5]),
            Ok(vec![Some([4.0, 5.0, 6.0]), None])
        );
        assert_eq!(
            ranks.agree_on_failure(Some("bad input")),
            "rank 0 of 1: bad input"
        );
    }
}
