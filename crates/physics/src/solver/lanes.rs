//! Eight f32 lanes as the contact kernels see them, in two implementations with the same
//! results bit for bit: `wide::f32x8` (portable; on x86-64 without `-C target-cpu` it runs
//! as two SSE halves) and [`Avx`], whole 256-bit registers, which the kernels use when the
//! CPU has AVX2 (detected at run time, so the default build stays portable).
//!
//! Why both agree: every operation is one IEEE-754 operation per lane (add, sub, mul, div,
//! max, min, compare, blend, sign flip), the same in both, in the same order; no fused
//! multiply-add is ever formed (docs/soft_step.md 9.1: "never `mul_add`").
#![allow(unsafe_code)]

use std::ops::{Add, AddAssign, BitAnd, Div, Mul, Neg, Sub, SubAssign};

use wide::{f32x4, f32x8};

/// What the contact kernels need of eight lanes.
pub trait Lanes:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + BitAnd<Output = Self>
    + AddAssign
    + SubAssign
{
    /// From stored lanes.
    fn load(x: f32x8) -> Self;
    /// To stored lanes.
    fn store(self) -> f32x8;
    /// Every lane `x`.
    fn splat(x: f32) -> Self;
    /// The sign bit cleared, as `f32::abs` does it.
    fn abs(self) -> Self;
    /// `max` as `maxps` does it (the second operand when either is NaN).
    fn fast_max(self, rhs: Self) -> Self;
    /// `min` as `minps` does it.
    fn fast_min(self, rhs: Self) -> Self;
    /// All-ones lanes where `self > rhs` (ordered).
    fn gt(self, rhs: Self) -> Self;
    /// Lanes where `self != rhs` (true where either is NaN, as `!=` is), as a mask.
    fn ne(self, rhs: Self) -> Self;
    /// `if_true` where this mask is set, else `if_false`.
    fn select(self, if_true: Self, if_false: Self) -> Self;
    /// Whether any lane of this mask is set.
    fn any(self) -> bool;
    /// This mask's lanes as bits (bit l: lane l set).
    fn bits(self) -> u8;
    /// The square root in each lane (IEEE-754's, correctly rounded, as `f32::sqrt`).
    fn sqrt(self) -> Self;
    /// Lanes 0–3 from `lo`, 4–7 from `hi`.
    fn join(lo: f32x4, hi: f32x4) -> Self;
    /// The inverse of `join`.
    fn halves(self) -> [f32x4; 2];
}

impl Lanes for f32x8 {
    #[inline(always)]
    fn load(x: f32x8) -> Self {
        x
    }
    #[inline(always)]
    fn store(self) -> f32x8 {
        self
    }
    #[inline(always)]
    fn splat(x: f32) -> Self {
        f32x8::splat(x)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f32x8::abs(self)
    }
    #[inline(always)]
    fn fast_max(self, rhs: Self) -> Self {
        f32x8::fast_max(self, rhs)
    }
    #[inline(always)]
    fn fast_min(self, rhs: Self) -> Self {
        f32x8::fast_min(self, rhs)
    }
    #[inline(always)]
    fn gt(self, rhs: Self) -> Self {
        f32x8::simd_gt(self, rhs)
    }
    #[inline(always)]
    fn ne(self, rhs: Self) -> Self {
        f32x8::simd_ne(self, rhs)
    }
    #[inline(always)]
    fn select(self, if_true: Self, if_false: Self) -> Self {
        f32x8::select(self, if_true, if_false)
    }
    #[inline(always)]
    fn any(self) -> bool {
        self.to_bitmask() != 0
    }
    #[inline(always)]
    fn bits(self) -> u8 {
        self.to_bitmask() as u8
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f32x8::sqrt(self)
    }
    #[inline(always)]
    fn join(lo: f32x4, hi: f32x4) -> Self {
        wide::bytemuck::cast([lo, hi])
    }
    #[inline(always)]
    fn halves(self) -> [f32x4; 2] {
        wide::bytemuck::cast(self)
    }
}

