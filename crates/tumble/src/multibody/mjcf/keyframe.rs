//! `<keyframe><key name time qpos qvel ctrl>`: named states in MuJoCo's layout. A key gives any of
//! them; what it does not give is MuJoCo's default (`qpos0`, zero velocities and controls).
//! Lengths must be the model's (`nq`, `nv`, the number of actuators), as MuJoCo requires; `act`,
//! `mpos` and `mquat` must be empty (tumble has no actuator activations and no mocap bodies, both
//! refused elsewhere). Quaternions of ball and free joints are normalised (MuJoCo normalises them
//! where it uses them); a zero one is an error.

use super::attrs::View;
use super::xml::El;
use super::{MjcfError, MjcfErrorKind, MjcfKey, MujocoLayout};
use crate::multibody::MultibodyModel;

/// The keys of `root`'s `<keyframe>` elements.
pub(super) fn read_keyframes(
    root: &El,
    model: &MultibodyModel,
    layout: &MujocoLayout,
    nu: usize,
) -> Result<Vec<MjcfKey>, MjcfError> {
    let mut keys = Vec::new();
    for el in root.children.iter().filter(|e| e.tag == "keyframe") {
        for key in &el.children {
            if key.tag != "key" {
                return Err(key.error(MjcfErrorKind::Invalid(format!("unknown element <{}> in <keyframe>", key.tag))));
            }
            let v = View::new(key, None);
            v.check_known(&["name", "time", "qpos", "qvel", "act", "ctrl", "mpos", "mquat"])?;
            for (attr, what) in [("act", "actuator activations"), ("mpos", "mocap bodies"), ("mquat", "mocap bodies")] {
                if v.numbers(attr)?.is_some_and(|x| !x.is_empty()) {
                    return Err(v.err(attr, MjcfErrorKind::Invalid(format!("the model has no {what}"))));
                }
            }
            let sized = |attr: &'static str, n: usize, default: Vec<f64>| -> Result<Vec<f64>, MjcfError> {
                match v.numbers(attr)? {
                    None => Ok(default),
                    Some(x) if x.len() == n => Ok(x),
                    Some(x) => Err(v.err(
                        attr,
                        MjcfErrorKind::BadValue {
                            value: format!("{} numbers", x.len()),
                            expected: format!("{n} numbers (the model's {attr} size)"),
                        },
                    )),
                }
            };
            let mut qpos = sized("qpos", model.nq(), layout.qpos0())?;
            let qvel = sized("qvel", model.nv(), vec![0.0; model.nv()])?;
            let ctrl = sized("ctrl", nu, vec![0.0; nu])?;
            for b in &model.bodies {
                let (qi, nq) = (b.joint.q_index, b.joint.kind.nq());
                if nq != 4 && nq != 7 {
                    continue;
                }
                let quat = &mut qpos[qi + nq - 4..qi + nq];
                let norm = quat.iter().map(|x| x * x).sum::<f64>().sqrt();
                if !(norm > 1e-10) {
                    return Err(
                        v.err("qpos", MjcfErrorKind::Invalid(format!("joint '{}': a zero quaternion", b.joint.name)))
                    );
                }
                quat.iter_mut().for_each(|x| *x /= norm);
            }
            keys.push(MjcfKey {
                name: v.str("name").map(str::to_string),
                time: v.f64("time", 0.0)?,
                qpos,
                qvel,
                ctrl,
                at: format!("{}:{}:{}", key.pos.file, key.pos.line, key.pos.column),
            });
        }
    }
    Ok(keys)
}
