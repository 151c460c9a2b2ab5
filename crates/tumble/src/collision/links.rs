//! Collision detection for the links of robots: each link's URDF `<collision>` shapes against the
//! bodies of the world (planes, boxes, meshes as terrain, free bodies), against the links of other
//! robots, and — when the robot asks for it — against its own links.
//!
//! The link shapes move with their bodies: at each step their poses come from the robots' forward
//! kinematics of the state at the start of the step (`world_from_shape = world_from_body ·
//! body_from_shape`), and their sweeps from the bodies' spatial velocities, `(|v_o| + |ω| ρ) dt`
//! (`v_o` the velocity of the body frame's origin, `ρ` the distance from it to the farthest point of
//! the shape). A shape fixed to the world (a fixed base and what is fixed to it) does not sweep.
//!
//! Pairs: a link shape and a body are paired when the body's swept box (from the bodies' broad
//! phase of the same step) meets the link's, or the body is a plane; two link shapes when their
//! boxes meet, they move with different bodies, and the pair is allowed (different robots, or the
//! same robot with `self_collision`, not parent and child, not touching in the initial pose, not
//! excluded by `no_collide`). The cost is `O(L (B + L))` box tests for `L` link shapes and `B` bodies:
//! robots have tens of shapes, not thousands.
//!
//! Narrow phase: parry's contact manifolds (`contact_manifolds`, any shape pair, with parry's
//! workspace kept per pair from step to step), each point written as a [`LinkContact`] in the world
//! frame: midpoint of the two surface points, unit normal from side `a` to side `b`, signed gap.
//! A link is always side `b` against a body (the normal points from the body to the link, as the
//! contact file writes it: `{"a": "ground", "b": "robot/foot"}`); of two links, the one listed first is
//! side `a`.

use super::face_search::FaceGraph;
use super::{feature_key, Colliders, DUPLICATE_DISTANCE, PREDICTION_MARGIN};
use crate::body::{RigidBody, Shape};
use crate::math::{DQuat, DVec3};
use parry3d_f64::bounding_volume::{Aabb, BoundingSphere, BoundingVolume};
use parry3d_f64::math::Pose;
use parry3d_f64::query::{
    ContactManifold, ContactManifoldsWorkspace, DefaultQueryDispatcher, PersistentQueryDispatcher,
};
use parry3d_f64::shape::{PackedFeatureId, SharedShape};
use std::collections::HashMap;
use std::sync::Arc;

/// Pairs whose buffers (parry's manifolds and workspace) are kept after they part.
const CACHE_KEPT: usize = 4096;

/// One side of a contact: a body of the world, or a link shape (index into [`LinkColliders`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Side {
    Body(usize),
    Link(usize),
}

/// One contact point between a link shape and a body or another link shape, world frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinkContact {
    /// The first side (the normal points away from it).
    pub a: Side,
    /// The second side (always a link).
    pub b: Side,
    /// The contact point, midway between the two surfaces (m).
    pub point_world: DVec3,
    /// Unit normal from `a` towards `b`.
    pub normal_world: DVec3,
    /// Signed distance between the surfaces (m), negative when they overlap.
    pub gap: f64,
    /// The two touching features (for warm starting), as in [`super::Contact`].
    pub features: (u64, u64),
}

/// One collision shape of a robot's link.
#[derive(Clone)]
pub struct LinkCollider {
    /// The robot (index into the world's robots).
    pub robot: usize,
    /// The model body it moves with; `None`: fixed to the world.
    pub body: Option<usize>,
    /// `robot/link`, as written in the contact file.
    pub name: String,
    shape: SharedShape,
    /// `body_from_shape` (parry's frame of the shape in the body frame).
    body_from_shape: Pose,
    /// Distance from the body frame's origin to the farthest point of the shape (m).
    reach: f64,
    /// For a shape of many vertices (a hull, a mesh, a compound), its box and bounding sphere in
    /// its own frame: the world box is then the overlap of the two placed boxes (the placed local
    /// box `c ± |R| h`, the sphere's `c ± ρ`), no pass over the vertices per step. `None`: a
    /// primitive, whose exact box is as cheap.
    local_bounds: Option<(Aabb, BoundingSphere)>,
    /// For a convex hull, the walk that finds its face against a plane
    /// ([`super::face_search`]); shared between clones of the world.
    faces: Option<Arc<FaceGraph>>,
    /// Whether it collides at all (`no_collide = [["link"]]` takes a link out).
    pub enabled: bool,
}

