//! `tumble run`: every check on the input first (exit 2, nothing written), then the outputs are
//! opened (exit 4 before any simulation), then the loop, then the summary.

use crate::cli::RunArgs;
use crate::error::{Failure, Status};
use crate::output::{same_file, OutputFile};
use crate::report::{self, Stdout, Ticker};
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};
use tumble::scene::{self, Scene};
use tumble::trajectory::{ContactWriter, Format, Monitor, StopReason, Summary, TrajectoryError, TrajectoryWriter};
use tumble::world::StepError;
use tumble::World;

/// Default directory of trajectories when `--out` is not given.
pub const DEFAULT_OUT_DIR: &str = "out";
/// Largest trajectory written without `--force` (bytes, estimated before the run).
pub const MAX_OUTPUT_BYTES: f64 = 10e9;
/// Estimated bytes per body per sample (a CSV row of 15 numbers at full precision).
const BYTES_PER_ROW: f64 = 300.0;

/// Everything `tumble run` will do, checked.
#[derive(Debug)]
pub struct Plan {
    pub scene: Scene,
    /// The trajectory file.
    pub out: PathBuf,
    /// Whether `out` is the default (its directory is then created).
    pub default_out: bool,
    pub format: Format,
    pub summary: Option<PathBuf>,
    /// `--contacts`: the contacts file (JSON Lines).
    pub contacts: Option<PathBuf>,
    pub quiet: bool,
    /// `--max-wall-time`.
    pub wall_time_limit: Option<Duration>,
}

impl Plan {
    /// Checks the command line and the scene; touches no file.
    pub fn new(args: &RunArgs) -> Result<Plan, Failure> {
        let stem = match &args.scene {
            Some(path) => path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or("scene".into()),
            None => "demo".to_string(),
        };
        let (out, default_out) = match &args.out {
            Some(out) => (out.clone(), false),
            None => (Path::new(DEFAULT_OUT_DIR).join(format!("{stem}.csv")), true),
        };
        let format = Format::from_path(&out).ok_or_else(|| {
            let ext = out.extension().map(|e| format!("`.{}`", e.to_string_lossy())).unwrap_or("no extension".into());
            Failure::bad_input(format!(
                "--out {}: unsupported trajectory format ({ext}); use FILE.csv or FILE.jsonl",
                out.display()
            ))
        })?;
        crate::plot::check_run(args, &out)?;
        if let Some(scene) = &args.scene {
            for (flag, path) in
                [("--out", Some(&out)), ("--summary", args.summary.as_ref()), ("--contacts", args.contacts.as_ref())]
            {
                if path.is_some_and(|p| same_file(scene, p)) {
                    return Err(Failure::bad_input(format!(
                        "{flag} {}: this is the scene file {}; refusing to overwrite it",
                        path.unwrap().display(),
                        scene.display()
                    )));
                }
            }
        }
        if let Some(summary) = &args.summary {
            if same_file(&out, summary) {
                return Err(Failure::bad_input(format!(
                    "--summary {}: the same file as the trajectory (--out {})",
                    summary.display(),
                    out.display()
                )));
            }
        }
        if let Some(contacts) = &args.contacts {
            if Format::from_path(contacts) != Some(Format::JsonLines) {
                return Err(Failure::bad_input(format!(
                    "--contacts {}: the contacts file is JSON Lines; name it FILE.jsonl",
                    contacts.display()
                )));
            }
            for (flag, path) in [("--out", Some(&out)), ("--summary", args.summary.as_ref())] {
                if path.is_some_and(|p| same_file(contacts, p)) {
                    return Err(Failure::bad_input(format!(
                        "--contacts {}: the same file as {flag} {}",
                        contacts.display(),
                        path.unwrap().display()
                    )));
                }
            }
        }
        let mjcf = |p: &std::path::Path| p.extension().is_some_and(|e| e == "xml" || e == "mjcf");
        let mut scene = match (&args.scene, &args.keyframe) {
            (Some(path), Some(key)) if mjcf(path) => {
                scene::load_mjcf_world_from(path, Some(key)).map_err(Failure::bad_input)?
            }
            (_, Some(key)) => {
                return Err(Failure::bad_input(format!(
                    "--keyframe {key}: applies to an MJCF file (.xml); in a scene, give `keyframe = \"{key}\"` under \
                     its [[robot]] (`mjcf = ...`)"
                )))
            }
            (Some(path), None) => scene::load(path).map_err(Failure::bad_input)?,
            (None, None) => scene::demo(),
        };
        apply_overrides(&mut scene, args)?;
        let wall_time_limit = match args.max_wall_time {
            Some(s) if s.is_finite() && s > 0.0 => Some(Duration::from_secs_f64(s.min(1e9))),
            Some(s) => return Err(Failure::bad_input(format!("--max-wall-time: must be finite and > 0 (got {s})"))),
            None => None,
        };
        let plan = Plan {
            scene,
            out,
            default_out,
            format,
            summary: args.summary.clone(),
            contacts: args.contacts.clone(),
            quiet: args.quiet,
            wall_time_limit,
        };
        let bytes = plan.estimated_bytes();
        if bytes > MAX_OUTPUT_BYTES && !args.force {
            return Err(Failure::bad_input(format!(
                "--out {}: the trajectory would take about {:.0} GB (over the 10 GB cap)\n\
                 hint: write fewer samples with --sample-every K, shorten --duration, or pass --force",
                plan.out.display(),
                bytes / 1e9
            )));
        }
        Ok(plan)
    }

