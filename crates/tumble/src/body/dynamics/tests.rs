//! Newton–Euler: the body-frame and world-frame rotational equations agree, Euler's equations match
//! their component form (3.6), and the resultant of the loads is what the hand says.

// the one tolerance helper of the unit tests (test modules are private to their parents, so it is
// included by path rather than imported)
#[allow(clippy::duplicate_mod)]
#[path = "../../math/tests/support.rs"]
mod support;

use super::*;
use crate::body::{PointForce, RigidBody};
use crate::math::{quat_rate_body, DQuat};
use proptest::prelude::*;
use support::{assert_close, principal_moments, unit_quat, vec3, EPS};

const GRAVITY: DVec3 = DVec3::new(0.0, 0.0, -9.81);

proptest! {
    /// (3.3) ⇔ (3.5): `α_world = R α_body`, where `α_body` solves Euler's equations with constant
    /// `I_body` and `α_world` solves `τ_world = I_world α_world + ω_world × I_world ω_world` with
    /// `I_world = R I_body Rᵀ` and its inverse formed afresh; to 1e-12 of the size of the terms
    /// (`|I⁻¹| (|τ| + |ω| |I ω|)`), since `α` itself may cancel to zero.
    #[test]
    fn alpha_body_and_alpha_world_agree(
        q in unit_quat(),
        inertia_body in principal_moments(),
        omega_body in vec3(20.0),
        torque_body in vec3(10.0),
    ) {
        let r = DMat3::from_quat(q);
        let alpha_b = alpha_body(inertia_body, omega_body, torque_body);
        let alpha_w = alpha_world(r, inertia_body, r * omega_body, r * torque_body);
        let gyro = omega_body.length() * (inertia_body * omega_body).length();
        let scale = (torque_body.length() + gyro) / inertia_body.min_element();
        assert_close("R α_body vs α_world", r * alpha_b, alpha_w, 1e-12, scale);
    }

    /// (3.4) rearranged: `I_body α_body + ω_body × I_body ω_body = τ_body`, and torque-free motion keeps
    /// the kinetic energy (`ωᵀ I α = 0`) and the world angular momentum (`d/dt (R L_body) = 0`).
    #[test]
    fn euler_equations_hold_and_conserve(
        inertia_body in principal_moments(),
        omega_body in vec3(20.0),
        torque_body in vec3(10.0),
    ) {
        let alpha = alpha_body(inertia_body, omega_body, torque_body);
        let l_body = inertia_body * omega_body;
        let gyro = omega_body.cross(l_body);
        // round-off is relative to the products inside ω × L, |ω| |L|, not to |ω × L|, which may cancel
        let gyro_scale = omega_body.length() * l_body.length();
        let scale = torque_body.length() + gyro_scale;
        assert_close("I α + ω × I ω vs τ", inertia_body * alpha + gyro, torque_body, 8.0 * EPS, scale);
        let free = alpha_body(inertia_body, omega_body, DVec3::ZERO);
        // dT/dt = ωᵀ I α
        let energy_scale = omega_body.length() * gyro_scale;
        assert_close("dT/dt torque-free", omega_body.dot(inertia_body * free), 0.0, 16.0 * EPS, energy_scale);
        // d/dt L_world = R (I α + ω × L_body): zero when torque-free
        assert_close("dL_world/dt torque-free", inertia_body * free + gyro, DVec3::ZERO, 8.0 * EPS, gyro_scale);
    }

    /// `resultant` with one point force: the force plus the torque `p × f` about the centre of mass,
    /// for a force fixed in the world or turning with the body.
    #[test]
    fn point_force_gives_force_and_moment(
        q in unit_quat(),
        point_body in vec3(2.0),
        force in vec3(100.0),
        world_frame in any::<bool>(),
    ) {
        let mass = MassProperties::from_principal(3.0, DVec3::new(1.0, 1.5, 2.0)).unwrap();
        let frame = if world_frame { Frame::World } else { Frame::Body };
        let loads = Loads { point_forces: vec![PointForce { point_body, force, frame }], ..Default::default() };
        let state = BodyState { orientation: q, ..BodyState::REST };
        let (force_world, torque_body) = resultant(&mass, &loads, &state, GRAVITY);
        let f_world = if world_frame { force } else { q * force };
        let scale = force.length();
        assert_close("force", force_world, 3.0 * GRAVITY + f_world, 8.0 * EPS, scale + 30.0);
        // in the world frame: τ_world = (R p) × f_world
        let torque_world_expected = (q * point_body).cross(f_world);
        assert_close("R τ_body vs (R p) × f", q * torque_body, torque_world_expected, 16.0 * EPS, point_body.length() * scale);
    }
}

