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

/// Rows of the contact space handled together by [`delassus`]: up to four consecutive rows with
/// the same chain (a point's three rows), one lane each.
pub(crate) const BLOCK_LANES: usize = 4;

/// The length of [`delassus`]'s scratch for `rows` rows of a tree of `nv` velocity coordinates
/// (enough for blocks of one row each).
pub(crate) fn delassus_scratch_len(rows: usize, nv: usize) -> usize {
    rows * nv * BLOCK_LANES
}

/// The Delassus matrix of a set of contact-space rows of one tree, `G = J M⁻¹ Jᵀ`, from the
/// `LᵀDL` factor of `M` without forming `M⁻¹ Jᵀ`: with `Y = L⁻ᵀ Jᵀ`, `G = Yᵀ D⁻¹ Y`
/// (Featherstone 2008, §6.5 and §8.4; the rows' `Y` are non-zero only on the coordinates that move
/// them, so `Y` costs `O(d²)` per row for a path of `d` coordinates).
///
/// Branch-induced sparsity (Featherstone 2008, §6.5): row `i` is non-zero only on its chain `c_i`,
/// the path from its deepest coordinate to the root, so `G_ij = Σ_{k ∈ c_i ∩ c_j} Y_ki Y_kj / D_k`
/// sums over the chains' common part only — the path from their deepest common coordinate to the
/// root, a common tail of the two lists (deepest first). For two feet of a quadruped that is the
/// floating base's six coordinates, not the tree's eighteen. Consecutive rows with the same chain
/// (a point's three rows) go together as one block of up to [`BLOCK_LANES`] lanes: one walk of the
/// tree for the block's `Y`, and `G`'s block of two blocks as sums of lane-wise products, with no
/// horizontal sum.
///
/// A chain may also be a union of paths (a fixed tendon's row over joints on several branches:
/// the coordinates above any of its joints, in decreasing index, which is deepest first since a
/// coordinate's parent has a smaller index); `c_i ∩ c_j` is then not a common tail, and a pair
/// with such a chain sums over the coordinates of `c_i` that are in `c_j`.
///
/// `y`: `n` rows of length nv, holding `J` on entry and `Y` on return; row `i` is zero outside
/// `chains[chain_of[i].0..][..chain_of[i].1]` (velocity coordinates, deepest first, closed under
/// [`MultibodyModel::dof_parent`]). `scratch`: at least [`delassus_scratch_len`]. `inv_sqrt_d`: the
/// `D_k^{-1/2}` of the factor (nv). `blocks`: cleared, then each block's first row, row count, and
/// whether its chain is a path (each coordinate's parent the next).
/// `g`: `n × n`, row-major, symmetric on return. Needs the factors of [`super::ltdl_factor`] in
/// `ws`; lengths checked by the caller.
///
/// On a CPU with AVX2 (detected at run time) the same code runs compiled for it: the four lanes in
/// one register instead of two, the same operations in the same order, so the same bits.
#[allow(clippy::too_many_arguments)]
pub(crate) fn delassus(
    model: &MultibodyModel,
    ws: &Workspace,
    inv_sqrt_d: &[f64],
    y: &mut [f64],
    scratch: &mut [f64],
    blocks: &mut Vec<(usize, usize, bool)>,
    chain_of: &[(usize, usize)],
    chains: &[usize],
    g: &mut [f64],
) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2
        #[allow(unsafe_code)]
        return unsafe { delassus_avx2(model, ws, inv_sqrt_d, y, scratch, blocks, chain_of, chains, g) };
    }
    delassus_in(model, ws, inv_sqrt_d, y, scratch, blocks, chain_of, chains, g);
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
    scratch: &mut [f64],
    blocks: &mut Vec<(usize, usize, bool)>,
    chain_of: &[(usize, usize)],
    chains: &[usize],
    g: &mut [f64],
) {
    delassus_in(model, ws, inv_sqrt_d, y, scratch, blocks, chain_of, chains, g);
}

