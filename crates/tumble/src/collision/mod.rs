//! Collision geometry: the only module that talks to `parry3d-f64`.
//!
//! What it computes, once per step, from the bodies' poses and velocities at the start of the step:
//! the list of [`Contact`]s — body pairs whose shapes touch, overlap, or come within the distance
//! they can close during the step (so that fast bodies are caught before they pass through thin
//! walls: a *speculative* contact, Catto 2013, "Continuous collision", GDC).
//!
//! Stages:
//! 1. **Shapes → parry shapes** ([`Colliders::new`], once): sphere → `Ball`, box → `Cuboid`,
//!    capsule → `Capsule` (axis body z), cylinder → `Cylinder` (parry's axis is y: rotated to z),
//!    plane → `HalfSpace` (outward normal body +z), convex → `ConvexPolyhedron`, compound →
//!    `Compound` of its parts; a mesh → `TriMesh` on a fixed body, else the `Compound` of its convex
//!    decomposition when it has one, else its convex hull ([`parry_shape`]).
//! 2. **Broad phase** (module `broad`): the pairs whose *swept* bounding boxes overlap (a box at the
//!    start of the step grown by the distance it can travel in `dt`, `|v| dt + |ω| ρ dt +
//!    ½|g_body| dt²`, `ρ` the bounding radius, `g_body` the body's gravity `gravity_scale · g`),
//!    found with a uniform grid: each box in the cell of its lower corner, each cell tested against
//!    its neighbours once, the few boxes much wider than the mean against the cells they cover.
//!    Pairs of fixed bodies are never tested; planes (unbounded) are paired with every free body.
//!    Cost `O(n + cells + tests)`, about 14 box tests per box in a pile.
//! 3. **Narrow phase**: parry's contact manifold of each candidate pair with a prediction distance
//!    equal to the two bodies' sweeps, giving up to four points with their signed distance. A pair
//!    of convex shapes (the common case) takes one convex–convex manifold, kept from step to step
//!    and reused, with its gaps computed again, while the pair has barely moved (module `pairs`:
//!    relative motion below 1e-4 of the shape); a pair with a compound
//!    or a triangle mesh takes parry's composite manifolds (one per pair of touching sub-shapes,
//!    module `composite`), with parry's workspace kept per pair from step to step.
//!
//! With a thread pool (the world's `threads`), the narrow phase shares its pairs out in chunks and
//! gathers the results in pair order (module `parallel`): the contacts are the same
//! bit for bit for any number of threads.
//!
//! Frames: every output is in the world frame. A body's shape is placed by its `world_from_user`
//! pose (shapes are given in the user's body axes, centred on the centre of mass).
//!
//! References: parry's `contact_manifolds`; C. Ericson, *Real-Time Collision Detection* (2005),
//! §7.1 (uniform grids).

mod broad;
mod overlap;
pub use overlap::{Overlap, DEEP_OVERLAP_DEPTH, DEEP_OVERLAP_FRACTION};
mod composite;
pub(crate) mod face_search;
mod hull;
pub mod links;
mod pairs;
mod parallel;
pub use pairs::{REUSE_FRACTION, REUSE_MARGIN};

pub use hull::{
    convex_decomposition, convex_hull, decomposition_parameters, mesh_hull_excess, VHACD_CONCAVITY, VHACD_MAX_PIECES,
    VHACD_RESOLUTION,
};

use crate::body::{RigidBody, Shape};
use crate::math::{DQuat, DVec3};
use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::math::Pose;
use parry3d_f64::shape::{SharedShape, TriMeshFlags};

/// Manifold points closer than this (m) are one point.
pub const DUPLICATE_DISTANCE: f64 = 1e-3;

/// The least distance (m) beyond the step's motion at which a pair is still tested: touching
/// bodies stay in the contact list even with no slop.
pub const PREDICTION_MARGIN: f64 = 1e-3;

/// One contact point between bodies `a` and `b` (indices into `World::bodies`), world frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// The first body (the normal points away from it).
    pub a: usize,
    /// The second body.
    pub b: usize,
    /// The contact point, midway between the two surfaces, world frame (m).
    pub point_world: DVec3,
    /// Unit normal from `a` towards `b`, world frame.
    pub normal_world: DVec3,
    /// Signed distance between the surfaces along the normal (m): negative when they overlap.
    pub gap: f64,
    /// The two touching features, stable from step to step (for warm starting): parry's feature id
    /// in the low 32 bits, the index of the sub-shape (part of a compound, triangle of a mesh; 0 for
    /// a convex shape) in the high 32 bits.
    pub features: (u64, u64),
}

