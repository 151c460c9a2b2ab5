//! One `[[body]]` entry (or a grid's template) → a validated [`RigidBody`].
//!
//! Frames: the file speaks of the *user's* body axes; when an inertia tensor is diagonalised the
//! engine's body frame is the principal frame, `user_from_body = MassProperties::user_from_body`.
//! Orientation, `angular_velocity_body`, `force_body`, `torque_body` and point-force `point`s are
//! converted here, once, from the user's axes to the principal axes.

use super::error::{num, nums, SceneError, Source};
use super::schema::{BodyDoc, Loc, PointForceDoc, Table, Vec3Doc};
use super::{MAX_ANGULAR_SPEED, MAX_GRAVITY, MAX_POSITION, MAX_SPEED, QUAT_SILENT_TOLERANCE, QUAT_WARN_TOLERANCE};
use crate::body::{Frame, MassProperties, Material, PointForce, RigidBody, Shape};
use crate::math::{DMat3, DQuat, DVec3};
use std::ops::Range;

/// Reads one body; errors name `path.key` (e.g. `body[3].mass`).
pub(crate) struct BodyReader<'r, 'a> {
    pub src: &'r Source<'a>,
    /// `body[3]` or `grid[0].body`.
    pub path: &'r str,
    /// The body's table (TOML).
    pub span: Option<&'r Range<usize>>,
    pub warnings: &'r mut Vec<String>,
    /// The world's gravity (m/s², world frame), to bound a body's `gravity_scale`.
    pub gravity: DVec3,
}

impl BodyReader<'_, '_> {
    pub(super) fn at(&self, key: &str) -> String {
        format!("{}.{}", self.path, key)
    }

    pub(super) fn err<T>(&self, key: &str, loc: &Loc<T>, problem: impl Into<String>) -> SceneError {
        self.src.error(loc.span.as_ref(), self.at(key), problem)
    }

    /// A scalar that must be finite.
    fn finite(&self, key: &str, loc: &Option<Loc<f64>>) -> Result<Option<f64>, SceneError> {
        match loc {
            Some(l) if !l.value.is_finite() => Err(self.err(key, l, "must be finite").got(num(l.value))),
            _ => Ok(loc.as_ref().map(|l| l.value)),
        }
    }

    /// A scalar that must be finite and satisfy `ok`.
    fn ranged(
        &self,
        key: &str,
        loc: &Option<Loc<f64>>,
        ok: fn(f64) -> bool,
        problem: &str,
    ) -> Result<Option<f64>, SceneError> {
        match (self.finite(key, loc)?, loc) {
            (Some(x), Some(l)) if !ok(x) => Err(self.err(key, l, problem).got(num(x))),
            (x, _) => Ok(x),
        }
    }

    /// A vector that must be finite in every component.
    pub(super) fn finite3(&self, key: &str, loc: &Option<Vec3Doc>) -> Result<Option<DVec3>, SceneError> {
        match loc {
            Some(l) if l.value.iter().any(|x| !x.is_finite()) => {
                Err(self.err(key, l, "must be finite").got(nums(&l.value)))
            }
            _ => Ok(loc.as_ref().map(|l| DVec3::from_array(l.value))),
        }
    }

    /// A finite vector of magnitude at most `max` (`unit` for the message).
    fn bounded3(&self, key: &str, loc: &Option<Vec3Doc>, max: f64, unit: &str) -> Result<Option<DVec3>, SceneError> {
        match (self.finite3(key, loc)?, loc) {
            (Some(v), Some(l)) if v.length() > max => Err(self
                .err(key, l, format!("magnitude {:e} {unit} exceeds the limit of {max:e} {unit}", v.length()))
                .got(nums(&l.value))),
            (v, _) => Ok(v),
        }
    }

    /// Builds the body named `name` from `doc`.
    pub fn read(&mut self, doc: &BodyDoc, name: String) -> Result<RigidBody, SceneError> {
        let fixed = doc.fixed.as_ref().is_some_and(|f| f.value);
        let shape = self.shape(doc, fixed)?;
        if let (Some(Shape::Plane), Some(loc), false) = (&shape, &doc.shape, fixed) {
            return Err(self
                .err("shape", loc, "a plane is for fixed bodies only (it has no finite volume or mass)")
                .got("type = \"plane\" on a body with fixed = false")
                .hint("set `fixed = true` on this body"));
        }
        let mass = self.mass_properties(doc, shape.as_ref(), fixed, &name)?;
        let mut body = RigidBody::new(name, mass);
        body.fixed = fixed;
        body.shape = shape;
        self.state(doc, &mut body)?;
        body.material = Material {
            restitution: self.ranged(
                "restitution",
                &doc.restitution,
                |e| (0.0..=1.0).contains(&e),
                "must be in [0, 1]",
            )?,
            friction: self.ranged("friction", &doc.friction, |f| f >= 0.0, "must be ≥ 0")?,
        };
        self.loads(doc, &mut body)?;
        body.gravity_scale = self.gravity_scale(doc)?;
        if fixed {
            self.reject_motion_of_fixed(doc)?;
        }
        Ok(body)
    }

