//! The resting-contact solver of free bodies four manifolds at a time: graph colours and `f64x4` lanes.
//!
//! The same equations as [`Constraint::solve`] and [`warm_start_pair`](super::solver::warm_start_pair),
//! with each scalar of a constraint replaced by an `f64x4` holding that scalar for the constraints of
//! four pairs of bodies (structure of arrays), and each body's velocities, displacement and rotation
//! gathered into lanes for the batch and scattered back after it.
//!
//! **Colouring** (after Box2D v3's graph colouring, E. Catto 2024, `b2AddContactToGraph`): the
//! pairs of bodies (manifolds) are taken in pair order and each goes to a colour of [`COLOURS`] in
//! which neither of its *moving* bodies is yet (a bitset of bodies per colour); fixed bodies do not
//! count, since impulses do not change them. The manifolds of one colour touch disjoint moving
//! bodies, so their order within the colour does not matter and four of them can be solved at once.
//! The colour is the lowest free one *after* the colours of the earlier manifolds of the same two
//! bodies (a level schedule of the pair-order sweep), and only past the last colour the lowest free
//! one: so each body meets its manifolds in pair order, and as long as the chains of manifolds
//! sharing bodies are at most [`COLOURS`] long, a sweep in colours is the scalar pair-order sweep bit
//! for bit (Gauss–Seidel updates that share no body commute). Box2D's plain greedy lowest colour
//! interleaves a stack's joints (1–2, 3–4, … then 2–3, …): support then climbs a tower at half the
//! speed per sweep, and a ten-box tower moved 14.9 mm instead of 8.0 mm, the 10-wide pyramid 11.7 mm
//! instead of 1.7 mm. A manifold that finds no free colour goes to the overflow, solved one at a
//! time after the colours by the scalar [`solve_pair`].
//!
//! **A colour of one manifold** (a tower's: each of its manifolds waits for the one below) is
//! solved at its place among the colours by the scalar [`solve_pair`], not in one lane of four: the
//! same operations in the same order, so the same bits, without the other three lanes' work and the
//! gathering of four bodies per side.
//!
//! **Lanes**: within a colour, the manifolds sorted by their number of points (their order there
//! changes no bit, and a batch of alike manifolds has little padding), four manifolds per batch,
//! lane `k` the `k`-th; the batch's point slot
//! `j` holds the `j`-th point of each manifold, so the points of one pair keep the Gauss–Seidel
//! order of the scalar solver. Manifolds with fewer points, and lanes without a manifold, are padded
//! with inert data and masked out of the velocity updates. Every branch of the scalar solve is kept
//! per lane with masks and selects: the speculative contact's "let go", the open (`s > 0`),
//! biased and relaxing normal rows, sticking and sliding friction, and the projection on the
//! friction disc (Newton with each lane frozen at the iteration at which the scalar loop breaks).
//!
//! Bit-identical to the scalar solve applied in the same order, up to the sign of zero impulses:
//! each lane performs the scalar formulae's IEEE operations in the same order (`+ − × ÷ √`, no fused
//! multiply-add, no reassociation; Rust never contracts), see the tests below.
//!
//! Threads: the batches of one colour touch disjoint moving bodies; [`LaneSolver::solve_batches`]
//! and [`LaneSolver::warm_start_batches`] take a range of batches, which a parallel loop could split
//! (fixed bodies are read, never written).

use super::solver::{
    patch_centre, patch_frame, solve_pair, solve_patch_pair, warm_start_pair, warm_start_patch_pair, Constraint,
    ContactPoint, FrictionModel, Manifold, Pass, Patch, SolverBody, Sweep,
};
use crate::integrate::lanes::{SolveLanes, V3};
use crate::math::DVec3;
use std::ops::Range;
use wide::f64x4;

/// Manifolds per batch.
pub const LANES: usize = 4;
/// Colours of the graph colouring; manifolds that find none free are solved one at a time.
pub const COLOURS: usize = 24;
/// A lane without a manifold, or a point slot a manifold does not fill.
const NONE: usize = usize::MAX;

// A 3-vector of four lanes is `integrate::lanes::V3`, whose operations follow `DVec3`'s operand for
// operand; the solve adds gathering from four constraints or bodies, and a select.
impl<L: SolveLanes> V3<L> {
    #[inline(always)]
    fn gather(f: impl Fn(usize) -> DVec3) -> Self {
        let v = [f(0), f(1), f(2), f(3)];
        Self {
            x: L::new([v[0].x, v[1].x, v[2].x, v[3].x]),
            y: L::new([v[0].y, v[1].y, v[2].y, v[3].y]),
            z: L::new([v[0].z, v[1].z, v[2].z, v[3].z]),
        }
    }

    #[inline(always)]
    fn select(mask: L, t: Self, f: Self) -> Self {
        Self { x: mask.select(t.x, f.x), y: mask.select(t.y, f.y), z: mask.select(t.z, f.z) }
    }
}

/// `DMat3 * DVec3` of four lanes, columns `c`: `(c0 x + c1 y) + c2 z`.
#[inline(always)]
fn mat_vec<L: SolveLanes>(c: &[V3<L>; 3], v: V3<L>) -> V3<L> {
    c[0].scale(v.x).add(c[1].scale(v.y)).add(c[2].scale(v.z))
}

/// The part of [`SolverBody`] the solve reads, for the bodies on one side of four manifolds.
#[derive(Clone, Copy)]
struct Motion4<L> {
    inv_mass: L,
    v: V3<L>,
    w: V3<L>,
    dx: V3<L>,
    /// `ΔR` by columns.
    drot: [V3<L>; 3],
}

impl<L: SolveLanes> Motion4<L> {
    /// Four bodies at rest with no motion since the start of the step ([`SolverBody::FIXED`]'s
    /// values in every lane).
    #[inline(always)]
    fn unmoved() -> Self {
        let (zero, one) = (L::splat(0.0), L::splat(1.0));
        let zeros = V3 { x: zero, y: zero, z: zero };
        Self {
            inv_mass: zero,
            v: zeros,
            w: zeros,
            dx: zeros,
            drot: [V3 { x: one, y: zero, z: zero }, V3 { x: zero, y: one, z: zero }, V3 { x: zero, y: zero, z: one }],
        }
    }

    /// Lane `k` from `bodies[index[k]]`, a fixed body at rest for [`NONE`].
    #[inline(always)]
    fn gather(bodies: &[SolverBody], index: &[usize; LANES]) -> Self {
        let body = |k: usize| if index[k] == NONE { &SolverBody::FIXED } else { &bodies[index[k]] };
        let b = [body(0), body(1), body(2), body(3)];
        Self {
            inv_mass: L::new([b[0].inv_mass, b[1].inv_mass, b[2].inv_mass, b[3].inv_mass]),
            v: V3::gather(|k| b[k].v),
            w: V3::gather(|k| b[k].w),
            dx: V3::gather(|k| b[k].dx),
            drot: [
                V3::gather(|k| b[k].drot.x_axis),
                V3::gather(|k| b[k].drot.y_axis),
                V3::gather(|k| b[k].drot.z_axis),
            ],
        }
    }

    /// Writes the velocities of lane `k` back to moving body `index[k]`, marking it reached by an
    /// impulse where `touched`; fixed bodies and empty lanes are left alone.
    #[inline(always)]
    fn scatter(&self, bodies: &mut [SolverBody], index: &[usize; LANES], moving: &[bool; LANES], touched: L) {
        let touched = touched.bitmask();
        for k in 0..LANES {
            if moving[k] {
                let body = &mut bodies[index[k]];
                body.v = self.v.lane(k);
                body.w = self.w.lane(k);
                body.touched |= touched & (1 << k) != 0;
            }
        }
    }
}

/// One point of each of four manifolds: [`Constraint`]'s data in lanes. Stored as `Slot<f64x4>`;
/// the AVX kernel reads the same memory as `Slot<Avx>` (`repr(C)`, lanes of the same layout).
#[derive(Debug, Clone, Copy, Default)]
#[repr(C)]
struct Slot<L> {
    r_a: V3<L>,
    r_b: V3<L>,
    n: V3<L>,
    t1: V3<L>,
    t2: V3<L>,
    adjusted_gap: L,
    normal_mass: L,
    tangent_per_normal: [L; 2],
    tangent_mass: [L; 4],
    tangent_k: [L; 3],
    ang_a: [V3<L>; 3],
    ang_b: [V3<L>; 3],
    mu: L,
    bias_rate: L,
    mass_scale: L,
    impulse_scale: L,
    /// All bits set in the lanes of speculative contacts.
    speculative: L,
    /// All bits set in the lanes that hold a point.
    valid: L,
    lambda: [L; 3],
    /// The separation at the bodies' current positions (m): measured when the slot is built and by
    /// every relaxing sweep, which follows each move of the bodies; read by the biased sweeps (the
    /// bodies do not move between a relaxing sweep and the next substep's biased one).
    separation: L,
    /// The accumulated impulses summed over the substeps so far (N·s).
    lambda_sum: [L; 3],
}

impl Slot<f64x4> {
    /// The lanes of `constraints[index[k]]`, inert data in the lanes of [`NONE`], with the
    /// separation at the positions of the bodies `ma`, `mb`; loaded in place into a slot fresh from
    /// `Slot::default()` (a slot is 1.8 kB: no copy of it).
    fn load(&mut self, constraints: &[Constraint], index: &[usize; LANES], ma: &Motion4<f64x4>, mb: &Motion4<f64x4>) {
        for (k, &i) in index.iter().enumerate() {
            if i != NONE {
                self.set_lane(k, &constraints[i]);
            }
        }
        self.separation = self.measure(ma, mb);
    }

    fn set_lane(&mut self, k: usize, c: &Constraint) {
        fn set(x: &mut f64x4, k: usize, value: f64) {
            x.as_mut_array()[k] = value;
        }
        fn set3(v: &mut V3<f64x4>, k: usize, value: DVec3) {
            set(&mut v.x, k, value.x);
            set(&mut v.y, k, value.y);
            set(&mut v.z, k, value.z);
        }
        let all = f64::from_bits(u64::MAX);
        set3(&mut self.r_a, k, c.r_a);
        set3(&mut self.r_b, k, c.r_b);
        set3(&mut self.n, k, c.n);
        set3(&mut self.t1, k, c.t1);
        set3(&mut self.t2, k, c.t2);
        set(&mut self.adjusted_gap, k, c.adjusted_gap);
        set(&mut self.normal_mass, k, c.normal_mass);
        set(&mut self.tangent_per_normal[0], k, c.tangent_per_normal[0]);
        set(&mut self.tangent_per_normal[1], k, c.tangent_per_normal[1]);
        for j in 0..4 {
            set(&mut self.tangent_mass[j], k, c.tangent_mass[j]);
        }
        for j in 0..3 {
            set(&mut self.tangent_k[j], k, c.tangent_k[j]);
            set3(&mut self.ang_a[j], k, c.ang_a[j]);
            set3(&mut self.ang_b[j], k, c.ang_b[j]);
            set(&mut self.lambda[j], k, c.lambda[j]);
        }
        set(&mut self.mu, k, c.mu);
        set(&mut self.bias_rate, k, c.softness.bias_rate);
        set(&mut self.mass_scale, k, c.softness.mass_scale);
        set(&mut self.impulse_scale, k, c.softness.impulse_scale);
        set(&mut self.speculative, k, if c.speculative { all } else { 0.0 });
        set(&mut self.valid, k, all);
    }
}

impl<L: SolveLanes> Slot<L> {
    /// The separation at the bodies' current positions, as [`Constraint`]'s
    /// `gap − n·(r_b − r_a) + n·(p_b − p_a)` with `p = Δx + ΔR r` (m).
    #[inline(always)]
    fn measure(&self, ma: &Motion4<L>, mb: &Motion4<L>) -> L {
        let p_a = ma.dx.add(mat_vec(&ma.drot, self.r_a));
        let p_b = mb.dx.add(mat_vec(&mb.drot, self.r_b));
        self.adjusted_gap + self.n.dot(p_b.sub(p_a))
    }

    /// Whether the lanes' accumulated impulses are nonzero (`λ != [0; 3]`).
    #[inline(always)]
    fn holds(&self) -> L {
        nonzero(&self.lambda)
    }

    /// [`Constraint::apply`] in the lanes of `mask` (the others keep their velocities bit for bit).
    #[inline(always)]
    fn apply(&self, ma: &mut Motion4<L>, mb: &mut Motion4<L>, dn: L, d1: L, d2: L, mask: L) {
        let p = self.n.scale(dn).add(self.t1.scale(d1)).add(self.t2.scale(d2));
        let va = ma.v.sub(p.scale(ma.inv_mass));
        let wa = ma.w.sub(self.ang_a[0].scale(dn).add(self.ang_a[1].scale(d1)).add(self.ang_a[2].scale(d2)));
        let vb = mb.v.add(p.scale(mb.inv_mass));
        let wb = mb.w.add(self.ang_b[0].scale(dn).add(self.ang_b[1].scale(d1)).add(self.ang_b[2].scale(d2)));
        ma.v = V3::select(mask, va, ma.v);
        ma.w = V3::select(mask, wa, ma.w);
        mb.v = V3::select(mask, vb, mb.v);
        mb.w = V3::select(mask, wb, mb.w);
    }

    /// The normal row's new accumulated impulse at the normal velocity `un`, as
    /// [`Constraint`]'s: the separation at this substep (measured by the first relaxing sweep
    /// after the bodies moved, `MEASURE`), then the open / biased / relaxing row.
    #[inline(always)]
    fn normal_row<const RELAX: bool, const MEASURE: bool>(
        &mut self,
        ma: &Motion4<L>,
        mb: &Motion4<L>,
        sweep: &Sweep,
        un: L,
    ) -> L {
        let zero = L::splat(0.0);
        if RELAX && MEASURE {
            self.separation = self.measure(ma, mb);
        }
        let s = self.separation;
        let open = s.gt(zero);
        let (closed_bias, closed_mass, closed_impulse) = if !RELAX {
            let bias = (self.bias_rate * (s + L::splat(sweep.slop)).min(zero)).max(L::splat(-sweep.max_push));
            (bias, self.mass_scale, self.impulse_scale)
        } else {
            (zero, L::splat(1.0), zero)
        };
        let bias = open.select(s * L::splat(sweep.inv_h), closed_bias);
        let mass_scale = open.select(L::splat(1.0), closed_mass);
        let impulse_scale = open.select(zero, closed_impulse);
        let l0 = self.lambda[0];
        let mass = self.normal_mass * mass_scale;
        let rest = l0 - mass * bias - impulse_scale * l0;
        (rest - mass * un).max(zero)
    }

