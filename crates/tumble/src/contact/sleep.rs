//! Islands and sleeping: a pile at rest costs nothing until something touches it.
//!
//! **Islands.** The free bodies joined by the contacts of a step (any contact the narrow phase
//! reports, touching or speculative) form the connected components of the contact graph, found by
//! union–find with path halving (Tarjan 1975). A fixed body joins no island: two boxes resting
//! side by side on the floor are two islands.
//!
//! **Falling asleep.** A body is *still* while the fastest point of its bounding sphere moves
//! slower than `sleep_speed`, `|v| + ρ |ω| < v_sleep` (`ρ` the radius of the shape's bounding
//! sphere about the centre of mass). An island falls asleep, all of it at once, when every one of
//! its bodies has been still for `sleep_time` and it rests on something: it has a contact with a
//! fixed body, and none of its bodies touches a robot's link (robots do not sleep). A body alone in
//! space, however slowly it turns, never sleeps: torque-free motion stays exact. Falling asleep
//! sets the bodies' velocities to zero; the kinetic energy they had (below `½ m v_sleep²` each) is
//! booked with the resting contacts' loss ([`super::ContactEnergy::friction`]), so the energy
//! balance still closes.
//!
//! **Asleep.** A sleeping body is not integrated, and the narrow phase skips the pairs of two
//! bodies that are asleep or fixed: their contacts of the step in which the island fell asleep are
//! kept, with their impulses (the force that holds the body, for the contact outputs) and their
//! accumulated impulses (the warm start of the step in which the island wakes). The solver and the
//! collision stage see only the other contacts.
//!
//! **Waking.** An island wakes, all of it, in the step in which
//! - a contact joins one of its bodies to an awake free body (touching or within the distance the
//!   two can close in the step: a falling body wakes the pile in time for the collision stage to
//!   resolve the impact), or a robot's link comes that close to one of its bodies;
//! - a body's state, loads, mass or gravity scale differ from when it fell asleep (changed by the
//!   caller between steps), the world's gravity changed, or a fixed body it rests on moved.
//!
//! With `sleep = false` nothing sleeps, and the step is the same bit for bit as without this module.
//!
//! References: E. Catto, Box2D v3 (`solver_set`, `island`: sleep by island after a time below a
//! speed threshold); B. Mirtich, thesis §5.4 (a resting body's contacts need no work until
//! disturbed).

use super::{Contact, ContactSettings};
use crate::body::RigidBody;
use crate::math::DVec3;

/// What a sleeping body (or a fixed body a sleeping one rests on) was when its island fell asleep:
/// whatever the caller could change between steps, bit for bit (state, loads, damping, mass,
/// gravity scale; the point forces by a hash).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Snapshot {
    bits: [u64; SNAPSHOT_WORDS],
    /// 0 without point forces, else their hash (odd).
    point_forces: u64,
}

/// The words of a snapshot: position 3, orientation 4, velocity 3, ω 3, four load vectors 12,
/// two dampings, mass, gravity scale.
const SNAPSHOT_WORDS: usize = 29;

impl Snapshot {
    fn of(b: &RigidBody) -> Self {
        Self { bits: Self::bits(b), point_forces: Self::point_forces(b) }
    }

    /// The bits of every scalar the caller could change (one array, compared at once).
    #[inline]
    fn bits(b: &RigidBody) -> [u64; SNAPSHOT_WORDS] {
        let (s, l) = (&b.state, &b.loads);
        let q = s.orientation;
        let words: [f64; SNAPSHOT_WORDS] = [
            s.position.x,
            s.position.y,
            s.position.z,
            q.x,
            q.y,
            q.z,
            q.w,
            s.velocity.x,
            s.velocity.y,
            s.velocity.z,
            s.omega_body.x,
            s.omega_body.y,
            s.omega_body.z,
            l.force_world.x,
            l.force_world.y,
            l.force_world.z,
            l.force_body.x,
            l.force_body.y,
            l.force_body.z,
            l.torque_world.x,
            l.torque_world.y,
            l.torque_world.z,
            l.torque_body.x,
            l.torque_body.y,
            l.torque_body.z,
            l.linear_damping,
            l.angular_damping,
            b.mass.mass,
            b.gravity_scale,
        ];
        words.map(f64::to_bits)
    }

