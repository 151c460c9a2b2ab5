//! The invariant monitor: how well a run keeps energy and momentum, and how often bodies flip.
//!
//! **Errors.** At every observed sample the monitor measures
//! `|E − E₀| / |E₀|` (energy, kinetic plus gravitational potential) and `|L − L₀| / |L₀|` (angular
//! momentum about the world origin, Euclidean norm of the vector difference) and keeps the largest.
//! When the initial value is exactly zero (a body at rest at the origin, a world with no spin) a
//! relative error has no meaning; the error is then the **absolute** error `|E − E₀|` (J) or
//! `|L − L₀|` (kg·m²/s), and [`Monitor::energy_error_is_absolute`] /
//! [`Monitor::angular_momentum_error_is_absolute`] say so. See [`relative_error`].
//!
//! **Flips.** A body whose three principal moments are distinct has an intermediate axis, about which
//! rotation is unstable (the Dzhanibekov or tennis-racket effect): the body turns over again and
//! again, and each turn reverses the sign of the body-frame angular velocity `ω_body` about that axis
//! (and of the angular momentum `L_body = I_body ω_body` along it). A plain sign change is not enough:
//! a body spinning stably about its largest or smallest axis wobbles, and the small components of
//! `ω_body` change sign at every wobble. So a flip is counted with hysteresis, on the direction cosine
//! `c = L_body[axis] / |L_body|` of the intermediate axis with the angular momentum: one flip each time
//! `c` goes from `≥ +½` to `≤ −½` or back, that is, each time the intermediate axis turns from within
//! 60° of `L` to within 60° of `−L`. The samples must be closer together than the flips for the count
//! to be complete. A body with two equal moments (relative difference ≤ [`DISTINCT_MOMENTS_TOLERANCE`]
//! of the largest) has no intermediate axis and no flip count. Flips are counted until the body's
//! first contact ([`World::first_contact_time`]): contacts change the angular momentum, and a body
//! bouncing on the floor or lying on it (where `L` is round-off) would count flips that are none.
//!
//! **Energy growth.** A passive system cannot gain energy: without applied forces or torques (only
//! gravity and damping on the free bodies; no constant joint force, no PD gain and no damping
//! towards a moving target on the robots) and without contact (no body has touched anything yet,
//! and no collision or resting contact took or gave energy), `E` is constant or falls. A rise
//! between two samples is the integrator's doing: explicit Euler's `½ h² αᵀ I α` per step, or a
//! step too large for a stiff or fast motion. The first rise of more than [`ENERGY_RISE`] of the
//! largest kinetic energy seen at the samples (the energy in motion; the potential's zero is
//! arbitrary, so `E` itself is no scale) is recorded ([`Monitor::instability`]), once: the CLI
//! warns "possible instability". A system with no kinetic energy yet is never flagged (its rises
//! are round-off). Once a load or a contact may do work the check is off for the rest of the run.
use crate::analytic::AsymmetricTop;
use crate::math::DVec3;
use crate::world::World;

/// Two principal moments closer than this fraction of the largest are taken as equal.
pub const DISTINCT_MOMENTS_TOLERANCE: f64 = 1e-9;

/// The direction cosine of the intermediate axis with `L` beyond which the axis counts as aligned
/// with `L` (or `−L`): `cos 60°`.
pub const FLIP_ALIGNMENT: f64 = 0.5;

/// The rise of the energy of a passive system between two samples, as a fraction of the largest
/// kinetic energy seen, above which the run is flagged as possibly unstable.
pub const ENERGY_RISE: f64 = 0.01;

/// The first rise of a passive system's energy beyond [`ENERGY_RISE`] (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EnergyRise {
    /// The time of the sample that saw it (s).
    pub time: f64,
    /// The rise since the previous sample (J).
    pub rise: f64,
    /// The rise as a fraction of the largest kinetic energy seen at the samples until then.
    pub relative: f64,
}

impl std::fmt::Display for EnergyRise {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "possible instability at t = {} s: energy rose by {:.3e} J ({:.3} % of the kinetic energy) in one \
             sample interval of a passive system; reduce dt or use a structure-preserving integrator",
            self.time,
            self.rise,
            100.0 * self.relative
        )
    }
}

/// Whether `world` is passive now, as far as its loads, controls and contacts tell (module docs).
fn passive(world: &World) -> bool {
    let loads_passive = world.free_bodies().all(|b| {
        let l = &b.loads;
        l.force_world == DVec3::ZERO
            && l.force_body == DVec3::ZERO
            && l.torque_world == DVec3::ZERO
            && l.torque_body == DVec3::ZERO
            && l.point_forces.is_empty()
    });
    let robots_passive = world.robots.iter().all(|r| {
        let c = &r.control;
        let still_target = c.v_target.iter().all(|&v| v == 0.0) || c.kd.iter().all(|&k| k == 0.0);
        c.tau.iter().all(|&t| t == 0.0) && c.kp.iter().all(|&k| k == 0.0) && still_target
    });
    let energy = world.contact_energy();
    let untouched = world.contact_collisions() == 0
        && energy.collisions == 0.0
        && energy.friction == 0.0
        && (0..world.bodies.len()).all(|i| world.first_contact_time(i).is_none());
    loads_passive && robots_passive && untouched
}

