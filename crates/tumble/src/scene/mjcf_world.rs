//! An MJCF file as a whole world (`tumble run X.xml`), written as a JSON scene: what MuJoCo's
//! `simulate` would run, in tumble's terms.
//!
//! - `[world]` from `<option>`: `timestep` as `dt`, `gravity`, `integrator` (`Euler` →
//!   `semi_implicit_euler`, `RK4` → `rk4`, the implicit ones → `semi_implicit_euler` with a warning).
//! - Every collision geom fixed to the world (the worldbody's, and those of bodies welded to it)
//!   becomes a fixed `[[body]]` with its shape, its pose in the world and its first friction
//!   coefficient: sphere, capsule, box, cylinder, plane (any orientation), mesh (its convex hull,
//!   as MuJoCo collides meshes).
//! - Every body with a free joint and no child bodies becomes a moving `[[body]]`: its mass, its
//!   inertia tensor about the centre of mass in the MJCF body's axes, its collision geoms as `shape`
//!   (one geom centred on the centre of mass, in the body's axes) or `shapes` (a compound), the pose
//!   and velocity of `qpos0` (or of the keyframe), its friction. The scene's compound sits on its
//!   parts' volume centroid, so a body whose centre of mass is elsewhere (an `<inertial>` off the
//!   geoms, geoms of different densities), whose geoms have different frictions, stays a floating
//!   robot of one link, with a warning saying why.
//! - The rest of the tree is one `[[robot]]` (`mjcf`, `leave_out` the world and the free bodies
//!   above), its actuators at `ctrl = 0`.

use super::SceneError;
use crate::body::Shape;
use crate::math::{DMat3, DQuat, DVec3};
use crate::multibody::link_shapes::{collision_shapes, LinkShape};
use crate::multibody::mjcf::{load_mjcf, Mjcf, MjcfIntegrator, MjcfOptions};
use crate::multibody::{GeometryRole, LinkGeometry};
use serde_json::{json, Value};
use std::path::Path;

/// A compound's volume centroid may sit this far (relative to the body's size) from the MJCF
/// centre of mass for the body to be written as a scene body.
const CENTROID_TOLERANCE: f64 = 1e-9;