    /// The impulse `dn n` on B and its opposite on A in the lanes of `mask`.
    #[inline(always)]
    fn apply_normal(&self, ma: &mut Motion4<L>, mb: &mut Motion4<L>, dn: L, mask: L) {
        let p = self.n.scale(dn);
        let va = ma.v.sub(p.scale(ma.inv_mass));
        let wa = ma.w.sub(self.ang_a[0].scale(dn));
        let vb = mb.v.add(p.scale(mb.inv_mass));
        let wb = mb.w.add(self.ang_b[0].scale(dn));
        ma.v = V3::select(mask, va, ma.v);
        ma.w = V3::select(mask, wa, ma.w);
        mb.v = V3::select(mask, vb, mb.v);
        mb.w = V3::select(mask, wb, mb.w);
    }

    /// [`Constraint::solve`] in four lanes, or with `NORMAL_ONLY` [`Constraint::solve_normal`];
    /// the lanes in which an impulse is held (or was let go). `RELAX` is `sweep.pass ==
    /// Pass::Relax`: the relaxing sweep measures the separation when `MEASURE` (`sweep.moved`: the
    /// bodies moved since the last one), the biased sweep reads it (see [`Slot::separation`]).
    #[inline(always)]
    fn solve<const RELAX: bool, const MEASURE: bool, const NORMAL_ONLY: bool>(
        &mut self,
        ma: &mut Motion4<L>,
        mb: &mut Motion4<L>,
        sweep: &Sweep,
    ) -> L {
        debug_assert_eq!(RELAX, sweep.pass == Pass::Relax);
        debug_assert!(!RELAX || MEASURE == sweep.moved);
        let zero = L::splat(0.0);
        let u = mb.v.add(mb.w.cross(self.r_b)).sub(ma.v.add(ma.w.cross(self.r_a)));
        let un = u.dot(self.n);
        // a speculative contact approaching faster than the impact speed lets go of what it held
        let let_go = self.speculative & un.neg().gt(L::splat(sweep.impact_speed));
        let held = self.holds();
        let l0 = self.lambda[0];
        let new = self.normal_row::<RELAX, MEASURE>(ma, mb, sweep, un);
        let dn = new - l0;
        if NORMAL_ONLY {
            // (λ_t1 = λ_t2 = 0 throughout)
            if !let_go.any() {
                self.lambda[0] = new;
                self.apply_normal(ma, mb, dn, self.valid);
                return self.valid & new.ne(zero);
            }
            let dn = let_go.select(l0.neg(), dn);
            self.lambda[0] = let_go.select(zero, new);
            let apply = self.valid & let_go.select(held, self.valid);
            self.apply_normal(ma, mb, dn, apply);
            return self.valid & let_go.select(held, self.lambda[0].ne(zero));
        }

        // friction: sticking inside the disc, else the disc's point nearest λ* in the metric of K_tt
        let (ux, uy) = (u.dot(self.t1), u.dot(self.t2));
        let (m, f) = (self.tangent_mass, self.tangent_per_normal);
        let l1 = self.lambda[1] - (m[0] * ux + m[1] * uy) - dn * f[0];
        let l2 = self.lambda[2] - (m[2] * ux + m[3] * uy) - dn * f[1];
        let (l1, l2) = friction_on_disc(self.tangent_k, l1, l2, self.mu * new);
        let (d1, d2) = (l1 - self.lambda[1], l2 - self.lambda[2]);

        if !let_go.any() {
            // (the common case: the selects below would keep every lane's own values)
            self.lambda = [new, l1, l2];
            self.apply(ma, mb, dn, d1, d2, self.valid);
            return self.valid & self.holds();
        }
        // the let-go lanes apply −λ and hold nothing (when they held nothing, nothing is applied)
        let dn = let_go.select(l0.neg(), dn);
        let d1 = let_go.select(self.lambda[1].neg(), d1);
        let d2 = let_go.select(self.lambda[2].neg(), d2);
        self.lambda[0] = let_go.select(zero, new);
        self.lambda[1] = let_go.select(zero, l1);
        self.lambda[2] = let_go.select(zero, l2);
        let apply = self.valid & let_go.select(held, self.valid);
        self.apply(ma, mb, dn, d1, d2, apply);
        self.valid & let_go.select(held, self.holds())
    }

    /// The warm start of the lanes that hold an impulse; those lanes. With `NORMAL_ONLY`, the
    /// normal impulse alone (as [`warm_start_patch_pair`]).
    #[inline(always)]
    fn warm_start<const NORMAL_ONLY: bool>(&self, ma: &mut Motion4<L>, mb: &mut Motion4<L>) -> L {
        if NORMAL_ONLY {
            let held = self.valid & self.lambda[0].ne(L::splat(0.0));
            self.apply_normal(ma, mb, self.lambda[0], held);
            return held;
        }
        let held = self.valid & self.holds();
        self.apply(ma, mb, self.lambda[0], self.lambda[1], self.lambda[2], held);
        held
    }
}

/// [`solver::friction_on_disc`](super::solver::friction_on_disc) in four lanes: `(l1, l2)` where it
/// lies in the disc `|λ| ≤ limit` (sticking), else the disc's point nearest it in the metric of
/// `K_tt` ([`project_on_disc`]) put on the circle.
#[inline(always)]
fn friction_on_disc<L: SolveLanes>(tangent_k: [L; 3], mut l1: L, mut l2: L, limit: L) -> (L, L) {
    let zero = L::splat(0.0);
    let sliding = (l1 * l1 + l2 * l2).gt(limit * limit);
    if sliding.any() {
        let project = sliding & limit.gt(zero);
        let scale = if project.any() {
            let (p1, p2) = project_on_disc(tangent_k, l1, l2, limit, project);
            l1 = project.select(p1, l1);
            l2 = project.select(p2, l2);
            let len = (l1 * l1 + l2 * l2).sqrt();
            (len.gt(zero) & len.is_finite()).select(limit / len, zero)
        } else {
            // no sliding lane has a positive limit (an open point, or μ = 0): there `limit` is
            // ±0 (`μ ≥ 0`, `λ_n ≥ 0`), so `limit / len` is `limit` itself for a positive finite
            // `len = √(l1² + l2²)`, and the square root and the division (on the sweep's
            // critical path, in most of a pile's solves) are not needed: the same bits
            let len_squared = l1 * l1 + l2 * l2;
            (len_squared.gt(zero) & len_squared.is_finite()).select(limit, zero)
        };
        l1 = sliding.select(l1 * scale, l1);
        l2 = sliding.select(l2 * scale, l2);
    }
    (l1, l2)
}

/// The [`Patch`] of each of four manifolds, in lanes (one per batch, with
/// [`FrictionModel::Manifold`]). `repr(C)` over its lanes, as [`Slot`].
#[derive(Debug, Clone, Copy, Default)]
#[repr(C)]
struct PatchSlot<L> {
    r_a: V3<L>,
    r_b: V3<L>,
    n: V3<L>,
    t1: V3<L>,
    t2: V3<L>,
    tangent_mass: [L; 4],
    tangent_k: [L; 3],
    ang_a: [V3<L>; 3],
    ang_b: [V3<L>; 3],
    twist_mass: L,
    radius: L,
    mu: L,
    /// All bits set in the lanes that hold a manifold.
    valid: L,
    lambda: [L; 3],
    lambda_sum: [L; 3],
}

/// The lanes in which any of three accumulated impulses is nonzero.
#[inline(always)]
fn nonzero<L: SolveLanes>(lambda: &[L; 3]) -> L {
    let zero = L::splat(0.0);
    lambda[0].ne(zero) | lambda[1].ne(zero) | lambda[2].ne(zero)
}

impl<L: SolveLanes> PatchSlot<L> {
    #[inline(always)]
    fn holds(&self) -> L {
        nonzero(&self.lambda)
    }

    /// [`Patch`]'s friction impulse in the lanes of `mask`.
    #[inline(always)]
    fn apply_tangent(&self, ma: &mut Motion4<L>, mb: &mut Motion4<L>, d1: L, d2: L, mask: L) {
        let p = self.t1.scale(d1).add(self.t2.scale(d2));
        let va = ma.v.sub(p.scale(ma.inv_mass));
        let wa = ma.w.sub(self.ang_a[0].scale(d1).add(self.ang_a[1].scale(d2)));
        let vb = mb.v.add(p.scale(mb.inv_mass));
        let wb = mb.w.add(self.ang_b[0].scale(d1).add(self.ang_b[1].scale(d2)));
        ma.v = V3::select(mask, va, ma.v);
        ma.w = V3::select(mask, wa, ma.w);
        mb.v = V3::select(mask, vb, mb.v);
        mb.w = V3::select(mask, wb, mb.w);
    }

    /// [`Patch`]'s twist impulse in the lanes of `mask`.
    #[inline(always)]
    fn apply_twist(&self, ma: &mut Motion4<L>, mb: &mut Motion4<L>, dt: L, mask: L) {
        ma.w = V3::select(mask, ma.w.sub(self.ang_a[2].scale(dt)), ma.w);
        mb.w = V3::select(mask, mb.w.add(self.ang_b[2].scale(dt)), mb.w);
    }

    /// [`Patch::solve`] in four lanes with the manifolds' normal impulses `normal_sum`; the lanes
    /// that hold an impulse.
    #[inline(always)]
    fn solve(&mut self, ma: &mut Motion4<L>, mb: &mut Motion4<L>, normal_sum: L) -> L {
        let u = mb.v.add(mb.w.cross(self.r_b)).sub(ma.v.add(ma.w.cross(self.r_a)));
        let (ux, uy) = (u.dot(self.t1), u.dot(self.t2));
        let m = self.tangent_mass;
        let l1 = self.lambda[0] - (m[0] * ux + m[1] * uy);
        let l2 = self.lambda[1] - (m[2] * ux + m[3] * uy);
        let limit = self.mu * normal_sum;
        let (l1, l2) = friction_on_disc(self.tangent_k, l1, l2, limit);
        let (d1, d2) = (l1 - self.lambda[0], l2 - self.lambda[1]);
        self.lambda[0] = l1;
        self.lambda[1] = l2;
        self.apply_tangent(ma, mb, d1, d2, self.valid);
        let spin = mb.w.sub(ma.w).dot(self.n);
        let twist_limit = limit * self.radius;
        let twist = (self.lambda[2] - self.twist_mass * spin).max(twist_limit.neg()).min(twist_limit);
        let dt = twist - self.lambda[2];
        self.lambda[2] = twist;
        self.apply_twist(ma, mb, dt, self.valid);
        self.valid & self.holds()
    }

    /// [`Patch`]'s warm start in the lanes that hold an impulse; those lanes.
    #[inline(always)]
    fn warm_start(&self, ma: &mut Motion4<L>, mb: &mut Motion4<L>) -> L {
        let held = self.valid & self.holds();
        self.apply_tangent(ma, mb, self.lambda[0], self.lambda[1], held);
        self.apply_twist(ma, mb, self.lambda[2], held);
        held
    }
}

/// [`project_on_disc`](super::solver::project_on_disc) in the lanes of `mask`: Newton on
/// `1/|λ(ν)| = 1/limit` with `λ(ν) = (K_tt + ν 1)⁻¹ K_tt λ*`, each lane frozen at the iteration at
/// which the scalar loop would break, so that each lane takes the scalar loop's steps.
#[inline(always)]
fn project_on_disc<L: SolveLanes>(k: [L; 3], l1: L, l2: L, limit: L, mask: L) -> (L, L) {
    let [k11, k12, k22] = k;
    let (b1, b2) = (k11 * l1 + k12 * l2, k12 * l1 + k22 * l2);
    let (zero, half) = (L::splat(0.0), L::splat(0.5));
    let inv_limit = L::splat(1.0) / limit;
    let half_gap = half * (k11 - k22);
    let k_max = half * (k11 + k22) + (half_gap * half_gap + k12 * k12).sqrt();
    let b_sq = b1 * b1 + b2 * b2;
    let b_norm = b_sq.sqrt();
    let lower = (b_norm * inv_limit - k_max).max(zero);
    let (kb1, kb2) = (k11 * b1 + k12 * b2, k12 * b1 + k22 * b2);
    let inv_b_sq = L::splat(1.0) / b_sq;
    let (m1, m2) = ((b1 * kb1 + b2 * kb2) * inv_b_sq, (kb1 * kb1 + kb2 * kb2) * inv_b_sq);
    let far = b_norm * inv_limit - m1;
    let mut nu = far.gt(zero).select((far + L::splat(1.5) * (m2 - m1 * m1) / far).max(lower), lower);
    let mut active = mask;
    for _ in 0..super::solver::NEWTON_STEPS {
        if !active.any() {
            break;
        }
        let (a11, a22) = (k11 + nu, k22 + nu);
        let det = a11 * a22 - k12 * k12;
        let (x1, x2) = (a22 * b1 - k12 * b2, a11 * b2 - k12 * b1);
        let (y1, y2) = (a22 * x1 - k12 * x2, a11 * x2 - k12 * x1);
        let x_sq = x1 * x1 + x2 * x2;
        let xy = x1 * y1 + x2 * y2;
        let inv_xy = L::splat(1.0) / xy;
        let gap = det - x_sq.sqrt() * inv_limit;
        let stop = xy.is_nan() | xy.le(zero) | gap.abs().lt(L::splat(1e-12) * det);
        active = stop.select(zero, active);
        nu = active.select((nu - x_sq * gap * inv_xy).max(zero), nu);
    }
    // λ(ν) = X/det at each lane's last ν (as the scalar loop returns it)
    let (a11, a22) = (k11 + nu, k22 + nu);
    let inv_det = L::splat(1.0) / (a11 * a22 - k12 * k12);
    ((a22 * b1 - k12 * b2) * inv_det, (a11 * b2 - k12 * b1) * inv_det)
}

