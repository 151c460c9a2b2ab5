//! Properties of the frame and rotation helpers: the identities (1.1), (1.2), (2.1)–(2.3) of the seed
//! text and the quaternion exponential map, on random vectors and random unit quaternions.

mod support;

use super::*;
use crate::integrate::renormalize;
use proptest::prelude::*;
use support::{assert_close, assert_rel, unit_quat, unit_vec3, vec3, EPS};

/// The rotation matrix `world_from_body` of a unit quaternion.
fn rot(q: DQuat) -> DMat3 {
    DMat3::from_quat(q)
}

/// The three invariants of a symmetric matrix (trace, sum of principal 2×2 minors, determinant): the
/// coefficients of its characteristic polynomial, so equal invariants mean equal eigenvalues. (Unlike
/// an eigen-solver, they are well conditioned at repeated eigenvalues.)
fn invariants(m: DMat3) -> DVec3 {
    let tr = m.x_axis.x + m.y_axis.y + m.z_axis.z;
    let tr_sq = (m * m).x_axis.x + (m * m).y_axis.y + (m * m).z_axis.z;
    DVec3::new(tr, 0.5 * (tr * tr - tr_sq), m.determinant())
}

proptest! {
    /// (2.1) `ã b = a × b`.
    #[test]
    fn skew_times_b_is_cross_product(a in vec3(10.0), b in vec3(10.0)) {
        assert_close("skew(a) b vs a × b", skew(a) * b, a.cross(b), 2.0 * EPS, a.length() * b.length());
    }

    /// `ãᵀ = −ã`, exactly (the entries are copies and negations of `a`'s components).
    #[test]
    fn skew_is_antisymmetric(a in vec3(10.0)) {
        prop_assert_eq!(skew(a).transpose(), -skew(a));
        prop_assert_eq!(skew(a).x_axis.x + skew(a).y_axis.y + skew(a).z_axis.z, 0.0);
    }

    /// `unskew(skew(a)) = a`, exactly; and `unskew` ignores a symmetric part.
    #[test]
    fn unskew_inverts_skew(a in vec3(10.0), s in vec3(10.0)) {
        prop_assert_eq!(unskew(skew(a)), a);
        let symmetric = DMat3::from_diagonal(s) + skew(s) * skew(s);
        assert_close("unskew(ã + S) vs a", unskew(skew(a) + symmetric), a, 4.0 * EPS, a.length() + s.length_squared());
    }

    /// (2.2) `skew(R a) = R ã Rᵀ`, and `change_frame` is that conjugation.
    #[test]
    fn skew_changes_frame_by_conjugation(q in unit_quat(), a in vec3(10.0)) {
        let r = rot(q);
        assert_close("skew(R a) vs R ã Rᵀ", skew(r * a), change_frame(r, skew(a)), 16.0 * EPS, a.length());
        assert_close("skew(q a) vs R ã Rᵀ", skew(q * a), r * skew(a) * r.transpose(), 16.0 * EPS, a.length());
    }

    /// (1.1) `R⁻¹ = Rᵀ`, `Rᵀ R = 1` and `det R = +1`.
    #[test]
    fn rotation_inverse_is_transpose(q in unit_quat()) {
        let r = rot(q);
        assert_close("R⁻¹ vs Rᵀ", r.inverse(), r.transpose(), 16.0 * EPS, 1.0);
        // |q|² = 1 ± 2ε after normalize, each entry of R carries ~3 roundings and each entry of Rᵀ R sums
        // three products: ≈ 2·2ε + 9ε < 16ε
        assert_close("Rᵀ R vs 1", r.transpose() * r, DMat3::IDENTITY, 16.0 * EPS, 1.0);
        // det R = |q|⁶ = 1 ± 6ε, plus the determinant's own few roundings
        assert_close("det R vs 1", r.determinant(), 1.0, 16.0 * EPS, 1.0);
    }

    /// (1.2) `I_world = R I_body Rᵀ` maps `ω_world = R ω_body` to `L_world = R (I_body ω_body)`, is
    /// symmetric, and has the principal moments as eigenvalues.
    #[test]
    fn inertia_world_maps_omega_world_to_momentum_world(
        q in unit_quat(),
        inertia_body in support::principal_moments(),
        omega_body in vec3(10.0),
    ) {
        let r = rot(q);
        let inertia_world = inertia_world(r, inertia_body);
        let l_world = r * (inertia_body * omega_body);
        let scale = inertia_body.max_element() * omega_body.length();
        assert_close("I_world ω_world vs R I_body ω_body", inertia_world * (r * omega_body), l_world, 32.0 * EPS, scale);
        prop_assert_eq!(inertia_world, change_frame(r, DMat3::from_diagonal(inertia_body)));
        let big = inertia_body.max_element();
        assert_close("I_world symmetric", inertia_world.transpose(), inertia_world, 8.0 * EPS, big);
        // eigenvalues kept: equal characteristic polynomials (scale: I, I², I³). The matrix of a
        // normalised quaternion is orthonormal to < 16ε (see `rotation_inverse_is_transpose`), so e.g.
        // tr(R I Rᵀ) = Σ I_k |R e_k|² is off by up to 3 · 16ε · I_max
        let (expected, actual) = (invariants(DMat3::from_diagonal(inertia_body)), invariants(inertia_world));
        assert_close("trace", actual.x, expected.x, 48.0 * EPS, big);
        assert_close("sum of 2×2 minors", actual.y, expected.y, 96.0 * EPS, big * big);
        assert_close("determinant", actual.z, expected.z, 128.0 * EPS, big * big * big);
    }

    /// (2.3) `Ṙ = ω̃_world R = R ω̃_body`, against a central difference of `R(t) = R0 exp(ω_body t)`.
    ///
    /// The central difference has truncation error `≤ h² |ω|³ / 6` per entry and round-off `≈ 2 ε / h`;
    /// the tolerance is twice their sum.
    #[test]
    fn rotation_rate_matches_finite_difference(q0 in unit_quat(), axis in unit_vec3(), speed in 0.1..5.0_f64) {
        let omega_body = speed * axis;
        let h = 1e-5;
        let r_at = |t: f64| rot(q0 * quat_exp(omega_body * t));
        let r_dot_numeric = (r_at(h) - r_at(-h)) * (0.5 / h);
        let r0 = rot(q0);
        let omega_world = r0 * omega_body;
        let tol = 2.0 * (h * h * speed.powi(3) / 6.0 + 2.0 * EPS / h);
        assert_close("R ω̃_body vs (R(h) − R(−h))/2h", rotation_rate_body(r0, omega_body), r_dot_numeric, tol, 1.0);
        assert_close("ω̃_world R vs (R(h) − R(−h))/2h", rotation_rate_world(r0, omega_world), r_dot_numeric, tol, 1.0);
        // (2.4): both forms are the same matrix up to round-off
        assert_close(
            "ω̃_world R vs R ω̃_body",
            rotation_rate_world(r0, omega_world),
            rotation_rate_body(r0, omega_body),
            16.0 * EPS,
            speed,
        );
    }

    /// `q̇ = ½ q ⊗ (0, ω_body)` moves `R(q)` at the rate `Ṙ = R ω̃_body`.
    ///
    /// `DMat3::from_quat` is a quadratic polynomial in the components of `q`, so the central difference
    /// `(R(q + h q̇) − R(q − h q̇)) / 2h` is its exact derivative along `q̇` up to round-off (`≈ ε / h`).
    #[test]
    fn quat_rate_body_agrees_with_rotation_rate(q in unit_quat(), omega_body in vec3(5.0)) {
        let q_dot = quat_rate_body(q, omega_body);
        prop_assert!(DVec4::from(q).dot(q_dot).abs() <= 4.0 * EPS * omega_body.length(), "q̇ is tangent to |q| = 1");
        let h = 1e-3;
        let r_plus = DMat3::from_quat(quat_add(q, h * q_dot));
        let r_minus = DMat3::from_quat(quat_add(q, -h * q_dot));
        let r_dot = (r_plus - r_minus) * (0.5 / h);
        assert_close("R(q)˙ vs R ω̃_body", r_dot, rotation_rate_body(rot(q), omega_body), 16.0 * EPS / h, 1.0 + omega_body.length());
    }

    /// Quaternion → matrix → quaternion gives `q` back up to its sign (`q` and `−q` are one rotation).
    #[test]
    fn quat_matrix_round_trip_up_to_sign(q in unit_quat()) {
        let back = DQuat::from_mat3(&DMat3::from_quat(q));
        let back = if back.dot(q) < 0.0 { -back } else { back };
        assert_close("from_mat3(from_quat(q)) vs ±q", back, q, 8.0 * EPS, 1.0);
        assert_close("R(−q) vs R(q)", DMat3::from_quat(-q), DMat3::from_quat(q), 0.0, 1.0);
    }

    /// Files write `[w, x, y, z]`; the conversion is exact both ways and puts `w` first.
    #[test]
    fn wxyz_round_trip_is_exact(q in unit_quat()) {
        let wxyz = quat_to_wxyz(q);
        prop_assert_eq!(wxyz, [q.w, q.x, q.y, q.z]);
        prop_assert_eq!(quat_from_wxyz(wxyz), q);
    }

    /// `exp` then `log` gives the rotation vector back, for angles in `(0, π)`.
    #[test]
    fn quat_log_inverts_quat_exp(axis in unit_vec3(), angle in 0.0..std::f64::consts::PI) {
        let phi = angle * axis;
        assert_close("log(exp(φ)) vs φ", quat_log(quat_exp(phi)), phi, 8.0 * EPS, angle.max(f64::MIN_POSITIVE));
    }

    /// Tiny angles (`|φ| ≈ 1e-12`) lose no digits: the round trip is relative to `|φ|`, and `exp(φ) ≈ (1, φ/2)`.
    #[test]
    fn quat_exp_log_tiny_angles(axis in unit_vec3(), log_angle in -14.0..-4.0_f64) {
        let angle = 10f64.powf(log_angle);
        let phi = angle * axis;
        let q = quat_exp(phi);
        assert_close("exp(φ).xyz vs φ/2", DVec3::new(q.x, q.y, q.z), 0.5 * phi, 4.0 * EPS + angle * angle / 24.0, angle);
        assert_close("log(exp(φ)) vs φ", quat_log(q), phi, 8.0 * EPS, angle);
    }

    /// Angles near `π` (where `w → 0` and the sign of `q` matters): the round trip holds within
    /// `|φ| < π`, and beyond `π` the logarithm returns the same rotation as the shorter vector `φ − 2π φ̂`.
    #[test]
    fn quat_exp_log_near_pi(axis in unit_vec3(), log_gap in -12.0..-1.0_f64, beyond in any::<bool>()) {
        let gap = 10f64.powf(log_gap);
        let angle = if beyond { std::f64::consts::PI + gap } else { std::f64::consts::PI - gap };
        let phi = angle * axis;
        let q = quat_exp(phi);
        let expected = if beyond { (angle - 2.0 * std::f64::consts::PI) * axis } else { phi };
        assert_close("log(exp(φ)) near π", quat_log(q), expected, 8.0 * EPS, std::f64::consts::PI);
        let back = quat_exp(quat_log(q));
        let back = if back.dot(q) < 0.0 { -back } else { back };
        assert_close("exp(log(q)) vs ±q near π", back, q, 8.0 * EPS, 1.0);
    }

    /// `exp(log(q)) = ±q` for any unit quaternion.
    #[test]
    fn quat_exp_inverts_quat_log(q in unit_quat()) {
        let back = quat_exp(quat_log(q));
        let back = if back.dot(q) < 0.0 { -back } else { back };
        assert_close("exp(log(q)) vs ±q", back, q, 8.0 * EPS, 1.0);
    }

    /// `quat_exp` returns a unit quaternion to 1e-15, for small and large angles alike, and agrees with
    /// glam's axis–angle constructor.
    #[test]
    fn quat_exp_is_unit(axis in unit_vec3(), log_angle in -14.0..2.0_f64) {
        let angle = 10f64.powf(log_angle);
        let q = quat_exp(angle * axis);
        assert_close("|exp(φ)|", q.length(), 1.0, 1e-15, 1.0);
        let reference = DQuat::from_axis_angle(axis, angle);
        assert_close("exp(φ) vs from_axis_angle", q, reference, 8.0 * EPS * (1.0 + angle), 1.0);
    }

    /// A thousand compositions of unit quaternions, each followed by `renormalize`, stay at
    /// `|q| = 1 ± 1e-15`, and the product is still the product of the rotations.
    #[test]
    fn composition_with_renormalize_keeps_unit_norm(factors in prop::collection::vec(unit_quat(), 1000)) {
        let mut q = DQuat::IDENTITY;
        let mut r = DMat3::IDENTITY;
        for f in &factors {
            q = renormalize(q * *f);
            assert_close("|q| after renormalize", q.length(), 1.0, 1e-15, 1.0);
            r *= rot(*f);
        }
        // the matrix product accumulates round-off like a random walk: ~ √n ε per entry
        assert_close("R(Π q) vs Π R(q)", rot(q), r, 1e-12, 1.0);
    }

    /// `renormalize` is one Newton step: from `|q| = 1 + δ` it scales by `(3 − |q|²)/2 = 1 − δ − δ²/2`,
    /// leaving `|q| = 1 − 3δ²/2 − δ³/2`: the distance to the unit sphere is squared (times 3/2).
    #[test]
    fn renormalize_squares_the_norm_error(q in unit_quat(), log_delta in -12.0..-4.5_f64) {
        let delta = 10f64.powf(log_delta);
        let n = renormalize(q * (1.0 + delta)).length();
        let expected = 1.0 - 1.5 * delta * delta - 0.5 * delta.powi(3);
        assert_close("|renormalize(q (1 + δ))| vs 1 − 3δ²/2 − δ³/2", n, expected, 4.0 * EPS, 1.0);
        let far = renormalize(q * 1.5).length();
        assert_close("|renormalize(1.5 q)|", far, 1.0, 4.0 * EPS, 1.0);
    }
}

