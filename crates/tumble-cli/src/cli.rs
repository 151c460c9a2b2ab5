//! The command line.
//!
//! The doc comments below are the `--help` text, written for the terminal: `[world]` there names the
//! scene's table and `<scene name>` a placeholder, not an item or a tag.
#![allow(rustdoc::broken_intra_doc_links, rustdoc::invalid_html_tags)]

use clap::{Args, Parser, Subcommand};
use std::path::PathBuf;
use tumble::Integrator;

/// tumble: rigid-body dynamics, simulated correctly and fast.
///
/// Exit status: 0 success; 2 bad input (scene, flags, files), nothing written; 3 the simulation
/// diverged (what was written so far stays valid); 4 an output could not be written; 130 interrupted.
#[derive(Debug, Parser)]
#[command(name = "tumble", version)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Simulate a scene (or the built-in demo) and write its trajectory and summary.
    Run(RunArgs),
    /// Parse and validate a scene file and print what was understood.
    Check(CheckArgs),
    /// Plot a trajectory: energy and angular-momentum errors, body-frame angular velocity, position.
    Plot(PlotArgs),
    /// Write a 3D replay of a trajectory: one self-contained HTML file that works offline.
    View(ViewArgs),
    /// Mass properties of the solid a mesh (.obj, .stl) bounds, as JSON.
    Mass(MassArgs),
    /// Print the joint layout of a URDF robot (joint order, coordinates, mass).
    Model(ModelArgs),
    /// Mass matrix, bias forces, forward and inverse dynamics of a URDF robot for states read from
    /// JSON Lines; or, with --bench, the time per call of RNEA, CRBA and ABA.
    Dynamics(DynamicsArgs),
}

/// The robot of `tumble model` and `tumble dynamics`.
#[derive(Debug, Args)]
pub struct RobotArgs {
    /// URDF file, or an MJCF (MuJoCo) file ending in `.xml`.
    pub urdf: PathBuf,

    /// MJCF only: read joints with `frictionloss` as if it were zero (with a warning each), as MuJoCo's
    /// `<flag frictionloss="disable">`.
    #[arg(long)]
    pub drop_frictionloss: bool,

    /// Give the root link a floating base: q = [x, y, z, qw, qx, qy, qz, ...], v = [linear velocity,
    /// angular velocity, ...], both of the base in the base frame.
    #[arg(long)]
    pub floating: bool,

    /// Order of a link's children in the depth-first joint numbering: `file` (as the joints appear in
    /// the file) or `name` (sorted by joint name, which gives Pinocchio's numbering).
    #[arg(long, value_name = "ORDER", default_value = "file", value_parser = ["file", "name"])]
    pub joint_order: String,

    /// Replace a link inertia that is not physical (a negative principal moment, the triangle
    /// inequality violated, inertia without mass) by the nearest physical one, with one warning per
    /// link; without it such a link is an error.
    #[arg(long)]
    pub balance_inertia: bool,

    /// A movable joint whose subtree has no mass: `error`, or `fuse` (held at q = 0 as a fixed joint,
    /// with one warning per joint).
    #[arg(long, value_name = "RULE", default_value = "error", value_parser = ["error", "fuse"])]
    pub massless: String,

    /// Joints held fixed, the model reduced as a scene's `lock` does: `NAME` (held at 0) or
    /// `NAME=VALUE` (rad or m), comma-separated or repeated. `q`, `v` and every output then follow
    /// the reduced layout; a joint that moves no mass is allowed when it is locked.
    #[arg(long, value_name = "JOINT[=VALUE]", value_delimiter = ',')]
    pub lock: Vec<String>,
}

/// `tumble model`.
#[derive(Debug, Args)]
pub struct ModelArgs {
    #[command(flatten)]
    pub robot: RobotArgs,

    /// Print JSON: {"name", "nq", "nv", "total_mass", "joints": [{"name", "type", "parent", "child",
    /// "q_index", "v_index", "nq", "nv"}]}.
    #[arg(long)]
    pub json: bool,
}

/// `tumble dynamics`.
#[derive(Debug, Args)]
pub struct DynamicsArgs {
    #[command(flatten)]
    pub robot: RobotArgs,

    /// States, one JSON object per line: {"q": [..], "v": [..], "tau": [..]?, "a": [..]?}.
    #[arg(long, value_name = "IN.jsonl", required_unless_present = "bench")]
    pub input: Option<PathBuf>,

    /// Results, one JSON object per input line: "mass_matrix", "bias", and "qdd" (when tau is given)
    /// and "tau" (when a is given).
    #[arg(long, value_name = "OUT.jsonl", required_unless_present = "bench")]
    pub out: Option<PathBuf>,

    /// Gravity in the world frame, m/s² [default: 0 0 -9.81].
    #[arg(long, num_args = 3, value_names = ["GX", "GY", "GZ"], allow_negative_numbers = true)]
    pub gravity: Option<Vec<f64>>,

    /// Time RNEA, CRBA and ABA on random states instead and print
    /// {"nv", "rnea_us", "crba_us", "aba_us"}: the median time per call in microseconds.
    #[arg(long, conflicts_with_all = ["input", "out"])]
    pub bench: bool,

    /// Number of random states timed by --bench (each timed over a batch of calls).
    #[arg(long, value_name = "N", default_value_t = 2000, requires = "bench")]
    pub bench_states: usize,
}

