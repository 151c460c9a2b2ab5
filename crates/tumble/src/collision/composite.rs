//! The narrow phase of pairs with a composite shape: a compound (a `shapes` body, a decomposed
//! mesh) or a triangle mesh (a fixed mesh body), against anything but another fixed body.
//!
//! parry's `contact_manifolds` finds, through the composite's bounding-volume tree, the sub-shapes
//! (parts, triangles) near the other shape and gives one manifold per touching pair of sub-shapes,
//! each in the frames of its two sub-shapes (`subshape_pos1/2` place a part in its shape; a
//! triangle is in the mesh's frame). Each manifold point becomes a [`Contact`] exactly as on the
//! convex path — midpoint of the two surface points, unit normal from the first body to the second,
//! signed gap — with the sub-shape's index above parry's feature id, so that warm starting matches
//! the same feature of the same part from step to step. Points of different sub-shapes at one place
//! with the same normal (a ball on the common edge of two triangles) are one contact, the deeper.
//!
//! parry keeps, per pair, the sub-shapes found last step and their manifolds (a workspace), so the
//! tree is searched again only when the other shape leaves the region searched; tumble keeps them
//! from step to step and drops those of pairs that the broad phase no longer reports.

use super::{feature_key, Colliders, Contact, DUPLICATE_DISTANCE};
use crate::body::RigidBody;
use crate::math::DVec3;
use parry3d_f64::query::{
    ContactManifold, ContactManifoldsWorkspace, DefaultQueryDispatcher, PersistentQueryDispatcher,
};
use std::collections::HashMap;

/// Contacts of one pair at one place with normals closer than this (cosine) are one contact.
const SAME_NORMAL_COSINE: f64 = 1.0 - 1e-6;

/// parry's manifolds and workspace for one pair, and the step it was last used.
#[derive(Clone, Default)]
struct PairCache {
    manifolds: Vec<ContactManifold<(), ()>>,
    workspace: Option<ContactManifoldsWorkspace>,
    step: u64,
}

/// The caches of the pairs with a composite shape, by `(first, second)` body index. (std's hasher:
/// creating it allocates nothing, where ahash's allocates its process-wide seed at first use.)
#[derive(Clone, Default)]
pub(super) struct CompositePairs {
    pairs: HashMap<(usize, usize), PairCache>,
    step: u64,
}

impl CompositePairs {
    /// Forgets every pair (the bodies changed).
    pub(super) fn clear(&mut self) {
        self.pairs.clear();
    }

    /// After a step's narrow phase: drops the pairs not tested in it.
    pub(super) fn end_step(&mut self) {
        if !self.pairs.is_empty() {
            let step = self.step;
            self.pairs.retain(|_, p| p.step == step);
        }
        self.step += 1;
    }
}

impl Colliders {
    /// parry's composite manifolds between bodies `i` and `j` (one of them a compound or a triangle
    /// mesh), appended to `out` in the world frame.
    pub(super) fn narrow_phase_composite(&mut self, bodies: &[RigidBody], i: usize, j: usize, out: &mut Vec<Contact>) {
        let pose_i = self.pose(bodies, i);
        let pose_j = self.pose(bodies, j);
        let (Some(shape_i), Some(shape_j)) = (&self.shapes[i], &self.shapes[j]) else { return };
        let prediction = self.sweeps[i] + self.sweeps[j];
        let pos12 = pose_i.inv_mul(&pose_j);
        let step = self.composite_pairs.step;
        let cache = self.composite_pairs.pairs.entry((i, j)).or_default();
        cache.step = step;
        let found = DefaultQueryDispatcher.contact_manifolds(
            &pos12,
            shape_i.as_ref(),
            shape_j.as_ref(),
            prediction,
            &mut cache.manifolds,
            &mut cache.workspace,
        );
        if found.is_err() {
            return;
        }
        let first = out.len();
        for m in &cache.manifolds {
            if m.points.is_empty() {
                continue;
            }
            // the frames of the two sub-shapes: a part's pose in its compound, or the shape's own
            let sub_i = m.subshape_pos1().map_or(pose_i, |p| pose_i * *p);
            let sub_j = m.subshape_pos2().map_or(pose_j, |p| pose_j * *p);
            let normal_world = sub_i.rotation * m.local_n1;
            let normal_world = if normal_world.is_finite() && normal_world.length_squared() > 0.5 {
                normal_world.normalize()
            } else {
                DVec3::Z
            };
            for c in &m.points {
                if c.dist.is_nan() || c.dist > prediction {
                    continue;
                }
                let point_world = 0.5 * (sub_i * c.local_p1 + sub_j * c.local_p2);
                if let Some(twin) = out[first..].iter_mut().find(|o| {
                    (o.point_world - point_world).length_squared() < DUPLICATE_DISTANCE * DUPLICATE_DISTANCE
                        && o.normal_world.dot(normal_world) > SAME_NORMAL_COSINE
                }) {
                    twin.gap = twin.gap.min(c.dist);
                    continue;
                }
                let features = (feature_key(m.subshape1, c.fid1.0), feature_key(m.subshape2, c.fid2.0));
                out.push(Contact { a: i, b: j, point_world, normal_world, gap: c.dist, features });
            }
        }
    }
}
