//! A body's shape as written → [`Shape`]: `shape = { type = "...", ... }`, or a compound,
//! `shapes = [ { type = "...", ..., position = [...], orientation = [...] }, ... ]`.
//!
//! Errors name `body[i].shape.<key>` or `body[i].shapes[k].<key>`. A mesh file is read and measured
//! here, and a concave mesh on a moving body is decomposed into convex pieces (once per `[[body]]`
//! entry or grid template: copies share it).

use super::body::BodyReader;
use super::error::{nearest, num, nums, SceneError};
use super::schema::{BodyDoc, Loc, ShapeDoc, Table};
use crate::body::{CompoundPart, CompoundShape, ConvexShape, MeshShape, Shape};
use crate::math::{DQuat, DVec3};
use crate::mesh::MeshLimits;
use std::path::Path;
use std::sync::Arc;

/// A mesh whose convex hull exceeds its volume by more than this fraction is concave: on a moving
/// body it collides as a convex decomposition, not as its hull.
pub(crate) const MESH_HULL_TOLERANCE: f64 = 0.01;

/// The shape types, as written in files.
pub(crate) const SHAPE_TYPES: [&str; 7] = ["sphere", "box", "capsule", "cylinder", "plane", "mesh", "convex"];

/// The shape types a compound's part may have.
const PART_TYPES: [&str; 5] = ["sphere", "box", "capsule", "cylinder", "convex"];

impl BodyReader<'_, '_> {
    /// The body's shape: `shape` or `shapes` (not both); `fixed` for a fixed body (a concave mesh on
    /// a moving body is decomposed).
    pub(super) fn shape(&mut self, doc: &BodyDoc, fixed: bool) -> Result<Option<Shape>, SceneError> {
        match (&doc.shape, &doc.shapes) {
            (Some(_), Some(parts)) => Err(self
                .err("shapes", parts, "give `shape` (one shape) or `shapes` (a compound), not both")
                .hint("put the shape of `shape` into `shapes` as one more part")),
            (Some(loc), None) => self.one_shape("shape", loc, fixed, false).map(Some),
            (None, Some(parts)) => self.compound(parts).map(Some),
            (None, None) => Ok(None),
        }
    }

