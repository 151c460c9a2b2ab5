//! 64-bit FNV-1a over the bit patterns of `f64`s: the fingerprint behind `World::state_hash` and
//! the sleep stage's snapshot of a body's loads. It depends on nothing but the numbers (no
//! process-wide seed), so it is the same on every run and every machine.

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
