//! A running simulation as the viewer sees it: the world, the scene it came from, the
//! fixed-step clock that turns frame times into whole physics steps, the mouse spring, and the
//! recent per-stage profile.
//!
//! The physics always advances by the scene's `dt`, never by the frame's time: the clock
//! accumulates frame time and hands out whole steps, so a scene gives the same result at 30
//! and at 144 frames per second (the test below proves it through [`World::state_hash`]).

use std::collections::VecDeque;
use std::sync::Arc;

use anyhow::{Context, Result};
use glam::Vec2;
use tumble_physics::{BodyKind, Rot, SceneDef, StepSettings, World};
use tumble_scene::LoadLimits;

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

/// The mouse spring: a body held at a point of its own, pulled toward the pointer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Drag {
    /// The body held.
    pub body: usize,
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

    /// Applies one step's spring impulse to the held body. The spring is solved implicitly
    /// (Box2D's soft constraint: a stiffness and damping ratio turned into a bias rate and a
    /// mass scale), so it is stable at any step size.
    pub fn apply(&self, world: &mut World, dt: f32) {
        if self.body >= world.body_count() {
            return;
        }
        let body = world.body(self.body);
        if body.kind != BodyKind::Dynamic {
            return;
        }
        let mass = world.mass(self.body);
        if mass <= 0.0 {
            return;
        }
        let anchor = self.anchor(body.position, body.rotation);
        let r = anchor - body.position;
        let point_velocity = body.linear_velocity + Vec2::new(-r.y, r.x) * body.angular_velocity;
        let omega = 2.0 * std::f32::consts::PI * DRAG_HERTZ;
        let a = 2.0 * DRAG_DAMPING + dt * omega;
        let bias_rate = omega / a;
        let mass_scale = dt * omega * a / (1.0 + dt * omega * a);
        let c = anchor - self.target;
        let mut impulse = -mass * mass_scale * (point_velocity + bias_rate * c);
        let max = DRAG_MAX_FORCE_PER_KG * mass * dt;
        if impulse.length() > max {
            impulse = impulse.normalize_or_zero() * max;
        }
        world.apply_linear_impulse(self.body, impulse, anchor);
    }
}

/// One step's timings, for the profile plot.
#[derive(Clone, Copy, Debug)]
pub struct ProfileSample {
    /// Simulated time at the end of the step (s).
    pub time: f64,
    /// The whole step (ms).
    pub step_ms: f64,
    /// Each stage (ms), in pipeline order.
    pub stages: [(&'static str, f64); 6],
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
    /// Steps since the world was (re)built.
    pub steps: u64,
    /// Steps over the whole run, restarts included (for `--stats`).
    pub total_steps: u64,
    /// Sum of every step's wall time (ms) over the whole run.
    pub total_step_ms: f64,
    /// The last seconds of per-stage timings.
    pub history: VecDeque<ProfileSample>,
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
            steps: 0,
            total_steps: 0,
            total_step_ms: 0.0,
            history: VecDeque::new(),
        };
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
        }
        self.world.set_thread_count(threads);
        *self.world.settings_mut() = settings;
        self.clock.reset();
        self.drag = None;
        self.steps = 0;
        self.history.clear();
    }

    /// Advances by one frame's duration: as many fixed steps as the clock hands out (none
    /// while paused). Returns the steps taken.
    pub fn advance(&mut self, frame_seconds: f64) -> u32 {
        if !self.running {
            self.clock.reset();
            return 0;
        }
        let steps = self.clock.advance(frame_seconds);
        for _ in 0..steps {
            self.step_once();
        }
        steps
    }

    /// One step now, whether running or not.
    pub fn single_step(&mut self) {
        self.step_once();
    }

    fn step_once(&mut self) {
        let dt = self.scene.dt;
        if let Some(drag) = self.drag {
            drag.apply(&mut self.world, dt);
        }
        self.world.step(dt, self.substeps.max(1));
        self.steps += 1;
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

    /// Starts holding the dynamic body under `point`, if any; returns whether one was caught.
    pub fn grab(&mut self, point: Vec2) -> bool {
        let Some(body) = self.world.body_at(point) else {
            return false;
        };
        let view = self.world.body(body);
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
        let p = sim.world.body(0).position;
        assert!((p - Vec2::new(3.0, 2.0)).length() < 0.05, "{p}");
        // Nothing to hold in empty space.
        assert!(!sim.grab(Vec2::new(-5.0, -5.0)));
    }
}
