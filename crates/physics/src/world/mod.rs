//! The world: the stores of bodies, shapes, contacts and islands, and the public API that
//! creates, changes and reads them. The step's stages are in `step.rs`, sleeping and waking
//! in `sleep.rs`, snapshots in `snapshot.rs`, the invariants between the stores in
//! `validate.rs`.
//!
//! Stores are flat arrays indexed by a body's or a shape's slot (its id's `index`), so the
//! step's stages split them across threads; a destroyed object leaves its slot free for the
//! next, under a new generation.

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

use crate::AABB_MARGIN;
use crate::body::{BodyMass, part_geometry};
use crate::collision::Manifold;
use crate::collision::broad_phase::BroadPhase;
use crate::crew::Crew;
use crate::error::SceneError;
use crate::id::{BodyId, ShapeId, Slots};
use crate::island::{Islands, NO_ISLAND};
use crate::math::{Rot, Transform};
use crate::profile::StepProfile;
use crate::scene::{BodyDef, BodyKind, Filter, Limits, PartDef, SceneDef};
use crate::shape::{Aabb, Shape};
use crate::solver::contact_solver::BodyState;
use crate::solver::{
    BodyMotion, ContactInput, NOT_DYNAMIC, Solver, SolverBody, SolverContact, Touching,
};

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
}

/// A shape as the outside sees it (for drawing and queries).
#[derive(Clone, Copy, Debug)]
pub struct ShapeView<'a> {
    /// Its id.
    pub id: ShapeId,
    /// Its body's slot.
    pub body: usize,
    /// Its geometry, centred on its own frame.
    pub shape: &'a Shape,
    /// Its frame in the world.
    pub transform: Transform,
    /// Its place in its body's parts (0 for a body of one shape).
    pub part: usize,
    /// Whether it is a sensor.
    pub sensor: bool,
}

/// A contact as the outside sees it (for debug drawing and tests).
#[derive(Clone, Copy, Debug)]
pub struct ContactView<'a> {
    /// First body (the polygon's, when a polygon meets a circle).
    pub body_a: usize,
    /// Second body.
    pub body_b: usize,
    /// First shape.
    pub shape_a: usize,
    /// Second shape.
    pub shape_b: usize,
    /// The manifold, with last step's impulses.
    pub manifold: &'a Manifold,
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
    /// Moved more than half its thickness last step: its contacts are always recomputed.
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
    /// Neither body is awake: the narrow phase leaves it as it is.
    frozen: bool,
    /// A dynamic body of it sleeps: the solver leaves it out.
    sleeping: bool,
}

impl ContactKey {
    fn of(c: &Contact, awake: &[bool]) -> ContactKey {
        let side = |i: u32, m: &SolverBody| if m.dynamic { i } else { NOT_DYNAMIC };
        let (a, b) = (c.body_a as usize, c.body_b as usize);
        ContactKey {
            dynamic: [side(c.body_a, &c.masses[0]), side(c.body_b, &c.masses[1])],
            touching: c.manifold.count > 0,
            remove: false,
            frozen: !(awake[a] || awake[b]),
            sleeping: (c.masses[0].dynamic && !awake[a]) || (c.masses[1].dynamic && !awake[b]),
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
    /// Set by finalize for a body whose state went non-finite (then counted and cleared).
    guarded: Vec<bool>,
    /// Kinematic bodies in the world (their motion keeps what they touch awake).
    kinematic_count: usize,
    // Shapes, by slot.
    shape_slots: Slots,
    shapes: Vec<Shape>,
    shape_records: Vec<ShapeRecord>,
    /// Each shape's body (a compact copy of `ShapeRecord::body` for the broad phase).
    shape_body: Vec<u32>,
    fat_aabbs: Vec<Aabb>,
    /// Proxies whose fat box changed since the last pair search.
    moved: Vec<u32>,
    moved_flags: Vec<bool>,
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
            guarded: Vec::new(),
            kinematic_count: 0,
            shape_slots: Slots::default(),
            shapes: Vec::new(),
            shape_records: Vec::new(),
            shape_body: Vec::new(),
            fat_aabbs: Vec::new(),
            moved: Vec::new(),
            moved_flags: Vec::new(),
            moved_rank: Vec::new(),
            proxies_changed: true,
            tree_dirty: true,
            broad_phase: BroadPhase::default(),
            contacts: Vec::new(),
            contact_keys: Vec::new(),
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
        }
    }

