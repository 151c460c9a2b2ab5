//! Forward dynamics by the articulated-body algorithm (ABA): `q̈ = M(q)⁻¹ (τ − C(q, q̇) q̇ − g(q))` in `O(n)`.
//!
//! Reference: Featherstone (2008), §7.3, Table 7.1.
//!
//! Three passes over the tree:
//! 1. parents first: velocities `v_i`, velocity products `c_i = v_i ×ₘ v_J`, and the rigid-body
//!    inertias and bias forces `I^A_i = I_i`, `p^A_i = v_i ×* I_i v_i`;
//! 2. children first: `U_i = I^A_i S_i`, `D_i = S_iᵀ U_i + a_i 1` (`a_i` the joint's armature, a
//!    rotor inertia on the joint's own coordinates: Featherstone (2008) §9.6), `u_i = τ_i − S_iᵀ p^A_i`, and each body's
//!    articulated inertia and bias handed to its parent: `I^a = I^A − U D⁻¹ Uᵀ`,
//!    `p^a = p^A + I^a c + U D⁻¹ u`, `I^A_λ += λ_X_i* I^a i_X_λ`, `p^A_λ += λ_X_i* p^a`;
//! 3. parents first: `a' = i_X_λ a_λ + c_i`, `q̈_i = D⁻¹ (u_i − U_iᵀ a')`, `a_i = a' + S_i q̈_i`,
//!    with `a_0 = −g`.
//!
//! Inputs: `q` (nq), `v` (nv), `tau` (nv). Output: `qdd` (nv), in the units of `v` per second; for a
//! floating base the derivative of the child-frame components `[v; ω]`. No allocation.

use super::fk::placements_up;
use super::model::MultibodyModel;
use super::spatial::{ArticulatedInertia, Motion};
use super::workspace::{check_len, LengthError, Workspace};
use crate::math::DVec3;

/// Why forward dynamics failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum AbaError {
    #[error("the articulated inertia of joint '{joint}' about its motion subspace is not positive definite")]
    Singular { joint: String },
    #[error(transparent)]
    Length(#[from] LengthError),
}

