//! The trajectory writers: CSV and JSON Lines.
//!
//! One call of [`TrajectoryWriter::write_sample`] writes the state of every non-fixed body at the
//! world's current time, then of every moving link of every robot (named `robot/link`: the link
//! frame's origin and orientation, the velocity of that origin, the angular velocity, all world
//! frame); JSON Lines then adds `"robots": [{"name", "q", "v"}]` when the world has robots. A sample is first checked (every value finite), then formatted body by body
//! into a reused line buffer and handed to a [`BufWriter`]: after the first sample has sized the
//! buffer, writing allocates nothing.

use super::{Format, TrajectoryError};
use crate::math::quat_to_wxyz;
use crate::world::World;
use crate::RigidBody;
use std::io::{BufWriter, Write};

/// The CSV header, exactly (the contract).
pub const CSV_HEADER: &str = "t,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz";

/// Capacity of the output buffer (bytes).
const BUFFER_CAPACITY: usize = 64 * 1024;

/// Writes a trajectory, one sample at a time, to a sink (a file, a pipe, memory).
#[derive(Debug)]
pub struct TrajectoryWriter<W: Write> {
    sink: BufWriter<W>,
    format: Format,
    /// Each body's name as it is written: CSV-quoted when needed, or a JSON string literal.
    names: Vec<String>,
    /// Each robot's name and its links' names `robot/link`, formatted as `names`.
    robot_names: Vec<(String, Vec<String>)>,
    /// The text of one row (CSV) or of one body (JSON), reused.
    line: Vec<u8>,
    samples: u64,
}

/// What is written of one body, all world frame: position (m), orientation `[w, x, y, z]` of the
/// user's body axes, velocity (m/s), angular velocity (rad/s).
struct Row {
    position: [f64; 3],
    orientation: [f64; 4],
    velocity: [f64; 3],
    angular_velocity: [f64; 3],
}

impl Row {
    /// Link `k` of a robot: the link frame's origin, orientation and the velocity of its origin.
    #[inline]
    fn of_link(robot: &crate::world::Robot, k: usize) -> Row {
        let s = robot.link_state(k);
        Row {
            position: s.position.to_array(),
            orientation: quat_to_wxyz(s.orientation),
            velocity: s.velocity.to_array(),
            angular_velocity: s.angular_velocity.to_array(),
        }
    }

    #[inline]
    fn of(body: &RigidBody) -> Row {
        let s = &body.state;
        Row {
            position: s.position.to_array(),
            orientation: quat_to_wxyz(body.orientation_user()),
            velocity: s.velocity.to_array(),
            angular_velocity: s.omega_world().to_array(),
        }
    }

    /// The row as one array, `[x y z qw qx qy qz vx vy vz wx wy wz]`.
    #[inline]
    fn to_array(&self) -> [f64; 13] {
        let mut out = [0.0; 13];
        out[0..3].copy_from_slice(&self.position);
        out[3..7].copy_from_slice(&self.orientation);
        out[7..10].copy_from_slice(&self.velocity);
        out[10..13].copy_from_slice(&self.angular_velocity);
        out
    }

    /// The first quantity that is not finite, if any.
    #[inline]
    fn non_finite(&self) -> Option<&'static str> {
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        if !finite(&self.position) {
            Some("position")
        } else if !finite(&self.orientation) {
            Some("orientation")
        } else if !finite(&self.velocity) {
            Some("velocity")
        } else if !finite(&self.angular_velocity) {
            Some("angular velocity")
        } else {
            None
        }
    }
}

