use super::*;
use crate::math::{quat_to_wxyz, DQuat, DVec3};
use crate::{MassProperties, RigidBody, World, WorldConfig};

fn body(name: &str, moments: [f64; 3]) -> RigidBody {
    RigidBody::new(name, MassProperties::from_principal(2.0, DVec3::from_array(moments)).unwrap())
}

/// A world whose values are hard to print: round-off, subnormals, huge and tiny magnitudes, −0.
fn awkward_world() -> World {
    let mut a = body("a", [1.0, 2.0, 3.0]);
    a.state.position = DVec3::new(0.1 + 0.2, -0.0, 5e-324);
    a.state.velocity = DVec3::new(1.7976931348623157e308 / 1e300, -1e-300, 1.0 / 3.0);
    a.state.orientation = DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 0.7);
    a.state.omega_body = DVec3::new(std::f64::consts::PI, -2.0 / 7.0, 1e10 / 3.0);
    let tensor = crate::math::DMat3::from_cols_array(&[2.0, 0.1, 0.0, 0.1, 3.0, 0.2, 0.0, 0.2, 4.0]);
    let mut b = RigidBody::new("b, \"quoted\"", MassProperties::from_tensor(1.5, tensor).unwrap());
    b.set_orientation_user(DQuat::from_rotation_z(0.3));
    b.set_omega_world(DVec3::new(0.3, 0.2, 0.1));
    let mut ground = body("ground", [1.0, 1.0, 1.0]);
    ground.fixed = true;
    let config = WorldConfig { dt: 0.1, ..Default::default() };
    World::new(config, vec![a, ground, b])
}

/// The 13 numbers written for a body, in column order.
fn expected_values(b: &RigidBody) -> Vec<f64> {
    let mut v = b.state.position.to_array().to_vec();
    v.extend(quat_to_wxyz(b.orientation_user()));
    v.extend(b.state.velocity.to_array());
    v.extend(b.state.omega_world().to_array());
    v
}

fn write(world: &World, format: Format, samples: usize) -> String {
    let mut writer = TrajectoryWriter::new(Vec::new(), format, world).unwrap();
    for _ in 0..samples {
        writer.write_sample(world).unwrap();
    }
    String::from_utf8(writer.finish().unwrap()).unwrap()
}

/// Splits one CSV line into fields (RFC 4180 quoting).
fn csv_fields(line: &str) -> Vec<String> {
    let mut fields = vec![String::new()];
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                chars.next();
                fields.last_mut().unwrap().push('"');
            }
            ('"', _) => quoted = !quoted,
            (',', false) => fields.push(String::new()),
            (c, _) => fields.last_mut().unwrap().push(c),
        }
    }
    fields
}

#[test]
fn csv_header_is_exactly_the_contract_and_fixed_bodies_are_left_out() {
    let world = awkward_world();
    let text = write(&world, Format::Csv, 2);
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], "t,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz");
    assert_eq!(lines.len(), 1 + 2 * 2, "two samples of two free bodies");
    assert!(text.ends_with('\n'));
    assert!(!text.contains("ground"));
    let names: Vec<String> = lines[1..].iter().map(|l| csv_fields(l)[1].clone()).collect();
    assert_eq!(names, ["a", "b, \"quoted\"", "a", "b, \"quoted\""]);
}

#[test]
fn csv_round_trip_is_bit_exact() {
    let world = awkward_world();
    let text = write(&world, Format::Csv, 1);
    let free: Vec<&RigidBody> = world.free_bodies().collect();
    for (line, b) in text.lines().skip(1).zip(&free) {
        let fields = csv_fields(line);
        assert_eq!(fields.len(), 15);
        assert_eq!(fields[0].parse::<f64>().unwrap().to_bits(), world.time().to_bits());
        let read: Vec<f64> = fields[2..].iter().map(|f| f.parse::<f64>().unwrap()).collect();
        let expected = expected_values(b);
        for (i, (r, e)) in read.iter().zip(&expected).enumerate() {
            assert_eq!(r.to_bits(), e.to_bits(), "column {} of {}: {r} vs {e}", i + 2, b.name);
        }
    }
    // the shortest text: 0.1 + 0.2 is written as 0.30000000000000004, never padded
    assert!(text.contains(",0.30000000000000004,"));
    assert!(text.contains(",-0.0,"), "the sign of zero is kept");
    assert!(text.contains("5e-324"));
}

