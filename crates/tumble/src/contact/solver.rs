//! Resting contact: sequential impulses with warm starting and split-impulse position correction.
//!
//! References: E. Catto, "Iterative Dynamics with Temporal Coherence" (GDC 2005) and "Fast and
//! Simple Physics using Sequential Impulses" (GDC 2006): accumulated impulses clamped to `λ_n ≥ 0`
//! and to the friction disc `|λ_t| ≤ μ λ_n`, warm started from the previous step; the split impulse
//! (Catto; Box2D v2.x "soft step" notes) corrects overlap with pseudo-velocities that move the
//! bodies but are never added to their velocities, so correcting a penetration adds no energy.
//!
//! Each constraint is a contact point with normal `n` (A → B) and tangents `t1, t2`. The
//! relative velocity at the point is `u = (v_b + ω_b × r_b) − (v_a + ω_a × r_a)`, world frame.
//! - normal: `u·n ≥ −max(gap, 0)/dt` (a speculative contact lets the bodies close an open gap,
//!   no more), `λ_n ≥ 0`; effective mass `m_n = 1/(nᵀ K n)`;
//! - friction: the tangential velocity `u_t = (u·t1, u·t2)` is driven to zero by `Δλ_t = −K_tt⁻¹ u_t`
//!   (the 2×2 block, so friction is isotropic), then `λ_t` is clamped to the disc of radius `μ λ_n`;
//! - position: a pseudo-velocity `u'·n ≥ β max(−gap − slop, 0)/dt`, at most `max_correction_speed`.
//!
//! Velocities are those predicted at the end of the step (external forces applied); the solver
//! returns the change of every body's velocity, which the contact stage applies through the step.

use super::impact::tangent_basis;
use crate::math::{DMat3, DVec3};

/// One resting-contact constraint (world frame throughout).
#[derive(Debug, Clone, Copy)]
pub struct Constraint {
    pub a: usize,
    pub b: usize,
    /// Offsets of the contact point from the centres of mass of A and B (m).
    pub r_a: DVec3,
    pub r_b: DVec3,
    pub n: DVec3,
    pub t1: DVec3,
    pub t2: DVec3,
    /// `1/(nᵀKn)` (kg).
    pub normal_mass: f64,
    /// `K_tt⁻¹` as `[[a, b], [c, d]]` (kg).
    pub tangent_mass: [f64; 4],
    /// `K_tt` as `[k11, k12, k22]` (1/kg).
    pub tangent_k: [f64; 3],
    /// Angular velocity change per unit impulse along `n`, `t1`, `t2`: `I_a⁻¹ (r_a × d)`,
    /// `I_b⁻¹ (r_b × d)` (1/(kg·m)).
    pub ang_a: [DVec3; 3],
    pub ang_b: [DVec3; 3],
    pub mu: f64,
    /// Allowed approach speed `max(gap, 0)/dt` (m/s).
    pub speculative: f64,
    /// Target separation pseudo-speed of the position correction (m/s).
    pub bias: f64,
    /// Accumulated impulses `λ_n`, `λ_t1`, `λ_t2` (N·s) and the position impulse.
    pub lambda: [f64; 3],
    pub lambda_split: f64,
}

/// Per-body quantities of the solve: inverse mass (1/kg), world inverse inertia (1/(kg·m²)),
/// velocity (m/s) and angular velocity (rad/s), and the pseudo-velocities of the split impulse.
#[derive(Debug, Clone, Copy)]
pub struct SolverBody {
    pub inv_mass: f64,
    pub inv_inertia: DMat3,
    pub v: DVec3,
    pub w: DVec3,
    pub v_split: DVec3,
    pub w_split: DVec3,
}

impl SolverBody {
    /// A body that impulses do not move: inverse mass and inverse inertia zero (glam's
    /// `DMat3::default()` is the identity, so this is spelled out).
    pub const FIXED: Self = Self {
        inv_mass: 0.0,
        inv_inertia: DMat3::ZERO,
        v: DVec3::ZERO,
        w: DVec3::ZERO,
        v_split: DVec3::ZERO,
        w_split: DVec3::ZERO,
    };