/// Kinetic energy of the free bodies and the robots (J).
fn kinetic_energy(world: &World) -> f64 {
    world.free_bodies().map(|b| b.kinetic_energy()).sum::<f64>()
        + world.robots.iter().map(|r| r.kinetic_energy()).sum::<f64>()
}

/// The quantities a free rigid-body system conserves, at one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Invariants {
    /// Kinetic plus gravitational potential energy of the free bodies (J).
    pub energy: f64,
    /// Total linear momentum, world frame (kg·m/s).
    pub linear_momentum: DVec3,
    /// Total angular momentum about the world origin, world frame (kg·m²/s).
    pub angular_momentum: DVec3,
}

impl Invariants {
    /// The invariants of `world` now.
    pub fn of(world: &World) -> Self {
        Self {
            energy: world.energy(),
            linear_momentum: world.linear_momentum(),
            angular_momentum: world.angular_momentum(),
        }
    }
}

/// The error of a quantity against its initial value: `error / initial` when `initial > 0`, and the
/// absolute `error` itself when `initial` is exactly zero (both are norms, so never negative).
#[inline]
pub fn relative_error(error: f64, initial: f64) -> f64 {
    if initial > 0.0 {
        error / initial
    } else {
        error
    }
}

/// Counts the flips of one body about its intermediate principal axis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FlipCounter {
    /// Index of the body in `World::bodies`.
    pub body: usize,
    /// The intermediate principal axis: 0, 1 or 2 (x, y or z of the body's principal frame).
    pub axis: usize,
    /// Flips seen so far.
    pub count: u64,
    /// Time of the first and of the latest flip (s), at the sample that saw it.
    pub first_flip_time: f64,
    pub last_flip_time: f64,
    /// The exact time between flips `2K(k)/λ` of the torque-free body from its initial state (s), when
    /// the body has no loads besides gravity (which exerts no torque about the centre of mass).
    pub exact_interval: Option<f64>,
    /// The start of the step of the body's first contact (s): flips are counted until then, since a
    /// contact changes the angular momentum (a box bouncing or at rest would count spurious flips).
    pub counted_until: Option<f64>,
    /// The last alignment seen: +1 (with `L`), −1 (with `−L`), or 0 before the first.
    last_side: f64,
}

impl FlipCounter {
    /// The index of the intermediate moment, when the three moments are distinct.
    pub fn intermediate_axis(moments: DVec3) -> Option<usize> {
        let m = moments.to_array();
        let mut order = [0, 1, 2];
        order.sort_by(|&a, &b| m[a].total_cmp(&m[b]));
        let [low, mid, high] = order.map(|i| m[i]);
        let tolerance = DISTINCT_MOMENTS_TOLERANCE * high.abs();
        (mid - low > tolerance && high - mid > tolerance).then_some(order[1])
    }

    /// A counter for body `body` about `axis`, with no alignment seen yet.
    pub fn new(body: usize, axis: usize) -> Self {
        Self {
            body,
            axis,
            count: 0,
            first_flip_time: 0.0,
            last_flip_time: 0.0,
            exact_interval: None,
            counted_until: None,
            last_side: 0.0,
        }
    }

    /// The mean time between the flips seen (s): `(t_last − t_first)/(count − 1)`, from two flips on.
    /// Its resolution is the sampling interval divided by `count − 1`.
    pub fn mean_interval(&self) -> Option<f64> {
        (self.count >= 2).then(|| (self.last_flip_time - self.first_flip_time) / (self.count - 1) as f64)
    }

    /// Takes one more sample at time `t` (s) of the body-frame angular momentum `L_body = I_body ω_body`
    /// (kg·m²/s).
    #[inline]
    pub fn observe(&mut self, l_body: DVec3, t: f64) {
        let cosine = l_body[self.axis] / l_body.length();
        let side = if cosine >= FLIP_ALIGNMENT {
            1.0
        } else if cosine <= -FLIP_ALIGNMENT {
            -1.0
        } else {
            return; // in between, not spinning (0/0), or not finite: no alignment
        };
        if self.last_side != 0.0 && side != self.last_side {
            self.count += 1;
            if self.count == 1 {
                self.first_flip_time = t;
            }
            self.last_flip_time = t;
        }
        self.last_side = side;
    }
}

