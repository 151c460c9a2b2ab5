//! The contact manifold of each pair of convex shapes, kept from step to step, and reused while the
//! pair has barely moved.
//!
//! A pair's manifold holds its points in the two shapes' own frames (`local_p1` on shape 1,
//! `local_p2` on shape 2, normal `local_n1` in shape 1's frame), with the relative pose
//! `pos12 = shape1⁻¹ · shape2` at which it was made. At the next step, if shape 2 has moved
//! relative to shape 1 by less than a fraction of the smaller shape's bounding radius (the scene's
//! `manifold_reuse`, [`REUSE_FRACTION`] by default), the
//! points are kept as material points of the two bodies — each placed by its body's current pose —
//! and only their gaps are computed again, `dist = (pos12 · local_p2 − local_p1) · local_n1`
//! (parry's `update_separations`); else the manifold is made again from scratch. Jolt (its body-pair
//! cache, 1 mm and 2°) and parry itself (1 mm and 1° for box pairs) do the same with looser bounds.
//!
//! The motion bound: a point `p` of shape 2 (in its frame, `|p| ≤ ρ₂`) moves in shape 1's frame by
//! `|Δt + (R − R₀) p| ≤ |Δt| + 2 sin(θ/2) ρ₂`, `θ` the angle of `R R₀ᵀ`; `2 sin(θ/2)` is twice the
//! length of the vector part of that rotation's unit quaternion. So every surface point of shape 2
//! is within the bound of where it was, and the reused contact points are within it of the points a
//! fresh manifold would have on the same features: a tangential shift of at most the bound, with
//! the gap exact for those material points: an error in the contact point of at most 1e-4 of the
//! shape. The contact tests keep their figures within their bounds, moved by about as much as any
//! small perturbation moves them (docs/contact.md). The features (corners, faces) and their ids
//! stay those of the manifold, so warm starting matches them as before.
//!
//! A manifold is made with the prediction distance of the step plus [`REUSE_MARGIN`] (or the reuse
//! distance, when a looser `manifold_reuse` makes it larger; the contacts
//! beyond the step's prediction are dropped when the contacts are written, so this changes no
//! contact); it is reused only when the step's prediction plus the motion bound stays within what it
//! was made with, so that no point that a fresh manifold would give within the prediction — and no
//! pair that was apart — is missed.
//!
//! The entries are kept sorted by pair, as the broad phase gives the pairs: each step merges the
//! new pair list with the old entries, reusing those of the pairs still listed and handing the
//! manifolds of the others (their buffers) to a pool for new pairs. No allocation once warm.

use parry3d_f64::math::Pose;
use parry3d_f64::query::{
    ContactManifold, DefaultQueryDispatcher, PersistentQueryDispatcher, TrackedContact, Unsupported,
};
use parry3d_f64::shape::{
    ConvexPolyhedron, HalfSpace, PackedFeatureId, PolygonalFeature, PolygonalFeatureMap, Shape, ShapeType,
};

use super::face_search::{face_feature, FaceGraph};
use crate::math::DVec3;

/// A pair's manifold is reused while the pair's relative motion since it was made, bounded as in
/// the module documentation, is below this fraction of the smaller bounding radius of the two shapes
/// (a plane counts as unbounded): 1e-4, 87 µm for the pyramid's unit boxes.
pub const REUSE_FRACTION: f64 = 1e-4;

/// Added to the step's prediction distance when a manifold is made (m), so that the next steps,
/// whose prediction varies with the bodies' speeds, can reuse it.
pub const REUSE_MARGIN: f64 = 1e-3;

/// Room for points made in every manifold when it is first used: parry's face–face clipping gives
/// a polygon's vertices inside the other's and their edges' crossings, at most 4 + 4 + 8 for two
/// quadrilaterals, so a manifold never grows (never allocates) after its first step.
const POINTS_RESERVED: usize = 16;

/// One pair's manifold and the relative pose and prediction it was made with.
#[derive(Clone)]
pub(super) struct PairManifold {
    pair: (usize, usize),
    /// parry's manifold, in the shapes' frames.
    pub(super) manifold: ContactManifold<(), ()>,
    /// `shape1⁻¹ · shape2` when the manifold was made.
    pos12: Pose,
    /// The prediction distance it was made with (m); negative: never made.
    prediction: f64,
}

