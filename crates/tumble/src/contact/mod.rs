//! Contacts: collisions by integrating through the impact, resting contact by sequential impulses.
//!
//! The contact stage runs before the free-body integration of each step (state at `t`, step `dt`):
//!
//! 1. **Impacts** ([`impact`], Mirtich 1996 §4 with Stronge's law; scheduled by `collisions`): a
//!    contact whose surfaces close within the step along the bodies' motion — the parabola the
//!    integrator will draw, `x + (v + λ a dt) t + ½ a t²` with its
//!    [position lead](crate::Integrator::position_lead) `λ` — and whose approach speed then exceeds
//!    [`ContactSettings::impact_speed`], is a collision. Collisions are resolved one at a time in
//!    the order in which they happen (the earliest first; at one instant, in contact order), each
//!    with the velocities at its time `t_c`; a body's end-of-step position is then shifted by
//!    `−Δv t_c` (and its rotation by `−Δω t_c`), which is exactly where a body that moved freely
//!    until `t_c` and with the new velocity after it would be, and the contacts of the two bodies
//!    are timed again. So momentum travels down a chain of touching bodies as in a Newton's cradle
//!    (Mirtich's sequential view), all at the instant of the strike.
//! 2. **Resting contact** ([`solver`], Catto 2005/2006, the soft step of Box2D v3): every contact is
//!    solved by sequential impulses with warm starting in [`ContactSettings::substeps`] substeps,
//!    each one adding the external forces, solving with a soft spring that pushes overlapping bodies
//!    apart, moving the bodies, and relaxing (solving again without the spring's bias, which so adds
//!    no energy). A speculative contact (surfaces apart at the start of the step) holds only
//!    approaches slower than `impact_speed`: a faster one is a collision, which stage 1 resolves in
//!    the step in which the surfaces meet. A body the impulses reached ends the step where the substeps moved it; its
//!    velocity change is applied at the start of the step, so that the free-body integration ends
//!    at the solver's velocity.
//!
//! After the integration, [`ContactStage::finish`] puts the held bodies where the substeps moved them
//! and applies the collisions' position and rotation shifts.
//!
//! Material combine rules for a pair: friction `μ = √(μ_a μ_b)` (geometric mean), restitution
//! `e = max(e_a, e_b)`; a body without a value takes the world's default. When both bodies give the
//! same value the pair uses it.

pub mod batch;
mod collisions;
pub mod impact;
pub mod links;
pub mod sleep;
pub mod solver;

pub use impact::{collide, collision_matrix, Impact, RestitutionLaw};

use crate::body::RigidBody;
use crate::collision::{Colliders, Contact};
use crate::math::{quat_exp, DMat3, DQuat, DVec3};
pub use solver::FrictionModel;
use solver::{Constraint, ContactPoint, Manifold, SolverBody};

/// Contact settings, the contact keys of `[world]`. Units SI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactSettings {
    /// Whether contacts are detected and resolved at all. Default `true`.
    pub enabled: bool,
    /// Restitution of bodies that give none, in [0, 1]. Default `0.5`.
    pub restitution: f64,
    /// Coulomb friction of bodies that give none, ≥ 0. Default `0.5`.
    pub friction: f64,
    /// The law that ends an impact's restitution phase. Default Stronge's.
    pub law: RestitutionLaw,
    /// Approach speed above which a contact is a collision with restitution (m/s); slower contacts
    /// are resting contacts, without restitution. Default `0.5`.
    pub impact_speed: f64,
    /// Substeps of the resting-contact solver per step. Default `6`.
    pub substeps: u32,
    /// Solver passes per substep (each followed by as many relaxation passes). Default `1`.
    pub iterations: u32,
    /// How the resting contacts between free bodies take friction: at every point (default), or
    /// one disc and one twist per manifold ([`FrictionModel::Manifold`], cheaper and coarser).
    /// Robots' contacts keep friction at every point.
    pub friction_model: FrictionModel,
    /// A pair's contact manifold is kept from the last step, its points moved with the bodies and
    /// only their gaps measured again, while the pair has moved relative to itself by less than
    /// this fraction of the smaller shape's bounding radius since the manifold was made (module
    /// `collision::pairs`); `0`: every manifold made afresh at every step. Larger is cheaper for
    /// slowly creeping stacks and moves each contact point by up to this fraction of the shape.
    /// Default [`crate::collision::REUSE_FRACTION`] (`1e-4`).
    pub manifold_reuse: f64,
    /// Overlap tolerated without correction (m). Default `0`: the spring below holds the overlap
    /// of a body resting on another at `m g/(m_n ω²)`, a fraction of a millimetre.
    pub slop: f64,
    /// Frequency of the spring that pushes overlapping bodies apart (Hz); at most a quarter of the
    /// substep rate, twice it against a fixed body. Default `60`.
    pub hertz: f64,
    /// Damping ratio of that spring. Default `10` (overdamped: no bounce from the correction).
    pub damping_ratio: f64,
    /// Largest speed of the position correction (m/s). Default `3` (Box2D's `contactSpeed`).
    pub max_correction_speed: f64,
    /// Whether islands of bodies at rest on a fixed body fall asleep (module [`sleep`]). Default
    /// `true`.
    pub sleep: bool,
    /// Speed below which a body is still: `|v| + ρ |ω|`, `ρ` its bounding radius (m/s). Default
    /// `0.01`.
    pub sleep_speed: f64,
    /// Time every body of an island must have been still before it falls asleep (s). Default `0.25`.
    pub sleep_time: f64,
    /// The most candidate pairs the broad phase may find in a step; beyond, the step fails
    /// ([`crate::world::StepError::ContactBudget`]). Default `None`: [`default_pair_budget`] of
    /// the body count.
    pub max_pairs: Option<u64>,
}

/// Candidate pairs per body in the default pair budget.
pub const PAIRS_PER_BODY: u64 = 32;
/// Candidate pairs the default pair budget allows whatever the body count.
pub const MIN_PAIR_BUDGET: u64 = 10_000;

