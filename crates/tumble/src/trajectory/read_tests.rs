//! Reading trajectories back: round trips, bad files, truncation, decimation, the derived quantities.

use super::*;
use crate::scene;
use crate::trajectory::derived::{self, InvariantErrors};
use crate::trajectory::{Invariants, TrajectoryWriter};

/// The demo's floating pair (`flipper` and `stable`, torque-free) stepped `steps` times, written
/// every step in `format`; with the invariants of each written state.
fn demo_file(format: Format, steps: usize) -> (String, World, Vec<Invariants>) {
    let mut world = scene::demo().world;
    world.bodies.truncate(2);
    world.config.dt = 0.01;
    let start = world.clone();
    let mut writer = TrajectoryWriter::new(Vec::new(), format, &world).unwrap();
    let mut invariants = Vec::new();
    for i in 0..=steps {
        if i > 0 {
            world.step().unwrap();
        }
        writer.write_sample(&world).unwrap();
        invariants.push(Invariants::of(&world));
    }
    (String::from_utf8(writer.finish().unwrap()).unwrap(), start, invariants)
}

fn read_text(text: &str, format: Format) -> Result<Trajectory, ReadError> {
    read_from(text.as_bytes(), format, "t.csv", ReadOptions::default())
}

#[test]
fn a_written_trajectory_reads_back_exactly() {
    for format in [Format::Csv, Format::JsonLines] {
        let (text, world, _) = demo_file(format, 20);
        let trajectory = read_text(&text, format).unwrap();
        assert_eq!(trajectory.bodies, ["flipper", "stable"]);
        assert_eq!(trajectory.frames.len(), 21);
        assert_eq!((trajectory.frames_in_file, trajectory.stride, trajectory.truncated.clone()), (21, 1, None));
        let first = &trajectory.frames[0];
        assert_eq!(first.t, 0.0);
        assert_eq!(first.states[1].position, world.bodies[1].state.position);
        assert_eq!(first.states[0].angular_velocity, world.bodies[0].state.omega_world());
        assert!((trajectory.frames[20].t - 0.2).abs() < 1e-12);
    }
}

#[test]
fn invariants_read_back_are_those_of_the_run() {
    let (text, world, expected) = demo_file(Format::Csv, 50);
    let trajectory = read_text(&text, Format::Csv).unwrap();
    let got = derived::invariants(&trajectory, &world, "t.csv", "demo").unwrap();
    assert_eq!(got.len(), expected.len());
    for (g, e) in got.iter().zip(&expected) {
        assert!((g.energy - e.energy).abs() <= 1e-13 * e.energy.abs(), "{} vs {}", g.energy, e.energy);
        assert!((g.angular_momentum - e.angular_momentum).length() <= 1e-13 * e.angular_momentum.length());
    }
    let errors = InvariantErrors::of(&got);
    assert_eq!((errors.energy[0], errors.angular_momentum[0]), (0.0, 0.0));
    assert!(!errors.energy_is_absolute && !errors.angular_momentum_is_absolute);
    // the flipper spins about body y: its body-frame angular velocity is read back in body axes
    let omega = derived::omega_user(&trajectory.frames[0].states[0]);
    assert!((omega - crate::math::DVec3::new(0.01, 5.0, 0.01)).length() < 1e-12, "{omega}");
}

#[test]
fn missing_columns_are_all_named() {
    let text = "t,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wz\n";
    let err = read_text(text, Format::Csv).unwrap_err();
    let message = err.to_string();
    assert!(matches!(&err, ReadError::MissingColumns { missing, .. } if missing == &["wx", "wy"]), "{message}");
    assert!(message.starts_with("t.csv:1: missing columns `wx`, `wy`"), "{message}");
}

#[test]
fn columns_may_come_in_any_order() {
    let text = "body,t,wx,wy,wz,x,y,z,qw,qx,qy,qz,vx,vy,vz,extra\na,0.5,1,2,3,4,5,6,1,0,0,0,7,8,9,hello\n";
    let trajectory = read_text(text, Format::Csv).unwrap();
    let s = trajectory.frames[0].states[0];
    assert_eq!(trajectory.frames[0].t, 0.5);
    assert_eq!(s.position.to_array(), [4.0, 5.0, 6.0]);
    assert_eq!(s.angular_velocity.to_array(), [1.0, 2.0, 3.0]);
}

#[test]
fn a_cut_last_line_is_dropped_and_reported() {
    let (text, _, _) = demo_file(Format::Csv, 10);
    // cut inside the last row's numbers: it still parses as numbers, but cannot be trusted
    let cut = &text[..text.len() - 5];
    let trajectory = read_text(cut, Format::Csv).unwrap();
    assert_eq!(trajectory.frames.len(), 10, "the last frame lost a body: dropped");
    let truncation = trajectory.truncated.unwrap();
    assert_eq!(truncation.what, "a line with no line break");
    assert_eq!(truncation.line, 23);
}