/// (3.6), Euler's equations written out for a diagonal `I_body = diag(Ix, Iy, Iz)`:
/// `Ix αx = τx + (Iy − Iz) ωy ωz`, `Iy αy = τy + (Iz − Ix) ωz ωx`, `Iz αz = τz + (Ix − Iy) ωx ωy`.
#[test]
fn alpha_body_matches_component_form() {
    let (i, w, t) = (DVec3::new(1.0, 2.0, 4.0), DVec3::new(3.0, -1.0, 2.0), DVec3::new(0.5, 1.0, -2.0));
    let expected = DVec3::new(
        (t.x + (i.y - i.z) * w.y * w.z) / i.x, // (0.5 + (−2)(−2))/1 = 4.5
        (t.y + (i.z - i.x) * w.z * w.x) / i.y, // (1 + 3·6)/2 = 9.5
        (t.z + (i.x - i.y) * w.x * w.y) / i.z, // (−2 + (−1)(−3))/4 = 0.25
    );
    assert_eq!(expected, DVec3::new(4.5, 9.5, 0.25));
    assert_close("α_body vs (3.6)", alpha_body(i, w, t), expected, 4.0 * EPS, 9.5);
}

/// Spin about a principal axis is steady: no gyroscopic acceleration, in either form.
#[test]
fn principal_spin_is_steady() {
    let i = DVec3::new(1.0, 2.0, 3.0);
    let q = DQuat::from_axis_angle(DVec3::new(0.0, 0.6, 0.8), 0.9);
    for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
        let omega_body = 7.0 * axis;
        assert_eq!(alpha_body(i, omega_body, DVec3::ZERO), DVec3::ZERO);
        let alpha_w = alpha_world(DMat3::from_quat(q), i, q * omega_body, DVec3::ZERO);
        assert_close("α_world, principal spin", alpha_w, DVec3::ZERO, 64.0 * EPS, 7.0 * 7.0 * 3.0);
    }
}

/// Every kind of load in one resultant, by hand: body turned 90° about z (body x = world y).
#[test]
fn resultant_by_hand() {
    let mass = MassProperties::from_principal(2.0, DVec3::new(1.0, 2.0, 3.0)).unwrap();
    let state = BodyState {
        position: DVec3::ZERO,
        orientation: DQuat::from_rotation_z(std::f64::consts::FRAC_PI_2),
        velocity: DVec3::new(1.0, 0.0, 0.0),
        omega_body: DVec3::new(0.0, 0.0, 1.0),
    };
    let loads = Loads {
        force_world: DVec3::new(1.0, 0.0, 0.0),
        force_body: DVec3::new(1.0, 0.0, 0.0),   // world +y
        torque_world: DVec3::new(1.0, 0.0, 0.0), // body −y
        torque_body: DVec3::new(0.0, 0.0, 1.0),
        // at body (1, 0, 0) a world force (0, 0, 1): body force (0, 0, 1), torque (1,0,0)×(0,0,1) = (0, −1, 0)
        point_forces: vec![PointForce { point_body: DVec3::X, force: DVec3::Z, frame: Frame::World }],
        linear_damping: 0.5,   // −0.5·2·(1, 0, 0)
        angular_damping: 0.25, // −0.25·(0, 0, 3)
    };
    let (force_world, torque_body) = resultant(&mass, &loads, &state, GRAVITY);
    // m g + f_world + R f_body + f_point − c m v = (0,0,−19.62) + (1,0,0) + (0,1,0) + (0,0,1) − (1,0,0)
    assert_close("force", force_world, DVec3::new(0.0, 1.0, -18.62), 8.0 * EPS, 20.0);
    // τ_body + Rᵀ τ_world + p × f − c I ω = (0,0,1) + (0,−1,0) + (0,−1,0) − (0,0,0.75)
    assert_close("torque", torque_body, DVec3::new(0.0, -2.0, 0.25), 8.0 * EPS, 2.0);
    // `applied` is the same without the damping terms
    let (f_applied, t_applied) = applied(&mass, &loads, &state, GRAVITY);
    assert_close("applied force", f_applied, DVec3::new(1.0, 1.0, -18.62), 8.0 * EPS, 20.0);
    assert_close("applied torque", t_applied, DVec3::new(0.0, -2.0, 1.0), 8.0 * EPS, 2.0);
}

/// (3.7) as the integrators see it: `state_rate` stacks `ẋ = v`, `v̇ = f/m`, `q̇ = ½ q ⊗ (0, ω_body)`
/// and `ω̇_body = α_body`.
#[test]
fn state_rate_stacks_newton_euler() {
    let mut body = RigidBody::new("b", MassProperties::from_principal(4.0, DVec3::new(1.0, 2.0, 2.5)).unwrap());
    body.state.orientation = DQuat::from_axis_angle(DVec3::new(0.0, 0.6, 0.8), 0.4);
    body.state.velocity = DVec3::new(1.0, 2.0, 3.0);
    body.state.omega_body = DVec3::new(0.3, -2.0, 1.0);
    body.loads.torque_body = DVec3::new(0.0, 0.5, 0.0);
    body.loads.force_world = DVec3::new(4.0, 0.0, 0.0);
    let rate = state_rate(&body.mass, &body.loads, &body.state, GRAVITY);
    assert_eq!(rate.velocity, body.state.velocity);
    assert_close("v̇", rate.acceleration, DVec3::new(1.0, 0.0, -9.81), 2.0 * EPS, 10.0);
    assert_eq!(rate.orientation_rate, quat_rate_body(body.state.orientation, body.state.omega_body));
    let alpha = alpha_body(body.mass.inertia_body, body.state.omega_body, body.loads.torque_body);
    assert_eq!(rate.alpha_body, alpha);
}