/// A contact's feature key: the sub-shape's index above parry's feature id.
#[inline]
fn feature_key(subshape: u32, feature: u32) -> u64 {
    (u64::from(subshape) << 32) | u64::from(feature)
}

/// The collision shapes of the bodies and the buffers of the broad and narrow phases (reused from
/// step to step: no allocation once they have grown to the scene's size).
#[derive(Clone)]
pub struct Colliders {
    /// The parry shape of each body (same index), `None` for a body without a shape.
    shapes: Vec<Option<SharedShape>>,
    /// `user_from_shape`: the pose of the parry shape in the user's body axes.
    shape_offsets: Vec<Pose>,
    /// Bodies with a plane (paired with every free body).
    planes: Vec<usize>,
    /// Bounding radius of each shape about the centre of mass (m).
    radii: Vec<f64>,
    /// Pairs the scene excludes, `(min, max)` body indices, sorted.
    excluded: Vec<(usize, usize)>,
    aabbs: Vec<Aabb>,
    sweeps: Vec<f64>,
    /// Each body's shape pose in the world (`pose`), made by the broad phase with its box and kept
    /// with it; read by the narrow phase (one per body and step instead of one per pair).
    poses: Vec<Pose>,
    /// Per body, whether its box and sweep were made while it slept (module `broad`: a body asleep
    /// then and now keeps them), and the step settings `(dt, gravity, margin)` they were made with.
    made_asleep: Vec<bool>,
    broad_settings: Option<(f64, DVec3, f64)>,
    /// The broad phase's grid and buffers (module `broad`).
    grid: broad::Grid,
    pairs: Vec<(usize, usize)>,
    /// The manifold of each pair of convex shapes, kept across steps (module `pairs`).
    manifolds: pairs::PairManifolds,
    /// A pair's manifold is reused while it moved less than this fraction of its smaller shape.
    reuse_fraction: f64,
    /// Whether each body's parry shape is composite (a compound or a triangle mesh).
    composite: Vec<bool>,
    /// parry's manifolds and workspace of each pair with a composite shape, kept across steps.
    composite_pairs: composite::CompositePairs,
    /// The world's thread pool (`None`: one thread) and the buffers of its chunks (module `parallel`).
    pool: Option<std::sync::Arc<rayon::ThreadPool>>,
    /// With a pool, the narrow phase runs on it from this many candidate pairs on.
    parallel_min_pairs: usize,
    chunks: parallel::Chunks,
    /// The most candidate pairs the broad phase may find (module `broad`, "The budget").
    pair_budget: usize,
    /// The pairs found when the last broad phase went over the budget and stopped.
    over_budget: Option<usize>,
}

impl std::fmt::Debug for Colliders {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Colliders").field("shapes", &self.shapes.len()).field("planes", &self.planes).finish()
    }
}

/// The parry shape of a body's shape and its pose in the user's body axes; `fixed` for a fixed
/// body (a fixed mesh collides as its triangles, a moving one as convex pieces or its hull).
pub fn parry_shape(shape: &Shape, fixed: bool) -> (SharedShape, Pose) {
    match *shape {
        Shape::Sphere { radius } => (SharedShape::ball(radius), Pose::IDENTITY),
        Shape::Box { half_extents: h } => (SharedShape::cuboid(h.x, h.y, h.z), Pose::IDENTITY),
        Shape::Capsule { radius, half_height } => (SharedShape::capsule_z(half_height, radius), Pose::IDENTITY),
        Shape::Cylinder { radius, half_height } => {
            // parry's cylinder stands on its y axis: turn y onto z
            let y_to_z = DQuat::from_rotation_x(std::f64::consts::FRAC_PI_2);
            (SharedShape::cylinder(half_height, radius), Pose::from_rotation(y_to_z))
        }
        Shape::Plane => (SharedShape::halfspace(DVec3::Z), Pose::IDENTITY),
        // a mesh's vertices are about the centre of mass, body axes
        Shape::Mesh(ref mesh) => (mesh_shape(mesh, fixed), Pose::IDENTITY),
        Shape::Convex(ref convex) => (hull::mesh_hull(&convex.hull), Pose::IDENTITY),
        Shape::Compound(ref compound) => {
            let parts = compound
                .parts
                .iter()
                .map(|part| {
                    let (shape, offset) = parry_shape(&part.shape, fixed);
                    (Pose::from_parts(part.position, part.orientation) * offset, shape)
                })
                .collect();
            (SharedShape::compound(parts), Pose::IDENTITY)
        }
    }
}

