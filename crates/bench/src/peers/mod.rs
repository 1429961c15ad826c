//! The same scene in Box2D v3 (boxdd) and Rapier2D, built from the same `SceneDef` numbers that
//! tumble's `World::from_scene` reads, with tumble's step settings where the peer has them.

pub mod box2d;
pub mod rapier;

use anyhow::Result;

/// A peer engine's world, stepped with the scene's `dt` and substeps.
pub trait Peer {
    /// One step (what is timed).
    fn step(&mut self) -> Result<()>;
    /// Body `index` of the scene: (x, y, angle).
    fn pose(&mut self, index: usize) -> Result<[f32; 3]>;
}

/// A peer error as an `anyhow` error (the peers' error types are not all `Send + Sync`).
pub(crate) fn ok<T, E: std::fmt::Display>(r: Result<T, E>, what: &str) -> Result<T> {
    r.map_err(|e| anyhow::anyhow!("{what}: {e}"))
}
