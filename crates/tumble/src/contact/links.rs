//! Robot links in contact: collisions and resting contact of link shapes, in generalized velocities.
//!
//! References: B. Mirtich, PhD thesis (1996), ch. 4 (the collision matrix of a point of an
//! articulated body, `K = J_c M⁻¹ J_cᵀ`, constant during the impact, so that the impact integration
//! of a pair of rigid bodies applies unchanged); R. Featherstone, *Rigid Body Dynamics Algorithms*
//! (2008), §6.5 (the `LᵀDL` factor that gives `M⁻¹ J_cᵀ`); E. Catto, Box2D v3 (the soft step).
//!
//! A contact point `c` on a link of a robot moves with `u_c = J_c v` (module
//! [`crate::multibody::contact_point`]); an impulse `p` there changes the robot's joint velocities by
//! `Δv = W p`, `W = M⁻¹ J_cᵀ`. A contact has two sides, each a fixed body, a free body or a robot
//! link; with `σ_a = −1`, `σ_b = +1` (the impulse `p` acts on `b`, `−p` on `a`):
//!
//! ```text
//! u = Σ_s σ_s u_s                      relative velocity of b with respect to a at the point
//! K = Σ_s K_s + Σ_{s,s' same robot} σ_s σ_s' J_s W_s'
//! ```
//!
//! with `K_s` a free body's own `(1/m) 1 − r̃ I⁻¹ r̃` (fixed: zero). Two links of the same robot thus
//! give `K = (J_b − J_a) M⁻¹ (J_b − J_a)ᵀ`, not a sum; links of two robots the sum of their
//! matrices. `K` is only positive semi-definite at a singular pose (an arm stretched along the
//! normal): collisions use `K + ε tr(K) 1` with `ε = 1e-12` ([`SINGULAR_EPSILON`]), and the resting
//! rows skip a direction whose `K` entry is below `ε tr(K)`, zero but for the round-off of `J` (a
//! wheel touching the floor below its axle cannot move along the normal; taken as a mass, that
//! round-off sent the wheel to 3.8e14 rad in one step).
//!
//! Per step, for each robot with a contact: `M(q₀)` by CRBA and its `LᵀDL` factor, each point's
//! `J_c`, and the free acceleration `a₀ = ABA(q₀, v₀, τ(q₀, v₀))` (gravity, the joint forces and PD,
//! held over the step as the free bodies' forces are).
//!
//! **Contact space.** The solve never forms `W`: a robot's rows of the step (three per contact
//! point, one per joint-limit row, one per friction-loss row) make its contact space, with the Delassus matrix
//! `G = J M⁻¹ Jᵀ = Yᵀ D⁻¹ Y`, `Y = L⁻ᵀ Jᵀ` (non-zero only on the coordinates on the path of each
//! row's link to the root: branch-induced sparsity, Featherstone 2008, §6.5), and per row the
//! velocity `u = J v`, the displacement `s = J d`, `J a₀`, and the impulses `P` applied so far. An
//! impulse `Δp` on rows `k` changes every row's velocity by `G_{·k} Δp` (`O(rows)`, not `O(nv)`); a
//! substep adds `h J a₀` to `u` and `h u` to `s`. After the substeps the joint-space results follow
//! from one sparse solve each: `v = v₀ + dt a₀ + M⁻¹ Jᵀ P`, `d = dt v₀ + (Σ h t) a₀ + M⁻¹ Jᵀ Q` with
//! `Q = Σ h P` over the substeps' moves, `τ_c = Jᵀ P / dt`. Then, as for the free bodies:
//!
//! 1. **Collisions**: a contact approaching faster than `impact_speed` whose gap closes within the
//!    step at that speed is a collision, integrated through the impact with `K` and `u`
//!    ([`super::collide`]: Coulomb friction, Stronge's law, never a gain of energy). Collisions are
//!    taken in contact order, sweep after sweep, until no contact collides (at most
//!    [`IMPACT_SWEEPS`] sweeps). The impulse is applied at the start of the step (a robot has no
//!    position shift for the time of impact: the energy of an elastic strike is then kept exactly).
//! 2. **Resting contact**: each contact is a row of the soft step beside the free bodies' constraints
//!    (same softness, speculative rule, friction disc, relaxation). In each substep `h` a robot's
//!    solver velocity gains `h a₀`, the rows change it by `W Δλ`, and its displacement in velocity
//!    coordinates grows by `h v`, which moves the point by `J_c d` (the row's separation).
//!
//! **Joint rows.** The joint limits of an engaged robot are rows `J = s e_iᵀ` of the same substeps
//! (one-sided, with the contacts' position bias and softness), and so are the limits of its
//! limited fixed tendons, rows `J = ±J_t` on the length `L = L₀ + Σ c_k q_k` (`s c_k` on each
//! term's coordinate; the row's chain is the union of the terms' paths to the root, which
//! [`delassus`](crate::multibody::contact_point) handles as a chain that is not a path), with the
//! gap `L − lo` or `hi − L`, each measured from its floor
//! ([`crate::multibody::JointLimitSolver::floor`]: 0 for a quantity that started inside its range,
//! so a soft row's overshoot is driven back by the position bias as a contact point's overlap is,
//! instead of creeping under a steady load; lower for one that started outside, which is not
//! pushed in); and so is its joints' dry friction
//! (MuJoCo documentation, *Computation*: friction loss): per velocity coordinate `k` of a joint with
//! friction loss `F`, a row `J = e_kᵀ` with
//!
//! ```text
//! λ ← clamp(λ − u / G_kk, −F h, F h)      u = v_k, target u⁺ = 0, h the substep
//! ```
//!
//! no position bias and no softness, in the same passes as the limit rows (projected Gauss–Seidel
//! with the box clamp, Erleben 2007). `λ` is the impulse of one substep (applied again by the warm
//! start of the next, as the contact rows'), so the step's friction impulse is `|Σ λ| ≤ F dt`, a
//! force within `±F`. It is warm started from the previous step's last substep: without a position
//! bias, the residual velocity that one sweep per pass leaves would otherwise become drift.
//!
//! A robot the resting rows reached is integrated by its own method with the rows' generalized
//! force over the step added to its joint forces, `τ_c = Jᵀ P / dt` (`P` the rows' impulses of the
//! step), so that it ends at the solver's velocity up to the change of `a` over the step — RK4; the
//! Euler methods, whose single evaluation at `(q₀, v₀)` is `a₀`, take the solver's end velocity
//! itself — and its configuration is then replaced by where the substeps put it, `q₀ ⊕ d`, which
//! holds the overlap correction. A robot only struck (collisions, no resting impulse) gets the
//! collisions' `Δv` at the start of its step and is integrated as usual.

use super::impact::tangent_basis;
use super::solver::{Pass, Softness, SolverBody, Sweep};
use super::{collide, ContactSettings};
use crate::body::{Material, RigidBody};
use crate::collision::links::{BodyMotion, LinkColliders, LinkContact, Side};
use crate::collision::Colliders;
use crate::math::{DMat3, DQuat, DVec3};
use crate::multibody::contact_point::{chain_dot, delassus, delassus_scratch_len, path_dofs, point_jacobian};
use crate::multibody::{bias_forces_placed, crba, ltdl_factor, ContactChange, Control, MultibodyModel, Workspace};
use parry3d_f64::math::Pose;

