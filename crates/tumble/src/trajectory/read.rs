//! Reading a trajectory back: CSV or JSON Lines, as [`TrajectoryWriter`](super::TrajectoryWriter)
//! writes them, into [`Trajectory`] frames, with precise errors.
//!
//! - **Frames.** Rows (CSV) are grouped into frames by time: consecutive rows with the same `t` and
//!   distinct bodies form one frame. The bodies of the first frame, in their order, are the
//!   trajectory's bodies; every later frame must have exactly those bodies (in any order).
//! - **Columns.** The CSV header must name the 15 columns of the contract; they may come in any
//!   order, and other columns are ignored. A missing column is [`ReadError::MissingColumns`], naming
//!   every missing one. JSON Lines objects must have `t` and `bodies`, and each body `name`,
//!   `position`, `orientation`, `velocity` and `angular_velocity` ([`ReadError::MissingField`]).
//! - **Truncation.** A run that stopped early (killed, disk full) leaves a file whose last line may
//!   be cut, or whose last frame lacks some bodies. A last line with no line break is never trusted
//!   (a number cut short may still parse), and an incomplete last frame is dropped: both are
//!   reported in [`Trajectory::truncated`], not as errors, so that what is there can be shown.
//! - **Against a scene.** [`Trajectory::check_bodies`] compares the bodies with a scene's moving
//!   bodies, naming the unknown and the missing ones.
//! - **Decimation.** [`ReadOptions::max_frames`] bounds the frames kept in memory: when the kept
//!   frames reach twice the bound, every other one is dropped and the stride doubles, so the
//!   frames kept are evenly spaced (every `2^k`-th frame of the file) and the last frame of the file
//!   is always kept.
//!
//! Units and frames are those of the files: world frame, SI units, orientation `[w, x, y, z]` of the
//! user's body axes (`world_from_user`), angular velocity in the world frame.

use super::writer::CSV_HEADER;
use super::Format;
use crate::math::{quat_from_wxyz, DQuat, DVec3};
use crate::world::World;
use std::collections::HashMap;
use std::io::{BufRead, BufReader, Read};
use std::path::Path;

/// The state of one body at one sample, as written in a trajectory file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodySample {
    /// Position of the centre of mass, world frame (m).
    pub position: DVec3,
    /// Orientation `world_from_user` of the user's body axes (unit quaternion, normalised on reading).
    pub orientation: DQuat,
    /// Velocity of the centre of mass, world frame (m/s).
    pub velocity: DVec3,
    /// Angular velocity, world frame (rad/s).
    pub angular_velocity: DVec3,
}

/// Every body's state at one time.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    /// Time (s).
    pub t: f64,
    /// `states[i]` is the state of `Trajectory::bodies[i]`.
    pub states: Vec<BodySample>,
}

/// What was dropped at the end of a file that was cut short.
#[derive(Debug, Clone, PartialEq)]
pub struct Truncation {
    /// The 1-based line where the dropped part starts.
    pub line: usize,
    /// What was dropped, for messages: `a line with no line break`, `a frame with 1 of 2 bodies`.
    pub what: String,
}

/// A trajectory read back from a file.
#[derive(Debug, Clone, PartialEq)]
pub struct Trajectory {
    /// The bodies' names, in the order of the first frame.
    pub bodies: Vec<String>,
    /// The frames kept, in time order.
    pub frames: Vec<Frame>,
    /// Frames in the file (complete ones), before decimation.
    pub frames_in_file: usize,
    /// Every `stride`-th frame of the file was kept (and the last one); 1 when nothing was dropped.
    pub stride: usize,
    /// Set when the end of the file was cut short and dropped.
    pub truncated: Option<Truncation>,
}

/// How to read a trajectory.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ReadOptions {
    /// Keep at most about this many frames (between this and twice it; see the module doc). `None`: all.
    pub max_frames: Option<usize>,
}

