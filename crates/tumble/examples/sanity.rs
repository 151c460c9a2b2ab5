use tumble::math::DVec3;
use tumble::*;
fn main() {
    for integ in Integrator::ALL {
        let mp = MassProperties::from_principal(1.0, DVec3::new(1.0, 2.0, 3.0)).unwrap();
        let mut b = RigidBody::new("a", mp);
        b.state.omega_body = DVec3::new(0.01, 5.0, 0.01);
        let cfg =
            WorldConfig { gravity: DVec3::ZERO, dt: 1e-3, duration: 20.0, integrator: integ, ..Default::default() };
        let mut w = World::new(cfg, vec![b]);
        let e0 = w.energy();
        let l0 = w.angular_momentum();
        let mut flips = 0;
        let mut last = 1.0f64;
        let mut first_flip = None;
        let t0 = std::time::Instant::now();
        for _ in 0..cfg.step_count() {
            w.step().unwrap();
            let s = w.bodies[0].state.omega_body.y.signum();
            if s != last {
                flips += 1;
                last = s;
                if first_flip.is_none() {
                    first_flip = Some(w.time());
                }
            }
        }
        println!(
            "{:20} dE/E={:.3e} dL={:.3e} flips={} first={:?} wall={:?}",
            integ.name(),
            (w.energy() - e0) / e0,
            (w.angular_momentum() - l0).length() / l0.length(),
            flips,
            first_flip,
            t0.elapsed()
        );
    }
}
