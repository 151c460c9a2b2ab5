//! `tumble plot TRAJ [--scene SCENE] --out FILE.svg|FILE.png`, and `tumble run --plot FILE`.
//!
//! Stacked panels over time, drawn with `plotters`:
//! 1. the relative energy error `(E − E₀)/|E₀|` of the moving bodies and the robots' links (needs the
//!    scene's masses);
//! 2. the angular-momentum error `|L − L₀|/|L₀|` about the world origin (needs the scene), of the
//!    moving bodies and the floating-base robots; left out when the only things that move are
//!    fixed-base robots (the world holds them: their momentum is not conserved, and the run summary
//!    does not count it);
//! 3. for each robot (needs the scene), its kinetic, potential and total energy (J): how a pendulum
//!    trades one for the other, and what PD control and damping do to the total;
//! 4. for each chosen body, the angular velocity in its body axes (rad/s), x, y and z; for a robot
//!    link, in its link axes;
//! 5. for each chosen body, the position of its centre of mass (m), x, y and z; for a robot link, of
//!    its link frame's origin (what its trajectory row holds: the path of a tool frame such as
//!    `tip`). No per-link conservation panel: a link exchanges energy and momentum with the others.
//!
//! SVG text is left to the viewer's `sans-serif` font. PNG text is drawn with DejaVu Sans, which the
//! binary carries (`assets/fonts`, Bitstream Vera license beside it), so a PNG looks the same on a
//! machine with no font installed.

use crate::cli::{PlotArgs, RunArgs};
use crate::error::{Failure, Status};
use crate::output::OutputFile;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::io::Write;
use std::path::Path;
use tumble::scene;
use tumble::trajectory::derived::{self, InvariantErrors};
use tumble::trajectory::{read, ReadError, ReadOptions, Trajectory};
use tumble::World;

/// Bodies plotted when `--bodies` is not given (the first ones of the trajectory).
pub const DEFAULT_MAX_BODIES: usize = 4;
/// Most bodies in one figure (`--bodies`): two panels each.
pub const MAX_BODIES: usize = 16;
/// Frames kept for a plot: far more than the pixels of a panel's width (see `ReadOptions`).
pub const PLOT_MAX_FRAMES: usize = 5000;
/// Width of the figure (pixels).
const WIDTH: u32 = 1200;
/// Height of one panel (pixels).
const PANEL_HEIGHT: u32 = 230;
/// The font carried for PNG text.
const FONT: &[u8] = include_bytes!("../assets/fonts/DejaVuSans.ttf");

/// The image format of a plot, by extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ImageFormat {
    Svg,
    Png,
}

impl ImageFormat {
    /// `.svg` or `.png` (any case); anything else is bad input, named after `flag`.
    pub fn of(path: &Path, flag: &str) -> Result<ImageFormat, Failure> {
        let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("svg") => Ok(ImageFormat::Svg),
            Some("png") => Ok(ImageFormat::Png),
            _ => Err(Failure::bad_input(format!(
                "{flag} {}: unsupported image format; use FILE.svg or FILE.png",
                path.display()
            ))),
        }
    }
}

/// `tumble plot`.
pub fn plot(args: &PlotArgs) -> Result<Status, Failure> {
    let format = ImageFormat::of(&args.out, "--out")?;
    let scene = args.scene.as_deref().map(|p| scene::load(p).map_err(Failure::bad_input)).transpose()?;
    let trajectory = read_trajectory(&args.trajectory, PLOT_MAX_FRAMES, Failure::bad_input)?;
    let names = args.bodies.as_deref().map(|b| b.split(',').map(|s| s.trim().to_string()).collect::<Vec<_>>());
    let chosen = choose_bodies(&trajectory, names.as_deref(), &args.trajectory)?;
    if chosen.len() < trajectory.bodies.len() && names.is_none() {
        let (shown, all) = (chosen.len(), trajectory.bodies.len());
        let _ = writeln!(
            std::io::stderr().lock(),
            "note: plotting the first {shown} of {all} bodies; choose with --bodies"
        );
    }
    if let Some(note) = truncation_note(&trajectory) {
        let _ = writeln!(std::io::stderr().lock(), "warning: {}: {note}", args.trajectory.display());
    }
    let world = scene.as_ref().map(|s| (&s.world, s.origin.as_str()));
    let image = render(&trajectory, world, &args.trajectory, &chosen, format).map_err(Failure::bad_input)?;
    write_output(&args.out, &image)?;
    Ok(Status::Success)
}

