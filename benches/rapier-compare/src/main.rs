//! Runs the contact scenes in tumble and in Rapier, single-threaded, side by side: wall time per step,
//! the ratio, and the stability of the pyramid (the largest displacement of a body after the run).
//!
//! Usage: `cargo run --release -p rapier-compare -- [STEPS] [--reps N] [--threads N] [--sleep-speed V]
//! [SCENE.toml ...]` (default: 1,000 steps of `scenes/pyramid.toml` and `scenes/balls.toml`, 5
//! repetitions, tumble on one thread; `--threads N` gives tumble's collision detection N threads,
//! Rapier stays on one; `--sleep-speed V` sets tumble's `sleep_speed`, m/s — Rapier's default
//! thresholds are 0.05 m/s and 0.5 rad/s, tumble's default 0.01 m/s on `‖v‖ + ρ ‖ω‖`).
//!
//! The machine's speed drifts (other builds share its cores), so each repetition runs the engines
//! one after the other — Rapier and tumble with sleeping off (every body solved at every step: the
//! work of a step), then both with sleeping on (each engine's default: islands at rest fall asleep)
//! — and the tables give the median over the repetitions of each time and of each repetition's
//! ratio.
//! tumble runs with its per-stage timing on (`World::set_profiling`, two clock reads per stage and
//! step) and Rapier with its `profiler` counters, which give the second table: the time per step
//! of each stage. A scene with
//! `contacts = false` (`scenes/many.toml`: 10,000 free tumbling bodies) is built in Rapier as bodies
//! without colliders carrying the same mass and principal inertia: a comparison of the free-body
//! integration alone.
//!
//! The Rapier world is built from the tumble world the scene loader produced: same shapes, poses,
//! velocities, masses (Rapier computes the inertia from the shape and the mass, as tumble does for a
//! `mass` with a shape), friction and restitution (equal on every body in these scenes, so the two
//! engines' combine rules agree), `dt` and gravity.
//!
//! `--curve` sweeps both engines' accuracy knobs (`curve`; `--curve --cheap`: only the settings of
//! one or two substeps or solver iterations, a quick check of the cheap end); `--sleep-onset` measures how soon each
//! engine puts the settled scenes to sleep and what waking costs (`onset`).

mod curve;
mod onset;

use rapier3d_f64::prelude::*;
use std::path::Path;
use std::time::Instant;
use tumble::body::Shape;
use tumble::math::{DQuat, DVec3};

fn rapier_world(world: &tumble::World, sleep: bool) -> (PhysicsWorld, Vec<Option<RigidBodyHandle>>) {
    let mut rw = PhysicsWorld { gravity: world.config.gravity, ..PhysicsWorld::default() };
    rw.integration_parameters.dt = world.config.dt;
    let contact = world.config.contact;
    let mut handles = Vec::with_capacity(world.bodies.len());
    for b in &world.bodies {
        if !contact.enabled && !b.fixed {
            // free bodies (contacts off in the scene): no collider, the body's own mass properties
            let mass = MassProperties::with_principal_inertia_frame(
                DVec3::ZERO,
                b.mass.mass,
                b.mass.inertia_body,
                b.mass.user_from_body,
            );
            let body = RigidBodyBuilder::dynamic()
                .pose(Pose::from_parts(b.state.position, b.orientation_user()))
                .linvel(b.state.velocity)
                .angvel(b.state.omega_world())
                .additional_mass_properties(mass)
                .gravity_scale(b.gravity_scale)
                .can_sleep(false);
            handles.push(Some(rw.insert_body(body)));
            continue;
        }
        let Some(shape) = &b.shape else {
            handles.push(None);
            continue;
        };
        let collider = match *shape {
            Shape::Sphere { radius } => ColliderBuilder::ball(radius),
            Shape::Box { half_extents: h } => ColliderBuilder::cuboid(h.x, h.y, h.z),
            Shape::Capsule { radius, half_height } => ColliderBuilder::capsule_z(half_height, radius),
            Shape::Cylinder { radius, half_height } => ColliderBuilder::cylinder(half_height, radius)
                .rotation(DVec3::new(std::f64::consts::FRAC_PI_2, 0.0, 0.0)),
            Shape::Plane => ColliderBuilder::halfspace(rapier3d_f64::na::Unit::new_unchecked(Vector::Z)),
            // meshes (triangles when fixed; convex pieces or the hull when moving), convex hulls and
            // compounds: the very parry shape tumble collides with (Rapier uses the same parry)
            Shape::Mesh(_) | Shape::Convex(_) | Shape::Compound(_) => {
                let (parry, offset) = tumble::collision::parry_shape(shape, b.fixed);
                ColliderBuilder::new(parry).position(offset)
            }
        };
        let friction = b.material.friction.unwrap_or(contact.friction);
        let restitution = b.material.restitution.unwrap_or(contact.restitution);
        let collider = collider
            .friction(friction)
            .restitution(restitution)
            .friction_combine_rule(CoefficientCombineRule::Min)
            .restitution_combine_rule(CoefficientCombineRule::Max)
            .mass(b.mass.mass);
        let rotation: DQuat = b.orientation_user();
        let pose = Pose::from_parts(b.state.position, rotation);
        let body = if b.fixed { RigidBodyBuilder::fixed() } else { RigidBodyBuilder::dynamic() }
            .pose(pose)
            .linvel(b.state.velocity)
            .angvel(b.state.omega_world())
            .gravity_scale(b.gravity_scale)
            .can_sleep(sleep);
        let (handle, _) = rw.insert(body, collider);
        handles.push(Some(handle));
    }
    (rw, handles)
}

