//! The world: bodies, configuration and the step.

use crate::body::{BodyState, RigidBody};
use crate::collision::Overlap;
use crate::contact::{ContactEnergy, ContactSettings, ContactStage};
use crate::integrate::{advance_body, BodyRhs, Integrator, Tolerances};
use crate::math::DVec3;

mod batched;
mod bodies;
mod hash;
mod robots;
mod state;
mod threads;
pub use crate::math::StateHasher;
pub(crate) use crate::profile::Clock;
pub use crate::profile::{PerStep, Profile};
pub use bodies::Bodies;
pub use robots::{robot_method, ActuatorDrive, CtrlError, DriveTarget, JointSteps, LinkState, Robot};
pub use state::{StateError, BODY_STATE_LEN, STATE_QUAT_TOLERANCE};

/// Largest position (m), velocity (m/s) or angular velocity (rad/s) magnitude taken as a sane state;
/// beyond it the simulation is declared diverged (MuJoCo's `mjMAXVAL` bound).
pub const MAX_STATE_MAGNITUDE: f64 = 1e10;

/// World settings, the `[world]` table of a scene file. Units are SI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WorldConfig {
    /// Gravitational acceleration, world frame (m/s²). Default `[0, 0, −9.81]`.
    pub gravity: DVec3,
    /// Time step (s); for `dopri5` the largest internal step and the output step. Default `1e-3`.
    pub dt: f64,
    /// Simulated time (s). Default `10`.
    pub duration: f64,
    /// The integrator. Default `rk4`.
    pub integrator: Integrator,
    /// Tolerances of `dopri5`. Default `rtol = 1e-9`, `atol = 1e-12`.
    pub tolerances: Tolerances,
    /// Write every k-th step to the trajectory. Default `1`.
    pub sample_every: u64,
    /// Contact settings (see [`ContactSettings`]).
    pub contact: ContactSettings,
    /// Threads of the collision detection: 0 (the default) for one per core, 1 for none but the
    /// caller's (no thread pool at all). The results are the same bit for bit for any number.
    pub threads: usize,
}

impl Default for WorldConfig {
    fn default() -> Self {
        Self {
            gravity: DVec3::new(0.0, 0.0, -9.81),
            dt: 1e-3,
            duration: 10.0,
            integrator: Integrator::Rk4,
            tolerances: Tolerances::default(),
            sample_every: 1,
            contact: ContactSettings::default(),
            threads: 0,
        }
    }
}

/// A `[world]` setting out of range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{field}: {problem} (got {value})")]
pub struct ConfigError {
    /// The setting, e.g. `dt`.
    pub field: &'static str,
    /// What is wrong with it.
    pub problem: String,
    /// The value given, as text.
    pub value: String,
}

/// Smallest accepted time step (s).
pub const MIN_DT: f64 = 1e-9;
/// Largest accepted number of steps in one run.
pub const MAX_STEPS: f64 = 1e9;
/// Largest accepted number of threads.
pub const MAX_THREADS: usize = 1024;

impl WorldConfig {
    /// Checks every setting: finite gravity with `|g| ≤ 1e6`, `1e-9 ≤ dt`, `duration ≥ 0`,
    /// `duration/dt ≤ 1e9` steps, `0 < rtol < 1`, `atol > 0`, `sample_every ≥ 1`.
    pub fn validate(&self) -> Result<(), ConfigError> {
        let bad = |field, problem: &str, value: String| Err(ConfigError { field, problem: problem.to_string(), value });
        if !self.gravity.is_finite() || self.gravity.length() > 1e6 {
            return bad("gravity", "must be finite with |g| ≤ 1e6 m/s²", format!("{:?}", self.gravity.to_array()));
        }
        if !self.dt.is_finite() || self.dt <= 0.0 {
            return bad("dt", "must be finite and > 0", self.dt.to_string());
        }
        if self.dt < MIN_DT {
            return bad("dt", "must be at least 1e-9 s", self.dt.to_string());
        }
        if !self.duration.is_finite() || self.duration < 0.0 {
            return bad("duration", "must be finite and ≥ 0", self.duration.to_string());
        }
        if self.duration / self.dt > MAX_STEPS {
            let problem = format!("duration/dt = {:e} steps exceeds the cap of 1e9 steps", self.duration / self.dt);
            return bad("duration", &problem, self.duration.to_string());
        }
        let t = self.tolerances;
        if !(t.rtol.is_finite() && t.rtol > 0.0 && t.rtol < 1.0) {
            return bad("rtol", "must be in (0, 1)", t.rtol.to_string());
        }
        if !(t.atol.is_finite() && t.atol > 0.0) {
            return bad("atol", "must be finite and > 0", t.atol.to_string());
        }
        if self.sample_every == 0 {
            return bad("sample_every", "must be ≥ 1", "0".into());
        }
        if self.threads > MAX_THREADS {
            return bad("threads", "must be at most 1024 (0: one per core)", self.threads.to_string());
        }
        crate::contact::validate(&self.contact).map_err(|(field, problem, value)| ConfigError {
            field,
            problem: problem.to_string(),
            value,
        })
    }

