//! The world: its stores (`stores.rs`: bodies, shapes with their broad-phase proxies,
//! contacts and joints, each owning its rows and raising its own change flags; islands in
//! `crate::island`) and the public API over them: creating, changing and destroying bodies
//! and shapes in `bodies.rs`, reading them in `read.rs`, joints in `joints.rs`, queries in
//! `query.rs`, events in `events.rs`, snapshots in `snapshot.rs`, the step's stages in
//! `step.rs`; touching, islands and sleep in `sleep.rs`, continuous collision in
//! `continuous.rs`, the invariants between the stores in `validate.rs`, the settings in
//! `settings.rs`; the worker threads in `crate::threads`. docs/architecture.md walks a step
//! through them.
//!
//! Stores are flat arrays indexed by an object's slot (its id's `index`), so the step's
//! stages split them across threads; a destroyed object leaves its slot free for the next,
//! under a new generation.

mod bodies;
mod body_properties;
mod continuous;
pub mod draw;
mod events;
mod explode;
mod forces;
mod hooks;
mod joint_state;
mod joints;
mod mover;
mod query;
mod read;
mod settings;
mod shape_properties;
mod sleep;
mod snapshot;
mod step;
mod stores;
mod validate;

#[cfg(test)]
mod tests;

use glam::Vec2;

use crate::collision::Manifold;
use crate::def::{BodyKind, Filter, Limits};
use crate::error::SceneError;
use crate::id::{BodyId, JointId, ShapeId};
use crate::island::Islands;
use crate::math::{Rot, Transform};
use crate::scene::SceneDef;
use crate::shape::{Aabb, Shape};
use crate::solver::{ContactInput, NOT_DYNAMIC, Solver, SolverBody, SolverContact};

use crate::threads::{THREAD_SOURCE, default_thread_count, start_crew};
pub use draw::{DebugDraw, DrawOptions, ShapeDraw};
pub use events::{BodyMove, Event, EventCursor, ShapeRef};
pub use explode::ExplosionDef;
pub use hooks::{CustomFilter, PreSolve};
pub use query::{QueryFilter, RayHit};
pub use settings::{RESTITUTION_PASSES, StepSettings, WideThresholds};
pub use snapshot::WorldSnapshot;
use stores::{Bodies, Contacts, Joints, Shapes, Stats, Sweeps, Workers};

/// "None" in the linked lists of shapes.
const NONE: u32 = u32::MAX;

/// A body's state as the outside sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyView {
    /// Centre of mass.
    pub position: Vec2,
    /// The body frame's origin: where a scene placed a body of several parts (for a body of
    /// one shape, its centre of mass).
    pub origin: Vec2,
    /// Orientation (rad), in (-π, π].
    pub angle: f32,
    /// Orientation as cosine and sine (exact state; `angle` is derived).
    pub rotation: Rot,
    /// Velocity of the centre of mass.
    pub linear_velocity: Vec2,
    /// Angular velocity.
    pub angular_velocity: f32,
    /// Static, dynamic or kinematic.
    pub kind: BodyKind,
    /// Whether it is awake (static bodies never are; kinematic bodies always are).
    pub awake: bool,
    /// Whether it is a bullet (swept against moving bodies too; see [`World::set_bullet`]).
    pub bullet: bool,
}

/// A shape as the outside sees it (for drawing and queries).
#[derive(Clone, Copy, Debug)]
pub struct ShapeView<'a> {
    /// Its id.
    pub id: ShapeId,
    /// Its body.
    pub body: BodyId,
    /// Its geometry, centred on its own frame.
    pub shape: &'a Shape,
    /// Its frame in the world.
    pub transform: Transform,
    /// Its place in its body's parts (0 for a body of one shape).
    pub part: usize,
    /// Whether it is a sensor.
    pub sensor: bool,
    /// Its fat bounding box, as the broad phase sees it.
    pub fat_aabb: Aabb,
}

/// A contact as the outside sees it (for debug drawing and tests).
#[derive(Clone, Copy, Debug)]
pub struct ContactView<'a> {
    /// First body (the polygon's, when a polygon meets a circle).
    pub body_a: BodyId,
    /// Second body.
    pub body_b: BodyId,
    /// First shape.
    pub shape_a: ShapeId,
    /// Second shape.
    pub shape_b: ShapeId,
    /// The manifold, with last step's impulses.
    pub manifold: &'a Manifold,
    /// Each manifold point in the world: body A's centre now plus the point's anchor (as
    /// computed, or recycled since); read through [`ContactView::world_points`].
    points: [Vec2; 2],
}

