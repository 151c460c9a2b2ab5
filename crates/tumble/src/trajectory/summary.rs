//! The run summary, serialised as the summary JSON of the contract:
//!
//! ```text
//! {"steps", "simulated_time", "wall_time_s", "bodies", "integrator", "dt",
//!  "energy": {"initial", "final", "max_relative_error"},
//!  "linear_momentum": {"initial": [..], "final": [..]},
//!  "angular_momentum": {"initial": [..], "final": [..], "max_relative_error"}}
//! ```
//!
//! Fields added beyond the contract (never renamed): `energy.error_is_absolute` and
//! `angular_momentum.error_is_absolute` (the initial value was zero, so the error is absolute: see
//! [`Monitor`](super::Monitor)), `stopped`, `free_bodies`, `samples`, `sample_every`, `flips`, `scene`,
//! `robots` (only when the scene has robots), `flips[].counted_until` (the body's first contact, s).
//! `contact` (`collisions`, `energy_lost_in_collisions`, `energy_lost_in_friction`, J;
//! `asleep_at_end`, the free bodies asleep at the end). `instability` (only when the monitor saw a
//! passive system's energy rise by more than 1 % of its kinetic energy between two samples:
//! `time` s, `energy_rise` J, `relative`; see [`Monitor::instability`](super::Monitor::instability)).
//! No field is ever null and no number is ever NaN or infinite: [`Summary::to_json`] refuses them.

use super::{Monitor, TrajectoryError};
use crate::world::World;
use serde::{Deserialize, Serialize};

/// Why a run stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StopReason {
    /// Every step was taken.
    Completed,
    /// A body's state became non-finite or absurd; the summary describes the last finite state.
    Diverged,
    /// The run was interrupted (SIGINT/SIGTERM) after a whole step.
    Interrupted,
    /// The broad phase found more candidate contact pairs than the budget (`[world] max_pairs`);
    /// the summary describes the state before that step.
    ContactBudget,
    /// The run reached its wall-time limit (`--max-wall-time`) and stopped after a whole step.
    WallTimeLimit,
}

/// Energy: kinetic plus gravitational potential, of the free bodies (J).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct EnergySummary {
    pub initial: f64,
    #[serde(rename = "final")]
    pub final_: f64,
    /// Largest `|E − E₀| / |E₀|` over the samples (or `|E − E₀|` in J when `E₀ = 0`).
    pub max_relative_error: f64,
    /// `E₀ = 0`: `max_relative_error` is the absolute error (J).
    pub error_is_absolute: bool,
}

/// Total linear momentum of the free bodies, world frame (kg·m/s).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LinearMomentumSummary {
    pub initial: [f64; 3],
    #[serde(rename = "final")]
    pub final_: [f64; 3],
}

/// Total angular momentum of the free bodies about the world origin, world frame (kg·m²/s).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AngularMomentumSummary {
    pub initial: [f64; 3],
    #[serde(rename = "final")]
    pub final_: [f64; 3],
    /// Largest `|L − L₀| / |L₀|` over the samples (or `|L − L₀|` in kg·m²/s when `L₀ = 0`).
    pub max_relative_error: f64,
    /// `L₀ = 0`: `max_relative_error` is the absolute error (kg·m²/s).
    pub error_is_absolute: bool,
}

/// Flips of one body about its intermediate principal axis (see [`Monitor`](super::Monitor)).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FlipSummary {
    /// The body's name.
    pub body: String,
    /// Sign changes of `ω_body` about the intermediate axis between samples.
    pub flips: u64,
    /// Mean time between the flips seen (s), from two flips on.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mean_interval: Option<f64>,
    /// The exact time between flips of the torque-free body, `2K(k)/λ` (s), when it has no loads.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub exact_interval: Option<f64>,
    /// The body's first contact (s), when it had one: flips are counted until then.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub counted_until: Option<f64>,
}