#[test]
fn an_incomplete_last_frame_is_dropped_and_reported() {
    let (text, _, _) = demo_file(Format::Csv, 10);
    let lines: Vec<&str> = text.lines().collect();
    let without_last_row = lines[..lines.len() - 1].join("\n") + "\n";
    let trajectory = read_text(&without_last_row, Format::Csv).unwrap();
    assert_eq!(trajectory.frames.len(), 10);
    assert_eq!(trajectory.truncated.unwrap().what, "a frame with 1 of 2 bodies");
}

#[test]
fn a_frame_lacking_a_body_in_the_middle_is_an_error() {
    let (text, _, _) = demo_file(Format::Csv, 10);
    let mut lines: Vec<&str> = text.lines().collect();
    lines.remove(6); // frame 3's second body
    let err = read_text(&(lines.join("\n") + "\n"), Format::Csv).unwrap_err();
    assert!(err.to_string().contains("lacks body `stable`"), "{err}");
}

#[test]
fn a_file_with_no_complete_sample_is_an_error() {
    let err = read_text("t,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n0,a,1,2", Format::Csv).unwrap_err();
    assert!(matches!(err, ReadError::NoSamples { truncated: Some(_), .. }), "{err}");
    assert!(read_text("", Format::Csv).is_err());
}

#[test]
fn bad_numbers_name_the_line_and_the_column() {
    let text = "t,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n0,a,1,2,3,1,0,0,0,0,0,0,0,0,0\n0.1,a,1,oops,3,1,0,0,0,0,0,0,0,0,0\n";
    let err = read_text(text, Format::Csv).unwrap_err().to_string();
    assert_eq!(err, "t.csv:3: y: not a number (got \"oops\")");
    let zero_quaternion = "t,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n0,a,1,2,3,0,0,0,0,0,0,0,0,0,0\n";
    assert!(read_text(zero_quaternion, Format::Csv).unwrap_err().to_string().contains("orientation"));
    let short_row = "t,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n0,a,1,2\n";
    assert!(read_text(short_row, Format::Csv).unwrap_err().to_string().contains("4 fields, the header has 15"));
}

#[test]
fn time_must_not_go_backwards() {
    let text =
        "t,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n1,a,0,0,0,1,0,0,0,0,0,0,0,0,0\n0.5,a,0,0,0,1,0,0,0,0,0,0,0,0,0\n";
    assert!(matches!(read_text(text, Format::Csv), Err(ReadError::TimeBackwards { line: 3, .. })));
}

#[test]
fn quoted_names_read_back() {
    let text = "t,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n0,\"b, \"\"q\"\"\",0,0,0,1,0,0,0,0,0,0,0,0,0\n";
    assert_eq!(read_text(text, Format::Csv).unwrap().bodies, ["b, \"q\""]);
}

#[test]
fn json_lines_name_a_missing_field() {
    let line =
        r#"{"t":0,"bodies":[{"name":"a","position":[0,0,0],"orientation":[1,0,0,0],"angular_velocity":[0,0,0]}]}"#;
    let err = read_text(&format!("{line}\n"), Format::JsonLines).unwrap_err();
    assert_eq!(err.to_string(), "t.csv:1: missing field `bodies[0].velocity`");
    let err = read_text("{\"bodies\":[]}\n", Format::JsonLines).unwrap_err();
    assert_eq!(err.to_string(), "t.csv:1: missing field `t`");
}

#[test]
fn json_lines_cut_short_keep_the_whole_lines() {
    let (text, _, _) = demo_file(Format::JsonLines, 10);
    let trajectory = read_text(&text[..text.len() - 30], Format::JsonLines).unwrap();
    assert_eq!(trajectory.frames.len(), 10);
    assert_eq!(trajectory.truncated.unwrap().line, 11);
}

#[test]
fn bodies_are_checked_against_the_scene() {
    let (text, world, _) = demo_file(Format::Csv, 2);
    let renamed = text.replace(",stable,", ",wobbly,");
    let trajectory = read_text(&renamed, Format::Csv).unwrap();
    let err = trajectory.check_bodies(&world, "t.csv", "demo.toml").unwrap_err();
    assert!(
        matches!(&err, ReadError::BodiesMismatch { unknown, missing, .. } if unknown == &["wobbly"] && missing == &["stable"])
    );
    assert_eq!(
        err.to_string(),
        "t.csv: the trajectory does not match the scene: it has bodies that are not moving bodies of the scene \
         demo.toml: `wobbly`; and it lacks moving bodies of the scene demo.toml: `stable`"
    );
    assert!(derived::invariants(&trajectory, &world, "t.csv", "demo.toml").is_err());
}

