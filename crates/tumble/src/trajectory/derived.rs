//! Quantities derived from a trajectory read back, for plots and the replay: the invariants of each
//! frame (computed with the scene's mass properties and gravity), their errors against the first
//! frame, and the body-frame angular velocity.
//!
//! - Energy `E = Σ ½ m |v|² + ½ ω_bodyᵀ I_body ω_body − m g · x` over the moving bodies, plus the
//!   energy of the robots' moving links ([`link_invariants`]) (J): the run summary's energy.
//! - Angular momentum about the world origin `L = Σ x × m v + R I_body ω_body`, world frame
//!   (kg·m²/s), plus that of the links of floating-base robots (a fixed base is held by the world, so
//!   the summary leaves fixed-base robots out of the momenta, and so does this).
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
use crate::math::{DMat3, DVec3};
use crate::multibody::{Motion, RigidInertia};
use crate::world::World;
use crate::RigidBody;

/// What a trajectory row is: a free body of the scene (a scratch copy, its state replaced frame by
/// frame) or a moving link of a robot (its own inertia in the link frame; whether its momentum
/// counts, that is, whether its robot has a floating base).
enum Row {
    Body(Box<RigidBody>),
    Link { inertia: RigidInertia, momentum: bool },
}

/// The invariants of every frame of `trajectory`, with the mass properties and gravity of `world`.
///
/// The trajectory's bodies must be exactly the world's moving bodies and robot links
/// ([`Trajectory::check_bodies`]; `trajectory_name` and `scene_name` name the files in the error).
pub fn invariants(
    trajectory: &Trajectory,
    world: &World,
    trajectory_name: &str,
    scene_name: &str,
) -> Result<Vec<Invariants>, ReadError> {
    trajectory.check_bodies(world, trajectory_name, scene_name)?;
    let mut rows: Vec<Row> = trajectory.bodies.iter().filter_map(|name| row(world, name)).collect();
    let gravity = world.config.gravity;
    let out = trajectory
        .frames
        .iter()
        .map(|frame| {
            let mut total = Invariants { energy: 0.0, linear_momentum: DVec3::ZERO, angular_momentum: DVec3::ZERO };
            for (row, sample) in rows.iter_mut().zip(&frame.states) {
                match row {
                    Row::Body(body) => {
                        set_state(body, sample);
                        total.energy += body.kinetic_energy() + body.potential_energy(gravity);
                        total.linear_momentum += body.mass.mass * body.state.velocity;
                        total.angular_momentum += body.angular_momentum_world();
                    }
                    Row::Link { inertia, momentum } => {
                        let link = link_invariants(inertia, sample, gravity);
                        total.energy += link.energy;
                        if *momentum {
                            total.linear_momentum += link.linear_momentum;
                            total.angular_momentum += link.angular_momentum;
                        }
                    }
                }
            }
            total
        })
        .collect();
    Ok(out)
}

/// The row of the trajectory body `name` in `world` (after [`Trajectory::check_bodies`]).
fn row(world: &World, name: &str) -> Option<Row> {
    if let Some(body) = world.free_bodies().find(|b| b.name == name) {
        return Some(Row::Body(Box::new(body.clone())));
    }
    world.robots.iter().find_map(|robot| {
        let k = robot.link_names().iter().position(|n| n == name)?;
        Some(Row::Link { inertia: robot.link_frame(k).inertia, momentum: robot.floating })
    })
}

/// The energy and momentum of one robot link from its trajectory sample (`position` the link
/// frame's origin, `orientation` `world_from_link`, `velocity` that of the origin, all world frame)
/// and the link's own inertia `inertia` in the link frame, under `gravity` (m/s²).
///
/// With `R = world_from_link`, `p` the origin and `c` the centre of mass in the link frame:
/// - `v_link = [Rᵀ ω; Rᵀ v_o]` (the link's spatial velocity in its own frame);
/// - `T = ½ v_linkᵀ I v_link`, `V = −m g · (p + R c)` (J; zero potential at the world origin);
/// - `[L; P] = link_X_worldᵀ (I v_link)`, the momentum about the world origin, world frame.
///
/// These are the sums [`Robot::energy`](crate::world::Robot::energy) makes over the tree's bodies,
/// link by link (a body's inertia is the sum of its links').
pub fn link_invariants(inertia: &RigidInertia, sample: &BodySample, gravity: DVec3) -> Invariants {
    let world_from_link = DMat3::from_quat(sample.orientation);
    let v_link = link_velocity(&world_from_link, sample);
    // h = I v_link (link frame), then to the world: [R n + p × R f; R f]
    let h_link = inertia.mul_motion(v_link);
    let linear_momentum = world_from_link * h_link.lin;
    let (kinetic, potential) = link_energy(inertia, sample, gravity);
    Invariants {
        energy: kinetic + potential,
        linear_momentum,
        angular_momentum: world_from_link * h_link.ang + sample.position.cross(linear_momentum),
    }
}

/// The kinetic and the gravitational potential energy of one robot link (J), as in
/// [`link_invariants`]: `T = ½ v_linkᵀ I v_link`, `V = −m g · (p + R c)`.
pub fn link_energy(inertia: &RigidInertia, sample: &BodySample, gravity: DVec3) -> (f64, f64) {
    let world_from_link = DMat3::from_quat(sample.orientation);
    let kinetic = inertia.kinetic_energy(link_velocity(&world_from_link, sample));
    let com_world = sample.position + world_from_link * inertia.com();
    (kinetic, -inertia.mass * gravity.dot(com_world))
}

/// `v_link = [Rᵀ ω; Rᵀ v_o]`: a link's spatial velocity in its own frame, from its row.
fn link_velocity(world_from_link: &DMat3, sample: &BodySample) -> Motion {
    let link_from_world = world_from_link.transpose();
    Motion { ang: link_from_world * sample.angular_velocity, lin: link_from_world * sample.velocity }
}

/// The kinetic and potential energy (J) of each robot of `world`, frame by frame, from its links'
/// rows ([`link_energy`]): `out[r][f]` is `(T, V)` of robot `r` at frame `f`. The trajectory's bodies
/// must be those of `world` ([`Trajectory::check_bodies`]); a link without a row counts nothing.
pub fn robot_energies(trajectory: &Trajectory, world: &World) -> Vec<Vec<(f64, f64)>> {
    let gravity = world.config.gravity;
    world
        .robots
        .iter()
        .map(|robot| {
            let rows: Vec<(usize, RigidInertia)> = (0..robot.link_names().len())
                .filter_map(|k| {
                    let row = trajectory.bodies.iter().position(|n| n == &robot.link_names()[k])?;
                    Some((row, robot.link_frame(k).inertia))
                })
                .collect();
            trajectory
                .frames
                .iter()
                .map(|frame| {
                    rows.iter().fold((0.0, 0.0), |(t, v), (row, inertia)| {
                        let (dt, dv) = link_energy(inertia, &frame.states[*row], gravity);
                        (t + dt, v + dv)
                    })
                })
                .collect()
        })
        .collect()
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