/// The warm start of `batches` in lanes `L`; with `PATCH` ([`FrictionModel::Manifold`]) the
/// points' normal impulses then each batch's patch (`patches` aligned with `batches`).
#[inline(always)]
fn warm_start_in<L: SolveLanes, const PATCH: bool>(
    batches: &[Batch],
    slots: &[Slot<L>],
    patches: &[PatchSlot<L>],
    bodies: &mut [SolverBody],
) {
    for (j, batch) in batches.iter().enumerate() {
        let (mut ma, mut mb) = (Motion4::<L>::gather(bodies, &batch.a), Motion4::<L>::gather(bodies, &batch.b));
        let mut any = L::splat(0.0);
        for slot in &slots[batch.slots.0..batch.slots.1] {
            any = any | slot.warm_start::<PATCH>(&mut ma, &mut mb);
        }
        if PATCH {
            any = any | patches[j].warm_start(&mut ma, &mut mb);
        }
        ma.scatter(bodies, &batch.a, &batch.moving_a, any);
        mb.scatter(bodies, &batch.b, &batch.moving_b, any);
    }
}

/// One sweep over `batches` in lanes `L`; `RELAX` the pass and `MEASURE` whether a relaxing sweep
/// measures the separations (a biased sweep, and a relaxing one that keeps them, gather only the
/// bodies' velocities: the unused loads of their motion are dropped when compiling); with `PATCH`
/// ([`FrictionModel::Manifold`]) the points' normal rows, summed in the order solved, then each
/// batch's patch (`patches` aligned with `batches`), as [`solve_patch_pair`].
#[inline(always)]
fn sweep_in<L: SolveLanes, const RELAX: bool, const MEASURE: bool, const PATCH: bool>(
    batches: &[Batch],
    slots: &mut [Slot<L>],
    patches: &mut [PatchSlot<L>],
    bodies: &mut [SolverBody],
    sweep: &Sweep,
) {
    for (j, batch) in batches.iter().enumerate() {
        let (mut ma, mut mb) = (Motion4::<L>::gather(bodies, &batch.a), Motion4::<L>::gather(bodies, &batch.b));
        let mut any = L::splat(0.0);
        let mut normal_sum = L::splat(0.0);
        // two plain loops, not `solver::in_sweep_order`: a closure does not inherit the caller's
        // `target_feature(avx2)`, and the lanes' arithmetic compiled without it costs 20× here
        let points = &mut slots[batch.slots.0..batch.slots.1];
        if sweep.reverse {
            for slot in points.iter_mut().rev() {
                any = any | slot.solve::<RELAX, MEASURE, PATCH>(&mut ma, &mut mb, sweep);
                if PATCH {
                    normal_sum = normal_sum + slot.lambda[0];
                }
            }
        } else {
            for slot in points {
                any = any | slot.solve::<RELAX, MEASURE, PATCH>(&mut ma, &mut mb, sweep);
                if PATCH {
                    normal_sum = normal_sum + slot.lambda[0];
                }
            }
        }
        if PATCH {
            any = any | patches[j].solve(&mut ma, &mut mb, normal_sum);
        }
        ma.scatter(bodies, &batch.a, &batch.moving_a, any);
        mb.scatter(bodies, &batch.b, &batch.moving_b, any);
    }
}

/// What [`LaneSolver::build_points`] loads the slots from.
pub(super) struct PointInput<'a> {
    manifolds: &'a [Manifold],
    points: &'a [ContactPoint],
    bodies: &'a [SolverBody],
    positions: &'a [DVec3],
    /// Every body has the bits of no motion yet (`Δx = +0`, `ΔR = I`: a build at the start of the
    /// step): the separations are measured with those constants, the same bits as gathered.
    unmoved: bool,
}

/// The point of a padding lane: a unit normal, so that its arithmetic stays finite (its results are
/// replaced by zeros).
const INERT_POINT: ContactPoint = ContactPoint { point: DVec3::ZERO, n: DVec3::Z, gap: 0.0, lambda: [0.0; 3] };

/// `K d = (1/m_a + 1/m_b) d + (I_a⁻¹ (r_a × d)) × r_a + (I_b⁻¹ (r_b × d)) × r_b` from the angular
/// responses `[I_a⁻¹ (r_a × d), I_b⁻¹ (r_b × d)]`, as in [`Constraint::new`].
#[inline(always)]
fn k_times<L: SolveLanes>(d: V3<L>, inv_mass: L, ang: [V3<L>; 2], r_a: V3<L>, r_b: V3<L>) -> V3<L> {
    d.scale(inv_mass).add(ang[0].cross(r_a)).add(ang[1].cross(r_b))
}

/// Four lanes of the scalars `f(0)…f(3)`.
#[inline(always)]
fn lanes_of<L: SolveLanes>(f: impl Fn(usize) -> f64) -> L {
    L::new([f(0), f(1), f(2), f(3)])
}

/// `x` in the lanes of the mask `valid`, zero in the others.
#[inline(always)]
fn keep<L: SolveLanes>(valid: L, x: L) -> L {
    valid.select(x, L::splat(0.0))
}

#[inline(always)]
fn keep3<L: SolveLanes>(valid: L, v: V3<L>) -> V3<L> {
    V3 { x: keep(valid, v.x), y: keep(valid, v.y), z: keep(valid, v.z) }
}

/// The world inverse inertias of `bodies[side[k]]` by columns (zero for [`NONE`]).
#[inline(always)]
fn inv_inertia4<L: SolveLanes>(bodies: &[SolverBody], side: &[usize; LANES]) -> [V3<L>; 3] {
    let body = |i: usize| if i == NONE { &SolverBody::FIXED } else { &bodies[i] };
    [
        V3::gather(|k| body(side[k]).inv_inertia.x_axis),
        V3::gather(|k| body(side[k]).inv_inertia.y_axis),
        V3::gather(|k| body(side[k]).inv_inertia.z_axis),
    ]
}

/// What the build of a batch takes from its two sides' bodies: the world inverse inertias by
/// columns, the summed inverse masses `1/m_a + 1/m_b` and the centres of mass (zeros for [`NONE`]).
struct Sides<L> {
    inertia_a: [V3<L>; 3],
    inertia_b: [V3<L>; 3],
    inv_mass: L,
    center_a: V3<L>,
    center_b: V3<L>,
}

impl<L: SolveLanes> Sides<L> {
    #[inline(always)]
    fn of(batch: &Batch, input: &PointInput) -> Self {
        let bodies = input.bodies;
        let body = |i: usize| if i == NONE { &SolverBody::FIXED } else { &bodies[i] };
        let position = |i: usize| if i == NONE { DVec3::ZERO } else { input.positions[i] };
        Self {
            inertia_a: inv_inertia4::<L>(bodies, &batch.a),
            inertia_b: inv_inertia4::<L>(bodies, &batch.b),
            inv_mass: lanes_of::<L>(|k| body(batch.a[k]).inv_mass) + lanes_of::<L>(|k| body(batch.b[k]).inv_mass),
            center_a: V3::<L>::gather(|k| position(batch.a[k])),
            center_b: V3::<L>::gather(|k| position(batch.b[k])),
        }
    }
}

/// `K_tt⁻¹ = adj(K_tt)/det` as `[[a, b], [c, d]]` in the lanes of `valid` where `det > 0` (zeros
/// elsewhere), as the scalar [`tangent_inverse`](super::solver::tangent_inverse).
#[inline(always)]
fn tangent_inverse<L: SolveLanes>(valid: L, k11: L, k12: L, k22: L) -> [L; 4] {
    let det = k11 * k22 - k12 * k12;
    let invertible = valid & det.gt(L::splat(0.0));
    let cross_mass = keep(invertible, k12.neg() / det);
    [keep(invertible, k22 / det), cross_mass, cross_mass, keep(invertible, k11 / det)]
}

/// The tangents of the unit normals `n`, as `impact::tangent_basis` (glam's
/// `any_orthonormal_vector`); `sign` the signs of `n.z` (`f64::signum`).
#[inline(always)]
fn tangents<L: SolveLanes>(n: V3<L>, sign: L) -> (V3<L>, V3<L>) {
    let a = L::splat(-1.0) / (sign + n.z);
    let b = n.x * n.y * a;
    let t1 = V3 { x: b, y: sign + n.y * n.y * a, z: n.y.neg() };
    (t1, n.cross(t1))
}

/// The patch of `batch` ([`FrictionModel::Manifold`]) computed in lanes `L` with the batch's
/// `sides`: [`Patch::new`] for four manifolds at once, operation for operation (the centre, normal
/// and twist arm of each by the scalar [`patch_frame`]), zeros in the lanes without a manifold; each
/// manifold's centre into `centres` (by manifold), for the sharing of the patch's impulse among
/// its points.
#[inline(always)]
fn load_patch<L: SolveLanes>(
    batch: &Batch,
    patch: &mut PatchSlot<L>,
    sides: &Sides<L>,
    input: &PointInput,
    centres: &mut [DVec3],
) {
    let zero = L::splat(0.0);
    let all = f64::from_bits(u64::MAX);
    let Sides { inertia_a, inertia_b, inv_mass, center_a, center_b } = sides;
    let (inv_mass, center_a, center_b) = (*inv_mass, *center_a, *center_b);
    let manifold = |k: usize| (batch.manifold[k] != NONE).then(|| &input.manifolds[batch.manifold[k]]);
    let frame = [0, 1, 2, 3].map(|k| {
        manifold(k).map_or((DVec3::ZERO, DVec3::Z, 0.0), |m| patch_frame(&input.points[m.points.0..m.points.1]))
    });
    for (k, &g) in batch.manifold.iter().enumerate() {
        if g != NONE {
            centres[g] = frame[k].0;
        }
    }
    let warm = [0, 1, 2, 3].map(|k| manifold(k).map_or([DVec3::ZERO; 2], |m| m.friction_warm));
    let valid = lanes_of::<L>(|k| if manifold(k).is_some() { all } else { 0.0 });
    let c = V3::<L>::gather(|k| frame[k].0);
    let n = V3::<L>::gather(|k| frame[k].1);
    let (r_a, r_b) = (c.sub(center_a), c.sub(center_b));
    let (t1, t2) = tangents(n, lanes_of::<L>(|k| frame[k].1.z.signum()));
    let ang_a = [mat_vec(inertia_a, r_a.cross(t1)), mat_vec(inertia_a, r_a.cross(t2)), mat_vec(inertia_a, n)];
    let ang_b = [mat_vec(inertia_b, r_b.cross(t1)), mat_vec(inertia_b, r_b.cross(t2)), mat_vec(inertia_b, n)];
    let k_t1 = k_times(t1, inv_mass, [ang_a[0], ang_b[0]], r_a, r_b);
    let k_t2 = k_times(t2, inv_mass, [ang_a[1], ang_b[1]], r_a, r_b);
    let k11 = t1.dot(k_t1);
    let k12 = t1.dot(k_t2);
    let k22 = t2.dot(k_t2);
    let kww = n.dot(ang_a[2]) + n.dot(ang_b[2]);
    patch.r_a = keep3(valid, r_a);
    patch.r_b = keep3(valid, r_b);
    patch.n = keep3(valid, n);
    patch.t1 = keep3(valid, t1);
    patch.t2 = keep3(valid, t2);
    patch.tangent_mass = tangent_inverse(valid, k11, k12, k22);
    patch.tangent_k = [keep(valid, k11), keep(valid, k12), keep(valid, k22)];
    patch.ang_a = ang_a.map(|v| keep3(valid, v));
    patch.ang_b = ang_b.map(|v| keep3(valid, v));
    patch.twist_mass = keep(valid & kww.gt(zero), L::splat(1.0) / kww);
    patch.radius = lanes_of::<L>(|k| frame[k].2);
    patch.mu = lanes_of::<L>(|k| manifold(k).map_or(0.0, |m| m.mu));
    patch.valid = valid;
    let force = V3::<L>::gather(|k| warm[k][0]);
    let twist = V3::<L>::gather(|k| warm[k][1]);
    patch.lambda = [keep(valid, force.dot(t1)), keep(valid, force.dot(t2)), keep(valid, twist.dot(n))];
    patch.lambda_sum = [zero; 3];
}

/// The slots of `batches` computed from their points in lanes `L`: [`Constraint::new`] for four
/// points at once, operation for operation (so the same bits as [`Slot::load`] of the scalar
/// constraints), zeros in the lanes without a point, the separations measured at the bodies'
/// current motion. (No closure here makes lanes: a closure does not inherit the caller's
/// `target_feature`.) With `NORMAL_ONLY` ([`FrictionModel::Manifold`]) the normal rows alone, the
/// fields of friction zero.
#[inline(always)]
fn load_points_in<L: SolveLanes, const NORMAL_ONLY: bool>(
    batches: &[Batch],
    slot_index: &[[usize; LANES]],
    slots: &mut [Slot<L>],
    (patches, centres): (&mut [PatchSlot<L>], &mut [DVec3]),
    input: &PointInput,
) {
    let bodies = input.bodies;
    for (j, batch) in batches.iter().enumerate() {
        // the bodies and the manifold of each lane: the same for all the batch's slots and its patch
        let sides = Sides::of(batch, input);
        if NORMAL_ONLY {
            load_patch(batch, &mut patches[j], &sides, input, centres);
        }
        let manifold = |k: usize| (batch.manifold[k] != NONE).then(|| &input.manifolds[batch.manifold[k]]);
        let mu = lanes_of::<L>(|k| manifold(k).map_or(0.0, |m| m.mu));
        let bias_rate = lanes_of::<L>(|k| manifold(k).map_or(0.0, |m| m.softness.bias_rate));
        let mass_scale = lanes_of::<L>(|k| manifold(k).map_or(0.0, |m| m.softness.mass_scale));
        let impulse_scale = lanes_of::<L>(|k| manifold(k).map_or(0.0, |m| m.softness.impulse_scale));
        // (the separations read only the motion: at the start of a step, a constant)
        let (ma, mb) = if input.unmoved {
            (Motion4::<L>::unmoved(), Motion4::<L>::unmoved())
        } else {
            (Motion4::<L>::gather(bodies, &batch.a), Motion4::<L>::gather(bodies, &batch.b))
        };
        let range = batch.slots.0..batch.slots.1;
        let manifold = (mu, bias_rate, mass_scale, impulse_scale);
        for (slot, index) in slots[range.clone()].iter_mut().zip(&slot_index[range]) {
            // a slot of four points (most) needs no zeros put in empty lanes: the same values,
            // without the masking
            if index.contains(&NONE) {
                load_slot::<L, NORMAL_ONLY, false>(slot, index, &sides, manifold, (&ma, &mb), input);
            } else {
                load_slot::<L, NORMAL_ONLY, true>(slot, index, &sides, manifold, (&ma, &mb), input);
            }
        }
    }
}

