//! A fingerprint of the world's state: the bit patterns of every number that moves.
//!
//! [`World::state_hash`] hashes, in scene order, each moving body's stored state — position,
//! orientation (its principal axes), velocity and body-frame angular velocity — then each robot's
//! `q` and `v`, with 64-bit FNV-1a over the bytes of each `f64`'s bits (little-endian). Equal hashes
//! mean, to a chance of 2⁻⁶⁴, bit-identical states: the check that a change left the numbers alone
//! (golden hashes in `tests/golden_hash.rs`) and that runs with any number of threads agree. It
//! depends on nothing but the numbers (no process-wide seed), so it is the same on every run and
//! every machine that computes the same state.

use super::World;
use crate::math::StateHasher;

impl World {
    /// The fingerprint of the current state (see the module documentation): equal for bit-identical
    /// states of the same scene.
    pub fn state_hash(&self) -> u64 {
        let mut h = StateHasher::default();
        for body in self.free_bodies() {
            let s = &body.state;
            h.add_all(&s.position.to_array());
            h.add_all(&[s.orientation.w, s.orientation.x, s.orientation.y, s.orientation.z]);
            h.add_all(&s.velocity.to_array());
            h.add_all(&s.omega_body.to_array());
        }
        for robot in &self.robots {
            h.add_all(robot.q());
            h.add_all(robot.v());
        }
        h.finish()
    }
}
