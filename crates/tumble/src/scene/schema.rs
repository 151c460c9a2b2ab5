//! The scene file as written: serde structures that mirror `docs/scene-format.md` key for key.
//!
//! Every struct denies unknown keys. Every value is wrapped in [`Loc`], which keeps the byte span
//! of the value in a TOML file, so that errors found after parsing (a negative mass, a duplicate
//! name) still point at the line and column of the offending value. JSON gives no spans; there the
//! field path stands in for the position.
//!
//! Nothing here checks ranges or finiteness: that is `build`'s work, which knows what each value means.

use serde::de::Deserializer;
use serde::Deserialize;
use std::cell::Cell;
use std::ops::Range;

thread_local! {
    /// Whether the deserializer running on this thread is `toml`'s, which understands the
    /// `Spanned` protocol. `serde_json` does not: asking it for a span fails on plain numbers.
    static SPANS: Cell<bool> = const { Cell::new(false) };
}

/// While alive, [`Loc`] values deserialized on this thread ask the deserializer for their span.
pub(crate) struct SpanGuard {
    previous: bool,
}

impl SpanGuard {
    pub(crate) fn enable() -> Self {
        Self { previous: SPANS.with(|s| s.replace(true)) }
    }
}

impl Drop for SpanGuard {
    fn drop(&mut self) {
        SPANS.with(|s| s.set(self.previous));
    }
}

/// A value and, for TOML files, the byte range it occupies in the text.
#[derive(Debug, Clone, PartialEq)]
pub struct Loc<T> {
    /// The value as parsed.
    pub value: T,
    /// Byte range in the source text (TOML only).
    pub span: Option<Range<usize>>,
}

impl<'de, T: Deserialize<'de>> Deserialize<'de> for Loc<T> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        if SPANS.with(|s| s.get()) {
            let spanned = toml::Spanned::<T>::deserialize(deserializer)?;
            let span = spanned.span();
            Ok(Loc { value: spanned.into_inner(), span: Some(span) })
        } else {
            Ok(Loc { value: T::deserialize(deserializer)?, span: None })
        }
    }
}

/// A table (`{...}` in JSON): serde would also read a struct from an array, by position, which
/// would accept `body = [["a", 1.0]]`; this wrapper accepts only tables.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Table<T>(pub T);

impl<T> std::ops::Deref for Table<T> {
    type Target = T;
    fn deref(&self) -> &T {
        &self.0
    }
}

impl<'de, T: Deserialize<'de>> Deserialize<'de> for Table<T> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct TableVisitor<T>(std::marker::PhantomData<T>);
        impl<'de, T: Deserialize<'de>> serde::de::Visitor<'de> for TableVisitor<T> {
            type Value = Table<T>;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a table (an object in JSON)")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, map: A) -> Result<Table<T>, A::Error> {
                T::deserialize(serde::de::value::MapAccessDeserializer::new(map)).map(Table)
            }
        }
        deserializer.deserialize_map(TableVisitor(std::marker::PhantomData))
    }
}

/// A three-vector as written in files, `[x, y, z]`.
pub type Vec3Doc = Loc<[f64; 3]>;

/// The whole file.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneDoc {
    /// Format version; required, must be 1.
    pub version: Option<Loc<i64>>,
    /// `[world]`: settings (defaults from `WorldConfig::default()`).
    pub world: Option<Loc<Table<WorldDoc>>>,
    /// `[[body]]`: the bodies, in order.
    #[serde(default)]
    pub body: Vec<Loc<Table<BodyDoc>>>,
    /// `[[grid]]`: generated blocks of identical bodies, appended after the `[[body]]` entries.
    #[serde(default)]
    pub grid: Vec<Loc<Table<GridDoc>>>,
    /// `[[robot]]`: URDF trees (see [`RobotDoc`]).
    #[serde(default)]
    pub robot: Vec<Loc<Table<RobotDoc>>>,
}

impl SceneDoc {
    /// Whether the document has no key at all (an empty file).
    pub fn is_empty(&self) -> bool {
        self.version.is_none()
            && self.world.is_none()
            && self.body.is_empty()
            && self.grid.is_empty()
            && self.robot.is_empty()
    }
}

