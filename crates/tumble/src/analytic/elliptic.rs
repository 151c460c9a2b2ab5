//! Complete and incomplete elliptic integrals of the first kind and the Jacobi elliptic functions.
//!
//! References: M. Abramowitz, I. Stegun, *Handbook of Mathematical Functions*, §16.4 (descending
//! Landen transformation), §17.6 (arithmetic–geometric mean); R. Bulirsch, "Numerical calculation
//! of elliptic integrals and elliptic functions", Numer. Math. 7 (1965) 78–90 (the `sncndn`
//! algorithm, also in Press et al., *Numerical Recipes*, 3rd ed., §6.12); B. C. Carlson, "Numerical
//! computation of real or complex elliptic integrals", Numer. Algorithms 10 (1995) 13–26 (`R_F`,
//! `R_C`, `R_J`);
//! NIST DLMF §19.8 (AGM), §19.25 (`F` through `R_F`), §22 (Jacobi functions).
//!
//! Parameter convention: `m = k²` (the *parameter*, as in Abramowitz & Stegun and DLMF), and
//! `m1 = 1 − m` (the *complementary parameter*). Near the separatrix of a rigid body `m → 1`, and
//! `m1` can be computed from the physics without cancellation: every function here has a `_m1`
//! form that takes `m1` directly, which keeps all of its digits.
//!
//! - `K(m) = ∫₀^{π/2} dθ / sqrt(1 − m sin²θ) = π / (2 AGM(1, sqrt(1 − m)))` (DLMF 19.8.5);
//!   `K → ln(4/sqrt(m1))` as `m1 → 0`. Quadratic convergence: about five AGM steps for `f64`.
//! - `F(φ, m) = ∫₀^φ dθ / sqrt(1 − m sin²θ) = sin φ · R_F(cos²φ, 1 − m sin²φ, 1)` for `|φ| ≤ π/2`
//!   (DLMF 19.25.5), and `F(φ + nπ) = F(φ) + 2nK` beyond.
//! - `Π(n; φ | m) = ∫₀^φ dθ / ((1 − n sin²θ) sqrt(1 − m sin²θ))
//!   = sin φ R_F(c², Δ², 1) + (n/3) sin³φ R_J(c², Δ², 1, 1 − n sin²φ)`, `c = cos φ`,
//!   `Δ² = 1 − m sin²φ` (DLMF 19.25.14), for `n < 1`; `Π(φ + kπ) = Π(φ) + 2k Π(n | m)`.
//! - `sn(u, m) = sin φ`, `cn(u, m) = cos φ`, `dn(u, m) = sqrt(1 − m sn²)` with `φ = am(u, m)` the
//!   inverse of `u = F(φ, m)`; computed by the descending Landen (Gauss) transformation, which
//!   shrinks `m` quadratically towards 0 where `sn = sin`, `cn = cos`, `dn = 1`, and climbs back up
//!   with ratios of positive numbers (Bulirsch), so that `dn` keeps its relative accuracy even where
//!   it is as small as `sqrt(m1)`.

use std::f64::consts::PI;

/// `sn`, `cn` and `dn` at one argument (dimensionless).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Jacobi {
    /// `sn(u, m) = sin am(u, m)`.
    pub sn: f64,
    /// `cn(u, m) = cos am(u, m)`.
    pub cn: f64,
    /// `dn(u, m) = sqrt(1 − m sn²(u, m))`.
    pub dn: f64,
}

/// The arithmetic–geometric mean of two non-negative numbers (quadratic convergence).
pub fn agm(a: f64, b: f64) -> f64 {
    let (mut a, mut b) = (a, b);
    // at most ~6 iterations for f64 unless one argument is tiny; 64 bounds the pathological cases
    for _ in 0..64 {
        if (a - b).abs() <= 2.0 * f64::EPSILON * a {
            break;
        }
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
    }
    0.5 * (a + b)
}

/// The complete elliptic integral of the first kind `K(m)`, `0 ≤ m < 1` (parameter `m = k²`).
///
/// `K(m) = π / (2 AGM(1, sqrt(1 − m)))`. When `m` is within a few ulps of 1, prefer
/// [`ellipk_m1`] with `m1 = 1 − m` computed without cancellation. Returns `+∞` at `m = 1` and
/// `NaN` outside `[0, 1]`.
pub fn ellipk(m: f64) -> f64 {
    ellipk_m1(1.0 - m)
}

