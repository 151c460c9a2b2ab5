//! Forces of a still or moving medium (air, water) on the bodies: MuJoCo's inertia-box fluid model.
//!
//! Reference: E. Todorov, MuJoCo documentation, *Computation › Fluid forces › Inertia model*, and
//! its source (`engine_passive.c`, the inertia-box model). Each body with mass is replaced by the
//! solid box of uniform density that has its mass and principal moments `I₀, I₁, I₂` about its
//! centre of mass; the box's full side along principal axis `i` is
//!
//! ```text
//! s_i = √(6 (I_j + I_k − I_i) / m)                      ({i, j, k} = {0, 1, 2}; the difference at least 1e-15)
//! ```
//!
//! In the body's inertial frame (origin at the centre of mass, axes along the principal axes), with
//! `ω` the body's angular velocity, `v` the velocity of its centre of mass minus the wind `w`
//! (all in inertial axes), medium density `ρ` and viscosity `μ`, the force `f` and the moment `n`
//! about the centre of mass are
//!
//! ```text
//! d   = (s₀ + s₁ + s₂) / 3                             (the diameter of the equivalent sphere)
//! f_i = −3 π μ d v_i − ½ ρ s_j s_k |v_i| v_i            (Stokes drag + quadratic drag on face i)
//! n_i = −π μ d³ ω_i − ρ s_i (s_j⁴ + s_k⁴) |ω_i| ω_i / 64
//! ```
//!
//! and the generalized force is `τ_fluid = Σ_b J_bᵀ [n; f]_b` (MuJoCo counts it in `qfrc_passive`).
//! With no wind every term opposes the motion, so the power `τ_fluid · v = Σ_b [n; f]_b · [ω; v]_b`
//! is never positive.
//!
//! Inputs: `q` (nq), `v` (nv) and the model's [`Fluid`]. Output: `τ_fluid` (nv; N·m or N) added to
//! `tau`. Cost: one forward-kinematics pass and one backward pass over the tree, `O(n)`; nothing at
//! all when the medium has neither density nor viscosity (every URDF model, and MJCF by default).

use super::model::MultibodyModel;
use super::spatial::{Force, Motion, Xform};
use super::workspace::Workspace;
use crate::math::{DMat3, DVec3};
use std::f64::consts::PI;

/// A body lighter than this (kg) feels no fluid force (MuJoCo's `mjMINVAL`).
pub const MIN_FLUID_MASS: f64 = 1e-15;

/// The medium the bodies move in (MJCF `<option density viscosity wind>`); all zero by default,
/// which switches fluid forces off.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Medium {
    /// Density `ρ` (kg/m³), ≥ 0: quadratic drag.
    pub density: f64,
    /// Dynamic viscosity `μ` (Pa·s), ≥ 0: Stokes (linear) drag.
    pub viscosity: f64,
    /// Velocity of the medium in the world frame (m/s).
    pub wind: DVec3,
}

impl Medium {
    /// No density and no viscosity: no fluid force, whatever the wind.
    #[inline]
    pub fn is_void(&self) -> bool {
        self.density == 0.0 && self.viscosity == 0.0
    }
}

/// One body's equivalent box, placed at its centre of mass along its principal axes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FluidBox {
    /// The tree body it is fixed to.
    pub body: usize,
    /// `inertial_X_body`: the inertial frame (origin at the centre of mass, principal axes) in the
    /// body frame.
    pub inertial_from_body: Xform,
    /// Full side lengths `s` of the equivalent box along the principal axes (m).
    pub size: DVec3,
}

impl FluidBox {
    /// The box of a part of mass `mass` (kg) with principal moments `moments` (kg·m², about its
    /// centre of mass) along the columns of `body_from_principal`, its centre of mass at `com_body`
    /// (m, body frame); `None` when it is lighter than [`MIN_FLUID_MASS`] (MuJoCo skips it).
    pub fn new(body: usize, mass: f64, com_body: DVec3, body_from_principal: DMat3, moments: DVec3) -> Option<Self> {
        if mass.is_nan() || mass < MIN_FLUID_MASS {
            return None;
        }
        Some(Self {
            body,
            inertial_from_body: Xform::from_pose(body_from_principal, com_body),
            size: box_size(mass, moments),
        })
    }
}

/// The medium and the bodies' boxes: what the model needs for [`add_fluid_forces`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Fluid {
    pub medium: Medium,
    /// One box per body part with mass (a source body merged into another keeps its own box).
    pub boxes: Vec<FluidBox>,
}

impl Fluid {
    /// Whether any fluid force can act (a medium with density or viscosity, and a box).
    #[inline]
    pub fn is_active(&self) -> bool {
        !self.medium.is_void() && !self.boxes.is_empty()
    }
}

/// The full sides of the uniform box of mass `mass` with principal moments `moments`:
/// `s_i = √(6 max(I_j + I_k − I_i, 1e-15) / m)` (m).
pub fn box_size(mass: f64, moments: DVec3) -> DVec3 {
    let side = |i: f64, j: f64, k: f64| (6.0 * (j + k - i).max(MIN_FLUID_MASS) / mass).sqrt();
    DVec3::new(
        side(moments.x, moments.y, moments.z),
        side(moments.y, moments.x, moments.z),
        side(moments.z, moments.x, moments.y),
    )
}

