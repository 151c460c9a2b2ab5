//! Resting contact and stacking: a tower of ten boxes, a pyramid, a heavy box on a light one, a
//! box landing flat, and bodies that start overlapping.

mod contact_support;
use contact_support::*;
use tumble::math::{DQuat, DVec3};

const G: f64 = 9.81;

fn run(w: &mut tumble::World, seconds: f64) -> f64 {
    let steps = (seconds / w.config.dt).round() as usize;
    let start: Vec<DVec3> = w.bodies.iter().map(|b| b.state.position).collect();
    let mut worst: f64 = 0.0;
    for _ in 0..steps {
        w.step().unwrap();
        for (b, s) in w.bodies.iter().zip(&start) {
            worst = worst.max((b.state.position - *s).length());
        }
    }
    worst
}

#[test]
fn ten_boxes_stacked_stay_put_for_ten_seconds() {
    let h = DVec3::splat(0.5);
    let mut bodies = vec![material(ground(DQuat::IDENTITY), 0.5, 0.0)];
    for i in 0..10 {
        bodies.push(material(cuboid(&format!("box{i}"), h, 1.0, DVec3::new(0.0, 0.0, 0.5 + i as f64)), 0.5, 0.0));
    }
    let mut w = world(1.0 / 60.0, DVec3::new(0.0, 0.0, -G), bodies);
    let drift = run(&mut w, 10.0);
    eprintln!("ten-box tower: worst displacement {drift:.5} m over 10 s");
    assert!(drift < 0.01, "a box moved {drift} m");
    let jitter = w.bodies.iter().map(|b| b.state.velocity.length()).fold(0.0, f64::max);
    assert!(jitter < 1e-3, "residual speed {jitter} m/s");
}

#[test]
fn pyramid_ten_wide_stands_for_ten_seconds() {
    let h = DVec3::splat(0.5);
    let mut bodies = vec![material(ground(DQuat::IDENTITY), 0.5, 0.0)];
    for row in 0..10 {
        for k in 0..(10 - row) {
            let x = (k as f64 - (9 - row) as f64 * 0.5) * 1.0;
            let z = 0.5 + row as f64;
            bodies.push(material(cuboid(&format!("b{row}_{k}"), h, 1.0, DVec3::new(x, 0.0, z)), 0.5, 0.0));
        }
    }
    let mut w = world(1.0 / 60.0, DVec3::new(0.0, 0.0, -G), bodies);
    let drift = run(&mut w, 10.0);
    eprintln!("pyramid 10 wide: worst displacement {drift:.5} m over 10 s");
    assert!(drift < 0.01, "a box of the pyramid moved {drift} m");
}

#[test]
fn heavy_box_on_a_light_one_does_not_sink_in() {
    let h = DVec3::splat(0.5);
    let light = material(cuboid("light", h, 1.0, DVec3::new(0.0, 0.0, 0.5)), 0.5, 0.0);
    let heavy = material(cuboid("heavy", h, 10.0, DVec3::new(0.0, 0.0, 1.5)), 0.5, 0.0);
    let mut w =
        world(1.0 / 60.0, DVec3::new(0.0, 0.0, -G), vec![material(ground(DQuat::IDENTITY), 0.5, 0.0), light, heavy]);
    run(&mut w, 10.0);
    let gap = (w.bodies[2].state.position.z - 0.5) - (w.bodies[1].state.position.z + 0.5);
    eprintln!(
        "10:1 stack: overlap {:.2e} m; light box into the ground {:.2e} m",
        -gap,
        0.5 - w.bodies[1].state.position.z
    );
    assert!(-gap < 1e-3, "the heavy box sank {} m into the light one", -gap);
    let floor = w.bodies[1].state.position.z - 0.5;
    assert!(-floor < 1e-3, "the light box sank {} m into the ground", -floor);
}

#[test]
fn box_landing_flat_comes_to_rest_without_spinning() {
    let h = DVec3::new(0.3, 0.2, 0.1);
    let b = material(cuboid("box", h, 1.0, DVec3::new(0.0, 0.0, 1.1)), 0.5, 0.3);
    let mut w = world(1e-3, DVec3::new(0.0, 0.0, -G), vec![material(ground(DQuat::IDENTITY), 0.5, 0.3), b]);
    let e0 = w.energy();
    run(&mut w, 3.0);
    let s = w.bodies[1].state;
    assert!(s.velocity.length() < 1e-3 && s.omega_body.length() < 1e-3, "still moving: {s:?}");
    assert!((s.position.z - 0.1).abs() < 1e-3, "rests at z = {}", s.position.z);
    // energy bookkeeping: what was lost went to collisions and friction
    let lost = w.contact_energy();
    assert!(lost.collisions > 0.0);
    let balance = e0 - w.energy() - lost.collisions - lost.friction;
    assert!(balance.abs() < 0.02 * e0, "energy unaccounted for: {balance} J of {e0} J");
}

#[test]
fn deep_overlap_at_the_start_is_separated_gently() {
    // two boxes overlapping by half their size: pushed apart no faster than the correction cap
    let h = DVec3::splat(0.5);
    let a = cuboid("a", h, 1.0, DVec3::new(0.0, 0.0, 0.5));
    let b = cuboid("b", h, 1.0, DVec3::new(0.0, 0.0, 1.0));
    let mut w = world(1.0 / 60.0, DVec3::new(0.0, 0.0, -G), vec![ground(DQuat::IDENTITY), a, b]);
    let mut top_speed: f64 = 0.0;
    for _ in 0..300 {
        w.step().unwrap();
        top_speed = top_speed.max(w.bodies.iter().map(|b| b.state.velocity.length()).fold(0.0, f64::max));
    }
    assert!(top_speed <= 3.0 + G * 5.0, "a body reached {top_speed} m/s");
    let gap = (w.bodies[2].state.position.z - 0.5) - (w.bodies[1].state.position.z + 0.5);
    assert!(gap > -0.01, "still overlapping by {} m after 5 s", -gap);
}
