//! Four `f64` lanes for the batched step ([`super::batch`]), two ways:
//! - `wide::f64x4`: portable; two SSE2 registers in the default `x86-64` build, one AVX register when
//!   the build enables AVX (`-C target-cpu=native`);
//! - [`Avx`] (x86-64 only): one AVX register, whatever the build; used only inside functions compiled
//!   with `#[target_feature(enable = "avx2")]` and called after `is_x86_feature_detected!("avx2")`.
//!
//! Both perform the IEEE operations `+ − ×` lane by lane, as the scalar code does (no fused
//! multiply-add), so the results are the same bits either way. A mask is a lane value with all bits
//! set (true) or clear (false); a comparison with a NaN is false.

use crate::math::DVec3;
use core::ops::{Add, BitAnd, BitOr, Div, Mul, Sub};
use wide::f64x4;

/// Four `f64` lanes and the operations the batched step needs.
pub(crate) trait Lanes:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + BitAnd<Output = Self> + BitOr<Output = Self>
{
    /// `x` in every lane.
    fn splat(x: f64) -> Self;
    /// Lane `k` from `a[k]`.
    fn new(a: [f64; 4]) -> Self;
    /// Lane `k` into `a[k]`.
    fn to_array(self) -> [f64; 4];
    /// The mask of `self <= other`.
    fn le(self, other: Self) -> Self;
    /// The mask of `self < other`.
    fn lt(self, other: Self) -> Self;
    /// `|self|`, lane by lane.
    fn abs(self) -> Self;
    /// Bit `k` set where lane `k` of the mask is true.
    fn bitmask(self) -> u32;
    /// The transpose of a 4×4 block: lane `j` of `rows[k]` goes to lane `k` of the result's `j`.
    /// Four rows read from four bodies become four quantities in lanes, and back.
    #[inline(always)]
    fn transpose(rows: [Self; 4]) -> [Self; 4] {
        let r = rows.map(Self::to_array);
        core::array::from_fn(|j| Self::new([r[0][j], r[1][j], r[2][j], r[3][j]]))
    }
}

impl Lanes for f64x4 {
    #[inline(always)]
    fn splat(x: f64) -> Self {
        f64x4::splat(x)
    }
    #[inline(always)]
    fn new(a: [f64; 4]) -> Self {
        f64x4::new(a)
    }
    #[inline(always)]
    fn to_array(self) -> [f64; 4] {
        f64x4::to_array(self)
    }
    #[inline(always)]
    fn le(self, other: Self) -> Self {
        self.simd_le(other)
    }
    #[inline(always)]
    fn lt(self, other: Self) -> Self {
        self.simd_lt(other)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f64x4::abs(self)
    }
    #[inline(always)]
    fn bitmask(self) -> u32 {
        self.to_bitmask()
    }
}

/// A 3-vector in four lanes (four bodies, or four constraints), with `DVec3`'s operations performed
/// operand for operand, so that each lane gives the scalar `DVec3` result bit for bit.
#[derive(Debug, Clone, Copy, Default)]
#[repr(C)]
pub(crate) struct V3<L> {
    pub(crate) x: L,
    pub(crate) y: L,
    pub(crate) z: L,
}

impl<L: Lanes> V3<L> {
    /// `self · self`, summed as `DVec3::length_squared`: `(x x + y y) + z z`.
    #[inline(always)]
    pub(crate) fn length_squared(self) -> L {
        self.x * self.x + self.y * self.y + self.z * self.z
    }

    /// `s self`, as `f64 * DVec3`.
    #[inline(always)]
    pub(crate) fn scale(self, s: L) -> Self {
        V3 { x: s * self.x, y: s * self.y, z: s * self.z }
    }

    /// `self * other` componentwise, as `DVec3 * DVec3`.
    #[inline(always)]
    pub(crate) fn mul(self, o: Self) -> Self {
        V3 { x: self.x * o.x, y: self.y * o.y, z: self.z * o.z }
    }

    #[inline(always)]
    pub(crate) fn add(self, o: Self) -> Self {
        V3 { x: self.x + o.x, y: self.y + o.y, z: self.z + o.z }
    }

    #[inline(always)]
    pub(crate) fn sub(self, o: Self) -> Self {
        V3 { x: self.x - o.x, y: self.y - o.y, z: self.z - o.z }
    }

