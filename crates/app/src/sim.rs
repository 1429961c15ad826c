//! A running simulation as the viewer sees it: the world, the scene it came from, the
//! fixed-step clock that turns frame times into whole physics steps, the mouse spring, and the
//! recent per-stage profile.
//!
//! The physics always advances by the scene's `dt`, never by the frame's time: the clock
//! accumulates frame time and hands out whole steps, so a scene gives the same result at 30
//! and at 144 frames per second (the test below proves it through [`World::state_hash`]).
//!
//! Before every step the built-in scene's script runs (the `junkyard` moves its pusher with
//! it; [`tumble_scene::builtin::script`]). Bodies the user drops or removes between steps
//! ([`Edit`]) are recorded with the step they came before, so a replay makes them again at
//! the same point and still ends bit for bit where the run was.

use std::collections::VecDeque;
use std::sync::Arc;

use anyhow::{Context, Result};
use glam::Vec2;
use tumble_physics::{
    BodyDef, BodyId, BodyKind, Event, EventCursor, JointId, JointKind, Rot, SceneDef, ShapeDef,
    StepSettings, World, WorldSnapshot,
};
use tumble_scene::LoadLimits;
use tumble_scene::builtin::Script;
use tumble_scene::sample::{Controller, KeyScript, Keys};

/// The longest frame the clock accepts (s): a frame that took longer (a window drag, a
/// debugger) counts as this long, so the simulation does not leap ahead.
pub const MAX_FRAME_SECONDS: f64 = 0.25;

/// Turns frame times into fixed steps.
#[derive(Clone, Debug)]
pub struct FixedStep {
    dt: f64,
    accumulated: f64,
    /// Most steps one frame may take; beyond it the backlog is dropped and the simulation runs
    /// slower than real time instead of spiralling (each frame taking longer than the last).
    pub max_steps_per_frame: u32,
}

impl FixedStep {
    /// A clock for steps of `dt` seconds, allowing a tenth of a second of steps per frame.
    pub fn new(dt: f32) -> Self {
        let dt = f64::from(dt);
        Self {
            dt,
            accumulated: 0.0,
            max_steps_per_frame: ((0.1 / dt).ceil() as u32).max(1),
        }
    }

    /// Seconds per step.
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// Adds one frame's duration and returns how many steps to take now.
    pub fn advance(&mut self, frame_seconds: f64) -> u32 {
        if frame_seconds.is_finite() && frame_seconds > 0.0 {
            self.accumulated += frame_seconds.min(MAX_FRAME_SECONDS);
        }
        // A frame time that is a whole number of steps up to rounding (1/30 s is two steps of
        // 1/60 s) must give exactly that many steps, hence the tolerance.
        let tolerance = self.dt * 1e-6;
        let mut steps = 0;
        while self.accumulated + tolerance >= self.dt && steps < self.max_steps_per_frame {
            self.accumulated -= self.dt;
            steps += 1;
        }
        if steps == self.max_steps_per_frame {
            // Behind real time: drop the time still owed rather than replay it.
            self.accumulated = 0.0;
        }
        self.accumulated = self.accumulated.max(0.0);
        steps
    }

    /// Forgets accumulated time (after a restart or a pause).
    pub fn reset(&mut self) {
        self.accumulated = 0.0;
    }
}

/// The mouse spring: a body held at a point of its own, pulled toward the pointer by the
/// engine's mouse joint (a soft constraint solved in the substeps with everything else).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Drag {
    /// The body held.
    pub body: BodyId,
    /// The held point in the body's frame.
    pub local_anchor: Vec2,
    /// Where the pointer is, in the world.
    pub target: Vec2,
}

/// Stiffness of the mouse spring (Hz) and its damping ratio: soft enough to feel like a
/// spring, damped enough not to swing.
pub const DRAG_HERTZ: f32 = 5.0;
/// Damping ratio of the mouse spring.
pub const DRAG_DAMPING: f32 = 0.7;
/// The spring's force is capped at this many times the body's weight under 10 m/s².
pub const DRAG_MAX_FORCE_PER_KG: f32 = 1000.0;

impl Drag {
    /// The held point, in the world, for a body at `position` turned by `rotation`.
    pub fn anchor(&self, position: Vec2, rotation: Rot) -> Vec2 {
        position + rotation.apply(self.local_anchor)
    }
}

/// The world's mouse joint, if it has one (a restored snapshot may carry the drag's).
fn find_mouse(world: &World) -> Option<JointId> {
    world.joint_ids().find(|&id| {
        world
            .joint(id)
            .is_ok_and(|j| matches!(j.kind, JointKind::Mouse(_)))
    })
}

/// The world's mouse joint and the drag it serves: the held body and point, or `None` for a
/// joint found in a restored snapshot, which serves the next drag of its body (a replay
/// starting mid-drag goes on with the joint the run had, impulses and all).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Mouse {
    joint: JointId,
    serves: Option<(BodyId, Vec2)>,
}

/// Makes the world's mouse joint follow `drag`: moves its target, or replaces it when the
/// held body or point changed, or removes it when nothing is held. Returns the joint now.
fn sync_mouse(world: &mut World, mouse: Option<Mouse>, drag: Option<Drag>) -> Option<Mouse> {
    let live = mouse.filter(|m| world.joint(m.joint).is_ok());
    if let (Some(m), Some(d)) = (live, drag) {
        let same = match m.serves {
            Some(held) => held == (d.body, d.local_anchor),
            None => world.joint_bodies(m.joint).is_ok_and(|[_, b]| b == d.body),
        };
        if same {
            world.set_mouse_target(m.joint, d.target).ok()?;
            return Some(Mouse {
                joint: m.joint,
                serves: Some((d.body, d.local_anchor)),
            });
        }
    }
    if let Some(m) = live {
        let _ = world.destroy_joint(m.joint);
    }
    let d = drag?;
    let (b, mass) = (world.body(d.body).ok()?, world.mass(d.body).ok()?);
    if b.kind != BodyKind::Dynamic || mass <= 0.0 {
        return None;
    }
    let body = d.body;
    let anchor = d.anchor(b.position, b.rotation);
    let max_force = DRAG_MAX_FORCE_PER_KG * mass;
    let joint = world
        .create_mouse_joint(body, anchor, DRAG_HERTZ, DRAG_DAMPING, max_force)
        .ok()?;
    world.set_mouse_target(joint, d.target).ok()?;
    Some(Mouse {
        joint,
        serves: Some((d.body, d.local_anchor)),
    })
}