/// `keep(valid, x)`, or `x` when every lane is `FULL` (holds a point).
#[inline(always)]
fn kept<L: SolveLanes, const FULL: bool>(valid: L, x: L) -> L {
    if FULL {
        x
    } else {
        keep(valid, x)
    }
}

/// `keep3(valid, v)`, or `v` when every lane is `FULL`.
#[inline(always)]
fn kept3<L: SolveLanes, const FULL: bool>(valid: L, v: V3<L>) -> V3<L> {
    if FULL {
        v
    } else {
        keep3(valid, v)
    }
}

/// One slot of [`load_points_in`]: the points `index` with their batch's [`Sides`], `manifold` values (`μ` and the softness's bias
/// rate, mass and impulse scales) and the bodies' `motion`. `FULL`: no lane is empty.
#[inline(always)]
fn load_slot<L: SolveLanes, const NORMAL_ONLY: bool, const FULL: bool>(
    slot: &mut Slot<L>,
    index: &[usize; LANES],
    sides: &Sides<L>,
    (mu, bias_rate, mass_scale, impulse_scale): (L, L, L, L),
    (ma, mb): (&Motion4<L>, &Motion4<L>),
    input: &PointInput,
) {
    let Sides { inertia_a, inertia_b, inv_mass, center_a, center_b } = sides;
    let (inv_mass, center_a, center_b) = (*inv_mass, *center_a, *center_b);
    let zero = L::splat(0.0);
    let all = f64::from_bits(u64::MAX);
    let p = |k: usize| if index[k] == NONE { &INERT_POINT } else { &input.points[index[k]] };
    let valid = lanes_of::<L>(|k| if index[k] == NONE { 0.0 } else { all });
    let n = V3::<L>::gather(|k| p(k).n);
    let point = V3::<L>::gather(|k| p(k).point);
    let gap = lanes_of::<L>(|k| p(k).gap);
    let (r_a, r_b) = (point.sub(center_a), point.sub(center_b));
    slot.r_a = kept3::<L, FULL>(valid, r_a);
    slot.r_b = kept3::<L, FULL>(valid, r_b);
    slot.n = kept3::<L, FULL>(valid, n);
    slot.adjusted_gap = kept::<L, FULL>(valid, gap - n.dot(r_b.sub(r_a)));
    slot.mu = kept::<L, FULL>(valid, mu);
    slot.bias_rate = kept::<L, FULL>(valid, bias_rate);
    slot.mass_scale = kept::<L, FULL>(valid, mass_scale);
    slot.impulse_scale = kept::<L, FULL>(valid, impulse_scale);
    slot.speculative = kept::<L, FULL>(valid, gap.gt(zero));
    slot.valid = valid;
    slot.lambda_sum = [zero; 3];
    slot.separation = slot.measure(ma, mb);
    if NORMAL_ONLY {
        // the normal row alone (its patch takes the friction): no tangents, zeros in the
        // tangents and the tangential impulses (which the normal row's sweeps, the sums over the
        // substeps and the points' impulses read); the other fields of friction (the tangent rows'
        // masses and angular responses) are read by no pass over normal rows and are left as
        // they are, unwritten
        let (ang_a, ang_b) = (mat_vec(inertia_a, r_a.cross(n)), mat_vec(inertia_b, r_b.cross(n)));
        let knn = n.dot(k_times(n, inv_mass, [ang_a, ang_b], r_a, r_b));
        slot.normal_mass = keep(valid & knn.gt(zero), L::splat(1.0) / knn);
        let none = V3 { x: zero, y: zero, z: zero };
        slot.ang_a[0] = kept3::<L, FULL>(valid, ang_a);
        slot.ang_b[0] = kept3::<L, FULL>(valid, ang_b);
        (slot.t1, slot.t2) = (none, none);
        slot.lambda = [kept::<L, FULL>(valid, lanes_of::<L>(|k| p(k).lambda[0])), zero, zero];
        return;
    }
    let (t1, t2) = tangents(n, lanes_of::<L>(|k| p(k).n.z.signum()));
    let ang_a =
        [mat_vec(inertia_a, r_a.cross(n)), mat_vec(inertia_a, r_a.cross(t1)), mat_vec(inertia_a, r_a.cross(t2))];
    let ang_b =
        [mat_vec(inertia_b, r_b.cross(n)), mat_vec(inertia_b, r_b.cross(t1)), mat_vec(inertia_b, r_b.cross(t2))];
    // K d = (1/m_a + 1/m_b) d + (I_a⁻¹ (r_a × d)) × r_a + (I_b⁻¹ (r_b × d)) × r_b, as
    // `Constraint::new`
    let (k_n, k_t1, k_t2) = (
        k_times(n, inv_mass, [ang_a[0], ang_b[0]], r_a, r_b),
        k_times(t1, inv_mass, [ang_a[1], ang_b[1]], r_a, r_b),
        k_times(t2, inv_mass, [ang_a[2], ang_b[2]], r_a, r_b),
    );
    let knn = n.dot(k_n);
    let k11 = t1.dot(k_t1);
    let k12 = t1.dot(k_t2);
    let k22 = t2.dot(k_t2);
    slot.t1 = kept3::<L, FULL>(valid, t1);
    slot.t2 = kept3::<L, FULL>(valid, t2);
    slot.normal_mass = keep(valid & knn.gt(zero), L::splat(1.0) / knn);
    let (k1n, k2n) = (t1.dot(k_n), t2.dot(k_n));
    let m = tangent_inverse(valid, k11, k12, k22);
    slot.tangent_mass = m;
    slot.tangent_per_normal =
        [kept::<L, FULL>(valid, m[0] * k1n + m[1] * k2n), kept::<L, FULL>(valid, m[2] * k1n + m[3] * k2n)];
    slot.tangent_k = [kept::<L, FULL>(valid, k11), kept::<L, FULL>(valid, k12), kept::<L, FULL>(valid, k22)];
    slot.ang_a = ang_a.map(|v| kept3::<L, FULL>(valid, v));
    slot.ang_b = ang_b.map(|v| kept3::<L, FULL>(valid, v));
    slot.lambda = [
        kept::<L, FULL>(valid, lanes_of::<L>(|k| p(k).lambda[0])),
        kept::<L, FULL>(valid, lanes_of::<L>(|k| p(k).lambda[1])),
        kept::<L, FULL>(valid, lanes_of::<L>(|k| p(k).lambda[2])),
    ];
}

/// The sweeps compiled for AVX2, in [`Avx`] lanes, on the slots stored as `wide::f64x4`.
#[cfg(target_arch = "x86_64")]
#[allow(unsafe_code)]
mod avx {
    use super::{
        load_points_in, sweep_in, warm_start_in, Batch, DVec3, PatchSlot, PointInput, Slot, SolverBody, Sweep, LANES,
    };
    use crate::integrate::lanes::Avx;
    use wide::f64x4;

    // the same layout: four `f64` in lane order, 32 bytes aligned to 32
    const _: () = assert!(size_of::<f64x4>() == size_of::<Avx>() && align_of::<f64x4>() == align_of::<Avx>());
    const _: () = assert!(size_of::<Slot<f64x4>>() == size_of::<Slot<Avx>>());
    const _: () = assert!(size_of::<PatchSlot<f64x4>>() == size_of::<PatchSlot<Avx>>());

    /// The slots as `Slot<Avx>`: `Slot` is `repr(C)` over its lanes, and `f64x4` and `Avx` are both
    /// four `f64` in lane order (32 bytes, aligned to 32; asserted above), any bits valid in both.
    pub(super) fn slots(slots: &mut [Slot<f64x4>]) -> &mut [Slot<Avx>] {
        // SAFETY: same size, alignment and field layout (above); the borrow is handed on
        unsafe { std::slice::from_raw_parts_mut(slots.as_mut_ptr().cast::<Slot<Avx>>(), slots.len()) }
    }

    /// The patches as `PatchSlot<Avx>`, as [`slots`].
    pub(super) fn patches(patches: &mut [PatchSlot<f64x4>]) -> &mut [PatchSlot<Avx>] {
        // SAFETY: as `slots`: `PatchSlot` is `repr(C)` over its lanes (size asserted above)
        unsafe { std::slice::from_raw_parts_mut(patches.as_mut_ptr().cast::<PatchSlot<Avx>>(), patches.len()) }
    }

    #[target_feature(enable = "avx2")]
    pub(super) fn load_points<const NORMAL_ONLY: bool>(
        batches: &[Batch],
        slot_index: &[[usize; LANES]],
        slots: &mut [Slot<Avx>],
        patches: (&mut [PatchSlot<Avx>], &mut [DVec3]),
        input: &PointInput,
    ) {
        load_points_in::<Avx, NORMAL_ONLY>(batches, slot_index, slots, patches, input);
    }

    #[target_feature(enable = "avx2")]
    pub(super) fn warm_start<const PATCH: bool>(
        batches: &[Batch],
        slots: &[Slot<Avx>],
        patches: &[PatchSlot<Avx>],
        bodies: &mut [SolverBody],
    ) {
        warm_start_in::<Avx, PATCH>(batches, slots, patches, bodies);
    }

    #[target_feature(enable = "avx2")]
    pub(super) fn sweep<const RELAX: bool, const MEASURE: bool, const PATCH: bool>(
        batches: &[Batch],
        slots: &mut [Slot<Avx>],
        patches: &mut [PatchSlot<Avx>],
        bodies: &mut [SolverBody],
        sweep: &Sweep,
    ) {
        sweep_in::<Avx, RELAX, MEASURE, PATCH>(batches, slots, patches, bodies, sweep);
    }
}

/// A colour in use, as the passes take it.
#[derive(Debug, Clone, Copy)]
enum Colour {
    /// The colour's batches in lanes: a range of [`LaneSolver`]'s batches.
    Batches(usize, usize),
    /// The colour's one manifold, solved by the scalar solver: an index of `overflow`.
    Single(usize),
}

/// Four manifolds of one colour: their bodies and their point slots.
#[derive(Debug, Clone, Copy)]
pub struct Batch {
    /// The manifold of each lane ([`NONE`] for an empty lane), an index of the `groups` given to
    /// [`LaneSolver::build`] or the manifolds given to [`LaneSolver::build_points`].
    manifold: [usize; LANES],
    a: [usize; LANES],
    b: [usize; LANES],
    /// Whether lane `k`'s body `a` (`b`) moves: only those are written back.
    moving_a: [bool; LANES],
    moving_b: [bool; LANES],
    /// The batch's slots, a range of [`LaneSolver`]'s slots.
    slots: (usize, usize),
}

/// The colours, batches and point slots of the resting contacts of free bodies, rebuilt at every
/// step in buffers kept from step to step (no allocation once grown).
#[derive(Debug, Clone, Default)]
pub struct LaneSolver {
    /// Per colour, a bit per body: the moving bodies of the colour's manifolds.
    colour_bodies: Vec<u64>,
    /// The last colour given to each body's manifolds ([`NONE`] before the first).
    last: Vec<usize>,
    /// The colour of each manifold, `COLOURS` for the overflow.
    colour_of: Vec<usize>,
    /// The manifolds of each colour by number of points then pair order, concatenated;
    /// `colour_start[c]..colour_start[c + 1]`.
    order: Vec<usize>,
    colour_start: Vec<usize>,
    batches: Vec<Batch>,
    /// The batches of each colour: `batch_start[c]..batch_start[c + 1]`.
    batch_start: Vec<usize>,
    /// The colours in use, in increasing order, each as the passes take it: the passes visit only
    /// these (a small scene uses a few of the [`COLOURS`], and each colour's pass is a call;
    /// returning early from an empty colour's call instead made the 10:1 stack's
    /// `examples/threads` run 1.2× as long).
    used: Vec<Colour>,
    /// The manifold of each colour of one manifold (solved by the scalar solver), in colour order.
    singles: Vec<usize>,
    slots: Vec<Slot<f64x4>>,
    /// The constraint of each lane of each slot ([`NONE`] for padding).
    slot_index: Vec<[usize; LANES]>,
    /// Manifolds (ranges of the constraints given to [`solve`](LaneSolver::solve)) solved one at a
    /// time by the scalar solver: first those of the colours of one manifold (`singles`, each
    /// solved at its place among the colours), then the overflow, solved after the colours.
    overflow: Vec<(usize, usize)>,
    /// The first point of each of `overflow`'s manifolds among the points (groups' ranges) of the
    /// build.
    overflow_points: Vec<usize>,
    /// The manifold of each of `overflow`'s (an index of the build's manifolds or groups).
    overflow_manifold: Vec<usize>,
    /// Whether friction is per manifold ([`FrictionModel::Manifold`], [`build_points`](Self::build_points)
    /// only): the slots then hold normal rows, and each batch has a patch.
    patch: bool,
    /// The patch of each batch (with `patch`).
    patches: Vec<PatchSlot<f64x4>>,
    /// The patch of each of `overflow`'s manifolds, and its impulses summed over the substeps (with
    /// `patch`).
    overflow_patches: Vec<Patch>,
    overflow_patch_sums: Vec<[f64; 3]>,
    /// The centre of each manifold's points (with `patch`, by manifold; [`patch_centre`]).
    patch_centres: Vec<DVec3>,
    /// Whether the sweeps run in AVX registers (the CPU has AVX2, found by each build).
    #[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
    avx: bool,
    /// Keeps the portable `wide::f64x4` lanes even on a CPU with AVX2 (the tests run both).
    #[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
    portable: bool,
    /// What the layout was made from, per manifold: its bodies, its number of points and whether
    /// each body moves; and the body count (a build with the same keeps the colours and batches).
    key: Vec<LayoutKey>,
    next_key: Vec<LayoutKey>,
    key_bodies: usize,
}

/// A manifold's bodies `a`, `b`, its number of points and whether `a` and `b` move.
type LayoutKey = (usize, usize, usize, bool, bool);

