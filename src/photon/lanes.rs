//! Four f64 lanes for `beam`: the portable `wide::f64x4` (two SSE2 halves
//! on baseline x86-64), or one AVX register inside a function compiled for
//! AVX2 (half the instructions). Both do each lane's IEEE operation (add,
//! subtract, multiply, divide, square root: correctly rounded), so they
//! give the same bits as each other and as the scalar code.

use crate::optics::glass::Real;
use std::ops::{BitAnd, BitOr, Not};

/// Four f64s, and masks of four (all bits set: true). As `Real`s (add,
/// subtract, multiply, divide, `splat`, `max`, `sqrt`) they run the
/// dispersion formulas too.
pub(super) trait Lanes: Real + BitAnd<Output = Self> + BitOr<Output = Self> + Not<Output = Self> {
    fn new(a: [f64; 4]) -> Self;
    fn to_array(self) -> [f64; 4];
    /// `f64::min` lane by lane: `other` where `self` is NaN, `self` where
    /// `other` is.
    fn min(self, other: Self) -> Self;
    fn lt(self, other: Self) -> Self;
    fn gt(self, other: Self) -> Self;
    fn ge(self, other: Self) -> Self;
    fn le(self, other: Self) -> Self;
    fn eq(self, other: Self) -> Self;
    /// A bit a lane: lane i's mask in bit i.
    fn to_bitmask(self) -> u32;
    /// `if_one` where the mask `self` is set, `if_zero` elsewhere.
    fn bitselect(self, if_one: Self, if_zero: Self) -> Self;
}

impl Real for wide::f64x4 {
    #[inline(always)]
    fn splat(x: f64) -> Self {
        wide::f64x4::splat(x)
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        wide::f64x4::max(self, other)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        wide::f64x4::sqrt(self)
    }
}

impl Lanes for wide::f64x4 {
    #[inline(always)]
    fn new(a: [f64; 4]) -> Self {
        wide::f64x4::new(a)
    }
    #[inline(always)]
    fn to_array(self) -> [f64; 4] {
        wide::f64x4::to_array(self)
    }
    #[inline(always)]
    fn min(self, other: Self) -> Self {
        wide::f64x4::min(self, other)
    }
    #[inline(always)]
    fn lt(self, other: Self) -> Self {
        self.simd_lt(other)
    }
    #[inline(always)]
    fn gt(self, other: Self) -> Self {
        self.simd_gt(other)
    }
    #[inline(always)]
    fn ge(self, other: Self) -> Self {
        self.simd_ge(other)
    }
    #[inline(always)]
    fn le(self, other: Self) -> Self {
        self.simd_le(other)
    }
    #[inline(always)]
    fn eq(self, other: Self) -> Self {
        self.simd_eq(other)
    }
    #[inline(always)]
    fn to_bitmask(self) -> u32 {
        wide::f64x4::to_bitmask(self)
    }
    #[inline(always)]
    fn bitselect(self, if_one: Self, if_zero: Self) -> Self {
        wide::f64x4::bitselect(self, if_one, if_zero)
    }
}

/// Proof that the processor has AVX2: what code must hold to reach the
/// `Avx` lanes. Only `detect`, which asks the processor, makes one.
#[derive(Clone, Copy, Debug)]
pub(super) struct HasAvx2(());

impl HasAvx2 {
    /// `Some` where the processor has AVX2; `None` elsewhere (and off x86-64).
    pub(super) fn detect() -> Option<HasAvx2> {
        #[cfg(target_arch = "x86_64")]
        let has = std::arch::is_x86_feature_detected!("avx2");
        #[cfg(not(target_arch = "x86_64"))]
        let has = false;
        has.then_some(HasAvx2(()))
    }
}

/// One AVX register of four f64s. Only for code compiled with AVX enabled
/// (`#[target_feature(enable = "avx2")]`) and run where the processor has
/// it: its operations are inlined there as single instructions. `beam`
/// reaches that code only holding a `HasAvx2`.
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy)]
pub(super) struct Avx(std::arch::x86_64::__m256d);

#[cfg(target_arch = "x86_64")]
mod avx {
    use super::{Avx, Lanes, Real};
    use std::arch::x86_64::*;

    macro_rules! op {
        ($trait:ident, $f:ident, $intrinsic:ident) => {
            impl std::ops::$trait for Avx {
                type Output = Avx;
                #[inline(always)]
                fn $f(self, other: Avx) -> Avx {
                    // SAFETY: `Avx` values exist only where AVX is enabled and present.
                    Avx(unsafe { $intrinsic(self.0, other.0) })
                }
            }
        };
    }
    op!(Add, add, _mm256_add_pd);
    op!(Sub, sub, _mm256_sub_pd);
    op!(Mul, mul, _mm256_mul_pd);
    op!(Div, div, _mm256_div_pd);
    op!(BitAnd, bitand, _mm256_and_pd);
    op!(BitOr, bitor, _mm256_or_pd);

    impl std::ops::Not for Avx {
        type Output = Avx;
        #[inline(always)]
        fn not(self) -> Avx {
            // SAFETY: as above.
            Avx(unsafe { _mm256_xor_pd(self.0, _mm256_castsi256_pd(_mm256_set1_epi64x(-1))) })
        }
    }

    /// A comparison (`_CMP_*` predicate) lane by lane.
    #[inline(always)]
    fn cmp<const P: i32>(a: Avx, b: Avx) -> Avx {
        // SAFETY: as above.
        Avx(unsafe { _mm256_cmp_pd::<P>(a.0, b.0) })
    }

