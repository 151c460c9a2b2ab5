//! The free bodies' integration under `semi_implicit_euler`, eight bodies at a time with AVX-512,
//! four otherwise ([`crate::integrate::batch`]); bit-identical to the per-body loop of `integrate_free_bodies`,
//! with the same divergence check: the first diverged body in scene order is named, and every body
//! stepped so far has its state saved for the undo.
//!
//! Two ways, the same bits:
//! - **by rows**: each group of bodies is gathered from `World::bodies` (rows of four adjacent
//!   fields, transposed into lanes), stepped and scattered back;
//! - **from blocks** ([`FreePack`]): while the bodies are not changed between steps, the step keeps
//!   the moving bodies' constants and states in its own compact layout ([`Block`]: eight lanes per
//!   number, 352 bytes per body against the seven cache lines of a `RigidBody`), steps them there and
//!   writes each new state into `World::bodies`, so that every reader sees it. The blocks are made
//!   when the bodies still bear, at the start of a step, the seal ([`Bodies::seal`](super::Bodies))
//!   put on them at the end of the step before, for as many steps in a row as `FreePack::wait`
//!   asks (one, more after blocks that were dropped before they paid): a caller who changes the
//!   bodies at every step, or every few steps, never pays for making them. They are used only
//!   without robots and with no body asleep.

use super::{check_state, Diverged, Stop, World};
use crate::body::RigidBody;
use crate::integrate::batch::{
    batch_width, batchable, semi_implicit_euler_batch, step_blocks, Block, BLOCK, MAX_LANES,
};
use crate::integrate::euler::semi_implicit_euler_step;
use crate::integrate::BodyRhs;

/// The moving bodies in the free-body step's own layout, valid while `World::bodies` bears the seal
/// they were made under (see the module's documentation).
#[derive(Clone, Default)]
pub(super) struct FreePack {
    /// The batchable moving bodies, eight by eight in scene order.
    blocks: Vec<Block>,
    /// The moving bodies that take the scalar step (loads that depend on the orientation), in order.
    scalar: Vec<usize>,
    /// The blocks' state copy that holds the bodies' present states.
    parity: usize,
    /// The seal of the bodies the blocks were made from; 0: none.
    seal: u64,
    /// Whether a moving body has a shape.
    shaped: bool,
    /// The seal put on the bodies at the end of the last step taken by rows: if they still bear it
    /// at the next step, they were not changed in between.
    pending: u64,
    /// Steps in a row that found the bodies as the step before left them (without blocks).
    unchanged: u32,
    /// Such steps needed before the blocks are made (0 counts as 1): doubled (up to [`MAX_WAIT`])
    /// each time blocks are dropped before they served [`PAYING_STEPS`] steps — so the first such
    /// drop leaves it at 1, the next ones make it 2, 4, … —, back to 1 when they did. A
    /// caller who changes the bodies every few steps would otherwise pay for making the blocks
    /// (a step's worth of reading) more often than they save.
    wait: u32,
    /// Steps taken from the present blocks.
    served: u32,
}

/// Steps from the blocks that pay for making them (each saves about a third of a step by rows).
const PAYING_STEPS: u32 = 4;

/// The longest wait, in steps without a change, before the blocks are made.
const MAX_WAIT: u32 = 64;

impl std::fmt::Debug for FreePack {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FreePack")
            .field("blocks", &self.blocks.len())
            .field("scalar", &self.scalar.len())
            .field("seal", &self.seal)
            .finish_non_exhaustive()
    }
}

impl FreePack {
    /// Makes the blocks from the bodies, which bear the seal `seal`.
    fn make(&mut self, bodies: &[RigidBody], seal: u64) {
        self.blocks.clear();
        self.scalar.clear();
        self.shaped = false;
        self.parity = 0;
        self.served = 0;
        let mut group = [0usize; BLOCK];
        let mut count = 0;
        for (index, body) in bodies.iter().enumerate().filter(|(_, b)| !b.fixed) {
            self.shaped |= body.shape.is_some();
            if !batchable(body) {
                self.scalar.push(index);
                continue;
            }
            group[count] = index;
            count += 1;
            if count == BLOCK {
                self.blocks.push(Block::new(bodies, &group));
                count = 0;
            }
        }
        if count > 0 {
            self.blocks.push(Block::new(bodies, &group[..count]));
        }
        self.seal = seal;
    }
}