/// The default pair budget of a world of `bodies` bodies: `32 · bodies + 10,000`. A pile of equal
/// bodies at rest has about 3–10 candidate pairs per body (its neighbours, and the floor); bodies
/// heaped at one spot have `(n − 1)/2` each.
pub fn default_pair_budget(bodies: usize) -> u64 {
    PAIRS_PER_BODY.saturating_mul(bodies as u64).saturating_add(MIN_PAIR_BUDGET)
}

impl ContactSettings {
    /// The pair budget for a world of `bodies` bodies: `max_pairs`, else [`default_pair_budget`].
    pub fn pair_budget(&self, bodies: usize) -> u64 {
        self.max_pairs.unwrap_or_else(|| default_pair_budget(bodies))
    }
}

impl Default for ContactSettings {
    fn default() -> Self {
        Self {
            enabled: true,
            restitution: 0.5,
            friction: 0.5,
            law: RestitutionLaw::Stronge,
            impact_speed: 0.5,
            substeps: 6,
            iterations: 1,
            friction_model: FrictionModel::Point,
            manifold_reuse: crate::collision::REUSE_FRACTION,
            slop: 0.0,
            hertz: 60.0,
            damping_ratio: 10.0,
            max_correction_speed: 3.0,
            sleep: true,
            sleep_speed: 0.01,
            sleep_time: 0.25,
            max_pairs: None,
        }
    }
}

/// Energy taken out of the bodies' motion by contacts since the start (J).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ContactEnergy {
    /// Kinetic energy dissipated in collisions (impacts).
    pub collisions: f64,
    /// Mechanical energy (kinetic plus gravitational) lost by bodies held by resting contacts:
    /// friction, inelastic resting contact, and the overlap correction (which may add some).
    pub friction: f64,
}

/// A manifold's friction patch of the previous step ([`FrictionModel::Manifold`]): its friction
/// impulse and twist's angular impulse, world frame (N·s, N·m·s).
#[derive(Debug, Clone, Copy)]
struct PreviousPatch {
    a: usize,
    b: usize,
    friction_warm: [DVec3; 2],
}

/// A manifold's patch at the end of the solve: normal, tangents, accumulated impulses and their
/// sum over the substeps (`LaneSolver::for_each_patch`).
type PatchResult = (DVec3, DVec3, DVec3, [f64; 3], [f64; 3]);

/// The contact stage's buffers, kept from step to step (no allocation once grown).
#[derive(Debug, Clone, Default)]
pub struct ContactStage {
    colliders: Option<Colliders>,
    /// Pairs of bodies that never collide (from the scene's `no_collide` lists).
    excluded: Vec<(usize, usize)>,
    contacts: Vec<Contact>,
    /// The impulse on body `b` of each contact over the step, impacts and resting contact,
    /// world frame (N·s); aligned with `contacts`.
    impulses: Vec<DVec3>,
    /// Each overflow constraint's accumulated impulses `λ_n, λ_t1, λ_t2` summed over the substeps
    /// (N·s); aligned with `constraints`.
    lambda_sums: Vec<[f64; 3]>,
    bodies: Vec<SolverBody>,
    positions: Vec<DVec3>,
    predicted: Vec<(DVec3, DVec3)>,
    /// The constraints of the manifolds the colours could not take (`batch`'s overflow), solved
    /// one at a time.
    constraints: Vec<Constraint>,
    /// The resting solver's input: the manifolds of the contacts that are not frozen (ranges of
    /// `points`), in pair order.
    manifolds: Vec<Manifold>,
    points: Vec<ContactPoint>,
    /// The pairs' colours and the constraints in `f64x4` lanes (the free bodies' solve).
    lanes: batch::LaneSolver,
    /// End-of-step position shift (m) and rotation vector (rad) per body, world frame.
    shifts: Vec<(DVec3, DVec3)>,
    /// The collisions of the step in time order (stage 1's buffers).
    sequence: collisions::Sequence,
    /// Where the substeps of the resting-contact solver moved each body they held: position (m)
    /// and orientation.
    held: Vec<Option<(DVec3, DQuat)>>,
    /// The bodies the resting constraints move, and a flag per body for building that list.
    active: Vec<usize>,
    in_active: Vec<bool>,
    /// Kinetic plus potential energy of each held body before the resting impulses (J).
    energy_before: Vec<f64>,
    gravity: DVec3,
    /// The previous step's contacts and their accumulated impulses `λ_n, λ_t1, λ_t2` (N·s), sorted
    /// by pair (warm starting). While `previous_pending`, they are `contacts` and `lambdas`
    /// themselves, not yet copied here: the next step's list takes their buffers over, swapped
    /// rather than copied, or copies them before changing them.
    previous: Vec<Contact>,
    previous_lambdas: Vec<[f64; 3]>,
    /// `contacts` and `lambdas` are the previous step's (sorted by pair), not copied to `previous`.
    previous_pending: bool,
    /// The previous step's friction patches, sorted by pair ([`FrictionModel::Manifold`]).
    previous_patches: Vec<PreviousPatch>,
    /// Per point of `points`, its normal impulse summed over the substeps, and per manifold its
    /// patch at the end of the solve ([`FrictionModel::Manifold`]).
    normal_sums: Vec<f64>,
    patch_results: Vec<Option<PatchResult>>,
    /// Scratch of `share_patch`: each point's offset from its manifold's centre across the normal.
    across: Vec<DVec3>,
    /// Each contact's accumulated impulses at the end of the step (N·s); aligned with `contacts`.
    lambdas: Vec<[f64; 3]>,
    /// Per contact: both bodies fixed or asleep (kept from when they fell asleep, not solved).
    frozen: Vec<bool>,
    /// The contact of each point of `points` (the contacts that are not frozen).
    constrained: Vec<usize>,
    /// The narrow phase's contacts, before the frozen ones are merged in.
    fresh: Vec<Contact>,
    /// Islands and sleeping (module [`sleep`]).
    sleep: sleep::Sleep,
    /// The sleep epoch in which the contacts were all kept ones of sleeping pairs (the narrow
    /// phase found none): while it holds, the step has nothing to do.
    steady: Option<u64>,
    /// The last step's contact list is the one of the step before, pair for pair (`steady`).
    kept: bool,
    /// The last step solved its contacts (`shifts`, `held` and `energy_before` are this step's).
    solved: bool,
    /// The settings, gravity (m/s²), time step (s) and body count of the last step when it found
    /// every free body asleep and nothing to do ([`at_rest`](Self::at_rest)).
    rest: Option<(ContactSettings, DVec3, f64, usize)>,
    /// The contacts of robot links (collision shapes, rows, the robots' part of the solve).
    pub links: links::LinkStage,
    /// Energy dissipated so far.
    pub energy: ContactEnergy,
    /// Collisions resolved so far.
    pub impacts: u64,
    /// Wall time per stage when profiling is on (see [`crate::World::set_profiling`]).
    profile: Option<crate::profile::Profile>,
}