/// Reads a trajectory; every read error becomes `failure` (bad input for `tumble plot`, an output
/// error when `tumble run` reads back its own file).
pub fn read_trajectory(
    path: &Path,
    max_frames: usize,
    failure: fn(ReadError) -> Failure,
) -> Result<Trajectory, Failure> {
    read(path, ReadOptions { max_frames: Some(max_frames) }).map_err(failure)
}

/// What was dropped from a trajectory cut short, for messages.
pub fn truncation_note(trajectory: &Trajectory) -> Option<String> {
    let cut = trajectory.truncated.as_ref()?;
    let (_, end) = trajectory.time_span();
    Some(format!("the file was cut short: line {} ({}) was dropped; shown up to t = {end} s", cut.line, cut.what))
}

/// The indices of the bodies to plot: the named ones (each must be in the trajectory), or the first
/// [`DEFAULT_MAX_BODIES`].
pub fn choose_bodies(trajectory: &Trajectory, names: Option<&[String]>, path: &Path) -> Result<Vec<usize>, Failure> {
    let Some(names) = names else {
        return Ok((0..trajectory.bodies.len().min(DEFAULT_MAX_BODIES)).collect());
    };
    let mut chosen = Vec::new();
    for name in names.iter().filter(|n| !n.is_empty()) {
        match trajectory.bodies.iter().position(|b| b == name) {
            Some(i) if !chosen.contains(&i) => chosen.push(i),
            Some(_) => {}
            None => {
                let known: Vec<&str> = trajectory.bodies.iter().take(10).map(String::as_str).collect();
                return Err(Failure::bad_input(format!(
                    "--bodies: `{name}` is not a body of {} (its bodies: {}{})",
                    path.display(),
                    known.join(", "),
                    if trajectory.bodies.len() > 10 { ", ..." } else { "" }
                )));
            }
        }
    }
    if chosen.is_empty() {
        return Err(Failure::bad_input("--bodies: no body named"));
    }
    if chosen.len() > MAX_BODIES {
        return Err(Failure::bad_input(format!(
            "--bodies: {} bodies named; one figure shows at most {MAX_BODIES}",
            chosen.len()
        )));
    }
    Ok(chosen)
}

/// Writes `bytes` to `path` through a `.partial` file renamed into place (exit 4 on failure).
pub fn write_output(path: &Path, bytes: &[u8]) -> Result<(), Failure> {
    let cannot = |e: &dyn std::fmt::Display| Failure::output(format!("cannot write '{}': {e}", path.display()));
    let (output, mut file) = OutputFile::create(path).map_err(|e| cannot(&e))?;
    if let Err(e) = file.write_all(bytes).and_then(|()| file.flush()) {
        output.discard();
        return Err(cannot(&e));
    }
    drop(file);
    output.commit().map_err(|e| cannot(&e))
}

/// `tumble run --plot/--view`, before the run: each must name an image or a page, and the trajectory
/// must be a file that can be read back (not a device or a pipe). Touches no file.
pub fn check_run(args: &RunArgs, out: &Path) -> Result<(), Failure> {
    if let Some(plot) = &args.plot {
        ImageFormat::of(plot, "--plot")?;
    }
    if let Some(view) = &args.view {
        crate::view::check_out(view, "--view")?;
    }
    for (flag, path) in [("--plot", &args.plot), ("--view", &args.view)] {
        let Some(path) = path else { continue };
        let taken = [Some(out), args.summary.as_deref(), args.scene.as_deref()];
        if taken.into_iter().flatten().any(|other| crate::output::same_file(path, other)) {
            return Err(Failure::bad_input(format!(
                "{flag} {}: the same file as the trajectory, the summary or the scene",
                path.display()
            )));
        }
    }
    let special = std::fs::metadata(out).is_ok_and(|m| !m.is_file());
    if (args.plot.is_some() || args.view.is_some()) && special {
        return Err(Failure::bad_input(format!(
            "--plot/--view read the trajectory back, but --out {} is not a regular file",
            out.display()
        )));
    }
    Ok(())
}

