//! Stage 1 of the contact step: the collisions of the step, one at a time, in the order in which
//! they happen (Mirtich's sequential view of simultaneous collisions, 1996 §4.3).
//!
//! Within the step each body moves along the parabola of its integrator,
//! `x(t) = x + (v + λ a dt) t + ½ a t² + Δx`, and turns by `ω t + Δθ` (`λ` the integrator's
//! [position lead](crate::Integrator::position_lead), `a` the acceleration of the constant forces;
//! world frame). `(Δx, Δθ)` are the shifts of the collisions the body has had so far in the step,
//! `−Δv t_c` and `−Δω t_c`: after a collision at `t_c` the body moves as if it had had the new
//! velocity since the start of the step, shifted back by what that velocity would have moved it
//! before `t_c`. The gap of a contact at time `t` is then
//!
//! ```text
//! gap(t) = G − w t − ½ α t²,    G = gap₀ + n·[(Δx_b + Δθ_b × r_b) − (Δx_a + Δθ_a × r_a)]
//! ```
//!
//! with `w` the approach speed along `n` of the current contact-point velocities (with the lead) and
//! `α` that of the accelerations. A contact collides at the first `t ∈ [t_last, dt]` at which its
//! gap is closed while the surfaces approach, `t_last` the time of either body's latest collision
//! (before it the current velocities did not hold), if the approach speed then exceeds
//! `impact_speed`: slower contacts are resting contacts (stage 2).
//!
//! The earliest pending collision is resolved first; collisions at the same instant (surfaces
//! within [`TOUCHING`] of each other then) are taken in contact order, the order of the body
//! pairs. A collision changes the
//! velocities of its two bodies, so the contacts of those two bodies are timed again. A queue
//! ordered by time holds the pending collisions; an entry whose bodies collided since it was
//! timed is stale and dropped. So a chain of touching balls collides at the instant the first
//! ball strikes, ball after ball, and a ball struck by a heavier one that also reaches the next
//! ball is resolved in that order, never through a ball in between.

use super::{collide, collision_matrix, combine, ContactSettings, ContactStage};
use crate::body::RigidBody;
use crate::math::DVec3;
use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// A pending collision: contact `contact` closes at `t` (s into the step), timed when its two
/// bodies had had `epochs` collisions.
#[derive(Debug, Clone, Copy)]
struct Pending {
    t: f64,
    contact: usize,
    epochs: (u32, u32),
}