/// The manifolds of the pairs of convex shapes, by pair, sorted (see the module documentation).
#[derive(Clone, Default)]
pub(super) struct PairManifolds {
    /// This step's entries, in pair order.
    current: Vec<PairManifold>,
    /// The previous step's entries, consumed in pair order during this step.
    old: Vec<PairManifold>,
    cursor: usize,
    /// Manifolds of pairs that left, with their buffers, for new pairs.
    pool: Vec<ContactManifold<(), ()>>,
}

impl PairManifolds {
    /// Forgets every pair (the bodies changed).
    pub(super) fn clear(&mut self) {
        self.current.clear();
        self.old.clear();
        self.cursor = 0;
    }

    /// Before a step's narrow phase: the last step's entries become the old ones.
    pub(super) fn begin_step(&mut self) {
        std::mem::swap(&mut self.current, &mut self.old);
        self.current.clear();
        self.cursor = 0;
    }

    /// This step's entries so far, in pair order.
    pub(super) fn current_mut(&mut self) -> &mut [PairManifold] {
        &mut self.current
    }

    /// After it: the manifolds of the pairs no longer listed go to the pool.
    pub(super) fn end_step(&mut self) {
        self.retire_before((usize::MAX, usize::MAX));
        self.old.clear();
    }

    /// Hands the old entries before `pair` to the pool.
    fn retire_before(&mut self, pair: (usize, usize)) {
        while let Some(e) = self.old.get_mut(self.cursor).filter(|e| e.pair < pair) {
            self.pool.push(std::mem::take(&mut e.manifold));
            self.cursor += 1;
        }
    }

    /// The entry of `pair` for this step: last step's, or a new one that was never made. Pairs must
    /// come in increasing order within a step.
    pub(super) fn entry(&mut self, pair: (usize, usize)) -> &mut PairManifold {
        self.retire_before(pair);
        let entry = match self.old.get_mut(self.cursor).filter(|e| e.pair == pair) {
            Some(e) => {
                self.cursor += 1;
                PairManifold { manifold: std::mem::take(&mut e.manifold), ..*e }
            }
            None => {
                // a pair that left gives its buffer, nothing else: parry's manifold also keeps a
                // normal and sub-shapes, which its next computation may start from (a search for
                // the separating direction), and a new pair's first manifold must not depend on
                // which pair left before it (the same scene with one pair fewer elsewhere gave a
                // capsule's contact depth another last bit)
                let mut points = self.pool.pop().map(|m| m.points).unwrap_or_default();
                points.clear();
                points.reserve(POINTS_RESERVED);
                let manifold = ContactManifold { points, ..ContactManifold::default() };
                PairManifold { pair, manifold, pos12: Pose::IDENTITY, prediction: -1.0 }
            }
        };
        self.current.push(entry);
        self.current.last_mut().expect("just pushed")
    }
}

impl PairManifold {
    /// The pair of bodies, `(first, second)`.
    pub(super) fn pair(&self) -> (usize, usize) {
        self.pair
    }

    /// Whether the manifold can be reused at relative pose `pos12` with the step's `prediction` (m):
    /// the motion bound of shape 2 (bounding radius `radius2`, m) since the manifold was made is below
    /// `reuse_distance` (m) and, added to the prediction, within the prediction it was made with.
    pub(super) fn reusable(&self, pos12: &Pose, prediction: f64, radius2: f64, reuse_distance: f64) -> bool {
        if self.prediction < 0.0 {
            return false;
        }
        // Δt, and the rotation R R₀ᵀ: 2 sin(θ/2) = 2 |vector part|
        let shift = (pos12.translation - self.pos12.translation).length();
        let turn = pos12.rotation * self.pos12.rotation.inverse();
        let motion = shift + 2.0 * crate::math::DVec3::new(turn.x, turn.y, turn.z).length() * radius2;
        motion < reuse_distance && prediction + motion <= self.prediction
    }

    /// Keeps the manifold's points and computes their gaps at `pos12`.
    pub(super) fn reuse(&mut self, pos12: &Pose) {
        self.manifold.update_separations(pos12);
    }