/// `tumble run --plot/--view`, after the run: reads the trajectory `out` back and writes the plot
/// and the replay (exit 4 when they cannot be written or the trajectory cannot be read back).
pub fn after_run(args: &RunArgs, world: &World, origin: &str, out: &Path) -> Result<(), Failure> {
    let read_back = |e: ReadError| Failure::output(format!("cannot read the trajectory back: {e}"));
    if let Some(plot) = &args.plot {
        let trajectory = read_trajectory(out, PLOT_MAX_FRAMES, read_back)?;
        let chosen = choose_bodies(&trajectory, None, out)?;
        let format = ImageFormat::of(plot, "--plot")?;
        let image = render(&trajectory, Some((world, origin)), out, &chosen, format).map_err(Failure::output)?;
        write_output(plot, &image)?;
    }
    if let Some(view) = &args.view {
        let trajectory = read_trajectory(out, crate::view::frames_budget(world, None), read_back)?;
        let page =
            crate::view::page(&trajectory, world, origin, out, args.contacts.as_deref()).map_err(Failure::output)?;
        if !args.quiet {
            for warning in &page.warnings {
                let _ = writeln!(std::io::stderr().lock(), "warning: {warning}");
            }
        }
        write_output(view, page.html.as_bytes())?;
    }
    if args.scene.is_none() && args.view.is_none() && !args.quiet {
        // the demo says how to watch it
        let hint = "  watch it: tumble run --view demo.html, then open demo.html in a browser (docs/viewing.md)\n";
        crate::report::Stdout::default()
            .write(hint)
            .map_err(|e| Failure::output(format!("cannot write to standard output: {e}")))?;
    }
    Ok(())
}

/// A named line of `(t, value)` points, in a colour.
type Series = (String, RGBColor, Vec<(f64, f64)>);

/// One panel: a title, the y axis label, and named series of `(t, value)`.
struct Panel {
    title: String,
    y_label: String,
    series: Vec<Series>,
    /// Tick labels in scientific notation (errors).
    scientific: bool,
}

const X_COLOR: RGBColor = RGBColor(214, 39, 40);
const Y_COLOR: RGBColor = RGBColor(44, 160, 44);
const Z_COLOR: RGBColor = RGBColor(31, 119, 180);

