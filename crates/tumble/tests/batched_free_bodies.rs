//! The batched `semi_implicit_euler` path of `World::step` (four bodies per `f64x4` or AVX register,
//! eight per AVX-512 register, `integrate::batch`) against the scalar per-body step
//! (`advance_body`): bit-identical states over many steps on random bodies, each kernel driven
//! directly too; the divergence check naming the first bad body in scene order and undoing the
//! step; the integration pass's look for a body with a shape (the contact stage's work) seeing the
//! bodies' edits; and no allocation per step.
//!
//! The allocator counts the allocations of each thread separately, so that the test harness's own
//! threads do not disturb the count.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use tumble::body::{Frame, Loads, PointForce, Shape};
use tumble::integrate::batch::{
    batchable, semi_implicit_euler_x4, semi_implicit_euler_x4_portable, semi_implicit_euler_x8_avx512, LANES, MAX_LANES,
};
use tumble::integrate::{advance_body, BodyRhs, Tolerances};
use tumble::math::{quat_exp, DQuat, DVec3};
use tumble::{Integrator, MassProperties, RigidBody, World, WorldConfig};

struct Counting;

thread_local! {
    /// Allocations (and reallocations) made by this thread.
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

fn count() {
    // `try_with`: the slot may be gone while the thread ends
    let _ = ALLOCATIONS.try_with(|n| n.set(n.get() + 1));
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// A small deterministic generator (xorshift).
struct Rng(u64);

impl Rng {
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        lo + (hi - lo) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
    }
    fn vec(&mut self, r: f64) -> DVec3 {
        DVec3::new(self.uniform(-r, r), self.uniform(-r, r), self.uniform(-r, r))
    }
    fn chance(&mut self, p: f64) -> bool {
        self.uniform(0.0, 1.0) < p
    }
}

/// `n` random bodies: random masses and principal moments (triangle inequality kept), states,
/// gravity scales, loads (world forces, body torques, damping; one in eight with an
/// orientation-dependent load, which takes the scalar step), one in ten fixed, one in twenty
/// spinning at several radians per step (the implicit solve's continuation and `quat_exp`'s
/// `sin_cos`), one in twenty with `|q|²` off by 1e-3 (exact normalisation).
fn random_bodies(seed: u64, n: usize) -> Vec<RigidBody> {
    let mut rng = Rng(seed);
    (0..n)
        .map(|i| {
            let (a, b) = (rng.uniform(0.2, 3.0), rng.uniform(0.2, 3.0));
            let c = rng.uniform((a - b).abs() + 0.05, a + b);
            let mass = MassProperties::from_principal(rng.uniform(0.1, 10.0), DVec3::new(a, b, c)).unwrap();
            let mut body = RigidBody::new(format!("body{i}"), mass);
            body.state.position = rng.vec(10.0);
            body.state.velocity = rng.vec(3.0);
            body.state.orientation = quat_exp(rng.vec(3.0));
            body.state.omega_body = rng.vec(5.0);
            body.gravity_scale = rng.uniform(-1.0, 2.0);
            body.loads = Loads {
                force_world: rng.vec(2.0),
                torque_body: rng.vec(1.0),
                linear_damping: if rng.chance(0.5) { rng.uniform(0.0, 0.5) } else { 0.0 },
                angular_damping: if rng.chance(0.5) { rng.uniform(0.0, 0.5) } else { 0.0 },
                ..Loads::default()
            };
            if rng.chance(0.125) {
                body.loads.force_body = rng.vec(1.0);
                body.loads.point_forces.push(PointForce {
                    point_body: rng.vec(0.5),
                    force: rng.vec(1.0),
                    frame: Frame::World,
                });
            }
            body.fixed = rng.chance(0.1);
            if rng.chance(0.05) {
                body.state.omega_body = rng.vec(3000.0);
            }
            if rng.chance(0.05) {
                body.state.orientation *= 1.0 + 5e-4;
            }
            body
        })
        .collect()
}

fn config() -> WorldConfig {
    WorldConfig {
        integrator: Integrator::SemiImplicitEuler,
        dt: 1e-3,
        gravity: DVec3::new(0.3, -0.2, -9.81),
        ..Default::default()
    }
}

/// One step of every free body with the scalar integrator, as `World::step` did before the
/// batched path.
fn scalar_step(bodies: &mut [RigidBody], config: &WorldConfig) {
    for body in bodies.iter_mut().filter(|b| !b.fixed) {
        let rhs = BodyRhs { mass: &body.mass, loads: &body.loads, gravity_world: body.gravity(config.gravity) };
        let mut hint = 0.0;
        advance_body(config.integrator, Tolerances::default(), &rhs, &mut body.state, config.dt, &mut hint).unwrap();
    }
}

fn bits(body: &RigidBody) -> [u64; 13] {
    let s = &body.state;
    let v = [
        s.position.x,
        s.position.y,
        s.position.z,
        s.orientation.x,
        s.orientation.y,
        s.orientation.z,
        s.orientation.w,
        s.velocity.x,
        s.velocity.y,
        s.velocity.z,
        s.omega_body.x,
        s.omega_body.y,
        s.omega_body.z,
    ];
    v.map(f64::to_bits)
}

/// One step of the world and of the reference list by the scalar step; the states must be the same
/// bits (`what` names the case in the message).
fn step_both(world: &mut World, reference: &mut [RigidBody], config: &WorldConfig, what: &str) {
    world.step().unwrap();
    scalar_step(reference, config);
    for (a, b) in world.bodies.iter().zip(reference.iter()) {
        assert_eq!(bits(a), bits(b), "{what}, body {}: {:?} vs {:?}", a.name, a.state, b.state);
    }
}

#[test]
fn batched_semi_implicit_euler_is_bit_identical_to_the_scalar_step() {
    // counts that leave 0..3 bodies in the last group
    for (seed, n) in [(1, 1), (2, 3), (3, 4), (4, 7), (5, 64), (6, 201), (7, 1002)] {
        let config = config();
        let mut reference = random_bodies(seed, n);
        let mut world = World::new(config, reference.clone());
        for step in 0..300 {
            world.step().unwrap();
            scalar_step(&mut reference, &config);
            for (a, b) in world.bodies.iter().zip(&reference) {
                assert_eq!(
                    bits(a),
                    bits(b),
                    "seed {seed}, n {n}, step {step}, body {}: {:?} vs {:?}",
                    a.name,
                    a.state,
                    b.state
                );
            }
        }
    }
}

/// A step of `N` lanes: `semi_implicit_euler_x4` or its portable twin (`N = 4`), the AVX-512 one
/// (`N = 8`).
type Kernel<const N: usize> = fn(&mut [RigidBody], &[usize; N], usize, DVec3, f64) -> u32;

/// The `N`-lane kernel `kernel` applied directly to every batchable body of `bodies` (groups of up
/// to `N` in order; the others take the scalar step), as `World::step` drives it.
fn kernel_step<const N: usize>(kernel: Kernel<N>, bodies: &mut [RigidBody], config: &WorldConfig) {
    let lanes: Vec<usize> = (0..bodies.len()).filter(|&i| batchable(&bodies[i])).collect();
    for group in lanes.chunks(N) {
        let mut indices = [group[0]; N];
        indices[..group.len()].copy_from_slice(group);
        assert_eq!(kernel(bodies, &indices, group.len(), config.gravity, config.dt), 0);
    }
    for body in bodies.iter_mut().filter(|b| !b.fixed && !batchable(b)) {
        let rhs = BodyRhs { mass: &body.mass, loads: &body.loads, gravity_world: body.gravity(config.gravity) };
        let mut hint = 0.0;
        advance_body(config.integrator, Tolerances::default(), &rhs, &mut body.state, config.dt, &mut hint).unwrap();
    }
}

#[test]
fn the_portable_and_the_dispatched_kernels_give_the_scalar_bits() {
    // the dispatched kernel runs AVX lanes where the CPU has AVX2, the portable one `wide::f64x4`
    // lanes (SSE2 in the default build): both must reproduce the scalar step
    for (seed, n) in [(51, 5), (52, 6), (53, 7), (54, 203)] {
        let config = config();
        let mut reference = random_bodies(seed, n);
        let mut portable = reference.clone();
        let mut dispatched = reference.clone();
        for step in 0..200 {
            scalar_step(&mut reference, &config);
            kernel_step::<LANES>(semi_implicit_euler_x4_portable, &mut portable, &config);
            kernel_step::<LANES>(semi_implicit_euler_x4, &mut dispatched, &config);
            for ((a, b), c) in portable.iter().zip(&dispatched).zip(&reference) {
                assert_eq!(bits(a), bits(c), "portable, seed {seed}, step {step}, body {}", a.name);
                assert_eq!(bits(b), bits(c), "dispatched, seed {seed}, step {step}, body {}", b.name);
            }
        }
    }
}

#[test]
fn the_eight_lane_kernel_gives_the_scalar_bits() {
    // AVX-512 lanes, where the CPU has AVX-512F (else the world's step uses four lanes, tested above)
    #[cfg(target_arch = "x86_64")]
    let avx512 = std::arch::is_x86_feature_detected!("avx512f");
    #[cfg(not(target_arch = "x86_64"))]
    let avx512 = false;
    if !avx512 {
        eprintln!("no AVX-512F on this CPU: the eight-lane kernel is not run");
        return;
    }
    let kernel: Kernel<MAX_LANES> =
        |bodies, lanes, count, gravity, h| semi_implicit_euler_x8_avx512(bodies, lanes, count, gravity, h).unwrap();
    // counts that leave 1..7 bodies in the last group, and many groups
    for (seed, n) in [(71, 1), (72, 9), (73, 11), (74, 14), (75, 16), (76, 203), (77, 1001)] {
        let config = config();
        let mut reference = random_bodies(seed, n);
        let mut eight = reference.clone();
        for step in 0..200 {
            scalar_step(&mut reference, &config);
            kernel_step::<MAX_LANES>(kernel, &mut eight, &config);
            for (a, b) in eight.iter().zip(&reference) {
                assert_eq!(bits(a), bits(b), "seed {seed}, n {n}, step {step}, body {}", a.name);
            }
        }
    }
}

/// `bodies` with a fixed ground plane (its normal world z) and a ball of radius 0.5 m sunk 5 cm into
/// it, put at index `ball`; the ball has no shape yet.
fn with_ground_and_ball(mut bodies: Vec<RigidBody>, ball: usize) -> Vec<RigidBody> {
    let mut ground = RigidBody::new("ground", MassProperties::from_principal(1.0, DVec3::ONE).unwrap());
    ground.fixed = true;
    ground.shape = Some(Shape::Plane);
    let mut b = RigidBody::new("ball", MassProperties::from_principal(1.0, DVec3::splat(0.1)).unwrap());
    b.state.position = DVec3::new(0.0, 0.0, 0.45);
    bodies.insert(ball, b);
    bodies.push(ground);
    bodies
}

#[test]
fn a_shape_given_or_taken_between_steps_is_seen() {
    // Whether the contact stage has work (a moving body with a shape) is found by the integration
    // pass itself, and the last body found is remembered and checked again at each step: every
    // change of a shape or of the fixed flag between steps must be seen. The ball, sunk into the
    // ground, is pushed out by the contact stage whenever it runs, and falls freely otherwise; the
    // other bodies (no shape) take the scalar step whatever happens, never two.
    let config = config();
    let ball = 23;
    let mut world = World::new(config, with_ground_and_ball(random_bodies(81, 40), ball));
    let mut reference = world.bodies.clone();
    let sphere = Some(Shape::Sphere { radius: 0.5 });
    for step in 0..80 {
        let edit = match step {
            10 | 30 | 70 => Some((sphere.clone(), false)),
            20 | 60 => Some((None, false)),
            40 => Some((sphere.clone(), true)),
            50 => Some((sphere.clone(), false)),
            _ => None,
        };
        if let Some((shape, fixed)) = edit.clone() {
            for body in [&mut world.bodies[ball], &mut reference[ball]] {
                body.shape = shape.clone();
                body.fixed = fixed;
                // sunk again, at rest: the contact stage pushes it if it runs
                body.state.position = DVec3::new(0.0, 0.0, 0.45);
                body.state.velocity = DVec3::ZERO;
            }
        }
        let contacts = world.bodies[ball].shape.is_some() && !world.bodies[ball].fixed;
        world.step().unwrap();
        scalar_step(&mut reference, &config);
        for (i, (a, b)) in world.bodies.iter().zip(&reference).enumerate() {
            if i != ball {
                assert_eq!(bits(a), bits(b), "step {step}, body {}", a.name);
            }
        }
        let (a, b) = (&world.bodies[ball], &reference[ball]);
        if !contacts {
            assert_eq!(bits(a), bits(b), "step {step}: the ball falls freely");
        } else if edit.is_some() {
            // the step right after the edit: sunk 5 cm, the ball is pushed up (falling freely, it
            // would sink further)
            assert!(a.state.position.z > 0.45, "step {step}: the ball is not pushed: {:?}", a.state);
            assert!(b.state.position.z < 0.45);
        }
        reference[ball] = world.bodies[ball].clone();
    }
}

#[test]
fn a_divergence_before_a_body_with_a_shape_is_named_after_the_contact_stage() {
    // the first body diverges; a later one has a shape, so the contact stage runs first (the pass
    // that found the divergence is undone, the step redone with contacts) and the error is the same
    let config = config();
    for ball in [1, 9, 30] {
        let mut bodies = random_bodies(91, 30);
        bodies[0].fixed = false;
        bodies[0].loads = Loads { force_world: DVec3::new(1e15 * bodies[0].mass.mass, 0.0, 0.0), ..Loads::default() };
        let mut bodies = with_ground_and_ball(bodies, ball);
        bodies[ball].shape = Some(Shape::Sphere { radius: 0.5 });
        let mut world = World::new(config, bodies);
        let before = world.bodies.to_vec();
        let err = world.step().unwrap_err().diverged().cloned().unwrap();
        assert_eq!(err.body, "body0", "{err}");
        assert!(err.quantity.contains("velocity"), "{err}");
        assert_eq!(world.steps(), 0);
        for (a, b) in world.bodies.iter().zip(&before) {
            assert_eq!(bits(a), bits(b), "body {} was not restored", a.name);
        }
        // without the ball's shape, the same error from the pass without contacts
        let mut world = World::new(config, before.clone());
        world.bodies[ball].shape = None;
        assert_eq!(world.step().unwrap_err().diverged(), Some(&err));
        for (a, b) in world.bodies.iter().zip(&before) {
            assert_eq!(bits(a), bits(b), "body {} was not restored", a.name);
        }
    }
}

#[test]
fn bodies_changed_between_steps_are_stepped_from_their_new_state() {
    // the users' `world.bodies` stays the source of truth: edits between steps are seen
    let config = config();
    let mut reference = random_bodies(11, 37);
    let mut world = World::new(config, reference.clone());
    let mut rng = Rng(99);
    for step in 0..100 {
        let i = (rng.uniform(0.0, 37.0) as usize).min(36);
        let kick = rng.vec(1.0);
        world.bodies[i].state.velocity += kick;
        reference[i].state.velocity += kick;
        world.bodies[i].loads.torque_body = kick;
        reference[i].loads.torque_body = kick;
        // every parameter the four-lane step reads, changed on another body
        let j = (rng.uniform(0.0, 37.0) as usize).min(36);
        let (a, b) = (rng.uniform(0.2, 3.0), rng.uniform(0.2, 3.0));
        let c = rng.uniform((a - b).abs() + 0.05, a + b);
        let mass = MassProperties::from_principal(rng.uniform(0.1, 10.0), DVec3::new(a, b, c)).unwrap();
        let (force, scale) = (rng.vec(2.0), rng.uniform(-1.0, 2.0));
        let (linear, angular) = (rng.uniform(0.0, 0.5), rng.uniform(0.0, 0.5));
        let fixed = rng.chance(0.2);
        for body in [&mut world.bodies[j], &mut reference[j]] {
            body.mass = mass;
            body.loads.force_world = force;
            body.loads.linear_damping = linear;
            body.loads.angular_damping = angular;
            body.gravity_scale = scale;
            body.fixed = fixed;
        }
        step_both(&mut world, &mut reference, &config, &format!("step {step}"));
    }
}

/// `n` random bodies, all moving and batchable, spinning at most 5 rad/s with unit quaternions:
/// none diverges unless a test makes it.
fn calm_bodies(seed: u64, n: usize) -> Vec<RigidBody> {
    let mut bodies = random_bodies(seed, n);
    for b in &mut bodies {
        b.fixed = false;
        b.loads.force_body = DVec3::ZERO;
        b.loads.point_forces.clear();
        b.state.omega_body = b.state.omega_body.clamp_length_max(5.0);
        b.state.orientation = b.state.orientation.normalize();
    }
    bodies
}

#[test]
fn a_diverging_body_in_a_group_is_named_and_the_step_undone() {
    let config = config();
    for bad in [0, 5, 6, 9, 10] {
        let mut bodies = calm_bodies(21, 11);
        // |v| jumps to 1e12 m/s in one step, |x| stays below 1e10 m
        bodies[bad].loads.force_world = DVec3::new(1e15 * bodies[bad].mass.mass, 0.0, 0.0);
        // a later body in the same group diverges too: the first one in scene order is named
        if bad + 1 < bodies.len() {
            bodies[bad + 1].state.position = DVec3::new(f64::NAN, 0.0, 0.0);
        }
        let mut world = World::new(config, bodies);
        let before = world.bodies.to_vec();
        let err = world.step().unwrap_err().diverged().cloned().unwrap();
        assert_eq!(err.body, format!("body{bad}"), "{err}");
        assert!(err.quantity.contains("velocity"), "{err}");
        assert_eq!(err.step, 1);
        assert_eq!(world.steps(), 0);
        for (a, b) in world.bodies.iter().zip(&before) {
            assert_eq!(bits(a), bits(b), "body {} was not restored", a.name);
        }
    }
}

#[test]
fn a_nan_is_named_when_no_other_body_diverges() {
    let config = config();
    let mut bodies = random_bodies(31, 9);
    bodies[6].fixed = false;
    bodies[6].loads = Loads::default();
    bodies[6].state.omega_body = DVec3::new(f64::NAN, 0.0, 0.0);
    bodies[6].state.orientation = DQuat::IDENTITY;
    bodies[6].state.velocity = DVec3::ZERO;
    bodies[6].state.position = DVec3::ZERO;
    let mut world = World::new(config, bodies.clone());
    let err = world.step().unwrap_err().diverged().cloned().unwrap();
    assert_eq!(err.body, "body6", "{err}");
    for (a, b) in world.bodies.iter().zip(&bodies) {
        assert_eq!(bits(a), bits(b), "body {} was not restored", a.name);
    }
}

#[test]
fn the_batched_step_allocates_nothing() {
    // the step's own layout of the bodies is made once, at the second step (the first that finds
    // the bodies as the step before left them): after that, nothing
    let mut world = World::new(config(), random_bodies(41, 203));
    world.step().unwrap();
    world.step().unwrap();
    let before = ALLOCATIONS.with(Cell::get);
    for _ in 0..200 {
        world.step().unwrap();
    }
    assert_eq!(ALLOCATIONS.with(Cell::get) - before, 0);
    // nor when the bodies are changed at every step (stepped by rows)
    let before = ALLOCATIONS.with(Cell::get);
    for step in 0..200 {
        world.bodies[step % 203].state.velocity.x += 1e-3;
        world.step().unwrap();
    }
    assert_eq!(ALLOCATIONS.with(Cell::get) - before, 0);
}

/// Applies one of several edits to body `j` of both lists: a kick, new mass properties and loads,
/// the fixed flag, an orientation-dependent load given or taken (the body moves between the blocks
/// and the scalar step).
fn edit(rng: &mut Rng, j: usize, lists: [&mut [RigidBody]; 2]) {
    let kind = (rng.uniform(0.0, 4.0) as usize).min(3);
    let (a, b) = (rng.uniform(0.2, 3.0), rng.uniform(0.2, 3.0));
    let c = rng.uniform((a - b).abs() + 0.05, a + b);
    let mass = MassProperties::from_principal(rng.uniform(0.1, 10.0), DVec3::new(a, b, c)).unwrap();
    let (kick, force, damping, flip) = (rng.vec(1.0), rng.vec(2.0), rng.uniform(0.0, 0.5), rng.chance(0.5));
    for list in lists {
        let body = &mut list[j];
        match kind {
            0 => body.state.velocity += kick,
            1 => {
                body.mass = mass;
                body.loads.force_world = force;
                body.loads.angular_damping = damping;
            }
            2 => body.fixed = flip,
            _ => body.loads.force_body = if flip { kick } else { DVec3::ZERO },
        }
    }
}

#[test]
fn bodies_edited_now_and_then_are_stepped_from_their_new_state() {
    // between edits the step keeps the bodies in its own layout (made at the second step after an
    // edit, then kept): every way in and out of it, bit for bit against the scalar step
    for (seed, n, chance) in [(61, 37, 0.3), (62, 203, 0.1), (63, 9, 0.5)] {
        let config = config();
        let mut reference = random_bodies(seed, n);
        let mut world = World::new(config, reference.clone());
        let mut rng = Rng(seed + 1000);
        for step in 0..300 {
            if rng.chance(chance) {
                let j = (rng.uniform(0.0, n as f64) as usize).min(n - 1);
                edit(&mut rng, j, [&mut world.bodies, &mut reference]);
            }
            step_both(&mut world, &mut reference, &config, &format!("seed {seed}, step {step}"));
        }
    }
}

#[test]
fn worlds_cloned_or_swapping_their_bodies_step_their_own() {
    let config = config();
    let mut first = World::new(config, random_bodies(71, 29));
    let mut second = World::new(config, random_bodies(72, 29));
    for _ in 0..5 {
        first.step().unwrap();
        second.step().unwrap();
    }
    // a clone, then one of the two edited: each steps its own bodies
    let mut clone = first.clone();
    clone.bodies[3].state.velocity.x += 1.0;
    let mut references: Vec<Vec<RigidBody>> = [&first, &second, &clone].map(|w| w.bodies.to_vec()).into();
    // the bodies of two worlds swapped whole (no mutable borrow of a body in either)
    std::mem::swap(&mut first.bodies, &mut second.bodies);
    references.swap(0, 1);
    for step in 0..20 {
        for (world, reference) in [&mut first, &mut second, &mut clone].into_iter().zip(&mut references) {
            step_both(world, reference, &config, &format!("step {step}"));
        }
    }
}

#[test]
fn a_body_diverging_in_a_later_step_is_named_and_that_step_undone() {
    // the bodies are in the step's own layout by then: a block's first half is written before its
    // second half is found diverging, a scalar body (orientation-dependent load) after every block
    let config = config();
    for (bad, scalar) in [(0, false), (5, false), (6, false), (10, false), (3, true), (10, true)] {
        let mut bodies = calm_bodies(81, 11);
        bodies[bad].state.velocity = DVec3::ZERO;
        bodies[bad].gravity_scale = 0.0;
        bodies[bad].loads.linear_damping = 0.0;
        // |v| = k h F/m after k steps: 9.9e9 m/s after nine, 1.1e10 after ten
        bodies[bad].loads.force_world = DVec3::new(1.1e12 * bodies[bad].mass.mass, 0.0, 0.0);
        if scalar {
            bodies[bad].loads.force_body = DVec3::new(0.0, 1e-9, 0.0);
        }
        let mut world = World::new(config, bodies.clone());
        for _ in 0..9 {
            world.step().unwrap();
            scalar_step(&mut bodies, &config);
        }
        let err = world.step().unwrap_err().diverged().cloned().unwrap();
        assert_eq!(err.body, format!("body{bad}"), "{err}");
        assert!(err.quantity.contains("velocity"), "{err}");
        assert_eq!((err.step, world.steps()), (10, 9));
        for (a, b) in world.bodies.iter().zip(&bodies) {
            assert_eq!(bits(a), bits(b), "body {} was not restored", a.name);
        }
        // and the world goes on from there as the scalar step does, once the force is gone
        world.bodies[bad].loads.force_world = DVec3::ZERO;
        bodies[bad].loads.force_world = DVec3::ZERO;
        for step in 0..5 {
            step_both(&mut world, &mut bodies, &config, &format!("step {step} after"));
        }
    }
}