struct Run {
    ms_per_step: f64,
    largest_displacement: f64,
    /// Per-stage ms per step: broad, narrow, impacts, resting, integration (tumble) or broad phase,
    /// the rest of collision detection (narrow phase), solver, other stages (Rapier).
    stages: [f64; 5],
    /// tumble: convex pairs and reused manifolds per step.
    pairs: (f64, f64),
    /// Bodies asleep at the end.
    asleep: usize,
    /// Contact points per step given to the solver (tumble: found by the narrow phase; Rapier: its
    /// solver contacts, counted after each step outside the timing), and its substeps.
    points: f64,
    substeps: f64,
}

fn run_tumble(mut world: tumble::World, steps: usize, sleep: bool) -> Run {
    let start: Vec<DVec3> = world.bodies.iter().map(|b| b.state.position).collect();
    world.config.contact.sleep = sleep;
    world.set_profiling(true);
    let t = Instant::now();
    for _ in 0..steps {
        if let Err(e) = world.step() {
            eprintln!("tumble: {e}");
            break;
        }
    }
    let ms_per_step = t.elapsed().as_secs_f64() * 1e3 / steps as f64;
    let largest_displacement = world
        .bodies
        .iter()
        .zip(&start)
        .filter(|(b, _)| !b.fixed)
        .map(|(b, s)| (b.state.position - *s).length())
        .fold(0.0, f64::max);
    let p = world.profile().expect("profiling is on").per_step();
    let stages = [p.broad_phase, p.narrow_phase, p.impacts, p.resting, p.integration].map(|s| s * 1e3);
    let asleep = world.contacts().sleep().count();
    let substeps = f64::from(world.config.contact.substeps);
    Run { ms_per_step, largest_displacement, stages, pairs: (p.pairs, p.reused), asleep, points: p.contacts, substeps }
}

fn run_rapier(world: &tumble::World, steps: usize, sleep: bool) -> Run {
    let (mut rw, handles) = rapier_world(world, sleep);
    let mut stages = [0.0; 5];
    let (mut points, mut counting) = (0usize, std::time::Duration::ZERO);
    let t = Instant::now();
    for _ in 0..steps {
        rw.step();
        let count = Instant::now();
        for pair in rw.contact_pairs() {
            if let PairContacts::Rigid(rigid) = &pair.contacts {
                points += rigid.solver_manifolds().iter().map(|m| m.data.solver_contacts.len()).sum::<usize>();
            }
        }
        counting += count.elapsed();
        // the counters are reset at the start of every step
        let c = &rw.physics_pipeline.counters;
        let broad = c.cd.broad_phase_time.time_ms();
        let detection = c.stages.collision_detection_time.time_ms();
        let solver = c.stages.solver_time.time_ms();
        stages[0] += broad;
        stages[1] += detection - broad;
        stages[2] += solver;
        stages[3] += c.step_time.time_ms() - detection - solver;
    }
    let ms_per_step = (t.elapsed() - counting).as_secs_f64() * 1e3 / steps as f64;
    let largest_displacement = world
        .bodies
        .iter()
        .zip(&handles)
        .filter(|(b, _)| !b.fixed)
        .filter_map(|(b, h)| h.map(|h| (rw.bodies[h].translation() - b.state.position).length()))
        .fold(0.0, f64::max);
    let asleep = rw.bodies.iter().filter(|(_, b)| b.is_dynamic() && b.is_sleeping()).count();
    Run {
        ms_per_step,
        largest_displacement,
        stages: stages.map(|s| s / steps as f64),
        pairs: (0.0, 0.0),
        asleep,
        points: points as f64 / steps as f64,
        substeps: rw.integration_parameters.num_solver_iterations as f64,
    }
}

