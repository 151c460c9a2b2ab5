//! `tumble view TRAJ --scene SCENE --out replay.html`, and `tumble run --view FILE`: a 3D replay in
//! one self-contained HTML file.
//!
//! The page is `assets/viewer.html` (a small WebGL renderer written for tumble, no library, no
//! network) with the replay's data put in place of its `/*TUMBLE_DATA*/null` marker, as one JSON
//! object:
//!
//! - `title`; `truncated` (a note when the file was cut short, or `null`); `decimation` (a note when
//!   frames were dropped, or `null`);
//! - `bodies`: `{name, color: [r, g, b] in 0..1, index, position, orientation, parts}` where `index`
//!   is the body's place in each frame (`null` for a fixed body, drawn at `position` (m, world) and
//!   `orientation` `[w, x, y, z]`), and `parts` are `{geometry, position, orientation}` in the user's
//!   body axes, `geometry` one of `sphere {radius}`, `box {half_extents}`, `capsule {radius,
//!   half_height}`, `cylinder {radius, half_height}`, `plane {}` (a floor grid), `mesh` or
//!   `convex_hull {vertices, triangles}` (a `convex` shape). A compound has one part per shape, at
//!   its pose. A body without a shape gets its inertia-equivalent box (`inertia_box: true`).
//! - Robots (`view/robots.rs`): every link is a body named `robot/link`, with `robot` its robot's
//!   name; the legend lists the links by robot. A moving link's `index` is its trajectory row, which
//!   holds the **link frame's** pose (origin and `world_from_link`, not the centre of mass); the
//!   links fixed to the world (a fixed base) are fixed bodies (`index: null`). A link's parts are its
//!   URDF geometry (`view/link_geometry.rs`: its `<visual>` elements if all can be drawn, else its
//!   `<collision>` elements, each at its `<origin>` in the link frame; meshes as `mesh` parts), else
//!   its inertia-equivalent box at its centre of mass and principal axes (`inertia_box: true`), else,
//!   for a link without mass (`tip`), a sphere at the frame's origin (`marker: true`); `drawn` says
//!   which (`"visual"`, `"collision"`, `"inertia_box"`, `"marker"`).
//! - `times` (s) and `frames`: per frame, `x, y, z, qw, qx, qy, qz` of every moving body in order
//!   (world frame, m; orientation `world_from_user`, for a robot link `world_from_link`);
//! - `energy`: `{label, values}`, the relative energy error per frame (or `null`) of the whole
//!   system: the moving bodies and the robots' links (kinetic plus gravitational potential, the
//!   energy of the run summary; see `tumble::trajectory::derived`). For a robot driven by PD control
//!   or damped, the change is the work of the controls and the damping, not an integration error.
//! - `contacts` (`view/contacts.rs`; `null` without `--contacts`): `{source, reference, reference_of,
//!   most, stride, frames}`, per frame the points and forces (`px, py, pz, fx, fy, fz` per contact, m
//!   and N, world frame) of the contacts file's sample nearest the frame's time (`null` for the frames
//!   left out when there are very many: only every `stride`-th frame is written), and the force (N)
//!   the page scales the arrows against (the robots' weight, else the moving bodies', else the
//!   largest).
//!
//! **Decimation.** At most about [`MAX_BODY_SAMPLES`] body-samples are kept (between that and twice
//! it, and never more than 2 × [`MAX_FRAMES`] frames): frames are dropped evenly (every `2^k`-th
//! frame of the file, and the last one; see `tumble::trajectory::ReadOptions`), and the replay
//! interpolates between the frames kept (positions linearly, orientations by normalised linear
//! interpolation). Numbers are written with `f32` precision (7 significant digits). The demo (30 s,
//! 6 moving bodies, 3001 samples) keeps 1501 frames and makes a file of about 540 kB.

use crate::cli::ViewArgs;
use crate::error::{Failure, Status};
use crate::plot::{read_trajectory, truncation_note, write_output};
use std::fmt::Write as _;
use std::path::Path;
use tumble::body::Shape;
use tumble::math::quat_to_wxyz;
use tumble::scene;
use tumble::trajectory::derived::{self, InvariantErrors};
use tumble::trajectory::Trajectory;
use tumble::{RigidBody, World};

mod contacts;
mod link_geometry;
mod robots;

/// The page, with its data marker.
const TEMPLATE: &str = include_str!("../assets/viewer.html");
/// Where the data goes in the page.
const DATA_MARKER: &str = "/*TUMBLE_DATA*/null";
/// Body-samples kept in a replay (frames × moving bodies), about.
pub const MAX_BODY_SAMPLES: usize = 100_000;
/// Frames kept in a replay, about (the bound for few bodies).
pub const MAX_FRAMES: usize = 1000;

