//! Resting contact: soft sequential impulses in substeps, with warm starting and relaxation.
//!
//! References: E. Catto, "Iterative Dynamics with Temporal Coherence" (GDC 2005) and "Fast and
//! Simple Physics using Sequential Impulses" (GDC 2006) for sequential impulses, accumulated
//! impulses clamped to `λ_n ≥ 0` and to the friction disc `|λ_t| ≤ μ λ_n`, and warm starting;
//! E. Catto, "Solver2D" (2024) and Box2D v3 for the *soft step*: the step is cut into substeps
//! `h = dt/n`, each one applying the external forces, solving the contacts with a soft
//! (spring–damper) position bias, moving the bodies, then *relaxing* (solving again without the
//! bias, so the bias adds no energy to the motion).
//!
//! Each constraint is a contact point with normal `n` (A → B) and tangents `t1, t2`. The
//! relative velocity at the point is `u = (v_b + ω_b × r_b) − (v_a + ω_a × r_a)`, world frame.
//! - separation at the current substep: `s = gap + n·[(Δx_b + ΔR_b r_b − r_b) − (Δx_a + ΔR_a r_a − r_a)]`,
//!   with `Δx`, `ΔR` each body's motion since the start of the step;
//! - normal, `λ_n ≥ 0`, effective mass `m_n = 1/(nᵀ K n)`:
//!   - open (`s > 0`): `u·n ≥ −s/h`, the bodies may close the gap in this substep, no more
//!     (a speculative contact);
//!   - touching, with bias: the soft constraint `Δλ = −m_n s_m (u·n + b) − s_i λ_n` with the bias
//!     `b = max(β_s min(s + slop, 0), −v_max)` and the softness `(β_s, s_m, s_i)` of a damped
//!     spring of frequency `f` and damping ratio `ζ` (below);
//!   - touching, relaxing: the rigid `u·n ≥ 0`;
//! - friction: the tangential velocity `u_t = (u·t1, u·t2)` is driven to zero by `Δλ_t = −K_tt⁻¹ u_t`
//!   (the 2×2 block, so friction is isotropic), then `λ_t` is put back in the disc `|λ_t| ≤ μ λ_n`
//!   at the point nearest in the metric of `K_tt` (friction opposes the slip).
//!
//! With [`FrictionModel::Manifold`] (an option, never the default) the points of a manifold keep
//! only their normal rows, and friction is one [`Patch`] per manifold: a 2-D friction row at the
//! centre `c = (1/m) Σ p_i` of its points, `Δλ_t = −K_tt⁻¹ u_t(c)` put back in the disc
//! `|λ_t| ≤ μ Σ λ_n,i` as above, and a twist row about the normal, `Δλ_τ = −(nᵀ(I_a⁻¹ + I_b⁻¹) n)⁻¹
//! (ω_b − ω_a)·n` clamped to `|λ_τ| ≤ μ ρ Σ λ_n,i` with `ρ` the mean distance of the points from `c`
//! across the normal (the torque that Coulomb friction at the points would give against a twist,
//! when the points are at equal distances from the centre). The normal rows are solved first in each
//! pass, then the patch with their new sum. The model of Rapier's `FrictionModel::Simplified`.
//!
//! Softness of a spring–damper of angular frequency `ω = 2π f` and damping ratio `ζ` discretised
//! implicitly over the substep `h`: `a₁ = 2ζ + hω`, `a₂ = hω a₁`, `a₃ = 1/(1 + a₂)`, bias rate
//! `β_s = ω/a₁`, mass scale `s_m = a₂ a₃`, impulse scale `s_i = a₃`.

use super::impact::tangent_basis;
use crate::math::{quat_exp, DMat3, DQuat, DVec3};

/// The softness of a contact: a damped spring that pushes overlapping bodies apart.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Softness {
    /// `β_s` (1/s): the bias speed per metre of overlap.
    pub bias_rate: f64,
    /// `s_m`: the fraction of the rigid impulse applied.
    pub mass_scale: f64,
    /// `s_i`: the fraction of the accumulated impulse taken back (the spring's give).
    pub impulse_scale: f64,
    /// `ω²` (1/s²): the spring's stiffness per unit of the row's effective mass, `k = m_n ω²`
    /// (zero for a rigid row). A row at rest holds the load `λ/h = −m_n ω² C` at the deflection
    /// `C < 0` and stores `½ m_n ω² C²` ([`Self::stored_energy`]).
    pub omega_squared: f64,
}

impl Softness {
    /// A spring of `hertz` (Hz) and damping ratio `zeta` over the substep `h` (s); `hertz = 0`
    /// is rigid without bias.
    pub fn new(hertz: f64, zeta: f64, h: f64) -> Self {
        if hertz <= 0.0 {
            return Self { bias_rate: 0.0, mass_scale: 1.0, impulse_scale: 0.0, omega_squared: 0.0 };
        }
        let omega = 2.0 * std::f64::consts::PI * hertz;
        let a1 = 2.0 * zeta + h * omega;
        let a2 = h * omega * a1;
        let a3 = 1.0 / (1.0 + a2);
        Self { bias_rate: omega / a1, mass_scale: a2 * a3, impulse_scale: a3, omega_squared: omega * omega }
    }

    /// The potential energy (J) of the row's spring at the deflection `c` (m or rad; only `c < 0`,
    /// an overlap or an overshoot, loads it), for the row's effective mass `normal_mass`
    /// (`m_n = 1/(J M⁻¹ Jᵀ)`): `½ m_n ω² min(0, c)²`.
    ///
    /// The soft constraint is the implicit discretisation of the force `F = −k C − c_d u` with
    /// `k = m_n ω²`, `c_d = 2 ζ m_n ω` (Catto, Solver2D): at rest (`u = 0`, the same `λ = F h` applied
    /// every substep) its update `Δλ = −m_n s_m (u + β_s C) − s_i λ` is stationary iff
    /// `s_i λ = −m_n s_m β_s C`, and `s_m / s_i = a₂ = hω a₁`, `β_s = ω/a₁` give `λ/h = −m_n ω² C`:
    /// the load is held by a spring of stiffness `m_n ω²` at the deflection `C`. When the deflection
    /// shrinks, that spring gives its energy back to the bodies (their `T + V` rises by up to it).
    pub fn stored_energy(&self, normal_mass: f64, c: f64) -> f64 {
        let c = c.min(0.0);
        0.5 * normal_mass * self.omega_squared * c * c
    }
}