/// `q̈ = ABA(q, v, τ)`, written into `qdd` (length nv).
pub fn aba(
    model: &MultibodyModel,
    ws: &mut Workspace,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
    qdd: &mut [f64],
) -> Result<(), AbaError> {
    check_len("q", q.len(), model.nq())?;
    check_len("v", v.len(), model.nv())?;
    check_len("tau", tau.len(), model.nv())?;
    check_len("qdd", qdd.len(), model.nv())?;
    placements_up(model, ws, q);
    let n = model.nbodies();

    // pass 1: velocities, velocity products, rigid-body inertias and bias forces
    for (i, body) in model.bodies.iter().enumerate() {
        let vi = body.joint.v_index;
        // v_J = S q̇
        let mut v_joint = Motion::ZERO;
        for (k, s_k) in model.subspace(i).iter().enumerate() {
            v_joint += v[vi + k] * *s_k;
        }
        // v_i = i_X_λ v_λ + v_J
        let v_i = match body.parent {
            Some(p) => ws.x_up[i].apply_motion(ws.v[p]) + v_joint,
            None => v_joint,
        };
        ws.v[i] = v_i;
        // c_i = v_i ×ₘ v_J  (c_J = 0)
        ws.c[i] = v_i.cross_motion(v_joint);
        // I^A_i = I_i,  p^A_i = v_i ×* I_i v_i
        ws.ia[i] = ArticulatedInertia::from(body.inertia);
        ws.f[i] = v_i.cross_force(body.inertia.mul_motion(v_i));
    }

    // pass 2: articulated-body inertias and bias forces, leaves to root
    for i in (0..n).rev() {
        let body = &model.bodies[i];
        let vi = body.joint.v_index;
        let s = model.subspace(i);
        let nj = s.len();
        let mut d = [0.0; 36];
        for (k, s_k) in s.iter().enumerate() {
            // U = I^A S,  u = τ − Sᵀ p^A
            ws.u_cols[vi + k] = ws.ia[i].mul_motion(*s_k);
            ws.u[vi + k] = tau[vi + k] - s_k.dot(ws.f[i]);
        }
        let armature = body.joint.dynamics.armature;
        for (k, s_k) in s.iter().enumerate() {
            for l in 0..nj {
                // D = Sᵀ U (+ armature on the diagonal)
                d[k * nj + l] = s_k.dot(ws.u_cols[vi + l]);
            }
            if armature != 0.0 {
                d[k * nj + k] += armature;
            }
        }
        let off = model.block_offset(i);
        if !invert_spd(nj, &mut d, &mut ws.d_inv[off..off + nj * nj]) {
            return Err(AbaError::Singular { joint: body.joint.name.clone() });
        }
        if let Some(p) = body.parent {
            let d_inv = &ws.d_inv[off..off + nj * nj];
            // I^a = I^A − U D⁻¹ Uᵀ
            let mut ia = ws.ia[i];
            // D⁻¹ u
            let mut d_inv_u = [0.0; 6];
            for k in 0..nj {
                for l in 0..nj {
                    ia.sub_outer(ws.u_cols[vi + k], ws.u_cols[vi + l], d_inv[k * nj + l]);
                    d_inv_u[k] += d_inv[k * nj + l] * ws.u[vi + l];
                }
            }
            // p^a = p^A + I^a c + U D⁻¹ u
            let mut pa = ws.f[i] + ia.mul_motion(ws.c[i]);
            for (k, &du) in d_inv_u.iter().enumerate().take(nj) {
                pa += du * ws.u_cols[vi + k];
            }
            // I^A_λ += λ_X_i* I^a i_X_λ,  p^A_λ += λ_X_i* p^a
            let ia_parent = ia.transform_to_a(&ws.x_up[i]);
            ws.ia[p] += ia_parent;
            let pa_parent = ws.x_up[i].inv_apply_force(pa);
            ws.f[p] += pa_parent;
        }
    }

    // pass 3: accelerations, root to leaves; a_0 = −g
    let a_world = Motion::new(DVec3::ZERO, -model.gravity);
    for (i, body) in model.bodies.iter().enumerate() {
        let vi = body.joint.v_index;
        let s = model.subspace(i);
        let nj = s.len();
        // a' = i_X_λ a_λ + c_i
        let a_parent = match body.parent {
            Some(p) => ws.a[p],
            None => a_world,
        };
        let a_prime = ws.x_up[i].apply_motion(a_parent) + ws.c[i];
        // q̈_i = D⁻¹ (u_i − U_iᵀ a')
        let mut rhs = [0.0; 6];
        for (k, r) in rhs.iter_mut().enumerate().take(nj) {
            *r = ws.u[vi + k] - a_prime.dot(ws.u_cols[vi + k]);
        }
        let off = model.block_offset(i);
        let d_inv = &ws.d_inv[off..off + nj * nj];
        let mut a_i = a_prime;
        for (k, s_k) in s.iter().enumerate() {
            let mut acc = 0.0;
            for (l, r) in rhs.iter().enumerate().take(nj) {
                acc += d_inv[k * nj + l] * r;
            }
            qdd[vi + k] = acc;
            // a_i = a' + S q̈
            a_i += acc * *s_k;
        }
        ws.a[i] = a_i;
    }
    Ok(())
}

/// The inverse of a symmetric positive definite `n × n` matrix (`n ≤ 6`, row-major in `m`), written
/// into `out`; false if a pivot is not positive and finite. Gauss–Jordan elimination, which needs no
/// pivoting on a positive definite matrix.
#[inline]
fn invert_spd(n: usize, m: &mut [f64; 36], out: &mut [f64]) -> bool {
    if n == 1 {
        let d = m[0];
        if !(d > 0.0 && d.is_finite()) {
            return false;
        }
        out[0] = 1.0 / d;
        return true;
    }
    let mut inv = [0.0; 36];
    for k in 0..n {
        inv[k * n + k] = 1.0;
    }
    for col in 0..n {
        let pivot = m[col * n + col];
        if !(pivot > 0.0 && pivot.is_finite()) {
            return false;
        }
        let scale = 1.0 / pivot;
        for c in 0..n {
            m[col * n + c] *= scale;
            inv[col * n + c] *= scale;
        }
        for r in 0..n {
            if r != col {
                let factor = m[r * n + col];
                if factor != 0.0 {
                    for c in 0..n {
                        m[r * n + c] -= factor * m[col * n + c];
                        inv[r * n + c] -= factor * inv[col * n + c];
                    }
                }
            }
        }
    }
    out[..n * n].copy_from_slice(&inv[..n * n]);
    true
}
