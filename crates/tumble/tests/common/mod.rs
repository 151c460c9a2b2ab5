//! Shared helpers of the integration tests: one-body worlds and the one tolerance check.
#![allow(dead_code)]

use tumble::body::Loads;
use tumble::math::{DQuat, DVec3};
use tumble::{Integrator, MassProperties, RigidBody, World, WorldConfig};

/// `I = (1, 2, 3)` kg·m², the body of the note's worked examples.
pub const INERTIA: DVec3 = DVec3::new(1.0, 2.0, 3.0);
/// Spun close to the intermediate axis, `M² > 2E I2` (flip interval 5.0259291 s).
pub const NEAR_AXIS2_ABOUT_3: DVec3 = DVec3::new(0.01, 5.0, 0.01);
/// Spun close to the intermediate axis, `M² < 2E I2` (flip interval 5.2660277 s).
pub const NEAR_AXIS2_ABOUT_1: DVec3 = DVec3::new(0.02, 5.0, -0.01);
/// A generic tumbling motion, well away from the separatrix (rad/s, body frame).
pub const TUMBLING: DVec3 = DVec3::new(1.0, 0.5, -0.8);

/// An orientation with no special alignment, so that world and body frames differ.
pub fn tilted() -> DQuat {
    DQuat::from_axis_angle(DVec3::new(0.3, -1.0, 0.5).normalize(), 0.7)
}

/// A world holding one body of mass `mass` (kg) and principal moments `inertia` (kg·m²), with initial
/// body angular velocity `omega_body` (rad/s), no gravity unless set afterwards.
pub fn one_body_world(integrator: Integrator, dt: f64, mass: f64, inertia: DVec3, omega_body: DVec3) -> World {
    let mut body = RigidBody::new("body", MassProperties::from_principal(mass, inertia).unwrap());
    body.state.orientation = tilted();
    body.state.omega_body = omega_body;
    let config = WorldConfig { gravity: DVec3::ZERO, dt, integrator, ..Default::default() };
    World::new(config, vec![body])
}

/// A torque-free body of moments [`INERTIA`].
pub fn torque_free(integrator: Integrator, dt: f64, omega_body: DVec3) -> World {
    one_body_world(integrator, dt, 1.0, INERTIA, omega_body)
}

/// Sets the loads of the single body.
pub fn with_loads(mut world: World, loads: Loads) -> World {
    world.bodies[0].loads = loads;
    world
}

/// Steps `n` times, calling `observe` after each step.
pub fn run(world: &mut World, n: u64, mut observe: impl FnMut(&World)) {
    for _ in 0..n {
        world.step().expect("the state must stay finite");
        observe(world);
    }
}

/// `|got − want| ≤ tol`, with a message that names the quantity.
#[track_caller]
pub fn assert_within(got: f64, want: f64, tol: f64, what: &str) {
    let diff = (got - want).abs();
    assert!(diff <= tol, "{what}: got {got:.15e}, want {want:.15e}, |diff| = {diff:.3e} > tolerance {tol:.3e}");
}

/// The angle (rad) of the rotation that takes `b` to `a` (sign of the quaternions ignored).
pub fn rotation_angle_between(a: DQuat, b: DQuat) -> f64 {
    let d = a * b.conjugate();
    2.0 * DVec3::new(d.x, d.y, d.z).length().atan2(d.w.abs())
}

/// Observed order from the errors at `dt` and `dt/2`.
pub fn observed_order(error_dt: f64, error_half_dt: f64) -> f64 {
    (error_dt / error_half_dt).log2()
}
