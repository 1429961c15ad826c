//! The simulation state: the world stepping on its fixed clock, drawn through a camera the
//! user pans (right drag) and zooms (wheel), with a mouse spring on the left button, keys
//! that drop and remove bodies at the pointer (B, N, X / Delete), and the control and
//! profile panels.

mod controls;

use glam::Vec2;

use super::{Paused, Shared, Signal, State, StateKind, Transition, View};
use crate::camera::{Camera, world_bounds};
use crate::input::{Button, InputEvent, Key};
use crate::sim::{SavedWorld, Sim};
use crate::ui::profiler::Sweep;
use tumble_physics::BodyKind;
use tumble_scene::sample::Keys;

/// The simulation state.
pub struct Simulation {
    /// The running simulation.
    pub sim: Sim,
    /// The camera.
    pub camera: Camera,
    /// Frames left in which to frame the scene (the panel's width is known after one frame).
    pub(crate) fit_frames: u8,
    /// Right-button panning in progress.
    pub(crate) panning: bool,
    /// Where the pointer was last seen over the world (physical pixels), for the keys that
    /// drop and remove bodies there.
    pub(crate) pointer: Option<Vec2>,
    /// The thread sweep (runs on its own thread).
    pub(crate) sweep: Sweep,
    /// The scenes the panel's picker offers.
    pub(crate) entries: Vec<super::main_menu::SceneEntry>,
    /// The last scene-loading error, shown in the panel.
    pub(crate) error: Option<String>,
    /// The world saved by Save snapshot (natively also in [`SNAPSHOT_FILE`]).
    pub(crate) saved: Option<SavedWorld>,
    /// What a left drag does.
    pub(crate) tool: Tool,
    /// A ray is being dragged out (the ray tool, left button held).
    pub(crate) casting: bool,
    /// Which kinds of event the event log lists (as [`crate::sim::EventLog::kind`] numbers
    /// them).
    pub(crate) event_filter: [bool; 6],
    /// The camera follows a played sample's character, keeping it this far from the
    /// view's centre (until the user pans; F frames it again).
    pub(crate) follow: Option<Vec2>,
}

/// What a left drag does in the simulation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tool {
    /// Pull a body on the mouse joint.
    Grab,
    /// Drag out a ray; its hits and normals are drawn.
    Ray,
}

/// Where Save snapshot writes natively (in the working directory, beside screenshots) and
/// Load snapshot reads when nothing was saved in this run.
pub const SNAPSHOT_FILE: &str = "tumble-snapshot.json";

impl Simulation {
    /// A simulation state for `sim`.
    pub fn new(sim: Sim, shared: &Shared) -> Self {
        Self {
            sim,
            camera: Camera::new(Vec2::ZERO, 20.0, shared.viewport),
            fit_frames: 2,
            panning: false,
            pointer: None,
            sweep: Sweep::default(),
            entries: super::main_menu::scene_entries(),
            error: None,
            saved: None,
            tool: Tool::Grab,
            casting: false,
            event_filter: [true; 6],
            follow: None,
        }
    }

    /// Save snapshot: the world as it is now, kept for Load snapshot (natively also written
    /// to [`SNAPSHOT_FILE`], so a later run can load it).
    pub fn save_snapshot(&mut self, shared: &mut Shared) {
        let saved = self.sim.save();
        #[cfg(not(target_arch = "wasm32"))]
        match std::fs::write(SNAPSHOT_FILE, saved.to_json()) {
            Ok(()) => shared.toast(format!(
                "Snapshot of step {} saved: {SNAPSHOT_FILE}",
                saved.steps
            )),
            Err(e) => shared.toast(format!("Snapshot kept for this run; {SNAPSHOT_FILE}: {e}")),
        }
        #[cfg(target_arch = "wasm32")]
        shared.toast(format!("Snapshot of step {} saved", saved.steps));
        self.saved = Some(saved);
    }

