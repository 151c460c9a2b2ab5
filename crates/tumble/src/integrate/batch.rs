//! Semi-implicit Euler on four or eight bodies at once: the same equations as
//! [`semi_implicit_euler_step`](super::euler::semi_implicit_euler_step), with each scalar of a body
//! replaced by lanes holding that scalar for several bodies (structure of arrays in registers): eight
//! lanes in one AVX-512 register where the CPU has AVX-512F, four in one AVX register where it has
//! AVX2 (detected at run time, the kernel compiled with `#[target_feature(enable = "avx512f")]` or
//! `"avx2"`), `wide::f64x4` otherwise ([`super::lanes`]). One generic kernel for all three.
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
//! The bodies stay in `World::bodies` (the users' `Vec<RigidBody>`): each group is gathered into
//! lanes, stepped and scattered back, so every reader sees the stepped state and a user may change
//! any body between steps. Gather and scatter go by rows of four adjacent fields (`m, I`; `1/m, I⁻¹`;
//! `τ_load, c_lin`; `f_load`; `c_ang`; the state's 13 numbers and the gravity scale in four rows), each
//! row one load where the layout has the fields adjacent (`Row`), the rows of the group's bodies
//! turned into lanes by 4×4 transposes (two at once in AVX-512 registers).
//!
//! No copy of the constant parameters is kept between steps: `World::bodies` is a public field
//! that any reader may change, so a copy would have to be checked against the bodies each step,
//! reading the same memory as the gather (see docs/integrators.md for the measured ceiling).

use super::euler::finish_implicit_gyroscopic;
#[cfg(target_arch = "x86_64")]
use super::lanes::{Avx, Avx512};
use super::lanes::{BatchLanes, V3};
use crate::body::RigidBody;
use crate::math::{quat_exp, DQuat, DVec3};
use crate::world::MAX_STATE_MAGNITUDE;
use wide::f64x4;

/// Bodies per batch of [`semi_implicit_euler_x4`].
pub const LANES: usize = 4;

/// Bodies per batch at most: [`semi_implicit_euler_batch`] takes up to [`batch_width`] of them.
pub const MAX_LANES: usize = 8;

/// Whether a body can take the batched step: it moves, and its loads do not depend on its
/// orientation (gravity, world-frame forces, body-frame torques and damping only).
#[inline]
pub fn batchable(body: &RigidBody) -> bool {
    !body.fixed && !body.loads.needs_rotation()
}

/// Four `f64` fields of a body that the step reads together, by their byte offsets in `RigidBody`.
/// When the compiler has laid them out adjacent and in order (checked at compile time), the row is
/// read with one 32-byte load; otherwise field by field (same values either way).
#[derive(Clone, Copy)]
struct Row([usize; 4]);

impl Row {
    /// Whether the four fields are adjacent `f64`s in order.
    const fn adjacent(self) -> bool {
        let o = self.0;
        o[1] == o[0] + 8 && o[2] == o[0] + 16 && o[3] == o[0] + 24
    }

    /// The four fields of `body`, `fields(body)` read as one load when they are adjacent.
    #[inline(always)]
    fn read(self, body: &RigidBody, fields: fn(&RigidBody) -> [f64; 4]) -> [f64; 4] {
        if self.adjacent() {
            // SAFETY: the 32 bytes at this offset are four `f64` fields of `body` (checked above; the
            // offsets are `offset_of!` of those fields), read through a pointer to the whole body
            #[allow(unsafe_code)]
            unsafe {
                (body as *const RigidBody).cast::<u8>().add(self.0[0]).cast::<[f64; 4]>().read_unaligned()
            }
        } else {
            fields(body)
        }
    }

    /// Sets the four fields of `body` to `row`, `set(body, row)` written as one store when they are
    /// adjacent.
    #[inline(always)]
    fn write(self, body: &mut RigidBody, row: [f64; 4], set: fn(&mut RigidBody, [f64; 4])) {
        if self.adjacent() {
            // SAFETY: the 32 bytes at this offset are four `f64` fields of `body` (checked above; the
            // offsets are `offset_of!` of those fields), written through a pointer to the whole body
            #[allow(unsafe_code)]
            unsafe {
                (body as *mut RigidBody).cast::<u8>().add(self.0[0]).cast::<[f64; 4]>().write_unaligned(row)
            }
        } else {
            set(body, row)
        }
    }
}