/// A limited coordinate within this distance (rad or m) of its limit, beyond what the step's
/// velocity can cover, gets a limit row.
pub const LIMIT_MARGIN: f64 = 1e-3;

/// `ε` of the regularised collision matrix `K + ε tr(K) 1` of a collision involving a robot.
pub const SINGULAR_EPSILON: f64 = 1e-12;

/// Sweeps over the robot contacts in the collision stage at most.
pub const IMPACT_SWEEPS: usize = 16;

/// The robots as the contact stage reads them, one [`RobotView`] each: the world implements it for
/// its robots and hands them down, so that the contact stage never names the world's `Robot`.
pub trait RobotViews {
    /// How many robots.
    fn count(&self) -> usize;
    /// Robot `robot`'s view.
    fn view(&self, robot: usize) -> RobotView<'_>;
}

/// What the contact stage reads of a robot: its model, the forward kinematics of its current state
/// (`ws.x_world`, `ws.v`), its state, control and material ([`crate::world::Robot::contact_view`]).
#[derive(Clone, Copy)]
pub struct RobotView<'a> {
    pub model: &'a MultibodyModel,
    pub ws: &'a Workspace,
    pub q: &'a [f64],
    pub v: &'a [f64],
    pub control: &'a Control,
    pub material: Material,
    /// The joint position limits, when enforced.
    pub limits: Option<&'a crate::multibody::JointLimitSolver>,
}

/// One side of a row.
#[derive(Debug, Clone, Copy, PartialEq)]
enum RowSide {
    Fixed,
    Body(usize),
    /// A point of a robot link: its three rows (world x, y, z) start at row `off` of the robot's
    /// contact space.
    Robot {
        robot: usize,
        off: usize,
    },
}

/// One contact row (world frame).
#[derive(Debug, Clone, Copy)]
struct Row {
    a: RowSide,
    b: RowSide,
    /// Offsets of the point from the centres of mass of free-body sides (zero otherwise) (m).
    r_a: DVec3,
    r_b: DVec3,
    n: DVec3,
    t1: DVec3,
    t2: DVec3,
    gap: f64,
    /// `gap − n·(r_b − r_a)`.
    adjusted_gap: f64,
    k: DMat3,
    normal_mass: f64,
    tangent_mass: [f64; 4],
    tangent_k: [f64; 3],
    ang_a: [DVec3; 3],
    ang_b: [DVec3; 3],
    mu: f64,
    e: f64,
    softness: Softness,
    speculative: bool,
    lambda: [f64; 3],
}

/// A joint-limit row of a robot the contact rows engage: `J = s e_iᵀ` in joint space (`s = +1` at a
/// lower limit, `−1` at an upper one), or `J = s J_t` for a limited fixed tendon, one-sided,
/// without friction; a row of the robot's contact space. Solved in the same substeps as the contact
/// rows, so that the two never fight.
#[derive(Debug, Clone, Copy)]
struct LimitRow {
    robot: usize,
    /// Index among the robot's limited coordinates, then its limited tendons (for the run report:
    /// [`crate::multibody::JointLimitSolver::note_active`]).
    limited: usize,
    /// Distance at the start of the step to the limit, measured from its floor
    /// ([`crate::multibody::JointLimitSolver::floor`]): `g − floor` (rad or m; negative when the
    /// coordinate sank below its floor, which the position bias then drives back).
    gap: f64,
    /// Its row in the robot's contact space.
    off: usize,
    normal_mass: f64,
    softness: Softness,
    lambda: f64,
}

/// A friction-loss row of a robot the contact rows engage: `J = e_iᵀ` for a velocity coordinate `i`
/// of a joint with dry friction `F`, the impulse of each substep of `h` bounded, `|λ| ≤ F h`, the
/// target velocity `u⁺ = 0`, no position bias and no softness; a row of the robot's contact space,
/// solved in the same passes as the limit rows.
#[derive(Debug, Clone, Copy)]
struct FrictionRow {
    robot: usize,
    /// `F` (N·m or N).
    friction_loss: f64,
    /// Its row in the robot's contact space.
    off: usize,
    normal_mass: f64,
    /// The impulse of the current substep (N·m·s or N·s).
    lambda: f64,
}

impl LimitRow {
    /// The row of robot `r`'s `k`-th limited coordinate or tendon at distance `gap` from its
    /// limit, whose floor is `floor` (`≤ 0`). A quantity that started outside its limit (where the
    /// simulation started or the state was set) is measured from its floor, the furthest in it has
    /// come since: the row stops further motion out and lets it come back, it does not push it in
    /// (as `multibody::limits` does without contact). Below its floor — a soft row's overshoot in an
    /// earlier step — the gap is negative and the row's position bias drives it back, as a contact
    /// point's overlap: measured from where each step starts instead, the overshoot of every step
    /// was kept and a steady load crept through the limit (a held leg's tendon to 0.051 for a limit
    /// of 0.02 in 2 s).
    fn new(robot: usize, limited: usize, gap: f64, floor: f64, off: usize, softness: Softness) -> Self {
        LimitRow { robot, limited, gap: gap - floor, off, normal_mass: 0.0, softness, lambda: 0.0 }
    }
}

/// A row of the previous step and its impulses (warm starting).
#[derive(Debug, Clone, Copy)]
struct Previous {
    a: Side,
    b: Side,
    features: (u64, u64),
    point_world: DVec3,
    lambda: [f64; 3],
}

/// A robot's part of the solve.
#[derive(Debug, Clone)]
struct RobotSolve {
    /// Whether a row uses it in this step (its `M`, `a₀` are computed).
    engaged: bool,
    nv: usize,
    ws: Workspace,
    tau: Vec<f64>,
    /// `v₀`, the velocity at the end of the substeps (from [`Self::velocity_change`]), `a₀`, and
    /// the displacement `d = Σ h v` (velocity coordinates).
    v0: Vec<f64>,
    v: Vec<f64>,
    a0: Vec<f64>,
    d: Vec<f64>,
    /// The contact space of the step (module text): per row its Jacobian row `J` and then
    /// `Y = L⁻ᵀ Jᵀ` (`rows × nv`), its chain of coordinates (`chains[start..start + len]`), and
    /// `G = J M⁻¹ Jᵀ` (`rows × rows`, row-major).
    jac: Vec<f64>,
    y: Vec<f64>,
    /// Scratch of [`delassus`] (`D^{-1/2} Y` by blocks of rows, and the blocks), and the factor's
    /// `1 / D_k`, `D_k^{-1/2}` (nv).
    y_scaled: Vec<f64>,
    blocks: Vec<(usize, usize, bool)>,
    inv_d: Vec<f64>,
    inv_sqrt_d: Vec<f64>,
    chain_of: Vec<(usize, usize)>,
    chains: Vec<usize>,
    g: Vec<f64>,
    /// Per row: `u = J v`, `s = J d`, `J a₀`, `J v₀`, the impulses applied `P`, and `Q = Σ h P`.
    u: Vec<f64>,
    s: Vec<f64>,
    ja0: Vec<f64>,
    u0: Vec<f64>,
    p: Vec<f64>,
    q: Vec<f64>,
    /// Time the velocity was advanced by `h a₀` (s), `Σ h t` over the moves (s²), `Σ h` (s).
    t_velocity: f64,
    t_moves: f64,
    t_moved: f64,
    /// What the robot's own step takes: `Δv` and, when held, `q₀ ⊕ d`.
    dv: Vec<f64>,
    q_end: Vec<f64>,
    tau_c: Vec<f64>,
    struck: bool,
    touched: bool,
    /// The kinetic energy this step's collisions took from the robot (J): `T(v₀) − T(v₀ + Δv)`,
    /// `T(v) = ½ vᵀ M(q₀) v`.
    impact_loss: f64,
    /// The last substep's impulse of each friction-loss row of the previous step, in the order of
    /// [`crate::multibody::JointLimitSolver::friction_losses`] (warm starting; empty when the robot
    /// was not engaged).
    friction_warm: Vec<f64>,
}

