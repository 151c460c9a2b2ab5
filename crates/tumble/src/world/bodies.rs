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

use crate::body::RigidBody;
use std::ops::{Deref, DerefMut};

/// The bodies of a [`World`](super::World), in scene order: a `Vec<RigidBody>` to its users
/// (`Deref`/`DerefMut`), with a note of whether it was borrowed mutably since the last step.
#[derive(Debug, Clone, Default)]
pub struct Bodies {
    list: Vec<RigidBody>,
    /// Borrowed mutably (possibly changed) since the end of the last step.
    lent: bool,
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
        &mut self.list
    }
}

impl From<Vec<RigidBody>> for Bodies {
    fn from(list: Vec<RigidBody>) -> Self {
        Self { list, lent: true }
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
}