macro_rules! row {
    ($($field:tt).+ , $($f1:tt).+ , $($f2:tt).+ , $($f3:tt).+) => {
        Row([
            core::mem::offset_of!(RigidBody, $($field).+),
            core::mem::offset_of!(RigidBody, $($f1).+),
            core::mem::offset_of!(RigidBody, $($f2).+),
            core::mem::offset_of!(RigidBody, $($f3).+),
        ])
    };
}

/// `m, I` (the row's fields must match the closures that read them field by field in [`step`]).
const ROW_MASS: Row = row!(mass.mass, mass.inertia_body.x, mass.inertia_body.y, mass.inertia_body.z);
/// `1/m, I⁻¹`.
const ROW_INV_MASS: Row =
    row!(mass.inv_mass, mass.inv_inertia_body.x, mass.inv_inertia_body.y, mass.inv_inertia_body.z);
/// `τ_body, c_lin`.
const ROW_TORQUE: Row = row!(loads.torque_body.x, loads.torque_body.y, loads.torque_body.z, loads.linear_damping);
/// `c_ang` (and `τ_y, τ_z, c_lin` again, not used).
const ROW_DAMPING: Row = row!(loads.torque_body.y, loads.torque_body.z, loads.linear_damping, loads.angular_damping);
/// `f_world` and the first component of `f_body` (zero, not used).
const ROW_FORCE: Row = row!(loads.force_world.x, loads.force_world.y, loads.force_world.z, loads.force_body.x);
/// The state's 13 numbers and the gravity scale: `x, q_x`; `q_y, q_z, q_w, v_x`; `v_y, v_z, ω_x, ω_y`;
/// `ω, s` (`ω_x, ω_y` again, not used).
const ROW_STATE: [Row; 4] = [
    row!(state.position.x, state.position.y, state.position.z, state.orientation.x),
    row!(state.orientation.y, state.orientation.z, state.orientation.w, state.velocity.x),
    row!(state.velocity.y, state.velocity.z, state.omega_body.x, state.omega_body.y),
    row!(state.omega_body.x, state.omega_body.y, state.omega_body.z, gravity_scale),
];

/// Lane `k` of a 3-vector of lanes.
#[inline(always)]
fn lane3<L: BatchLanes>(v: V3<L>, k: usize) -> DVec3 {
    DVec3::new(v.x.lane(k), v.y.lane(k), v.z.lane(k))
}

/// Lane `k` of a 3-vector of lanes set to `value`.
#[inline(always)]
fn set_lane3<L: BatchLanes>(v: &mut V3<L>, k: usize, value: DVec3) {
    v.x.set_lane(k, value.x);
    v.y.set_lane(k, value.y);
    v.z.set_lane(k, value.z);
}

/// A row of the group's bodies, transposed: lane `k` of result `j` is `fields(group[k])[j]`.
#[inline(always)]
fn rows<L: BatchLanes>(group: &[&RigidBody; MAX_LANES], row: Row, fields: fn(&RigidBody) -> [f64; 4]) -> [L; 4] {
    L::from_rows(|k| row.read(group[k], fields))
}

/// Whether the CPU has AVX-512F (eight lanes), detected once (the standard library caches it).
#[inline]
fn has_avx512() -> bool {
    #[cfg(target_arch = "x86_64")]
    return std::arch::is_x86_feature_detected!("avx512f");
    #[allow(unreachable_code)]
    false
}

/// Bodies per batch of [`semi_implicit_euler_batch`] on this CPU: 8 with AVX-512F, else 4.
#[inline]
pub fn batch_width() -> usize {
    if has_avx512() {
        MAX_LANES
    } else {
        LANES
    }
}