#[test]
fn orientation_is_the_users_axes_and_angular_velocity_the_world_frame() {
    let world = awkward_world();
    let b = &world.bodies[2];
    assert_ne!(b.mass.user_from_body, DQuat::IDENTITY, "the tensor is not diagonal");
    let text = write(&world, Format::Csv, 1);
    let row = csv_fields(text.lines().nth(2).unwrap());
    let q: Vec<f64> = row[5..9].iter().map(|f| f.parse().unwrap()).collect();
    let user = DQuat::from_rotation_z(0.3);
    // q and −q are the same rotation
    let dot = q[0] * user.w + q[1] * user.x + q[2] * user.y + q[3] * user.z;
    assert!((dot.abs() - 1.0).abs() < 1e-12, "written {q:?}, user set {user:?}");
    let w: Vec<f64> = row[12..15].iter().map(|f| f.parse().unwrap()).collect();
    for (got, want) in w.iter().zip([0.3, 0.2, 0.1]) {
        assert!((got - want).abs() < 1e-14, "{w:?}");
    }
}

#[test]
fn json_lines_have_the_contract_shape_and_round_trip_bit_exactly() {
    let world = awkward_world();
    let text = write(&world, Format::JsonLines, 3);
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 3);
    for line in lines {
        let v: serde_json::Value = serde_json::from_str(line).unwrap();
        let object = v.as_object().unwrap();
        assert_eq!(object.keys().collect::<Vec<_>>(), ["bodies", "t"]);
        let bodies = v["bodies"].as_array().unwrap();
        assert_eq!(bodies.len(), 2);
        assert_eq!(bodies[1]["name"], "b, \"quoted\"");
        for b in bodies {
            let keys: Vec<&String> = b.as_object().unwrap().keys().collect();
            assert_eq!(keys, ["angular_velocity", "name", "orientation", "position", "velocity"]);
        }
        assert_eq!(bodies[0]["orientation"].as_array().unwrap().len(), 4);
        // bit exactness, read with Rust's correctly rounded parser: every number token in order
        let numbers: Vec<f64> = line
            .split(|c: char| !(c.is_ascii_digit() || "+-.e".contains(c)))
            .filter(|s| !s.is_empty() && s.chars().any(|c| c.is_ascii_digit()))
            .map(|s| s.parse().unwrap())
            .collect();
        let mut expected = vec![world.time()];
        for b in world.free_bodies() {
            expected.extend(expected_values(b));
        }
        assert_eq!(numbers.len(), expected.len());
        for (r, e) in numbers.iter().zip(&expected) {
            assert_eq!(r.to_bits(), e.to_bits(), "{r} vs {e}");
        }
    }
}

#[test]
fn a_non_finite_value_is_an_error_and_nothing_of_the_sample_is_written() {
    for format in [Format::Csv, Format::JsonLines] {
        let mut world = awkward_world();
        let mut writer = TrajectoryWriter::new(Vec::new(), format, &world).unwrap();
        writer.write_sample(&world).unwrap();
        writer.flush().unwrap();
        let before = writer.get_ref().clone();
        world.bodies[2].state.velocity.y = f64::NAN;
        let err = writer.write_sample(&world).unwrap_err();
        match &err {
            TrajectoryError::NonFinite { body, quantity, .. } => {
                assert_eq!(body, "b, \"quoted\"");
                assert_eq!(*quantity, "velocity");
            }
            other => panic!("{other:?}"),
        }
        assert!(err.to_string().contains("velocity is not finite"));
        world.bodies[2].state.velocity.y = 0.0;
        world.bodies[0].state.omega_body.z = f64::INFINITY;
        assert!(matches!(writer.write_sample(&world), Err(TrajectoryError::NonFinite { .. })));
        let after = writer.finish().unwrap();
        assert_eq!(before, after, "{format:?}: the bad samples left no trace");
        let text = String::from_utf8(after).unwrap();
        assert!(!text.contains("NaN") && !text.contains("null") && !text.contains("inf"));
    }
}