    /// Estimated size of the trajectory (bytes).
    pub fn estimated_bytes(&self) -> f64 {
        let c = &self.scene.world.config;
        let samples = (c.step_count() / c.sample_every) as f64 + 2.0;
        let rows = self.scene.world.free_bodies().count() + self.scene.world.robot_link_count();
        samples * rows as f64 * BYTES_PER_ROW
    }
}

/// Applies `--duration`, `--dt`, `--integrator`, `--sample-every`, `--threads` to the scene's `[world]` and
/// validates the result, naming the flag (or the scene) of a bad setting.
fn apply_overrides(scene: &mut Scene, args: &RunArgs) -> Result<(), Failure> {
    let config = &mut scene.world.config;
    if let Some(duration) = args.duration {
        config.duration = duration;
    }
    if let Some(dt) = args.dt {
        config.dt = dt;
    }
    if let Some(integrator) = args.integrator {
        config.integrator = integrator;
    }
    if let Some(k) = args.sample_every {
        config.sample_every = k;
    }
    if let Some(n) = args.threads {
        config.threads = n;
    }
    config.validate().map_err(|e| {
        // the flag behind the bad setting, and its value
        let flag = match e.field {
            "dt" if args.dt.is_some() => Some(("--dt", e.value.clone())),
            "duration" if args.duration.is_some() => Some(("--duration", e.value.clone())),
            "duration" => args.dt.map(|dt| ("--dt", dt.to_string())),
            "sample_every" if args.sample_every.is_some() => Some(("--sample-every", e.value.clone())),
            "threads" if args.threads.is_some() => Some(("--threads", e.value.clone())),
            _ => None,
        };
        match flag {
            Some((flag, value)) => Failure::bad_input(format!("{flag}: {} (got {value})", e.problem)),
            None => Failure::bad_input(format!("{}: [world] {e}", scene.origin)),
        }
    })
}

/// How a run ended.
#[derive(Debug)]
pub enum Stop {
    Completed,
    /// A body diverged, or the broad phase went over the pair budget (`[world] max_pairs`).
    Diverged(StepError),
    Interrupted,
    WallTimeLimit,
}

/// A failure of the loop's writing, and which output it hit.
#[derive(Debug)]
pub enum LoopError {
    /// The trajectory (or a value of the sample that the step did not catch).
    Trajectory(TrajectoryError),
    /// The contacts file (`--contacts`).
    Contacts(TrajectoryError),
}