impl ContactStage {
    /// The collision shapes (built at the first step).
    pub fn colliders_mut(&mut self, bodies: &[RigidBody]) -> &mut Colliders {
        if !self.colliders.as_ref().is_some_and(|c| c.matches(bodies)) {
            let mut colliders = Colliders::new(bodies);
            for &(i, j) in &self.excluded {
                colliders.exclude_pair(i, j);
            }
            self.colliders = Some(colliders);
        }
        self.colliders.as_mut().expect("just built")
    }

    /// Bodies `i` and `j` (indices into the world's bodies) never collide with each other.
    pub fn exclude_pair(&mut self, i: usize, j: usize) {
        self.excluded.push((i.min(j), i.max(j)));
        if let Some(c) = &mut self.colliders {
            c.exclude_pair(i, j);
        }
    }

    /// Whether bodies `i` and `j` are a pair [`exclude_pair`](Self::exclude_pair) took out.
    pub fn is_excluded(&self, i: usize, j: usize) -> bool {
        self.excluded.contains(&(i.min(j), i.max(j)))
    }

    /// Switches the timing of the stages on (from zero) or off.
    pub fn set_profiling(&mut self, on: bool) {
        self.profile = on.then(Default::default);
    }

    /// The stages' times since profiling was switched on, `None` when off.
    pub fn profile(&self) -> Option<&crate::profile::Profile> {
        self.profile.as_ref()
    }

    /// The candidate pairs found by the last step's broad phase when it went over the pair budget
    /// (`ContactSettings::max_pairs`) and stopped, with the budget; `None` when it kept within it.
    pub fn pairs_over_budget(&self) -> Option<(u64, u64)> {
        let colliders = self.colliders.as_ref()?;
        colliders.pairs_over_budget().map(|found| (found as u64, colliders.pair_budget() as u64))
    }

    /// The contacts found at the last step.
    pub fn contacts(&self) -> &[Contact] {
        &self.contacts
    }

    /// Whether a step with these settings, gravity (m/s²), time step (s) and `n` bodies has nothing
    /// to do for the bodies: the last step found every free body asleep, its contacts the kept ones
    /// of the step before, and no robot link; with the same settings, and the bodies not borrowed
    /// mutably since (the caller's part: [`crate::world::Bodies`]), nothing can wake or move, and
    /// the step would find the same again. The caller skips the step's passes over the bodies.
    pub fn at_rest(&self, settings: &ContactSettings, gravity: DVec3, dt: f64, n: usize) -> bool {
        self.rest == Some((*settings, gravity, dt, n))
    }

    /// Whether the last step's [`contacts`](Self::contacts) are those of the step before, pair for
    /// pair: the kept contacts of sleeping islands, with nothing awake touching anything.
    pub fn contacts_kept(&self) -> bool {
        self.kept
    }

    /// The impulse on body `b` of each of [`contacts`](Self::contacts) over the last step (N·s,
    /// world frame): its collision impulse, if it was a collision, plus the resting-contact
    /// impulses of every substep. Body `a` received the opposite. Over `dt` it is the contact's
    /// mean force on `b` during the step.
    pub fn impulses(&self) -> &[DVec3] {
        &self.impulses
    }

    /// The active contacts of the last step, each with its impulse on `b` (N·s): those that
    /// carried an impulse, or whose surfaces overlapped. A speculative contact (surfaces still
    /// apart) that pushed nothing is not active.
    pub fn active(&self) -> impl Iterator<Item = (&Contact, DVec3)> {
        self.contacts
            .iter()
            .zip(&self.impulses)
            .filter(|(c, p)| **p != DVec3::ZERO || c.gap < 0.0)
            .map(|(c, p)| (c, *p))
    }