/// The cross-product matrix has the layout printed in the seed's (2.1).
#[test]
fn skew_layout_matches_seed() {
    let m = skew(DVec3::new(1.0, 2.0, 3.0));
    // rows: [0 −a_z a_y], [a_z 0 −a_x], [−a_y a_x 0]
    assert_eq!(m.row(0), DVec3::new(0.0, -3.0, 2.0));
    assert_eq!(m.row(1), DVec3::new(3.0, 0.0, -1.0));
    assert_eq!(m.row(2), DVec3::new(-2.0, 1.0, 0.0));
}

/// `quat_exp` switches from its series to `sin`/`cos` at `|φ| = 2e-4`; both sides agree there.
#[test]
fn quat_exp_is_continuous_at_series_switch() {
    let axis = DVec3::new(1.0, -2.0, 2.0) / 3.0;
    let switch = 2e-4;
    for angle in [switch * (1.0 - 1e-9), switch, switch * (1.0 + 1e-9)] {
        let q = quat_exp(angle * axis);
        assert_rel("exp vs from_axis_angle at the switch", q, DQuat::from_axis_angle(axis, angle), 4.0 * EPS);
    }
}

/// `log` of the identity is the zero vector; of a half turn it is a vector of length `π`.
#[test]
fn quat_log_special_values() {
    assert_eq!(quat_log(DQuat::IDENTITY), DVec3::ZERO);
    assert_eq!(quat_log(-DQuat::IDENTITY), DVec3::ZERO);
    let half_turn = DQuat::from_xyzw(0.0, 0.0, 1.0, 0.0);
    assert_close("log(half turn about z)", quat_log(half_turn), DVec3::new(0.0, 0.0, std::f64::consts::PI), 0.0, 1.0);
}
