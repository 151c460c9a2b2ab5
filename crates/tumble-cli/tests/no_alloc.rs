//! The run loop allocates nothing per step: the allocations of a run of 100 steps and of a run of
//! 3000 steps are the same, for every integrator and both formats, writing every step.
//!
//! The allocator counts the allocations of each thread separately, so that the test harness's own
//! threads do not disturb the count.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::AtomicBool;
use tumble::trajectory::{ContactWriter, Format, TrajectoryWriter};
use tumble::Integrator;
use tumble_cli::report::Ticker;
use tumble_cli::run::{simulate, Stop};

struct Counting;

thread_local! {
    /// Allocations (and reallocations) made by this thread.
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

fn count() {
    // `try_with`: the slot may be gone while the thread ends
    let _ = ALLOCATIONS.try_with(|n| n.set(n.get() + 1));
}

fn allocations_so_far() -> usize {
    ALLOCATIONS.with(Cell::get)
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

/// Allocations made by `simulate` over `steps` steps of the demo's free motion (contacts off), every
/// step written to a sink.
fn allocations(integrator: Integrator, format: Format, steps: u64) -> usize {
    let mut world = tumble::scene::demo().world;
    world.config.contact.enabled = false;
    world.config.integrator = integrator;
    world.config.duration = steps as f64 * world.config.dt;
    world.config.sample_every = 1;
    let mut writer = TrajectoryWriter::new(std::io::sink(), format, &world).unwrap();
    let mut ticker = Ticker::new(steps, 6, false);
    let stop = AtomicBool::new(false);
    let before = allocations_so_far();
    let outcome =
        simulate(&mut world, &mut writer, None::<&mut ContactWriter<std::io::Sink>>, &stop, &mut ticker).unwrap();
    let after = allocations_so_far();
    assert!(matches!(outcome.stop, Stop::Completed));
    assert_eq!(world.steps(), steps);
    after - before
}

#[test]
fn the_run_loop_allocates_nothing_per_step() {
    for integrator in Integrator::ALL {
        for format in [Format::Csv, Format::JsonLines] {
            let short = allocations(integrator, format, 100);
            let long = allocations(integrator, format, 3000);
            assert_eq!(short, long, "{integrator} {format:?}: {short} allocations for 100 steps, {long} for 3000");
        }
    }
}

/// The same for a robot scene (`scenes/panda.toml`: PD control, damping, nine joints; or
/// `scenes/limit.toml`: an arm striking and resting on its joint limits from step ~200 on).
fn robot_allocations(scene: &str, integrator: Integrator, format: Format, steps: u64) -> usize {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes").join(scene);
    let mut world = tumble::scene::load(&path).unwrap().world;
    world.config.integrator = integrator;
    world.config.duration = steps as f64 * world.config.dt;
    world.config.sample_every = 1;
    let mut writer = TrajectoryWriter::new(std::io::sink(), format, &world).unwrap();
    let mut ticker = Ticker::new(steps, 12, false);
    let stop = AtomicBool::new(false);
    let before = allocations_so_far();
    let outcome =
        simulate(&mut world, &mut writer, None::<&mut ContactWriter<std::io::Sink>>, &stop, &mut ticker).unwrap();
    let after = allocations_so_far();
    assert!(matches!(outcome.stop, Stop::Completed));
    after - before
}

#[test]
fn the_run_loop_allocates_nothing_per_step_with_robots() {
    for integrator in Integrator::ALL {
        for format in [Format::Csv, Format::JsonLines] {
            let short = robot_allocations("panda.toml", integrator, format, 100);
            let long = robot_allocations("panda.toml", integrator, format, 1000);
            assert_eq!(short, long, "{integrator} {format:?}: {short} allocations for 100 steps, {long} for 1000");
            // the limits are struck at about step 200 and held from step 550 on
            let short = robot_allocations("limit.toml", integrator, format, 600);
            let long = robot_allocations("limit.toml", integrator, format, 2000);
            assert_eq!(
                short, long,
                "limits, {integrator} {format:?}: {short} allocations for 600 steps, {long} for 2000"
            );
        }
    }
}

/// A robot standing on its joints' dry friction (`scenes/leg_friction.xml`: the friction rows in the
/// contact solve once the foot lands, and in the robot's own solve before) steps without allocating.
#[test]
fn the_run_loop_allocates_nothing_per_step_with_joint_friction() {
    for integrator in Integrator::ALL {
        let short = robot_allocations("leg_friction.xml", integrator, Format::JsonLines, 300);
        let long = robot_allocations("leg_friction.xml", integrator, Format::JsonLines, 1500);
        assert_eq!(short, long, "{integrator}: {short} allocations for 300 steps, {long} for 1500");
    }
}

/// A reduced robot (`scenes/panda_locked.toml`: wrist and fingers locked) steps without allocating:
/// the reduction is done once, when the scene is read.
#[test]
fn the_run_loop_allocates_nothing_per_step_with_a_locked_robot() {
    for integrator in Integrator::ALL {
        let short = robot_allocations("panda_locked.toml", integrator, Format::JsonLines, 100);
        let long = robot_allocations("panda_locked.toml", integrator, Format::JsonLines, 1000);
        assert_eq!(short, long, "{integrator}: {short} allocations for 100 steps, {long} for 1000");
    }
}

/// The same for a contact scene with its contacts on: allocations over `steps` steps of
/// `scenes/NAME.toml`, every step written, the contacts file (`--contacts`) too, with the collision
/// detection on `threads` threads (0: one per core; on more than one, the narrow phase on the pool
/// however few the pairs: these scenes have fewer than it shares out by default).
fn contact_allocations_on(name: &str, steps: u64, threads: usize) -> usize {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../scenes/{name}.toml"));
    let mut world = tumble::scene::load(&path).unwrap().world;
    assert!(world.config.contact.enabled);
    world.set_threads(threads);
    world.set_parallel_min_pairs(0);
    world.config.duration = steps as f64 * world.config.dt;
    world.config.sample_every = 1;
    let mut writer = TrajectoryWriter::new(std::io::sink(), Format::Csv, &world).unwrap();
    let mut contacts = ContactWriter::new(std::io::sink(), &world);
    let mut ticker = Ticker::new(steps, 6, false);
    let stop = AtomicBool::new(false);
    let before = allocations_so_far();
    let outcome = simulate(&mut world, &mut writer, Some(&mut contacts), &stop, &mut ticker).unwrap();
    let after = allocations_so_far();
    assert!(matches!(outcome.stop, Stop::Completed));
    after - before
}

/// [`contact_allocations_on`] on one thread.
fn contact_allocations(name: &str, steps: u64) -> usize {
    contact_allocations_on(name, steps, 1)
}

/// The 210-box pyramid (`scenes/pyramid.toml`: box–box and box–plane manifolds kept per pair, the
/// soft solver's buffers) allocates nothing per step once its buffers have grown: 100 steps (the
/// boxes settle onto each other) and 600 steps make the same allocations.
#[test]
fn the_run_loop_allocates_nothing_per_step_with_contacts() {
    let short = contact_allocations("pyramid", 100);
    let long = contact_allocations("pyramid", 600);
    assert_eq!(short, long, "pyramid: {short} allocations for 100 steps, {long} for 600");
}

/// Robots in contact (`scenes/quadruped.toml`: a quadruped lands at about step 60 and stands on its
/// four feet, its rows in the soft step beside the free bodies' constraints; `scenes/chain.toml`: a
/// chain lands link after link and lies on the floor with 40 contact points) allocate nothing per
/// step once the contacts have settled: the same allocations for a short and a long run.
#[test]
fn the_run_loop_allocates_nothing_per_step_with_robots_in_contact() {
    let short = contact_allocations("quadruped", 1000);
    let long = contact_allocations("quadruped", 2000);
    assert_eq!(short, long, "quadruped: {short} allocations for 1000 steps, {long} for 2000");
    let short = contact_allocations("chain", 2500);
    let long = contact_allocations("chain", 3500);
    assert_eq!(short, long, "chain: {short} allocations for 2500 steps, {long} for 3500");
}

/// The quadrupeds of example-robot-data standing and trotting (`scenes/{solo12,go1}_{stand,trot}.toml`:
/// Solo-12's mesh feet, Go1's sphere feet; the trot lifts and lands them every 250 steps, so the
/// contact space of the rows grows and shrinks): the same allocations for 1,000 and 2,000 steps.
#[test]
fn the_run_loop_allocates_nothing_per_step_with_legged_robots() {
    for name in ["solo12_stand", "go1_stand", "solo12_trot", "go1_trot"] {
        let short = contact_allocations(name, 1000);
        let long = contact_allocations(name, 2000);
        assert_eq!(short, long, "{name}: {short} allocations for 1000 steps, {long} for 2000");
    }
}

/// On two threads the calling thread allocates almost nothing per step: the pool is built at the
/// first step, and the jobs are handed to it through rayon's injector queue, which allocates one
/// block of 63 slots every 63 jobs (one job per step for the pyramid's narrow phase, 780 pairs; two
/// for the balls, whose sweep of 1,005 boxes is shared out too). Nothing else: the extra allocations
/// of a longer run are at most one per 63 jobs. (The counter sees the calling thread only; the pool's
/// workers are not counted.) On one thread no rayon code runs: nothing at all (the tests above).
#[test]
fn the_run_loop_allocates_only_rayons_queue_blocks_on_two_threads() {
    for (scene, short_steps, long_steps, jobs_per_step) in [("pyramid", 100, 600, 1), ("balls", 200, 400, 2)] {
        let short = contact_allocations_on(scene, short_steps, 2);
        let long = contact_allocations_on(scene, long_steps, 2);
        let blocks = ((long_steps - short_steps) * jobs_per_step).div_ceil(63) + 1;
        assert!(
            long >= short && long - short <= blocks as usize,
            "{scene}, 2 threads: {short} allocations for {short_steps} steps, {long} for {long_steps} \
             (at most {blocks} more expected)"
        );
    }
}