/// Advances the bodies `bodies[lanes[k]]`, `k < count`, `count ≤` [`batch_width`], by one
/// semi-implicit Euler step of `h` seconds under the world's gravity `gravity_world` (m/s², world
/// frame): eight lanes in AVX-512 registers where the CPU has AVX-512F, else as
/// [`semi_implicit_euler_x4`] (`lanes[4..]` unused). Entries `count..` of `lanes` are not read.
/// Every body must be [`batchable`] and the lanes distinct.
///
/// Returns the lanes (bit `k`) whose new state fails the quick sanity test of the world's
/// divergence check, as [`semi_implicit_euler_x4`]. The results are the same bits whatever the lanes.
pub fn semi_implicit_euler_batch(
    bodies: &mut [RigidBody],
    lanes: &[usize; MAX_LANES],
    count: usize,
    gravity_world: DVec3,
    h: f64,
) -> u32 {
    if let Some(diverging) = semi_implicit_euler_x8_avx512(bodies, lanes, count, gravity_world, h) {
        return diverging;
    }
    assert!(count <= LANES, "{count} bodies in a batch of {LANES}");
    let four = core::array::from_fn(|k| lanes[k.min(count - 1)]);
    semi_implicit_euler_x4(bodies, &four, count, gravity_world, h)
}

/// [`semi_implicit_euler_batch`] in eight AVX-512 lanes, or `None` where the CPU lacks AVX-512F (the
/// batch's own first choice; public to drive the eight-lane kernel directly in tests and benchmarks).
pub fn semi_implicit_euler_x8_avx512(
    bodies: &mut [RigidBody],
    lanes: &[usize; MAX_LANES],
    count: usize,
    gravity_world: DVec3,
    h: f64,
) -> Option<u32> {
    #[cfg(target_arch = "x86_64")]
    if has_avx512() {
        // SAFETY: the CPU has AVX-512F
        #[allow(unsafe_code)]
        return Some(unsafe { x8_avx512(bodies, lanes, count, gravity_world, h) });
    }
    let _ = (bodies, lanes, count, gravity_world, h);
    None
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
    step::<f64x4>(bodies, lanes, count, gravity_world, h)
}

/// [`semi_implicit_euler_x4`] compiled for AVX2, in [`Avx`] lanes.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn x4_avx2(bodies: &mut [RigidBody], lanes: &[usize; LANES], count: usize, gravity_world: DVec3, h: f64) -> u32 {
    step::<Avx>(bodies, lanes, count, gravity_world, h)
}

/// [`semi_implicit_euler_batch`] compiled for AVX-512F, in [`Avx512`] lanes (no FMA: `avx512f`
/// does not enable it).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn x8_avx512(bodies: &mut [RigidBody], lanes: &[usize; MAX_LANES], count: usize, gravity_world: DVec3, h: f64) -> u32 {
    step::<Avx512>(bodies, lanes, count, gravity_world, h)
}

/// The constants of `N` bodies' step, in lanes (from the bodies' rows, or from a [`Block`]).
#[derive(Clone, Copy)]
struct Params<L> {
    mass: L,
    inertia: V3<L>,
    inv_mass: L,
    inv_inertia: V3<L>,
    /// `f_world` of the loads (the body-frame force is zero: the bodies are batchable).
    force_load: V3<L>,
    /// `τ_body` of the loads.
    torque_load: V3<L>,
    linear_damping: L,
    angular_damping: L,
    gravity_scale: L,
    /// `ε/(h|ω|) = ΔI/I_min`, as in `implicit_gyroscopic`: `(max I − min I) max I⁻¹`.
    spread: L,
}

/// The state of `N` bodies in lanes: `x`, `q` (`x, y, z, w`), `v`, `ω_body`.
#[derive(Clone, Copy)]
struct State<L> {
    position: V3<L>,
    orientation: [L; 4],
    velocity: V3<L>,
    omega: V3<L>,
}

