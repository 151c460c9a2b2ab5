//! A contact point on a link: its Jacobian `J_c`, the tree's response `W = M⁻¹ J_cᵀ` to an impulse
//! there, and the point's collision matrix `K = J_c M⁻¹ J_cᵀ`.
//!
//! References: B. Mirtich, PhD thesis (1996), ch. 4 (impulses on articulated bodies: the collision
//! matrix of a point of a link is constant during the impact); R. Featherstone, *Rigid Body
//! Dynamics Algorithms* (2008), §4.5 (Jacobians from the motion subspaces) and §6.5 (the sparse
//! `LᵀDL` factor, which gives `M⁻¹ J_cᵀ` by two sparse triangular solves).
//!
//! A point `c` fixed on body `k` moves with the world velocity `u_c = J_c v` (m/s), `J_c` 3 × nv.
//! Column `j` of `J_c`, for a velocity coordinate on the path from `k` to the root, is the world
//! velocity of `c` under a unit rate of that coordinate: with `S⁰_j = [ω_j; v_j] = 0_X_i S_j` the
//! motion subspace column in world coordinates (Plücker, at the world origin),
//!
//! ```text
//! J_c[:, j] = v_j + ω_j × c
//! ```
//!
//! and zero for the other coordinates. An impulse `p` (world frame, N·s) at `c` changes the joint
//! velocities by `Δv = M⁻¹ J_cᵀ p = W p`, so the point's velocity by `Δu_c = J_c W p = K p`.
//!
//! Storage: `J_c` as three rows of `nv` (`jac[r * nv + j]`, rows x, y, z) and `W` as three columns of
//! `nv` (`w[r * nv + j]`, the response to a unit impulse along world axis `r`). Nothing allocates.

use super::ltdl::ltdl_solve;
use super::model::{MultibodyModel, NONE};
use super::workspace::{check_len, LengthError, Workspace};
use crate::math::{DMat3, DVec3};

/// The velocity coordinates on the path from body `body` to the root, leaf first.
pub fn path_dofs(model: &MultibodyModel, body: usize) -> impl Iterator<Item = usize> + '_ {
    let j = &model.bodies[body].joint;
    let mut k = if j.kind.nv() == 0 { NONE } else { j.v_index + j.kind.nv() - 1 };
    std::iter::from_fn(move || {
        if k == NONE {
            return None;
        }
        let here = k;
        k = model.dof_parent(k);
        Some(here)
    })
}

/// Fills `jac` (3 × nv, rows x, y, z) with the Jacobian of the world velocity of the point
/// `point_world` (m) fixed on body `body`. Needs the motion subspaces in world coordinates of the
/// current configuration, `ws.s_world`, which [`crba`](super::crba::crba) computes.
pub fn point_jacobian(
    model: &MultibodyModel,
    ws: &Workspace,
    body: usize,
    point_world: DVec3,
    jac: &mut [f64],
) -> Result<(), LengthError> {
    let nv = model.nv();
    check_len("point jacobian (3 nv)", jac.len(), 3 * nv)?;
    check_len("motion subspaces in world coordinates (call crba first)", ws.s_world.len(), nv)?;
    jac.fill(0.0);
    for j in path_dofs(model, body) {
        // J_c[:, j] = v_j + ω_j × c
        let s = ws.s_world[j];
        let column = s.lin + s.ang.cross(point_world);
        jac[j] = column.x;
        jac[nv + j] = column.y;
        jac[2 * nv + j] = column.z;
    }
    Ok(())
}

/// Fills `w` (three columns of nv) with `W = M⁻¹ J_cᵀ`, the joint velocity change per unit impulse
/// along each world axis, from the `LᵀDL` factors in `ws.ltdl` ([`ltdl_factor`](super::ltdl::ltdl_factor)).
pub fn impulse_response(model: &MultibodyModel, ws: &Workspace, jac: &[f64], w: &mut [f64]) -> Result<(), LengthError> {
    let nv = model.nv();
    check_len("point jacobian (3 nv)", jac.len(), 3 * nv)?;
    check_len("impulse response (3 nv)", w.len(), 3 * nv)?;
    w.copy_from_slice(jac);
    for r in 0..3 {
        // M w_r = J_rᵀ
        ltdl_solve(model, ws, &mut w[r * nv..(r + 1) * nv])?;
    }
    Ok(())
}

/// `K = J_c W` (3 × 3, symmetric positive semi-definite, 1/kg), world frame.
pub fn collision_matrix(jac: &[f64], w: &[f64], nv: usize) -> DMat3 {
    let mut k = [[0.0; 3]; 3];
    for (r, row) in k.iter_mut().enumerate() {
        for (s, entry) in row.iter_mut().enumerate() {
            *entry = dot(&jac[r * nv..(r + 1) * nv], &w[s * nv..(s + 1) * nv]);
        }
    }
    // symmetrise the round-off: K_rs = J_r M⁻¹ J_sᵀ = K_sr
    for (r, s) in [(0, 1), (0, 2), (1, 2)] {
        let mean = 0.5 * (k[r][s] + k[s][r]);
        k[r][s] = mean;
        k[s][r] = mean;
    }
    DMat3::from_cols_array_2d(&k).transpose()
}