#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn delassus_in(
    model: &MultibodyModel,
    ws: &Workspace,
    inv_sqrt_d: &[f64],
    y: &mut [f64],
    scratch: &mut [f64],
    blocks: &mut Vec<(usize, usize, bool)>,
    chain_of: &[(usize, usize)],
    chains: &[usize],
    g: &mut [f64],
) {
    const L: usize = BLOCK_LANES;
    let nv = model.nv();
    let n = chain_of.len();
    let h = &ws.ltdl;
    blocks.clear();
    let mut first = 0;
    while first < n {
        let mut count = 1;
        while count < L && first + count < n && chain_of[first + count] == chain_of[first] {
            count += 1;
        }
        let chain = &chains[chain_of[first].0..chain_of[first].0 + chain_of[first].1];
        let path = chain.windows(2).all(|w| model.dof_parent(w[0]) == w[1])
            && chain.last().is_none_or(|&k| model.dof_parent(k) == NONE);
        blocks.push((first, count, path));
        first += count;
    }
    let chain = |row: usize| &chains[chain_of[row].0..chain_of[row].0 + chain_of[row].1];
    // each block's D^{-1/2} Y, lanes side by side: scratch[b nv L + k L + lane]; Y back into `y`
    for (b, &(first, count, _)) in blocks.iter().enumerate() {
        let block = &mut scratch[b * nv * L..(b + 1) * nv * L];
        let chain = chain(first);
        for &k in chain {
            for lane in 0..L {
                block[k * L + lane] = if lane < count { y[(first + lane) * nv + k] } else { 0.0 };
            }
        }
        // Y = L⁻ᵀ Jᵀ on the chain (zero outside it: the chain holds every ancestor of its
        // coordinates), the lanes at once
        for &k in chain {
            let mut y_k = [0.0; L];
            y_k.copy_from_slice(&block[k * L..(k + 1) * L]);
            if y_k == [0.0; L] {
                continue;
            }
            let mut i = model.dof_parent(k);
            while i != NONE {
                let l_ki = h[(k, i)];
                for lane in 0..L {
                    block[i * L + lane] -= l_ki * y_k[lane];
                }
                i = model.dof_parent(i);
            }
        }
        for &k in chain {
            for lane in 0..count {
                y[(first + lane) * nv + k] = block[k * L + lane];
            }
            for lane in 0..L {
                block[k * L + lane] *= inv_sqrt_d[k];
            }
        }
    }
    for (bi, &(first_i, count_i, path_i)) in blocks.iter().enumerate() {
        let chain_i = chain(first_i);
        let block_i = &scratch[bi * nv * L..(bi + 1) * nv * L];
        for (bj, &(first_j, count_j, path_j)) in blocks.iter().enumerate().skip(bi) {
            let chain_j = chain(first_j);
            let block_j = &scratch[bj * nv * L..(bj + 1) * nv * L];
            // sums[c][r] = G_{first_i + r, first_j + c} = Σ_k (D^{-1/2} Y)_{k, i+r} (D^{-1/2} Y)_{k, j+c}
            let mut sums = [[0.0; L]; L];
            if path_i && path_j {
                // c_i ∩ c_j: the common tail of the two chains
                let common = chain_i.iter().rev().zip(chain_j.iter().rev()).take_while(|(a, b)| a == b).count();
                for &k in &chain_i[chain_i.len() - common..] {
                    outer_add(&mut sums, &block_i[k * L..(k + 1) * L], &block_j[k * L..(k + 1) * L]);
                }
            } else {
                // a union of paths (a tendon's row): the coordinates of c_i in c_j
                for &k in chain_i.iter().filter(|k| chain_j.contains(k)) {
                    outer_add(&mut sums, &block_i[k * L..(k + 1) * L], &block_j[k * L..(k + 1) * L]);
                }
            }
            for (c, column) in sums.iter().enumerate().take(count_j) {
                for (r, &g_rc) in column.iter().enumerate().take(count_i) {
                    g[(first_i + r) * n + first_j + c] = g_rc;
                    g[(first_j + c) * n + first_i + r] = g_rc;
                }
            }
        }
    }
}

/// `sums[c][r] += a[r] b[c]`: one coordinate's term of a block of `G`. Inlined into
/// [`delassus_in`] (and so compiled for AVX2 with it), where a closure was not.
#[inline(always)]
fn outer_add(sums: &mut [[f64; BLOCK_LANES]; BLOCK_LANES], a: &[f64], b: &[f64]) {
    for c in 0..BLOCK_LANES {
        for r in 0..BLOCK_LANES {
            sums[c][r] += a[r] * b[c];
        }
    }
}