    /// The number of steps that cover `duration`: `round(duration / dt)`.
    pub fn step_count(&self) -> u64 {
        (self.duration / self.dt).round() as u64
    }
}

/// A simulation stopped because a body's state became non-finite or absurd.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("simulation diverged: body `{body}`: {quantity} at step {step}, t = {time} s")]
pub struct Diverged {
    /// The body's name.
    pub body: String,
    /// What went wrong, e.g. "velocity is not finite".
    pub quantity: String,
    /// The step that produced the bad state (1-based: the state after that step).
    pub step: u64,
    /// The time that step reached (s).
    pub time: f64,
}

/// A step stopped because the broad phase found more candidate contact pairs than the budget
/// (`[world] max_pairs`, [`ContactSettings::max_pairs`]): bodies heaped at one spot, whose pairs
/// and contacts would grow as the square of their number.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error(
    "contact budget exceeded at step {step} (t = {time} s): {pairs} candidate pairs, more than the budget of {budget} \
     (`max_pairs` in [world])"
)]
pub struct ContactBudget {
    /// The step that found them (1-based, as in [`Diverged`]); 0 for the bodies' starting poses.
    pub step: u64,
    /// The time that step would have reached (s).
    pub time: f64,
    /// Candidate pairs found when the search stopped (at least this many).
    pub pairs: u64,
    /// The budget.
    pub budget: u64,
}