impl PartialEq for Pending {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for Pending {}
impl PartialOrd for Pending {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Pending {
    /// Reversed, so that `BinaryHeap` pops the earliest, then the first contact.
    fn cmp(&self, other: &Self) -> Ordering {
        other.t.total_cmp(&self.t).then(other.contact.cmp(&self.contact))
    }
}

/// The buffers of stage 1, kept from step to step.
#[derive(Debug, Clone, Default)]
pub(super) struct Sequence {
    /// Per body: the time of its latest collision in the step (s), and how many it has had.
    times: Vec<f64>,
    epochs: Vec<u32>,
    /// The contacts of each body: `by_body[starts[i]..starts[i + 1]]`.
    starts: Vec<usize>,
    by_body: Vec<usize>,
    queue: BinaryHeap<Pending>,
}

impl ContactStage {
    /// Stage 1: resolves the collisions of the step in time order (see the module's text), changing
    /// the solver bodies' velocities and the shifts; writes the new velocities to `bodies`.
    pub(super) fn impacts(&mut self, bodies: &mut [RigidBody], settings: &ContactSettings, dt: f64, lead: f64) {
        let n = bodies.len();
        let seq = &mut self.sequence;
        seq.times.clear();
        seq.times.resize(n, 0.0);
        seq.epochs.clear();
        seq.epochs.resize(n, 0);
        seq.queue.clear();
        // the contacts come grouped by pair (`Colliders::find_contacts`): a pair's bodies are read
        // once for the bound of its points' approach speeds
        let mut start = 0;
        while start < self.contacts.len() {
            let (a, b) = (self.contacts[start].a, self.contacts[start].b);
            let end = start + self.contacts[start..].iter().take_while(|c| (c.a, c.b) == (a, b)).count();
            if self.frozen[start..end].iter().all(|&f| f) {
                // two bodies asleep or fixed do not move: no bound to make
                start = end;
                continue;
            }
            let bound = self.approach_bound(a, b, dt, lead);
            // every point below (checked at once, with two square roots for the pair): none timed
            if bound.all_below(self.contacts[start..end].iter().map(|c| c.point_world), settings.impact_speed) {
                start = end;
                continue;
            }
            for ci in start..end {
                // two bodies asleep or fixed do not move; a contact that cannot approach faster than
                // the impact speed in the step cannot collide (`schedule` would queue nothing)
                if !self.frozen[ci] && !bound.below(self.contacts[ci].point_world, settings.impact_speed) {
                    self.schedule(ci, settings, dt, lead);
                }
            }
            start = end;
        }
        if self.sequence.queue.is_empty() {
            return;
        }
        self.index_contacts_by_body(n);
        // a bound against endless sequences (each collision takes energy or is elastic; a chain of
        // n bodies needs at most about n² of them)
        let cap = (4 + 2 * self.contacts.len().min(64)) * self.contacts.len().max(1);
        let mut count = 0;
        while let Some(next) = self.sequence.queue.pop() {
            let c = self.contacts[next.contact];
            let (a, b, n) = (c.a, c.b, c.normal_world);
            if next.epochs != (self.sequence.epochs[a], self.sequence.epochs[b]) {
                continue;
            }
            // the relative velocity of the contact points at t_c, along the integrators' parabolas
            let (r_a, r_b, u0, accel) = self.approach(next.contact, dt, lead);
            let u = u0 + next.t * accel;
            let (ba, bb) = (&self.bodies[a], &self.bodies[b]);
            let k = collision_matrix(ba.inv_mass, ba.inv_inertia, r_a, bb.inv_mass, bb.inv_inertia, r_b);
            let (mu, e) = combine(&bodies[a], &bodies[b], settings);
            let Some(hit) = collide(k, n, u, mu, e, settings.law) else { continue };
            let p = hit.impulse_world;
            self.impulses[next.contact] += p;
            for (i, r, sign) in [(a, r_a, -1.0), (b, r_b, 1.0)] {
                if bodies[i].fixed {
                    continue;
                }
                let sb = &mut self.bodies[i];
                let (dv, dw) = (sb.inv_mass * sign * p, sb.inv_inertia * r.cross(sign * p));
                sb.v += dv;
                sb.w += dw;
                self.shifts[i].0 -= dv * next.t;
                self.shifts[i].1 -= dw * next.t;
                self.sequence.times[i] = next.t;
                self.sequence.epochs[i] += 1;
            }
            self.energy.collisions += hit.energy_lost;
            self.impacts += 1;
            count += 1;
            if count >= cap {
                break;
            }
            // the two bodies' contacts, timed again with the new velocities
            for i in [a, b] {
                if bodies[i].fixed {
                    continue;
                }
                for k in self.sequence.starts[i]..self.sequence.starts[i + 1] {
                    let cj = self.sequence.by_body[k];
                    self.schedule(cj, settings, dt, lead);
                }
            }
        }
        if count > 0 {
            self.store_velocities(bodies);
        }
    }

    /// The contacts of each of the `n` bodies, `by_body[starts[i]..starts[i + 1]]` (a counting
    /// sort; built only in a step with a collision).
    fn index_contacts_by_body(&mut self, n: usize) {
        let seq = &mut self.sequence;
        seq.starts.clear();
        seq.starts.resize(n + 1, 0);
        for c in &self.contacts {
            seq.starts[c.a + 1] += 1;
            seq.starts[c.b + 1] += 1;
        }
        for i in 0..n {
            seq.starts[i + 1] += seq.starts[i];
        }
        seq.by_body.clear();
        seq.by_body.resize(2 * self.contacts.len(), 0);
        for (ci, c) in self.contacts.iter().enumerate() {
            for i in [c.a, c.b] {
                // starts[i] is the next free slot of body i until the pass ends; shifted back below
                seq.by_body[seq.starts[i]] = ci;
                seq.starts[i] += 1;
            }
        }
        for i in (0..n).rev() {
            seq.starts[i + 1] = seq.starts[i];
        }
        seq.starts[0] = 0;
    }

