//! Unit tests of the elliptic functions and the closed-form tops.
//!
//! Reference values marked "mpmath" were computed independently with mpmath 1.3 at 30 digits
//! (`ellipk`, `ellipf`, `ellipfun`).

#![allow(clippy::excessive_precision)] // reference values keep all the digits mpmath gave

use super::*;
use crate::math::{DQuat, DVec3};
use std::f64::consts::PI;

fn assert_close(got: f64, want: f64, tol: f64, what: &str) {
    assert!(
        (got - want).abs() <= tol,
        "{what}: got {got:.17e}, want {want:.17e}, |diff| = {:e} > {tol:e}",
        (got - want).abs()
    );
}

/// A small deterministic generator (xorshift) for sampled checks.
struct Rng(u64);
impl Rng {
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        lo + (hi - lo) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
    }
}

#[test]
fn complete_integral_matches_mpmath() {
    // (m, K(m)) from mpmath
    let table = [
        (0.1, 1.6124413487202193982),
        (0.5, 1.8540746773013719184),
        (0.9, 2.5780921133481731882),
        (0.99, 3.6956373629898746778),
        (0.999992000096, 7.2543473778725325541),
    ];
    for (m, k) in table {
        // the rounding of m itself (half an ulp) moves K by ∂K/∂m δm ≈ δm / (2 m (1 − m)) near m = 1
        let input_rounding = 0.5 * f64::EPSILON * m / (2.0 * m * (1.0 - m));
        assert_close(ellipk(m), k, 4e-16 * k + input_rounding, &format!("K({m})"));
    }
    // the same parameter given by its exact complement keeps every digit
    assert_close(ellipk_m1(7.999904e-6), 7.2543473778725325541, 4e-16 * 7.3, "K(m1 = 7.999904e-6)");
    assert_close(ellipk(0.0), PI / 2.0, 1e-16, "K(0)");
    // 1 − 0.999999999999 is not exactly 1e-12 in f64: give the complementary parameter itself
    assert_close(ellipk_m1(1e-12), 15.201804919087715174, 1e-14, "K(m1 = 1e-12)");
    assert!(ellipk(1.0).is_infinite());
    assert!(ellipk(1.5).is_nan() && ellipk(-0.5).is_nan());
}

#[test]
fn complete_integral_near_one_follows_the_logarithmic_asymptote() {
    // K = ln(4/k') + m1/4 (ln(4/k') − 1) + O(m1² ln m1), k' = sqrt(m1) (DLMF 19.12.1)
    for m1 in [1e-8, 1e-10, 1e-12, 1e-14] {
        let l = (4.0 / f64::sqrt(m1)).ln();
        let asymptote = l + 0.25 * m1 * (l - 1.0);
        assert_close(ellipk_m1(m1), asymptote, 1e-14 * asymptote, &format!("K(m1 = {m1:e})"));
    }
}

#[test]
fn incomplete_integral_matches_mpmath_and_inverts_the_amplitude() {
    assert_close(ellipf(0.7, 0.5), 0.72877030571819026436, 2e-16, "F(0.7, 0.5)");
    assert_close(ellipf(1.5, 0.999), 3.2950027527258307549, 1e-15, "F(1.5, 0.999)");
    assert_close(ellipf(PI / 2.0, 0.9), ellipk(0.9), 1e-15, "F(π/2) = K");
    assert_close(ellipf(-0.7, 0.5), -ellipf(0.7, 0.5), 0.0, "F is odd");
    assert_close(ellipf(0.7, 0.0), 0.7, 2.5e-16, "F(φ, 0) = φ");
    assert_close(ellipf(0.7, 1.0), f64::atanh(f64::sin(0.7)), 1e-15, "F(φ, 1) = atanh sin φ");
    // F(am(u)) = u on three quarters of a period, for several parameters
    for m1 in [0.9, 0.5, 0.1, 1e-3, 8e-6] {
        let k = ellipk_m1(m1);
        for i in -20..=30 {
            let u = i as f64 / 10.0 * k;
            let j = jacobi_m1(u, m1);
            // the amplitude, continued past ±π: am(u) is close to π u / (2K)
            let principal = j.sn.atan2(j.cn);
            let phi = principal + 2.0 * PI * ((PI * u / (2.0 * k) - principal) / (2.0 * PI)).round();
            let back = ellipf_m1(phi, m1);
            // dF/dφ = 1/dn ≤ 1/sqrt(m1): the inverse is that much worse conditioned
            let tol = 4e-16 * (1.0 + u.abs()) / j.dn;
            assert_close(back, u, tol, &format!("F(am({u}), m1 = {m1})"));
        }
    }
}

