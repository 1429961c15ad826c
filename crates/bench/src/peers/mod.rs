//! The same scene in Box2D v3 (boxdd) and Rapier2D, built from the same `SceneDef` numbers that
//! tumble's `World::from_scene` reads, with tumble's step settings where the peer has them.
//!
//! The [`Peer`] trait is always compiled (the accuracy report steps tumble through it too); the
//! peers themselves only with the `peers` feature.

#[cfg(feature = "peers")]
pub mod box2d;
#[cfg(feature = "peers")]
pub mod rapier;

use anyhow::Result;

/// A peer engine's world, stepped with the scene's `dt` and substeps.
pub trait Peer {
    /// One step (what is timed).
    fn step(&mut self) -> Result<()>;
    /// Body `index` of the scene: (x, y, angle).
    fn pose(&mut self, index: usize) -> Result<[f32; 3]>;
    /// Body `index` of the scene: linear velocity of its centre of mass and angular velocity
    /// (vx, vy, w).
    fn velocity(&mut self, index: usize) -> Result<[f32; 3]>;
    /// The last step's time per stage in ms, under the common names of [`STAGES`] (a peer
    /// that cannot tell returns nothing).
    #[cfg_attr(not(feature = "peers"), allow(dead_code))]
    fn stages(&mut self) -> Vec<(&'static str, f64)> {
        Vec::new()
    }
    /// Bodies the engine had to stop so far because their state turned non-finite, hiding
    /// the bad numbers from the poses (tumble's NaN guard, `World::non_finite_bodies`); 0 for
    /// an engine without such a guard, whose bad numbers show in its poses.
    fn non_finite_bodies(&mut self) -> u64 {
        0
    }
}

/// Stage names comparable across engines, in step order: finding new pairs (and refitting
/// the tree), the narrow phase, preparing constraints, the substep loop (integration, warm
/// start, solve, relax, restitution), storing impulses for the next warm start, finalizing
/// bodies. What each engine counts in each is said where it reports them.
#[cfg_attr(not(feature = "peers"), allow(dead_code))]
pub const STAGES: [&str; 6] = [
    "broad phase",
    "narrow phase",
    "prepare",
    "substeps",
    "store impulses",
    "finalize",
];

/// A peer error as an `anyhow` error (the peers' error types are not all `Send + Sync`).
#[cfg(feature = "peers")]
pub(crate) fn ok<T, E: std::fmt::Display>(r: Result<T, E>, what: &str) -> Result<T> {
    r.map_err(|e| anyhow::anyhow!("{what}: {e}"))
}
