//! Body-steps per second of `World::step` on N free tumbling bodies under gravity (default 10,000),
//! per integrator, no output: the best of 200 short rounds (about 20,000 body-steps each, a few
//! milliseconds), so that on a shared machine some rounds run without being descheduled.
//! `cargo run --release -p tumble --example many -- [N] [INTEGRATOR] [K]`: with `K`, one body's
//! velocity is changed every `K` steps (as a caller applying actions every `K` steps would), so
//! that under `semi_implicit_euler` the step's own layout of the bodies is dropped and made again.
use tumble::math::{DQuat, DVec3};
use tumble::*;
fn main() {
    let n: usize = std::env::args().nth(1).map(|s| s.parse().unwrap()).unwrap_or(10_000);
    let steps = (20_000 / n).max(1);
    let only: Option<Integrator> = std::env::args().nth(2).map(|s| s.parse().expect("an integrator name"));
    let edit_every: Option<usize> = std::env::args().nth(3).map(|s| s.parse().expect("a number of steps"));
    // rounds of whole edit cycles
    let steps = edit_every.map_or(steps, |k| steps.div_ceil(k) * k);
    for integ in Integrator::ALL.into_iter().filter(|i| only.is_none_or(|o| o == *i)) {
        let mut bodies = Vec::with_capacity(n);
        for i in 0..n {
            let f = i as f64 / n as f64;
            let mp = MassProperties::from_principal(1.0 + f, DVec3::new(1.0, 2.0 + f, 3.0 + f)).unwrap();
            let mut b = RigidBody::new(format!("b{i}"), mp);
            b.state.position = DVec3::new(i as f64, 0.0, 0.0);
            b.state.orientation = DQuat::from_rotation_x(f);
            b.state.velocity = DVec3::new(0.0, 1.0, 2.0);
            b.state.omega_body = DVec3::new(0.3, 2.0 + f, 0.1);
            bodies.push(b);
        }
        let cfg = WorldConfig { dt: 1e-3, integrator: integ, ..Default::default() };
        let mut w = World::new(cfg, bodies);
        // best of many short rounds: the machine may be busy
        let mut el = f64::INFINITY;
        let mut step = 0;
        for _ in 0..200 {
            let t0 = std::time::Instant::now();
            for _ in 0..steps {
                if edit_every.is_some_and(|k| step % k == 0) {
                    w.bodies[step % n].state.velocity.x += 1e-6;
                }
                step += 1;
                w.step().unwrap();
            }
            el = el.min(t0.elapsed().as_secs_f64());
        }
        let line = format!("{:20} {:8.2} M body-steps/s\n", integ.name(), (n * steps) as f64 / el / 1e6);
        if std::io::Write::write_all(&mut std::io::stdout(), line.as_bytes()).is_err() {
            return;
        }
    }
}