/// How the resting contacts of free bodies take friction.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FrictionModel {
    /// Coulomb friction at every contact point (the default).
    #[default]
    Point,
    /// One friction disc at the centre of each manifold's points and one twist row about its
    /// normal ([`Patch`]): fewer rows, a coarser friction.
    Manifold,
}

impl FrictionModel {
    /// The scene file's names, in the order of the variants.
    pub const NAMES: [&'static str; 2] = ["point", "manifold"];

    /// Parses a scene file's name.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "point" => Some(Self::Point),
            "manifold" => Some(Self::Manifold),
            _ => None,
        }
    }

    /// The scene file's name.
    pub fn name(self) -> &'static str {
        match self {
            Self::Point => Self::NAMES[0],
            Self::Manifold => Self::NAMES[1],
        }
    }
}

/// One resting-contact constraint (world frame throughout).
#[derive(Debug, Clone, Copy)]
pub struct Constraint {
    pub a: usize,
    pub b: usize,
    /// Offsets of the contact point from the centres of mass of A and B at the start of the step (m).
    pub r_a: DVec3,
    pub r_b: DVec3,
    pub n: DVec3,
    pub t1: DVec3,
    pub t2: DVec3,
    /// `gap − n·(r_b − r_a)`: the separation is this plus `n·(p_b − p_a)` with `p` the moved offsets (m).
    pub adjusted_gap: f64,
    /// `1/(nᵀKn)` (kg).
    pub normal_mass: f64,
    /// `K_tt⁻¹ (t1·K n, t2·K n)` (dimensionless): the tangential impulse that cancels the tangential
    /// velocity a unit normal impulse gives (what friction sees of the normal impulse just applied).
    pub tangent_per_normal: [f64; 2],
    /// `K_tt⁻¹` as `[[a, b], [c, d]]` (kg).
    pub tangent_mass: [f64; 4],
    /// `K_tt` as `[k11, k12, k22]` (1/kg).
    pub tangent_k: [f64; 3],
    /// Angular velocity change per unit impulse along `n`, `t1`, `t2`: `I_a⁻¹ (r_a × d)`,
    /// `I_b⁻¹ (r_b × d)` (1/(kg·m)).
    pub ang_a: [DVec3; 3],
    pub ang_b: [DVec3; 3],
    pub mu: f64,
    /// The spring that pushes the bodies apart when they overlap.
    pub softness: Softness,
    /// Whether the surfaces were apart at the start of the step (`gap > 0`): a speculative contact,
    /// which holds only approaches slower than the impact speed (faster ones are collisions).
    pub speculative: bool,
    /// Accumulated impulses of a substep, `λ_n`, `λ_t1`, `λ_t2` (N·s).
    pub lambda: [f64; 3],
}

/// A manifold as the resting solver takes it in: its two bodies, its points (a range of the
/// [`ContactPoint`]s, in the narrow phase's order), the pair's friction coefficient and the softness
/// of its rows (against a fixed body or not). With its points, the input of [`Constraint::new`] and
/// of the lanes' build ([`LaneSolver::build_points`](super::batch::LaneSolver::build_points)).
#[derive(Debug, Clone, Copy)]
pub struct Manifold {
    pub a: usize,
    pub b: usize,
    pub points: (usize, usize),
    pub mu: f64,
    pub softness: Softness,
    /// The warm start of its [`Patch`] (with [`FrictionModel::Manifold`]): the friction impulse
    /// and the twist's angular impulse it ended the last step with, world frame (N·s, N·m·s).
    pub friction_warm: [DVec3; 2],
}

/// `K_tt⁻¹ = adj(K_tt)/det` as `[[a, b], [c, d]]` for `K_tt = [k11 k12; k12 k22]` (kg); zeros when
/// `det ≤ 0` (no tangential response).
pub(super) fn tangent_inverse(k11: f64, k12: f64, k22: f64) -> [f64; 4] {
    let det = k11 * k22 - k12 * k12;
    if det > 0.0 {
        [k22 / det, -k12 / det, -k12 / det, k11 / det]
    } else {
        [0.0; 4]
    }
}

/// The centre `c = (1/m) Σ p_i` of a manifold's points (m), its normal (the points' normal when
/// they share one, as a convex pair's do; else their normalised sum) and the twist arm `ρ`: the mean
/// distance of the points from `c` across that normal (m). `points` is not empty.
pub fn patch_frame(points: &[ContactPoint]) -> (DVec3, DVec3, f64) {
    let (c, n) = patch_centre(points);
    let m = points.len() as f64;
    let radius = points
        .iter()
        .map(|p| {
            let d = p.point - c;
            (d - d.dot(n) * n).length()
        })
        .sum::<f64>()
        / m;
    (c, n, radius)
}

/// The centre and the normal of [`patch_frame`].
pub fn patch_centre(points: &[ContactPoint]) -> (DVec3, DVec3) {
    let first = points[0].n;
    let (mut sum_p, mut sum_n, mut shared) = (DVec3::ZERO, DVec3::ZERO, true);
    for p in points {
        sum_p += p.point;
        sum_n += p.n;
        shared &= p.n == first;
    }
    let n = if shared { first } else { sum_n.try_normalize().unwrap_or(first) };
    (sum_p / points.len() as f64, n)
}

