//! An arm pushes a box across a table (`scenes/panda_push.toml`): a Panda under PD sweeps its hand
//! through a 0.4 kg box resting on a fixed table and pushes it along with its fingers.
//!
//! What must hold: no NaN; the box is pushed (it travels decimetres in the sweep's direction); no
//! contact overlaps by 2 mm or more (fingers against the box, box against the table); the box ends at
//! rest on the table, upright, neither sinking nor drifting in the last second; and at rest the
//! fingers' horizontal push on it is one the table's friction can hold, `|F_h| ≤ μ m g`.

use std::path::Path;
use tumble::collision::links::Side;
use tumble::math::DVec3;
use tumble::scene;

#[test]
fn a_panda_pushes_a_box_across_the_table_and_the_box_comes_to_rest_on_it() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/panda_push.toml");
    let mut scene = scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
    let world = &mut scene.world;
    let b = world.body_index("box").unwrap();
    let (mass, mu, g) = (0.4, 0.5, 9.81);
    let half_height = 0.03;
    let start = world.bodies[b].state.position;
    let steps = world.config.step_count();
    let last_second = steps - (1.0 / world.config.dt).round() as u64;
    let (mut link_depth, mut table_depth, mut push) = (0.0_f64, 0.0_f64, DVec3::ZERO);
    let (mut push_steps, mut push_force_sum, mut push_force_max) = (0_u64, 0.0_f64, 0.0_f64);
    let mut at_last_second = start;
    for step in 1..=steps {
        world.step().unwrap_or_else(|e| panic!("{e}"));
        assert!(world.energy().is_finite(), "a non-finite state at step {step}");
        let dt = world.config.dt;
        // the links' push on the box: minus the impulses on the links, over dt (N)
        push = DVec3::ZERO;
        let mut touched = false;
        for (c, p) in world.contacts().links.active() {
            link_depth = link_depth.max(-c.gap);
            if c.a == Side::Body(b) {
                touched = true;
                push -= p / dt;
            }
        }
        for (c, _) in world.contacts().active() {
            if c.a == b || c.b == b {
                table_depth = table_depth.max(-c.gap);
            }
        }
        if touched {
            push_steps += 1;
            push_force_sum += push.length();
            push_force_max = push_force_max.max(push.length());
        }
        if step == last_second {
            at_last_second = world.bodies[b].state.position;
        }
    }
    let state = world.bodies[b].state;
    let travel = state.position - start;
    let drift = (state.position - at_last_second).length();
    let up = state.orientation * DVec3::Z;
    let sink = half_height - state.position.z;
    println!(
        "panda push: box travel {:.4} m along y ({:.4} m along x), {} steps pushed, push {:.3} N mean / {:.3} N \
         max; deepest link contact {:.4} mm, box on table {:.4} mm; last second drift {drift:e} m, final speed \
         {:e} m/s, sink {sink:e} m, tilt {:e}; final push horizontal {:.4} N, vertical {:.4} N (μ m g = {:.4} N)",
        travel.y,
        travel.x,
        push_steps,
        push_force_sum / push_steps.max(1) as f64,
        push_force_max,
        1e3 * link_depth,
        1e3 * table_depth,
        state.velocity.length(),
        1.0 - up.z,
        (push.x * push.x + push.y * push.y).sqrt(),
        push.z,
        mu * mass * g
    );
    assert!(travel.y >= 0.2, "the box was pushed only {} m along y", travel.y);
    assert!(push_steps > 0, "no link ever touched the box");
    assert!(link_depth < 2e-3, "a link overlapped {link_depth} m");
    assert!(table_depth < 2e-3, "the box overlapped the table {table_depth} m");
    assert!(sink.abs() < 2e-4, "the box's centre ends {sink} m below its resting height");
    assert!(1.0 - up.z < 1e-6, "the box ends tilted: its z axis is {up:?}");
    assert!(drift < 1e-4, "the box drifted {drift} m in the last second");
    assert!(state.velocity.length() < 1e-4, "the box still moves at {} m/s", state.velocity.length());
    let horizontal = (push.x * push.x + push.y * push.y).sqrt();
    let normal = mass * g - push.z;
    assert!(
        horizontal <= mu * normal * (1.0 + 1e-9),
        "at rest the fingers push {horizontal} N, the table holds {}",
        mu * normal
    );
}