impl std::fmt::Debug for LinkCollider {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LinkCollider").field("name", &self.name).field("body", &self.body).finish()
    }
}

impl LinkCollider {
    /// A link shape of robot `robot` on model body `body` (`None`: fixed to the world), placed at
    /// `position_body` with `body_from_shape` rotation `orientation_body` (tumble's shape axes).
    pub fn new(
        robot: usize,
        body: Option<usize>,
        name: String,
        shape: &Shape,
        position_body: DVec3,
        orientation_body: DQuat,
    ) -> Self {
        let (parry, offset) = super::parry_shape(shape, false);
        let body_from_shape = Pose::from_parts(position_body, orientation_body) * offset;
        let sphere = parry.compute_local_bounding_sphere();
        let reach = sphere.radius() + body_from_shape.translation.length();
        let many_vertices =
            parry.as_convex_polyhedron().is_some() || parry.as_trimesh().is_some() || parry.as_compound().is_some();
        let local_bounds = many_vertices.then(|| (parry.compute_local_aabb(), sphere));
        let faces = parry.as_convex_polyhedron().and_then(FaceGraph::new).map(Arc::new);
        Self { robot, body, name, shape: parry, body_from_shape, reach, local_bounds, faces, enabled: true }
    }
}

/// parry's manifolds and workspace of one pair, and the step it was last used.
#[derive(Clone, Default)]
struct PairCache {
    manifolds: Vec<ContactManifold<(), ()>>,
    workspace: Option<ContactManifoldsWorkspace>,
    /// The hull's face found against a plane last time (where the next walk starts).
    face: u32,
    step: u64,
}

/// The pose and velocity of a robot body at the start of the step, world frame.
#[derive(Debug, Clone, Copy)]
pub struct BodyMotion {
    /// `world_from_body`.
    pub pose: Pose,
    /// Speed of the body frame's origin (m/s) and angular speed (rad/s).
    pub speed: f64,
    pub angular_speed: f64,
}

/// The link shapes of every robot and the buffers of their contact detection.
#[derive(Clone, Default)]
pub struct LinkColliders {
    links: Vec<LinkCollider>,
    /// Pairs of link shapes that never collide, `(min, max)`, sorted.
    excluded_links: Vec<(usize, usize)>,
    /// Pairs `(link, body)` that never collide, sorted.
    excluded_bodies: Vec<(usize, usize)>,
    /// Per robot: whether its own links collide.
    self_collision: Vec<bool>,
    poses: Vec<Pose>,
    sweeps: Vec<f64>,
    aabbs: Vec<Aabb>,
    cache: HashMap<(Side, Side), PairCache>,
    /// Per link: the end of the run of consecutive links of its robot that it lies in (a robot
    /// without self-collision skips that run at once).
    run_end: Vec<usize>,
    /// Per body, this step: its shape's pose, swept box (`None`: a plane) and sweep, as the broad
    /// phase made them (`None`: no shape), placed once for all the links.
    placed_bodies: Vec<Option<(Pose, Option<Aabb>, f64)>>,
    step: u64,
}

impl std::fmt::Debug for LinkColliders {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LinkColliders").field("links", &self.links.len()).finish()
    }
}

impl LinkColliders {
    /// Adds a link shape; returns its index.
    pub fn push(&mut self, link: LinkCollider) -> usize {
        if self.self_collision.len() <= link.robot {
            self.self_collision.resize(link.robot + 1, false);
        }
        self.links.push(link);
        self.links.len() - 1
    }

    /// The link shapes.
    pub fn links(&self) -> &[LinkCollider] {
        &self.links
    }

    /// Whether there is any link shape.
    pub fn is_empty(&self) -> bool {
        self.links.is_empty()
    }

    /// Lets robot `robot`'s own links collide (or not).
    pub fn set_self_collision(&mut self, robot: usize, on: bool) {
        if self.self_collision.len() <= robot {
            self.self_collision.resize(robot + 1, false);
        }
        self.self_collision[robot] = on;
    }

    /// Link shapes `i` and `j` never collide.
    pub fn exclude_links(&mut self, i: usize, j: usize) {
        let pair = (i.min(j), i.max(j));
        if let Err(at) = self.excluded_links.binary_search(&pair) {
            self.excluded_links.insert(at, pair);
        }
    }

    /// Link shape `link` never collides with body `body`.
    pub fn exclude_body(&mut self, link: usize, body: usize) {
        if let Err(at) = self.excluded_bodies.binary_search(&(link, body)) {
            self.excluded_bodies.insert(at, (link, body));
        }
    }