    /// Detects the contacts of the step and changes the bodies' velocities by the impulses of
    /// collisions and resting contacts (state at the start of the step; `gravity` m/s², `dt` s;
    /// `lead` the integrator's [`position_lead`](crate::Integrator::position_lead), which says
    /// where the step will move the bodies).
    pub fn resolve(
        &mut self,
        bodies: &mut [RigidBody],
        bodies_lent: bool,
        robots: &dyn links::RobotViews,
        settings: &ContactSettings,
        gravity: DVec3,
        dt: f64,
        lead: f64,
    ) {
        self.in_active.resize(bodies.len(), false);
        self.gravity = gravity;
        self.kept = false;
        self.solved = false;
        self.rest = None;
        if !settings.enabled || (bodies.is_empty() && self.links.colliders.is_empty()) {
            self.settle_previous();
            self.contacts.clear();
            self.impulses.clear();
            self.lambdas.clear();
            self.frozen.clear();
            self.links.clear();
            self.sleep.wake_all();
            self.steady = None;
            return;
        }
        let budget = settings.pair_budget(bodies.len());
        let colliders = self.colliders_mut(bodies);
        colliders.set_pair_budget(usize::try_from(budget).unwrap_or(usize::MAX));
        colliders.set_reuse_fraction(settings.manifold_reuse);
        self.fall_asleep(bodies, bodies_lent, settings, gravity, dt);
        let mut fresh = std::mem::take(&mut self.fresh);
        let mut profile = self.profile.take();
        let asleep = self.sleep.asleep();
        self.colliders.as_mut().expect("built above").find_contacts_profiled(
            bodies,
            asleep,
            dt,
            gravity,
            settings.slop,
            &mut fresh,
            profile.as_mut(),
        );
        self.profile = profile;
        if self.pairs_over_budget().is_some() {
            // the step fails (`World::step`): nothing is solved
            self.fresh = fresh;
            self.settle_previous();
            self.contacts.clear();
            self.impulses.clear();
            self.lambdas.clear();
            self.frozen.clear();
            self.steady = None;
            return;
        }
        // nothing awake touches anything, and nobody fell asleep or woke since the last step: the
        // contacts, their impulses and the warm starts are the last step's
        let epoch = self.sleep.epoch();
        let none_found = fresh.is_empty();
        let steady = none_found && self.steady == Some(epoch);
        self.kept = steady;
        if !steady {
            self.merge_frozen(bodies, &mut fresh);
        }
        self.steady = none_found.then_some(epoch);
        self.fresh = fresh;
        if !self.links.colliders.is_empty() {
            let mut clock = crate::profile::Clock::start(self.profile.is_some());
            let colliders = self.colliders.as_ref().expect("built above");
            self.links.detect(colliders, bodies, robots, dt, settings.slop);
            if let Some(p) = &mut self.profile {
                let t = clock.lap();
                p.link_detect += t;
                p.narrow_phase += t;
                p.link_contacts += self.links.contacts().len() as u64;
            }
        }
        if steady && self.links.is_empty() {
            // the kept contacts are all between sleeping or fixed bodies (nothing awake touched
            // anything in this step or the last, and nothing fell asleep or woke since), so they
            // wake nobody: nothing to solve. As below when there is no contact at all: the robots'
            // rows of an earlier step go
            self.links.clear();
            if settings.sleep && self.sleep.awake_count() == 0 && self.links.colliders.is_empty() {
                self.rest = Some((*settings, gravity, dt, bodies.len()));
            }
            return;
        }
        if self.sleep.wake_touched(bodies, &self.contacts, self.links.touched_bodies()) {
            self.steady = None;
            // the contacts of an island that woke are solved in this step
            for (k, c) in self.contacts.iter().enumerate() {
                if self.frozen[k] && !(self.sleep.resting(bodies, c.a) && self.sleep.resting(bodies, c.b)) {
                    self.frozen[k] = false;
                    self.impulses[k] = DVec3::ZERO;
                }
            }
        }
        if self.contacts.is_empty() && self.links.is_empty() {
            self.previous_pending = false;
            self.previous.clear();
            self.previous_lambdas.clear();
            self.previous_patches.clear();
            self.links.clear();
            return;
        }
        let mut clock = crate::profile::Clock::start(self.profile.is_some());
        // the per-body results of a solve, applied by `finish` (a step that returns above has none)
        self.solved = true;
        self.shifts.clear();
        self.shifts.resize(bodies.len(), (DVec3::ZERO, DVec3::ZERO));
        self.held.clear();
        self.held.resize(bodies.len(), None);
        self.energy_before.clear();
        self.energy_before.resize(bodies.len(), 0.0);
        self.load_bodies(bodies, gravity);
        self.impacts(bodies, settings, dt, lead);
        let (soft, soft_fixed) = softness(settings, dt);
        if !self.links.is_empty() {
            let mut rows_clock = crate::profile::Clock::start(self.profile.is_some());
            self.links.prepare(bodies, &self.bodies, &self.positions, robots, settings, dt, soft, soft_fixed);
            if let Some(p) = &mut self.profile {
                p.link_rows += rows_clock.lap();
            }
            if self.links.impacts(&mut self.bodies, settings, dt) {
                self.store_velocities(bodies);
            }
        }
        let impacts = clock.lap();
        self.resting(bodies, robots, settings, gravity, dt);
        if let Some(p) = &mut self.profile {
            p.impacts += impacts;
            p.resting += clock.lap();
        }
    }

    /// At the start of the step: wakes the islands the caller changed, then puts to sleep the
    /// islands that have been still long enough, from the last step's contacts (module [`sleep`]).
    fn fall_asleep(
        &mut self,
        bodies: &mut [RigidBody],
        bodies_lent: bool,
        settings: &ContactSettings,
        gravity: DVec3,
        dt: f64,
    ) {
        self.sleep.resize(bodies.len());
        if !settings.sleep {
            self.sleep.wake_all();
            return;
        }
        self.sleep.wake_changed(bodies, bodies_lent, gravity);
        let colliders = self.colliders.as_ref().expect("built by the caller");
        let lost = self.sleep.update(
            bodies,
            |i| colliders.radius(i),
            &self.contacts,
            &self.impulses,
            &self.lambdas,
            self.links.touched_bodies(),
            settings,
            gravity,
            dt,
        );
        self.energy.friction += lost;
    }