/// The step in lanes `L`, on the bodies `lanes[..count]` (`lanes.len() >= L::N`): gathered by rows,
/// advanced, scattered by rows.
#[inline(always)]
fn step<L: BatchLanes>(bodies: &mut [RigidBody], lanes: &[usize], count: usize, gravity_world: DVec3, h: f64) -> u32 {
    debug_assert!((1..=L::N).contains(&count) && lanes.len() >= L::N);
    let index: [usize; MAX_LANES] = core::array::from_fn(|k| if k < count { lanes[k] } else { lanes[0] });
    let group: [&RigidBody; MAX_LANES] = core::array::from_fn(|k| &bodies[index[k]]);
    let (params, state) = gather::<L>(&group);
    let (state, insane) = advance(&params, state, gravity_world, h);
    scatter(&state, &index, count, bodies);
    insane & ((1 << count) - 1)
}

/// The parameters (constants of each body) and the states of the group's bodies: rows of four
/// adjacent fields of each body (one load each where the layout has them adjacent, see `Row`),
/// transposed into lanes.
#[inline(always)]
fn gather<L: BatchLanes>(group: &[&RigidBody; MAX_LANES]) -> (Params<L>, State<L>) {
    let [mass, ix, iy, iz] = rows::<L>(group, ROW_MASS, |b| {
        let i = b.mass.inertia_body;
        [b.mass.mass, i.x, i.y, i.z]
    });
    let [inv_mass, jx, jy, jz] = rows::<L>(group, ROW_INV_MASS, |b| {
        let j = b.mass.inv_inertia_body;
        [b.mass.inv_mass, j.x, j.y, j.z]
    });
    let [tx, ty, tz, linear_damping] = rows::<L>(group, ROW_TORQUE, |b| {
        let t = b.loads.torque_body;
        [t.x, t.y, t.z, b.loads.linear_damping]
    });
    // (the body-frame force is zero: the body is batchable)
    let [fx, fy, fz, _] = rows::<L>(group, ROW_FORCE, |b| {
        let f = b.loads.force_world;
        [f.x, f.y, f.z, b.loads.force_body.x]
    });
    let [_, _, _, angular_damping] = rows::<L>(group, ROW_DAMPING, |b| {
        let l = &b.loads;
        [l.torque_body.y, l.torque_body.z, l.linear_damping, l.angular_damping]
    });
    let (inertia, inv_inertia) = (V3 { x: ix, y: iy, z: iz }, V3 { x: jx, y: jy, z: jz });
    // `DVec3::max_element`'s and `min_element`'s comparisons in the same order (NaNs included)
    let max_i = inertia.x.cmp_max(inertia.y.cmp_max(inertia.z));
    let min_i = inertia.x.cmp_min(inertia.y.cmp_min(inertia.z));
    let max_j = inv_inertia.x.cmp_max(inv_inertia.y.cmp_max(inv_inertia.z));
    let [px, py, pz, qx] = rows::<L>(group, ROW_STATE[0], |b| {
        let s = &b.state;
        [s.position.x, s.position.y, s.position.z, s.orientation.x]
    });
    let [qy, qz, qw, vx] = rows::<L>(group, ROW_STATE[1], |b| {
        let s = &b.state;
        [s.orientation.y, s.orientation.z, s.orientation.w, s.velocity.x]
    });
    let [vy, vz, wx, wy] = rows::<L>(group, ROW_STATE[2], |b| {
        let s = &b.state;
        [s.velocity.y, s.velocity.z, s.omega_body.x, s.omega_body.y]
    });
    let [_, _, wz, gravity_scale] = rows::<L>(group, ROW_STATE[3], |b| {
        let w = b.state.omega_body;
        [w.x, w.y, w.z, b.gravity_scale]
    });
    let params = Params {
        mass,
        inertia,
        inv_mass,
        inv_inertia,
        force_load: V3 { x: fx, y: fy, z: fz },
        torque_load: V3 { x: tx, y: ty, z: tz },
        linear_damping,
        angular_damping,
        gravity_scale,
        spread: (max_i - min_i) * max_j,
    };
    let state = State {
        position: V3 { x: px, y: py, z: pz },
        orientation: [qx, qy, qz, qw],
        velocity: V3 { x: vx, y: vy, z: vz },
        omega: V3 { x: wx, y: wy, z: wz },
    };
    (params, state)
}

