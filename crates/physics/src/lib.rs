//! tumble-physics: a 2D rigid-body engine with Box2D v3's Soft Step solver and a step that
//! runs on the caller's thread and the world's own worker threads (started from a rayon pool,
//! which on the web is made of Web Workers).
//!
//! The public surface is small: a [`World`] built from a [`SceneDef`] (or bodies added one by
//! one), [`World::step`], [`StepSettings`] for the knobs that trade speed for accuracy, and a
//! per-stage [`StepProfile`]. Everything else is flat arrays that the step's stages split
//! across threads.
//!
//! # A first program
//!
//! A box dropped on the ground, the events of its landing, and a ray cast at it
//! (`crates/physics/examples/` has more: hits and sensors, ray casts, a chain of joints, a pile
//! falling asleep):
//!
//! ```
//! use tumble_physics::{BodyDef, BodyKind, Event, QueryFilter, ShapeDef, StepSettings, Vec2, World};
//!
//! let mut world = World::new(StepSettings::default());
//! let ground = world
//!     .create_body(
//!         &BodyDef::new(ShapeDef::Box { half_extents: [10.0, 0.5], radius: 0.0 })
//!             .kind(BodyKind::Static)
//!             .at(0.0, -0.5),
//!     )
//!     .unwrap();
//! let crate_ = world
//!     .create_body(&BodyDef::new(ShapeDef::Box { half_extents: [0.5, 0.5], radius: 0.0 }).at(0.0, 3.0))
//!     .unwrap();
//! let mut landed = false;
//! for _ in 0..120 {
//!     world.step(1.0 / 60.0, 4);
//!     for event in world.events() {
//!         if let Event::Hit { shapes, approach_speed, .. } = event {
//!             assert_eq!([shapes[0].body, shapes[1].body], [ground, crate_]);
//!             assert!(*approach_speed > 5.0); // fell 2.5 m: about 7 m/s
//!             landed = true;
//!         }
//!     }
//! }
//! assert!(landed);
//! // It rests on the ground: a ray down from above meets its top face at y = 1.
//! let hit = world
//!     .cast_ray_closest(Vec2::new(0.0, 5.0), Vec2::new(0.0, -10.0), &QueryFilter::default())
//!     .unwrap();
//! assert_eq!(hit.shape.body, crate_);
//! assert!((hit.point.y - 1.0).abs() < 0.02);
//! ```
//!
//! # What each feature costs, and when it is skipped
//! - **Friction**: one extra row per contact point in the relax pass; skipped for every
//!   contact whose mixed friction is zero.
//! - **Restitution**: one pass over all contacts after the substeps; skipped entirely when no
//!   contact of the step has restitution above zero.
//! - **Rotation**: bodies with `fixed_rotation` (and circles would not gain from it) have zero
//!   inverse inertia; their rotation integration is skipped and the solver's angular terms
//!   vanish for them.
//! - **Damping**: the division by `1 + h·c` is skipped for bodies with zero damping.
//! - **Narrow phase**: one routine per pair of shape types (circles, capsules, polygons
//!   rounded or not, segments and chain segments), chosen by the contact's shapes; a scene of
//!   circles and boxes runs only their routines.

#![deny(missing_docs)]

mod body;
pub mod collision;
mod def;
mod error;
mod id;
mod island;
pub mod joint;
mod math;
pub mod mover;
mod profile;
mod scene;
mod shape;
mod softness;
mod solver;
mod threads;
mod world;

pub use body::BodyMass;
pub use def::{
    BodyDef, BodyKind, Filter, Limits, MAX_POLYGON_VERTICES, PartDef, ResolvedPart, ShapeDef,
};
pub use error::{PolygonError, SceneError, SettingsError};
pub use glam::Vec2;
pub use id::{BodyId, JointId, ShapeId};
pub use joint::{JointDef, JointKind};
pub use math::{Rot, Transform};
pub use profile::StepProfile;
#[cfg(feature = "schema")]
pub use scene::scene_schema;
pub use scene::{MAX_SOLVER_PASSES, SceneDef, SolverDef};
pub use shape::{
    Aabb, Capsule, ChainSegment, Circle, MassData, Polygon, Segment, Shape, chain_segments,
};
pub use threads::{SpawnWorker, default_thread_count, set_thread_source};
pub use world::draw;
pub use world::{
    BodyMove, BodyView, ContactView, CustomFilter, DebugDraw, DrawOptions, Event, EventCursor,
    ExplosionDef, PreSolve, QueryFilter, RESTITUTION_PASSES, RayHit, ShapeDraw, ShapeRef,
    ShapeView, StepSettings, WideThresholds, World, WorldError, WorldSnapshot,
};

/// Length tolerance used by collision (Box2D's `B2_LINEAR_SLOP`, 5 mm).
pub const LINEAR_SLOP: f32 = 0.005;
/// Contacts closer than this (beyond the velocity-based margin) are kept as speculative
/// points, so bodies meet without overlapping (Box2D's `B2_SPECULATIVE_DISTANCE`, 4 slops).
pub const SPECULATIVE_DISTANCE: f32 = 4.0 * LINEAR_SLOP;
/// Most a body's fat AABB is grown beyond its tight box, so it need not be re-inserted
/// into the broad phase every step (Box2D's `B2_MAX_AABB_MARGIN`).
pub const AABB_MARGIN: f32 = 0.05;