/// `[world]`.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WorldDoc {
    /// m/s², world frame.
    pub gravity: Option<Vec3Doc>,
    /// s.
    pub dt: Option<Loc<f64>>,
    /// s.
    pub duration: Option<Loc<f64>>,
    pub integrator: Option<Loc<String>>,
    pub rtol: Option<Loc<f64>>,
    pub atol: Option<Loc<f64>>,
    pub sample_every: Option<Loc<u64>>,
    /// Threads of the collision detection, ≥ 0 (0: one per core).
    pub threads: Option<Loc<i64>>,
    /// Contacts on or off (default on).
    pub contacts: Option<Loc<bool>>,
    /// Default restitution of bodies that give none, [0, 1].
    pub restitution: Option<Loc<f64>>,
    /// Default friction of bodies that give none, ≥ 0.
    pub friction: Option<Loc<f64>>,
    /// `stronge` | `newton` | `poisson`.
    pub restitution_law: Option<Loc<String>>,
    /// m/s: approach speed above which a contact is a collision.
    pub impact_speed: Option<Loc<f64>>,
    /// Solver passes per substep of the resting-contact solver.
    pub contact_iterations: Option<Loc<u32>>,
    /// `point` | `manifold`: friction at every contact point, or one disc and twist per manifold.
    pub friction_model: Option<Loc<String>>,
    /// Fraction of the smaller shape's bounding radius a pair may move while its manifold is kept.
    pub manifold_reuse: Option<Loc<f64>>,
    /// Substeps of the resting-contact solver per step.
    pub contact_substeps: Option<Loc<u32>>,
    /// m: overlap left uncorrected.
    pub contact_slop: Option<Loc<f64>>,
    /// Hz: frequency of the spring that removes overlap.
    pub contact_hertz: Option<Loc<f64>>,
    /// Damping ratio of that spring.
    pub contact_damping_ratio: Option<Loc<f64>>,
    /// m/s: largest speed of the overlap correction.
    pub max_correction_speed: Option<Loc<f64>>,
    /// Islands at rest fall asleep (default on).
    pub sleep: Option<Loc<bool>>,
    /// m/s: speed below which a body is still.
    pub sleep_speed: Option<Loc<f64>>,
    /// s: time an island must be still before it falls asleep.
    pub sleep_time: Option<Loc<f64>>,
    /// The most candidate contact pairs of a step (default: 32 per body + 10,000).
    pub max_pairs: Option<Loc<u64>>,
}

/// One `[[body]]` (or the template `[grid.body]`).
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodyDoc {
    pub name: Option<Loc<String>>,
    /// kg.
    pub mass: Option<Loc<f64>>,
    /// kg/m³, with a shape.
    pub density: Option<Loc<f64>>,
    /// Principal moments about the centre of mass, user's body axes (kg·m²).
    pub inertia: Option<Vec3Doc>,
    /// Full symmetric tensor about the centre of mass, user's body axes (kg·m²), rows.
    pub inertia_tensor: Option<Loc<[[f64; 3]; 3]>>,
    pub shape: Option<Loc<Table<ShapeDoc>>>,
    /// A compound: several shapes, each with its `position` and `orientation` (not with `shape`).
    pub shapes: Option<Loc<Vec<Loc<Table<ShapeDoc>>>>>,
    /// Centre of mass, world frame (m).
    pub position: Option<Vec3Doc>,
    /// `world_from_user`, `[w, x, y, z]`.
    pub orientation: Option<Loc<[f64; 4]>>,
    /// World frame (m/s).
    pub velocity: Option<Vec3Doc>,
    /// World frame (rad/s).
    pub angular_velocity: Option<Vec3Doc>,
    /// User's body axes (rad/s).
    pub angular_velocity_body: Option<Vec3Doc>,
    pub fixed: Option<Loc<bool>>,
    pub restitution: Option<Loc<f64>>,
    pub friction: Option<Loc<f64>>,
    /// World frame, at the centre of mass (N).
    pub force: Option<Vec3Doc>,
    /// User's body axes, at the centre of mass (N).
    pub force_body: Option<Vec3Doc>,
    /// World frame (N·m).
    pub torque: Option<Vec3Doc>,
    /// User's body axes (N·m).
    pub torque_body: Option<Vec3Doc>,
    /// 1/s.
    pub linear_damping: Option<Loc<f64>>,
    /// 1/s.
    pub angular_damping: Option<Loc<f64>>,
    /// Factor on the world's gravity for this body (default 1).
    pub gravity_scale: Option<Loc<f64>>,
    /// Names of bodies this body never collides with.
    pub no_collide: Option<Loc<Vec<String>>>,
    /// `[[body.point_force]]`.
    #[serde(default)]
    pub point_force: Vec<Loc<Table<PointForceDoc>>>,
}

