//! Test impulses through the articulated-body algorithm: the joint velocity change `Δv` of an
//! impulse at a point of a link, and the link's collision matrix `K` there, from the articulated
//! inertias that [`aba`](super::aba::aba) has cached.
//!
//! References: B. Mirtich, PhD thesis (1996), ch. 4 (the collision matrix of a point on an
//! articulated body, column by column from test impulses); R. Featherstone, *Rigid Body Dynamics
//! Algorithms* (2008), §7.3, Table 7.1 (ABA), here in its impulse form: no velocity products, no
//! gravity, no joint forces, one external impulse. Moby's `FSABAlgorithm::apply_impulse` and
//! Bullet's `btMultiBody::calcAccelerationDeltasMultiDof` are the same sweep.
//!
//! An impulse `p` (world frame, N·s) at the point `c` (world frame, m) of body `k` is the spatial
//! impulse `f⁰ = [c × p; p]` about the world origin, `f_k = k_X_0* f⁰ = [c_k × p_k; p_k]` in body
//! `k`'s frame. It enters ABA as a bias impulse `p^A_k = −f_k`; every other bias is zero. With
//! `I^A_i`, `U_i = I^A_i S_i` and `D_i⁻¹ = (S_iᵀ U_i)⁻¹` from ABA at the same `q` (they depend on
//! `q` only):
//!
//! ```text
//! up, from k to the root (zero off that path):
//!     u_i   = −S_iᵀ p^A_i
//!     p^a_i = p^A_i + U_i D_i⁻¹ u_i
//!     p^A_λ = λ_X_i* p^a_i
//! down, parents first, Δa_world = 0 (u_i = 0 off the path):
//!     Δa'_i = i_X_λ Δa_λ
//!     Δv_i  = D_i⁻¹ (u_i − U_iᵀ Δa'_i)
//!     Δa_i  = Δa'_i + S_i Δv_i
//! ```
//!
//! `Δv` solves `M Δv = J_cᵀ p` and `Δa_i` is body `i`'s spatial velocity change (body frame). A
//! floating base needs no special case: its joint is a 6-coordinate joint whose `S` is invertible,
//! so `S_0 Δv_0 = −(I^A_0)⁻¹ p^A_0`, the thesis's `Δa_0`.
//!
//! The point's velocity change is `Δu_c = R_k (Δa_k.lin + Δa_k.ang × c_k)` (world frame), with `R_k`
//! the body's rotation to the world; for the three unit impulses `p = e_r` it is column `r` of
//! `K = J_c M⁻¹ J_cᵀ` (1/kg). Only the path from `k` to the root is needed for `K`, since `Δa_k`
//! depends only on the ancestors of `k`.
//!
//! Cost: `O(d)` for the up sweep and for `K` (`d` the depth of `k`), `O(n)` for the whole `Δv`; the
//! pose of `k` is composed from ABA's `i_X_λ`, so neither forward kinematics nor CRBA is needed.
//! Nothing allocates after [`ImpulseScratch::new`].

use super::model::MultibodyModel;
use super::spatial::{Force, Motion, Xform};
use super::workspace::{check_len, LengthError, Workspace};
use crate::math::{DMat3, DVec3};

/// The scratch of the sweeps, allocated once per model.
#[derive(Debug, Clone)]
pub struct ImpulseScratch {
    /// `Δa_i`: the spatial velocity change of each body (body frame; rad/s, m/s per N·s).
    delta_a: Vec<Motion>,
    /// The bodies from the struck body to the root, leaf first.
    path: Vec<usize>,
    /// `u` on the path, then `Δv` on the path (one entry per velocity coordinate), for `K`.
    dv_path: Vec<f64>,
}

impl ImpulseScratch {
    /// Scratch sized for `model`.
    pub fn new(model: &MultibodyModel) -> Self {
        Self {
            delta_a: vec![Motion::ZERO; model.nbodies()],
            path: Vec::with_capacity(model.nbodies()),
            dv_path: vec![0.0; model.nv()],
        }
    }
}

