//! Golden hashes: the final state of the contact benchmarks, bit for bit.
//!
//! Each scene runs a fixed number of steps and its final state is hashed
//! ([`World::state_hash`]: the bit patterns of every position, orientation, velocity and angular
//! velocity). The hash must equal the committed golden value, and two runs must agree. A change that
//! moves any number by one bit fails here: if the change of the physics is meant, put the new value
//! printed by the failure into the table below and say in the commit why the numbers moved.
//!
//! `final_hash` takes a function that configures the world before the run, so that a test can run a
//! scene with other settings (1, 2, 4 threads) and compare the hashes.

use std::path::Path;
use tumble::World;

/// Steps of each run: 5 s at `dt = 1/60`, past the pyramid's settling and the balls' landing.
const STEPS: u64 = 300;

/// `(scene, golden hash of the state after STEPS steps)`.
const GOLDEN: [(&str, u64); 2] = [("pyramid", 0x49f2_bfdd_6a16_8174), ("balls", 0x7dd2_4454_3f7c_0cad)];

/// The hash of the scene's state after `steps` steps, the world configured by `configure` first.
fn final_hash(scene: &str, steps: u64, configure: impl FnOnce(&mut World)) -> u64 {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes").join(format!("{scene}.toml"));
    let mut world = tumble::scene::load(&path).unwrap_or_else(|e| panic!("{scene}: {e}")).world;
    configure(&mut world);
    for _ in 0..steps {
        world.step().unwrap_or_else(|e| panic!("{scene}: {e}"));
    }
    world.state_hash()
}

fn check(scene: &str) {
    let golden = GOLDEN.iter().find(|(s, _)| *s == scene).expect("a golden value").1;
    let first = final_hash(scene, STEPS, |_| {});
    let second = final_hash(scene, STEPS, |_| {});
    assert_eq!(first, second, "{scene}: two runs of {STEPS} steps differ ({first:#018x}, {second:#018x})");
    assert_eq!(
        first, golden,
        "{scene}: the state after {STEPS} steps hashes to {first:#018x}, the golden value is {golden:#018x}. \
         If the physics changed on purpose, set the golden value of `{scene}` in \
         crates/tumble/tests/golden_hash.rs to {first:#018x} and say why in the commit."
    );
}

#[test]
fn pyramid_matches_its_golden_hash() {
    check("pyramid");
}

#[test]
fn balls_match_their_golden_hash() {
    check("balls");
}

/// The per-stage timing observes the step without changing it.
#[test]
fn profiling_leaves_the_numbers_alone() {
    let plain = final_hash("pyramid", 60, |_| {});
    let profiled = final_hash("pyramid", 60, |w| w.set_profiling(true));
    assert_eq!(plain, profiled);
}
