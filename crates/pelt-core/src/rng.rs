//! The one pseudo-random generator of the crate: SplitMix64 (Steele, Lea and Flood 2014).
//!
//! Tiny, fast, identical on every platform, and good enough for jitter and shuffles. Seeding from
//! a hash of `(seed, stream, index)` ([`Rng::stream`]) gives every strand or cell its own sequence,
//! so results never depend on the order in which threads do the work.

/// A SplitMix64 state.
pub struct Rng(u64);

impl Rng {
    /// A generator whose state starts at `seed` itself.
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }

    /// An independent sequence for item `index` of stream `stream` under `seed`.
    pub fn stream(seed: u64, stream: u64, index: u64) -> Self {
        Rng(mix64(mix64(mix64(seed) ^ stream) ^ index))
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        mix64(self.0)
    }

    /// Uniform in `[0, 1)` with 53 random bits (they fill an f64 mantissa exactly).
    pub fn next_f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform integer in `[0, n)` by multiply-shift; the bias, below `n / 2⁶⁴`, is irrelevant
    /// for shuffling at most 2²¹ cells.
    pub fn below(&mut self, n: u64) -> u64 {
        ((u128::from(self.next_u64()) * u128::from(n)) >> 64) as u64
    }
}

/// SplitMix64's output function, a bijection on u64 with good avalanche.
fn mix64(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}