/// One sample: the trajectory, then the contacts of the step that ended there.
fn write_sample<W: Write, C: Write>(
    world: &World,
    writer: &mut TrajectoryWriter<W>,
    contacts: Option<&mut ContactWriter<C>>,
) -> Result<(), LoopError> {
    writer.write_sample(world).map_err(LoopError::Trajectory)?;
    if let Some(c) = contacts {
        c.write_sample(world).map_err(LoopError::Contacts)?;
    }
    Ok(())
}

/// What the loop leaves behind.
#[derive(Debug)]
pub struct Outcome {
    pub monitor: Monitor,
    pub stop: Stop,
    /// Wall time of the loop: stepping and writing, the final flush included (s).
    pub wall_time_s: f64,
}

/// The simulation loop: writes the initial state, then steps `config.step_count()` times, writing
/// and monitoring every `sample_every`-th step and the last one.
///
/// - A step that diverges is undone by [`World::step`]: the last finite state is written, and the
///   loop stops with [`Stop::Diverged`].
/// - When `stop` turns true (SIGINT/SIGTERM), or the ticker's wall-time limit is reached, the loop
///   ends after the current step, writing it.
/// - The trajectory is flushed about every second, and at the end.
///
/// With `contacts`, each sample also writes the active contacts of the step that ended there.
///
/// Nothing is allocated per step: the writers reuse their buffers.
pub fn simulate<W: Write, C: Write>(
    world: &mut World,
    writer: &mut TrajectoryWriter<W>,
    mut contacts: Option<&mut ContactWriter<C>>,
    stop: &AtomicBool,
    ticker: &mut Ticker,
) -> Result<Outcome, LoopError> {
    let start = Instant::now();
    let total = world.config.step_count();
    let every = world.config.sample_every;
    write_sample(world, writer, contacts.as_deref_mut())?;
    let mut monitor = Monitor::new(world);
    let mut last_sampled = world.steps();
    let mut end = Stop::Completed;
    while world.steps() < total {
        // a step that diverges leaves the world at the last finite state
        if let Err(diverged) = world.step() {
            end = Stop::Diverged(diverged);
            break;
        }
        let step = world.steps();
        if step.is_multiple_of(every) || step == total {
            write_sample(world, writer, contacts.as_deref_mut())?;
            monitor.observe(world);
            last_sampled = step;
        }
        if stop.load(Ordering::Relaxed) {
            end = Stop::Interrupted;
            break;
        }
        if ticker.due(step) {
            let tick = ticker.tick(step);
            if tick.flush {
                writer.flush().map_err(LoopError::Trajectory)?;
                if let Some(c) = contacts.as_deref_mut() {
                    c.flush().map_err(LoopError::Contacts)?;
                }
            }
            if tick.out_of_time {
                end = Stop::WallTimeLimit;
                break;
            }
        }
    }
    if last_sampled != world.steps() {
        write_sample(world, writer, contacts.as_deref_mut())?;
        monitor.observe(world);
    }
    writer.flush().map_err(LoopError::Trajectory)?;
    if let Some(c) = contacts {
        c.flush().map_err(LoopError::Contacts)?;
    }
    Ok(Outcome { monitor, stop: end, wall_time_s: start.elapsed().as_secs_f64() })
}

