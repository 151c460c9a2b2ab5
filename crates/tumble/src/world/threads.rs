//! The world's threads: a rayon pool for the collision detection, built when more than one thread
//! is asked ([`WorldConfig::threads`](super::WorldConfig::threads), [`World::set_threads`]).
//!
//! With one thread no pool exists and no rayon code runs: the step is the single-threaded one. With
//! more, the narrow phase splits its work into chunks whose results are gathered in pair order (the
//! broad phase, a few tens of µs, stays on the caller's thread), so the contacts, and every number after them, are the same
//! bit for bit for any number of threads (`tests/golden_hash.rs`).
//!
//! The pool is built at the first step of a world of at least [`MIN_BODIES`] bodies and kept while
//! the count stays the same; a cloned world shares it. A world stepped from inside another rayon
//! pool (many worlds stepped in parallel) does its collision detection on the caller's thread: one
//! level of parallelism is enough, and nesting would only oversubscribe the cores.

use super::World;
use std::sync::Arc;

/// Worlds with fewer bodies than this detect their contacts on the caller's thread, and build no
/// pool: their few pairs are done before the threads would have started.
pub(super) const MIN_BODIES: usize = 64;

/// The pool and the thread count it was built for.
#[derive(Debug, Clone, Default)]
pub(super) struct Threads {
    /// `None`: one thread (or the pool could not be built: the step runs on the caller's thread).
    pool: Option<Arc<rayon::ThreadPool>>,
    /// The setting the pool was last settled for (`None`: never).
    built_for: Option<usize>,
    /// The candidate pairs from which the narrow phase goes to the pool (`None`: the default).
    pub(super) min_pairs: Option<usize>,
}

/// The number of threads a setting means: `0` is one per core.
pub(super) fn effective(threads: usize) -> usize {
    if threads == 0 {
        std::thread::available_parallelism().map_or(1, |n| n.get())
    } else {
        threads
    }
}

impl Threads {
    /// The pool for `threads` (the setting; 0 one per core), built or rebuilt when the setting
    /// changed; `None` for one thread, or when called from inside another rayon pool.
    pub(super) fn pool(&mut self, threads: usize) -> Option<&Arc<rayon::ThreadPool>> {
        if self.built_for != Some(threads) {
            let n = effective(threads);
            self.pool = if n > 1 {
                rayon::ThreadPoolBuilder::new()
                    .num_threads(n)
                    .thread_name(|i| format!("tumble-{i}"))
                    .build()
                    .ok()
                    .map(Arc::new)
            } else {
                None
            };
            self.built_for = Some(threads);
        }
        // only reached with a pool: with one thread, no rayon call at all
        let pool = self.pool.as_ref()?;
        if rayon::current_thread_index().is_some() {
            return None;
        }
        Some(pool)
    }
}

impl World {
    /// Sets the number of threads of the collision detection: 0 for one per core, 1 for the
    /// caller's thread only. The results do not depend on it.
    pub fn set_threads(&mut self, threads: usize) {
        self.config.threads = threads;
    }

    /// Sends the narrow phase to the thread pool (when there is one) from `pairs` candidate pairs
    /// on, instead of the default 4,096 (below it, handing the work over costs more than it saves;
    /// `docs/contact.md`, "Many cores"). 0: always. The contacts are the same bit for bit either
    /// way: the tests use it to run small scenes on the threads.
    pub fn set_parallel_min_pairs(&mut self, pairs: usize) {
        self.threads.min_pairs = Some(pairs);
    }

    /// The number of threads the collision detection uses: the setting, 0 read as the number of
    /// cores.
    pub fn threads(&self) -> usize {
        effective(self.config.threads)
    }
}