/// Colours of moving bodies, in turn (sRGB, 0..1).
const PALETTE: [[f32; 3]; 8] = [
    [0.94, 0.55, 0.22],
    [0.30, 0.62, 0.90],
    [0.47, 0.78, 0.38],
    [0.86, 0.36, 0.44],
    [0.68, 0.52, 0.88],
    [0.95, 0.78, 0.30],
    [0.30, 0.78, 0.76],
    [0.80, 0.80, 0.82],
];
/// Colour of fixed bodies.
const FIXED_COLOR: [f32; 3] = [0.55, 0.58, 0.62];

/// `tumble view`.
pub fn view(args: &ViewArgs) -> Result<Status, Failure> {
    check_out(&args.out, "--out")?;
    let scene = scene::load(&args.scene).map_err(Failure::bad_input)?;
    let max_frames = frames_budget(&scene.world, args.max_frames);
    let trajectory = read_trajectory(&args.trajectory, max_frames, Failure::bad_input)?;
    if let Some(note) = truncation_note(&trajectory) {
        let _ = writeln_stderr(&format!("warning: {}: {note}", args.trajectory.display()));
    }
    let page = page(&trajectory, &scene.world, &scene.origin, &args.trajectory, args.contacts.as_deref())
        .map_err(Failure::bad_input)?;
    for warning in &page.warnings {
        let _ = writeln_stderr(&format!("warning: {warning}"));
    }
    write_output(&args.out, page.html.as_bytes())?;
    Ok(Status::Success)
}

fn writeln_stderr(text: &str) -> std::io::Result<()> {
    use std::io::Write;
    writeln!(std::io::stderr().lock(), "{text}")
}

/// A replay is written to `.html` or `.htm`; anything else is bad input, named after `flag`.
pub fn check_out(path: &Path, flag: &str) -> Result<(), Failure> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("html" | "htm") => Ok(()),
        _ => Err(Failure::bad_input(format!("{flag} {}: a replay is an HTML file; use FILE.html", path.display()))),
    }
}

/// The frames to keep for a scene (see the module doc), or `requested`.
pub fn frames_budget(world: &World, requested: Option<usize>) -> usize {
    let moving = (world.free_bodies().count() + world.robot_link_count()).max(1);
    requested.unwrap_or((MAX_BODY_SAMPLES / moving).clamp(2, MAX_FRAMES)).max(2)
}

/// A replay: the page, and the warnings to print (meshes not drawn, a contacts file cut short).
#[derive(Debug, Clone)]
pub struct Page {
    pub html: String,
    pub warnings: Vec<String>,
}

/// The page for a trajectory of the scene `world` (from `origin`), with the contacts file
/// `contacts` drawn over it if given; `path` names the trajectory in the title and messages.
pub fn page(
    trajectory: &Trajectory,
    world: &World,
    origin: &str,
    path: &Path,
    contacts: Option<&Path>,
) -> Result<Page, String> {
    let mut warnings = Vec::new();
    let data = data(trajectory, world, origin, path, contacts, &mut warnings)?;
    Ok(Page { html: TEMPLATE.replacen(DATA_MARKER, &data, 1), warnings })
}