/// The friction of one manifold with [`FrictionModel::Manifold`] (module documentation): a 2-D
/// friction row at the centre of its points and a twist row about its normal, world frame.
#[derive(Debug, Clone, Copy)]
pub struct Patch {
    pub a: usize,
    pub b: usize,
    /// Offsets of the centre of the points from the centres of mass of A and B (m).
    pub r_a: DVec3,
    pub r_b: DVec3,
    pub n: DVec3,
    pub t1: DVec3,
    pub t2: DVec3,
    /// `K_tt⁻¹` at the centre as `[[a, b], [c, d]]` (kg).
    pub tangent_mass: [f64; 4],
    /// `K_tt` as `[k11, k12, k22]` (1/kg).
    pub tangent_k: [f64; 3],
    /// `I_a⁻¹ (r_a × t1)`, `I_a⁻¹ (r_a × t2)`, `I_a⁻¹ n`, and the same for B (1/(kg·m), 1/(kg·m²)).
    pub ang_a: [DVec3; 3],
    pub ang_b: [DVec3; 3],
    /// `1/(nᵀ (I_a⁻¹ + I_b⁻¹) n)` (kg·m²).
    pub twist_mass: f64,
    /// The twist arm `ρ` (m): the twist row holds at most `μ ρ Σλ_n`.
    pub radius: f64,
    pub mu: f64,
    /// Accumulated impulses of a substep: `λ_t1`, `λ_t2` (N·s) and the twist `λ_τ` (N·m·s).
    pub lambda: [f64; 3],
}

impl Patch {
    /// The patch of the manifold between bodies `a` and `b` with `points`, friction `mu`, warm
    /// started from `warm` (its [`Manifold::friction_warm`]).
    pub fn new(
        bodies: &[SolverBody],
        positions: &[DVec3],
        a: usize,
        b: usize,
        points: &[ContactPoint],
        mu: f64,
        warm: [DVec3; 2],
    ) -> Self {
        let (ba, bb) = (&bodies[a], &bodies[b]);
        let (c, n, radius) = patch_frame(points);
        let (r_a, r_b) = (c - positions[a], c - positions[b]);
        let (t1, t2) = tangent_basis(n);
        let ang_a = [ba.inv_inertia * r_a.cross(t1), ba.inv_inertia * r_a.cross(t2), ba.inv_inertia * n];
        let ang_b = [bb.inv_inertia * r_b.cross(t1), bb.inv_inertia * r_b.cross(t2), bb.inv_inertia * n];
        // K d as in `Constraint::new`
        let inv_mass = ba.inv_mass + bb.inv_mass;
        let k_times = |j: usize, d: DVec3| inv_mass * d + ang_a[j].cross(r_a) + ang_b[j].cross(r_b);
        let (k_t1, k_t2) = (k_times(0, t1), k_times(1, t2));
        let (k11, k12, k22) = (t1.dot(k_t1), t1.dot(k_t2), t2.dot(k_t2));
        let tangent_mass = tangent_inverse(k11, k12, k22);
        let kww = n.dot(ang_a[2]) + n.dot(ang_b[2]);
        Self {
            a,
            b,
            r_a,
            r_b,
            n,
            t1,
            t2,
            tangent_mass,
            tangent_k: [k11, k12, k22],
            ang_a,
            ang_b,
            twist_mass: if kww > 0.0 { 1.0 / kww } else { 0.0 },
            radius,
            mu,
            lambda: [warm[0].dot(t1), warm[0].dot(t2), warm[1].dot(n)],
        }
    }

    /// The friction impulse `d1 t1 + d2 t2` at the centre on B and its opposite on A.
    #[inline]
    fn apply_tangent(&self, ma: &mut Motion, mb: &mut Motion, d1: f64, d2: f64) {
        let p = d1 * self.t1 + d2 * self.t2;
        ma.v -= ma.inv_mass * p;
        ma.w -= d1 * self.ang_a[0] + d2 * self.ang_a[1];
        mb.v += mb.inv_mass * p;
        mb.w += d1 * self.ang_b[0] + d2 * self.ang_b[1];
    }

    /// The angular impulse `dt n` on B and its opposite on A.
    #[inline]
    fn apply_twist(&self, ma: &mut Motion, mb: &mut Motion, dt: f64) {
        ma.w -= dt * self.ang_a[2];
        mb.w += dt * self.ang_b[2];
    }

    /// One pass over the patch with `normal_sum` the manifold's normal impulses `Σλ_n` (N·s):
    /// friction at the centre (sticking inside the disc `μ Σλ_n`, else its point nearest `λ*` in the
    /// metric of `K_tt`, as [`Constraint::solve`]), then the twist, clamped to `μ ρ Σλ_n`. Whether
    /// an impulse is held.
    #[inline]
    pub fn solve(&mut self, ma: &mut Motion, mb: &mut Motion, normal_sum: f64) -> bool {
        let u = mb.point_velocity(self.r_b) - ma.point_velocity(self.r_a);
        let (ux, uy) = (u.dot(self.t1), u.dot(self.t2));
        let m = self.tangent_mass;
        let l1 = self.lambda[0] - (m[0] * ux + m[1] * uy);
        let l2 = self.lambda[1] - (m[2] * ux + m[3] * uy);
        let limit = self.mu * normal_sum;
        let (l1, l2) = friction_on_disc(self.tangent_k, l1, l2, limit);
        let (d1, d2) = (l1 - self.lambda[0], l2 - self.lambda[1]);
        self.lambda[0] = l1;
        self.lambda[1] = l2;
        self.apply_tangent(ma, mb, d1, d2);
        // the twist, with the spin the friction impulse left
        let spin = (mb.w - ma.w).dot(self.n);
        let twist_limit = limit * self.radius;
        let twist = (self.lambda[2] - self.twist_mass * spin).max(-twist_limit).min(twist_limit);
        let dt = twist - self.lambda[2];
        self.lambda[2] = twist;
        self.apply_twist(ma, mb, dt);
        self.lambda != [0.0; 3]
    }