/// A mesh's parry shape: the triangles for a fixed body; for a moving one the compound of its
/// convex pieces, or its hull.
fn mesh_shape(mesh: &crate::body::MeshShape, fixed: bool) -> SharedShape {
    if fixed {
        // internal edges fixed: a body sliding over two triangles of one face is not bumped by their edge
        let flags = TriMeshFlags::ORIENTED | TriMeshFlags::FIX_INTERNAL_EDGES;
        let vertices = mesh.mesh.vertices().to_vec();
        if let Ok(trimesh) = SharedShape::trimesh_with_flags(vertices, mesh.mesh.triangles().to_vec(), flags) {
            return trimesh;
        }
    } else if let Some(pieces) = &mesh.decomposition {
        let parts: Vec<_> = pieces.iter().filter_map(hull::piece_shape).map(|s| (Pose::IDENTITY, s)).collect();
        if !parts.is_empty() {
            return SharedShape::compound(parts);
        }
    }
    hull::mesh_hull(&mesh.mesh)
}

impl Colliders {
    /// The collision shapes of `bodies`.
    pub fn new(bodies: &[RigidBody]) -> Self {
        let mut c = Self {
            shapes: Vec::new(),
            shape_offsets: Vec::new(),
            planes: Vec::new(),
            radii: Vec::new(),
            excluded: Vec::new(),
            aabbs: Vec::new(),
            sweeps: Vec::new(),
            poses: Vec::new(),
            made_asleep: Vec::new(),
            broad_settings: None,
            grid: broad::Grid::default(),
            pairs: Vec::new(),
            manifolds: pairs::PairManifolds::default(),
            reuse_fraction: REUSE_FRACTION,
            composite: Vec::new(),
            composite_pairs: composite::CompositePairs::default(),
            pool: None,
            parallel_min_pairs: parallel::MIN_PAIRS,
            chunks: parallel::Chunks::default(),
            pair_budget: usize::MAX,
            over_budget: None,
        };
        c.rebuild(bodies);
        c
    }

    /// Rebuilds the shapes after bodies were added or removed.
    pub fn rebuild(&mut self, bodies: &[RigidBody]) {
        self.broad_settings = None;
        self.shapes.clear();
        self.shape_offsets.clear();
        self.planes.clear();
        self.radii.clear();
        self.composite.clear();
        self.composite_pairs.clear();
        self.manifolds.clear();
        for (i, body) in bodies.iter().enumerate() {
            let Some(shape) = &body.shape else {
                self.shapes.push(None);
                self.shape_offsets.push(Pose::IDENTITY);
                self.radii.push(0.0);
                self.composite.push(false);
                continue;
            };
            let (parry, offset) = parry_shape(shape, body.fixed);
            self.composite.push(parry.as_composite_shape().is_some());
            if matches!(shape, Shape::Plane) {
                self.planes.push(i);
                self.radii.push(0.0);
            } else {
                self.radii.push(parry.compute_local_bounding_sphere().radius() + offset.translation.length());
            }
            self.shapes.push(Some(parry));
            self.shape_offsets.push(offset);
        }
    }

    /// Sets the fraction of the smaller shape's bounding radius below which a pair's relative motion
    /// lets its manifold be reused ([`REUSE_FRACTION`] by default; 0: every manifold is made at every
    /// step, as before the manifolds were kept). A world's contact stage sets it at every step from
    /// [`ContactSettings::manifold_reuse`](crate::contact::ContactSettings::manifold_reuse): set
    /// that on a world.
    pub fn set_reuse_fraction(&mut self, fraction: f64) {
        self.reuse_fraction = fraction.max(0.0);
    }

