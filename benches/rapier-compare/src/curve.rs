//! `--curve`: the speed–accuracy curve of each engine on the stacking scenes.
//!
//! Each engine has knobs that trade time for accuracy. Rapier: `num_solver_iterations` (its
//! substeps, 1–16), `num_internal_pgs_iterations` (PGS passes in each) and its friction model
//! (`Simplified`, the default: one friction row and a twist per manifold; `Coulomb`: friction at
//! every point). tumble: `contact_substeps`, `contact_iterations` and its friction model (`point`,
//! the default: friction at every point; `manifold`: one friction disc and a twist per manifold,
//! an option) and `manifold_reuse` (the default `1e-4`, or the [`LOOSER_REUSE`]: `1e-3`, about
//! the 1 mm that parry reuses Rapier's box manifolds for on these unit boxes, and `1e-2`). Every setting runs the scene
//! with sleeping off (the work of every step) and gives a point: time per step, against the
//! settling drift (the largest displacement of a moving body between the start and the end of the
//! run) and the overlap (the deepest penetration between two shapes at the end, found by parry on
//! the final poses, the same query for both engines).
//!
//! A curve lies on or below another where, for every setting of the other, it has a setting at
//! most as slow with no more drift: the tool prints that check per scene, for every Rapier
//! setting the cheapest tumble setting that matches its drift, and the plot (`--plot FILE.svg`).

use rapier3d_f64::parry::query;
use rapier3d_f64::prelude::*;
use std::path::Path;
use std::time::Instant;

/// tumble's looser `manifold_reuse` swept beside the default (`Setting::Tumble::reuse` 1 and 2):
/// 1e-3 and 1e-2 of the smaller shape's bounding radius, 0.87 mm and 8.7 mm for the pyramid's unit
/// boxes.
pub const LOOSER_REUSE: [f64; 2] = [1e-3, 1e-2];

/// One knob setting of one engine.
#[derive(Clone, Copy, Debug)]
pub enum Setting {
    /// tumble: `contact_substeps`, `contact_iterations`, friction per manifold (else at every point),
    /// `reuse`: 0 the default `manifold_reuse`, `k` the `LOOSER_REUSE[k − 1]`.
    Tumble { substeps: u32, iterations: u32, manifold: bool, reuse: usize },
    /// Rapier: `num_solver_iterations`, `num_internal_pgs_iterations`, Coulomb friction at every
    /// point (else the default `Simplified` model).
    Rapier { iterations: usize, pgs: usize, coulomb: bool },
}

impl Setting {
    pub fn engine(&self) -> &'static str {
        match self {
            Setting::Tumble { .. } => "tumble",
            Setting::Rapier { .. } => "Rapier",
        }
    }

    pub fn label(&self) -> String {
        match *self {
            Setting::Tumble { substeps, iterations, manifold, reuse } => format!(
                "substeps {substeps}, iterations {iterations}{}{}",
                if manifold { ", manifold" } else { "" },
                if reuse > 0 { format!(", reuse {:e}", LOOSER_REUSE[reuse - 1]) } else { String::new() }
            ),
            Setting::Rapier { iterations, pgs, coulomb } => {
                format!("iterations {iterations}, pgs {pgs}{}", if coulomb { ", Coulomb" } else { "" })
            }
        }
    }

    fn is_default(&self) -> bool {
        let d = tumble::contact::ContactSettings::default();
        match *self {
            Setting::Tumble { substeps, iterations, manifold, reuse } => {
                substeps == d.substeps && iterations == d.iterations && !manifold && reuse == 0
            }
            Setting::Rapier { iterations, pgs, coulomb } => {
                let r = IntegrationParameters::default();
                iterations == r.num_solver_iterations && pgs == r.num_internal_pgs_iterations && !coulomb
            }
        }
    }
}

/// The settings swept: tumble's substeps × iterations with either friction model and either
/// manifold reuse, Rapier's
/// iterations × PGS passes with its default friction, and its iterations with Coulomb friction.
pub fn settings() -> Vec<Setting> {
    let mut s = Vec::new();
    for reuse in 0..=LOOSER_REUSE.len() {
        for manifold in [false, true] {
            for iterations in [1, 2] {
                for substeps in [1, 2, 3, 4, 6, 8, 12] {
                    s.push(Setting::Tumble { substeps, iterations, manifold, reuse });
                }
            }
        }
    }
    for pgs in [1, 2, 4] {
        for iterations in [1, 2, 4, 8, 16] {
            s.push(Setting::Rapier { iterations, pgs, coulomb: false });
        }
    }
    for iterations in [1, 2, 4, 8, 16] {
        s.push(Setting::Rapier { iterations, pgs: 1, coulomb: true });
    }
    s
}