    /// The mass rules: `density` + shape → both; `mass` + `inertia`/`inertia_tensor` → as given;
    /// `mass` + shape → the shape's inertia scaled to the mass; fixed bodies need neither (placeholder).
    fn mass_properties(
        &self,
        doc: &BodyDoc,
        shape: Option<&Shape>,
        fixed: bool,
        name: &str,
    ) -> Result<MassProperties, SceneError> {
        let mass = self.finite("mass", &doc.mass)?;
        let density = self.finite("density", &doc.density)?;
        let inertia = self.finite3("inertia", &doc.inertia)?;
        let tensor = match &doc.inertia_tensor {
            Some(l) if l.value.iter().flatten().any(|x| !x.is_finite()) => {
                return Err(self.err("inertia_tensor", l, "must be finite").got(format!("{:?}", l.value)));
            }
            Some(l) => Some(l.value),
            None => None,
        };
        if let (Some(_), Some(l)) = (mass, &doc.density) {
            return Err(self.err("density", l, "give `mass` or `density`, not both"));
        }
        if let (Some(_), Some(l)) = (inertia, &doc.inertia_tensor) {
            return Err(self.err(
                "inertia_tensor",
                l,
                "give `inertia` (principal moments) or `inertia_tensor`, not both",
            ));
        }
        let inertia_key = if tensor.is_some() { "inertia_tensor" } else { "inertia" };
        let inertia_span = doc.inertia.as_ref().map(|l| &l.span).or(doc.inertia_tensor.as_ref().map(|l| &l.span));
        let inertia_err =
            |problem: String| self.src.error(inertia_span.and_then(|s| s.as_ref()), self.at(inertia_key), problem);

        if let (Some(rho), Some(l)) = (density, &doc.density) {
            if rho <= 0.0 {
                return Err(self.err("density", l, "must be > 0 (kg/m³)").got(num(rho)));
            }
            if inertia_span.is_some() {
                return Err(inertia_err(format!(
                    "`density` computes the inertia from the shape; give `{inertia_key}` with `mass` instead"
                )));
            }
            let Some((m, tensor)) = shape.and_then(|s| s.inertia_tensor(rho)) else {
                let why = if shape.is_some() { "a plane has no volume" } else { "there is no shape" };
                return Err(self.err("density", l, format!("cannot compute a mass from a density: {why}")).hint(
                    "give a shape with a volume (sphere, box, capsule, cylinder, mesh, convex, or `shapes`), \
                     or `mass` and `inertia`",
                ));
            };
            return MassProperties::from_tensor(m, tensor)
                .map_err(|e| self.err("density", l, format!("gives unusable mass properties: {e}")).got(num(rho)));
        }
        if let (Some(m), Some(l)) = (mass, &doc.mass) {
            if m <= 0.0 {
                return Err(self
                    .err("mass", l, "must be > 0 (kg)")
                    .got(num(m))
                    .hint("a body that must not move is written `fixed = true`"));
            }
            if let Some(moments) = inertia {
                return MassProperties::from_principal(m, moments).map_err(|e| inertia_err(e.to_string()));
            }
            if let Some(rows) = tensor {
                let tensor_user = DMat3::from_cols_array_2d(&rows).transpose();
                return MassProperties::from_tensor(m, tensor_user).map_err(|e| inertia_err(e.to_string()));
            }
            return match shape.and_then(|s| s.inertia_tensor(1.0)) {
                // the shape's inertia at unit density, scaled to the given mass
                Some((m1, tensor1)) => MassProperties::from_tensor(m, tensor1 * (m / m1)).map_err(|e| {
                    self.err("mass", l, format!("with this shape gives unusable inertia: {e}")).got(num(m))
                }),
                None => Err(self.err("mass", l, "there is no inertia for this mass").hint(
                    "give `inertia` (principal moments, kg·m²), `inertia_tensor`, or a shape to compute it from",
                )),
            };
        }
        if inertia_span.is_some() {
            return Err(inertia_err(format!("`{inertia_key}` needs `mass` (kg)")));
        }
        if fixed {
            // a fixed body is never integrated: its mass properties are a placeholder
            return Ok(MassProperties::from_principal(1.0, DVec3::ONE).expect("unit mass properties are valid"));
        }
        Err(self
            .src
            .error(self.span, self.at("mass"), format!("missing: body `{name}` moves (fixed = false) and needs a mass"))
            .hint(
                "give `mass` (kg) with `inertia` or a shape, or `density` (kg/m³) with a shape, or set `fixed = true`",
            ))
    }