/// Writes lanes `..count` of `state` into the bodies `index[..count]`: the state's rows, transposed
/// back.
#[inline(always)]
fn scatter<L: BatchLanes>(state: &State<L>, index: &[usize], count: usize, bodies: &mut [RigidBody]) {
    let (p, q, v, o) = (state.position, state.orientation, state.velocity, state.omega);
    L::to_rows([p.x, p.y, p.z, q[0]], |k, row| {
        if k < count {
            ROW_STATE[0].write(&mut bodies[index[k]], row, |b, [x, y, z, qx]| {
                (b.state.position, b.state.orientation.x) = (DVec3::new(x, y, z), qx);
            });
        }
    });
    L::to_rows([q[1], q[2], q[3], v.x], |k, row| {
        if k < count {
            ROW_STATE[1].write(&mut bodies[index[k]], row, |b, [qy, qz, qw, vx]| {
                let s = &mut b.state;
                (s.orientation.y, s.orientation.z, s.orientation.w, s.velocity.x) = (qy, qz, qw, vx);
            });
        }
    });
    L::to_rows([v.y, v.z, o.x, o.y], |k, row| {
        if k < count {
            ROW_STATE[2].write(&mut bodies[index[k]], row, |b, [vy, vz, wx, wy]| {
                let s = &mut b.state;
                (s.velocity.y, s.velocity.z, s.omega_body.x, s.omega_body.y) = (vy, vz, wx, wy);
            });
        }
    });
    for (k, &i) in index.iter().enumerate().take(count) {
        bodies[i].state.omega_body.z = o.z.lane(k);
    }
}

