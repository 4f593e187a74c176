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
    if base == 2 {
        // The bits reversed: the same value, exactly for i below 2^53
        // (every partial sum of the loop below is a dyadic fraction it
        // represents exactly), in one instruction instead of one per bit.
        return i.reverse_bits() as f64 * (1.0 / 18_446_744_073_709_551_616.0);
    }
    let inv = 1.0 / base as f64;
    let (mut f, mut r) = (1.0, 0.0);
    while i > 0 {
        f *= inv;
        r += f * (i % base) as f64;
        i /= base;
    }
    r
}

/// The radical inverses of i, i + 1, i + 2, ... in one base, one step at
/// a time: the digits of i are kept and counted up (a carry every `base`
/// steps), and each term `f_k d_k` of `radical_inverse`'s loop is read from
/// a table built by that loop's own products, then added in the loop's
/// order, so every value is `radical_inverse`'s to the bit, without a
/// division per digit.
#[derive(Clone, Debug)]
pub struct RadicalInverses {
    base: u32,
    /// The digits of the current index, least significant first; `len`
    /// of them up to its highest non-zero one.
    digits: [u8; 64],
    len: usize,
    /// `terms[k][d]`: the loop's `f * d` at digit k (f = base^-(k+1) as
    /// its repeated products round it).
    terms: Box<[[f64; 8]; 64]>,
    /// `terms[k][digits[k]]` for every k: the sum's terms as they stand.
    current: [f64; 64],
}

impl RadicalInverses {
    /// Starting at index `i`, in `base` (2 to 8).
    pub fn new(base: u64, mut i: u64) -> RadicalInverses {
        assert!((2..=8).contains(&base), "radical inverse base {base}");
        let inv = 1.0 / base as f64;
        let mut terms = Box::new([[0.0; 8]; 64]);
        let mut f = 1.0;
        for row in terms.iter_mut() {
            f *= inv;
            for (d, t) in row.iter_mut().enumerate().take(base as usize) {
                *t = f * d as f64;
            }
        }
        let (mut digits, mut len) = ([0u8; 64], 0);
        while i > 0 {
            digits[len] = (i % base) as u8;
            i /= base;
            len += 1;
        }
        let current = std::array::from_fn(|k| terms[k][digits[k] as usize]);
        RadicalInverses { base: base as u32, digits, len, terms, current }
    }

    /// The radical inverse of the current index.
    #[inline]
    pub fn value(&self) -> f64 {
        self.current[..self.len].iter().fold(0.0, |r, &t| r + t)
    }