    /// Applies the accumulated impulses (warm start); whether there were any.
    #[inline]
    fn warm_start(&self, ma: &mut Motion, mb: &mut Motion) -> bool {
        if self.lambda == [0.0; 3] {
            return false;
        }
        self.apply_tangent(ma, mb, self.lambda[0], self.lambda[1]);
        self.apply_twist(ma, mb, self.lambda[2]);
        true
    }
}

/// A contact point of a [`Manifold`]: where (m), the unit normal `n` (A → B), the signed distance
/// `gap` (m, negative when overlapping), and the accumulated impulses it starts the step with (the
/// warm start, N·s).
#[derive(Debug, Clone, Copy)]
pub struct ContactPoint {
    pub point: DVec3,
    pub n: DVec3,
    pub gap: f64,
    pub lambda: [f64; 3],
}

/// Per-body quantities of the solve: inverse mass (1/kg), world inverse inertia (1/(kg·m²)),
/// velocity (m/s), angular velocity (rad/s), the acceleration of the external forces (m/s²), and
/// the motion since the start of the step: displacement `Δx` (m) and rotation `ΔR`.
#[derive(Debug, Clone, Copy)]
pub struct SolverBody {
    pub inv_mass: f64,
    pub inv_inertia: DMat3,
    pub v: DVec3,
    pub w: DVec3,
    pub accel: DVec3,
    pub dx: DVec3,
    pub dq: DQuat,
    pub drot: DMat3,
    /// Whether any impulse reached this body in the step.
    pub touched: bool,
}

impl SolverBody {
    /// A body that impulses do not move: inverse mass and inverse inertia zero (glam's
    /// `DMat3::default()` is the identity, so this is spelled out).
    pub const FIXED: Self = Self {
        inv_mass: 0.0,
        inv_inertia: DMat3::ZERO,
        v: DVec3::ZERO,
        w: DVec3::ZERO,
        accel: DVec3::ZERO,
        dx: DVec3::ZERO,
        dq: DQuat::IDENTITY,
        drot: DMat3::IDENTITY,
        touched: false,
    };

    /// Whether the body's motion since the start of the step has the bits of [`SolverBody::FIXED`]'s
    /// (`Δx = +0`, `ΔR = I`): no substep has moved it yet.
    pub(super) fn unmoved(&self) -> bool {
        let bits = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
        bits(&self.dx.to_array(), &Self::FIXED.dx.to_array())
            && bits(&self.drot.to_cols_array(), &Self::FIXED.drot.to_cols_array())
    }

    /// Semi-implicit Euler over the substep `h`: the velocity first (external forces), ...
    #[inline]
    pub fn integrate_velocity(&mut self, h: f64) {
        self.v += h * self.accel;
    }

    /// ... then the position and rotation with the new velocities: `Δx ← Δx + h v`,
    /// `ΔR ← exp(h ω̃) ΔR`.
    #[inline]
    pub fn integrate_position(&mut self, h: f64) {
        self.dx += h * self.v;
        if self.w != DVec3::ZERO {
            self.dq = (quat_exp(h * self.w) * self.dq).normalize();
            self.drot = DMat3::from_quat(self.dq);
        }
    }
}

/// A body's velocities and motion since the start of the step, copied out of [`SolverBody`] while
/// the constraints of one pair of bodies are solved (kept in registers, written back once).
#[derive(Debug, Clone, Copy)]
pub struct Motion {
    pub inv_mass: f64,
    pub v: DVec3,
    pub w: DVec3,
    pub dx: DVec3,
    pub drot: DMat3,
}

impl Motion {
    #[inline]
    fn of(b: &SolverBody) -> Self {
        Self { inv_mass: b.inv_mass, v: b.v, w: b.w, dx: b.dx, drot: b.drot }
    }

    #[inline]
    fn point_velocity(&self, r: DVec3) -> DVec3 {
        self.v + self.w.cross(r)
    }

    /// Writes the velocities back to body `i`, marking it reached by an impulse if `touched`.
    #[inline]
    fn store(&self, bodies: &mut [SolverBody], i: usize, touched: bool) {
        let body = &mut bodies[i];
        body.v = self.v;
        body.w = self.w;
        body.touched |= touched;
    }
}

/// Solves the constraints of one pair of bodies, all with the same `a` and `b` (one Gauss–Seidel
/// pass; see [`Constraint::solve`]).
#[inline]
pub fn solve_pair(constraints: &mut [Constraint], bodies: &mut [SolverBody], sweep: &Sweep) {
    let Some(first) = constraints.first() else { return };
    let (a, b) = (first.a, first.b);
    let (mut ma, mut mb) = (Motion::of(&bodies[a]), Motion::of(&bodies[b]));
    let mut any = false;
    in_sweep_order(constraints, sweep, |k| {
        debug_assert!(k.a == a && k.b == b);
        any |= k.solve(&mut ma, &mut mb, sweep);
    });
    ma.store(bodies, a, any);
    mb.store(bodies, b, any);
}

/// Calls `f` on a pair's points in the order of the sweep: first to last, or last to first when
/// [`Sweep::reverse`] (the scalar pairs of the overflow; the lanes' sweep writes its two loops out,
/// see `batch::sweep_in`).
#[inline(always)]
pub(super) fn in_sweep_order<T>(points: &mut [T], sweep: &Sweep, f: impl FnMut(&mut T)) {
    if sweep.reverse {
        points.iter_mut().rev().for_each(f);
    } else {
        points.iter_mut().for_each(f);
    }
}

