//! Helpers shared by the crate's unit tests.

/// A reproducible sequence of numbers in [−½, ½) (xorshift64 from `seed`, which must not be 0).
pub(crate) fn uniform(mut state: u64) -> impl FnMut() -> f64 {
    move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }
}
