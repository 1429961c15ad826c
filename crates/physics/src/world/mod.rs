//! The world: the stores of bodies, shapes, contacts and islands (here), and the public API
//! over them: creating, changing and destroying bodies and shapes in `bodies.rs`, reading
//! them in `read.rs`, the step's stages in `step.rs`, touching, islands and sleep in
//! `sleep.rs`, snapshots in `snapshot.rs`, the invariants between the stores in
//! `validate.rs`, the settings in `settings.rs`, the worker threads in `threads.rs` and the
//! joints in `joints.rs`.
//!
//! Stores are flat arrays indexed by a body's or a shape's slot (its id's `index`), so the
//! step's stages split them across threads; a destroyed object leaves its slot free for the
//! next, under a new generation.

mod bodies;
mod continuous;
mod events;
mod joints;
mod query;
mod read;
mod settings;
mod sleep;
mod snapshot;
mod step;
mod threads;
mod validate;

#[cfg(test)]
mod tests;

use glam::Vec2;
use rustc_hash::FxHashMap;

use crate::body::BodyState;
use crate::collision::Manifold;
use crate::collision::broad_phase::BroadPhase;
use crate::crew::Crew;
use crate::def::{BodyKind, Filter, Limits};
use crate::error::SceneError;
use crate::id::{BodyId, JointId, ShapeId, Slots};
use crate::island::Islands;
use crate::joint::Joint;
use crate::math::{Rot, Transform};
use crate::profile::StepProfile;
use crate::scene::SceneDef;
use crate::shape::{Aabb, Shape};
use crate::solver::{
    BodyMotion, ContactInput, NOT_DYNAMIC, Solver, SolverBody, SolverContact, Touching,
};

pub use events::{BodyMove, Event, EventCursor, ShapeRef};
pub use query::{QueryFilter, RayHit};
pub use settings::{StepSettings, WideThresholds};
pub use snapshot::WorldSnapshot;
pub use threads::{SpawnWorker, default_thread_count, set_thread_source};
use threads::{THREAD_SOURCE, start_crew};

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
            manifold: &self.manifold,
            masses: self.masses,
        }
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
    // Bodies, by slot.
    body_slots: Slots,
    sims: Vec<BodySim>,
    states: Vec<BodyState>,
    records: Vec<BodyRecord>,
    solver_bodies: Vec<SolverBody>,
    motion: Vec<BodyMotion>,
    /// Awake: kinematic bodies and awake dynamic ones (never static ones or free slots).
    awake: Vec<bool>,
    /// The awake set's bodies (Box2D's awake solver set, as a list of slots): every body
    /// whose `motion.moves`, ascending. The body stages walk it, so a sleeping body costs
    /// them nothing. Rebuilt at the next step when `moving_stale`.
    moving: Vec<u32>,
    moving_stale: bool,
    /// Kinematic bodies in the world (their motion keeps what they touch awake).
    kinematic_count: usize,
    // Shapes, by slot.
    shape_slots: Slots,
    shapes: Vec<Shape>,
    shape_records: Vec<ShapeRecord>,
    /// Each shape's body (a compact copy of `ShapeRecord::body` for the broad phase).
    shape_body: Vec<u32>,
    /// Each shape's fat box, swept along its body's velocity over a step: the broad phase's
    /// proxies. A pair with a static body needs these to overlap, so that a fast body meets
    /// a wall a step early and its speculative contact stops it (tumble has no time of
    /// impact yet).
    fat_aabbs: Vec<Aabb>,
    /// Each shape's fat box without the sweep along its velocity. A pair of two moving
    /// bodies needs these to overlap too (Box2D's pairs: fat boxes, no sweep): bodies that
    /// fall side by side then make no pair. A shape of a static body or a bullet has
    /// [`Aabb::EVERYWHERE`], so its pairs go by the swept boxes alone.
    core_aabbs: Vec<Aabb>,
    /// Proxies whose fat or core box changed since the last pair search.
    moved: Vec<u32>,
    moved_flags: Vec<bool>,
    /// The proxies the pair search just took from `moved`: their flags stay set until the
    /// narrow phase has retested their contacts' boxes, then are cleared (the buffers of
    /// the two lists take turns, so a steady step allocates nothing).
    moved_done: Vec<u32>,
    /// Scratch: each moved proxy's place in `moved` (the tree walk's creation order).
    moved_rank: Vec<u32>,
    /// A proxy was added or removed: the tree must be rebuilt.
    proxies_changed: bool,
    tree_dirty: bool,
    broad_phase: BroadPhase,
    // Contacts, in the deterministic order the solver sees them.
    contacts: Vec<Contact>,
    /// One per contact, in the same order.
    contact_keys: Vec<ContactKey>,
    /// The awake set's contacts: every contact not `frozen`, ascending. While an island
    /// sleeps, the contact stages walk it instead of every contact. Rebuilt when needed
    /// once `awake_contacts_stale`.
    awake_contacts: Vec<u32>,
    awake_contacts_stale: bool,
    pairs: FxHashMap<u64, u32>,
    islands: Islands,
    guarded_last_step: usize,
    /// Every body the guard has stopped, over the world's whole life (snapshots keep it).
    non_finite_bodies: u64,
    solver: Solver,
    /// Indices of this step's touching contacts, in contact order (reused).
    touching: Vec<Touching>,
    /// The threads that help the caller's with a wide step; `None` at one thread, and where
    /// the platform has no threads (see [`set_thread_source`]): every step is then inline.
    crew: Option<std::sync::Arc<Crew>>,
    threads: usize,
    wide: WideThresholds,
    profile: StepProfile,
    steps: u64,
    speed_caps: u64,
    profile_recycled: usize,
    joint_slots: Slots,
    /// Joints by slot (a free slot holds its last joint, unsolved).
    joints: Vec<Joint>,
    /// Pairs of bodies (by `pair_key`) that joints keep from touching, with how many do.
    no_collide: FxHashMap<u64, u32>,
    /// This step's awake joints, for the colouring.
    joint_list: Vec<Touching>,
    /// Last step's substep rate, for the joints' reaction forces.
    last_inv_h: f32,
    /// This step's chains of hinges (slots in path order) and each chain's range; their
    /// joints are not in `joint_list`.
    chain_list: Vec<u32>,
    chain_ranges: Vec<std::ops::Range<usize>>,
    /// The eligible joints the chains were found among (searched again when they change),
    /// and a per-slot scratch flag.
    chain_links: Vec<crate::joint::chain::Link>,
    chain_scratch: Vec<crate::joint::chain::Link>,
    chain_flags: Vec<bool>,
    /// The solver holds the awake joints' live state (impulses): `joints` is stale for them
    /// until `sync_joints` (see `Solver::prepare_joints`).
    joint_copies: bool,
    /// Each joint slot's bodies and kind flags, for the step's walk; rebuilt when a joint is
    /// made, destroyed or edited.
    joint_meta: Vec<joints::JointMeta>,
    joint_meta_stale: bool,
    /// The last step's events (and those made since), and what gathering them needs.
    event_log: events::EventLog,
    /// Each sensor shape's overlaps after the last step.
    sensors: events::SensorOverlaps,
    /// Continuous collision's kept buffers: each fast body's pose at the step's start (by
    /// slot) and this step's fast bodies.
    sweep_starts: Vec<Transform>,
    fast_bodies: Vec<u32>,
    /// Each fast body's time of impact in this pass of continuous collision, by its place in
    /// the list of fast bodies (a kept buffer).
    sweep_impacts: Vec<f32>,
    /// Bodies continuous collision moved back this step (for the profile).
    profile_rewound: usize,
    /// A tree of the static shapes alone, which a fast body is swept against (Box2D keeps a
    /// tree per body type): rebuilt when a static shape is added, removed or moved.
    static_tree: BroadPhase,
    static_tree_stale: bool,
}