#[test]
fn jacobi_functions_match_mpmath() {
    // (u, m, sn, cn, dn) from mpmath
    let table = [
        (0.3, 0.1, 0.29509812430436884371, 0.95546695234950082199, 0.99563633406139027236),
        (1.2, 0.5, 0.88771548861927815676, 0.4603924535278963859, 0.77844756126069154554),
        (2.5, 0.9, 0.99969453845058613495, 0.024714971010898632614, 0.31709580068626358868),
        (7.0, 0.99, 0.37254730130781770964, -0.92801320480274529607, 0.92876069210824133812),
        (-3.3, 0.7, -0.70988286138012905202, -0.70431975914264998055, 0.80451626843907409988),
        (10.0, 0.999992000096, 0.99975945578223881171, -0.021932409215626044395, 0.022113946499963889567),
        (40.0, 0.3, -0.88065369794056446313, 0.47376055587565439138, 0.87597643763464477903),
    ];
    for (u, m, sn, cn, dn) in table {
        let j = jacobi(u, m);
        // near m = 1 the reference's m is itself rounded: the sensitivity ∂/∂m is ~u/m1 there
        let tol = if m > 0.9999 { 1e-12 } else { 2e-15 * (1.0 + u.abs()) };
        assert_close(j.sn, sn, tol, &format!("sn({u}, {m})"));
        assert_close(j.cn, cn, tol, &format!("cn({u}, {m})"));
        assert_close(j.dn, dn, tol, &format!("dn({u}, {m})"));
    }
}

#[test]
fn jacobi_identities_hold_across_parameters() {
    let mut rng = Rng(0x9e3779b97f4a7c15);
    for _ in 0..2000 {
        let m1 = 10f64.powf(rng.uniform(-14.0, 0.0));
        let m = 1.0 - m1;
        let u = rng.uniform(-30.0, 30.0);
        let j = jacobi_m1(u, m1);
        assert_close(j.sn * j.sn + j.cn * j.cn, 1.0, 1e-15, "sn² + cn² = 1");
        assert_close(j.dn * j.dn + m * j.sn * j.sn, 1.0, 1e-15, "dn² + m sn² = 1");
        // dn² − m1 = m cn² in relative terms, the form that shows dn's accuracy when it is small
        let rel = (j.dn * j.dn - m1 - m * j.cn * j.cn).abs() / (j.dn * j.dn);
        assert!(rel < 1e-13, "dn relative accuracy at u = {u}, m1 = {m1:e}: {rel:e}");
        assert!(j.dn > 0.0);
    }
}

#[test]
fn jacobi_derivatives_match_their_definitions() {
    // d sn/du = cn dn, d cn/du = −sn dn, d dn/du = −m sn cn (central differences, O(h²) = 1e-10)
    let h = 1e-5;
    for m1 in [0.8, 0.3, 1e-2, 1e-6] {
        let m = 1.0 - m1;
        for i in 0..40 {
            let u = -5.0 + 0.37 * i as f64;
            let (a, j, b) = (jacobi_m1(u - h, m1), jacobi_m1(u, m1), jacobi_m1(u + h, m1));
            let d = |f: fn(&Jacobi) -> f64| (f(&b) - f(&a)) / (2.0 * h);
            assert_close(d(|j| j.sn), j.cn * j.dn, 1e-9, "sn'");
            assert_close(d(|j| j.cn), -j.sn * j.dn, 1e-9, "cn'");
            assert_close(d(|j| j.dn), -m * j.sn * j.cn, 1e-9, "dn'");
        }
    }
}