    /// The contacts of the step: the narrow phase's (`fresh`) and, merged in pair order, the kept
    /// contacts of pairs whose bodies are both asleep or fixed, with their impulses and
    /// accumulated impulses.
    /// `fresh` is left with no meaning (the narrow phase clears it).
    fn merge_frozen(&mut self, bodies: &[RigidBody], fresh: &mut Vec<Contact>) {
        if self.sleep.frozen.is_empty() && self.previous_pending {
            // the last step's contacts and impulses become the previous ones: their buffers are
            // swapped in (the buffers of the ones before are reused for this step's lists)
            std::mem::swap(&mut self.previous, &mut self.contacts);
            std::mem::swap(&mut self.previous_lambdas, &mut self.lambdas);
            self.previous_pending = false;
        }
        self.settle_previous();
        self.contacts.clear();
        self.impulses.clear();
        self.lambdas.clear();
        self.frozen.clear();
        if self.sleep.frozen.is_empty() {
            // nothing kept (nobody asleep): the narrow phase's list is the step's, its buffer and
            // the last one's swapped rather than copied
            std::mem::swap(&mut self.contacts, fresh);
            let n = self.contacts.len();
            self.impulses.resize(n, DVec3::ZERO);
            self.lambdas.resize(n, [0.0; 3]);
            self.frozen.resize(n, false);
            return;
        }
        let kept = self.sleep.frozen.iter().filter(|f| {
            let c = &f.contact;
            self.sleep.resting(bodies, c.a) && self.sleep.resting(bodies, c.b)
        });
        let mut kept = kept.peekable();
        for c in fresh {
            while let Some(f) = kept.next_if(|f| (f.contact.a, f.contact.b) < (c.a, c.b)) {
                self.contacts.push(f.contact);
                self.impulses.push(f.impulse);
                self.lambdas.push(f.lambda);
                self.frozen.push(true);
            }
            self.contacts.push(*c);
            self.impulses.push(DVec3::ZERO);
            self.lambdas.push([0.0; 3]);
            self.frozen.push(false);
        }
        for f in kept {
            self.contacts.push(f.contact);
            self.impulses.push(f.impulse);
            self.lambdas.push(f.lambda);
            self.frozen.push(true);
        }
    }

    /// The islands and their sleep (module [`sleep`]).
    pub fn sleep(&self) -> &sleep::Sleep {
        &self.sleep
    }

    /// After the integration: puts the bodies held by resting contacts where the substeps moved
    /// them, and shifts the bodies by the collisions' corrections.
    pub fn finish(&mut self, bodies: &mut [RigidBody]) {
        if !self.solved {
            return;
        }
        for (i, ((body, &(dx, dtheta)), held)) in bodies.iter_mut().zip(&self.shifts).zip(&self.held).enumerate() {
            if body.fixed {
                continue;
            }
            if let Some((position, orientation)) = *held {
                body.state.position = position;
                body.state.orientation = orientation;
            }
            if dx != DVec3::ZERO || dtheta != DVec3::ZERO {
                body.state.position += dx;
                body.state.orientation = (quat_exp(dtheta) * body.state.orientation).normalize();
            }
            if held.is_some() {
                let after = body.kinetic_energy() + body.potential_energy(self.gravity);
                self.energy.friction += self.energy_before[i] - after;
            }
        }
    }

    /// Copies the last solved step's contacts and impulses to `previous` if they are still
    /// `contacts` and `lambdas` (before those change), sorted by pair: the contacts come grouped
    /// by pair, in pair order (`Colliders::find_contacts`); a stable sort keeps the order within a
    /// pair otherwise.
    fn settle_previous(&mut self) {
        if !self.previous_pending {
            return;
        }
        self.previous_pending = false;
        self.previous.clone_from(&self.contacts);
        self.previous_lambdas.clone_from(&self.lambdas);
        if !self.previous.is_sorted_by_key(|c| (c.a, c.b)) {
            let mut both: Vec<(Contact, [f64; 3])> =
                self.previous.iter().copied().zip(self.previous_lambdas.iter().copied()).collect();
            both.sort_by_key(|(c, _)| (c.a, c.b));
            (self.previous, self.previous_lambdas) = both.into_iter().unzip();
        }
    }

    /// The solver's copy of the bodies: inverse mass and world inverse inertia, velocities, and the
    /// acceleration of the constant world forces, `s_g g + F_world/m` (m/s²).
    fn load_bodies(&mut self, bodies: &[RigidBody], gravity: DVec3) {
        self.bodies.clear();
        self.positions.clear();
        for (i, b) in bodies.iter().enumerate() {
            let mut sb = SolverBody { v: b.state.velocity, w: b.state.omega_world(), ..SolverBody::FIXED };
            if !b.fixed && !self.sleep.is_asleep(i) {
                let r = DMat3::from_quat(b.state.orientation);
                sb.inv_mass = b.mass.inv_mass;
                sb.inv_inertia = crate::math::change_frame(r, DMat3::from_diagonal(b.mass.inv_inertia_body));
                sb.accel = b.gravity(gravity) + b.loads.force_world * b.mass.inv_mass;
            }
            self.bodies.push(sb);
            self.positions.push(b.state.position);
        }
    }

    /// Writes the solver's velocities back to the bodies (world → body frame for ω).
    fn store_velocities(&self, bodies: &mut [RigidBody]) {
        for (i, (b, sb)) in bodies.iter_mut().zip(&self.bodies).enumerate() {
            if !b.fixed && !self.sleep.is_asleep(i) {
                b.state.velocity = sb.v;
                b.set_omega_world(sb.w);
            }
        }
    }