    /// Runs the narrow phase on `pool`'s threads when it has at least `min_pairs` candidate pairs
    /// (`None`: 4,096), or on the caller's alone (always for a `pool` of `None`); the contacts are
    /// the same bit for bit either way.
    pub fn set_thread_pool(&mut self, pool: Option<&std::sync::Arc<rayon::ThreadPool>>, min_pairs: Option<usize>) {
        self.parallel_min_pairs = min_pairs.unwrap_or(parallel::MIN_PAIRS);
        let same = match (&self.pool, pool) {
            (Some(a), Some(b)) => std::sync::Arc::ptr_eq(a, b),
            (None, None) => true,
            _ => false,
        };
        if !same {
            self.pool = pool.cloned();
        }
    }

    /// The most candidate pairs the broad phase may find (no limit by default): beyond, it stops,
    /// finds no contact, and [`Self::pairs_over_budget`] says how many it had found.
    pub fn set_pair_budget(&mut self, budget: usize) {
        self.pair_budget = budget;
    }

    /// The pair budget ([`Self::set_pair_budget`]).
    pub fn pair_budget(&self) -> usize {
        self.pair_budget
    }

    /// The candidate pairs the last broad phase had found when it went over the pair budget and
    /// stopped (so that step found no contact), or `None` when it kept within it.
    pub fn pairs_over_budget(&self) -> Option<usize> {
        self.over_budget
    }

    /// Whether the bodies' shapes match what was built (same count).
    pub fn matches(&self, bodies: &[RigidBody]) -> bool {
        self.shapes.len() == bodies.len()
    }

    /// Excludes the pair of bodies `i` and `j` from collision.
    pub fn exclude_pair(&mut self, i: usize, j: usize) {
        let pair = (i.min(j), i.max(j));
        if let Err(at) = self.excluded.binary_search(&pair) {
            self.excluded.insert(at, pair);
        }
    }

    /// Whether the pair `(i, j)` is excluded from collision.
    pub fn is_excluded(&self, i: usize, j: usize) -> bool {
        !self.excluded.is_empty() && self.excluded.binary_search(&(i.min(j), i.max(j))).is_ok()
    }

    /// Body `i`'s parry shape, its pose in the world, its swept box (`None` for a plane) and its
    /// sweep (m) as this step's broad phase made them; `None` for a body without a shape.
    pub(crate) fn placed(&self, bodies: &[RigidBody], i: usize) -> Option<(&SharedShape, Pose, Option<&Aabb>, f64)> {
        let shape = self.shapes.get(i)?.as_ref()?;
        let aabb = if self.planes.contains(&i) { None } else { self.aabbs.get(i) };
        Some((shape, self.pose(bodies, i), aabb, self.sweeps.get(i).copied().unwrap_or(0.0)))
    }

    /// Body `i`'s parry shape (`None` for a body without one).
    pub(crate) fn shape(&self, i: usize) -> Option<&SharedShape> {
        self.shapes.get(i)?.as_ref()
    }

    /// The pose of body `i`'s parry shape in the world, `world_from_shape`.
    fn pose(&self, bodies: &[RigidBody], i: usize) -> Pose {
        let b = &bodies[i];
        Pose::from_parts(b.state.position, b.orientation_user()) * self.shape_offsets[i]
    }

    /// The radius of body `i`'s bounding sphere about its centre of mass (m); 0 for a plane or a
    /// body without a shape.
    pub fn radius(&self, i: usize) -> f64 {
        self.radii.get(i).copied().unwrap_or(0.0)
    }

    /// Finds every contact of the step into `out` (cleared first): pairs whose shapes are within
    /// the distance they can close during `dt` (s) under `gravity` (the world's, m/s², world frame,
    /// scaled by each body's `gravity_scale`), plus `slop` (m) or [`PREDICTION_MARGIN`], whichever
    /// is larger. None when the broad phase went over the pair budget ([`Self::set_pair_budget`]).
    pub fn find_contacts(&mut self, bodies: &[RigidBody], dt: f64, gravity: DVec3, slop: f64, out: &mut Vec<Contact>) {
        self.find_contacts_profiled(bodies, &[], dt, gravity, slop, out, None);
    }