/// Why a trajectory could not be read.
#[derive(Debug, thiserror::Error)]
pub enum ReadError {
    /// The file could not be opened or read.
    #[error("{path}: cannot read: {source}")]
    Io {
        path: String,
        #[source]
        source: std::io::Error,
    },
    /// The format could not be told from the file name.
    #[error("{path}: cannot tell the trajectory format from the file name (use .csv or .jsonl)")]
    UnknownFormat { path: String },
    /// The file has no complete sample.
    #[error("{path}: no complete sample{}", .truncated.as_ref().map(|t| format!(" (line {} is {})", t.line, t.what)).unwrap_or_default())]
    NoSamples { path: String, truncated: Option<Truncation> },
    /// The CSV header lacks columns of the contract.
    #[error("{path}:1: missing column{} {}; the header must name {CSV_HEADER}", if .missing.len() > 1 { "s" } else { "" }, .missing.iter().map(|c| format!("`{c}`")).collect::<Vec<_>>().join(", "))]
    MissingColumns { path: String, missing: Vec<String> },
    /// A JSON Lines object lacks a field.
    #[error("{path}:{line}: missing field `{field}`")]
    MissingField { path: String, line: usize, field: String },
    /// A value could not be read.
    #[error("{path}:{line}: {field}: {problem} (got {got:?})")]
    BadValue { path: String, line: usize, field: String, problem: String, got: String },
    /// A row has fewer fields than the header.
    #[error("{path}:{line}: {got} fields, the header has {expected}")]
    WrongFieldCount { path: String, line: usize, expected: usize, got: usize },
    /// A frame (not the last) lacks a body of the first frame, or has one the first frame lacks.
    #[error("{path}:{line}: the frame at t = {t} s {problem}")]
    InconsistentFrame { path: String, line: usize, t: f64, problem: String },
    /// Time goes backwards.
    #[error("{path}:{line}: time goes backwards: t = {t} s after {previous} s")]
    TimeBackwards { path: String, line: usize, t: f64, previous: f64 },
    /// The trajectory's bodies are not the scene's moving bodies.
    #[error("{}", mismatch_text(.trajectory, .scene, .unknown, .missing, .notes))]
    BodiesMismatch {
        /// The trajectory file.
        trajectory: String,
        /// The scene.
        scene: String,
        /// Bodies of the trajectory that are not moving bodies of the scene.
        unknown: Vec<String>,
        /// Moving bodies of the scene that the trajectory lacks.
        missing: Vec<String>,
        /// What the unknown names `robot/link` miss: a robot the scene lacks, a link its robot lacks
        /// or a link fixed to the world (never written).
        notes: Vec<String>,
    },
}

fn quoted(names: &[String]) -> String {
    const SHOWN: usize = 10;
    let mut text = names.iter().take(SHOWN).map(|n| format!("`{n}`")).collect::<Vec<_>>().join(", ");
    if names.len() > SHOWN {
        text.push_str(&format!(" and {} more", names.len() - SHOWN));
    }
    text
}

fn mismatch_text(trajectory: &str, scene: &str, unknown: &[String], missing: &[String], notes: &[String]) -> String {
    let mut parts = Vec::new();
    if !unknown.is_empty() {
        parts.push(format!("has bodies that are not moving bodies of the scene {scene}: {}", quoted(unknown)));
    }
    if !missing.is_empty() {
        parts.push(format!("lacks moving bodies of the scene {scene}: {}", quoted(missing)));
    }
    let mut text = format!("{trajectory}: the trajectory does not match the scene: it {}", parts.join("; and it "));
    for note in notes {
        text.push_str("; ");
        text.push_str(note);
    }
    text
}