/// `K` as a function of the complementary parameter `m1 = 1 − m`, `0 ≤ m1 ≤ 1`.
pub fn ellipk_m1(m1: f64) -> f64 {
    if !(0.0..=1.0).contains(&m1) {
        return f64::NAN;
    }
    if m1 == 0.0 {
        return f64::INFINITY;
    }
    PI / (2.0 * agm(1.0, m1.sqrt()))
}

/// Carlson's symmetric integral `R_F(x, y, z) = ½ ∫₀^∞ dt / sqrt((t + x)(t + y)(t + z))`, `x, y, z ≥ 0`
/// with at most one of them zero, by the duplication theorem (Carlson 1995, relative error ≲ 1e-16).
pub fn carlson_rf(x: f64, y: f64, z: f64) -> f64 {
    // |1 − x/A| ≤ 0.0008 leaves a truncation error of the 5th-order series below 1e-17
    const TOL: f64 = 0.0008;
    let (mut x, mut y, mut z) = (x, y, z);
    let mut mean;
    let (mut dx, mut dy, mut dz);
    let mut iterations = 0;
    loop {
        mean = (x + y + z) / 3.0;
        dx = 1.0 - x / mean;
        dy = 1.0 - y / mean;
        dz = 1.0 - z / mean;
        if dx.abs().max(dy.abs()).max(dz.abs()) <= TOL || iterations >= 100 {
            break;
        }
        let (sx, sy, sz) = (x.sqrt(), y.sqrt(), z.sqrt());
        let lambda = sx * (sy + sz) + sy * sz;
        x = 0.25 * (x + lambda);
        y = 0.25 * (y + lambda);
        z = 0.25 * (z + lambda);
        iterations += 1;
    }
    let e2 = dx * dy - dz * dz;
    let e3 = dx * dy * dz;
    // DLMF 19.36.1: R_F = A^(−1/2) (1 − E2/10 + E3/14 + E2²/24 − 3 E2 E3/44)
    (1.0 + (e2 / 24.0 - 0.1 - 3.0 * e3 / 44.0) * e2 + e3 / 14.0) / mean.sqrt()
}

/// Carlson's degenerate integral `R_C(x, y) = R_F(x, y, y)`, `x ≥ 0`, `y > 0` (Carlson 1995).
pub fn carlson_rc(x: f64, y: f64) -> f64 {
    const TOL: f64 = 0.0012;
    let (mut x, mut y) = (x, y);
    let mut iterations = 0;
    loop {
        let mean = (x + 2.0 * y) / 3.0;
        let s = (y - mean) / mean;
        if s.abs() <= TOL || iterations >= 100 {
            // DLMF 19.36.8
            return (1.0 + s * s * (0.3 + s * (1.0 / 7.0 + s * (0.375 + s * 9.0 / 22.0)))) / mean.sqrt();
        }
        let lambda = 2.0 * x.sqrt() * y.sqrt() + y;
        x = 0.25 * (x + lambda);
        y = 0.25 * (y + lambda);
        iterations += 1;
    }
}