    /// Makes the manifold again at `pos12` with `prediction` (m) plus the larger of [`REUSE_MARGIN`]
    /// and `reuse_distance` (m), the motion it may be reused for.
    pub(super) fn make(
        &mut self,
        pos12: &Pose,
        shape1: &dyn Shape,
        shape2: &dyn Shape,
        prediction: f64,
        reuse_distance: f64,
    ) -> bool {
        let margin = if reuse_distance.is_finite() { REUSE_MARGIN.max(reuse_distance) } else { REUSE_MARGIN };
        let prediction = prediction + margin;
        self.manifold.points.clear();
        let found = convex_manifold(pos12, shape1, shape2, prediction, &mut self.manifold).is_ok();
        self.pos12 = *pos12;
        self.prediction = if found { prediction } else { -1.0 };
        found
    }
}

/// parry's convex–convex manifold, except a half-space against a polyhedral shape, computed here
/// the same way into the manifold's own buffer: parry's version moves its points out and pushes
/// the new ones into a fresh `Vec`, one allocation per call (the dispatcher takes a ball first, as
/// parry's does).
pub(super) fn convex_manifold(
    pos12: &Pose,
    shape1: &dyn Shape,
    shape2: &dyn Shape,
    prediction: f64,
    manifold: &mut ContactManifold<(), ()>,
) -> Result<(), Unsupported> {
    let (t1, t2) = (shape1.shape_type(), shape2.shape_type());
    if t1 == ShapeType::HalfSpace && t2 != ShapeType::Ball && t2 != ShapeType::HalfSpace {
        if let (Some(plane), Some((pfm, border))) = (shape1.as_halfspace(), shape2.as_polygonal_feature_map()) {
            halfspace_manifold(pos12, plane, pfm, border, prediction, manifold, false);
            return Ok(());
        }
    } else if t2 == ShapeType::HalfSpace && t1 != ShapeType::Ball && t1 != ShapeType::HalfSpace {
        if let (Some((pfm, border)), Some(plane)) = (shape1.as_polygonal_feature_map(), shape2.as_halfspace()) {
            halfspace_manifold(&pos12.inverse(), plane, pfm, border, prediction, manifold, true);
            return Ok(());
        }
    }
    DefaultQueryDispatcher.contact_manifold_convex_convex(pos12, shape1, shape2, None, None, prediction, manifold)
}

/// parry's `contact_manifold_halfspace_pfm` (0.31), writing into `manifold.points` in place: the
/// vertices of the shape's support feature against the plane's normal that lie within `prediction`
/// of the plane, each with its projection on the plane.
fn halfspace_manifold<S: ?Sized + PolygonalFeatureMap>(
    pos12: &Pose,
    halfspace1: &HalfSpace,
    pfm2: &S,
    border_radius2: f64,
    prediction: f64,
    manifold: &mut ContactManifold<(), ()>,
    flipped: bool,
) {
    let feature = |dir, out: &mut PolygonalFeature| pfm2.local_support_feature(dir, out);
    halfspace_feature_manifold(pos12, halfspace1, feature, border_radius2, prediction, manifold, flipped);
}

/// [`halfspace_manifold`] for a convex polyhedron (shape 2) whose support face is found by a walk
/// on its [`FaceGraph`] from `face`, the face found last time (updated), instead of parry's scan
/// of every face: the same points when the walk finds the scan's face (see
/// [`super::face_search`]).
pub(super) fn halfspace_hull_manifold(
    pos12: &Pose,
    halfspace1: &HalfSpace,
    poly2: &ConvexPolyhedron,
    graph: &FaceGraph,
    face: &mut u32,
    prediction: f64,
    manifold: &mut ContactManifold<(), ()>,
) {
    let feature = |dir, out: &mut PolygonalFeature| {
        *face = graph.support_face(poly2, dir, *face);
        face_feature(poly2, *face, out);
    };
    halfspace_feature_manifold(pos12, halfspace1, feature, 0.0, prediction, manifold, false);
}