/// The link contacts of a step and the buffers to resolve them (no allocation once grown).
#[derive(Debug, Clone, Default)]
pub struct LinkStage {
    /// The link shapes of every robot.
    pub colliders: LinkColliders,
    contacts: Vec<LinkContact>,
    impulses: Vec<DVec3>,
    rows: Vec<Row>,
    limit_rows: Vec<LimitRow>,
    friction_rows: Vec<FrictionRow>,
    lambda_sums: Vec<[f64; 3]>,
    robots: Vec<RobotSolve>,
    previous: Vec<Previous>,
    /// The step (s) and the contact stage's substep (s).
    dt: f64,
    substep: f64,
    /// Collisions resolved and kinetic energy they dissipated (J), since the start.
    pub impacts: u64,
    pub energy_lost: f64,
    /// Mechanical energy (kinetic plus gravitational) the resting link contacts took from the robots
    /// they held, since the start (J): per held step, `E(q₀, v₀ + Δv) − E(end)` with `Δv` the
    /// step's collisions; booked by the world after each robot's step ([`Self::book_resting`]).
    pub resting_energy_lost: f64,
    /// The potential energy stored in the soft rows' springs at the end of the last solve (J):
    /// [`Self::elastic_energy`].
    elastic_energy: f64,
}

impl LinkStage {
    /// The link contacts of the last step.
    pub fn contacts(&self) -> &[LinkContact] {
        &self.contacts
    }

    /// The impulse on side `b` of each link contact over the last step (N·s, world frame).
    pub fn impulses(&self) -> &[DVec3] {
        &self.impulses
    }

    /// The active link contacts of the last step with their impulses on `b` (N·s): those that
    /// carried an impulse or whose surfaces overlapped (as [`super::ContactStage::active`]).
    pub fn active(&self) -> impl Iterator<Item = (&LinkContact, DVec3)> {
        self.contacts
            .iter()
            .zip(&self.impulses)
            .filter(|(c, p)| **p != DVec3::ZERO || c.gap < 0.0)
            .map(|(c, p)| (c, *p))
    }

    /// Finds the link contacts at the start of the step.
    pub(super) fn detect(
        &mut self,
        colliders: &Colliders,
        bodies: &[RigidBody],
        robots: &dyn RobotViews,
        dt: f64,
        slop: f64,
    ) {
        // (set again by the step's solve, if it has one)
        self.elastic_energy = 0.0;
        if self.colliders.is_empty() {
            self.contacts.clear();
            return;
        }
        self.colliders.place(dt, slop, |r, b| {
            let ws = robots.view(r).ws;
            let (x, v) = (ws.x_world[b], ws.v[b]);
            // b_X_0 = (E, r): world_from_body = (Eᵀ, r)
            BodyMotion {
                pose: Pose::from_parts(x.r, DQuat::from_mat3(&x.rotation_a_from_b()).normalize()),
                speed: v.lin.length(),
                angular_speed: v.ang.length(),
            }
        });
        let mut contacts = std::mem::take(&mut self.contacts);
        self.colliders.find_contacts(colliders, bodies, &mut contacts);
        self.contacts = contacts;
    }