#[test]
fn jacobi_special_parameters_are_circular_and_hyperbolic() {
    for i in 0..100 {
        let u = -12.0 + 0.25 * i as f64;
        // m = 0: sin, cos, 1 (exactly, and continuously from m = 1e-18)
        for j in [jacobi(u, 0.0), jacobi_m1(u, 1.0 - 1e-16)] {
            assert_close(j.sn, u.sin(), 1e-15, "sn(u, 0)");
            assert_close(j.cn, u.cos(), 1e-15, "cn(u, 0)");
            assert_close(j.dn, 1.0, 1e-15, "dn(u, 0)");
        }
        // m = 1: tanh, sech, sech (exactly, and continuously from m1 = 1e-300)
        for j in [jacobi(u, 1.0), jacobi_m1(u, 1e-300)] {
            let sech = 1.0 / u.cosh();
            assert_close(j.sn, u.tanh(), 1e-15, "sn(u, 1)");
            // relative accuracy of sech(u) is that of u, ~|u| ε, times the dozen Landen levels of m1 = 1e-300
            let tol = 1e-15 * (1.0 + u.abs()) * sech;
            assert_close(j.cn, sech, tol, "cn(u, 1)");
            assert_close(j.dn, sech, tol, "dn(u, 1)");
        }
    }
}

#[test]
fn jacobi_at_quarter_and_half_periods() {
    for m1 in [0.99, 0.5, 0.1, 1e-3, 8e-6, 1e-12] {
        let k = ellipk_m1(m1);
        let j = jacobi_m1(k, m1);
        assert_close(j.sn, 1.0, 1e-15, "sn(K) = 1");
        // cn(K) and dn(K) − k' are first order in the rounding of K: |∂cn/∂u| = dn = k'
        assert_close(j.cn, 0.0, 4e-16 * k, "cn(K) = 0");
        assert_close(j.dn / m1.sqrt(), 1.0, 1e-13, "dn(K) = sqrt(m1)");
        let j2 = jacobi_m1(2.0 * k, m1);
        assert_close(j2.sn, 0.0, 1e-15 * k, "sn(2K) = 0");
        assert_close(j2.cn, -1.0, 1e-15, "cn(2K) = −1");
        for u in [0.3, 1.1, 2.9] {
            let (a, b, c) = (jacobi_m1(u, m1), jacobi_m1(u + 2.0 * k, m1), jacobi_m1(u + 4.0 * k, m1));
            let tol = 1e-15 * (1.0 + 4.0 * k) / m1.sqrt().max(1e-3);
            assert_close(b.sn, -a.sn, tol, "sn(u + 2K) = −sn(u)");
            assert_close(b.cn, -a.cn, tol, "cn(u + 2K) = −cn(u)");
            assert_close(c.sn, a.sn, tol, "sn(u + 4K) = sn(u)");
            assert_close(c.dn, a.dn, tol, "dn(u + 4K) = dn(u)");
        }
    }
}

/// Euler's equations' residual `I ω̇ − (I ω) × ω`, with `ω̇` by a central difference of the solution.
fn euler_residual(inertia: DVec3, omega: impl Fn(f64) -> DVec3, t: f64) -> DVec3 {
    let h = 1e-5;
    let w = omega(t);
    let dw = (omega(t + h) - omega(t - h)) / (2.0 * h);
    inertia * dw - (inertia * w).cross(w)
}

#[test]
fn worked_flip_intervals_of_the_note() {
    let inertia = DVec3::new(1.0, 2.0, 3.0);
    let a = AsymmetricTop::new(inertia, DVec3::new(0.01, 5.0, 0.01)).unwrap();
    assert_eq!(a.regime(), Regime::AboutAxis3);
    assert_close(a.parameter(), 0.999992000096, 1e-12, "k² (axis 3)");
    assert_close(a.lambda(), 2.88676867, 1e-8, "λ (axis 3)");
    assert_close(a.flip_interval(), 5.0259291, 1e-7, "flip interval (axis 3)");
    let b = AsymmetricTop::new(inertia, DVec3::new(0.02, 5.0, -0.01)).unwrap();
    assert_eq!(b.regime(), Regime::AboutAxis1);
    assert_close(b.parameter(), 0.999996000064, 1e-12, "k² (axis 1)");
    assert_close(b.lambda(), 2.88677444, 1e-8, "λ (axis 1)");
    assert_close(b.flip_interval(), 5.2660277, 1e-7, "flip interval (axis 1)");
    // ω2 really changes sign once per flip interval: sample each half period at its middle
    for top in [a, b] {
        let t_flip = top.flip_interval();
        // the first zero of ω2 after t = 0: τ crosses a multiple of 2K
        let k = ellipk_m1(top.complementary_parameter());
        let first = ((top.tau0() / (2.0 * k)).floor() + 1.0) * 2.0 * k;
        let t_zero = (first - top.tau0()) / top.lambda();
        for n in 0..6 {
            let before = top.omega_body(t_zero + n as f64 * t_flip - 0.5 * t_flip).y;
            let after = top.omega_body(t_zero + n as f64 * t_flip + 0.5 * t_flip).y;
            assert!(before * after < 0.0, "ω2 must change sign at the {n}-th flip");
            assert!(top.omega_body(t_zero + n as f64 * t_flip).y.abs() < 1e-9);
        }
    }
}