#[test]
fn the_world_may_not_change_its_bodies_under_a_writer() {
    let mut world = awkward_world();
    let mut writer = TrajectoryWriter::new(std::io::sink(), Format::Csv, &world).unwrap();
    world.bodies.pop();
    assert!(matches!(writer.write_sample(&world), Err(TrajectoryError::BodiesChanged { expected: 3, got: 2 })));
}

#[test]
fn format_follows_the_extension() {
    use std::path::Path;
    assert_eq!(Format::from_path(Path::new("out/a.csv")), Some(Format::Csv));
    assert_eq!(Format::from_path(Path::new("a.JSONL")), Some(Format::JsonLines));
    assert_eq!(Format::from_path(Path::new("a.json")), None);
    assert_eq!(Format::from_path(Path::new("csv")), None);
}

/// A torque-free body spun about its intermediate axis (the demo's flipper).
fn flipper_world(integrator: crate::Integrator) -> World {
    let mut flipper = body("flipper", [1.0, 2.0, 3.0]);
    flipper.state.omega_body = DVec3::new(0.01, 5.0, 0.01);
    let mut stable = body("stable", [1.0, 2.0, 3.0]);
    stable.state.omega_body = DVec3::new(0.01, 0.01, 5.0);
    let mut top = body("top", [1.0, 1.0, 2.0]);
    top.state.omega_body = DVec3::new(0.1, 0.0, 3.0);
    let config = WorldConfig { gravity: DVec3::ZERO, dt: 1e-3, integrator, ..Default::default() };
    World::new(config, vec![flipper, stable, top])
}

#[test]
fn the_intermediate_axis_exists_only_for_distinct_moments() {
    assert_eq!(FlipCounter::intermediate_axis(DVec3::new(1.0, 2.0, 3.0)), Some(1));
    assert_eq!(FlipCounter::intermediate_axis(DVec3::new(3.0, 1.0, 2.0)), Some(2));
    assert_eq!(FlipCounter::intermediate_axis(DVec3::new(2.0, 3.0, 1.0)), Some(0));
    assert_eq!(FlipCounter::intermediate_axis(DVec3::new(1.0, 1.0, 2.0)), None);
    assert_eq!(FlipCounter::intermediate_axis(DVec3::new(1.0, 2.0, 2.0)), None);
    assert_eq!(FlipCounter::intermediate_axis(DVec3::splat(1.0)), None);
}

#[test]
fn a_flip_is_a_turn_of_the_intermediate_axis_from_l_to_minus_l() {
    let mut c = FlipCounter::new(0, 1);
    let l = |cosine: f64| DVec3::new((1.0 - cosine * cosine).max(0.0).sqrt(), cosine, 0.0);
    // wobbles about zero are no flip; 0/0 and NaN are skipped
    let mut t = 0.0;
    let mut sample = |c: &mut FlipCounter, l_body: DVec3| {
        t += 1.0;
        c.observe(l_body, t);
    };
    for cosine in [0.1, -0.1, 0.4, -0.4, 0.2] {
        sample(&mut c, l(cosine));
    }
    sample(&mut c, DVec3::ZERO);
    sample(&mut c, DVec3::NAN);
    assert_eq!(c.count, 0);
    assert_eq!(c.mean_interval(), None);
    // samples at t = 8, 9, ..., 17: flips seen at t = 11 (−0.6), 15 (0.5) and 17 (−0.5)
    for cosine in [0.9, 0.3, -0.3, -0.6, -1.0, 0.0, 0.49, 0.5, 1.0, -0.5] {
        sample(&mut c, l(cosine));
    }
    assert_eq!(c.count, 3);
    assert_eq!((c.first_flip_time, c.last_flip_time), (11.0, 17.0));
    assert_eq!(c.mean_interval(), Some(3.0));
}