#[cfg(target_arch = "x86_64")]
pub use avx::Avx;

/// [`crate::math::atan2`] in each lane, operation for operation, so the bits are the same.
#[inline(always)]
pub fn atan2<V: Lanes>(y: V, x: V) -> V {
    use std::f32::consts::{FRAC_PI_2, PI};
    let zero = V::splat(0.0);
    let (ax, ay) = (x.abs(), y.abs());
    let steep = ay.gt(ax);
    let (small, large) = (steep.select(ax, ay), steep.select(ay, ax));
    let t = small / large;
    let t2 = t * t;
    let s2 = t2 * t2;
    let s4 = s2 * s2;
    let a = crate::math::ATAN_COEFFICIENTS.map(V::splat);
    let e0 = a[0] + a[1] * t2;
    let e1 = a[2] + a[3] * t2;
    let e2 = a[4] + a[5] * t2;
    let e3 = a[6] + a[7] * t2;
    let p = (e0 + e1 * s2) + (e2 + e3 * s2) * s4;
    let mut r = t + t * (p * t2);
    r = steep.select(V::splat(FRAC_PI_2) - r, r);
    r = zero.gt(x).select(V::splat(PI) - r, r);
    r = zero.gt(y).select(-r, r);
    // The origin gives 0 (a NaN is not equal to 0, and passes through).
    large.ne(zero).select(r, zero)
}

/// Whether this CPU runs the [`Avx`] kernels (checked once; std caches the answer).
#[inline]
pub fn avx2_available() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

#[cfg(target_arch = "x86_64")]
mod avx {
    //! SAFETY, for every `unsafe` block below: each calls an AVX intrinsic. These methods are
    //! only reached from functions compiled with `#[target_feature(enable = "avx2")]`, which
    //! are only called after `avx2_available()` said yes (the callers' SAFETY notes), and they
    //! are `#[inline(always)]`, so they are compiled inside those functions.
    use super::*;
    use std::arch::x86_64::*;

    /// Eight lanes in one 256-bit register.
    #[derive(Clone, Copy)]
    #[repr(transparent)]
    pub struct Avx(__m256);

    /// One binary operator as one AVX intrinsic.
    macro_rules! binary {
        ($trait:ident, $method:ident, $intrinsic:ident) => {
            impl $trait for Avx {
                type Output = Avx;
                #[inline(always)]
                fn $method(self, rhs: Avx) -> Avx {
                    Avx(unsafe { $intrinsic(self.0, rhs.0) })
                }
            }
        };
    }
    /// `x op= y` as `x = x op y`.
    macro_rules! assign {
        ($assign:ident, $assign_method:ident, $trait:ident, $method:ident) => {
            impl $assign for Avx {
                #[inline(always)]
                fn $assign_method(&mut self, rhs: Avx) {
                    *self = $trait::$method(*self, rhs);
                }
            }
        };
    }
    binary!(Add, add, _mm256_add_ps);
    binary!(Sub, sub, _mm256_sub_ps);
    binary!(Mul, mul, _mm256_mul_ps);
    binary!(Div, div, _mm256_div_ps);
    binary!(BitAnd, bitand, _mm256_and_ps);
    assign!(AddAssign, add_assign, Add, add);
    assign!(SubAssign, sub_assign, Sub, sub);

    impl Neg for Avx {
        type Output = Avx;
        /// A sign flip, as `wide` does it (not `0 − x`, which differs at zero).
        #[inline(always)]
        fn neg(self) -> Avx {
            Avx(unsafe { _mm256_xor_ps(self.0, _mm256_set1_ps(-0.0)) })
        }
    }