impl ContactView<'_> {
    /// The manifold's points in the world.
    pub fn world_points(&self) -> &[Vec2] {
        &self.points[..self.manifold.count]
    }
}

/// Why a call on the world was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum WorldError {
    /// The body was destroyed (or never was).
    #[error("{0} does not exist (destroyed, or from another world)")]
    NoBody(BodyId),
    /// The shape was destroyed (or never was).
    #[error("{0} does not exist (destroyed, or from another world)")]
    NoShape(ShapeId),
    /// The joint was destroyed (or never was).
    #[error("{0} does not exist (destroyed, or from another world)")]
    NoJoint(JointId),
    /// The change was checked as a scene's would be, and refused.
    #[error("{0}")]
    Refused(#[from] SceneError),
    /// A value the call cannot use.
    #[error("{what}: {why}")]
    Invalid {
        /// What was given.
        what: String,
        /// Why it cannot be used.
        why: String,
    },
}

/// Per-body data that the step reads but the substep loop does not.
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
struct BodySim {
    /// The centre of mass's pose.
    xf: Transform,
    kind: BodyKind,
    inv_inertia: f32,
    /// Largest centre-to-surface distance, for rotation-swept bounds.
    extent: f32,
    /// Fat-box margin for this body.
    margin: f32,
    /// Smallest centre-to-surface distance (how thin the body is).
    min_extent: f32,
    /// Moved more than half its thickness last step, or will at its velocity: its contacts
    /// are recomputed each step, unless with another dynamic body (`step::recycle`).
    fast: bool,
    /// Seconds it has rested (below the sleep threshold); 0 while it moves.
    sleep_time: f32,
}

/// What a body keeps that the step does not read every step.
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
struct BodyRecord {
    /// Centre of mass in the body's frame (zero for a body of one shape, and for every body
    /// that is not dynamic).
    local_center: Vec2,
    /// Its first shape (then each shape's `next`).
    first_shape: u32,
    /// Parts it was given (the next part's index).
    parts: u32,
    fixed_rotation: bool,
    linear_damping: f32,
    angular_damping: f32,
    gravity_scale: f32,
    enable_sleep: bool,
    /// Its pairs with moving bodies are found by swept boxes too (see `core_aabbs`).
    #[serde(default)]
    bullet: bool,
    /// The caller's tag for the body ([`World::set_user_data`]); the step never reads it.
    #[serde(default)]
    user_data: u64,
    /// Its mass data were given by [`World::set_mass_data`], not computed from its shapes.
    #[serde(default)]
    custom_mass: bool,
    /// Disabled ([`World::set_enabled`]): out of the broad phase, the solver, islands and
    /// every query until enabled again.
    #[serde(default)]
    disabled: bool,
}

/// A shape on a body.
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
struct ShapeRecord {
    body: u32,
    /// Its frame in its body's frame, as placed.
    local: Transform,
    /// Its frame relative to its body's centre of mass (`local` less the local centre).
    from_center: Transform,
    /// `from_center` is not the identity (the shape is off its body's centre).
    offset: bool,
    density: f32,
    friction: f32,
    restitution: f32,
    filter: Filter,
    sensor: bool,
    /// The body's next shape.
    next: u32,
    /// Its place among its body's parts.
    part: u32,
    /// The caller's tag ([`World::set_shape_user_data`]); the step never reads it.
    #[serde(default)]
    user_data: u64,
    /// How fast its surface moves along itself (m/s; a conveyor belt; 0 for most shapes).
    #[serde(default)]
    tangent_speed: f32,
    /// Its rolling resistance coefficient (0 for most shapes).
    #[serde(default)]
    rolling_resistance: f32,
    /// Its body is disabled: the shape is in no tree, no pair and no query (a copy of the
    /// body's flag where the tree build, the pair search and the queries read).
    #[serde(default)]
    disabled: bool,
}

impl ShapeRecord {
    /// A contact's friction from its shapes': Box2D's default mixing rule (and the
    /// contract's), the geometric mean.
    #[inline]
    fn mixed_friction(a: &ShapeRecord, b: &ShapeRecord) -> f32 {
        (a.friction * b.friction).sqrt()
    }