#[test]
fn the_monitor_counts_the_flips_of_the_intermediate_axis_only() {
    let mut world = flipper_world(crate::Integrator::Rk4);
    let mut monitor = Monitor::new(&world);
    assert_eq!(monitor.flips().len(), 2, "the symmetric top has no intermediate axis");
    // 20 s: flips every 5.026 s (notes/torque-free.md), the first after half of that: 2.5, 7.5, 12.6, 17.6 s
    for step in 1..=20_000 {
        world.step().unwrap();
        if step % 10 == 0 {
            monitor.observe(&world);
        }
    }
    let flips = monitor.flips();
    assert_eq!(world.bodies[flips[0].body].name, "flipper");
    assert_eq!(flips[0].count, 4, "flipper");
    assert_eq!(world.bodies[flips[1].body].name, "stable");
    assert_eq!(flips[1].count, 0, "spin about the largest axis is stable");
    assert_eq!(monitor.samples(), 2001);
    assert!(monitor.max_energy_error() > 0.0 && monitor.max_energy_error() < 1e-6);
    assert!(!monitor.energy_error_is_absolute());
}

#[test]
fn explicit_euler_shows_a_larger_energy_error_than_rk4() {
    let errors: Vec<f64> = [crate::Integrator::Euler, crate::Integrator::Rk4]
        .into_iter()
        .map(|integrator| {
            let mut world = flipper_world(integrator);
            let mut monitor = Monitor::new(&world);
            for _ in 0..2000 {
                world.step().unwrap();
                monitor.observe(&world);
            }
            monitor.max_energy_error()
        })
        .collect();
    assert!(errors[0] > 1e3 * errors[1], "euler {} vs rk4 {}", errors[0], errors[1]);
}

#[test]
fn a_zero_initial_value_gives_the_absolute_error() {
    assert_eq!(relative_error(2.0, 4.0), 0.5);
    assert_eq!(relative_error(2.0, 0.0), 2.0);
    // a body falling from rest at the origin: E₀ = 0 and L₀ = 0
    let config = WorldConfig { dt: 1e-2, ..Default::default() };
    let mut world = World::new(config, vec![body("stone", [1.0, 1.0, 1.0])]);
    let mut monitor = Monitor::new(&world);
    assert!(monitor.energy_error_is_absolute() && monitor.angular_momentum_error_is_absolute());
    world.bodies[0].state.velocity.z = -1.0; // an energy error of exactly 1 J (m = 2 kg)
    monitor.observe(&world);
    assert_eq!(monitor.max_energy_error(), 1.0);
}