/// The scene of [`super::load_mjcf_world`] as JSON scene text (the MJCF file named by its
/// absolute path), and the warnings of reading the file's options and worldbody.
///
/// `keyframe`: the name (or an unnamed key's index) of a `<keyframe><key>` to start from: its
/// `qpos`/`qvel` place the free bodies and the robot (written as the robot's `q` and `v` by joint),
/// its `ctrl` drives the actuators (`ctrl` by actuator).
pub fn mjcf_world_text(path: &Path, keyframe: Option<&str>) -> Result<(String, Vec<String>), SceneError> {
    let origin = path.display().to_string();
    let mjcf = load_mjcf(path, MjcfOptions::default()).map_err(|e| SceneError::file(&origin, e.to_string()))?;
    let mut warnings = Vec::new();
    let integrator = match mjcf.option.integrator {
        MjcfIntegrator::Euler => "semi_implicit_euler",
        MjcfIntegrator::Rk4 => "rk4",
        MjcfIntegrator::Implicit | MjcfIntegrator::ImplicitFast => {
            warnings.push(format!(
                "{origin}: option integrator: MuJoCo's implicit integrators are run as semi_implicit_euler (the joints' \
                 damping explicit)"
            ));
            "semi_implicit_euler"
        }
    };
    let world = World::read(&mjcf, &origin)?;
    let key = match keyframe {
        Some(name) => Some(mjcf.keyframe(name).map_err(|why| SceneError::file(&origin, why))?),
        None => None,
    };
    let (qpos, qvel) = match key {
        Some(k) => (k.qpos.clone(), k.qvel.clone()),
        None => (mjcf.layout.qpos0(), vec![0.0; mjcf.model.nv()]),
    };
    if let Some(k) = key.filter(|k| k.time != 0.0) {
        warnings
            .push(format!("{}: <key time=\"{}\">: the run starts at t = 0 (the key's time is not used)", k.at, k.time));
    }
    let (q, v) = mjcf.layout.state_from_mujoco(&qpos, &qvel).map_err(|e| SceneError::file(&origin, e.to_string()))?;
    let robot_name: String =
        mjcf.model.name.chars().map(|c| if c == '/' || c.is_whitespace() { '_' } else { c }).collect();
    let robot_name = if robot_name.is_empty() { "model".to_string() } else { robot_name };
    let mut taken = vec![robot_name.clone()];
    let mut bodies = Vec::new();
    // the geoms (model geometry indices) of each scene body, and whether it is fixed
    let mut members: Vec<(Vec<usize>, bool)> = Vec::new();
    for (k, Geom { shape, geom, .. }) in world.fixed.iter().enumerate() {
        let name = unique(geom.name.clone().unwrap_or_else(|| format!("world_geom_{k}")), &mut taken);
        let Some(shape_doc) = shape_json(&shape.shape) else {
            return Err(SceneError::file(&format!("{origin}:{}", geom.line), "worldbody geom: no scene shape for it"));
        };
        let r = shape.orientation_body;
        let mut body = json!({
            "name": name,
            "shape": shape_doc,
            "fixed": true,
            "position": shape.position_body.to_array(),
            "orientation": [r.w, r.x, r.y, r.z],
        });
        if let Some(mu) = geom.friction {
            body["friction"] = json!(mu);
        }
        bodies.push(body);
        members.push((vec![world.fixed[k].index], true));
    }
    let mut leave_out = vec!["world".to_string()];
    for name in &mjcf.free_bodies {
        match world.free_body(&mjcf, name, &q, &v) {
            Ok(mut body) => {
                body["name"] = json!(unique(name.clone(), &mut taken));
                bodies.push(body);
                leave_out.push(name.clone());
                let parts = world.moving.iter().filter(|g| g.geom.link == *name).map(|g| g.index).collect();
                members.push((parts, false));
            }
            Err(why) => warnings.push(format!(
                "{origin}: body '{name}': kept as a floating robot of one link, not a scene body: {why}"
            )),
        }
    }
    // the robot's links (MJCF bodies) with their geoms
    let mut links: Vec<(String, Vec<usize>)> = Vec::new();
    for g in world.moving.iter().filter(|g| !leave_out.contains(&g.geom.link)) {
        match links.iter_mut().find(|(l, _)| *l == g.geom.link) {
            Some((_, list)) => list.push(g.index),
            None => links.push((g.geom.link.clone(), vec![g.index])),
        }
    }
    // MuJoCo's filter between scene bodies and between a body and a link: `no_collide`
    let verdict = |a: &[usize], b: &[usize], what: &str| -> Result<bool, SceneError> {
        let allowed =
            a.iter().flat_map(|&x| b.iter().map(move |&y| (x, y))).filter(|&(x, y)| mjcf.filter.may_collide(x, y));
        match allowed.count() {
            0 => Ok(false),
            n if n == a.len() * b.len() => Ok(true),
            _ => Err(SceneError::file(
                &origin,
                format!("{what}: some of their geoms may collide and others not (contype/conaffinity); tumble filters contacts per body and per link"),
            )),
        }
    };
    for x in 0..bodies.len() {
        let mut no_collide = Vec::new();
        for y in 0..bodies.len() {
            let ((gx, fixed_x), (gy, fixed_y)) = (&members[x], &members[y]);
            if x == y || (*fixed_x && *fixed_y) || gx.is_empty() || gy.is_empty() {
                continue;
            }
            let what = format!(
                "bodies '{}' and '{}'",
                bodies[x]["name"].as_str().unwrap_or(""),
                bodies[y]["name"].as_str().unwrap_or("")
            );
            if y > x && !verdict(gx, gy, &what)? {
                no_collide.push(bodies[y]["name"].clone());
            }
        }
        for (link, geoms) in &links {
            let what = format!("body '{}' and robot link '{link}'", bodies[x]["name"].as_str().unwrap_or(""));
            if !members[x].0.is_empty() && !verdict(&members[x].0, geoms, &what)? {
                no_collide.push(json!(format!("{robot_name}/{link}")));
            }
        }
        if !no_collide.is_empty() {
            bodies[x]["no_collide"] = json!(no_collide);
        }
    }
    let robot_geoms: Vec<usize> = links.iter().flat_map(|(_, g)| g.iter().copied()).collect();
    let self_collision = robot_geoms
        .iter()
        .enumerate()
        .any(|(k, &a)| robot_geoms[k + 1..].iter().any(|&b| mjcf.filter.may_collide(a, b)));
    // MuJoCo's defaults where a geom gives nothing: friction 1; its soft contacts (solref 0.02 s,
    // damping ratio 1) do not bounce: restitution 0
    let mut doc = json!({
        "version": 1,
        "world": {
            "dt": mjcf.option.timestep,
            "gravity": mjcf.option.gravity.to_array(),
            "integrator": integrator,
            "friction": 1.0,
            "restitution": 0.0,
        },
        "body": bodies,
    });
    // the tree, unless every moving body became a scene body
    let left = mjcf.model.bodies.iter().filter(|b| !leave_out.contains(&b.name)).count();
    if left > 0 {
        let file = path.canonicalize().unwrap_or(path.to_path_buf()).display().to_string();
        let mut robot = json!({ "name": robot_name, "mjcf": file, "leave_out": leave_out });
        if self_collision {
            robot["self_collision"] = json!(true);
        }
        if let Some(k) = key {
            // the key's state of the robot's joints (tumble's coordinates) and its controls
            let (mut q_table, mut v_table) = (serde_json::Map::new(), serde_json::Map::new());
            for b in mjcf.model.bodies.iter().filter(|b| !leave_out.contains(&b.name)) {
                let j = &b.joint;
                let (qs, vs) = (&q[j.q_index..j.q_index + j.kind.nq()], &v[j.v_index..j.v_index + j.kind.nv()]);
                let value = |x: &[f64]| if x.len() == 1 { json!(x[0]) } else { json!(x) };
                q_table.insert(j.name.clone(), value(qs));
                v_table.insert(j.name.clone(), value(vs));
            }
            robot["q"] = Value::Object(q_table);
            robot["v"] = Value::Object(v_table);
            if !mjcf.actuators.is_empty() {
                let ctrl: serde_json::Map<String, Value> =
                    mjcf.actuators.iter().zip(&k.ctrl).map(|(a, u)| (a.name.clone(), json!(u))).collect();
                robot["ctrl"] = Value::Object(ctrl);
            }
        }
        // a robot has one friction for all its links: the geoms' when they agree
        let link_frictions: Vec<Option<f64>> =
            world.moving.iter().filter(|g| !leave_out.contains(&g.geom.link)).map(|g| g.geom.friction).collect();
        match link_frictions.first() {
            Some(&first) if link_frictions.iter().all(|&f| f == first) => {
                if let Some(mu) = first {
                    robot["friction"] = json!(mu);
                }
            }
            Some(_) => warnings.push(format!(
                "{origin}: the robot's geoms have different frictions; a robot has one for all its links: they take MuJoCo's default, 1"
            )),
            None => {}
        }
        doc["robot"] = json!([robot]);
    }
    Ok((doc.to_string(), warnings))
}

