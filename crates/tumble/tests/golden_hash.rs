//! Golden hashes: the final state of the contact benchmarks, bit for bit.
//!
//! Each scene runs a fixed number of steps and its final state is hashed
//! ([`World::state_hash`]: the bit patterns of every position, orientation, velocity and angular
//! velocity). The hash must equal the committed golden value, and two runs must agree. A change that
//! moves any number by one bit fails here: if the change of the physics is meant, put the new value
//! printed by the failure into the table below and say in the commit why the numbers moved.
//!
//! `final_hash` takes a function that configures the world before the run, so that a test can run a
//! scene with other settings and compare the hashes: each scene is run with 1, 2 and 4 threads
//! (`World::set_threads`), and all three must give the golden value — the collision detection
//! shares its work among the threads but gathers it in the same order, so no bit may move. These
//! scenes have fewer candidate pairs than the narrow phase shares out by default (4,096), so the
//! runs on several threads lower that threshold to 0 (`on_threads`): their narrow phase really
//! runs on the pool.

use std::path::Path;
use tumble::World;

/// `(scene, steps, golden hash of the state after that many steps)`: the pyramid and the balls 5 s
/// at `dt = 1/60`, past the pyramid's settling and the balls' landing (both asleep by then); the
/// quadruped 0.4 s at `dt = 1e-3`, past its feet's landing (link contacts on the floor; robots do
/// not sleep). The quadruped's changed on 2026-12-04 (was 0xb4c5_52b8_6ee0_1354) when the feet's
/// landings began to be integrated in `σ` near the slip's stop (their impulses moved by the old
/// fixed-step integration's error, up to 5e-7), and again on 2026-12-05 (was 0xf42b_3846_56c0_a0cf)
/// when the slide's adaptive steps went from Dormand–Prince 5(4) to 8(5,3): the same 1e-10 local
/// tolerance, other steps, so the impulses moved within it. The pyramid's and the quadruped's moved
/// again the same day (pyramid was 0xb523_f40f_b5ea_34ec, awake 0x49f2_bfdd_6a16_8174; quadruped
/// 0x5bc8_d1d8_ecb9_9263) when the friction disc's projection started its Newton iteration at the
/// lower bound of its root and took reciprocals once per iteration (it converges now where eight
/// iterations from zero left `|λ|` 1.2e-7 off the disc; sliding impulses moved in their last bits).
/// The quadruped's moved on 2026-12-05 again (was 0xd394_a8eb_9fdd_f9b9) when the robot's `G = J M⁻¹ Jᵀ`
/// began to be summed over the rows' common chains only, by blocks of rows (the same sums without
/// the zero terms, in another order: `G` moved in its last bits, 2e-14 m on the trajectory; was
/// 0x8b82_62c7_8ee3_241d), and the same day the pyramid's (was 0xa650_5e5b_fb98_28b8, awake
/// 0x5b0e_2711_ce87_35ea) and the quadruped's when the friction disc's projection began its Newton
/// iteration at the asymptotic root instead of the lower bound (the same root to 1e-12, other
/// iterates: sliding impulses moved in their last bits), and once more (pyramid was
/// 0xc984_3406_547c_8370, awake 0xcc13_8003_d66b_7f0b; quadruped 0xd4fa_37c3_5513_3225) when its
/// Newton step was written with the adjugate (one square root and one division per iteration) and
/// the impacts' step-size controller took `r^(−1/8)` by square roots instead of `powf`. The
/// pyramid's moved once more on 2026-12-05 (was 0x7c86_2e84_6580_5861, awake
/// 0x933a_0dd9_a4a9_6b2d) when the contact sweeps began to alternate their direction over a
/// manifold's points (`solver::Sweep::reverse`: a 10:1 stack rocked and walked 42.6 mm in 1,000
/// steps, now 1.1 mm); the balls (one point per pair) and the quadruped (robot rows only) kept theirs.
/// The pyramid's and the balls' (sleeping on) moved on 2026-12-07 (were 0x4616_0d20_0ba9_b7e8 and
/// 0x26a1_2a4d_f7b3_1ba5) when the default `sleep_time` went from 0.5 s to 0.25 s: both scenes fall
/// asleep sooner (pyramid at step 36 instead of 51, balls at 80 instead of 95), so their bodies are
/// frozen earlier: at step 300 within 0.15 mm (pyramid) and 0.09 mm (balls) of where they were
/// before; the awake values did not move. The pyramid's (both) moved again on 2026-12-07 (were
/// 0xc014_afef_88b8_cf7b and 0x367c_dfb8_6ae9_8ceb) when the resting constraints began to compute
/// `K d` from their angular responses, `(1/m_a + 1/m_b) d + (I_a⁻¹ (r_a × d)) × r_a + …`, instead
/// of forming `K`, and the normal and friction rows to add the terms that wait for the point's
/// velocity last (`(λ_n − m b − s_i λ_n) − m u_n`, `λ* = (λ_t − K_tt⁻¹ u_t) − Δλ_n K_tt⁻¹ (t·K n)`):
/// the same quantities rounded otherwise, the pyramid at step 300 (sleeping on) within 1e-4 m of
/// where it was; the quadruped and the balls sleeping on kept theirs. The balls' sleeping-off value
/// moved with it (was 0x7dd2_4454_3f7c_0cad): their resting rows round the normal impulse otherwise,
/// velocities moved by at most 1.4e-16 m/s and no position sampled once a second moved a bit.
const GOLDEN: [(&str, u64, u64); 3] = [
    ("pyramid", 300, 0x6246_010b_9347_46f9),
    ("balls", 300, 0xf830_4cf1_40ac_8e65),
    ("quadruped", 400, 0xa637_b67e_301e_528c),
];