/// Applies the accumulated impulses of the constraints of one pair of bodies (warm start).
#[inline]
pub fn warm_start_pair(constraints: &[Constraint], bodies: &mut [SolverBody]) {
    let Some(first) = constraints.first() else { return };
    let (a, b) = (first.a, first.b);
    let (mut ma, mut mb) = (Motion::of(&bodies[a]), Motion::of(&bodies[b]));
    let mut any = false;
    for k in constraints {
        if k.lambda != [0.0; 3] {
            k.apply(&mut ma, &mut mb, k.lambda[0], k.lambda[1], k.lambda[2]);
            any = true;
        }
    }
    ma.store(bodies, a, any);
    mb.store(bodies, b, any);
}

/// [`solve_pair`] with [`FrictionModel::Manifold`]: the points' normal rows in the order of the
/// sweep, then the pair's patch with their normal impulses' sum.
#[inline]
pub fn solve_patch_pair(constraints: &mut [Constraint], patch: &mut Patch, bodies: &mut [SolverBody], sweep: &Sweep) {
    let (a, b) = (patch.a, patch.b);
    let (mut ma, mut mb) = (Motion::of(&bodies[a]), Motion::of(&bodies[b]));
    let (mut any, mut normal_sum) = (false, 0.0);
    in_sweep_order(constraints, sweep, |k| {
        debug_assert!(k.a == a && k.b == b);
        any |= k.solve_normal(&mut ma, &mut mb, sweep);
        normal_sum += k.lambda[0];
    });
    any |= patch.solve(&mut ma, &mut mb, normal_sum);
    ma.store(bodies, a, any);
    mb.store(bodies, b, any);
}

/// [`warm_start_pair`] with [`FrictionModel::Manifold`]: the points' normal impulses, then the
/// patch's.
#[inline]
pub fn warm_start_patch_pair(constraints: &[Constraint], patch: &Patch, bodies: &mut [SolverBody]) {
    let (a, b) = (patch.a, patch.b);
    let (mut ma, mut mb) = (Motion::of(&bodies[a]), Motion::of(&bodies[b]));
    let mut any = false;
    for k in constraints {
        if k.lambda[0] != 0.0 {
            k.apply_normal(&mut ma, &mut mb, k.lambda[0]);
            any = true;
        }
    }
    any |= patch.warm_start(&mut ma, &mut mb);
    ma.store(bodies, a, any);
    mb.store(bodies, b, any);
}

/// The settings of one pass over the constraints.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sweep {
    /// Solving with the position bias, or relaxing.
    pub pass: Pass,
    /// `1/h` (1/s), `h` the substep.
    pub inv_h: f64,
    /// Overlap left alone (m).
    pub slop: f64,
    /// Largest bias speed (m/s).
    pub max_push: f64,
    /// Approach speed above which a contact is a collision (m/s): a speculative contact
    /// approaching faster is left to the collision stage.
    pub impact_speed: f64,
    /// The points of each pair in reverse order. One Gauss–Seidel pass over a manifold favours
    /// the points it solves first (their impulses set the velocity that the later ones correct):
    /// with one pass per substep, always in the same order, that bias pushed a light box under a
    /// box ten times heavier into a rocking that grew until the stack walked (42.6 mm in 1,000
    /// steps at the default settings). The contact stage alternates the direction, forward, back,
    /// back, forward, … (a symmetric Gauss–Seidel over the step): 1.1 mm.
    pub reverse: bool,
    /// Relaxing: whether the bodies moved since the last relaxing sweep (the first relaxing sweep
    /// of a substep). The lanes keep the separations that sweep measured when they did not: the
    /// sweeps between change velocities only, so a second measure gives the same bits. The scalar
    /// rows measure at every sweep.
    pub moved: bool,
}

impl Sweep {
    /// A normal row's bias speed `b` (m/s) and soft scales `(s_m, s_i)` at the separation `s` (m):
    /// apart, the speculative `s/h` with no softness; overlapping in the biased pass, the spring's
    /// push, its `bias_rate` times the overlap beyond the slop, at most `max_push`; relaxing, none.
    #[inline]
    pub fn normal_terms(&self, s: f64, softness: Softness) -> (f64, f64, f64) {
        if s > 0.0 {
            (s * self.inv_h, 1.0, 0.0)
        } else if self.pass == Pass::Solve {
            let k = softness;
            ((k.bias_rate * (s + self.slop).min(0.0)).max(-self.max_push), k.mass_scale, k.impulse_scale)
        } else {
            (0.0, 1.0, 0.0)
        }
    }
}

/// What a pass over the constraints does at points in touch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Pass {
    /// The soft constraint with the position bias.
    Solve,
    /// The rigid constraint without bias (removes the bias's velocity).
    Relax,
}