/// `shape = { type = "...", ... }`, or one part of `shapes = [...]`; which sizes a type needs is
/// checked when building.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ShapeDoc {
    #[serde(rename = "type")]
    pub kind: Loc<String>,
    /// m (sphere, capsule, cylinder).
    pub radius: Option<Loc<f64>>,
    /// m (box).
    pub half_extents: Option<Vec3Doc>,
    /// m (capsule, cylinder).
    pub half_height: Option<Loc<f64>>,
    /// Mesh file (.obj, .stl), relative to the scene file's directory (mesh).
    pub file: Option<Loc<String>>,
    /// Factor on the mesh file's coordinates: one number or one per axis (mesh).
    pub scale: Option<Loc<ScaleDoc>>,
    /// Points whose convex hull is the shape (convex), m.
    pub points: Option<Loc<Vec<Vec3Doc>>>,
    /// A compound's part only: where the part's origin sits in the compound's coordinates (m).
    pub position: Option<Vec3Doc>,
    /// A compound's part only: `compound_from_part`, `[w, x, y, z]`.
    pub orientation: Option<Loc<[f64; 4]>>,
}

/// `scale = 0.001` or `scale = [sx, sy, sz]`.
#[derive(Debug, Clone, PartialEq)]
pub struct ScaleDoc(pub [f64; 3]);

impl<'de> Deserialize<'de> for ScaleDoc {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct ScaleVisitor;
        impl<'de> serde::de::Visitor<'de> for ScaleVisitor {
            type Value = ScaleDoc;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a number or an array of three numbers")
            }
            fn visit_f64<E: serde::de::Error>(self, x: f64) -> Result<ScaleDoc, E> {
                Ok(ScaleDoc([x; 3]))
            }
            fn visit_i64<E: serde::de::Error>(self, x: i64) -> Result<ScaleDoc, E> {
                Ok(ScaleDoc([x as f64; 3]))
            }
            fn visit_u64<E: serde::de::Error>(self, x: u64) -> Result<ScaleDoc, E> {
                Ok(ScaleDoc([x as f64; 3]))
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(self, seq: A) -> Result<ScaleDoc, A::Error> {
                <[f64; 3]>::deserialize(serde::de::value::SeqAccessDeserializer::new(seq)).map(ScaleDoc)
            }
        }
        deserializer.deserialize_any(ScaleVisitor)
    }
}

/// `[[body.point_force]]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointForceDoc {
    /// Point of application relative to the centre of mass, user's body axes (m).
    pub point: Option<Vec3Doc>,
    /// World frame (N).
    pub force: Option<Vec3Doc>,
    /// User's body axes (N).
    pub force_body: Option<Vec3Doc>,
}

/// `[[grid]]`: `count[0] × count[1] × count[2]` copies of `body`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GridDoc {
    /// Copies along world x, y, z.
    pub count: Loc<[u64; 3]>,
    /// Distance between neighbours along world x, y, z (m).
    pub spacing: Option<Vec3Doc>,
    /// Position of copy `(0, 0, 0)`, world frame (m).
    pub origin: Option<Vec3Doc>,
    /// The template; its `name` becomes `name_i_j_k`.
    pub body: Loc<Table<BodyDoc>>,
}

