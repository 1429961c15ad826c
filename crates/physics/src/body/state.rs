//! A body's solver state: what the substep loop reads and writes of a body, shared by the
//! contact solver, the joints and the workers' shared accessors (`crate::threads::parallel`).

use glam::Vec2;

use crate::math::Rot;

/// The part of a body the substep loop touches: 32 bytes, so 2 fit a cache line.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
#[repr(C, align(32))]
pub struct BodyState {
    /// Linear velocity of the centre of mass.
    pub v: Vec2,
    /// Angular velocity.
    pub w: f32,
    /// Unused padding kept for the 32-byte layout (Box2D keeps flags here).
    pub flags: u32,
    /// Translation accumulated over this step's substeps.
    pub dp: Vec2,
    /// Rotation accumulated over this step's substeps.
    pub dq: Rot,
}

// The solver's wide kernels write `v`, `w` and `flags` back as one 16-byte row
// (`PerBody::set_motion_row`).
const _: () = assert!(
    std::mem::offset_of!(BodyState, v) == 0
        && std::mem::offset_of!(BodyState, w) == 8
        && std::mem::offset_of!(BodyState, flags) == 12
        && std::mem::size_of::<BodyState>() == 32
);

impl Default for BodyState {
    fn default() -> Self {
        Self {
            v: Vec2::ZERO,
            w: 0.0,
            flags: 0,
            dp: Vec2::ZERO,
            dq: Rot::IDENTITY,
        }
    }
}