/// `name`, or `name_2`, `name_3`, … when taken; recorded as taken.
fn unique(name: String, taken: &mut Vec<String>) -> String {
    let mut candidate = name.clone();
    let mut k = 2;
    while taken.contains(&candidate) {
        candidate = format!("{name}_{k}");
        k += 1;
    }
    taken.push(candidate.clone());
    candidate
}

/// One collision geom of the file: its shape, its geometry and that geometry's index in the model.
struct Geom<'m> {
    shape: LinkShape,
    geom: &'m LinkGeometry,
    index: usize,
}

/// The collision geometry of the file that can collide with something of the file (MuJoCo's
/// filter, [`crate::multibody::mjcf::filter`]), split: fixed to the world, and on moving bodies.
struct World<'m> {
    /// The geoms fixed to the world, in file order.
    fixed: Vec<Geom<'m>>,
    /// The geoms on moving bodies, in file order.
    moving: Vec<Geom<'m>>,
}

impl<'m> World<'m> {
    fn read(mjcf: &'m Mjcf, origin: &str) -> Result<Self, SceneError> {
        let geometries = &mjcf.model.geometries;
        let candidates: Vec<usize> =
            (0..geometries.len()).filter(|&g| geometries[g].role == GeometryRole::Collision).collect();
        let alive = |a: usize| candidates.iter().any(|&b| b != a && mjcf.filter.may_collide(a, b));
        let indices: Vec<usize> = candidates.iter().copied().filter(|&a| alive(a)).collect();
        // the shapes of the geoms that can collide (one that cannot needs none, and may have none:
        // an ellipsoid)
        let mut model = mjcf.model.clone();
        for (g, geometry) in model.geometries.iter_mut().enumerate() {
            if !indices.contains(&g) {
                geometry.role = GeometryRole::Visual;
            }
        }
        let shapes = collision_shapes(&model, origin).map_err(|e| SceneError::file(origin, e.to_string()))?;
        let (fixed, moving) = shapes
            .into_iter()
            .zip(&indices)
            .map(|(shape, &index)| Geom { shape, geom: &geometries[index], index })
            .partition(|g| g.shape.body.is_none());
        Ok(World { fixed, moving })
    }

