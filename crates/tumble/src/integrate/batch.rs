//! Semi-implicit Euler on four bodies at once: the same equations as
//! [`semi_implicit_euler_step`](super::euler::semi_implicit_euler_step), with each scalar of a body
//! replaced by four lanes holding that scalar for four bodies (structure of arrays in registers):
//! one AVX register where the CPU has AVX2 (detected at run time, the kernel compiled with
//! `#[target_feature(enable = "avx2")]`), `wide::f64x4` otherwise ([`super::lanes`]).
//!
//! Bit-identical to the scalar step: every lane performs the scalar step's IEEE operations in the
//! same order (`+ − ×` only, no fused multiply-add, no reassociation: Rust never contracts), and the
//! three places where the scalar step branches per body fall back to the scalar code for the lanes
//! that take the rare branch:
//! - the implicit gyroscopic solve, when the linearised step is not accepted
//!   ([`finish_implicit_gyroscopic`]);
//! - `quat_exp`, when a body turns by more than 0.2 rad in a step (`sin_cos`);
//! - `renormalize`, when `|q|²` is further than 1e-4 from 1 (`normalize`).
//!
//! Only bodies whose loads do not depend on their orientation take this path ([`batchable`]);
//! the others (body-frame forces, world-frame torques, point forces) keep the scalar step.
//!
//! The bodies stay in `World::bodies` (the users' `Vec<RigidBody>`): each group of four is gathered
//! into lanes, stepped and scattered back, so every reader sees the stepped state and a user may
//! change any body between steps. Gather and scatter go by rows of four adjacent fields (`m, I`;
//! `1/m, I⁻¹`; `f_load, c_lin`; `τ_load, c_ang`; the state's 13 numbers in three rows and one),
//! each row a load, four rows of four bodies turned into four lanes by one 4×4 transpose.
//!
//! No copy of the constant parameters is kept between steps: `World::bodies` is a public field
//! that any reader may change, so a copy would have to be checked against the bodies each step,
//! reading the same memory as the gather (see docs/integrators.md for the measured ceiling).

use super::euler::finish_implicit_gyroscopic;
#[cfg(target_arch = "x86_64")]
use super::lanes::Avx;
use super::lanes::{Lanes, V3};
use crate::body::RigidBody;
use crate::math::{quat_exp, DQuat, DVec3};
use crate::world::MAX_STATE_MAGNITUDE;
use wide::f64x4;

/// Bodies per batch.
pub const LANES: usize = 4;

/// Whether a body can take the batched step: it moves, and its loads do not depend on its
/// orientation (gravity, world-frame forces, body-frame torques and damping only).
#[inline]
pub fn batchable(body: &RigidBody) -> bool {
    !body.fixed && !body.loads.needs_rotation()
}

/// One scalar of four bodies, `f(bodies[k])` in lane `k`.
#[inline(always)]
fn gather<L: Lanes>(bodies: &[&RigidBody; LANES], f: impl Fn(&RigidBody) -> f64) -> L {
    L::new([f(bodies[0]), f(bodies[1]), f(bodies[2]), f(bodies[3])])
}

/// Advances the bodies `bodies[lanes[k]]`, `k < count`, by one semi-implicit Euler step of `h`
/// seconds under the world's gravity `gravity_world` (m/s², world frame); lanes `count..` repeat
/// lane 0 and are not written. Every body must be [`batchable`] and the lanes distinct.
///
/// Returns the lanes (bit `k`) whose new state fails the quick sanity test of the world's
/// divergence check (a magnitude above `MAX_STATE_MAGNITUDE`, a NaN, or `|q|² > 4`): the caller names
/// the quantity with the full check.
///
/// The lanes are AVX registers where the CPU has AVX2 (detected at run time), `wide::f64x4` otherwise;
/// the results are the same bits.
pub fn semi_implicit_euler_x4(
    bodies: &mut [RigidBody],
    lanes: &[usize; LANES],
    count: usize,
    gravity_world: DVec3,
    h: f64,
) -> u32 {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2
        #[allow(unsafe_code)]
        return unsafe { x4_avx2(bodies, lanes, count, gravity_world, h) };
    }
    semi_implicit_euler_x4_portable(bodies, lanes, count, gravity_world, h)
}

/// [`semi_implicit_euler_x4`] in `wide::f64x4` lanes whatever the CPU (SSE2 in the default build):
/// the portable path, for tests and benchmarks.
pub fn semi_implicit_euler_x4_portable(
    bodies: &mut [RigidBody],
    lanes: &[usize; LANES],
    count: usize,
    gravity_world: DVec3,
    h: f64,
) -> u32 {
    x4::<f64x4>(bodies, lanes, count, gravity_world, h)
}

/// [`semi_implicit_euler_x4`] compiled for AVX2, in [`Avx`] lanes.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn x4_avx2(bodies: &mut [RigidBody], lanes: &[usize; LANES], count: usize, gravity_world: DVec3, h: f64) -> u32 {
    x4::<Avx>(bodies, lanes, count, gravity_world, h)
}

