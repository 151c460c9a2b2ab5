//! Joint position limits — one-sided, speculative, inelastic constraints on joint coordinates — and
//! joint dry friction (friction loss), a bounded force over the step.
//!
//! References: R. Featherstone, *Rigid Body Dynamics Algorithms* (2008), §6.5 (the sparse `LᵀDL`
//! factor used for `M⁻¹`) and ch. 11 (contact as a complementarity problem); B. Mirtich, PhD thesis
//! (1996), ch. 4 (impulses on articulated bodies); E. Catto, "Speculative contacts" (GDC 2012) for
//! the speculative distance `d / h`.
//!
//! A limited coordinate `q_i ∈ [lo, hi]` (a revolute or prismatic joint with a URDF `<limit>`) gives
//! up to two rows, each a unit row in joint space with a sign `s`:
//!
//! ```text
//! lower: J = +e_iᵀ, gap g = q_i − lo ≥ 0        upper: J = −e_iᵀ, gap g = hi − q_i ≥ 0
//! row velocity u = J v = s v_i,  generalized impulse Jᵀ λ with λ ≥ 0 (it only pushes away)
//! Δv = M⁻¹ Jᵀ λ,   K_rs = J_r M⁻¹ J_sᵀ = s_r s_s (M⁻¹)_{i_r i_s}
//! ```
//!
//! A limited fixed tendon (MJCF `<tendon><fixed range>`: module [`super::tendon`]; MuJoCo
//! documentation, *Modeling*: tendons, and *Computation*: limits, which treats a tendon's limit as
//! a joint's, on its length) gives the same two rows on its length `L = L₀ + Σ c_k q_k`, whose
//! Jacobian `J_t = (c_k)` is constant:
//!
//! ```text
//! lower: J = +J_t, gap g = L − lo ≥ 0           upper: J = −J_t, gap g = hi − L ≥ 0
//! u = s J_t v,  M⁻¹ Jᵀ = s M⁻¹ J_tᵀ (one sparse solve, Featherstone §6.5),  K_rs = J_r M⁻¹ J_sᵀ
//! ```
//!
//! Everything below holds for them unchanged (`L` is linear in `q`, so `Δq = c h Δv` moves it by
//! exactly `c h J_t Δv`). A row is stored as its sign and either a coordinate (a joint's, `J = s e_iᵀ`:
//! its column `M⁻¹ e_i` and `K_rs = s_r s_s (M⁻¹)_{i_r i_s}`, computed as before, bit for bit) or
//! a tendon (`J = s J_t`: the column `M⁻¹ J_tᵀ`, `K_rs = s_r s_s J_t · (M⁻¹ J_sᵀ / s_s)`). Tendon rows
//! exist when limits are on, as the joints'; their activity is counted apart
//! ([`JointLimitSolver::tendon_active_steps`]).
//!
//! Rows are solved together (several joints at their limits couple through `M⁻¹`) as the linear
//! complementarity problem `w = K λ − b ≥ 0, λ ≥ 0, λᵀ w = 0`, exactly, by Murty's principal
//! pivoting (K is symmetric positive definite, a P-matrix, so the least-index rule ends; projected
//! Gauss–Seidel is the fallback for a singular `K`); `b` is the change of row velocity each row
//! needs. A row that the others' impulses push past its own limit joins the solve, which is then
//! repeated. A step of `h` has two phases:
//!
//! 1. **Impact (before the integrator, at `(q₀, v₀)`)**: speculative, restitution 0. A row is
//!    active when the step would carry the joint past its limit, `g₀ + h u₀ < 0`; it then asks for
//!    `u₀⁺ ≥ min(0, −g₀/h)`, i.e. `b = min(0, −g₀/h) − u₀`: the joint may arrive exactly at the
//!    limit at the end of the step and no faster. Since the target is `≤ 0` and `λ ≥ 0`,
//!    `ΔT = Σ λ_r (u_r⁻ + u_r⁺)/2 ≤ 0`: an impact never adds energy (perfectly inelastic).
//! 2. **Force (after the integrator, at `(q₁, v₁)`)**: during the step the free acceleration can
//!    still carry the joint past the limit by `O(a h²)`. The limit then acts as a constant
//!    generalized force `F = Jᵀ λ/h` over the step, which moves the end state by
//!    `Δv = M⁻¹ Jᵀ λ` and `Δq = c h Δv`, with `c` the position weight of a constant force in the
//!    integrator: `c = ½` for RK4 (`q₁ = q₀ + h v₀ + ½ h² a` exactly for constant `a`), `c = 1` for
//!    semi-implicit Euler (`q₁ = q₀ + h v₁`). The rows ask for a zero gap at the end of the step,
//!    `g₁ + c h Δu ≥ 0`, i.e. `b = −g₁ / (c h)`. A joint held at its limit by a constant torque
//!    thus ends each step at the limit with zero velocity: the force cancels exactly the free
//!    acceleration's `Δv = a h` and its `Δq = c a h²`; what is left of the row velocity into the
//!    limit (the acceleration is not exactly constant over an RK4 step: `O(h³)`) is then removed by
//!    the velocity condition of phase 1 at the end state. Explicit Euler moves `q` with the old `v`
//!    (`c = 0`): a force cannot move `q₁`, and phase 1 already made `q₁ = q₀ + h v₀⁺` respect the
//!    limit, so its phase 2 is the velocity condition of phase 1 at the end state,
//!    `b = min(0, −g₁/h) − u₁`.
//!
//! A joint that starts outside its limit (`g₀ < 0`) is measured from where it is: the rows use the
//! gap `g − min(0, g₀)` in phase 2 and the target `0` in phase 1, so the limit stops further motion
//! outward and lets the joint come back, without pushing it in (no energy is injected). The contact
//! stage's rows (a robot held by resting contact: `contact::links`) are soft, so a step may leave
//! a quantity past its limit; they measure the gap from a floor kept across steps instead
//! ([`JointLimitSolver::floor`]), so that such an overshoot is driven back rather than kept, while
//! a quantity that started outside is still not pushed in.
//!
//! **Friction loss** (MuJoCo documentation, *Computation*: the "friction loss" rows of the
//! constraint solver; MJCF joint `frictionloss`): a joint with dry friction `F > 0` has one row per
//! velocity coordinate `k`, in phase 2 with the limit rows (explicit Euler: in its phase 2′), always
//! — whether limits are enforced or not:
//!
//! ```text
//! J = e_kᵀ,   target u⁺ = 0: b = −u₁,   |λ| ≤ F h   (a force |τ| ≤ F constant over the step)
//! Δv = M⁻¹ Jᵀ λ,   Δq = c h Δv   (as the limit rows' force)
//! ```
//!
//! With the limit rows (`λ ∈ [0, ∞)`) this is a boxed problem, `w = K λ − b` with `w = 0` for a row
//! strictly between its bounds, `w ≥ 0` at its lower and `w ≤ 0` at its upper bound; for symmetric
//! positive definite `K` its solution minimises `½ λᵀ K λ − bᵀ λ` over the box (for friction rows
//! alone: the kinetic energy after the impulse), solved exactly by principal pivoting on the box,
//! with projected Gauss–Seidel clamped to the box as the fallback (K. Erleben, ACM TOG 26(2), 2007;
//! E. Catto, "Iterative dynamics with temporal coherence", GDC 2005). Limits alone keep Murty's
//! method (bit for bit as without friction). A joint whose other forces stay within `F` thus ends the
//! step where it started, at rest (exactly for semi-implicit Euler, `O(h⁴)` a step for RK4, whose
//! acceleration is not constant over the step); a sliding one loses `F h` of momentum per step. The
//! impulse opposes `u₁` and never reverses it. With `c = 1` the joint moves by `h u₁⁺`, which the
//! impulse opposes: friction never adds energy. With `c = ½` (RK4) it moves by `h ū`,
//! `ū = (1 − c) u₀ + c u₁`: a row whose `ū` and `u₁` have opposite signs (the joint turned back within
//! the step) is left free for the step, and an impulse may not reverse `ū` (`|λ| ≤ |ū| / (c K_kk)`),
//! so that a row's force never works along the step's motion (coupled rows can still leave a rise of
//! `O(F h² a)` at a turning point: 4e-8 J measured on a double pendulum).
//!
//! `M⁻¹` columns come from CRBA and the sparse `LᵀDL` factor (`O(n d)` each), computed only when a
//! row is active (with friction rows: every step in which a frictional joint moves). Every buffer is
//! allocated when the solver is made: a step allocates nothing.

