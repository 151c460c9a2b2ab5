//! The broad phase: a uniform grid over the bodies' swept boxes.
//!
//! What it computes: the candidate pairs of the step, every pair of bodies `(i, j)` whose swept
//! boxes overlap, closed on all three axes,
//!
//! `lo_i,k ≤ hi_j,k ∧ lo_j,k ≤ hi_i,k` for `k = x, y, z`,
//!
//! without pairs of two fixed bodies; each plane (unbounded) paired with every free body whose
//! box reaches within half the prediction margin of it; the scene's excluded pairs left out; sorted
//! by `(i, j)`. A body's box is its shape's box at the start of the step grown by the distance it can travel in the step (`|v| dt + |ω| ρ dt +
//! ½ |g_body| dt²`, `ρ` the bounding radius) and half the prediction margin. The pairs depend on
//! the boxes alone, not on how they were found: the grid below gives the set a test of every pair
//! would give, in the same order.
//!
//! How (Ericson, *Real-Time Collision Detection* (2005), §7.1, a uniform grid with each object in
//! one cell; the cell list of particle codes):
//! 1. **Small and large boxes.** A box is *small* when its widest side `e = max_k (hi_k − lo_k)` is
//!    at most [`LARGE_FACTOR`] times the mean `ē` over the boxes, else *large* (walls, a floor box:
//!    a few). Planes have no box.
//! 2. **The grid.** Cubic cells of side `h` at least the widest small box (`h = max e · (1 +
//!    10⁻⁶)`, the margin keeping the rounding of the cell coordinates on the right side), over the
//!    box of the small boxes' lower corners. Each small box goes into the one cell holding its lower
//!    corner, `c_k = ⌊(lo_k − o_k) / h⌋`. Two small boxes that overlap have lower corners less than
//!    `h` apart on every axis (`lo_j,k ≤ hi_i,k ≤ lo_i,k + h`), so their cells are neighbours: each
//!    cell is tested against itself and its 13 *forward* neighbours (those after it in the cells'
//!    order `x + n_x (y + n_y z)`), which meets every pair of neighbouring cells exactly once. The
//!    boxes are sorted by cell with a counting sort (`O(n + cells)`), so a cell's box list and a row
//!    of three cells along x are contiguous. When the lower corners spread over more than
//!    [`CELLS_PER_BOX`] cells per small box, the cells grow (more tests per cell, never a missed
//!    pair).
//! 3. **Large boxes** are tested against the small boxes in the cells their box covers, widened by
//!    one cell below (`c(lo_k) − 1 … c(hi_k)`: the lower corner of a small box that meets them), or
//!    against every small box when that is fewer; and against each other.
//! 4. **The order.** The pairs found `(min, max)` are sorted by their first body with a counting
//!    sort and each body's few second bodies by insertion sort (a long list by `sort_unstable`):
//!    `O(n + pairs)`; the plane pairs are emitted in their place and the excluded pairs dropped.
//! 5. **The budget.** Bodies heaped at one spot pair with each other, `n²/2` pairs for `n` bodies
//!    (2·10⁸ for 20,000, gigabytes of pairs and contacts). The search stops as soon as it has found
//!    more than the pair budget ([`Colliders::set_pair_budget`], `[world] max_pairs`), leaves no
//!    pair, and says so ([`Colliders::pairs_over_budget`]); the caller ends the run.
//!
//! 6. **Kept from step to step** (module `fat`): the pairs of boxes a little larger than the swept
//!    boxes are kept while every body stays inside its larger box, and the step's pairs are those of
//!    them whose swept boxes overlap — the same pairs in the same order; a body that left its box
//!    has its pairs found again against every box, and the grid runs again when many left.
//!
//! Cost: `O(n + cells + tests)`, with about `14 · m` box tests per small box for `m` boxes per cell
//! (about one for a pile of equal balls), against the sort and sweep's `O(n)` boxes overlapping each
//! box along the sweep axis (150 for the 1,000 balls) that it replaced. It runs on the caller's
//! thread: a few tens of µs for a thousand bodies, about what handing work to the pool costs.
//! Boxes of widely different sizes would want a hierarchy of grids (Ericson §7.2); the large boxes'
//! list covers the common case of a few walls and floors among bodies of one size.
//!
//! Frames: world; lengths in m.
//!
//! References: C. Ericson, *Real-Time Collision Detection* (2005), §7.1 (uniform grids: the cell
//! size, each object in one cell, each pair of neighbouring cells tested once); D. Baraff, "Dynamic simulation of non-penetrating rigid bodies" (1992), ch. 6 (swept boxes).

