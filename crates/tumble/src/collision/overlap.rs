//! Deep overlaps: pairs of bodies placed inside each other, found before the first step so that a
//! scene's mistake is reported rather than silently pushed apart.
//!
//! The contact stage separates overlapping bodies gently (a split impulse at most
//! `max_correction_speed`, `docs/contact.md`), which is right for the small overlaps of a stack and
//! hides a misplaced body. A pair counts as *deeply* overlapping when its penetration depth, the
//! largest `−gap` of its contact points at zero prediction distance, exceeds
//!
//! `max(slop, min(1 cm, 10 % of ρ_min)))`
//!
//! with `ρ_min` the smaller bounding radius of the two shapes about their centres of mass (a plane
//! has none: the other body's is used) and `slop` the overlap contacts leave uncorrected. So a
//! 1 m box pressed 2 cm into the floor is reported, a 5 cm pebble 6 mm into it too, and the 0.5 mm
//! of a settled stack never. Pairs the scene excludes (`no_collide`) and pairs of fixed bodies are
//! not tested, as in the step.

use super::{Colliders, Contact};
use crate::body::RigidBody;
use crate::math::DVec3;

/// Penetration depth above which a pair is reported, whatever the bodies' size (m).
pub const DEEP_OVERLAP_DEPTH: f64 = 0.01;
/// Fraction of the smaller bounding radius above which a pair is reported.
pub const DEEP_OVERLAP_FRACTION: f64 = 0.1;

/// Two bodies that overlap deeply.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Overlap {
    /// The first body (index into the world's bodies).
    pub a: usize,
    /// The second body, `b > a`.
    pub b: usize,
    /// Penetration depth, the deepest point of the pair (m).
    pub depth: f64,
    /// The depth above which this pair is reported (m).
    pub threshold: f64,
}

impl Colliders {
    /// The pairs of `bodies` (in their current poses) that overlap by more than the threshold of the
    /// module documentation, with `slop` (m) the overlap the contacts tolerate; sorted by pair.
    pub fn deep_overlaps(&mut self, bodies: &[RigidBody], slop: f64) -> Vec<Overlap> {
        let mut contacts: Vec<Contact> = Vec::new();
        // no motion and no prediction: only touching or overlapping pairs
        self.find_contacts(bodies, 0.0, DVec3::ZERO, 0.0, &mut contacts);
        let mut overlaps: Vec<Overlap> = Vec::new();
        for c in contacts.iter().filter(|c| c.gap < 0.0) {
            let (a, b) = (c.a.min(c.b), c.a.max(c.b));
            // a pair's points are found together
            match overlaps.last_mut().filter(|o| (o.a, o.b) == (a, b)) {
                Some(o) => o.depth = o.depth.max(-c.gap),
                None => overlaps.push(Overlap { a, b, depth: -c.gap, threshold: self.overlap_threshold(a, b, slop) }),
            }
        }
        overlaps.retain(|o| o.depth > o.threshold);
        overlaps.sort_unstable_by_key(|o| (o.a, o.b));
        overlaps
    }

    /// `max(slop, min(DEEP_OVERLAP_DEPTH, DEEP_OVERLAP_FRACTION · ρ_min))` for bodies `a` and `b` (m).
    fn overlap_threshold(&self, a: usize, b: usize, slop: f64) -> f64 {
        let size = |i: usize| if self.planes.contains(&i) { f64::INFINITY } else { self.radii[i] };
        let smaller = size(a).min(size(b));
        DEEP_OVERLAP_DEPTH.min(DEEP_OVERLAP_FRACTION * smaller).max(slop)
    }
}