    #[inline(always)]
    pub(crate) fn dot(self, o: Self) -> L {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// As `DVec3::cross`.
    #[inline(always)]
    pub(crate) fn cross(self, o: Self) -> Self {
        V3 { x: self.y * o.z - o.y * self.z, y: self.z * o.x - o.z * self.x, z: self.x * o.y - o.x * self.y }
    }

    #[inline(always)]
    pub(crate) fn lane(self, k: usize) -> DVec3 {
        DVec3::new(self.x.to_array()[k], self.y.to_array()[k], self.z.to_array()[k])
    }

    #[inline(always)]
    pub(crate) fn set_lane(&mut self, k: usize, v: DVec3) {
        set_lane(&mut self.x, k, v.x);
        set_lane(&mut self.y, k, v.y);
        set_lane(&mut self.z, k, v.z);
    }
}

/// Lane `k` of `lanes` set to `value`.
#[inline(always)]
pub(crate) fn set_lane<L: Lanes>(lanes: &mut L, k: usize, value: f64) {
    let mut a = lanes.to_array();
    a[k] = value;
    *lanes = L::new(a);
}

/// What the contact solver's lanes (`contact::batch`) need besides [`Lanes`]: division, square
/// root, minimum and maximum, comparisons and selects, each as the scalar `f64` operation lane by
/// lane, and as `wide::f64x4` does it (its NaN rules included), so that every kind of lanes gives
/// the same bits.
pub(crate) trait SolveLanes: Lanes + Default + Div<Output = Self> {
    /// `−self` (the sign bit flipped, as `f64`'s `-`).
    fn neg(self) -> Self;
    fn sqrt(self) -> Self;
    /// `f64::max` lane by lane: a NaN in `other` gives `self`, in `self` gives `other`.
    fn max(self, other: Self) -> Self;
    /// `f64::min` lane by lane, with `max`'s NaN rule.
    fn min(self, other: Self) -> Self;
    /// The mask of `self > other` (false with a NaN).
    fn gt(self, other: Self) -> Self;
    /// The mask of `self != other` (true with a NaN).
    fn ne(self, other: Self) -> Self;
    /// The mask of the NaN lanes.
    fn is_nan(self) -> Self;
    /// The mask of the finite lanes.
    fn is_finite(self) -> Self;
    /// Lane by lane, `t` where the mask `self` is true, else `f`.
    fn select(self, t: Self, f: Self) -> Self;
    /// Whether any lane of the mask is true.
    #[inline(always)]
    fn any(self) -> bool {
        self.bitmask() != 0
    }
}

impl SolveLanes for f64x4 {
    #[inline(always)]
    fn neg(self) -> Self {
        -self
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f64x4::sqrt(self)
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        f64x4::max(self, other)
    }
    #[inline(always)]
    fn min(self, other: Self) -> Self {
        f64x4::min(self, other)
    }
    #[inline(always)]
    fn gt(self, other: Self) -> Self {
        self.simd_gt(other)
    }
    #[inline(always)]
    fn ne(self, other: Self) -> Self {
        self.simd_ne(other)
    }
    #[inline(always)]
    fn is_nan(self) -> Self {
        f64x4::is_nan(self)
    }
    #[inline(always)]
    fn is_finite(self) -> Self {
        f64x4::is_finite(self)
    }
    #[inline(always)]
    fn select(self, t: Self, f: Self) -> Self {
        f64x4::select(self, t, f)
    }
}

#[cfg(target_arch = "x86_64")]
pub(crate) use avx::Avx;

#[cfg(target_arch = "x86_64")]
#[allow(unsafe_code)]
mod avx {
    use super::{Lanes, SolveLanes};
    use core::arch::x86_64::*;
    use core::ops::{Add, BitAnd, BitOr, Div, Mul, Sub};

    /// Four lanes in one AVX register.
    ///
    /// Safety: every method runs AVX instructions. The type is private to the batched step, whose only
    /// use of it is inside a `#[target_feature(enable = "avx2")]` function entered after
    /// `is_x86_feature_detected!("avx2")`; the methods are `#[inline(always)]` so that they are
    /// compiled into that function.
    #[derive(Clone, Copy)]
    #[repr(transparent)]
    pub(crate) struct Avx(__m256d);

    macro_rules! binary {
        ($trait:ident, $method:ident, $intrinsic:ident) => {
            impl $trait for Avx {
                type Output = Self;
                #[inline(always)]
                fn $method(self, other: Self) -> Self {
                    // SAFETY: see the type's documentation
                    Avx(unsafe { $intrinsic(self.0, other.0) })
                }
            }
        };
    }
    binary!(Add, add, _mm256_add_pd);
    binary!(Sub, sub, _mm256_sub_pd);
    binary!(Mul, mul, _mm256_mul_pd);
    binary!(BitAnd, bitand, _mm256_and_pd);
    binary!(BitOr, bitor, _mm256_or_pd);
    binary!(Div, div, _mm256_div_pd);

    impl Default for Avx {
        #[inline(always)]
        fn default() -> Self {
            // SAFETY: see the type's documentation
            Avx(unsafe { _mm256_setzero_pd() })
        }
    }