use super::Colliders;
use crate::body::RigidBody;
use crate::math::DVec3;
use parry3d_f64::bounding_volume::{Aabb, BoundingVolume};
use parry3d_f64::math::Pose;
use parry3d_f64::shape::SharedShape;

mod fat;
#[cfg(test)]
mod tests;

/// A box wider than this factor times the mean box width is *large*: tested against the cells it
/// covers rather than put into one.
pub const LARGE_FACTOR: f64 = 4.0;

/// The grid has at most this many cells per small box (plus [`MIN_CELLS`]); beyond, the cells grow.
pub const CELLS_PER_BOX: f64 = 8.0;

/// The grid may always have this many cells.
const MIN_CELLS: f64 = 64.0;

/// The relative margin of the cell side over the widest small box.
const CELL_MARGIN: f64 = 1e-6;

/// Up to this many bodies with a box, every pair of them is tested and no grid is made: a ten-box
/// tower's 55 tests cost less than the grid's lattice, counting sort and neighbour runs.
pub const ALL_PAIRS_MAX: usize = 16;

/// A body's partners beyond this many are sorted by `sort_unstable` rather than insertion sort.
const INSERTION_SORT_MAX: usize = 32;

/// The forward neighbour rows of a cell `(x, y, z)`: rows `x − 1 … x + 1` at `(y + dy, z + dz)`;
/// with the cell's own remainder and the cell `x + 1`, the 13 cells after it.
const FORWARD_ROWS: [(isize, isize); 4] = [(1, 0), (-1, 1), (0, 1), (1, 1)];

/// Whether two swept boxes overlap, closed on all three axes.
#[inline]
fn overlap(a: &Aabb, b: &Aabb) -> bool {
    // no early exit: one branch per pair, rarely taken, rather than six unpredictable ones
    (a.mins.x <= b.maxs.x)
        & (b.mins.x <= a.maxs.x)
        & (a.mins.y <= b.maxs.y)
        & (b.mins.y <= a.maxs.y)
        & (a.mins.z <= b.maxs.z)
        & (b.mins.z <= a.maxs.z)
}

/// A plane's side, world frame: its unit outward normal and offset (its solid is `n·x ≤ offset`);
/// for a shape that is not a half-space, an offset of +∞: every box reaches it.
#[derive(Debug, Clone, Copy)]
struct PlaneSide {
    normal: DVec3,
    offset: f64,
}

impl PlaneSide {
    fn of(shape: Option<&SharedShape>, pose: &Pose) -> Self {
        match shape.and_then(|s| s.as_halfspace()) {
            Some(h) => {
                let normal = pose.rotation * h.normal;
                Self { normal, offset: normal.dot(pose.translation) }
            }
            None => Self { normal: DVec3::ZERO, offset: f64::INFINITY },
        }
    }

    /// Whether a body with the swept box `aabb` pairs with the plane: not when the box lies wholly
    /// above it by more than `slop / 2`. Such a body's shape is more than its sweep plus `slop / 2`
    /// from the plane (its box is its shape's bound grown by its sweep `w`, `|v| dt + … + slop / 2`,
    /// on every axis, which along the unit normal is at least `w`), farther than the pair's
    /// prediction `w + slop / 2`, so the narrow phase would find no contact (a ten-box tower's nine
    /// upper boxes, the upper layers of a pile of balls).
    #[inline]
    fn reaches(&self, aabb: &Aabb, slop: f64) -> bool {
        let lowest = self.normal.dot(aabb.center()) - self.offset - self.normal.abs().dot(aabb.half_extents());
        lowest <= 0.5 * slop
    }
}