/// One step's timings, for the profile plot.
#[derive(Clone, Copy, Debug)]
pub struct ProfileSample {
    /// Simulated time at the end of the step (s).
    pub time: f64,
    /// The whole step (ms).
    pub step_ms: f64,
    /// Each stage (ms), in pipeline order.
    pub stages: [(&'static str, f64); 7],
}

/// Seconds of the past the replay can go back to.
pub const REPLAY_SECONDS: f64 = 10.0;
/// Most memory the replay's snapshots may hold; a world too big for [`REPLAY_SECONDS`] of
/// one-second snapshots within it keeps fewer seconds (22,000 bodies: about 13 MB each).
pub const REPLAY_BYTES: usize = 192 << 20;

/// What a step was taken with, beyond the world itself: what a replay must apply again to
/// reproduce it bit for bit. (The user's edits before the step are kept beside, in
/// [`Recording`]'s edit log, as they are rare.)
#[derive(Clone, Copy, Debug, PartialEq)]
struct StepInput {
    drag: Option<Drag>,
    /// The keys a sample read (none for a scene without a controller).
    keys: Keys,
    substeps: u32,
    settings: StepSettings,
}

/// Side of the box the B key drops (m).
pub const DROP_BOX_SIZE: f32 = 0.5;
/// Radius of the ball the N key drops (m).
pub const DROP_BALL_RADIUS: f32 = 0.25;

/// A change the user makes to the world between steps, through the world's API. It is
/// recorded with the step it came before and made again there by a replay.
#[derive(Clone, Debug, PartialEq)]
pub enum Edit {
    /// Create this body (it takes the lowest free slot, as it did live).
    Create(Box<BodyDef>),
    /// Destroy this body.
    Destroy(BodyId),
}

impl Edit {
    /// A dynamic box of [`DROP_BOX_SIZE`] at `at`, default material.
    pub fn drop_box(at: Vec2) -> Edit {
        let h = DROP_BOX_SIZE / 2.0;
        Edit::Create(Box::new(
            BodyDef::new(ShapeDef::Box {
                half_extents: [h, h],
                radius: 0.0,
            })
            .at(at.x, at.y),
        ))
    }

    /// A dynamic ball of radius [`DROP_BALL_RADIUS`] at `at`, default material.
    pub fn drop_ball(at: Vec2) -> Edit {
        Edit::Create(Box::new(
            BodyDef::new(ShapeDef::Circle {
                radius: DROP_BALL_RADIUS,
            })
            .at(at.x, at.y),
        ))
    }

    /// Makes the change; the created body's id, or why the world refused.
    fn apply(&self, world: &mut World) -> Result<Option<BodyId>> {
        match self {
            Edit::Create(def) => world
                .create_body(def)
                .map(Some)
                .context("cannot create the body"),
            Edit::Destroy(id) => world
                .destroy_body(*id)
                .map(|()| None)
                .context("cannot remove the body"),
        }
    }
}

/// The last seconds of the run: a snapshot of the world every second and the input of every
/// step since the oldest one, with the user's edits. The simulation is deterministic, so
/// restoring a snapshot and stepping with the recorded inputs (making the recorded edits
/// before their steps) gives the recorded states again, bit for bit.
#[derive(Default)]
pub struct Recording {
    /// `(steps since the world was built, the world then)`, oldest first. A snapshot of
    /// step `s` is taken before the edits made before step `s`.
    snapshots: VecDeque<(u64, WorldSnapshot, Option<Controller>)>,
    /// The input of each step from the oldest snapshot on, in order.
    inputs: VecDeque<StepInput>,
    /// `(the step it came before, the edit)`, from the oldest snapshot on, in order made.
    edits: VecDeque<(u64, Edit)>,
    bytes: usize,
}

impl Recording {
    /// Seconds of the past it holds, at `dt` per step.
    pub fn seconds(&self, dt: f32) -> f64 {
        self.inputs.len() as f64 * f64::from(dt)
    }

    fn clear(&mut self) {
        *self = Recording::default();
    }

    /// Called before step `step` (counted from the build) is taken.
    fn record(
        &mut self,
        step: u64,
        world: &World,
        controller: Option<&Controller>,
        input: StepInput,
        steps_per_snapshot: u64,
    ) {
        self.snapshot_if_due(step, world, controller, steps_per_snapshot);
        self.inputs.push_back(input);
    }

    /// Called after an edit was made before step `step` (and after
    /// [`Recording::snapshot_if_due`] was called before it: the snapshot of that step, if
    /// one is due, must show the world without it).
    fn record_edit(&mut self, step: u64, edit: Edit) {
        self.edits.push_back((step, edit));
    }

    /// The edits recorded before step `step`, in the order they were made.
    fn edits_at(&self, step: u64) -> Vec<Edit> {
        self.edits
            .iter()
            .filter(|(s, _)| *s == step)
            .map(|(_, e)| e.clone())
            .collect()
    }

    /// Takes the snapshot of step `step` if one is due and not taken yet; drops what is
    /// older than the replay keeps.
    fn snapshot_if_due(
        &mut self,
        step: u64,
        world: &World,
        controller: Option<&Controller>,
        steps_per_snapshot: u64,
    ) {
        let due = step.is_multiple_of(steps_per_snapshot) || self.snapshots.is_empty();
        if due && self.snapshots.back().is_none_or(|&(s, ..)| s != step) {
            let snapshot = world.snapshot();
            self.bytes += snapshot.approx_bytes();
            self.snapshots
                .push_back((step, snapshot, controller.cloned()));
            // One snapshot a second: REPLAY_SECONDS of them, plus the one the oldest second
            // starts from.
            let keep = REPLAY_SECONDS as usize + 1;
            while self.snapshots.len() > keep
                || (self.bytes > REPLAY_BYTES && self.snapshots.len() > 2)
            {
                let (_, old, _) = self.snapshots.pop_front().expect("more than two");
                self.bytes -= old.approx_bytes();
                let first = self.snapshots.front().expect("one left").0;
                let drop = self.inputs.len() - (step - first) as usize;
                self.inputs.drain(..drop);
                while self.edits.front().is_some_and(|&(s, _)| s < first) {
                    self.edits.pop_front();
                }
            }
        }
    }

    /// Forgets everything from step `step` on (the replay was stopped there: the future
    /// recorded beyond it will not happen now).
    fn truncate_at(&mut self, step: u64) {
        while self.snapshots.back().is_some_and(|&(s, ..)| s > step) {
            let (_, old, _) = self.snapshots.pop_back().expect("checked");
            self.bytes -= old.approx_bytes();
        }
        let first = self.snapshots.front().map_or(step, |&(s, ..)| s);
        self.inputs.truncate(step.saturating_sub(first) as usize);
        // The edits before step `step` were not made again yet (a replayed step makes them
        // first): they belong to the forgotten future too.
        while self.edits.back().is_some_and(|&(s, _)| s >= step) {
            self.edits.pop_back();
        }
    }
}

/// A replay in progress: the world was restored to an older step and steps forward with the
/// recorded inputs until it is back where it was when the replay started.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Replay {
    /// The step (since the build) the replay started from, and where it ends.
    pub until: u64,
    /// The step it went back to.
    pub from: u64,
}

/// A saved world with what it needs to go on exactly: its scene (for restart), its steps and
/// substeps. Written to files as JSON (f32 values shortest-round-trip, so they read back bit
/// for bit).
#[derive(Clone, serde::Serialize, serde::Deserialize)]
pub struct SavedWorld {
    /// Always [`SavedWorld::FORMAT`]: refuses other JSON files with a clear message.
    pub format: String,
    /// The scene the world was built from.
    pub scene: SceneDef,
    /// Steps since the world was built.
    pub steps: u64,
    /// Substeps per step in use.
    pub substeps: u32,
    /// The world.
    pub world: WorldSnapshot,
    /// A played sample's state beside the world (its character, its score).
    #[serde(default)]
    pub controller: Option<Controller>,
}

impl SavedWorld {
    /// The `format` tag of a snapshot file.
    pub const FORMAT: &'static str = "tumble-snapshot-1";