    /// Whether link shape `link` and body `body` are a pair [`exclude_body`](Self::exclude_body) took out.
    pub fn is_body_excluded(&self, link: usize, body: usize) -> bool {
        self.excluded_bodies.binary_search(&(link, body)).is_ok()
    }

    /// Takes link shape `link` out of all contact.
    pub fn disable(&mut self, link: usize) {
        self.links[link].enabled = false;
    }

    /// Whether links `i` and `j` may collide at all (the filter without the boxes).
    pub fn pair_allowed(&self, i: usize, j: usize) -> bool {
        let (a, b) = (&self.links[i], &self.links[j]);
        if !a.enabled || !b.enabled || i == j {
            return false;
        }
        if a.robot == b.robot && (!self.self_collision[a.robot] || a.body == b.body) {
            return false;
        }
        if a.body.is_none() && b.body.is_none() {
            return false;
        }
        self.excluded_links.binary_search(&(i.min(j), i.max(j))).is_err()
    }

    /// Places every link shape for a step of `dt` (s): `motion(robot, body)` gives a body's pose and
    /// speeds (a shape fixed to the world is placed in the world frame already). `slop` (m) as in [`Colliders::find_contacts`]: the boxes grow by half of it or of
    /// [`PREDICTION_MARGIN`], whichever is larger.
    pub fn place(&mut self, dt: f64, slop: f64, mut motion: impl FnMut(usize, usize) -> BodyMotion) {
        self.poses.clear();
        self.sweeps.clear();
        self.aabbs.clear();
        let margin = slop.max(PREDICTION_MARGIN);
        // the shapes of one link come one after another: its motion is asked once
        let mut last: Option<((usize, usize), BodyMotion)> = None;
        for link in &self.links {
            let (world_from_body, sweep) = match link.body {
                Some(b) => {
                    let m = match last {
                        Some((key, m)) if key == (link.robot, b) => m,
                        _ => {
                            let m = motion(link.robot, b);
                            last = Some(((link.robot, b), m));
                            m
                        }
                    };
                    (m.pose, (m.speed + m.angular_speed * link.reach) * dt)
                }
                None => (Pose::IDENTITY, 0.0),
            };
            let pose = world_from_body * link.body_from_shape;
            self.poses.push(pose);
            self.sweeps.push(sweep + 0.5 * margin);
            let aabb = match &link.local_bounds {
                Some((local_aabb, sphere)) => {
                    let (a, b) = (local_aabb.transform_by(&pose), sphere.transform_by(&pose));
                    let b = Aabb::from_half_extents(b.center, DVec3::splat(b.radius));
                    Aabb::new(a.mins.max(b.mins), a.maxs.min(b.maxs))
                }
                None => match link.shape.as_cylinder() {
                    // exact, in closed form (parry's takes six support points): about the axis
                    // `a` (the shape's y), half extents `h |a_i| + r √(1 − a_i²)`
                    Some(c) => {
                        let axis = pose.rotation * DVec3::Y;
                        let half = DVec3::from_array(
                            axis.to_array().map(|a| c.half_height * a.abs() + c.radius * (1.0 - a * a).max(0.0).sqrt()),
                        );
                        Aabb::from_half_extents(pose.translation, half)
                    }
                    None => link.shape.compute_aabb(&pose),
                },
            };
            self.aabbs.push(aabb.loosened(sweep + 0.5 * margin));
        }
    }