    /// The scene body (without its name) of the free body `name` at the full model's state `(q,
    /// v)`, or why it cannot be one.
    fn free_body(&self, mjcf: &Mjcf, name: &str, q: &[f64], v: &[f64]) -> Result<Value, String> {
        let model = &mjcf.model;
        let i = model.bodies.iter().position(|b| b.name == name).ok_or("not in the model")?;
        let body = &model.bodies[i];
        let inertia = body.inertia;
        if !(inertia.mass > 0.0) {
            return Err("it has no mass".into());
        }
        // the centre of mass c and the tensor about it, MJCF body axes: Ī_c = Ī_o − m (|c|² 1 − c cᵀ)
        let c = inertia.com();
        let outer = DMat3::from_cols(c * c.x, c * c.y, c * c.z);
        let i_com = inertia.i_o - inertia.mass * (DMat3::from_diagonal(DVec3::splat(c.length_squared())) - outer);
        let parts: Vec<&Geom> = self.moving.iter().filter(|g| g.shape.body == Some(i)).collect();
        let friction = parts.first().and_then(|g| g.geom.friction);
        if parts.iter().any(|g| g.geom.friction != friction) {
            return Err("its geoms have different frictions (a scene body has one)".into());
        }
        let masks = |g: &Geom| (g.geom.contype, g.geom.conaffinity);
        if parts.iter().any(|g| masks(g) != masks(parts[0])) {
            return Err(
                "its geoms have different contype/conaffinity (a scene body's contacts are filtered as one)".into()
            );
        }
        let mut doc = json!({
            "mass": inertia.mass,
            "inertia_tensor": [i_com.x_axis.to_array(), i_com.y_axis.to_array(), i_com.z_axis.to_array()],
        });
        let centred = |p: DVec3| (p - c).length() <= CENTROID_TOLERANCE * (1.0 + c.length());
        match parts.as_slice() {
            [] => {}
            [Geom { shape: s, .. }]
                if s.orientation_body.angle_between(DQuat::IDENTITY) < 1e-12 && centred(s.position_body) =>
            {
                doc["shape"] = shape_json(&s.shape).ok_or("no scene shape for its geom")?;
            }
            _ => {
                let (mut volume, mut moment) = (0.0, DVec3::ZERO);
                let mut list = Vec::new();
                for Geom { shape: s, .. } in &parts {
                    let Some((vol, _)) = s.shape.inertia_tensor(1.0) else {
                        return Err("a part without volume".into());
                    };
                    volume += vol;
                    moment += vol * s.position_body;
                    let mut part = shape_json(&s.shape).ok_or("no scene shape for one of its geoms")?;
                    let r = s.orientation_body;
                    part["position"] = json!(s.position_body.to_array());
                    part["orientation"] = json!([r.w, r.x, r.y, r.z]);
                    list.push(part);
                }
                let centroid = moment / volume;
                let size = parts.iter().map(|g| g.shape.position_body.length()).fold(c.length(), f64::max);
                if (centroid - c).length() > CENTROID_TOLERANCE * (1.0 + size) {
                    return Err(format!(
                        "its centre of mass {:?} is not its collision shapes' volume centroid {:?} (where a scene \
                         compound sits)",
                        c.to_array(),
                        centroid.to_array()
                    ));
                }
                doc["shapes"] = json!(list);
            }
        }
        // the free joint's q = [x, y, z, qw, qx, qy, qz] of the body frame, v = [v_o, ω] body frame
        let (qi, vi) = (body.joint.q_index, body.joint.v_index);
        let rot = DQuat::from_xyzw(q[qi + 4], q[qi + 5], q[qi + 6], q[qi + 3]).normalize();
        let origin = DVec3::from_slice(&q[qi..qi + 3]);
        let (v_o, omega) = (DVec3::from_slice(&v[vi..vi + 3]), DVec3::from_slice(&v[vi + 3..vi + 6]));
        doc["position"] = json!((origin + rot * c).to_array());
        doc["orientation"] = json!([rot.w, rot.x, rot.y, rot.z]);
        // the centre of mass's velocity, world frame: R (v_o + ω × c)
        let velocity = rot * (v_o + omega.cross(c));
        if velocity != DVec3::ZERO {
            doc["velocity"] = json!(velocity.to_array());
        }
        if omega != DVec3::ZERO {
            doc["angular_velocity_body"] = json!(omega.to_array());
        }
        if let Some(mu) = friction {
            doc["friction"] = json!(mu);
        }
        Ok(doc)
    }
}

/// A shape as a scene `shape` table (`None` for a mesh or compound, which link shapes never are).
fn shape_json(shape: &Shape) -> Option<Value> {
    Some(match shape {
        Shape::Sphere { radius } => json!({ "type": "sphere", "radius": radius }),
        Shape::Box { half_extents } => json!({ "type": "box", "half_extents": half_extents.to_array() }),
        Shape::Capsule { radius, half_height } => {
            json!({ "type": "capsule", "radius": radius, "half_height": half_height })
        }
        Shape::Cylinder { radius, half_height } => {
            json!({ "type": "cylinder", "radius": radius, "half_height": half_height })
        }
        Shape::Plane => json!({ "type": "plane" }),
        Shape::Convex(c) => {
            let points: Vec<[f64; 3]> = c.hull.vertices().iter().map(|p| p.to_array()).collect();
            json!({ "type": "convex", "points": points })
        }
        Shape::Mesh(_) | Shape::Compound(_) => return None,
    })
}