    /// A contact's tangent speed from its shapes': their sum (Box2D's rule).
    #[inline]
    fn mixed_tangent_speed(a: &ShapeRecord, b: &ShapeRecord) -> f32 {
        a.tangent_speed + b.tangent_speed
    }

    /// A contact's rolling resistance from its shapes' (`a` and `b` with their geometry):
    /// the larger coefficient times the larger radius, a lever in metres (Box2D v3.1's
    /// `b2UpdateContact`); 0 when neither has any.
    #[inline]
    fn mixed_rolling_resistance(a: &ShapeRecord, sa: &Shape, b: &ShapeRecord, sb: &Shape) -> f32 {
        if a.rolling_resistance > 0.0 || b.rolling_resistance > 0.0 {
            a.rolling_resistance.max(b.rolling_resistance) * sa.radius().max(sb.radius())
        } else {
            0.0
        }
    }

    /// A contact's restitution from its shapes': the larger (Box2D's default rule).
    #[inline]
    fn mixed_restitution(a: &ShapeRecord, b: &ShapeRecord) -> f32 {
        a.restitution.max(b.restitution)
    }

    /// The shape's pose in the world when its body's centre of mass is at `body`.
    #[inline]
    fn pose(&self, body: Transform) -> Transform {
        if self.offset {
            body.compose(self.from_center)
        } else {
            body
        }
    }
}

#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
struct Contact {
    shape_a: u32,
    shape_b: u32,
    body_a: u32,
    body_b: u32,
    friction: f32,
    restitution: f32,
    manifold: Manifold,
    /// Poses when the manifold was last computed, for contact recycling.
    cache: Option<ContactCache>,
    /// Touching at the end of the last narrow phase (to see it begin and end).
    #[serde(default)]
    touched: bool,
    /// It began touching and has not pushed yet: a hit event is still to be judged (see
    /// `World::gather_hits`).
    #[serde(default)]
    hit_pending: bool,
    /// Accumulated rolling-resistance impulse (N·m·s; warm start for the next step; Box2D
    /// keeps it in the manifold). It fits the contact's padding: a contact stays 200 bytes,
    /// and its surface materials are read from its shapes by prepare, only in a world that
    /// has any (`Shapes::any_surface`), so a world without pays nothing for them.
    #[serde(default)]
    rolling_impulse: f32,
    /// The bodies' masses, refreshed from the bodies whenever one's mass data change (see
    /// `ContactInput::masses`). Not stored in snapshots: restoring copies them again.
    #[serde(skip)]
    masses: [SolverBody; 2],
}

/// What the passes that walk every contact in order need of it, kept apart in a compact
/// array in the same order: a contact spans four cache lines, and reading one field of each
/// of 15,000 to find the touching ones and the parted ones cost 0.5 ms a step.
#[derive(Clone, Copy, Debug)]
struct ContactKey {
    /// Its bodies as the colouring sees them: each `NOT_DYNAMIC` unless dynamic.
    dynamic: [u32; 2],
    /// This step's manifold has points (written by the narrow phase).
    touching: bool,
    /// The fat boxes no longer overlap: removed at the end of the narrow phase.
    remove: bool,
    /// Touching after the last touch update: the contact's own `touched`, kept here too so
    /// that finding the contacts that began or stopped touching reads no contact.
    touched: bool,
    /// Neither body is awake: the narrow phase leaves it as it is.
    frozen: bool,
    /// A dynamic body of it sleeps: the solver leaves it out.
    sleeping: bool,
    /// Its boxes' overlap must be tested at its next narrow phase even if neither shape
    /// moved: it is new, was frozen (its boxes may have moved as it fell asleep, untested),
    /// or was restored. Otherwise a contact whose shapes did not move overlaps as it did.
    retest: bool,
}

impl ContactKey {
    fn of(c: &Contact, awake: &[bool]) -> ContactKey {
        let side = |i: u32, m: &SolverBody| if m.dynamic { i } else { NOT_DYNAMIC };
        let (a, b) = (c.body_a as usize, c.body_b as usize);
        ContactKey {
            dynamic: [side(c.body_a, &c.masses[0]), side(c.body_b, &c.masses[1])],
            touching: c.manifold.count > 0,
            touched: c.touched,
            remove: false,
            frozen: !(awake[a] || awake[b]),
            sleeping: (c.masses[0].dynamic && !awake[a]) || (c.masses[1].dynamic && !awake[b]),
            retest: true,
        }
    }
}