    // SAFETY (every block below): `Avx` values exist only where AVX is
    // enabled and present.
    impl Real for Avx {
        #[inline(always)]
        fn splat(x: f64) -> Self {
            Avx(unsafe { _mm256_set1_pd(x) })
        }
        #[inline(always)]
        fn max(self, other: Self) -> Self {
            // As `min`.
            let m = Avx(unsafe { _mm256_max_pd(self.0, other.0) });
            cmp::<_CMP_UNORD_Q>(other, other).bitselect(self, m)
        }
        #[inline(always)]
        fn sqrt(self) -> Self {
            Avx(unsafe { _mm256_sqrt_pd(self.0) })
        }
    }

    impl Lanes for Avx {
        #[inline(always)]
        fn new(a: [f64; 4]) -> Self {
            Avx(unsafe { _mm256_loadu_pd(a.as_ptr()) })
        }
        #[inline(always)]
        fn to_array(self) -> [f64; 4] {
            let mut a = [0.0; 4];
            unsafe { _mm256_storeu_pd(a.as_mut_ptr(), self.0) };
            a
        }
        #[inline(always)]
        fn min(self, other: Self) -> Self {
            // `minpd` gives its second operand where either is NaN: `self`
            // where `other` is NaN, as `f64::min` (and `wide`).
            let m = Avx(unsafe { _mm256_min_pd(self.0, other.0) });
            cmp::<_CMP_UNORD_Q>(other, other).bitselect(self, m)
        }
        #[inline(always)]
        fn lt(self, other: Self) -> Self {
            cmp::<_CMP_LT_OQ>(self, other)
        }
        #[inline(always)]
        fn gt(self, other: Self) -> Self {
            cmp::<_CMP_GT_OQ>(self, other)
        }
        #[inline(always)]
        fn ge(self, other: Self) -> Self {
            cmp::<_CMP_GE_OQ>(self, other)
        }
        #[inline(always)]
        fn le(self, other: Self) -> Self {
            cmp::<_CMP_LE_OQ>(self, other)
        }
        #[inline(always)]
        fn eq(self, other: Self) -> Self {
            cmp::<_CMP_EQ_OQ>(self, other)
        }
        #[inline(always)]
        fn to_bitmask(self) -> u32 {
            unsafe { _mm256_movemask_pd(self.0) as u32 }
        }
        #[inline(always)]
        fn bitselect(self, if_one: Self, if_zero: Self) -> Self {
            Avx(unsafe { _mm256_blendv_pd(if_zero.0, if_one.0, self.0) })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The AVX lanes give `wide`'s bits (and the scalar operations'), NaN
    /// and infinities included.
    #[test]
    fn avx_lanes_match_the_portable_ones() {
        #[cfg(target_arch = "x86_64")]
        {
            if HasAvx2::detect().is_none() {
                return;
            }
            // SAFETY: the processor has AVX2 (`HasAvx2::detect`).
            unsafe { check() }
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn check() {
        let mut rng = crate::sampling::Rng::new(5, 6, 7);
        let special = [0.0, -0.0, 1.0, -1.5, f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 1e-310, 3.0];
        let mut draw = |k: usize| if k.is_multiple_of(3) { special[(rng.next_u64() % special.len() as u64) as usize] } else { rng.f64() * 4.0 - 2.0 };
        let same = |a: [f64; 4], b: [f64; 4]| a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits());
        for k in 0..20_000 {
            let x: [f64; 4] = std::array::from_fn(|i| draw(k + i));
            let y: [f64; 4] = std::array::from_fn(|i| draw(k + 2 * i + 1));
            let (a, b) = (Avx::new(x), Avx::new(y));
            let (p, q) = (wide::f64x4::new(x), wide::f64x4::new(y));
            assert!(same((a + b).to_array(), (p + q).to_array()) && same((a - b).to_array(), (p - q).to_array()));
            assert!(same((a * b).to_array(), (p * q).to_array()) && same((a / b).to_array(), (p / q).to_array()));
            assert!(same(a.sqrt().to_array(), p.sqrt().to_array()), "{x:?}");
            assert!(same(a.min(b).to_array(), Lanes::min(p, q).to_array()), "{x:?} {y:?}");
            assert!(same(a.max(b).to_array(), Real::max(p, q).to_array()), "{x:?} {y:?}");
            // `f64::min` may return either of two equal inputs (+0 and -0).
            let scalar: [f64; 4] = std::array::from_fn(|i| if x[i] == y[i] { a.min(b).to_array()[i] } else { x[i].min(y[i]) });
            assert!(same(a.min(b).to_array(), scalar), "{x:?} {y:?}");
            let scalar: [f64; 4] = std::array::from_fn(|i| if x[i] == y[i] { a.max(b).to_array()[i] } else { x[i].max(y[i]) });
            assert!(same(a.max(b).to_array(), scalar), "{x:?} {y:?}");
            for (m, n) in [(a.lt(b), p.lt(q)), (a.gt(b), p.gt(q)), (a.ge(b), p.ge(q)), (a.le(b), p.le(q)), (a.eq(b), p.eq(q))] {
                assert_eq!(m.to_bitmask(), n.to_bitmask());
                assert_eq!((!m).to_bitmask(), (!n).to_bitmask());
                assert!(same(m.bitselect(a, b).to_array(), n.bitselect(p, q).to_array()));
                assert_eq!((m & a.lt(b)).to_bitmask() | (m | a.eq(b)).to_bitmask() << 4, (n & p.lt(q)).to_bitmask() | (n | p.eq(q)).to_bitmask() << 4);
            }
        }
    }
}