/// Watches a run at its samples: initial and latest invariants, largest errors, flips.
#[derive(Debug, Clone)]
pub struct Monitor {
    initial: Invariants,
    last: Invariants,
    last_time: f64,
    max_energy_error: f64,
    max_angular_momentum_error: f64,
    flips: Vec<FlipCounter>,
    samples: u64,
    /// Whether the energy-growth check is on (the system has been passive so far).
    watching_energy: bool,
    /// The largest kinetic energy seen at the samples (J).
    max_kinetic: f64,
    /// The first rise of the energy beyond [`ENERGY_RISE`], if any.
    instability: Option<EnergyRise>,
}

impl Monitor {
    /// Records the initial invariants of `world` and observes it as the first sample.
    pub fn new(world: &World) -> Self {
        let initial = Invariants::of(world);
        let flips = world
            .bodies
            .iter()
            .enumerate()
            .filter(|(_, b)| !b.fixed)
            .filter_map(|(i, b)| {
                FlipCounter::intermediate_axis(b.mass.inertia_body).map(|axis| {
                    let mut counter = FlipCounter::new(i, axis);
                    if b.loads.is_empty() {
                        counter.exact_interval = AsymmetricTop::new(b.mass.inertia_body, b.state.omega_body)
                            .ok()
                            .map(|top| top.flip_interval())
                            .filter(|t| t.is_finite());
                    }
                    counter
                })
            })
            .collect();
        let mut monitor = Self {
            initial,
            last: initial,
            last_time: world.time(),
            max_energy_error: 0.0,
            max_angular_momentum_error: 0.0,
            flips,
            samples: 0,
            watching_energy: passive(world),
            max_kinetic: 0.0,
            instability: None,
        };
        monitor.observe(world);
        monitor
    }

    /// Observes one sample: updates the latest invariants, the largest errors and the flip counts.
    pub fn observe(&mut self, world: &World) {
        let now = Invariants::of(world);
        let energy_error = relative_error((now.energy - self.initial.energy).abs(), self.initial.energy.abs());
        let l_error = relative_error(
            (now.angular_momentum - self.initial.angular_momentum).length(),
            self.initial.angular_momentum.length(),
        );
        // `f64::max` would skip a NaN: keep it visible instead, so that it is caught when written
        if energy_error.is_nan() || energy_error > self.max_energy_error {
            self.max_energy_error = energy_error;
        }
        if l_error.is_nan() || l_error > self.max_angular_momentum_error {
            self.max_angular_momentum_error = l_error;
        }
        for counter in &mut self.flips {
            if counter.counted_until.is_some() {
                continue;
            }
            counter.counted_until = world.first_contact_time(counter.body);
            if counter.counted_until.is_none() {
                counter.observe(world.bodies[counter.body].angular_momentum_body(), world.time());
            }
        }
        self.watch_energy(world, now.energy);
        self.last = now;
        self.last_time = world.time();
        self.samples += 1;
    }

    /// The energy-growth check of one sample of energy `energy` (J) (module docs).
    fn watch_energy(&mut self, world: &World, energy: f64) {
        if !self.watching_energy {
            return;
        }
        if !passive(world) {
            self.watching_energy = false;
            return;
        }
        let rise = energy - self.last.energy;
        if self.samples > 0 && self.instability.is_none() && self.max_kinetic > 0.0 {
            let relative = rise / self.max_kinetic;
            if relative > ENERGY_RISE {
                self.instability = Some(EnergyRise { time: world.time(), rise, relative });
            }
        }
        self.max_kinetic = self.max_kinetic.max(kinetic_energy(world));
    }

    /// The first rise of a passive system's energy by more than [`ENERGY_RISE`] of its largest
    /// kinetic energy between two samples, if any (module docs).
    pub fn instability(&self) -> Option<EnergyRise> {
        self.instability
    }

    /// The invariants at the first sample.
    pub fn initial(&self) -> Invariants {
        self.initial
    }

    /// The invariants at the latest sample.
    pub fn last(&self) -> Invariants {
        self.last
    }

    /// The time of the latest sample (s).
    pub fn last_time(&self) -> f64 {
        self.last_time
    }

    /// Samples observed, the first included.
    pub fn samples(&self) -> u64 {
        self.samples
    }

    /// Largest energy error over the samples: relative, or absolute (J) when `E₀ = 0`.
    pub fn max_energy_error(&self) -> f64 {
        self.max_energy_error
    }

    /// Largest angular-momentum error over the samples: relative, or absolute (kg·m²/s) when `L₀ = 0`.
    pub fn max_angular_momentum_error(&self) -> f64 {
        self.max_angular_momentum_error
    }

    /// Whether the energy error is absolute because the initial energy is exactly zero.
    pub fn energy_error_is_absolute(&self) -> bool {
        self.initial.energy == 0.0
    }

    /// Whether the angular-momentum error is absolute because the initial angular momentum is zero.
    pub fn angular_momentum_error_is_absolute(&self) -> bool {
        self.initial.angular_momentum == DVec3::ZERO
    }

    /// The flip counters, one per free body with distinct principal moments, in body order.
    pub fn flips(&self) -> &[FlipCounter] {
        &self.flips
    }
}