    #[inline]
    fn point_velocity(&self, r: DVec3) -> DVec3 {
        self.v + self.w.cross(r)
    }
}

impl Constraint {
    /// A constraint at `point` (m) with unit normal `n` between bodies `a` and `b`.
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
        dt: f64,
        settings: &super::ContactSettings,
    ) -> Self {
        let (ba, bb) = (&bodies[a], &bodies[b]);
        let (r_a, r_b) = (point - positions[a], point - positions[b]);
        let k = super::impact::collision_matrix(ba.inv_mass, ba.inv_inertia, r_a, bb.inv_mass, bb.inv_inertia, r_b);
        let (t1, t2) = tangent_basis(n);
        let knn = n.dot(k * n);
        let (k11, k12, k22) = (t1.dot(k * t1), t1.dot(k * t2), t2.dot(k * t2));
        let det = k11 * k22 - k12 * k12;
        let tangent_mass = if det > 0.0 { [k22 / det, -k12 / det, -k12 / det, k11 / det] } else { [0.0; 4] };
        let penetration = (-gap - settings.slop).max(0.0);
        Self {
            a,
            b,
            r_a,
            r_b,
            n,
            t1,
            t2,
            normal_mass: if knn > 0.0 { 1.0 / knn } else { 0.0 },
            tangent_mass,
            tangent_k: [k11, k12, k22],
            ang_a: [n, t1, t2].map(|d| ba.inv_inertia * r_a.cross(d)),
            ang_b: [n, t1, t2].map(|d| bb.inv_inertia * r_b.cross(d)),
            mu,
            speculative: gap.max(0.0) / dt,
            bias: (settings.position_correction * penetration / dt).min(settings.max_correction_speed),
            lambda: [0.0; 3],
            lambda_split: 0.0,
        }
    }

    /// The relative velocity at the contact point, `u = u_b − u_a` (m/s).
    #[inline]
    fn relative_velocity(&self, bodies: &[SolverBody]) -> DVec3 {
        bodies[self.b].point_velocity(self.r_b) - bodies[self.a].point_velocity(self.r_a)
    }

    /// Applies the impulse `dn n + d1 t1 + d2 t2` on B and its opposite on A, with the angular
    /// responses `I⁻¹ (r × d)` computed once per step (no 3×3 product inside the sweeps).
    #[inline]
    fn apply(&self, bodies: &mut [SolverBody], dn: f64, d1: f64, d2: f64) {
        let p = dn * self.n + d1 * self.t1 + d2 * self.t2;
        let a = &mut bodies[self.a];
        a.v -= a.inv_mass * p;
        a.w -= dn * self.ang_a[0] + d1 * self.ang_a[1] + d2 * self.ang_a[2];
        let b = &mut bodies[self.b];
        b.v += b.inv_mass * p;
        b.w += dn * self.ang_b[0] + d1 * self.ang_b[1] + d2 * self.ang_b[2];
    }

    /// Applies the accumulated impulses of the previous step (warm start).
    pub fn warm_start(&self, bodies: &mut [SolverBody]) {
        self.apply(bodies, self.lambda[0], self.lambda[1], self.lambda[2]);
    }

    /// One Gauss–Seidel pass over this constraint: friction (with the current normal impulse as
    /// the disc's radius), then the normal.
    pub fn solve_velocity(&mut self, bodies: &mut [SolverBody]) {
        // friction: sticking if λ* = λ_t − K_tt⁻¹ u_t lies in the disc |λ_t| ≤ μ λ_n; otherwise
        // sliding, with λ_t the point of the disc nearest λ* in the metric of K_tt. That point makes
        // the resulting slip u = K_tt (λ_t − λ*) normal to the disc, i.e. friction opposes the slip
        // (maximum dissipation), which the plain Euclidean clamp would not do when K_tt is not
        // isotropic. λ(ν) = (K_tt + ν 1)⁻¹ K_tt λ*, with ν ≥ 0 the root of the secular equation
        // 1/|λ(ν)| = 1/(μ λ_n), by Newton's method (Moré & Sorensen 1983: concave, converges from ν = 0).
        let u = self.relative_velocity(bodies);
        let (ux, uy) = (u.dot(self.t1), u.dot(self.t2));
        let m = self.tangent_mass;
        let (mut l1, mut l2) = (self.lambda[1] - (m[0] * ux + m[1] * uy), self.lambda[2] - (m[2] * ux + m[3] * uy));
        let limit = self.mu * self.lambda[0];
        let len = (l1 * l1 + l2 * l2).sqrt();
        if len > limit {
            if limit > 0.0 {
                let [k11, k12, k22] = self.tangent_k;
                let (b1, b2) = (k11 * l1 + k12 * l2, k12 * l1 + k22 * l2);
                let mut nu = 0.0;
                for _ in 0..8 {
                    let (a11, a22) = (k11 + nu, k22 + nu);
                    let det = a11 * a22 - k12 * k12;
                    let (x1, x2) = ((a22 * b1 - k12 * b2) / det, (a11 * b2 - k12 * b1) / det);
                    let norm = (x1 * x1 + x2 * x2).sqrt();
                    // λᵀ (K + ν)⁻¹ λ
                    let (y1, y2) = ((a22 * x1 - k12 * x2) / det, (a11 * x2 - k12 * x1) / det);
                    let slope = (x1 * y1 + x2 * y2) / (norm * norm * norm);
                    let phi = 1.0 / norm - 1.0 / limit;
                    if slope.is_nan() || slope <= 0.0 || phi.abs() < 1e-12 / limit {
                        break;
                    }
                    nu = (nu - phi / slope).max(0.0);
                }
                let (a11, a22) = (k11 + nu, k22 + nu);
                let det = a11 * a22 - k12 * k12;
                (l1, l2) = ((a22 * b1 - k12 * b2) / det, (a11 * b2 - k12 * b1) / det);
            }
            // round-off of the root: land exactly on the disc
            let len = (l1 * l1 + l2 * l2).sqrt();
            let s = if len > 0.0 && len.is_finite() { limit / len } else { 0.0 };
            l1 *= s;
            l2 *= s;
        }
        let (d1, d2) = (l1 - self.lambda[1], l2 - self.lambda[2]);
        self.lambda[1] = l1;
        self.lambda[2] = l2;
        self.apply(bodies, 0.0, d1, d2);

        // normal: u·n ≥ −speculative, λ_n ≥ 0
        let un = self.relative_velocity(bodies).dot(self.n);
        let new = (self.lambda[0] - self.normal_mass * (un + self.speculative)).max(0.0);
        let dl = new - self.lambda[0];
        self.lambda[0] = new;
        self.apply(bodies, dl, 0.0, 0.0);
    }

    /// One pass of the split-impulse position correction on the pseudo-velocities.
    pub fn solve_position(&mut self, bodies: &mut [SolverBody]) {
        if self.bias == 0.0 && self.lambda_split == 0.0 {
            return;
        }
        let (ba, bb) = (&bodies[self.a], &bodies[self.b]);
        let u = (bb.v_split + bb.w_split.cross(self.r_b)) - (ba.v_split + ba.w_split.cross(self.r_a));
        let new = (self.lambda_split + self.normal_mass * (self.bias - u.dot(self.n))).max(0.0);
        let dl = new - self.lambda_split;
        self.lambda_split = new;
        let a = &mut bodies[self.a];
        a.v_split -= (dl * a.inv_mass) * self.n;
        a.w_split -= dl * self.ang_a[0];
        let b = &mut bodies[self.b];
        b.v_split += (dl * b.inv_mass) * self.n;
        b.w_split += dl * self.ang_b[0];
    }
}