    /// Reads a snapshot file written by [`SavedWorld::to_json`].
    pub fn from_json(text: &str, file: &str) -> Result<SavedWorld> {
        let saved: SavedWorld = serde_json::from_str(text)
            .with_context(|| format!("{file}: not a tumble snapshot file"))?;
        if saved.format != Self::FORMAT {
            anyhow::bail!(
                "{file}: snapshot format `{}`; allowed: `{}` (written by this viewer's Save snapshot)",
                saved.format,
                Self::FORMAT
            );
        }
        Ok(saved)
    }

    /// The file's text.
    pub fn to_json(&self) -> String {
        serde_json::to_string(self).expect("a snapshot is plain data")
    }
}

/// The world with everything the viewer drives it with.
pub struct Sim {
    /// The scene as loaded: restart and the thread sweep start from it.
    pub scene: Arc<SceneDef>,
    /// The world being simulated.
    pub world: World,
    /// Frame time to fixed steps.
    pub clock: FixedStep,
    /// Solver substeps per step (the scene's, until the user changes it).
    pub substeps: u32,
    /// Steps advance with time; when false only [`Sim::single_step`] moves the world.
    pub running: bool,
    /// The body held by the mouse, if any.
    pub drag: Option<Drag>,
    /// The world's mouse joint for `drag` (made and moved before each step).
    mouse: Option<Mouse>,
    /// Steps since the world was (re)built.
    pub steps: u64,
    /// Steps over the whole run, restarts included (for `--stats`).
    pub total_steps: u64,
    /// Sum of every step's wall time (ms) over the whole run.
    pub total_step_ms: f64,
    /// The last seconds of per-stage timings.
    pub history: VecDeque<ProfileSample>,
    /// The last seconds of the run, for the replay.
    pub recording: Recording,
    /// The replay in progress, if any.
    pub replay: Option<Replay>,
    /// The scene's error metric, measured after each frame's steps.
    pub metrics: crate::metrics::Metrics,
    /// The built-in scene's per-step script, if it is a built-in that has one.
    script: Option<Script>,
    /// The last events of the run (the event log panel).
    pub events: EventLog,
    /// The ray tool's ray (from, to), drawn with its hits.
    pub ray: Option<(Vec2, Vec2)>,
    /// A played sample's controller (the platformer's character), if the scene has one.
    pub controller: Option<Controller>,
    /// The keys the person holds now (what the controller reads at the next step).
    pub keys: Keys,
    /// Keys scripted by step (`--keys`, the page's `keys=`): they replace the live keys.
    pub key_script: Option<KeyScript>,
    /// Stop stepping at this many steps since the scene started (`--steps`).
    pub step_limit: Option<u64>,
}

/// The last [`EventLog::CAPACITY`] events of a run, each with the step it came in (counted
/// from 1), and how many of each kind there were since the scene started.
#[derive(Clone, Debug, Default)]
pub struct EventLog {
    /// Oldest first.
    pub entries: VecDeque<(u64, Event)>,
    /// Contact begins, contact ends, hits, sensor begins, sensor ends, joint thresholds.
    pub counts: [u64; 6],
    /// What of the world's events is logged.
    cursor: EventCursor,
}

impl EventLog {
    /// Events kept for the panel.
    pub const CAPACITY: usize = 200;

    /// The kind's place in `counts`.
    pub fn kind(event: &Event) -> usize {
        match event {
            Event::ContactBegin { .. } => 0,
            Event::ContactEnd { .. } => 1,
            Event::Hit { .. } => 2,
            Event::SensorBegin { .. } => 3,
            Event::SensorEnd { .. } => 4,
            Event::JointThreshold { .. } => 5,
        }
    }

    /// Logs what `world` reported since the last call, as step `step`'s.
    fn record(&mut self, world: &World, step: u64) {
        for event in self.cursor.take(world) {
            self.counts[Self::kind(event)] += 1;
            if self.entries.len() == Self::CAPACITY {
                self.entries.pop_front();
            }
            self.entries.push_back((step, *event));
        }
    }
}

/// Seconds of simulated time the profile history keeps.
pub const HISTORY_SECONDS: f64 = 5.0;

impl Sim {
    /// Builds the world of `scene` with `threads` workers (0 = all cores).
    pub fn new(scene: Arc<SceneDef>, threads: usize) -> Result<Self> {
        let world = build_world(&scene)?;
        let mut sim = Self {
            clock: FixedStep::new(scene.dt),
            substeps: scene.substeps,
            scene,
            world,
            running: true,
            drag: None,
            mouse: None,
            steps: 0,
            total_steps: 0,
            total_step_ms: 0.0,
            history: VecDeque::new(),
            recording: Recording::default(),
            replay: None,
            metrics: crate::metrics::Metrics::default(),
            script: None,
            events: EventLog::default(),
            ray: None,
            controller: None,
            keys: Keys::NONE,
            key_script: None,
            step_limit: None,
        };
        sim.script = tumble_scene::builtin::script_for(&sim.scene);
        let controller = Controller::for_scene(&sim.scene);
        sim.set_controller(controller);
        sim.metrics = crate::metrics::Metrics::new(&sim.scene, &sim.world);
        sim.set_threads(threads);
        Ok(sim)
    }