#[test]
fn decimation_keeps_evenly_spaced_frames_and_the_last() {
    let (text, _, _) = demo_file(Format::Csv, 1000);
    let options = ReadOptions { max_frames: Some(100) };
    let trajectory = read_from(text.as_bytes(), Format::Csv, "t.csv", options).unwrap();
    let n = trajectory.frames.len();
    assert!((100..=201).contains(&n), "{n} frames");
    assert_eq!((trajectory.frames_in_file, trajectory.stride), (1001, 8));
    let times: Vec<f64> = trajectory.frames.iter().map(|f| f.t).collect();
    assert_eq!(times[0], 0.0);
    assert!((times[n - 1] - 10.0).abs() < 1e-9, "the last frame is kept: {}", times[n - 1]);
    for pair in times[..n - 1].windows(2) {
        assert!((pair[1] - pair[0] - 0.08).abs() < 1e-9, "every 8th frame: {pair:?}");
    }
}

#[test]
fn the_partial_file_of_a_stopped_run_has_a_format() {
    assert_eq!(format_of(Path::new("out/demo.csv.partial")), Some(Format::Csv));
    assert_eq!(format_of(Path::new("a.JSONL")), Some(Format::JsonLines));
    assert_eq!(format_of(Path::new("a.txt")), None);
}

#[test]
fn the_inertia_box_of_a_box_is_the_box() {
    let world = scene::demo().world;
    let (half, user_from_body) = derived::inertia_equivalent_box(&world.bodies[0].mass);
    assert!((half - crate::math::DVec3::new(1.5, 1.0, 0.5)).length() < 1e-12, "{half}");
    assert_eq!(user_from_body, crate::math::DQuat::IDENTITY);
}

#[test]
fn errors_are_absolute_when_the_initial_value_is_zero() {
    let at_rest = |e: f64| Invariants {
        energy: e,
        linear_momentum: crate::math::DVec3::ZERO,
        angular_momentum: crate::math::DVec3::new(e, 0.0, 0.0),
    };
    let errors = InvariantErrors::of(&[at_rest(0.0), at_rest(-0.5), at_rest(2.0)]);
    assert!(errors.energy_is_absolute && errors.angular_momentum_is_absolute);
    assert_eq!(errors.energy, [0.0, -0.5, 2.0], "signed, in J");
    assert_eq!(errors.angular_momentum, [0.0, 0.5, 2.0], "a norm, in kg·m²/s");
    let relative = InvariantErrors::of(&[at_rest(-2.0), at_rest(-1.0)]);
    assert_eq!((relative.energy[1], relative.angular_momentum[1]), (0.5, 0.5), "over |E₀| and |L₀|");
    assert!(InvariantErrors::of(&[]).energy.is_empty());
}

#[test]
fn robot_links_are_checked_against_the_scene_and_named() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/double_pendulum.toml");
    let world = scene::load(&path).unwrap().world;
    let row = |name: &str| format!("0.0,{name},0,0,0,1,0,0,0,0,0,0,0,0,0\n");
    let text = |names: &[&str]| format!("{CSV_HEADER}\n{}", names.iter().map(|n| row(n)).collect::<String>());
    let links = ["pendulum/upper", "pendulum/lower", "pendulum/tip"];
    let trajectory = read_text(&text(&links), Format::Csv).unwrap();
    trajectory.check_bodies(&world, "t.csv", "dp.toml").unwrap();
    assert_eq!(derived::invariants(&trajectory, &world, "t.csv", "dp.toml").unwrap().len(), 1);

    let wrong = ["pendulum/upper", "pendulum/nolink", "pendulum/base", "pendulum/tip", "arm/link1"];
    let err = read_text(&text(&wrong), Format::Csv).unwrap().check_bodies(&world, "t.csv", "dp.toml").unwrap_err();
    assert_eq!(
        err.to_string(),
        "t.csv: the trajectory does not match the scene: it has bodies that are not moving bodies of the scene \
         dp.toml: `pendulum/nolink`, `pendulum/base`, `arm/link1`; and it lacks moving bodies of the scene \
         dp.toml: `pendulum/lower`; robot `pendulum` has no moving link `nolink`, and `base` of robot `pendulum` \
         is fixed to the world (never written) (its moving links: `upper`, `lower`, `tip`); the scene has no \
         robot `arm` (its robots: `pendulum`)"
    );
}