    /// Validates a scene (with `limits`) and builds its world; body ids follow the scene's
    /// order. The scene's `dt` and `substeps` are the caller's to pass to [`World::step`].
    pub fn from_scene(scene: &SceneDef, limits: &Limits) -> Result<World, SceneError> {
        scene.validate(limits)?;
        let mut settings = StepSettings {
            gravity: Vec2::from(scene.gravity),
            enable_sleep: scene.sleep,
            ..StepSettings::default()
        };
        scene.solver.apply(&mut settings);
        settings.validate()?;
        let mut world = World::new(settings);
        world.reserve(scene.bodies.len());
        for (i, body) in scene.bodies.iter().enumerate() {
            world.insert_body(body, i);
        }
        Ok(world)
    }

    fn reserve(&mut self, n: usize) {
        self.shapes.reserve(n);
        self.sims.reserve(n);
        self.states.reserve(n);
        self.fat_aabbs.reserve(n);
    }

    /// Adds a body, checked as a scene body would be, and returns its id. Kept under its
    /// old name; see [`World::create_body`].
    pub fn add_body(&mut self, def: &BodyDef) -> Result<usize, SceneError> {
        self.create_body(def).map(|id| id.index as usize)
    }

    /// Creates a body (between steps), checked as a scene body would be (the error names
    /// the slot it would have taken), and returns its id. It takes the lowest free slot.
    pub fn create_body(&mut self, def: &BodyDef) -> Result<BodyId, SceneError> {
        let index = self.body_slots.next_index() as usize;
        let one = SceneDef {
            bodies: vec![def.clone()],
            ..SceneDef::new("")
        };
        one.validate(&Limits::default()).map_err(|e| match e {
            SceneError::Body {
                field,
                value,
                allowed,
                ..
            } => SceneError::Body {
                index,
                field,
                value,
                allowed,
            },
            other => other,
        })?;
        let id = self.insert_body(def, index);
        self.debug_validate();
        Ok(id)
    }

    /// Builds a validated body into the stores.
    fn insert_body(&mut self, def: &BodyDef, expected: usize) -> BodyId {
        let (index, generation, new) = self.body_slots.take();
        debug_assert_eq!(index as usize, expected);
        let i = index as usize;
        let xf = Transform {
            p: Vec2::from(def.position),
            q: Rot::from_angle(def.angle),
        };
        let sim = BodySim {
            xf,
            kind: def.kind,
            inv_inertia: 0.0,
            extent: 0.0,
            margin: 0.0,
            min_extent: 0.0,
            fast: false,
            sleep_time: 0.0,
        };
        let record = BodyRecord {
            local_center: Vec2::ZERO,
            first_shape: NONE,
            parts: 0,
            fixed_rotation: def.fixed_rotation,
            linear_damping: def.linear_damping,
            angular_damping: def.angular_damping,
            gravity_scale: def.gravity_scale,
            enable_sleep: def.enable_sleep,
        };
        let rotates = !(def.kind == BodyKind::Dynamic && def.fixed_rotation);
        let state = BodyState {
            v: Vec2::from(def.linear_velocity),
            w: if rotates { def.angular_velocity } else { 0.0 },
            ..BodyState::default()
        };
        if new {
            self.sims.push(sim);
            self.records.push(record);
            self.states.push(state);
            self.solver_bodies.push(SolverBody::default());
            self.motion.push(BodyMotion::default());
            self.awake.push(false);
            self.guarded.push(false);
        } else {
            self.sims[i] = sim;
            self.records[i] = record;
            self.states[i] = state;
            self.guarded[i] = false;
        }
        self.islands.grow(i + 1);
        if def.kind == BodyKind::Kinematic {
            self.kinematic_count += 1;
        }
        let parts = def.parts();
        for part in &parts {
            // Validation has checked every shape, so this cannot fail.
            let Ok((shape, local)) = part_geometry(part) else {
                continue;
            };
            self.insert_shape(index, shape, local, part);
        }
        self.records[i].parts = parts.len() as u32;
        // A body of one shape: its position is its centre of mass (its one shape is centred
        // there). A body of several: its position is its frame's origin, and `update_mass`
        // moves the centre to where the parts put it.
        self.update_mass(index);
        let asleep = !def.awake && self.settings.enable_sleep && def.kind == BodyKind::Dynamic;
        if def.kind == BodyKind::Dynamic {
            self.islands.create(index, !asleep);
        }
        self.awake[i] = def.kind != BodyKind::Static && !asleep;
        if asleep {
            let st = &mut self.states[i];
            st.v = Vec2::ZERO;
            st.w = 0.0;
        }
        self.refresh_motion(index);
        self.refresh_shape_boxes(index);
        BodyId { index, generation }
    }

