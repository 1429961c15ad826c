//! The world: bodies and contacts in flat arrays, the worker threads, and the step pipeline.
//!
//! `step` runs the stages in order, each timed into [`StepProfile`]:
//! broad phase → narrow phase → prepare → substeps (solve) → restitution → finalize.
//! A step runs on the caller's thread; when it is large enough (`WideThresholds`) its
//! stages are shared with the world's crew of worker threads. Shared stages write only their
//! own index's slot or part, so their results are the same on any thread count.

#[cfg(not(target_arch = "wasm32"))]
use std::time::Instant;

use glam::Vec2;
use rustc_hash::FxHashMap;
// `std::time::Instant` panics on the web; web-time's reads `performance.now()` there.
#[cfg(target_arch = "wasm32")]
use web_time::Instant;

use crate::collision::broad_phase::BroadPhase;
use crate::collision::{Manifold, collide};
use crate::crew::Crew;
use crate::error::{SceneError, SettingsError};
use crate::math::{Rot, Transform};
use crate::parallel::{Spread, for_each_part, for_parts};
use crate::profile::StepProfile;
use crate::scene::{BodyDef, BodyKind, Limits, SceneDef};
use crate::shape::{Aabb, Shape};
use crate::solver::contact_solver::{BodyState, Softness};
use crate::solver::{
    BodyMotion, ContactInput, NOT_DYNAMIC, Solver, SolverBody, SolverContact, SolverParams,
    SubstepParams, Touching,
};
use crate::{AABB_MARGIN, SPECULATIVE_DISTANCE};

/// The knobs of the step that trade speed for accuracy. Defaults are Box2D v3's.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StepSettings {
    /// Gravity (m/s²).
    pub gravity: Vec2,
    /// Stiffness of contacts (Hz); clamped to an eighth of the substep rate, which keeps low
    /// substep counts stable (Box2D HEAD, SOFT_STEP.md 2.3). Contacts against static bodies
    /// use twice it. Box2D's 30 Hz: at 60 Hz (with a quarter-rate clamp) the 100-row pyramid
    /// was measured to jitter at 0.4 m/s after 500 steps, against 0.13 m/s at 30 Hz.
    pub contact_hertz: f32,
    /// Damping ratio of the contact spring (Box2D: 10, heavily over-damped).
    pub contact_damping_ratio: f32,
    /// Fastest that overlap is pushed apart (m/s), Box2D's `contactSpeed`.
    pub max_push_speed: f32,
    /// Rigid relax passes per substep after the soft solve (Box2D: 1).
    pub relax_iterations: u32,
    /// Approach speed (m/s) below which restitution is not applied.
    pub restitution_threshold: f32,
    /// Passes of the restitution stage at the end of the step. One pass (Box2D's) applies
    /// each contact's bounce once, in colour order, so a body that hits two others in one
    /// step (a wall and a ball) is sent back into the first by the second; more passes
    /// converge to bounces that hold for every contact at once. Skipped when nothing bounces.
    #[serde(default = "one")]
    pub restitution_iterations: u32,
    /// Speed cap (m/s), Box2D's `maxLinearSpeed`.
    pub max_linear_speed: f32,
    /// Seed each step's solve with the last step's impulses.
    pub warm_starting: bool,
    /// Keep a contact's manifold while its pair barely moves (Box2D v3's contact recycling):
    /// cheaper narrow phase and steadier stacks.
    pub contact_recycling: bool,
    /// Solve each colour eight constraints at a time with SIMD. Off runs the scalar path,
    /// which gives bit-identical results; it exists to measure what SIMD buys.
    pub simd: bool,
}

fn one() -> u32 {
    1
}

impl Default for StepSettings {
    fn default() -> Self {
        Self {
            gravity: Vec2::new(0.0, -10.0),
            contact_hertz: 30.0,
            contact_damping_ratio: 10.0,
            max_push_speed: 3.0,
            relax_iterations: 1,
            restitution_threshold: 1.0,
            restitution_iterations: 1,
            max_linear_speed: 400.0,
            warm_starting: true,
            contact_recycling: true,
            simd: true,
        }
    }
}

impl StepSettings {
    /// Checks every knob for a value the step cannot use: a non-finite or negative number
    /// (gravity, contact hertz, damping ratio, push-out speed, restitution threshold) turns
    /// the state non-finite or pulls bodies together; zero relax passes silently drop
    /// friction (friction is solved in the relax pass); zero restitution passes drop every
    /// bounce; a speed cap that is not a finite number > 0 stops every body or caps nothing.
    /// [`World::from_scene`] and [`World::from_snapshot`] call it; so should anything that
    /// takes settings from outside (flags, sliders, files) before
    /// [`World::settings_mut`].
    pub fn validate(&self) -> Result<(), SettingsError> {
        let err = |field: &'static str, value: String, allowed: &str| SettingsError {
            field,
            value,
            allowed: allowed.to_string(),
        };
        if !self.gravity.is_finite() {
            return Err(err(
                "gravity",
                format!("{:?}", <[f32; 2]>::from(self.gravity)),
                "two finite numbers (m/s²)",
            ));
        }
        let non_negative = |field: &'static str, v: f32, unit: &str| {
            if v.is_finite() && v >= 0.0 {
                Ok(())
            } else {
                Err(err(
                    field,
                    v.to_string(),
                    &format!("a finite number >= 0 ({unit})"),
                ))
            }
        };
        non_negative(
            "contact_hertz",
            self.contact_hertz,
            "Hz; Box2D's default is 30",
        )?;
        non_negative(
            "contact_damping_ratio",
            self.contact_damping_ratio,
            "Box2D's default is 10",
        )?;
        non_negative(
            "max_push_speed",
            self.max_push_speed,
            "m/s; Box2D's default is 3",
        )?;
        non_negative(
            "restitution_threshold",
            self.restitution_threshold,
            "m/s; Box2D's default is 1",
        )?;
        if !(self.max_linear_speed.is_finite() && self.max_linear_speed > 0.0) {
            return Err(err(
                "max_linear_speed",
                self.max_linear_speed.to_string(),
                "a finite number > 0 (m/s; 0 would stop every body; Box2D's default is 400)",
            ));
        }
        if self.relax_iterations == 0 {
            return Err(err(
                "relax_iterations",
                "0".into(),
                "1 or more (friction is solved in the relax pass, so 0 would silently remove \
                 it; Box2D's default is 1)",
            ));
        }
        if self.restitution_iterations == 0 {
            return Err(err(
                "restitution_iterations",
                "0".into(),
                "1 or more (0 would silently remove every bounce; Box2D's default is 1)",
            ));
        }
        Ok(())
    }
}

/// A body's state as the outside sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyView {
    /// Centre of mass.
    pub position: Vec2,
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
}

/// A contact as the outside sees it (for debug drawing and tests).
#[derive(Clone, Copy, Debug)]
pub struct ContactView<'a> {
    /// First body (the polygon, when a polygon meets a circle).
    pub body_a: usize,
    /// Second body.
    pub body_b: usize,
    /// The manifold, with last step's impulses.
    pub manifold: &'a Manifold,
}

/// Number of cores, the default thread count (as [`set_thread_source`] says, where it was
/// called). Read once: the solver asks every step, and the standard library's answer reads
/// the cgroup files each time (a file read and allocations in every step).
pub fn default_thread_count() -> usize {
    static CORES: std::sync::OnceLock<usize> = std::sync::OnceLock::new();
    match THREAD_SOURCE.get() {
        Some(&(cores, _)) => cores.max(1),
        None => *CORES.get_or_init(|| std::thread::available_parallelism().map_or(1, |n| n.get())),
    }
}

/// Starts one worker thread of a step's pool (a rayon spawn handler).
pub type SpawnWorker = fn(rayon::ThreadBuilder) -> std::io::Result<()>;

static THREAD_SOURCE: std::sync::OnceLock<(usize, Option<SpawnWorker>)> =
    std::sync::OnceLock::new();

/// For a platform where `std::thread` cannot start threads (the web, whose threads are Web
/// Workers): `cores` is what [`default_thread_count`] returns from now on, and `spawn` starts
/// each worker of the pools built from now on; with `None` there are no threads, and every
/// step runs on the calling thread. Natively nothing calls it and rayon starts std threads.
/// Returns false if a source was set already (the first one stays).
pub fn set_thread_source(cores: usize, spawn: Option<SpawnWorker>) -> bool {
    THREAD_SOURCE.set((cores, spawn)).is_ok()
}