    /// One shape table at `key` (`shape` or `shapes[k]`); `part` for a compound's part, which may
    /// (and alone may) have `position` and `orientation`.
    fn one_shape(
        &mut self,
        key: &str,
        loc: &Loc<Table<ShapeDoc>>,
        fixed: bool,
        part: bool,
    ) -> Result<Shape, SceneError> {
        let s = &loc.value;
        let kind = s.kind.value.as_str();
        let takes: &[&str] = match kind {
            "sphere" => &["radius"],
            "box" => &["half_extents"],
            "capsule" | "cylinder" => &["radius", "half_height"],
            "plane" => &[],
            "mesh" => &["file", "scale"],
            "convex" => &["points"],
            _ => {
                let e = self.err(&format!("{key}.type"), &s.kind, "unknown shape type").got(format!("\"{kind}\""));
                let types: &[&str] = if part { &PART_TYPES } else { &SHAPE_TYPES };
                let list = types.join(", ");
                return Err(match nearest(kind, types) {
                    Some(best) => e.hint(format!("did you mean `{best}`? (shape types: {list})")),
                    None => e.hint(format!("shape types: {list}")),
                });
            }
        };
        if part && !PART_TYPES.contains(&kind) {
            return Err(self
                .err(&format!("{key}.type"), &s.kind, format!("a {kind} cannot be part of a compound"))
                .got(format!("\"{kind}\""))
                .hint(format!(
                    "parts are {}; a {kind} is a body of its own (`shape = {{ type = \"{kind}\", ... }}`)",
                    PART_TYPES.join(", ")
                )));
        }
        let given = [
            ("radius", s.radius.as_ref().map(|l| &l.span)),
            ("half_extents", s.half_extents.as_ref().map(|l| &l.span)),
            ("half_height", s.half_height.as_ref().map(|l| &l.span)),
            ("file", s.file.as_ref().map(|l| &l.span)),
            ("scale", s.scale.as_ref().map(|l| &l.span)),
            ("points", s.points.as_ref().map(|l| &l.span)),
        ];
        for (field, span) in given {
            if let (Some(span), false) = (span, takes.contains(&field)) {
                let takes = if takes.is_empty() { "nothing but `type`".to_string() } else { takes.join(", ") };
                return Err(self
                    .src
                    .error(span.as_ref(), self.at(&format!("{key}.{field}")), format!("a {kind} has no `{field}`"))
                    .hint(format!("a {kind} takes: {takes}")));
            }
        }
        if !part {
            let pose = [
                ("position", s.position.as_ref().map(|l| &l.span)),
                ("orientation", s.orientation.as_ref().map(|l| &l.span)),
            ];
            if let Some((field, Some(span))) = pose.into_iter().find(|(_, span)| span.is_some()) {
                return Err(self
                    .src
                    .error(
                        span.as_ref(),
                        self.at(&format!("{key}.{field}")),
                        format!("`{field}` places a part of a compound; a body's `shape` sits on its centre of mass"),
                    )
                    .hint(format!(
                        "give the body's own `{field}`, or write `shapes = [{{ type = \"{kind}\", ..., {field} = ... }}]`"
                    )));
            }
        }
        match kind {
            "mesh" => return self.mesh(key, s, loc, fixed),
            "convex" => return self.convex(key, s, loc).map(|c| Shape::Convex(Arc::new(c))),
            _ => {}
        }
        let size = |field: &str, l: &Option<Loc<f64>>| -> Result<f64, SceneError> {
            let Some(l) = l else {
                return Err(self.err(key, loc, format!("a {kind} needs `{field}` (m)")));
            };
            if l.value.is_finite() && l.value > 0.0 {
                Ok(l.value)
            } else {
                Err(self
                    .err(&format!("{key}.{field}"), l, format!("{kind} size must be finite and > 0 (m)"))
                    .got(num(l.value)))
            }
        };
        Ok(match kind {
            "sphere" => Shape::Sphere { radius: size("radius", &s.radius)? },
            "box" => {
                let Some(h) = &s.half_extents else {
                    return Err(self.err(key, loc, "a box needs `half_extents` (m)"));
                };
                if h.value.iter().any(|x| !(x.is_finite() && *x > 0.0)) {
                    return Err(self
                        .err(&format!("{key}.half_extents"), h, "box half extents must be finite and > 0 (m)")
                        .got(nums(&h.value)));
                }
                Shape::Box { half_extents: DVec3::from_array(h.value) }
            }
            "capsule" => {
                Shape::Capsule { radius: size("radius", &s.radius)?, half_height: size("half_height", &s.half_height)? }
            }
            "cylinder" => Shape::Cylinder {
                radius: size("radius", &s.radius)?,
                half_height: size("half_height", &s.half_height)?,
            },
            _ => Shape::Plane,
        })
    }

    /// `{ type = "convex", points = [[x, y, z], ...] }`: the hull of at least 4 finite points that do
    /// not all lie in one plane.
    fn convex(&mut self, key: &str, s: &ShapeDoc, loc: &Loc<Table<ShapeDoc>>) -> Result<ConvexShape, SceneError> {
        let Some(points) = &s.points else {
            return Err(self.err(key, loc, "a convex shape needs `points` (at least 4 points [x, y, z], m)"));
        };
        for (k, p) in points.value.iter().enumerate() {
            if p.value.iter().any(|x| !x.is_finite()) {
                let span = p.span.as_ref().or(points.span.as_ref());
                return Err(self
                    .src
                    .error(span, self.at(&format!("{key}.points[{k}]")), "must be finite")
                    .got(nums(&p.value)));
            }
        }
        let xyz: Vec<DVec3> = points.value.iter().map(|p| DVec3::from_array(p.value)).collect();
        ConvexShape::new(&xyz).map_err(|e| {
            let hint = match xyz.len() {
                0..=3 => "a solid needs 4 points not in one plane, e.g. the corners of a tetrahedron",
                _ => "a convex shape is a solid: give points that span three dimensions",
            };
            self.err(&format!("{key}.points"), points, e.to_string()).hint(hint)
        })
    }