#[test]
fn asymmetric_top_starts_at_its_initial_condition_and_solves_euler() {
    let mut rng = Rng(0x2545f4914f6cdd1d);
    let mut regimes = [0, 0];
    for _ in 0..400 {
        let i1 = rng.uniform(0.5, 2.0);
        let i2 = i1 + rng.uniform(0.05, 1.5);
        let i3 = i2 + rng.uniform(0.05, 1.5);
        let inertia = DVec3::new(i1, i2, i3);
        let w0 = DVec3::new(rng.uniform(-3.0, 3.0), rng.uniform(-3.0, 3.0), rng.uniform(-3.0, 3.0));
        let top = AsymmetricTop::new(inertia, w0).unwrap();
        regimes[(top.regime() == Regime::AboutAxis1) as usize] += 1;
        let scale = w0.length();
        let w = top.omega_body(0.0);
        // the inverse F is conditioned by 1/dn: allow for it
        assert!((w - w0).length() <= 1e-13 * scale / top.complementary_parameter().sqrt().min(1.0));
        let (two_e, m2) = (top.twice_energy(), top.angular_momentum_squared());
        for n in 0..20 {
            let t = 0.37 * n as f64;
            let w = top.omega_body(t);
            assert!((w.dot(inertia * w) - two_e).abs() <= 1e-13 * two_e, "energy along the solution");
            assert!(((inertia * w).length_squared() - m2).abs() <= 1e-13 * m2, "|L|² along the solution");
            let r = euler_residual(inertia, |t| top.omega_body(t), t);
            let scale_r = (inertia * w).length() * scale;
            assert!(r.length() <= 1e-8 * scale_r, "Euler residual {r:?} at t = {t} ({:?})", top.regime());
        }
        // one full period later ω is back
        let p = top.period();
        assert!((top.omega_body(p + 0.4) - top.omega_body(0.4)).length() <= 1e-11 * scale);
    }
    assert!(regimes[0] > 50 && regimes[1] > 50, "both regimes sampled: {regimes:?}");
}

#[test]
fn asymmetric_top_degenerate_initial_conditions() {
    let inertia = DVec3::new(1.0, 2.0, 3.0);
    // steady rotations about each principal axis
    for w0 in [DVec3::new(0.0, 0.0, 2.0), DVec3::new(-1.5, 0.0, 0.0), DVec3::new(0.0, 3.0, 0.0), DVec3::ZERO] {
        let top = AsymmetricTop::new(inertia, w0).unwrap();
        for t in [0.0, 1.0, 10.0] {
            assert!((top.omega_body(t) - w0).length() <= 1e-15 * (1.0 + w0.length()), "{w0:?} at {t}");
        }
    }
    // on the separatrix (d2 = 0): ω2 tends to ±|A2| and never comes back
    // I = (1, 2, 2.25): I1(I2 − I1) ω1² = I3(I3 − I2) ω3² = 0.5625 exactly
    let inertia_s = DVec3::new(1.0, 2.0, 2.25);
    let w0 = DVec3::new(0.75, 1.0, 1.0);
    let top = AsymmetricTop::new(inertia_s, w0).unwrap();
    assert_eq!(top.complementary_parameter(), 0.0);
    assert!(top.flip_interval().is_infinite());
    for t in [0.0, 0.3, 2.0, 10.0] {
        assert!(euler_residual(inertia_s, |t| top.omega_body(t), t).length() < 1e-8 * 10.0);
    }
    assert!((top.omega_body(0.0) - w0).length() < 1e-14);
    assert!(AsymmetricTop::new(DVec3::new(1.0, 1.0, 3.0), w0).is_err());
    assert!(AsymmetricTop::new(DVec3::new(3.0, 1.0, 3.0), w0).is_err());
    assert!(AsymmetricTop::new(inertia, DVec3::new(f64::NAN, 0.0, 0.0)).is_err());
}