/// `tumble run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// Scene file (.toml or .json). Without it, the built-in demo: a body spun near its intermediate
    /// axis, flipping over and over, beside one spun about its largest axis, above a floor on which
    /// four thrown bodies land.
    pub scene: Option<PathBuf>,

    /// Simulated time in seconds (overrides [world] duration).
    #[arg(long, value_name = "T", allow_hyphen_values = true)]
    pub duration: Option<f64>,

    /// Time step in seconds (overrides [world] dt).
    #[arg(long, value_name = "S", allow_hyphen_values = true)]
    pub dt: Option<f64>,

    /// Integrator (overrides [world] integrator): euler, semi_implicit_euler, rk4, dopri5, splitting,
    /// splitting4.
    #[arg(long, value_name = "NAME", value_parser = parse_integrator)]
    pub integrator: Option<Integrator>,

    /// MJCF files (.xml) only: start from the file's <keyframe><key name="NAME"> (or an unnamed
    /// key's index): its qpos, qvel and ctrl. In a scene, `keyframe = "NAME"` under [[robot]].
    #[arg(long, value_name = "NAME")]
    pub keyframe: Option<String>,

    /// Write every K-th step to the trajectory (overrides [world] sample_every); the first and the
    /// last state are always written.
    #[arg(long, value_name = "K", allow_hyphen_values = true)]
    pub sample_every: Option<u64>,

    /// Threads of the collision detection (overrides [world] threads): 0 for one per core, 1 for
    /// none but the main thread. The results are the same bit for bit for any number.
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,

    /// Trajectory file: FILE.csv or FILE.jsonl [default: out/<scene name>.csv, out/demo.csv for the demo]
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,

    /// Also write the run summary as JSON to this file.
    #[arg(long, value_name = "FILE")]
    pub summary: Option<PathBuf>,

    /// Also write every active contact at each sample to FILE.jsonl: the two bodies, the point, the
    /// normal, the depth and the force on the second body (the step's impulse over dt).
    #[arg(long, value_name = "FILE.jsonl")]
    pub contacts: Option<PathBuf>,

    /// Stop after this many seconds of wall time (after a whole step; outputs are valid, exit 0).
    #[arg(long, value_name = "SECONDS", allow_hyphen_values = true)]
    pub max_wall_time: Option<f64>,

    /// Print only errors (no table, no progress bar).
    #[arg(long, short)]
    pub quiet: bool,

    /// Time every stage of the step (broad and narrow phase, robot contact rows, collisions,
    /// resting contact, integration, robot dynamics and bookkeeping): a table on standard error at
    /// the end, and a `profile` object in the summary (µs per step).
    #[arg(long)]
    pub profile: bool,

    /// Write the trajectory even when its estimated size exceeds 10 GB.
    #[arg(long)]
    pub force: bool,

    /// After the run, plot the trajectory to FILE.svg or FILE.png (as `tumble plot`).
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,

    /// After the run, write a 3D replay to FILE.html (as `tumble view`).
    #[arg(long, value_name = "FILE")]
    pub view: Option<PathBuf>,
}

/// `tumble plot`.
#[derive(Debug, Args)]
pub struct PlotArgs {
    /// Trajectory file (.csv or .jsonl, or the .partial file a stopped run left).
    pub trajectory: PathBuf,

    /// The scene that made the trajectory: its masses give the energy and angular momentum panels.
    #[arg(long, value_name = "SCENE")]
    pub scene: Option<PathBuf>,

    /// Image file: FILE.svg or FILE.png.
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,

    /// Bodies to plot, comma-separated [default: the first 4].
    #[arg(long, value_name = "NAMES")]
    pub bodies: Option<String>,
}

/// `tumble view`.
#[derive(Debug, Args)]
pub struct ViewArgs {
    /// Trajectory file (.csv or .jsonl, or the .partial file a stopped run left).
    pub trajectory: PathBuf,

    /// The scene that made the trajectory (shapes, fixed bodies, masses).
    #[arg(long, value_name = "SCENE")]
    pub scene: PathBuf,

    /// The replay: FILE.html.
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,

    /// Keep about this many frames (between it and twice it) [default: 1000, fewer for many bodies].
    #[arg(long, value_name = "N")]
    pub max_frames: Option<usize>,

    /// Draw the contacts of this file (from `tumble run --contacts`): the points and the forces of
    /// the sample nearest each frame, toggled by a checkbox.
    #[arg(long, value_name = "FILE.jsonl")]
    pub contacts: Option<PathBuf>,
}

/// `tumble check`.
#[derive(Debug, Args)]
pub struct CheckArgs {
    /// Scene file (.toml or .json).
    pub scene: PathBuf,
}

/// `tumble mass`.
#[derive(Debug, Args)]
pub struct MassArgs {
    /// Mesh file: .obj, or .stl (binary or ASCII). It must be closed and consistently oriented;
    /// coordinates are read as metres (see --scale).
    pub mesh: PathBuf,

    /// Density in kg/m³ [default: 1000, water].
    #[arg(long, value_name = "RHO", allow_hyphen_values = true)]
    pub density: Option<f64>,

    /// Multiply every coordinate by S to get metres (e.g. 0.001 for a mesh in millimetres).
    #[arg(long, value_name = "S", default_value_t = 1.0, allow_hyphen_values = true)]
    pub scale: f64,

    /// Refuse meshes with more triangles than N [default: 10000000].
    #[arg(long, value_name = "N")]
    pub max_triangles: Option<u64>,
}

fn parse_integrator(name: &str) -> Result<Integrator, String> {
    name.parse().map_err(|e: tumble::integrate::UnknownIntegrator| e.to_string())
}