fn median(mut xs: Vec<f64>) -> f64 {
    xs.sort_by(f64::total_cmp);
    let n = xs.len();
    if n % 2 == 1 {
        xs[n / 2]
    } else {
        0.5 * (xs[n / 2 - 1] + xs[n / 2])
    }
}

/// The world of the scene file at `path`; a scene that does not load is reported and ends the
/// run with status 2.
fn load_world(path: &str) -> tumble::World {
    match tumble::scene::load(Path::new(path)) {
        Ok(s) => s.world,
        Err(e) => {
            eprintln!("{e}");
            std::process::exit(2);
        }
    }
}

/// The median over the runs of `f`.
fn med(runs: &[Run], f: impl Fn(&Run) -> f64) -> f64 {
    median(runs.iter().map(f).collect())
}

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let steps = match args.first().and_then(|a| a.parse::<usize>().ok()) {
        Some(n) => {
            args.remove(0);
            n
        }
        None => 1000,
    };
    let mut reps = 5;
    if let Some(at) = args.iter().position(|a| a == "--reps") {
        reps = args.get(at + 1).and_then(|n| n.parse().ok()).filter(|&n| n > 0).unwrap_or_else(|| {
            eprintln!("--reps takes a positive number");
            std::process::exit(2);
        });
        args.drain(at..at + 2);
    }
    let mut threads = 1;
    if let Some(at) = args.iter().position(|a| a == "--threads") {
        threads = args.get(at + 1).and_then(|n| n.parse().ok()).unwrap_or_else(|| {
            eprintln!("--threads takes a number ≥ 0");
            std::process::exit(2);
        });
        args.drain(at..at + 2);
    }
    let mut sleep_speed = None;
    if let Some(at) = args.iter().position(|a| a == "--sleep-speed") {
        sleep_speed =
            Some(args.get(at + 1).and_then(|n| n.parse::<f64>().ok()).filter(|v| *v >= 0.0).unwrap_or_else(|| {
                eprintln!("--sleep-speed takes a speed ≥ 0 (m/s)");
                std::process::exit(2);
            }));
        args.drain(at..at + 2);
    }
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    if let Some(at) = args.iter().position(|a| a == "--sleep-onset") {
        args.remove(at);
        let scenes = if args.is_empty() { onset::default_scenes(&root) } else { args };
        onset::report(&scenes, steps, reps);
        return;
    }
    if let Some(at) = args.iter().position(|a| a == "--curve") {
        args.remove(at);
        let mut take_path = |flag: &str| {
            args.iter().position(|a| a == flag).map(|at| {
                let p = args.get(at + 1).cloned().unwrap_or_else(|| {
                    eprintln!("{flag} takes a file name");
                    std::process::exit(2);
                });
                args.drain(at..at + 2);
                p
            })
        };
        let plot = take_path("--plot");
        let csv = take_path("--csv");
        let cheap = args.iter().position(|a| a == "--cheap").map(|at| args.remove(at)).is_some();
        let scenes = if args.is_empty() { curve::default_scenes(&root) } else { args };
        println!(
            "{steps} steps each, both engines single-threaded, sleeping off, median of {reps} interleaved repetitions"
        );
        let curves = curve::sweep(&scenes, steps, reps, cheap);
        let unmatched = curve::report(&curves);
        println!();
        println!("Rapier settings with no tumble setting at most as slow and with no more drift: {unmatched}");
        if let Some(p) = csv {
            if let Err(e) = curve::write_csv(&curves, Path::new(&p)) {
                eprintln!("{p}: {e}");
                std::process::exit(1);
            }
        }
        if let Some(p) = plot {
            if let Err(e) = curve::plot(&curves, Path::new(&p)) {
                eprintln!("{p}: {e}");
                std::process::exit(1);
            }
        }
        return;
    }
    let scenes: Vec<String> = if args.is_empty() {
        ["scenes/pyramid.toml", "scenes/balls.toml"].iter().map(|s| root.join(s).display().to_string()).collect()
    } else {
        args
    };
    println!("{steps} steps each, Rapier single-threaded, tumble on {threads} thread(s), median of {reps} interleaved repetitions");
    let mut results = Vec::new();
    for path in scenes {
        let mut world = load_world(&path);
        world.set_threads(threads);
        if let Some(v) = sleep_speed {
            world.config.contact.sleep_speed = v;
        }
        // awake: sleeping off in both engines (the work of every step); asleep: both engines'
        // default, islands at rest fall asleep
        let mut runs: [Vec<Run>; 4] = Default::default();
        for _ in 0..reps {
            runs[0].push(run_rapier(&world, steps, false));
            runs[1].push(run_tumble(world.clone(), steps, false));
            runs[2].push(run_rapier(&world, steps, true));
            runs[3].push(run_tumble(world.clone(), steps, true));
        }
        let name = Path::new(&path).file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or(path.clone());
        results.push((name, world.bodies.len(), runs));
    }
    println!();
    println!("| scene | bodies | sleeping | tumble ms/step | Rapier ms/step | tumble/Rapier | largest displacement tumble (m) | Rapier (m) | asleep at the end, tumble | Rapier |");
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for (name, n, runs) in &results {
        for (label, rapier, tumble) in [("off", &runs[0], &runs[1]), ("on", &runs[2], &runs[3])] {
            let ratio = median(tumble.iter().zip(rapier).map(|(t, r)| t.ms_per_step / r.ms_per_step).collect());
            println!(
                "| {name} | {n} | {label} | {:.3} | {:.3} | {:.2} | {:.5} | {:.5} | {:.0} | {:.0} |",
                med(tumble, |r| r.ms_per_step),
                med(rapier, |r| r.ms_per_step),
                ratio,
                med(tumble, |r| r.largest_displacement),
                med(rapier, |r| r.largest_displacement),
                med(tumble, |r| r.asleep as f64),
                med(rapier, |r| r.asleep as f64),
            );
        }
    }
    for (name, _, runs) in &results {
        println!();
        println!("{name}: ms per step by stage (median of {reps})");
        println!();
        println!("| stage | tumble, sleeping off | Rapier, sleeping off | tumble, sleeping on | Rapier, sleeping on |");
        println!("|---|---|---|---|---|");
        let stage = |runs: &[Run], k: usize| med(runs, |r| r.stages[k]);
        let rows = [
            ("broad phase", 0, Some(0)),
            ("narrow phase", 1, Some(1)),
            ("collisions (impacts)", 2, None),
            ("resting contact (constraints and solver)", 3, Some(2)),
            ("integration", 4, None),
        ];
        for (label, k, rk) in rows {
            let r = |runs: &[Run]| rk.map_or("—".to_string(), |rk| format!("{:.3}", stage(runs, rk)));
            println!(
                "| {label} | {:.3} | {} | {:.3} | {} |",
                stage(&runs[1], k),
                r(&runs[0]),
                stage(&runs[3], k),
                r(&runs[2])
            );
        }
        println!(
            "| Rapier's other stages (islands, integration, user changes) | | {:.3} | | {:.3} |",
            stage(&runs[0], 3),
            stage(&runs[2], 3)
        );
        println!(
            "| whole step | {:.3} | {:.3} | {:.3} | {:.3} |",
            med(&runs[1], |r| r.ms_per_step),
            med(&runs[0], |r| r.ms_per_step),
            med(&runs[3], |r| r.ms_per_step),
            med(&runs[2], |r| r.ms_per_step)
        );
        println!(
            "| contact points per step, solver substeps | {:.0}, {:.0} | {:.0}, {:.0} | {:.0}, {:.0} | {:.0}, {:.0} |",
            med(&runs[1], |r| r.points),
            med(&runs[1], |r| r.substeps),
            med(&runs[0], |r| r.points),
            med(&runs[0], |r| r.substeps),
            med(&runs[3], |r| r.points),
            med(&runs[3], |r| r.substeps),
            med(&runs[2], |r| r.points),
            med(&runs[2], |r| r.substeps)
        );
        // the resting stage (Rapier: its solver) per contact point and substep
        let per_point = |runs: &[Run], k: usize| {
            med(runs, |r| if r.points > 0.0 { r.stages[k] * 1e6 / (r.points * r.substeps) } else { f64::NAN })
        };
        println!(
            "| resting contact per point and substep (ns) | {:.0} | {:.0} | {:.0} | {:.0} |",
            per_point(&runs[1], 3),
            per_point(&runs[0], 2),
            per_point(&runs[3], 3),
            per_point(&runs[2], 2)
        );
        println!(
            "| convex pairs per step, manifolds reused | {:.0}, {:.0} | | {:.0}, {:.0} | |",
            med(&runs[1], |r| r.pairs.0),
            med(&runs[1], |r| r.pairs.1),
            med(&runs[3], |r| r.pairs.0),
            med(&runs[3], |r| r.pairs.1)
        );
    }
}
