//! The broad phase: sort and sweep over the bodies' swept boxes.
//!
//! Each body's box is its shape's box at the start of the step grown by the distance it can travel
//! in the step (`|v| dt + |ω| ρ dt + ½ |g_body| dt²`, `ρ` the bounding radius) and half the
//! prediction margin. The boxes are sorted by their lower bound along one axis and swept: a box
//! meets the boxes after it whose lower bound is below its upper bound, and of those the ones that
//! overlap on the two other axes are the candidate pairs (Baraff 1992, ch. 6).
//!
//! - **The axis** is the one along which the boxes' centres are most spread (largest variance,
//!   `Σ c² / n − (Σ c / n)²`): along it the fewest boxes overlap in projection, so the sweep visits
//!   the fewest non-pairs. A new axis is taken only when its spread exceeds the current one's by a
//!   quarter, so that the axis does not flicker.
//! - **The sort** starts from the last step's order and is an insertion sort: bodies move little in
//!   a step, the order is nearly sorted, and the cost is `O(n + swaps)` rather than `O(n log n)`.
//!   A new axis or a new set of bodies sorts from scratch.
//! - **The sweep** runs over a copy of the boxes in sorted order (contiguous memory), cut into
//!   chunks on the world's threads when there are some.
//!
//! The candidate pairs are then sorted, so they — and everything after them — do not depend on the
//! axis, the order of equal bounds, or the chunks. Planes (unbounded) are paired with every free
//! body; pairs of fixed bodies are never candidates.
//!
//! References: D. Baraff, "Dynamic simulation of non-penetrating rigid bodies" (1992), ch. 6;
//! G. van den Bergen, *Collision Detection in Interactive 3D Environments* (2004), §7.2.

use super::{parallel, Colliders};
use crate::body::RigidBody;
use crate::math::DVec3;
use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};
use rayon::prelude::*;

/// A new sweep axis is taken when the boxes' spread along it exceeds the current axis's by this
/// factor.
const AXIS_HYSTERESIS: f64 = 1.25;

/// Fewer boxes than this are swept on the caller's thread.
const MIN_PARALLEL_BOXES: usize = 256;

/// A swept box in sorted order: its bounds along the sweep axis first, then the two others.
#[derive(Debug, Clone, Copy)]
pub(super) struct SweepBox {
    /// Lower and upper bound along the sweep axis (m).
    lo: f64,
    hi: f64,
    /// Lower and upper bounds along the two other axes (m).
    mins: [f64; 2],
    maxs: [f64; 2],
    body: usize,
    fixed: bool,
}

impl SweepBox {
    #[inline]
    fn meets(&self, other: &SweepBox) -> bool {
        self.mins[0] <= other.maxs[0]
            && other.mins[0] <= self.maxs[0]
            && self.mins[1] <= other.maxs[1]
            && other.mins[1] <= self.maxs[1]
    }
}

/// The candidate pairs of box `k` of `boxes` (sorted by `lo`) with the boxes after it, appended
/// to `pairs` as `(min, max)` body indices.
#[inline]
fn sweep_one(boxes: &[SweepBox], k: usize, pairs: &mut Vec<(usize, usize)>) {
    let a = &boxes[k];
    for b in &boxes[k + 1..] {
        if b.lo > a.hi {
            break;
        }
        if !(a.fixed && b.fixed) && a.meets(b) {
            pairs.push((a.body.min(b.body), a.body.max(b.body)));
        }
    }
}