use super::crba::crba;
use super::joint::JointKind;
use super::ltdl::{ltdl_factor, ltdl_solve};
use super::model::MultibodyModel;
use super::tendon::TendonTerm;
use super::workspace::{ensure_square, Workspace};
use nalgebra::DMatrix;

/// Sweeps of projected Gauss–Seidel at most (the fallback for a singular `K`).
const MAX_SWEEPS: usize = 200;
/// Principal pivots of Murty's method at most (it ends in far fewer for the few rows of a tree).
const MAX_PIVOTS: usize = 200;
/// Times the active set may grow by rows that the others' impulses push past their limits.
const MAX_GROWTH: usize = 4;
/// Relative change of `λ` under which Gauss–Seidel stops.
const SWEEP_TOLERANCE: f64 = 1e-14;
/// A row whose gap is below this (rad or m) joins the solve even if it does not need an impulse, so
/// that the coupling of the other rows cannot push it through its limit.
const NEAR_GAP: f64 = 1e-6;

/// Which phase of the step a solve is for (see the module's doc).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Phase {
    /// Phase 1, at the start of the step: velocity condition `u⁺ ≥ min(0, −g/h)`.
    Impact,
    /// Phase 2, at the end of the step: zero end gap through `Δq = c h Δv` (`c > 0`).
    Force { c: f64 },
    /// Phase 2′, at the end of the step: the velocity condition of phase 1 at the end state (all of
    /// phase 2 for explicit Euler, whose `q₁` a force cannot move: `friction` then brings the
    /// friction rows, with the position weight `c = 0`).
    EndVelocity { friction: bool },
}

impl Phase {
    /// Whether the friction rows join this phase's solve: the force over the step (once per step).
    fn with_friction(self) -> bool {
        matches!(self, Phase::Force { .. } | Phase::EndVelocity { friction: true })
    }
}

/// A limited quantity `x ∈ [lower, upper]`: a joint coordinate `x = q[q_index]` (velocity
/// `v[v_index]`, `J = e_iᵀ`), or a fixed tendon's length `x = L₀ + Σ c_k q_k` (`J = J_t`, its
/// terms `tendon_terms[terms.0..terms.1]`, an empty range for a joint).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Limited {
    q_index: usize,
    v_index: usize,
    lower: f64,
    upper: f64,
    /// A tendon's `L₀` (0 for a joint).
    offset: f64,
    /// A tendon's terms in [`JointLimitSolver::tendon_terms`]; empty for a joint.
    terms: (usize, usize),
    /// A tendon's index in [`MultibodyModel::tendons`] ([`NONE`] for a joint).
    tendon: usize,
}