#[test]
fn symmetric_top_body_rate_and_world_orientation() {
    let inertia = DVec3::new(2.0, 2.0, 3.5);
    let w0 = DVec3::new(0.7, -0.4, 2.5);
    let q0 = DQuat::from_axis_angle(DVec3::new(1.0, 2.0, -0.5).normalize(), 0.9);
    let top = SymmetricTop::new(inertia, w0, q0).unwrap();
    assert_close(top.body_precession_rate(), (3.5 - 2.0) / 2.0 * 2.5, 1e-15, "Ω");
    let l_world = q0 * (inertia * w0);
    let h = 1e-5;
    for n in 0..50 {
        let t = 0.23 * n as f64;
        let w = top.omega_body(t);
        assert!(euler_residual(inertia, |t| top.omega_body(t), t).length() < 1e-8 * 10.0);
        let q = top.orientation(t);
        assert!((q.length() - 1.0).abs() < 1e-14);
        // L_world = R I ω stays put
        assert!((q * (inertia * w) - l_world).length() < 1e-13 * l_world.length());
        // q̇ = ½ q ⊗ (0, ω_body)
        let dq = (DVec4::from(top.orientation(t + h)) - DVec4::from(top.orientation(t - h))) / (2.0 * h);
        let want = crate::math::quat_rate_body(q, w);
        assert!((dq - want).length() < 1e-9, "q̇ at t = {t}: {dq:?} vs {want:?}");
    }
    assert!(SymmetricTop::new(DVec3::new(1.0, 2.0, 3.0), w0, q0).is_err());
}

use crate::math::DVec4;

#[test]
fn carlson_integrals_and_the_third_kind_match_mpmath() {
    use super::elliptic::{carlson_rc, carlson_rj, ellippi_complete_m1};
    assert_close(carlson_rc(1.0, 2.0), PI / 4.0, 2e-16, "R_C(1, 2) = π/4");
    assert_close(carlson_rj(0.5, 1.0, 2.0, 3.0), 0.46698009947142691457, 2e-16, "R_J(0.5, 1, 2, 3)");
    assert_close(ellippi(-3.0, 0.9, 0.7), 0.64069192082881642844, 4e-16, "Π(−3; 0.9 | 0.7)");
    assert_close(ellippi(-0.5, 1.3, 0.999), 1.6088457950442870821, 1e-15, "Π(−0.5; 1.3 | 0.999)");
    assert_close(ellippi_complete_m1(-3.0, 7.999904e-6), 2.267032073260015241, 1e-15, "Π(−3 | m1 = 7.999904e-6)");
    // n = 0 is F; beyond π/2 the quasi-periodicity
    assert_close(ellippi(0.0, 2.4, 0.6), ellipf(2.4, 0.6), 1e-15, "Π(0; φ | m) = F(φ | m)");
    let h = 1e-5;
    for phi in [-4.0, -1.0, 0.3, 1.5, 2.0, 7.0] {
        let (n, m) = (-2.5, 0.8);
        let d = (ellippi(n, phi + h, m) - ellippi(n, phi - h, m)) / (2.0 * h);
        let s2 = f64::sin(phi).powi(2);
        assert_close(d, 1.0 / ((1.0 - n * s2) * (1.0 - m * s2).sqrt()), 1e-9, "dΠ/dφ");
    }
}

