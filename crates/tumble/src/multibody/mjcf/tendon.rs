//! `<tendon><fixed>`: fixed tendons read into [`FixedTendon`]s of the model.
//!
//! MuJoCo's fixed tendon has the length `L = Σ c_i qpos_i`; tumble's `q = qpos − ref`, so
//! `L = L₀ + Σ c_i q_i` with `L₀ = Σ c_i ref_i`. Its `springlength` defaults to `-1`: the length at
//! `qpos_spring` (each joint's `springref`), as MuJoCo's compiler computes it; two values give a
//! dead band. Read: `name`, `class`, `stiffness`, `damping`, `springlength`, `limited`/`range`
//! ([`FixedTendon::range`], with `limited="auto"` following the compiler's `autolimits`; `lo ≤ hi`
//! checked): a one-sided limit on `L` when the robot's joint limits are enforced
//! ([`crate::multibody::JointLimitSolver`], and the contact stage's rows for a held robot). A
//! tendon's `margin`, `solreflimit`, `solimplimit` are warned (soft parameters: the limit is hard).
//! Refused: spatial tendons, tendon `frictionloss` and `armature`.

use super::attrs::{all_zero, View};
use super::build::{unsupported, Reader};
use super::layout::MujocoLayout;
use super::xml::El;
use super::{MjcfError, MjcfErrorKind};
use crate::multibody::joint::JointKind;
use crate::multibody::tendon::{FixedTendon, TendonTerm};
use crate::multibody::MultibodyModel;

/// Every `<tendon>` child of the file, as fixed tendons of `model` (whose joints it names).
pub(super) fn read_tendons(
    reader: &mut Reader,
    root: &El,
    model: &MultibodyModel,
    layout: &MujocoLayout,
) -> Result<Vec<FixedTendon>, MjcfError> {
    let mut out: Vec<FixedTendon> = Vec::new();
    for el in root.children.iter().filter(|e| e.tag == "tendon") {
        for t in &el.children {
            if t.tag != "fixed" {
                return Err(t.error(unsupported("spatial tendons")));
            }
            let mut v = reader.view(t, None)?;
            // tendon defaults are stored under "tendon"; the element's tag is "fixed"
            v.set_default_tag("tendon");
            v.check_known(&[
                "name",
                "class",
                "group",
                "limited",
                "actuatorfrclimited",
                "range",
                "actuatorfrcrange",
                "solreflimit",
                "solimplimit",
                "solreffriction",
                "solimpfriction",
                "frictionloss",
                "springlength",
                "width",
                "material",
                "margin",
                "stiffness",
                "damping",
                "armature",
                "rgba",
                "user",
            ])?;
            v.refuse_unless("frictionloss", all_zero, "tendon frictionloss: dry friction along a tendon")?;
            v.refuse_unless(
                "armature",
                all_zero,
                "tendon armature: an inertia along the tendon couples the mass matrix across the tree",
            )?;
            v.refuse_unless("actuatorfrcrange", all_zero, "actuatorfrcrange on a tendon")?;
            reader.soft(&v);
            let name = v.str("name").map(str::to_string).unwrap_or_else(|| format!("tendon{}", out.len()));
            if v.str("name").is_some() && out.iter().any(|o| o.name == name) {
                return Err(v.err("name", MjcfErrorKind::Invalid(format!("a second tendon named '{name}'"))));
            }
            let range = v.vec("range", 2)?;
            let limited = match v.keyword("limited", &["true", "false", "auto"])?.unwrap_or("auto") {
                "true" => true,
                "false" => false,
                _ => reader.compiler.autolimits && range.is_some(),
            };
            let range = if limited {
                let r =
                    range.ok_or_else(|| v.err("limited", MjcfErrorKind::Invalid("limited without a range".into())))?;
                if r[0] > r[1] {
                    return Err(v.err("range", MjcfErrorKind::Invalid(format!("lower {} > upper {}", r[0], r[1]))));
                }
                // MuJoCo compares ten_length (in qpos units) with the range; `length()` includes L₀
                Some((r[0], r[1]))
            } else {
                None
            };
            let stiffness = v.nonneg("stiffness", 0.0)?;
            let damping = v.nonneg("damping", 0.0)?;
            let mut terms: Vec<TendonTerm> = Vec::new();
            let mut offset = 0.0;
            let mut spring_at = 0.0;
            for j in &t.children {
                if j.tag != "joint" {
                    return Err(j.error(MjcfErrorKind::Invalid(format!("unknown element <{}> in <fixed>", j.tag))));
                }
                let jv = View::new(j, None);
                jv.check_known(&["joint", "coef"])?;
                let Some(joint) = jv.str("joint") else {
                    return Err(j.error(MjcfErrorKind::MissingAttribute("joint")));
                };
                let Some(coef) = jv.numbers("coef")?.and_then(|c| c.first().copied()) else {
                    return Err(j.error(MjcfErrorKind::MissingAttribute("coef")));
                };
                let Some(b) = model.joint_index(joint) else {
                    return Err(jv.err("joint", MjcfErrorKind::Invalid(format!("no joint named '{joint}'"))));
                };
                let mj = &model.bodies[b].joint;
                if !matches!(
                    mj.kind,
                    JointKind::Revolute { .. } | JointKind::Continuous { .. } | JointKind::Prismatic { .. }
                ) {
                    return Err(jv.err(
                        "joint",
                        MjcfErrorKind::Invalid(format!(
                            "joint '{joint}' is a {} joint: a fixed tendon couples hinges and slides",
                            mj.kind.name()
                        )),
                    ));
                }
                // L = Σ c qpos = Σ c (q + ref); the spring's default length at qpos_spring = springref
                let reference = layout.joints[b].reference;
                offset += coef * reference;
                spring_at += coef * (mj.dynamics.spring_ref + reference);
                match terms.iter_mut().find(|t| t.body == b) {
                    Some(term) => term.coef += coef,
                    None => terms.push(TendonTerm { body: b, q_index: mj.q_index, v_index: mj.v_index, coef }),
                }
            }
            if terms.is_empty() {
                return Err(t.error(MjcfErrorKind::Invalid("a fixed tendon without a <joint>".into())));
            }
            let spring_length = match v.numbers("springlength")?.as_deref() {
                None => (spring_at, spring_at),
                Some([l]) if *l == -1.0 => (spring_at, spring_at),
                Some([l]) => (*l, *l),
                Some([lo, hi]) if *lo == -1.0 && *hi == -1.0 => (spring_at, spring_at),
                Some([lo, hi]) if lo <= hi => (*lo, *hi),
                Some(_) => {
                    return Err(v.err(
                        "springlength",
                        MjcfErrorKind::Invalid("one length, or two with the first not above the second".into()),
                    ))
                }
            };
            out.push(FixedTendon { name, terms, offset, stiffness, spring_length, damping, range });
        }
    }
    Ok(out)
}