    /// Load snapshot: back to the saved world (natively from [`SNAPSHOT_FILE`] when nothing
    /// was saved in this run); it goes on exactly as it would have from there.
    pub fn load_snapshot(&mut self, shared: &mut Shared) {
        let saved = match self.saved.clone() {
            Some(saved) => Ok(saved),
            None => read_snapshot_file(),
        };
        match saved.and_then(|saved| {
            let steps = saved.steps;
            self.sim.restore(saved).map(|()| steps)
        }) {
            Ok(steps) => {
                self.error = None;
                shared.toast(format!("Snapshot of step {steps} loaded"));
            }
            Err(e) => self.error = Some(format!("{e:#}")),
        }
    }

    /// Frames the whole scene in the part of the window the panels leave free; in a played
    /// sample, the character and 12 m around it, and follows it from then on.
    pub fn fit(&mut self, shared: &Shared) {
        self.camera.viewport = shared.viewport;
        match self.sim.controller.as_ref().and_then(|c| c.focus()) {
            Some(focus) => {
                let bounds = tumble_physics::Aabb {
                    min: focus - Vec2::new(12.0, 5.0),
                    max: focus + Vec2::new(12.0, 7.0),
                };
                self.camera.fit(bounds, shared.view_area);
                self.follow = Some(self.camera.center - focus);
            }
            None => self
                .camera
                .fit(world_bounds(&self.sim.world), shared.view_area),
        }
    }

    /// Swaps in another scene (from the panel's picker), keeping threads and settings.
    pub fn load(&mut self, source: &str, shared: &mut Shared) {
        let threads = self.sim.world.thread_count();
        match Sim::load(source, threads) {
            Ok(sim) => {
                self.sim = sim;
                self.fit_frames = 2;
                self.error = None;
                shared.settings.scene = source.to_string();
            }
            Err(e) => self.error = Some(format!("{e:#}")),
        }
    }

    /// Play or pause.
    pub fn toggle_running(&mut self) {
        self.sim.running = !self.sim.running;
    }

    /// One step, pausing first.
    pub fn step_once(&mut self) {
        self.sim.running = false;
        self.sim.single_step();
    }

    /// B, N, X and Delete: drops a box or a ball at the pointer, or removes the body under
    /// it (not a static one), through [`Sim::edit`] so the replay makes it again.
    fn edit_at_pointer(&mut self, key: Key, shared: &mut Shared) {
        let Some(pointer) = self.pointer else {
            return;
        };
        let point = self.camera.screen_to_world(pointer);
        let result = match key {
            Key::B => self.sim.drop_box(point).map(|_| ()),
            Key::N => self.sim.drop_ball(point).map(|_| ()),
            _ => {
                let on_static = self.sim.world.body_at(point).is_some_and(|i| {
                    self.sim
                        .world
                        .body(i)
                        .is_ok_and(|b| b.kind == BodyKind::Static)
                });
                if on_static {
                    shared.toast("Static bodies stay (X and Delete remove moving ones)");
                }
                self.sim.remove_at(point).map(|_| ())
            }
        };
        if let Err(e) = result {
            shared.toast(format!("{e:#}"));
        }
    }
}

/// The sample key a keyboard key stands for in a played sample (Box2D's samples: arrows or
/// A and D to walk, Space, Up or W to jump).
pub fn sample_key(key: Key) -> Option<Keys> {
    Some(match key {
        Key::ArrowLeft | Key::A => Keys::LEFT,
        Key::ArrowRight | Key::D => Keys::RIGHT,
        Key::Space | Key::ArrowUp | Key::W => Keys::JUMP,
        Key::ArrowDown => Keys::DOWN,
        _ => return None,
    })
}

#[cfg(not(target_arch = "wasm32"))]
fn read_snapshot_file() -> anyhow::Result<SavedWorld> {
    use anyhow::Context;
    let text = std::fs::read_to_string(SNAPSHOT_FILE)
        .with_context(|| format!("{SNAPSHOT_FILE}: nothing saved yet (Save snapshot writes it)"))?;
    SavedWorld::from_json(&text, SNAPSHOT_FILE)
}