    /// Stage 2: resting contact by soft sequential impulses in substeps (see [`solver`]).
    fn resting(
        &mut self,
        bodies: &mut [RigidBody],
        robots: &dyn links::RobotViews,
        settings: &ContactSettings,
        gravity: DVec3,
        dt: f64,
    ) {
        let substeps = settings.substeps.max(1);
        let h = dt / substeps as f64;
        let inv_h = 1.0 / h;
        let (soft, soft_fixed) = softness(settings, dt);

        // the velocities after the collisions
        self.predicted.clear();
        self.predicted.extend(self.bodies.iter().map(|sb| (sb.v, sb.w)));
        // the manifolds (the contacts come grouped by pair: `Colliders::find_contacts`) and their
        // points with the impulses they start from
        self.manifolds.clear();
        self.points.clear();
        self.constrained.clear();
        // (a step that keeps its contacts, for robots' rows among sleeping islands, comes here
        // without a new list: its previous ones are its own, copied now)
        self.settle_previous();
        let mut warm = WarmStarts::new(&self.previous, &self.previous_lambdas);
        let per_manifold = settings.friction_model == FrictionModel::Manifold;
        let mut patches = self.previous_patches.iter().peekable();
        for (ci, c) in self.contacts.iter().enumerate() {
            if self.frozen[ci] {
                continue;
            }
            let row = self.points.len();
            if self.manifolds.last().is_none_or(|m| (m.a, m.b) != (c.a, c.b)) {
                let (mu, _) = combine(&bodies[c.a], &bodies[c.b], settings);
                let softness = if bodies[c.a].fixed || bodies[c.b].fixed { soft_fixed } else { soft };
                // the pair's patch of the last step (both lists in pair order)
                while patches.next_if(|p| (p.a, p.b) < (c.a, c.b)).is_some() {}
                let friction_warm = match patches.peek() {
                    Some(p) if per_manifold && (p.a, p.b) == (c.a, c.b) => p.friction_warm,
                    _ => [DVec3::ZERO; 2],
                };
                self.manifolds.push(Manifold { a: c.a, b: c.b, points: (row, row), mu, softness, friction_warm });
            }
            let mut lambda = warm.find(c).unwrap_or([0.0; 3]);
            if per_manifold {
                // the patch takes the friction
                lambda = [lambda[0], 0.0, 0.0];
            }
            // the vectors by component: copied whole, they went through a stack copy whose 16-byte
            // loads straddled its 8-byte stores (a store-forwarding stall per point)
            let (p, n) = (c.point_world, c.normal_world);
            self.points.push(ContactPoint {
                point: DVec3::new(p.x, p.y, p.z),
                n: DVec3::new(n.x, n.y, n.z),
                gap: c.gap,
                lambda,
            });
            self.manifolds.last_mut().expect("pushed above").points.1 = row + 1;
            self.constrained.push(ci);
        }
        // the bodies the constraints move, and those the robots' rows move
        self.active.clear();
        for i in self.manifolds.iter().flat_map(|m| [m.a, m.b]).chain(self.links.bodies()) {
            if !bodies[i].fixed && !self.in_active[i] {
                self.in_active[i] = true;
                self.active.push(i);
            }
        }
        // the soft step: per substep, forces, warm start, soft solve, move, relax
        let (slop, max_push) = (settings.slop, settings.max_correction_speed);
        // the manifolds in colours, four to a batch (`batch`): the manifolds of a colour share no
        // moving body; each batch's constraints computed in the lanes, each manifold solved with its
        // two bodies' velocities held locally
        self.lanes.build_points(
            &self.manifolds,
            &self.points,
            &self.bodies,
            &self.positions,
            |i| !bodies[i].fixed,
            settings.friction_model,
            &mut self.constraints,
        );
        let lanes = &mut self.lanes;
        let constraints = &mut self.constraints;
        self.lambda_sums.clear();
        self.lambda_sums.resize(constraints.len(), [0.0; 3]);
        let links = &mut self.links;
        let with_links = !links.is_empty();
        // a robot alone on the floor has no body constraint: the lanes' calls (one per colour and
        // pass) are skipped
        let with_bodies = !self.points.is_empty();
        // the sweeps of the step, counted: each pass over a manifold's points runs the other way
        // than the one before, with a pass and the next one going the same way in pairs (forward,
        // back, back, forward, …; `solver::Sweep::reverse`)
        let mut sweeps_done = 0u32;
        for _ in 0..substeps {
            for &i in &self.active {
                self.bodies[i].integrate_velocity(h);
            }
            if with_links {
                links.integrate_velocity(h);
            }
            if with_bodies {
                lanes.warm_start(constraints, &mut self.bodies);
            }
            if with_links {
                links.warm_start(&mut self.bodies);
                links.warm_start_limits();
            }
            let mut sweep = |bodies: &mut [SolverBody], links: &mut links::LinkStage, pass| {
                for iteration in 0..settings.iterations {
                    let reverse = (sweeps_done + 1) / 2 % 2 == 1;
                    sweeps_done += 1;
                    // the bodies move between the biased sweeps and the first relaxing one only
                    let moved = iteration == 0;
                    let impact_speed = settings.impact_speed;
                    let sweep = solver::Sweep { pass, inv_h, slop, max_push, impact_speed, reverse, moved };
                    if with_bodies {
                        lanes.solve(constraints, bodies, &sweep);
                    }
                    if with_links {
                        links.solve(bodies, &sweep);
                        links.solve_limits(&sweep);
                    }
                }
            };
            sweep(&mut self.bodies, links, solver::Pass::Solve);
            for &i in &self.active {
                self.bodies[i].integrate_position(h);
            }
            if with_links {
                links.integrate_position(h);
            }
            sweep(&mut self.bodies, links, solver::Pass::Relax);
            if with_links {
                links.accumulate();
            }
            // the impulse a constraint applied in this substep is its accumulated λ (the warm start
            // applied the λ it started with, the sweeps the changes)
            if with_bodies {
                lanes.accumulate(constraints, &mut self.lambda_sums);
            }
        }
        let (impulses, lambdas, constrained, points) =
            (&mut self.impulses, &mut self.lambdas, &self.constrained, &self.points);
        let normal_sums = &mut self.normal_sums;
        normal_sums.clear();
        normal_sums.resize(if per_manifold { points.len() } else { 0 }, 0.0);
        lanes.for_each_point_impulse(constraints, &self.lambda_sums, |row, impulse, lambda, normal_sum| {
            let ci = constrained[row];
            impulses[ci] += impulse;
            lambdas[ci] = lambda;
            if per_manifold {
                normal_sums[row] = normal_sum;
            }
        });
        self.previous_patches.clear();
        if per_manifold {
            self.patch_results.clear();
            self.patch_results.resize(self.manifolds.len(), None);
            let results = &mut self.patch_results;
            lanes.for_each_patch(|g, n, t1, t2, lambda, sum| results[g] = Some((n, t1, t2, lambda, sum)));
            for (g, (m, result)) in self.manifolds.iter().zip(&self.patch_results).enumerate() {
                let Some((n, t1, t2, lambda, sum)) = *result else { continue };
                self.previous_patches.push(PreviousPatch {
                    a: m.a,
                    b: m.b,
                    friction_warm: [lambda[0] * t1 + lambda[1] * t2, lambda[2] * n],
                });
                let rows = m.points.0..m.points.1;
                share_patch(
                    (&self.points[rows.clone()], self.lanes.patch_centre(g)),
                    &self.normal_sums[rows.clone()],
                    n,
                    (sum[0] * t1 + sum[1] * t2, sum[2]),
                    &mut self.across,
                    |j, impulse| self.impulses[self.constrained[rows.start + j]] += impulse,
                );
            }
        }
        if with_links {
            links.store_elastic_energy(&self.bodies, slop);
            links.finish(robots, dt);
        }
        // the contacts and their impulses are the next step's previous ones, copied only if the
        // next step's list does not take their buffers over (`settle_previous`; now if they are
        // out of pair order, to be sorted)
        self.previous_pending = true;
        if !self.contacts.is_sorted_by_key(|c| (c.a, c.b)) {
            self.settle_previous();
        }
        // a body the impulses reached: its velocity change goes in at the start of the step, so
        // that the integration ends at the solver's velocity; its motion is the substeps' (`finish`)
        for &i in &self.active {
            self.in_active[i] = false;
            let sb = &self.bodies[i];
            if !sb.touched {
                continue;
            }
            let b = &mut bodies[i];
            let (v0, w0) = self.predicted[i];
            let (dv, dw) = (sb.v - (v0 + sb.accel * dt), sb.w - w0);
            // the mechanical energy before the resting impulses; `finish` counts what it lost. After
            // a collision the body moves as from its start position shifted by the collision's
            // `−Δv t_c` with the new velocity: that motion's energy, or the shift's work against
            // gravity, `m g·Δv t_c`, would be booked as resting loss
            let shift = self.shifts[i].0;
            self.energy_before[i] =
                b.kinetic_energy() + b.potential_energy(gravity) - b.mass.mass * b.gravity(gravity).dot(shift);
            b.state.velocity += dv;
            let omega = b.state.omega_world() + dw;
            b.set_omega_world(omega);
            self.held[i] = Some((b.state.position + sb.dx, (sb.dq * b.state.orientation).normalize()));
        }
    }
}