    fn point_forces(b: &RigidBody) -> u64 {
        let l = &b.loads;
        if l.point_forces.is_empty() {
            return 0;
        }
        let mut h = crate::math::StateHasher::default();
        for p in &l.point_forces {
            h.add_all(&p.point_body.to_array());
            h.add_all(&p.force.to_array());
            h.add(f64::from(u8::from(p.frame == crate::body::Frame::Body)));
        }
        h.finish() | 1
    }

    /// Whether `b` still is as recorded, bit for bit (the point forces' hash computed only when
    /// there are some).
    fn matches(&self, b: &RigidBody) -> bool {
        // the words' differences OR-ed together: one vectorised pass, no call to `memcmp`
        let now = Self::bits(b);
        let differ = self.bits.iter().zip(&now).fold(0, |acc, (a, b)| acc | (a ^ b));
        differ == 0
            && (self.point_forces == 0) == b.loads.point_forces.is_empty()
            && (self.point_forces == 0 || self.point_forces == Self::point_forces(b))
    }
}

/// A contact of two bodies that are asleep or fixed, kept as it was when the island fell asleep.
#[derive(Debug, Clone, Copy)]
pub(super) struct Frozen {
    pub contact: Contact,
    /// Its impulse on `b` over the last step it was solved (N·s, world frame).
    pub impulse: DVec3,
    /// Its accumulated impulses `λ_n, λ_t1, λ_t2` at the end of that step (N·s).
    pub lambda: [f64; 3],
}

/// The sleep state of the bodies, kept from step to step (no allocation once grown).
#[derive(Debug, Clone, Default)]
pub struct Sleep {
    /// Per body: asleep now.
    asleep: Vec<bool>,
    /// Per body: how long it has been still (s).
    still: Vec<f64>,
    /// Per body: the island it fell asleep with (an index of one of its bodies).
    island: Vec<usize>,
    /// Per body: what it was when it (or an island resting on it, for a fixed body) fell asleep.
    snapshots: Vec<Option<Snapshot>>,
    /// Union–find parents over the bodies, and per root: rests on a fixed body, may not sleep.
    parent: Vec<usize>,
    grounded: Vec<bool>,
    blocked: Vec<bool>,
    /// The contacts of sleeping pairs, in pair order.
    pub(super) frozen: Vec<Frozen>,
    /// Gravity when the sleeping islands fell asleep (m/s²).
    gravity: DVec3,
    /// Bodies asleep now.
    count: usize,
    /// Free bodies awake at the end of the last [`update`](Self::update) (sleeping enabled).
    awake: usize,
    /// Whether an island fell asleep or woke since `frozen` was built.
    changed: bool,
    /// Counts every change of who sleeps or of `frozen`: equal epochs, the same sleeping state.
    epoch: u64,
}

impl Sleep {
    /// Sizes the state for `n` bodies (a new set of bodies wakes everything).
    pub(super) fn resize(&mut self, n: usize) {
        if self.asleep.len() != n {
            *self = Self { gravity: self.gravity, epoch: self.epoch + 1, ..Self::default() };
            self.asleep.resize(n, false);
            self.still.resize(n, 0.0);
            self.island.resize(n, 0);
            self.snapshots.resize(n, None);
        }
    }

    /// Per body, whether it is asleep (empty before the first step with contacts).
    pub fn asleep(&self) -> &[bool] {
        &self.asleep
    }

    /// A number that changes whenever a body falls asleep or wakes or the kept contacts change.
    pub(super) fn epoch(&self) -> u64 {
        self.epoch
    }

    /// How many bodies are asleep.
    pub fn count(&self) -> usize {
        self.count
    }

    /// How many free bodies were awake at the end of the last [`update`](Self::update) (before any
    /// woke in that step's contacts), counted only while sleeping is enabled.
    pub(super) fn awake_count(&self) -> usize {
        self.awake
    }

    /// Whether body `i` is asleep.
    #[inline]
    pub fn is_asleep(&self, i: usize) -> bool {
        self.asleep.get(i).copied().unwrap_or(false)
    }

    /// Wakes everything (e.g. `sleep` switched off).
    pub(super) fn wake_all(&mut self) {
        if self.count > 0 {
            self.asleep.iter_mut().for_each(|a| *a = false);
            self.still.iter_mut().for_each(|s| *s = 0.0);
            self.snapshots.iter_mut().for_each(|s| *s = None);
            self.count = 0;
            self.changed = true;
            self.epoch += 1;
        }
        self.frozen.clear();
    }

