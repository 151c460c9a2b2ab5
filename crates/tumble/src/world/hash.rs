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

/// FNV-1a, 64 bits: offset basis and prime.
const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;
const FNV_PRIME: u64 = 0x0000_0100_0000_01b3;

/// 64-bit FNV-1a over the bit patterns of a sequence of `f64`s.
#[derive(Debug, Clone, Copy)]
pub struct StateHasher(u64);

impl Default for StateHasher {
    fn default() -> Self {
        Self(FNV_OFFSET)
    }
}

impl StateHasher {
    /// Adds the bits of `x` (so `0.0` and `−0.0`, and NaNs of different payloads, differ).
    #[inline]
    pub fn add(&mut self, x: f64) {
        for byte in x.to_bits().to_le_bytes() {
            self.0 = (self.0 ^ u64::from(byte)).wrapping_mul(FNV_PRIME);
        }
    }

    /// Adds every number of `xs`, in order.
    pub fn add_all(&mut self, xs: &[f64]) {
        for &x in xs {
            self.add(x);
        }
    }

    /// The hash so far.
    pub fn finish(&self) -> u64 {
        self.0
    }
}

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
