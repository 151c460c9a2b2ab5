//! What `tumble run` prints: a line when it starts, a table when it ends (stdout), and a progress bar
//! (stderr, only on a terminal and only for runs longer than a second).
//!
//! Stdout is written through a locked handle with `write!`, never `println!`, so a closed pipe
//! (`tumble run | head -c 10`) is an error value, not a panic; [`Stdout`] then goes quiet.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::fmt::Write as _;
use std::io::{self, Write};
use std::path::Path;
use std::time::{Duration, Instant};
use tumble::trajectory::{Format, StopReason, Summary};

/// Standard output that goes quiet, without an error, once its reader has gone (broken pipe).
#[derive(Debug, Default)]
pub struct Stdout {
    closed: bool,
}

impl Stdout {
    /// Writes `text`; a broken pipe silences this and every later write. Other errors are returned.
    pub fn write(&mut self, text: &str) -> io::Result<()> {
        if self.closed {
            return Ok(());
        }
        let stdout = io::stdout();
        let mut lock = stdout.lock();
        match lock.write_all(text.as_bytes()).and_then(|()| lock.flush()) {
            Err(e) if e.kind() == io::ErrorKind::BrokenPipe => {
                self.closed = true;
                Ok(())
            }
            other => other,
        }
    }
}

/// The line printed when a run starts.
pub fn start_line(origin: &str, world: &tumble::World, out: &Path) -> String {
    let c = &world.config;
    let robots = match world.robots.len() {
        0 => String::new(),
        1 => ", 1 robot".to_string(),
        n => format!(", {n} robots"),
    };
    format!(
        "running {origin}: {} bodies{robots}, {} s in {} steps of {} s ({}) → {}\n",
        world.bodies.len(),
        c.duration,
        c.step_count(),
        c.dt,
        c.integrator,
        out.display()
    )
}

/// The table `--profile` prints when a run ends: µs per step of each stage, indented under the
/// stage it is part of, and its share of the step.
pub fn profile_table(p: &tumble::trajectory::ProfileSummary) -> String {
    let rows = [
        ("broad phase", p.broad_phase_us, 0),
        ("narrow phase", p.narrow_phase_us, 0),
        ("robot links: shapes, contacts", p.link_detect_us, 1),
        ("collisions", p.impacts_us, 0),
        ("robot contact rows: M, a0, J, W, K", p.link_rows_us, 1),
        ("resting contact (substeps)", p.resting_us, 0),
        ("integration", p.integration_us, 0),
        ("robot dynamics and integrator", p.robot_dynamics_us, 1),
        ("robot kinematics, energy", p.robot_bookkeeping_us, 1),
    ];
    let mut out = String::from("profile (per step):\n");
    let share = |x: f64| if p.step_us > 0.0 { 100.0 * x / p.step_us } else { 0.0 };
    for (name, us, depth) in rows {
        let label = format!("{}{name}", "  ".repeat(depth + 1));
        let _ = writeln!(out, "{label:<40} {us:>9.2} µs {:>5.1} %", share(us));
    }
    let _ = writeln!(out, "  {:<38} {:>9.2} µs", "step", p.step_us);
    let _ =
        writeln!(out, "  pairs {:.1}, contacts {:.1}, robot link contacts {:.1}", p.pairs, p.contacts, p.link_contacts);
    out
}