/// Notes on the unknown names that look like robot links (`robot/link`), one per robot named: the
/// scene has no such robot, or the robot has no such moving link (with the links it has).
fn robot_notes(world: &World, unknown: &[String]) -> Vec<String> {
    let mut robots: Vec<(&str, Vec<&str>)> = Vec::new();
    for (robot, link) in unknown.iter().filter_map(|n| n.split_once('/')) {
        match robots.iter_mut().find(|(r, _)| *r == robot) {
            Some((_, links)) => links.push(link),
            None => robots.push((robot, vec![link])),
        }
    }
    let names = |items: &[&str]| quoted(&items.iter().map(|s| s.to_string()).collect::<Vec<_>>());
    robots
        .into_iter()
        .map(|(robot, links)| match world.robots.iter().find(|r| r.name == robot) {
            None if world.robots.is_empty() => format!("the scene has no robot `{robot}`"),
            None => {
                let known: Vec<&str> = world.robots.iter().map(|r| r.name.as_str()).collect();
                format!("the scene has no robot `{robot}` (its robots: {})", names(&known))
            }
            Some(r) => {
                let fixed: Vec<&str> =
                    r.model.frames.iter().filter(|f| f.body.is_none()).map(|f| f.name.as_str()).collect();
                let (held, absent): (Vec<&str>, Vec<&str>) = links.iter().partition(|l| fixed.contains(l));
                let moving: Vec<&str> =
                    r.link_names().iter().map(|n| n.strip_prefix(&format!("{robot}/")).unwrap_or(n)).collect();
                let mut parts = Vec::new();
                if !absent.is_empty() {
                    parts.push(format!("robot `{robot}` has no moving link {}", names(&absent)));
                }
                if !held.is_empty() {
                    parts.push(format!(
                        "{} of robot `{robot}` {} fixed to the world (never written)",
                        names(&held),
                        if held.len() > 1 { "are" } else { "is" }
                    ));
                }
                format!("{} (its moving links: {})", parts.join(", and "), names(&moving))
            }
        })
        .collect()
}

/// The trajectory format of a path: `.csv` or `.jsonl`, looking through a `.partial` suffix (the file
/// a run that was killed leaves).
pub fn format_of(path: &Path) -> Option<Format> {
    let name = path.file_name()?.to_str()?;
    let name = name.strip_suffix(".partial").unwrap_or(name);
    Format::from_path(Path::new(name))
}

/// Reads a trajectory file (format from the extension, see [`format_of`]).
pub fn read(path: &Path, options: ReadOptions) -> Result<Trajectory, ReadError> {
    let origin = path.display().to_string();
    let format = format_of(path).ok_or_else(|| ReadError::UnknownFormat { path: origin.clone() })?;
    let file = std::fs::File::open(path).map_err(|source| ReadError::Io { path: origin.clone(), source })?;
    read_from(file, format, &origin, options)
}

/// Reads a trajectory from any reader; `origin` names it in messages.
pub fn read_from(
    source: impl Read,
    format: Format,
    origin: &str,
    options: ReadOptions,
) -> Result<Trajectory, ReadError> {
    let mut reader = BufReader::new(source);
    let mut builder = Builder::new(origin, options);
    let mut line = String::new();
    let mut number = 0;
    let mut columns: Option<Columns> = None;
    loop {
        line.clear();
        let read = reader.read_line(&mut line).map_err(|source| ReadError::Io { path: origin.into(), source })?;
        if read == 0 {
            break;
        }
        number += 1;
        if !line.ends_with('\n') {
            // a run cut short: the last line may end inside a number
            builder.truncated = Some(Truncation { line: number, what: "a line with no line break".into() });
            break;
        }
        let text = line.trim_end_matches(['\n', '\r']);
        match format {
            Format::Csv => match &columns {
                None => columns = Some(Columns::from_header(text, origin)?),
                Some(_) if text.is_empty() => {}
                Some(c) => {
                    let (t, name, sample) = c.row(text, origin, number)?;
                    builder.push(t, name, sample, number)?;
                }
            },
            Format::JsonLines if text.trim().is_empty() => {}
            Format::JsonLines => {
                for (t, name, sample) in json_line(text, origin, number)? {
                    builder.push(t, name, sample, number)?;
                }
                builder.end_json_line()?;
            }
        }
    }
    builder.finish()
}

/// Accumulates rows into frames.
struct Builder<'a> {
    origin: &'a str,
    options: ReadOptions,
    bodies: Vec<String>,
    index: HashMap<String, usize>,
    /// The frame being filled: time, first line, states by body index.
    current: Option<(f64, usize, Vec<Option<BodySample>>)>,
    frames: Vec<Frame>,
    /// The last complete frame of the file (kept whatever the decimation).
    last: Option<Frame>,
    frames_in_file: usize,
    stride: usize,
    truncated: Option<Truncation>,
}

