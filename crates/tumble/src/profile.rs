//! Where the time of a step goes: wall time per stage, filled only when asked
//! ([`World::set_profiling`](crate::world::World::set_profiling)). It sits below the world, the
//! contact stage and the collision detection, which all fill it (the world calls down into them).
//!
//! Off (the default), a stage costs one test of an `Option` per step and nothing is stored; on, it
//! costs two reads of the monotonic clock per stage and step (about 50 ns), and the figures are
//! sums since profiling was switched on, so that a caller divides by [`Profile::steps`].

use std::time::Instant;

/// Wall time per stage of the step, summed over [`steps`](Profile::steps) steps (s), and the
/// narrow phase's counts over the same steps.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Profile {
    /// Steps taken since profiling was switched on.
    pub steps: u64,
    /// Broad phase: swept boxes, the grid's pairs (s).
    pub broad_phase: f64,
    /// Narrow phase: contact manifolds of the candidate pairs (s).
    pub narrow_phase: f64,
    /// Collisions: the solver's copy of the bodies and the time-ordered impacts (s).
    pub impacts: f64,
    /// Resting contact: building the constraints and the substeps of the soft solver (s).
    pub resting: f64,
    /// Free-body integration, robots, and moving the held bodies after it (s).
    pub integration: f64,
    /// Of `narrow_phase`: placing the robots' link shapes and their contacts (s).
    pub link_detect: f64,
    /// Of `impacts`: the robots' contact rows: `M` by CRBA, its `LᵀDL` factor, the free
    /// acceleration `a₀`, each point's `J_c`, `W = M⁻¹ J_cᵀ` and `K`, the joint-limit rows (s).
    pub link_rows: f64,
    /// Of `integration`: the robots' own steps (joint forces, ABA, the integrator, the limits'
    /// end-of-step phase) (s).
    pub robot_dynamics: f64,
    /// Of `integration`: the robots' forward kinematics of the new state, their energy and
    /// momentum (s).
    pub robot_bookkeeping: f64,
    /// The whole step (s).
    pub step: f64,
    /// Candidate pairs of convex shapes given to the narrow phase.
    pub pairs: u64,
    /// Of these, the pairs whose manifold was reused (they had barely moved since it was made).
    pub reused: u64,
    /// Contact points found.
    pub contacts: u64,
    /// Contact points of robot links found.
    pub link_contacts: u64,
}

impl Profile {
    /// The time per step of each stage (s), and the counts per step.
    pub fn per_step(&self) -> PerStep {
        let n = self.steps.max(1) as f64;
        PerStep {
            broad_phase: self.broad_phase / n,
            narrow_phase: self.narrow_phase / n,
            impacts: self.impacts / n,
            resting: self.resting / n,
            integration: self.integration / n,
            link_detect: self.link_detect / n,
            link_rows: self.link_rows / n,
            robot_dynamics: self.robot_dynamics / n,
            robot_bookkeeping: self.robot_bookkeeping / n,
            step: self.step / n,
            pairs: self.pairs as f64 / n,
            reused: self.reused as f64 / n,
            contacts: self.contacts as f64 / n,
            link_contacts: self.link_contacts as f64 / n,
        }
    }

    /// Adds the contact stage's times and counts to this one's.
    pub(crate) fn add_contact_stage(&mut self, other: &Profile) {
        self.broad_phase += other.broad_phase;
        self.narrow_phase += other.narrow_phase;
        self.impacts += other.impacts;
        self.resting += other.resting;
        self.link_detect += other.link_detect;
        self.link_rows += other.link_rows;
        self.pairs += other.pairs;
        self.reused += other.reused;
        self.contacts += other.contacts;
        self.link_contacts += other.link_contacts;
    }
}

/// [`Profile`] divided by its step count: seconds per step, counts per step.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
#[allow(missing_docs)]
pub struct PerStep {
    pub broad_phase: f64,
    pub narrow_phase: f64,
    pub impacts: f64,
    pub resting: f64,
    pub integration: f64,
    pub link_detect: f64,
    pub link_rows: f64,
    pub robot_dynamics: f64,
    pub robot_bookkeeping: f64,
    pub step: f64,
    pub pairs: f64,
    pub reused: f64,
    pub contacts: f64,
    pub link_contacts: f64,
}

/// A stopwatch that reads the clock only when profiling is on.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Clock(Option<Instant>);

impl Clock {
    /// Started now when `on`, else a stopwatch that never reads the clock.
    #[inline]
    pub(crate) fn start(on: bool) -> Self {
        Self(if on { Some(Instant::now()) } else { None })
    }

    /// Seconds since the start or the last lap, and restarts; 0 when off.
    #[inline]
    pub(crate) fn lap(&mut self) -> f64 {
        match &mut self.0 {
            Some(t) => {
                let now = Instant::now();
                let s = (now - *t).as_secs_f64();
                *t = now;
                s
            }
            None => 0.0,
        }
    }
}