/// The cells: origin (the least lower corner of the small boxes), inverse side and counts.
#[derive(Debug, Clone, Copy)]
struct Lattice {
    /// The least lower corner of the small boxes, world frame (m).
    origin: DVec3,
    /// `1 / h` (1/m).
    inv_side: f64,
    /// Cells along x, y, z.
    dims: [usize; 3],
}

impl Lattice {
    /// The cells of side at least `side` (m) over the lower corners in `[origin, top]`: at most
    /// `max_cells` cells, larger ones when that many would not cover the corners.
    fn new(origin: DVec3, top: DVec3, side: f64, max_cells: f64) -> Self {
        let side = side * (1.0 + CELL_MARGIN);
        let mut lattice = Self { origin, inv_side: if side > 0.0 { 1.0 / side } else { 1.0 }, dims: [1; 3] };
        loop {
            let span = ((top - origin) * lattice.inv_side).to_array();
            // saturating casts: a non-finite or huge span gives many cells, then larger ones
            let dims = span.map(|s| (s as usize).saturating_add(1));
            let cells = dims.iter().map(|&d| d as f64).product::<f64>();
            if cells <= max_cells {
                lattice.dims = dims;
                return lattice;
            }
            lattice.inv_side *= (max_cells / cells).cbrt().min(0.9);
        }
    }

    /// The cell coordinate of `x` (m) along axis `k`, clamped to the grid.
    #[inline]
    fn coordinate(&self, x: f64, k: usize) -> usize {
        // the cast saturates (NaN is 0); below the origin is 0
        (((x - self.origin[k]) * self.inv_side) as i64).clamp(0, self.dims[k] as i64 - 1) as usize
    }

    /// The cell coordinates of the point `p` (m).
    #[inline]
    fn coordinates(&self, p: DVec3) -> [usize; 3] {
        [self.coordinate(p.x, 0), self.coordinate(p.y, 1), self.coordinate(p.z, 2)]
    }

    /// The index of the cell `c` in the cells' order `x + n_x (y + n_y z)`.
    #[inline]
    fn index(&self, c: [usize; 3]) -> usize {
        c[0] + self.dims[0] * (c[1] + self.dims[1] * c[2])
    }

    fn cells(&self) -> usize {
        self.dims.iter().product()
    }
}

/// The broad phase's buffers, kept from step to step (no allocation once grown).
#[derive(Debug, Clone, Default)]
pub(super) struct Grid {
    /// The bodies with a box (a shape other than a plane), in index order, and those of them free.
    boxed: Vec<usize>,
    free_boxed: Vec<usize>,
    /// Whether each body is fixed (read here rather than in the bodies: fewer cache lines).
    fixed: Vec<bool>,
    /// The large boxes' bodies, in index order.
    large: Vec<usize>,
    /// The small boxes' bodies and their cell (index and coordinates), in index order.
    small: Vec<(usize, usize, [usize; 3])>,
    /// `starts[c] .. starts[c + 1]`: the small boxes of cell `c` in the lists below (`cells + 2`
    /// entries).
    starts: Vec<usize>,
    /// The small boxes sorted by cell: their swept boxes (m), bodies and whether fixed, and cells
    /// (index and coordinates: no division to find them).
    bounds: Vec<Aabb>,
    owners: Vec<(usize, bool)>,
    places: Vec<(usize, [usize; 3])>,
    /// The places in the lists above of the boxes a cell is tested against.
    candidates: Vec<u32>,
    /// The pairs found, `(min, max)` body indices, in no order.
    found: Vec<(usize, usize)>,
    /// `firsts[i] .. firsts[i + 1]`: body `i`'s partners `j > i` in `seconds` (`n + 2` entries).
    firsts: Vec<usize>,
    seconds: Vec<usize>,
    /// The fat boxes and their pairs, kept from step to step (module `fat`).
    fat: fat::FatBoxes,
}

