//! The world's state as one flat vector, for bindings and batched rollouts.
//!
//! Layout (the trajectory CSV row, then the robots): each moving body in scene order
//! `[x, y, z, qw, qx, qy, qz, vx, vy, vz, wx, wy, wz]` — position of the centre of mass, orientation
//! `world_from_user` (the axes the scene gave), velocity and angular velocity, all world frame — then
//! each robot's `q` (nq) then its `v` (nv), in robot order.
//!
//! [`World::write_state`] writes exactly the numbers of a trajectory row (bit for bit).
//! [`World::set_state`] checks the vector (length, finite, magnitudes, unit quaternions) before it
//! changes anything, so a rejected vector leaves the world as it was. Reading back a state just set
//! gives it to round-off (about 1e-16 relative): the body is stored in its principal axes with a body-frame
//! angular velocity, and quaternions are renormalised.
//!
//! Neither function allocates.

use super::{World, MAX_STATE_MAGNITUDE};
use crate::math::{quat_from_wxyz, DVec3};
use crate::multibody::simulate::quaternion_slots;

/// Numbers per moving body in the state vector.
pub const BODY_STATE_LEN: usize = 13;

/// Largest `| |q| − 1 |` of a quaternion accepted by [`World::set_state`] (it is then renormalised).
pub const STATE_QUAT_TOLERANCE: f64 = 1e-6;

/// Why a state vector was rejected. Every variant names the entry.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StateError {
    #[error("state has length {got}, expected {expected} (13 per moving body, then each robot's nq + nv)")]
    Length { expected: usize, got: usize },
    #[error("state[{index}] ({owner}: {quantity}) is not finite (got {value})")]
    NotFinite { index: usize, owner: String, quantity: String, value: f64 },
    #[error("state[{index}] ({owner}: {quantity}) has magnitude {value:e}, beyond {MAX_STATE_MAGNITUDE:e}")]
    TooLarge { index: usize, owner: String, quantity: String, value: f64 },
    #[error(
        "state[{index}..{}] ({owner}: {quantity}) is not a unit quaternion: |q| = {norm} (allowed 1 ± {STATE_QUAT_TOLERANCE:e})",
        index + 4
    )]
    NotUnitQuaternion { index: usize, owner: String, quantity: String, norm: f64 },
}

impl World {
    /// Length of the state vector: 13 per moving body plus `nq + nv` per robot.
    pub fn state_len(&self) -> usize {
        BODY_STATE_LEN * self.free_bodies().count()
            + self.robots.iter().map(|r| r.q().len() + r.v().len()).sum::<usize>()
    }

    /// Writes the state into `out` (length [`state_len`](Self::state_len)): the trajectory row of each
    /// moving body, then each robot's `q` and `v` (see the module's layout).
    pub fn write_state(&self, out: &mut [f64]) -> Result<(), StateError> {
        let expected = self.state_len();
        if out.len() != expected {
            return Err(StateError::Length { expected, got: out.len() });
        }
        let mut k = 0;
        for body in self.free_bodies() {
            out[k..k + BODY_STATE_LEN].copy_from_slice(&crate::trajectory::body_row(body));
            k += BODY_STATE_LEN;
        }
        for robot in &self.robots {
            let (q, v) = (robot.q(), robot.v());
            out[k..k + q.len()].copy_from_slice(q);
            k += q.len();
            out[k..k + v.len()].copy_from_slice(v);
            k += v.len();
        }
        Ok(())
    }

    /// Sets the state from `x` (the layout of [`write_state`](Self::write_state)). Checked first, as a
    /// whole: length, every entry finite and at most [`MAX_STATE_MAGNITUDE`], every body's and every
    /// spherical or floating joint's quaternion of norm `1 ± STATE_QUAT_TOLERANCE` (renormalised).
    /// On `Err` nothing changed. Time, contact history and controls are kept.
    pub fn set_state(&mut self, x: &[f64]) -> Result<(), StateError> {
        self.check_state_vector(x)?;
        let mut k = 0;
        for body in self.bodies.iter_mut().filter(|b| !b.fixed) {
            let row = &x[k..k + BODY_STATE_LEN];
            let vec3 = |i: usize| DVec3::new(row[i], row[i + 1], row[i + 2]);
            body.state.position = vec3(0);
            body.set_orientation_user(quat_from_wxyz([row[3], row[4], row[5], row[6]]));
            body.state.velocity = vec3(7);
            body.set_omega_world(vec3(10));
            k += BODY_STATE_LEN;
        }
        for robot in &mut self.robots {
            let (nq, nv) = (robot.q().len(), robot.v().len());
            robot.set_state(&x[k..k + nq], &x[k + nq..k + nq + nv]);
            k += nq + nv;
        }
        Ok(())
    }

