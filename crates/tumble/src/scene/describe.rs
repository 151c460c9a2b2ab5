//! `Scene::describe`: what the loader understood, for `tumble check`.
//!
//! Everything is printed in the frames of the file: orientation and `_body` quantities in the
//! user's body axes (converted back from the principal axes), the rest in the world frame.

use super::Scene;
use crate::body::{Frame, RigidBody, Shape};
use crate::integrate::Integrator;
use crate::math::{DQuat, DVec3};
use std::fmt::Write as _;

/// Bodies listed one by one; the rest are counted.
pub const MAX_LISTED_BODIES: usize = 50;

/// A number with 7 significant digits at most, trailing zeros trimmed.
pub(crate) fn g(x: f64) -> String {
    if x == 0.0 {
        return "0".to_string();
    }
    let a = x.abs();
    if !(1e-4..1e7).contains(&a) {
        return format!("{x:.6e}");
    }
    let decimals = (6 - a.log10().floor() as i32).max(0) as usize;
    let s = format!("{x:.decimals$}");
    let s = if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_string() } else { s };
    if s == "-0" {
        "0".to_string()
    } else {
        s
    }
}

/// A vector; components below 1e-12 of the largest are round-off of a frame change and shown as 0.
fn v3(v: DVec3) -> String {
    let scale = v.abs().max_element();
    let c = |x: f64| g(if x.abs() <= 1e-12 * scale { 0.0 } else { x });
    format!("[{}, {}, {}]", c(v.x), c(v.y), c(v.z))
}

/// `[w, x, y, z]`, as in files, with `w ≥ 0` (`q` and `−q` are the same rotation).
fn wxyz(q: DQuat) -> String {
    let q = if q.w < 0.0 { -q } else { q };
    let c = |x: f64| g(if x.abs() <= 1e-12 { 0.0 } else { x });
    format!("[{}, {}, {}, {}]", c(q.w), c(q.x), c(q.y), c(q.z))
}

pub(crate) fn describe(scene: &Scene) -> String {
    let w = &scene.world;
    let c = &w.config;
    let mut out = String::new();
    let _ = writeln!(out, "scene {}", scene.origin);
    let _ = writeln!(out, "world");
    let _ = writeln!(out, "  gravity      {} m/s² (world frame)", v3(c.gravity));
    let _ = writeln!(out, "  dt           {} s", g(c.dt));
    let _ = writeln!(out, "  duration     {} s ({} steps)", g(c.duration), c.step_count());
    let _ = write!(out, "  integrator   {} (order {})", c.integrator, c.integrator.order());
    if c.integrator == Integrator::Dopri5 {
        let _ = write!(out, ", rtol {}, atol {}", g(c.tolerances.rtol), g(c.tolerances.atol));
    }
    let _ = writeln!(out);
    let _ = writeln!(
        out,
        "  sample_every {} (every {} s of simulated time)",
        c.sample_every,
        g(c.dt * c.sample_every as f64)
    );
    let fixed = w.bodies.iter().filter(|b| b.fixed).count();
    let _ = writeln!(out, "{} bodies ({} moving, {} fixed)", w.bodies.len(), w.bodies.len() - fixed, fixed);
    for body in w.bodies.iter().take(MAX_LISTED_BODIES) {
        describe_body(&mut out, body, c.gravity);
    }
    if w.bodies.len() > MAX_LISTED_BODIES {
        let _ = writeln!(out, "... and {} more bodies", w.bodies.len() - MAX_LISTED_BODIES);
    }
    for robot in &w.robots {
        super::robot::describe_robot(&mut out, robot);
    }
    for warning in &scene.warnings {
        let _ = writeln!(out, "warning: {warning}");
    }
    out
}