/// The panels of a trajectory (see the module doc).
fn panels(
    trajectory: &Trajectory,
    world: Option<(&World, &str)>,
    path: &Path,
    chosen: &[usize],
) -> Result<Vec<Panel>, String> {
    let times: Vec<f64> = trajectory.frames.iter().map(|f| f.t).collect();
    // a value that overflowed (an energy of 1e300 m/s squared) is left out, not drawn at the edge
    let series =
        |values: Vec<f64>| times.iter().copied().zip(values).filter(|(_, v)| v.is_finite()).collect::<Vec<_>>();
    let mut panels = Vec::new();
    if let Some((world, origin)) = world {
        let invariants =
            derived::invariants(trajectory, world, &path.display().to_string(), origin).map_err(|e| e.to_string())?;
        let errors = InvariantErrors::of(&invariants);
        let (e_title, e_label) = if errors.energy_is_absolute {
            ("energy error E − E₀ (E₀ = 0)", "E − E₀ (J)")
        } else {
            ("relative energy error (E − E₀)/|E₀|", "(E − E₀)/|E₀|")
        };
        let what = if world.robots.is_empty() { "moving bodies" } else { "moving bodies and robot links" };
        let e0 = invariants.first().map_or(0.0, |i| i.energy);
        panels.push(Panel {
            title: format!("{e_title}, {what}, E₀ = {} J{}", short(e0), driven_note(world)),
            y_label: e_label.into(),
            series: vec![("energy".into(), X_COLOR, series(errors.energy))],
            scientific: true,
        });
        // fixed-base robots alone: no momentum is counted (the world holds them)
        let momentum_counted = world.free_bodies().next().is_some() || world.robots.iter().any(|r| r.floating);
        let (l_title, l_label) = if errors.angular_momentum_is_absolute {
            ("angular-momentum error |L − L₀| about the origin (L₀ = 0)", "|L − L₀| (kg·m²/s)")
        } else {
            ("angular-momentum error |L − L₀|/|L₀| about the origin", "|L − L₀|/|L₀|")
        };
        if momentum_counted || world.robots.is_empty() {
            panels.push(Panel {
                title: l_title.into(),
                y_label: l_label.into(),
                series: vec![("angular momentum".into(), Z_COLOR, series(errors.angular_momentum))],
                scientific: true,
            });
        }
        for (robot, energies) in world.robots.iter().zip(derived::robot_energies(trajectory, world)) {
            let part = |f: fn(&(f64, f64)) -> f64| series(energies.iter().map(f).collect());
            panels.push(Panel {
                title: format!("{}: kinetic, potential (zero at z = 0) and total energy of its links", robot.name),
                y_label: "energy (J)".into(),
                series: vec![
                    ("kinetic".into(), X_COLOR, part(|e| e.0)),
                    ("potential".into(), Y_COLOR, part(|e| e.1)),
                    ("total".into(), Z_COLOR, part(|e| e.0 + e.1)),
                ],
                scientific: false,
            });
        }
    }
    for &b in chosen {
        let name = &trajectory.bodies[b];
        let omega: Vec<[f64; 3]> =
            trajectory.frames.iter().map(|f| derived::omega_user(&f.states[b]).to_array()).collect();
        let position: Vec<[f64; 3]> = trajectory.frames.iter().map(|f| f.states[b].position.to_array()).collect();
        let xyz = |values: &[[f64; 3]], prefix: &str| {
            ["x", "y", "z"]
                .iter()
                .zip([X_COLOR, Y_COLOR, Z_COLOR])
                .enumerate()
                .map(|(k, (axis, color))| {
                    (format!("{prefix}{axis}"), color, series(values.iter().map(|v| v[k]).collect()))
                })
                .collect()
        };
        // a robot link's row holds its link frame: its axes and its origin
        let link = match world {
            Some((world, _)) => world.robots.iter().any(|r| r.link_names().contains(name)),
            None => false,
        };
        let (axes, omega_label, place) = if link {
            ("link axes", "ω_link (rad/s)", "position of the link frame's origin")
        } else if world.is_none() && name.contains('/') {
            ("body axes (a robot link: link axes)", "ω_body (rad/s)", "position (a robot link: its frame's origin)")
        } else {
            ("body axes", "ω_body (rad/s)", "position of the centre of mass")
        };
        panels.push(Panel {
            title: format!("{name}: angular velocity in {axes}"),
            y_label: omega_label.into(),
            series: xyz(&omega, "ω_"),
            scientific: false,
        });
        panels.push(Panel {
            title: format!("{name}: {place}, world frame"),
            y_label: "position (m)".into(),
            series: xyz(&position, ""),
            scientific: false,
        });
    }
    Ok(panels)
}

/// A note for energy titles when a robot is driven (torques, damping or PD gains): its energy is not
/// conserved, and the change is their work, not an integration error. Empty otherwise.
pub fn driven_note(world: &World) -> &'static str {
    let driven = world.robots.iter().any(|r| {
        let c = &r.control;
        c.tau.iter().chain(&c.damping).chain(&c.kp).chain(&c.kd).any(|x| *x != 0.0)
    });
    if driven {
        " (robots under control or damping: the change includes their work)"
    } else {
        ""
    }
}

/// Draws the figure and returns the file's bytes.
pub fn render(
    trajectory: &Trajectory,
    world: Option<(&World, &str)>,
    path: &Path,
    chosen: &[usize],
    format: ImageFormat,
) -> Result<Vec<u8>, String> {
    register_font()?;
    let panels = panels(trajectory, world, path, chosen)?;
    let height = PANEL_HEIGHT * panels.len().max(1) as u32 + 40;
    let mut caption = format!("tumble: {}", path.display());
    if world.is_none() {
        caption.push_str(" (energy and angular momentum need --scene)");
    }
    if trajectory.truncated.is_some() {
        caption.push_str(" (cut short)");
    }
    match format {
        ImageFormat::Svg => {
            let mut text = String::new();
            {
                let root = SVGBackend::with_string(&mut text, (WIDTH, height)).into_drawing_area();
                draw(&root, &caption, &panels)?;
            }
            Ok(text.into_bytes())
        }
        ImageFormat::Png => {
            let mut pixels = vec![0u8; (WIDTH * height * 3) as usize];
            {
                let root = BitMapBackend::with_buffer(&mut pixels, (WIDTH, height)).into_drawing_area();
                draw(&root, &caption, &panels)?;
            }
            let mut png = Vec::new();
            use image::ImageEncoder;
            image::codecs::png::PngEncoder::new(&mut png)
                .write_image(&pixels, WIDTH, height, image::ColorType::Rgb8)
                .map_err(|e| format!("cannot encode the PNG: {e}"))?;
            Ok(png)
        }
    }
}

