//! What a capped query reports besides its results.

/// The outcome of a query with a result cap (`max_results`, Kratos' `allocation_size`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct QueryStatus {
    /// `true` when at least one further hit existed after the cap was reached and was dropped,
    /// so the results are the first `max_results` hits in traversal order, not all of them.
    pub truncated: bool,
}