impl<W: Write> TrajectoryWriter<W> {
    /// A writer for the bodies of `world`; for CSV the header is written (buffered) at once.
    pub fn new(sink: W, format: Format, world: &World) -> Result<Self, TrajectoryError> {
        let names = world
            .bodies
            .iter()
            .map(|b| match format {
                Format::Csv => csv_field(&b.name),
                Format::JsonLines => serde_json::to_string(&b.name).expect("a string always serialises"),
            })
            .collect();
        let quote = |name: &str| match format {
            Format::Csv => csv_field(name),
            Format::JsonLines => serde_json::to_string(name).expect("a string always serialises"),
        };
        let robot_names =
            world.robots.iter().map(|r| (quote(&r.name), r.link_names().iter().map(|n| quote(n)).collect())).collect();
        let mut writer = Self {
            sink: BufWriter::with_capacity(BUFFER_CAPACITY, sink),
            format,
            names,
            robot_names,
            line: Vec::with_capacity(512),
            samples: 0,
        };
        if format == Format::Csv {
            writer.sink.write_all(CSV_HEADER.as_bytes())?;
            writer.sink.write_all(b"\n")?;
        }
        Ok(writer)
    }

    /// The format being written.
    pub fn format(&self) -> Format {
        self.format
    }

    /// Samples written so far.
    pub fn samples(&self) -> u64 {
        self.samples
    }

    /// Writes the state of every non-fixed body at `world.time()`.
    ///
    /// Every value is checked first: if one is not finite, nothing of the sample is written and
    /// [`TrajectoryError::NonFinite`] names the body and the quantity.
    pub fn write_sample(&mut self, world: &World) -> Result<(), TrajectoryError> {
        if world.bodies.len() != self.names.len() {
            return Err(TrajectoryError::BodiesChanged { expected: self.names.len(), got: world.bodies.len() });
        }
        let links = self.robot_names.iter().map(|(_, l)| l.len()).sum::<usize>();
        if world.robots.len() != self.robot_names.len() || world.robot_link_count() != links {
            return Err(TrajectoryError::BodiesChanged {
                expected: self.names.len() + links,
                got: world.bodies.len() + world.robot_link_count(),
            });
        }
        let t = world.time();
        for body in world.free_bodies() {
            let problem = if t.is_finite() { Row::of(body).non_finite() } else { Some("time") };
            if let Some(quantity) = problem {
                return Err(TrajectoryError::NonFinite { body: body.name.clone(), quantity, time: t });
            }
        }
        for robot in &world.robots {
            for (k, name) in robot.link_names().iter().enumerate() {
                if let Some(quantity) = Row::of_link(robot, k).non_finite() {
                    return Err(TrajectoryError::NonFinite { body: name.clone(), quantity, time: t });
                }
            }
            if !robot.q().iter().chain(robot.v()).all(|x| x.is_finite()) {
                return Err(TrajectoryError::NonFinite { body: robot.name.clone(), quantity: "q or v", time: t });
            }
        }
        match self.format {
            Format::Csv => self.write_csv(world, t)?,
            Format::JsonLines => self.write_json(world, t)?,
        }
        self.samples += 1;
        Ok(())
    }

    fn write_csv(&mut self, world: &World, t: f64) -> std::io::Result<()> {
        for (body, name) in world.bodies.iter().zip(&self.names) {
            if body.fixed {
                continue;
            }
            csv_row(&mut self.line, t, name, &Row::of(body));
            self.sink.write_all(&self.line)?;
        }
        for (robot, (_, links)) in world.robots.iter().zip(&self.robot_names) {
            for (k, name) in links.iter().enumerate() {
                csv_row(&mut self.line, t, name, &Row::of_link(robot, k));
                self.sink.write_all(&self.line)?;
            }
        }
        Ok(())
    }