impl LaneSolver {
    /// Colours the manifolds `groups` (ranges of `constraints`, each of one pair of bodies, in pair
    /// order) and loads their constraints into batches, measuring their separations at the
    /// positions of `bodies`; `moving(i)` whether body `i` moves. The overflow's manifolds are solved
    /// on `constraints` (the same slice is given to [`solve`](Self::solve) and the other passes).
    pub fn build(
        &mut self,
        groups: &[(usize, usize)],
        constraints: &[Constraint],
        bodies: &[SolverBody],
        moving: impl Fn(usize) -> bool,
    ) {
        let pair = |g: usize| (constraints[groups[g].0].a, constraints[groups[g].0].b);
        self.layout(groups.len(), |g| groups[g], pair, bodies.len(), &moving);
        self.overflow.clear();
        self.overflow_points.clear();
        self.overflow_manifold.clear();
        self.patch = false;
        self.patches.clear();
        self.overflow_patches.clear();
        self.overflow_patch_sums.clear();
        for &g in self.singles.iter().chain(&self.order[self.colour_start[COLOURS]..]) {
            self.overflow.push(groups[g]);
            self.overflow_points.push(groups[g].0);
            self.overflow_manifold.push(g);
        }
        self.slots.clear();
        for batch in &self.batches {
            let (ma, mb) = (Motion4::gather(bodies, &batch.a), Motion4::gather(bodies, &batch.b));
            for index in &self.slot_index[batch.slots.0..batch.slots.1] {
                self.slots.push(Slot::default());
                self.slots.last_mut().expect("pushed").load(constraints, index, &ma, &mb);
            }
        }
    }

    /// [`build`](Self::build) straight from the manifolds and their points, with the constraints
    /// of the colours' manifolds computed in the lanes (the arithmetic of [`Constraint::new`],
    /// operation for operation: the same slots bit for bit, no `Constraint` made); `positions` the
    /// bodies' centres of mass (m). The manifolds of the colours of one manifold and of the
    /// overflow are made into `overflow` as [`Constraint`]s, which are then the constraints to give
    /// to [`solve`](Self::solve) and the other passes. With [`FrictionModel::Manifold`] each
    /// manifold also has a [`Patch`] (in lanes per batch, or kept here for the overflow's), and its
    /// points' tangential impulses must be zero.
    #[allow(unsafe_code, clippy::too_many_arguments)]
    pub fn build_points(
        &mut self,
        manifolds: &[Manifold],
        points: &[ContactPoint],
        bodies: &[SolverBody],
        positions: &[DVec3],
        moving: impl Fn(usize) -> bool,
        friction: FrictionModel,
        overflow: &mut Vec<Constraint>,
    ) {
        self.layout(
            manifolds.len(),
            |g| manifolds[g].points,
            |g| (manifolds[g].a, manifolds[g].b),
            bodies.len(),
            &moving,
        );
        overflow.clear();
        self.overflow.clear();
        self.overflow_points.clear();
        self.overflow_manifold.clear();
        self.patch = friction == FrictionModel::Manifold;
        self.patch_centres.clear();
        self.patch_centres.resize(if self.patch { manifolds.len() } else { 0 }, DVec3::ZERO);
        self.overflow_patches.clear();
        self.overflow_patch_sums.clear();
        for &g in self.singles.iter().chain(&self.order[self.colour_start[COLOURS]..]) {
            let m = &manifolds[g];
            let start = overflow.len();
            let own = &points[m.points.0..m.points.1];
            for p in own {
                let mut k = if self.patch {
                    Constraint::new_normal(bodies, positions, m.a, m.b, p.point, p.n, p.gap, m.softness)
                } else {
                    Constraint::new(bodies, positions, m.a, m.b, p.point, p.n, p.gap, m.mu, m.softness)
                };
                k.lambda = p.lambda;
                overflow.push(k);
            }
            self.overflow.push((start, overflow.len()));
            self.overflow_points.push(m.points.0);
            self.overflow_manifold.push(g);
            if self.patch {
                self.patch_centres[g] = patch_centre(own).0;
                self.overflow_patches.push(Patch::new(bodies, positions, m.a, m.b, own, m.mu, m.friction_warm));
                self.overflow_patch_sums.push([0.0; 3]);
            }
        }
        // every field of every slot that a pass reads is written below: the slots of the last step
        // are overwritten, not zeroed first (normal rows alone leave the tangent rows' fields)
        let count = self.slot_index.len();
        if self.slots.len() != count {
            self.slots.resize(count, Slot::default());
        }
        let unmoved = bodies.iter().all(SolverBody::unmoved);
        let input = PointInput { manifolds, points, bodies, positions, unmoved };
        let patches = if self.patch { self.batches.len() } else { 0 };
        if self.patches.len() != patches {
            self.patches.resize(patches, PatchSlot::default());
        }
        let centres = &mut self.patch_centres;
        #[cfg(target_arch = "x86_64")]
        if self.avx {
            // SAFETY: `layout` found AVX2 on this CPU
            unsafe {
                let slots = avx::slots(&mut self.slots);
                let patches = (avx::patches(&mut self.patches), &mut centres[..]);
                if self.patch {
                    avx::load_points::<true>(&self.batches, &self.slot_index, slots, patches, &input);
                } else {
                    avx::load_points::<false>(&self.batches, &self.slot_index, slots, patches, &input);
                }
            }
            return;
        }
        let patches = (&mut self.patches[..], &mut centres[..]);
        if self.patch {
            load_points_in::<f64x4, true>(&self.batches, &self.slot_index, &mut self.slots, patches, &input);
        } else {
            load_points_in::<f64x4, false>(&self.batches, &self.slot_index, &mut self.slots, patches, &input);
        }
    }

    /// The colours, the batches and the slots' points of `count` manifolds, manifold `g` being the
    /// points `range(g)` between the bodies `pair(g)` (in pair order); `moving(i)` whether body `i`
    /// moves. Leaves the slots' contents to the caller.
    fn layout(
        &mut self,
        count: usize,
        range: impl Fn(usize) -> (usize, usize),
        pair: impl Fn(usize) -> (usize, usize),
        body_count: usize,
        moving: &impl Fn(usize) -> bool,
    ) {
        #[cfg(target_arch = "x86_64")]
        {
            self.avx = !self.portable && std::arch::is_x86_feature_detected!("avx2");
        }
        // the manifolds of the last build (the same pairs, numbers of points and moving bodies, in
        // the same order): the same colours and batches, kept (a stack at rest keeps its manifolds
        // step after step), with the slots' points taken again from this build's ranges
        self.next_key.clear();
        self.next_key.extend((0..count).map(|g| {
            let ((a, b), (s, e)) = (pair(g), range(g));
            (a, b, e - s, moving(a), moving(b))
        }));
        if self.key_bodies == body_count && self.next_key == self.key && !self.batch_start.is_empty() {
            for batch in &self.batches {
                for (j, index) in self.slot_index[batch.slots.0..batch.slots.1].iter_mut().enumerate() {
                    for (lane, &g) in index.iter_mut().zip(&batch.manifold) {
                        *lane = NONE;
                        if g != NONE {
                            let (s, e) = range(g);
                            if s + j < e {
                                *lane = s + j;
                            }
                        }
                    }
                }
            }
            return;
        }
        std::mem::swap(&mut self.key, &mut self.next_key);
        self.key_bodies = body_count;
        let words = body_count.div_ceil(64);
        self.colour_bodies.clear();
        self.colour_bodies.resize(COLOURS * words, 0);
        self.colour_of.clear();
        self.last.clear();
        self.last.resize(body_count, NONE);
        let mut counts = [0usize; COLOURS + 1];
        for g in 0..count {
            let (a, b) = pair(g);
            let (move_a, move_b) = (moving(a), moving(b));
            let taken = |bits: &[u64], i: usize| bits[i / 64] & (1 << (i % 64)) != 0;
            // after the colours of the bodies' earlier manifolds, so that each body meets its
            // manifolds in pair order; past the last colour, the lowest free one
            let after = |i: usize, m: bool| if m && self.last[i] != NONE { self.last[i] + 1 } else { 0 };
            let first = after(a, move_a).max(after(b, move_b));
            let mut colour = COLOURS;
            for c in (first..COLOURS).chain(0..first.min(COLOURS)) {
                let bits = &mut self.colour_bodies[c * words..(c + 1) * words];
                if (move_a && taken(bits, a)) || (move_b && taken(bits, b)) {
                    continue;
                }
                if move_a {
                    bits[a / 64] |= 1 << (a % 64);
                    self.last[a] = c;
                }
                if move_b {
                    bits[b / 64] |= 1 << (b % 64);
                    self.last[b] = c;
                }
                colour = c;
                break;
            }
            self.colour_of.push(colour);
            counts[colour] += 1;
        }
        // counting sort by colour, stable: pair order within a colour
        self.colour_start.clear();
        let mut start = 0;
        for &n in &counts {
            self.colour_start.push(start);
            start += n;
        }
        self.colour_start.push(start);
        self.order.clear();
        self.order.resize(count, 0);
        let mut next = counts;
        let mut at = 0;
        for (c, n) in next.iter_mut().enumerate() {
            let count = *n;
            *n = at;
            at += count;
            debug_assert_eq!(*n, self.colour_start[c]);
        }
        for (g, &c) in self.colour_of.iter().enumerate() {
            self.order[next[c]] = g;
            next[c] += 1;
        }

        // within a colour the manifolds share no moving body, so their order there changes no bit:
        // by number of points (then pair order), so that a batch's four have as many points as
        // possible alike and few slots are padding (the pyramid's 4- and 6-point manifolds)
        let points = |g: usize| {
            let (s, e) = range(g);
            e - s
        };
        for c in 0..COLOURS {
            self.order[self.colour_start[c]..self.colour_start[c + 1]].sort_unstable_by_key(|&g| (points(g), g));
        }
        // batches of four manifolds per colour, slot j holding the j-th point of each
        self.batches.clear();
        self.batch_start.clear();
        self.slot_index.clear();
        self.singles.clear();
        self.used.clear();
        for c in 0..COLOURS {
            self.batch_start.push(self.batches.len());
            let members = &self.order[self.colour_start[c]..self.colour_start[c + 1]];
            if let [g] = *members {
                self.used.push(Colour::Single(self.singles.len()));
                self.singles.push(g);
                continue;
            }
            if !members.is_empty() {
                let first = self.batches.len();
                self.used.push(Colour::Batches(first, first + members.len().div_ceil(LANES)));
            }
            for chunk in members.chunks(LANES) {
                let first = self.slot_index.len();
                let mut batch = Batch {
                    manifold: [NONE; LANES],
                    a: [NONE; LANES],
                    b: [NONE; LANES],
                    moving_a: [false; LANES],
                    moving_b: [false; LANES],
                    slots: (first, first),
                };
                let mut most = 0;
                for (k, &g) in chunk.iter().enumerate() {
                    let (a, b) = pair(g);
                    batch.manifold[k] = g;
                    (batch.a[k], batch.b[k]) = (a, b);
                    (batch.moving_a[k], batch.moving_b[k]) = (moving(a), moving(b));
                    most = most.max(points(g));
                }
                for j in 0..most {
                    let mut index = [NONE; LANES];
                    for (k, &g) in chunk.iter().enumerate() {
                        let (s, e) = range(g);
                        if s + j < e {
                            index[k] = s + j;
                        }
                    }
                    self.slot_index.push(index);
                }
                batch.slots.1 = self.slot_index.len();
                self.batches.push(batch);
            }
        }
        self.batch_start.push(self.batches.len());
    }

    /// The number of colours in use and of the manifolds left to the overflow.
    pub fn colours_used(&self) -> (usize, usize) {
        (self.used.len(), self.overflow.len() - self.singles.len())
    }

    /// The manifolds in the order the solver takes them: the colours' in batch order, then the
    /// overflow (indices into the `groups` given to [`build`](Self::build)).
    pub fn order(&self) -> &[usize] {
        &self.order
    }

    /// The batches of colour `c` (none for a colour of one manifold, which the scalar solver takes).
    pub fn colour_batches(&self, c: usize) -> Range<usize> {
        self.batch_start[c]..self.batch_start[c + 1]
    }

    /// Warm start of every manifold: the colours, then the overflow.
    pub fn warm_start(&mut self, constraints: &[Constraint], bodies: &mut [SolverBody]) {
        for k in 0..self.used.len() {
            match self.used[k] {
                Colour::Batches(first, end) => self.warm_start_batches(first..end, bodies),
                Colour::Single(j) => self.warm_start_one(j, constraints, bodies),
            }
        }
        for j in self.singles.len()..self.overflow.len() {
            self.warm_start_one(j, constraints, bodies);
        }
    }

    /// The warm start of `overflow[j]` by the scalar solver.
    fn warm_start_one(&self, j: usize, constraints: &[Constraint], bodies: &mut [SolverBody]) {
        let (s, e) = self.overflow[j];
        if self.patch {
            warm_start_patch_pair(&constraints[s..e], &self.overflow_patches[j], bodies);
        } else {
            warm_start_pair(&constraints[s..e], bodies);
        }
    }

    /// One sweep over `overflow[j]` by the scalar solver.
    fn solve_one(&mut self, j: usize, constraints: &mut [Constraint], bodies: &mut [SolverBody], sweep: &Sweep) {
        let (s, e) = self.overflow[j];
        if self.patch {
            solve_patch_pair(&mut constraints[s..e], &mut self.overflow_patches[j], bodies, sweep);
        } else {
            solve_pair(&mut constraints[s..e], bodies, sweep);
        }
    }

    /// One sweep over every manifold: the colours, then the overflow.
    pub fn solve(&mut self, constraints: &mut [Constraint], bodies: &mut [SolverBody], sweep: &Sweep) {
        for k in 0..self.used.len() {
            match self.used[k] {
                Colour::Batches(first, end) => self.solve_batches(first..end, bodies, sweep),
                Colour::Single(j) => self.solve_one(j, constraints, bodies, sweep),
            }
        }
        for j in self.singles.len()..self.overflow.len() {
            self.solve_one(j, constraints, bodies, sweep);
        }
    }

    /// The warm start of a range of batches of one colour.
    #[allow(unsafe_code)]
    pub fn warm_start_batches(&mut self, batches: Range<usize>, bodies: &mut [SolverBody]) {
        if self.patch {
            self.warm_start_batches_as::<true>(batches, bodies);
        } else {
            self.warm_start_batches_as::<false>(batches, bodies);
        }
    }

    /// [`warm_start_batches`](Self::warm_start_batches) with the friction model known when compiling.
    #[allow(unsafe_code)]
    fn warm_start_batches_as<const PATCH: bool>(&mut self, range: Range<usize>, bodies: &mut [SolverBody]) {
        let batches = &self.batches[range.clone()];
        let patches = if PATCH { &mut self.patches[range] } else { &mut [] };
        #[cfg(target_arch = "x86_64")]
        if self.avx {
            // SAFETY: `build` found AVX2 on this CPU
            return unsafe {
                avx::warm_start::<PATCH>(batches, avx::slots(&mut self.slots), avx::patches(patches), bodies)
            };
        }
        warm_start_in::<f64x4, PATCH>(batches, &self.slots, patches, bodies);
    }

