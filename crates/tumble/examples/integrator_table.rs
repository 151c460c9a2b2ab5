//! Prints a markdown table that compares the integrators on a torque-free body against the exact
//! (Jacobi elliptic) solution.
//!
//! Run: `cargo run --release -p tumble --example integrator_table`
//!
//! The body: principal moments `I = (1, 2, 3)` kg·m², no gravity, no loads. Two runs of 100 s each:
//! spun close to the intermediate axis, `ω_body(0) = (0.01, 5, 0.01)` rad/s (it flips every
//! 5.0259 s), and a generic tumble, `ω_body(0) = (1, 0.5, −0.8)` rad/s. Columns:
//! - `max |ΔE|/E`: the largest relative kinetic-energy error over the run;
//! - `max |Δ|L||/|L|`: the largest relative error of the magnitude of the world angular momentum;
//! - `max |Δω|/|ω|`: the largest angular-velocity error against the exact solution, relative to |ω(0)|;
//! - `max ∠Δq`: the largest orientation error against the exact solution, the angle of `q_exact⁻¹ q` (rad);
//! - `flip interval error` (first run): the mean time between sign changes of `ω2` (interpolated
//!   between steps) against `2K(m)/λ`;
//! - `ns/step`: wall time per step of `World::step` alone (the fastest of 40 bursts of 2000 steps).
//!
//! `dopri5` runs with its default tolerances (`rtol = 1e-9`, `atol = 1e-12`); `dt` is then its output
//! step and its largest internal step.

use std::time::Instant;
use tumble::analytic::AsymmetricTop;
use tumble::math::{DQuat, DVec3};
use tumble::{Integrator, MassProperties, RigidBody, World, WorldConfig};

const INERTIA: DVec3 = DVec3::new(1.0, 2.0, 3.0);
const DURATION: f64 = 100.0;

fn world(integrator: Integrator, dt: f64, omega_body: DVec3) -> World {
    let mut body = RigidBody::new("body", MassProperties::from_principal(1.0, INERTIA).expect("valid moments"));
    body.state.omega_body = omega_body;
    let config = WorldConfig { gravity: DVec3::ZERO, dt, duration: DURATION, integrator, ..Default::default() };
    World::new(config, vec![body])
}

struct Row {
    energy: f64,
    momentum: f64,
    omega: f64,
    orientation: f64,
    flip: f64,
    ns_per_step: f64,
}

fn measure(integrator: Integrator, dt: f64, omega0: DVec3) -> Row {
    let top = AsymmetricTop::new(INERTIA, omega0).expect("I1 < I2 < I3").with_orientation(DQuat::IDENTITY);
    let steps = (DURATION / dt).round() as u64;
    // timing: the step alone; the fastest of 40 bursts of 2000 steps from t = 0, which filters out the moments
    // when the core is busy with something else
    let mut ns_per_step = f64::INFINITY;
    for _ in 0..40 {
        let mut w = world(integrator, dt, omega0);
        let start = Instant::now();
        for _ in 0..2000 {
            w.step().expect("finite state");
        }
        ns_per_step = ns_per_step.min(start.elapsed().as_nanos() as f64 / 2000.0);
        std::hint::black_box(&w);
    }
    // errors
    let mut w = world(integrator, dt, omega0);
    let (e0, l0) = (w.energy(), w.angular_momentum().length());
    let (mut energy, mut momentum, mut omega, mut orientation): (f64, f64, f64, f64) = (0.0, 0.0, 0.0, 0.0);
    let mut previous = omega0.y;
    let mut flips = Vec::new();
    for _ in 0..steps {
        w.step().expect("finite state");
        let t = w.time();
        let s = &w.bodies[0].state;
        energy = energy.max(((w.energy() - e0) / e0).abs());
        momentum = momentum.max((w.angular_momentum().length() - l0).abs() / l0);
        omega = omega.max((s.omega_body - top.omega_body(t)).length() / omega0.length());
        let d = s.orientation * top.orientation(t).conjugate();
        orientation = orientation.max(2.0 * DVec3::new(d.x, d.y, d.z).length().atan2(d.w.abs()));
        let current = s.omega_body.y;
        if current * previous < 0.0 {
            flips.push(t - dt + dt * previous / (previous - current));
        }
        previous = current;
    }
    let flip = if flips.len() >= 2 {
        let mean = (flips[flips.len() - 1] - flips[0]) / (flips.len() - 1) as f64;
        mean / top.flip_interval() - 1.0
    } else {
        f64::NAN
    };
    Row { energy, momentum, omega, orientation, flip, ns_per_step }
}

fn table(title: &str, omega0: DVec3, with_flip: bool) {
    println!("### {title}\n");
    let top = AsymmetricTop::new(INERTIA, omega0).expect("I1 < I2 < I3");
    let (w, flip) = (omega0, top.flip_interval());
    print!("`I = (1, 2, 3)` kg·m², `ω_body(0) = ({}, {}, {})` rad/s, {DURATION} s; ", w.x, w.y, w.z);
    println!("`ω2` changes sign every `2K/λ` = {flip:.7} s.\n");
    let flip_head = if with_flip { " flip interval error |" } else { "" };
    let flip_rule = if with_flip { "---:|" } else { "" };
    let errors = r"max \|ΔE\|/E | max \|Δ\|L\|\|/\|L\| | max \|Δω\|/\|ω\| | max ∠Δq (rad)";
    println!("| integrator | dt (s) | {errors} |{flip_head} ns/step |");
    println!("|---|---:|---:|---:|---:|---:|{flip_rule}---:|");
    for integrator in Integrator::ALL {
        for dt in [1e-2, 1e-3] {
            let r = measure(integrator, dt, omega0);
            let flip = if with_flip { format!(" {:.1e} |", r.flip) } else { String::new() };
            println!(
                "| `{integrator}` | {dt:.0e} | {:.1e} | {:.1e} | {:.1e} | {:.1e} |{flip} {:.0} |",
                r.energy, r.momentum, r.omega, r.orientation, r.ns_per_step
            );
        }
    }
    println!();
}

fn main() {
    table("Near the intermediate axis (the flip)", DVec3::new(0.01, 5.0, 0.01), true);
    table("A generic tumble", DVec3::new(1.0, 0.5, -0.8), false);
}