    /// Loads a scene by file path or built-in name and builds its world.
    pub fn load(source: &str, threads: usize) -> Result<Self> {
        let scene = tumble_scene::load(source, &LoadLimits::default())?;
        Self::new(Arc::new(scene), threads)
    }

    /// Sets the step's worker threads (0 = all cores); takes effect from the next step.
    pub fn set_threads(&mut self, threads: usize) {
        let threads = if threads == 0 {
            tumble_physics::default_thread_count()
        } else {
            threads
        };
        self.world.set_thread_count(threads);
    }

    /// Seconds of simulated time since the world was (re)built.
    pub fn time(&self) -> f64 {
        self.steps as f64 * f64::from(self.scene.dt)
    }

    /// Rebuilds the world from the scene, keeping the thread count and the step settings the
    /// user chose.
    pub fn restart(&mut self) {
        let threads = self.world.thread_count();
        let settings: StepSettings = *self.world.settings();
        // The scene was built once already, so this cannot fail.
        if let Ok(world) = build_world(&self.scene) {
            self.world = world;
            self.mouse = None;
        }
        self.world.set_thread_count(threads);
        *self.world.settings_mut() = settings;
        self.clock.reset();
        self.drag = None;
        self.steps = 0;
        self.history.clear();
        self.recording.clear();
        self.replay = None;
        self.events = EventLog::default();
        self.metrics = crate::metrics::Metrics::new(&self.scene, &self.world);
        self.keys = Keys::NONE;
        let controller = Controller::for_scene(&self.scene);
        self.set_controller(controller);
    }

    /// Puts in a sample's controller (or none) and sets the world's hooks it needs.
    fn set_controller(&mut self, controller: Option<Controller>) {
        if let Some(c) = &controller {
            c.install(&mut self.world);
        }
        self.controller = controller;
    }

    /// Goes back to the oldest second the recording holds (up to [`REPLAY_SECONDS`]) and
    /// plays the steps since again, with the inputs they had (mouse spring, substeps,
    /// settings), until the world is back where it is now. Returns false with nothing
    /// recorded yet.
    pub fn start_replay(&mut self) -> bool {
        let until = self.replay.map_or(self.steps, |r| r.until);
        let Some((from, snapshot, controller)) = self.recording.snapshots.front() else {
            return false;
        };
        let from = *from;
        let controller = controller.clone();
        if from >= until {
            return false;
        }
        // The snapshot was taken from this world, so it is consistent.
        let Ok(world) = World::from_snapshot(snapshot.clone()) else {
            return false;
        };
        self.install_world(world, from);
        self.set_controller(controller);
        self.replay = Some(Replay { until, from });
        true
    }

    /// Ends a replay where it is: the simulation goes on live from here, and the recorded
    /// future beyond this step is forgotten.
    pub fn stop_replay(&mut self) {
        if self.replay.take().is_some() {
            self.recording.truncate_at(self.steps);
        }
    }

    /// The world as it is, to save (see [`SavedWorld`]).
    pub fn save(&self) -> SavedWorld {
        SavedWorld {
            format: SavedWorld::FORMAT.to_string(),
            scene: (*self.scene).clone(),
            steps: self.steps,
            substeps: self.substeps,
            world: self.world.snapshot(),
            controller: self.controller.clone(),
        }
    }

    /// Puts a saved world back (its scene too, for restart), keeping the thread count. It
    /// then goes on exactly as the saved one would have. (Its bodies need not be its
    /// scene's: the user may have dropped and removed some.)
    pub fn restore(&mut self, saved: SavedWorld) -> Result<()> {
        // Everything that can fail comes first, so a bad file leaves the running world as it
        // was: the scene is validated by building its start (what the metrics measure from).
        let start = build_world(&saved.scene)?;
        let world = World::from_snapshot(saved.world)
            .with_context(|| format!("snapshot of `{}`", saved.scene.name))?;
        if *self.scene != saved.scene {
            self.clock = FixedStep::new(saved.scene.dt);
            self.scene = Arc::new(saved.scene);
            self.script = tumble_scene::builtin::script_for(&self.scene);
        }
        self.install_world(world, saved.steps);
        let controller = saved
            .controller
            .or_else(|| Controller::for_scene(&self.scene).filter(|_| saved.steps == 0));
        self.set_controller(controller);
        self.substeps = saved.substeps;
        self.history.clear();
        self.recording.clear();
        self.replay = None;
        self.metrics = crate::metrics::Metrics::new(&self.scene, &start);
        Ok(())
    }

    /// Swaps in a restored world at step `steps`, keeping the thread count.
    fn install_world(&mut self, world: World, steps: u64) {
        let threads = self.world.thread_count();
        self.world = world;
        self.mouse = find_mouse(&self.world).map(|joint| Mouse {
            joint,
            serves: None,
        });
        self.world.set_thread_count(threads);
        self.steps = steps;
        self.drag = None;
        self.clock.reset();
    }

    /// Advances by one frame's duration: as many fixed steps as the clock hands out (none
    /// while paused). Returns the steps taken.
    pub fn advance(&mut self, frame_seconds: f64) -> u32 {
        if !self.running {
            self.clock.reset();
            return 0;
        }
        let mut steps = self.clock.advance(frame_seconds);
        if let Some(limit) = self.step_limit {
            steps = steps.min(limit.saturating_sub(self.steps).min(u64::from(u32::MAX)) as u32);
        }
        for _ in 0..steps {
            self.step_once();
        }
        if steps > 0 {
            self.metrics.measure(&self.world);
        }
        steps
    }

    /// One step now, whether running or not.
    pub fn single_step(&mut self) {
        self.step_once();
        self.metrics.measure(&self.world);
    }

    /// Steps between two of the replay's snapshots: one a second.
    fn steps_per_snapshot(&self) -> u64 {
        (1.0 / f64::from(self.scene.dt)).round().max(1.0) as u64
    }

    /// Makes the edits recorded before step `step` again (a replay).
    fn replay_edits(&mut self, step: u64) {
        for edit in self.recording.edits_at(step) {
            // It succeeded live on this same world, so it succeeds again.
            let _ = edit.apply(&mut self.world);
        }
    }