/// A manifold's patch impulse over the step ([`FrictionModel::Manifold`]) shared among its points as
/// forces the contacts report: the friction impulse `friction` (N·s) in proportion to each point's
/// normal impulse `normal_sums` (equally when they are all zero), and the twist `twist` (N·m·s about
/// `n`) as the impulses `τ n × d_i / Σ|d_j|²` with `d_i` the point's offset from the centre across
/// the normal: they add up to no force and to the twist's moment `τ n` about the centre (exactly when
/// the points lie in the plane across `n`). `f(j, impulse)` for the `j`-th point.
fn share_patch(
    (points, centre): (&[ContactPoint], DVec3),
    normal_sums: &[f64],
    n: DVec3,
    (friction, twist): (DVec3, f64),
    across: &mut Vec<DVec3>,
    mut f: impl FnMut(usize, DVec3),
) {
    across.clear();
    across.extend(points.iter().map(|p| {
        let d = p.point - centre;
        d - d.dot(n) * n
    }));
    let arm_squared: f64 = across.iter().map(|d| d.length_squared()).sum();
    let total: f64 = normal_sums.iter().sum();
    for (j, (d, &normal)) in across.iter().zip(normal_sums).enumerate() {
        let share = if total > 0.0 { normal / total } else { 1.0 / points.len() as f64 };
        let turn = if arm_squared > 0.0 { (twist / arm_squared) * n.cross(*d) } else { DVec3::ZERO };
        f(j, share * friction + turn);
    }
}

/// The softness of the resting contacts' position bias over a substep of `dt / substeps`: against a
/// moving body, and twice as stiff against a fixed body, which has no give of its own (Box2D v3);
/// never stiffer than a quarter of the substep rate (ω h ≤ π/2; a ground spring at twice that rate
/// set a ten-box tower wandering).
fn softness(settings: &ContactSettings, dt: f64) -> (solver::Softness, solver::Softness) {
    let h = dt / settings.substeps.max(1) as f64;
    let cap = 0.25 / h;
    (
        solver::Softness::new(settings.hertz.min(cap), settings.damping_ratio, h),
        solver::Softness::new((2.0 * settings.hertz).min(cap), settings.damping_ratio, h),
    )
}

/// Largest distance (m) between a contact point and the previous step's point of the same pair
/// whose impulse it inherits when the feature ids do not match.
pub(super) const WARM_MATCH_DISTANCE: f64 = 0.02;

/// The accumulated impulses a contact inherits from the previous step: those of the point of the
/// same pair with the same features (the normal impulse, and the friction impulse taken as it is in
/// this step's tangents), or else, when parry renumbered the features (a clipped manifold changes
/// its points), those of the nearest point of the same pair within [`WARM_MATCH_DISTANCE`].
/// `previous` is sorted by pair, `lambdas` its impulses, and `start` the first entry not of an
/// earlier pair than `c`'s.
fn previous_impulse(previous: &[Contact], lambdas: &[[f64; 3]], start: usize, c: &Contact) -> Option<[f64; 3]> {
    let pair = previous[start..].iter().zip(&lambdas[start..]).take_while(|(p, _)| (p.a, p.b) == (c.a, c.b));
    // the features first (the common case, with no distance computed), then the nearest point
    if let Some((_, lambda)) = pair.clone().find(|(p, _)| p.features == c.features) {
        return Some(*lambda);
    }
    let mut best: Option<(f64, [f64; 3])> = None;
    for (p, lambda) in pair {
        let d = (p.point_world - c.point_world).length_squared();
        if d <= WARM_MATCH_DISTANCE * WARM_MATCH_DISTANCE && best.is_none_or(|b| d < b.0) {
            best = Some((d, *lambda));
        }
    }
    best.map(|b| b.1)
}

/// The warm starts of a step's contacts, looked up in the previous step's (sorted by pair): the
/// contacts come in pair order too, so a cursor that only moves forward finds each pair's first
/// previous point in one pass over both lists (a contact out of order is looked up by bisection).
struct WarmStarts<'a> {
    previous: &'a [Contact],
    lambdas: &'a [[f64; 3]],
    /// The first previous point of a pair not before the last contact's.
    cursor: usize,
}

