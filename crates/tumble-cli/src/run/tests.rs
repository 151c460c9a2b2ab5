use super::*;
use tumble::math::DVec3;
use tumble::trajectory::CSV_HEADER;
use tumble::{MassProperties, RigidBody, WorldConfig};

fn demo(duration: f64) -> World {
    let mut world = scene::demo().world;
    world.config.duration = duration;
    world
}

/// Runs the loop into memory and returns the outcome and the CSV text.
fn simulate_csv(world: &mut World, stop: bool) -> (Outcome, String) {
    let mut writer = TrajectoryWriter::new(Vec::new(), Format::Csv, world).unwrap();
    let mut ticker = Ticker::new(world.config.step_count(), 2, false);
    let outcome =
        simulate(world, &mut writer, None::<&mut ContactWriter<Vec<u8>>>, &AtomicBool::new(stop), &mut ticker).unwrap();
    (outcome, String::from_utf8(writer.finish().unwrap()).unwrap())
}

/// The times of the samples of a CSV trajectory (one per row of the first body).
fn sample_times(csv: &str, body: &str) -> Vec<f64> {
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some(CSV_HEADER));
    lines
        .map(|l| l.split(',').collect::<Vec<_>>())
        .inspect(|fields| {
            assert_eq!(fields.len(), 15);
            assert!(fields.iter().skip(2).all(|f| f.parse::<f64>().unwrap().is_finite()));
        })
        .filter(|fields| fields[1] == body)
        .map(|fields| fields[0].parse().unwrap())
        .collect()
}

#[test]
fn every_kth_step_is_written_and_the_last_one_too() {
    let mut world = demo(0.025); // 25 steps of 1 ms, every 10th written
    assert_eq!(world.config.sample_every, 10);
    let (outcome, csv) = simulate_csv(&mut world, false);
    assert!(matches!(outcome.stop, Stop::Completed));
    assert_eq!(world.steps(), 25);
    let times = sample_times(&csv, "flipper");
    let expected: Vec<f64> = [0, 10, 20, 25].iter().map(|&n| n as f64 * 1e-3).collect();
    assert_eq!(times, expected);
    assert_eq!(sample_times(&csv, "stable").len(), 4);
    assert_eq!(outcome.monitor.samples(), 4);
    assert_eq!(outcome.monitor.last(), tumble::trajectory::Invariants::of(&world));
}

#[test]
fn a_stop_request_ends_the_run_after_a_whole_step_which_is_written() {
    let mut world = demo(10.0);
    let (outcome, csv) = simulate_csv(&mut world, true);
    assert!(matches!(outcome.stop, Stop::Interrupted));
    assert_eq!(world.steps(), 1);
    assert_eq!(sample_times(&csv, "flipper"), [0.0, 1e-3]);
    assert!(csv.ends_with('\n'));
}

/// A body driven by a torque so large that its spin passes the sanity bound of 1e10 rad/s at
/// t ≈ 0.01 s.
fn runaway_world() -> World {
    let mp = MassProperties::from_principal(1.0, DVec3::ONE).unwrap();
    let mut runaway = RigidBody::new("runaway", mp);
    runaway.loads.torque_body = DVec3::new(0.0, 0.0, 1e12);
    let calm = RigidBody::new("calm", mp);
    let config = WorldConfig { dt: 1e-3, duration: 1.0, sample_every: 3, ..Default::default() };
    World::new(config, vec![calm, runaway])
}

#[test]
fn a_diverging_step_is_undone_and_the_last_finite_state_is_written() {
    let mut world = runaway_world();
    let (outcome, csv) = simulate_csv(&mut world, false);
    let Stop::Diverged(tumble::world::StepError::Diverged(d)) = outcome.stop else { panic!("{:?}", outcome.stop) };
    assert_eq!(d.body, "runaway");
    assert!(d.quantity.contains("angular velocity"), "{}", d.quantity);
    assert!((9..=12).contains(&d.step), "step {}", d.step);
    assert_eq!(world.steps(), d.step - 1, "the world is back at the last finite state");
    assert!(world.bodies.iter().all(|b| b.state.is_finite()));
    let times = sample_times(&csv, "runaway");
    assert_eq!(*times.last().unwrap(), world.time(), "the last finite state is the last sample");
    assert_eq!(times.len(), sample_times(&csv, "calm").len(), "whole samples only");
    assert_eq!(outcome.monitor.last(), tumble::trajectory::Invariants::of(&world));
    let summary = Summary::new(&world, &outcome.monitor, outcome.wall_time_s, StopReason::Diverged, "t");
    assert!(summary.to_json().is_ok(), "the summary of a diverged run is finite");
}

/// A sink that accepts `room` bytes and then fails like a full disk.
struct Full {
    room: usize,
}

impl Write for Full {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        if self.room == 0 {
            return Err(std::io::Error::from_raw_os_error(28));
        }
        let n = buf.len().min(self.room);
        self.room -= n;
        Ok(n)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

#[test]
fn a_full_disk_is_an_io_error() {
    let mut world = demo(10.0);
    let mut writer = TrajectoryWriter::new(Full { room: 10_000 }, Format::JsonLines, &world).unwrap();
    let mut ticker = Ticker::new(world.config.step_count(), 2, false);
    let result =
        simulate(&mut world, &mut writer, None::<&mut ContactWriter<Vec<u8>>>, &AtomicBool::new(false), &mut ticker);
    match result {
        Err(LoopError::Trajectory(TrajectoryError::Io(e))) => assert_eq!(e.raw_os_error(), Some(28)),
        other => panic!("{other:?}"),
    }
    assert!(world.steps() < 10_000, "stopped at the failure, not at the end");
}