    /// Adds one shape to body `body`'s list (its first), with a fat box to come.
    fn insert_shape(
        &mut self,
        body: u32,
        shape: Shape,
        local: Transform,
        part: &crate::scene::ResolvedPart<'_>,
    ) -> ShapeId {
        let (index, generation, new) = self.shape_slots.take();
        let record = ShapeRecord {
            body,
            local,
            from_center: local,
            offset: local != Transform::IDENTITY,
            density: part.density,
            friction: part.friction,
            restitution: part.restitution,
            filter: part.filter,
            sensor: part.sensor,
            next: NONE,
            part: self.records[body as usize].parts,
        };
        // Appended: a body's shapes are listed in part order.
        match self.shapes_of_body(body as usize).last() {
            None => self.records[body as usize].first_shape = index,
            Some(last) => self.shape_records[last as usize].next = index,
        }
        let empty = Aabb {
            min: Vec2::ZERO,
            max: Vec2::ZERO,
        };
        let s = index as usize;
        if new {
            self.shapes.push(shape);
            self.shape_records.push(record);
            self.shape_body.push(body);
            self.fat_aabbs.push(empty);
            self.moved_flags.push(false);
        } else {
            self.shapes[s] = shape;
            self.shape_records[s] = record;
            self.shape_body[s] = body;
            self.fat_aabbs[s] = empty;
            self.moved_flags[s] = false;
        }
        self.proxies_changed = true;
        self.tree_dirty = true;
        ShapeId { index, generation }
    }

    /// In debug builds, checks every invariant between the stores after an API change
    /// (an internal bug, not bad input, if it fails).
    fn debug_validate(&self) {
        #[cfg(debug_assertions)]
        if let Err(e) = self.validate() {
            panic!("tumble: the world's stores disagree after a change: {e}");
        }
    }

