//! The contacts file of `tumble run --contacts FILE.jsonl`: one JSON object per sample,
//!
//! ```text
//! {"t": 1.25, "contacts": [{"a": "ground", "b": "box", "point": [x, y, z], "normal": [nx, ny, nz],
//!  "depth": 0.0004, "force": [fx, fy, fz]}, …]}
//! ```
//!
//! every active contact of the step that ends at `t` ([`ContactStage::active`]: it carried an
//! impulse, or its surfaces overlapped), world frame: `normal` points from `a` to `b`, `depth` > 0
//! is overlap (m) at the start of the step, `force` is the force on `b` (N), the contact's whole
//! impulse over the step (collision and resting contact) divided by `dt`. The first sample, at
//! `t = 0`, has no step behind it and lists none. Numbers are the shortest text that reads back to
//! the same `f64`; after the first samples have sized the buffer, writing allocates nothing.
//!
//! [`ContactStage::active`]: crate::contact::ContactStage::active

use super::writer::{push_array, push_f64};
use super::TrajectoryError;
use crate::collision::links::Side;
use crate::world::World;
use std::io::{BufWriter, Write};

/// Writes the contacts of a run, one sample at a time.
#[derive(Debug)]
pub struct ContactWriter<W: Write> {
    sink: BufWriter<W>,
    /// Each body's name as a JSON string literal.
    names: Vec<String>,
    /// Each link collider's name, `robot/link`, as a JSON string literal.
    link_names: Vec<String>,
    line: Vec<u8>,
}

impl<W: Write> ContactWriter<W> {
    /// A writer for the bodies of `world`.
    pub fn new(sink: W, world: &World) -> Self {
        let json = |name: &str| serde_json::to_string(name).expect("a string always serialises");
        let names = world.bodies.iter().map(|b| json(&b.name)).collect();
        let link_names = world.contacts().links.colliders.links().iter().map(|l| json(&l.name)).collect();
        Self { sink: BufWriter::with_capacity(64 * 1024, sink), names, link_names, line: Vec::with_capacity(4096) }
    }

    /// Writes the active contacts of the world's last step at `world.time()`. A value that is not
    /// finite writes nothing of the sample and is reported, naming the two bodies.
    pub fn write_sample(&mut self, world: &World) -> Result<(), TrajectoryError> {
        if world.bodies.len() != self.names.len() {
            return Err(TrajectoryError::BodiesChanged { expected: self.names.len(), got: world.bodies.len() });
        }
        let t = world.time();
        let inv_dt = 1.0 / world.config.dt;
        let line = &mut self.line;
        line.clear();
        line.extend_from_slice(b"{\"t\":");
        if !t.is_finite() {
            return Err(TrajectoryError::NonFinite { body: "contacts".into(), quantity: "time", time: t });
        }
        push_f64(line, t);
        line.extend_from_slice(b",\"contacts\":[");
        let bodies = world
            .contacts()
            .active()
            .map(|(c, p)| (&self.names[c.a], &self.names[c.b], c.point_world, c.normal_world, c.gap, p));
        let side = |s: Side| match s {
            Side::Body(i) => &self.names[i],
            Side::Link(l) => &self.link_names[l],
        };
        let links = world
            .contacts()
            .links
            .active()
            .map(|(c, p)| (side(c.a), side(c.b), c.point_world, c.normal_world, c.gap, p));
        for (k, (a, b, point, normal, gap, p)) in bodies.chain(links).enumerate() {
            let force = (p * inv_dt).to_array();
            let (point, normal) = (point.to_array(), normal.to_array());
            let values = point.iter().chain(&normal).chain(&force).chain(std::iter::once(&gap));
            if values.into_iter().any(|x| !x.is_finite()) {
                let body = format!("{a} against {b}");
                return Err(TrajectoryError::NonFinite { body, quantity: "contact", time: t });
            }
            if k > 0 {
                line.push(b',');
            }
            line.extend_from_slice(b"{\"a\":");
            line.extend_from_slice(a.as_bytes());
            line.extend_from_slice(b",\"b\":");
            line.extend_from_slice(b.as_bytes());
            push_array(line, b",\"point\":", &point);
            push_array(line, b",\"normal\":", &normal);
            line.extend_from_slice(b",\"depth\":");
            push_f64(line, -gap);
            push_array(line, b",\"force\":", &force);
            line.push(b'}');
        }
        line.extend_from_slice(b"]}\n");
        self.sink.write_all(line)?;
        Ok(())
    }

    /// Writes out everything buffered so far (the file then ends with a whole line).
    pub fn flush(&mut self) -> Result<(), TrajectoryError> {
        self.sink.flush()?;
        Ok(())
    }

    /// Flushes and returns the sink.
    pub fn finish(mut self) -> Result<W, TrajectoryError> {
        self.sink.flush()?;
        self.sink.into_inner().map_err(|e| TrajectoryError::Io(e.into_error()))
    }
}
