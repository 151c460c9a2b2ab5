//! Fat boxes: the broad phase's pairs kept from step to step while every body stays inside a box a
//! little larger than its swept box (the "fat" boxes of Box2D's dynamic tree and Rapier's
//! broad phase), the step's pairs then found among the kept ones.
//!
//! The invariant: `pairs` holds every pair `(i, j)`, `i < j`, of bodies with a box, not both
//! resting, whose fat boxes overlap (closed on the three axes), sorted. While every body's swept box
//! lies inside its fat box, two swept boxes that overlap have fat boxes that overlap, so the step's
//! pairs — the pairs of overlapping swept boxes — are the kept pairs whose swept boxes overlap: a
//! filter of `pairs`, in order. They are the grid's pairs bit for bit, whatever the fat boxes.
//!
//! Keeping the invariant: a body whose swept box left its fat box takes a new fat box (its swept box
//! grown by [`FAT_FRACTION`] of its width on every side; a resting body's is its swept box, which
//! does not move), its kept pairs are dropped and its pairs
//! are found again against every other fat box, and merged back in order; when more than
//! [`MAX_REFRESHED`] bodies left in one step, or the bodies with a box or which of them rest
//! changed, every fat box is made again and the grid finds their pairs. Where the fat boxes made in
//! one step do not last the next (everything falling fast), the grid runs on the swept boxes alone
//! for 1, 3, 7, … 63 steps before fat boxes are tried again ([`MAX_BACKOFF`]).
//!
//! Cost of a step in which no body left: one containment test per body and one box test per kept
//! pair, against the grid's cells, counting sorts and neighbour runs (the 1,000 balls awake: the
//! broad phase 87–89 → 50–58 µs per step, most of what is left making the swept boxes).
//!
//! Reference: E. Catto, Box2D v3 (`b2_aabbMargin`, the enlarged boxes of its dynamic tree).

use super::{overlap, Grid};
use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};

/// A fat box is the swept box grown by this fraction of the swept box's widest side, on every side.
pub const FAT_FRACTION: f64 = 0.05;

/// When more bodies than this left their fat boxes in a step, the grid finds every pair again
/// (each body that left is tested against every other box: a few cost less than the grid).
pub const MAX_REFRESHED: usize = 8;

/// After this many steps in a row whose fat boxes had to be made again, the grid runs on the swept
/// boxes alone for `2^k − 1` steps (`k` up to this): where everything moves fast (bodies falling),
/// making fat boxes that no step keeps would cost more than the grid alone.
pub const MAX_BACKOFF: u32 = 6;

/// The fat boxes and their pairs (module documentation), kept from step to step.
#[derive(Debug, Clone, Default)]
pub(super) struct FatBoxes {
    /// Whether `boxes` and `pairs` hold the invariant for `boxed` and `rests`.
    valid: bool,
    /// Whether the last step made every fat box again; how many times in a row that was undone by
    /// the next step (the back-off's exponent), and the steps left to run the grid alone.
    made_last: bool,
    misses: u32,
    skip: u32,
    /// Each body's fat box (those of the bodies with a box), world frame (m).
    boxes: Vec<Aabb>,
    /// The bodies with a box, and whether each body rests (fixed or asleep), when the pairs were made.
    boxed: Vec<usize>,
    rests: Vec<bool>,
    /// The pairs of overlapping fat boxes, sorted.
    pairs: Vec<(usize, usize)>,
    /// The bodies that left their fat boxes in this step, and a flag per body.
    left: Vec<usize>,
    is_left: Vec<bool>,
    /// The pairs of the bodies that left, and the merged list (buffers).
    fresh: Vec<(usize, usize)>,
    merged: Vec<(usize, usize)>,
}

/// `outer` holds `inner` (closed); `false` if either has a NaN bound.
#[inline]
fn contains(outer: &Aabb, inner: &Aabb) -> bool {
    (outer.mins.x <= inner.mins.x)
        & (outer.mins.y <= inner.mins.y)
        & (outer.mins.z <= inner.mins.z)
        & (inner.maxs.x <= outer.maxs.x)
        & (inner.maxs.y <= outer.maxs.y)
        & (inner.maxs.z <= outer.maxs.z)
}

/// The fat box of the swept box `aabb` of a body that moves (`rests`: fixed or asleep, the box
/// itself: it does not move, and a wall's box grown by a fraction of its length would meet every
/// body near it); `None` for a box with a bound that is not finite (the grid tests those).
fn fattened(aabb: &Aabb, rests: bool) -> Option<Aabb> {
    let finite = aabb.mins.is_finite() && aabb.maxs.is_finite();
    let margin = if rests { 0.0 } else { FAT_FRACTION * (aabb.maxs - aabb.mins).max_element() };
    finite.then(|| aabb.loosened(margin))
}

impl Grid {
    /// The step's pairs of overlapping swept boxes `aabbs` (not both resting) from the kept fat
    /// boxes, sorted by first body into `firsts`/`seconds` for `n` bodies, as
    /// [`sort_pairs`](Grid::sort_pairs) leaves them; `self.boxed` and `self.fixed` filled for the
    /// step. `false` when it cannot say (more than `budget` pairs, or a box that is not finite):
    /// the caller runs the grid on the swept boxes. `large_width` (m): the grid's large boxes.
    pub(super) fn pairs_from_fat(&mut self, aabbs: &[Aabb], n: usize, large_width: f64, budget: usize) -> bool {
        let mut fat = std::mem::take(&mut self.fat);
        let found = self.pairs_from(&mut fat, aabbs, n, large_width, budget);
        self.fat = fat;
        found
    }