/// The table printed when a run ends.
pub fn table(
    summary: &Summary,
    trajectory: &Path,
    format: Format,
    summary_path: Option<&Path>,
    contacts_path: Option<&Path>,
) -> String {
    let s = summary;
    let mut t = String::new();
    let mut row = |label: &str, value: String| {
        let _ = writeln!(t, "  {label:<26} {value}");
    };
    let stopped = match s.stopped {
        StopReason::Completed => "",
        StopReason::Diverged => " (diverged)",
        StopReason::ContactBudget => " (contact budget exceeded)",
        StopReason::Interrupted => " (interrupted)",
        StopReason::WallTimeLimit => " (stopped at the wall-time limit)",
    };
    row("scene", s.scene.clone());
    row("bodies", format!("{} ({} moving)", s.bodies, s.free_bodies));
    for r in &s.robots {
        row("robot", format!("{}: {} base, nv = {}, {} links written", r.name, r.base, r.nv, r.links));
        let steps = |list: &[tumble::trajectory::JointStepsSummary]| {
            list.iter().map(|c| format!("{} ({} steps)", c.joint, c.steps)).collect::<Vec<_>>().join(", ")
        };
        if !r.effort_clamped.is_empty() {
            row("  effort clamped", steps(&r.effort_clamped));
        }
        if !r.joint_limits_active.is_empty() {
            row("  at a joint limit", steps(&r.joint_limits_active));
        }
        if !r.tendon_limits_active.is_empty() {
            let list: Vec<String> =
                r.tendon_limits_active.iter().map(|c| format!("{} ({} steps)", c.tendon, c.steps)).collect();
            row("  at a tendon limit", list.join(", "));
        }
    }
    row("integrator", format!("{}, dt = {} s", s.integrator, s.dt));
    row("steps", format!("{}{stopped}", s.steps));
    row("simulated time", format!("{} s", s.simulated_time));
    row("wall time", seconds(s.wall_time_s));
    let body_steps = (s.free_bodies as f64) * (s.steps as f64);
    let rate = if s.wall_time_s > 0.0 { format!("{:.3e}", body_steps / s.wall_time_s) } else { "-".into() };
    row("body-steps/s", rate);
    let c = &s.contact;
    let contacts = c.collisions > 0 || c.energy_lost_in_friction != 0.0;
    let mut energy = error_text(s.energy.max_relative_error, s.energy.error_is_absolute, "J");
    let mut momentum =
        error_text(s.angular_momentum.max_relative_error, s.angular_momentum.error_is_absolute, "kg·m²/s");
    if contacts {
        energy = note(&energy, "contacts took energy out: see the balance below");
        if s.bodies > s.free_bodies {
            momentum = note(&momentum, "the fixed bodies' contact impulses change it");
        }
    }
    if s.robots.iter().any(|r| !r.joint_limits_active.is_empty() || !r.tendon_limits_active.is_empty()) {
        // a strike on a joint limit is perfectly inelastic (docs/multibody.md, joint limits)
        energy = note(&energy, "joint-limit strikes took energy out");
    }
    row("energy error", energy);
    row("angular momentum error", momentum);
    let flips = if s.flips.is_empty() {
        "- (no moving body has three distinct principal moments)".to_string()
    } else {
        s.flips.iter().map(flip_text).collect::<Vec<_>>().join(", ")
    };
    row("flips (intermediate axis)", flips);
    if contacts {
        row("collisions", format!("{} ({} J lost)", c.collisions, joules(c.energy_lost_in_collisions)));
        row("friction, resting contact", format!("{} J lost", joules(c.energy_lost_in_friction)));
        if c.asleep_at_end > 0 {
            row("asleep at the end", format!("{} of {} free bodies", c.asleep_at_end, s.free_bodies));
        }
        let lost = c.energy_lost_in_collisions + c.energy_lost_in_friction;
        let balance = s.energy.initial - s.energy.final_ - lost;
        let mut share =
            if lost > 0.0 { format!(" ({:.1e} of the energy lost)", balance.abs() / lost) } else { String::new() };
        // the Euler integrators' velocity is half a step of velocity change off their positions:
        // their ½ m v² + m g z varies by about ½ m g dt |v| (docs/contact.md, energy bookkeeping)
        if lost > 0.0 && matches!(s.integrator.as_str(), "euler" | "semi_implicit_euler") {
            share = note(&share, "with the integrator's own energy error, about ½ m g dt |v|");
        }
        // a robot's link contacts are booked (docs/multibody.md, robots in contact), its actuators'
        // and joint damping's work is not
        if lost > 0.0 && !s.robots.is_empty() {
            share = note(&share, "with the work of the robots' actuators and joint damping, if any");
        }
        row("energy balance", format!("E₀ − E − lost = {} J{share}", joules(balance)));
    }
    let kind = match format {
        Format::Csv => "CSV",
        Format::JsonLines => "JSON Lines",
    };
    row("trajectory", format!("{} ({kind}, {} samples)", trajectory.display(), s.samples));
    if let Some(path) = summary_path {
        row("summary", path.display().to_string());
    }
    if let Some(path) = contacts_path {
        row("contacts", format!("{} (JSON Lines, {} samples)", path.display(), s.samples));
    }
    t
}