impl SolverContact for Contact {
    #[inline]
    fn input(&self) -> ContactInput<'_> {
        ContactInput {
            body_a: self.body_a,
            body_b: self.body_b,
            friction: self.friction,
            restitution: self.restitution,
            shapes: [self.shape_a, self.shape_b],
            tangent_speed: 0.0,
            rolling_resistance: 0.0,
            rolling_impulse: 0.0,
            manifold: &self.manifold,
            masses: self.masses,
        }
    }

    #[inline]
    fn rolling_impulse(&self) -> f32 {
        self.rolling_impulse
    }
}

/// What a contact remembers of the poses its manifold was computed at.
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
struct ContactCache {
    q_a: Rot,
    q_b: Rot,
    /// B's pose in A's frame.
    relative: Transform,
    /// How far (m) the pair may close in one step, its closing bound times dt, while the
    /// manifold still holds every point within reach (`step::recycle`). A snapshot without it
    /// loads 0: a fast pair that can close at all then computes its manifold afresh.
    #[serde(default)]
    closing_reach: f32,
}

#[inline]
fn pair_key(a: u32, b: u32) -> u64 {
    let (lo, hi) = if a < b { (a, b) } else { (b, a) };
    (u64::from(lo) << 32) | u64::from(hi)
}

/// A 2D rigid-body world.
pub struct World {
    settings: StepSettings,
    /// How much work a stage needs before it is split over the threads.
    wide: WideThresholds,
    bodies: Bodies,
    shapes: Shapes,
    contacts: Contacts,
    joints: Joints,
    islands: Islands,
    /// The solver's per-step scratch: constraints in colour order, lanes, joint copies.
    solver: Solver,
    /// The last step's events (and those made since), and what gathering them needs.
    events: events::EventLog,
    /// Each sensor shape's overlaps after the last step.
    sensors: events::SensorOverlaps,
    /// The game's custom filter and pre-solve callback.
    hooks: hooks::Hooks,
    sweeps: Sweeps,
    stats: Stats,
    workers: Workers,
}

/// A world: made empty or from a scene, its settings and its worker threads. A different
/// thread count never changes a result.
///
/// ```
/// use tumble_physics::{BodyDef, Limits, SceneDef, ShapeDef, World};
///
/// let mut scene = SceneDef::new("one ball");
/// scene.push(BodyDef::new(ShapeDef::Circle { radius: 0.5 }).at(0.0, 3.0));
/// let mut world = World::from_scene(&scene, &Limits::default()).unwrap();
/// world.set_thread_count(2);
/// world.settings_mut().gravity = tumble_physics::Vec2::new(0.0, -9.81);
/// world.step(scene.dt, scene.substeps);
/// assert_eq!(world.body_count(), 1);
/// ```
impl Default for World {
    /// An empty world with [`StepSettings::default`], on all cores.
    fn default() -> World {
        World::new(StepSettings::default())
    }
}

impl World {
    /// An empty world with the given settings, on all cores.
    pub fn new(settings: StepSettings) -> World {
        let threads = default_thread_count();
        World {
            settings,
            wide: WideThresholds::default(),
            bodies: Bodies {
                awake_set_stale: true,
                ..Bodies::default()
            },
            shapes: Shapes {
                proxies_changed: true,
                tree_dirty: true,
                static_tree_stale: true,
                ..Shapes::default()
            },
            contacts: Contacts {
                awake_stale: true,
                ..Contacts::default()
            },
            joints: Joints {
                meta_stale: true,
                ..Joints::default()
            },
            islands: Islands::default(),
            solver: Solver::new(),
            events: events::EventLog::default(),
            sensors: events::SensorOverlaps::new(),
            hooks: hooks::Hooks::default(),
            sweeps: Sweeps::default(),
            stats: Stats::default(),
            workers: Workers {
                crew: start_crew(threads),
                threads,
                solve_payoff: Default::default(),
            },
        }
    }