/// What a run did.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    /// Steps taken.
    pub steps: u64,
    /// Simulated time reached (s).
    pub simulated_time: f64,
    /// Wall time of the simulation loop, stepping and writing (s).
    pub wall_time_s: f64,
    /// Number of bodies in the scene (fixed ones included).
    pub bodies: usize,
    /// The integrator's name.
    pub integrator: String,
    /// The step (s).
    pub dt: f64,
    pub energy: EnergySummary,
    pub linear_momentum: LinearMomentumSummary,
    pub angular_momentum: AngularMomentumSummary,
    /// Why the run stopped.
    pub stopped: StopReason,
    /// Number of bodies that move.
    pub free_bodies: usize,
    /// Samples written to the trajectory (the initial one included).
    pub samples: u64,
    /// Every `sample_every`-th step was written (and the last one).
    pub sample_every: u64,
    /// Flip counts of the free bodies with three distinct principal moments.
    pub flips: Vec<FlipSummary>,
    /// Where the scene came from.
    pub scene: String,
    /// The robots (absent when there are none): their energy is in `energy`, the momentum of the
    /// floating-base ones in the momenta.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub robots: Vec<RobotSummary>,
    /// What contacts did: collisions resolved and kinetic energy they dissipated.
    pub contact: ContactSummary,
    /// The first rise of a passive system's energy beyond 1 % of its kinetic energy between two
    /// samples (a possible instability); absent when there was none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub instability: Option<InstabilitySummary>,
    /// Where the time of a step went (`tumble run --profile`); absent unless profiled.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub profile: Option<ProfileSummary>,
}

/// The wall time of a step per stage (µs per step, averaged over the run) and the contact counts
/// per step ([`crate::profile::Profile`]). The `link_*` and `robot_*` stages are parts of the stage
/// before them in this list (`link_detect` of `narrow_phase`, `link_rows` of `impacts`,
/// `robot_dynamics` and `robot_bookkeeping` of `integration`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[allow(missing_docs)]
pub struct ProfileSummary {
    pub step_us: f64,
    pub broad_phase_us: f64,
    pub narrow_phase_us: f64,
    pub link_detect_us: f64,
    pub impacts_us: f64,
    pub link_rows_us: f64,
    pub resting_us: f64,
    pub integration_us: f64,
    pub robot_dynamics_us: f64,
    pub robot_bookkeeping_us: f64,
    pub pairs: f64,
    pub contacts: f64,
    pub link_contacts: f64,
}

impl From<crate::profile::Profile> for ProfileSummary {
    fn from(p: crate::profile::Profile) -> Self {
        let s = p.per_step();
        let us = 1e6;
        Self {
            step_us: s.step * us,
            broad_phase_us: s.broad_phase * us,
            narrow_phase_us: s.narrow_phase * us,
            link_detect_us: s.link_detect * us,
            impacts_us: s.impacts * us,
            link_rows_us: s.link_rows * us,
            resting_us: s.resting * us,
            integration_us: s.integration * us,
            robot_dynamics_us: s.robot_dynamics * us,
            robot_bookkeeping_us: s.robot_bookkeeping * us,
            pairs: s.pairs,
            contacts: s.contacts,
            link_contacts: s.link_contacts,
        }
    }
}

/// A possible instability: a passive system's energy rose between two samples
/// ([`Monitor::instability`](super::Monitor::instability)).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct InstabilitySummary {
    /// The time of the sample that saw the rise (s).
    pub time: f64,
    /// The rise since the previous sample (J).
    pub energy_rise: f64,
    /// The rise as a fraction of the largest kinetic energy seen until then.
    pub relative: f64,
}

/// A robot of the run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RobotSummary {
    pub name: String,
    /// `"fixed"` or `"floating"`.
    pub base: String,
    /// Configuration and velocity coordinates.
    pub nq: usize,
    pub nv: usize,
    /// Trajectory rows per sample (`robot/link`, the links that move).
    pub links: usize,
    /// Final energy, kinetic plus gravitational potential (J).
    pub energy: f64,
    /// Joints whose commanded force was clamped to the URDF `effort`, and in how many steps.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub effort_clamped: Vec<JointStepsSummary>,
    /// Joints whose position limit pushed, and in how many steps.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub joint_limits_active: Vec<JointStepsSummary>,
    /// Fixed tendons (MJCF) whose length limit pushed, and in how many steps.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub tendon_limits_active: Vec<TendonStepsSummary>,
}

/// A fixed tendon and a number of steps.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct TendonStepsSummary {
    pub tendon: String,
    pub steps: u64,
}

/// A joint and a number of steps.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct JointStepsSummary {
    pub joint: String,
    pub steps: u64,
}

fn joint_steps(list: Vec<crate::world::JointSteps>) -> Vec<JointStepsSummary> {
    list.into_iter().map(|c| JointStepsSummary { joint: c.joint, steps: c.steps }).collect()
}

/// Contacts over the run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ContactSummary {
    /// Collisions resolved by integrating through the impact.
    pub collisions: u64,
    /// Kinetic energy dissipated in collisions (J).
    pub energy_lost_in_collisions: f64,
    /// Kinetic energy dissipated by friction and inelastic resting contact (J).
    pub energy_lost_in_friction: f64,
    /// Free bodies asleep at the end (`[world] sleep`: islands at rest).
    #[serde(default)]
    pub asleep_at_end: usize,
}