    /// Position, orientation, velocity and angular velocity.
    fn state(&mut self, doc: &BodyDoc, body: &mut RigidBody) -> Result<(), SceneError> {
        if let Some(p) = self.bounded3("position", &doc.position, MAX_POSITION, "m")? {
            body.state.position = p;
        }
        // always set through the user's axes: with a diagonalised tensor, "no rotation" means the
        // user's axes are the world's, not the principal axes
        let world_from_user = self.orientation(doc)?.unwrap_or(DQuat::IDENTITY);
        body.set_orientation_user(world_from_user);
        if let Some(v) = self.bounded3("velocity", &doc.velocity, MAX_SPEED, "m/s")? {
            body.state.velocity = v;
        }
        let omega_world = self.bounded3("angular_velocity", &doc.angular_velocity, MAX_ANGULAR_SPEED, "rad/s")?;
        let omega_user =
            self.bounded3("angular_velocity_body", &doc.angular_velocity_body, MAX_ANGULAR_SPEED, "rad/s")?;
        match (omega_world, omega_user, &doc.angular_velocity_body) {
            (Some(_), Some(_), Some(l)) => {
                return Err(self.err(
                    "angular_velocity_body",
                    l,
                    "give `angular_velocity` (world frame) or `angular_velocity_body` (body axes), not both",
                ))
            }
            (Some(w), _, _) => body.set_omega_world(w),
            (None, Some(w), _) => body.set_omega_user(w),
            _ => {}
        }
        Ok(())
    }

    /// `orientation = [w, x, y, z]`, `world_from_user`; see the tolerances in the module's constants.
    fn orientation(&mut self, doc: &BodyDoc) -> Result<Option<DQuat>, SceneError> {
        doc.orientation.as_ref().map(|l| self.quaternion("orientation", l)).transpose()
    }

    /// A unit quaternion `[w, x, y, z]` at `key`: normalised silently within
    /// `QUAT_SILENT_TOLERANCE`, with a warning within `QUAT_WARN_TOLERANCE`, else an error.
    pub(super) fn quaternion(&mut self, key: &str, l: &Loc<[f64; 4]>) -> Result<DQuat, SceneError> {
        let [w, x, y, z] = l.value;
        if l.value.iter().any(|c| !c.is_finite()) {
            return Err(self.err(key, l, "must be finite (a quaternion [w, x, y, z])").got(nums(&l.value)));
        }
        let norm = (w * w + x * x + y * y + z * z).sqrt();
        if norm == 0.0 {
            return Err(self
                .err(key, l, "must be a unit quaternion [w, x, y, z], not zero")
                .got(nums(&l.value))
                .hint("the identity (no rotation) is [1, 0, 0, 0]"));
        }
        let unit = [w / norm, x / norm, y / norm, z / norm];
        let deviation = (norm - 1.0).abs();
        if deviation > QUAT_WARN_TOLERANCE {
            return Err(self
                .err(key, l, format!("must be a unit quaternion [w, x, y, z] (|q| = {norm})"))
                .got(nums(&l.value))
                .hint(format!("normalised it is {}; write that if it is what you meant", nums(&unit))));
        }
        if deviation > QUAT_SILENT_TOLERANCE {
            let text = format!("not a unit quaternion (|q| = {norm}); normalised to {}", nums(&unit));
            self.warnings.push(self.src.warning(l.span.as_ref(), &self.at(key), &text));
        }
        Ok(DQuat::from_xyzw(unit[1], unit[2], unit[3], unit[0]))
    }

    /// `gravity_scale`: any finite factor (negative: the body falls upwards), with `|scale · g|`
    /// within the bound on the world's gravity.
    fn gravity_scale(&self, doc: &BodyDoc) -> Result<f64, SceneError> {
        let Some(scale) = self.finite("gravity_scale", &doc.gravity_scale)? else { return Ok(1.0) };
        let g = scale.abs() * self.gravity.length();
        if let (Some(l), true) = (&doc.gravity_scale, g > MAX_GRAVITY) {
            return Err(self
                .err("gravity_scale", l, format!("gives |g| = {g:e} m/s², above the limit of {MAX_GRAVITY:e} m/s²"))
                .got(num(scale)));
        }
        Ok(scale)
    }