/// The replay's data as JSON (the fields of the module doc); warnings are pushed to `warnings`.
fn data(
    trajectory: &Trajectory,
    world: &World,
    origin: &str,
    path: &Path,
    contacts: Option<&Path>,
    warnings: &mut Vec<String>,
) -> Result<String, String> {
    let name = path.display().to_string();
    let invariants = derived::invariants(trajectory, world, &name, origin).map_err(|e| e.to_string())?;
    let errors = InvariantErrors::of(&invariants);
    let mut out = String::with_capacity(64 + trajectory.frames.len() * trajectory.bodies.len() * 64);
    let (t0, t1) = trajectory.time_span();
    let what = match world.robots.len() {
        0 => format!("{} moving bodies", trajectory.bodies.len()),
        n => format!(
            "{} moving bodies, {n} robot{} ({} moving links)",
            world.free_bodies().count(),
            if n > 1 { "s" } else { "" },
            world.robot_link_count()
        ),
    };
    let title = format!("{name} · {origin} · {what} · t = {t0}–{t1} s");
    let _ = write!(out, "{{\"title\":{},", json_string(&title));
    let truncated = truncation_note(trajectory).map(|n| format!("the trajectory ends early: {n}"));
    let _ = write!(out, "\"truncated\":{},", truncated.as_deref().map_or("null".into(), json_string));
    let decimation = (trajectory.stride > 1).then(|| {
        format!(
            "{} of {} frames shown (one in {})",
            trajectory.frames.len(),
            trajectory.frames_in_file,
            trajectory.stride
        )
    });
    let _ = write!(out, "\"decimation\":{},", decimation.as_deref().map_or("null".into(), json_string));

    out.push_str("\"bodies\":[");
    let mut colour = 0;
    let mut first = true;
    for body in &world.bodies {
        let index = trajectory.bodies.iter().position(|n| n == &body.name);
        let Some(parts) = parts(body) else { continue };
        if !first {
            out.push(',');
        }
        first = false;
        let color = if body.fixed {
            FIXED_COLOR
        } else {
            colour += 1;
            PALETTE[(colour - 1) % PALETTE.len()]
        };
        let _ = write!(
            out,
            "{{\"name\":{},\"color\":{},\"index\":{},\"position\":{},\"orientation\":{},\"inertia_box\":{},\"parts\":[{parts}]}}",
            json_string(&body.name),
            numbers(&color.map(f64::from)),
            index.map_or("null".into(), |i| i.to_string()),
            numbers(&body.state.position.to_array()),
            numbers(&quat_to_wxyz(body.orientation_user())),
            body.shape.is_none(),
        );
    }
    for robot in &world.robots {
        colour += 1;
        let color = PALETTE[(colour - 1) % PALETTE.len()];
        warnings.extend(robots::push_bodies(&mut out, &mut first, robot, color, &trajectory.bodies));
    }
    out.push_str("],");

    out.push_str("\"times\":[");
    push_joined(&mut out, trajectory.frames.iter().map(|f| f.t));
    out.push_str("],\"frames\":[");
    for (k, frame) in trajectory.frames.iter().enumerate() {
        if k > 0 {
            out.push(',');
        }
        out.push('[');
        let values = frame.states.iter().flat_map(|s| {
            let q = quat_to_wxyz(s.orientation);
            [s.position.x, s.position.y, s.position.z, q[0], q[1], q[2], q[3]]
        });
        push_joined(&mut out, values);
        out.push(']');
    }
    out.push_str("],");
    let e0 = invariants.first().map_or(0.0, |i| i.energy);
    // the whole system's energy: with robots, say that their links count
    let what = if world.robots.is_empty() { "" } else { " of the bodies and robot links" };
    let label = if errors.energy_is_absolute {
        format!("energy error E − E₀ (J){what}, E₀ = 0")
    } else {
        format!("relative energy error (E − E₀)/|E₀|{what}, E₀ = {} J", crate::plot::short(e0))
    } + crate::plot::driven_note(world);
    let _ = write!(out, "\"energy\":{{\"label\":{},\"values\":[", json_string(&label));
    push_joined(&mut out, errors.energy.iter().copied());
    out.push_str("]},\"contacts\":");
    match contacts {
        None => out.push_str("null"),
        Some(file) => {
            let times: Vec<f64> = trajectory.frames.iter().map(|f| f.t).collect();
            let (overlay, cut_short) = contacts::read(file, &times, world)?;
            warnings.extend(cut_short);
            let _ = write!(
                out,
                "{{\"source\":{},\"reference\":{},\"reference_of\":{},\"most\":{},\"stride\":{},\"frames\":[",
                json_string(&file.display().to_string()),
                num(overlay.reference),
                json_string(overlay.reference_of),
                overlay.most,
                overlay.stride
            );
            for (k, frame) in overlay.frames.iter().enumerate() {
                out.push_str(if k > 0 { "," } else { "" });
                match frame {
                    Some(frame) => {
                        out.push('[');
                        push_joined(&mut out, frame.iter().copied());
                        out.push(']');
                    }
                    None => out.push_str("null"),
                }
            }
            out.push_str("]}");
        }
    }
    out.push('}');
    Ok(out)
}

/// Meshes with more triangles than this are drawn as their inertia-equivalent box.
const MAX_DRAWN_TRIANGLES: usize = 50_000;

/// The parts of a body (JSON objects, comma-separated), or `None` for a fixed body without a shape
/// (its mass properties are placeholders: nothing to draw).
fn parts(body: &RigidBody) -> Option<String> {
    let identity = "\"position\":[0,0,0],\"orientation\":[1,0,0,0]";
    if let Some(Shape::Compound(ref compound)) = body.shape {
        // each part at its pose in the body axes
        let parts: Option<Vec<String>> = compound
            .parts
            .iter()
            .map(|part| {
                geometry(&part.shape).map(|g| {
                    format!(
                        "{{\"geometry\":{g},\"position\":{},\"orientation\":{}}}",
                        numbers(&part.position.to_array()),
                        numbers(&quat_to_wxyz(part.orientation))
                    )
                })
            })
            .collect();
        if let Some(parts) = parts {
            return Some(parts.join(","));
        }
    }
    match body.shape.as_ref().and_then(geometry) {
        Some(geometry) => Some(format!("{{\"geometry\":{geometry},{identity}}}")),
        None if body.shape.is_none() && body.fixed => None,
        None => {
            let (half_extents, user_from_body) = derived::inertia_equivalent_box(&body.mass);
            Some(format!(
                "{{\"geometry\":{{\"type\":\"box\",\"half_extents\":{}}},\"position\":[0,0,0],\"orientation\":{}}}",
                numbers(&half_extents.to_array()),
                numbers(&quat_to_wxyz(user_from_body))
            ))
        }
    }
}