/// One `[[robot]]`.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RobotDoc {
    /// Unique among bodies and robots.
    pub name: Option<Loc<String>>,
    /// URDF file, relative to the scene file's directory.
    pub urdf: Option<Loc<String>>,
    /// MJCF file (MuJoCo's XML), relative to the scene file's directory; instead of `urdf`.
    pub mjcf: Option<Loc<String>>,
    /// The controls of the MJCF file's actuators, held over the run: one number for every
    /// actuator, or a table by actuator name (the others 0, as MuJoCo starts them).
    pub ctrl: Option<Loc<CtrlDoc>>,
    /// What of the MJCF file the robot leaves out: `"world"` (the geometry fixed to the world)
    /// and bodies with a free joint and no child bodies, by name (`tumble run X.xml` makes those
    /// scene bodies).
    pub leave_out: Option<Loc<Vec<Loc<String>>>>,
    /// The MJCF file's `<keyframe><key>` to start from (by name, or an unnamed key's index): its
    /// state and controls, under what `q`, `v`, `ctrl`, `position` and `orientation` give.
    pub keyframe: Option<Loc<String>>,
    /// `"fixed"` (default) or `"floating"`.
    pub base: Option<Loc<String>>,
    /// Root link frame's origin, world frame (m).
    pub position: Option<Vec3Doc>,
    /// `world_from_root`, `[w, x, y, z]`.
    pub orientation: Option<Loc<[f64; 4]>>,
    /// Initial configuration by joint name (a number, or an array for spherical/floating joints).
    pub q: Option<Loc<JointTable<Loc<JointValue>>>>,
    /// Initial velocity by joint name.
    pub v: Option<Loc<JointTable<Loc<JointValue>>>>,
    /// Viscous damping: a number for every one-coordinate joint, `"urdf"`, or a table by joint name.
    pub damping: Option<Loc<DampingDoc>>,
    /// Constant joint forces by joint name (N·m, N; arrays for spherical/floating joints).
    pub torque: Option<Loc<JointTable<Loc<JointValue>>>>,
    /// PD targets by joint name.
    pub pd: Option<Loc<JointTable<Loc<Table<PdDoc>>>>>,
    /// Replace a link inertia that is not physical by the nearest physical one (reported per link).
    pub balance_inertia: Option<Loc<bool>>,
    /// Joints held at their initial value: the model reduced, their coordinates removed from `q` and `v`.
    pub lock: Option<Loc<Vec<Loc<String>>>>,
    /// Directories (relative to the scene file) that hold packages, searched for `package://NAME/`
    /// after the URDF's parent directories.
    pub package_paths: Option<Loc<Vec<Loc<String>>>>,
    /// Enforce the URDF `<limit lower upper>` of revolute and prismatic joints (default true).
    pub joint_limits: Option<Loc<bool>>,
    /// Clamp commanded joint forces (constant, PD, `set_torque`) to the URDF `effort` (default true).
    pub effort_limits: Option<Loc<bool>>,
    /// Links collide through their URDF `<collision>` geometry (default true).
    pub collision: Option<Loc<bool>>,
    /// The robot's own links collide with each other too (default false).
    pub self_collision: Option<Loc<bool>>,
    /// Link pairs `["a", "b"]` that never collide; `["link"]` takes a link out of all contact.
    pub no_collide: Option<Loc<Vec<Vec<String>>>>,
    /// Coulomb friction of every link, ≥ 0 (else the world's default).
    pub friction: Option<Loc<f64>>,
    /// Restitution of every link, [0, 1] (else the world's default).
    pub restitution: Option<Loc<f64>>,
}

/// `{ joint_name = value, ... }`, in the file's order (duplicate names are refused).
#[derive(Debug, Clone, PartialEq)]
pub struct JointTable<T>(pub Vec<(String, T)>);

impl<T> Default for JointTable<T> {
    fn default() -> Self {
        Self(Vec::new())
    }
}

impl<'de, T: Deserialize<'de>> Deserialize<'de> for JointTable<T> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct V<T>(std::marker::PhantomData<T>);
        impl<'de, T: Deserialize<'de>> serde::de::Visitor<'de> for V<T> {
            type Value = JointTable<T>;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a table of joint names")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, mut map: A) -> Result<JointTable<T>, A::Error> {
                let mut out: Vec<(String, T)> = Vec::new();
                while let Some(key) = map.next_key::<String>()? {
                    if out.iter().any(|(k, _)| *k == key) {
                        return Err(serde::de::Error::custom(format!("joint `{key}` is given twice")));
                    }
                    let value = map.next_value::<T>()?;
                    out.push((key, value));
                }
                Ok(JointTable(out))
            }
        }
        deserializer.deserialize_map(V(std::marker::PhantomData))
    }
}

/// A joint's value: one number, or an array (spherical: 4 or 3, floating: 7 or 6 entries).
#[derive(Debug, Clone, PartialEq)]
pub struct JointValue(pub Vec<f64>);