    impl Lanes for Avx {
        #[inline(always)]
        fn load(x: f32x8) -> Self {
            // Same size, both 32-byte aligned plain floats.
            Avx(wide::bytemuck::cast(x))
        }
        #[inline(always)]
        fn store(self) -> f32x8 {
            wide::bytemuck::cast(self.0)
        }
        #[inline(always)]
        fn splat(x: f32) -> Self {
            Avx(unsafe { _mm256_set1_ps(x) })
        }
        #[inline(always)]
        fn abs(self) -> Self {
            Avx(unsafe { _mm256_andnot_ps(_mm256_set1_ps(-0.0), self.0) })
        }
        #[inline(always)]
        fn fast_max(self, rhs: Self) -> Self {
            Avx(unsafe { _mm256_max_ps(self.0, rhs.0) })
        }
        #[inline(always)]
        fn fast_min(self, rhs: Self) -> Self {
            Avx(unsafe { _mm256_min_ps(self.0, rhs.0) })
        }
        #[inline(always)]
        fn gt(self, rhs: Self) -> Self {
            Avx(unsafe { _mm256_cmp_ps::<_CMP_GT_OQ>(self.0, rhs.0) })
        }
        #[inline(always)]
        fn ne(self, rhs: Self) -> Self {
            Avx(unsafe { _mm256_cmp_ps::<_CMP_NEQ_UQ>(self.0, rhs.0) })
        }
        #[inline(always)]
        fn select(self, if_true: Self, if_false: Self) -> Self {
            Avx(unsafe { _mm256_blendv_ps(if_false.0, if_true.0, self.0) })
        }
        #[inline(always)]
        fn any(self) -> bool {
            unsafe { _mm256_movemask_ps(self.0) != 0 }
        }
        #[inline(always)]
        fn bits(self) -> u8 {
            unsafe { _mm256_movemask_ps(self.0) as u8 }
        }
        #[inline(always)]
        fn sqrt(self) -> Self {
            Avx(unsafe { _mm256_sqrt_ps(self.0) })
        }
        #[inline(always)]
        fn join(lo: f32x4, hi: f32x4) -> Self {
            let lo: __m128 = wide::bytemuck::cast(lo);
            let hi: __m128 = wide::bytemuck::cast(hi);
            Avx(unsafe { _mm256_set_m128(hi, lo) })
        }
        #[inline(always)]
        fn halves(self) -> [f32x4; 2] {
            wide::bytemuck::cast(self.0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lanes' arctangent against `math::atan2`, bit for bit: points round the circle at
    /// three radii, the axes, both zeros, infinities and NaN (a NaN only as a NaN).
    #[test]
    fn atan2_in_lanes_is_the_scalar_bit_for_bit() {
        let mut points = Vec::new();
        for k in 0..4096 {
            let a = -std::f32::consts::PI + (k as f32 + 0.5) * std::f32::consts::TAU / 4096.0;
            for r in [1.0f32, 1e-3, 7e4] {
                points.push((a.sin() * r, a.cos() * r));
            }
        }
        let (inf, nan) = (f32::INFINITY, f32::NAN);
        for y in [0.0, -0.0, 1.0, -1.0, inf, -inf, nan] {
            for x in [0.0, -0.0, 1.0, -1.0, inf, -inf, nan] {
                points.push((y, x));
            }
        }
        points.resize(points.len().next_multiple_of(8), (0.5, 0.25));
        let same = |lanes: [f32; 8], group: &[(f32, f32)]| {
            for (l, &(y, x)) in group.iter().enumerate() {
                let want = crate::math::atan2(y, x);
                let got = lanes[l];
                assert!(
                    got.to_bits() == want.to_bits() || (got.is_nan() && want.is_nan()),
                    "atan2({y}, {x}): {got} in lanes, {want} alone"
                );
            }
        };
        for group in points.chunks_exact(8) {
            let y = f32x8::new(std::array::from_fn(|l| group[l].0));
            let x = f32x8::new(std::array::from_fn(|l| group[l].1));
            same(atan2(y, x).to_array(), group);
            #[cfg(target_arch = "x86_64")]
            if avx2_available() {
                // SAFETY: the CPU has AVX2 (checked just above).
                #[target_feature(enable = "avx2")]
                fn wide(y: f32x8, x: f32x8) -> f32x8 {
                    atan2(Avx::load(y), Avx::load(x)).store()
                }
                same(unsafe { wide(y, x) }.to_array(), group);
            }
        }
    }
}