/// `J_row · x` over the row's chain (the only coordinates where `J_row` is not zero).
#[inline]
pub(crate) fn chain_dot(chain: &[usize], jac_row: &[f64], x: &[f64]) -> f64 {
    chain.iter().map(|&k| jac_row[k] * x[k]).sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::DQuat;
    use crate::multibody::{crba, ltdl_factor, JointKind, ModelBuilder, RigidInertia, Xform};

    /// A floating base with three legs of three revolute joints, one leg branching in two after its
    /// first joint: chains that share the base, a hip, or nothing but the base.
    fn branched_tree() -> MultibodyModel {
        let mut b = ModelBuilder::new("branched");
        let inertia = |m: f64, a: f64| {
            RigidInertia::from_com(
                m,
                DVec3::new(0.01, -0.02, 0.03),
                DMat3::from_diagonal(DVec3::new(a, 1.3 * a, 1.7 * a)),
            )
        };
        let place = |x: f64, y: f64, z: f64, angle: f64| {
            Xform::from_pose(
                DMat3::from_quat(DQuat::from_axis_angle(DVec3::new(1.0, 2.0, -1.0).normalize(), angle)),
                DVec3::new(x, y, z),
            )
        };
        let base = b.add_body("base", None, "root", JointKind::Floating, Xform::IDENTITY, inertia(3.0, 0.05)).unwrap();
        let axes = [DVec3::X, DVec3::Y, DVec3::new(0.0, 0.6, 0.8)];
        for leg in 0..3 {
            let mut parent = base;
            for j in 0..3 {
                let name = format!("leg{leg}_{j}");
                let x_tree = place(0.2 - 0.1 * leg as f64, 0.1 * j as f64, -0.15, 0.3 * (leg + j) as f64);
                parent = b
                    .add_body(
                        name.clone(),
                        Some(parent),
                        name,
                        JointKind::Revolute { axis: axes[j] },
                        x_tree,
                        inertia(0.4, 0.004),
                    )
                    .unwrap();
                if leg == 2 && j == 0 {
                    let x_tree = place(0.05, -0.1, -0.1, 0.7);
                    b.add_body(
                        "toe",
                        Some(parent),
                        "toe",
                        JointKind::Revolute { axis: DVec3::Z },
                        x_tree,
                        inertia(0.2, 0.002),
                    )
                    .unwrap();
                }
            }
        }
        b.build().unwrap()
    }

    /// `G` by the blocks and the chains' common tails against `J M⁻¹ Jᵀ` formed densely (`M⁻¹ Jᵀ`
    /// column by column through the full factor solve): rows of points (three with one chain), of
    /// single coordinates (a joint limit's row), a run of five rows with one chain (more than a
    /// block's four lanes), in mixed order.
    #[test]
    fn delassus_is_j_m_inverse_j_transpose() {
        let model = branched_tree();
        let (nv, nq) = (model.nv(), model.nq());
        let mut ws = Workspace::new(&model);
        let mut q = vec![0.0; nq];
        q[..7].copy_from_slice(&[0.1, -0.2, 0.3, 0.9, 0.1, -0.3, 0.2]);
        let norm = q[3..7].iter().map(|x| x * x).sum::<f64>().sqrt();
        q[3..7].iter_mut().for_each(|x| *x /= norm);
        for (i, x) in q[7..].iter_mut().enumerate() {
            *x = 0.4 * (i as f64 + 1.0).sin();
        }
        crba(&model, &mut ws, &q).unwrap();
        ltdl_factor(&model, &mut ws).unwrap();
        let (mut jac, mut chain_of, mut chains) = (Vec::new(), Vec::new(), Vec::new());
        let mut add = |chain: Vec<usize>, rows: &[Vec<f64>]| {
            let start = chains.len();
            chains.extend(&chain);
            for row in rows {
                chain_of.push((start, chain.len()));
                jac.extend(row);
            }
        };
        let point_rows = |body: usize, point: DVec3| {
            let mut j = vec![0.0; 3 * nv];
            point_jacobian(&model, &ws, body, point, &mut j).unwrap();
            (
                path_dofs(&model, body).collect::<Vec<_>>(),
                (0..3).map(|r| j[r * nv..(r + 1) * nv].to_vec()).collect::<Vec<_>>(),
            )
        };
        let unit_row = |k: usize, sign: f64| {
            let mut chain = vec![k];
            while model.dof_parent(*chain.last().unwrap()) != NONE {
                chain.push(model.dof_parent(*chain.last().unwrap()));
            }
            let mut row = vec![0.0; nv];
            row[k] = sign;
            (chain, vec![row])
        };
        let bodies = model.bodies.len();
        for (body, point) in [(3, DVec3::new(0.3, 0.1, -0.5)), (bodies - 1, DVec3::new(-0.2, 0.0, -0.4))] {
            let (c, r) = point_rows(body, point);
            add(c, &r);
        }
        let (c, r) = unit_row(nv - 2, -1.0);
        add(c, &r);
        let (c, r) = point_rows(5, DVec3::new(0.0, 0.2, -0.3));
        let five: Vec<Vec<f64>> = r
            .iter()
            .chain(&r[..2])
            .enumerate()
            .map(|(i, x)| x.iter().map(|v| v * (1.0 + 0.1 * i as f64)).collect())
            .collect();
        add(c, &five);
        let (c, r) = point_rows(0, DVec3::new(0.1, 0.1, 0.0));
        add(c, &r);
        let (c, r) = unit_row(8, 1.0);
        add(c, &r);
        // a fixed tendon's row over coordinates on two branches: its chain the union of their
        // paths, decreasing (not a path: its intersections with the others are not common tails)
        let (k1, k2) = (7, nv - 1);
        let above = |k: usize, mut d: usize| loop {
            if d == k {
                return true;
            }
            if d == NONE {
                return false;
            }
            d = model.dof_parent(d);
        };
        let union: Vec<usize> = (0..nv).rev().filter(|&k| above(k, k1) || above(k, k2)).collect();
        let mut tendon = vec![0.0; nv];
        tendon[k1] = 0.7;
        tendon[k2] = -1.3;
        add(union.clone(), &[tendon.clone()]);
        let (c, r) = point_rows(4, DVec3::new(0.1, -0.2, 0.0));
        add(c, &r);
        add(union, &[tendon.iter().map(|x| -x).collect()]);
        let n = chain_of.len();
        let inv_sqrt_d: Vec<f64> = (0..nv).map(|k| 1.0 / ws.ltdl[(k, k)].sqrt()).collect();
        let mut y = jac.clone();
        let mut scratch = vec![f64::NAN; delassus_scratch_len(n, nv)];
        let (mut blocks, mut g) = (Vec::new(), vec![f64::NAN; n * n]);
        delassus(&model, &ws, &inv_sqrt_d, &mut y, &mut scratch, &mut blocks, &chain_of, &chains, &mut g);
        assert_eq!(blocks.iter().map(|b| b.1).collect::<Vec<_>>(), [3, 3, 1, 4, 1, 3, 1, 1, 3, 1]);
        assert_eq!(blocks.iter().filter(|b| !b.2).count(), 2, "the tendon rows' chains are not paths");
        let mut worst: f64 = 0.0;
        for j in 0..n {
            let mut w = jac[j * nv..(j + 1) * nv].to_vec();
            ltdl_solve(&model, &ws, &mut w).unwrap();
            for i in 0..n {
                let dense: f64 = jac[i * nv..(i + 1) * nv].iter().zip(&w).map(|(a, b)| a * b).sum();
                worst = worst.max((g[i * n + j] - dense).abs() / dense.abs().max(1e-3));
                assert_eq!(g[i * n + j], g[j * n + i], "G symmetric at {i}, {j}");
            }
        }
        assert!(worst < 1e-12, "G against J M⁻¹ Jᵀ: {worst:e}");
        // Y = L⁻ᵀ Jᵀ (checked through G = Yᵀ D⁻¹ Y above) is zero outside each row's chain
        for (i, &(start, len)) in chain_of.iter().enumerate() {
            for k in 0..nv {
                if !chains[start..start + len].contains(&k) {
                    assert_eq!(y[i * nv + k], 0.0, "Y row {i} outside its chain at {k}");
                }
            }
        }
    }
}