impl<'a> Builder<'a> {
    fn new(origin: &'a str, options: ReadOptions) -> Self {
        Self {
            origin,
            options,
            bodies: Vec::new(),
            index: HashMap::new(),
            current: None,
            frames: Vec::new(),
            last: None,
            frames_in_file: 0,
            stride: 1,
            truncated: None,
        }
    }

    fn push(&mut self, t: f64, name: String, sample: BodySample, line: usize) -> Result<(), ReadError> {
        let first_frame = self.frames_in_file == 0;
        let starts_new = match &self.current {
            None => true,
            Some((ct, _, states)) => {
                *ct != t || self.index.get(&name).is_some_and(|&i| states.get(i).is_some_and(Option::is_some))
            }
        };
        if starts_new {
            if let Some((ct, _, _)) = &self.current {
                if t < *ct {
                    return Err(ReadError::TimeBackwards { path: self.origin.into(), line, t, previous: *ct });
                }
            }
            self.close_frame()?;
            self.current = Some((t, line, vec![None; self.bodies.len()]));
        }
        let first_frame = first_frame && self.frames_in_file == 0;
        let i = match self.index.get(&name) {
            Some(&i) => i,
            None if first_frame => {
                self.index.insert(name.clone(), self.bodies.len());
                self.bodies.push(name);
                if let Some((_, _, states)) = &mut self.current {
                    states.push(None);
                }
                self.bodies.len() - 1
            }
            None => {
                return Err(ReadError::InconsistentFrame {
                    path: self.origin.into(),
                    line,
                    t,
                    problem: format!("has body `{name}`, which the first frame does not have"),
                })
            }
        };
        if let Some((_, _, states)) = &mut self.current {
            states[i] = Some(sample);
        }
        Ok(())
    }

    /// JSON Lines: one line is one frame.
    fn end_json_line(&mut self) -> Result<(), ReadError> {
        self.close_frame()
    }

    /// Closes the current frame: it must have every body.
    fn close_frame(&mut self) -> Result<(), ReadError> {
        let Some((t, line, states)) = self.current.take() else { return Ok(()) };
        if let Some(i) = states.iter().position(Option::is_none) {
            let present = states.iter().filter(|s| s.is_some()).count();
            // the caller decides at the end whether this incomplete frame is the last one
            return Err(ReadError::InconsistentFrame {
                path: self.origin.into(),
                line,
                t,
                problem: format!("lacks body `{}` (it has {present} of {} bodies)", self.bodies[i], self.bodies.len()),
            });
        }
        let frame = Frame { t, states: states.into_iter().flatten().collect() };
        self.frames_in_file += 1;
        if (self.frames_in_file - 1).is_multiple_of(self.stride) {
            if let Some(max) = self.options.max_frames {
                if self.frames.len() >= 2 * max.max(1) {
                    // keep every other frame: the kept ones stay evenly spaced
                    let mut k = 0;
                    self.frames.retain(|_| {
                        k += 1;
                        k % 2 == 1
                    });
                    self.stride *= 2;
                }
            }
            if (self.frames_in_file - 1).is_multiple_of(self.stride) {
                self.frames.push(frame.clone());
            }
        }
        self.last = Some(frame);
        Ok(())
    }

    fn finish(mut self) -> Result<Trajectory, ReadError> {
        if let Some((_, line, states)) = &self.current {
            let present = states.iter().filter(|s| s.is_some()).count();
            if present < states.len() {
                // the last frame of a run cut short: drop it, say so
                let what = format!("a frame with {present} of {} bodies", states.len());
                self.truncated.get_or_insert(Truncation { line: *line, what });
                self.current = None;
            }
        }
        self.close_frame()?;
        let Some(last) = self.last.take() else {
            return Err(ReadError::NoSamples { path: self.origin.into(), truncated: self.truncated });
        };
        if self.frames.last().is_none_or(|f| f.t != last.t) {
            self.frames.push(last);
        }
        Ok(Trajectory {
            bodies: self.bodies,
            frames: self.frames,
            frames_in_file: self.frames_in_file,
            stride: self.stride,
            truncated: self.truncated,
        })
    }
}

