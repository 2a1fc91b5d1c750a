//! A seeded xorshift generator for the unit tests (deterministic, no dependency).

/// Marsaglia's xorshift64 with the shifts 13, 7, 17.
pub(crate) struct TestRng(u64);

impl TestRng {
    /// A generator started at `seed` (not zero).
    pub(crate) fn new(seed: u64) -> Self {
        TestRng(seed)
    }

    /// The next 32 bits.
    pub(crate) fn next_u32(&mut self) -> u32 {
        (self.signed(i64::MAX / 2 - 1) as u64 >> 7) as u32
    }

    /// The next value in `-range..=range`.
    pub(crate) fn signed(&mut self, range: i64) -> i64 {
        let s = &mut self.0;
        *s ^= *s << 13;
        *s ^= *s >> 7;
        *s ^= *s << 17;
        (*s % (2 * range as u64 + 1)) as i64 - range
    }
}