impl World {
    /// `integrate_free_bodies` for `semi_implicit_euler`: the batchable bodies go through the
    /// batched step (eight or four lanes, [`batch_width`]) in scene order, the others through the scalar step (a pending group is stepped
    /// first, so bodies are stepped and checked in scene order); `watch`: stop at the first moving
    /// body with a shape. When stopped, the number of bodies whose states were saved (`save`) so far.
    pub(super) fn integrate_free_bodies_batched(&mut self, save: bool, watch: bool) -> Result<(), (usize, Stop)> {
        if self.step_packed(watch) {
            return Ok(());
        }
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
        self.pack.pending = self.bodies.put_seal();
        Ok(())
    }

    /// Steps the moving bodies from the blocks, if they hold (the bodies bear their seal) or can be
    /// made (the bodies bear the seal of the step before), no robot steps after them, no body is
    /// asleep, and, when `watch`, no moving body has a shape. `false`: not stepped, or stepped with
    /// a state that fails the quick sanity test and undone; the caller steps by rows, which names the
    /// body with the full check (or finds the state sane: `|q|² > 4` alone is not a divergence).
    fn step_packed(&mut self, watch: bool) -> bool {
        // the blocks hold no sleeping body, and the robots' step may undo the bodies' (`World::undo`
        // restores from the scratch, which this path does not write)
        if !self.robots.is_empty() || self.contact.sleep().count() > 0 {
            return false;
        }
        let seal = self.bodies.seal();
        let pack = &mut self.pack;
        if seal == 0 || (seal != pack.seal && seal != pack.pending) {
            // changed since the last step: drop the blocks, and wait longer before making them
            // again if they did not pay
            if pack.seal != 0 {
                pack.wait = if pack.served < PAYING_STEPS { (pack.wait * 2).clamp(1, MAX_WAIT) } else { 1 };
                pack.seal = 0;
            }
            pack.unchanged = 0;
            return false;
        }
        if seal != pack.seal {
            pack.unchanged += 1;
            if pack.unchanged < pack.wait.max(1) {
                return false;
            }
            pack.make(&self.bodies, seal);
        }
        if watch && self.pack.shaped {
            return false;
        }
        let (gravity, h) = (self.config.gravity, self.config.dt);
        let (pack, scratch) = (&mut self.pack, &mut self.scratch);
        let bodies = self.bodies.sealed_mut();
        let parity = pack.parity;
        if let Err(last) = step_blocks(&mut pack.blocks, parity, bodies, gravity, h) {
            for block in &pack.blocks[..=last] {
                block.restore(parity, bodies);
            }
            return false;
        }
        for (n, &index) in pack.scalar.iter().enumerate() {
            let body = &mut bodies[index];
            scratch[index].before = body.state;
            let rhs = BodyRhs { mass: &body.mass, loads: &body.loads, gravity_world: body.gravity(gravity) };
            semi_implicit_euler_step(&rhs, &mut body.state, h);
            if check_state(body).is_some() {
                for &i in &pack.scalar[..=n] {
                    bodies[i].state = scratch[i].before;
                }
                for block in &pack.blocks {
                    block.restore(parity, bodies);
                }
                return false;
            }
        }
        pack.parity = 1 - parity;
        pack.served += 1;
        true
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

    /// The seal of the bodies the free-body layout was made from (0: none), for tests.
    #[cfg(test)]
    pub(super) fn pack_seal(&self) -> u64 {
        self.pack.seal
    }

    /// The error for body `index` diverging in the current step.
    #[cold]
    fn diverged(&self, index: usize, quantity: String) -> Diverged {
        let step = self.steps + 1;
        Diverged { body: self.bodies[index].name.clone(), quantity, step, time: step as f64 * self.config.dt }
    }
}