impl Colliders {
    /// Fills `self.aabbs`, `self.sweeps` and the candidate pairs `self.pairs` (sorted) of the step.
    pub(super) fn broad_phase(&mut self, bodies: &[RigidBody], dt: f64, gravity: DVec3, slop: f64) {
        let n = bodies.len().min(self.shapes.len());
        self.aabbs.clear();
        self.sweeps.clear();
        self.pairs.clear();
        // ½ |g| dt², times each body's |gravity_scale|
        let fall = 0.5 * gravity.length() * dt * dt;
        let (mut sum, mut sum2, mut boxed) = (DVec3::ZERO, DVec3::ZERO, 0usize);
        for i in 0..n {
            let b = &bodies[i];
            let sweep = if b.fixed {
                0.0
            } else {
                (b.state.velocity.length() + b.state.omega_body.length() * self.radii[i]) * dt
                    + fall * b.gravity_scale.abs()
            };
            self.sweeps.push(sweep + 0.5 * slop);
            let aabb = match &self.shapes[i] {
                Some(s) if !self.planes.contains(&i) => {
                    let pose = self.pose(bodies, i);
                    let aabb = s.compute_aabb(&pose).loosened(sweep + 0.5 * slop);
                    let centre = 0.5 * (aabb.mins + aabb.maxs);
                    sum += centre;
                    sum2 += centre * centre;
                    boxed += 1;
                    aabb
                }
                _ => Aabb::new_invalid(),
            };
            self.aabbs.push(aabb);
        }
        self.choose_axis(sum, sum2, boxed);
        self.sort_boxes(bodies, boxed);
        self.sweep();
        for &p in &self.planes {
            for (i, body) in bodies.iter().enumerate().take(n) {
                if i != p && !body.fixed && self.shapes[i].is_some() && !self.planes.contains(&i) {
                    self.pairs.push((p, i));
                }
            }
        }
        if !self.excluded.is_empty() {
            let excluded = &self.excluded;
            self.pairs.retain(|&(i, j)| excluded.binary_search(&(i.min(j), i.max(j))).is_err());
        }
        // pairs in index order: the contacts come out grouped by pair, in the same order every run
        self.pairs.sort_unstable();
    }

    /// Takes the axis of the largest spread of the box centres (sums `sum`, `sum2` of `count`
    /// centres and of their squares), unless it is not a quarter above the current axis's.
    fn choose_axis(&mut self, sum: DVec3, sum2: DVec3, count: usize) {
        if count == 0 {
            return;
        }
        let mean = sum / count as f64;
        let spread = (sum2 / count as f64 - mean * mean).to_array();
        let widest = (0..3).fold(0, |best, k| if spread[k] > spread[best] { k } else { best });
        if spread[widest] > AXIS_HYSTERESIS * spread[self.axis] {
            self.axis = widest;
            // another axis: the last order says nothing of this one
            self.order.clear();
        }
    }

    /// Sorts the bodies with a box by their lower bound along the axis — an insertion sort from the
    /// last step's order when it holds the same bodies, else a full sort — and copies their boxes
    /// into `self.sorted` in that order.
    fn sort_boxes(&mut self, bodies: &[RigidBody], boxed: usize) {
        let (axis, aabbs) = (self.axis, &self.aabbs);
        let lo = |i: usize| aabbs[i].mins[axis];
        if self.order.len() == boxed {
            // insertion sort: moves each body back past the ones with a larger bound
            for k in 1..self.order.len() {
                let i = self.order[k];
                let key = lo(i);
                let mut m = k;
                while m > 0 && lo(self.order[m - 1]) > key {
                    self.order[m] = self.order[m - 1];
                    m -= 1;
                }
                self.order[m] = i;
            }
        } else {
            self.order.clear();
            let planes = &self.planes;
            self.order.extend((0..aabbs.len()).filter(|&i| self.shapes[i].is_some() && !planes.contains(&i)));
            self.order.sort_unstable_by(|&i, &j| lo(i).total_cmp(&lo(j)));
        }
        let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
        self.sorted.clear();
        self.sorted.extend(self.order.iter().map(|&i| {
            let b = &aabbs[i];
            SweepBox {
                lo: b.mins[axis],
                hi: b.maxs[axis],
                mins: [b.mins[u], b.mins[w]],
                maxs: [b.maxs[u], b.maxs[w]],
                body: i,
                fixed: bodies[i].fixed,
            }
        }));
    }

    /// The candidate pairs of the sorted boxes into `self.pairs`: on the pool's threads in chunks
    /// when there is a pool and enough boxes, else in one pass.
    fn sweep(&mut self) {
        let boxes = &self.sorted;
        match &self.pool {
            Some(pool) if boxes.len() >= MIN_PARALLEL_BOXES => {
                let len = parallel::chunk_len(boxes.len(), pool.current_num_threads());
                let count = boxes.len().div_ceil(len);
                let buffers = &mut self.chunks.pairs;
                if buffers.len() < count {
                    buffers.resize_with(count, Vec::new);
                }
                pool.install(|| {
                    buffers[..count].par_iter_mut().enumerate().for_each(|(c, pairs)| {
                        pairs.clear();
                        for k in c * len..((c + 1) * len).min(boxes.len()) {
                            sweep_one(boxes, k, pairs);
                        }
                    });
                });
                for pairs in &buffers[..count] {
                    self.pairs.extend_from_slice(pairs);
                }
            }
            _ => {
                for k in 0..boxes.len() {
                    sweep_one(boxes, k, &mut self.pairs);
                }
            }
        }
    }
}