/// Carlson's integral of the third kind
/// `R_J(x, y, z, p) = (3/2) ∫₀^∞ dt / ((t + p) sqrt((t + x)(t + y)(t + z)))`, `x, y, z ≥ 0` (at most one
/// zero), `p > 0`, by the duplication theorem (Carlson 1995).
pub fn carlson_rj(x: f64, y: f64, z: f64, p: f64) -> f64 {
    const TOL: f64 = 0.0015;
    let (mut x, mut y, mut z, mut p) = (x, y, z, p);
    let (mut sum, mut factor) = (0.0, 1.0);
    let mut iterations = 0;
    let (mut mean, mut dx, mut dy, mut dz, mut dp);
    loop {
        let (sx, sy, sz) = (x.sqrt(), y.sqrt(), z.sqrt());
        let lambda = sx * (sy + sz) + sy * sz;
        let alpha = (p * (sx + sy + sz) + sx * sy * sz).powi(2);
        let beta = p * (p + lambda).powi(2);
        sum += factor * carlson_rc(alpha, beta);
        factor *= 0.25;
        x = 0.25 * (x + lambda);
        y = 0.25 * (y + lambda);
        z = 0.25 * (z + lambda);
        p = 0.25 * (p + lambda);
        mean = 0.2 * (x + y + z + 2.0 * p);
        dx = (mean - x) / mean;
        dy = (mean - y) / mean;
        dz = (mean - z) / mean;
        dp = (mean - p) / mean;
        iterations += 1;
        if dx.abs().max(dy.abs()).max(dz.abs()).max(dp.abs()) <= TOL || iterations >= 100 {
            break;
        }
    }
    let ea = dx * (dy + dz) + dy * dz;
    let eb = dx * dy * dz;
    let ec = dp * dp;
    let ed = ea - 3.0 * ec;
    let ee = eb + 2.0 * dp * (ea - ec);
    const C1: f64 = 3.0 / 14.0;
    const C2: f64 = 1.0 / 3.0;
    const C3: f64 = 3.0 / 22.0;
    const C4: f64 = 3.0 / 26.0;
    const C5: f64 = 0.75 * C3;
    const C6: f64 = 1.5 * C4;
    const C7: f64 = 0.5 * C2;
    const C8: f64 = C3 + C3;
    let series = 1.0 + ed * (-C1 + C5 * ed - C6 * ee) + eb * (C7 + dp * (-C8 + dp * C4)) + dp * ea * (C2 - dp * C3)
        - C2 * dp * ec;
    3.0 * sum + factor * series / (mean * mean.sqrt())
}

/// The complete elliptic integral of the third kind `Π(n | m) = Π(n; π/2 | m)`, `n < 1`, with the
/// complementary parameter `m1 = 1 − m`: `R_F(0, m1, 1) + (n/3) R_J(0, m1, 1, 1 − n)`.
pub fn ellippi_complete_m1(n: f64, m1: f64) -> f64 {
    if !(0.0..=1.0).contains(&m1) || n.is_nan() || n >= 1.0 {
        return f64::NAN;
    }
    carlson_rf(0.0, m1, 1.0) + n / 3.0 * carlson_rj(0.0, m1, 1.0, 1.0 - n)
}

/// `Π(n; φ | m)` for `|φ| ≤ π/2` from `s = sin φ`, `c = cos φ ≥ 0` and `Δ² = 1 − m s²` (given, so that
/// the caller can pass `cn` and `dn²` of the same argument without losing digits).
pub fn ellippi_sc(n: f64, s: f64, c: f64, delta2: f64) -> f64 {
    let (s2, c2) = (s * s, c * c);
    s * carlson_rf(c2, delta2, 1.0) + n / 3.0 * s * s2 * carlson_rj(c2, delta2, 1.0, 1.0 - n * s2)
}

/// The incomplete elliptic integral of the third kind `Π(n; φ | m)` for any real `φ` (rad), `n < 1`,
/// `0 ≤ m ≤ 1` (characteristic `n` with the sign convention `1 − n sin²θ`, as in DLMF 19.2.7).
pub fn ellippi(n: f64, phi: f64, m: f64) -> f64 {
    let m1 = 1.0 - m;
    if !(0.0..=1.0).contains(&m1) || !phi.is_finite() || n.is_nan() || n >= 1.0 {
        return f64::NAN;
    }
    let k = (phi / PI).round();
    let psi = phi - k * PI;
    let (s, c) = psi.sin_cos();
    let f = ellippi_sc(n, s, c, c * c + m1 * s * s);
    if k == 0.0 {
        f
    } else {
        f + 2.0 * k * ellippi_complete_m1(n, m1)
    }
}

/// The incomplete elliptic integral of the first kind `F(φ, m)` for any real amplitude `φ` (rad),
/// `0 ≤ m ≤ 1`. Inverse of the amplitude: `F(am(u, m), m) = u`.
pub fn ellipf(phi: f64, m: f64) -> f64 {
    ellipf_m1(phi, 1.0 - m)
}