    /// One sweep over a range of batches of one colour (see [`Constraint::solve`]). A relaxing sweep
    /// with `sweep.moved` also measures the separations that the next relaxing and biased sweeps
    /// use: the bodies must not move between a relaxing sweep and the next biased one, nor between
    /// [`build`](Self::build) and the first biased sweep, and a relaxing sweep without
    /// `sweep.moved` must follow one at the same positions.
    pub fn solve_batches(&mut self, batches: Range<usize>, bodies: &mut [SolverBody], sweep: &Sweep) {
        match (sweep.pass, sweep.moved, self.patch) {
            (Pass::Solve, _, false) => self.sweep_batches::<false, false, false>(batches, bodies, sweep),
            (Pass::Relax, true, false) => self.sweep_batches::<true, true, false>(batches, bodies, sweep),
            (Pass::Relax, false, false) => self.sweep_batches::<true, false, false>(batches, bodies, sweep),
            (Pass::Solve, _, true) => self.sweep_batches::<false, false, true>(batches, bodies, sweep),
            (Pass::Relax, true, true) => self.sweep_batches::<true, true, true>(batches, bodies, sweep),
            (Pass::Relax, false, true) => self.sweep_batches::<true, false, true>(batches, bodies, sweep),
        }
    }

    /// [`solve_batches`](Self::solve_batches) with the pass and the friction model known when
    /// compiling.
    #[allow(unsafe_code)]
    fn sweep_batches<const RELAX: bool, const MEASURE: bool, const PATCH: bool>(
        &mut self,
        range: Range<usize>,
        bodies: &mut [SolverBody],
        sweep: &Sweep,
    ) {
        let batches = &self.batches[range.clone()];
        let patches = if PATCH { &mut self.patches[range] } else { &mut [] };
        #[cfg(target_arch = "x86_64")]
        if self.avx {
            // SAFETY: `build` found AVX2 on this CPU
            return unsafe {
                avx::sweep::<RELAX, MEASURE, PATCH>(
                    batches,
                    avx::slots(&mut self.slots),
                    avx::patches(patches),
                    bodies,
                    sweep,
                )
            };
        }
        sweep_in::<f64x4, RELAX, MEASURE, PATCH>(batches, &mut self.slots, patches, bodies, sweep);
    }

    /// Adds each constraint's accumulated impulses to its sum over the substeps: in the lanes for
    /// the colours' constraints, in `sums` (aligned with `constraints`) for the overflow's.
    pub fn accumulate(&mut self, constraints: &[Constraint], sums: &mut [[f64; 3]]) {
        for slot in &mut self.slots {
            for j in 0..3 {
                slot.lambda_sum[j] += slot.lambda[j];
            }
        }
        for patch in &mut self.patches {
            for j in 0..3 {
                patch.lambda_sum[j] += patch.lambda[j];
            }
        }
        for (sum, patch) in self.overflow_patch_sums.iter_mut().zip(&self.overflow_patches) {
            for (x, l) in sum.iter_mut().zip(patch.lambda) {
                *x += l;
            }
        }
        for &(s, e) in &self.overflow {
            for (sum, k) in sums[s..e].iter_mut().zip(&constraints[s..e]) {
                for (x, l) in sum.iter_mut().zip(k.lambda) {
                    *x += l;
                }
            }
        }
    }

    /// Each point of [`build_points`](Self::build_points) with its tangents, its accumulated
    /// impulses and their sum over the substeps: `f(point, t1, t2, λ, Σλ)` (indices of the points
    /// given to the build); `constraints` and `sums` the overflow's, as given to the passes.
    pub fn for_each_point(
        &self,
        constraints: &[Constraint],
        sums: &[[f64; 3]],
        mut f: impl FnMut(usize, DVec3, DVec3, [f64; 3], [f64; 3]),
    ) {
        for (slot, index) in self.slots.iter().zip(&self.slot_index) {
            let l = slot.lambda.map(|x| x.to_array());
            let sum = slot.lambda_sum.map(|x| x.to_array());
            for (k, &i) in index.iter().enumerate() {
                if i != NONE {
                    f(
                        i,
                        slot.t1.lane(k),
                        slot.t2.lane(k),
                        [l[0][k], l[1][k], l[2][k]],
                        [sum[0][k], sum[1][k], sum[2][k]],
                    );
                }
            }
        }
        for (&(s, e), &first) in self.overflow.iter().zip(&self.overflow_points) {
            for (j, (k, sum)) in constraints[s..e].iter().zip(&sums[s..e]).enumerate() {
                f(first + j, k.t1, k.t2, k.lambda, *sum);
            }
        }
    }

    /// Each point of [`build_points`](Self::build_points) with its impulse over the step, `Σλ_n n +
    /// Σλ_t1 t1 + Σλ_t2 t2` (N·s: the sums over the substeps along its normal and tangents, computed
    /// in the lanes for the colours' points, the same operations as for one point), its
    /// accumulated impulses `λ` and `Σλ_n`: `f(point, impulse, λ, Σλ_n)`; `constraints` and `sums`
    /// the overflow's, as given to the passes.
    pub fn for_each_point_impulse(
        &self,
        constraints: &[Constraint],
        sums: &[[f64; 3]],
        mut f: impl FnMut(usize, DVec3, [f64; 3], f64),
    ) {
        for (slot, index) in self.slots.iter().zip(&self.slot_index) {
            let [s0, s1, s2] = slot.lambda_sum;
            let impulse = slot.n.scale(s0).add(slot.t1.scale(s1)).add(slot.t2.scale(s2));
            let (x, y, z) = (impulse.x.to_array(), impulse.y.to_array(), impulse.z.to_array());
            let l = slot.lambda.map(|x| x.to_array());
            let normal_sum = s0.to_array();
            for (k, &i) in index.iter().enumerate() {
                if i != NONE {
                    f(i, DVec3::new(x[k], y[k], z[k]), [l[0][k], l[1][k], l[2][k]], normal_sum[k]);
                }
            }
        }
        for (&(s, e), &first) in self.overflow.iter().zip(&self.overflow_points) {
            for (j, (k, sum)) in constraints[s..e].iter().zip(&sums[s..e]).enumerate() {
                f(first + j, sum[0] * k.n + sum[1] * k.t1 + sum[2] * k.t2, k.lambda, sum[0]);
            }
        }
    }

    /// Each manifold's [`Patch`] after the solve ([`FrictionModel::Manifold`]): `f(manifold, n, t1,
    /// t2, λ, Σλ)` with the patch's normal and tangents, its accumulated impulses `[λ_t1, λ_t2,
    /// λ_τ]` and their sum over the substeps (indices of the manifolds given to
    /// [`build_points`](Self::build_points)). Nothing with per-point friction.
    pub fn for_each_patch(&self, mut f: impl FnMut(usize, DVec3, DVec3, DVec3, [f64; 3], [f64; 3])) {
        for (batch, patch) in self.batches.iter().zip(&self.patches) {
            let l = patch.lambda.map(|x| x.to_array());
            let sum = patch.lambda_sum.map(|x| x.to_array());
            for (k, &g) in batch.manifold.iter().enumerate() {
                if g != NONE {
                    let (n, t1, t2) = (patch.n.lane(k), patch.t1.lane(k), patch.t2.lane(k));
                    f(g, n, t1, t2, [l[0][k], l[1][k], l[2][k]], [sum[0][k], sum[1][k], sum[2][k]]);
                }
            }
        }
        for ((p, sum), &g) in self.overflow_patches.iter().zip(&self.overflow_patch_sums).zip(&self.overflow_manifold) {
            f(g, p.n, p.t1, p.t2, p.lambda, *sum);
        }
    }

    /// The centre of manifold `g`'s points ([`patch_centre`]) as the last
    /// [`build_points`](Self::build_points) with [`FrictionModel::Manifold`] found it.
    pub fn patch_centre(&self, g: usize) -> DVec3 {
        self.patch_centres[g]
    }

