//! MuJoCo's contact filter between two geoms, as its collision stage applies it (MuJoCo
//! documentation, "Computation: Collision detection"; checked against `mujoco` 4.0.1 on a chain
//! with a welded body, a free body and `<exclude>` pairs):
//!
//! 1. geoms on one *weld body* (an MJCF body and the bodies welded to it, without joints between
//!    them; the world and what is welded to it is one) never collide;
//! 2. nor, when neither weld body is the world, those of a weld body and of its parent's weld
//!    body (`<flag filterparent>`, on by default; the reader refuses turning it off);
//! 3. nor those of two bodies named by a `<contact><exclude body1 body2>` (the bodies the geoms
//!    are written in, not their weld bodies);
//! 4. otherwise they may collide when `(contype₁ & conaffinity₂) ≠ 0 or (contype₂ & conaffinity₁) ≠ 0`.
//!
//! A weld body is tumble's body (the one a geom moves with), `None` for the world.

/// What the filter knows of one geom.
#[derive(Debug, Clone, PartialEq)]
pub struct GeomFilter {
    /// The MJCF body the geom is written in (`world` for the worldbody).
    pub body: String,
    /// Its weld body: the tumble body it moves with (`None`: the world).
    pub weld: Option<usize>,
    /// The weld body of its weld body's parent (`None`: the world).
    pub weld_parent: Option<usize>,
    pub contype: u32,
    pub conaffinity: u32,
}

/// The filter of a model's geoms: one [`GeomFilter`] per geometry of the model (visual ones too),
/// in the model's order, and the file's `<exclude>` pairs.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ContactFilter {
    pub geoms: Vec<GeomFilter>,
    /// `<contact><exclude>` pairs (MJCF body names).
    pub excludes: Vec<(String, String)>,
}

impl ContactFilter {
    /// Whether geoms `a` and `b` (indices into the model's geometries) may collide.
    pub fn may_collide(&self, a: usize, b: usize) -> bool {
        pair_may_collide(&self.geoms[a], &self.geoms[b], &self.excludes)
    }
}

/// Rules 1–4 of the module's documentation for two geoms.
pub fn pair_may_collide(a: &GeomFilter, b: &GeomFilter, excludes: &[(String, String)]) -> bool {
    if a.weld == b.weld {
        return false;
    }
    if a.weld.is_some() && b.weld.is_some() && (a.weld_parent == b.weld || b.weld_parent == a.weld) {
        return false;
    }
    let excluded = excludes.iter().any(|(x, y)| (*x == a.body && *y == b.body) || (*x == b.body && *y == a.body));
    if excluded {
        return false;
    }
    (a.contype & b.conaffinity) != 0 || (b.contype & a.conaffinity) != 0
}