/// Why [`World::step`] failed; the step was undone either way.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StepError {
    /// A body's state became non-finite or absurd.
    #[error(transparent)]
    Diverged(#[from] Diverged),
    /// The broad phase went over the pair budget.
    #[error(transparent)]
    ContactBudget(#[from] ContactBudget),
}

impl StepError {
    /// The divergence, if that is what stopped the step.
    pub fn diverged(&self) -> Option<&Diverged> {
        match self {
            Self::Diverged(d) => Some(d),
            Self::ContactBudget(_) => None,
        }
    }
}

/// Rigid bodies and the settings that move them.
#[derive(Debug, Clone)]
pub struct World {
    /// Settings (units in [`WorldConfig`]).
    pub config: WorldConfig,
    /// The bodies, in scene order: a `Vec<RigidBody>` to read and write (see [`Bodies`]: it notes
    /// a mutable borrow, so that the step checks sleeping bodies only when one may have changed).
    pub bodies: Bodies,
    steps: u64,
    /// Per-body scratch of the step, in body order.
    scratch: Vec<BodyScratch>,
    /// Robots (URDF trees), in scene order, stepped after the bodies (see [`Robot`]).
    pub robots: Vec<Robot>,
    /// Contact detection and response: buffers, warm-start impulses, dissipated energy.
    contact: ContactStage,
    /// Per body, the step (0-based) in which it first had a contact, if any.
    first_contact: Vec<Option<u64>>,
    /// Wall time per stage since profiling was switched on; `None`: off (see [`World::set_profiling`]).
    profile: Option<Profile>,
    /// The collision detection's threads (module `threads`).
    threads: threads::Threads,
    /// The last moving body with a shape found, if any: a witness that the contact stage has work,
    /// checked again at each step (the bodies may have changed) before it is believed.
    shaped: Option<usize>,
    /// The moving bodies in the free-body step's own layout, while `bodies` is not changed elsewhere
    /// (module `batched`).
    pack: batched::FreePack,
}

/// Why the integration of the free bodies stopped early.
#[derive(Debug)]
enum Stop {
    /// A body's state diverged.
    Diverged(Diverged),
    /// Body `index` moves and has a shape: the contact stage has work, the step must start over
    /// with it (only when the integration was asked to watch for one).
    Shaped(usize),
}

/// What the step keeps per body: the state before the step (to undo a step that diverges) and
/// `dopri5`'s proposed internal step (s).
#[derive(Debug, Clone, Copy)]
struct BodyScratch {
    before: BodyState,
    step_hint: f64,
}

impl World {
    /// A world with these settings and bodies, at `t = 0`.
    pub fn new(config: WorldConfig, bodies: Vec<RigidBody>) -> Self {
        Self {
            config,
            bodies: bodies.into(),
            steps: 0,
            scratch: Vec::new(),
            robots: Vec::new(),
            contact: ContactStage::default(),
            first_contact: Vec::new(),
            profile: None,
            threads: threads::Threads::default(),
            shaped: None,
            pack: batched::FreePack::default(),
        }
    }

    /// Switches the per-stage timing of the step on (from zero) or off. Off, the default, it costs
    /// nothing but a test per stage.
    pub fn set_profiling(&mut self, on: bool) {
        self.profile = on.then(Profile::default);
        self.contact.set_profiling(on);
    }

    /// Wall time per stage and narrow-phase counts since profiling was switched on, or `None` when off.
    pub fn profile(&self) -> Option<Profile> {
        let mut p = self.profile?;
        if let Some(contact) = self.contact.profile() {
            p.add_contact_stage(contact);
        }
        Some(p)
    }

    /// Steps taken so far.
    #[inline]
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Simulated time (s): `steps · dt` (no accumulated round-off).
    #[inline]
    pub fn time(&self) -> f64 {
        self.steps as f64 * self.config.dt
    }

    /// Advances the world by one step `dt`:
    /// 1. contacts: detect them, resolve collisions and resting contacts by impulses ([`crate::contact`]);
    /// 2. integrate every free body's Newton–Euler equations with the chosen integrator, and check
    ///    that every state stayed finite and sane;
    /// 3. advance the robots ([`Robot`]: the tree method matching the integrator) and check them;
    /// 4. contacts: move the bodies to where the impulses, applied through the step, put them.
    ///
    /// A step that diverges is undone: on `Err` the bodies and robots are as they were before the call
    /// (the last finite state), and the error names the body, the quantity, the step and the time.
    /// So is a step whose broad phase finds more candidate pairs than the pair budget
    /// ([`ContactSettings::max_pairs`]): [`StepError::ContactBudget`].
    pub fn step(&mut self) -> Result<(), StepError> {
        // with contacts, the states are saved before the impulses change them; without, in the
        // integration's own pass (no extra sweep over the bodies)
        let mut clock = Clock::start(self.profile.is_some());
        if self.at_rest() {
            // every free body asleep and nothing that could wake one: the step would save, test,
            // integrate and restore nothing (`ContactStage::at_rest`), so it only counts
            if let Some(p) = &mut self.profile {
                p.steps += 1;
                p.step += clock.lap();
            }
            self.steps += 1;
            return Ok(());
        }
        let t = self.time();
        for robot in &mut self.robots {
            robot.control.follow_waves(t);
        }
        // whether the contact stage has work; when that takes a look at every body, the integration
        // pass looks (no pass of its own over the bodies), supposing there is none
        let (contacts, integrated) = match self.contacts_known() {
            Some(contacts) => (contacts, false),
            None => {
                let integrated = self.integrate_unless_shaped()?;
                (!integrated, integrated)
            }
        };
        self.save_states(contacts);
        if contacts {
            // a small world is not worth the threads (nor their start)
            let min_pairs = self.threads.min_pairs;
            let pool =
                if self.bodies.len() >= threads::MIN_BODIES { self.threads.pool(self.config.threads) } else { None };
            self.contact.colliders_mut(&self.bodies).set_thread_pool(pool, min_pairs);
            let lead = self.config.integrator.position_lead();
            // read before the step's own borrows mark the list
            let lent = self.bodies.lent();
            self.contact.resolve(
                &mut self.bodies,
                lent,
                &self.robots,
                &self.config.contact,
                self.config.gravity,
                self.config.dt,
                lead,
            );
            if let Some((pairs, budget)) = self.contact.pairs_over_budget() {
                self.undo(self.bodies.len());
                let (step, time) = (self.steps + 1, (self.steps + 1) as f64 * self.config.dt);
                return Err(ContactBudget { step, time, pairs, budget }.into());
            }
            self.note_first_contacts();
        }
        let contact_time = clock.lap();
        // a step that diverges is undone for the bodies whose states were saved
        if !integrated {
            if let Err((saved, stop)) = self.integrate_free_bodies(!contacts, false) {
                self.undo(if contacts { self.bodies.len() } else { saved });
                match stop {
                    Stop::Diverged(diverged) => return Err(diverged.into()),
                    Stop::Shaped(_) => unreachable!("not watched"),
                }
            }
        }
        if let Err(diverged) = self.step_robots() {
            self.undo(self.bodies.len());
            return Err(diverged.into());
        }
        if contacts {
            self.contact.finish(&mut self.bodies);
            // the sleeping bodies were checked against the caller's changes (if any) in this step;
            // a step without the contact stage leaves the mark for the next that has it
            self.bodies.step_ended();
        }
        if let Some(p) = &mut self.profile {
            let integration = clock.lap();
            p.steps += 1;
            p.integration += integration;
            p.step += contact_time + integration;
        }
        self.steps += 1;
        Ok(())
    }

    /// Whether the world is at rest: the last step found every free body asleep with nothing to
    /// solve ([`ContactStage::at_rest`](crate::contact::ContactStage::at_rest)), under the same
    /// settings, no robot (a robot moves every step), and the bodies not borrowed mutably since
    /// ([`Bodies`]: a change to a sleeping body, its loads or the fixed bodies under it would wake
    /// it). Such a step changes no state, and is skipped whole: a world asleep costs nothing per
    /// body.
    pub fn at_rest(&self) -> bool {
        let c = &self.config;
        self.robots.is_empty()
            && !self.bodies.lent()
            && self.contact.at_rest(&c.contact, c.gravity, c.dt, self.bodies.len())
    }

    /// Whether the contact stage has anything to do — contacts enabled and a moving body with a shape
    /// or a robot link with one — when that is known without a pass over the bodies: contacts off, a
    /// robot link with a shape, or the body found last time still moving with a shape. `None`: only
    /// a look at every body can tell ([`World::integrate_unless_shaped`]).
    fn contacts_known(&self) -> Option<bool> {
        if !self.config.contact.enabled {
            return Some(false);
        }
        let still_shaped = |&i: &usize| self.bodies.get(i).is_some_and(|b| b.shape.is_some() && !b.fixed);
        (!self.contact.links.colliders.is_empty() || self.shaped.as_ref().is_some_and(still_shaped)).then_some(true)
    }

    /// The first moving body with a shape, if any.
    fn first_shaped(&self) -> Option<usize> {
        // the shape first: a body without one is settled by the one field
        self.bodies.iter().position(|b| b.shape.is_some() && !b.fixed)
    }

    /// The integration of the free bodies when contacts are enabled but no robot link has a shape
    /// and no moving body is known to have one: integrates the bodies as if the contact stage had
    /// nothing to do, looking at each body for a shape on the way (the pass over the bodies that
    /// says whether the contact stage has work is the integration's own). `Ok(true)`: no moving body
    /// has a shape, every body is integrated. `Ok(false)`: body `i` moves with a shape; what was
    /// stepped is undone and `i` is remembered, the step goes through the contact stage. A
    /// divergence is undone and returned only if no moving body has a shape (else the contact stage
    /// would have run first, and the step is done with it).
    fn integrate_unless_shaped(&mut self) -> Result<bool, Diverged> {
        self.save_states(false);
        let Err((saved, stop)) = self.integrate_free_bodies(true, true) else {
            return Ok(true);
        };
        self.undo(saved);
        self.shaped = match stop {
            Stop::Shaped(index) => Some(index),
            Stop::Diverged(diverged) => match self.first_shaped() {
                None => return Err(diverged),
                index => index,
            },
        };
        Ok(false)
    }

    /// Sizes the per-body scratch; saves every state now unless the integration will (`now`).
    fn save_states(&mut self, now: bool) {
        if self.scratch.len() != self.bodies.len() {
            self.scratch.resize(self.bodies.len(), BodyScratch { before: BodyState::REST, step_hint: 0.0 });
        }
        if now {
            for (scratch, body) in self.scratch.iter_mut().zip(&self.bodies) {
                scratch.before = body.state;
            }
        }
    }

    /// Records the step of each body's first contact (the contacts the stage just found; nothing to
    /// do when they are the last step's).
    fn note_first_contacts(&mut self) {
        if self.first_contact.len() != self.bodies.len() {
            self.first_contact.resize(self.bodies.len(), None);
        } else if self.contact.contacts_kept() {
            return;
        }
        for c in self.contact.contacts() {
            self.first_contact[c.a].get_or_insert(self.steps);
            self.first_contact[c.b].get_or_insert(self.steps);
        }
    }

    /// The start time (s) of the step in which body `index` first had a contact — touching,
    /// overlapping or within the distance it could close in the step — or `None` if it never had one.
    /// Until then a body moves freely (under gravity and its loads).
    pub fn first_contact_time(&self, index: usize) -> Option<f64> {
        self.first_contact.get(index).copied().flatten().map(|step| step as f64 * self.config.dt)
    }

    /// Energy dissipated by contacts since the start (J): the bodies' and the robots' links'
    /// (collisions; resting contact and friction).
    pub fn contact_energy(&self) -> ContactEnergy {
        let links = &self.contact.links;
        ContactEnergy {
            collisions: self.contact.energy.collisions + links.energy_lost,
            friction: self.contact.energy.friction + links.resting_energy_lost,
        }
    }

    /// The potential energy (J) stored at the end of the last step in the soft rows that hold the
    /// robots (their resting contacts, joint and tendon limits): each row a spring of stiffness
    /// `m_n ω²` on its deflection ([`crate::contact::links::LinkStage::elastic_energy`]). The
    /// energy of a passive robot that cannot rise is its `T + V` plus this.
    pub fn contact_elastic_energy(&self) -> f64 {
        self.contact.links.elastic_energy()
    }

    /// Collisions resolved since the start, the links' included.
    pub fn contact_collisions(&self) -> u64 {
        self.contact.impacts + self.contact.links.impacts
    }

    /// The pairs of bodies that overlap deeply now (see [`crate::collision::Overlap`] for the
    /// threshold), sorted by pair; none when contacts are off. The scene loader reports them as
    /// warnings; the contact stage pushes them apart at up to `max_correction_speed`. An error
    /// (at step 0) when the bodies' starting poses give more candidate pairs than the pair budget.
    pub fn deep_overlaps(&mut self) -> Result<Vec<Overlap>, ContactBudget> {
        if !self.config.contact.enabled {
            return Ok(Vec::new());
        }
        let budget = self.config.contact.pair_budget(self.bodies.len());
        let colliders = self.contact.colliders_mut(&self.bodies);
        colliders.set_pair_budget(usize::try_from(budget).unwrap_or(usize::MAX));
        let overlaps = colliders.deep_overlaps(&self.bodies, self.config.contact.slop);
        match colliders.pairs_over_budget() {
            Some(pairs) => Err(ContactBudget { step: 0, time: 0.0, pairs: pairs as u64, budget }),
            None => Ok(overlaps),
        }
    }

    /// The radius of body `index`'s collision shape's bounding sphere about its centre of mass (m);
    /// 0 for a plane or a body without a shape.
    pub fn bounding_radius(&mut self, index: usize) -> f64 {
        self.contact.colliders_mut(&self.bodies).radius(index)
    }

    /// The contact stage (contacts of the last step, collision shapes, collisions so far).
    pub fn contact_stage(&mut self) -> &mut ContactStage {
        &mut self.contact
    }

    /// The contacts of the last step, read only: [`ContactStage::contacts`], its
    /// [`impulses`](ContactStage::impulses) and its [`active`](ContactStage::active) contacts.
    pub fn contacts(&self) -> &ContactStage {
        &self.contact
    }

    /// Integrates every free body over one step and checks its state; `save`: keep each state from
    /// before the step in the same pass; `watch`: stop at the first moving body with a shape. When
    /// stopped, also the number of bodies whose states were saved so far (`save`).
    fn integrate_free_bodies(&mut self, save: bool, watch: bool) -> Result<(), (usize, Stop)> {
        let config = self.config;
        if config.integrator == Integrator::SemiImplicitEuler {
            return self.integrate_free_bodies_batched(save, watch);
        }
        let sleep = self.contact.sleep();
        for (index, (body, scratch)) in self.bodies.iter_mut().zip(self.scratch.iter_mut()).enumerate() {
            if body.fixed {
                continue;
            }
            if watch && body.shape.is_some() {
                return Err((index, Stop::Shaped(index)));
            }
            if save {
                scratch.before = body.state;
            }
            if sleep.is_asleep(index) {
                continue;
            }
            let rhs = BodyRhs { mass: &body.mass, loads: &body.loads, gravity_world: body.gravity(config.gravity) };
            let advanced = advance_body(
                config.integrator,
                config.tolerances,
                &rhs,
                &mut body.state,
                config.dt,
                &mut scratch.step_hint,
            );
            let problem = match advanced {
                Err(e) => Some(format!("the adaptive integrator failed: {e}")),
                Ok(()) => check_state(body),
            };
            if let Some(quantity) = problem {
                let diverged = Diverged {
                    body: body.name.clone(),
                    quantity,
                    step: self.steps + 1,
                    time: (self.steps + 1) as f64 * config.dt,
                };
                return Err((index + 1, Stop::Diverged(diverged)));
            }
        }
        Ok(())
    }

    /// Restores the states of the first `count` bodies from before the current step (the others
    /// were not stepped); the robots undo their own step.
    #[cold]
    fn undo(&mut self, count: usize) {
        for (body, scratch) in self.bodies.iter_mut().zip(&self.scratch).take(count) {
            if !body.fixed {
                body.state = scratch.before;
            }
        }
    }

    /// Total mechanical energy, kinetic plus gravitational potential, of the free bodies and the
    /// robots (J).
    pub fn energy(&self) -> f64 {
        self.free_bodies().map(|b| b.kinetic_energy() + b.potential_energy(self.config.gravity)).sum::<f64>()
            + self.robots_energy()
    }

    /// Total linear momentum of the free bodies and the floating-base robots, world frame (kg·m/s).
    pub fn linear_momentum(&self) -> DVec3 {
        self.free_bodies().map(|b| b.mass.mass * b.state.velocity).sum::<DVec3>() + self.robots_momentum().0
    }

    /// Total angular momentum of the free bodies and the floating-base robots about the world
    /// origin, world frame (kg·m²/s).
    pub fn angular_momentum(&self) -> DVec3 {
        self.free_bodies().map(|b| b.angular_momentum_world()).sum::<DVec3>() + self.robots_momentum().1
    }

    /// The bodies that move.
    pub fn free_bodies(&self) -> impl Iterator<Item = &RigidBody> {
        self.bodies.iter().filter(|b| !b.fixed)
    }

    /// The index of the body with this name.
    pub fn body_index(&self, name: &str) -> Option<usize> {
        self.bodies.iter().position(|b| b.name == name)
    }
}

/// Names the first non-finite or absurd quantity of a body's state, if any.
#[inline]
fn check_state(body: &RigidBody) -> Option<String> {
    let s = &body.state;
    // squared magnitudes: a NaN fails the `<=` test too, so the common case costs four comparisons
    let max2 = MAX_STATE_MAGNITUDE * MAX_STATE_MAGNITUDE;
    let sane = s.position.length_squared() <= max2
        && s.velocity.length_squared() <= max2
        && s.omega_body.length_squared() <= max2
        && s.orientation.length_squared() <= 4.0;
    if sane {
        return None;
    }
    let checks = [
        ("position", s.position.is_finite(), s.position.length()),
        ("orientation", s.orientation.is_finite(), 1.0),
        ("velocity", s.velocity.is_finite(), s.velocity.length()),
        ("angular velocity", s.omega_body.is_finite(), s.omega_body.length()),
    ];
    for (name, finite, magnitude) in checks {
        if !finite {
            return Some(format!("{name} is not finite"));
        }
        if magnitude > MAX_STATE_MAGNITUDE {
            return Some(format!("|{name}| = {magnitude:e} exceeds {MAX_STATE_MAGNITUDE:e}"));
        }
    }
    None
}

#[cfg(test)]
mod tests;