    /// Forces, torques, damping and point forces; `_body` vectors and points go to principal axes.
    fn loads(&self, doc: &BodyDoc, body: &mut RigidBody) -> Result<(), SceneError> {
        let body_from_user = body.mass.user_from_body.conjugate();
        let loads = &mut body.loads;
        loads.force_world = self.finite3("force", &doc.force)?.unwrap_or(DVec3::ZERO);
        loads.force_body = body_from_user * self.finite3("force_body", &doc.force_body)?.unwrap_or(DVec3::ZERO);
        loads.torque_world = self.finite3("torque", &doc.torque)?.unwrap_or(DVec3::ZERO);
        loads.torque_body = body_from_user * self.finite3("torque_body", &doc.torque_body)?.unwrap_or(DVec3::ZERO);
        let nonneg = |x: f64| x >= 0.0;
        loads.linear_damping =
            self.ranged("linear_damping", &doc.linear_damping, nonneg, "must be ≥ 0 (1/s)")?.unwrap_or(0.0);
        loads.angular_damping =
            self.ranged("angular_damping", &doc.angular_damping, nonneg, "must be ≥ 0 (1/s)")?.unwrap_or(0.0);
        for (k, pf) in doc.point_force.iter().enumerate() {
            loads.point_forces.push(self.point_force(k, pf, body_from_user)?);
        }
        Ok(())
    }

    fn point_force(
        &self,
        k: usize,
        loc: &Loc<Table<PointForceDoc>>,
        body_from_user: DQuat,
    ) -> Result<PointForce, SceneError> {
        let key = |field: &str| format!("point_force[{k}].{field}");
        let pf = &loc.value;
        let Some(point_user) = self.finite3(&key("point"), &pf.point)? else {
            return Err(self.err(
                &format!("point_force[{k}]"),
                loc,
                "missing `point` (body axes, relative to the centre of mass, m)",
            ));
        };
        let force = self.finite3(&key("force"), &pf.force)?;
        let force_body = self.finite3(&key("force_body"), &pf.force_body)?;
        let (force, frame) = match (force, force_body, &pf.force_body) {
            (Some(_), Some(_), Some(l)) => {
                return Err(self.err(
                    &key("force_body"),
                    l,
                    "give `force` (world frame) or `force_body` (body axes), not both",
                ))
            }
            (Some(f), _, _) => (f, Frame::World),
            (None, Some(f), _) => (body_from_user * f, Frame::Body),
            _ => {
                return Err(self.err(
                    &format!("point_force[{k}]"),
                    loc,
                    "missing `force` (world frame, N) or `force_body` (body axes, N)",
                ))
            }
        };
        Ok(PointForce { point_body: body_from_user * point_user, force, frame })
    }

    /// A fixed body never moves: a velocity or a load on it would be silently ignored, so it is an error.
    fn reject_motion_of_fixed(&self, doc: &BodyDoc) -> Result<(), SceneError> {
        let vectors = [
            ("velocity", &doc.velocity),
            ("angular_velocity", &doc.angular_velocity),
            ("angular_velocity_body", &doc.angular_velocity_body),
            ("force", &doc.force),
            ("force_body", &doc.force_body),
            ("torque", &doc.torque),
            ("torque_body", &doc.torque_body),
        ];
        for (key, loc) in vectors {
            if let Some(l) = loc.as_ref().filter(|l| l.value != [0.0; 3]) {
                return Err(self.err(key, l, "a fixed body never moves, so this would be ignored").got(nums(&l.value)));
            }
        }
        for (key, loc) in [("linear_damping", &doc.linear_damping), ("angular_damping", &doc.angular_damping)] {
            if let Some(l) = loc.as_ref().filter(|l| l.value != 0.0) {
                return Err(self.err(key, l, "a fixed body never moves, so this would be ignored").got(num(l.value)));
            }
        }
        if let Some(l) = doc.gravity_scale.as_ref().filter(|l| l.value != 1.0) {
            return Err(self
                .err("gravity_scale", l, "a fixed body never moves, so this would be ignored")
                .got(num(l.value)));
        }
        if let Some(l) = doc.point_force.first() {
            return Err(self.err("point_force[0]", l, "a fixed body never moves, so this would be ignored"));
        }
        Ok(())
    }
}
