//! The narrow phase on the world's threads.
//!
//! The candidate pairs of convex shapes are cut into contiguous chunks, a few per thread; each chunk
//! writes the contacts of its pairs, in pair order, into its own buffer and notes where each pair's
//! contacts start and end (its slot). Each pair's kept manifold is its own entry, touched by one
//! chunk only. The contacts are then gathered on the caller's thread in pair order — a pair with a
//! composite shape computed there, in its place, as its caches are shared in a map — so the list is
//! the one the single-threaded loop gives, bit for bit, whatever the number of threads or chunks:
//! each pair's computation is the same function of the same inputs, and only the order of the work
//! changed.
//!
//! The buffers and slots are kept from step to step (no allocation once grown).

use super::pairs::{PairManifold, PairManifolds};
use super::{Colliders, Contact};
use crate::body::RigidBody;
use rayon::prelude::*;

/// Fewer candidate pairs than this are done on the caller's thread
/// ([`World::set_parallel_min_pairs`](crate::World::set_parallel_min_pairs) changes it). On the 2-vCPU machine the figures come from,
/// handing the narrow phase to the pool and waiting for it cost 0.3–0.4 ms per step: the pyramid's
/// 780 pairs (0.22 ms on one thread) took 2.8× as long on two, the balls' 1,900 (0.30 ms) 2.3×
/// (`examples/threads.rs`); the pile's 12,000 (about 5 ms) came out between 1.16× and 1.01×, within
/// the machine's noise. So only scenes with thousands of pairs go to the pool (`docs/contact.md`,
/// "Many cores").
pub(super) const MIN_PAIRS: usize = 4096;

/// Chunks per thread: enough for the threads to even out pairs of unequal cost.
const CHUNKS_PER_THREAD: usize = 4;

/// Where a pair's contacts are in its chunk's buffer, and whether its manifold was reused.
#[derive(Debug, Clone, Copy, Default)]
struct Slot {
    start: usize,
    end: usize,
    reused: bool,
}

/// The chunks' buffers, kept from step to step.
#[derive(Debug, Clone, Default)]
pub(super) struct Chunks {
    /// The contacts of each chunk, in pair order.
    contacts: Vec<Vec<Contact>>,
    /// One slot per convex pair, in pair order.
    slots: Vec<Slot>,
}

/// The length of the chunks that cut `n` items for `threads` threads: at least 1.
fn chunk_len(n: usize, threads: usize) -> usize {
    n.div_ceil((threads * CHUNKS_PER_THREAD).max(1)).max(1)
}

impl Colliders {
    /// The narrow phase of `pairs` (sorted) on `pool`'s threads, the contacts appended to `out` in
    /// pair order; the pairs of convex shapes and how many of their manifolds were reused.
    pub(super) fn narrow_phase_parallel(
        &mut self,
        pool: &rayon::ThreadPool,
        bodies: &[RigidBody],
        pairs: &[(usize, usize)],
        manifolds: &mut PairManifolds,
        out: &mut Vec<Contact>,
    ) -> (u64, u64) {
        // this step's entries, in pair order, before the work is shared out
        for &(i, j) in pairs {
            if !(self.composite[i] || self.composite[j]) {
                manifolds.entry((i, j));
            }
        }
        let entries: &mut [PairManifold] = manifolds.current_mut();
        let n = entries.len();
        let len = chunk_len(n, pool.current_num_threads());
        let count = n.div_ceil(len);
        let mut chunks = std::mem::take(&mut self.chunks);
        if chunks.contacts.len() < count {
            chunks.contacts.resize_with(count, Vec::new);
        }
        chunks.slots.clear();
        chunks.slots.resize(n, Slot::default());
        let this = &*self;
        pool.install(|| {
            entries
                .par_chunks_mut(len)
                .zip(chunks.slots.par_chunks_mut(len))
                .zip(&mut chunks.contacts[..count])
                .for_each(|((entries, slots), buffer)| {
                    buffer.clear();
                    for (entry, slot) in entries.iter_mut().zip(slots) {
                        let start = buffer.len();
                        let reused = this.narrow_phase(bodies, entry, buffer);
                        *slot = Slot { start, end: buffer.len(), reused };
                    }
                });
        });
        // gathered in pair order; the composite pairs in their places
        let (mut convex, mut reused) = (0, 0);
        for &(i, j) in pairs {
            if self.composite[i] || self.composite[j] {
                self.narrow_phase_composite(bodies, i, j, out);
                continue;
            }
            let slot = chunks.slots[convex];
            out.extend_from_slice(&chunks.contacts[convex / len][slot.start..slot.end]);
            reused += u64::from(slot.reused);
            convex += 1;
        }
        self.chunks = chunks;
        (convex as u64, reused)
    }
}
