//! `--sleep-onset`: how soon a settled scene falls asleep in each engine, what it has moved by
//! then, and what a step costs asleep and in the step that wakes it.
//!
//! Each scene runs from its start with sleeping on: Rapier with its default activation
//! thresholds, tumble with a grid of `sleep_speed` × `sleep_time` (its default among them). Per
//! run: the first step from which at least 90 % of the moving bodies are asleep, the first from
//! which all of them are, the largest displacement of a moving body at the end (a body put to sleep
//! while still creeping freezes where it was; one that kept creeping awake moves on) and the
//! time per step over the last quarter of the run. For tumble's default, also the step that wakes
//! the whole scene (a caller's change to one body's velocity, 1 mm/s, wakes its island): the
//! median over repetitions of that one step, on copies of the asleep world, against an awake
//! step of the same world.

use std::path::Path;
use std::time::Instant;

/// One run's figures.
struct Onset {
    /// First step from which ≥ 90 % (all) of the moving bodies stay asleep to the end.
    most: Option<usize>,
    all: Option<usize>,
    /// Asleep at the end, of `moving`.
    asleep: usize,
    moving: usize,
    /// Largest displacement of a moving body at the end (m).
    drift: f64,
    /// ms per step over the last quarter of the run.
    ms_late: f64,
}

/// The first step from which `counts[k] ≥ need` holds to the end.
fn settled_from(counts: &[usize], need: usize) -> Option<usize> {
    let last_below = counts.iter().rposition(|&c| c < need);
    match last_below {
        None => Some(0),
        Some(k) if k + 1 < counts.len() => Some(k + 1),
        Some(_) => None,
    }
}

fn onset(counts: &[usize], moving: usize, drift: f64, ms_late: f64) -> Onset {
    Onset {
        most: settled_from(counts, (moving * 9).div_ceil(10)),
        all: settled_from(counts, moving),
        asleep: counts.last().copied().unwrap_or(0),
        moving,
        drift,
        ms_late,
    }
}

fn drift_of(world: &tumble::World, end: impl Fn(usize) -> Option<tumble::math::DVec3>) -> f64 {
    world
        .bodies
        .iter()
        .enumerate()
        .filter(|(_, b)| !b.fixed)
        .filter_map(|(i, b)| end(i).map(|p| (p - b.state.position).length()))
        .fold(0.0, f64::max)
}

fn run_tumble(world: &tumble::World, steps: usize, speed: f64, time: f64) -> (Onset, tumble::World) {
    let mut w = world.clone();
    w.config.contact.sleep = true;
    w.config.contact.sleep_speed = speed;
    w.config.contact.sleep_time = time;
    let moving = w.bodies.iter().filter(|b| !b.fixed).count();
    let mut counts = Vec::with_capacity(steps);
    let late = steps - steps / 4;
    let mut t_late = Instant::now();
    for k in 0..steps {
        if k == late {
            t_late = Instant::now();
        }
        if let Err(e) = w.step() {
            eprintln!("tumble: {e}");
            break;
        }
        counts.push(w.contacts().sleep().count());
    }
    let ms_late = t_late.elapsed().as_secs_f64() * 1e3 / (steps - late) as f64;
    let drift = drift_of(world, |i| Some(w.bodies[i].state.position));
    (onset(&counts, moving, drift, ms_late), w)
}

fn run_rapier(world: &tumble::World, steps: usize) -> Onset {
    let (mut rw, handles) = super::rapier_world(world, true);
    let moving = handles.iter().flatten().filter(|h| rw.bodies[**h].is_dynamic()).count();
    let mut counts = Vec::with_capacity(steps);
    let late = steps - steps / 4;
    let mut t_late = Instant::now();
    for k in 0..steps {
        if k == late {
            t_late = Instant::now();
        }
        rw.step();
        counts.push(rw.bodies.iter().filter(|(_, b)| b.is_dynamic() && b.is_sleeping()).count());
    }
    let ms_late = t_late.elapsed().as_secs_f64() * 1e3 / (steps - late) as f64;
    let drift = drift_of(world, |i| handles[i].map(|h| rw.bodies[h].translation()));
    onset(&counts, moving, drift, ms_late)
}