impl Colliders {
    /// Fills `self.aabbs`, `self.sweeps` and the candidate pairs `self.pairs` (sorted) of the step.
    /// A body asleep (`asleep[i]`, `contact::sleep`; empty: none) pairs as a fixed one: never with
    /// another body that is fixed or asleep.
    ///
    /// When more pairs than the pair budget are found, the search stops: no pair is left, and
    /// [`Colliders::pairs_over_budget`] gives the number found so far.
    pub(super) fn broad_phase(&mut self, bodies: &[RigidBody], asleep: &[bool], dt: f64, gravity: DVec3, slop: f64) {
        let n = bodies.len().min(self.shapes.len());
        self.over_budget = None;
        // a body asleep now and at the last broad phase, under the same step settings, keeps the box
        // and sweep it had: asleep, its state has not changed by a bit since (`contact::sleep`; a
        // change by the caller wakes it) and its velocity is zero, so they would come out the same
        let settings = (dt, gravity, slop);
        let keep = self.broad_settings == Some(settings) && self.aabbs.len() == n && self.made_asleep.len() == n;
        self.broad_settings = Some(settings);
        if !keep {
            self.aabbs.clear();
            self.aabbs.resize(n, Aabb::new_invalid());
            self.sweeps.clear();
            self.sweeps.resize(n, 0.0);
            self.poses.clear();
            self.poses.resize(n, Pose::IDENTITY);
            self.made_asleep.clear();
            self.made_asleep.resize(n, false);
        }
        self.pairs.clear();
        let mut grid = std::mem::take(&mut self.grid);
        grid.boxed.clear();
        grid.free_boxed.clear();
        grid.fixed.clear();
        // ½ |g| dt², times each body's |gravity_scale|
        let fall = 0.5 * gravity.length() * dt * dt;
        let (mut width_sum, mut widths) = (0.0, 0usize);
        for i in 0..n {
            let b = &bodies[i];
            let sleeping = !b.fixed && asleep.get(i).copied().unwrap_or(false);
            let rests = b.fixed || sleeping;
            grid.fixed.push(rests);
            let boxed = matches!(&self.shapes[i], Some(_) if !self.planes.contains(&i));
            if !(sleeping && self.made_asleep[i]) {
                let sweep = if b.fixed {
                    0.0
                } else {
                    (b.state.velocity.length() + b.state.omega_body.length() * self.radii[i]) * dt
                        + fall * b.gravity_scale.abs()
                };
                self.sweeps[i] = sweep + 0.5 * slop;
                if self.shapes[i].is_some() {
                    self.poses[i] = self.pose(bodies, i);
                }
                self.aabbs[i] = match &self.shapes[i] {
                    Some(s) if boxed => s.compute_aabb(&self.poses[i]).loosened(sweep + 0.5 * slop),
                    _ => Aabb::new_invalid(),
                };
                self.made_asleep[i] = sleeping;
            }
            if boxed {
                let aabb = &self.aabbs[i];
                let width = (aabb.maxs - aabb.mins).max_element();
                if width.is_finite() {
                    width_sum += width;
                    widths += 1;
                }
                grid.boxed.push(i);
                if !rests {
                    grid.free_boxed.push(i);
                }
            }
        }
        // every body with a box asleep or fixed (a pile at rest): no pair to find
        if grid.free_boxed.is_empty() {
            self.grid = grid;
            return;
        }
        let large_width = LARGE_FACTOR * width_sum / widths.max(1) as f64;
        // each plane pairs with the free bodies with a box that reach it: what is left of the
        // budget for the rest
        let plane_pairs: usize = self
            .planes
            .iter()
            .map(|&p| {
                let side = PlaneSide::of(self.shapes[p].as_ref(), &self.poses[p]);
                grid.free_boxed.iter().filter(|&&k| side.reaches(&self.aabbs[k], slop)).count()
            })
            .sum();
        let budget = self.pair_budget.saturating_sub(plane_pairs);
        // the pairs from the kept fat boxes when they can say (module `fat`): the same pairs
        if plane_pairs <= self.pair_budget && grid.pairs_from_fat(&self.aabbs, n, large_width, budget) {
            self.emit_pairs(&grid, n, slop);
            self.grid = grid;
            return;
        }
        if !grid.find_pairs(&self.aabbs, large_width, budget) || plane_pairs > self.pair_budget {
            self.over_budget = Some(grid.found.len().saturating_add(plane_pairs));
            grid.found.clear();
            self.grid = grid;
            return;
        }
        grid.sort_pairs(n);
        self.emit_pairs(&grid, n, slop);
        self.grid = grid;
    }