    /// Validates a scene (with `limits`) and builds its world; body ids follow the scene's
    /// order. The scene's `dt` and `substeps` are the caller's to pass to [`World::step`].
    pub fn from_scene(scene: &SceneDef, limits: &Limits) -> Result<World, SceneError> {
        scene.validate(limits)?;
        let mut settings = StepSettings {
            gravity: Vec2::from(scene.gravity),
            enable_sleep: scene.sleep,
            hit_speed: scene.hit_speed,
            continuous: scene.continuous,
            ..StepSettings::default()
        };
        scene.solver.apply(&mut settings);
        settings.validate()?;
        let mut world = World::new(settings);
        world.reserve(scene.bodies.len());
        for (i, body) in scene.bodies.iter().enumerate() {
            world.insert_body(body, i);
        }
        for def in &scene.joints {
            let [a, b] = def.bodies();
            let joint = def.build(
                world.body_frame(a.index as usize),
                world.body_frame(b.index as usize),
                world.settings.joint_hertz,
                world.settings.joint_damping_ratio,
            );
            world.insert_joint(joint);
        }
        // Once for the whole scene (a check per joint would make a big scene's build
        // quadratic in debug builds).
        world.debug_validate();
        Ok(world)
    }

    fn reserve(&mut self, n: usize) {
        self.shapes.geometry.reserve(n);
        self.bodies.sims.reserve(n);
        self.bodies.states.reserve(n);
        self.shapes.swept_boxes.reserve(n);
        self.shapes.unswept_boxes.reserve(n);
    }

    /// The step's settings.
    pub fn settings(&self) -> &StepSettings {
        &self.settings
    }

    /// The step's settings, to change between steps.
    pub fn settings_mut(&mut self) -> &mut StepSettings {
        &mut self.settings
    }

    /// Sets the worker threads for the next steps (at least 1). Results do not change.
    pub fn set_thread_count(&mut self, threads: usize) {
        // Without threads (see `set_thread_source`) every step runs on the calling thread.
        let threads = if matches!(THREAD_SOURCE.get(), Some((_, None))) {
            1
        } else {
            threads.max(1)
        };
        if threads != self.workers.threads {
            // The old crew's threads are told to exit before the new ones start.
            self.workers.crew = None;
            self.workers.crew = start_crew(threads);
            self.workers.threads = threads;
        }
    }

    /// Lets the solver run on every thread of [`World::set_thread_count`] even where there
    /// are more threads than cores (by default it stops at the cores: workers beyond them
    /// only wait on each other), and in every step that splits it, whether or not splitting
    /// pays ([`WideThresholds::solve_by_payoff`]). The result is the same either way; tests of
    /// determinism use it to run 3 and 4 real workers on a 2-core machine.
    pub fn set_workers_beyond_cores(&mut self, allow: bool) {
        self.solver.workers_beyond_cores = allow;
    }

    /// Sets how much work per worker a stage needs before it is split over the threads (see
    /// [`WideThresholds`]). Results do not change.
    pub fn set_wide_thresholds(&mut self, thresholds: WideThresholds) {
        self.wide = thresholds;
    }

    /// See [`World::set_wide_thresholds`].
    pub fn wide_thresholds(&self) -> WideThresholds {
        self.wide
    }

    /// Worker threads the step uses.
    pub fn thread_count(&self) -> usize {
        self.workers.threads
    }
}
#[cfg(test)]
mod layout_tests {
    /// The contact is the step's largest stream: the narrow phase reads every awake one,
    /// prepare and the impulse store touch every touching one. At 216 bytes (surface
    /// materials copied into it, the rolling impulse in the manifold) the narrow phase took
    /// 7% and the store 6% longer on many_pyramids than at 200 (docs/bench/game_api_ab.md):
    /// what a world without those features must not pay.
    #[test]
    fn a_contact_stays_within_200_bytes() {
        assert!(std::mem::size_of::<super::Contact>() <= 200);
        assert!(std::mem::size_of::<crate::collision::manifold::Manifold>() <= 104);
    }

    /// The same for the wide constraints every solve pass streams: 1,184 bytes before the
    /// surface materials, which now live beside them (`WideSurface`) in the worlds that
    /// have any; at 1,312 prepare took 4% longer on many_pyramids.
    #[test]
    fn a_wide_constraint_stays_within_1184_bytes() {
        assert!(std::mem::size_of::<crate::solver::wide::WideConstraint>() <= 1184);
    }
}
