//! [`Bodies`]: the world's `Vec<RigidBody>`, which notes when it was lent out mutably.
//!
//! A sleeping body is checked at each step against what it was when it fell asleep, bit for bit,
//! since the caller may have changed it (`contact::sleep`). That check reads every sleeping body at
//! every step: with a thousand bodies asleep it was a third of the step. Every change a caller can
//! make goes through `&mut Vec<RigidBody>` ([`DerefMut`]), so the list keeps one flag, set there:
//! when no mutable access happened since the last step ended, nothing can have changed and the
//! check is skipped. Readers (`&world.bodies`, `world.bodies[i].state`, `.iter()`) see a
//! `Vec<RigidBody>` through [`Deref`] as before; writers (`world.bodies[i].state.velocity = …`,
//! `.push`, `&mut world.bodies`) too, and mark the list.
//!
//! The same mark breaks the list's *seal*: a number the step puts on the list, unique in the
//! process, that stays on it until the next mutable borrow. The free-body step keeps a copy of the
//! moving bodies in its own compact layout (`world::batched`) under the seal it was made from: while
//! the list still bears that seal, nothing can have changed and the copy holds.

use crate::body::RigidBody;
use std::ops::{Deref, DerefMut};
use std::sync::atomic::{AtomicU64, Ordering};

/// The last seal put on a list (seals are unique in the process; 0 is none).
static SEALS: AtomicU64 = AtomicU64::new(0);

/// The bodies of a [`World`](super::World), in scene order: a `Vec<RigidBody>` to its users
/// (`Deref`/`DerefMut`), with a note of whether it was borrowed mutably since the last step.
#[derive(Debug, Clone, Default)]
pub struct Bodies {
    list: Vec<RigidBody>,
    /// Borrowed mutably (possibly changed) since the end of the last step.
    lent: bool,
    /// The seal put on the list and not broken since by a mutable borrow; 0: none.
    seal: u64,
}

impl Bodies {
    /// The bodies, out of the world.
    pub fn into_vec(self) -> Vec<RigidBody> {
        self.list
    }

    /// Whether the list was borrowed mutably since the end of the last step (a body may have
    /// changed). A new list counts as borrowed.
    pub(crate) fn lent(&self) -> bool {
        self.lent
    }

    /// At the end of a step: the step's own changes are its own.
    pub(crate) fn step_ended(&mut self) {
        self.lent = false;
    }

    /// The list's seal: the number [`Bodies::put_seal`] gave it, if it was not borrowed mutably
    /// since; 0 otherwise.
    pub(crate) fn seal(&self) -> u64 {
        self.seal
    }

    /// Puts a new seal on the list, unique in the process, and returns it.
    pub(crate) fn put_seal(&mut self) -> u64 {
        self.seal = SEALS.fetch_add(1, Ordering::Relaxed) + 1;
        self.seal
    }

    /// The bodies to write, keeping the seal: for the step's own writes that the copy kept under
    /// the seal makes as well (the list counts as borrowed for the sleeping bodies' check).
    pub(crate) fn sealed_mut(&mut self) -> &mut [RigidBody] {
        self.lent = true;
        &mut self.list
    }
}

impl Deref for Bodies {
    type Target = Vec<RigidBody>;
    #[inline]
    fn deref(&self) -> &Vec<RigidBody> {
        &self.list
    }
}

impl DerefMut for Bodies {
    #[inline]
    fn deref_mut(&mut self) -> &mut Vec<RigidBody> {
        self.lent = true;
        self.seal = 0;
        &mut self.list
    }
}

impl From<Vec<RigidBody>> for Bodies {
    fn from(list: Vec<RigidBody>) -> Self {
        Self { list, lent: true, seal: 0 }
    }
}

impl From<Bodies> for Vec<RigidBody> {
    fn from(bodies: Bodies) -> Self {
        bodies.list
    }
}

impl FromIterator<RigidBody> for Bodies {
    fn from_iter<I: IntoIterator<Item = RigidBody>>(iter: I) -> Self {
        Vec::from_iter(iter).into()
    }
}

impl PartialEq for Bodies {
    fn eq(&self, other: &Self) -> bool {
        self.list == other.list
    }
}

impl PartialEq<Vec<RigidBody>> for Bodies {
    fn eq(&self, other: &Vec<RigidBody>) -> bool {
        &self.list == other
    }
}

impl<'a> IntoIterator for &'a Bodies {
    type Item = &'a RigidBody;
    type IntoIter = std::slice::Iter<'a, RigidBody>;
    fn into_iter(self) -> Self::IntoIter {
        self.list.iter()
    }
}

impl<'a> IntoIterator for &'a mut Bodies {
    type Item = &'a mut RigidBody;
    type IntoIter = std::slice::IterMut<'a, RigidBody>;
    fn into_iter(self) -> Self::IntoIter {
        self.deref_mut().iter_mut()
    }
}

impl IntoIterator for Bodies {
    type Item = RigidBody;
    type IntoIter = std::vec::IntoIter<RigidBody>;
    fn into_iter(self) -> Self::IntoIter {
        self.list.into_iter()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::MassProperties;
    use crate::math::DVec3;

    fn list() -> Bodies {
        let mp = MassProperties::from_principal(1.0, DVec3::ONE).unwrap();
        vec![RigidBody::new("a", mp), RigidBody::new("b", mp)].into()
    }

    /// Every way of writing to a body marks the list; reading does not.
    #[test]
    fn a_mutable_borrow_marks_the_list_and_a_read_does_not() {
        let mut bodies = list();
        assert!(bodies.lent(), "a new list counts as changed");
        bodies.step_ended();
        let _ = bodies[1].state.velocity;
        let _ = bodies.iter().count();
        for b in &bodies {
            let _ = b.name.len();
        }
        let _: &[RigidBody] = &bodies;
        assert!(!bodies.lent());
        bodies[1].state.velocity.x = 1.0;
        assert!(bodies.lent());
        bodies.step_ended();
        for b in &mut bodies {
            let _ = b.name.len();
        }
        assert!(bodies.lent());
        bodies.step_ended();
        let slice: &mut [RigidBody] = &mut bodies;
        slice[0].fixed = true;
        assert!(bodies.lent());
        bodies.step_ended();
        bodies.iter_mut().for_each(|b| b.gravity_scale = 2.0);
        assert!(bodies.lent());
        bodies.step_ended();
        let first = bodies[0].clone();
        bodies.push(first);
        assert!(bodies.lent());
    }

    /// A seal is unique and lasts until the next mutable borrow; reads and the step's own sealed
    /// writes keep it.
    #[test]
    fn a_seal_is_broken_by_a_mutable_borrow_only() {
        let mut bodies = list();
        assert_eq!(bodies.seal(), 0, "a new list bears no seal");
        let seal = bodies.put_seal();
        assert_ne!(seal, 0);
        let _ = bodies[1].state.velocity;
        let _ = bodies.iter().count();
        bodies.sealed_mut()[0].state.velocity.x = 2.0;
        assert_eq!(bodies.seal(), seal);
        let copy = bodies.clone();
        assert_eq!(copy.seal(), seal, "a copy bears the same seal: the same bodies");
        let mut other = list();
        assert_ne!(other.put_seal(), seal, "seals are unique");
        bodies[1].state.velocity.x = 1.0;
        assert_eq!(bodies.seal(), 0);
        assert_ne!(bodies.put_seal(), seal);
        let slice: &mut [RigidBody] = &mut bodies;
        slice[0].fixed = true;
        assert_eq!(bodies.seal(), 0);
    }
}