/// The half-space manifold with shape 2's support feature toward a direction (its frame) given by
/// `support_feature`.
fn halfspace_feature_manifold(
    pos12: &Pose,
    halfspace1: &HalfSpace,
    mut support_feature: impl FnMut(DVec3, &mut PolygonalFeature),
    border_radius2: f64,
    prediction: f64,
    manifold: &mut ContactManifold<(), ()>,
    flipped: bool,
) {
    let normal1_2 = pos12.rotation.inverse() * halfspace1.normal;
    let mut feature2 = PolygonalFeature::default();
    support_feature(-normal1_2, &mut feature2);
    manifold.points.clear();
    for i in 0..feature2.num_vertices {
        let vtx2 = feature2.vertices[i];
        let vtx2_1 = pos12 * vtx2;
        let dist_to_plane = vtx2_1.dot(halfspace1.normal);
        if dist_to_plane - border_radius2 <= prediction {
            manifold.points.push(TrackedContact::flipped(
                vtx2_1 - halfspace1.normal * dist_to_plane,
                vtx2 - normal1_2 * border_radius2,
                PackedFeatureId::face(0),
                feature2.vids[i],
                dist_to_plane - border_radius2,
                flipped,
            ));
        }
    }
    if flipped {
        manifold.local_n1 = -normal1_2;
        manifold.local_n2 = halfspace1.normal;
    } else {
        manifold.local_n1 = halfspace1.normal;
        manifold.local_n2 = -normal1_2;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{quat_exp, DVec3};
    use parry3d_f64::shape::SharedShape;

    /// The half-space manifold written in place is parry's, bit for bit, both ways round, for boxes,
    /// cylinders and capsules in poses touching, tilted, apart and sunk.
    #[test]
    fn halfspace_manifold_is_parrys() {
        let plane = SharedShape::halfspace(DVec3::Z);
        let others =
            [SharedShape::cuboid(0.5, 0.3, 0.2), SharedShape::cylinder(0.4, 0.2), SharedShape::capsule_z(0.3, 0.1)];
        let mut count = 0;
        for other in &others {
            for k in 0..40 {
                let t = k as f64;
                let rotation = quat_exp(DVec3::new((0.7 * t).sin(), (1.3 * t).cos(), 0.4 * t) * 0.02 * t);
                let pose = Pose::from_parts(DVec3::new(0.1 * t, -0.2, 0.25 + 0.01 * (t - 20.0)), rotation);
                for (s1, s2, pos12) in [(&plane, other, pose), (other, &plane, pose.inverse())] {
                    let (mut ours, mut parrys) = (ContactManifold::<(), ()>::new(), ContactManifold::<(), ()>::new());
                    convex_manifold(&pos12, s1.as_ref(), s2.as_ref(), 0.05, &mut ours).unwrap();
                    DefaultQueryDispatcher
                        .contact_manifold_convex_convex(&pos12, s1.as_ref(), s2.as_ref(), None, None, 0.05, &mut parrys)
                        .unwrap();
                    assert_eq!(ours.points.len(), parrys.points.len());
                    assert_eq!((ours.local_n1, ours.local_n2), (parrys.local_n1, parrys.local_n2));
                    for (a, b) in ours.points.iter().zip(&parrys.points) {
                        assert_eq!(
                            (a.local_p1, a.local_p2, a.dist.to_bits()),
                            (b.local_p1, b.local_p2, b.dist.to_bits())
                        );
                        assert_eq!((a.fid1, a.fid2), (b.fid1, b.fid2));
                        count += 1;
                    }
                }
            }
        }
        assert!(count > 100, "only {count} points compared");
    }

    /// Entries follow the pairs: a pair listed again keeps its manifold, a pair gone hands its buffer
    /// to the pool, a new pair takes it.
    #[test]
    fn entries_follow_the_pairs() {
        let mut m = PairManifolds::default();
        let box_ = SharedShape::cuboid(0.5, 0.5, 0.5);
        let touching = Pose::from_translation(DVec3::new(0.0, 0.0, 0.999));
        m.begin_step();
        for pair in [(0, 1), (0, 2), (1, 2)] {
            assert!(m.entry(pair).make(&touching, box_.as_ref(), box_.as_ref(), 0.01, 0.0));
        }
        m.end_step();
        m.begin_step();
        let e = m.entry((0, 2));
        assert_eq!(e.pair, (0, 2));
        assert!(!e.manifold.points.is_empty(), "kept");
        assert!(e.reusable(&touching, 0.01, 0.9, 1e-4));
        let new = m.entry((3, 4));
        assert!(new.manifold.points.is_empty() && new.prediction < 0.0, "a new pair starts empty");
        m.end_step();
        assert_eq!(m.current.iter().map(|e| e.pair).collect::<Vec<_>>(), [(0, 2), (3, 4)]);
        assert_eq!(m.pool.len(), 1, "(0, 1) and (1, 2) left, (3, 4) took one buffer");
    }

    /// A manifold is reused while the motion bound stays below the distance and the prediction
    /// within the one it was made with; not after a turn whose chord at the radius exceeds it.
    #[test]
    fn reuse_follows_the_motion_bound() {
        let box_ = SharedShape::cuboid(0.5, 0.5, 0.5);
        let at = Pose::from_translation(DVec3::new(0.0, 0.0, 1.0));
        let mut e = PairManifold { pair: (0, 1), manifold: ContactManifold::new(), pos12: at, prediction: -1.0 };
        assert!(!e.reusable(&at, 0.01, 0.9, 1e-4), "never made");
        assert!(e.make(&at, box_.as_ref(), box_.as_ref(), 0.01, 0.0));
        let moved = |dz: f64, angle: f64| Pose::from_parts(at.translation + DVec3::Z * dz, quat_exp(DVec3::X * angle));
        assert!(e.reusable(&moved(5e-5, 0.0), 0.01, 0.9, 1e-4));
        assert!(!e.reusable(&moved(2e-4, 0.0), 0.01, 0.9, 1e-4));
        // chord 2 sin(θ/2) ρ: 0.9e-4 at θ = 1e-4, ρ = 0.9
        assert!(e.reusable(&moved(0.0, 1e-4), 0.01, 0.9, 1e-4));
        assert!(!e.reusable(&moved(0.0, 2e-4), 0.01, 0.9, 1e-4));
        // the prediction grew past the one it was made with (0.01 + REUSE_MARGIN)
        assert!(!e.reusable(&at, 0.01 + 2.0 * REUSE_MARGIN, 0.9, 1e-4));
        // reused: the gaps follow the pose
        e.reuse(&moved(5e-5, 0.0));
        assert!(e.manifold.points.iter().all(|p| (p.dist - 5e-5).abs() < 1e-12));
    }

    /// A new pair's first manifold does not depend on which pair left the buffer it takes: a
    /// capsule on a box (parry's search for the separating direction, which may start from the
    /// manifold's normal) made in a buffer that another pair left, at another pose, is the one a
    /// fresh buffer gives, bit for bit.
    #[test]
    fn a_new_pair_does_not_inherit_a_normal() {
        let (capsule, box_) = (SharedShape::capsule_z(0.5, 0.2), SharedShape::cuboid(0.5, 0.4, 0.3));
        let pose = |k: f64| {
            Pose::from_parts(
                DVec3::new(0.3 * k.sin(), -0.2 * k.cos(), 0.95 + 0.01 * k),
                quat_exp(DVec3::new(0.4 * k, -0.9 + 0.3 * k, 0.2) * 0.8),
            )
        };
        let mut compared = 0;
        for k in 0..12 {
            let (before, after) = (pose(k as f64), pose(k as f64 + 3.7));
            let mut fresh =
                PairManifold { pair: (2, 3), manifold: ContactManifold::new(), pos12: after, prediction: -1.0 };
            fresh.make(&after, capsule.as_ref(), box_.as_ref(), 0.05, 0.0);
            let mut m = PairManifolds::default();
            m.begin_step();
            m.entry((0, 1)).make(&before, box_.as_ref(), capsule.as_ref(), 0.05, 0.0);
            m.end_step();
            m.begin_step();
            let reused = m.entry((2, 3));
            reused.make(&after, capsule.as_ref(), box_.as_ref(), 0.05, 0.0);
            let (a, b) = (&fresh.manifold, &reused.manifold);
            assert_eq!((a.local_n1, a.local_n2), (b.local_n1, b.local_n2), "pose {k}");
            assert_eq!(a.points.len(), b.points.len(), "pose {k}");
            for (p, q) in a.points.iter().zip(&b.points) {
                assert_eq!((p.local_p1, p.local_p2, p.dist.to_bits()), (q.local_p1, q.local_p2, q.dist.to_bits()));
                compared += 1;
            }
        }
        assert!(compared > 10, "only {compared} points compared");
    }
}