/// [`Limited::tendon`] of a joint.
const NONE: usize = usize::MAX;

/// A velocity coordinate with dry friction: `|τ_friction| ≤ friction_loss` on `v[v_index]`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Frictional {
    v_index: usize,
    /// `F` (N·m or N).
    friction_loss: f64,
    /// `v[v_index]` at the start of the step, after the impact phase (rad/s or m/s).
    start_velocity: f64,
}

/// Marks a row as a friction row in [`Row::coord`].
const FRICTION: usize = usize::MAX;

/// One active row of a solve.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct Row {
    /// Index into `limited`; [`FRICTION`] for a friction row.
    coord: usize,
    /// The velocity coordinate `i` of `J = s e_iᵀ` (a joint's or a friction row); [`NONE`] for a
    /// tendon's row `J = s J_t`.
    v_index: usize,
    /// `+1` for a lower limit or a friction row, `−1` for an upper limit (`J = s e_iᵀ`, `s J_t`).
    sign: f64,
    /// The change of row velocity it asks for (m/s or rad/s).
    b: f64,
    /// The impulse's bounds `λ ∈ [lo, hi]` (N·s or N·m·s): `[0, ∞)` for a limit, `[−F h, F h]` for
    /// friction.
    lo: f64,
    hi: f64,
    /// A friction row in a force phase with `c < 1`: `|ū| / c` (m/s or rad/s), the largest change
    /// of row velocity that does not reverse the row's mean velocity over the step; `∞` otherwise.
    mean_cap: f64,
}

/// Where a row of the boxed solve sits: between its bounds (its row equation holds) or at one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Bound {
    Free,
    Lower,
    Upper,
}

/// The joint-limit and friction-loss rows of a tree and the buffers to solve them (one per
/// simulator).
#[derive(Debug, Clone)]
pub struct JointLimitSolver {
    /// The limited joint coordinates (the first `n_joints`), then the limited tendons.
    limited: Vec<Limited>,
    n_joints: usize,
    /// The limited tendons' terms, one after the other.
    tendon_terms: Vec<TendonTerm>,
    frictional: Vec<Frictional>,
    /// The boxed solve's state per row (friction rows present).
    bound: Vec<Bound>,
    /// Gap of each limited coordinate's lower and upper row at the start of the step (`min(0, g₀)`
    /// is the reference of a joint that started outside).
    start_gap: Vec<[f64; 2]>,
    /// How far past each limited coordinate's lower and upper limit the contact stage's rows let
    /// it be (`≤ 0`, rad or m): `min(0, g)` where the limits started (or the state was set), then
    /// raised, never lowered, to `min(0, g)` at the end of every step
    /// ([`raise_floor`](Self::raise_floor)); see [`floor`](Self::floor).
    floor: Vec<[f64; 2]>,
    rows: Vec<Row>,
    /// `M⁻¹ J_rᵀ / s_r` for each active row `r` (`M⁻¹ e_i` for a joint's row, `M⁻¹ J_tᵀ` for a
    /// tendon's), column `r` (nv × rows at most).
    minv_cols: DMatrix<f64>,
    /// `K` (rows × rows, stored 2 n_limited square).
    k: DMatrix<f64>,
    lambda: Vec<f64>,
    /// Murty's method: which rows are in the basis, their indices, the reduced system and its
    /// right-hand side.
    basis: Vec<bool>,
    basis_rows: Vec<usize>,
    reduced: DMatrix<f64>,
    rhs: Vec<f64>,
    /// Rows (coordinate, side) that joined the solve because the others pushed them past their limit.
    forced: Vec<[bool; 2]>,
    /// `Δv = M⁻¹ Jᵀ λ` (nv).
    dv: Vec<f64>,
    /// Scratch configuration (nq).
    q_tmp: Vec<f64>,
    /// Steps in which each limited coordinate (then each limited tendon) had a row with `λ > 0`.
    active_steps: Vec<u64>,
    active_now: Vec<bool>,
}