/// `3.1e-12 (max relative; note)`: a note added inside the closing parenthesis.
fn note(text: &str, note: &str) -> String {
    match text.strip_suffix(')') {
        Some(open) => format!("{open}; {note})"),
        None => format!("{text} ({note})"),
    }
}

/// An energy for people: `1303.2`, `0.0123` (J).
fn joules(e: f64) -> String {
    if e != 0.0 && e.abs() < 0.1 {
        format!("{e:.2e}")
    } else {
        format!("{e:.1}")
    }
}

/// A duration for people: `2.35 s`, `12.3 ms`, `85 µs`.
fn seconds(s: f64) -> String {
    if s >= 1.0 {
        format!("{s:.2} s")
    } else if s >= 1e-3 {
        format!("{:.1} ms", s * 1e3)
    } else {
        format!("{:.0} µs", s * 1e6)
    }
}

/// `3.1e-12 (max relative)`, or the absolute error with its unit when the initial value was zero.
fn error_text(error: f64, absolute: bool, unit: &str) -> String {
    if !error.is_finite() {
        "not finite (the state overflowed)".to_string()
    } else if absolute {
        format!("{error:.2e} {unit} (max absolute: the initial value is 0)")
    } else {
        format!("{error:.2e} (max relative)")
    }
}

/// Time between periodic flushes of the trajectory (a killed run loses at most this much).
pub const FLUSH_INTERVAL: Duration = Duration::from_secs(1);
/// A run shows a progress bar once it has lasted this long.
pub const PROGRESS_DELAY: Duration = Duration::from_secs(1);

/// What a tick found due.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Tick {
    /// Flush the trajectory (about once per [`FLUSH_INTERVAL`]).
    pub flush: bool,
    /// The wall-time limit is reached: stop after this step.
    pub out_of_time: bool,
}

/// Periodic work of the run loop that needs the clock: the progress bar, the periodic flush and the
/// wall-time limit.
/// The loop calls [`Ticker::due`] every step (a comparison) and [`Ticker::tick`] every
/// [`Ticker::every`] steps, so the clock is read about once per millisecond of simulation work.
#[derive(Debug)]
pub struct Ticker {
    /// Steps between two ticks.
    every: u64,
    next: u64,
    total_steps: u64,
    start: Instant,
    last_flush: Instant,
    /// Whether a bar may be shown (stderr is a terminal and the run is not quiet).
    progress_allowed: bool,
    bar: Option<ProgressBar>,
    /// Stop once the loop has run this long.
    wall_time_limit: Option<Duration>,
}

impl Ticker {
    /// A ticker for a run of `total_steps` steps of `free_bodies` moving bodies.
    pub fn new(total_steps: u64, free_bodies: usize, progress_allowed: bool) -> Self {
        // about 1000 body-steps between ticks
        let every = (1024 / free_bodies.max(1) as u64).max(1);
        let now = Instant::now();
        Self {
            every,
            next: every,
            total_steps,
            start: now,
            last_flush: now,
            progress_allowed,
            bar: None,
            wall_time_limit: None,
        }
    }

    /// Stops the run once it has lasted `limit` (checked at each tick).
    pub fn with_wall_time_limit(mut self, limit: Option<Duration>) -> Self {
        self.wall_time_limit = limit;
        self
    }

    /// Steps between two ticks.
    pub fn every(&self) -> u64 {
        self.every
    }

    /// Whether step `step` is due for a tick.
    #[inline]
    pub fn due(&self, step: u64) -> bool {
        step >= self.next
    }

