//! Quantities derived from a trajectory read back, for plots and the replay: the invariants of each
//! frame (computed with the scene's mass properties and gravity), their errors against the first
//! frame, and the body-frame angular velocity.
//!
//! - Energy `E = Σ ½ m |v|² + ½ ω_bodyᵀ I_body ω_body − m g · x` over the moving bodies (J).
//! - Angular momentum about the world origin `L = Σ x × m v + R I_body ω_body`, world frame (kg·m²/s).
//! - Errors as in the run summary ([`Monitor`](super::Monitor)): the energy error is signed,
//!   `(E − E₀) / |E₀|`, so a plot shows drift up or down; the angular-momentum error is
//!   `|L − L₀| / |L₀|`. When the initial value is exactly zero the error is absolute (J or kg·m²/s).
//! - Body-frame angular velocity `ω_user = R_userᵀ ω_world` in the user's body axes (rad/s), the axes
//!   of the scene file; it needs no mass property.
//!
//! The values written to a trajectory are rounded to the shortest text that reads back exactly, so
//! the invariants computed here are those of the run, not approximations of them.

use super::read::{BodySample, ReadError, Trajectory};
use super::Invariants;
use crate::math::DVec3;
use crate::world::World;
use crate::RigidBody;

/// The invariants of every frame of `trajectory`, with the mass properties and gravity of `world`.
///
/// The trajectory's bodies must be exactly the world's moving bodies ([`Trajectory::check_bodies`];
/// `trajectory_name` and `scene_name` name the files in the error).
pub fn invariants(
    trajectory: &Trajectory,
    world: &World,
    trajectory_name: &str,
    scene_name: &str,
) -> Result<Vec<Invariants>, ReadError> {
    trajectory.check_bodies(world, trajectory_name, scene_name)?;
    // one scratch copy of each body, its state replaced frame by frame
    let mut bodies: Vec<RigidBody> =
        trajectory.bodies.iter().filter_map(|name| world.free_bodies().find(|b| &b.name == name).cloned()).collect();
    let gravity = world.config.gravity;
    let out = trajectory
        .frames
        .iter()
        .map(|frame| {
            let mut total = Invariants { energy: 0.0, linear_momentum: DVec3::ZERO, angular_momentum: DVec3::ZERO };
            for (body, sample) in bodies.iter_mut().zip(&frame.states) {
                set_state(body, sample);
                total.energy += body.kinetic_energy() + body.potential_energy(gravity);
                total.linear_momentum += body.mass.mass * body.state.velocity;
                total.angular_momentum += body.angular_momentum_world();
            }
            total
        })
        .collect();
    Ok(out)
}

/// Sets a body's state from a trajectory sample (world frame, the user's body axes).
pub fn set_state(body: &mut RigidBody, sample: &BodySample) {
    body.state.position = sample.position;
    body.set_orientation_user(sample.orientation);
    body.state.velocity = sample.velocity;
    body.set_omega_world(sample.angular_velocity);
}

/// Errors of a series of invariants against its first element.
#[derive(Debug, Clone, PartialEq)]
pub struct InvariantErrors {
    /// `(E − E₀) / |E₀|` per frame (signed, dimensionless), or `E − E₀` (J) when `E₀ = 0`.
    pub energy: Vec<f64>,
    /// Whether `energy` is absolute (J) because `E₀ = 0`.
    pub energy_is_absolute: bool,
    /// `|L − L₀| / |L₀|` per frame (dimensionless), or `|L − L₀|` (kg·m²/s) when `L₀ = 0`.
    pub angular_momentum: Vec<f64>,
    /// Whether `angular_momentum` is absolute (kg·m²/s) because `L₀ = 0`.
    pub angular_momentum_is_absolute: bool,
}

impl InvariantErrors {
    /// The errors of `series` against `series[0]` (empty series: empty errors).
    pub fn of(series: &[Invariants]) -> Self {
        let Some(first) = series.first() else {
            return Self {
                energy: Vec::new(),
                energy_is_absolute: false,
                angular_momentum: Vec::new(),
                angular_momentum_is_absolute: false,
            };
        };
        let (e0, l0) = (first.energy, first.angular_momentum);
        let e_scale = if e0 != 0.0 { e0.abs() } else { 1.0 };
        let l_scale = if l0 != DVec3::ZERO { l0.length() } else { 1.0 };
        Self {
            energy: series.iter().map(|s| (s.energy - e0) / e_scale).collect(),
            energy_is_absolute: e0 == 0.0,
            angular_momentum: series.iter().map(|s| (s.angular_momentum - l0).length() / l_scale).collect(),
            angular_momentum_is_absolute: l0 == DVec3::ZERO,
        }
    }
}

/// Angular velocity in the user's body axes, `ω_user = R_userᵀ ω_world` (rad/s).
#[inline]
pub fn omega_user(sample: &BodySample) -> DVec3 {
    sample.orientation.conjugate() * sample.angular_velocity
}

/// The box of uniform density with the same mass and principal moments as `mass`: half extents
/// along the principal axes (m) and the rotation of those axes in the user's body axes
/// (`user_from_body`). The replay draws a body without a shape as this box.
///
/// A solid box has `I1 = m (h2² + h3²) / 3` and its permutations, so `h1² = 3 (I2 + I3 − I1) / (2 m)`;
/// the triangle inequality the moments obey keeps it ≥ 0 (a flat body gets a thin box, never a
/// negative one).
pub fn inertia_equivalent_box(mass: &crate::MassProperties) -> (DVec3, crate::math::DQuat) {
    let i = mass.inertia_body;
    let half = |a: f64, b: f64, c: f64| (3.0 * (b + c - a) / (2.0 * mass.mass)).max(0.0).sqrt();
    let h = DVec3::new(half(i.x, i.y, i.z), half(i.y, i.z, i.x), half(i.z, i.x, i.y));
    // a perfectly flat body would vanish: give it a sliver of the largest extent
    let h = h.max(DVec3::splat(1e-3 * h.max_element().max(1e-9)));
    (h, mass.user_from_body)
}