    /// Wakes the island of sleeping body `i`: every body that fell asleep with it.
    fn wake_island(&mut self, i: usize) {
        let island = self.island[i];
        for j in 0..self.asleep.len() {
            if self.asleep[j] && self.island[j] == island {
                self.asleep[j] = false;
                self.still[j] = 0.0;
                self.snapshots[j] = None;
                self.count -= 1;
            }
        }
        self.changed = true;
        self.epoch += 1;
    }

    /// Before the narrow phase: wakes the islands whose bodies (or the fixed bodies under them)
    /// the caller changed since they fell asleep, and all of them if gravity changed. `lent`:
    /// whether the caller borrowed the bodies mutably since the last step ([`crate::world::Bodies`]);
    /// if not, none can have changed and they are not read.
    pub(super) fn wake_changed(&mut self, bodies: &[RigidBody], lent: bool, gravity: DVec3) {
        if self.count == 0 {
            return;
        }
        if gravity != self.gravity {
            self.wake_all();
            return;
        }
        if !lent {
            return;
        }
        // a fixed body that moved wakes every island resting on it
        let mut moved_fixed = false;
        for (i, b) in bodies.iter().enumerate() {
            if let Some(s) = &self.snapshots[i] {
                if !s.matches(b) {
                    if b.fixed {
                        moved_fixed = true;
                    } else if self.asleep[i] {
                        self.wake_island(i);
                    }
                }
            }
            // a body the caller fixed
            if self.asleep[i] && b.fixed {
                self.wake_island(i);
            }
        }
        if moved_fixed {
            let moved = |snapshots: &[Option<Snapshot>], i: usize| snapshots[i].is_some_and(|s| !s.matches(&bodies[i]));
            for k in 0..self.frozen.len() {
                let (a, b) = (self.frozen[k].contact.a, self.frozen[k].contact.b);
                for (i, other) in [(a, b), (b, a)] {
                    if self.asleep[i] && bodies[other].fixed && moved(&self.snapshots, other) {
                        self.wake_island(i);
                    }
                }
            }
            for (i, b) in bodies.iter().enumerate() {
                if b.fixed && moved(&self.snapshots, i) {
                    self.snapshots[i] = Some(Snapshot::of(b));
                }
            }
        }
    }

    /// Whether body `i` takes no part in the step: fixed or asleep.
    #[inline]
    pub(super) fn resting(&self, bodies: &[RigidBody], i: usize) -> bool {
        bodies[i].fixed || self.is_asleep(i)
    }

    /// After the narrow phase: wakes every sleeping island joined by a contact to an awake free
    /// body or touched by a robot's link (`link_bodies`), until none is. Whether any woke.
    pub(super) fn wake_touched(
        &mut self,
        bodies: &[RigidBody],
        contacts: &[Contact],
        link_bodies: impl Iterator<Item = usize>,
    ) -> bool {
        if self.count == 0 {
            return false;
        }
        let epoch = self.epoch;
        for i in link_bodies {
            if self.asleep[i] {
                self.wake_island(i);
            }
        }
        // a woken island's contacts may join another sleeping island: repeat until none does
        loop {
            let mut woke = false;
            for c in contacts {
                let (a, b) = (c.a, c.b);
                for (i, other) in [(a, b), (b, a)] {
                    // `asleep` first: a sleeping island's contacts are between sleeping bodies,
                    // and the bodies themselves (far apart in memory) are then not read
                    if self.asleep[i] && !self.asleep[other] && !bodies[other].fixed {
                        self.wake_island(i);
                        woke = true;
                    }
                }
            }
            if !woke || self.count == 0 {
                break;
            }
        }
        self.epoch != epoch
    }

