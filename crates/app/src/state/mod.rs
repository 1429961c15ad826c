//! The viewer's states and the stack that runs them.
//!
//! A state owns its data (the intro and the menu own a background simulation, the
//! simulation state owns its world and camera, the pause state owns nothing) and answers
//! every call with a [`Transition`]: an explicit value saying what comes next, never a flag
//! someone else has to notice. The [`StateMachine`] applies transitions, keeps the stack, and
//! routes input: the [`Global`] state first, then egui, then the state on top.
//!
//! Only the state on top updates and gets input; a state marked as an overlay (pause) is drawn
//! over the state below it, which stays visible and frozen.

pub mod intro;
pub mod main_menu;
pub mod paused;
pub mod simulation;

use glam::Vec2;

use crate::input::{Global, GlobalOutcome, InputEvent, Toggles};
pub use crate::render::View;
use crate::settings::Settings;
use crate::sim::Sim;
use crate::ui::Notices;

pub use intro::Intro;
pub use main_menu::MainMenu;
pub use paused::Paused;
pub use simulation::{Simulation, Tool};

/// Which state a state is (for titles, tests and stats).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StateKind {
    /// The animated title.
    Intro,
    /// The scene picker.
    MainMenu,
    /// Physics and drawing.
    Simulation,
    /// Drawn over the frozen simulation.
    Paused,
}

/// What a state asks for next.
pub enum Transition {
    /// Stay.
    None,
    /// Put a state on top (the current one stays below, frozen).
    Push(Box<dyn State>),
    /// Leave this state; the one below resumes.
    Pop,
    /// Leave this state and hand the one below a signal.
    PopWith(Signal),
    /// Swap this state for another.
    Replace(Box<dyn State>),
    /// Empty the stack and start over from this state.
    Reset(Box<dyn State>),
    /// Leave the app.
    Quit,
}

impl std::fmt::Debug for Transition {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Transition::None => write!(f, "None"),
            Transition::Push(s) => write!(f, "Push({:?})", s.kind()),
            Transition::Pop => write!(f, "Pop"),
            Transition::PopWith(s) => write!(f, "PopWith({s:?})"),
            Transition::Replace(s) => write!(f, "Replace({:?})", s.kind()),
            Transition::Reset(s) => write!(f, "Reset({:?})", s.kind()),
            Transition::Quit => write!(f, "Quit"),
        }
    }
}

/// A message a state leaving hands to the state below.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Signal {
    /// Rebuild the world from its scene.
    Restart,
}

/// App-wide data every state may read and change: the persisted settings, the toggles of
/// the global keys, the notices the UI shows, and what the frame knows of the window.
#[derive(Clone, Debug)]
pub struct Shared {
    /// Persisted settings.
    pub settings: Settings,
    /// What F1, H, F12 and P flip.
    pub toggles: Toggles,
    /// The toast and a recovered crash.
    pub notices: Notices,
    /// The window's size in physical pixels.
    pub viewport: Vec2,
    /// The part of the window not covered by panels (physical pixels: min, max), where
    /// "fit scene" puts the world.
    pub view_area: (Vec2, Vec2),
    /// Physical pixels per egui point.
    pub pixels_per_point: f32,
    /// Frames per second, smoothed.
    pub fps: f64,
    /// The graphics backend, as wgpu names it ("Vulkan", "Gl", ...).
    pub backend: String,
    /// Seconds since the app started.
    pub time: f64,
    /// Why the platform offers fewer threads than the machine has, if it does (the web build
    /// in a page that is not cross-origin isolated).
    pub threads_note: Option<String>,
    /// Where the thread slider was drawn this frame (egui points), for tests that drive it.
    pub threads_slider: Option<egui::Rect>,
}

impl Shared {
    /// Defaults for a window of `viewport` physical pixels.
    pub fn new(settings: Settings, viewport: Vec2) -> Self {
        Self {
            settings,
            toggles: Toggles::default(),
            notices: Notices::default(),
            viewport,
            view_area: (Vec2::ZERO, viewport),
            pixels_per_point: 1.0,
            fps: 0.0,
            backend: String::new(),
            time: 0.0,
            threads_note: None,
            threads_slider: None,
        }
    }

    /// Shows `text` for a few seconds.
    pub fn toast(&mut self, text: impl Into<String>) {
        self.notices.toast = Some((text.into(), self.time + 4.0));
    }
}

/// One state of the viewer. Every method has a default that does nothing. States are `Send`:
/// the web build runs their update on a worker.
pub trait State: Send {
    /// Which state this is.
    fn kind(&self) -> StateKind;

    /// Escape was pressed (the global state translates it): what "back" means here.
    fn on_back(&mut self, _shared: &mut Shared) -> Transition {
        Transition::None
    }

    /// Input for this state: only when it is on top, and only input that neither the global
    /// state nor egui took.
    fn on_input(&mut self, _event: &InputEvent, _shared: &mut Shared) -> Transition {
        Transition::None
    }

    /// One frame passed (`frame_seconds` of real time); only the state on top updates.
    fn update(&mut self, _frame_seconds: f64, _shared: &mut Shared) -> Transition {
        Transition::None
    }

    /// The state's UI (egui), drawn when it is on top.
    fn ui(&mut self, _ui: &mut egui::Ui, _shared: &mut Shared) -> Transition {
        Transition::None
    }

    /// A signal from the state above as it left.
    fn on_signal(&mut self, _signal: Signal, _shared: &mut Shared) {}

    /// Drawn over the state below it (which stays visible, frozen).
    fn is_overlay(&self) -> bool {
        false
    }

    /// The world this state shows, if any.
    fn view(&self) -> Option<View<'_>> {
        None
    }

    /// The simulation this state runs, if any (for `--stats`).
    fn sim(&self) -> Option<&Sim> {
        None
    }
}