/// One semi-implicit Euler step of `h` seconds of `N` bodies in lanes, under the world's gravity
/// `gravity_world`: the scalar step's operations in the same order, the rare branches in scalar
/// code for the lanes that take them. Returns the new states and the lanes (bit `k`, all `N`) whose
/// new state fails the quick sanity test of the world's divergence check (a magnitude above
/// `MAX_STATE_MAGNITUDE`, a NaN, or `|q|² > 4`).
#[inline(always)]
fn advance<L: BatchLanes>(p: &Params<L>, s: State<L>, gravity_world: DVec3, h: f64) -> (State<L>, u32) {
    let all = (1u32 << L::N) - 1;
    let hv = L::splat(h);
    // g_body = s g, as `RigidBody::gravity`
    let gravity = V3 { x: L::splat(gravity_world.x), y: L::splat(gravity_world.y), z: L::splat(gravity_world.z) }
        .scale(p.gravity_scale);
    let (mass, inertia, inv_mass, inv_inertia) = (p.mass, p.inertia, p.inv_mass, p.inv_inertia);
    let (mut position, mut velocity, omega) = (s.position, s.velocity, s.omega);

    // resultant: f = m g + f_load − (c m) v ;  τ = τ_load − c (I ω)
    let force = gravity.scale(mass).add(p.force_load).sub(velocity.scale(p.linear_damping * mass));
    let torque = p.torque_load.sub(inertia.mul(omega).scale(p.angular_damping));
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
    let spread = p.spread;
    let small = (hv * hv * w.length_squared() * spread * spread).le(L::splat(0.05 * 0.05));
    // the residual test only where the step is not small (the scalar `small || …`)
    let converged = if L::bits(small) == all {
        small
    } else {
        let residual_after = l_after.sub(l_before).add(omega_new.cross(l_after).scale(hv));
        small | residual_after.length_squared().le(L::splat(1e-6) * l_before.length_squared())
    };
    let rejected = !L::bits(converged & kept) & all;
    if rejected != 0 {
        for k in (0..L::N).filter(|k| rejected & (1 << k) != 0) {
            set_lane3(&mut omega_new, k, finish_implicit_gyroscopic(lane3(i, k), lane3(w, k), h));
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
    let large = !L::bits(x2.lt(L::splat(0.01))) & all;
    if large != 0 {
        for k in (0..L::N).filter(|k| large & (1 << k) != 0) {
            let exp = quat_exp(lane3(phi, k));
            for (component, value) in e.iter_mut().zip([exp.x, exp.y, exp.z, exp.w]) {
                component.set_lane(k, value);
            }
        }
    }
    // as `DQuat::mul_quat`
    let ([x0, y0, z0, w0], [x1, y1, z1, w1]) = (s.orientation, e);
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
    let far = !L::bits(near) & all;

    // the quick sanity test of `check_state`
    let max2 = L::splat(MAX_STATE_MAGNITUDE * MAX_STATE_MAGNITUDE);
    let sane =
        position.length_squared().le(max2) & velocity.length_squared().le(max2) & omega_new.length_squared().le(max2);
    // |q|² of the stored quaternion, summed as `DQuat::length_squared` (the far lanes are redone)
    let q2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
    let mut insane = (!L::bits(sane) | (!L::bits(q2.le(L::splat(4.0))) & !far)) & all;
    // exact normalisation where |q|² was far from 1 (rare)
    if far != 0 {
        for k in (0..L::N).filter(|&k| far & (1 << k) != 0) {
            let qu = q_unrenormalized.map(|c| c.lane(k));
            let normalized = DQuat::from_xyzw(qu[0], qu[1], qu[2], qu[3]).normalize();
            for (component, value) in q.iter_mut().zip([normalized.x, normalized.y, normalized.z, normalized.w]) {
                component.set_lane(k, value);
            }
            if normalized.length_squared() > 4.0 || normalized.length_squared().is_nan() {
                insane |= 1 << k;
            }
        }
    }
    (State { position, orientation: q, velocity, omega: omega_new }, insane)
}

/// Bodies per [`Block`]: eight, the widest lanes; four-lane CPUs step a block in two halves.
pub(crate) const BLOCK: usize = MAX_LANES;

/// The numbers of a body's state in a [`Block`]: `x`, `q` (`x, y, z, w`), `v`, `ω_body`.
const STATE_LEN: usize = 13;

/// The constants of a body's step in a [`Block`], in this order: `m`, `I`, `1/m`, `I⁻¹`, `f_world`,
/// `τ_body`, `c_lin`, `c_ang`, the gravity scale and the spread `(max I − min I) max I⁻¹`.
const PARAM_LEN: usize = 18;

/// Up to eight batchable bodies' step data as a structure of arrays: each number of the step is
/// eight lanes, one per body, so that the step loads its lanes directly (no transposes) from 352
/// bytes per body instead of the seven cache lines of a `RigidBody` it reads through rows. The
/// state is kept twice: the step reads state `parity` and writes state `1 − parity`, so that the
/// state from before the step stays here (for the undo of a step that diverges). Lanes `count..`
/// repeat lane 0 (stepped, never written out).
///
/// A copy of the bodies: valid only while they are not changed elsewhere (the world keeps it with
/// the seal of its [`Bodies`](crate::world::Bodies)).
#[derive(Clone)]
#[repr(C, align(64))]
pub(crate) struct Block {
    /// `state[b][j][k]`: number `j` of the state of lane `k`, copy `b`.
    state: [[[f64; BLOCK]; STATE_LEN]; 2],
    /// `params[j][k]`: constant `j` of lane `k`.
    params: [[f64; BLOCK]; PARAM_LEN],
    /// The bodies' indices in the world's list, lanes `count..` repeating lane 0.
    index: [usize; BLOCK],
    count: usize,
}

impl Block {
    /// The block of the bodies `indices` (1 to 8 distinct indices of batchable bodies), their states
    /// as both copies.
    pub(crate) fn new(bodies: &[RigidBody], indices: &[usize]) -> Self {
        let count = indices.len();
        assert!((1..=BLOCK).contains(&count), "{count} bodies in a block of {BLOCK}");
        let mut block = Block {
            state: [[[0.0; BLOCK]; STATE_LEN]; 2],
            params: [[0.0; BLOCK]; PARAM_LEN],
            index: core::array::from_fn(|k| if k < count { indices[k] } else { indices[0] }),
            count,
        };
        for k in 0..BLOCK {
            let body = &bodies[block.index[k]];
            debug_assert!(batchable(body));
            let s = &body.state;
            let (x, q, v, w) = (s.position, s.orientation, s.velocity, s.omega_body);
            let state = [x.x, x.y, x.z, q.x, q.y, q.z, q.w, v.x, v.y, v.z, w.x, w.y, w.z];
            let (m, l) = (&body.mass, &body.loads);
            let (i, j, f, t) = (m.inertia_body, m.inv_inertia_body, l.force_world, l.torque_body);
            // as `implicit_gyroscopic`
            let spread = (i.max_element() - i.min_element()) * j.max_element();
            let params = [
                m.mass,
                i.x,
                i.y,
                i.z,
                m.inv_mass,
                j.x,
                j.y,
                j.z,
                f.x,
                f.y,
                f.z,
                t.x,
                t.y,
                t.z,
                l.linear_damping,
                l.angular_damping,
                body.gravity_scale,
                spread,
            ];
            for copy in &mut block.state {
                for (row, value) in copy.iter_mut().zip(state) {
                    row[k] = value;
                }
            }
            for (row, value) in block.params.iter_mut().zip(params) {
                row[k] = value;
            }
        }
        block
    }

    /// The indices of the block's bodies.
    pub(crate) fn indices(&self) -> &[usize] {
        &self.index[..self.count]
    }

    /// Writes state copy `parity` of the block's bodies into `bodies` (the undo).
    pub(crate) fn restore(&self, parity: usize, bodies: &mut [RigidBody]) {
        let n = &self.state[parity];
        for (k, &i) in self.indices().iter().enumerate() {
            let s = &mut bodies[i].state;
            s.position = DVec3::new(n[0][k], n[1][k], n[2][k]);
            s.orientation = DQuat::from_xyzw(n[3][k], n[4][k], n[5][k], n[6][k]);
            s.velocity = DVec3::new(n[7][k], n[8][k], n[9][k]);
            s.omega_body = DVec3::new(n[10][k], n[11][k], n[12][k]);
        }
    }

    /// The constants of lanes `start..start + N`.
    #[inline(always)]
    fn params<L: BatchLanes>(&self, start: usize) -> Params<L> {
        let p = &self.params;
        Params {
            mass: lanes_at(&p[0], start),
            inertia: V3 { x: lanes_at(&p[1], start), y: lanes_at(&p[2], start), z: lanes_at(&p[3], start) },
            inv_mass: lanes_at(&p[4], start),
            inv_inertia: V3 { x: lanes_at(&p[5], start), y: lanes_at(&p[6], start), z: lanes_at(&p[7], start) },
            force_load: V3 { x: lanes_at(&p[8], start), y: lanes_at(&p[9], start), z: lanes_at(&p[10], start) },
            torque_load: V3 { x: lanes_at(&p[11], start), y: lanes_at(&p[12], start), z: lanes_at(&p[13], start) },
            linear_damping: lanes_at(&p[14], start),
            angular_damping: lanes_at(&p[15], start),
            gravity_scale: lanes_at(&p[16], start),
            spread: lanes_at(&p[17], start),
        }
    }

    /// State copy `parity` of lanes `start..start + N`.
    #[inline(always)]
    fn state<L: BatchLanes>(&self, parity: usize, start: usize) -> State<L> {
        let n = &self.state[parity];
        State {
            position: V3 { x: lanes_at(&n[0], start), y: lanes_at(&n[1], start), z: lanes_at(&n[2], start) },
            orientation: [
                lanes_at(&n[3], start),
                lanes_at(&n[4], start),
                lanes_at(&n[5], start),
                lanes_at(&n[6], start),
            ],
            velocity: V3 { x: lanes_at(&n[7], start), y: lanes_at(&n[8], start), z: lanes_at(&n[9], start) },
            omega: V3 { x: lanes_at(&n[10], start), y: lanes_at(&n[11], start), z: lanes_at(&n[12], start) },
        }
    }

    /// Sets state copy `parity` of lanes `start..start + N`.
    #[inline(always)]
    fn set_state<L: BatchLanes>(&mut self, parity: usize, start: usize, s: &State<L>) {
        let n = &mut self.state[parity];
        let q = s.orientation;
        let numbers = [
            s.position.x,
            s.position.y,
            s.position.z,
            q[0],
            q[1],
            q[2],
            q[3],
            s.velocity.x,
            s.velocity.y,
            s.velocity.z,
        ];
        for (row, value) in n.iter_mut().zip(numbers) {
            value.store(&mut row[start..]);
        }
        s.omega.x.store(&mut n[10][start..]);
        s.omega.y.store(&mut n[11][start..]);
        s.omega.z.store(&mut n[12][start..]);
    }
}

/// Lanes `start..start + N` of a block's row.
#[inline(always)]
fn lanes_at<L: BatchLanes>(row: &[f64; BLOCK], start: usize) -> L {
    L::load(&row[start..])
}

/// Advances the bodies of every block by one semi-implicit Euler step of `h` seconds under the
/// world's gravity `gravity_world` (m/s², world frame), from state copy `parity` to copy
/// `1 − parity`, and writes each new state into `bodies` as well: bit for bit the step of
/// [`semi_implicit_euler_batch`]. Eight lanes in AVX-512 registers where the CPU has AVX-512F, four
/// (a block in two halves) in AVX registers where it has AVX2, `wide::f64x4` otherwise.
///
/// Stops at the first block with a body whose new state fails the quick sanity test of the world's
/// divergence check: `Err(j)`, blocks `..j` stepped and written, block `j` possibly in part (its
/// first half); the caller restores them ([`Block::restore`]) and names the body with the full check.
pub(crate) fn step_blocks(
    blocks: &mut [Block],
    parity: usize,
    bodies: &mut [RigidBody],
    gravity_world: DVec3,
    h: f64,
) -> Result<(), usize> {
    #[cfg(target_arch = "x86_64")]
    if has_avx512() {
        // SAFETY: the CPU has AVX-512F
        #[allow(unsafe_code)]
        return unsafe { blocks_avx512(blocks, parity, bodies, gravity_world, h) };
    }
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2
        #[allow(unsafe_code)]
        return unsafe { blocks_avx2(blocks, parity, bodies, gravity_world, h) };
    }
    step_blocks_portable(blocks, parity, bodies, gravity_world, h)
}

/// [`step_blocks`] in `wide::f64x4` lanes whatever the CPU: the portable path, for tests.
pub(crate) fn step_blocks_portable(
    blocks: &mut [Block],
    parity: usize,
    bodies: &mut [RigidBody],
    gravity_world: DVec3,
    h: f64,
) -> Result<(), usize> {
    blocks_in::<f64x4>(blocks, parity, bodies, gravity_world, h)
}

/// [`step_blocks`] compiled for AVX2, in [`Avx`] lanes.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn blocks_avx2(
    blocks: &mut [Block],
    parity: usize,
    bodies: &mut [RigidBody],
    gravity_world: DVec3,
    h: f64,
) -> Result<(), usize> {
    blocks_in::<Avx>(blocks, parity, bodies, gravity_world, h)
}

/// [`step_blocks`] compiled for AVX-512F, in [`Avx512`] lanes.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn blocks_avx512(
    blocks: &mut [Block],
    parity: usize,
    bodies: &mut [RigidBody],
    gravity_world: DVec3,
    h: f64,
) -> Result<(), usize> {
    blocks_in::<Avx512>(blocks, parity, bodies, gravity_world, h)
}

/// [`step_blocks`] in lanes `L`.
#[inline(always)]
fn blocks_in<L: BatchLanes>(
    blocks: &mut [Block],
    parity: usize,
    bodies: &mut [RigidBody],
    gravity_world: DVec3,
    h: f64,
) -> Result<(), usize> {
    for (j, block) in blocks.iter_mut().enumerate() {
        let mut start = 0;
        while start < block.count {
            let count = (block.count - start).min(L::N);
            let (state, insane) = advance(&block.params::<L>(start), block.state::<L>(parity, start), gravity_world, h);
            if insane & ((1 << count) - 1) != 0 {
                return Err(j);
            }
            block.set_state(1 - parity, start, &state);
            scatter(&state, &block.index[start..], count, bodies);
            start += L::N;
        }
    }
    Ok(())
}