impl JointLimitSolver {
    /// The solver for every revolute and prismatic joint of `model` that has position limits and
    /// every fixed tendon with a length range (when `limits` is on), and every velocity coordinate
    /// of a joint with friction loss (always), with its buffers; `None` when there is none of them.
    /// Also sizes `ws`'s mass matrix and factor.
    pub fn new(model: &MultibodyModel, ws: &mut Workspace, limits: bool) -> Option<Self> {
        let mut limited: Vec<Limited> = model
            .bodies
            .iter()
            .filter_map(|b| {
                let j = &b.joint;
                let (lower, upper) = j.limits.position?;
                matches!(j.kind, JointKind::Revolute { .. } | JointKind::Prismatic { .. }).then_some(Limited {
                    q_index: j.q_index,
                    v_index: j.v_index,
                    lower,
                    upper,
                    offset: 0.0,
                    terms: (0, 0),
                    tendon: NONE,
                })
            })
            .filter(|_| limits)
            .collect();
        let n_joints = limited.len();
        let mut tendon_terms: Vec<TendonTerm> = Vec::new();
        for (index, t) in model.tendons.iter().enumerate().filter(|_| limits) {
            let Some((lower, upper)) = t.range else { continue };
            if t.terms.is_empty() {
                continue;
            }
            let start = tendon_terms.len();
            tendon_terms.extend_from_slice(&t.terms);
            limited.push(Limited {
                q_index: NONE,
                v_index: NONE,
                lower,
                upper,
                offset: t.offset,
                terms: (start, tendon_terms.len()),
                tendon: index,
            });
        }
        let frictional: Vec<Frictional> = model
            .bodies
            .iter()
            .filter(|b| b.joint.dynamics.friction_loss > 0.0)
            .flat_map(|b| {
                let j = &b.joint;
                (j.v_index..j.v_index + j.kind.nv()).map(|v_index| Frictional {
                    v_index,
                    friction_loss: j.dynamics.friction_loss,
                    start_velocity: 0.0,
                })
            })
            .collect();
        if (limited.is_empty() && frictional.is_empty()) || ensure_square(&mut ws.mass_matrix, model.nv()).is_err() {
            return None;
        }
        if ws.ltdl.shape() != ws.mass_matrix.shape() {
            ws.ltdl = ws.mass_matrix.clone();
        }
        let n = limited.len();
        // rows at most: two per limited coordinate or tendon, one per frictional coordinate
        let m = 2 * n + frictional.len();
        Some(Self {
            start_gap: vec![[0.0; 2]; n],
            floor: vec![[0.0; 2]; n],
            rows: Vec::with_capacity(m),
            minv_cols: DMatrix::zeros(model.nv(), m),
            k: DMatrix::zeros(m, m),
            lambda: vec![0.0; m],
            basis: vec![false; m],
            bound: vec![Bound::Free; m],
            basis_rows: Vec::with_capacity(m),
            reduced: DMatrix::zeros(m, m),
            rhs: vec![0.0; m],
            forced: vec![[false; 2]; n],
            dv: vec![0.0; model.nv()],
            q_tmp: vec![0.0; model.nq()],
            active_steps: vec![0; n],
            active_now: vec![false; n],
            limited,
            n_joints,
            tendon_terms,
            frictional,
        })
    }

    /// Whether it enforces position limits (limits on and some joint or tendon limited).
    pub fn has_limits(&self) -> bool {
        !self.limited.is_empty()
    }

