//! Time of each step of a scene from its start, by stage: where a scene that settles and falls
//! asleep spends its time before it sleeps. The scene is run `ROUNDS` times from its start on one
//! thread; each step's line gives the stages of the round in which that step was fastest (the
//! machine's speed drifts), the narrow phase's counts and the bodies asleep after it, and the
//! running sum of the step times.
//!
//! Usage: `cargo run --release -p tumble --example settling -- SCENE.toml [STEPS=60] [ROUNDS=5]
//! [awake]` (`awake` turns sleeping off).

use std::path::Path;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(path) = args.first() else {
        eprintln!("usage: settling SCENE.toml [STEPS=60] [ROUNDS=5] [awake]");
        std::process::exit(2);
    };
    let arg = |i: usize, default: usize| args.get(i).and_then(|a| a.parse().ok()).unwrap_or(default);
    let (steps, rounds) = (arg(1, 60), arg(2, 5).max(1));
    let mut start = match tumble::scene::load(Path::new(path)) {
        Ok(scene) => scene.world,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    };
    if args.get(3).is_some_and(|a| a == "awake") {
        start.config.contact.sleep = false;
    }
    start.set_threads(1);
    // per step: the fastest round's [step, broad, narrow, impacts, resting, integration] (s), and
    // [pairs, reused, contact points, asleep after it]
    let mut best = vec![[f64::INFINITY; 6]; steps];
    let mut counts = vec![[0u64; 4]; steps];
    for _ in 0..rounds {
        let mut world = start.clone();
        world.set_profiling(true);
        let mut before = world.profile().expect("profiling is on");
        for k in 0..steps {
            if let Err(e) = world.step() {
                eprintln!("step {k}: {e}");
                std::process::exit(1);
            }
            let p = world.profile().expect("profiling is on");
            let stages = [
                p.step - before.step,
                p.broad_phase - before.broad_phase,
                p.narrow_phase - before.narrow_phase,
                p.impacts - before.impacts,
                p.resting - before.resting,
                p.integration - before.integration,
            ];
            if stages[0] < best[k][0] {
                best[k] = stages;
            }
            let asleep = world.contacts().sleep().count() as u64;
            counts[k] = [p.pairs - before.pairs, p.reused - before.reused, p.contacts - before.contacts, asleep];
            before = p;
        }
    }
    println!("{path}: each step from the start, the fastest of {rounds} rounds, ms");
    println!();
    println!("| step | whole step | broad | narrow | impacts | resting | integration | pairs | reused | points | asleep | sum of steps |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|");
    let mut sum = 0.0;
    for (k, (t, c)) in best.iter().zip(&counts).enumerate() {
        sum += t[0];
        let ms = t.map(|s| s * 1e3);
        println!(
            "| {k} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {:.3} | {} | {} | {} | {} | {:.1} |",
            ms[0],
            ms[1],
            ms[2],
            ms[3],
            ms[4],
            ms[5],
            c[0],
            c[1],
            c[2],
            c[3],
            sum * 1e3
        );
    }
}