    /// The checks of [`set_state`](Self::set_state), naming the first bad entry.
    fn check_state_vector(&self, x: &[f64]) -> Result<(), StateError> {
        let expected = self.state_len();
        if x.len() != expected {
            return Err(StateError::Length { expected, got: x.len() });
        }
        const BODY_QUANTITIES: [(&str, usize); 4] =
            [("position", 0), ("orientation", 3), ("velocity", 7), ("angular velocity", 10)];
        let mut k = 0;
        for body in self.free_bodies() {
            for (i, &value) in x[k..k + BODY_STATE_LEN].iter().enumerate() {
                let quantity = BODY_QUANTITIES.iter().rev().find(|(_, start)| i >= *start).map_or("", |q| q.0);
                check_entry(k + i, value, || format!("body `{}`", body.name), quantity)?;
            }
            check_unit(&x[k + 3..k + 7], k + 3, || format!("body `{}`", body.name), "orientation")?;
            k += BODY_STATE_LEN;
        }
        for robot in &self.robots {
            let model = &robot.model;
            let owner = || format!("robot `{}`", robot.name);
            for (what, len) in [("q", model.nq()), ("v", model.nv())] {
                for (i, &value) in x[k..k + len].iter().enumerate() {
                    check_entry(k + i, value, owner, &format!("{what}[{i}]"))?;
                }
                if what == "q" {
                    for (joint, start) in quaternion_slots(model) {
                        let quantity = format!("joint `{}` quaternion", joint.name);
                        check_unit(&x[k + start..k + start + 4], k + start, owner, &quantity)?;
                    }
                }
                k += len;
            }
        }
        Ok(())
    }
}

fn check_entry(index: usize, value: f64, owner: impl Fn() -> String, quantity: &str) -> Result<(), StateError> {
    if !value.is_finite() {
        return Err(StateError::NotFinite { index, owner: owner(), quantity: quantity.to_string(), value });
    }
    if value.abs() > MAX_STATE_MAGNITUDE {
        return Err(StateError::TooLarge { index, owner: owner(), quantity: quantity.to_string(), value });
    }
    Ok(())
}

fn check_unit(q: &[f64], index: usize, owner: impl Fn() -> String, quantity: &str) -> Result<(), StateError> {
    let norm = q.iter().map(|c| c * c).sum::<f64>().sqrt();
    if (norm - 1.0).abs() > STATE_QUAT_TOLERANCE {
        return Err(StateError::NotUnitQuaternion { index, owner: owner(), quantity: quantity.to_string(), norm });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use crate::scene;
    use std::path::Path;

    fn scene(name: &str) -> crate::World {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes").join(name);
        scene::load(&path).unwrap().world
    }

    #[test]
    fn state_is_the_trajectory_row_and_reads_back_to_round_off() {
        let mut world = scene("demo.toml");
        for _ in 0..50 {
            world.step().unwrap();
        }
        let mut x = vec![0.0; world.state_len()];
        world.write_state(&mut x).unwrap();
        let first = world.free_bodies().next().unwrap();
        assert_eq!(x[0..3], first.state.position.to_array());
        assert_eq!(x[10..13], first.state.omega_world().to_array());
        let mut other = scene("demo.toml");
        other.set_state(&x).unwrap();
        let mut y = vec![0.0; x.len()];
        other.write_state(&mut y).unwrap();
        for (a, b) in x.iter().zip(&y) {
            assert!((a - b).abs() <= 1e-14 * (1.0 + a.abs()), "{a} vs {b}");
        }
    }

    #[test]
    fn robot_state_round_trips_exactly() {
        let mut world = scene("double_pendulum.toml");
        assert_eq!(world.state_len(), 4);
        let x = [0.3, -0.2, 1.5, -2.0];
        world.set_state(&x).unwrap();
        let mut y = [0.0; 4];
        world.write_state(&mut y).unwrap();
        assert_eq!(x, y);
        let e = world.energy();
        world.set_state(&[1.0, -0.5, 0.0, 0.0]).unwrap();
        assert_ne!(world.energy(), e, "energy follows the state just set");
    }

    #[test]
    fn bad_vectors_are_rejected_and_change_nothing() {
        let mut world = scene("demo.toml");
        let mut x = vec![0.0; world.state_len()];
        world.write_state(&mut x).unwrap();
        let short = world.set_state(&x[1..]).unwrap_err();
        assert!(short.to_string().contains("expected"), "{short}");
        let mut nan = x.clone();
        nan[20] = f64::NAN;
        let e = world.set_state(&nan).unwrap_err().to_string();
        assert!(e.contains("state[20]") && e.contains("not finite"), "{e}");
        let mut long_quat = x.clone();
        long_quat[3] += 0.1;
        let e = world.set_state(&long_quat).unwrap_err().to_string();
        assert!(e.contains("unit quaternion") && e.contains("orientation"), "{e}");
        let mut y = vec![0.0; x.len()];
        world.write_state(&mut y).unwrap();
        assert_eq!(x, y);
    }
}