#[test]
fn asymmetric_top_world_orientation_follows_the_kinematics() {
    // q(0) = q0, q̇ = ½ q ⊗ (0, ω_body(t)) and L_world = R(t) I ω(t) constant, in both regimes
    let mut rng = Rng(0x853c49e6748fea9b);
    let h = 1e-5;
    let mut regimes = [0, 0];
    for case in 0..200 {
        let i1 = rng.uniform(0.5, 2.0);
        let i2 = i1 + rng.uniform(0.05, 1.5);
        let i3 = i2 + rng.uniform(0.05, 1.5);
        let inertia = DVec3::new(i1, i2, i3);
        let w0 = match case {
            0 => DVec3::new(0.01, 5.0, 0.01),
            1 => DVec3::new(0.02, 5.0, -0.01),
            _ => DVec3::new(rng.uniform(-3.0, 3.0), rng.uniform(-3.0, 3.0), rng.uniform(-3.0, 3.0)),
        };
        let inertia = if case < 2 { DVec3::new(1.0, 2.0, 3.0) } else { inertia };
        let axis = DVec3::new(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0)).normalize();
        let q0 = DQuat::from_axis_angle(axis, rng.uniform(0.0, 3.0));
        let top = AsymmetricTop::new(inertia, w0).unwrap().with_orientation(q0);
        regimes[(top.regime() == Regime::AboutAxis1) as usize] += 1;
        let q = top.orientation(0.0);
        assert!((q - q0).length().min((q + q0).length()) < 1e-12, "q(0) = {q:?}, want {q0:?}");
        let l_world = top.angular_momentum_world();
        for k in 0..25 {
            let t = 0.43 * k as f64;
            let q = top.orientation(t);
            let w = top.omega_body(t);
            assert!((q * (inertia * w) - l_world).length() <= 1e-12 * l_world.length(), "L_world at t = {t}");
            // the sign of q is continuous in t here: compare derivatives directly
            let dq = (DVec4::from(top.orientation(t + h)) - DVec4::from(top.orientation(t - h))) / (2.0 * h);
            let want = crate::math::quat_rate_body(q, w);
            assert!((dq - want).length() < 1e-8 * (1.0 + w.length()), "case {case}, t = {t}: q̇ {dq:?} vs {want:?}");
        }
    }
    assert!(regimes[0] > 20 && regimes[1] > 20, "both regimes sampled: {regimes:?}");
    // steady rotations: q0 ⊗ exp(ω t)
    let top = AsymmetricTop::new(DVec3::new(1.0, 2.0, 3.0), DVec3::new(0.0, 0.0, 2.0)).unwrap();
    assert_eq!(top.regime(), Regime::Steady);
    assert!((top.orientation(1.0) - DQuat::from_rotation_z(2.0)).length() < 1e-15);
}

#[test]
fn asymmetric_top_accepts_the_moments_in_any_order() {
    let mut rng = Rng(0xda942042e4dd58b5);
    let permutations = [[0, 1, 2], [1, 2, 0], [2, 0, 1], [0, 2, 1], [1, 0, 2], [2, 1, 0]];
    let h = 1e-5;
    for _ in 0..20 {
        let sorted = [rng.uniform(0.5, 1.0), rng.uniform(1.1, 1.6), rng.uniform(1.7, 2.5)];
        let w = [rng.uniform(-3.0, 3.0), rng.uniform(-3.0, 3.0), rng.uniform(-3.0, 3.0)];
        let q0 = DQuat::from_axis_angle(DVec3::new(0.2, 0.9, -0.4).normalize(), rng.uniform(0.0, 3.0));
        for p in permutations {
            let inertia = DVec3::new(sorted[p[0]], sorted[p[1]], sorted[p[2]]);
            let w0 = DVec3::new(w[p[0]], w[p[1]], w[p[2]]);
            let top = AsymmetricTop::new(inertia, w0).unwrap().with_orientation(q0);
            let s = top.sorted_from_body();
            assert!((s * s.transpose() - crate::math::DMat3::IDENTITY).abs_diff_eq(crate::math::DMat3::ZERO, 0.0));
            assert_eq!(s.determinant(), 1.0, "a proper rotation for {p:?}");
            assert!((top.omega_body(0.0) - w0).length() <= 1e-11 * w0.length(), "ω(0) for {p:?}");
            let l_world = top.angular_momentum_world();
            for k in 0..10 {
                let t = 0.61 * k as f64;
                let r = euler_residual(inertia, |t| top.omega_body(t), t);
                assert!(r.length() <= 1e-8 * (inertia * w0).length() * w0.length(), "Euler residual for {p:?}");
                let q = top.orientation(t);
                let omega = top.omega_body(t);
                assert!((q * (inertia * omega) - l_world).length() <= 1e-12 * l_world.length());
                let dq = (DVec4::from(top.orientation(t + h)) - DVec4::from(top.orientation(t - h))) / (2.0 * h);
                assert!((dq - crate::math::quat_rate_body(q, omega)).length() < 1e-8 * (1.0 + omega.length()));
            }
        }
    }
}