/// A passive body whose energy rises by more than 1 % of its kinetic energy between two samples is
/// flagged once, at the first such sample; a smaller rise, a body at rest (round-off) and a body
/// under a load are not.
#[test]
fn the_monitor_flags_the_first_energy_rise_of_a_passive_system() {
    let config = WorldConfig { dt: 1e-2, gravity: DVec3::ZERO, ..Default::default() };
    let moving = |v: f64| {
        let mut stone = body("stone", [1.0, 1.0, 1.0]);
        stone.state.velocity.x = v;
        World::new(config, vec![stone])
    };
    // T = ½ · 2 kg · v²: from 1 J, +0.5 % then +1.5 % of the kinetic energy
    let mut world = moving(1.0);
    let mut monitor = Monitor::new(&world);
    world.bodies[0].state.velocity.x = 1.005f64.sqrt();
    monitor.observe(&world);
    assert_eq!(monitor.instability(), None, "a rise of 0.5 %");
    world.bodies[0].state.velocity.x = 1.02f64.sqrt();
    for _ in 0..3 {
        world.step().unwrap(); // free flight: the energy is unchanged
    }
    monitor.observe(&world);
    let rise = monitor.instability().expect("a rise of 1.5 %");
    assert_eq!(rise.time, world.time());
    assert!((rise.rise - 0.015).abs() < 1e-12 && (rise.relative - 0.015 / 1.005).abs() < 1e-12, "{rise:?}");
    let message = rise.to_string();
    assert!(message.starts_with("possible instability at t = 0.03 s: energy rose by 1.500e-2 J"), "{message}");
    assert!(message.ends_with("reduce dt or use a structure-preserving integrator"), "{message}");
    // once: a later, larger rise leaves the first
    world.bodies[0].state.velocity.x = 2.0;
    monitor.observe(&world);
    assert_eq!(monitor.instability(), Some(rise));
    let summary = Summary::new(&world, &monitor, 0.0, StopReason::Completed, "<test>");
    let v: serde_json::Value = serde_json::from_str(&summary.to_json().unwrap()).unwrap();
    assert_eq!(v["instability"]["time"].as_f64(), Some(0.03));
    assert_eq!(v["instability"]["energy_rise"].as_f64(), Some(rise.rise));

    // at rest: no kinetic energy, no scale, no flag
    let mut world = moving(0.0);
    let mut monitor = Monitor::new(&world);
    world.bodies[0].state.position.z = 1.0;
    monitor.observe(&world);
    assert_eq!(monitor.instability(), None);
    // a constant force does work: not passive, no flag
    let mut world = moving(1.0);
    world.bodies[0].loads.force_world = DVec3::X;
    let mut monitor = Monitor::new(&world);
    world.bodies[0].state.velocity.x = 2.0;
    monitor.observe(&world);
    assert_eq!(monitor.instability(), None);
    // and without a flag the summary has no `instability`
    let summary = Summary::new(&world, &monitor, 0.0, StopReason::Completed, "<test>");
    assert!(!summary.to_json().unwrap().contains("instability"));
}

#[test]
fn summary_json_has_the_contract_fields() {
    let mut world = flipper_world(crate::Integrator::Splitting);
    let mut monitor = Monitor::new(&world);
    for _ in 0..100 {
        world.step().unwrap();
        monitor.observe(&world);
    }
    let summary = Summary::new(&world, &monitor, 0.25, StopReason::Completed, "<test>");
    let text = summary.to_json().unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(v["steps"], 100);
    assert_eq!(v["simulated_time"].as_f64().unwrap(), world.time());
    assert_eq!(v["wall_time_s"], 0.25);
    assert_eq!(v["bodies"], 3);
    assert_eq!(v["integrator"], "splitting");
    assert_eq!(v["dt"], 1e-3);
    for key in ["initial", "final", "max_relative_error"] {
        assert!(v["energy"][key].is_f64(), "energy.{key}");
    }
    for key in ["initial", "final"] {
        assert_eq!(v["linear_momentum"][key].as_array().unwrap().len(), 3);
        assert_eq!(v["angular_momentum"][key].as_array().unwrap().len(), 3);
    }
    assert!(v["angular_momentum"]["max_relative_error"].as_f64().unwrap() < 1e-12, "splitting keeps L");
    assert_eq!(v["stopped"], "completed");
    assert_eq!(v["flips"][0]["body"], "flipper");
    let back: Summary = serde_json::from_str(&text).unwrap();
    assert_eq!((back.steps, back.stopped, back.flips), (summary.steps, summary.stopped, summary.flips));
}

#[test]
fn a_non_finite_summary_is_refused_naming_the_field() {
    let world = flipper_world(crate::Integrator::Rk4);
    let monitor = Monitor::new(&world);
    let mut summary = Summary::new(&world, &monitor, 0.0, StopReason::Completed, "<test>");
    summary.angular_momentum.final_[1] = f64::NAN;
    match summary.to_json() {
        Err(TrajectoryError::NonFiniteSummary { field }) => assert_eq!(field, "angular_momentum.final[1]"),
        other => panic!("{other:?}"),
    }
    summary.angular_momentum.final_[1] = 0.0;
    summary.wall_time_s = f64::INFINITY;
    assert!(summary.to_json().unwrap_err().to_string().contains("wall_time_s"));
}

mod round_trip {
    use super::*;
    use proptest::prelude::*;