    /// The contacts of the placed link shapes ([`place`](Self::place)) with the bodies (whose shapes,
    /// poses and swept boxes `colliders` computed in this step's broad phase) and with each other,
    /// into `out` (cleared first).
    pub fn find_contacts(&mut self, colliders: &Colliders, bodies: &[RigidBody], out: &mut Vec<LinkContact>) {
        out.clear();
        let step = self.step;
        let count = self.links.len();
        self.run_end.resize(count, count);
        for l in (0..count).rev() {
            let same = l + 1 < count && self.links[l + 1].robot == self.links[l].robot;
            self.run_end[l] = if same { self.run_end[l + 1] } else { l + 1 };
        }
        self.placed_bodies.clear();
        self.placed_bodies.extend(
            (0..bodies.len())
                .map(|i| colliders.placed(bodies, i).map(|(_, pose, aabb, sweep)| (pose, aabb.copied(), sweep))),
        );
        for l in 0..count {
            if !self.links[l].enabled {
                continue;
            }
            let moving = self.links[l].body.is_some();
            // against the bodies
            for (i, body) in bodies.iter().enumerate() {
                let (Some((pose_i, aabb, sweep_i)), Some(shape)) = (self.placed_bodies[i], colliders.shape(i)) else {
                    continue;
                };
                let aabb = aabb.as_ref();
                if body.fixed && !moving {
                    continue;
                }
                match aabb {
                    Some(aabb) if !aabb.intersects(&self.aabbs[l]) => continue,
                    // a plane: the link's swept box entirely above it cannot touch it
                    None if above_plane(shape, &pose_i, &self.aabbs[l]) => continue,
                    _ => {}
                }
                if self.excluded_bodies.binary_search(&(l, i)).is_ok() {
                    continue;
                }
                let prediction = sweep_i + self.sweeps[l];
                let cache = self.cache.entry((Side::Body(i), Side::Link(l))).or_default();
                cache.step = step;
                manifold_contacts(
                    cache,
                    (Side::Body(i), &pose_i, shape),
                    (Side::Link(l), &self.poses[l], &self.links[l].shape),
                    self.links[l].faces.as_deref(),
                    prediction,
                    out,
                );
            }
            // against the link shapes after it (a robot without self-collision skips its own
            // links before any box test)
            let robot = self.links[l].robot;
            let own = !self.self_collision[robot];
            let first = if own { self.run_end[l] } else { l + 1 };
            for m in first..count {
                if own && self.links[m].robot == robot {
                    continue;
                }
                if !self.aabbs[l].intersects(&self.aabbs[m]) || !self.pair_allowed(l, m) {
                    continue;
                }
                let prediction = self.sweeps[l] + self.sweeps[m];
                let cache = self.cache.entry((Side::Link(l), Side::Link(m))).or_default();
                cache.step = step;
                manifold_contacts(
                    cache,
                    (Side::Link(l), &self.poses[l], &self.links[l].shape),
                    (Side::Link(m), &self.poses[m], &self.links[m].shape),
                    None,
                    prediction,
                    out,
                );
            }
        }
        // a pair's buffers are kept when it parts (a trotting foot lifts and lands again every few
        // hundred steps: dropping them made its landing allocate), up to CACHE_KEPT pairs; past
        // that, the pairs not met in this step go
        if self.cache.len() > CACHE_KEPT {
            self.cache.retain(|_, p| p.step == step);
        }
        self.step += 1;
    }

    /// The pairs of link shapes of one robot that overlap or touch (within `distance`, m) in the
    /// current placement: the pairs a robot's initial pose puts in touch, which self-collision leaves
    /// alone.
    pub fn touching_pairs(&self, robot: usize, distance: f64) -> Vec<(usize, usize)> {
        let mut pairs = Vec::new();
        for l in 0..self.links.len() {
            for m in l + 1..self.links.len() {
                let (a, b) = (&self.links[l], &self.links[m]);
                if a.robot != robot || b.robot != robot || a.body == b.body {
                    continue;
                }
                let pos12 = self.poses[l].inv_mul(&self.poses[m]);
                if let Ok(d) = parry3d_f64::query::distance(&pos12, a.shape.as_ref(), &Pose::IDENTITY, b.shape.as_ref())
                {
                    if d.distance <= distance {
                        pairs.push((l, m));
                    }
                }
            }
        }
        pairs
    }
}

/// Whether the box lies entirely on the outer side of the half-space `shape` placed at `pose`
/// (`false` for any other shape): `n·(centre − p₀) − Σ |n_i| h_i > 0`, world frame.
fn above_plane(shape: &SharedShape, pose: &Pose, aabb: &Aabb) -> bool {
    let Some(plane) = shape.as_halfspace() else { return false };
    let n = pose.rotation * plane.normal;
    let (center, half) = (aabb.center(), aabb.half_extents());
    n.dot(center - pose.translation) - n.abs().dot(half) > 0.0
}