    /// Contact `ci`'s offsets `r_a`, `r_b` (m), the relative velocity of its two points at the
    /// start of the step along the integrators' parabolas, `u₀ = u + λ dt Δa` (m/s), and their
    /// relative acceleration `Δa` (m/s²), world frame, with the current velocities.
    fn approach(&self, ci: usize, dt: f64, lead: f64) -> (DVec3, DVec3, DVec3, DVec3) {
        let c = &self.contacts[ci];
        let (ba, bb) = (&self.bodies[c.a], &self.bodies[c.b]);
        let (r_a, r_b) = (c.point_world - self.positions[c.a], c.point_world - self.positions[c.b]);
        let accel = bb.accel - ba.accel;
        let u0 = (bb.v + bb.w.cross(r_b)) - (ba.v + ba.w.cross(r_a)) + lead * dt * accel;
        (r_a, r_b, u0, accel)
    }

    /// The bound of the approach speeds of the contacts between bodies `a` and `b` over the step,
    /// with the velocities at its start (see [`ApproachBound`]).
    fn approach_bound(&self, a: usize, b: usize, dt: f64, lead: f64) -> ApproachBound {
        let (ba, bb) = (&self.bodies[a], &self.bodies[b]);
        ApproachBound {
            centres: (self.positions[a], self.positions[b]),
            linear: (bb.v - ba.v).length() + (bb.accel - ba.accel).length() * (lead.abs() + 1.0) * dt,
            angular: (ba.w.length(), bb.w.length()),
        }
    }

    /// Times contact `ci` with the current velocities and shifts, and queues it if it collides in
    /// the step faster than `impact_speed`.
    fn schedule(&mut self, ci: usize, settings: &ContactSettings, dt: f64, lead: f64) {
        let (r_a, r_b, u0, accel) = self.approach(ci, dt, lead);
        let c = &self.contacts[ci];
        let (a, b, n) = (c.a, c.b, c.normal_world);
        // G = gap + n·(s_b − s_a), s the point's shift
        let shift = |i: usize, r| self.shifts[i].0 + self.shifts[i].1.cross(r);
        let gap = c.gap + n.dot(shift(b, r_b) - shift(a, r_a));
        let seq = &self.sequence;
        let t_last = seq.times[a].max(seq.times[b]);
        let Some(t) = closing_time(gap, -u0.dot(n), -accel.dot(n), t_last, dt) else { return };
        if -(u0 + accel * t).dot(n) <= settings.impact_speed {
            return;
        }
        let epochs = (seq.epochs[a], seq.epochs[b]);
        self.sequence.queue.push(Pending { t, contact: ci, epochs });
    }
}

/// A bound of the approach speed `w(t) = −(u₀ + Δa t)·n` of any contact of one pair of bodies at
/// any `t ∈ [0, dt]` ([`ContactStage::approach`]): with `u₀ = (v_b + ω_b × r_b) − (v_a + ω_a × r_a) +
/// λ dt Δa` and `|n| = 1`,
///
/// `|w(t)| ≤ |v_b − v_a| + |Δa| (|λ| + 1) dt + |ω_a| |r_a| + |ω_b| |r_b|`.
///
/// A contact whose bound is below the impact speed (with a margin of 1e-9 of it, far above the
/// rounding of either computation) cannot collide in the step: the collision stage does not time it,
/// which changes nothing (`schedule` would queue nothing). This is most contacts of a resting pile.
#[derive(Debug, Clone, Copy)]
struct ApproachBound {
    /// The bodies' centres of mass (m).
    centres: (DVec3, DVec3),
    /// `|v_b − v_a| + |Δa| (|λ| + 1) dt` (m/s).
    linear: f64,
    /// `|ω_a|`, `|ω_b|` (rad/s).
    angular: (f64, f64),
}

impl ApproachBound {
    /// Whether a contact at `point` (m) approaches slower than `impact_speed` (m/s) throughout the
    /// step (false for a non-finite bound).
    #[inline]
    fn below(&self, point: DVec3, impact_speed: f64) -> bool {
        let (r_a, r_b) = (self.distance_squared(point, 0).sqrt(), self.distance_squared(point, 1).sqrt());
        self.below_at(r_a, r_b, impact_speed)
    }