    /// At the start of a step, from the velocities the last step left and its contacts (with their
    /// impulses and accumulated impulses, aligned with `contacts`): advances the bodies' still
    /// times, puts the islands that qualify to sleep (zeroing their velocities; the kinetic energy
    /// they had is returned), and rebuilds the frozen contacts if anything fell asleep or woke.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn update(
        &mut self,
        bodies: &mut [RigidBody],
        radii: impl Fn(usize) -> f64,
        contacts: &[Contact],
        impulses: &[DVec3],
        lambdas: &[[f64; 3]],
        link_bodies: impl Iterator<Item = usize>,
        settings: &ContactSettings,
        gravity: DVec3,
        dt: f64,
    ) -> f64 {
        let n = bodies.len();
        self.resize(n);
        if !settings.sleep {
            self.wake_all();
            return 0.0;
        }
        // still times; the islands are built only when a body has been still long enough
        let mut candidate = false;
        self.awake = 0;
        for (i, b) in bodies.iter().enumerate() {
            if b.fixed || self.asleep[i] {
                continue;
            }
            self.awake += 1;
            let s = &b.state;
            let speed = s.velocity.length() + radii(i) * s.omega_body.length();
            self.still[i] = if speed < settings.sleep_speed { self.still[i] + dt } else { 0.0 };
            candidate |= self.still[i] >= settings.sleep_time;
        }
        if !candidate {
            self.rebuild_frozen(bodies, contacts, impulses, lambdas);
            return 0.0;
        }
        // islands of the awake free bodies
        self.parent.clear();
        self.parent.extend(0..n);
        self.grounded.clear();
        self.grounded.resize(n, false);
        self.blocked.clear();
        self.blocked.resize(n, false);
        let mut grounded = false;
        for c in contacts {
            let (fa, fb) = (bodies[c.a].fixed, bodies[c.b].fixed);
            if !fa && !fb {
                let (ra, rb) = (find(&mut self.parent, c.a), find(&mut self.parent, c.b));
                if ra != rb {
                    // the smaller index is the root: islands are named the same every run
                    let (lo, hi) = (ra.min(rb), ra.max(rb));
                    self.parent[hi] = lo;
                    self.grounded[lo] |= self.grounded[hi];
                    self.blocked[lo] |= self.blocked[hi];
                }
            } else if fa != fb {
                let free = if fa { c.b } else { c.a };
                let r = find(&mut self.parent, free);
                self.grounded[r] = true;
                grounded = true;
            }
        }
        if !grounded {
            self.rebuild_frozen(bodies, contacts, impulses, lambdas);
            return 0.0;
        }
        for i in link_bodies {
            let r = find(&mut self.parent, i);
            self.blocked[r] = true;
        }
        // an island with an awake body not still long enough, or a sleeping body (which a contact
        // joins to awake ones only in the step in which it woke), may not sleep
        for (i, b) in bodies.iter().enumerate() {
            if b.fixed {
                continue;
            }
            let r = find(&mut self.parent, i);
            if self.asleep[i] || self.still[i] < settings.sleep_time || b.shape.is_none() {
                self.blocked[r] = true;
            }
        }
        let mut energy = 0.0;
        for (i, b) in bodies.iter_mut().enumerate() {
            if b.fixed || self.asleep[i] {
                continue;
            }
            let r = find(&mut self.parent, i);
            if !self.grounded[r] || self.blocked[r] {
                continue;
            }
            energy += b.kinetic_energy();
            b.state.velocity = DVec3::ZERO;
            b.state.omega_body = DVec3::ZERO;
            self.asleep[i] = true;
            self.island[i] = r;
            self.snapshots[i] = Some(Snapshot::of(b));
            self.count += 1;
            self.awake -= 1;
            self.changed = true;
            self.epoch += 1;
        }
        if self.changed {
            self.gravity = gravity;
            // the fixed bodies under the sleeping islands: a move of one wakes them
            for c in contacts {
                for (i, other) in [(c.a, c.b), (c.b, c.a)] {
                    // (`wake_changed` ran first this step: a fixed body's move is already seen)
                    if bodies[i].fixed && self.asleep[other] {
                        self.snapshots[i] = Some(Snapshot::of(&bodies[i]));
                    }
                }
            }
        }
        self.rebuild_frozen(bodies, contacts, impulses, lambdas);
        energy
    }

    /// Rebuilds the frozen contacts from the last step's if an island fell asleep or woke since
    /// they were built.
    fn rebuild_frozen(&mut self, bodies: &[RigidBody], contacts: &[Contact], impulses: &[DVec3], lambdas: &[[f64; 3]]) {
        if !self.changed {
            return;
        }
        self.changed = false;
        self.epoch += 1;
        self.frozen.clear();
        if self.count == 0 {
            return;
        }
        for (k, c) in contacts.iter().enumerate() {
            if self.resting(bodies, c.a) && self.resting(bodies, c.b) {
                let lambda = lambdas.get(k).copied().unwrap_or([0.0; 3]);
                let impulse = impulses.get(k).copied().unwrap_or(DVec3::ZERO);
                self.frozen.push(Frozen { contact: *c, impulse, lambda });
            }
        }
    }
}

/// The root of `i`'s set, halving the path on the way.
#[inline]
fn find(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}