    /// The free bodies the links' contacts of the step touch (with repeats).
    pub(super) fn touched_bodies(&self) -> impl Iterator<Item = usize> + '_ {
        self.contacts.iter().flat_map(|c| [c.a, c.b]).filter_map(|s| match s {
            crate::collision::links::Side::Body(i) => Some(i),
            crate::collision::links::Side::Link(_) => None,
        })
    }

    /// Whether the step has link contacts.
    pub(super) fn is_empty(&self) -> bool {
        self.contacts.is_empty()
    }

    /// Builds the rows of the step's link contacts: each robot's `M`, `a₀`, each point's `J_c`, `W`.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn prepare(
        &mut self,
        bodies: &[RigidBody],
        solver_bodies: &[SolverBody],
        positions: &[DVec3],
        robots: &dyn RobotViews,
        settings: &ContactSettings,
        dt: f64,
        soft: Softness,
        soft_fixed: Softness,
    ) {
        self.impulses.clear();
        self.impulses.resize(self.contacts.len(), DVec3::ZERO);
        self.rows.clear();
        self.dt = dt;
        self.substep = dt / f64::from(settings.substeps.max(1));
        if self.robots.len() != robots.count() {
            self.robots = (0..robots.count()).map(|r| RobotSolve::new(robots.view(r).model)).collect();
        }
        for r in &mut self.robots {
            r.engaged = false;
            r.struck = false;
            r.touched = false;
        }
        for ci in 0..self.contacts.len() {
            let c = &self.contacts[ci].clone();
            let a = self.side(c.a, c.point_world, bodies, robots);
            let b = self.side(c.b, c.point_world, bodies, robots);
            let material = |s: Side| match s {
                Side::Body(i) => bodies[i].material,
                Side::Link(l) => robots.view(self.colliders.links()[l].robot).material,
            };
            let (ma, mb) = (material(c.a), material(c.b));
            let (mu, e) = super::combine_materials(ma, mb, settings);
            let against_fixed = a == RowSide::Fixed || b == RowSide::Fixed;
            let softness = if against_fixed { soft_fixed } else { soft };
            let mut row = self.row(a, b, c, solver_bodies, positions, mu, e, softness);
            if let Some(l) = previous_impulse(&self.previous, c) {
                row.lambda = l;
            }
            self.rows.push(row);
        }
        self.lambda_sums.clear();
        self.lambda_sums.resize(self.rows.len(), [0.0; 3]);
        self.limit_rows(robots, soft_fixed);
        // the rows of every engaged robot are known: its contact space, then each row's K
        for (r, solve) in self.robots.iter_mut().enumerate() {
            if solve.engaged {
                solve.contact_space(robots.view(r).model);
            }
        }
        for i in 0..self.rows.len() {
            let k = self.rows[i].k + self.robot_k(&self.rows[i]);
            self.rows[i].set_k(k);
        }
        for row in &mut self.limit_rows {
            let solve = &self.robots[row.robot];
            let k_ii = solve.g[row.off * solve.rows() + row.off];
            row.normal_mass = if k_ii > 0.0 { 1.0 / k_ii } else { 0.0 };
        }
        for row in &mut self.friction_rows {
            let solve = &self.robots[row.robot];
            let k_ii = solve.g[row.off * solve.rows() + row.off];
            row.normal_mass = if k_ii > 0.0 { 1.0 / k_ii } else { 0.0 };
        }
    }

    /// The robots' part of a row's `K`: `Σ_{s,s' same robot} σ_s σ_s' G_{ss'}` (3 × 3 blocks of
    /// the robot's `G`).
    fn robot_k(&self, row: &Row) -> DMat3 {
        let mut k = DMat3::ZERO;
        for (s, sigma) in [(row.a, -1.0), (row.b, 1.0)] {
            for (s2, sigma2) in [(row.a, -1.0), (row.b, 1.0)] {
                if let (RowSide::Robot { robot, off }, RowSide::Robot { robot: robot2, off: off2 }) = (s, s2) {
                    if robot == robot2 {
                        let solve = &self.robots[robot];
                        let n = solve.rows();
                        let g = |r: usize, c: usize| solve.g[(off + r) * n + off2 + c];
                        let block = DMat3::from_cols(
                            DVec3::new(g(0, 0), g(1, 0), g(2, 0)),
                            DVec3::new(g(0, 1), g(1, 1), g(2, 1)),
                            DVec3::new(g(0, 2), g(1, 2), g(2, 2)),
                        );
                        k += sigma * sigma2 * block;
                    }
                }
            }
        }
        k
    }

    /// The joint-limit rows of the engaged robots: each limited coordinate (and limited tendon length)
    /// that the step could carry to its limit (`gap ≤ |v| dt` plus a margin) gets a one-sided row; and their
    /// friction-loss rows: every velocity coordinate of a joint with friction loss gets one.
    fn limit_rows(&mut self, robots: &dyn RobotViews, soft: Softness) {
        self.limit_rows.clear();
        self.friction_rows.clear();
        for r in 0..robots.count() {
            if !self.robots[r].engaged {
                continue;
            }
            let view = robots.view(r);
            let Some(limits) = view.limits else { continue };
            for (k, (vi, friction_loss)) in limits.friction_losses().enumerate() {
                // J = e_iᵀ; its chain: coordinate i and those above it
                let solve = &mut self.robots[r];
                let off = solve.add_rows(1, dof_chain(view.model, vi));
                solve.jac[off * solve.nv + vi] = 1.0;
                // warm started from the previous step's last substep (a row without position bias
                // keeps what a single sweep per pass leaves of its velocity as drift otherwise)
                let bound = friction_loss * self.substep;
                let lambda = solve.friction_warm.get(k).map_or(0.0, |l| l.max(-bound).min(bound));
                self.friction_rows.push(FrictionRow { robot: r, friction_loss, off, normal_mass: 0.0, lambda });
            }
            for (k, (qi, vi, lower, upper)) in limits.bounds().enumerate() {
                let (q, v) = (view.q[qi], self.robots[r].v0[vi]);
                let floor = limits.floor(k);
                for ((sign, gap), floor) in [(1.0, q - lower), (-1.0, upper - q)].into_iter().zip(floor) {
                    if gap - floor > v.abs() * self.dt + LIMIT_MARGIN {
                        continue;
                    }
                    // J = s e_iᵀ; its chain: coordinate i and those above it
                    let solve = &mut self.robots[r];
                    let off = solve.add_rows(1, dof_chain(view.model, vi));
                    solve.jac[off * solve.nv + vi] = sign;
                    self.limit_rows.push(LimitRow::new(r, k, gap, floor, off, soft));
                }
            }
            // the limited fixed tendons: rows J = s J_t on `L = L₀ + Σ c_k q_k`, as the joints'
            for (k, t, lower, upper) in limits.tendon_bounds() {
                let tendon = &view.model.tendons[t];
                let (length, rate) = (tendon.length(view.q), tendon.rate(&self.robots[r].v0));
                let floor = limits.floor(k);
                for ((sign, gap), floor) in [(1.0, length - lower), (-1.0, upper - length)].into_iter().zip(floor) {
                    if gap - floor > rate.abs() * self.dt + LIMIT_MARGIN {
                        continue;
                    }
                    // J = s J_t: s c_k on each term's coordinate; its chain: the coordinates above
                    // any of them
                    let solve = &mut self.robots[r];
                    let off = solve.add_rows(1, tendon_chain(view.model, &tendon.terms));
                    for term in &tendon.terms {
                        solve.jac[off * solve.nv + term.v_index] = sign * term.coef;
                    }
                    self.limit_rows.push(LimitRow::new(r, k, gap, floor, off, soft));
                }
            }
        }
    }

    /// The row side of a contact side: a robot link's point adds three rows to its robot's contact
    /// space, with their Jacobian (the robot's `M` and `a₀` are computed at its first row of the
    /// step).
    fn side(&mut self, side: Side, point: DVec3, bodies: &[RigidBody], robots: &dyn RobotViews) -> RowSide {
        match side {
            Side::Body(i) if bodies[i].fixed => RowSide::Fixed,
            Side::Body(i) => RowSide::Body(i),
            Side::Link(l) => {
                let link = &self.colliders.links()[l];
                let Some(body) = link.body else { return RowSide::Fixed };
                let robot = link.robot;
                let view = robots.view(robot);
                let solve = &mut self.robots[robot];
                if !solve.engaged && !solve.engage(&view) {
                    return RowSide::Fixed;
                }
                let nv = solve.nv;
                let off = solve.add_rows(3, path_dofs(view.model, body));
                if point_jacobian(view.model, &solve.ws, body, point, &mut solve.jac[off * nv..(off + 3) * nv]).is_err()
                {
                    solve.truncate_rows(off);
                    return RowSide::Fixed;
                }
                RowSide::Robot { robot, off }
            }
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn row(
        &self,
        a: RowSide,
        b: RowSide,
        c: &LinkContact,
        bodies: &[SolverBody],
        positions: &[DVec3],
        mu: f64,
        e: f64,
        softness: Softness,
    ) -> Row {
        let n = c.normal_world;
        let (t1, t2) = tangent_basis(n);
        let offset = |s: RowSide| match s {
            RowSide::Body(i) => c.point_world - positions[i],
            _ => DVec3::ZERO,
        };
        let (r_a, r_b) = (offset(a), offset(b));
        // K = Σ K_s + Σ_{same robot} σ σ' J W
        let mut k = DMat3::ZERO;
        for (s, r) in [(a, r_a), (b, r_b)] {
            if let RowSide::Body(i) = s {
                let sb = &bodies[i];
                k += super::collision_matrix(sb.inv_mass, sb.inv_inertia, r, 0.0, DMat3::ZERO, DVec3::ZERO);
            }
        }
        let ang = |s: RowSide, r: DVec3| match s {
            RowSide::Body(i) => [n, t1, t2].map(|d| bodies[i].inv_inertia * r.cross(d)),
            _ => [DVec3::ZERO; 3],
        };
        Row {
            a,
            b,
            r_a,
            r_b,
            n,
            t1,
            t2,
            gap: c.gap,
            adjusted_gap: c.gap - n.dot(r_b - r_a),
            // the free bodies' part; the robots' part and the masses come with the contact space
            // (`set_k`)
            k,
            normal_mass: 0.0,
            tangent_mass: [0.0; 4],
            tangent_k: [0.0; 3],
            ang_a: ang(a, r_a),
            ang_b: ang(b, r_b),
            mu,
            e,
            softness,
            speculative: c.gap > 0.0,
            lambda: [0.0; 3],
        }
    }

    /// Stage 1 for the link contacts: collisions in contact order, sweep after sweep (see the
    /// module's text). Changes the free bodies' solver velocities (the caller writes them back).
    /// Whether any collision happened.
    pub(super) fn impacts(&mut self, bodies: &mut [SolverBody], settings: &ContactSettings, dt: f64) -> bool {
        let mut any = false;
        for _ in 0..IMPACT_SWEEPS {
            let mut struck = false;
            for (i, row) in self.rows.iter().enumerate() {
                let u = self.velocity(row, bodies);
                let un = u.dot(row.n);
                // approaching faster than the impact speed, and closing within the step at that speed
                if un >= -settings.impact_speed || row.gap + un * dt > 0.0 {
                    continue;
                }
                let k = row.k + SINGULAR_EPSILON * (row.k.x_axis.x + row.k.y_axis.y + row.k.z_axis.z) * DMat3::IDENTITY;
                let Some(impact) = collide(k, row.n, u, row.mu, row.e, settings.law) else { continue };
                let p = impact.impulse_world;
                apply(&mut self.robots, bodies, row, p);
                self.impulses[i] += p;
                self.impacts += 1;
                self.energy_lost += impact.energy_lost;
                struck = true;
            }
            if !struck {
                break;
            }
            any = true;
        }
        for r in &mut self.robots {
            if r.engaged {
                r.struck = r.p.iter().any(|&p| p != 0.0);
                // T(v₀) − T(v₀ + W P) = −(J v₀)·P − ½ Pᵀ G P
                r.impact_loss = if r.struck { -(dot(&r.u0, &r.p) + 0.5 * r.quadratic(&r.p)) } else { 0.0 };
            }
        }
        any
    }

    /// The kinetic energy the collisions of this step took from robot `robot` (J; 0 when none
    /// struck it).
    pub fn impact_loss(&self, robot: usize) -> f64 {
        self.robots.get(robot).filter(|r| r.engaged).map_or(0.0, |r| r.impact_loss)
    }

    /// Books the energy the resting contacts took from a robot they held this step: `energy_before`
    /// its mechanical energy at the start of the step (J), `energy_after` at the end. The robot's
    /// own collisions are taken out of it (they are in [`Self::energy_lost`]). The change also holds
    /// the work of the robot's actuators and joint damping over the step, and its integrator's error.
    pub fn book_resting(&mut self, robot: usize, energy_before: f64, energy_after: f64) {
        self.resting_energy_lost += energy_before - self.impact_loss(robot) - energy_after;
    }

    /// The velocity of side `b` relative to side `a` at the row's point (m/s, world frame).
    fn velocity(&self, row: &Row, bodies: &[SolverBody]) -> DVec3 {
        side_velocity(&self.robots, bodies, row.b, row.r_b) - side_velocity(&self.robots, bodies, row.a, row.r_a)
    }

    /// The free bodies the rows move (to add to the solver's active bodies).
    pub(super) fn bodies(&self) -> impl Iterator<Item = usize> + '_ {
        self.rows.iter().flat_map(|r| [r.a, r.b]).filter_map(|s| match s {
            RowSide::Body(i) => Some(i),
            _ => None,
        })
    }

    /// Substep: the robots' velocities gain `h a₀` (their rows' `u` gain `h J a₀`).
    pub(super) fn integrate_velocity(&mut self, h: f64) {
        for r in self.robots.iter_mut().filter(|r| r.engaged) {
            for (u, ja) in r.u.iter_mut().zip(&r.ja0) {
                *u += h * ja;
            }
            r.t_velocity += h;
        }
    }

    /// Substep: the robots' displacements grow by `h v` (their rows' `s` by `h u`, and `Q` by
    /// `h P`).
    pub(super) fn integrate_position(&mut self, h: f64) {
        for r in self.robots.iter_mut().filter(|r| r.engaged) {
            for (s, u) in r.s.iter_mut().zip(&r.u) {
                *s += h * u;
            }
            for (q, p) in r.q.iter_mut().zip(&r.p) {
                *q += h * p;
            }
            r.t_moves += h * r.t_velocity;
            r.t_moved += h;
        }
    }

    /// Substep: applies the rows' accumulated impulses (warm start); compiled for AVX2 where the
    /// CPU has it, as [`Self::solve`].
    pub(super) fn warm_start(&mut self, bodies: &mut [SolverBody]) {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2
            #[allow(unsafe_code)]
            return unsafe { self.warm_start_avx2(bodies) };
        }
        self.warm_start_in(bodies);
    }

    /// [`Self::warm_start`] compiled for AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn warm_start_avx2(&mut self, bodies: &mut [SolverBody]) {
        self.warm_start_in(bodies);
    }

    #[inline(always)]
    fn warm_start_in(&mut self, bodies: &mut [SolverBody]) {
        for row in &self.rows {
            if row.lambda != [0.0; 3] {
                let p = row.lambda[0] * row.n + row.lambda[1] * row.t1 + row.lambda[2] * row.t2;
                apply(&mut self.robots, bodies, row, p);
            }
        }
    }

    /// One Gauss–Seidel pass over the rows (as [`super::solver::Constraint::solve`]). On a CPU
    /// with AVX2 (detected at run time) the same code runs compiled for it: a robot's rows'
    /// velocities are updated four at a time instead of two, the same operations, the same bits.
    pub(super) fn solve(&mut self, bodies: &mut [SolverBody], sweep: &Sweep) {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2
            #[allow(unsafe_code)]
            return unsafe { self.solve_avx2(bodies, sweep) };
        }
        self.solve_in(bodies, sweep);
    }

    /// [`Self::solve`] compiled for AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn solve_avx2(&mut self, bodies: &mut [SolverBody], sweep: &Sweep) {
        self.solve_in(bodies, sweep);
    }

    #[inline(always)]
    fn solve_in(&mut self, bodies: &mut [SolverBody], sweep: &Sweep) {
        // the row by reference (a copy of it per solve was a memmove of 400 bytes)
        let (rows, robots) = (&mut self.rows, &mut self.robots);
        for i in 0..rows.len() {
            let row = &rows[i];
            let u = side_velocity(robots, bodies, row.b, row.r_b) - side_velocity(robots, bodies, row.a, row.r_a);
            let un = u.dot(row.n);
            if row.speculative && -un > sweep.impact_speed {
                if row.lambda != [0.0; 3] {
                    let p = row.lambda[0] * row.n + row.lambda[1] * row.t1 + row.lambda[2] * row.t2;
                    apply(robots, bodies, row, -p);
                    rows[i].lambda = [0.0; 3];
                }
                continue;
            }
            // the separation now: gap + n·(Δp_b − Δp_a)
            let s = row.adjusted_gap
                + row.n.dot(
                    side_displacement(robots, bodies, row.b, row.r_b)
                        - side_displacement(robots, bodies, row.a, row.r_a),
                );
            let (bias, mass_scale, impulse_scale) = sweep.normal_terms(s, row.softness);
            let lambda = row.lambda;
            let new = (lambda[0] - row.normal_mass * mass_scale * (un + bias) - impulse_scale * lambda[0]).max(0.0);
            let dn = new - lambda[0];
            // friction, with the normal impulse's effect on the velocity: u + Δλ_n K n
            let u = u + dn * (row.k * row.n);
            let (ux, uy) = (u.dot(row.t1), u.dot(row.t2));
            let m = row.tangent_mass;
            let (l1, l2) = (lambda[1] - (m[0] * ux + m[1] * uy), lambda[2] - (m[2] * ux + m[3] * uy));
            let (l1, l2) = super::solver::friction_on_disc(row.tangent_k, l1, l2, row.mu * new);
            let (d1, d2) = (l1 - lambda[1], l2 - lambda[2]);
            if dn != 0.0 || d1 != 0.0 || d2 != 0.0 {
                let p = dn * row.n + d1 * row.t1 + d2 * row.t2;
                apply(robots, bodies, row, p);
            }
            if [new, l1, l2] != [0.0; 3] {
                mark_touched(robots, bodies, row);
            }
            rows[i].lambda = [new, l1, l2];
        }
    }

    /// After the substeps: the potential energy stored in the rows' springs where the substeps left
    /// the bodies, `Σ ½ m_n ω² min(0, C)²` ([`Softness::stored_energy`]), with `C` the contact
    /// rows' separation beyond the slop, `s + slop` (the deflection their position bias acts on),
    /// and the limit rows' gap from their floor, `g − floor + s`.
    pub(super) fn store_elastic_energy(&mut self, bodies: &[SolverBody], slop: f64) {
        let mut energy = 0.0;
        for row in &self.rows {
            let s = row.adjusted_gap
                + row.n.dot(
                    side_displacement(&self.robots, bodies, row.b, row.r_b)
                        - side_displacement(&self.robots, bodies, row.a, row.r_a),
                );
            energy += row.softness.stored_energy(row.normal_mass, s + slop);
        }
        for row in &self.limit_rows {
            let s = row.gap + self.robots[row.robot].s[row.off];
            energy += row.softness.stored_energy(row.normal_mass, s);
        }
        self.elastic_energy = energy;
    }

    /// The potential energy (J) stored at the end of the last step in the springs of the soft rows
    /// of the robots' resting contacts and of their joint and tendon limits: each row's
    /// `½ m_n ω² C²` for a deflection `C < 0` (an overlap beyond the slop, an overshoot past a
    /// limit's floor; [`Softness::stored_energy`]), zero when no row acted. A robot resting on such
    /// rows has sunk into them under its load; when a deflection shrinks, the row gives that energy
    /// back, so that a passive robot's `T + V` alone may rise while `T + V` plus this does not.
    pub fn elastic_energy(&self) -> f64 {
        self.elastic_energy
    }

    /// One pass over the joint-limit rows (the normal part of [`Self::solve`], in joint space).
    pub(super) fn solve_limits(&mut self, sweep: &Sweep) {
        for row in self.limit_rows.iter_mut() {
            let solve = &mut self.robots[row.robot];
            // u = J v = s v_i, and s d_i (the row's J holds the sign)
            let u = solve.u[row.off];
            let s = row.gap + solve.s[row.off];
            let (bias, mass_scale, impulse_scale) = if s > 0.0 {
                (s * sweep.inv_h, 1.0, 0.0)
            } else if sweep.pass == Pass::Solve {
                let k = row.softness;
                ((k.bias_rate * s).max(-sweep.max_push), k.mass_scale, k.impulse_scale)
            } else {
                (0.0, 1.0, 0.0)
            };
            let new = (row.lambda - row.normal_mass * mass_scale * (u + bias) - impulse_scale * row.lambda).max(0.0);
            solve.accumulate(row.off, &mut row.lambda, new);
        }
        // the friction-loss rows: λ ← clamp(λ − u / G_ii, −F h, F h), u = v_i, target u⁺ = 0
        // (MuJoCo, *Computation*: friction loss; the box clamp of projected Gauss–Seidel, Erleben
        // 2007); `λ` is the impulse of one substep of `h`, a force `|τ| ≤ F` over it
        let h = 1.0 / sweep.inv_h;
        for row in self.friction_rows.iter_mut() {
            let solve = &mut self.robots[row.robot];
            let bound = row.friction_loss * h;
            let new = (row.lambda - row.normal_mass * solve.u[row.off]).max(-bound).min(bound);
            solve.accumulate(row.off, &mut row.lambda, new);
        }
    }

    /// Applies the limit and friction rows' accumulated impulses (warm start within the step).
    pub(super) fn warm_start_limits(&mut self) {
        for row in &self.limit_rows {
            if row.lambda != 0.0 {
                self.robots[row.robot].impulse(row.off, row.lambda);
            }
        }
        for row in &self.friction_rows {
            if row.lambda != 0.0 {
                self.robots[row.robot].impulse(row.off, row.lambda);
            }
        }
    }

    /// The limited coordinates whose limit pushed in this step's solve, per robot: `(robot, k)`.
    pub fn limits_pushed(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.limit_rows.iter().filter(|r| r.lambda != 0.0).map(|r| (r.robot, r.limited))
    }

    /// End of a substep: adds each row's accumulated impulses to its sum.
    pub(super) fn accumulate(&mut self) {
        for (sum, row) in self.lambda_sums.iter_mut().zip(&self.rows) {
            for (s, l) in sum.iter_mut().zip(row.lambda) {
                *s += l;
            }
        }
    }

    /// After the substeps: the impulses of the step, the rows kept for warm starting, and what each
    /// robot's own step takes (`Δv`, and `q₀ ⊕ d` when the resting rows held it).
    pub(super) fn finish(&mut self, robots: &dyn RobotViews, dt: f64) {
        for ((p, sum), row) in self.impulses.iter_mut().zip(&self.lambda_sums).zip(&self.rows) {
            *p += sum[0] * row.n + sum[1] * row.t1 + sum[2] * row.t2;
        }
        self.previous.clear();
        for (c, row) in self.contacts.iter().zip(&self.rows) {
            self.previous.push(Previous {
                a: c.a,
                b: c.b,
                features: c.features,
                point_world: c.point_world,
                lambda: row.lambda,
            });
        }
        // (std's stable sort allocates for more than 20 elements; the order within a pair does not
        // matter to the lookup, which looks at every point of the pair)
        if !self.previous.is_sorted_by_key(|p| (p.a, p.b)) {
            self.previous.sort_unstable_by_key(|p| (p.a, p.b));
        }
        for r in &mut self.robots {
            r.friction_warm.clear();
        }
        for row in &self.friction_rows {
            self.robots[row.robot].friction_warm.push(row.lambda);
        }
        for (k, r) in self.robots.iter_mut().enumerate() {
            if !r.engaged {
                continue;
            }
            let view = robots.view(k);
            r.velocity_changes(view.model);
            if r.touched {
                // where the substeps put it, q₀ ⊕ d, d = (Σ h) v₀ + (Σ h t) a₀ + M⁻¹ Jᵀ Q
                for i in 0..r.nv {
                    r.d[i] += r.t_moved * r.v0[i] + r.t_moves * r.a0[i];
                }
                if view.model.integrate(view.q, &r.d, 1.0, &mut r.q_end).is_err() {
                    r.touched = false;
                }
                // the contact's generalized force over the step, τ_c = Jᵀ P / dt, and the end
                // velocity v₀ + dt a₀ + M⁻¹ Jᵀ P
                r.contact_force(dt);
                for i in 0..r.nv {
                    r.v[i] = r.v0[i] + dt * r.a0[i] + r.dv[i];
                }
            }
            // not held but struck: the collisions' Δv alone, W P, in `dv`
        }
    }

    /// What robot `robot`'s own step takes from the contacts: the end state of the substeps when
    /// resting contact held it, else the collisions' velocity change. `None`: untouched.
    pub fn robot_change(&self, robot: usize) -> Option<ContactChange<'_>> {
        let r = self.robots.get(robot)?;
        if !r.engaged {
            return None;
        }
        if r.touched {
            Some(ContactChange::Held { q: &r.q_end, tau: &r.tau_c, v: &r.v })
        } else if r.struck {
            Some(ContactChange::Impulse(&r.dv))
        } else {
            None
        }
    }

    /// Forgets the step's rows (no contact this step).
    pub(super) fn clear(&mut self) {
        self.elastic_energy = 0.0;
        self.contacts.clear();
        self.impulses.clear();
        self.rows.clear();
        self.limit_rows.clear();
        self.friction_rows.clear();
        self.previous.clear();
        for r in &mut self.robots {
            r.engaged = false;
            r.friction_warm.clear();
        }
    }
}

