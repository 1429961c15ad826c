//! Collision: the broad phase finds pairs of bodies whose fat boxes overlap, the narrow phase
//! turns each pair into a contact manifold of up to two points.

pub mod broad_phase;
pub(crate) mod distance;
pub(crate) mod manifold;
pub mod ray;

pub use manifold::{Manifold, ManifoldPoint, collide};
pub use ray::{Ray, RayHitLocal, ray_cast};
