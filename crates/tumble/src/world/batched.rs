//! The free bodies' integration under `semi_implicit_euler`, eight bodies at a time with AVX-512,
//! four otherwise ([`crate::integrate::batch`]); bit-identical to the per-body loop of `integrate_free_bodies`,
//! with the same divergence check: the first diverged body in scene order is named, and every body
//! stepped so far has its state saved for the undo.

use super::{check_state, Diverged, Stop, World};
use crate::integrate::batch::{batch_width, batchable, semi_implicit_euler_batch, MAX_LANES};
use crate::integrate::euler::semi_implicit_euler_step;
use crate::integrate::BodyRhs;

impl World {
    /// `integrate_free_bodies` for `semi_implicit_euler`: the batchable bodies go through the
    /// batched step (eight or four lanes, [`batch_width`]) in scene order, the others through the scalar step (a pending group is stepped
    /// first, so bodies are stepped and checked in scene order); `watch`: stop at the first moving
    /// body with a shape. When stopped, the number of bodies whose states were saved (`save`) so far.
    pub(super) fn integrate_free_bodies_batched(&mut self, save: bool, watch: bool) -> Result<(), (usize, Stop)> {
        let width = batch_width();
        let mut group = [0usize; MAX_LANES];
        let mut count = 0;
        for index in 0..self.bodies.len() {
            let body = &mut self.bodies[index];
            if body.fixed {
                continue;
            }
            if watch && body.shape.is_some() {
                return Err((index, Stop::Shaped(index)));
            }
            if save {
                self.scratch[index].before = body.state;
            }
            if self.contact.sleep().is_asleep(index) {
                continue;
            }
            if batchable(body) {
                group[count] = index;
                count += 1;
                if count == width {
                    self.step_group(&group, count)?;
                    count = 0;
                }
                continue;
            }
            if count > 0 {
                self.step_group(&group, count)?;
                count = 0;
            }
            let body = &mut self.bodies[index];
            let gravity_world = body.gravity(self.config.gravity);
            let rhs = BodyRhs { mass: &body.mass, loads: &body.loads, gravity_world };
            semi_implicit_euler_step(&rhs, &mut body.state, self.config.dt);
            if let Some(quantity) = check_state(body) {
                return Err((index + 1, Stop::Diverged(self.diverged(index, quantity))));
            }
        }
        if count > 0 {
            self.step_group(&group, count)?;
        }
        Ok(())
    }

    /// Steps the bodies `group[..count]` (ascending indices) and checks them in order.
    #[inline]
    fn step_group(&mut self, group: &[usize; MAX_LANES], count: usize) -> Result<(), (usize, Stop)> {
        let insane = semi_implicit_euler_batch(&mut self.bodies, group, count, self.config.gravity, self.config.dt);
        if insane != 0 {
            for &index in &group[..count] {
                if let Some(quantity) = check_state(&self.bodies[index]) {
                    return Err((group[count - 1] + 1, Stop::Diverged(self.diverged(index, quantity))));
                }
            }
        }
        Ok(())
    }

    /// The error for body `index` diverging in the current step.
    #[cold]
    fn diverged(&self, index: usize, quantity: String) -> Diverged {
        let step = self.steps + 1;
        Diverged { body: self.bodies[index].name.clone(), quantity, step, time: step as f64 * self.config.dt }
    }
}