/// Writes into `dv` (nv) the joint velocity change `Δv = M⁻¹ J_cᵀ p` of the impulse `impulse_world`
/// (N·s, world frame) applied at `point_world` (m, world frame), a point fixed on body `body`.
///
/// Needs [`aba`](super::aba::aba) to have run at the current `q` (any `v` and `τ`): it reads the
/// articulated inertias `ws.ia`, `ws.u_cols`, `ws.d_inv` and the transforms `ws.x_up`. Units of `dv`:
/// those of `v` (rad/s, m/s; the floating base's `[v; ω]` in its own frame). Cost `O(n)`.
pub fn impulse_velocity_change(
    model: &MultibodyModel,
    ws: &Workspace,
    scratch: &mut ImpulseScratch,
    body: usize,
    point_world: DVec3,
    impulse_world: DVec3,
    dv: &mut [f64],
) -> Result<(), LengthError> {
    check_sizes(model, scratch, body)?;
    check_len("dv", dv.len(), model.nv())?;
    dv.fill(0.0);
    let body_x_world = path_and_pose(model, ws, &mut scratch.path, body);
    sweep_up(model, ws, &scratch.path, spatial_impulse_body(&body_x_world, point_world, impulse_world), dv);
    for i in 0..model.nbodies() {
        let a_parent = model.bodies[i].parent.map_or(Motion::ZERO, |p| scratch.delta_a[p]);
        scratch.delta_a[i] = sweep_down(model, ws, i, a_parent, dv);
    }
    Ok(())
}

/// The collision matrix `K = J_c M⁻¹ J_cᵀ` (3 × 3, 1/kg, world frame) of the point `point_world`
/// (m, world frame) fixed on body `body`, column by column: column `r` is the point's velocity
/// change under a unit impulse along world axis `r` (the sweep of [`impulse_velocity_change`],
/// down the path only). Needs [`aba`](super::aba::aba) at the current `q`. Cost `O(d)`.
pub fn collision_matrix_aba(
    model: &MultibodyModel,
    ws: &Workspace,
    scratch: &mut ImpulseScratch,
    body: usize,
    point_world: DVec3,
) -> Result<DMat3, LengthError> {
    check_sizes(model, scratch, body)?;
    let body_x_world = path_and_pose(model, ws, &mut scratch.path, body);
    // c_k = k_X_0 c: the point in the body's frame
    let point_body = body_x_world.apply_point(point_world);
    let world_from_body = body_x_world.rotation_a_from_b();
    let mut columns = [DVec3::ZERO; 3];
    for (r, column) in columns.iter_mut().enumerate() {
        let f_body = spatial_impulse_body(&body_x_world, point_world, DVec3::AXES[r]);
        sweep_up(model, ws, &scratch.path, f_body, &mut scratch.dv_path);
        let mut delta_a = Motion::ZERO;
        for &i in scratch.path.iter().rev() {
            delta_a = sweep_down(model, ws, i, delta_a, &mut scratch.dv_path);
        }
        // K e_r = Δu_c = R_k (Δa_k.lin + Δa_k.ang × c_k)
        *column = world_from_body * (delta_a.lin + delta_a.ang.cross(point_body));
    }
    let k = DMat3::from_cols(columns[0], columns[1], columns[2]);
    // K is symmetric; average the round-off of the two triangles
    Ok(0.5 * (k + k.transpose()))
}

fn check_sizes(model: &MultibodyModel, scratch: &ImpulseScratch, body: usize) -> Result<(), LengthError> {
    if body >= model.nbodies() {
        return Err(LengthError {
            what: "bodies (the body index is past the end)",
            expected: body + 1,
            got: model.nbodies(),
        });
    }
    check_len("impulse scratch (bodies)", scratch.delta_a.len(), model.nbodies())?;
    check_len("impulse scratch (velocity coordinates)", scratch.dv_path.len(), model.nv())
}