/// `tumble run`.
pub fn run(args: &RunArgs) -> Result<Status, Failure> {
    let Plan { scene, out, default_out, format, summary, contacts, quiet, wall_time_limit } = Plan::new(args)?;
    let Scene { mut world, origin, warnings } = scene;
    if !quiet {
        let mut stderr = std::io::stderr().lock();
        for warning in &warnings {
            let _ = writeln!(stderr, "warning: {warning}");
        }
    }
    let stop = crate::signal::install().map_err(|e| Failure::output(format!("cannot handle signals: {e}")))?;

    // open every output before simulating: an unwritable one is reported now (exit 4)
    let cannot_write = |path: &Path, e: &dyn std::fmt::Display| format!("cannot write '{}': {e}", path.display());
    if default_out {
        let dir = Path::new(DEFAULT_OUT_DIR);
        std::fs::create_dir_all(dir).map_err(|e| Failure::output(cannot_write(&out, &e)))?;
    }
    let (trajectory_out, file) = OutputFile::create(&out).map_err(|e| Failure::output(cannot_write(&out, &e)))?;
    let summary_out = match &summary {
        Some(path) => match OutputFile::create(path) {
            Ok((output, _file)) => Some(output),
            Err(e) => {
                trajectory_out.discard();
                return Err(Failure::output(cannot_write(path, &e)));
            }
        },
        None => None,
    };
    // the outputs opened so far, discarded together when one fails before the loop
    let discard_all = |trajectory: OutputFile, summary: Option<OutputFile>, contacts: Option<OutputFile>| {
        trajectory.discard();
        summary.into_iter().chain(contacts).for_each(OutputFile::discard);
    };
    let (contacts_out, mut contacts_writer) = match &contacts {
        Some(path) => match OutputFile::create(path) {
            Ok((output, file)) => (Some(output), Some(ContactWriter::new(file, &world))),
            Err(e) => {
                discard_all(trajectory_out, summary_out, None);
                return Err(Failure::output(cannot_write(path, &e)));
            }
        },
        None => (None, None),
    };

    let mut stdout = Stdout::default();
    let stdout_failure = |e: std::io::Error| Failure::output(format!("cannot write to standard output: {e}"));
    if !quiet {
        if let Err(e) = stdout.write(&report::start_line(&origin, &world, &out)) {
            discard_all(trajectory_out, summary_out, contacts_out);
            return Err(stdout_failure(e));
        }
    }
    if args.profile {
        world.set_profiling(true);
    }
    let progress_allowed = !quiet && std::io::stderr().is_terminal();
    let mut ticker = Ticker::new(world.config.step_count(), world.free_bodies().count(), progress_allowed)
        .with_wall_time_limit(wall_time_limit);
    let looped = TrajectoryWriter::new(file, format, &world).map_err(LoopError::Trajectory).and_then(|mut writer| {
        simulate(&mut world, &mut writer, contacts_writer.as_mut(), &stop, &mut ticker).map(|o| (o, writer))
    });
    ticker.finish();
    let finished = looped.and_then(|(outcome, writer)| {
        writer.finish().map_err(LoopError::Trajectory)?;
        if let Some(c) = contacts_writer.take() {
            c.finish().map_err(LoopError::Contacts)?;
        }
        Ok(outcome)
    });
    let outcome = match finished {
        Ok(outcome) => outcome,
        Err(e) => {
            summary_out.into_iter().for_each(OutputFile::discard);
            // what was written before the failure stays, in the .partial files
            let written = (out.as_path(), trajectory_out.partial());
            let contacts_written = contacts.as_deref().zip(contacts_out.as_ref().map(OutputFile::partial));
            return Err(loop_failure(e, written, contacts_written));
        }
    };
    if let (Some(rise), false) = (outcome.monitor.instability(), quiet) {
        let _ = writeln!(std::io::stderr().lock(), "warning: {rise}");
    }
    if let Err(e) = trajectory_out.commit() {
        summary_out.into_iter().chain(contacts_out).for_each(OutputFile::discard);
        return Err(Failure::output(cannot_write(&out, &e)));
    }
    if let (Some(output), Some(path)) = (contacts_out, &contacts) {
        if let Err(e) = output.commit() {
            summary_out.into_iter().for_each(OutputFile::discard);
            return Err(Failure::output(cannot_write(path, &e)));
        }
    }

    let reason = match outcome.stop {
        Stop::Completed => StopReason::Completed,
        Stop::Diverged(StepError::Diverged(_)) => StopReason::Diverged,
        Stop::Diverged(StepError::ContactBudget(_)) => StopReason::ContactBudget,
        Stop::Interrupted => StopReason::Interrupted,
        Stop::WallTimeLimit => StopReason::WallTimeLimit,
    };
    let run_summary = Summary::new(&world, &outcome.monitor, outcome.wall_time_s, reason, &origin);
    if let (Some(output), Some(path)) = (summary_out, &summary) {
        write_summary(&run_summary, output, path)?;
    }
    if let Some(p) = &run_summary.profile {
        let _ = std::io::stderr().lock().write_all(report::profile_table(p).as_bytes());
    }
    if !quiet {
        let table = report::table(&run_summary, &out, format, summary.as_deref(), contacts.as_deref());
        stdout.write(&table).map_err(stdout_failure)?;
    }
    crate::plot::after_run(args, &world, &origin, &out)?;
    let t = world.time();
    match outcome.stop {
        Stop::Completed => Ok(Status::Success),
        Stop::Diverged(StepError::ContactBudget(b)) => Err(Failure::diverged(format!(
            "{b}\nthe trajectory up to t = {t} s (step {}) is in '{}'",
            world.steps(),
            out.display()
        ))),
        Stop::Diverged(StepError::Diverged(d)) => Err(Failure::diverged(format!(
            "{d}\nthe trajectory up to t = {t} s (step {}, the last finite state) is in '{}'",
            world.steps(),
            out.display()
        ))),
        Stop::Interrupted => {
            let _ = writeln!(
                std::io::stderr().lock(),
                "interrupted at step {} (t = {t} s); the trajectory up to there is in '{}'",
                world.steps(),
                out.display()
            );
            Ok(Status::Interrupted)
        }
        Stop::WallTimeLimit => {
            if !quiet {
                let _ = writeln!(
                    std::io::stderr().lock(),
                    "stopped at the wall-time limit at step {} (t = {t} s); the trajectory up to there is in '{}'",
                    world.steps(),
                    out.display()
                );
            }
            Ok(Status::Success)
        }
    }
}