    /// The sorted pairs found in `grid` with the plane pairs in their places, the excluded pairs
    /// left out, into `self.pairs`; `slop` the broad phase's (m). A plane pairs with every free
    /// body with a box that reaches it ([`PlaneSide::reaches`]).
    fn emit_pairs(&mut self, grid: &Grid, n: usize, slop: f64) {
        let (planes, excluded) = (&self.planes, &self.excluded);
        let kept = |i: usize, j: usize| excluded.is_empty() || excluded.binary_search(&(i.min(j), i.max(j))).is_err();
        // `planes` is in index order: the next plane's place
        let mut next_plane = 0;
        for i in 0..n {
            if planes.get(next_plane) == Some(&i) {
                next_plane += 1;
                let side = PlaneSide::of(self.shapes[i].as_ref(), &self.poses[i]);
                // every free body with a box (not a plane: not `i`) that reaches it
                for &k in &grid.free_boxed {
                    if side.reaches(&self.aabbs[k], slop) && kept(i, k) {
                        self.pairs.push((i, k));
                    }
                }
                continue;
            }
            for &j in &grid.seconds[grid.firsts[i]..grid.firsts[i + 1]] {
                if kept(i, j) {
                    self.pairs.push((i, j));
                }
            }
        }
    }
}

impl Grid {
    /// The pairs of overlapping boxes among `self.boxed` (boxes `aabbs`, by body) into
    /// `self.found`, in no order: boxes wider than `large_width` (m) as large ones. `false` when
    /// more than `budget` pairs were found (the search stopped there).
    fn find_pairs(&mut self, aabbs: &[Aabb], large_width: f64, budget: usize) -> bool {
        self.found.clear();
        self.large.clear();
        self.small.clear();
        if self.boxed.len() <= ALL_PAIRS_MAX {
            // the same pairs as the grid's (the pairs of overlapping boxes not both resting), each
            // pair tested; `boxed` is in index order, so each pair comes as (min, max)
            for (k, &i) in self.boxed.iter().enumerate() {
                for &j in &self.boxed[k + 1..] {
                    if overlap(&aabbs[i], &aabbs[j]) && !(self.fixed[i] && self.fixed[j]) {
                        self.found.push((i, j));
                    }
                }
            }
            return self.found.len() <= budget;
        }
        // small and large boxes; the widest small box and the box of their lower corners
        let (mut side, mut lowest, mut highest) =
            (0.0f64, DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
        for &i in &self.boxed {
            let aabb = &aabbs[i];
            let width = (aabb.maxs - aabb.mins).max_element();
            // a box with a non-finite bound (never in a valid state) is large: tested against all
            if width <= large_width && aabb.mins.is_finite() && aabb.maxs.is_finite() {
                side = side.max(width);
                lowest = lowest.min(aabb.mins);
                highest = highest.max(aabb.mins);
                self.small.push((i, 0, [0; 3]));
            } else {
                self.large.push(i);
            }
        }
        let lattice = Lattice::new(lowest, highest, side, CELLS_PER_BOX * self.small.len() as f64 + MIN_CELLS);
        self.fill_cells(&lattice, aabbs);
        self.small_pairs(&lattice, budget) && self.large_pairs(&lattice, aabbs, budget)
    }

    /// Sorts the small boxes into their cells (a counting sort by cell index): `self.bounds`,
    /// `self.owners`, `self.places` and `self.starts`.
    fn fill_cells(&mut self, lattice: &Lattice, aabbs: &[Aabb]) {
        let cells = if self.small.is_empty() { 0 } else { lattice.cells() };
        self.starts.clear();
        self.starts.resize(cells + 2, 0);
        // starts[c + 2]: the count of cell c
        for (i, cell, at) in &mut self.small {
            *at = lattice.coordinates(aabbs[*i].mins);
            *cell = lattice.index(*at);
            self.starts[*cell + 2] += 1;
        }
        // starts[c + 1]: the start of cell c
        for c in 2..cells + 2 {
            self.starts[c] += self.starts[c - 1];
        }
        let count = self.small.len();
        self.bounds.resize(count, Aabb::new_invalid());
        self.owners.resize(count, (0, false));
        self.places.resize(count, (0, [0; 3]));
        // each box at starts[c + 1], which moves on: it ends as the end of cell c, the start of c + 1
        for &(body, cell, at) in &self.small {
            let next = &mut self.starts[cell + 1];
            self.bounds[*next] = aabbs[body];
            self.owners[*next] = (body, self.fixed[body]);
            self.places[*next] = (cell, at);
            *next += 1;
        }
    }

    /// The pairs of small boxes: each cell against itself and its 13 forward neighbours. `false`
    /// as soon as more than `budget` pairs were found.
    fn small_pairs(&mut self, lattice: &Lattice, budget: usize) -> bool {
        /// Places written at once into the candidates, whatever a run's length.
        const LANES: usize = 8;
        let [nx, ny, nz] = lattice.dims;
        let (bounds, owners, starts) = (&self.bounds, &self.owners, &self.starts);
        let (candidates, found) = (&mut self.candidates, &mut self.found);
        let mut first = 0;
        while first < bounds.len() {
            let (cell, [x, y, z]) = self.places[first];
            let end = starts[cell + 1];
            // runs of places: the cell and the cell x + 1 (contiguous), then the forward rows
            let mut runs = [(0, 0); 1 + FORWARD_ROWS.len()];
            runs[0] = (first, if x + 1 < nx { starts[cell + 2] } else { end });
            let mut run_count = 1;
            for (dy, dz) in FORWARD_ROWS {
                let (Some(yy), Some(zz)) = (y.checked_add_signed(dy), z.checked_add_signed(dz)) else { continue };
                if yy >= ny || zz >= nz {
                    continue;
                }
                let row = nx * (yy + ny * zz);
                runs[run_count] = (starts[row + x.saturating_sub(1)], starts[row + (x + 1).min(nx - 1) + 1]);
                run_count += 1;
            }
            let total: usize = runs[..run_count].iter().map(|&(s, e)| e - s).sum();
            if candidates.len() < total + LANES {
                candidates.resize(total + LANES, 0);
            }
            // the runs' places one after the other, LANES at a time: no branch on a run's length
            // (short, and unpredictable) unless it is longer
            let mut len = 0;
            for &(s, e) in &runs[..run_count] {
                for (k, c) in candidates[len..len + LANES].iter_mut().enumerate() {
                    *c = (s + k) as u32;
                }
                if e - s > LANES {
                    for (k, c) in candidates[len + LANES..len + e - s].iter_mut().enumerate() {
                        *c = (s + LANES + k) as u32;
                    }
                }
                len += e - s;
            }
            // the box at `a` meets the boxes after it in its cell (the first run) and the others
            for a in first..end {
                let (box_a, (body_a, fixed_a)) = (&bounds[a], owners[a]);
                for &b in &candidates[a + 1 - first..len] {
                    let b = b as usize;
                    if overlap(box_a, &bounds[b]) && !(fixed_a && owners[b].1) {
                        let body_b = owners[b].0;
                        found.push((body_a.min(body_b), body_a.max(body_b)));
                    }
                }
                // checked per box: one box adds at most n pairs
                if found.len() > budget {
                    return false;
                }
            }
            first = end;
        }
        true
    }

    /// The pairs of each large box with the small boxes whose lower corner is in a cell its box
    /// covers (widened by one cell below), or with every small box when that is fewer; and the
    /// pairs of large boxes. `false` as soon as more than `budget` pairs were found.
    fn large_pairs(&mut self, lattice: &Lattice, aabbs: &[Aabb], budget: usize) -> bool {
        let (bounds, owners, starts, found) = (&self.bounds, &self.owners, &self.starts, &mut self.found);
        let fixed_body = &self.fixed;
        for (k, &i) in self.large.iter().enumerate() {
            let (aabb, fixed) = (&aabbs[i], fixed_body[i]);
            let meet = |found: &mut Vec<(usize, usize)>, b: &Aabb, (j, fixed_j): (usize, bool)| {
                if overlap(aabb, b) && !(fixed && fixed_j) {
                    found.push((i.min(j), i.max(j)));
                }
            };
            for &j in &self.large[k + 1..] {
                meet(found, &aabbs[j], (j, fixed_body[j]));
            }
            if found.len() > budget {
                return false;
            }
            if bounds.is_empty() {
                continue;
            }
            let lo = lattice.coordinates(aabb.mins).map(|c| c.saturating_sub(1));
            let hi = lattice.coordinates(aabb.maxs);
            let covered = (0..3).fold(1usize, |count, k| count.saturating_mul((hi[k] + 1).saturating_sub(lo[k])));
            // (a box with lo > hi has a NaN bound and meets nothing: all are tested all the same)
            if covered >= bounds.len() || (0..3).any(|k| lo[k] > hi[k]) {
                for (b, &owner) in bounds.iter().zip(owners) {
                    meet(found, b, owner);
                }
                if found.len() > budget {
                    return false;
                }
                continue;
            }
            for z in lo[2]..=hi[2] {
                for y in lo[1]..=hi[1] {
                    let (s, e) = (starts[lattice.index([lo[0], y, z])], starts[lattice.index([hi[0], y, z]) + 1]);
                    for (b, &owner) in bounds[s..e].iter().zip(&owners[s..e]) {
                        meet(found, b, owner);
                    }
                }
            }
            if found.len() > budget {
                return false;
            }
        }
        true
    }

    /// Sorts `self.found` by first body (a counting sort into `firsts`, `seconds`), each body's
    /// partners in increasing order, for `n` bodies.
    fn sort_pairs(&mut self, n: usize) {
        self.firsts.clear();
        self.firsts.resize(n + 2, 0);
        for &(i, _) in &self.found {
            self.firsts[i + 2] += 1;
        }
        for i in 2..n + 2 {
            self.firsts[i] += self.firsts[i - 1];
        }
        self.seconds.clear();
        self.seconds.resize(self.found.len(), 0);
        for &(i, j) in &self.found {
            let at = &mut self.firsts[i + 1];
            self.seconds[*at] = j;
            *at += 1;
        }
        // a body has a few partners: insertion sort; many (a heap), `sort_unstable`, not O(m²)
        for i in 0..n {
            let partners = &mut self.seconds[self.firsts[i]..self.firsts[i + 1]];
            if partners.len() > INSERTION_SORT_MAX {
                partners.sort_unstable();
                continue;
            }
            for k in 1..partners.len() {
                let j = partners[k];
                let mut m = k;
                while m > 0 && partners[m - 1] > j {
                    partners[m] = partners[m - 1];
                    m -= 1;
                }
                partners[m] = j;
            }
        }
    }
}
