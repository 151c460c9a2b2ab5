//! Time per step of each stage of a scene at one thread and at N, interleaved: the world is run
//! from the same state for `STEPS` steps at each thread count in turn, `ROUNDS` times, and the
//! median of each stage is printed (the machine's speed drifts; interleaving compares like with
//! like). The trajectories are the same bit for bit at any thread count; this checks it too.
//!
//! Usage: `cargo run --release -p tumble --example threads -- SCENE.toml [N=2] [STEPS=60] [ROUNDS=5]
//! [WARM=0] [awake|asleep] [MIN_PAIRS]` (`WARM` steps are taken first, once, at one thread, to
//! start from a settled state; `awake` turns sleeping off: every body is solved at every step;
//! `MIN_PAIRS` sets the number of candidate pairs from which the narrow phase goes to the pool,
//! `World::set_parallel_min_pairs`). The thread pool is built by one untimed step before the
//! rounds (the same step at each thread count), and shared by the rounds' copies of the world.

use std::path::Path;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(path) = args.first() else {
        eprintln!("usage: threads SCENE.toml [N=2] [STEPS=60] [ROUNDS=5] [WARM=0] [awake|asleep] [MIN_PAIRS]");
        std::process::exit(2);
    };
    let arg = |i: usize, default: usize| args.get(i).and_then(|a| a.parse().ok()).unwrap_or(default);
    let (n, steps, rounds, warm) = (arg(1, 2), arg(2, 60), arg(3, 5), arg(4, 0));
    let scene = match tumble::scene::load(Path::new(path)) {
        Ok(scene) => scene,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    };
    let mut start = scene.world;
    if args.get(5).is_some_and(|a| a == "awake") {
        start.config.contact.sleep = false;
    }
    start.set_threads(1);
    for _ in 0..warm {
        start.step().expect("the scene runs");
    }
    let min_pairs: Option<usize> = args.get(6).and_then(|a| a.parse().ok());
    let counts = [1, n];
    // one step at each thread count outside the timing: it builds the pool, which the copies share
    let bases: Vec<tumble::World> = counts
        .iter()
        .map(|&threads| {
            let mut world = start.clone();
            world.set_threads(threads);
            if let Some(m) = min_pairs {
                world.set_parallel_min_pairs(m);
            }
            world.step().expect("the scene runs");
            world
        })
        .collect();
    // per thread count, per round: the stages (ms per step)
    let mut times: Vec<Vec<[f64; 6]>> = vec![Vec::new(); 2];
    let mut ends = [Vec::new(), Vec::new()];
    for _ in 0..rounds {
        for (k, &threads) in counts.iter().enumerate() {
            let mut world = bases[k].clone();
            debug_assert_eq!(world.threads(), threads);
            world.set_profiling(true);
            for _ in 0..steps {
                world.step().expect("the scene runs");
            }
            let p = world.profile().expect("profiling is on").per_step();
            times[k]
                .push([p.broad_phase, p.narrow_phase, p.impacts, p.resting, p.integration, p.step].map(|t| t * 1e3));
            ends[k] = world.bodies.iter().map(|b| (b.state.position, b.state.velocity)).collect();
        }
    }
    let median = |k: usize, s: usize| {
        let mut v: Vec<f64> = times[k].iter().map(|t| t[s]).collect();
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    println!("{path}: {steps} steps from step {}, median of {rounds} interleaved rounds, ms per step\n", warm + 1);
    println!("| stage | 1 thread | {n} threads | ratio |");
    println!("|---|---|---|---|");
    let names = ["broad phase", "narrow phase", "collisions (impacts)", "resting contact", "integration", "whole step"];
    for (s, name) in names.iter().enumerate() {
        let (a, b) = (median(0, s), median(1, s));
        println!("| {name} | {a:.3} | {b:.3} | {:.2} |", b / a);
    }
    println!("\nsame positions and velocities at the end: {}", ends[0] == ends[1]);
}