impl World {
    /// An empty world with the given settings, on all cores.
    pub fn new(settings: StepSettings) -> World {
        let threads = default_thread_count();
        World {
            settings,
            body_slots: Slots::default(),
            sims: Vec::new(),
            states: Vec::new(),
            records: Vec::new(),
            solver_bodies: Vec::new(),
            motion: Vec::new(),
            awake: Vec::new(),
            moving: Vec::new(),
            moving_stale: true,
            kinematic_count: 0,
            shape_slots: Slots::default(),
            shapes: Vec::new(),
            shape_records: Vec::new(),
            shape_body: Vec::new(),
            fat_aabbs: Vec::new(),
            core_aabbs: Vec::new(),
            moved: Vec::new(),
            moved_flags: Vec::new(),
            moved_done: Vec::new(),
            moved_rank: Vec::new(),
            proxies_changed: true,
            tree_dirty: true,
            broad_phase: BroadPhase::default(),
            contacts: Vec::new(),
            contact_keys: Vec::new(),
            awake_contacts: Vec::new(),
            awake_contacts_stale: true,
            pairs: FxHashMap::default(),
            islands: Islands::default(),
            guarded_last_step: 0,
            non_finite_bodies: 0,
            solver: Solver::new(),
            touching: Vec::new(),
            crew: start_crew(threads),
            threads,
            wide: WideThresholds::default(),
            profile: StepProfile::default(),
            steps: 0,
            speed_caps: 0,
            profile_recycled: 0,
            joint_slots: Slots::default(),
            joints: Vec::new(),
            no_collide: FxHashMap::default(),
            joint_list: Vec::new(),
            last_inv_h: 0.0,
            chain_list: Vec::new(),
            chain_ranges: Vec::new(),
            chain_links: Vec::new(),
            chain_scratch: Vec::new(),
            chain_flags: Vec::new(),
            joint_copies: false,
            joint_meta: Vec::new(),
            joint_meta_stale: true,
            event_log: events::EventLog::default(),
            sensors: events::SensorOverlaps::new(),
            sweep_starts: Vec::new(),
            fast_bodies: Vec::new(),
            sweep_impacts: Vec::new(),
            profile_rewound: 0,
            static_tree: BroadPhase::default(),
            static_tree_stale: true,
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
        self.shapes.reserve(n);
        self.sims.reserve(n);
        self.states.reserve(n);
        self.fat_aabbs.reserve(n);
        self.core_aabbs.reserve(n);
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
        if threads != self.threads {
            // The old crew's threads are told to exit before the new ones start.
            self.crew = None;
            self.crew = start_crew(threads);
            self.threads = threads;
        }
    }

    /// Lets the solver run on every thread of [`World::set_thread_count`] even where there
    /// are more threads than cores (by default it stops at the cores: workers beyond them
    /// only wait on each other). The result is the same either way; tests of determinism use
    /// it to run 3 and 4 real workers on a 2-core machine.
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
        self.threads
    }
}