/// The median time (ms) of the step after `touch` on copies of `world`, over `reps` copies.
fn one_step_ms(world: &tumble::World, reps: usize, touch: impl Fn(&mut tumble::World)) -> f64 {
    let mut times: Vec<f64> = (0..reps)
        .map(|_| {
            let mut w = world.clone();
            touch(&mut w);
            let t = Instant::now();
            let _ = w.step();
            t.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    times.sort_by(f64::total_cmp);
    times[times.len() / 2]
}

fn step_label(s: Option<usize>, dt: f64) -> String {
    match s {
        Some(k) => format!("{k} ({:.2} s)", k as f64 * dt),
        None => "never".into(),
    }
}

/// Runs every scene and prints its table.
pub fn report(scenes: &[String], steps: usize, reps: usize) {
    let defaults = tumble::contact::ContactSettings::default();
    for path in scenes {
        let world = super::load_world(path);
        let dt = world.config.dt;
        let name = Path::new(path).file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or(path.clone());
        println!();
        println!(
            "{name}: {steps} steps, sleeping on (asleep from: the first step after which the count holds to the end)"
        );
        println!();
        println!("| engine | thresholds | 90 % asleep from step | all asleep from step | asleep at the end | largest displacement (mm) | ms/step, last quarter |");
        println!("|---|---|---|---|---|---|---|");
        let r = run_rapier(&world, steps);
        println!(
            "| Rapier | default | {} | {} | {}/{} | {:.3} | {:.4} |",
            step_label(r.most, dt),
            step_label(r.all, dt),
            r.asleep,
            r.moving,
            r.drift * 1e3,
            r.ms_late
        );
        let mut asleep_default = None;
        for speed in [0.005, 0.01, 0.02, 0.05] {
            for time in [0.25, 0.5, 1.0] {
                let (o, w) = run_tumble(&world, steps, speed, time);
                let default = speed == defaults.sleep_speed && time == defaults.sleep_time;
                println!(
                    "| tumble | {speed} m/s, {time} s{} | {} | {} | {}/{} | {:.3} | {:.4} |",
                    if default { " (default)" } else { "" },
                    step_label(o.most, dt),
                    step_label(o.all, dt),
                    o.asleep,
                    o.moving,
                    o.drift * 1e3,
                    o.ms_late
                );
                if default {
                    asleep_default = Some((o, w));
                }
            }
        }
        // what waking costs: the step after a 1 mm/s nudge to the first moving body (its island
        // wakes), against a step of the same world awake throughout
        if let Some((o, w)) = asleep_default.filter(|(o, _)| o.all.is_some()) {
            let first = w.bodies.iter().position(|b| !b.fixed).expect("a moving body");
            let nudge = |w: &mut tumble::World| w.bodies[first].state.velocity.x += 1e-3;
            let waking = one_step_ms(&w, reps, nudge);
            let asleep = one_step_ms(&w, reps, |_| {});
            let mut awake = w.clone();
            awake.config.contact.sleep = false;
            let awake_ms = one_step_ms(&awake, reps, nudge);
            println!();
            println!(
                "tumble default, all {} asleep: an asleep step {asleep:.4} ms; the step that wakes them {waking:.4} ms; the same step with sleeping off {awake_ms:.4} ms (median of {reps})",
                o.moving
            );
        }
    }
}

/// The scenes of the report: the pyramid, the balls, the tower and the 10:1 stack.
pub fn default_scenes(root: &Path) -> Vec<String> {
    ["pyramid", "balls", "tower", "stack_10_1"]
        .iter()
        .map(|s| root.join(format!("scenes/{s}.toml")).display().to_string())
        .collect()
}