impl RobotSolve {
    fn new(model: &MultibodyModel) -> Self {
        let nv = model.nv();
        Self {
            engaged: false,
            nv,
            ws: Workspace::new(model),
            tau: vec![0.0; nv],
            v0: vec![0.0; nv],
            v: vec![0.0; nv],
            a0: vec![0.0; nv],
            d: vec![0.0; nv],
            dv: vec![0.0; nv],
            q_end: vec![0.0; model.nq()],
            tau_c: vec![0.0; nv],
            jac: Vec::new(),
            y: Vec::new(),
            y_scaled: Vec::new(),
            blocks: Vec::new(),
            inv_d: Vec::new(),
            inv_sqrt_d: Vec::new(),
            chain_of: Vec::new(),
            chains: Vec::new(),
            g: Vec::new(),
            u: Vec::new(),
            s: Vec::new(),
            ja0: Vec::new(),
            u0: Vec::new(),
            p: Vec::new(),
            q: Vec::new(),
            t_velocity: 0.0,
            t_moves: 0.0,
            t_moved: 0.0,
            struck: false,
            touched: false,
            impact_loss: 0.0,
            friction_warm: Vec::new(),
        }
    }

    /// `M(q₀)` and its factor, `a₀ = M⁻¹ (τ(q₀, v₀) − C(q₀, v₀))`, and the solver's state at `v₀`.
    /// `false` if the dynamics cannot be evaluated (the robot then takes no contact this step).
    fn engage(&mut self, view: &RobotView) -> bool {
        let (model, q, v) = (view.model, view.q, view.v);
        if crba(model, &mut self.ws, q).is_err() || ltdl_factor(model, &mut self.ws).is_err() {
            return false;
        }
        // a₀ = M⁻¹ (τ − C(q, v)) with the factor at hand: the bias forces by RNEA and one solve
        // (cheaper than a second articulated-body pass)
        if view.control.joint_forces(model, &mut self.ws, q, v, &mut self.tau).is_err()
            || bias_forces_placed(model, &mut self.ws, v, &mut self.a0).is_err()
        {
            return false;
        }
        for (a, t) in self.a0.iter_mut().zip(&self.tau) {
            *a = t - *a;
        }
        if crate::multibody::ltdl_solve(model, &self.ws, &mut self.a0).is_err() {
            return false;
        }
        // (RNEA ran at the CRBA's placements of the same q, which it leaves as they were)
        self.v0.copy_from_slice(v);
        self.v.copy_from_slice(v);
        self.d.fill(0.0);
        self.dv.fill(0.0);
        self.impact_loss = 0.0;
        self.jac.clear();
        self.chain_of.clear();
        self.chains.clear();
        self.engaged = true;
        true
    }

