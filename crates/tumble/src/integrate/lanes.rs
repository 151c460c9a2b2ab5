//! Four `f64` lanes for the batched step ([`super::batch`]), two ways:
//! - `wide::f64x4`: portable; two SSE2 registers in the default `x86-64` build, one AVX register when
//!   the build enables AVX (`-C target-cpu=native`);
//! - [`Avx`] (x86-64 only): one AVX register, whatever the build; used only inside functions compiled
//!   with `#[target_feature(enable = "avx2")]` and called after `is_x86_feature_detected!("avx2")`.
//!
//! Both perform the IEEE operations `+ − ×` lane by lane, as the scalar code does (no fused
//! multiply-add), so the results are the same bits either way. A mask is a lane value with all bits
//! set (true) or clear (false); a comparison with a NaN is false.
//!
//! The batched free-body step is generic over [`BatchLanes`], four or eight lanes: the two above,
//! and [`Avx512`] (x86-64 only), eight lanes in one AVX-512 register, used only inside functions
//! compiled with `#[target_feature(enable = "avx512f")]` and called after
//! `is_x86_feature_detected!("avx512f")`; its masks are the bits of a mask register.

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

/// What [`V3`]'s arithmetic needs of its lanes: `+ − ×`, lane by lane.
pub(crate) trait Arith: Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> {}

impl<T: Copy + Add<Output = T> + Sub<Output = T> + Mul<Output = T>> Arith for T {}

impl<L: Arith> V3<L> {
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
}