    /// On to the next index.
    #[inline]
    pub fn advance(&mut self) {
        for k in 0..64 {
            let d = &mut self.digits[k];
            *d += 1;
            if u32::from(*d) < self.base {
                self.current[k] = self.terms[k][*d as usize];
                self.len = self.len.max(k + 1);
                return;
            }
            *d = 0;
            self.current[k] = 0.0;
        }
    }
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

/// `n` sample points for one pixel: (x, y) multi-jittered (Chiu, Shirley
/// & Wang, "Multi-jittered sampling", Graphics Gems IV, 1994): one point
/// in each cell of an m x n/m grid and in each of the n strata of either
/// axis, the whole set shifted by one random offset modulo 1 (each point
/// uniform, the strata kept); and a third coordinate in its own n strata,
/// paired with the points in random order. A straight edge across the
/// pixel is then estimated to within about 1/n, not 1/sqrt(n).
pub fn multi_jittered(n: usize, rng: &mut Rng) -> Vec<[f64; 3]> {
    let mut out = Vec::new();
    multi_jittered_into(n, rng, &mut out, &mut Vec::new());
    out
}

/// The same points into `out` (cleared first), with `scratch` for the
/// shuffle: a caller that makes a pattern per pixel keeps both and
/// allocates nothing per pixel.
pub fn multi_jittered_into(n: usize, rng: &mut Rng, out: &mut Vec<[f64; 3]>, scratch: &mut Vec<usize>) {
    let n = n.max(1);
    // The grid: m the largest divisor of n not above its square root.
    let m = (1..=n).take_while(|d| d * d <= n).filter(|d| n.is_multiple_of(*d)).last().unwrap_or(1);
    let k = n / m;
    let (ox, oy) = (rng.f64(), rng.f64());
    let third = scratch;
    third.clear();
    third.extend(0..n);
    for i in (1..n).rev() {
        third.swap(i, (rng.next_u64() % (i as u64 + 1)) as usize);
    }
    let nf = n as f64;
    out.clear();
    for i in 0..m {
        for j in 0..k {
            let x = ((i * k + j) as f64 + rng.f64()) / nf;
            let y = ((j * m + i) as f64 + rng.f64()) / nf;
            let w = (third[i * k + j] as f64 + rng.f64()) / nf;
            out.push([rotate(x, ox).min(1.0 - 1e-12), rotate(y, oy).min(1.0 - 1e-12), w]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn multi_jittered_points_fill_every_stratum() {
        for n in [1, 2, 4, 6, 16, 64] {
            for key in 0..20 {
                let pts = multi_jittered(n, &mut Rng::new(7, key, 0));
                assert_eq!(pts.len(), n);
                // Undo the common shift: strata are counted on the torus, so
                // shift by the first point's offset within its stratum.
                for axis in 0..3 {
                    let mut v: Vec<f64> = pts.iter().map(|p| p[axis]).collect();
                    v.sort_by(f64::total_cmp);
                    // n points, one per stratum after a rotation: consecutive
                    // gaps are under 2/n, and all lie in [0, 1).
                    assert!(v.iter().all(|&x| (0.0..1.0).contains(&x)));
                    let gaps = v.windows(2).map(|w| w[1] - w[0]).chain([v[0] + 1.0 - v[n - 1]]);
                    assert!(gaps.into_iter().all(|g| g < 2.0 / n as f64 + 1e-12), "n {n} axis {axis}: {v:?}");
                }
            }
        }
        // Each point alone is uniform over the pixel.
        let mean: f64 = (0..20_000).map(|k| multi_jittered(4, &mut Rng::new(1, k, 0))[2][0]).sum::<f64>() / 20_000.0;
        assert!((mean - 0.5).abs() < 0.01, "{mean}");
    }

    /// Base 2 by reversing the bits gives the digit loop's value to the
    /// last bit (photon positions, and so the figures, do not move), and
    /// the digits come out as they should.
    #[test]
    fn the_base_2_radical_inverse_is_the_digit_loops_to_the_bit() {
        let by_digits = |mut i: u64| {
            let (mut f, mut r) = (1.0, 0.0);
            while i > 0 {
                f *= 0.5;
                r += f * (i % 2) as f64;
                i /= 2;
            }
            r
        };
        let mut rng = Rng::new(5, 6, 7);
        for i in (0..200_000).chain((0..10_000).map(|_| rng.next_u64() >> 11)) {
            assert_eq!(radical_inverse(i, 2).to_bits(), by_digits(i).to_bits(), "{i}");
        }
        assert_eq!((radical_inverse(1, 2), radical_inverse(6, 2)), (0.5, 0.375));
        assert!((radical_inverse(5, 3) - 7.0 / 9.0).abs() < 1e-15, "5 = 12 in base 3 reads 0.21");
    }

    /// Counting up the digits gives `radical_inverse` to the bit, in
    /// bases 2, 3, 5 and 7, from 0 and from large starts, across carries.
    #[test]
    fn radical_inverses_counted_up_are_the_loops_to_the_bit() {
        let mut rng = Rng::new(8, 9, 10);
        for base in [2, 3, 5, 7] {
            for start in [0, 1, base - 1, base * base - 2, 3_000_000, rng.next_u64() >> 14, u64::MAX - 20_000] {
                let mut seq = RadicalInverses::new(base, start);
                for i in start..start.saturating_add(20_000) {
                    assert_eq!(seq.value().to_bits(), radical_inverse(i, base).to_bits(), "base {base}, index {i}");
                    seq.advance();
                }
            }
        }
    }

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