    fn step_once(&mut self) {
        let dt = self.scene.dt;
        let mut replay_ends = false;
        let input = match self.replay {
            Some(replay) => {
                self.replay_edits(self.steps);
                let first = self.recording.snapshots.front().map_or(0, |&(s, ..)| s);
                let recorded = self.recording.inputs[(self.steps - first) as usize];
                if self.steps + 1 >= replay.until {
                    // This is the last replayed step: live from the next one on.
                    self.replay = None;
                    replay_ends = true;
                }
                *self.world.settings_mut() = recorded.settings;
                self.substeps = recorded.substeps;
                recorded
            }
            None => {
                // Live edits were made when asked (see [`Sim::edit`]); only recorded here.
                let keys = match &self.key_script {
                    Some(script) => script.keys_at(self.steps, self.keys),
                    None => self.keys,
                };
                self.keys = keys;
                let input = StepInput {
                    drag: self.drag,
                    keys,
                    substeps: self.substeps.max(1),
                    settings: *self.world.settings(),
                };
                let per_snapshot = self.steps_per_snapshot();
                self.recording.record(
                    self.steps,
                    &self.world,
                    self.controller.as_ref(),
                    input,
                    per_snapshot,
                );
                input
            }
        };
        if let Some(script) = self.script {
            script(self.steps, &mut self.world);
            self.events.record(&self.world, self.steps + 1);
        }
        self.mouse = sync_mouse(&mut self.world, self.mouse, input.drag);
        if let Some(c) = &mut self.controller {
            c.before_step(self.steps, input.keys, &mut self.world);
        }
        self.world.step(dt, input.substeps);
        if let Some(c) = &mut self.controller {
            c.after_step(self.steps, &mut self.world);
        }
        self.steps += 1;
        self.events.record(&self.world, self.steps);
        if replay_ends {
            // Edits made after the last recorded step, before the replay began: the world
            // was showing them then.
            self.replay_edits(self.steps);
        }
        self.total_steps += 1;
        let profile = self.world.profile();
        self.total_step_ms += profile.step_ms;
        let sample = ProfileSample {
            time: self.time(),
            step_ms: profile.step_ms,
            stages: profile.stages(),
        };
        self.history.push_back(sample);
        while self
            .history
            .front()
            .is_some_and(|s| sample.time - s.time > HISTORY_SECONDS)
        {
            self.history.pop_front();
        }
    }

    /// Mean wall time of one step over the run (ms), 0 before the first step.
    pub fn step_ms_mean(&self) -> f64 {
        if self.total_steps == 0 {
            0.0
        } else {
            self.total_step_ms / self.total_steps as f64
        }
    }

    /// Makes an edit now, between steps (a replay in progress stops first: the run goes on
    /// live from here) and records it for the replay. Returns the created body's id, if it
    /// made one, or why the world refused (nothing is recorded then).
    pub fn edit(&mut self, edit: Edit) -> Result<Option<BodyId>> {
        self.stop_replay();
        let per_snapshot = self.steps_per_snapshot();
        // The snapshot due at this step must not show the edit: taken first (a refused edit
        // changes nothing, so it is right then too).
        self.recording.snapshot_if_due(
            self.steps,
            &self.world,
            self.controller.as_ref(),
            per_snapshot,
        );
        let made = edit.apply(&mut self.world)?;
        if let Edit::Destroy(id) = &edit
            && self.drag.is_some_and(|d| d.body == *id)
        {
            self.drag = None;
        }
        self.recording.record_edit(self.steps, edit);
        Ok(made)
    }

    /// Drops a dynamic box of [`DROP_BOX_SIZE`] at `point` (the B key).
    pub fn drop_box(&mut self, point: Vec2) -> Result<BodyId> {
        self.edit(Edit::drop_box(point))
            .map(|id| id.expect("a created body"))
    }

    /// Drops a dynamic ball of radius [`DROP_BALL_RADIUS`] at `point` (the N key).
    pub fn drop_ball(&mut self, point: Vec2) -> Result<BodyId> {
        self.edit(Edit::drop_ball(point))
            .map(|id| id.expect("a created body"))
    }

    /// Removes the body under `point` (the Delete and X keys), unless it is static: the
    /// scene's ground and walls stay, so a stray key cannot empty a container. Returns the
    /// removed body's id; `None` with nothing (or only a static body) there.
    pub fn remove_at(&mut self, point: Vec2) -> Result<Option<BodyId>> {
        let Some(id) = self.world.body_at(point) else {
            return Ok(None);
        };
        if self.world.body(id)?.kind == BodyKind::Static {
            return Ok(None);
        }
        self.edit(Edit::Destroy(id))?;
        Ok(Some(id))
    }