impl<L: Lanes> V3<L> {
    #[inline(always)]
    pub(crate) fn lane(self, k: usize) -> DVec3 {
        DVec3::new(self.x.to_array()[k], self.y.to_array()[k], self.z.to_array()[k])
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

/// `N` `f64` lanes (four or eight) and the operations the batched free-body step needs
/// ([`super::batch`]); masks of any kind.
pub(crate) trait BatchLanes: Arith {
    /// The number of lanes.
    const N: usize;
    /// The result of a comparison, lane by lane; combined with `&` and `|`, read by [`BatchLanes::bits`].
    type Mask: Copy + BitAnd<Output = Self::Mask> + BitOr<Output = Self::Mask>;
    /// `x` in every lane.
    fn splat(x: f64) -> Self;
    /// Lane `k` from `f(k)`, `k < N`.
    fn from_fn(f: impl FnMut(usize) -> f64) -> Self;
    /// Lane `k`.
    fn lane(self, k: usize) -> f64;
    /// Lane `k` from `a[k]`, `k < N` (`a` holds at least `N` numbers).
    fn load(a: &[f64]) -> Self;
    /// Lane `k` into `a[k]`, `k < N` (`a` holds at least `N` numbers).
    fn store(self, a: &mut [f64]);
    /// Lane `k` set to `value`.
    fn set_lane(&mut self, k: usize, value: f64);
    /// The mask of `self <= other` (false where a lane is a NaN, as the scalar `<=`).
    fn le(self, other: Self) -> Self::Mask;
    /// The mask of `self < other`.
    fn lt(self, other: Self) -> Self::Mask;
    /// Bit `k` set where lane `k` of the mask is true (bits `N..` clear).
    fn bits(mask: Self::Mask) -> u32;
    /// `|self|`, lane by lane.
    fn abs(self) -> Self;
    /// `if self > other { self } else { other }`, lane by lane (`other` where either is a NaN): the
    /// `max` of `DVec3::max_element`, and x86's `maxpd`.
    fn cmp_max(self, other: Self) -> Self;
    /// `if self < other { self } else { other }`, lane by lane: `DVec3::min_element`'s `min`, x86's
    /// `minpd`.
    fn cmp_min(self, other: Self) -> Self;
    /// Four quantities of `N` bodies from one row of four adjacent fields per body: lane `k` of
    /// result `j` is `rows(k)[j]` (a transpose: one load per body, a few shuffles per row).
    #[inline(always)]
    fn from_rows(rows: impl Fn(usize) -> [f64; 4]) -> [Self; 4] {
        core::array::from_fn(|j| Self::from_fn(|k| rows(k)[j]))
    }
    /// The inverse of [`BatchLanes::from_rows`]: `row(k, r)` receives body `k`'s row `r[j] = lane k of
    /// lanes[j]`, for `k < N` in order.
    #[inline(always)]
    fn to_rows(lanes: [Self; 4], mut row: impl FnMut(usize, [f64; 4])) {
        for k in 0..Self::N {
            row(k, lanes.map(|l| l.lane(k)));
        }
    }
}

/// The batched step's operations from the four-lane ones, for `f64x4` and [`Avx`].
macro_rules! batch_lanes_of_lanes {
    ($lanes:ty) => {
        impl BatchLanes for $lanes {
            const N: usize = 4;
            type Mask = $lanes;
            #[inline(always)]
            fn splat(x: f64) -> Self {
                <Self as Lanes>::splat(x)
            }
            #[inline(always)]
            fn from_fn(mut f: impl FnMut(usize) -> f64) -> Self {
                <Self as Lanes>::new([f(0), f(1), f(2), f(3)])
            }
            #[inline(always)]
            fn lane(self, k: usize) -> f64 {
                self.to_array()[k]
            }
            #[inline(always)]
            fn load(a: &[f64]) -> Self {
                <Self as Lanes>::new([a[0], a[1], a[2], a[3]])
            }
            #[inline(always)]
            fn store(self, a: &mut [f64]) {
                a[..4].copy_from_slice(&self.to_array());
            }
            #[inline(always)]
            fn set_lane(&mut self, k: usize, value: f64) {
                set_lane(self, k, value)
            }
            #[inline(always)]
            fn le(self, other: Self) -> Self {
                <Self as Lanes>::le(self, other)
            }
            #[inline(always)]
            fn lt(self, other: Self) -> Self {
                <Self as Lanes>::lt(self, other)
            }
            #[inline(always)]
            fn bits(mask: Self) -> u32 {
                mask.bitmask()
            }
            #[inline(always)]
            fn abs(self) -> Self {
                <Self as Lanes>::abs(self)
            }
            #[inline(always)]
            fn cmp_max(self, other: Self) -> Self {
                // lane by lane, as the scalar comparison (x86's `maxpd` would do the same)
                let (a, b) = (self.to_array(), other.to_array());
                <Self as BatchLanes>::from_fn(|k| if a[k] > b[k] { a[k] } else { b[k] })
            }
            #[inline(always)]
            fn cmp_min(self, other: Self) -> Self {
                let (a, b) = (self.to_array(), other.to_array());
                <Self as BatchLanes>::from_fn(|k| if a[k] < b[k] { a[k] } else { b[k] })
            }
            #[inline(always)]
            fn from_rows(rows: impl Fn(usize) -> [f64; 4]) -> [Self; 4] {
                // (no closure around the lanes' operations: a closure does not inherit the target
                // features of the function it is in, and is not always inlined)
                let (r0, r1, r2, r3) = (rows(0), rows(1), rows(2), rows(3));
                Self::transpose([Self::new(r0), Self::new(r1), Self::new(r2), Self::new(r3)])
            }
            #[inline(always)]
            fn to_rows(lanes: [Self; 4], mut row: impl FnMut(usize, [f64; 4])) {
                let [r0, r1, r2, r3] = Self::transpose(lanes);
                row(0, r0.to_array());
                row(1, r1.to_array());
                row(2, r2.to_array());
                row(3, r3.to_array());
            }
        }
    };
}

batch_lanes_of_lanes!(f64x4);
#[cfg(target_arch = "x86_64")]
batch_lanes_of_lanes!(Avx);

#[cfg(target_arch = "x86_64")]
pub(crate) use avx::{Avx, Avx512};

#[cfg(target_arch = "x86_64")]
#[allow(unsafe_code)]
mod avx {
    use super::{BatchLanes, Lanes, SolveLanes};
    use core::arch::x86_64::*;
    use core::ops::{Add, BitAnd, BitOr, Div, Mul, Sub};

    /// Four lanes in one AVX register.
    ///
    /// Safety: every method runs AVX instructions. The type's only uses, in the batched step and the
    /// contact solver (`contact::batch`), are inside `#[target_feature(enable = "avx2")]` functions
    /// entered after `is_x86_feature_detected!("avx2")`; the methods are `#[inline(always)]` so that they are
    /// compiled into that function.
    #[derive(Clone, Copy)]
    #[repr(transparent)]
    pub(crate) struct Avx(__m256d);

    /// `impl Trait for Lanes` by one intrinsic on the register of each operand.
    macro_rules! binary {
        ($lanes:ident, $trait:ident, $method:ident, $intrinsic:ident) => {
            impl $trait for $lanes {
                type Output = Self;
                #[inline(always)]
                fn $method(self, other: Self) -> Self {
                    // SAFETY: see the type's documentation
                    $lanes(unsafe { $intrinsic(self.0, other.0) })
                }
            }
        };
    }
    binary!(Avx, Add, add, _mm256_add_pd);
    binary!(Avx, Sub, sub, _mm256_sub_pd);
    binary!(Avx, Mul, mul, _mm256_mul_pd);
    binary!(Avx, BitAnd, bitand, _mm256_and_pd);
    binary!(Avx, BitOr, bitor, _mm256_or_pd);
    binary!(Avx, Div, div, _mm256_div_pd);

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

    /// Eight lanes in one AVX-512 register; masks in a mask register (`__mmask8`, as bits).
    ///
    /// Safety: every method runs AVX-512F instructions (and AVX for the 256-bit loads and stores).
    /// The type's only use is inside a `#[target_feature(enable = "avx512f")]` function entered after
    /// `is_x86_feature_detected!("avx512f")`; the methods are `#[inline(always)]`.
    #[derive(Clone, Copy)]
    pub(crate) struct Avx512(__m512d);

    binary!(Avx512, Add, add, _mm512_add_pd);
    binary!(Avx512, Sub, sub, _mm512_sub_pd);
    binary!(Avx512, Mul, mul, _mm512_mul_pd);

    /// The 4×4 transposes of the low and of the high halves of four AVX-512 registers at once:
    /// lane `j` of half `h` of `z[k]` goes to lane `k` of half `h` of result `j`.
    ///
    /// Safety: AVX-512F.
    #[inline(always)]
    unsafe fn transpose4x2(z: [__m512d; 4]) -> [__m512d; 4] {
        // SAFETY: AVX-512F (the caller's)
        unsafe {
            // per 128-bit block: t0 = (z0₀ z1₀ | z0₂ z1₂ | z0₄ z1₄ | z0₆ z1₆), t1 the odd lanes, t2, t3
            // the same of z2, z3
            let (t0, t1) = (_mm512_unpacklo_pd(z[0], z[1]), _mm512_unpackhi_pd(z[0], z[1]));
            let (t2, t3) = (_mm512_unpacklo_pd(z[2], z[3]), _mm512_unpackhi_pd(z[2], z[3]));
            // blocks 0 of t and t' then their blocks 2 (columns 0, 1 of each half), or blocks 1, 3
            // (columns 2, 3); indices 8.. pick from the second operand
            let even = _mm512_set_epi64(13, 12, 5, 4, 9, 8, 1, 0);
            let odd = _mm512_set_epi64(15, 14, 7, 6, 11, 10, 3, 2);
            [
                _mm512_permutex2var_pd(t0, even, t2),
                _mm512_permutex2var_pd(t1, even, t3),
                _mm512_permutex2var_pd(t0, odd, t2),
                _mm512_permutex2var_pd(t1, odd, t3),
            ]
        }
    }

    impl BatchLanes for Avx512 {
        const N: usize = 8;
        type Mask = u32;
        #[inline(always)]
        fn splat(x: f64) -> Self {
            // SAFETY: see the type's documentation
            Avx512(unsafe { _mm512_set1_pd(x) })
        }
        #[inline(always)]
        fn from_fn(mut f: impl FnMut(usize) -> f64) -> Self {
            let a = [f(0), f(1), f(2), f(3), f(4), f(5), f(6), f(7)];
            // SAFETY: see the type's documentation; `a` is eight readable f64
            Avx512(unsafe { _mm512_loadu_pd(a.as_ptr()) })
        }
        #[inline(always)]
        fn lane(self, k: usize) -> f64 {
            let mut a = [0.0; 8];
            // SAFETY: see the type's documentation; `a` is eight writable f64
            unsafe { _mm512_storeu_pd(a.as_mut_ptr(), self.0) };
            a[k]
        }
        #[inline(always)]
        fn load(a: &[f64]) -> Self {
            let a: &[f64; 8] = a[..8].try_into().expect("eight lanes");
            // SAFETY: see the type's documentation; `a` is eight readable f64
            Avx512(unsafe { _mm512_loadu_pd(a.as_ptr()) })
        }
        #[inline(always)]
        fn store(self, a: &mut [f64]) {
            let a: &mut [f64; 8] = (&mut a[..8]).try_into().expect("eight lanes");
            // SAFETY: see the type's documentation; `a` is eight writable f64
            unsafe { _mm512_storeu_pd(a.as_mut_ptr(), self.0) }
        }
        #[inline(always)]
        fn set_lane(&mut self, k: usize, value: f64) {
            let mut a = [0.0; 8];
            // SAFETY: see the type's documentation; `a` is eight f64
            unsafe {
                _mm512_storeu_pd(a.as_mut_ptr(), self.0);
                a[k] = value;
                self.0 = _mm512_loadu_pd(a.as_ptr());
            }
        }
        #[inline(always)]
        fn le(self, other: Self) -> u32 {
            // ordered, quiet: false where either lane is a NaN, as the scalar `<=`
            // SAFETY: see the type's documentation
            u32::from(unsafe { _mm512_cmp_pd_mask::<_CMP_LE_OQ>(self.0, other.0) })
        }
        #[inline(always)]
        fn lt(self, other: Self) -> u32 {
            // SAFETY: see the type's documentation
            u32::from(unsafe { _mm512_cmp_pd_mask::<_CMP_LT_OQ>(self.0, other.0) })
        }
        #[inline(always)]
        fn bits(mask: u32) -> u32 {
            mask
        }
        #[inline(always)]
        fn abs(self) -> Self {
            // clear the sign bit, as `f64::abs`
            // SAFETY: see the type's documentation
            Avx512(unsafe { _mm512_abs_pd(self.0) })
        }
        #[inline(always)]
        fn cmp_max(self, other: Self) -> Self {
            // `self > other ? self : other`: the second operand where either is a NaN
            // SAFETY: see the type's documentation
            Avx512(unsafe { _mm512_max_pd(self.0, other.0) })
        }
        #[inline(always)]
        fn cmp_min(self, other: Self) -> Self {
            // SAFETY: see the type's documentation
            Avx512(unsafe { _mm512_min_pd(self.0, other.0) })
        }
        #[inline(always)]
        fn from_rows(rows: impl Fn(usize) -> [f64; 4]) -> [Self; 4] {
            // SAFETY: see the type's documentation; each row is four readable f64
            // (no closure around the intrinsics: a closure does not inherit the target features)
            unsafe {
                let r: [[f64; 4]; 8] = [rows(0), rows(1), rows(2), rows(3), rows(4), rows(5), rows(6), rows(7)];
                // z_k = (row k | row k+4), then a 4×4 transpose in each half
                let mut z = [_mm512_setzero_pd(); 4];
                for k in 0..4 {
                    let low = _mm512_castpd256_pd512(_mm256_loadu_pd(r[k].as_ptr()));
                    z[k] = _mm512_insertf64x4::<1>(low, _mm256_loadu_pd(r[k + 4].as_ptr()));
                }
                let [t0, t1, t2, t3] = transpose4x2(z);
                [Avx512(t0), Avx512(t1), Avx512(t2), Avx512(t3)]
            }
        }
        #[inline(always)]
        fn to_rows(lanes: [Self; 4], mut row: impl FnMut(usize, [f64; 4])) {
            // SAFETY: see the type's documentation; each row is four writable f64
            unsafe {
                // the transpose of each half is its own inverse: z_k = (row k | row k+4)
                let [l0, l1, l2, l3] = lanes;
                let z = transpose4x2([l0.0, l1.0, l2.0, l3.0]);
                for half in 0..2 {
                    for (k, zk) in z.iter().enumerate() {
                        let r = if half == 0 { _mm512_castpd512_pd256(*zk) } else { _mm512_extractf64x4_pd::<1>(*zk) };
                        let mut a = [0.0; 4];
                        _mm256_storeu_pd(a.as_mut_ptr(), r);
                        row(k + 4 * half, a);
                    }
                }
            }
        }
    }
}
