//! Hashing for deterministic sampling.
//!
//! Every random number in the engine is a hash of *where* it is used (a pixel and a sample, a
//! pair of elements and a ray, a link and a ray), never a draw from a shared generator: so
//! results do not depend on the order in which threads do the work. The hash is SplitMix64's
//! finaliser (Steele, Lea & Flood 2014, "Fast splittable pseudorandom number generators"), a
//! bijection of 64-bit words whose output bits each depend on every input bit.

/// SplitMix64's finaliser: a well-mixed 64-bit hash of `z` (the generator's output for the
/// state `z`).
#[must_use]
pub fn mix(z: u64) -> u64 {
    let z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    let z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The top 24 bits of `bits` as a number in [0, 1), exact in `f32`.
#[must_use]
pub fn unit_f32(bits: u64) -> f32 {
    (bits >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
}

/// The top 53 bits of `bits` as a number in [0, 1), exact in `f64`.
#[must_use]
pub fn unit_f64(bits: u64) -> f64 {
    (bits >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// The SplitMix64 generator (successive [`mix`] of a counter), for benchmarks and tools that
/// want a plain stream.
#[derive(Clone, Debug)]
pub struct SplitMix(pub u64);

impl SplitMix {
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        let out = mix(self.0);
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        out
    }

    /// The next number in [0, 1) ([`unit_f32`] of the next 64 bits).
    pub fn next_f32(&mut self) -> f32 {
        unit_f32(self.next_u64())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matches_the_published_splitmix64_stream() {
        // The first outputs of SplitMix64 seeded with 0 (Vigna's reference implementation).
        let mut g = SplitMix(0);
        assert_eq!(g.next_u64(), 0xE220_A839_7B1D_CDAF);
        assert_eq!(g.next_u64(), 0x6E78_9E6A_A1B9_65F4);
        assert_eq!(g.next_u64(), 0x06C4_5D18_8009_454F);
    }
}