/// The step in lanes `L`.
#[inline(always)]
fn x4<L: Lanes>(bodies: &mut [RigidBody], lanes: &[usize; LANES], count: usize, gravity_world: DVec3, h: f64) -> u32 {
    debug_assert!((1..=LANES).contains(&count));
    let lanes = &core::array::from_fn(|k| if k < count { lanes[k] } else { lanes[0] });
    let hv = L::splat(h);
    let group: &[&RigidBody; LANES] = &lanes.map(|index| &bodies[index]);

    // parameters (constants of each body) and state
    // four rows of each body, transposed into lanes (rows of adjacent fields: a load each)
    let [mass, ix, iy, iz] = L::transpose(group.map(|b| {
        let i = b.mass.inertia_body;
        L::new([b.mass.mass, i.x, i.y, i.z])
    }));
    let [inv_mass, jx, jy, jz] = L::transpose(group.map(|b| {
        let j = b.mass.inv_inertia_body;
        L::new([b.mass.inv_mass, j.x, j.y, j.z])
    }));
    let [fx, fy, fz, linear_damping] = L::transpose(group.map(|b| {
        let f = b.loads.force_world;
        L::new([f.x, f.y, f.z, b.loads.linear_damping])
    }));
    let [tx, ty, tz, angular_damping] = L::transpose(group.map(|b| {
        let t = b.loads.torque_body;
        L::new([t.x, t.y, t.z, b.loads.angular_damping])
    }));
    let (inertia, inv_inertia) = (V3 { x: ix, y: iy, z: iz }, V3 { x: jx, y: jy, z: jz });
    let (force_load, torque_load) = (V3 { x: fx, y: fy, z: fz }, V3 { x: tx, y: ty, z: tz });
    // ε/(h|ω|) = ΔI/I_min, as in `implicit_gyroscopic` (scalar: `f64::max` and `min` on NaNs)
    let spread = gather::<L>(group, |b| {
        let (i, inv) = (b.mass.inertia_body, b.mass.inv_inertia_body);
        (i.max_element() - i.min_element()) * inv.max_element()
    });
    // g_body = s g, as `RigidBody::gravity`
    let gravity_scale = gather::<L>(group, |b| b.gravity_scale);
    let gravity = V3 { x: L::splat(gravity_world.x), y: L::splat(gravity_world.y), z: L::splat(gravity_world.z) }
        .scale(gravity_scale);
    let s = group.map(|b| &b.state);
    let [px, py, pz, qx] = L::transpose(s.map(|s| L::new([s.position.x, s.position.y, s.position.z, s.orientation.x])));
    let [qy, qz, qw, vx] =
        L::transpose(s.map(|s| L::new([s.orientation.y, s.orientation.z, s.orientation.w, s.velocity.x])));
    let [vy, vz, wx, wy] =
        L::transpose(s.map(|s| L::new([s.velocity.y, s.velocity.z, s.omega_body.x, s.omega_body.y])));
    let wz = L::new(s.map(|s| s.omega_body.z));
    let mut position = V3 { x: px, y: py, z: pz };
    let mut velocity = V3 { x: vx, y: vy, z: vz };
    let omega = V3 { x: wx, y: wy, z: wz };
    let q = [qx, qy, qz, qw];

    // resultant: f = m g + f_load − (c m) v ;  τ = τ_load − c (I ω)
    let force = gravity.scale(mass).add(force_load).sub(velocity.scale(linear_damping * mass));
    let torque = torque_load.sub(inertia.mul(omega).scale(angular_damping));
    // v ← v + h f/m ;  x ← x + h v
    velocity = velocity.add(force.scale(hv * inv_mass));
    position = position.add(velocity.scale(hv));
    // ω₁ = ω + h I⁻¹ τ
    let w = omega.add(torque.scale(hv).mul(inv_inertia));

    // I (ω' − ω₁) + h ω' × I ω' = 0, linearised: see `implicit_gyroscopic` for the derivation
    let i = inertia;
    let (a, b, c) = (hv * (i.z - i.y), hv * (i.x - i.z), hv * (i.y - i.x));
    let residual = V3 { x: a * w.y * w.z, y: b * w.z * w.x, z: c * w.x * w.y };
    let d0 = residual.mul(inv_inertia);
    let n_d0 =
        V3 { x: a * (w.z * d0.y + w.y * d0.z), y: b * (w.z * d0.x + w.x * d0.z), z: c * (w.y * d0.x + w.x * d0.y) };
    let mut omega_new = w.sub(residual.sub(n_d0).mul(inv_inertia));
    let (l_before, l_after) = (i.mul(w), i.mul(omega_new));
    let round_off = L::splat(1.0 + 4.0 * f64::EPSILON);
    let kept = omega_new.dot(l_after).le(w.dot(l_before) * round_off)
        & l_after.length_squared().le(l_before.length_squared() * round_off);
    let small = (hv * hv * w.length_squared() * spread * spread).le(L::splat(0.05 * 0.05));
    // the residual test only where the step is not small (the scalar `small || …`)
    let converged = if small.bitmask() == (1 << LANES) - 1 {
        small
    } else {
        let residual_after = l_after.sub(l_before).add(omega_new.cross(l_after).scale(hv));
        small | residual_after.length_squared().le(L::splat(1e-6) * l_before.length_squared())
    };
    let rejected = !(converged & kept).bitmask() & ((1 << LANES) - 1);
    if rejected != 0 {
        for k in (0..LANES).filter(|k| rejected & (1 << k) != 0) {
            omega_new.set_lane(k, finish_implicit_gyroscopic(i.lane(k), w.lane(k), h));
        }
    }

    // q ← q ⊗ exp(h ω'), exp from its Taylor series (`quat_exp`)
    let phi = omega_new.scale(hv);
    let x2 = L::splat(0.25) * phi.length_squared();
    let sinc = L::splat(1.0)
        + x2 * (L::splat(-1.0 / 6.0)
            + x2 * (L::splat(1.0 / 120.0) + x2 * (L::splat(-1.0 / 5040.0) + x2 * L::splat(1.0 / 362880.0))));
    let cos = L::splat(1.0)
        + x2 * (L::splat(-0.5)
            + x2 * (L::splat(1.0 / 24.0)
                + x2 * (L::splat(-1.0 / 720.0) + x2 * (L::splat(1.0 / 40320.0) + x2 * L::splat(-1.0 / 3628800.0)))));
    let v = phi.scale(L::splat(0.5) * sinc);
    let mut e = [v.x, v.y, v.z, cos];
    let large = !x2.lt(L::splat(0.01)).bitmask() & ((1 << LANES) - 1);
    if large != 0 {
        for k in (0..LANES).filter(|k| large & (1 << k) != 0) {
            let exp = quat_exp(phi.lane(k));
            for (component, value) in e.iter_mut().zip([exp.x, exp.y, exp.z, exp.w]) {
                let mut a = component.to_array();
                a[k] = value;
                *component = L::new(a);
            }
        }
    }
    // as `DQuat::mul_quat`
    let ([x0, y0, z0, w0], [x1, y1, z1, w1]) = (q, e);
    let mut q: [L; 4] = [
        w0 * x1 + x0 * w1 + y0 * z1 - z0 * y1,
        w0 * y1 - x0 * z1 + y0 * w1 + z0 * x1,
        w0 * z1 + x0 * y1 - y0 * x1 + z0 * w1,
        w0 * w1 - x0 * x1 - y0 * y1 - z0 * z1,
    ];
    // renormalise: one Newton step of |q|² = 1 (`renormalize`)
    let n2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
    let newton = L::splat(0.5) * (L::splat(3.0) - n2);
    let near = (n2 - L::splat(1.0)).abs().lt(L::splat(1e-4));
    let q_unrenormalized = q;
    for component in &mut q {
        *component = *component * newton;
    }
    let far = !near.bitmask() & ((1 << LANES) - 1);

    // the quick sanity test of `check_state`
    let max2 = L::splat(MAX_STATE_MAGNITUDE * MAX_STATE_MAGNITUDE);
    let sane =
        position.length_squared().le(max2) & velocity.length_squared().le(max2) & omega_new.length_squared().le(max2);
    // |q|² of the stored quaternion, summed as `DQuat::length_squared` (the far lanes are redone)
    let q2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
    let mut insane = (!sane.bitmask() | (!q2.le(L::splat(4.0)).bitmask() & !far)) & ((1 << LANES) - 1);

    // scatter: the same rows, transposed back
    let (p, v, o) = (position, velocity, omega_new);
    let rows_a = L::transpose([p.x, p.y, p.z, q[0]]).map(L::to_array);
    let rows_b = L::transpose([q[1], q[2], q[3], v.x]).map(L::to_array);
    let rows_c = L::transpose([v.y, v.z, o.x, o.y]).map(L::to_array);
    let wz = o.z.to_array();
    for (k, &index) in lanes.iter().enumerate().take(count) {
        let s = &mut bodies[index].state;
        let ([a0, a1, a2, a3], [b0, b1, b2, b3], [c0, c1, c2, c3]) = (rows_a[k], rows_b[k], rows_c[k]);
        s.position = DVec3::new(a0, a1, a2);
        s.orientation = DQuat::from_xyzw(a3, b0, b1, b2);
        s.velocity = DVec3::new(b3, c0, c1);
        s.omega_body = DVec3::new(c2, c3, wz[k]);
    }
    // exact normalisation where |q|² was far from 1 (rare)
    if far != 0 {
        let qu = q_unrenormalized.map(|c| c.to_array());
        for (k, &index) in lanes.iter().enumerate().take(count).filter(|&(k, _)| far & (1 << k) != 0) {
            let s = &mut bodies[index].state;
            s.orientation = DQuat::from_xyzw(qu[0][k], qu[1][k], qu[2][k], qu[3][k]).normalize();
            if s.orientation.length_squared() > 4.0 || s.orientation.length_squared().is_nan() {
                insane |= 1 << k;
            }
        }
    }
    insane & ((1 << count) - 1)
}