/// Fills `path` with the bodies from `body` to the root (leaf first) and returns `k_X_0`, composed
/// from ABA's `i_X_λ` along the way.
fn path_and_pose(model: &MultibodyModel, ws: &Workspace, path: &mut Vec<usize>, body: usize) -> Xform {
    path.clear();
    let mut body_x_world = Xform::IDENTITY;
    let mut i = Some(body);
    while let Some(b) = i {
        path.push(b);
        // k_X_λ(b) = k_X_b · b_X_λ(b)
        body_x_world = body_x_world.compose(&ws.x_up[b]);
        i = model.bodies[b].parent;
    }
    body_x_world
}

/// `f_k = k_X_0* [c × p; p]`: the impulse `p` at the point `c` (both world frame) as a spatial
/// impulse in body `k`'s frame, given `k_X_0`.
fn spatial_impulse_body(body_x_world: &Xform, point_world: DVec3, impulse_world: DVec3) -> Force {
    body_x_world.apply_force(Force::new(point_world.cross(impulse_world), impulse_world))
}

/// The up sweep: writes `u_i = −S_iᵀ p^A_i` into `u` for the coordinates of the bodies of `path`
/// (leaf first), starting from `p^A_k = −f_k`.
fn sweep_up(model: &MultibodyModel, ws: &Workspace, path: &[usize], f_body: Force, u: &mut [f64]) {
    // p^A_k = −f_k
    let mut p_a = -f_body;
    for &i in path {
        let vi = model.bodies[i].joint.v_index;
        let s = model.subspace(i);
        let nj = s.len();
        for (k, s_k) in s.iter().enumerate() {
            // u_i = −S_iᵀ p^A_i
            u[vi + k] = -s_k.dot(p_a);
        }
        let off = model.block_offset(i);
        let d_inv = &ws.d_inv[off..off + nj * nj];
        // p^a_i = p^A_i + U_i D_i⁻¹ u_i
        let mut p_arti = p_a;
        for k in 0..nj {
            let d_inv_u: f64 = (0..nj).map(|l| d_inv[k * nj + l] * u[vi + l]).sum();
            p_arti += d_inv_u * ws.u_cols[vi + k];
        }
        // p^A_λ = λ_X_i* p^a_i
        p_a = ws.x_up[i].inv_apply_force(p_arti);
    }
}

/// One step of the down sweep at body `i`: reads `u_i` from `dv` (zero off the path), writes
/// `Δv_i` over it and returns `Δa_i`, given `Δa_λ` (zero for a body hanging from the world).
#[inline]
fn sweep_down(model: &MultibodyModel, ws: &Workspace, i: usize, delta_a_parent: Motion, dv: &mut [f64]) -> Motion {
    let body = &model.bodies[i];
    let vi = body.joint.v_index;
    let s = model.subspace(i);
    let nj = s.len();
    // Δa' = i_X_λ Δa_λ  (Δa_world = 0)
    let delta_a_prime = match body.parent {
        Some(_) => ws.x_up[i].apply_motion(delta_a_parent),
        None => Motion::ZERO,
    };
    // rhs = u_i − U_iᵀ Δa'
    let mut rhs = [0.0; 6];
    for (k, r) in rhs.iter_mut().enumerate().take(nj) {
        *r = dv[vi + k] - delta_a_prime.dot(ws.u_cols[vi + k]);
    }
    let off = model.block_offset(i);
    let d_inv = &ws.d_inv[off..off + nj * nj];
    let mut delta_a = delta_a_prime;
    for (k, s_k) in s.iter().enumerate() {
        // Δv_i = D_i⁻¹ rhs
        let dv_k: f64 = (0..nj).map(|l| d_inv[k * nj + l] * rhs[l]).sum();
        dv[vi + k] = dv_k;
        // Δa_i = Δa' + S_i Δv_i
        delta_a += dv_k * *s_k;
    }
    delta_a
}
