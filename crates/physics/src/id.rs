//! Handles to the world's objects: an index into the world's arrays and the generation of
//! that slot, so a handle kept past its object's destruction is refused instead of naming
//! whatever took the slot next (Box2D v3's `b2BodyId`, Rapier's arena handles).

use std::fmt;

/// A body's handle. A body from a scene file keeps its index in the file's `bodies` as its
/// `index`, with generation 0.
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize, serde::Deserialize,
)]
pub struct BodyId {
    /// Slot in the world's body arrays.
    pub index: u32,
    /// How many bodies held the slot before this one.
    pub generation: u32,
}

/// A shape's handle: like [`BodyId`], for the world's shapes.
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize, serde::Deserialize,
)]
pub struct ShapeId {
    /// Slot in the world's shape arrays.
    pub index: u32,
    /// How many shapes held the slot before this one.
    pub generation: u32,
}

/// A joint's handle: like [`BodyId`], for the world's joints. A joint from a scene file keeps
/// its index in the file's `joints`.
#[derive(
    Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize, serde::Deserialize,
)]
pub struct JointId {
    /// Slot in the world's joint array.
    pub index: u32,
    /// How many joints held the slot before this one.
    pub generation: u32,
}

impl fmt::Display for JointId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "joint {} (generation {})", self.index, self.generation)
    }
}

impl BodyId {
    /// The id of the body a scene put at `index` (generation 0).
    pub fn scene(index: usize) -> BodyId {
        BodyId {
            index: index as u32,
            generation: 0,
        }
    }
}

impl fmt::Display for BodyId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "body {} (generation {})", self.index, self.generation)
    }
}

impl fmt::Display for ShapeId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "shape {} (generation {})", self.index, self.generation)
    }
}

/// A joint definition's two bodies as a scene file writes them: by their index in the
/// scene's `bodies`, which is a scene body's `BodyId::index` (generation 0). Written back the
/// same way, so a definition's bodies of a later generation are written by slot alone.
pub(crate) mod scene_bodies {
    use super::BodyId;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    pub fn serialize<S: Serializer>(bodies: &[BodyId; 2], s: S) -> Result<S::Ok, S::Error> {
        [bodies[0].index, bodies[1].index].serialize(s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<[BodyId; 2], D::Error> {
        let [a, b] = <[u32; 2]>::deserialize(d)?;
        Ok([BodyId::scene(a as usize), BodyId::scene(b as usize)])
    }
}

/// Slots of one kind of object: which are in use, each slot's generation, and the free
/// slots, reused lowest first so that a run that creates and destroys the same things gets
/// the same ids (determinism does not depend on it; replays are easier to read).
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Slots {
    generation: Vec<u32>,
    alive: Vec<bool>,
    /// Free slots, highest first (so `pop` gives the lowest).
    free: Vec<u32>,
}

impl Slots {
    /// Slots ever made (live or free).
    pub fn len(&self) -> usize {
        self.alive.len()
    }

    /// Slots in use.
    pub fn live(&self) -> usize {
        self.alive.len() - self.free.len()
    }

    /// Whether slot `i` holds a live object.
    #[inline]
    pub fn is_alive(&self, i: usize) -> bool {
        self.alive.get(i).copied().unwrap_or(false)
    }

    /// The generation of slot `i`.
    pub fn generation(&self, i: usize) -> u32 {
        self.generation[i]
    }

    /// Whether `(index, generation)` names a live object.
    pub fn holds(&self, index: u32, generation: u32) -> bool {
        self.is_alive(index as usize) && self.generation[index as usize] == generation
    }

    /// The slot the next `take` gives.
    pub fn next_index(&self) -> u32 {
        self.free.last().copied().unwrap_or(self.alive.len() as u32)
    }

    /// Takes a slot: the lowest free one, or a new one at the end. Returns its index and
    /// generation and whether it is new (the caller's arrays must grow).
    pub fn take(&mut self) -> (u32, u32, bool) {
        if let Some(i) = self.free.pop() {
            self.alive[i as usize] = true;
            (i, self.generation[i as usize], false)
        } else {
            self.alive.push(true);
            self.generation.push(0);
            ((self.alive.len() - 1) as u32, 0, true)
        }
    }

    /// Gives slot `i` back; its next holder gets the next generation.
    pub fn release(&mut self, i: u32) {
        debug_assert!(self.alive[i as usize]);
        self.alive[i as usize] = false;
        self.generation[i as usize] = self.generation[i as usize].wrapping_add(1);
        // Keep `free` sorted highest first.
        let at = self.free.partition_point(|&f| f > i);
        self.free.insert(at, i);
    }

    /// Checks the free list against the live flags (for `World::validate`).
    pub fn check(&self) -> Result<(), String> {
        let dead = self.alive.iter().filter(|a| !**a).count();
        if dead != self.free.len() {
            return Err(format!(
                "{dead} free slots, {} on the free list",
                self.free.len()
            ));
        }
        if self.free.iter().any(|&f| self.is_alive(f as usize)) {
            return Err("a live slot on the free list".into());
        }
        if self.free.windows(2).any(|w| w[0] <= w[1]) {
            return Err("free list out of order".into());
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_released_slot_is_reused_with_the_next_generation() {
        let mut s = Slots::default();
        assert_eq!(s.take(), (0, 0, true));
        assert_eq!(s.take(), (1, 0, true));
        assert_eq!(s.take(), (2, 0, true));
        s.release(2);
        s.release(0);
        assert!(!s.holds(0, 0) && s.holds(1, 0));
        assert_eq!(s.live(), 1);
        // Lowest first, one generation on.
        assert_eq!(s.take(), (0, 1, false));
        assert_eq!(s.take(), (2, 1, false));
        assert!(s.holds(0, 1) && !s.holds(0, 0));
        assert_eq!(s.check(), Ok(()));
    }
}