/// The least work per worker for which a stage of the step is split over the world's threads:
/// below it the stage runs on one thread, and a step none of whose stages reaches its
/// threshold runs inline on the caller's thread without waking the crew. Results never depend
/// on these (the tests of determinism run with [`WideThresholds::ALWAYS`] and the defaults).
///
/// The defaults come from measurement (`tumble-bench thresholds`, docs/bench/thresholds.md):
/// each is about where splitting the stage over two workers begins to pay on this project's
/// 2-core machine.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WideThresholds {
    /// Contacts (and moved proxies, which make contacts), for the step to leave the caller's
    /// thread at all: below it every stage runs inline (each split stage costs a hand-off to
    /// the followers and a wait for the last part).
    pub step: usize,
    /// Moved proxies, for the broad phase's queries.
    pub broad_phase: usize,
    /// Contacts, for the narrow phase.
    pub narrow_phase: usize,
    /// Touching contacts, for building, storing and checking the constraints.
    pub prepare: usize,
    /// Touching contacts, for the substeps and restitution (the solver's stage board).
    pub solve: usize,
    /// Bodies, for finalize.
    pub finalize: usize,
}

impl WideThresholds {
    /// Every stage of more than one item is split (for tests and measurement).
    pub const ALWAYS: WideThresholds = WideThresholds {
        step: 1,
        broad_phase: 1,
        narrow_phase: 1,
        prepare: 1,
        solve: 1,
        finalize: 1,
    };
    /// No stage is ever split: every step runs inline.
    pub const NEVER: WideThresholds = WideThresholds {
        step: usize::MAX / 2,
        broad_phase: usize::MAX / 2,
        narrow_phase: usize::MAX / 2,
        prepare: usize::MAX / 2,
        solve: usize::MAX / 2,
        finalize: usize::MAX / 2,
    };
}

impl Default for WideThresholds {
    fn default() -> Self {
        // docs/bench/thresholds.md: about half of each crossover measured on 2 cores (the
        // lower of two runs where one size's outlier moved a crossover, rounded).
        WideThresholds {
            step: 750,
            broad_phase: 120,
            narrow_phase: 630,
            prepare: 1200,
            solve: 950,
            finalize: 1000,
        }
    }
}

/// Per-body data that the step reads but the substep loop does not.
#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
struct BodySim {
    xf: Transform,
    kind: BodyKind,
    inv_inertia: f32,
    friction: f32,
    restitution: f32,
    /// Largest centre-to-surface distance, for rotation-swept bounds.
    extent: f32,
    /// Fat-box margin for this body.
    margin: f32,
    /// Smallest centre-to-surface distance (how thin the body is).
    min_extent: f32,
    /// Moved more than half its thickness last step: its contacts are always recomputed.
    fast: bool,
}

#[derive(Clone, Copy, Debug, serde::Serialize, serde::Deserialize)]
struct Contact {
    body_a: u32,
    body_b: u32,
    friction: f32,
    restitution: f32,
    manifold: Manifold,
    /// Poses when the manifold was last computed, for contact recycling.
    cache: Option<ContactCache>,
    /// The bodies' masses (copied at creation; see `ContactInput::masses`). Not stored in
    /// snapshots: restoring copies them from the bodies again, so a snapshot cannot make a
    /// dynamic body look static to the colouring.
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
}

/// A contact's copy of its bodies' masses (`Contact::masses`), made when it is created and
/// when a snapshot is restored.
fn masses_of(bodies: &[SolverBody], a: u32, b: u32) -> [SolverBody; 2] {
    [bodies[a as usize], bodies[b as usize]]
}