/// One run: ms per step, largest displacement (m), deepest overlap at the end (m).
#[derive(Clone, Copy, Debug, Default)]
pub struct Point {
    pub ms_per_step: f64,
    pub drift: f64,
    pub overlap: f64,
}

/// The deepest penetration between two shapes of `world`'s bodies placed at `poses` (each body's
/// pose of its user axes, `None` for bodies without a shape), at least one of the two moving.
fn deepest_overlap(world: &tumble::World, poses: &[Option<Pose>]) -> f64 {
    let shapes: Vec<_> = world
        .bodies
        .iter()
        .zip(poses)
        .filter_map(|(b, p)| {
            let (shape, offset) = tumble::collision::parry_shape(b.shape.as_ref()?, b.fixed);
            Some((b.fixed, *p.as_ref()? * offset, shape))
        })
        .collect();
    let mut deepest: f64 = 0.0;
    for (i, (fixed_a, pose_a, a)) in shapes.iter().enumerate() {
        for (fixed_b, pose_b, b) in &shapes[i + 1..] {
            if *fixed_a && *fixed_b {
                continue;
            }
            if let Ok(Some(c)) = query::contact(pose_a, a.as_ref(), pose_b, b.as_ref(), 0.0) {
                deepest = deepest.max(-c.dist);
            }
        }
    }
    deepest
}

fn largest_displacement(world: &tumble::World, end: &[Option<Pose>]) -> f64 {
    world
        .bodies
        .iter()
        .zip(end)
        .filter(|(b, _)| !b.fixed)
        .filter_map(|(b, p)| p.map(|p| (p.translation - b.state.position).length()))
        .fold(0.0, f64::max)
}