    /// The shapes of body `i`, in part order.
    fn shapes_of_body(&self, i: usize) -> impl Iterator<Item = u32> + '_ {
        let mut s = self.records[i].first_shape;
        std::iter::from_fn(move || {
            if s == NONE {
                return None;
            }
            let here = s;
            s = self.shape_records[s as usize].next;
            Some(here)
        })
    }

    /// The one place a body's mass data are computed from its shapes and kind, and every
    /// copy refreshed: the solver's masses, the motion flags, each shape's pose relative to
    /// the centre, and the masses the body's contacts keep. The centre of mass keeps its
    /// place in the body's frame: the frame stays where it is and the centre moves.
    fn update_mass(&mut self, body: u32) {
        let i = body as usize;
        let kind = self.sims[i].kind;
        let shape_ids: Vec<u32> = self.shapes_of_body(i).collect();
        let md = BodyMass::of_shapes(shape_ids.iter().map(|&s| {
            let r = &self.shape_records[s as usize];
            (&self.shapes[s as usize], r.local, r.density)
        }));
        let dynamic = kind == BodyKind::Dynamic;
        let center = if dynamic { md.center } else { Vec2::ZERO };
        // Keep the frame's origin where it is.
        let old_center = self.records[i].local_center;
        if old_center != center {
            let q = self.sims[i].xf.q;
            self.sims[i].xf.p += q.apply(center - old_center);
        }
        self.records[i].local_center = center;
        let (inv_mass, inv_inertia) = if dynamic && md.mass > 0.0 {
            let inv_i = if self.records[i].fixed_rotation || md.inertia <= 0.0 {
                0.0
            } else {
                1.0 / md.inertia
            };
            (1.0 / md.mass, inv_i)
        } else {
            (0.0, 0.0)
        };
        // Extents about the centre actually used (for other than dynamic bodies, the origin).
        let extent = shape_ids.iter().fold(0.0f32, |e, &s| {
            let r = &self.shape_records[s as usize];
            e.max((r.local.p - center).length() + self.shapes[s as usize].extent())
        });
        let sim = &mut self.sims[i];
        sim.inv_inertia = inv_inertia;
        sim.extent = extent;
        sim.min_extent = md.min_extent;
        sim.margin = match kind {
            BodyKind::Static => 0.0,
            // Box2D `b2ComputeShapeMargin`: small shapes get proportionally small margins.
            _ => AABB_MARGIN.min(0.125 * extent),
        };
        self.solver_bodies[i] = SolverBody {
            inv_mass,
            inv_inertia,
            dynamic,
        };
        for &s in &shape_ids {
            let r = &mut self.shape_records[s as usize];
            r.from_center = Transform {
                p: r.local.p - center,
                q: r.local.q,
            };
            r.offset = r.from_center != Transform::IDENTITY;
        }
        self.refresh_motion(body);
        // Contacts keep a copy of their bodies' masses (prepare reads no body): refresh it.
        // (The colouring needs no telling: it is checked against the touching pairs.)
        for (c, key) in self.contacts.iter_mut().zip(&mut self.contact_keys) {
            if c.body_a == body || c.body_b == body {
                c.masses = [
                    self.solver_bodies[c.body_a as usize],
                    self.solver_bodies[c.body_b as usize],
                ];
                *key = ContactKey {
                    touching: key.touching,
                    ..ContactKey::of(c, &self.awake)
                };
            }
        }
    }

    /// The integration flags of a body from its kind, mass and sleep state.
    fn refresh_motion(&mut self, body: u32) {
        let i = body as usize;
        let kind = self.sims[i].kind;
        let r = &self.records[i];
        let awake = self.awake[i];
        self.motion[i] = BodyMotion {
            dynamic: kind == BodyKind::Dynamic && awake,
            moves: kind != BodyKind::Static && awake,
            rotates: match kind {
                BodyKind::Static => false,
                BodyKind::Kinematic => true,
                BodyKind::Dynamic => self.sims[i].inv_inertia > 0.0,
            },
            linear_damping: r.linear_damping,
            angular_damping: r.angular_damping,
            gravity_scale: r.gravity_scale,
        };
    }

    /// Recomputes the fat boxes of a body's shapes and marks them moved (after the body was
    /// created or teleported).
    fn refresh_shape_boxes(&mut self, body: u32) {
        let i = body as usize;
        let ids: Vec<u32> = self.shapes_of_body(i).collect();
        for s in ids {
            let su = s as usize;
            let aabb = step::swept_aabb(
                &self.shapes[su],
                &self.shape_records[su],
                &self.sims[i],
                &self.states[i],
                1.0 / 60.0,
            )
            .grown(self.sims[i].margin);
            self.fat_aabbs[su] = aabb;
            if !self.moved_flags[su] {
                self.moved_flags[su] = true;
                self.moved.push(s);
            }
        }
        self.tree_dirty = true;
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

    /// Body slots (live bodies and free slots): valid indices are `0..body_count()` where
    /// [`World::is_body`] holds. Without destroyed bodies, every slot is a body.
    pub fn body_count(&self) -> usize {
        self.sims.len()
    }

    /// Live bodies.
    pub fn live_body_count(&self) -> usize {
        self.body_slots.live()
    }

    /// Whether slot `index` holds a body.
    pub fn is_body(&self, index: usize) -> bool {
        self.body_slots.is_alive(index)
    }

    /// The id of the body in slot `index`, if it holds one.
    pub fn body_id(&self, index: usize) -> Option<BodyId> {
        self.is_body(index).then(|| BodyId {
            index: index as u32,
            generation: self.body_slots.generation(index),
        })
    }

    /// Every live body's id, in slot order.
    pub fn body_ids(&self) -> impl Iterator<Item = BodyId> + '_ {
        (0..self.sims.len()).filter_map(|i| self.body_id(i))
    }

    fn slot(&self, id: BodyId) -> Result<usize, WorldError> {
        if self.body_slots.holds(id.index, id.generation) {
            Ok(id.index as usize)
        } else {
            Err(WorldError::NoBody(id))
        }
    }

    fn shape_slot(&self, id: ShapeId) -> Result<usize, WorldError> {
        if self.shape_slots.holds(id.index, id.generation) {
            Ok(id.index as usize)
        } else {
            Err(WorldError::NoShape(id))
        }
    }

    /// Contacts (pairs of overlapping fat boxes).
    pub fn contact_count(&self) -> usize {
        self.contacts.len()
    }

    /// Islands, and of those the awake ones.
    pub fn island_counts(&self) -> (usize, usize) {
        (self.islands.count(), self.islands.awake_count())
    }

    /// Body `index`'s island slot (`None` for static and kinematic bodies), for drawing.
    pub fn island_of(&self, index: usize) -> Option<usize> {
        let k = *self.islands.of_body.get(index)?;
        (k != NO_ISLAND).then_some(k as usize)
    }

    /// Awake bodies (kinematic and awake dynamic ones).
    pub fn awake_body_count(&self) -> usize {
        self.awake.iter().filter(|a| **a).count()
    }

    /// Steps taken so far.
    pub fn step_count(&self) -> u64 {
        self.steps
    }

    /// How often a body's speed was clamped to the caps, over all steps.
    pub fn speed_cap_count(&self) -> u64 {
        self.speed_caps
    }

    /// How many times, over the world's whole life (kept by [`World::snapshot`]), the
    /// numerical guard of the step had to stop a body whose state turned non-finite (NaN or
    /// infinite): the body keeps its last finite pose and loses its velocity, so
    /// [`World::is_finite`] stays true and only this count tells. A healthy world reports 0;
    /// every "stays finite" check should require it. [`StepProfile::non_finite`] counts the
    /// last step only.
    pub fn non_finite_bodies(&self) -> u64 {
        self.non_finite_bodies
    }

    /// The state of the body in slot `index` (see [`World::is_body`]; a free slot reads as
    /// a static body at rest where it was). [`World::get`] takes an id.
    pub fn body(&self, index: usize) -> BodyView {
        let sim = &self.sims[index];
        let st = &self.states[index];
        let c = self.records[index].local_center;
        BodyView {
            position: sim.xf.p,
            origin: if c == Vec2::ZERO {
                sim.xf.p
            } else {
                sim.xf.p - sim.xf.q.apply(c)
            },
            angle: sim.xf.q.angle(),
            rotation: sim.xf.q,
            linear_velocity: st.v,
            angular_velocity: st.w,
            kind: sim.kind,
            awake: self.awake[index],
        }
    }

    /// A body's state by id, or why not.
    pub fn get(&self, id: BodyId) -> Result<BodyView, WorldError> {
        self.slot(id).map(|i| self.body(i))
    }

    /// The first shape of the body in slot `index`, in its own frame (see
    /// [`World::body_shapes`] for every shape and where it sits).
    pub fn shape(&self, index: usize) -> &Shape {
        &self.shapes[self.records[index].first_shape as usize]
    }

    /// The shapes of the body in slot `index`, each with its pose in the world.
    pub fn body_shapes(&self, index: usize) -> impl Iterator<Item = ShapeView<'_>> + '_ {
        self.shapes_of_body(index)
            .map(move |s| self.shape_view(s as usize))
    }

    fn shape_view(&self, s: usize) -> ShapeView<'_> {
        let r = &self.shape_records[s];
        let xf = self.sims[r.body as usize].xf;
        ShapeView {
            id: ShapeId {
                index: s as u32,
                generation: self.shape_slots.generation(s),
            },
            body: r.body as usize,
            shape: &self.shapes[s],
            transform: if r.offset {
                xf.compose(r.from_center)
            } else {
                xf
            },
            part: r.part as usize,
            sensor: r.sensor,
        }
    }

    /// Every live shape, in slot order.
    pub fn shapes(&self) -> impl Iterator<Item = ShapeView<'_>> + '_ {
        (0..self.shapes.len())
            .filter(|&s| self.shape_slots.is_alive(s))
            .map(|s| self.shape_view(s))
    }

    /// The fat bounding box of the first shape of body `index`, as the broad phase sees it.
    pub fn fat_aabb(&self, index: usize) -> Aabb {
        self.fat_aabbs[self.records[index].first_shape as usize]
    }

    /// Every live shape's fat bounding box.
    pub fn fat_aabbs(&self) -> impl Iterator<Item = Aabb> + '_ {
        (0..self.shapes.len())
            .filter(|&s| self.shape_slots.is_alive(s))
            .map(|s| self.fat_aabbs[s])
    }

    /// The broad phase's tree, for debug drawing.
    pub fn broad_phase(&self) -> &BroadPhase {
        &self.broad_phase
    }

    /// Every contact, in the deterministic order the solver sees them.
    pub fn contacts(&self) -> impl Iterator<Item = ContactView<'_>> {
        self.contacts.iter().map(|c| ContactView {
            body_a: c.body_a as usize,
            body_b: c.body_b as usize,
            shape_a: c.shape_a as usize,
            shape_b: c.shape_b as usize,
            manifold: &c.manifold,
        })
    }

    /// Sets a body's velocities (e.g. a mouse drag) by slot; ignored for static bodies and
    /// free slots. Wakes the body.
    pub fn set_velocity(&mut self, index: usize, linear: Vec2, angular: f32) {
        if !self.is_body(index)
            || self.sims[index].kind == BodyKind::Static
            || !linear.is_finite()
            || !angular.is_finite()
        {
            return;
        }
        self.wake_body(index as u32);
        let s = &mut self.states[index];
        s.v = linear;
        if self.sims[index].inv_inertia > 0.0 || self.sims[index].kind == BodyKind::Kinematic {
            s.w = angular;
        }
    }

    /// Sets a body's velocities by id (see [`World::set_velocity`]).
    pub fn set_body_velocity(
        &mut self,
        id: BodyId,
        linear: Vec2,
        angular: f32,
    ) -> Result<(), WorldError> {
        let i = self.slot(id)?;
        if !(linear.is_finite() && angular.is_finite()) {
            return Err(WorldError::Invalid {
                what: format!("velocity {linear:?}, {angular}"),
                why: "velocities must be finite".into(),
            });
        }
        self.set_velocity(i, linear, angular);
        Ok(())
    }

    /// Moves a body's frame to `position` and `angle` (between steps): it teleports, keeps
    /// its velocity, and is awake. Its contacts are recomputed next step.
    pub fn set_transform(
        &mut self,
        id: BodyId,
        position: Vec2,
        angle: f32,
    ) -> Result<(), WorldError> {
        let i = self.slot(id)?;
        if !(position.is_finite() && angle.is_finite()) {
            return Err(WorldError::Invalid {
                what: format!("pose {position:?}, {angle}"),
                why: "a position and angle must be finite".into(),
            });
        }
        let q = Rot::from_angle(angle);
        let c = self.records[i].local_center;
        self.sims[i].xf = Transform {
            p: position + q.apply(c),
            q,
        };
        // The move is not motion the recycling could follow.
        for c in self.contacts.iter_mut() {
            if c.body_a as usize == i || c.body_b as usize == i {
                c.cache = None;
            }
        }
        self.wake_body(i as u32);
        self.refresh_shape_boxes(i as u32);
        self.debug_validate();
        Ok(())
    }

    /// Box2D's `b2Body_SetTargetTransform`: gives a (kinematic or dynamic) body the
    /// velocity that brings its frame to `position` and `angle` in one step of `dt`, so a
    /// kinematic pusher follows a path and still pushes what it meets.
    pub fn set_target_transform(
        &mut self,
        id: BodyId,
        position: Vec2,
        angle: f32,
        dt: f32,
    ) -> Result<(), WorldError> {
        let i = self.slot(id)?;
        if !(position.is_finite() && angle.is_finite() && dt.is_normal() && dt > 0.0) {
            return Err(WorldError::Invalid {
                what: format!("target {position:?}, {angle} in {dt} s"),
                why: "a finite pose and a time step > 0".into(),
            });
        }
        let sim = self.sims[i];
        let c = self.records[i].local_center;
        let q = Rot::from_angle(angle);
        let target_center = position + q.apply(c);
        let v = (target_center - sim.xf.p) / dt;
        // The turn from the current angle to the target's, the short way round.
        let dq = sim.xf.q.inv_mul(q);
        let w = dq.s.atan2(dq.c) / dt;
        if self.sims[i].kind == BodyKind::Static {
            return Err(WorldError::Invalid {
                what: format!("{id}"),
                why: "a static body does not move; make it kinematic first".into(),
            });
        }
        self.wake_body(i as u32);
        let st = &mut self.states[i];
        st.v = v;
        st.w = w;
        Ok(())
    }

    /// Changes a body's kind (between steps); its mass data, islands and contacts follow.
    pub fn set_kind(&mut self, id: BodyId, kind: BodyKind) -> Result<(), WorldError> {
        let i = self.slot(id)?;
        let old = self.sims[i].kind;
        if old == kind {
            return Ok(());
        }
        if kind == BodyKind::Dynamic {
            let md = BodyMass::of_shapes(self.shapes_of_body(i).map(|s| {
                let r = &self.shape_records[s as usize];
                (&self.shapes[s as usize], r.local, r.density)
            }));
            let invertible = |x: f32| x.is_normal() && (1.0 / x).is_normal();
            if !invertible(md.mass) {
                return Err(WorldError::Invalid {
                    what: format!("{id} made dynamic"),
                    why: format!(
                        "its shapes give a mass of {:e} kg, which f32 cannot invert: give a shape density",
                        md.mass
                    ),
                });
            }
        }
        // Its contacts' touching state and islands are rebuilt as if they were new.
        self.wake_touching(i as u32);
        self.islands.remove_body(i as u32);
        if old == BodyKind::Kinematic {
            self.kinematic_count -= 1;
        }
        if kind == BodyKind::Kinematic {
            self.kinematic_count += 1;
        }
        self.sims[i].kind = kind;
        if kind == BodyKind::Static {
            self.states[i].v = Vec2::ZERO;
            self.states[i].w = 0.0;
        }
        self.awake[i] = kind != BodyKind::Static;
        self.sims[i].sleep_time = 0.0;
        if kind == BodyKind::Dynamic {
            self.islands.create(i as u32, true);
        }
        self.update_mass(i as u32);
        // Contacts of this body are made afresh: pairs that may no longer touch (two
        // static bodies) go, and new ones are found from its moved proxies.
        self.remove_contacts_of(i as u32);
        self.refresh_shape_boxes(i as u32);
        self.debug_validate();
        Ok(())
    }

    /// Destroys a body and its shapes (between steps). Bodies it touched wake up, and its
    /// slot is free for the next body under a new generation.
    pub fn destroy_body(&mut self, id: BodyId) -> Result<(), WorldError> {
        let i = self.slot(id)?;
        self.wake_touching(i as u32);
        self.remove_contacts_of(i as u32);
        self.islands.remove_body(i as u32);
        let shapes: Vec<u32> = self.shapes_of_body(i).collect();
        for s in shapes {
            self.release_shape(s);
        }
        if self.sims[i].kind == BodyKind::Kinematic {
            self.kinematic_count -= 1;
        }
        self.records[i].first_shape = NONE;
        self.sims[i].kind = BodyKind::Static;
        self.states[i] = BodyState::default();
        self.awake[i] = false;
        self.solver_bodies[i] = SolverBody::default();
        self.refresh_motion(i as u32);
        self.body_slots.release(i as u32);
        self.debug_validate();
        Ok(())
    }

    /// Adds a shape to a body (between steps), checked as a scene part would be; the body's
    /// mass data follow.
    pub fn create_shape(&mut self, body: BodyId, part: &PartDef) -> Result<ShapeId, WorldError> {
        let i = self.slot(body)?;
        // Check it as the part of a one-part body of this kind.
        let mut def = BodyDef::compound(vec![part.clone()]);
        def.kind = self.sims[i].kind;
        let one = SceneDef {
            bodies: vec![def.clone()],
            ..SceneDef::new("")
        };
        one.validate(&Limits::default())?;
        let parts = def.parts();
        let resolved = &parts[0];
        let (shape, local) = part_geometry(resolved).map_err(|e| WorldError::Invalid {
            what: "shape".into(),
            why: e.to_string(),
        })?;
        // Appended as the body's last part.
        let id = self.insert_shape(i as u32, shape, local, resolved);
        self.records[i].parts += 1;
        self.wake_body(i as u32);
        self.update_mass(i as u32);
        self.refresh_shape_boxes(i as u32);
        self.debug_validate();
        Ok(id)
    }

    /// Destroys one shape (between steps). A dynamic body keeps at least one shape with
    /// area (destroy the body instead).
    pub fn destroy_shape(&mut self, id: ShapeId) -> Result<(), WorldError> {
        let s = self.shape_slot(id)?;
        let body = self.shape_records[s].body;
        let i = body as usize;
        if self.sims[i].kind == BodyKind::Dynamic {
            let others = self
                .shapes_of_body(i)
                .filter(|&o| o as usize != s && self.shape_records[o as usize].density > 0.0)
                .count();
            if others == 0 {
                return Err(WorldError::Invalid {
                    what: format!("{id}"),
                    why: "the last shape with mass of a dynamic body; destroy the body instead"
                        .into(),
                });
            }
        }
        self.wake_touching(body);
        // Its contacts go.
        self.remove_contacts_where(|c| c.shape_a as usize == s || c.shape_b as usize == s);
        // Unlink it from the body's list.
        let next = self.shape_records[s].next;
        if self.records[i].first_shape == s as u32 {
            self.records[i].first_shape = next;
        } else {
            let mut k = self.records[i].first_shape;
            while self.shape_records[k as usize].next != s as u32 {
                k = self.shape_records[k as usize].next;
            }
            self.shape_records[k as usize].next = next;
        }
        self.release_shape(s as u32);
        self.islands.unlink(body, body);
        self.update_mass(body);
        self.refresh_shape_boxes(body);
        self.debug_validate();
        Ok(())
    }

    /// Frees a shape's slot and drops it from the broad phase.
    fn release_shape(&mut self, s: u32) {
        let su = s as usize;
        if self.moved_flags[su] {
            self.moved_flags[su] = false;
            self.moved.retain(|&m| m != s);
        }
        self.shape_records[su].next = NONE;
        self.shape_records[su].body = NONE;
        self.shape_body[su] = NONE;
        self.shape_slots.release(s);
        self.proxies_changed = true;
        self.tree_dirty = true;
    }

    /// Removes every contact of body `i` (its islands were told by the caller).
    fn remove_contacts_of(&mut self, body: u32) {
        self.remove_contacts_where(|c| c.body_a == body || c.body_b == body);
    }

    /// Removes the contacts `gone` picks, keeping the others' order; a touching one unlinks
    /// its bodies' island.
    fn remove_contacts_where(&mut self, gone: impl Fn(&Contact) -> bool) {
        let mut keep = 0;
        for k in 0..self.contacts.len() {
            let c = self.contacts[k];
            if gone(&c) {
                if c.touched {
                    self.islands.unlink(c.body_a, c.body_b);
                }
                continue;
            }
            self.contacts[keep] = c;
            self.contact_keys[keep] = self.contact_keys[k];
            keep += 1;
        }
        if keep != self.contacts.len() {
            self.contacts.truncate(keep);
            self.contact_keys.truncate(keep);
            self.pairs = self
                .contacts
                .iter()
                .enumerate()
                .map(|(k, c)| (pair_key(c.shape_a, c.shape_b), k as u32))
                .collect();
        }
    }

    /// A body's mass (kg) by slot; zero for static and kinematic bodies.
    pub fn mass(&self, index: usize) -> f32 {
        let inv = self.solver_bodies[index].inv_mass;
        if inv > 0.0 { 1.0 / inv } else { 0.0 }
    }

    /// A body's centre of mass in its own frame.
    pub fn local_center(&self, index: usize) -> Vec2 {
        self.records[index].local_center
    }

    /// Whether every body's pose and velocities are finite numbers now. The step's
    /// numerical guard keeps them so (it stops a body that turns non-finite), so on its own
    /// this cannot fail after a step: checks of a run require
    /// [`World::non_finite_bodies`] to be 0 as well.
    pub fn is_finite(&self) -> bool {
        self.sims.iter().zip(&self.states).all(|(sim, st)| {
            sim.xf.p.is_finite()
                && sim.xf.q.c.is_finite()
                && sim.xf.q.s.is_finite()
                && st.v.is_finite()
                && st.w.is_finite()
        })
    }

    /// Kinetic energy of the dynamic bodies, translational and rotational (J), summed in f64:
    /// what the energy checks of the tests, the report and the viewer measure.
    pub fn kinetic_energy(&self) -> f64 {
        (0..self.body_count())
            .filter(|&i| self.sims[i].kind == BodyKind::Dynamic)
            .map(|i| {
                let st = &self.states[i];
                let linear = 0.5 * f64::from(self.mass(i)) * f64::from(st.v.length_squared());
                linear + 0.5 * f64::from(self.inertia(i)) * f64::from(st.w).powi(2)
            })
            .sum()
    }

    /// A body's rotational inertia about its centre of mass (kg·m²; 0 for static, kinematic
    /// and fixed-rotation bodies).
    pub fn inertia(&self, index: usize) -> f32 {
        let inv = self.solver_bodies[index].inv_inertia;
        if inv > 0.0 { 1.0 / inv } else { 0.0 }
    }

    /// Applies an impulse (N·s) at a world point to a dynamic body: its velocities change at
    /// once (a mouse spring, an explosion), and it wakes. Ignored for other bodies and
    /// non-finite input.
    pub fn apply_linear_impulse(&mut self, index: usize, impulse: Vec2, point: Vec2) {
        let body = self.solver_bodies[index];
        if !body.dynamic || !impulse.is_finite() || !point.is_finite() {
            return;
        }
        self.wake_body(index as u32);
        let r = point - self.sims[index].xf.p;
        let s = &mut self.states[index];
        s.v += impulse * body.inv_mass;
        s.w += body.inv_inertia * crate::math::cross(r, impulse);
    }

    /// The slot of a body one of whose shapes contains the world point, if any (the last in
    /// shape order, which a viewer draws on top).
    pub fn body_at(&self, point: Vec2) -> Option<usize> {
        (0..self.shapes.len())
            .rev()
            .filter(|&s| self.shape_slots.is_alive(s))
            .find(|&s| {
                let v = self.shape_view(s);
                let local = v.transform.apply_inv(point);
                match v.shape {
                    Shape::Circle(c) => local.length_squared() <= c.radius * c.radius,
                    Shape::Polygon(p) => (0..p.count)
                        .all(|k| crate::math::dot(p.normals[k], local - p.vertices[k]) <= 0.0),
                }
            })
            .map(|s| self.shape_records[s].body as usize)
    }

    /// `(contact index, graph colour)` for every touching contact of the last step, where the
    /// index is a position in [`World::contacts`] and colour 23 is the overflow; for debug
    /// drawing of the constraint graph.
    pub fn contact_colors(&self) -> Vec<(usize, u8)> {
        self.solver.contact_colors()
    }

    /// Which kernels solve the 8-lane colours: `"avx2"` (256-bit registers, chosen at run
    /// time where the CPU has AVX2), `"portable"` (`f32x8`, on x86-64 two SSE halves), or
    /// `"scalar"` when [`StepSettings::simd`] is off. All give the same results bit for bit.
    pub fn simd_kernel(&self) -> &'static str {
        if !self.settings.simd {
            "scalar"
        } else if self.solver.use_avx && crate::solver::lanes::avx2_available() {
            "avx2"
        } else {
            "portable"
        }
    }

    /// The last step's per-stage profile.
    pub fn profile(&self) -> &StepProfile {
        &self.profile
    }

    /// FNV-1a, 64-bit, over the exact bits of every live body's position, rotation (cos,
    /// sin), linear and angular velocity, in slot order.
    pub fn state_hash(&self) -> u64 {
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        let mut eat = |x: f32| {
            for byte in x.to_bits().to_le_bytes() {
                h ^= u64::from(byte);
                h = h.wrapping_mul(0x0000_0100_0000_01b3);
            }
        };
        for (i, (sim, st)) in self.sims.iter().zip(&self.states).enumerate() {
            if !self.body_slots.is_alive(i) {
                continue;
            }
            eat(sim.xf.p.x);
            eat(sim.xf.p.y);
            eat(sim.xf.q.c);
            eat(sim.xf.q.s);
            eat(st.v.x);
            eat(st.v.y);
            eat(st.w);
        }
        h
    }
}