    fn write_json(&mut self, world: &World, t: f64) -> std::io::Result<()> {
        let line = &mut self.line;
        line.clear();
        line.extend_from_slice(b"{\"t\":");
        push_f64(line, t);
        line.extend_from_slice(b",\"bodies\":[");
        self.sink.write_all(line)?;
        let mut first = true;
        for (body, name) in world.bodies.iter().zip(&self.names) {
            if body.fixed {
                continue;
            }
            json_body(line, !first, name, &Row::of(body));
            first = false;
            self.sink.write_all(line)?;
        }
        for (robot, (_, links)) in world.robots.iter().zip(&self.robot_names) {
            for (k, name) in links.iter().enumerate() {
                json_body(line, !first, name, &Row::of_link(robot, k));
                first = false;
                self.sink.write_all(line)?;
            }
        }
        if self.robot_names.is_empty() {
            return self.sink.write_all(b"]}\n");
        }
        // "robots": [{"name", "q", "v"}] after the bodies
        self.sink.write_all(b"],\"robots\":[")?;
        for (r, (robot, (name, _))) in world.robots.iter().zip(&self.robot_names).enumerate() {
            line.clear();
            if r > 0 {
                line.push(b',');
            }
            line.extend_from_slice(b"{\"name\":");
            line.extend_from_slice(name.as_bytes());
            push_array(line, b",\"q\":", robot.q());
            push_array(line, b",\"v\":", robot.v());
            line.push(b'}');
            self.sink.write_all(line)?;
        }
        self.sink.write_all(b"]}\n")
    }

    /// Writes out everything buffered so far (the file then ends with a whole row or line).
    pub fn flush(&mut self) -> Result<(), TrajectoryError> {
        self.sink.flush()?;
        Ok(())
    }

    /// Flushes and returns the sink.
    pub fn finish(mut self) -> Result<W, TrajectoryError> {
        self.sink.flush()?;
        self.sink.into_inner().map_err(|e| TrajectoryError::Io(e.into_error()))
    }

    /// The sink (what has been flushed to it so far).
    pub fn get_ref(&self) -> &W {
        self.sink.get_ref()
    }
}

/// Appends the shortest text that reads back to the same `f64` (the value must be finite).
#[inline]
pub(super) fn push_f64(line: &mut Vec<u8>, x: f64) {
    let mut buffer = ryu::Buffer::new();
    line.extend_from_slice(buffer.format_finite(x).as_bytes());
}

#[inline]
pub(super) fn push_array(line: &mut Vec<u8>, key: &[u8], values: &[f64]) {
    line.extend_from_slice(key);
    line.push(b'[');
    for (i, &x) in values.iter().enumerate() {
        if i > 0 {
            line.push(b',');
        }
        push_f64(line, x);
    }
    line.push(b']');
}

/// A CSV field (RFC 4180): quoted, with quotes doubled, when it holds a comma, quote, line break or
/// leading/trailing space.
fn csv_field(text: &str) -> String {
    let needs_quotes = text.contains([',', '"', '\n', '\r']) || text.starts_with(' ') || text.ends_with(' ');
    if needs_quotes {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

/// One CSV row `t,name,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz` into `line` (cleared first).
/// A moving body's trajectory row, `[x y z qw qx qy qz vx vy vz wx wy wz]` (world frame): the
/// numbers the CSV and JSON Lines writers print (also the body's part of `World::write_state`).
#[inline]
pub(crate) fn body_row(body: &RigidBody) -> [f64; 13] {
    Row::of(body).to_array()
}

fn csv_row(line: &mut Vec<u8>, t: f64, name: &str, row: &Row) {
    line.clear();
    push_f64(line, t);
    line.push(b',');
    line.extend_from_slice(name.as_bytes());
    for values in [&row.position[..], &row.orientation, &row.velocity, &row.angular_velocity] {
        for &x in values {
            line.push(b',');
            push_f64(line, x);
        }
    }
    line.push(b'\n');
}

/// One body object of a JSON Lines sample into `line` (cleared first), preceded by a comma when
/// `comma`; `name` is already a JSON string literal.
fn json_body(line: &mut Vec<u8>, comma: bool, name: &str, row: &Row) {
    line.clear();
    if comma {
        line.push(b',');
    }
    line.extend_from_slice(b"{\"name\":");
    line.extend_from_slice(name.as_bytes());
    push_array(line, b",\"position\":", &row.position);
    push_array(line, b",\"orientation\":", &row.orientation);
    push_array(line, b",\"velocity\":", &row.velocity);
    push_array(line, b",\"angular_velocity\":", &row.angular_velocity);
    line.push(b'}');
}