    /// Each velocity coordinate with dry friction: `(v_index, F)` (F in N·m or N).
    pub fn friction_losses(&self) -> impl Iterator<Item = (usize, f64)> + '_ {
        self.frictional.iter().map(|f| (f.v_index, f.friction_loss))
    }

    /// The velocity coordinates that have limits, in the order of [`active_steps`](Self::active_steps).
    pub fn limited_dofs(&self) -> impl Iterator<Item = usize> + '_ {
        self.limited[..self.n_joints].iter().map(|l| l.v_index)
    }

    /// Each limited coordinate: `(q_index, v_index, lower, upper)`.
    pub fn bounds(&self) -> impl Iterator<Item = (usize, usize, f64, f64)> + '_ {
        self.limited[..self.n_joints].iter().map(|l| (l.q_index, l.v_index, l.lower, l.upper))
    }

    /// Each limited tendon, after the limited coordinates: its index for
    /// [`note_active`](Self::note_active) (the number of limited coordinates plus its rank), its
    /// index in [`MultibodyModel::tendons`], and its range `[lower, upper]` on `L`.
    pub fn tendon_bounds(&self) -> impl Iterator<Item = (usize, usize, f64, f64)> + '_ {
        self.limited.iter().enumerate().skip(self.n_joints).map(|(k, l)| (k, l.tendon, l.lower, l.upper))
    }

    /// The limited tendons (indices in [`MultibodyModel::tendons`]), in the order of
    /// [`tendon_active_steps`](Self::tendon_active_steps).
    pub fn limited_tendons(&self) -> impl Iterator<Item = usize> + '_ {
        self.limited[self.n_joints..].iter().map(|l| l.tendon)
    }

    /// Counts a step in which the limit of the `k`-th limited coordinate pushed (from a solve made
    /// elsewhere: the contact solver's, for a robot held by resting contact); a `k` past the
    /// limited coordinates is a limited tendon's ([`tendon_bounds`](Self::tendon_bounds)).
    pub fn note_active(&mut self, k: usize) {
        if let Some(count) = self.active_steps.get_mut(k) {
            *count += 1;
        }
    }

    /// For each limited coordinate, the number of steps in which its limit pushed.
    pub fn active_steps(&self) -> &[u64] {
        &self.active_steps[..self.n_joints]
    }

    /// For each limited tendon, the number of steps in which its limit pushed.
    pub fn tendon_active_steps(&self) -> &[u64] {
        &self.active_steps[self.n_joints..]
    }

    /// The limited quantity `coord` at `q`: the joint coordinate, or the tendon's `L(q)` (as
    /// [`FixedTendon::length`](super::tendon::FixedTendon::length) computes it).
    #[inline]
    fn value(&self, coord: usize, q: &[f64]) -> f64 {
        let l = &self.limited[coord];
        if l.tendon == NONE {
            q[l.q_index]
        } else {
            l.offset + self.tendon_terms[l.terms.0..l.terms.1].iter().map(|t| t.coef * q[t.q_index]).sum::<f64>()
        }
    }

    /// `J x` of the limited quantity `coord` (unsigned): `x_i` for a joint, `J_t x` for a tendon.
    #[inline]
    fn jacobian_dot(&self, coord: usize, x: &[f64]) -> f64 {
        let l = &self.limited[coord];
        if l.tendon == NONE {
            x[l.v_index]
        } else {
            self.tendon_terms[l.terms.0..l.terms.1].iter().map(|t| t.coef * x[t.v_index]).sum()
        }
    }

    /// `J_r x` of row `r` without its sign.
    #[inline]
    fn row_dot(&self, r: usize, x: &[f64]) -> f64 {
        let row = &self.rows[r];
        if row.v_index != NONE {
            x[row.v_index]
        } else {
            self.jacobian_dot(row.coord, x)
        }
    }

    /// The floor of the `k`-th limited coordinate (then tendon, as in
    /// [`tendon_bounds`](Self::tendon_bounds)): how far past its `[lower, upper]` limits the
    /// contact stage's rows let it be (`≤ 0` each, rad or m). A row measures its gap from there,
    /// `g − floor`: a quantity that started outside its limit is not pushed in, only kept from
    /// going further out than it has come back to; one that started inside has the floor 0, so a
    /// step's overshoot (the rows are soft, as the contacts' points) is driven back by the next
    /// steps' position bias, as a contact point's overlap is, instead of being the next step's
    /// starting point (the creep that took a held leg's tendon to 0.051 for a limit of 0.02 in 2 s).
    pub fn floor(&self, k: usize) -> [f64; 2] {
        self.floor[k]
    }

    /// Sets every floor to `min(0, g)` at `q`: where the limits start (a new simulation, or a state
    /// set from outside), a quantity outside its limit is taken as it is.
    pub fn restart_floor(&mut self, q: &[f64]) {
        for coord in 0..self.limited.len() {
            let (x, l) = (self.value(coord, q), &self.limited[coord]);
            self.floor[coord] = [(x - l.lower).min(0.0), (l.upper - x).min(0.0)];
        }
    }

    /// At the end of a step: raises each floor to `min(0, g)` at `q` where that is higher (a
    /// quantity outside its limit that came back), never lowers it.
    pub fn raise_floor(&mut self, q: &[f64]) {
        for coord in 0..self.limited.len() {
            let (x, l) = (self.value(coord, q), &self.limited[coord]);
            let gap = [x - l.lower, l.upper - x];
            for (floor, g) in self.floor[coord].iter_mut().zip(gap) {
                *floor = floor.max(g).min(0.0);
            }
        }
    }

    /// Records the gaps at the start of a step and clears the step's activity.
    pub fn begin_step(&mut self, q: &[f64]) {
        for coord in 0..self.limited.len() {
            let (x, l) = (self.value(coord, q), &self.limited[coord]);
            self.start_gap[coord] = [x - l.lower, l.upper - x];
        }
        self.active_now.fill(false);
    }

    /// Records the velocity at the start of the step's integration (after the impact phase), from
    /// which the force phase tells a friction row whose joint turned back within the step.
    pub fn begin_integration(&mut self, v: &[f64]) {
        for f in &mut self.frictional {
            f.start_velocity = v[f.v_index];
        }
    }

    /// Counts the coordinates (and tendons) whose limit pushed during the step.
    pub fn end_step(&mut self) {
        for (count, &on) in self.active_steps.iter_mut().zip(&self.active_now) {
            *count += u64::from(on);
        }
    }

    /// Applies the limits (and, in the force phase, the friction) to `(q, v)` for one phase of a
    /// step of `h` seconds: finds the active rows, solves `K λ ≥ b ⊥ λ ≥ 0` (boxed for friction
    /// rows), then `v += M⁻¹ Jᵀ λ` (and, in the force phase, `q ← q ⊕ c h Δv`). Does nothing (and
    /// computes no `M`) when no row needs an impulse.
    pub fn apply(
        &mut self,
        model: &MultibodyModel,
        ws: &mut Workspace,
        phase: Phase,
        h: f64,
        q: &mut [f64],
        v: &mut [f64],
    ) {
        self.forced.fill([false; 2]);
        if !self.find_rows(phase, h, q, v) {
            return;
        }
        // M(q) = Lᵀ D L (Featherstone §6.5); a tree with a singular M cannot be stepped by ABA either
        if crba(model, ws, q).is_err() || ltdl_factor(model, ws).is_err() {
            return;
        }
        for _ in 0..MAX_GROWTH {
            if !self.solve(model, ws) {
                return;
            }
            // a row left out that the others' impulses push past its limit joins, and all is redone
            if !self.push_forced(phase, h, q, v) {
                break;
            }
            self.find_rows(phase, h, q, v);
        }
        for (r, row) in self.rows.iter().enumerate() {
            if self.lambda[r] > 0.0 && row.coord != FRICTION {
                self.active_now[row.coord] = true;
            }
        }
        for (v, dv) in v.iter_mut().zip(&self.dv) {
            *v += dv;
        }
        if let Phase::Force { c } = phase {
            // q ← q ⊕ c h Δv (the position moved by a constant force over the step)
            self.q_tmp.copy_from_slice(q);
            let _ = model.integrate(&self.q_tmp, &self.dv, c * h, q);
        }
    }

    /// The change of row velocity asked by row `(coord, sign)` at `(x, J v)` (the coordinate or
    /// tendon length and its rate), and its gap.
    fn demand(&self, phase: Phase, h: f64, coord: usize, side: usize, q_i: f64, v_i: f64) -> (f64, f64) {
        let l = &self.limited[coord];
        let (sign, gap) = if side == 0 { (1.0, q_i - l.lower) } else { (-1.0, l.upper - q_i) };
        let u = sign * v_i;
        let g0 = self.start_gap[coord][side];
        let b = match phase {
            // u⁺ ≥ min(0, −g/h); a joint outside its limit only loses its outward speed
            Phase::Impact | Phase::EndVelocity { .. } => (-gap / h).min(0.0) - u,
            // g₁ + c h Δu ≥ 0, the gap measured from the start when it started outside
            Phase::Force { c } => -(gap - g0.min(0.0)) / (c * h),
        };
        (b, gap)
    }

    /// Fills `rows` with the limit rows that need an impulse (`b > 0`), are near their limit, or
    /// were forced in, then (in a phase with friction) every friction row; returns whether one needs
    /// an impulse.
    fn find_rows(&mut self, phase: Phase, h: f64, q: &[f64], v: &[f64]) -> bool {
        self.rows.clear();
        let mut needed = false;
        for coord in 0..self.limited.len() {
            let l = self.limited[coord];
            let (x, u) = (self.value(coord, q), self.jacobian_dot(coord, v));
            for side in 0..2 {
                let (b, gap) = self.demand(phase, h, coord, side, x, u);
                if b > 0.0 {
                    needed = true;
                } else if gap >= NEAR_GAP && !self.forced[coord][side] {
                    continue;
                }
                let sign = if side == 0 { 1.0 } else { -1.0 };
                self.rows.push(Row {
                    coord,
                    v_index: l.v_index,
                    sign,
                    b,
                    lo: 0.0,
                    hi: f64::INFINITY,
                    mean_cap: f64::INFINITY,
                });
            }
        }
        if phase.with_friction() {
            for f in &self.frictional {
                // J = e_iᵀ, target u⁺ = 0: b = −u; |λ| ≤ F h (MuJoCo's friction-loss row)
                let b = -v[f.v_index];
                // the force moves the joint by h ū⁺ over the step, ū⁺ = (1 − c) u₀ + c u₁⁺ (exact
                // for constant acceleration), and works λ ū⁺: with c = 1 (semi-implicit Euler)
                // ū⁺ = u₁⁺, never opposed by λ. With c < 1 (RK4) a joint that turned back within the
                // step (ū and u₁ of opposite signs) is left free this step, and the impulse may not
                // reverse ū (bounded by |ū| / (c K_rr) in the solve), so that friction never adds
                // energy at a turning point
                let c = if let Phase::Force { c } = phase { c } else { 1.0 };
                let mean = (1.0 - c) * f.start_velocity + c * v[f.v_index];
                let bound = if mean * v[f.v_index] < 0.0 { 0.0 } else { f.friction_loss * h };
                let mean_cap = if c < 1.0 { mean.abs() / c } else { f64::INFINITY };
                needed |= b != 0.0;
                self.rows.push(Row {
                    coord: FRICTION,
                    v_index: f.v_index,
                    sign: 1.0,
                    b,
                    lo: -bound,
                    hi: bound,
                    mean_cap,
                });
            }
        }
        needed
    }

    /// Marks the rows left out of the solve that `Δv` pushes past their limits; whether there are any.
    fn push_forced(&mut self, phase: Phase, h: f64, q: &[f64], v: &[f64]) -> bool {
        let mut any = false;
        for coord in 0..self.limited.len() {
            for side in 0..2 {
                if self.forced[coord][side]
                    || self.rows.iter().any(|r| r.coord == coord && (r.sign > 0.0) == (side == 0))
                {
                    continue;
                }
                let (x, u) = (self.value(coord, q), self.jacobian_dot(coord, v));
                let (b, _) = self.demand(phase, h, coord, side, x, u);
                let j_dv = self.jacobian_dot(coord, &self.dv);
                let du = if side == 0 { j_dv } else { -j_dv };
                // still needs b − Δu > 0 after the others' impulses
                if b - du > 1e-12 * (1.0 + b.abs()) {
                    self.forced[coord][side] = true;
                    any = true;
                }
            }
        }
        any
    }

    /// Builds `K` from `M⁻¹` columns, solves the LCP, and writes `Δv = M⁻¹ Jᵀ λ`.
    fn solve(&mut self, model: &MultibodyModel, ws: &Workspace) -> bool {
        let n = self.rows.len();
        for (r, row) in self.rows.iter().enumerate() {
            // column r: M⁻¹ e_i (a joint's row), M⁻¹ J_tᵀ (a tendon's: Featherstone §6.5)
            let mut col = self.minv_cols.column_mut(r);
            col.fill(0.0);
            if row.v_index != NONE {
                col[row.v_index] = 1.0;
            } else {
                let l = &self.limited[row.coord];
                for t in &self.tendon_terms[l.terms.0..l.terms.1] {
                    col[t.v_index] += t.coef;
                }
            }
            if ltdl_solve(model, ws, col.as_mut_slice()).is_err() {
                return false;
            }
        }
        for r in 0..n {
            for s in 0..n {
                // K_rs = s_r s_s J_r M⁻¹ J_sᵀ: s_r s_s (M⁻¹)_{i_r i_s} for two joints' rows
                let (a, b) = (self.rows[r], self.rows[s]);
                let j_col = if a.v_index != NONE {
                    self.minv_cols[(a.v_index, s)]
                } else {
                    self.row_dot(r, self.minv_cols.column(s).as_slice())
                };
                self.k[(r, s)] = a.sign * b.sign * j_col;
            }
        }
        // a friction row's impulse may not reverse its mean velocity: |λ| ≤ |ū| / (c K_rr)
        for r in 0..n {
            let cap = self.rows[r].mean_cap / self.k[(r, r)];
            if cap < self.rows[r].hi {
                self.rows[r].hi = cap;
                self.rows[r].lo = -cap;
            }
        }
        // limits alone: Murty's exact pivoting; with friction rows the boxed pivoting; each falls
        // back to projected Gauss–Seidel
        let boxed = self.rows[..n].iter().any(|r| r.coord == FRICTION);
        if !(if boxed { self.solve_boxed(n) } else { self.solve_murty(n) }) {
            self.solve_pgs(n);
        }
        // Δv = Σ_r (M⁻¹ J_rᵀ / s_r) s_r λ_r
        self.dv.fill(0.0);
        for (r, row) in self.rows.iter().enumerate() {
            let l = self.lambda[r] * row.sign;
            for (dv, m) in self.dv.iter_mut().zip(self.minv_cols.column(r).iter()) {
                *dv += m * l;
            }
        }
        true
    }

    /// Murty's principal pivoting with the least-index rule on `w = K λ − b ≥ 0, λ ≥ 0, λᵀ w = 0`
    /// (first `n` rows): solve `K_BB λ_B = b_B` on the basis `B`, then move the first row with
    /// `λ_r < 0` (in `B`) or `w_r < 0` (out of `B`) across; ends for a P-matrix `K`.
    ///
    /// Reference: K. G. Murty, *Linear Complementarity, Linear and Nonlinear Programming* (1988),
    /// §4.1 (the least-index principal pivoting method). Returns false when a reduced system is
    /// singular or the pivots run out.
    fn solve_murty(&mut self, n: usize) -> bool {
        let scale = self.rows[..n].iter().map(|r| r.b.abs()).fold(0.0, f64::max).max(f64::MIN_POSITIVE);
        let tolerance = 1e-12 * scale;
        self.basis[..n].iter_mut().enumerate().for_each(|(r, b)| *b = self.rows[r].b > 0.0);
        for _ in 0..MAX_PIVOTS {
            if !self.solve_basis(n) {
                return false;
            }
            let mut pivot = None;
            for r in 0..n {
                let w: f64 = (0..n).map(|s| self.k[(r, s)] * self.lambda[s]).sum::<f64>() - self.rows[r].b;
                let lambda_r = self.lambda[r];
                // λ is in impulse units, b / K_rr
                let lambda_tolerance = tolerance / self.k[(r, r)];
                if (self.basis[r] && lambda_r < -lambda_tolerance) || (!self.basis[r] && w < -tolerance) {
                    pivot = Some(r);
                    break;
                }
            }
            match pivot {
                None => {
                    self.lambda[..n].iter_mut().for_each(|l| *l = l.max(0.0));
                    return true;
                }
                Some(r) => self.basis[r] = !self.basis[r],
            }
        }
        false
    }

    /// `λ_B = K_BB⁻¹ b_B`, `λ = 0` off the basis, by Gaussian elimination with partial pivoting.
    fn solve_basis(&mut self, n: usize) -> bool {
        self.basis_rows.clear();
        self.basis_rows.extend((0..n).filter(|&r| self.basis[r]));
        let m = self.basis_rows.len();
        for (a, &r) in self.basis_rows.iter().enumerate() {
            for (b, &s) in self.basis_rows.iter().enumerate() {
                self.reduced[(a, b)] = self.k[(r, s)];
            }
            self.rhs[a] = self.rows[r].b;
        }
        if !eliminate(&mut self.reduced, &mut self.rhs, m) {
            return false;
        }
        self.lambda[..n].fill(0.0);
        for (a, &r) in self.basis_rows.iter().enumerate() {
            self.lambda[r] = self.rhs[a];
        }
        true
    }

    /// The boxed problem exactly (rows with friction): `w = K λ − b` with `λ ∈ [lo, hi]`, `w = 0`
    /// for a row between its bounds (`F`), `w ≥ 0` at `lo` (`L`), `w ≤ 0` at `hi` (`U`), by
    /// principal pivoting with the least-index rule as [`Self::solve_murty`]: solve
    /// `K_FF λ_F = b_F − K_FB λ_B` with the others at their bounds, then move the first row that
    /// breaks its condition (`λ_r` past a bound in `F`; `w_r < 0` at `lo`, `w_r > 0` at `hi`) to the
    /// bound it crossed or into `F`. For symmetric positive definite `K` the solution minimises
    /// `½ λᵀ K λ − bᵀ λ` over the box and is unique.
    ///
    /// Reference: K. G. Murty (1988), §4.1, extended to bounds as the box-constrained LCP of
    /// friction (MuJoCo documentation, *Computation*: "friction loss" rows have `|f| ≤ frictionloss`;
    /// Erleben 2007 for the same problem by PGS). Returns false when a reduced system is singular
    /// (two rows on one coordinate, a limit and its friction) or the pivots run out: the caller then
    /// takes projected Gauss–Seidel.
    fn solve_boxed(&mut self, n: usize) -> bool {
        let scale = self.rows[..n].iter().map(|r| r.b.abs()).fold(0.0, f64::max).max(f64::MIN_POSITIVE);
        let tolerance = 1e-12 * scale;
        for r in 0..n {
            let row = self.rows[r];
            // start: friction sticks, a limit pushes where it needs to; a row whose box is a point
            // (a friction row left free this step) stays at it
            self.bound[r] = if row.lo == row.hi {
                Bound::Lower
            } else if row.coord == FRICTION || row.b > 0.0 {
                Bound::Free
            } else {
                Bound::Lower
            };
        }
        for _ in 0..MAX_PIVOTS {
            if !self.solve_boxed_basis(n) {
                return false;
            }
            let mut pivot = None;
            for r in 0..n {
                let w: f64 = (0..n).map(|s| self.k[(r, s)] * self.lambda[s]).sum::<f64>() - self.rows[r].b;
                let (lambda_r, row) = (self.lambda[r], self.rows[r]);
                let lambda_tolerance = tolerance / self.k[(r, r)];
                let next = match self.bound[r] {
                    _ if row.lo == row.hi => None,
                    Bound::Free if lambda_r < row.lo - lambda_tolerance => Some(Bound::Lower),
                    Bound::Free if lambda_r > row.hi + lambda_tolerance => Some(Bound::Upper),
                    Bound::Lower if w < -tolerance => Some(Bound::Free),
                    Bound::Upper if w > tolerance => Some(Bound::Free),
                    _ => None,
                };
                if let Some(b) = next {
                    pivot = Some((r, b));
                    break;
                }
            }
            match pivot {
                None => {
                    for (l, row) in self.lambda[..n].iter_mut().zip(&self.rows) {
                        *l = l.max(row.lo).min(row.hi);
                    }
                    return true;
                }
                Some((r, b)) => self.bound[r] = b,
            }
        }
        false
    }

    /// `λ_F = K_FF⁻¹ (b_F − K_FB λ_B)` with the rows off `F` at their bounds.
    fn solve_boxed_basis(&mut self, n: usize) -> bool {
        for r in 0..n {
            self.lambda[r] = match self.bound[r] {
                Bound::Free => 0.0,
                Bound::Lower => self.rows[r].lo,
                Bound::Upper => self.rows[r].hi,
            };
            // a limit row has no upper bound
            if !self.lambda[r].is_finite() {
                return false;
            }
        }
        self.basis_rows.clear();
        self.basis_rows.extend((0..n).filter(|&r| self.bound[r] == Bound::Free));
        let m = self.basis_rows.len();
        for (a, &r) in self.basis_rows.iter().enumerate() {
            for (b, &s) in self.basis_rows.iter().enumerate() {
                self.reduced[(a, b)] = self.k[(r, s)];
            }
            // b_r − Σ_{s ∉ F} K_rs λ_s
            let fixed: f64 =
                (0..n).filter(|&s| self.bound[s] != Bound::Free).map(|s| self.k[(r, s)] * self.lambda[s]).sum();
            self.rhs[a] = self.rows[r].b - fixed;
        }
        if !eliminate(&mut self.reduced, &mut self.rhs, m) {
            return false;
        }
        for (a, &r) in self.basis_rows.iter().enumerate() {
            self.lambda[r] = self.rhs[a];
        }
        true
    }

    /// Projected Gauss–Seidel on the boxed problem `w = K λ − b`, `λ ∈ [lo, hi]` with `w ≥ 0` at
    /// `lo`, `w ≤ 0` at `hi`, `w = 0` between (for a limit row `[0, ∞)`: `w ≥ 0, λ ≥ 0, λᵀ w = 0`),
    /// for the first `n` rows. Each update minimises `½ λᵀ K λ − bᵀ λ` along its row within the
    /// box, so from `λ = 0` the objective — for friction rows the kinetic energy after the impulse,
    /// less before — never rises.
    ///
    /// Reference: K. Erleben, "Velocity-based shock propagation for multibody dynamics animation",
    /// ACM TOG 26(2), 2007, §3 (PGS, with the box clamp of friction); converges for symmetric
    /// positive definite `K`.
    fn solve_pgs(&mut self, n: usize) {
        self.lambda[..n].fill(0.0);
        for _ in 0..MAX_SWEEPS {
            let mut change = 0.0_f64;
            let mut size = 0.0_f64;
            for r in 0..n {
                // λ_r ← clamp(λ_r − (Σ_s K_rs λ_s − b_r) / K_rr, lo_r, hi_r)
                let w: f64 = (0..n).map(|s| self.k[(r, s)] * self.lambda[s]).sum::<f64>() - self.rows[r].b;
                let k_rr = self.k[(r, r)];
                if k_rr.is_nan() || k_rr <= 0.0 {
                    continue;
                }
                let next = (self.lambda[r] - w / k_rr).max(self.rows[r].lo).min(self.rows[r].hi);
                change = change.max((next - self.lambda[r]).abs());
                size = size.max(next.abs());
                self.lambda[r] = next;
            }
            if change <= SWEEP_TOLERANCE * size {
                break;
            }
        }
    }
}