    /// Copies the lanes' accumulated impulses back to their constraints.
    pub fn store_lambdas(&self, constraints: &mut [Constraint]) {
        for (slot, index) in self.slots.iter().zip(&self.slot_index) {
            let l = slot.lambda.map(|x| x.to_array());
            for (k, &i) in index.iter().enumerate() {
                if i != NONE {
                    constraints[i].lambda = [l[0][k], l[1][k], l[2][k]];
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::solver::{Motion, Softness};
    use crate::math::{DMat3, DQuat};

    /// xorshift64*: a fixed sequence, no dependency.
    struct Rng(u64);

    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
        }
        /// Uniform in [lo, hi).
        fn range(&mut self, lo: f64, hi: f64) -> f64 {
            lo + (hi - lo) * (self.next() >> 11) as f64 / (1u64 << 53) as f64
        }
        fn vec(&mut self, r: f64) -> DVec3 {
            DVec3::new(self.range(-r, r), self.range(-r, r), self.range(-r, r))
        }
        fn unit(&mut self) -> DVec3 {
            loop {
                let v = self.vec(1.0);
                if v.length_squared() > 0.01 && v.length_squared() < 1.0 {
                    return v.normalize();
                }
            }
        }
        fn rotation(&mut self, angle: f64) -> DQuat {
            DQuat::from_axis_angle(self.unit(), self.range(-angle, angle))
        }
    }

    /// Bodies, whether each moves, constraints, and the manifolds as ranges of the constraints.
    type Scene = (Vec<SolverBody>, Vec<bool>, Vec<Constraint>, Vec<(usize, usize)>);

    /// Bodies (the first `fixed` of them fixed), and manifolds of 1–5 points between pairs of them:
    /// every pair of `hub` with the others, plus random pairs; in pair order.
    fn scene(rng: &mut Rng, count: usize, fixed: usize, extra_pairs: usize) -> Scene {
        let mut bodies = Vec::new();
        let mut moving = Vec::new();
        for i in 0..count {
            if i < fixed {
                bodies.push(SolverBody::FIXED);
                moving.push(false);
                continue;
            }
            let r = DMat3::from_quat(rng.rotation(3.0));
            let inertia =
                DMat3::from_diagonal(DVec3::new(rng.range(0.2, 3.0), rng.range(0.2, 3.0), rng.range(0.2, 3.0)));
            let dq = rng.rotation(0.05);
            bodies.push(SolverBody {
                inv_mass: rng.range(0.1, 2.0),
                inv_inertia: r * inertia * r.transpose(),
                v: rng.vec(1.0),
                w: rng.vec(2.0),
                accel: DVec3::new(0.0, 0.0, -9.81),
                dx: rng.vec(0.01),
                dq,
                drot: DMat3::from_quat(dq),
                touched: false,
            });
            moving.push(true);
        }
        let positions: Vec<DVec3> = (0..count).map(|_| rng.vec(2.0)).collect();
        let hub = fixed;
        let mut pairs: Vec<(usize, usize)> =
            (0..count).filter(|&i| i != hub).map(|i| (i.min(hub), i.max(hub))).collect();
        while pairs.len() < count - 1 + extra_pairs {
            let (a, b) = ((rng.next() % count as u64) as usize, (rng.next() % count as u64) as usize);
            if a < b && b >= fixed && !pairs.contains(&(a, b)) {
                pairs.push((a, b));
            }
        }
        pairs.sort();
        let softness = [
            Softness::new(60.0, 10.0, 1.0 / 360.0),
            Softness::new(120.0, 10.0, 1.0 / 360.0),
            Softness::new(0.0, 0.0, 1.0 / 360.0),
        ];
        let mut constraints = Vec::new();
        let mut groups = Vec::new();
        for (a, b) in pairs {
            let start = constraints.len();
            let points = 1 + (rng.next() % 5) as usize;
            let n = rng.unit();
            let mu = [0.0, 0.3, 1.0, 0.6][(rng.next() % 4) as usize];
            let soft = softness[(rng.next() % 3) as usize];
            for _ in 0..points {
                let point = 0.5 * (positions[a] + positions[b]) + rng.vec(0.5);
                let gap = rng.range(-0.02, 0.01);
                let mut k = Constraint::new(&bodies, &positions, a, b, point, n, gap, mu, soft);
                if rng.next() % 5 < 3 {
                    k.lambda = [rng.range(0.0, 2.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)];
                }
                constraints.push(k);
            }
            groups.push((start, constraints.len()));
        }
        (bodies, moving, constraints, groups)
    }

    /// `random` distinct pairs `(a, b)`, `a < b`, `b` moving, and every pair of `hub` with the others (a
    /// hub in more pairs than there are colours: some manifolds overflow), sorted.
    fn random_pairs(rng: &mut Rng, count: usize, hub: usize, moving: &[bool], random: usize) -> Vec<(usize, usize)> {
        let mut pairs: Vec<(usize, usize)> = Vec::new();
        while pairs.len() < random {
            let (a, b) = ((rng.next() % count as u64) as usize, (rng.next() % count as u64) as usize);
            if a < b && moving[b] && !pairs.contains(&(a, b)) {
                pairs.push((a, b));
            }
        }
        pairs.extend((0..count).filter(|&i| i != hub).map(|i| (i.min(hub), i.max(hub))));
        pairs.sort();
        pairs.dedup();
        pairs
    }

    /// What the scalar solves went through.
    #[derive(Debug, Default)]
    struct Branches {
        let_go: usize,
        open: usize,
        biased: usize,
        relaxed: usize,
        sliding: usize,
        sticking: usize,
    }

    /// The scalar reference: [`Constraint::solve`] over the manifolds in `order`, each with its pair's
    /// velocities held locally as in [`solve_pair`], counting the branches taken.
    fn scalar_sweep(
        order: &[usize],
        groups: &[(usize, usize)],
        constraints: &mut [Constraint],
        bodies: &mut [SolverBody],
        sweep: &Sweep,
        seen: &mut Branches,
    ) {
        for &g in order {
            let (s, e) = groups[g];
            let (a, b) = (constraints[s].a, constraints[s].b);
            let of = |x: &SolverBody| Motion { inv_mass: x.inv_mass, v: x.v, w: x.w, dx: x.dx, drot: x.drot };
            let (mut ma, mut mb) = (of(&bodies[a]), of(&bodies[b]));
            let mut any = false;
            crate::contact::solver::in_sweep_order(&mut constraints[s..e], sweep, |k| {
                let u = (mb.v + mb.w.cross(k.r_b)) - (ma.v + ma.w.cross(k.r_a));
                let sep = k.adjusted_gap + k.n.dot((mb.dx + mb.drot * k.r_b) - (ma.dx + ma.drot * k.r_a));
                if k.speculative && -u.dot(k.n) > sweep.impact_speed {
                    seen.let_go += (k.lambda != [0.0; 3]) as usize;
                } else if sep > 0.0 {
                    seen.open += 1;
                } else if sweep.pass == Pass::Solve {
                    seen.biased += 1;
                } else {
                    seen.relaxed += 1;
                }
                any |= k.solve(&mut ma, &mut mb, sweep);
                let limit = k.mu * k.lambda[0];
                if limit > 0.0 {
                    let t = (k.lambda[1] * k.lambda[1] + k.lambda[2] * k.lambda[2]).sqrt();
                    if t > limit * (1.0 - 1e-12) {
                        seen.sliding += 1;
                    } else {
                        seen.sticking += 1;
                    }
                }
            });
            for (i, m) in [(a, ma), (b, mb)] {
                bodies[i].v = m.v;
                bodies[i].w = m.w;
                bodies[i].touched |= any;
            }
        }
    }

    fn scalar_warm_start(
        order: &[usize],
        groups: &[(usize, usize)],
        constraints: &[Constraint],
        bodies: &mut [SolverBody],
    ) {
        for &g in order {
            let (s, e) = groups[g];
            warm_start_pair(&constraints[s..e], bodies);
        }
    }

    /// Whether `x` and `y` are the same bits; zeros of opposite signs pass and are counted in `zeros`
    /// (about 1.5 % of the values compared: the sign of a zero impulse, which changes no velocity;
    /// where it comes from is not found yet).
    fn same(x: f64, y: f64, zeros: &mut usize) -> bool {
        if x.to_bits() == y.to_bits() {
            return true;
        }
        *zeros += (x == 0.0 && y == 0.0) as usize;
        x == 0.0 && y == 0.0
    }

    fn assert_same(
        what: &str,
        moving: &[bool],
        scalar: (&[SolverBody], &[Constraint]),
        lanes: (&[SolverBody], &[Constraint]),
        zeros: &mut usize,
    ) {
        for (i, (x, y)) in scalar.0.iter().zip(lanes.0).enumerate() {
            let values = |b: &SolverBody| [b.v.x, b.v.y, b.v.z, b.w.x, b.w.y, b.w.z];
            let ok = values(x).iter().zip(values(y)).all(|(&p, q)| same(p, q, zeros));
            assert!(ok, "{what}: body {i} velocities {:?} {:?} / {:?} {:?}", x.v, x.w, y.v, y.w);
            // the scalar solve also marks fixed bodies, which nothing reads
            assert!(!moving[i] || x.touched == y.touched, "{what}: body {i} touched");
        }
        for (i, (x, y)) in scalar.1.iter().zip(lanes.1).enumerate() {
            let ok = x.lambda.iter().zip(y.lambda).all(|(&p, q)| same(p, q, zeros));
            assert!(ok, "{what}: constraint {i} λ {:?} / {:?}", x.lambda, y.lambda);
        }
    }

    /// Random bodies and manifolds, three substeps of warm start, biased sweep, motion and two
    /// relaxing sweeps: the lanes give the scalar solver's velocities and impulses bit for bit (up to
    /// the sign of zeros, counted and printed), and each point's impulse over the substeps the bits
    /// of the formula for one point, in the colour
    /// order, with every branch of the scalar solve taken many times and some manifolds in the
    /// overflow (a hub body in more pairs than there are colours).
    #[test]
    fn lanes_match_the_scalar_solve_bit_for_bit() {
        lanes_match(true);
    }

    /// The same with the kernel this CPU dispatches to (AVX2 where present: see the printed line).
    #[test]
    fn dispatched_lanes_match_the_scalar_solve_bit_for_bit() {
        lanes_match(false);
    }

    /// The check of the two tests above: `portable` keeps `wide::f64x4`, else the dispatched kernel.
    fn lanes_match(portable: bool) {
        let mut seen = Branches::default();
        let mut overflowed = 0;
        let mut singles = 0;
        let mut zeros = 0;
        let mut values = 0;
        let mut impulses_compared = 0;
        for seed in 1..=40u64 {
            let mut rng = Rng(0x9e37_79b9_7f4a_7c15 ^ seed.wrapping_mul(0xd1b5_4a32_d192_ed03));
            let count = 8 + (seed as usize % 4) * 8;
            let (bodies, moving, constraints, groups) = scene(&mut rng, count, 1 + seed as usize % 3, 2 * count);
            let mut lanes = LaneSolver { portable, ..LaneSolver::default() };
            lanes.build(&groups, &constraints, &bodies, |i| moving[i]);
            if seed == 1 {
                eprintln!("kernel: {}", if lanes.avx { "AVX2" } else { "portable f64x4" });
            }
            overflowed += lanes.colours_used().1;
            singles += lanes.singles.len();
            let order = lanes.order().to_vec();
            let (mut sb, mut sc) = (bodies.clone(), constraints.clone());
            let (mut lb, mut lc) = (bodies, constraints);
            let mut sums = vec![[0.0; 3]; lc.len()];
            let h = 1.0 / 360.0;
            for substep in 0..3 {
                for i in (0..sb.len()).filter(|&i| moving[i]) {
                    sb[i].integrate_velocity(h);
                    lb[i].integrate_velocity(h);
                }
                scalar_warm_start(&order, &groups, &sc, &mut sb);
                lanes.warm_start(&lc, &mut lb);
                assert_same(
                    &format!("seed {seed} substep {substep} warm start"),
                    &moving,
                    (&sb, &sc),
                    (&lb, &lc),
                    &mut zeros,
                );
                // two relaxing sweeps: the second keeps the separations the first measured
                for (pass, moved) in [(Pass::Solve, true), (Pass::Relax, true), (Pass::Relax, false)] {
                    let sweep = Sweep {
                        // both directions of the points
                        reverse: (substep + usize::from(pass == Pass::Relax)) % 2 == 1,
                        pass,
                        inv_h: 1.0 / h,
                        slop: [0.0, 0.001][seed as usize % 2],
                        max_push: 3.0,
                        impact_speed: 0.5,
                        moved,
                    };
                    scalar_sweep(&order, &groups, &mut sc, &mut sb, &sweep, &mut seen);
                    lanes.solve(&mut lc, &mut lb, &sweep);
                    lanes.store_lambdas(&mut lc);
                    assert_same(
                        &format!("seed {seed} substep {substep} {pass:?}"),
                        &moving,
                        (&sb, &sc),
                        (&lb, &lc),
                        &mut zeros,
                    );
                    values += 6 * sb.len() + 3 * sc.len();
                    if pass == Pass::Solve {
                        for i in (0..sb.len()).filter(|&i| moving[i]) {
                            sb[i].integrate_position(h);
                            lb[i].integrate_position(h);
                        }
                    }
                }
                // the impulses over the substeps so far, in the lanes: the bits of the formula
                // for one point
                lanes.accumulate(&lc, &mut sums);
                let mut expected = vec![None; lc.len()];
                lanes.for_each_point(&lc, &sums, |i, t1, t2, lambda, sum| {
                    expected[i] = Some((sum[0] * lc[i].n + sum[1] * t1 + sum[2] * t2, lambda, sum[0]));
                });
                let mut reached = 0;
                lanes.for_each_point_impulse(&lc, &sums, |i, impulse, lambda, normal_sum| {
                    let (p, l, s) = expected[i].expect("a point of the build");
                    let same_bits = |a: f64, b: f64| a.to_bits() == b.to_bits();
                    let ok = [(impulse.x, p.x), (impulse.y, p.y), (impulse.z, p.z), (normal_sum, s)]
                        .into_iter()
                        .chain(lambda.into_iter().zip(l))
                        .all(|(a, b)| same_bits(a, b));
                    assert!(ok, "seed {seed} substep {substep}: point {i} impulse {impulse:?} / {p:?}");
                    reached += 1;
                });
                assert_eq!(reached, lc.len());
                impulses_compared += reached;
            }
        }
        assert!(impulses_compared > 1000, "impulses compared {impulses_compared}");
        eprintln!("branches {seen:?}, manifolds in the overflow {overflowed}, colours of one manifold {singles}, values compared {values}, zeros of opposite sign {zeros}");
        for (name, n) in [
            ("let go", seen.let_go),
            ("open", seen.open),
            ("biased", seen.biased),
            ("relaxed", seen.relaxed),
            ("sliding", seen.sliding),
            ("sticking", seen.sticking),
        ] {
            assert!(n >= 50, "{name} taken {n} times");
        }
        assert!(overflowed > 0);
        assert!(singles > 0);
    }

    /// The slots computed in the lanes from the manifolds and their points are those loaded from
    /// the scalar [`Constraint::new`] of the same points, bit for bit, every field and lane, with
    /// either kernel; so are the overflow's constraints; and [`LaneSolver::for_each_point`] gives
    /// every point once, with its constraint's tangents and impulses.
    #[test]
    fn slots_computed_in_lanes_are_the_scalar_constraints() {
        for portable in [true, false] {
            for seed in 1..=12u64 {
                let mut rng = Rng(0x51_7cc1_b727_220a ^ seed.wrapping_mul(0x9e37_79b9_7f4a_7c15));
                let (count, hub) = (30 + (seed as usize % 4) * 8, 1 + seed as usize % 3);
                let (mut bodies, moving, _, _) = scene(&mut rng, count, hub, 0);
                if seed % 2 == 1 {
                    // no motion yet, as at the start of a step: the lanes measure the separations
                    // with constants (`PointInput::unmoved`), the scalar build with the gathered
                    // motion
                    for b in &mut bodies {
                        (b.dx, b.dq, b.drot) = (SolverBody::FIXED.dx, SolverBody::FIXED.dq, SolverBody::FIXED.drot);
                    }
                    assert!(bodies.iter().all(SolverBody::unmoved));
                }
                let positions: Vec<DVec3> = (0..count).map(|_| rng.vec(2.0)).collect();
                let pairs = random_pairs(&mut rng, count, hub, &moving, 3 * count);
                let (mut manifolds, mut points, mut constraints, mut groups) = (vec![], vec![], vec![], vec![]);
                for (a, b) in pairs {
                    let start = points.len();
                    let mu = [0.0, 0.3, 1.0][(rng.next() % 3) as usize];
                    let softness = Softness::new([0.0, 60.0, 120.0][(rng.next() % 3) as usize], 10.0, 1.0 / 360.0);
                    // normals of both signs of z, and along the axes (z = ±0)
                    let n = match rng.next() % 6 {
                        0 => DVec3::X,
                        1 => DVec3::new(0.0, -1.0, -0.0),
                        2 => -DVec3::Z,
                        _ => rng.unit(),
                    };
                    for _ in 0..1 + (rng.next() % 6) as usize {
                        let point = 0.5 * (positions[a] + positions[b]) + rng.vec(0.5);
                        let gap = rng.range(-0.02, 0.01);
                        let lambda = if rng.next() % 2 == 0 {
                            [rng.range(0.0, 2.0), rng.range(-1.0, 1.0), 0.5]
                        } else {
                            [0.0; 3]
                        };
                        points.push(ContactPoint { point, n, gap, lambda });
                        let mut k = Constraint::new(&bodies, &positions, a, b, point, n, gap, mu, softness);
                        k.lambda = lambda;
                        constraints.push(k);
                    }
                    manifolds.push(Manifold {
                        a,
                        b,
                        points: (start, points.len()),
                        mu,
                        softness,
                        friction_warm: [DVec3::ZERO; 2],
                    });
                    groups.push((start, points.len()));
                }
                let mut scalar = LaneSolver { portable, ..LaneSolver::default() };
                scalar.build(&groups, &constraints, &bodies, |i| moving[i]);
                let mut lanes = LaneSolver { portable, ..LaneSolver::default() };
                let mut overflow = Vec::new();
                // twice, the second over the first's slots (they are overwritten, not cleared)
                for _ in 0..2 {
                    let point = FrictionModel::Point;
                    lanes.build_points(&manifolds, &points, &bodies, &positions, |i| moving[i], point, &mut overflow);
                }
                assert_eq!(scalar.slot_index, lanes.slot_index);
                assert_eq!(scalar.slots.len(), lanes.slots.len());
                const WORDS: usize = size_of::<Slot<f64x4>>() / 8;
                let bits = |slot: &Slot<f64x4>| {
                    let mut out = [0u64; WORDS];
                    let lanes: [f64x4; WORDS / 4] = slot_lanes(slot);
                    for (j, l) in lanes.iter().enumerate() {
                        for (k, x) in l.to_array().iter().enumerate() {
                            out[4 * j + k] = x.to_bits();
                        }
                    }
                    out
                };
                for (i, (x, y)) in scalar.slots.iter().zip(&lanes.slots).enumerate() {
                    assert!(bits(x) == bits(y), "seed {seed}, portable {portable}: slot {i}\n{x:?}\n{y:?}");
                }
                assert!(lanes.colours_used().1 > 0, "seed {seed}: no overflow");
                let mut seen = vec![0; points.len()];
                lanes.for_each_point(&overflow, &vec![[0.0; 3]; overflow.len()], |i, t1, t2, lambda, _| {
                    seen[i] += 1;
                    let k = &constraints[i];
                    assert!(t1 == k.t1 && t2 == k.t2 && lambda == k.lambda, "point {i}");
                });
                assert!(seen.iter().all(|&n| n == 1));
                for (&(s, e), &first) in lanes.overflow.iter().zip(&lanes.overflow_points) {
                    for (j, k) in overflow[s..e].iter().enumerate() {
                        let c = &constraints[first + j];
                        assert!(
                            k.r_a == c.r_a
                                && k.ang_b == c.ang_b
                                && k.tangent_mass == c.tangent_mass
                                && k.lambda == c.lambda
                        );
                    }
                }
            }
        }
    }

    /// A build over the same manifolds as the last one (pairs, numbers of points, moving bodies)
    /// keeps its colours and batches and takes the slots' points from the new ranges: the same
    /// layout and slots as a fresh solver's, when the points moved within the list (a point
    /// inserted at the front) and when a manifold's number of points changed.
    #[test]
    fn a_build_over_the_same_manifolds_keeps_the_layout() {
        let mut rng = Rng(0x2545_f491_4f6c_dd1d);
        let count = 40;
        let (bodies, moving, _, _) = scene(&mut rng, count, 2, 0);
        let positions: Vec<DVec3> = (0..count).map(|_| rng.vec(2.0)).collect();
        let pairs = random_pairs(&mut rng, count, 2, &moving, 3 * count);
        let sizes: Vec<usize> = pairs.iter().map(|_| 1 + (rng.next() % 6) as usize).collect();
        let make = |rng: &mut Rng, front: usize, sizes: &[usize]| {
            let mut points: Vec<ContactPoint> = (0..front)
                .map(|_| ContactPoint { point: DVec3::ZERO, n: DVec3::Z, gap: 0.0, lambda: [0.0; 3] })
                .collect();
            let mut manifolds = Vec::new();
            for (&(a, b), &size) in pairs.iter().zip(sizes) {
                let start = points.len();
                for _ in 0..size {
                    let point = 0.5 * (positions[a] + positions[b]) + rng.vec(0.5);
                    points.push(ContactPoint { point, n: rng.unit(), gap: rng.range(-0.02, 0.01), lambda: [0.0; 3] });
                }
                let softness = Softness::new(60.0, 10.0, 1.0 / 360.0);
                let friction_warm = [DVec3::ZERO; 2];
                manifolds.push(Manifold { a, b, points: (start, points.len()), mu: 0.5, softness, friction_warm });
            }
            (manifolds, points)
        };
        let mut kept = LaneSolver::default();
        let mut overflow = Vec::new();
        let (m, p) = make(&mut rng, 0, &sizes);
        kept.build_points(&m, &p, &bodies, &positions, |i| moving[i], FrictionModel::Point, &mut overflow);
        let mut fewer = sizes.clone();
        fewer[3] = if fewer[3] == 1 { 2 } else { 1 };
        for (front, sizes) in [(1, &sizes), (3, &fewer), (0, &sizes)] {
            let (m, p) = make(&mut rng, front, sizes);
            kept.build_points(&m, &p, &bodies, &positions, |i| moving[i], FrictionModel::Point, &mut overflow);
            let mut fresh = LaneSolver::default();
            let mut fresh_overflow = Vec::new();
            fresh.build_points(&m, &p, &bodies, &positions, |i| moving[i], FrictionModel::Point, &mut fresh_overflow);
            assert_eq!(kept.order, fresh.order);
            assert_eq!(kept.slot_index, fresh.slot_index, "front {front}");
            assert_eq!(kept.overflow, fresh.overflow);
            assert_eq!(kept.overflow_points, fresh.overflow_points);
            assert_eq!(format!("{:?}", kept.slots), format!("{:?}", fresh.slots));
        }
    }

    /// With per-manifold friction the lanes give the scalar solver's velocities and impulses bit
    /// for bit (up to the sign of zeros): random manifolds of 1–6 points (some with points of
    /// different normals, some warm started), built by [`LaneSolver::build_points`], against
    /// [`Patch::new`], [`warm_start_patch_pair`] and [`solve_patch_pair`] over the manifolds in the
    /// colour order, three substeps of warm start, biased sweep, motion and relaxing sweep, with
    /// either kernel; the patches slide, stick and reach their twist limit many times.
    #[test]
    fn manifold_friction_in_lanes_matches_the_scalar_solve() {
        let (mut sliding, mut sticking, mut twisting, mut singles, mut zeros) = (0, 0, 0, 0, 0);
        for portable in [true, false] {
            for seed in 1..=16u64 {
                let mut rng = Rng(0x2f_6b3a_9c11_d4e7 ^ seed.wrapping_mul(0x9e37_79b9_7f4a_7c15));
                let (count, hub) = (20 + (seed as usize % 4) * 8, 1 + seed as usize % 3);
                let (bodies, moving, _, _) = scene(&mut rng, count, hub, 0);
                let positions: Vec<DVec3> = (0..count).map(|_| rng.vec(2.0)).collect();
                let pairs = random_pairs(&mut rng, count, hub, &moving, 2 * count);
                let (mut manifolds, mut points) = (vec![], vec![]);
                for (a, b) in pairs {
                    let start = points.len();
                    let mu = [0.0, 0.3, 1.0, 0.6][(rng.next() % 4) as usize];
                    let softness = Softness::new([0.0, 60.0, 120.0][(rng.next() % 3) as usize], 10.0, 1.0 / 360.0);
                    let n = rng.unit();
                    let bent = rng.next() % 4 == 0;
                    for _ in 0..1 + (rng.next() % 6) as usize {
                        let point = 0.5 * (positions[a] + positions[b]) + rng.vec(0.5);
                        let n = if bent { (n + rng.vec(0.2)).normalize() } else { n };
                        let lambda = if rng.next() % 2 == 0 { [rng.range(0.0, 2.0), 0.0, 0.0] } else { [0.0; 3] };
                        points.push(ContactPoint { point, n, gap: rng.range(-0.02, 0.01), lambda });
                    }
                    let friction_warm =
                        if rng.next() % 2 == 0 { [rng.vec(1.0), rng.vec(0.5)] } else { [DVec3::ZERO; 2] };
                    manifolds.push(Manifold { a, b, points: (start, points.len()), mu, softness, friction_warm });
                }
                let mut lanes = LaneSolver { portable, ..LaneSolver::default() };
                let mut overflow = Vec::new();
                let model = FrictionModel::Manifold;
                lanes.build_points(&manifolds, &points, &bodies, &positions, |i| moving[i], model, &mut overflow);
                singles += lanes.singles.len();
                // the scalar reference, manifold by manifold
                let mut constraints: Vec<Vec<Constraint>> = manifolds
                    .iter()
                    .map(|m| {
                        points[m.points.0..m.points.1]
                            .iter()
                            .map(|p| {
                                let mut k = Constraint::new(
                                    &bodies, &positions, m.a, m.b, p.point, p.n, p.gap, m.mu, m.softness,
                                );
                                k.lambda = p.lambda;
                                k
                            })
                            .collect()
                    })
                    .collect();
                let mut patches: Vec<Patch> = manifolds
                    .iter()
                    .map(|m| {
                        let own = &points[m.points.0..m.points.1];
                        Patch::new(&bodies, &positions, m.a, m.b, own, m.mu, m.friction_warm)
                    })
                    .collect();
                let order = lanes.order().to_vec();
                let (mut sb, mut lb) = (bodies.clone(), bodies);
                let h = 1.0 / 360.0;
                for substep in 0..3 {
                    for i in (0..sb.len()).filter(|&i| moving[i]) {
                        sb[i].integrate_velocity(h);
                        lb[i].integrate_velocity(h);
                    }
                    for &g in &order {
                        warm_start_patch_pair(&constraints[g], &patches[g], &mut sb);
                    }
                    lanes.warm_start(&overflow, &mut lb);
                    for (pass, moved) in [(Pass::Solve, true), (Pass::Relax, true), (Pass::Relax, false)] {
                        let sweep = Sweep {
                            reverse: (substep + usize::from(pass == Pass::Relax)) % 2 == 1,
                            pass,
                            inv_h: 1.0 / h,
                            slop: [0.0, 0.001][seed as usize % 2],
                            max_push: 3.0,
                            impact_speed: 0.5,
                            moved,
                        };
                        for &g in &order {
                            solve_patch_pair(&mut constraints[g], &mut patches[g], &mut sb, &sweep);
                            let p = &patches[g];
                            let limit = p.mu * constraints[g].iter().map(|k| k.lambda[0]).sum::<f64>();
                            if limit > 0.0 {
                                let t = (p.lambda[0] * p.lambda[0] + p.lambda[1] * p.lambda[1]).sqrt();
                                *if t > limit * (1.0 - 1e-12) { &mut sliding } else { &mut sticking } += 1;
                                twisting += usize::from(p.lambda[2].abs() >= limit * p.radius * (1.0 - 1e-12));
                            }
                        }
                        lanes.solve(&mut overflow, &mut lb, &sweep);
                        let what = format!("portable {portable}, seed {seed}, substep {substep}, {pass:?}");
                        for (i, (x, y)) in sb.iter().zip(&lb).enumerate() {
                            let values = |b: &SolverBody| [b.v.x, b.v.y, b.v.z, b.w.x, b.w.y, b.w.z];
                            let ok = values(x).iter().zip(values(y)).all(|(&p, q)| same(p, q, &mut zeros));
                            assert!(ok, "{what}: body {i} {:?} {:?} / {:?} {:?}", x.v, x.w, y.v, y.w);
                        }
                        lanes.for_each_patch(|g, n, t1, t2, lambda, _| {
                            let p = &patches[g];
                            assert!(n == p.n && t1 == p.t1 && t2 == p.t2, "{what}: patch {g} frame");
                            let ok = lambda.iter().zip(p.lambda).all(|(&x, y)| same(x, y, &mut zeros));
                            assert!(ok, "{what}: patch {g} λ {lambda:?} / {:?}", p.lambda);
                        });
                        let sums = vec![[0.0; 3]; overflow.len()];
                        let flat: Vec<&Constraint> = constraints.iter().flatten().collect();
                        lanes.for_each_point(&overflow, &sums, |i, _, _, lambda, _| {
                            let ok = lambda.iter().zip(flat[i].lambda).all(|(&x, y)| same(x, y, &mut zeros));
                            assert!(ok, "{what}: point {i} λ {lambda:?} / {:?}", flat[i].lambda);
                        });
                        if pass == Pass::Solve {
                            for i in (0..sb.len()).filter(|&i| moving[i]) {
                                sb[i].integrate_position(h);
                                lb[i].integrate_position(h);
                            }
                        }
                    }
                }
            }
        }
        eprintln!("patches sliding {sliding}, sticking {sticking}, at the twist limit {twisting}, colours of one manifold {singles}, zeros of opposite sign {zeros}");
        assert!(sliding >= 50 && sticking >= 50 && twisting >= 50);
        assert!(singles > 0);
    }

    /// A slot as its fields' lanes in order (`Slot` is `repr(C)` over `f64x4` fields only).
    fn slot_lanes<const N: usize>(slot: &Slot<f64x4>) -> [f64x4; N] {
        let s = slot;
        let mut out = [f64x4::splat(0.0); N];
        let fields: Vec<f64x4> = [
            [s.r_a.x, s.r_a.y, s.r_a.z, s.r_b.x, s.r_b.y, s.r_b.z].as_slice(),
            &[s.n.x, s.n.y, s.n.z, s.t1.x, s.t1.y, s.t1.z, s.t2.x, s.t2.y, s.t2.z],
            &[s.adjusted_gap, s.normal_mass, s.tangent_per_normal[0], s.tangent_per_normal[1]],
            &s.tangent_mass,
            &s.tangent_k,
            &s.ang_a.iter().chain(&s.ang_b).flat_map(|v| [v.x, v.y, v.z]).collect::<Vec<_>>(),
            &[s.mu, s.bias_rate, s.mass_scale, s.impulse_scale, s.speculative, s.valid],
            &s.lambda,
            &[s.separation],
            &s.lambda_sum,
        ]
        .concat();
        assert_eq!(fields.len(), N);
        out.copy_from_slice(&fields);
        out
    }

    /// The colouring: no two manifolds of a colour share a moving body, every manifold is once in the
    /// order, by number of points then pair order within each colour, the overflow in pair order and
    /// only when the colours ran out; with
    /// chains shorter than the colours, each body meets its manifolds in pair order.
    #[test]
    fn colours_share_no_moving_body() {
        let mut rng = Rng(7);
        let (bodies, moving, constraints, groups) = scene(&mut rng, 40, 2, 200);
        let mut lanes = LaneSolver::default();
        lanes.build(&groups, &constraints, &bodies, |i| moving[i]);
        let mut seen = vec![false; groups.len()];
        for c in 0..=COLOURS {
            let members = &lanes.order[lanes.colour_start[c]..lanes.colour_start[c + 1]];
            // by number of points then pair order in a colour; the overflow in pair order
            let points = |g: usize| if c < COLOURS { groups[g].1 - groups[g].0 } else { 0 };
            assert!(members.windows(2).all(|w| (points(w[0]), w[0]) < (points(w[1]), w[1])), "colour {c} out of order");
            let mut used = vec![false; bodies.len()];
            for &g in members {
                assert!(!seen[g]);
                seen[g] = true;
                let k = &constraints[groups[g].0];
                for i in [k.a, k.b] {
                    if moving[i] && c < COLOURS {
                        assert!(!used[i], "colour {c}: body {i} twice");
                        used[i] = true;
                    }
                }
            }
        }
        assert!(seen.iter().all(|&s| s));
        let (used, overflow) = lanes.colours_used();
        assert_eq!(used, COLOURS);
        assert!(overflow > 0, "the hub body is in 39 pairs");

        // a tower: ground (fixed) under body 1, body i on body i − 1, and each body also touching
        // the ground: chains of 20 manifolds, which the colours keep in pair order
        let mut rng = Rng(11);
        let (mut bodies, _, _, _) = scene(&mut rng, 21, 1, 0);
        bodies[0] = SolverBody::FIXED;
        let positions: Vec<DVec3> = (0..21).map(|i| DVec3::new(0.0, 0.0, i as f64)).collect();
        let mut constraints = Vec::new();
        let mut groups = Vec::new();
        let mut pairs: Vec<(usize, usize)> = (1..21).map(|i| (0, i)).chain((1..20).map(|i| (i, i + 1))).collect();
        pairs.sort();
        for &(a, b) in &pairs {
            let start = constraints.len();
            for _ in 0..2 {
                let soft = Softness::new(60.0, 10.0, 1.0 / 360.0);
                constraints.push(Constraint::new(&bodies, &positions, a, b, positions[b], DVec3::Z, -0.001, 0.5, soft));
            }
            groups.push((start, constraints.len()));
        }
        lanes.build(&groups, &constraints, &bodies, |i| i != 0);
        assert_eq!(lanes.colours_used().1, 0);
        for body in 1..21 {
            let mine: Vec<usize> =
                lanes.order().iter().copied().filter(|&g| pairs[g].0 == body || pairs[g].1 == body).collect();
            assert!(mine.windows(2).all(|w| w[0] < w[1]), "body {body} meets its manifolds in the order {mine:?}");
        }
    }
}
