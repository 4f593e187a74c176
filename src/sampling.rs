//! Deterministic random numbers keyed by what they are for (seed, photon
//! index, pixel, sample, dimension), so no result depends on which thread
//! drew them or in what order.

/// SplitMix64 finaliser: a good 64-bit hash.
#[inline]
pub fn splitmix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// A small generator (SplitMix64 stream) started from a key.
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A stream for (seed, a, b): e.g. (seed, pixel, sample) or (seed, photon, 0).
    pub fn new(seed: u64, a: u64, b: u64) -> Self {
        Rng(splitmix(seed ^ splitmix(a ^ splitmix(b.wrapping_add(0x51_7c_c1_b7)))))
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        splitmix(self.0)
    }

    /// Uniform in [0, 1).
    pub fn f64(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    pub fn f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 * (1.0 / (1u64 << 24) as f32)
    }
}

/// Radical inverse of `i` in a prime `base` (a Halton dimension).
pub fn radical_inverse(mut i: u64, base: u64) -> f64 {
    let inv = 1.0 / base as f64;
    let (mut f, mut r) = (1.0, 0.0);
    while i > 0 {
        f *= inv;
        r += f * (i % base) as f64;
        i /= base;
    }
    r
}

/// `u` shifted by `offset` modulo 1 (Cranley-Patterson rotation): a
/// randomised low-discrepancy point keeps its stratification.
pub fn rotate(u: f64, offset: f64) -> f64 {
    let v = u + offset;
    if v >= 1.0 {
        v - 1.0
    } else {
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_are_uniform_and_distinct() {
        let mut r = Rng::new(1, 2, 3);
        let n = 100_000;
        let mean: f64 = (0..n).map(|_| r.f64()).sum::<f64>() / n as f64;
        assert!((mean - 0.5).abs() < 0.005);
        assert_ne!(Rng::new(1, 2, 3).next_u64(), Rng::new(1, 2, 4).next_u64());
        // The radical inverse fills strata: the first 8 points in base 2 land in 8 bins.
        let mut bins = [0; 8];
        for i in 0..8 {
            bins[(radical_inverse(i, 2) * 8.0) as usize] += 1;
        }
        assert_eq!(bins, [1; 8]);
        assert!((radical_inverse(1, 3) - 1.0 / 3.0).abs() < 1e-15 && (radical_inverse(4, 3) - 4.0 / 9.0).abs() < 1e-15);
    }
}