/// A sphere (centre `c`, radius `r`, side `b`) on a plane (side `a`, unit normal `n_a` in its own
/// frame, through its origin), in closed form (a foot on the floor, with no support-map query): the
/// centre's height `h = n·(c − p₀)`, the gap `h − r`, the point midway between the sphere's lowest
/// point `c − r n` and the plane's `c − h n`, the normal `n` (from the plane to the sphere).
#[allow(clippy::too_many_arguments)]
fn plane_ball_contact(
    side_a: Side,
    pose_a: &Pose,
    normal_a: DVec3,
    side_b: Side,
    center: DVec3,
    radius: f64,
    prediction: f64,
    out: &mut Vec<LinkContact>,
) {
    let n = (pose_a.rotation * normal_a).normalize();
    let height = n.dot(center - pose_a.translation);
    let gap = height - radius;
    if gap.is_nan() || gap > prediction {
        return;
    }
    let point_world = center - 0.5 * (radius + height) * n;
    let face = PackedFeatureId::face(0).0;
    out.push(LinkContact {
        a: side_a,
        b: side_b,
        point_world,
        normal_world: n,
        gap,
        features: (feature_key(0, face), feature_key(0, face)),
    });
}

/// parry's manifolds of one pair, written as contacts from side `a` to side `b` (`faces_b`: the face
/// walk of side `b`, a convex hull).
fn manifold_contacts(
    cache: &mut PairCache,
    (side_a, pose_a, shape_a): (Side, &Pose, &SharedShape),
    (side_b, pose_b, shape_b): (Side, &Pose, &SharedShape),
    faces_b: Option<&FaceGraph>,
    prediction: f64,
    out: &mut Vec<LinkContact>,
) {
    if let (Some(plane), Some(ball)) = (shape_a.as_halfspace(), shape_b.as_ball()) {
        plane_ball_contact(side_a, pose_a, plane.normal, side_b, pose_b.translation, ball.radius, prediction, out);
        return;
    }
    let pos12 = pose_a.inv_mul(pose_b);
    let hull_on_plane = match (shape_a.as_halfspace(), shape_b.as_convex_polyhedron(), faces_b) {
        (Some(plane), Some(poly), Some(graph)) => Some((plane, poly, graph)),
        _ => None,
    };
    let found = if let Some((plane, poly, graph)) = hull_on_plane {
        // a hull on a plane: its support face by the walk from last step's face
        if cache.manifolds.is_empty() {
            cache.manifolds.push(ContactManifold::new());
            cache.manifolds[0].points.reserve(16);
        }
        let manifold = &mut cache.manifolds[0];
        super::pairs::halfspace_hull_manifold(&pos12, plane, poly, graph, &mut cache.face, prediction, manifold);
        Ok(())
    } else if shape_a.as_composite_shape().is_none() && shape_b.as_composite_shape().is_none() {
        // two convex shapes: one manifold, made in its own buffer (parry's half-space manifold
        // allocates a new one at every call)
        if cache.manifolds.is_empty() {
            cache.manifolds.push(ContactManifold::new());
            cache.manifolds[0].points.reserve(16);
        }
        cache.manifolds[0].points.clear();
        super::pairs::convex_manifold(&pos12, shape_a.as_ref(), shape_b.as_ref(), prediction, &mut cache.manifolds[0])
    } else {
        DefaultQueryDispatcher.contact_manifolds(
            &pos12,
            shape_a.as_ref(),
            shape_b.as_ref(),
            prediction,
            &mut cache.manifolds,
            &mut cache.workspace,
        )
    };
    if found.is_err() {
        return;
    }
    let first = out.len();
    for m in &cache.manifolds {
        if m.points.is_empty() {
            continue;
        }
        let sub_a = m.subshape_pos1().map_or(*pose_a, |p| *pose_a * *p);
        let sub_b = m.subshape_pos2().map_or(*pose_b, |p| *pose_b * *p);
        let normal_world = sub_a.rotation * m.local_n1;
        let normal_world = if normal_world.is_finite() && normal_world.length_squared() > 0.5 {
            normal_world.normalize()
        } else {
            DVec3::Z
        };
        for c in &m.points {
            if c.dist.is_nan() || c.dist > prediction {
                continue;
            }
            let point_world = 0.5 * (sub_a * c.local_p1 + sub_b * c.local_p2);
            if let Some(twin) = out[first..].iter_mut().find(|o| {
                (o.point_world - point_world).length_squared() < DUPLICATE_DISTANCE * DUPLICATE_DISTANCE
                    && o.normal_world.dot(normal_world) > 1.0 - 1e-6
            }) {
                twin.gap = twin.gap.min(c.dist);
                continue;
            }
            let features = (feature_key(m.subshape1, c.fid1.0), feature_key(m.subshape2, c.fid2.0));
            out.push(LinkContact { a: side_a, b: side_b, point_world, normal_world, gap: c.dist, features });
        }
    }
}
