//! The body's accessors: kinetic energy, angular momentum, world-frame inertia and angular velocity,
//! and the user's axes, against hand computations and against each other.

// the one tolerance helper of the unit tests (test modules are private to their parents, so it is
// included by path rather than imported)
#[allow(clippy::duplicate_mod)]
#[path = "../math/tests/support.rs"]
mod support;

use super::*;
use crate::math::inertia_world;
use proptest::prelude::*;
use support::{assert_close, principal_moments, unit_quat, vec3, EPS};

/// A body of mass 2 kg, moments (1, 2, 3) kg·m², turned 90° about world z.
fn turned_body() -> RigidBody {
    let mut body = RigidBody::new("b", MassProperties::from_principal(2.0, DVec3::new(1.0, 2.0, 3.0)).unwrap());
    body.state.orientation = DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2);
    body.state.position = DVec3::new(1.0, 0.0, 0.0);
    body.state.velocity = DVec3::new(0.0, 3.0, 0.0);
    body.state.omega_body = DVec3::new(1.0, 1.0, 2.0);
    body
}

/// By hand: `T = ½·2·9 + ½ (1·1 + 2·1 + 3·4) = 9 + 7.5 = 16.5 J`.
#[test]
fn kinetic_energy_by_hand() {
    assert_close("T", turned_body().kinetic_energy(), 16.5, 2.0 * EPS, 16.5);
}

/// By hand: `L_body = I ω = (1, 2, 6)`; turned 90° about z, `L_spin = (−2, 1, 6)`; the orbital part
/// `x × m v = (1, 0, 0) × (0, 6, 0) = (0, 0, 6)`; total `(−2, 1, 12)` kg·m²/s.
#[test]
fn angular_momentum_by_hand() {
    let body = turned_body();
    assert_eq!(body.angular_momentum_body(), DVec3::new(1.0, 2.0, 6.0));
    assert_close("L_world", body.angular_momentum_world(), DVec3::new(-2.0, 1.0, 12.0), 4.0 * EPS, 12.0);
    // ω_world = R ω_body = (−1, 1, 2)
    assert_close("ω_world", body.state.omega_world(), DVec3::new(-1.0, 1.0, 2.0), 4.0 * EPS, 2.0);
    // I_world = R diag(1, 2, 3) Rᵀ = diag(2, 1, 3) for a quarter turn about z
    assert_close("I_world", body.inertia_world(), DMat3::from_diagonal(DVec3::new(2.0, 1.0, 3.0)), 4.0 * EPS, 3.0);
}

/// `−m g · x`: a 2 kg body 5 m up in standard gravity has `U = 98.1 J`.
#[test]
fn potential_energy_by_hand() {
    let mut body = turned_body();
    body.state.position = DVec3::new(7.0, -3.0, 5.0);
    assert_close("U", body.potential_energy(DVec3::new(0.0, 0.0, -9.81)), 98.1, 2.0 * EPS, 98.1);
}

proptest! {
    /// The kinetic energy and the momenta computed in the body frame equal those computed in the world
    /// frame from `I_world = R I_body Rᵀ` and `ω_world = R ω_body` (1.2).
    #[test]
    fn accessors_agree_across_frames(
        q in unit_quat(),
        moments in principal_moments(),
        omega_body in vec3(10.0),
        x in vec3(10.0),
        v in vec3(10.0),
        mass in 0.1..100.0_f64,
    ) {
        let mut body = RigidBody::new("b", MassProperties::from_principal(mass, moments).unwrap());
        body.state = BodyState { position: x, orientation: q, velocity: v, omega_body };
        let omega_world = body.state.omega_world();
        let inertia_world = body.inertia_world();
        prop_assert_eq!(inertia_world, inertia_world_of(q, moments));
        let spin_energy = 0.5 * omega_world.dot(inertia_world * omega_world);
        let t_expected = 0.5 * mass * v.length_squared() + spin_energy;
        let t_scale = 0.5 * mass * v.length_squared() + 0.5 * moments.max_element() * omega_body.length_squared();
        assert_close("T body vs world", body.kinetic_energy(), t_expected, 32.0 * EPS, t_scale);
        let l_expected = x.cross(mass * v) + inertia_world * omega_world;
        let l_scale = mass * x.length() * v.length() + moments.max_element() * omega_body.length();
        assert_close("L body vs world", body.angular_momentum_world(), l_expected, 32.0 * EPS, l_scale);
    }

    /// `set_omega_world` then `omega_world` is the identity; the user's axes round-trip through
    /// `user_from_body`.
    #[test]
    fn setters_round_trip(q in unit_quat(), user_q in unit_quat(), omega_world in vec3(10.0), omega_user in vec3(10.0)) {
        let tensor = inertia_world_of(user_q, DVec3::new(1.0, 2.0, 2.5));
        let mut body = RigidBody::new("b", MassProperties::from_tensor(1.0, tensor).unwrap());
        body.state.orientation = q;
        body.set_omega_world(omega_world);
        assert_close("ω_world round trip", body.state.omega_world(), omega_world, 8.0 * EPS, omega_world.length());
        body.set_orientation_user(q);
        let back = body.orientation_user();
        let back = if back.dot(q) < 0.0 { -back } else { back };
        assert_close("orientation_user round trip", back, q, 8.0 * EPS, 1.0);
        body.set_omega_user(omega_user);
        let omega_user_back = body.mass.user_from_body * body.state.omega_body;
        assert_close("ω_user round trip", omega_user_back, omega_user, 8.0 * EPS, omega_user.length());
        // the world sees the same rotation through either set of axes: R_world_from_user ω_user
        let via_user = body.orientation_user() * omega_user;
        assert_close("ω_world via user axes", body.state.omega_world(), via_user, 16.0 * EPS, omega_user.length());
    }
}

fn inertia_world_of(q: DQuat, moments: DVec3) -> DMat3 {
    inertia_world(DMat3::from_quat(q), moments)
}

/// `Loads::needs_rotation` is true exactly for loads given in a frame other than the one they are
/// used in.
#[test]
fn loads_need_rotation_only_across_frames() {
    let mut loads = Loads::default();
    assert!(loads.is_empty() && !loads.needs_rotation());
    loads.force_world = DVec3::X;
    loads.torque_body = DVec3::Y;
    loads.linear_damping = 0.1;
    assert!(!loads.is_empty() && !loads.needs_rotation());
    for change in 0..3 {
        let mut l = loads.clone();
        match change {
            0 => l.force_body = DVec3::Z,
            1 => l.torque_world = DVec3::Z,
            _ => l.point_forces.push(PointForce { point_body: DVec3::X, force: DVec3::Z, frame: Frame::Body }),
        }
        assert!(l.needs_rotation(), "change {change}");
    }
}

/// A non-finite component anywhere in the state is seen.
#[test]
fn state_finiteness() {
    assert!(BodyState::REST.is_finite());
    for k in 0..4 {
        let mut s = BodyState::REST;
        match k {
            0 => s.position.y = f64::NAN,
            1 => s.orientation.w = f64::INFINITY,
            2 => s.velocity.z = f64::NEG_INFINITY,
            _ => s.omega_body.x = f64::NAN,
        }
        assert!(!s.is_finite(), "component {k}");
    }
}