    /// Rows in the contact space.
    fn rows(&self) -> usize {
        self.chain_of.len()
    }

    /// Adds `count` rows moved by the coordinates `chain` (deepest first, closed under the parent
    /// relation), their Jacobian rows zero; returns the first one's index.
    fn add_rows(&mut self, count: usize, chain: impl Iterator<Item = usize>) -> usize {
        let first = self.rows();
        let start = self.chains.len();
        self.chains.extend(chain);
        let len = self.chains.len() - start;
        for _ in 0..count {
            self.chain_of.push((start, len));
        }
        self.jac.resize(self.jac.len() + count * self.nv, 0.0);
        first
    }

    /// Removes the rows from `first` on (added last).
    fn truncate_rows(&mut self, first: usize) {
        if let Some(&(start, _)) = self.chain_of.get(first) {
            self.chains.truncate(start);
        }
        self.chain_of.truncate(first);
        self.jac.truncate(first * self.nv);
    }

    /// The chain of row `i`.
    fn chain(&self, i: usize) -> &[usize] {
        let (start, len) = self.chain_of[i];
        &self.chains[start..start + len]
    }

    /// Once every row is added: `Y`, `G`, and the rows' `J v₀`, `J a₀`; `u` at `v₀`, `s`, `P`, `Q`
    /// zero.
    fn contact_space(&mut self, model: &MultibodyModel) {
        let (n, nv) = (self.rows(), self.nv);
        self.y.clear();
        self.y.extend_from_slice(&self.jac);
        // (`delassus` writes every entry it reads of its scratch, and every entry of `G`)
        if self.y_scaled.len() < delassus_scratch_len(n, nv) {
            self.y_scaled.resize(delassus_scratch_len(n, nv), 0.0);
        }
        self.g.resize(n * n, 0.0);
        self.inv_d.clear();
        self.inv_sqrt_d.clear();
        for k in 0..nv {
            let d = self.ws.ltdl[(k, k)];
            self.inv_d.push(1.0 / d);
            self.inv_sqrt_d.push(1.0 / d.sqrt());
        }
        delassus(
            model,
            &self.ws,
            &self.inv_sqrt_d,
            &mut self.y,
            &mut self.y_scaled,
            &mut self.blocks,
            &self.chain_of,
            &self.chains,
            &mut self.g,
        );
        self.u0.clear();
        self.ja0.clear();
        for i in 0..n {
            let (chain, jac) = (self.chain(i), &self.jac[i * nv..(i + 1) * nv]);
            let (u0, ja0) = (chain_dot(chain, jac, &self.v0), chain_dot(chain, jac, &self.a0));
            self.u0.push(u0);
            self.ja0.push(ja0);
        }
        self.u.clear();
        self.u.extend_from_slice(&self.u0);
        for x in [&mut self.s, &mut self.p, &mut self.q] {
            x.clear();
            x.resize(n, 0.0);
        }
        self.t_velocity = 0.0;
        self.t_moves = 0.0;
        self.t_moved = 0.0;
    }