impl<'a> WarmStarts<'a> {
    fn new(previous: &'a [Contact], lambdas: &'a [[f64; 3]]) -> Self {
        Self { previous, lambdas, cursor: 0 }
    }

    /// See [`previous_impulse`].
    fn find(&mut self, c: &Contact) -> Option<[f64; 3]> {
        let key = (c.a, c.b);
        let before = |p: &Contact| (p.a, p.b) < key;
        if self.cursor > 0 && !before(&self.previous[self.cursor - 1]) {
            // out of pair order: start again from the first previous point of the pair
            self.cursor = self.previous.partition_point(before);
        }
        while self.cursor < self.previous.len() && before(&self.previous[self.cursor]) {
            self.cursor += 1;
        }
        previous_impulse(self.previous, self.lambdas, self.cursor, c)
    }
}

/// The pair's friction and restitution: `μ = √(μ_a μ_b)`, `e = max(e_a, e_b)`, defaults from `settings`.
pub fn combine(a: &RigidBody, b: &RigidBody, settings: &ContactSettings) -> (f64, f64) {
    combine_materials(a.material, b.material, settings)
}

/// [`combine`] for two materials (a body's, or a robot's links').
pub fn combine_materials(a: crate::body::Material, b: crate::body::Material, settings: &ContactSettings) -> (f64, f64) {
    let mu = |m: crate::body::Material| m.friction.unwrap_or(settings.friction);
    let e = |m: crate::body::Material| m.restitution.unwrap_or(settings.restitution);
    ((mu(a) * mu(b)).sqrt(), e(a).max(e(b)))
}

/// The largest [`ContactSettings::manifold_reuse`]: a tenth of a shape's size.
pub const MAX_MANIFOLD_REUSE: f64 = 0.1;

/// Checks the settings: `field`, problem, value on failure.
pub fn validate(s: &ContactSettings) -> Result<(), (&'static str, &'static str, String)> {
    let unit = |x: f64| x.is_finite() && (0.0..=1.0).contains(&x);
    let nonneg = |x: f64| x.is_finite() && x >= 0.0;
    let checks = [
        ("restitution", unit(s.restitution), "must be in [0, 1]", s.restitution),
        ("friction", nonneg(s.friction), "must be finite and ≥ 0", s.friction),
        ("impact_speed", nonneg(s.impact_speed), "must be finite and ≥ 0 (m/s)", s.impact_speed),
        ("slop", nonneg(s.slop), "must be finite and ≥ 0 (m)", s.slop),
        ("contact_hertz", nonneg(s.hertz), "must be finite and ≥ 0 (Hz)", s.hertz),
        ("contact_damping_ratio", nonneg(s.damping_ratio), "must be finite and ≥ 0", s.damping_ratio),
        (
            "max_correction_speed",
            nonneg(s.max_correction_speed),
            "must be finite and ≥ 0 (m/s)",
            s.max_correction_speed,
        ),
        ("sleep_speed", nonneg(s.sleep_speed), "must be finite and ≥ 0 (m/s)", s.sleep_speed),
        ("sleep_time", nonneg(s.sleep_time), "must be finite and ≥ 0 (s)", s.sleep_time),
        (
            "manifold_reuse",
            s.manifold_reuse.is_finite() && (0.0..=MAX_MANIFOLD_REUSE).contains(&s.manifold_reuse),
            "must be in [0, 0.1] (a fraction of the smaller shape's bounding radius)",
            s.manifold_reuse,
        ),
    ];
    for (field, ok, problem, value) in checks {
        if !ok {
            return Err((field, problem, value.to_string()));
        }
    }
    if s.max_pairs == Some(0) {
        return Err(("max_pairs", "must be ≥ 1 (leave it out for the default, 32 per body + 10,000)", "0".into()));
    }
    if s.iterations == 0 || s.iterations > 10_000 {
        return Err(("contact_iterations", "must be in 1..=10000", s.iterations.to_string()));
    }
    if s.substeps == 0 || s.substeps > 10_000 {
        return Err(("contact_substeps", "must be in 1..=10000", s.substeps.to_string()));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::{Contact, ContactStage};
    use crate::math::DVec3;

    fn contact(a: usize, b: usize, k: u64) -> Contact {
        Contact { a, b, point_world: DVec3::splat(k as f64), normal_world: DVec3::Z, gap: 0.0, features: (k, k) }
    }

    /// The last step's contacts, kept as they are for the warm starts of the next step, become
    /// the previous ones sorted by pair, each with its own impulses (the order within a pair
    /// kept), when copied before they change; and a warm start then finds each one's impulses.
    #[test]
    fn the_previous_contacts_are_copied_sorted_with_their_impulses() {
        let mut stage = ContactStage::default();
        let pairs = [(2, 3), (0, 1), (2, 3), (0, 5), (0, 1)];
        stage.contacts = pairs.iter().enumerate().map(|(k, &(a, b))| contact(a, b, k as u64)).collect();
        stage.lambdas = (0..pairs.len()).map(|k| [k as f64, 10.0 + k as f64, 20.0 + k as f64]).collect();
        stage.previous_pending = true;
        stage.settle_previous();
        assert!(!stage.previous_pending);
        let order: Vec<u64> = stage.previous.iter().map(|c| c.features.0).collect();
        assert_eq!(order, [1, 4, 3, 0, 2]);
        for (c, lambda) in stage.previous.iter().zip(&stage.previous_lambdas) {
            assert_eq!(lambda[0], c.features.0 as f64);
        }
        // a second settle copies nothing again
        stage.contacts.clear();
        stage.settle_previous();
        assert_eq!(stage.previous.len(), pairs.len());
        let mut warm = super::WarmStarts::new(&stage.previous, &stage.previous_lambdas);
        for k in [1, 4, 3, 0, 2] {
            let (a, b) = pairs[k as usize];
            assert_eq!(warm.find(&contact(a, b, k)), Some([k as f64, 10.0 + k as f64, 20.0 + k as f64]));
        }
    }
}
