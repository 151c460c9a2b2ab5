//! Per-body `gravity_scale`: a body's gravitational acceleration is `gravity_scale · g` in every
//! stage that applies gravity (the free-body integrators, the contact stage, the potential energy),
//! and scene files read, check and describe it.

mod contact_support;
use contact_support::*;
use tumble::math::{DQuat, DVec3};
use tumble::scene::{from_str, Format};
use tumble::{Integrator, World, WorldConfig};

const G: DVec3 = DVec3::new(0.0, 0.0, -9.81);

/// A spinning box thrown with `velocity`, of gravity scale `scale`, alone in a world of gravity `G`.
fn thrown(scale: f64, velocity: DVec3, integrator: Integrator) -> World {
    let mut b = cuboid("b", DVec3::new(0.3, 0.2, 0.1), 2.0, DVec3::new(0.0, 0.0, 5.0));
    b.gravity_scale = scale;
    b.state.velocity = velocity;
    b.state.omega_body = DVec3::new(0.1, 3.0, 0.2);
    let config = WorldConfig { dt: 1e-3, gravity: G, integrator, ..WorldConfig::default() };
    World::new(config, vec![b])
}

#[test]
fn a_body_with_gravity_scale_zero_keeps_its_velocity() {
    let v0 = DVec3::new(1.0, -2.0, 0.5);
    for integrator in Integrator::ALL {
        let mut w = thrown(0.0, v0, integrator);
        for _ in 0..1000 {
            w.step().unwrap();
        }
        let s = w.bodies[0].state;
        assert_eq!(s.velocity, v0, "{integrator}");
        let expected = DVec3::new(0.0, 0.0, 5.0) + v0 * w.time();
        assert!((s.position - expected).length() < 1e-12, "{integrator}: at {:?}, expected {expected:?}", s.position);
    }
}

#[test]
fn a_body_with_gravity_scale_one_half_falls_at_half_g() {
    let v0 = DVec3::new(0.5, 0.0, 2.0);
    for integrator in Integrator::ALL {
        let mut w = thrown(0.5, v0, integrator);
        for _ in 0..1000 {
            w.step().unwrap();
        }
        let (s, t) = (w.bodies[0].state, w.time());
        let g = 0.5 * G;
        // a constant acceleration: every integrator gets the velocity to round-off
        let v = v0 + g * t;
        assert!((s.velocity - v).length() < 1e-9, "{integrator}: v = {:?}, expected {v:?}", s.velocity);
        // the position to the method's order: the Euler methods are off by ½ |g| t dt = 2.5 mm
        let x = DVec3::new(0.0, 0.0, 5.0) + v0 * t + 0.5 * g * t * t;
        let first_order = matches!(integrator, Integrator::Euler | Integrator::SemiImplicitEuler);
        let tolerance = if first_order { 3e-3 } else { 1e-9 };
        assert!((s.position - x).length() < tolerance, "{integrator}: x = {:?}, expected {x:?}", s.position);
    }
}

#[test]
fn energy_with_the_scaled_potential_is_conserved() {
    for scale in [0.5, -0.25, 2.0] {
        let mut w = thrown(scale, DVec3::new(0.5, 0.0, 2.0), Integrator::Rk4);
        let e0 = w.energy();
        let naive = |w: &World| {
            let b = &w.bodies[0];
            b.kinetic_energy() - b.mass.mass * G.dot(b.state.position)
        };
        let naive0 = naive(&w);
        for _ in 0..1000 {
            w.step().unwrap();
        }
        let error = (w.energy() - e0).abs() / e0.abs();
        assert!(error < 1e-10, "scale {scale}: relative energy error {error:e}");
        // the potential of the world's gravity would not be conserved
        assert!((naive(&w) - naive0).abs() > 1.0, "scale {scale}");
    }
}