#[cfg(target_arch = "wasm32")]
fn read_snapshot_file() -> anyhow::Result<SavedWorld> {
    anyhow::bail!("nothing saved yet in this page (Save snapshot first)")
}

impl State for Simulation {
    fn kind(&self) -> StateKind {
        StateKind::Simulation
    }

    fn on_back(&mut self, _shared: &mut Shared) -> Transition {
        self.sim.drag = None;
        self.panning = false;
        Transition::Push(Box::new(Paused::new()))
    }

    fn on_signal(&mut self, signal: Signal, _shared: &mut Shared) {
        match signal {
            Signal::Restart => self.sim.restart(),
        }
    }

    fn on_input(&mut self, event: &InputEvent, shared: &mut Shared) -> Transition {
        if let InputEvent::Key { key, pressed, .. } = *event
            && self.sim.controller.is_some()
            && let Some(sample_key) = sample_key(key)
        {
            // A played sample reads these keys (Space jumps, not pauses), held or not.
            self.sim.keys.set(sample_key, pressed);
            return Transition::None;
        }
        match *event {
            InputEvent::Key {
                key,
                pressed: true,
                repeat,
            } => match key {
                Key::Space if !repeat => self.toggle_running(),
                Key::S => self.step_once(),
                Key::R if !repeat => self.sim.restart(),
                Key::F if !repeat => self.fit(shared),
                Key::B | Key::N | Key::X | Key::Delete if !repeat => {
                    self.edit_at_pointer(key, shared);
                }
                _ => {}
            },
            InputEvent::Button {
                button,
                pressed,
                position,
            } => {
                self.pointer = Some(position);
                match button {
                    Button::Left if pressed => {
                        let point = self.camera.screen_to_world(position);
                        match self.tool {
                            Tool::Grab => {
                                self.sim.grab(point);
                            }
                            Tool::Ray => {
                                self.sim.ray = Some((point, point));
                                self.casting = true;
                            }
                        }
                    }
                    Button::Left => {
                        self.sim.drag = None;
                        // The ray stays drawn (its hits follow the world) until the next.
                        self.casting = false;
                    }
                    Button::Right | Button::Middle => self.panning = pressed,
                    Button::Other => {}
                }
            }
            InputEvent::PointerMoved { position, delta } => {
                self.pointer = Some(position);
                if self.panning {
                    self.camera.pan_pixels(delta);
                    self.follow = None;
                }
                if let Some(drag) = &mut self.sim.drag {
                    drag.target = self.camera.screen_to_world(position);
                }
                if let (true, Some(ray)) = (self.casting, &mut self.sim.ray) {
                    ray.1 = self.camera.screen_to_world(position);
                }
            }
            InputEvent::Wheel { lines, position } => {
                self.camera.zoom_at(position, 1.15f32.powf(lines));
            }
            InputEvent::Key { .. } => {}
        }
        Transition::None
    }

    fn update(&mut self, frame_seconds: f64, shared: &mut Shared) -> Transition {
        self.camera.viewport = shared.viewport;
        if self.fit_frames > 0 {
            self.fit(shared);
            self.fit_frames -= 1;
        }
        self.sweep.poll();
        // The sweep measures the step on every core: the live world waits meanwhile.
        if !self.sweep.is_running() {
            self.sim.advance(frame_seconds);
        }
        if let (Some(offset), Some(focus)) = (
            self.follow,
            self.sim.controller.as_ref().and_then(|c| c.focus()),
        ) {
            self.camera.center = focus + offset;
        }
        Transition::None
    }

    fn ui(&mut self, ui: &mut egui::Ui, shared: &mut Shared) -> Transition {
        controls::simulation_ui(ui, self, shared)
    }

    fn view(&self) -> Option<View<'_>> {
        Some(View {
            sim: &self.sim,
            camera: &self.camera,
            debug: true,
            dim: 0.0,
        })
    }

    fn sim(&self) -> Option<&Sim> {
        Some(&self.sim)
    }
}