/// `F(φ, m)` as a function of the complementary parameter `m1 = 1 − m`.
///
/// `φ = ψ + nπ` with `|ψ| ≤ π/2`: `F = 2nK + sin ψ R_F(cos²ψ, cos²ψ + m1 sin²ψ, 1)`; the second
/// argument is `1 − m sin²ψ` written without cancellation.
pub fn ellipf_m1(phi: f64, m1: f64) -> f64 {
    if !(0.0..=1.0).contains(&m1) || !phi.is_finite() {
        return f64::NAN;
    }
    let n = (phi / PI).round();
    let psi = phi - n * PI;
    let (s, c) = psi.sin_cos();
    let (s2, c2) = (s * s, c * c);
    let f = s * carlson_rf(c2, c2 + m1 * s2, 1.0);
    if n == 0.0 {
        f
    } else {
        f + 2.0 * n * ellipk_m1(m1)
    }
}

/// `sn`, `cn` and `dn` of `u` (dimensionless) with parameter `0 ≤ m ≤ 1`.
pub fn jacobi(u: f64, m: f64) -> Jacobi {
    jacobi_m1(u, 1.0 - m)
}

/// `sn`, `cn` and `dn` of `u` with the complementary parameter `m1 = 1 − m`, `0 ≤ m1 ≤ 1`
/// (Bulirsch's descending Landen transformation).
///
/// Descent: `a₀ = 1`, `b₀ = sqrt(m1)`; `a_{n+1} = (a_n + b_n)/2`, `b_{n+1} = sqrt(a_n b_n)` until
/// `a ≈ b`; at the bottom the parameter is 0 and the functions are `sin`, `cos` of `u · AGM`.
/// Ascent: with `c = cot` of the bottom amplitude, each level sets `dn ← (b_n + a)/(a_n + a)`
/// (a ratio of positive numbers) and updates the cotangent; finally `sn = ±1/sqrt(1 + c²)`,
/// `cn = c · sn`. Special cases: `m1 = 1` gives `(sin u, cos u, 1)`, `m1 = 0` gives
/// `(tanh u, sech u, sech u)`. Accuracy ~1e-15 absolute for moderate `|u|`; like `sin`, the
/// functions of a large argument carry the argument's own rounding (`~|u| ε`).
pub fn jacobi_m1(u: f64, m1: f64) -> Jacobi {
    if !(0.0..=1.0).contains(&m1) || !u.is_finite() {
        return Jacobi { sn: f64::NAN, cn: f64::NAN, dn: f64::NAN };
    }
    if m1 == 0.0 {
        let sech = 1.0 / u.cosh();
        return Jacobi { sn: u.tanh(), cn: sech, dn: sech };
    }
    if m1 == 1.0 {
        let (sn, cn) = u.sin_cos();
        return Jacobi { sn, cn, dn: 1.0 };
    }
    // descending AGM: a_n (em) and b_n (en) at each level
    const TOL: f64 = 1e-9; // quadratic convergence: the next level would agree to ~1e-18
    let mut em = [0.0; 64];
    let mut en = [0.0; 64];
    let mut a = 1.0;
    let mut b2 = m1; // b_n²
    let mut levels = 0;
    let mut mean = 1.0;
    for level in 0..64 {
        levels = level;
        em[level] = a;
        let b = b2.sqrt();
        en[level] = b;
        mean = 0.5 * (a + b);
        if (a - b).abs() <= TOL * a {
            break;
        }
        b2 = a * b;
        a = mean;
    }
    // bottom: parameter 0, amplitude u · AGM(1, sqrt(m1))
    let (sin_bottom, cos_bottom) = (u * mean).sin_cos();
    if sin_bottom == 0.0 {
        return Jacobi { sn: 0.0, cn: cos_bottom, dn: 1.0 };
    }
    // ascend with c = cot of the amplitude at each level
    let mut dn = 1.0;
    let mut ratio = cos_bottom / sin_bottom;
    let mut c = mean * ratio;
    for level in (0..=levels).rev() {
        let a_level = em[level];
        ratio *= c;
        c *= dn;
        dn = (en[level] + ratio) / (a_level + ratio);
        ratio = c / a_level;
    }
    let sn_abs = 1.0 / (c * c + 1.0).sqrt();
    let sn = if sin_bottom >= 0.0 { sn_abs } else { -sn_abs };
    Jacobi { sn, cn: c * sn, dn }
}