    /// Whether [`below`](Self::below) holds at every one of `points`, from their farthest distances
    /// from each centre: those bound every point's bound from above (the same lengths rounded the
    /// same way, and `+`, `×` by non-negative numbers and `√` keep their order), so "true" here is
    /// "true" at each point. "False" says nothing of each (a NaN distance is kept: false).
    #[inline]
    fn all_below(&self, points: impl Iterator<Item = DVec3>, impact_speed: f64) -> bool {
        let farther = |d: f64, far: f64| if d.is_nan() || d > far { d } else { far };
        let (a, b) = points.fold((0.0, 0.0), |(a, b), p| {
            (farther(self.distance_squared(p, 0), a), farther(self.distance_squared(p, 1), b))
        });
        self.below_at(a.sqrt(), b.sqrt(), impact_speed)
    }

    /// [`below`](Self::below) for a point at distances `r_a`, `r_b` (m) from the two centres.
    #[inline]
    fn below_at(&self, r_a: f64, r_b: f64, impact_speed: f64) -> bool {
        let bound = self.linear + self.angular.0 * r_a + self.angular.1 * r_b;
        bound * (1.0 + 1e-9) < impact_speed
    }

    /// `|point − centre|²` (m²) for the centre of body A (`side` 0) or B (1).
    #[inline]
    fn distance_squared(&self, point: DVec3, side: usize) -> f64 {
        let centre = if side == 0 { self.centres.0 } else { self.centres.1 };
        (point - centre).length_squared()
    }
}

/// Surfaces closer than this (m) touch: a contact whose gap at `t_last` is below it collides at
/// `t_last`, so that the touching contacts of a struck chain collide at exactly the instant of the
/// strike (and in contact order), not a round-off apart.
pub const TOUCHING: f64 = 1e-9;

/// The first time `t ∈ [t_min, dt]` (s) at which a gap closes, `gap(t) = G − w t − ½ α t²` with
/// `G` the gap extrapolated to `t = 0` (m), approach speed `w` (m/s) and approach acceleration `α`
/// (m/s²), while the surfaces approach, `w + α t > 0`; `None` if it stays open. A gap below
/// [`TOUCHING`] at `t_min` is closed.
fn closing_time(gap: f64, w: f64, alpha: f64, t_min: f64, dt: f64) -> Option<f64> {
    // already closed at t_min: the collision is then, if the surfaces approach
    let gap_min = gap - t_min * (w + 0.5 * alpha * t_min);
    let w_min = w + alpha * t_min;
    if gap_min <= TOUCHING {
        return (w_min > 0.0).then_some(t_min);
    }
    // the smaller positive root of gap_min − w_min τ − ½ α τ² = 0, in the stable form
    // 2 gap_min / (w_min + √(w_min² + 2 α gap_min))
    let disc = w_min * w_min + 2.0 * alpha * gap_min;
    if disc < 0.0 {
        return None;
    }
    let denom = w_min + disc.sqrt();
    if denom <= 0.0 {
        return None;
    }
    let t = t_min + 2.0 * gap_min / denom;
    (t <= dt).then_some(t)
}

#[cfg(test)]
mod tests {
    use super::{closing_time, ApproachBound};
    use crate::contact::solver::SolverBody;
    use crate::contact::ContactStage;
    use crate::math::DVec3;

