//! Positions and orientations as MJCF writes them, with MuJoCo's conventions (MJCF reference,
//! "Frame orientations"): `quat` is `w x y z` and normalised; `axisangle` is an axis (normalised)
//! and an angle; `euler` three angles about the axes of `<compiler eulerseq>` (lowercase: rotating
//! axes, `q ← q · r`; uppercase: fixed axes, `q ← r · q`); `xyaxes` the frame's x and y axes
//! (y made orthogonal to x, then z = x × y); `zaxis` the frame's z axis (the shortest rotation from
//! +z, as `mjuu_z2quat`). Angles are in degrees unless `<compiler angle="radian">`. At most one
//! form per element.

use super::attrs::View;
use super::{Compiler, MjcfError, MjcfErrorKind};
use crate::math::{DQuat, DVec3};

/// The forms of orientation, in the order they are looked for.
pub const ORIENTATIONS: [&str; 5] = ["quat", "axisangle", "euler", "xyaxes", "zaxis"];

/// A rigid placement: `parent_from_child` rotation and the child's origin in the parent.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose {
    pub rot: DQuat,
    pub pos: DVec3,
}

impl Pose {
    pub const IDENTITY: Pose = Pose { rot: DQuat::IDENTITY, pos: DVec3::ZERO };

    pub fn translation(pos: DVec3) -> Pose {
        Pose { rot: DQuat::IDENTITY, pos }
    }

    /// `self ∘ child`: the child's placement given in this pose's frame, expressed in the parent.
    pub fn then(&self, child: &Pose) -> Pose {
        Pose { rot: (self.rot * child.rot).normalize(), pos: self.pos + self.rot * child.pos }
    }

    pub fn inverse(&self) -> Pose {
        let inv = self.rot.inverse();
        Pose { rot: inv, pos: -(inv * self.pos) }
    }

    /// As a Plücker transform `child_X_parent`.
    pub fn xform(&self) -> crate::multibody::Xform {
        crate::multibody::Xform::from_pose(crate::math::DMat3::from_quat(self.rot), self.pos)
    }
}

/// The rotation taking +z to the unit vector `z` (MuJoCo's `mjuu_z2quat`).
pub fn z_to_quat(z: DVec3) -> DQuat {
    let mut axis = DVec3::Z.cross(z);
    let s = axis.length();
    if s < 1e-10 {
        axis = DVec3::X;
    } else {
        axis /= s;
    }
    DQuat::from_axis_angle(axis, s.atan2(z.z))
}

/// The orientation written on an element (or given by its class), `None` when there is none.
pub fn orientation(view: &View, compiler: &Compiler) -> Result<Option<DQuat>, MjcfError> {
    // the element's own forms win over its class's
    let own: Vec<&str> = ORIENTATIONS.iter().copied().filter(|n| view.written(n)).collect();
    let forms: Vec<&str> =
        if own.is_empty() { ORIENTATIONS.iter().copied().filter(|n| view.get(n).is_some()).collect() } else { own };
    if forms.len() > 1 {
        return Err(view.err(
            forms[1],
            MjcfErrorKind::Invalid(format!("orientation given twice ({} and {})", forms[0], forms[1])),
        ));
    }
    let Some(&form) = forms.first() else { return Ok(None) };
    let angle = |a: f64| if compiler.degree { a.to_radians() } else { a };
    let q = match form {
        "quat" => {
            let v = view.vec("quat", 4)?.expect("present");
            let q = DQuat::from_xyzw(v[1], v[2], v[3], v[0]);
            let n = q.length();
            if !(n > 1e-10) {
                return Err(view.err("quat", MjcfErrorKind::Invalid("a zero quaternion".into())));
            }
            q / n
        }
        "axisangle" => {
            let v = view.vec("axisangle", 4)?.expect("present");
            let axis = DVec3::new(v[0], v[1], v[2]);
            let n = axis.length();
            if !(n > 1e-10) {
                return Err(view.err("axisangle", MjcfErrorKind::Invalid("a zero axis".into())));
            }
            DQuat::from_axis_angle(axis / n, angle(v[3]))
        }
        "euler" => {
            let v = view.vec("euler", 3)?.expect("present");
            let mut q = DQuat::IDENTITY;
            for (k, &c) in compiler.eulerseq.iter().enumerate() {
                let axis = match c.to_ascii_lowercase() {
                    b'x' => DVec3::X,
                    b'y' => DVec3::Y,
                    _ => DVec3::Z,
                };
                let r = DQuat::from_axis_angle(axis, angle(v[k]));
                // rotating axes (lowercase): q · r; fixed axes (uppercase): r · q
                q = if c.is_ascii_lowercase() { q * r } else { r * q };
            }
            q.normalize()
        }
        "xyaxes" => {
            let v = view.vec("xyaxes", 6)?.expect("present");
            let x = DVec3::new(v[0], v[1], v[2]);
            let y = DVec3::new(v[3], v[4], v[5]);
            let nx = x.length();
            if !(nx > 1e-10) {
                return Err(view.err("xyaxes", MjcfErrorKind::Invalid("a zero x axis".into())));
            }
            let x = x / nx;
            let y = y - x * x.dot(y);
            let ny = y.length();
            if !(ny > 1e-10) {
                return Err(view.err("xyaxes", MjcfErrorKind::Invalid("y is parallel to x".into())));
            }
            let y = y / ny;
            let z = x.cross(y);
            DQuat::from_mat3(&crate::math::DMat3::from_cols(x, y, z)).normalize()
        }
        _ => {
            let v = view.vec("zaxis", 3)?.expect("present");
            let z = DVec3::new(v[0], v[1], v[2]);
            let n = z.length();
            if !(n > 1e-10) {
                return Err(view.err("zaxis", MjcfErrorKind::Invalid("a zero axis".into())));
            }
            z_to_quat(z / n)
        }
    };
    Ok(Some(q))
}

/// `pos` and the orientation of an element, identity where absent.
pub fn pose(view: &View, compiler: &Compiler) -> Result<Pose, MjcfError> {
    let pos = view.vec("pos", 3)?.map(|v| DVec3::new(v[0], v[1], v[2])).unwrap_or(DVec3::ZERO);
    let rot = orientation(view, compiler)?.unwrap_or(DQuat::IDENTITY);
    Ok(Pose { rot, pos })
}