    /// A one-row solve's step: the row's accumulated impulse `lambda` becomes `new`, the
    /// difference is applied on row `k` ([`impulse`](Self::impulse)), and a non-zero impulse marks
    /// the robot as touched.
    #[inline]
    fn accumulate(&mut self, k: usize, lambda: &mut f64, new: f64) {
        let d = new - *lambda;
        *lambda = new;
        if d != 0.0 {
            self.impulse(k, d);
        }
        if new != 0.0 {
            self.touched = true;
        }
    }

    /// An impulse `x` on row `k`: `P_k += x`, `u += G_{·k} x`.
    #[inline]
    fn impulse(&mut self, k: usize, x: f64) {
        let n = self.rows();
        self.p[k] += x;
        for (u, g) in self.u.iter_mut().zip(&self.g[k * n..(k + 1) * n]) {
            *u += g * x;
        }
    }

    /// An impulse `x` on the three rows from `k`: `P_{k+i} += x_i`, `u += Σ_i G_{·k+i} x_i`, in
    /// one pass over `u` (the sums in the order of three [`impulse`](Self::impulse)s).
    #[inline(always)]
    fn impulse3(&mut self, k: usize, x: [f64; 3]) {
        let n = self.rows();
        for (p, xi) in self.p[k..k + 3].iter_mut().zip(x) {
            *p += xi;
        }
        let (g0, rest) = self.g[k * n..(k + 3) * n].split_at(n);
        let (g1, g2) = rest.split_at(n);
        for (((u, a), b), c) in self.u.iter_mut().zip(g0).zip(g1).zip(g2) {
            *u = ((*u + a * x[0]) + b * x[1]) + c * x[2];
        }
    }