impl<'de> Deserialize<'de> for JointValue {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = JointValue;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a number or an array of numbers")
            }
            fn visit_f64<E: serde::de::Error>(self, x: f64) -> Result<JointValue, E> {
                Ok(JointValue(vec![x]))
            }
            fn visit_i64<E: serde::de::Error>(self, x: i64) -> Result<JointValue, E> {
                Ok(JointValue(vec![x as f64]))
            }
            fn visit_u64<E: serde::de::Error>(self, x: u64) -> Result<JointValue, E> {
                Ok(JointValue(vec![x as f64]))
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(self, mut seq: A) -> Result<JointValue, A::Error> {
                let mut out = Vec::new();
                while let Some(x) = seq.next_element::<f64>()? {
                    if out.len() >= 16 {
                        return Err(serde::de::Error::custom("too many numbers (a joint has at most 7)"));
                    }
                    out.push(x);
                }
                Ok(JointValue(out))
            }
        }
        deserializer.deserialize_any(V)
    }
}

/// `ctrl = 0.5` or `ctrl = { actuator = 0.5, ... }`.
#[derive(Debug, Clone, PartialEq)]
pub enum CtrlDoc {
    /// The same control for every actuator.
    All(f64),
    /// By actuator name (others: 0).
    Actuators(JointTable<Loc<f64>>),
}

impl<'de> Deserialize<'de> for CtrlDoc {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = CtrlDoc;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a number or a table of actuator names")
            }
            fn visit_f64<E: serde::de::Error>(self, x: f64) -> Result<CtrlDoc, E> {
                Ok(CtrlDoc::All(x))
            }
            fn visit_i64<E: serde::de::Error>(self, x: i64) -> Result<CtrlDoc, E> {
                Ok(CtrlDoc::All(x as f64))
            }
            fn visit_u64<E: serde::de::Error>(self, x: u64) -> Result<CtrlDoc, E> {
                Ok(CtrlDoc::All(x as f64))
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, map: A) -> Result<CtrlDoc, A::Error> {
                JointTable::deserialize(serde::de::value::MapAccessDeserializer::new(map)).map(CtrlDoc::Actuators)
            }
        }
        deserializer.deserialize_any(V)
    }
}

/// `damping = 0.1`, `damping = "urdf"` or `damping = { joint = 0.1, ... }`.
#[derive(Debug, Clone, PartialEq)]
pub enum DampingDoc {
    /// The same coefficient for every one-coordinate joint.
    All(f64),
    /// Each joint's `<dynamics damping>` from the URDF.
    Urdf,
    /// By joint name (others: 0).
    Joints(JointTable<Loc<f64>>),
    /// Any other string (an error when building).
    Other(String),
}

impl<'de> Deserialize<'de> for DampingDoc {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> serde::de::Visitor<'de> for V {
            type Value = DampingDoc;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a number, \"urdf\" or a table of joint names")
            }
            fn visit_f64<E: serde::de::Error>(self, x: f64) -> Result<DampingDoc, E> {
                Ok(DampingDoc::All(x))
            }
            fn visit_i64<E: serde::de::Error>(self, x: i64) -> Result<DampingDoc, E> {
                Ok(DampingDoc::All(x as f64))
            }
            fn visit_u64<E: serde::de::Error>(self, x: u64) -> Result<DampingDoc, E> {
                Ok(DampingDoc::All(x as f64))
            }
            fn visit_str<E: serde::de::Error>(self, s: &str) -> Result<DampingDoc, E> {
                Ok(if s == "urdf" { DampingDoc::Urdf } else { DampingDoc::Other(s.to_string()) })
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(self, map: A) -> Result<DampingDoc, A::Error> {
                JointTable::deserialize(serde::de::value::MapAccessDeserializer::new(map)).map(DampingDoc::Joints)
            }
        }
        deserializer.deserialize_any(V)
    }
}

/// `pd = { joint = { target = .., kp = .., kd = .. } }`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PdDoc {
    /// Position target (rad or m).
    pub target: Option<Loc<f64>>,
    /// Velocity target (rad/s or m/s), default 0.
    pub target_velocity: Option<Loc<f64>>,
    /// Proportional gain (N·m/rad or N/m), ≥ 0.
    pub kp: Option<Loc<f64>>,
    /// Derivative gain (N·m·s/rad or N·s/m), ≥ 0.
    pub kd: Option<Loc<f64>>,
    /// A periodic target, `target + amplitude sin(2π frequency t + phase)` (rad or m).
    pub amplitude: Option<Loc<f64>>,
    /// Its frequency (Hz), > 0; required with `amplitude`.
    pub frequency: Option<Loc<f64>>,
    /// Its phase (rad), default 0.
    pub phase: Option<Loc<f64>>,
}