    /// [`Self::find_contacts`], adding the time of the broad and narrow phases and the narrow
    /// phase's counts to `profile` when given.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn find_contacts_profiled(
        &mut self,
        bodies: &[RigidBody],
        asleep: &[bool],
        dt: f64,
        gravity: DVec3,
        slop: f64,
        out: &mut Vec<Contact>,
        profile: Option<&mut crate::profile::Profile>,
    ) {
        let mut clock = crate::profile::Clock::start(profile.is_some());
        out.clear();
        // a margin of at least a millimetre keeps touching pairs in the list whatever the slop
        // two bodies that are each asleep or fixed keep their contacts (`contact::sleep`)
        self.broad_phase(bodies, asleep, dt, gravity, slop.max(PREDICTION_MARGIN));
        let broad = clock.lap();
        if self.over_budget.is_some() {
            return;
        }
        let pairs = std::mem::take(&mut self.pairs);
        let mut manifolds = std::mem::take(&mut self.manifolds);
        manifolds.begin_step();
        let (convex, reused) = match self.pool.clone() {
            Some(pool) if pairs.len() >= self.parallel_min_pairs => {
                self.narrow_phase_parallel(&pool, bodies, &pairs, &mut manifolds, out)
            }
            _ => {
                let (mut convex, mut reused) = (0, 0);
                for &(i, j) in &pairs {
                    if self.composite[i] || self.composite[j] {
                        self.narrow_phase_composite(bodies, i, j, out);
                    } else {
                        convex += 1;
                        reused += u64::from(self.narrow_phase(bodies, manifolds.entry((i, j)), out));
                    }
                }
                (convex, reused)
            }
        };
        manifolds.end_step();
        self.manifolds = manifolds;
        self.pairs = pairs;
        self.composite_pairs.end_step();
        if let Some(p) = profile {
            p.broad_phase += broad;
            p.narrow_phase += clock.lap();
            p.pairs += convex;
            p.reused += reused;
            p.contacts += out.len() as u64;
        }
    }

    /// parry's contact manifold of the entry's pair of bodies (both convex), appended to `out` in the
    /// world frame: the pair's manifold of the last step when the pair has barely moved since it was
    /// made (module `pairs`), else made again. Whether it was reused.
    fn narrow_phase(&self, bodies: &[RigidBody], entry: &mut pairs::PairManifold, out: &mut Vec<Contact>) -> bool {
        let (i, j) = entry.pair();
        let (Some(shape_i), Some(shape_j)) = (&self.shapes[i], &self.shapes[j]) else { return false };
        // the poses the broad phase made this step (the same function of the same states)
        let (pose_i, pose_j) = (self.poses[i], self.poses[j]);
        debug_assert!(pose_i == self.pose(bodies, i) && pose_j == self.pose(bodies, j));
        let prediction = self.sweeps[i] + self.sweeps[j];
        let pos12 = pose_i.inv_mul(&pose_j);
        // a plane is unbounded: the other shape's size sets the bound
        let size = |k: usize| if self.planes.contains(&k) { f64::INFINITY } else { self.radii[k] };
        let reuse_distance = self.reuse_fraction * size(i).min(size(j));
        let reused = entry.reusable(&pos12, prediction, self.radii[j], reuse_distance);
        if reused {
            entry.reuse(&pos12);
        } else if !entry.make(&pos12, shape_i.as_ref(), shape_j.as_ref(), prediction, reuse_distance) {
            return false;
        }
        let manifold = &entry.manifold;
        let normal_world = pose_i.rotation * manifold.local_n1;
        let normal_world = if normal_world.is_finite() && normal_world.length_squared() > 0.5 {
            normal_world.normalize()
        } else {
            // a non-finite or zero normal from parry: a fixed, deterministic fallback. Coincident
            // centres do not come here: parry gives two spheres the first one's +y axis, two boxes
            // a face axis (`contact_scene.rs`, coincident bodies)
            DVec3::Z
        };
        let first = out.len();
        for c in &manifold.points {
            if c.dist.is_nan() || c.dist > prediction {
                continue;
            }
            let p1 = pose_i * c.local_p1;
            let p2 = pose_j * c.local_p2;
            let point_world = 0.5 * (p1 + p2);
            // aligned faces give each corner twice (one per face): keep one point per place, the deeper
            if let Some(twin) = out[first..]
                .iter_mut()
                .find(|o| (o.point_world - point_world).length_squared() < DUPLICATE_DISTANCE * DUPLICATE_DISTANCE)
            {
                if c.dist < twin.gap {
                    twin.gap = c.dist;
                }
                continue;
            }
            let features = (u64::from(c.fid1.0), u64::from(c.fid2.0));
            out.push(Contact { a: i, b: j, point_world, normal_world, gap: c.dist, features });
        }
        reused
    }
}