/// The world velocity of the point: `J_c v` (m/s).
pub fn point_velocity(jac: &[f64], v: &[f64]) -> DVec3 {
    let nv = v.len();
    DVec3::new(dot(&jac[..nv], v), dot(&jac[nv..2 * nv], v), dot(&jac[2 * nv..3 * nv], v))
}

/// `v += W p`: the joint velocity change of the impulse `p` (world frame, N·s).
pub fn apply_impulse(w: &[f64], p: DVec3, v: &mut [f64]) {
    let nv = v.len();
    for (r, pr) in p.to_array().into_iter().enumerate() {
        if pr != 0.0 {
            for (vj, wj) in v.iter_mut().zip(&w[r * nv..(r + 1) * nv]) {
                *vj += pr * wj;
            }
        }
    }
}

#[inline]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// The Delassus matrix of a set of contact-space rows of one tree, `G = J M⁻¹ Jᵀ`, from the
/// `LᵀDL` factor of `M` without forming `M⁻¹ Jᵀ`: with `Y = L⁻ᵀ Jᵀ`, `G = Yᵀ D⁻¹ Y`
/// (Featherstone 2008, §6.5 and §8.4; the rows' `Y` are non-zero only on the coordinates that move
/// them, so `Y` costs `O(d²)` per row for a path of `d` coordinates).
///
/// `y`: `n` rows of length nv, holding `J` on entry and `Y` on return; row `i` is zero outside
/// `chains[chain_of[i].0..][..chain_of[i].1]` (velocity coordinates, deepest first, closed under
/// [`MultibodyModel::dof_parent`]). `scaled`: scratch of the same length, `D^{-1/2} Y` on return
/// (then `G_ij` is a plain dot product of two of its rows, which the compiler vectorises), with
/// `inv_sqrt_d` the `D_k^{-1/2}` of the factor (nv). `g`:
/// `n × n`, row-major, symmetric on return. Needs the factors of [`super::ltdl_factor`] in `ws`;
/// lengths checked by the caller.
///
/// On a CPU with AVX2 (detected at run time) the same code runs compiled for it: the dot products'
/// four partial sums in one register instead of two, the same operations in the same order, so the
/// same bits.
#[allow(clippy::too_many_arguments)]
pub(crate) fn delassus(
    model: &MultibodyModel,
    ws: &Workspace,
    inv_sqrt_d: &[f64],
    y: &mut [f64],
    scaled: &mut [f64],
    chain_of: &[(usize, usize)],
    chains: &[usize],
    g: &mut [f64],
) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2
        #[allow(unsafe_code)]
        return unsafe { delassus_avx2(model, ws, inv_sqrt_d, y, scaled, chain_of, chains, g) };
    }
    delassus_in(model, ws, inv_sqrt_d, y, scaled, chain_of, chains, g);
}

/// [`delassus`] compiled for AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[allow(clippy::too_many_arguments)]
fn delassus_avx2(
    model: &MultibodyModel,
    ws: &Workspace,
    inv_sqrt_d: &[f64],
    y: &mut [f64],
    scaled: &mut [f64],
    chain_of: &[(usize, usize)],
    chains: &[usize],
    g: &mut [f64],
) {
    delassus_in(model, ws, inv_sqrt_d, y, scaled, chain_of, chains, g);
}

#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn delassus_in(
    model: &MultibodyModel,
    ws: &Workspace,
    inv_sqrt_d: &[f64],
    y: &mut [f64],
    scaled: &mut [f64],
    chain_of: &[(usize, usize)],
    chains: &[usize],
    g: &mut [f64],
) {
    let nv = model.nv();
    let n = chain_of.len();
    for i in 0..n {
        let chain = &chains[chain_of[i].0..chain_of[i].0 + chain_of[i].1];
        let row = &mut y[i * nv..(i + 1) * nv];
        super::ltdl::ltdl_solve_upper_chain(model, ws, chain, row);
        let out = &mut scaled[i * nv..(i + 1) * nv];
        out.fill(0.0);
        for &k in chain {
            out[k] = row[k] * inv_sqrt_d[k];
        }
    }
    for i in 0..n {
        let yi = &scaled[i * nv..(i + 1) * nv];
        for j in i..n {
            // G_ij = Σ_k Y_ki Y_kj / D_k
            let g_ij = dot4(yi, &scaled[j * nv..(j + 1) * nv]);
            g[i * n + j] = g_ij;
            g[j * n + i] = g_ij;
        }
    }
}

/// `a · b` in four interleaved partial sums (independent chains of additions, which the compiler
/// keeps in one vector register).
#[inline(always)]
fn dot4(a: &[f64], b: &[f64]) -> f64 {
    let mut acc = [0.0; 4];
    let (ca, cb) = (a.chunks_exact(4), b.chunks_exact(4));
    let tail: f64 = ca.remainder().iter().zip(cb.remainder()).map(|(x, y)| x * y).sum();
    for (x, y) in ca.zip(cb) {
        for l in 0..4 {
            acc[l] += x[l] * y[l];
        }
    }
    (acc[0] + acc[2]) + (acc[1] + acc[3]) + tail
}

/// `J_row · x` over the row's chain (the only coordinates where `J_row` is not zero).
#[inline]
pub(crate) fn chain_dot(chain: &[usize], jac_row: &[f64], x: &[f64]) -> f64 {
    chain.iter().map(|&k| jac_row[k] * x[k]).sum()
}