#[test]
fn a_body_at_half_gravity_rests_on_the_floor_and_bounces_to_e_squared_h() {
    // resting: the contact stage predicts the end-of-step velocity with the body's own gravity
    let mut resting = material(cuboid("box", DVec3::new(0.5, 0.5, 0.5), 1.0, DVec3::new(0.0, 0.0, 0.5)), 0.5, 0.0);
    resting.gravity_scale = 0.5;
    let mut w = world(1e-3, G, vec![ground(DQuat::IDENTITY), resting]);
    for _ in 0..2000 {
        w.step().unwrap();
    }
    let s = w.bodies[1].state;
    assert!((s.position.z - 0.5).abs() < 1e-3, "the box sank or rose: z = {}", s.position.z);
    assert!(s.velocity.length() < 1e-6, "the box moves: {:?}", s.velocity);

    // bouncing: the closing time inside the step uses the body's gravity; rebound e² h
    let (r, h, e) = (0.1, 1.0, 0.5);
    let mut ball = material(sphere("ball", r, 1.0, DVec3::new(0.0, 0.0, r + h)), 0.0, e);
    ball.gravity_scale = 0.5;
    let mut w = world(1e-3, G, vec![material(ground(DQuat::IDENTITY), 0.0, e), ball]);
    let (mut top, mut bounced) = (0.0_f64, false);
    while w.time() < 3.0 {
        w.step().unwrap();
        let s = w.bodies[1].state;
        bounced |= s.velocity.z > 0.0;
        if bounced {
            top = top.max(s.position.z - r);
            if s.velocity.z < 0.0 {
                break;
            }
        }
    }
    let expected = e * e * h;
    assert!((top - expected).abs() < 0.01 * expected, "rebound {top} m, expected {expected} m");
    // it took √(2h / (g/2)) to fall: it is still in the air at the time a full-gravity body lands
    assert!(w.time() > 2.0 * (2.0 * h / 9.81_f64).sqrt());
}

#[test]
fn a_floating_body_above_the_floor_is_untouched_by_contacts() {
    // gravity scale 0 just above a floor: no contact, its state evolves as in free space
    let mut b = cuboid("b", DVec3::new(0.3, 0.2, 0.1), 2.0, DVec3::new(0.0, 0.0, 0.2));
    b.gravity_scale = 0.0;
    b.state.velocity = DVec3::new(0.3, 0.0, 0.0);
    let mut w = world(1e-3, G, vec![ground(DQuat::IDENTITY), b]);
    for _ in 0..1000 {
        w.step().unwrap();
    }
    assert_eq!(w.bodies[1].state.velocity, DVec3::new(0.3, 0.0, 0.0));
    assert!(w.contact_stage().contacts().is_empty());
}

fn load(text: &str) -> Result<tumble::scene::Scene, String> {
    from_str(text, "g.toml", Format::Toml).map_err(|e| e.to_string())
}

const BODY: &str = "version = 1\n[[body]]\nname = \"b\"\nmass = 1.0\ninertia = [1.0, 1.0, 1.0]\n";

#[test]
fn scenes_read_gravity_scale_and_describe_it() {
    let s = load(&format!("{BODY}gravity_scale = 0.5\n")).unwrap();
    assert_eq!(s.world.bodies[0].gravity_scale, 0.5);
    assert!(s.describe().contains("gravity      0.5 × the world's = [0, 0, -4.905] m/s²"), "{}", s.describe());
    let s = load(BODY).unwrap();
    assert_eq!(s.world.bodies[0].gravity_scale, 1.0, "default");
    assert!(!s.describe().contains("× the world's"));
    // any sign: a negative scale falls upwards
    let s = load(&format!("{BODY}gravity_scale = -1.0\n")).unwrap();
    assert_eq!(s.world.bodies[0].gravity(s.world.config.gravity), DVec3::new(0.0, 0.0, 9.81));
    // grid templates take it too
    let s = load(
        "version = 1\n[[grid]]\ncount = [2, 1, 1]\nspacing = [1.0, 1.0, 1.0]\n[grid.body]\nname = \"g\"\n\
         mass = 1.0\ninertia = [1.0, 1.0, 1.0]\ngravity_scale = 0.0\n",
    )
    .unwrap();
    assert!(s.world.bodies.iter().all(|b| b.gravity_scale == 0.0));
}

#[test]
fn bad_gravity_scales_name_the_file_line_column_and_field() {
    let cases = [
        ("gravity_scale = nan", "must be finite"),
        ("gravity_scale = inf", "must be finite"),
        ("gravity_scale = 1e300", "above the limit of 1e6 m/s²"),
        ("gravity_scale = \"half\"", "gravity_scale"),
    ];
    for (line, problem) in cases {
        let err = load(&format!("{BODY}{line}\n")).unwrap_err();
        assert!(err.contains("g.toml:6:17"), "`{line}`: no position in {err}");
        assert!(err.contains("body[0].gravity_scale"), "`{line}`: {err}");
        assert!(err.contains(problem), "`{line}`: {err}");
    }
    let fixed =
        "version = 1\n[[body]]\nname = \"floor\"\nfixed = true\nshape = { type = \"plane\" }\ngravity_scale = 0.0\n";
    let err = load(fixed).unwrap_err();
    assert!(err.contains("body[0].gravity_scale") && err.contains("a fixed body never moves"), "{err}");
    assert!(load(&fixed.replace("0.0\n", "1.0\n")).is_ok(), "the default on a fixed body is accepted");
}