/// The failure of the loop or of the final flush: an I/O error (exit 4, the part written so far
/// kept in the `.partial` file) or a non-finite value that the step did not catch (exit 3).
/// `trajectory` and `contacts`: each output's path and where its part written so far is.
fn loop_failure(e: LoopError, trajectory: (&Path, &Path), contacts: Option<(&Path, &Path)>) -> Failure {
    let (e, path) = match e {
        LoopError::Trajectory(e) => (e, trajectory.0),
        LoopError::Contacts(e) => (e, contacts.map_or(trajectory.0, |c| c.0)),
    };
    let mut kept = String::new();
    for (out, part) in std::iter::once(trajectory).chain(contacts) {
        if part != out {
            kept.push_str(&format!(
                "\nthe part of '{}' written before the failure is in '{}'",
                out.display(),
                part.display()
            ));
        }
    }
    match e {
        TrajectoryError::Io(io) => Failure::output(format!("cannot write '{}': {io}{kept}", path.display())),
        other => Failure::diverged(format!("{other}{kept}")),
    }
}

/// Writes the summary to its output. A pipe whose reader has gone (`--summary /dev/stdout -q | head
/// -c 0`: a broken pipe) is not a failure, as for the table on stdout ([`Stdout`]): the reader chose
/// to stop, and the other outputs are already complete. Any other error is exit 4.
fn write_summary(summary: &Summary, output: OutputFile, path: &Path) -> Result<(), Failure> {
    let json = match summary.to_json() {
        Ok(json) => json,
        Err(e) => {
            output.discard();
            return Err(Failure::diverged(format!("{}: {e}", path.display())));
        }
    };
    match std::fs::write(output.partial(), json).and_then(|()| output.commit()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        written => written.map_err(|e| Failure::output(format!("cannot write '{}': {e}", path.display()))),
    }
}

#[cfg(test)]
mod tests;