    fn pairs_from(&mut self, fat: &mut FatBoxes, aabbs: &[Aabb], n: usize, large_width: f64, budget: usize) -> bool {
        if fat.skip > 0 {
            fat.skip -= 1;
            fat.valid = false;
            return false;
        }
        let current = fat.valid && fat.boxes.len() == n && fat.boxed == self.boxed && fat.rests == self.fixed;
        fat.left.clear();
        if current {
            for &i in &self.boxed {
                if !contains(&fat.boxes[i], &aabbs[i]) {
                    fat.left.push(i);
                    if fat.left.len() > MAX_REFRESHED {
                        break;
                    }
                }
            }
        }
        let make = !current || fat.left.len() > MAX_REFRESHED;
        if make && fat.made_last {
            // the fat boxes made in the last step did not last one step: back off
            fat.misses = (fat.misses + 1).min(MAX_BACKOFF);
            fat.skip = (1 << fat.misses) - 1;
            fat.made_last = false;
            fat.valid = false;
            return false;
        }
        if !make {
            fat.misses = 0;
        }
        fat.made_last = make;
        let refreshed = if make {
            self.make_fat(fat, aabbs, n, large_width, budget)
        } else {
            fat.left.is_empty() || self.refresh(fat, aabbs)
        };
        if !refreshed {
            fat.valid = false;
            return false;
        }
        // the step's pairs: the kept pairs whose swept boxes overlap, in order
        self.seconds.clear();
        self.firsts.clear();
        self.firsts.resize(n + 2, 0);
        let mut next = 0;
        for &(i, j) in &fat.pairs {
            if overlap(&aabbs[i], &aabbs[j]) {
                while next <= i {
                    self.firsts[next] = self.seconds.len();
                    next += 1;
                }
                self.seconds.push(j);
            }
        }
        for first in &mut self.firsts[next..] {
            *first = self.seconds.len();
        }
        self.seconds.len() <= budget
    }

    /// Every fat box made from `aabbs` and their pairs found by the grid. `false` when a box is not
    /// finite or the fat pairs went over twice the budget.
    fn make_fat(&mut self, fat: &mut FatBoxes, aabbs: &[Aabb], n: usize, large_width: f64, budget: usize) -> bool {
        fat.boxes.clear();
        fat.boxes.resize(n, Aabb::new_invalid());
        for &i in &self.boxed {
            let Some(b) = fattened(&aabbs[i], self.fixed[i]) else { return false };
            fat.boxes[i] = b;
        }
        // the widths grow by 1 + 2 FAT_FRACTION: the same boxes are large
        if !self.find_pairs(&fat.boxes, large_width * (1.0 + 2.0 * FAT_FRACTION), budget.saturating_mul(2)) {
            return false;
        }
        self.sort_pairs(n);
        fat.pairs.clear();
        for i in 0..n {
            fat.pairs.extend(self.seconds[self.firsts[i]..self.firsts[i + 1]].iter().map(|&j| (i, j)));
        }
        fat.boxed.clone_from(&self.boxed);
        fat.rests.clone_from(&self.fixed);
        fat.valid = true;
        true
    }

    /// New fat boxes for the bodies in `fat.left` (in index order), their pairs found against every
    /// fat box and merged into `fat.pairs`. `false` when one of their boxes is not finite.
    fn refresh(&mut self, fat: &mut FatBoxes, aabbs: &[Aabb]) -> bool {
        fat.is_left.resize(fat.boxes.len(), false);
        for &m in &fat.left {
            let Some(b) = fattened(&aabbs[m], self.fixed[m]) else {
                for &k in &fat.left {
                    fat.is_left[k] = false;
                }
                return false;
            };
            fat.boxes[m] = b;
            fat.is_left[m] = true;
        }
        fat.fresh.clear();
        for &m in &fat.left {
            for &k in &self.boxed {
                // a pair of two that left is found once, from the lower one
                if k == m || (fat.is_left[k] && k < m) {
                    continue;
                }
                if overlap(&fat.boxes[m], &fat.boxes[k]) && !(self.fixed[m] && self.fixed[k]) {
                    fat.fresh.push((m.min(k), m.max(k)));
                }
            }
        }
        fat.fresh.sort_unstable();
        // the kept pairs of the others and the new ones, merged in order
        fat.merged.clear();
        let mut fresh = fat.fresh.iter().copied().peekable();
        for &(i, j) in &fat.pairs {
            if fat.is_left[i] || fat.is_left[j] {
                continue;
            }
            while let Some(p) = fresh.next_if(|&p| p < (i, j)) {
                fat.merged.push(p);
            }
            fat.merged.push((i, j));
        }
        fat.merged.extend(fresh);
        std::mem::swap(&mut fat.pairs, &mut fat.merged);
        for &m in &fat.left {
            fat.is_left[m] = false;
        }
        true
    }
}