/// The CSV columns of the contract, by position in the file's header.
struct Columns {
    /// Index of `t, body, x, y, z, qw, qx, qy, qz, vx, vy, vz, wx, wy, wz` in a row.
    at: [usize; 15],
    /// Fields in the header.
    count: usize,
    names: Vec<String>,
}

impl Columns {
    fn from_header(header: &str, origin: &str) -> Result<Columns, ReadError> {
        let fields = split_csv(header.strip_prefix('\u{feff}').unwrap_or(header));
        let names: Vec<String> = fields.iter().map(|f| f.trim().to_string()).collect();
        let wanted: Vec<&str> = CSV_HEADER.split(',').collect();
        let mut at = [0; 15];
        let mut missing = Vec::new();
        for (k, want) in wanted.iter().enumerate() {
            match names.iter().position(|n| n == want) {
                Some(i) => at[k] = i,
                None => missing.push(want.to_string()),
            }
        }
        if !missing.is_empty() {
            return Err(ReadError::MissingColumns { path: origin.into(), missing });
        }
        Ok(Columns { at, count: names.len(), names })
    }

    fn row(&self, text: &str, origin: &str, line: usize) -> Result<(f64, String, BodySample), ReadError> {
        let fields = split_csv(text);
        if fields.len() < self.count {
            return Err(ReadError::WrongFieldCount {
                path: origin.into(),
                line,
                expected: self.count,
                got: fields.len(),
            });
        }
        let mut values = [0.0; 15];
        for k in (0..15).filter(|&k| k != 1) {
            let i = self.at[k];
            values[k] = number(&fields[i], &self.names[i], origin, line)?;
        }
        let name = fields[self.at[1]].clone();
        if name.is_empty() {
            return Err(bad(origin, line, "body", "empty body name", ""));
        }
        let v = |k: usize| DVec3::new(values[k], values[k + 1], values[k + 2]);
        let orientation = orientation([values[5], values[6], values[7], values[8]], origin, line)?;
        let sample = BodySample { position: v(2), orientation, velocity: v(9), angular_velocity: v(12) };
        Ok((values[0], name, sample))
    }
}

fn bad(origin: &str, line: usize, field: &str, problem: &str, got: &str) -> ReadError {
    ReadError::BadValue {
        path: origin.into(),
        line,
        field: field.into(),
        problem: problem.into(),
        got: got.chars().take(40).collect(),
    }
}

fn number(text: &str, field: &str, origin: &str, line: usize) -> Result<f64, ReadError> {
    match text.trim().parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        Ok(_) => Err(bad(origin, line, field, "not finite", text)),
        Err(_) => Err(bad(origin, line, field, "not a number", text)),
    }
}

/// A unit quaternion from `[w, x, y, z]`; a zero one is an error.
fn orientation(wxyz: [f64; 4], origin: &str, line: usize) -> Result<DQuat, ReadError> {
    let norm = wxyz.iter().map(|x| x * x).sum::<f64>().sqrt();
    // also catches NaN, which a file cannot hold but a reader may be handed
    if norm.is_nan() || norm <= 1e-6 {
        let got = format!("{wxyz:?}");
        return Err(bad(origin, line, "orientation", "not a rotation (zero quaternion)", &got));
    }
    Ok(quat_from_wxyz(wxyz).normalize())
}

/// The fields of a CSV line (RFC 4180 quoting: `"a,b"`, `""` for a quote).
fn split_csv(line: &str) -> Vec<String> {
    let mut fields = Vec::with_capacity(16);
    let mut field = String::new();
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match (c, quoted) {
            ('"', true) if chars.peek() == Some(&'"') => {
                field.push('"');
                chars.next();
            }
            ('"', true) => quoted = false,
            ('"', false) if field.is_empty() => quoted = true,
            (',', false) => fields.push(std::mem::take(&mut field)),
            (c, _) => field.push(c),
        }
    }
    fields.push(field);
    fields
}