impl Summary {
    /// The summary of a run of `world` watched by `monitor`. The final values are those of the
    /// monitor's latest sample, which the caller makes the world's final (finite) state.
    pub fn new(world: &World, monitor: &Monitor, wall_time_s: f64, stopped: StopReason, scene: &str) -> Self {
        let initial = monitor.initial();
        let last = monitor.last();
        Self {
            steps: world.steps(),
            simulated_time: world.time(),
            wall_time_s,
            bodies: world.bodies.len(),
            integrator: world.config.integrator.name().to_string(),
            dt: world.config.dt,
            energy: EnergySummary {
                initial: initial.energy,
                final_: last.energy,
                max_relative_error: monitor.max_energy_error(),
                error_is_absolute: monitor.energy_error_is_absolute(),
            },
            linear_momentum: LinearMomentumSummary {
                initial: initial.linear_momentum.to_array(),
                final_: last.linear_momentum.to_array(),
            },
            angular_momentum: AngularMomentumSummary {
                initial: initial.angular_momentum.to_array(),
                final_: last.angular_momentum.to_array(),
                max_relative_error: monitor.max_angular_momentum_error(),
                error_is_absolute: monitor.angular_momentum_error_is_absolute(),
            },
            stopped,
            free_bodies: world.free_bodies().count(),
            samples: monitor.samples(),
            sample_every: world.config.sample_every,
            flips: monitor
                .flips()
                .iter()
                .map(|c| FlipSummary {
                    body: world.bodies[c.body].name.clone(),
                    flips: c.count,
                    mean_interval: c.mean_interval(),
                    // a body that never flipped only wobbles: its half-period is no flip interval
                    exact_interval: c.exact_interval.filter(|_| c.count > 0),
                    counted_until: c.counted_until,
                })
                .collect(),
            scene: scene.to_string(),
            robots: world
                .robots
                .iter()
                .map(|r| RobotSummary {
                    name: r.name.clone(),
                    base: if r.floating { "floating" } else { "fixed" }.to_string(),
                    nq: r.model.nq(),
                    nv: r.model.nv(),
                    links: r.link_names().len(),
                    energy: r.energy(),
                    effort_clamped: joint_steps(r.effort_clamps()),
                    joint_limits_active: joint_steps(r.limit_activity()),
                    tendon_limits_active: r
                        .tendon_limit_activity()
                        .into_iter()
                        .filter(|&(_, steps)| steps > 0)
                        .map(|(tendon, steps)| TendonStepsSummary { tendon: tendon.to_string(), steps })
                        .collect(),
                })
                .collect(),
            contact: ContactSummary {
                collisions: world.contact_collisions(),
                energy_lost_in_collisions: world.contact_energy().collisions,
                energy_lost_in_friction: world.contact_energy().friction,
                asleep_at_end: world.contacts().sleep().count(),
            },
            instability: monitor.instability().map(|r| InstabilitySummary {
                time: r.time,
                energy_rise: r.rise,
                relative: r.relative,
            }),
            profile: world.profile().map(ProfileSummary::from),
        }
    }

    /// The summary JSON (pretty-printed, ending with a newline). Fails, naming the field, when a
    /// number is not finite (serde would write it as `null`).
    pub fn to_json(&self) -> Result<String, TrajectoryError> {
        let value = serde_json::to_value(self).expect("a summary always serialises");
        if let Some(field) = first_null(&value, String::new()) {
            return Err(TrajectoryError::NonFiniteSummary { field });
        }
        // serialised from the struct, not from `value`, to keep the fields in their documented order
        let mut text = serde_json::to_string_pretty(self).expect("a summary always serialises");
        text.push('\n');
        Ok(text)
    }
}

/// The path of the first `null` in `value` (a summary has no nullable field: a `null` is a
/// non-finite number).
fn first_null(value: &serde_json::Value, path: String) -> Option<String> {
    use serde_json::Value;
    match value {
        Value::Null => Some(path),
        Value::Array(items) => items.iter().enumerate().find_map(|(i, v)| first_null(v, format!("{path}[{i}]"))),
        Value::Object(fields) => fields.iter().find_map(|(k, v)| {
            let path = if path.is_empty() { k.clone() } else { format!("{path}.{k}") };
            first_null(v, path)
        }),
        _ => None,
    }
}