impl Constraint {
    /// A constraint at `point` (m) with unit normal `n` between bodies `a` and `b`, signed
    /// distance `gap` (m, negative when overlapping).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        bodies: &[SolverBody],
        positions: &[DVec3],
        a: usize,
        b: usize,
        point: DVec3,
        n: DVec3,
        gap: f64,
        mu: f64,
        softness: Softness,
    ) -> Self {
        let (ba, bb) = (&bodies[a], &bodies[b]);
        let (r_a, r_b) = (point - positions[a], point - positions[b]);
        let (t1, t2) = tangent_basis(n);
        let ang_a = [n, t1, t2].map(|d| ba.inv_inertia * r_a.cross(d));
        let ang_b = [n, t1, t2].map(|d| bb.inv_inertia * r_b.cross(d));
        // K d along the three directions, K = (1/m_a + 1/m_b) 1 − r̃_a I_a⁻¹ r̃_a − r̃_b I_b⁻¹ r̃_b
        // (`impact::collision_matrix`) without forming K: −r̃ I⁻¹ r̃ d = (I⁻¹ (r × d)) × r
        let inv_mass = ba.inv_mass + bb.inv_mass;
        let k_times = |j: usize, d: DVec3| inv_mass * d + ang_a[j].cross(r_a) + ang_b[j].cross(r_b);
        let (k_n, k_t1, k_t2) = (k_times(0, n), k_times(1, t1), k_times(2, t2));
        let knn = n.dot(k_n);
        let (k11, k12, k22) = (t1.dot(k_t1), t1.dot(k_t2), t2.dot(k_t2));
        let tangent_mass = tangent_inverse(k11, k12, k22);
        Self {
            a,
            b,
            r_a,
            r_b,
            n,
            t1,
            t2,
            adjusted_gap: gap - n.dot(r_b - r_a),
            normal_mass: if knn > 0.0 { 1.0 / knn } else { 0.0 },
            tangent_per_normal: {
                let (k1n, k2n) = (t1.dot(k_n), t2.dot(k_n));
                let m = tangent_mass;
                [m[0] * k1n + m[1] * k2n, m[2] * k1n + m[3] * k2n]
            },
            tangent_mass,
            tangent_k: [k11, k12, k22],
            ang_a,
            ang_b,
            mu,
            softness,
            speculative: gap > 0.0,
            lambda: [0.0; 3],
        }
    }

    /// [`new`](Self::new) for the normal row alone ([`FrictionModel::Manifold`]: its manifold's
    /// [`Patch`] takes the friction): the same normal row, no tangents (the fields of friction
    /// zero).
    #[allow(clippy::too_many_arguments)]
    pub fn new_normal(
        bodies: &[SolverBody],
        positions: &[DVec3],
        a: usize,
        b: usize,
        point: DVec3,
        n: DVec3,
        gap: f64,
        softness: Softness,
    ) -> Self {
        let (ba, bb) = (&bodies[a], &bodies[b]);
        let (r_a, r_b) = (point - positions[a], point - positions[b]);
        let (ang_a, ang_b) = (ba.inv_inertia * r_a.cross(n), bb.inv_inertia * r_b.cross(n));
        // nᵀ K n as in `new`
        let k_n = (ba.inv_mass + bb.inv_mass) * n + ang_a.cross(r_a) + ang_b.cross(r_b);
        let knn = n.dot(k_n);
        Self {
            a,
            b,
            r_a,
            r_b,
            n,
            t1: DVec3::ZERO,
            t2: DVec3::ZERO,
            adjusted_gap: gap - n.dot(r_b - r_a),
            normal_mass: if knn > 0.0 { 1.0 / knn } else { 0.0 },
            tangent_per_normal: [0.0; 2],
            tangent_mass: [0.0; 4],
            tangent_k: [0.0; 3],
            ang_a: [ang_a, DVec3::ZERO, DVec3::ZERO],
            ang_b: [ang_b, DVec3::ZERO, DVec3::ZERO],
            mu: 0.0,
            softness,
            speculative: gap > 0.0,
            lambda: [0.0; 3],
        }
    }

    /// The separation at the current substep (m), from the bodies' motion since the step began.
    #[inline]
    fn separation(&self, ma: &Motion, mb: &Motion) -> f64 {
        let p_a = ma.dx + ma.drot * self.r_a;
        let p_b = mb.dx + mb.drot * self.r_b;
        self.adjusted_gap + self.n.dot(p_b - p_a)
    }

    /// Applies the impulse `dn n + d1 t1 + d2 t2` on B and its opposite on A, with the angular
    /// responses `I⁻¹ (r × d)` computed once per step (no 3×3 product inside the sweeps).
    #[inline]
    fn apply(&self, ma: &mut Motion, mb: &mut Motion, dn: f64, d1: f64, d2: f64) {
        let p = dn * self.n + d1 * self.t1 + d2 * self.t2;
        ma.v -= ma.inv_mass * p;
        ma.w -= dn * self.ang_a[0] + d1 * self.ang_a[1] + d2 * self.ang_a[2];
        mb.v += mb.inv_mass * p;
        mb.w += dn * self.ang_b[0] + d1 * self.ang_b[1] + d2 * self.ang_b[2];
    }

    /// The normal row's new accumulated impulse at the normal velocity `un` (m/s): open, biased or
    /// relaxing as the separation and the pass say.
    #[inline]
    fn normal_row(&self, ma: &Motion, mb: &Motion, sweep: &Sweep, un: f64) -> f64 {
        let (bias, mass_scale, impulse_scale) = sweep.normal_terms(self.separation(ma, mb), self.softness);
        // λ_n ← max(0, λ_n − m_n s_m (u_n + b) − s_i λ_n), the terms that do not wait for u_n first
        let mass = self.normal_mass * mass_scale;
        let rest = self.lambda[0] - mass * bias - impulse_scale * self.lambda[0];
        (rest - mass * un).max(0.0)
    }

    /// The impulse `dn n` on B and its opposite on A.
    #[inline]
    fn apply_normal(&self, ma: &mut Motion, mb: &mut Motion, dn: f64) {
        let p = dn * self.n;
        ma.v -= ma.inv_mass * p;
        ma.w -= dn * self.ang_a[0];
        mb.v += mb.inv_mass * p;
        mb.w += dn * self.ang_b[0];
    }

    /// The normal row alone ([`FrictionModel::Manifold`]: the manifold's [`Patch`] takes the
    /// friction; `λ_t1 = λ_t2 = 0`), as in [`solve`](Self::solve). Whether an impulse is held.
    #[inline]
    pub fn solve_normal(&mut self, ma: &mut Motion, mb: &mut Motion, sweep: &Sweep) -> bool {
        let u = mb.point_velocity(self.r_b) - ma.point_velocity(self.r_a);
        let un = u.dot(self.n);
        if self.speculative && -un > sweep.impact_speed {
            if self.lambda[0] != 0.0 {
                self.apply_normal(ma, mb, -self.lambda[0]);
                self.lambda[0] = 0.0;
                return true;
            }
            return false;
        }
        let new = self.normal_row(ma, mb, sweep, un);
        let dn = new - self.lambda[0];
        self.lambda[0] = new;
        self.apply_normal(ma, mb, dn);
        self.lambda[0] != 0.0
    }

    /// One Gauss–Seidel pass over this constraint: the normal, then friction with the new normal
    /// impulse as the disc's radius. Whether an impulse is held.
    ///
    /// A speculative contact approaching faster than the impact speed is left alone: it is a
    /// collision that has not happened yet, and the collision stage resolves it, with restitution,
    /// in the step in which the surfaces meet. Holding it here would stop the bodies short of each
    /// other as a perfectly inelastic collision, with no restitution and no collision counted.
    #[inline]
    pub fn solve(&mut self, ma: &mut Motion, mb: &mut Motion, sweep: &Sweep) -> bool {
        let u = mb.point_velocity(self.r_b) - ma.point_velocity(self.r_a);
        let un = u.dot(self.n);
        if self.speculative && -un > sweep.impact_speed {
            // whatever it held while slower (warm start, earlier substeps) is let go
            if self.lambda != [0.0; 3] {
                let [l0, l1, l2] = self.lambda;
                self.apply(ma, mb, -l0, -l1, -l2);
                self.lambda = [0.0; 3];
                return true;
            }
            return false;
        }
        let new = self.normal_row(ma, mb, sweep, un);
        let dn = new - self.lambda[0];
        self.lambda[0] = new;

        // friction: sticking if λ* = λ_t − K_tt⁻¹ u_t lies in the disc |λ_t| ≤ μ λ_n; otherwise
        // sliding, with λ_t the point of the disc nearest λ* in the metric of K_tt. That point makes
        // the resulting slip u = K_tt (λ_t − λ*) normal to the disc, i.e. friction opposes the slip
        // (maximum dissipation), which the plain Euclidean clamp would not do when K_tt is not
        // isotropic. λ(ν) = (K_tt + ν 1)⁻¹ K_tt λ*, with ν ≥ 0 the root of the secular equation
        // 1/|λ(ν)| = 1/(μ λ_n), by Newton's method (Moré & Sorensen 1983: concave, converges from below).
        // λ* from the tangential velocity after the normal impulse, u_t + Δλ_n (t·K n) (the impulse is
        // applied with friction's, once): λ_t − K_tt⁻¹ u_t, computed beside the normal row, minus
        // Δλ_n K_tt⁻¹ (t·K n), the one product that waits for Δλ_n
        let (ux, uy) = (u.dot(self.t1), u.dot(self.t2));
        let (m, f) = (self.tangent_mass, self.tangent_per_normal);
        let l1 = self.lambda[1] - (m[0] * ux + m[1] * uy) - dn * f[0];
        let l2 = self.lambda[2] - (m[2] * ux + m[3] * uy) - dn * f[1];
        let limit = self.mu * self.lambda[0];
        let (l1, l2) = friction_on_disc(self.tangent_k, l1, l2, limit);
        let (d1, d2) = (l1 - self.lambda[1], l2 - self.lambda[2]);
        self.lambda[1] = l1;
        self.lambda[2] = l2;
        self.apply(ma, mb, dn, d1, d2);
        self.lambda != [0.0; 3]
    }
}