impl ContactKey {
    fn of(c: &Contact) -> ContactKey {
        let side = |i: u32, m: &SolverBody| if m.dynamic { i } else { NOT_DYNAMIC };
        ContactKey {
            dynamic: [side(c.body_a, &c.masses[0]), side(c.body_b, &c.masses[1])],
            touching: c.manifold.count > 0,
            remove: false,
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

/// Contacts whose relative pose moved less than this keep their manifold (Box2D's
/// `B2_CONTACT_RECYCLE_DISTANCE`, 10 slops).
const RECYCLE_DISTANCE: f32 = 10.0 * crate::LINEAR_SLOP;
/// ...and whose bodies each turned less than about 11.5° (`B2_CONTACT_RECYCLE_COS_ANGLE`).
const RECYCLE_COS_ANGLE: f32 = 0.98;

#[inline]
fn pair_key(a: u32, b: u32) -> u64 {
    let (lo, hi) = if a < b { (a, b) } else { (b, a) };
    (u64::from(lo) << 32) | u64::from(hi)
}

/// Everything that decides a world's future, as plain serde data: bodies, contacts with
/// their warm-start impulses and recycling caches, and the broad phase's pending moves.
/// Restoring it and stepping gives bit-identical states to never having stopped. The thread
/// count is not part of it (it never changes results). The encoding is the caller's choice.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct WorldSnapshot {
    settings: StepSettings,
    shapes: Vec<Shape>,
    sims: Vec<BodySim>,
    states: Vec<BodyState>,
    fat_aabbs: Vec<Aabb>,
    solver_bodies: Vec<SolverBody>,
    motion: Vec<BodyMotion>,
    moved: Vec<u32>,
    contacts: Vec<Contact>,
    steps: u64,
    speed_caps: u64,
    /// Bodies the numerical guard has stopped (see [`World::non_finite_bodies`]); absent
    /// from snapshots written before it was counted, which read as 0.
    #[serde(default)]
    non_finite_bodies: u64,
}

impl WorldSnapshot {
    /// Bytes its arrays hold in memory (their lengths times their element sizes): what a
    /// caller keeping many snapshots (the viewer's replay) budgets with.
    pub fn approx_bytes(&self) -> usize {
        use std::mem::size_of_val;
        std::mem::size_of::<Self>()
            + size_of_val(&self.shapes[..])
            + size_of_val(&self.sims[..])
            + size_of_val(&self.states[..])
            + size_of_val(&self.fat_aabbs[..])
            + size_of_val(&self.solver_bodies[..])
            + size_of_val(&self.motion[..])
            + size_of_val(&self.moved[..])
            + size_of_val(&self.contacts[..])
    }

    /// Bodies in the snapshot.
    pub fn body_count(&self) -> usize {
        self.sims.len()
    }
}

/// A 2D rigid-body world.
pub struct World {
    settings: StepSettings,
    shapes: Vec<Shape>,
    sims: Vec<BodySim>,
    states: Vec<BodyState>,
    fat_aabbs: Vec<Aabb>,
    /// Proxies whose fat box changed since the last pair search.
    moved: Vec<u32>,
    moved_flags: Vec<bool>,
    /// Scratch: each moved proxy's place in `moved` (the tree walk's creation order).
    moved_rank: Vec<u32>,
    /// Set by finalize for a body whose state went non-finite (then counted and cleared).
    guarded: Vec<bool>,
    guarded_last_step: usize,
    /// Every body the guard has stopped, over the world's whole life (snapshots keep it).
    non_finite_bodies: u64,
    tree_dirty: bool,
    broad_phase: BroadPhase,
    contacts: Vec<Contact>,
    /// One per contact, in the same order.
    contact_keys: Vec<ContactKey>,
    pairs: FxHashMap<u64, u32>,
    solver: Solver,
    /// Indices of this step's touching contacts, in contact order (reused).
    touching: Vec<Touching>,
    solver_bodies: Vec<SolverBody>,
    motion: Vec<BodyMotion>,
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

/// The crew for `threads` threads: the caller's and `threads - 1` followers.
fn start_crew(threads: usize) -> Option<std::sync::Arc<Crew>> {
    if threads <= 1 {
        return None;
    }
    let builder = rayon::ThreadPoolBuilder::new()
        .num_threads(threads - 1)
        .thread_name(|i| format!("tumble-step-{i}"));
    let pool = match THREAD_SOURCE.get() {
        None => builder.build(),
        Some(&(_, Some(spawn))) => builder.spawn_handler(spawn).build(),
        Some(&(_, None)) => return None,
    }
    // Starting threads only fails if the OS refuses them; then nothing can run.
    .expect("the OS refused to start the step's worker threads");
    Some(std::sync::Arc::new(Crew::start(pool)))
}

impl World {
    /// An empty world with the given settings, on all cores.
    pub fn new(settings: StepSettings) -> World {
        let threads = default_thread_count();
        World {
            settings,
            shapes: Vec::new(),
            sims: Vec::new(),
            states: Vec::new(),
            fat_aabbs: Vec::new(),
            moved: Vec::new(),
            moved_flags: Vec::new(),
            moved_rank: Vec::new(),
            guarded: Vec::new(),
            guarded_last_step: 0,
            non_finite_bodies: 0,
            tree_dirty: true,
            broad_phase: BroadPhase::default(),
            contacts: Vec::new(),
            contact_keys: Vec::new(),
            pairs: FxHashMap::default(),
            solver: Solver::new(),
            touching: Vec::new(),
            solver_bodies: Vec::new(),
            motion: Vec::new(),
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
            ..StepSettings::default()
        };
        scene.solver.apply(&mut settings);
        settings.validate()?;
        let mut world = World::new(settings);
        world.reserve(scene.bodies.len());
        for (i, body) in scene.bodies.iter().enumerate() {
            world.add_body(body).map_err(|e| match e {
                SceneError::Body {
                    field,
                    value,
                    allowed,
                    ..
                } => SceneError::Body {
                    index: i,
                    field,
                    value,
                    allowed,
                },
                other => other,
            })?;
        }
        Ok(world)
    }

    fn reserve(&mut self, n: usize) {
        self.shapes.reserve(n);
        self.sims.reserve(n);
        self.states.reserve(n);
        self.fat_aabbs.reserve(n);
    }

    /// Adds a body and returns its id. The body is checked as a scene body would be.
    pub fn add_body(&mut self, def: &BodyDef) -> Result<usize, SceneError> {
        let index = self.sims.len();
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
        // Validation has checked the polygon, so this cannot fail.
        let shape = Shape::from_def(&def.shape).map_err(|e| SceneError::Body {
            index,
            field: "shape".into(),
            value: e.to_string(),
            allowed: "a valid shape".into(),
        })?;
        let (inv_mass, inv_inertia) = match def.kind {
            BodyKind::Dynamic => {
                let md = shape.mass(def.density);
                let inv_i = if def.fixed_rotation || md.inertia <= 0.0 {
                    0.0
                } else {
                    1.0 / md.inertia
                };
                (1.0 / md.mass, inv_i)
            }
            _ => (0.0, 0.0),
        };
        let extent = shape.extent();
        let margin = match def.kind {
            BodyKind::Static => 0.0,
            // Box2D `b2ComputeShapeMargin`: small shapes get proportionally small margins.
            _ => AABB_MARGIN.min(0.125 * extent),
        };
        let xf = Transform {
            p: Vec2::from(def.position),
            q: Rot::from_angle(def.angle),
        };
        let rotates = !(def.kind == BodyKind::Dynamic && def.fixed_rotation);
        let state = BodyState {
            v: Vec2::from(def.linear_velocity),
            w: if rotates { def.angular_velocity } else { 0.0 },
            ..BodyState::default()
        };
        let sim = BodySim {
            xf,
            kind: def.kind,
            inv_inertia,
            friction: def.friction,
            restitution: def.restitution,
            extent,
            margin,
            min_extent: shape.min_extent(),
            fast: false,
        };
        let aabb = swept_aabb(&shape, &sim, &state, 1.0 / 60.0).grown(margin);
        self.shapes.push(shape);
        self.sims.push(sim);
        self.states.push(state);
        self.fat_aabbs.push(aabb);
        self.moved.push(index as u32);
        self.moved_flags.push(true);
        self.guarded.push(false);
        self.motion.push(BodyMotion {
            dynamic: def.kind == BodyKind::Dynamic,
            moves: def.kind != BodyKind::Static,
            rotates: match def.kind {
                BodyKind::Static => false,
                BodyKind::Kinematic => true,
                BodyKind::Dynamic => inv_inertia > 0.0,
            },
            linear_damping: def.linear_damping,
            angular_damping: def.angular_damping,
        });
        self.solver_bodies.push(SolverBody {
            inv_mass,
            inv_inertia,
            dynamic: def.kind == BodyKind::Dynamic,
        });
        self.tree_dirty = true;
        Ok(index)
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

    /// Bodies in the world.
    pub fn body_count(&self) -> usize {
        self.sims.len()
    }

    /// Contacts (pairs of overlapping fat boxes).
    pub fn contact_count(&self) -> usize {
        self.contacts.len()
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

    /// One body's state.
    pub fn body(&self, index: usize) -> BodyView {
        let sim = &self.sims[index];
        let st = &self.states[index];
        BodyView {
            position: sim.xf.p,
            angle: sim.xf.q.angle(),
            rotation: sim.xf.q,
            linear_velocity: st.v,
            angular_velocity: st.w,
            kind: sim.kind,
        }
    }

    /// A body's shape, in its own frame.
    pub fn shape(&self, index: usize) -> &Shape {
        &self.shapes[index]
    }

    /// A body's fat bounding box, as the broad phase sees it.
    pub fn fat_aabb(&self, index: usize) -> Aabb {
        self.fat_aabbs[index]
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
            manifold: &c.manifold,
        })
    }

    /// Sets a body's velocities (e.g. a mouse drag); ignored for static bodies.
    pub fn set_velocity(&mut self, index: usize, linear: Vec2, angular: f32) {
        if self.sims[index].kind == BodyKind::Static || !linear.is_finite() || !angular.is_finite()
        {
            return;
        }
        let s = &mut self.states[index];
        s.v = linear;
        if self.sims[index].inv_inertia > 0.0 || self.sims[index].kind == BodyKind::Kinematic {
            s.w = angular;
        }
    }

    /// The world's state, to save and restore (see [`WorldSnapshot`]).
    pub fn snapshot(&self) -> WorldSnapshot {
        WorldSnapshot {
            settings: self.settings,
            shapes: self.shapes.clone(),
            sims: self.sims.clone(),
            states: self.states.clone(),
            fat_aabbs: self.fat_aabbs.clone(),
            solver_bodies: self.solver_bodies.clone(),
            motion: self.motion.clone(),
            moved: self.moved.clone(),
            contacts: self.contacts.clone(),
            steps: self.steps,
            speed_caps: self.speed_caps,
            non_finite_bodies: self.non_finite_bodies,
        }
    }

    /// A world in the state of `snapshot`, on all cores. Fails if the snapshot's arrays do
    /// not agree in length or its contacts name bodies it lacks (a corrupt or foreign file),
    /// or if its settings are out of range ([`StepSettings::validate`]).
    pub fn from_snapshot(snapshot: WorldSnapshot) -> Result<World, SceneError> {
        snapshot.settings.validate()?;
        let n = snapshot.sims.len();
        let lengths = [
            snapshot.shapes.len(),
            snapshot.states.len(),
            snapshot.fat_aabbs.len(),
            snapshot.solver_bodies.len(),
            snapshot.motion.len(),
        ];
        let bad_contact = snapshot
            .contacts
            .iter()
            .any(|c| c.body_a as usize >= n || c.body_b as usize >= n || c.manifold.count > 2);
        let bad_shape = snapshot.shapes.iter().any(|shape| match shape {
            Shape::Polygon(p) => !(3..=crate::MAX_POLYGON_VERTICES).contains(&p.count),
            Shape::Circle(_) => false,
        });
        if lengths.iter().any(|&l| l != n)
            || bad_contact
            || bad_shape
            || snapshot.moved.iter().any(|&m| m as usize >= n)
        {
            return Err(SceneError::Scene {
                field: "snapshot".into(),
                value: "inconsistent arrays".into(),
                allowed: "a snapshot written by World::snapshot".into(),
            });
        }
        let mut world = World::new(snapshot.settings);
        let mut moved_flags = vec![false; n];
        for &m in &snapshot.moved {
            moved_flags[m as usize] = true;
        }
        world.pairs = snapshot
            .contacts
            .iter()
            .enumerate()
            .map(|(k, c)| (pair_key(c.body_a, c.body_b), k as u32))
            .collect();
        world.shapes = snapshot.shapes;
        world.sims = snapshot.sims;
        world.states = snapshot.states;
        world.fat_aabbs = snapshot.fat_aabbs;
        world.solver_bodies = snapshot.solver_bodies;
        world.motion = snapshot.motion;
        world.moved = snapshot.moved;
        world.moved_flags = moved_flags;
        world.guarded = vec![false; n];
        world.contacts = snapshot.contacts;
        for c in &mut world.contacts {
            c.masses = masses_of(&world.solver_bodies, c.body_a, c.body_b);
        }
        world.contact_keys = world.contacts.iter().map(ContactKey::of).collect();
        world.steps = snapshot.steps;
        world.speed_caps = snapshot.speed_caps;
        world.non_finite_bodies = snapshot.non_finite_bodies;
        world.tree_dirty = true;
        Ok(world)
    }

    /// A body's mass (kg); zero for static and kinematic bodies.
    pub fn mass(&self, index: usize) -> f32 {
        let inv = self.solver_bodies[index].inv_mass;
        if inv > 0.0 { 1.0 / inv } else { 0.0 }
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
    /// once (a mouse spring, an explosion). Ignored for other bodies and non-finite input.
    pub fn apply_linear_impulse(&mut self, index: usize, impulse: Vec2, point: Vec2) {
        let body = self.solver_bodies[index];
        if !body.dynamic || !impulse.is_finite() || !point.is_finite() {
            return;
        }
        let r = point - self.sims[index].xf.p;
        let s = &mut self.states[index];
        s.v += impulse * body.inv_mass;
        s.w += body.inv_inertia * crate::math::cross(r, impulse);
    }

    /// The index of a body whose shape contains the world point, if any (the last one in id
    /// order, which a viewer draws on top).
    pub fn body_at(&self, point: Vec2) -> Option<usize> {
        (0..self.sims.len()).rev().find(|&i| {
            let local = self.sims[i].xf.apply_inv(point);
            match &self.shapes[i] {
                Shape::Circle(c) => local.length_squared() <= c.radius * c.radius,
                Shape::Polygon(p) => (0..p.count)
                    .all(|k| crate::math::dot(p.normals[k], local - p.vertices[k]) <= 0.0),
            }
        })
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

    /// FNV-1a, 64-bit, over the exact bits of every body's position, rotation (cos, sin),
    /// linear and angular velocity, in id order.
    pub fn state_hash(&self) -> u64 {
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        let mut eat = |x: f32| {
            for byte in x.to_bits().to_le_bytes() {
                h ^= u64::from(byte);
                h = h.wrapping_mul(0x0000_0100_0000_01b3);
            }
        };
        for (sim, st) in self.sims.iter().zip(&self.states) {
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

    /// Advances the world by `dt` seconds in `substeps` solver substeps.
    ///
    /// Does nothing (no step is counted, the profile is zeroed) for a `dt` that
    /// [`World::steppable`] refuses: not finite, not > 0, subnormal, or so small that one
    /// substep `dt / substeps` is subnormal (its inverse, the substep rate, would overflow to
    /// infinity and turn the state non-finite); nor for `substeps == 0`. Scene validation
    /// refuses such a scene's `dt` with a message.
    pub fn step(&mut self, dt: f32, substeps: u32) {
        let start = Instant::now();
        let mut profile = StepProfile::default();
        if !World::steppable(dt, substeps) {
            self.profile = profile;
            return;
        }
        // Only a wide step touches the crew (an inline one takes not even its reference
        // count). The step runs on this thread either way; a wide one's stages are shared.
        let crew = if self.goes_wide() {
            self.crew.clone()
        } else {
            None
        };
        let spread = crew.as_deref().map_or(Spread::INLINE, Spread::over);

        let t = Instant::now();
        self.update_pairs(spread);
        profile.broad_phase_ms = ms(t);

        let t = Instant::now();
        self.collide(dt, spread);
        profile.narrow_phase_ms = ms(t);

        self.solve(dt, substeps, spread, &mut profile);

        let t = Instant::now();
        self.finalize(dt, spread);
        profile.finalize_ms = ms(t);

        profile.inline = crew.is_none();
        self.steps += 1;
        profile.bodies = self.sims.len();
        profile.contacts = self.contacts.len();
        profile.moved = self.moved.len();
        profile.recycled = self.profile_recycled;
        profile.non_finite = self.guarded_last_step;
        profile.step_ms = ms(start);
        self.profile = profile;
    }

    /// Whether [`World::step`] steps with this `dt` and `substeps`: `dt` a finite, normal
    /// (not subnormal) number > 0, at least one substep, and `dt / substeps` normal too.
    pub fn steppable(dt: f32, substeps: u32) -> bool {
        dt > 0.0 && dt.is_normal() && substeps > 0 && (dt / substeps as f32).is_normal()
    }

    /// Whether this step shares its stages with the crew: when there is one, the step has
    /// [`WideThresholds::step`]'s contacts and moved proxies, and some stage of it would be
    /// split, judged on the counts the step starts from (a stage whose count crosses its
    /// threshold during the step runs on one thread until the next step).
    fn goes_wide(&self) -> bool {
        let Some(crew) = &self.crew else {
            return false;
        };
        let all = Spread::over(crew);
        let (w, contacts) = (&self.wide, self.contact_keys.len());
        let split = all.goes_wide(self.moved.len(), w.broad_phase)
            || all.goes_wide(contacts, w.narrow_phase)
            || all.goes_wide(self.touching.len(), w.prepare.min(w.solve))
            || all.goes_wide(self.sims.len(), w.finalize);
        // A new scene's first step has no contacts yet, but its moved proxies will make them.
        split && all.goes_wide(contacts + self.moved.len(), w.step)
    }

    /// Broad phase: rebuild the tree if a fat box changed, then find the new pairs of every
    /// moved proxy (in parallel, each into its own list) and create their contacts serially
    /// in moved order.
    fn update_pairs(&mut self, spread: Spread<'_>) {
        if self.moved.is_empty() {
            return;
        }
        if self.tree_dirty {
            // A cheap refit, and a full rebuild (serial, O(n log n): 3.4 ms of a 20,000-body
            // pile's 16 ms step when it ran every step) only when proxies were added or the
            // refitted tree has grown a quarter costlier than a fresh one: bodies that move
            // together (a falling pile, a drifting cloud) keep a refitted tree good. The tree's
            // shape never changes which pairs are found, nor their order (both are sorted).
            let n = self.fat_aabbs.len();
            if self.broad_phase.proxy_count() != n {
                self.broad_phase.rebuild(&self.fat_aabbs);
            } else {
                self.broad_phase.refit(&self.fat_aabbs);
                if self.broad_phase.looseness() > 1.25 {
                    self.broad_phase.rebuild(&self.fat_aabbs);
                }
            }
            self.tree_dirty = false;
        }
        let bp = &self.broad_phase;
        let aabbs = &self.fat_aabbs;
        // Whether each body is dynamic, from the 12-byte solver records rather than the
        // body sims (a cache line each, read at random for every overlapping pair).
        let dynamic = &self.solver_bodies;
        let moved_flags = &self.moved_flags;
        let pairs = &self.pairs;
        // A new contact only for a pair with a dynamic body (no other can ever push
        // anything) that has none yet.
        let wants_contact = |p: u32, q: u32| {
            (dynamic[p as usize].dynamic || dynamic[q as usize].dynamic)
                && !pairs.contains_key(&pair_key(p, q))
        };
        if self.moved.len() * 2 > aabbs.len() {
            // Most proxies moved (smash, an explosion, the first step): walk the tree against
            // itself once instead of querying it per proxy. The same pairs as the queries
            // would find, created in the same order (each by its finder's place in `moved`,
            // then the other's id), so the results do not depend on which way was taken.
            let mut rank = std::mem::take(&mut self.moved_rank);
            rank.clear();
            rank.resize(aabbs.len(), u32::MAX);
            for (k, &i) in self.moved.iter().enumerate() {
                rank[i as usize] = k as u32;
            }
            let keep = |p: u32, q: u32| {
                let (mp, mq) = (moved_flags[p as usize], moved_flags[q as usize]);
                if !(mp || mq) || !wants_contact(p, q) {
                    return None;
                }
                // The finder is the moved one; of two moved, the larger id (as below).
                let (finder, other) = if mp && mq {
                    (p.max(q), p.min(q))
                } else if mp {
                    (p, q)
                } else {
                    (q, p)
                };
                Some((u64::from(rank[finder as usize]) << 32) | u64::from(other))
            };
            let walk = spread.for_stage(self.moved.len(), self.wide.broad_phase);
            let mut found = bp.overlapping_pairs_parallel(aabbs, walk, &keep);
            // Each task's pairs come sorted: a merge sort joins the runs in O(n log tasks).
            found.sort();
            let moved = std::mem::take(&mut self.moved);
            for key in found {
                let (finder, other) = (moved[(key >> 32) as usize], key as u32);
                self.create_contact(finder, other);
            }
            self.moved_rank = rank;
            self.finish_moved(moved);
            return;
        }
        // Each part of the moved proxies lists its new pairs in moved order, each proxy's
        // sorted by the other's id; the parts are joined in order.
        let found = for_parts(
            spread,
            &self.moved[..],
            self.wide.broad_phase,
            &|_, part: &[u32]| {
                let mut out = Vec::new();
                for &i in part {
                    let start = out.len();
                    bp.query(&aabbs[i as usize], aabbs, |j| {
                        // A pair of moved proxies is found from the larger id only.
                        if j != i && !(moved_flags[j as usize] && j > i) && wants_contact(i, j) {
                            out.push((i, j));
                        }
                    });
                    out[start..].sort_unstable();
                }
                out
            },
            &|mut a, b| {
                a.extend(b);
                a
            },
        );
        for (i, j) in found {
            self.create_contact(i, j);
        }
        let moved = std::mem::take(&mut self.moved);
        self.finish_moved(moved);
    }

    /// Clears the moved proxies once their pairs are made, keeping the buffer.
    fn finish_moved(&mut self, mut moved: Vec<u32>) {
        for &i in &moved {
            self.moved_flags[i as usize] = false;
        }
        moved.clear();
        self.moved = moved;
    }

    fn create_contact(&mut self, i: u32, j: u32) {
        // Polygon first when a polygon meets a circle; otherwise the lower id first.
        let (mut a, mut b) = if i < j { (i, j) } else { (j, i) };
        if matches!(self.shapes[a as usize], Shape::Circle(_))
            && matches!(self.shapes[b as usize], Shape::Polygon(_))
        {
            std::mem::swap(&mut a, &mut b);
        }
        let sa = &self.sims[a as usize];
        let sb = &self.sims[b as usize];
        let contact = Contact {
            body_a: a,
            body_b: b,
            // Mixing rules: Box2D's defaults (and the contract's).
            friction: (sa.friction * sb.friction).sqrt(),
            restitution: sa.restitution.max(sb.restitution),
            manifold: Manifold::default(),
            cache: None,
            masses: masses_of(&self.solver_bodies, a, b),
        };
        self.pairs
            .insert(pair_key(a, b), self.contacts.len() as u32);
        self.contact_keys.push(ContactKey::of(&contact));
        self.contacts.push(contact);
    }

    /// Narrow phase: every contact computes its manifold into its own slot, carrying
    /// impulses over by feature id; contacts whose fat boxes parted are then removed in
    /// descending index order, so the surviving order is deterministic.
    fn collide(&mut self, dt: f32, spread: Spread<'_>) {
        let sims = &self.sims;
        let states = &self.states;
        let shapes = &self.shapes;
        let aabbs = &self.fat_aabbs;
        let recycling = self.settings.contact_recycling;
        let collide_one = |c: &mut Contact, key: &mut ContactKey| {
            let (a, b) = (c.body_a as usize, c.body_b as usize);
            if !aabbs[a].overlaps(&aabbs[b]) {
                key.remove = true;
                return 0;
            }
            let (xa, xb) = (sims[a].xf, sims[b].xf);
            if recycling && recycle(c, &sims[a], &sims[b]) {
                key.touching = c.manifold.count > 0;
                return 1;
            }
            c.cache = Some(ContactCache {
                q_a: xa.q,
                q_b: xb.q,
                relative: xa.inv_mul(xb),
            });
            // Speculative margin: how far the pair can close in one step, so bodies meet
            // without tunnelling at ordinary speeds.
            let (sa, sb) = (&states[a], &states[b]);
            let closing =
                (sb.v - sa.v).length() + sa.w.abs() * sims[a].extent + sb.w.abs() * sims[b].extent;
            let max_distance = SPECULATIVE_DISTANCE + dt * closing;
            let old = c.manifold;
            let mut m = collide(&shapes[a], xa, &shapes[b], xb, max_distance);
            for p in &mut m.points[..m.count] {
                p.base_separation = p.separation;
                if let Some(o) = old.points().iter().find(|o| o.id == p.id) {
                    p.normal_impulse = o.normal_impulse;
                    p.tangent_impulse = o.tangent_impulse;
                    p.persisted = true;
                }
            }
            c.manifold = m;
            key.touching = m.count > 0;
            0
        };
        let recycled = for_parts(
            spread,
            (&mut self.contacts[..], &mut self.contact_keys[..]),
            self.wide.narrow_phase,
            &|_, (contacts, keys): (&mut [Contact], &mut [ContactKey])| {
                contacts
                    .iter_mut()
                    .zip(keys)
                    .map(|(c, key)| collide_one(c, key))
                    .sum::<usize>()
            },
            &|a, b| a + b,
        );
        self.profile_recycled = recycled;
        for k in (0..self.contacts.len()).rev() {
            if self.contact_keys[k].remove {
                self.contact_keys.swap_remove(k);
                let c = self.contacts.swap_remove(k);
                self.pairs.remove(&pair_key(c.body_a, c.body_b));
                if k < self.contacts.len() {
                    let moved = &self.contacts[k];
                    self.pairs
                        .insert(pair_key(moved.body_a, moved.body_b), k as u32);
                }
            }
        }
    }

    /// Prepare, the substep loop, restitution and storing impulses.
    fn solve(&mut self, dt: f32, substeps: u32, spread: Spread<'_>, profile: &mut StepProfile) {
        let t = Instant::now();
        let h = dt / substeps as f32;
        let inv_h = 1.0 / h;
        let s = self.settings;
        // Soft contacts no stiffer than an eighth of the substep rate (Box2D HEAD).
        let hertz = s.contact_hertz.min(0.125 * inv_h);
        let params = SolverParams {
            contact_softness: Softness::new(hertz, s.contact_damping_ratio, h),
            static_softness: Softness::new(2.0 * hertz, s.contact_damping_ratio, h),
            warm_starting: s.warm_starting,
        };
        // The touching contacts in contact order, each with what the serial colouring needs,
        // so that it never reads the contacts. Serial, into the kept buffer: a scan of the
        // 12-byte keys costs about a nanosecond a contact, and rayon's parallel extend
        // allocates a list of vectors each step (issue 14: a steady step allocates nothing).
        self.touching.clear();
        self.touching.extend(
            self.contact_keys
                .iter()
                .enumerate()
                .filter(|(_, key)| key.touching)
                .map(|(k, key)| Touching {
                    contact: k as u32,
                    dynamic: key.dynamic,
                }),
        );
        profile.touching = self.touching.len();
        self.solver.use_wide = s.simd;
        self.solver.prepare(
            &self.touching,
            &self.contacts,
            self.solver_bodies.len(),
            &self.states,
            &params,
            spread,
            self.wide.prepare,
        );
        profile.colors = self.solver.active_colors();
        profile.overflow = self.solver.overflow_count();
        profile.prepare_ms = ms(t);

        let t = Instant::now();
        let step = SubstepParams {
            substeps,
            h,
            gravity: s.gravity,
            relax_iterations: s.relax_iterations,
            max_push_speed: s.max_push_speed,
            max_linear_speed: s.max_linear_speed,
            restitution_threshold: s.restitution_threshold,
            restitution_iterations: s.restitution_iterations,
        };
        // Below its threshold the solver runs on one worker: waking the others for every
        // stage (a hundred a step) costs more than their share of a small colour.
        let solve_spread = spread.for_stage(self.touching.len(), self.wide.solve);
        let (caps, workers) =
            self.solver
                .run_substeps(&mut self.states, &self.motion, &step, solve_spread);
        self.speed_caps += caps;
        profile.solver_workers = workers;
        profile.solve_ms = ms(t);

        let t = Instant::now();
        self.solver.store_impulses(
            &mut self.contacts,
            spread,
            self.wide.prepare,
            |contact, k, r| {
                let mp = &mut contact.manifold.points[k];
                mp.normal_impulse = r.normal_impulse;
                mp.tangent_impulse = r.tangent_impulse;
                mp.total_normal_impulse = r.total_normal_impulse;
                mp.normal_velocity = r.relative_velocity;
            },
        );
        profile.store_impulses_ms = ms(t);
    }

    /// Applies each body's substep deltas to its transform, resets them, and grows the fat
    /// box of any body that left it (those become the next step's moved proxies).
    fn finalize(&mut self, dt: f32, spread: Spread<'_>) {
        let shapes = &self.shapes;
        let finalize_one = |i: usize,
                            sim: &mut BodySim,
                            st: &mut BodyState,
                            fat: &mut Aabb,
                            moved: &mut bool,
                            guarded: &mut bool| {
            if sim.kind == BodyKind::Static {
                return;
            }
            // Box2D `b2FinalizeBodiesTask`: a body that moved more than half its thickness
            // is fast, and its contacts are recomputed rather than recycled.
            let max_motion = (st.dp.length() + st.dq.s.abs() * sim.extent)
                .max((st.v.length() + st.w.abs() * sim.extent) * dt);
            sim.fast = max_motion > 0.5 * sim.min_extent;
            let p = sim.xf.p + st.dp;
            let q = st.dq.then_from(sim.xf.q).normalize();
            st.dp = Vec2::ZERO;
            st.dq = Rot::IDENTITY;
            // Numerical guard: a body whose state went non-finite (it cannot with finite
            // input, but a guard costs four compares) keeps its last finite pose and stops,
            // rather than spreading NaN through its contacts.
            if p.is_finite()
                && q.c.is_finite()
                && q.s.is_finite()
                && st.v.is_finite()
                && st.w.is_finite()
            {
                sim.xf.p = p;
                sim.xf.q = q;
            } else {
                st.v = Vec2::ZERO;
                st.w = 0.0;
                *guarded = true;
            }
            let tight = swept_aabb(&shapes[i], sim, st, dt);
            if !fat.contains(&tight) {
                *fat = tight.grown(sim.margin);
                *moved = true;
            }
        };
        let bodies = (
            &mut self.sims[..],
            &mut self.states[..],
            &mut self.fat_aabbs[..],
            &mut self.moved_flags[..],
            &mut self.guarded[..],
        );
        type Bodies<'a> = (
            &'a mut [BodySim],
            &'a mut [BodyState],
            &'a mut [Aabb],
            &'a mut [bool],
            &'a mut [bool],
        );
        let finalize_part = |offset: usize, (sims, states, fats, moved, guarded): Bodies<'_>| {
            let each = sims
                .iter_mut()
                .zip(states)
                .zip(fats)
                .zip(moved)
                .zip(guarded);
            for (k, ((((sim, st), fat), moved), guarded)) in each.enumerate() {
                finalize_one(offset + k, sim, st, fat, moved, guarded);
            }
        };
        for_each_part(spread, bodies, self.wide.finalize, &finalize_part);
        for (i, &m) in self.moved_flags.iter().enumerate() {
            if m {
                self.moved.push(i as u32);
                self.tree_dirty = true;
            }
        }
        let mut guarded = 0;
        for g in &mut self.guarded {
            guarded += usize::from(std::mem::take(g));
        }
        self.guarded_last_step = guarded;
        self.non_finite_bodies += guarded as u64;
    }
}

/// Contact recycling (Box2D v3 `b2CollideTask`): when neither body is fast and the pair's
/// relative pose barely changed since the manifold was computed, keep its normal, anchors,
/// ids and impulses, and refresh only each point's separation from the motion since, as the
/// substeps do. This skips most of the narrow phase in resting piles and removes jitter.
fn recycle(c: &mut Contact, sa: &BodySim, sb: &BodySim) -> bool {
    let Some(cache) = c.cache else {
        return false;
    };
    if sa.fast || sb.fast {
        return false;
    }
    let (xa, xb) = (sa.xf, sb.xf);
    let relative = xa.inv_mul(xb);
    let cos_a = xa.q.c * cache.q_a.c + xa.q.s * cache.q_a.s;
    let cos_b = xb.q.c * cache.q_b.c + xb.q.s * cache.q_b.s;
    let extent_a = if sa.kind == BodyKind::Static {
        0.0
    } else {
        sa.extent
    };
    let extent_b = if sb.kind == BodyKind::Static {
        0.0
    } else {
        sb.extent
    };
    let max_extent = extent_a.max(extent_b);
    let distance = (relative.p - cache.relative.p).length();
    let turn = relative.q.inv_mul(cache.relative.q);
    // Non-touching pairs get a tighter tolerance so that a new touch is not missed.
    let tolerance = if c.manifold.count > 0 {
        RECYCLE_DISTANCE
    } else {
        RECYCLE_DISTANCE.min(SPECULATIVE_DISTANCE)
    };
    if cos_a.min(cos_b) <= RECYCLE_COS_ANGLE || distance + max_extent * turn.s.abs() >= tolerance {
        return false;
    }
    let dq_a = cache.q_a.inv_mul(xa.q);
    let dq_b = cache.q_b.inv_mul(xb.q);
    let normal = c.manifold.normal;
    let dc = xb.p - xa.p;
    for p in &mut c.manifold.points[..c.manifold.count] {
        let ra = dq_a.apply(p.anchor_a);
        let rb = dq_b.apply(p.anchor_b);
        p.separation = p.base_separation + crate::math::dot(dc + (rb - ra), normal);
        p.persisted = true;
    }
    true
}

/// The shape's box, stretched along the motion expected in the next step and grown by the
/// speculative distance: the broad phase then pairs what the speculative margin needs.
fn swept_aabb(shape: &Shape, sim: &BodySim, st: &BodyState, dt: f32) -> Aabb {
    let tight = shape.aabb(sim.xf);
    let d = st.v * dt;
    let swept = Aabb {
        min: tight.min + d.min(Vec2::ZERO),
        max: tight.max + d.max(Vec2::ZERO),
    };
    swept.grown(SPECULATIVE_DISTANCE + st.w.abs() * dt * sim.extent)
}

fn ms(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::ShapeDef;

    fn ball_on_ground() -> World {
        let mut w = World::new(StepSettings::default());
        w.add_body(
            &BodyDef::new(ShapeDef::Box {
                half_extents: [5.0, 0.5],
            })
            .kind(BodyKind::Static),
        )
        .unwrap();
        w.add_body(&BodyDef::new(ShapeDef::Circle { radius: 0.5 }).at(0.0, 1.0))
            .unwrap();
        w
    }

    #[test]
    fn kinetic_energy_is_half_m_v_squared_plus_half_i_w_squared_of_dynamic_bodies() {
        let mut w = ball_on_ground();
        w.set_velocity(1, Vec2::new(3.0, 4.0), 2.0);
        // Disc of radius 0.5, density 1: m = π/4, I = m r²/2 = π/32; the static ground counts
        // nothing. 1e-6 relative: f32 mass and inertia summed in f64.
        let m = std::f64::consts::PI / 4.0;
        let expected = 0.5 * m * 25.0 + 0.5 * (m * 0.125) * 4.0;
        let e = w.kinetic_energy();
        assert!((e / expected - 1.0).abs() < 1e-6, "{e} vs {expected}");
    }

    #[test]
    fn is_finite_sees_one_non_finite_velocity() {
        // set_velocity refuses non-finite input, so the state is written directly.
        let mut w = ball_on_ground();
        assert!(w.is_finite());
        w.states[1].v.x = f32::NAN;
        assert!(!w.is_finite());
        w.states[1].v.x = 0.0;
        w.states[1].w = f32::INFINITY;
        assert!(!w.is_finite());
        w.states[1].w = 0.0;
        w.sims[1].xf.p.y = f32::NEG_INFINITY;
        assert!(!w.is_finite());
    }

    /// One ball in the air, alone: nothing it touches can carry a bad number back to it.
    fn lone_ball() -> World {
        let mut w = World::new(StepSettings::default());
        w.add_body(&BodyDef::new(ShapeDef::Circle { radius: 0.5 }).at(0.0, 10.0))
            .unwrap();
        w
    }

    #[test]
    fn the_guard_counts_every_body_it_stops_and_snapshots_keep_the_count() {
        let mut w = lone_ball();
        for _ in 0..3 {
            w.step(1.0 / 60.0, 4);
        }
        assert_eq!(w.non_finite_bodies(), 0);
        // set_velocity refuses non-finite input, so the state is written directly: what a
        // broken upstream (a bad solve, a bad mass) would leave.
        w.states[0].v = Vec2::new(f32::NAN, 1.0);
        let before = w.body(0).position;
        w.step(1.0 / 60.0, 4);
        // The guard hid it: the state is finite again, the body kept its last finite pose.
        assert!(w.is_finite());
        assert_eq!(w.body(0).position, before);
        assert_eq!(w.profile().non_finite, 1);
        assert_eq!(w.non_finite_bodies(), 1);
        // Later healthy steps forget it in the profile but not in the total.
        for _ in 0..10 {
            w.step(1.0 / 60.0, 4);
        }
        assert_eq!(w.profile().non_finite, 0);
        assert_eq!(w.non_finite_bodies(), 1);
        // Through JSON and back, the count survives, and keeps counting from there.
        let text = serde_json::to_string(&w.snapshot()).unwrap();
        let mut restored = World::from_snapshot(serde_json::from_str(&text).unwrap()).unwrap();
        assert_eq!(restored.non_finite_bodies(), 1);
        restored.states[0].w = f32::NAN;
        restored.step(1.0 / 60.0, 4);
        assert!(restored.is_finite());
        assert_eq!(restored.non_finite_bodies(), 2);
    }

    #[test]
    fn a_snapshot_without_the_count_loads_as_zero() {
        let mut value = serde_json::to_value(lone_ball().snapshot()).unwrap();
        let fields = value.as_object_mut().unwrap();
        assert!(fields.remove("non_finite_bodies").is_some());
        let snap: WorldSnapshot = serde_json::from_value(value).unwrap();
        assert_eq!(World::from_snapshot(snap).unwrap().non_finite_bodies(), 0);
    }

    #[test]
    fn step_refuses_a_subnormal_or_non_positive_dt() {
        let mut w = lone_ball();
        let hash = w.state_hash();
        let tiny = f32::MIN_POSITIVE / 4.0;
        assert!(tiny > 0.0 && !tiny.is_normal());
        // A subnormal dt, a normal dt whose substep is subnormal, zero, negative, NaN,
        // infinity, and no substeps: none steps.
        for (dt, substeps) in [
            (tiny, 1),
            (f32::MIN_POSITIVE, 4),
            (0.0, 4),
            (-1.0 / 60.0, 4),
            (f32::NAN, 4),
            (f32::INFINITY, 4),
            (1.0 / 60.0, 0),
        ] {
            assert!(!World::steppable(dt, substeps), "{dt} {substeps}");
            w.step(dt, substeps);
            assert_eq!(w.step_count(), 0, "{dt} {substeps}");
            assert_eq!(w.state_hash(), hash, "{dt} {substeps}");
        }
        // The smallest dt it takes runs and stays finite.
        assert!(World::steppable(f32::MIN_POSITIVE, 1));
        w.step(f32::MIN_POSITIVE, 1);
        assert_eq!(w.step_count(), 1);
        assert!(w.is_finite());
        assert_eq!(w.non_finite_bodies(), 0);
    }

    #[test]
    fn step_settings_validate_refuses_each_bad_knob() {
        assert_eq!(StepSettings::default().validate(), Ok(()));
        let refused = |change: fn(&mut StepSettings), field: &str, words: &[&str]| {
            let mut s = StepSettings::default();
            change(&mut s);
            let e = s.validate().expect_err(field);
            assert_eq!(e.field, field);
            let text = e.to_string();
            assert!(text.contains(&format!("`{field}`")), "{text}");
            for w in words {
                assert!(text.contains(w), "{text} lacks {w}");
            }
        };
        refused(
            |s| s.relax_iterations = 0,
            "relax_iterations",
            &["friction"],
        );
        refused(
            |s| s.restitution_iterations = 0,
            "restitution_iterations",
            &["1 or more"],
        );
        refused(|s| s.contact_hertz = -1.0, "contact_hertz", &["-1", ">= 0"]);
        refused(|s| s.contact_hertz = f32::NAN, "contact_hertz", &["NaN"]);
        refused(
            |s| s.contact_damping_ratio = -0.5,
            "contact_damping_ratio",
            &["-0.5"],
        );
        refused(
            |s| s.contact_damping_ratio = f32::INFINITY,
            "contact_damping_ratio",
            &["inf"],
        );
        refused(|s| s.max_push_speed = -3.0, "max_push_speed", &["-3"]);
        refused(|s| s.max_push_speed = f32::NAN, "max_push_speed", &["NaN"]);
        refused(
            |s| s.restitution_threshold = -1.0,
            "restitution_threshold",
            &["-1"],
        );
        refused(
            |s| s.restitution_threshold = f32::INFINITY,
            "restitution_threshold",
            &["inf"],
        );
        refused(|s| s.max_linear_speed = -1.0, "max_linear_speed", &["> 0"]);
        refused(|s| s.max_linear_speed = 0.0, "max_linear_speed", &["> 0"]);
        refused(
            |s| s.max_linear_speed = f32::INFINITY,
            "max_linear_speed",
            &["inf"],
        );
        refused(|s| s.gravity.y = f32::NAN, "gravity", &["finite"]);
        // Zero is a usable value where it means "off": rigid contacts, no damping, no push-out,
        // every approach bounces.
        let zeros = StepSettings {
            contact_hertz: 0.0,
            contact_damping_ratio: 0.0,
            max_push_speed: 0.0,
            restitution_threshold: 0.0,
            ..StepSettings::default()
        };
        assert_eq!(zeros.validate(), Ok(()));
    }

    #[test]
    fn a_snapshot_with_bad_settings_is_refused() {
        let mut snap = ball_on_ground().snapshot();
        snap.settings.relax_iterations = 0;
        let e = World::from_snapshot(snap).err().expect("refused");
        assert!(e.to_string().contains("relax_iterations"), "{e}");
    }

    #[test]
    fn a_body_whose_mass_or_inertia_f32_cannot_invert_is_refused() {
        let mut w = ball_on_ground();
        let circle = |r: f32| BodyDef::new(ShapeDef::Circle { radius: r });
        // Radius 1e-20 m: mass π·1e-40 kg is subnormal, its inverse infinite.
        let e = w.add_body(&circle(1e-20)).unwrap_err().to_string();
        for word in [
            "body 2",
            "`density`",
            "mass",
            "raise the density",
            "enlarge",
        ] {
            assert!(e.contains(word), "{e} lacks {word}");
        }
        // A subnormal density: the same.
        let e = w
            .add_body(&circle(1.0).density(1e-40))
            .unwrap_err()
            .to_string();
        assert!(e.contains("`density`") && e.contains("mass"), "{e}");
        // A mass too large for f32.
        let e = w
            .add_body(&circle(1000.0).density(1e35))
            .unwrap_err()
            .to_string();
        assert!(e.contains("lower the density"), "{e}");
        // Radius 1e-10 m: the mass (3e-20 kg) is fine, the inertia (1.6e-40) underflows.
        let e = w.add_body(&circle(1e-10)).unwrap_err().to_string();
        for word in ["body 2", "`shape`", "rotational inertia", "fixed_rotation"] {
            assert!(e.contains(word), "{e} lacks {word}");
        }
        // A body that cannot rotate needs no inverse inertia, and one refused body leaves no
        // trace: ids continue from 2.
        assert_eq!(w.add_body(&circle(1e-10).fixed_rotation(true)), Ok(2));
        // Static bodies have no mass to invert.
        assert!(w.add_body(&circle(1e-20).kind(BodyKind::Static)).is_ok());
        // From a scene, the index is the body's place in it.
        let mut scene = SceneDef::new("tiny");
        scene.push(circle(1.0));
        scene.push(circle(1e-20));
        let e = World::from_scene(&scene, &Limits::default())
            .err()
            .expect("refused")
            .to_string();
        assert!(e.starts_with("body 1: field `density`"), "{e}");
    }

    #[test]
    fn impulse_changes_velocity_by_inverse_mass() {
        let mut w = ball_on_ground();
        let m = w.mass(1);
        // Disc of radius 0.5 at density 1: m = π/4.
        assert!((m - std::f32::consts::FRAC_PI_4).abs() < 1e-6);
        w.apply_linear_impulse(1, Vec2::new(2.0, 0.0), Vec2::new(0.0, 1.5));
        let b = w.body(1);
        assert!((b.linear_velocity.x - 2.0 / m).abs() < 1e-5);
        // Off-centre by +0.5 in y: torque r × J = 0.5·0 − 0.5·2 = −1; w = −1 / (m r²/2).
        assert!((b.angular_velocity + 1.0 / (0.5 * m * 0.25)).abs() < 1e-4);
        // Static bodies ignore it.
        w.apply_linear_impulse(0, Vec2::new(5.0, 0.0), Vec2::ZERO);
        assert_eq!(w.body(0).linear_velocity, Vec2::ZERO);
    }

    #[test]
    fn body_at_picks_the_shape_under_the_point() {
        let w = ball_on_ground();
        assert_eq!(w.body_at(Vec2::new(0.1, 1.2)), Some(1));
        assert_eq!(w.body_at(Vec2::new(4.0, 0.0)), Some(0));
        assert_eq!(w.body_at(Vec2::new(0.0, 3.0)), None);
    }

    #[test]
    fn thread_count_changes_between_steps_keep_the_result() {
        // A 30-row pyramid: 465 boxes, about 1,400 touching contacts, well above the 256 below
        // which one worker solves alone, so every step here really is solved by the workers
        // asked for (1 to 3, beyond the cores where there are fewer; checked each step).
        let pyramid = || {
            let mut w = World::new(StepSettings::default());
            w.set_workers_beyond_cores(true);
            // A 465-body pyramid is inline by default: split it anyway.
            w.set_wide_thresholds(WideThresholds::ALWAYS);
            let ground = BodyDef::new(ShapeDef::Box {
                half_extents: [40.0, 0.5],
            });
            w.add_body(&ground.kind(BodyKind::Static)).unwrap();
            for row in 0..30 {
                for col in 0..(30 - row) {
                    let x = col as f32 + row as f32 * 0.5 - 15.0;
                    let unit = ShapeDef::Box {
                        half_extents: [0.5, 0.5],
                    };
                    w.add_body(&BodyDef::new(unit).at(x, 1.0 + row as f32))
                        .unwrap();
                }
            }
            w
        };
        let run = |switch: bool| {
            let mut w = pyramid();
            w.set_thread_count(1);
            for i in 0..30 {
                let workers = if switch { 1 + i % 3 } else { 1 };
                w.set_thread_count(workers);
                w.step(1.0 / 60.0, 4);
                assert!(w.profile().touching > 256);
                assert_eq!(w.profile().solver_workers, workers, "step {i}");
            }
            w.state_hash()
        };
        assert_eq!(run(false), run(true));
    }

    /// An 8-row pyramid of boxes with 20 bouncy circles falling on it.
    fn pyramid_in_rain(settings: StepSettings) -> World {
        let mut w = World::new(settings);
        w.add_body(
            &BodyDef::new(ShapeDef::Box {
                half_extents: [20.0, 0.5],
            })
            .kind(BodyKind::Static),
        )
        .unwrap();
        for row in 0..8 {
            for col in 0..(8 - row) {
                let x = col as f32 * 1.0 + row as f32 * 0.5 - 4.0;
                w.add_body(
                    &BodyDef::new(ShapeDef::Box {
                        half_extents: [0.5, 0.5],
                    })
                    .at(x, 1.0 + row as f32),
                )
                .unwrap();
            }
        }
        for i in 0..20 {
            let shape = ShapeDef::Circle { radius: 0.25 };
            let body = BodyDef::new(shape)
                .at(i as f32 * 0.4 - 4.0, 12.0)
                .restitution(0.3);
            w.add_body(&body).unwrap();
        }
        w
    }

    #[test]
    fn a_kept_colouring_is_the_one_a_fresh_colouring_gives() {
        // One world keeps last step's colouring whenever the touching pairs repeat; the other
        // colours from scratch every step. The colouring is a function of those pairs, so
        // both must agree exactly, colour for colour and bit for bit.
        let mut kept = pyramid_in_rain(StepSettings::default());
        let mut fresh = pyramid_in_rain(StepSettings::default());
        let mut reused = 0;
        for _ in 0..240 {
            fresh.solver.forget_coloring();
            kept.step(1.0 / 60.0, 4);
            fresh.step(1.0 / 60.0, 4);
            assert!(fresh.solver.recolored);
            reused += usize::from(!kept.solver.recolored);
            assert_eq!(kept.contact_colors(), fresh.contact_colors());
            assert_eq!(kept.state_hash(), fresh.state_hash());
        }
        // The rain bounces, rolls off and settles: most of the run has touching pairs that
        // repeat, so the kept path was taken (its count is the test's reason to exist).
        assert!(reused > 60, "colouring kept on {reused} of 240 steps");
    }

    #[test]
    fn simd_and_scalar_solvers_agree_bit_for_bit() {
        // Both paths do the same per-lane operations in the same order, with no fused
        // multiply-add, so the whole state must match exactly, not within a tolerance.
        let run = |simd: bool, avx: bool| {
            let mut w = pyramid_in_rain(StepSettings::default());
            w.settings_mut().simd = simd;
            w.solver.use_avx = avx;
            for _ in 0..120 {
                w.step(1.0 / 60.0, 4);
            }
            assert!(w.profile().touching > 50);
            w.state_hash()
        };
        // The 8-lane kernels in AVX2 registers (where the CPU has AVX2; elsewhere both runs
        // take the portable path) against the portable f32x8 kernels, and against scalar.
        let portable = run(true, false);
        assert_eq!(run(true, true), portable);
        assert_eq!(run(false, false), portable);
    }

    #[test]
    fn a_restored_snapshot_continues_bit_for_bit() {
        let mut w = ball_on_ground();
        for i in 0..12 {
            let body = BodyDef::new(ShapeDef::Box {
                half_extents: [0.3, 0.2],
            })
            .at(i as f32 * 0.5 - 3.0, 2.0 + i as f32 * 0.3)
            .angle(0.1 * i as f32);
            w.add_body(&body).unwrap();
        }
        for _ in 0..45 {
            w.step(1.0 / 60.0, 4);
        }
        // Through JSON: f32 values are written shortest-round-trip, so they read back exactly.
        let text = serde_json::to_string(&w.snapshot()).unwrap();
        let mut restored = World::from_snapshot(serde_json::from_str(&text).unwrap()).unwrap();
        restored.set_thread_count(1);
        for _ in 0..90 {
            w.step(1.0 / 60.0, 4);
            restored.step(1.0 / 60.0, 4);
        }
        assert!(w.profile().touching > 5);
        assert_eq!(w.state_hash(), restored.state_hash());
        assert_eq!(w.step_count(), restored.step_count());
    }

    #[test]
    fn a_corrupt_snapshot_is_refused() {
        let mut snap = ball_on_ground().snapshot();
        snap.states.pop();
        assert!(World::from_snapshot(snap).is_err());
    }

    #[test]
    fn contact_colors_cover_the_touching_contacts() {
        let mut w = ball_on_ground();
        for _ in 0..30 {
            w.step(1.0 / 60.0, 4);
        }
        let colors = w.contact_colors();
        assert_eq!(colors.len(), w.profile().touching);
        // A dynamic body against a static one goes to the top colours (Box2D's rule).
        assert!(
            colors.iter().all(|&(_, c)| (1..23).contains(&c)),
            "{colors:?}"
        );
    }
}