/// Runs `world` for `steps` steps with `setting`, sleeping off.
pub fn run(world: &tumble::World, steps: usize, setting: Setting) -> Point {
    match setting {
        Setting::Tumble { substeps, iterations, manifold, reuse } => {
            let mut w = world.clone();
            w.config.contact.sleep = false;
            w.config.contact.substeps = substeps;
            w.config.contact.iterations = iterations;
            if manifold {
                w.config.contact.friction_model = tumble::contact::FrictionModel::Manifold;
            }
            if reuse > 0 {
                w.config.contact.manifold_reuse = LOOSER_REUSE[reuse - 1];
            }
            let t = Instant::now();
            for _ in 0..steps {
                if let Err(e) = w.step() {
                    eprintln!("tumble ({}): {e}", setting.label());
                    break;
                }
            }
            let ms_per_step = t.elapsed().as_secs_f64() * 1e3 / steps as f64;
            let end: Vec<Option<Pose>> =
                w.bodies.iter().map(|b| Some(Pose::from_parts(b.state.position, b.orientation_user()))).collect();
            Point { ms_per_step, drift: largest_displacement(world, &end), overlap: deepest_overlap(world, &end) }
        }
        Setting::Rapier { iterations, pgs, coulomb } => {
            let (mut rw, handles) = super::rapier_world(world, false);
            let p = &mut rw.integration_parameters;
            p.num_solver_iterations = iterations;
            p.num_internal_pgs_iterations = pgs;
            if coulomb {
                p.friction_model = FrictionModel::Coulomb;
            }
            let t = Instant::now();
            for _ in 0..steps {
                rw.step();
            }
            let ms_per_step = t.elapsed().as_secs_f64() * 1e3 / steps as f64;
            let end: Vec<Option<Pose>> = handles.iter().map(|h| h.map(|h| *rw.bodies[h].position())).collect();
            Point { ms_per_step, drift: largest_displacement(world, &end), overlap: deepest_overlap(world, &end) }
        }
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

/// A scene's curve: every setting with the median of its repetitions (time; drift and overlap
/// are deterministic in both engines, the median keeps them).
pub struct Curve {
    pub scene: String,
    pub points: Vec<(Setting, Point)>,
}

/// Sweeps every setting on each scene, `reps` interleaved repetitions (each repetition runs every
/// setting once, in turn, so that the machine's drift in speed reaches all settings alike).
///
/// `cheap`: only the cheap end, the settings of one or two substeps (tumble) and of one or two
/// solver iterations (Rapier), a quick check of where the curves are closest; a Rapier setting
/// there is matched only by these tumble settings, which are the cheapest.
pub fn sweep(scenes: &[String], steps: usize, reps: usize, cheap: bool) -> Vec<Curve> {
    let settings: Vec<Setting> = settings()
        .into_iter()
        .filter(|s| {
            !cheap
                || match *s {
                    Setting::Tumble { substeps, .. } => substeps <= 2,
                    Setting::Rapier { iterations, .. } => iterations <= 2,
                }
        })
        .collect();
    let mut curves = Vec::new();
    for path in scenes {
        let world = super::load_world(path);
        let mut runs: Vec<Vec<Point>> = vec![Vec::new(); settings.len()];
        for rep in 0..reps {
            eprintln!("{path}: repetition {}/{reps}", rep + 1);
            for (k, s) in settings.iter().enumerate() {
                runs[k].push(run(&world, steps, *s));
            }
        }
        let points = settings
            .iter()
            .zip(runs)
            .map(|(s, r)| {
                let p = Point {
                    ms_per_step: median(r.iter().map(|p| p.ms_per_step).collect()),
                    drift: median(r.iter().map(|p| p.drift).collect()),
                    overlap: median(r.iter().map(|p| p.overlap).collect()),
                };
                (*s, p)
            })
            .collect();
        let name = Path::new(path).file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or(path.clone());
        curves.push(Curve { scene: name, points });
    }
    curves
}

/// The cheapest tumble setting with no more drift than `than` (and no more overlap, if `overlap`).
fn cheapest_tumble(curve: &Curve, than: &Point, overlap: bool) -> Option<(Setting, Point)> {
    curve
        .points
        .iter()
        .filter(|(s, p)| {
            matches!(s, Setting::Tumble { .. }) && p.drift <= than.drift && (!overlap || p.overlap <= than.overlap)
        })
        .min_by(|a, b| a.1.ms_per_step.total_cmp(&b.1.ms_per_step))
        .copied()
}

/// Prints every point, then the check per Rapier setting; returns the number of Rapier settings
/// that tumble does not match (no tumble setting at most as slow with no more drift).
pub fn report(curves: &[Curve]) -> usize {
    let mut unmatched = 0;
    for c in curves {
        println!();
        println!("{}: time per step against settling (sleeping off; median of the repetitions)", c.scene);
        println!();
        println!("| engine | setting | ms/step | largest displacement (mm) | deepest overlap at the end (mm) |");
        println!("|---|---|---|---|---|");
        for (s, p) in &c.points {
            let mark = if s.is_default() { " (default)" } else { "" };
            println!(
                "| {} | {}{mark} | {:.4} | {:.3} | {:.3} |",
                s.engine(),
                s.label(),
                p.ms_per_step,
                p.drift * 1e3,
                p.overlap * 1e3
            );
        }
        println!();
        println!("{}: for each Rapier setting, the cheapest tumble setting with no more drift (and with no more drift and overlap)", c.scene);
        println!();
        println!("| Rapier setting | ms/step | drift (mm) | overlap (mm) | tumble: no more drift | ms/step | ratio | tumble: no more drift nor overlap | ms/step | ratio |");
        println!("|---|---|---|---|---|---|---|---|---|---|");
        for (s, p) in c.points.iter().filter(|(s, _)| matches!(s, Setting::Rapier { .. })) {
            let cell = |m: Option<(Setting, Point)>| match m {
                Some((t, q)) => format!("{} | {:.4} | {:.2}", t.label(), q.ms_per_step, q.ms_per_step / p.ms_per_step),
                None => "none | — | —".to_string(),
            };
            let by_drift = cheapest_tumble(c, p, false);
            if by_drift.is_none_or(|(_, q)| q.ms_per_step > p.ms_per_step) {
                unmatched += 1;
            }
            println!(
                "| {} | {:.4} | {:.3} | {:.3} | {} | {} |",
                s.label(),
                p.ms_per_step,
                p.drift * 1e3,
                p.overlap * 1e3,
                cell(by_drift),
                cell(cheapest_tumble(c, p, true))
            );
        }
    }
    unmatched
}

/// Writes every point as CSV: scene, engine, setting, ms per step, drift (m), overlap (m).
pub fn write_csv(curves: &[Curve], path: &Path) -> std::io::Result<()> {
    let mut out = String::from("scene,engine,setting,ms_per_step,drift_m,overlap_m\n");
    for c in curves {
        for (s, p) in &c.points {
            out +=
                &format!("{},{},\"{}\",{},{},{}\n", c.scene, s.engine(), s.label(), p.ms_per_step, p.drift, p.overlap);
        }
    }
    std::fs::write(path, out)
}

/// The curves as an SVG, one panel per scene: time per step (log) against drift (log); each
/// engine's points (tumble's with friction per manifold hollow, with `manifold_reuse` 1e-3 as
/// squares and 1e-2 as triangles) and its lower envelope (the least drift reached at each cost).
pub fn plot(curves: &[Curve], path: &Path) -> Result<(), Box<dyn std::error::Error>> {
    use plotters::prelude::*;
    let width = 520 * curves.len() as u32;
    let root = SVGBackend::new(path, (width, 440)).into_drawing_area();
    root.fill(&WHITE)?;
    let panels = root.split_evenly((1, curves.len()));
    for (c, area) in curves.iter().zip(panels) {
        let floor = 1e-6; // m: drifts below a micrometre are drawn at it
        let drift = |p: &Point| p.drift.max(floor) * 1e3;
        let (tmin, tmax) = c
            .points
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(a, b), (_, p)| (a.min(p.ms_per_step), b.max(p.ms_per_step)));
        let (dmin, dmax) =
            c.points.iter().fold((f64::INFINITY, 0.0f64), |(a, b), (_, p)| (a.min(drift(p)), b.max(drift(p))));
        let mut chart = ChartBuilder::on(&area)
            .caption(&c.scene, ("sans-serif", 20))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d((tmin / 1.3..tmax * 1.3).log_scale(), (dmin / 2.0..dmax * 2.0).log_scale())?;
        chart
            .configure_mesh()
            .x_desc("ms per step")
            .y_desc("largest displacement (mm)")
            .x_label_formatter(&|x| format!("{x:.2}"))
            .y_label_formatter(&|y| format!("{y:.3}"))
            .draw()?;
        for (engine, colour) in [("tumble", RGBColor(200, 60, 30)), ("Rapier", RGBColor(40, 90, 200))] {
            let mut pts: Vec<(f64, f64)> =
                c.points.iter().filter(|(s, _)| s.engine() == engine).map(|(_, p)| (p.ms_per_step, drift(p))).collect();
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
            // the lower envelope: the least drift reached at or below each cost
            let mut envelope = Vec::new();
            let mut best = f64::INFINITY;
            for &(t, d) in &pts {
                if d < best {
                    if best.is_finite() {
                        envelope.push((t, best));
                    }
                    best = d;
                    envelope.push((t, d));
                }
            }
            chart
                .draw_series(LineSeries::new(envelope, colour.stroke_width(2)))?
                .label(engine)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], colour.stroke_width(2)));
            // tumble's settings with friction per manifold drawn hollow, the looser reuses as squares
            // and triangles
            for (s, p) in c.points.iter().filter(|(s, _)| s.engine() == engine) {
                let (manifold, reuse) = match *s {
                    Setting::Tumble { manifold, reuse, .. } => (manifold, reuse),
                    Setting::Rapier { .. } => (false, 0),
                };
                let style = if manifold { colour.stroke_width(1) } else { colour.filled() };
                let at = (p.ms_per_step, drift(p));
                match reuse {
                    0 => chart.draw_series(std::iter::once(Circle::new(at, 3, style)))?,
                    1 => {
                        let square = EmptyElement::at(at) + Rectangle::new([(-3, -3), (3, 3)], style);
                        chart.draw_series(std::iter::once(square))?
                    }
                    _ => chart.draw_series(std::iter::once(TriangleMarker::new(at, 4, style)))?,
                };
            }
        }
        chart.configure_series_labels().background_style(WHITE.mix(0.8)).border_style(BLACK).draw()?;
    }
    root.present()?;
    Ok(())
}

/// The scenes of the curve: the pyramid, the ten-box tower and the 10:1 stack.
pub fn default_scenes(root: &Path) -> Vec<String> {
    ["scenes/pyramid.toml", "scenes/tower.toml", "scenes/stack_10_1.toml"]
        .iter()
        .map(|s| root.join(s).display().to_string())
        .collect()
}