/// The tangential impulse of a point with friction limit `limit = μ λ_n`: `λ* = (l1, l2)` where it
/// lies in the disc (sticking), else the disc's point nearest it in the metric of `K_tt`
/// ([`project_on_disc`]), put exactly on the circle (the root's round-off). The free bodies'
/// constraints and the robots' rows both take their friction here (the lanes of `contact::batch`
/// do the same operations).
#[inline]
pub(super) fn friction_on_disc(tangent_k: [f64; 3], l1: f64, l2: f64, limit: f64) -> (f64, f64) {
    // squared lengths: no square root on the way of the common case (sticking)
    if l1 * l1 + l2 * l2 <= limit * limit {
        return (l1, l2);
    }
    let (l1, l2) = if limit > 0.0 { project_on_disc(tangent_k, l1, l2, limit) } else { (l1, l2) };
    let len = (l1 * l1 + l2 * l2).sqrt();
    let s = if len > 0.0 && len.is_finite() { limit / len } else { 0.0 };
    (l1 * s, l2 * s)
}

/// Newton iterations of [`project_on_disc`] at most: two or three in the common case (the legged
/// scenes), more for a tangent matrix thousands of times stiffer one way than the other (eight
/// from zero were too few there: its property test found `|λ|` left off the disc by 1.2e-7 of it).
pub(super) const NEWTON_STEPS: usize = 30;