/// The same with sleeping off (`sleep = false`): the values from before sleeping existed, which
/// the step must still give bit for bit.
const GOLDEN_AWAKE: [(&str, u64, u64); 3] = [
    ("pyramid", 300, 0xa99e_6adf_eacf_fe2a),
    ("balls", 300, 0xc4c1_0988_cdda_d5fd),
    ("quadruped", 400, 0xa637_b67e_301e_528c),
];

/// The thread counts every scene is run with.
const THREADS: [usize; 3] = [1, 2, 4];

/// Runs `world` on `threads` threads, every narrow phase on the pool (when there is one: more than
/// one thread), however few its pairs.
fn on_threads(world: &mut World, threads: usize) {
    world.set_threads(threads);
    world.set_parallel_min_pairs(0);
}

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
    let &(_, steps, golden) = GOLDEN.iter().find(|(s, _, _)| *s == scene).expect("a golden value");
    let first = final_hash(scene, steps, |w| w.set_threads(1));
    let second = final_hash(scene, steps, |w| w.set_threads(1));
    assert_eq!(first, second, "{scene}: two runs of {steps} steps differ ({first:#018x}, {second:#018x})");
    assert_eq!(
        first, golden,
        "{scene}: the state after {steps} steps hashes to {first:#018x}, the golden value is {golden:#018x}. \
         If the physics changed on purpose, set the golden value of `{scene}` in \
         crates/tumble/tests/golden_hash.rs to {first:#018x} and say why in the commit."
    );
    for threads in THREADS {
        let hash = final_hash(scene, steps, |w| on_threads(w, threads));
        assert_eq!(
            hash, golden,
            "{scene}: with {threads} threads the state hashes to {hash:#018x}, not {golden:#018x}"
        );
    }
}

/// With sleeping off, every scene gives its value from before sleeping existed (1 and 2 threads).
#[test]
fn sleeping_off_changes_no_bit() {
    for (scene, steps, golden) in GOLDEN_AWAKE {
        for threads in [1, 2] {
            let hash = final_hash(scene, steps, |w| {
                on_threads(w, threads);
                w.config.contact.sleep = false;
            });
            assert_eq!(hash, golden, "{scene}, sleeping off, {threads} threads: {hash:#018x}, not {golden:#018x}");
        }
    }
}

#[test]
fn pyramid_matches_its_golden_hash() {
    check("pyramid");
}

#[test]
fn balls_match_their_golden_hash() {
    check("balls");
}

#[test]
fn quadruped_matches_its_golden_hash() {
    check("quadruped");
}

/// A world asked for several threads uses them (the pool is really there: the tests above compare
/// something), and one thread means one.
#[test]
fn the_thread_setting_is_kept() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/pyramid.toml");
    let mut world = tumble::scene::load(&path).unwrap().world;
    world.set_threads(3);
    assert_eq!(world.threads(), 3);
    world.set_threads(1);
    assert_eq!(world.threads(), 1);
    world.set_threads(0);
    assert!(world.threads() >= 1);
}

/// The per-stage timing observes the step without changing it.
#[test]
fn profiling_leaves_the_numbers_alone() {
    let plain = final_hash("pyramid", 60, |_| {});
    let profiled = final_hash("pyramid", 60, |w| w.set_profiling(true));
    assert_eq!(plain, profiled);
}