    /// `shapes = [ {...}, ... ]`: each part with its `position` (m) and `orientation` (`[w, x, y,
    /// z]`, `compound_from_part`) in the coordinates the parts are written in; the body's origin is
    /// then the compound's centre of mass.
    fn compound(&mut self, parts_loc: &Loc<Vec<Loc<Table<ShapeDoc>>>>) -> Result<Shape, SceneError> {
        if parts_loc.value.is_empty() {
            return Err(self
                .err("shapes", parts_loc, "a compound needs at least one part")
                .hint("give parts such as `{ type = \"sphere\", radius = 0.1, position = [0.0, 0.0, 0.5] }`"));
        }
        let mut parts = Vec::with_capacity(parts_loc.value.len());
        for (k, loc) in parts_loc.value.iter().enumerate() {
            let key = format!("shapes[{k}]");
            let shape = self.one_shape(&key, loc, false, true)?;
            let s = &loc.value;
            let position = self.finite3(&format!("{key}.position"), &s.position)?.unwrap_or(DVec3::ZERO);
            let orientation = match &s.orientation {
                Some(l) => self.quaternion(&format!("{key}.orientation"), l)?,
                None => DQuat::IDENTITY,
            };
            // a convex part sits on its centre of mass, which its points place in the part's axes
            let centre = match &shape {
                Shape::Convex(c) => position + orientation * c.center_of_mass_given,
                _ => position,
            };
            parts.push(CompoundPart { shape, position: centre, orientation });
        }
        CompoundShape::new(parts)
            .map(|c| Shape::Compound(Arc::new(c)))
            .map_err(|e| self.err("shapes", parts_loc, e.to_string()))
    }

    /// `{ type = "mesh", file = "...", scale = ... }`: the file is read, checked and measured now; a
    /// relative path is taken from the scene file's directory. The mesh's warnings (an inside-out
    /// mesh flipped, ...) become the scene's.
    fn mesh(&mut self, key: &str, s: &ShapeDoc, loc: &Loc<Table<ShapeDoc>>, fixed: bool) -> Result<Shape, SceneError> {
        let Some(file) = &s.file else {
            return Err(self.err(key, loc, "a mesh needs `file` (an .obj or .stl file)"));
        };
        let file_key = format!("{key}.file");
        let scale = s.scale.as_ref().map_or([1.0; 3], |l| l.value.0);
        if let (Some(l), false) = (&s.scale, scale.iter().all(|x| x.is_finite() && *x > 0.0)) {
            return Err(self.err(&format!("{key}.scale"), l, "mesh scale must be finite and > 0").got(nums(&scale)));
        }
        let path = Path::new(self.src.origin).parent().unwrap_or(Path::new("")).join(&file.value);
        let loaded = crate::mesh::load(&path, scale, &MeshLimits::default())
            .map_err(|e| self.err(&file_key, file, e.to_string()))?;
        let mut shape = MeshShape::new(file.value.clone(), DVec3::from_array(scale), loaded.mesh)
            .map_err(|e| self.err(&file_key, file, format!("{}: {e}", path.display())))?;
        for w in loaded.warnings {
            let text = format!("{}: {w}", path.display());
            self.warnings.push(self.src.warning(file.span.as_ref(), &self.at(&file_key), &text));
        }
        // a fixed mesh collides as its triangles; a moving concave one as convex pieces
        if !fixed && shape.hull_excess > MESH_HULL_TOLERANCE {
            shape.decompose();
            if shape.decomposition.is_none() {
                let text = format!(
                    "{}: the mesh is concave (its convex hull is {:.1}% larger) and its convex decomposition \
                     failed: it collides as its convex hull",
                    path.display(),
                    100.0 * shape.hull_excess
                );
                self.warnings.push(self.src.warning(file.span.as_ref(), &self.at(&file_key), &text));
            }
        }
        Ok(Shape::Mesh(Arc::new(shape)))
    }
}