    /// Any finite `f64`: normal, subnormal, zero of either sign, of any magnitude.
    fn finite() -> impl Strategy<Value = f64> {
        use proptest::num::f64::{NEGATIVE, NORMAL, POSITIVE, SUBNORMAL, ZERO};
        POSITIVE | NEGATIVE | NORMAL | SUBNORMAL | ZERO
    }

    /// A moderate `f64`, so that rotating it stays finite.
    fn moderate() -> impl Strategy<Value = f64> {
        finite().prop_map(|x| if x.abs() > 1e150 { x * 1e-160 } else { x })
    }

    proptest! {
        #[test]
        fn every_written_number_reads_back_bit_exactly(
            position in [finite(), finite(), finite()],
            velocity in [finite(), finite(), finite()],
            omega in [moderate(), moderate(), moderate()],
            axis in [-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64],
            angle in -10.0..10.0f64,
            steps in 0u64..1_000_000,
        ) {
            let mut b = body("p", [1.0, 2.0, 3.0]);
            b.state.position = DVec3::from_array(position);
            b.state.velocity = DVec3::from_array(velocity);
            b.state.omega_body = DVec3::from_array(omega);
            b.state.orientation = DQuat::from_scaled_axis(DVec3::from_array(axis).normalize_or_zero() * angle);
            let config = WorldConfig { dt: 1.0 / 3.0, ..Default::default() };
            let mut world = World::new(config, vec![b]);
            for _ in 0..steps % 3 {
                world.step().unwrap_or_default();
            }
            let expected = expected_values(&world.bodies[0]);
            prop_assume!(expected.iter().all(|x| x.is_finite()));
            let csv = write(&world, Format::Csv, 1);
            let row = csv_fields(csv.lines().nth(1).unwrap());
            prop_assert_eq!(row[0].parse::<f64>().unwrap().to_bits(), world.time().to_bits());
            for (text, e) in row[2..].iter().zip(&expected) {
                prop_assert_eq!(text.parse::<f64>().unwrap().to_bits(), e.to_bits(), "{} vs {}", text, e);
            }
        }
    }
}

/// The demo's flipper: the mean time between the flips the monitor sees matches the exact interval
/// `2K/λ` of the torque-free body to the sampling resolution, and the stable body reports none.
#[test]
fn demo_flip_interval_matches_the_exact_one() {
    let mut world = crate::scene::demo().world;
    let mut monitor = Monitor::new(&world);
    let every = world.config.sample_every;
    for _ in 0..world.config.step_count() {
        world.step().unwrap();
        if world.steps().is_multiple_of(every) {
            monitor.observe(&world);
        }
    }
    let summary = Summary::new(&world, &monitor, 0.0, StopReason::Completed, "demo");
    let flipper = &summary.flips[0];
    let stable = &summary.flips[1];
    assert!(flipper.flips >= 4, "{flipper:?}");
    let (mean, exact) = (flipper.mean_interval.unwrap(), flipper.exact_interval.unwrap());
    // each flip is seen at the first sample past it: the mean is exact to ± one sampling interval / (n − 1)
    let resolution = every as f64 * world.config.dt / (flipper.flips - 1) as f64;
    assert!((mean - exact).abs() <= resolution, "mean {mean} s, exact {exact} s, resolution {resolution} s");
    assert_eq!((stable.flips, stable.mean_interval, stable.exact_interval), (0, None, None));
    assert_eq!((flipper.counted_until, stable.counted_until), (None, None), "the floating pair never touches");
    // the thrown box is watched until it lands (~0.86 s): bouncing and lying on the floor, where its
    // angular momentum is round-off, it would count flips that are none
    let thrown = summary.flips.iter().find(|f| f.body == "box").unwrap();
    let landed = thrown.counted_until.unwrap();
    assert!(landed > 0.7 && landed < 1.0, "first contact at {landed} s");
    assert_eq!(thrown.flips, 0, "{thrown:?}");
    assert_eq!(world.first_contact_time(0), None);
}