fn describe_body(out: &mut String, b: &RigidBody, gravity: DVec3) {
    let user_from_body = b.mass.user_from_body;
    let _ = writeln!(out, "body `{}`{}", b.name, if b.fixed { " (fixed)" } else { "" });
    if b.fixed {
        let _ = writeln!(out, "  position     {} m", v3(b.state.position));
        let _ = writeln!(out, "  orientation  {} [w, x, y, z]", wxyz(b.orientation_user()));
    } else {
        let _ = writeln!(out, "  mass         {} kg", g(b.mass.mass));
        let _ = writeln!(out, "  inertia      {} kg·m² (principal moments)", v3(b.mass.inertia_body));
        if user_from_body.angle_between(DQuat::IDENTITY) > 1e-12 {
            // columns of user_from_body: the principal axes in the user's body axes
            let _ = writeln!(
                out,
                "  principal axes, in the body axes: x' = {}, y' = {}, z' = {}",
                v3(user_from_body * DVec3::X),
                v3(user_from_body * DVec3::Y),
                v3(user_from_body * DVec3::Z)
            );
        }
        let s = &b.state;
        let _ = writeln!(out, "  position     {} m", v3(s.position));
        let _ = writeln!(out, "  orientation  {} [w, x, y, z]", wxyz(b.orientation_user()));
        let _ = writeln!(out, "  velocity     {} m/s", v3(s.velocity));
        let _ = writeln!(
            out,
            "  angular velocity {} rad/s (world frame) = {} rad/s (body axes)",
            v3(s.omega_world()),
            v3(user_from_body * s.omega_body)
        );
    }
    if let Some(shape) = &b.shape {
        let _ = writeln!(out, "  shape        {} ({})", shape.type_name(), shape_text(shape, b.fixed));
        if let Shape::Compound(c) = shape {
            for (k, part) in c.parts.iter().enumerate() {
                let _ = writeln!(
                    out,
                    "    part {k}     {} ({}) at {} m, orientation {} (body axes)",
                    part.shape.type_name(),
                    shape_text(&part.shape, b.fixed),
                    v3(part.position),
                    wxyz(part.orientation)
                );
            }
        }
    }
    if let Some(e) = b.material.restitution {
        let _ = writeln!(out, "  restitution  {}", g(e));
    }
    if let Some(mu) = b.material.friction {
        let _ = writeln!(out, "  friction     {}", g(mu));
    }
    let l = &b.loads;
    let mut loads = Vec::new();
    if l.force_world != DVec3::ZERO {
        loads.push(format!("force {} N (world)", v3(l.force_world)));
    }
    if l.force_body != DVec3::ZERO {
        loads.push(format!("force {} N (body axes)", v3(user_from_body * l.force_body)));
    }
    if l.torque_world != DVec3::ZERO {
        loads.push(format!("torque {} N·m (world)", v3(l.torque_world)));
    }
    if l.torque_body != DVec3::ZERO {
        loads.push(format!("torque {} N·m (body axes)", v3(user_from_body * l.torque_body)));
    }
    if l.linear_damping != 0.0 {
        loads.push(format!("linear damping {} 1/s", g(l.linear_damping)));
    }
    if l.angular_damping != 0.0 {
        loads.push(format!("angular damping {} 1/s", g(l.angular_damping)));
    }
    for pf in &l.point_forces {
        let (force, frame) = match pf.frame {
            Frame::World => (pf.force, "world"),
            Frame::Body => (user_from_body * pf.force, "body axes"),
        };
        loads.push(format!("force {} N ({frame}) at {} m (body axes)", v3(force), v3(user_from_body * pf.point_body)));
    }
    if !b.fixed {
        if b.gravity_scale != 1.0 {
            let g_body = b.gravity(gravity);
            let _ = writeln!(out, "  gravity      {} × the world's = {} m/s²", g(b.gravity_scale), v3(g_body));
        }
        let text = if loads.is_empty() { "none besides gravity".to_string() } else { loads.join("; ") };
        let _ = writeln!(out, "  loads        {text}");
    }
}

/// A shape's sizes, and for meshes what contacts see (`fixed`: the body is fixed).
fn shape_text(shape: &Shape, fixed: bool) -> String {
    match *shape {
        Shape::Sphere { radius } => format!("radius {} m", g(radius)),
        Shape::Box { half_extents } => format!("half extents {} m", v3(half_extents)),
        Shape::Capsule { radius, half_height } | Shape::Cylinder { radius, half_height } => {
            format!("radius {} m, half height {} m", g(radius), g(half_height))
        }
        Shape::Plane => "normal +z (body axes)".to_string(),
        Shape::Mesh(ref m) => {
            let contacts = match (&m.decomposition, fixed) {
                (_, true) => "collides as its triangles".to_string(),
                (Some(pieces), false) => format!(
                    "collides as {} convex pieces (its hull is {:.1}% larger)",
                    pieces.len(),
                    100.0 * m.hull_excess
                ),
                (None, false) => format!("collides as its convex hull ({:.1}% larger)", 100.0 * m.hull_excess),
            };
            format!(
                "{}: {} triangles, volume {} m³, centre of mass at {} m in the file's axes × scale {}; {contacts}",
                m.file,
                m.mesh.triangles().len(),
                g(m.volume),
                v3(m.center_of_mass_file),
                v3(m.scale)
            )
        }
        Shape::Convex(ref c) => format!(
            "hull of {} points: {} vertices, {} triangles, volume {} m³, centre of mass at {} m in the points' axes",
            c.points_given,
            c.hull.vertices().len(),
            c.hull.triangles().len(),
            g(c.volume),
            v3(c.center_of_mass_given)
        ),
        Shape::Compound(ref c) => format!(
            "{} parts, volume {} m³, centre of mass at {} m in the parts' axes",
            c.parts.len(),
            g(c.volume),
            v3(c.center_of_mass_given)
        ),
    }
}