fn register_font() -> Result<(), String> {
    static REGISTERED: std::sync::OnceLock<bool> = std::sync::OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| plotters::style::register_font("sans-serif", FontStyle::Normal, FONT).is_ok());
    if ok {
        Ok(())
    } else {
        Err("the plot font could not be loaded".into())
    }
}

fn draw<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, caption: &str, panels: &[Panel]) -> Result<(), String> {
    let fail = |e: &dyn std::fmt::Display| format!("cannot draw the plot: {e}");
    root.fill(&WHITE).map_err(|e| fail(&e))?;
    let (top, body) = root.split_vertically(40);
    top.draw(&Text::new(caption.to_string(), (20, 12), ("sans-serif", 18).into_font())).map_err(|e| fail(&e))?;
    if panels.is_empty() {
        return Ok(());
    }
    let areas = body.split_evenly((panels.len(), 1));
    for (area, panel) in areas.iter().zip(panels) {
        draw_panel(area, panel).map_err(|e| fail(&e))?;
    }
    root.present().map_err(|e| fail(&e))
}

fn draw_panel<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, panel: &Panel) -> Result<(), String> {
    let all = || panel.series.iter().flat_map(|(_, _, s)| s.iter());
    let (t0, t1) = bounds(all().map(|p| p.0));
    let (y0, y1) = bounds(all().map(|p| p.1));
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, ("sans-serif", 16))
        .margin_left(10)
        .margin_right(20)
        .margin_bottom(6)
        .x_label_area_size(34)
        .y_label_area_size(95)
        .build_cartesian_2d(t0..t1, y0..y1)
        .map_err(|e| e.to_string())?;
    let (scientific, span) = (panel.scientific, y1 - y0);
    // enough decimals to tell ticks a fifth of the range apart
    let decimals = (1.0 - (span / 5.0).log10().floor()).clamp(0.0, 12.0) as usize;
    let y_format = move |v: &f64| {
        if v.abs() < span * 1e-9 {
            "0".to_string()
        } else if scientific {
            format!("{v:.2e}")
        } else {
            format!("{v:.decimals$}")
        }
    };
    chart
        .configure_mesh()
        .x_desc("time (s)")
        .y_desc(panel.y_label.as_str())
        .y_label_formatter(&y_format)
        .label_style(("sans-serif", 13))
        .axis_desc_style(("sans-serif", 14))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(|e| e.to_string())?;
    for (name, color, points) in &panel.series {
        let color = *color;
        chart
            .draw_series(LineSeries::new(points.iter().copied(), color.stroke_width(2)))
            .map_err(|e| e.to_string())?
            .label(name.as_str())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2)));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .margin(8)
        .legend_area_size(26)
        .label_font(("sans-serif", 13))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.4))
        .draw()
        .map_err(|e| e.to_string())?;
    Ok(())
}

/// A number to 7 significant digits, for titles: `57.50033`, `1.234568e-9`.
pub fn short(x: f64) -> String {
    let rounded: f64 = format!("{x:.6e}").parse().unwrap_or(x);
    if rounded == 0.0 || (1e-3..1e7).contains(&rounded.abs()) {
        format!("{rounded}")
    } else {
        format!("{rounded:e}")
    }
}

/// The range of finite values, widened when it is empty or a single value.
fn bounds(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) =
        values.filter(|v| v.is_finite()).fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| (lo.min(v), hi.max(v)));
    if lo > hi {
        // no finite value at all
        return (0.0, 1.0);
    }
    // keep the range and its padding finite, whatever the values
    let limit = f64::MAX / 8.0;
    (lo, hi) = (lo.clamp(-limit, limit), hi.clamp(-limit, limit));
    let span = hi - lo;
    let scale = lo.abs().max(hi.abs());
    if span <= scale * 1e-12 || span == 0.0 {
        // a constant: ±0.1 % of its value, or ±1 about zero
        let pad = if scale > 0.0 { scale * 1e-3 } else { 1.0 };
        lo -= pad;
        hi += pad;
    } else {
        lo -= span * 0.05;
        hi += span * 0.05;
    }
    (lo, hi)
}