    /// Numbers uniform in [0, 1) from `seed` (xorshift64).
    fn uniform(mut state: u64) -> impl FnMut() -> f64 {
        move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// The bound holds the approach speed `−(u₀ + Δa t)·n` of `schedule` (as `approach` computes
    /// `u₀`) at every `t` of the step, for random velocities, accelerations, points, normals, steps and
    /// position leads; and it is tight enough to skip a resting contact.
    #[test]
    fn the_approach_bound_holds_the_approach_speed() {
        let mut unit = uniform(0x2545_f491_4f6c_dd1d);
        let mut next = move || unit() * 2.0 - 1.0;
        let mut vec = |scale: f64| DVec3::new(next() * scale, next() * scale, next() * scale);
        for k in 0..20_000 {
            let scale = [1e-3, 0.1, 1.0, 10.0][k % 4];
            let (xa, xb, point) = (vec(2.0), vec(2.0), vec(2.0));
            let (va, vb, wa, wb) = (vec(scale), vec(scale), vec(scale), vec(scale));
            let (aa, ab) = (vec(10.0), vec(10.0));
            let n = vec(1.0).normalize();
            let dt = [1e-3, 1.0 / 60.0, 0.1][k % 3];
            let lead: f64 = [-0.5, 0.0, 0.5][(k / 3) % 3];
            let mut stage = ContactStage::default();
            let body = |v, w, accel| SolverBody { v, w, accel, ..SolverBody::FIXED };
            stage.bodies = vec![body(va, wa, aa), body(vb, wb, ab)];
            stage.positions = vec![xa, xb];
            let bound = stage.approach_bound(0, 1, dt, lead);
            let (r_a, r_b) = (point - xa, point - xb);
            let u0 = (vb + wb.cross(r_b)) - (va + wa.cross(r_a)) + lead * dt * (ab - aa);
            for t in [0.0, 0.5 * dt, dt] {
                // the bound says "below" for no impact speed at or under the contact's speed
                let speed = -(u0 + (ab - aa) * t).dot(n);
                assert!(!bound.below(point, speed.abs()), "case {k}: the bound is below the speed {speed}");
            }
        }
        // a box at rest on the ground at dt = 1/60 under semi-implicit Euler: skipped at 0.5 m/s
        let resting = ApproachBound {
            centres: (DVec3::ZERO, DVec3::new(0.0, 0.0, 0.5)),
            linear: 9.81 * 1.5 / 60.0,
            angular: (0.0, 1e-6),
        };
        assert!(resting.below(DVec3::new(0.5, 0.5, 0.0), 0.5));
    }

    /// `all_below` (the check that lets `impacts` skip a pair) says "below" only when every one of
    /// the pair's points does, the margin included: random pairs of up to eight points, at impact
    /// speeds near the largest point bound, where the two checks are closest.
    #[test]
    fn a_pair_below_at_its_farthest_points_is_below_at_each() {
        let mut next = uniform(0x9e37_79b9_7f4a_7c15);
        let (mut skipped, mut kept) = (0, 0);
        for k in 0..20_000 {
            let centres = (DVec3::new(next(), next(), next()), DVec3::new(next(), next(), 1.0 + next()));
            let bound = ApproachBound { centres, linear: 0.3 * next(), angular: (0.2 * next(), 0.2 * next()) };
            let points: Vec<DVec3> =
                (0..1 + k % 8).map(|_| DVec3::new(2.0 * next() - 0.5, 2.0 * next() - 0.5, 1.0)).collect();
            // an impact speed just above or below the largest of the points' bounds
            let largest = points
                .iter()
                .map(|&p| {
                    bound.linear
                        + bound.angular.0 * (p - centres.0).length()
                        + bound.angular.1 * (p - centres.1).length()
                })
                .fold(0.0, f64::max);
            let impact_speed = largest * (1.0 + 1e-9) * (1.0 + [1e-15, -1e-15, 1e-3, -1e-3][k % 4]);
            if bound.all_below(points.iter().copied(), impact_speed) {
                skipped += 1;
                assert!(points.iter().all(|&p| bound.below(p, impact_speed)), "case {k}");
            } else {
                kept += 1;
            }
        }
        assert!(skipped > 5_000 && kept > 5_000, "skipped {skipped}, kept {kept}");
    }

    #[test]
    fn closing_time_of_a_falling_gap() {
        // 1 cm closed at 1 m/s with 10 m/s² towards: 0.01 = t + 5 t² → t = (−1 + √1.2)/10
        let t = closing_time(0.01, 1.0, 10.0, 0.0, 1.0).unwrap();
        assert!((t - (-1.0 + 1.2f64.sqrt()) / 10.0).abs() < 1e-15);
        // not within the step
        assert_eq!(closing_time(0.01, 1.0, 0.0, 0.0, 0.005), None);
        // separating
        assert_eq!(closing_time(0.01, -1.0, 0.0, 0.0, 1.0), None);
        assert_eq!(closing_time(-0.01, -1.0, 0.0, 0.0, 1.0), None);
    }

    #[test]
    fn closing_time_after_the_latest_collision() {
        // a gap that the current velocities would have closed before t_min: closed at t_min
        assert_eq!(closing_time(0.001, 1.0, 0.0, 0.002, 0.01), Some(0.002));
        // still open at t_min = 0.002 (gap 0.003 − 0.002 = 0.001): closes 0.001 s later
        let t = closing_time(0.003, 1.0, 0.0, 0.002, 0.01).unwrap();
        assert!((t - 0.003).abs() < 1e-15);
    }
}