/// The fluid's force on a box of sides `size` (m) moving with `v_inertial = [ω; v_com]` (inertial
/// axes) through `medium` whose wind is `wind_inertial` (m/s, inertial axes): `[n; f]` about the
/// centre of mass, in inertial axes (N·m, N). The equations are in the module doc.
pub fn box_wrench(medium: &Medium, size: DVec3, v_inertial: Motion, wind_inertial: DVec3) -> Force {
    let omega = v_inertial.ang;
    // the velocity relative to the medium
    let v_rel = v_inertial.lin - wind_inertial;
    let mut f = Force::ZERO;
    if medium.viscosity > 0.0 {
        let d = (size.x + size.y + size.z) / 3.0;
        // n = −π μ d³ ω,  f = −3 π μ d v
        f.ang = -PI * d * d * d * medium.viscosity * omega;
        f.lin = -3.0 * PI * d * medium.viscosity * v_rel;
    }
    if medium.density > 0.0 {
        let rho = medium.density;
        let s = size;
        let s4 = s * s * s * s;
        // f_i −= ½ ρ s_j s_k |v_i| v_i  (the face normal to axis i)
        let face = DVec3::new(s.y * s.z, s.x * s.z, s.x * s.y);
        f.lin -= 0.5 * rho * face * v_rel.abs() * v_rel;
        // n_i −= ρ s_i (s_j⁴ + s_k⁴) |ω_i| ω_i / 64
        let arm = DVec3::new(s.x * (s4.y + s4.z), s.y * (s4.x + s4.z), s.z * (s4.x + s4.y));
        f.ang -= rho / 64.0 * arm * omega.abs() * omega;
    }
    f
}

/// Adds `τ_fluid(q, v)` to `tau` (lengths nq, nv, nv), using `ws` (its placements, velocities and
/// forces are overwritten). Does nothing when the model's medium is void.
pub fn add_fluid_forces(
    model: &MultibodyModel,
    ws: &mut Workspace,
    q: &[f64],
    v: &[f64],
    tau: &mut [f64],
) -> Result<(), super::LengthError> {
    super::workspace::check_len("q", q.len(), model.nq())?;
    super::workspace::check_len("v", v.len(), model.nv())?;
    super::workspace::check_len("tau", tau.len(), model.nv())?;
    add_unchecked(model, ws, q, v, tau);
    Ok(())
}

/// [`add_fluid_forces`] with lengths checked by the caller.
pub(crate) fn add_unchecked(model: &MultibodyModel, ws: &mut Workspace, q: &[f64], v: &[f64], tau: &mut [f64]) {
    let fluid = &model.fluid;
    if !fluid.is_active() {
        return;
    }
    // poses i_X_0 and body velocities v_i (body frame)
    super::fk::forward_kinematics(model, ws, q, v).expect("lengths checked by the caller");
    ws.f.fill(Force::ZERO);
    for b in &fluid.boxes {
        let x_cb = &b.inertial_from_body;
        // [ω; v_com] in inertial axes: c_X_b v_b
        let v_inertial = x_cb.apply_motion(ws.v[b.body]);
        // wind in inertial axes: E_c0 w = E_cb E_b0 w
        let wind_inertial = x_cb.e * (ws.x_world[b.body].e * fluid.medium.wind);
        let f_inertial = box_wrench(&fluid.medium, b.size, v_inertial, wind_inertial);
        // f_b = (c_X_b)ᵀ f_c
        ws.f[b.body] += x_cb.inv_apply_force(f_inertial);
    }
    // τ_k = S_kᵀ f_i, f_λ(i) += (i_X_λ)ᵀ f_i  (children before parents: the transpose of J)
    for i in (0..model.nbodies()).rev() {
        let body = &model.bodies[i];
        let f_i = ws.f[i];
        for (k, s) in model.subspace(i).iter().enumerate() {
            tau[body.joint.v_index + k] += s.dot(f_i);
        }
        if let Some(p) = body.parent {
            let f_parent = ws.x_up[i].inv_apply_force(f_i);
            ws.f[p] += f_parent;
        }
    }
}

/// The principal moments (kg·m²) and axes (`body_from_principal`, a proper rotation) of a
/// symmetric inertia tensor `inertia_com` (kg·m², body axes). Where moments repeat the axes within
/// their plane are those of the eigen-solver; MuJoCo's may differ by a rotation in that plane,
/// which changes the quadratic drag (see `docs/mjcf.md`).
pub fn principal_axes(inertia_com: DMat3) -> (DVec3, DMat3) {
    let c = inertia_com.to_cols_array();
    let m = nalgebra::Matrix3::from_column_slice(&c);
    let eig = nalgebra::SymmetricEigen::new(m);
    let col = |k: usize| DVec3::new(eig.eigenvectors[(0, k)], eig.eigenvectors[(1, k)], eig.eigenvectors[(2, k)]);
    let (x, y) = (col(0), col(1));
    // a right-handed frame: the third axis from the first two
    let axes = DMat3::from_cols(x, y, x.cross(y));
    (DVec3::new(eig.eigenvalues[0], eig.eigenvalues[1], eig.eigenvalues[2]), axes)
}

#[cfg(test)]
mod tests;
