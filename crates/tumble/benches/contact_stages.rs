//! The cost of each stage of a step with contacts, on the two contact benchmarks
//! (`scenes/pyramid.toml`: 210 boxes; `scenes/balls.toml`: 1,000 balls in a box).
//!
//! Each scene is first run 200 steps (the pyramid has settled, the balls have landed and are
//! piling up); each benchmark then steps on from there with the world's per-stage timing on
//! (`World::set_profiling`) and reports the time of one stage per step — `broad_phase`,
//! `narrow_phase`, `impacts`, `resting` (constraints and the soft solver), `integration` — or of the
//! whole `step`; after 300 steps the world goes back to the state at step 200, so that every sample
//! measures the same stretch of the scene. `narrow_phase_fresh` is the narrow phase with every
//! pair's manifold made afresh at every step (`manifold_reuse = 0`), as before the
//! manifolds were kept.
//!
//! `cargo bench -p tumble --bench contact_stages -- --warm-up-time 1 --measurement-time 3`

use criterion::{criterion_group, criterion_main, Criterion};
use std::path::Path;
use std::time::Duration;
use tumble::world::Profile;
use tumble::World;

/// Steps run before measuring, and steps measured before going back to that state.
const WARM: u64 = 200;
const STRETCH: u64 = 300;

type Stage = fn(&Profile) -> f64;

const STAGES: [(&str, Stage, bool); 7] = [
    ("broad_phase", |p| p.broad_phase, true),
    ("narrow_phase", |p| p.narrow_phase, true),
    ("narrow_phase_fresh", |p| p.narrow_phase, false),
    ("impacts", |p| p.impacts, true),
    ("resting", |p| p.resting, true),
    ("integration", |p| p.integration, true),
    ("step", |p| p.step, true),
];

fn warmed(scene: &str) -> World {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes").join(format!("{scene}.toml"));
    let mut world = tumble::scene::load(&path).unwrap().world;
    for _ in 0..WARM {
        world.step().unwrap();
    }
    world
}

/// The warmed world with profiling on from zero; `reuse`: keep the manifolds of barely moving pairs.
fn fresh_copy(base: &World, reuse: bool) -> World {
    let mut world = base.clone();
    if !reuse {
        world.config.contact.manifold_reuse = 0.0;
    }
    world.set_profiling(true);
    world
}

fn stages(c: &mut Criterion) {
    for scene in ["pyramid", "balls"] {
        let base = warmed(scene);
        let mut group = c.benchmark_group(format!("contact_stages/{scene}"));
        group.sample_size(20);
        for (name, stage, reuse) in STAGES {
            let mut world = fresh_copy(&base, reuse);
            group.bench_function(name, |b| {
                b.iter_custom(|iters| {
                    let mut seconds = 0.0;
                    for _ in 0..iters {
                        if world.steps() >= WARM + STRETCH {
                            world = fresh_copy(&base, reuse);
                        }
                        let before = stage(&world.profile().expect("profiling is on"));
                        world.step().unwrap();
                        seconds += stage(&world.profile().expect("profiling is on")) - before;
                    }
                    Duration::from_secs_f64(seconds)
                })
            });
        }
        group.finish();
    }
}

criterion_group!(benches, stages);
criterion_main!(benches);