/// The point of the disc `|λ| ≤ limit` nearest `λ* = (l1, l2)` in the metric of `K_tt = [k11 k12; k12 k22]`:
/// `λ(ν) = (K_tt + ν 1)⁻¹ K_tt λ*` with `ν ≥ 0` the root of `φ(ν) = 1/|λ(ν)| − 1/limit` by Newton's
/// method (Moré & Sorensen 1983: `φ` is increasing and concave, so Newton climbs to the root
/// monotonically from below it, and a step from above it lands below it).
///
/// The start: with `b = K_tt λ*` and `k_min ≤ k_max` the eigenvalues of `K_tt`, `|b|/(k_max + ν) ≤
/// |λ(ν)| ≤ |b|/(k_min + ν)`, so the root lies in `[|b|/limit − k_max, |b|/limit − k_min]`; where
/// the slip asks for far more than the disc holds (`|λ*| ≫ limit`, the sliding feet of a trot: 20
/// times the limit, typically), the root is large against `K_tt` and its expansion in `1/ν`,
/// `|λ(ν)|² = |b|²/ν² (1 − 2 m₁/ν + 3 m₂/ν² − …)` with the moments `m₁ = bᵀK_tt b/|b|²`, `m₂ =
/// |K_tt b|²/|b|²`, gives `ν ≈ T + (3/2)(m₂ − m₁²)/T`, `T = |b|/limit − m₁`. Newton starts there
/// (never below the lower bound; exact when `K_tt` is isotropic): 2.5 evaluations per call on the
/// trotting Solo-12 instead of 3.1 from the lower bound.
pub(super) fn project_on_disc([k11, k12, k22]: [f64; 3], l1: f64, l2: f64, limit: f64) -> (f64, f64) {
    let (b1, b2) = (k11 * l1 + k12 * l2, k12 * l1 + k22 * l2);
    let inv_limit = 1.0 / limit;
    let half_gap = 0.5 * (k11 - k22);
    let k_max = 0.5 * (k11 + k22) + (half_gap * half_gap + k12 * k12).sqrt();
    let b_sq = b1 * b1 + b2 * b2;
    let b_norm = b_sq.sqrt();
    let lower = (b_norm * inv_limit - k_max).max(0.0);
    let (kb1, kb2) = (k11 * b1 + k12 * b2, k12 * b1 + k22 * b2);
    let inv_b_sq = 1.0 / b_sq;
    let (m1, m2) = ((b1 * kb1 + b2 * kb2) * inv_b_sq, (kb1 * kb1 + kb2 * kb2) * inv_b_sq);
    let far = b_norm * inv_limit - m1;
    let mut nu = if far > 0.0 { (far + 1.5 * (m2 - m1 * m1) / far).max(lower) } else { lower };
    for _ in 0..NEWTON_STEPS {
        // (K_tt + ν)⁻¹ = adj/det: λ(ν) = X/det with X = adj b, and (K_tt + ν)⁻¹ λ = Y/det² with
        // Y = adj X; then φ = (det − |X|/limit)/|X|, φ' = λᵀ(K_tt + ν)⁻¹λ/|λ|³ = XᵀY/|X|³ and the
        // Newton step φ/φ' = |X|² (det − |X|/limit)/XᵀY: one square root and one division, side by
        // side, per iteration
        let (a11, a22) = (k11 + nu, k22 + nu);
        let det = a11 * a22 - k12 * k12;
        let (x1, x2) = (a22 * b1 - k12 * b2, a11 * b2 - k12 * b1);
        let (y1, y2) = (a22 * x1 - k12 * x2, a11 * x2 - k12 * x1);
        let x_sq = x1 * x1 + x2 * x2;
        let xy = x1 * y1 + x2 * y2;
        let inv_xy = 1.0 / xy;
        let gap = det - x_sq.sqrt() * inv_limit;
        // |φ| < 1e-12/|λ|: |λ| on the circle to 1e-12
        if xy.is_nan() || xy <= 0.0 || gap.abs() < 1e-12 * det {
            let inv_det = 1.0 / det;
            return (x1 * inv_det, x2 * inv_det);
        }
        nu = (nu - x_sq * gap * inv_xy).max(0.0);
    }
    let (a11, a22) = (k11 + nu, k22 + nu);
    let inv_det = 1.0 / (a11 * a22 - k12 * k12);
    ((a22 * b1 - k12 * b2) * inv_det, (a11 * b2 - k12 * b1) * inv_det)
}

#[cfg(test)]
mod tests {
    use super::project_on_disc;
    use proptest::prelude::*;

    proptest! {
        /// The projected impulse lies on the disc; the slip it leaves, `K_tt (λ − λ*)`, points
        /// along `−λ` (friction opposes the slip: the optimality condition of the nearest point in
        /// the metric of `K_tt`; to `1e-10 κ`, the slip being computed through `K_tt` of condition
        /// `κ`); and no point of the circle, searched every 0.1°, is nearer in that metric — for
        /// tangent matrices up to 10⁴ : 1 anisotropic.
        #[test]
        fn the_projection_is_the_nearest_point_of_the_disc(
            k_min in 1e-3f64..1.0, ratio in 1.0f64..1e4, angle in 0.0f64..std::f64::consts::PI,
            l1 in -10.0f64..10.0, l2 in -10.0f64..10.0, limit_fraction in 1e-3f64..0.999,
        ) {
            let (c, s) = (angle.cos(), angle.sin());
            let k_max = k_min * ratio;
            let k = [k_min * c * c + k_max * s * s, (k_min - k_max) * c * s, k_min * s * s + k_max * c * c];
            let limit = limit_fraction * (l1 * l1 + l2 * l2).sqrt();
            prop_assume!(limit > 1e-6);
            let (p1, p2) = project_on_disc(k, l1, l2, limit);
            let len = (p1 * p1 + p2 * p2).sqrt();
            prop_assert!((len - limit).abs() <= 1e-9 * limit, "|λ| = {len}, limit {limit}");
            let (d1, d2) = (p1 - l1, p2 - l2);
            let (slip1, slip2) = (k[0] * d1 + k[1] * d2, k[1] * d1 + k[2] * d2);
            let slip = (slip1 * slip1 + slip2 * slip2).sqrt();
            let cross = (slip1 * p2 - slip2 * p1) / (slip * len);
            let along = -(slip1 * p1 + slip2 * p2) / (slip * len);
            prop_assert!(cross.abs() <= 1e-10 * ratio && along > 0.0, "slip {slip1}, {slip2} against λ {p1}, {p2}");
            let distance = |q1: f64, q2: f64| {
                let (d1, d2) = (q1 - l1, q2 - l2);
                d1 * (k[0] * d1 + k[1] * d2) + d2 * (k[1] * d1 + k[2] * d2)
            };
            let found = distance(p1, p2);
            for i in 0..3600 {
                let theta = i as f64 * std::f64::consts::TAU / 3600.0;
                let other = distance(limit * theta.cos(), limit * theta.sin());
                prop_assert!(found <= other * (1.0 + 1e-12), "{found} against {other} at {theta} rad");
            }
        }
    }
}