    /// Reads the clock: whether the periodic flush is due and the time is up; shows or advances the
    /// progress bar.
    pub fn tick(&mut self, step: u64) -> Tick {
        self.next = step + self.every;
        let now = Instant::now();
        if self.progress_allowed && now - self.start >= PROGRESS_DELAY {
            let (total, elapsed) = (self.total_steps, now - self.start);
            let bar = self.bar.get_or_insert_with(|| new_bar(total).with_elapsed(elapsed));
            bar.set_position(step);
        }
        let flush = now - self.last_flush >= FLUSH_INTERVAL;
        if flush {
            self.last_flush = now;
        }
        let out_of_time = self.wall_time_limit.is_some_and(|limit| now - self.start >= limit);
        Tick { flush, out_of_time }
    }

    /// Removes the progress bar, if shown.
    pub fn finish(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
    }

    /// Whether the bar is showing.
    pub fn bar_shown(&self) -> bool {
        self.bar.is_some()
    }
}

fn new_bar(total: u64) -> ProgressBar {
    let bar = ProgressBar::with_draw_target(Some(total), ProgressDrawTarget::stderr());
    let style = ProgressStyle::with_template("{bar:40} {percent:>3}% step {pos}/{len}, {elapsed} elapsed, ~{eta} left")
        .expect("a valid template");
    bar.set_style(style);
    bar
}

/// `flipper 4 (every 6.4213 s; exact 2K/λ = 6.4213 s)`, `box 0 (until its first contact at 0.62 s)`.
fn flip_text(f: &tumble::trajectory::FlipSummary) -> String {
    let mut notes = Vec::new();
    match (f.mean_interval, f.exact_interval) {
        (Some(mean), Some(exact)) => notes.push(format!("every {mean:.4} s; exact 2K/λ = {exact:.4} s")),
        (Some(mean), None) => notes.push(format!("every {mean:.4} s")),
        _ => {}
    }
    if let Some(t) = f.counted_until {
        notes.push(format!("until its first contact at {t:.2} s"));
    }
    match notes.is_empty() {
        true => format!("{} {}", f.body, f.flips),
        false => format!("{} {} ({})", f.body, f.flips, notes.join("; ")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_bar_when_not_allowed_and_none_before_a_second() {
        let mut quiet = Ticker::new(1_000_000, 2, false);
        std::thread::sleep(Duration::from_millis(1100));
        quiet.tick(1000);
        assert!(!quiet.bar_shown());
        let mut fresh = Ticker::new(1_000_000, 2, true);
        fresh.tick(512);
        assert!(!fresh.bar_shown(), "a run shorter than a second shows no bar");
    }

    #[test]
    fn the_table_never_shows_nan() {
        let world = tumble::scene::demo().world;
        let monitor = tumble::trajectory::Monitor::new(&world);
        let mut summary = Summary::new(&world, &monitor, 0.0, StopReason::Completed, "<demo>");
        summary.energy.max_relative_error = f64::NAN;
        summary.angular_momentum.max_relative_error = f64::INFINITY;
        let text = table(&summary, Path::new("out/demo.csv"), Format::Csv, None, None);
        assert!(!text.to_lowercase().contains("nan") && !text.contains("inf"), "{text}");
        assert!(text.contains("not finite"), "{text}");
        assert!(text.contains("body-steps/s               -"), "no rate for a zero wall time: {text}");
    }

    #[test]
    fn ticks_are_spaced_by_the_number_of_bodies() {
        assert_eq!(Ticker::new(10, 1, false).every(), 1024);
        assert_eq!(Ticker::new(10, 100, false).every(), 10);
        assert_eq!(Ticker::new(10, 100_000, false).every(), 1);
        let t = Ticker::new(10, 0, false);
        assert!(!t.due(1023) && t.due(1024));
    }

    #[test]
    fn the_wall_time_limit_is_seen_at_a_tick() {
        let mut t = Ticker::new(10, 1, false).with_wall_time_limit(Some(Duration::from_millis(50)));
        assert!(!t.tick(1024).out_of_time);
        std::thread::sleep(Duration::from_millis(60));
        assert!(t.tick(2048).out_of_time);
        assert!(!Ticker::new(10, 1, false).tick(1024).out_of_time, "no limit");
    }
}