/// What egui wants, asked before each event is routed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EguiWants {
    /// The pointer is over egui or egui is dragging something.
    pub pointer: bool,
    /// A text field has keyboard focus.
    pub keyboard: bool,
}

/// Who got an input event.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Routed {
    /// The global state.
    Global,
    /// egui (the state on top never saw it).
    Egui,
    /// The state on top.
    State,
    /// Nobody: the stack is empty.
    Nobody,
}

/// The stack of states with the global state beside it. The default is an empty stack, a
/// placeholder while the states are away (their update running on another thread).
#[derive(Default)]
pub struct StateMachine {
    stack: Vec<Box<dyn State>>,
    /// The global state (always active).
    pub global: Global,
    quit: bool,
}

impl StateMachine {
    /// A machine starting in `first`.
    pub fn new(first: Box<dyn State>) -> Self {
        Self {
            stack: vec![first],
            global: Global::default(),
            quit: false,
        }
    }

    /// The states from bottom to top.
    pub fn kinds(&self) -> Vec<StateKind> {
        self.stack.iter().map(|s| s.kind()).collect()
    }

    /// The state on top.
    pub fn top_kind(&self) -> Option<StateKind> {
        self.stack.last().map(|s| s.kind())
    }

    /// Whether a state asked to quit (or the stack emptied).
    pub fn should_quit(&self) -> bool {
        self.quit || self.stack.is_empty()
    }

    /// Routes one input event: the global state sees it first; then, unless egui wants that
    /// kind of input (the keyboard while a text field has focus, the pointer over a panel),
    /// the state on top. A button release always reaches the state, so a drag that began in
    /// the world ends even when the pointer is let go over a panel.
    pub fn input(&mut self, event: InputEvent, egui: EguiWants, shared: &mut Shared) -> Routed {
        match self
            .global
            .handle(&event, egui.keyboard, &mut shared.toggles)
        {
            GlobalOutcome::Consumed => return Routed::Global,
            GlobalOutcome::Back => {
                if let Some(top) = self.stack.last_mut() {
                    let t = top.on_back(shared);
                    self.apply(t, shared);
                }
                return Routed::Global;
            }
            GlobalOutcome::Pass => {}
        }
        let egui_wants = match event {
            InputEvent::Key { .. } => egui.keyboard,
            InputEvent::Button { pressed: false, .. } => false,
            _ => egui.pointer,
        };
        if egui_wants {
            return Routed::Egui;
        }
        let Some(top) = self.stack.last_mut() else {
            return Routed::Nobody;
        };
        let t = top.on_input(&event, shared);
        self.apply(t, shared);
        Routed::State
    }

    /// One frame: the state on top updates.
    pub fn update(&mut self, frame_seconds: f64, shared: &mut Shared) {
        self.guarded(shared, |m, shared| {
            if let Some(top) = m.stack.last_mut() {
                let t = top.update(frame_seconds, shared);
                m.apply(t, shared);
            }
        });
    }

    /// The UI of the state on top, then the global UI (help, messages).
    pub fn ui(&mut self, ui: &mut egui::Ui, shared: &mut Shared) {
        self.guarded(shared, |m, shared| {
            if let Some(top) = m.stack.last_mut() {
                let t = top.ui(ui, shared);
                m.apply(t, shared);
            }
        });
        crate::ui::global_ui(
            ui,
            &mut shared.toggles.help_visible,
            &mut shared.notices,
            shared.time,
        );
    }

    /// Runs `f` on the states; if a state panics (a bug), the viewer goes back to the main
    /// menu and shows the message (`shared.notices.crash`) instead of dying or freezing its frame.
    /// The panic hook has printed it on stderr already. On the web, where panics abort, the
    /// page's overlay shows it instead.
    fn guarded(&mut self, shared: &mut Shared, f: impl FnOnce(&mut Self, &mut Shared)) {
        let run = std::panic::AssertUnwindSafe(|| f(self, shared));
        if let Err(payload) = std::panic::catch_unwind(run) {
            let what = payload
                .downcast_ref::<&str>()
                .map(|s| (*s).to_string())
                .or_else(|| payload.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown failure".to_string());
            // The states may be half-updated: none of them is trusted any more.
            self.stack.clear();
            self.stack.push(Box::new(MainMenu::new(None)));
            shared.notices.crash = Some(what);
            shared.notices.crashes += 1;
        }
    }

    /// The world to draw: that of the highest state that shows one (an overlay shows none,
    /// so the state under it is drawn).
    pub fn view(&self) -> Option<View<'_>> {
        self.stack.iter().rev().find_map(|s| s.view())
    }

    /// The simulation of the highest simulation state, for `--stats`.
    pub fn sim(&self) -> Option<&Sim> {
        self.stack
            .iter()
            .rev()
            .filter(|s| s.kind() == StateKind::Simulation)
            .find_map(|s| s.sim())
    }

    /// Applies a transition.
    pub fn apply(&mut self, transition: Transition, shared: &mut Shared) {
        match transition {
            Transition::None => {}
            Transition::Push(state) => self.stack.push(state),
            Transition::Pop => {
                self.stack.pop();
            }
            Transition::PopWith(signal) => {
                self.stack.pop();
                if let Some(top) = self.stack.last_mut() {
                    top.on_signal(signal, shared);
                }
            }
            Transition::Replace(state) => {
                self.stack.pop();
                self.stack.push(state);
            }
            Transition::Reset(state) => {
                self.stack.clear();
                self.stack.push(state);
            }
            Transition::Quit => self.quit = true,
        }
    }
}

#[cfg(test)]
mod tests;