/// The `geometry` object of a shape about its own centre, or `None` when it is drawn otherwise (a
/// compound, part by part; a mesh too large for the page, as the inertia-equivalent box).
fn geometry(shape: &Shape) -> Option<String> {
    Some(match *shape {
        Shape::Sphere { radius } => format!("{{\"type\":\"sphere\",\"radius\":{}}}", num(radius)),
        Shape::Box { half_extents } => {
            format!("{{\"type\":\"box\",\"half_extents\":{}}}", numbers(&half_extents.to_array()))
        }
        Shape::Capsule { radius, half_height } => {
            format!("{{\"type\":\"capsule\",\"radius\":{},\"half_height\":{}}}", num(radius), num(half_height))
        }
        Shape::Cylinder { radius, half_height } => {
            format!("{{\"type\":\"cylinder\",\"radius\":{},\"half_height\":{}}}", num(radius), num(half_height))
        }
        Shape::Plane => "{\"type\":\"plane\"}".to_string(),
        // a mesh is drawn as its triangles (file axes = body axes, about the centre of mass) while it
        // stays small enough for the page, whatever it collides as (hull, convex pieces, triangles)
        Shape::Mesh(ref mesh) if mesh.mesh.triangles().len() <= MAX_DRAWN_TRIANGLES => {
            triangles("mesh", mesh.mesh.vertices(), mesh.mesh.triangles())
        }
        Shape::Convex(ref convex) => triangles("convex_hull", convex.hull.vertices(), convex.hull.triangles()),
        Shape::Mesh(_) | Shape::Compound(_) => return None,
    })
}

/// A `mesh` or `convex_hull` geometry object: vertices (m) and triangles (corner indices).
fn triangles(kind: &str, vertices: &[tumble::math::DVec3], triangles: &[[u32; 3]]) -> String {
    let mut g = format!("{{\"type\":\"{kind}\",\"vertices\":[");
    for (i, v) in vertices.iter().enumerate() {
        g.push_str(if i > 0 { "," } else { "" });
        g.push_str(&numbers(&v.to_array()));
    }
    g.push_str("],\"triangles\":[");
    for (i, t) in triangles.iter().enumerate() {
        let _ = write!(g, "{}[{},{},{}]", if i > 0 { "," } else { "" }, t[0], t[1], t[2]);
    }
    g.push_str("]}");
    g
}

/// A number with `f32` precision, as JSON (non-finite values, which a trajectory never holds, as 0).
fn num(x: f64) -> String {
    let x = x as f32;
    if x.is_finite() {
        let mut buffer = ryu::Buffer::new();
        let text = buffer.format_finite(x);
        text.strip_suffix(".0").unwrap_or(text).to_string()
    } else {
        "0".to_string()
    }
}

fn numbers(values: &[f64]) -> String {
    let mut out = String::from("[");
    push_joined(&mut out, values.iter().copied());
    out.push(']');
    out
}

fn push_joined(out: &mut String, values: impl Iterator<Item = f64>) {
    for (i, x) in values.enumerate() {
        if i > 0 {
            out.push(',');
        }
        out.push_str(&num(x));
    }
}

/// A JSON string literal that is also safe inside a `<script>` element (`<` escaped).
fn json_string(text: &str) -> String {
    serde_json::to_string(text).unwrap_or_else(|_| "\"\"".into()).replace('<', "\\u003c")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_short_and_never_non_finite() {
        assert_eq!(num(1.0), "1");
        assert_eq!(num(0.1), "0.1");
        assert_eq!(num(f64::NAN), "0");
        assert_eq!(num(-2.5e-8), "-2.5e-8");
    }

    #[test]
    fn a_body_name_cannot_close_the_script() {
        assert_eq!(json_string("a</script><b>"), "\"a\\u003c/script>\\u003cb>\"");
    }

    #[test]
    fn the_template_has_one_data_marker() {
        assert_eq!(TEMPLATE.matches(DATA_MARKER).count(), 1);
    }
}