/// One JSON Lines object → its body samples.
fn json_line(text: &str, origin: &str, line: usize) -> Result<Vec<(f64, String, BodySample)>, ReadError> {
    use serde_json::Value;
    let value: Value = serde_json::from_str(text).map_err(|e| bad(origin, line, "line", &e.to_string(), text))?;
    let missing = |field: &str| ReadError::MissingField { path: origin.into(), line, field: field.into() };
    let object = value.as_object().ok_or_else(|| bad(origin, line, "line", "not a JSON object", text))?;
    let t = match object.get("t") {
        None => return Err(missing("t")),
        Some(v) => v
            .as_f64()
            .filter(|x| x.is_finite())
            .ok_or_else(|| bad(origin, line, "t", "not a number", &v.to_string()))?,
    };
    let bodies = object.get("bodies").ok_or_else(|| missing("bodies"))?;
    let bodies = bodies.as_array().ok_or_else(|| bad(origin, line, "bodies", "not an array", &bodies.to_string()))?;
    let mut out = Vec::with_capacity(bodies.len());
    for (b, body) in bodies.iter().enumerate() {
        let path = |key: &str| format!("bodies[{b}].{key}");
        let name = match body.get("name") {
            None => return Err(missing(&path("name"))),
            Some(Value::String(s)) if !s.is_empty() => s.clone(),
            Some(v) => return Err(bad(origin, line, &path("name"), "not a non-empty string", &v.to_string())),
        };
        let array = |key: &str, n: usize| -> Result<Vec<f64>, ReadError> {
            let v = body.get(key).ok_or_else(|| missing(&path(key)))?;
            let items = v.as_array().filter(|a| a.len() == n);
            let numbers: Option<Vec<f64>> =
                items.and_then(|a| a.iter().map(|x| x.as_f64().filter(|x| x.is_finite())).collect());
            numbers.ok_or_else(|| bad(origin, line, &path(key), &format!("not {n} finite numbers"), &v.to_string()))
        };
        let v3 = |key: &str| array(key, 3).map(|a| DVec3::new(a[0], a[1], a[2]));
        let q = array("orientation", 4)?;
        let sample = BodySample {
            position: v3("position")?,
            orientation: orientation([q[0], q[1], q[2], q[3]], origin, line)?,
            velocity: v3("velocity")?,
            angular_velocity: v3("angular_velocity")?,
        };
        out.push((t, name, sample));
    }
    Ok(out)
}

impl Trajectory {
    /// Checks that the bodies are exactly the moving bodies of `world` and the moving links of its
    /// robots (`robot/link`), in any order; `trajectory` and `scene` name the two files in the message.
    pub fn check_bodies(&self, world: &World, trajectory: &str, scene: &str) -> Result<(), ReadError> {
        let links = world.robots.iter().flat_map(|r| r.link_names().iter().map(String::as_str));
        let moving: Vec<&str> = world.free_bodies().map(|b| b.name.as_str()).chain(links).collect();
        let unknown: Vec<String> = self.bodies.iter().filter(|n| !moving.contains(&n.as_str())).cloned().collect();
        let missing: Vec<String> =
            moving.iter().filter(|n| !self.bodies.iter().any(|b| b == *n)).map(|n| n.to_string()).collect();
        if unknown.is_empty() && missing.is_empty() {
            return Ok(());
        }
        let notes = robot_notes(world, &unknown);
        Err(ReadError::BodiesMismatch { trajectory: trajectory.into(), scene: scene.into(), unknown, missing, notes })
    }

    /// The time of the first and last frame (s).
    pub fn time_span(&self) -> (f64, f64) {
        let first = self.frames.first().map_or(0.0, |f| f.t);
        let last = self.frames.last().map_or(0.0, |f| f.t);
        (first, last)
    }
}

#[cfg(test)]
#[path = "read_tests.rs"]
mod tests;