    /// `Pᵀ G P` of the rows' vector `p`.
    fn quadratic(&self, p: &[f64]) -> f64 {
        let n = self.rows();
        (0..n).map(|i| p[i] * dot(&self.g[i * n..(i + 1) * n], p)).sum()
    }

    /// `M⁻¹ Jᵀ P` into `dv` and `M⁻¹ Jᵀ Q` into `d` (the applied impulses and their integral
    /// over the moves): `L⁻¹ D⁻¹ (Y x)`, both in one walk of the tree.
    fn velocity_changes(&mut self, model: &MultibodyModel) {
        let nv = self.nv;
        self.dv.fill(0.0);
        self.d.fill(0.0);
        for i in 0..self.rows() {
            let (pi, qi) = (self.p[i], self.q[i]);
            if pi != 0.0 || qi != 0.0 {
                let (start, len) = self.chain_of[i];
                let y = &self.y[i * nv..(i + 1) * nv];
                for &k in &self.chains[start..start + len] {
                    self.dv[k] += y[k] * pi;
                    self.d[k] += y[k] * qi;
                }
            }
        }
        crate::multibody::ltdl::ltdl_solve_lower_pair(model, &self.ws, &self.inv_d, &mut self.dv, &mut self.d);
    }

    /// `τ_c = Jᵀ P / dt`: the generalized force of the step's impulses over the step.
    fn contact_force(&mut self, dt: f64) {
        let nv = self.nv;
        self.tau_c.fill(0.0);
        for (i, &pi) in self.p.iter().enumerate() {
            if pi != 0.0 {
                let (start, len) = self.chain_of[i];
                let jac = &self.jac[i * nv..(i + 1) * nv];
                for &k in &self.chains[start..start + len] {
                    self.tau_c[k] += jac[k] * pi / dt;
                }
            }
        }
    }
}

/// The coordinates on the path to the root of any of a fixed tendon's terms, in decreasing index
/// (deepest first: a coordinate's parent has a smaller index), each once: a union of paths, closed
/// under the parent relation.
fn tendon_chain<'a>(
    model: &'a MultibodyModel,
    terms: &'a [crate::multibody::tendon::TendonTerm],
) -> impl Iterator<Item = usize> + 'a {
    (0..model.nv()).rev().filter(move |&k| terms.iter().any(|t| dof_chain(model, t.v_index).any(|d| d == k)))
}

/// Velocity coordinate `k` and those above it, deepest first.
fn dof_chain(model: &MultibodyModel, k: usize) -> impl Iterator<Item = usize> + '_ {
    let mut next = k;
    std::iter::from_fn(move || {
        if next == crate::multibody::model::NONE {
            return None;
        }
        let here = next;
        next = model.dof_parent(next);
        Some(here)
    })
}

impl Row {
    /// Sets `K` and the masses derived from it.
    fn set_k(&mut self, k: DMat3) {
        let (n, t1, t2) = (self.n, self.t1, self.t2);
        let knn = n.dot(k * n);
        let (k11, k12, k22) = (t1.dot(k * t1), t1.dot(k * t2), t2.dot(k * t2));
        let det = k11 * k22 - k12 * k12;
        // a direction in which the point cannot move has K = 0 up to the round-off of J (a link
        // fixed along the normal, a wheel's contact point on its axle's plane): 1/K would turn that
        // round-off into an unbounded impulse, so it counts as zero below ε tr(K)
        let round_off = SINGULAR_EPSILON * (k.x_axis.x + k.y_axis.y + k.z_axis.z);
        self.tangent_mass =
            if det > round_off * (k11 + k22) { [k22 / det, -k12 / det, -k12 / det, k11 / det] } else { [0.0; 4] };
        self.tangent_k = [k11, k12, k22];
        self.normal_mass = if knn > round_off { 1.0 / knn } else { 0.0 };
        self.k = k;
    }
}

#[inline]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// The world velocity of a row side at the point (`r` the offset from a free body's centre of mass).
#[inline]
fn side_velocity(robots: &[RobotSolve], bodies: &[SolverBody], side: RowSide, r: DVec3) -> DVec3 {
    match side {
        RowSide::Fixed => DVec3::ZERO,
        RowSide::Body(i) => bodies[i].v + bodies[i].w.cross(r),
        RowSide::Robot { robot, off } => DVec3::from_slice(&robots[robot].u[off..off + 3]),
    }
}

/// The displacement of a row side's point since the start of the step (m, world frame; a free
/// body's as `Δx + ΔR r`, to be taken relative to `r`, as the free bodies' constraints do).
#[inline]
fn side_displacement(robots: &[RobotSolve], bodies: &[SolverBody], side: RowSide, r: DVec3) -> DVec3 {
    match side {
        RowSide::Fixed => DVec3::ZERO,
        RowSide::Body(i) => bodies[i].dx + bodies[i].drot * r,
        RowSide::Robot { robot, off } => DVec3::from_slice(&robots[robot].s[off..off + 3]),
    }
}

/// Applies the impulse `p` (N·s, world frame) on side `b` and `−p` on side `a`.
#[inline(always)]
fn apply(robots: &mut [RobotSolve], bodies: &mut [SolverBody], row: &Row, p: DVec3) {
    for (side, sign, ang) in [(row.a, -1.0, &row.ang_a), (row.b, 1.0, &row.ang_b)] {
        match side {
            RowSide::Fixed => {}
            RowSide::Body(i) => {
                let sb = &mut bodies[i];
                sb.v += sign * sb.inv_mass * p;
                // Δω = I⁻¹ (r × p), from the responses to n, t1, t2 computed once per step
                let (pn, p1, p2) = (p.dot(row.n), p.dot(row.t1), p.dot(row.t2));
                sb.w += sign * (pn * ang[0] + p1 * ang[1] + p2 * ang[2]);
            }
            RowSide::Robot { robot, off } => {
                // σ p on the point's three rows: u += Σ_k G_{·k} σ p_k
                robots[robot].impulse3(off, (sign * p).to_array());
            }
        }
    }
}

/// Marks the sides of a row that holds an impulse as reached by it.
fn mark_touched(robots: &mut [RobotSolve], bodies: &mut [SolverBody], row: &Row) {
    for side in [row.a, row.b] {
        match side {
            RowSide::Fixed => {}
            RowSide::Body(i) => bodies[i].touched = true,
            RowSide::Robot { robot, .. } => robots[robot].touched = true,
        }
    }
}

/// The impulses a link contact inherits from the previous step (as for the free bodies' contacts).
fn previous_impulse(previous: &[Previous], c: &LinkContact) -> Option<[f64; 3]> {
    let start = previous.partition_point(|p| (p.a, p.b) < (c.a, c.b));
    let mut best: Option<(f64, [f64; 3])> = None;
    for p in previous[start..].iter().take_while(|p| (p.a, p.b) == (c.a, c.b)) {
        if p.features == c.features {
            return Some(p.lambda);
        }
        let d = (p.point_world - c.point_world).length_squared();
        if d <= super::WARM_MATCH_DISTANCE * super::WARM_MATCH_DISTANCE && best.is_none_or(|b| d < b.0) {
            best = Some((d, p.lambda));
        }
    }
    best.map(|b| b.1)
}