/// Solves `k x = rhs` in place on the leading `m × m` block by Gaussian elimination with partial
/// pivoting (`x` left in `rhs`); false when a pivot is at round-off of `k`'s scale (singular).
fn eliminate(k: &mut DMatrix<f64>, x: &mut [f64], m: usize) -> bool {
    let k_max = (0..m).map(|a| k[(a, a)].abs()).fold(0.0, f64::max);
    for col in 0..m {
        let p = (col..m).max_by(|&a, &b| k[(a, col)].abs().total_cmp(&k[(b, col)].abs())).unwrap_or(col);
        // a pivot at round-off of K's scale: K_BB is singular (a joint with lower = upper)
        let pivot = k[(p, col)].abs();
        if pivot.is_nan() || pivot <= 1e-13 * k_max {
            return false;
        }
        if p != col {
            k.swap_rows(p, col);
            x.swap(p, col);
        }
        for r in col + 1..m {
            let f = k[(r, col)] / k[(col, col)];
            for c in col..m {
                k[(r, c)] -= f * k[(col, c)];
            }
            x[r] -= f * x[col];
        }
    }
    for col in (0..m).rev() {
        let tail: f64 = (col + 1..m).map(|c| k[(col, c)] * x[c]).sum();
        x[col] = (x[col] - tail) / k[(col, col)];
    }
    true
}