    impl SolveLanes for Avx {
        #[inline(always)]
        fn neg(self) -> Self {
            // SAFETY: see the type's documentation
            Avx(unsafe { _mm256_xor_pd(self.0, _mm256_set1_pd(-0.0)) })
        }
        #[inline(always)]
        fn sqrt(self) -> Self {
            // SAFETY: see the type's documentation
            Avx(unsafe { _mm256_sqrt_pd(self.0) })
        }
        #[inline(always)]
        fn max(self, other: Self) -> Self {
            // `vmaxpd` gives its second operand when either is a NaN; a NaN in `other` gives `self`
            // SAFETY: see the type's documentation
            other.is_nan().select(self, Avx(unsafe { _mm256_max_pd(self.0, other.0) }))
        }
        #[inline(always)]
        fn min(self, other: Self) -> Self {
            // SAFETY: see the type's documentation
            other.is_nan().select(self, Avx(unsafe { _mm256_min_pd(self.0, other.0) }))
        }
        #[inline(always)]
        fn gt(self, other: Self) -> Self {
            // SAFETY: see the type's documentation
            Avx(unsafe { _mm256_cmp_pd::<_CMP_GT_OQ>(self.0, other.0) })
        }
        #[inline(always)]
        fn ne(self, other: Self) -> Self {
            // unordered: true where either lane is a NaN, as the scalar `!=`
            // SAFETY: see the type's documentation
            Avx(unsafe { _mm256_cmp_pd::<_CMP_NEQ_UQ>(self.0, other.0) })
        }
        #[inline(always)]
        fn is_nan(self) -> Self {
            // SAFETY: see the type's documentation
            Avx(unsafe { _mm256_cmp_pd::<_CMP_UNORD_Q>(self.0, self.0) })
        }
        #[inline(always)]
        fn is_finite(self) -> Self {
            // `x − x` is 0 for a finite `x`, NaN for an infinity or a NaN
            // SAFETY: see the type's documentation
            Avx(unsafe { _mm256_cmp_pd::<_CMP_EQ_OQ>(_mm256_sub_pd(self.0, self.0), _mm256_setzero_pd()) })
        }
        #[inline(always)]
        fn select(self, t: Self, f: Self) -> Self {
            // SAFETY: see the type's documentation
            Avx(unsafe { _mm256_blendv_pd(f.0, t.0, self.0) })
        }
    }

    impl Lanes for Avx {
        #[inline(always)]
        fn splat(x: f64) -> Self {
            // SAFETY: see the type's documentation
            Avx(unsafe { _mm256_set1_pd(x) })
        }
        #[inline(always)]
        fn new(a: [f64; 4]) -> Self {
            // SAFETY: see the type's documentation; `a` is four readable f64
            Avx(unsafe { _mm256_loadu_pd(a.as_ptr()) })
        }
        #[inline(always)]
        fn to_array(self) -> [f64; 4] {
            let mut a = [0.0; 4];
            // SAFETY: see the type's documentation; `a` is four writable f64
            unsafe { _mm256_storeu_pd(a.as_mut_ptr(), self.0) };
            a
        }
        #[inline(always)]
        fn le(self, other: Self) -> Self {
            // ordered, quiet: false where either lane is a NaN, as the scalar `<=`
            // SAFETY: see the type's documentation
            Avx(unsafe { _mm256_cmp_pd::<_CMP_LE_OQ>(self.0, other.0) })
        }
        #[inline(always)]
        fn lt(self, other: Self) -> Self {
            // SAFETY: see the type's documentation
            Avx(unsafe { _mm256_cmp_pd::<_CMP_LT_OQ>(self.0, other.0) })
        }
        #[inline(always)]
        fn abs(self) -> Self {
            // clear the sign bit, as `f64::abs`
            // SAFETY: see the type's documentation
            Avx(unsafe { _mm256_andnot_pd(_mm256_set1_pd(-0.0), self.0) })
        }
        #[inline(always)]
        fn bitmask(self) -> u32 {
            // SAFETY: see the type's documentation
            unsafe { _mm256_movemask_pd(self.0) as u32 }
        }
        #[inline(always)]
        fn transpose(rows: [Self; 4]) -> [Self; 4] {
            let [r0, r1, r2, r3] = rows.map(|r| r.0);
            // SAFETY: see the type's documentation
            unsafe {
                // t0 = (r0₀ r1₀ r0₂ r1₂), t1 = (r0₁ r1₁ r0₃ r1₃), t2, t3 the same of r2, r3
                let (t0, t1) = (_mm256_unpacklo_pd(r0, r1), _mm256_unpackhi_pd(r0, r1));
                let (t2, t3) = (_mm256_unpacklo_pd(r2, r3), _mm256_unpackhi_pd(r2, r3));
                // low halves together give columns 0 and 1, high halves columns 2 and 3
                [
                    Avx(_mm256_permute2f128_pd::<0x20>(t0, t2)),
                    Avx(_mm256_permute2f128_pd::<0x20>(t1, t3)),
                    Avx(_mm256_permute2f128_pd::<0x31>(t0, t2)),
                    Avx(_mm256_permute2f128_pd::<0x31>(t1, t3)),
                ]
            }
        }
    }
}