    /// Starts holding the dynamic body under `point`, if any; returns whether one was caught.
    pub fn grab(&mut self, point: Vec2) -> bool {
        let Some(body) = self.world.body_at(point) else {
            return false;
        };
        let Ok(view) = self.world.body(body) else {
            return false;
        };
        if view.kind != BodyKind::Dynamic {
            return false;
        }
        self.drag = Some(Drag {
            body,
            local_anchor: view.rotation.apply_inv(point - view.position),
            target: point,
        });
        true
    }
}

/// Builds a scene's world with the loader's limits.
pub fn build_world(scene: &SceneDef) -> Result<World> {
    World::from_scene(scene, &LoadLimits::default().scene)
        .with_context(|| format!("{}: cannot build the world", scene.name))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene(name: &str) -> Arc<SceneDef> {
        Arc::new(tumble_scene::builtin::build(name).expect("built-in scene"))
    }

    /// Runs `seconds` of frames at `fps` and returns (steps, state hash).
    fn run_at(fps: u32, seconds: u32) -> (u64, u64) {
        let mut sim = Sim::new(scene("falling_circles"), 1).unwrap();
        for _ in 0..fps * seconds {
            sim.advance(1.0 / f64::from(fps));
        }
        (sim.steps, sim.world.state_hash())
    }

    #[test]
    fn same_result_at_30_and_144_fps() {
        let (steps_30, hash_30) = run_at(30, 3);
        let (steps_144, hash_144) = run_at(144, 3);
        assert_eq!(steps_30, 180);
        assert_eq!(steps_144, 180);
        assert_eq!(hash_30, hash_144);

        // And both equal stepping the engine directly, 180 times.
        let scene = scene("falling_circles");
        let mut world = build_world(&scene).unwrap();
        for _ in 0..180 {
            world.step(scene.dt, scene.substeps);
        }
        assert_eq!(world.state_hash(), hash_30);
    }

    #[test]
    fn uneven_frames_give_whole_steps_and_keep_the_remainder() {
        let mut clock = FixedStep::new(1.0 / 60.0);
        // 1/144 s frames: a step every 2.4 frames on average.
        let total: u32 = (0..144).map(|_| clock.advance(1.0 / 144.0)).sum();
        assert_eq!(total, 60);
        // A long hitch is capped, not replayed.
        let steps = clock.advance(5.0);
        assert_eq!(steps, clock.max_steps_per_frame);
        assert_eq!(clock.advance(0.0), 0);
    }

    #[test]
    fn the_mouse_spring_pulls_a_body_to_the_pointer() {
        let mut scene = SceneDef::new("drag");
        scene.gravity = [0.0, 0.0];
        scene.push(tumble_physics::BodyDef::new(
            tumble_physics::ShapeDef::Circle { radius: 0.5 },
        ));
        let mut sim = Sim::new(Arc::new(scene), 1).unwrap();
        assert!(sim.grab(Vec2::new(0.1, 0.0)));
        sim.drag.as_mut().unwrap().target = Vec2::new(3.1, 2.0);
        for _ in 0..240 {
            sim.single_step();
        }
        // The held point reaches the pointer (the disc may turn about it: the pull acts at
        // the point, as Box2D's mouse joint does). Without gravity the spring has no sag:
        // 1 mm allows the last of its damped swing after 4 s.
        let b = sim.world.body(BodyId::scene(0)).unwrap();
        let held = sim.drag.unwrap().anchor(b.position, b.rotation);
        assert!((held - Vec2::new(3.1, 2.0)).length() < 1e-3, "{held}");
        assert_eq!(sim.world.joint_count(), 1, "one mouse joint");
        // Letting go removes it.
        sim.drag = None;
        sim.single_step();
        assert_eq!(sim.world.joint_count(), 0);
        // Nothing to hold in empty space.
        assert!(!sim.grab(Vec2::new(-5.0, -5.0)));
    }

    /// Steps `sim` `n` times, pulling body `body` on the mouse spring during steps 60..150
    /// and switching to 6 substeps from step 150: inputs a replay must reproduce.
    fn drive(sim: &mut Sim, n: u64, body: usize) {
        for _ in 0..n {
            let i = sim.steps;
            if i == 60 {
                let p = sim.world.body(BodyId::scene(body)).unwrap().position;
                assert!(sim.grab(p));
                sim.drag.as_mut().unwrap().target = p + Vec2::new(2.0, 3.0);
            }
            if i == 150 {
                sim.drag = None;
                sim.substeps = 6;
            }
            sim.single_step();
        }
    }

    #[test]
    fn a_replay_ends_where_the_run_was_bit_for_bit() {
        let mut sim = Sim::new(scene("falling_circles"), 2).unwrap();
        let body = sim.world.body_count() - 1;
        drive(&mut sim, 240, body);
        let (hash, steps) = (sim.world.state_hash(), sim.steps);
        // 4 s recorded, all of it within the replay's reach.
        assert!((sim.recording.seconds(sim.scene.dt) - 4.0).abs() < 1e-6);
        assert!(sim.start_replay());
        assert_eq!(
            sim.replay,
            Some(Replay {
                until: 240,
                from: 0
            })
        );
        assert_eq!(sim.steps, 0);
        assert_ne!(sim.world.state_hash(), hash);
        // The live drag is ignored while replaying: the recorded one is applied.
        sim.drag = None;
        while sim.replay.is_some() {
            sim.single_step();
        }
        assert_eq!(sim.steps, steps);
        assert_eq!(sim.world.state_hash(), hash);
        assert_eq!(sim.substeps, 6);
    }

    #[test]
    fn the_recording_keeps_ten_seconds_and_a_stopped_replay_goes_on_live() {
        let mut sim = Sim::new(scene("vertical_stack"), 1).unwrap();
        for _ in 0..900 {
            sim.single_step();
        }
        // One snapshot a second (60 steps): between 10 and 11 seconds back.
        let held = sim.recording.inputs.len() as u64;
        assert!((600..=660).contains(&held), "{held} steps");
        assert!(sim.start_replay());
        let replay = sim.replay.unwrap();
        assert_eq!(replay.until, 900);
        assert_eq!(replay.from, 900 - held);
        for _ in 0..30 {
            sim.single_step();
        }
        sim.stop_replay();
        assert_eq!(sim.replay, None);
        assert_eq!(sim.recording.inputs.len() as u64, sim.steps - replay.from);
        // Live again, recording again, and replaying again reaches back as before.
        for _ in 0..120 {
            sim.single_step();
        }
        assert_eq!(sim.recording.inputs.len() as u64, sim.steps - replay.from);
        assert!(sim.start_replay());
    }

    /// The world's own consistency check, after an edit.
    fn valid(world: &World) {
        if let Err(e) = world.validate() {
            panic!("inconsistent world: {e}");
        }
    }

    fn steps(sim: &mut Sim, n: u64) {
        for _ in 0..n {
            sim.single_step();
        }
    }

    #[test]
    fn drops_and_removals_are_replayed_bit_for_bit() {
        let mut sim = Sim::new(scene("falling_circles"), 2).unwrap();
        let bodies = sim.world.body_count();
        assert_eq!(bodies, sim.scene.bodies.len());
        // Before the first step: the snapshot of step 0 must show the world without it.
        let first = sim.drop_box(Vec2::new(-3.0, 12.0)).unwrap();
        valid(&sim.world);
        assert_eq!(first.index as usize, bodies);
        assert_eq!(sim.world.body_count(), bodies + 1);
        assert_eq!(
            sim.world.body(BodyId::scene(bodies)).unwrap().kind,
            BodyKind::Dynamic
        );
        assert_eq!(
            sim.world.body(BodyId::scene(bodies)).unwrap().position,
            Vec2::new(-3.0, 12.0)
        );
        steps(&mut sim, 60);
        // At the step of a snapshot (one a second).
        sim.drop_ball(Vec2::new(3.0, 12.0)).unwrap();
        valid(&sim.world);
        assert_eq!(sim.world.body_count(), bodies + 2);
        steps(&mut sim, 40);
        // Remove a falling circle, held on the mouse spring: the spring lets go.
        let victim = sim.world.body_count() - 5;
        let at = sim.world.body(BodyId::scene(victim)).unwrap().position;
        assert!(sim.grab(at));
        let removed = sim
            .remove_at(at)
            .unwrap()
            .expect("a body under the pointer");
        valid(&sim.world);
        assert_eq!(removed.index as usize, victim);
        assert!(!sim.world.contains_body(BodyId::scene(victim)));
        assert_eq!(sim.world.body_count(), bodies + 1);
        assert_eq!(sim.drag, None);
        // The ground stays.
        assert_eq!(sim.remove_at(Vec2::new(30.0, -1.0)).unwrap(), None);
        assert_eq!(sim.world.body_count(), bodies + 1);
        // Nothing to remove in empty space.
        assert_eq!(sim.remove_at(Vec2::new(30.0, 50.0)).unwrap(), None);
        steps(&mut sim, 20);
        // The next body takes the freed slot, under a new generation.
        let again = sim.drop_box(Vec2::new(0.0, 14.0)).unwrap();
        valid(&sim.world);
        assert_eq!(again.index, removed.index);
        assert_eq!(again.generation, removed.generation + 1);
        steps(&mut sim, 60);
        // Made after the last step, just before the replay starts.
        let last = sim.drop_ball(Vec2::new(-6.0, 14.0)).unwrap();
        valid(&sim.world);
        let (hash, steps_then, live) = (sim.world.state_hash(), sim.steps, sim.world.body_count());
        assert_eq!(live, bodies + 3);

        assert!(sim.start_replay());
        assert_eq!(sim.replay.map(|r| (r.from, r.until)), Some((0, 180)));
        // Back before the first drop.
        assert_eq!(sim.world.body_count(), bodies);
        while sim.replay.is_some() {
            sim.single_step();
            valid(&sim.world);
        }
        assert_eq!(sim.steps, steps_then);
        assert_eq!(sim.world.body_count(), live);
        assert!(sim.world.contains_body(last));
        assert!(sim.world.contains_body(again) && again.index as usize == victim);
        assert_eq!(sim.world.state_hash(), hash);

        // And the run goes on as it would have without the replay.
        let mut live_run = Sim::new(scene("falling_circles"), 1).unwrap();
        live_run.drop_box(Vec2::new(-3.0, 12.0)).unwrap();
        steps(&mut live_run, 60);
        live_run.drop_ball(Vec2::new(3.0, 12.0)).unwrap();
        steps(&mut live_run, 40);
        live_run.remove_at(at).unwrap().unwrap();
        steps(&mut live_run, 20);
        live_run.drop_box(Vec2::new(0.0, 14.0)).unwrap();
        steps(&mut live_run, 60);
        live_run.drop_ball(Vec2::new(-6.0, 14.0)).unwrap();
        assert_eq!(live_run.world.state_hash(), hash);
        steps(&mut live_run, 30);
        steps(&mut sim, 30);
        assert_eq!(sim.world.state_hash(), live_run.world.state_hash());
    }

    #[test]
    fn a_stopped_replay_forgets_the_edits_it_did_not_reach() {
        let mut sim = Sim::new(scene("falling_circles"), 1).unwrap();
        let bodies = sim.world.body_count();
        sim.drop_box(Vec2::new(-3.0, 12.0)).unwrap();
        steps(&mut sim, 100);
        sim.drop_ball(Vec2::new(3.0, 12.0)).unwrap();
        steps(&mut sim, 100);
        assert_eq!(sim.world.body_count(), bodies + 2);
        assert!(sim.start_replay());
        steps(&mut sim, 50);
        assert_eq!(sim.world.body_count(), bodies + 1);
        sim.stop_replay();
        // Live from step 50: the ball of step 100 is not made again.
        steps(&mut sim, 150);
        assert_eq!(sim.world.body_count(), bodies + 1);
        valid(&sim.world);
        // An edit during a replay stops it and is made live.
        let hash = sim.world.state_hash();
        assert!(sim.start_replay());
        steps(&mut sim, 10);
        sim.drop_ball(Vec2::new(0.0, 20.0)).unwrap();
        assert_eq!(sim.replay, None);
        assert_eq!(sim.steps, 10);
        assert_eq!(sim.world.body_count(), bodies + 2);
        steps(&mut sim, 190);
        // A replay of this new past ends where it is, the ball included.
        let (hash2, live) = (sim.world.state_hash(), sim.world.body_count());
        assert_ne!(hash2, hash);
        assert!(sim.start_replay());
        while sim.replay.is_some() {
            sim.single_step();
        }
        assert_eq!(sim.steps, 200);
        assert_eq!(sim.world.body_count(), live);
        assert_eq!(sim.world.state_hash(), hash2);
    }

    #[test]
    fn a_saved_world_with_edits_goes_on_bit_for_bit() {
        let mut sim = Sim::new(scene("falling_circles"), 1).unwrap();
        sim.drop_box(Vec2::new(-3.0, 12.0)).unwrap();
        steps(&mut sim, 50);
        let victim = sim.world.body_count() - 3;
        let at = sim.world.body(BodyId::scene(victim)).unwrap().position;
        sim.remove_at(at).unwrap().unwrap();
        let text = sim.save().to_json();
        let mut other = Sim::new(scene("pyramid"), 2).unwrap();
        other
            .restore(SavedWorld::from_json(&text, "saved.json").unwrap())
            .unwrap();
        valid(&other.world);
        assert_eq!(other.world.body_count(), sim.world.body_count());
        assert!(!other.world.contains_body(BodyId::scene(victim)));
        steps(&mut sim, 60);
        steps(&mut other, 60);
        assert_eq!(sim.world.state_hash(), other.world.state_hash());
    }

    #[test]
    fn the_junkyard_script_moves_the_pusher_live_and_in_the_replay() {
        let junkyard = scene("junkyard");
        let pusher = junkyard.bodies.len() - 1;
        assert_eq!(junkyard.bodies[pusher].kind, BodyKind::Kinematic);
        let mut sim = Sim::new(Arc::clone(&junkyard), 2).unwrap();
        assert!(sim.script.is_some());
        steps(&mut sim, 70);
        let x = sim.world.body(BodyId::scene(pusher)).unwrap().origin.x;
        // x = 60 sin(0.2 t) at t = 70/60 s: the script ran before every step.
        let expected = 60.0 * (0.2f32 * 69.0 / 60.0).sin();
        assert!(
            (x - expected).abs() < 1e-3,
            "pusher at {x}, expected {expected}"
        );
        let hash = sim.world.state_hash();
        assert!(sim.start_replay());
        while sim.replay.is_some() {
            sim.single_step();
        }
        assert_eq!(sim.world.body(BodyId::scene(pusher)).unwrap().origin.x, x);
        assert_eq!(sim.world.state_hash(), hash);
        // Only the built-in itself has the script: not another scene, not one changed.
        assert!(Sim::new(scene("pyramid"), 1).unwrap().script.is_none());
        let mut changed = (*junkyard).clone();
        changed.bodies.remove(1);
        assert!(tumble_scene::builtin::script_for(&changed).is_none());
    }

    #[test]
    fn a_saved_world_read_back_from_its_file_goes_on_bit_for_bit() {
        let mut sim = Sim::new(scene("falling_circles"), 1).unwrap();
        let body = sim.world.body_count() - 1;
        drive(&mut sim, 100, body);
        let text = sim.save().to_json();

        // Into a viewer that shows another scene: the saved one comes back with it.
        let mut other = Sim::new(scene("pyramid"), 2).unwrap();
        other
            .restore(SavedWorld::from_json(&text, "saved.json").unwrap())
            .unwrap();
        assert_eq!(other.scene.name, "falling_circles");
        assert_eq!(other.steps, 100);
        assert_eq!(other.world.thread_count(), 2);
        // A restored world holds no body on the mouse spring; neither does the run it is
        // compared with from step 100 on.
        let mut first = Sim::new(scene("falling_circles"), 1).unwrap();
        drive(&mut first, 100, body);
        first.drag = None;
        for _ in 0..120 {
            first.single_step();
            other.single_step();
        }
        assert_eq!(first.world.state_hash(), other.world.state_hash());

        // A file whose scene is invalid is refused and the running world is kept as it was.
        let mut bad = SavedWorld::from_json(&text, "saved.json").unwrap();
        bad.scene.bodies[1].density = -1.0;
        let (hash, steps) = (other.world.state_hash(), other.steps);
        let err = other
            .restore(bad)
            .expect_err("a negative density is refused");
        assert!(format!("{err:#}").contains("density"), "{err:#}");
        assert_eq!((other.world.state_hash(), other.steps), (hash, steps));

        let err = SavedWorld::from_json("{\"format\": \"x\"}", "saved.json")
            .err()
            .unwrap();
        assert!(format!("{err:#}").contains("saved.json: not a tumble snapshot file"));
        let mut wrong: serde_json::Value = serde_json::from_str(&text).unwrap();
        wrong["format"] = "tumble-snapshot-0".into();
        let err = SavedWorld::from_json(&wrong.to_string(), "old.json")
            .err()
            .unwrap();
        assert!(
            format!("{err:#}").contains("allowed: `tumble-snapshot-1`"),
            "{err:#}"
        );
    }

    #[test]
    fn the_event_log_keeps_the_last_events_and_counts_them_all() {
        // falling_circles: circles land on the pyramid, contacts begin, hit and end.
        let mut sim = Sim::load("falling_circles", 1).unwrap();
        steps(&mut sim, 240);
        let log = &sim.events;
        assert!(log.counts[0] > 0 && log.counts[2] > 0, "{:?}", log.counts);
        let total: u64 = log.counts.iter().sum();
        assert!(total as usize > EventLog::CAPACITY);
        assert_eq!(log.entries.len(), EventLog::CAPACITY);
        // Oldest first, by step; the last is from the last step or before.
        assert!(
            log.entries
                .iter()
                .zip(log.entries.iter().skip(1))
                .all(|(a, b)| a.0 <= b.0)
        );
        assert!(log.entries.back().unwrap().0 <= sim.steps);
        // Each is what the world reported: the last step's events end the log.
        let last: Vec<_> = sim.world.events().to_vec();
        let tail: Vec<_> = log
            .entries
            .iter()
            .rev()
            .take(last.len())
            .rev()
            .map(|(_, e)| *e)
            .collect();
        assert_eq!(tail, last);
        sim.restart();
        assert!(sim.events.entries.is_empty() && sim.events.counts == [0; 6]);
    }

    /// The platformer under the scripted run's keys, as the viewer plays it: frames of 1/60 s.
    fn platformer(steps: u64) -> Sim {
        use tumble_scene::builtin::platformer::SCRIPT;
        let mut sim = Sim::new(scene("platformer"), 2).unwrap();
        sim.key_script = Some(KeyScript::parse(SCRIPT).unwrap());
        sim.step_limit = Some(steps);
        for _ in 0..steps + 10 {
            sim.advance(1.0 / 60.0);
        }
        sim
    }

    #[test]
    fn the_platformer_in_the_viewer_is_the_headless_run_bit_for_bit_and_stops_at_its_steps() {
        use tumble_scene::builtin::platformer::{SCRIPT, SCRIPT_STEPS};
        let sim = platformer(SCRIPT_STEPS);
        // `--steps`: not one step beyond, however many frames came after.
        assert_eq!(sim.steps, SCRIPT_STEPS);
        let script = KeyScript::parse(SCRIPT).unwrap();
        let (world, controller) =
            tumble_scene::sample::play(&sim.scene, &script, SCRIPT_STEPS, 1, |_, _, _| {}).unwrap();
        assert_eq!(sim.world.state_hash(), world.state_hash());
        assert_eq!(sim.controller, controller);
        assert!(sim.controller.as_ref().is_some_and(Controller::finished));
    }

    #[test]
    fn a_replay_of_the_platformer_restores_its_character_and_keys_bit_for_bit() {
        let mut sim = platformer(300);
        let (hash, character) = (sim.world.state_hash(), sim.controller.clone());
        assert!(sim.start_replay());
        assert_ne!(sim.controller, character);
        // Live keys are ignored while replaying: the recorded ones apply.
        sim.keys = Keys::LEFT;
        while sim.replay.is_some() {
            sim.single_step();
        }
        assert_eq!(sim.world.state_hash(), hash);
        assert_eq!(sim.controller, character);
    }

    #[test]
    fn a_saved_platformer_goes_on_with_its_character_bit_for_bit() {
        let mut sim = platformer(200);
        let text = sim.save().to_json();
        let mut other = Sim::new(scene("platformer"), 1).unwrap();
        other
            .restore(SavedWorld::from_json(&text, "test").unwrap())
            .unwrap();
        assert_eq!(other.controller, sim.controller);
        for s in [&mut sim, &mut other] {
            s.key_script = Some(KeyScript::parse("200:right+").unwrap());
            s.step_limit = None;
            for _ in 0..60 {
                s.single_step();
            }
        }
        assert_eq!(other.world.state_hash(), sim.world.state_hash());
        assert_eq!(other.controller, sim.controller);
        // The restart puts the character back at its start.
        sim.restart();
        assert_eq!(
            sim.controller,
            Controller::for_scene(&sim.scene),
            "a fresh character"
        );
    }
}
