//! Eight f32 lanes as the contact kernels see them, in two implementations with the same
//! results bit for bit: `wide::f32x8` (portable; on x86-64 without `-C target-cpu` it runs
//! as two SSE halves) and [`Avx`], whole 256-bit registers, which the kernels use when the
//! CPU has AVX2 (detected at run time, so the default build stays portable).
//!
//! Why both agree: every operation is one IEEE-754 operation per lane (add, sub, mul, div,
//! max, min, compare, blend, sign flip), the same in both, in the same order; no fused
//! multiply-add is ever formed (SOFT_STEP.md 9.1: "never `mul_add`").
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
