//! Input as the states see it, and the global state that sees every input first.
//!
//! Window events are turned into [`InputEvent`]s (keys the viewer uses, pointer buttons,
//! motion and wheel, in physical pixels) so the states and their tests need no window. The
//! [`Global`] state handles the keys that work everywhere (Escape, F1, F12/P, H) before egui or
//! the state on top sees them; see [`crate::state::StateMachine::input`] for the whole route.

use glam::Vec2;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::keyboard::{KeyCode, PhysicalKey};

/// The keys the viewer knows, by position on the keyboard (so they work on any layout).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Key {
    /// Back: pause, resume, leave.
    Escape,
    /// Show or hide all UI.
    F1,
    /// Screenshot.
    F12,
    /// Play or pause.
    Space,
    /// Start (menu) or resume (pause).
    Enter,
    /// Help window.
    H,
    /// Screenshot.
    P,
    /// Restart.
    R,
    /// Single step.
    S,
    /// Fit the scene in view.
    F,
    /// Drop a box at the pointer.
    B,
    /// Drop a ball at the pointer.
    N,
    /// Remove the body under the pointer.
    X,
    /// Remove the body under the pointer, too.
    Delete,
    /// Menu selection up.
    ArrowUp,
    /// Menu selection down; in a played sample, down.
    ArrowDown,
    /// In a played sample: left.
    ArrowLeft,
    /// In a played sample: right.
    ArrowRight,
    /// In a played sample: left.
    A,
    /// In a played sample: right.
    D,
    /// In a played sample: jump.
    W,
    /// Any other key: it still skips the intro.
    Other,
}

/// Pointer buttons.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Button {
    /// Grab a body.
    Left,
    /// Pan.
    Right,
    /// Pan, too.
    Middle,
    /// Anything else.
    Other,
}

/// One input event, in physical pixels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum InputEvent {
    /// A key went down (`pressed`, with `repeat` for auto-repeat) or up.
    Key {
        /// Which key.
        key: Key,
        /// Down or up.
        pressed: bool,
        /// An auto-repeat of a held key.
        repeat: bool,
    },
    /// A pointer button went down or up at `position`.
    Button {
        /// Which button.
        button: Button,
        /// Down or up.
        pressed: bool,
        /// Where the pointer is (pixels, y down).
        position: Vec2,
    },
    /// The pointer moved to `position`; `delta` is the motion since the last event.
    PointerMoved {
        /// Where the pointer is now.
        position: Vec2,
        /// Motion since the last pointer event.
        delta: Vec2,
    },
    /// The wheel turned by `lines` (positive: away from the user) at `position`.
    Wheel {
        /// Lines scrolled (pixel deltas are converted at 40 pixels per line).
        lines: f32,
        /// Where the pointer is.
        position: Vec2,
    },
}

impl InputEvent {
    /// A key press (not a repeat).
    pub fn press(key: Key) -> InputEvent {
        InputEvent::Key {
            key,
            pressed: true,
            repeat: false,
        }
    }

    /// Whether this comes from the keyboard (egui's keyboard focus decides), rather than the
    /// pointer (egui's pointer interest decides).
    pub fn is_keyboard(&self) -> bool {
        matches!(self, InputEvent::Key { .. })
    }

    /// A key or button going down (what skips the intro).
    pub fn is_press(&self) -> bool {
        matches!(
            self,
            InputEvent::Key {
                pressed: true,
                repeat: false,
                ..
            } | InputEvent::Button { pressed: true, .. }
        )
    }
}

/// Turns winit's window events into input events; remembers the pointer position.
#[derive(Clone, Copy, Debug, Default)]
pub struct Translator {
    pointer: Vec2,
}

impl Translator {
    /// The input event for a window event, if it is one the viewer uses.
    pub fn translate(&mut self, event: &WindowEvent) -> Option<InputEvent> {
        match event {
            WindowEvent::KeyboardInput { event, .. } => {
                let key = match event.physical_key {
                    PhysicalKey::Code(code) => key_from_code(code),
                    PhysicalKey::Unidentified(_) => Key::Other,
                };
                Some(InputEvent::Key {
                    key,
                    pressed: event.state == ElementState::Pressed,
                    repeat: event.repeat,
                })
            }
            WindowEvent::MouseInput { state, button, .. } => Some(InputEvent::Button {
                button: match button {
                    MouseButton::Left => Button::Left,
                    MouseButton::Right => Button::Right,
                    MouseButton::Middle => Button::Middle,
                    _ => Button::Other,
                },
                pressed: *state == ElementState::Pressed,
                position: self.pointer,
            }),
            WindowEvent::CursorMoved { position, .. } => {
                let p = Vec2::new(position.x as f32, position.y as f32);
                let delta = p - self.pointer;
                self.pointer = p;
                Some(InputEvent::PointerMoved { position: p, delta })
            }
            WindowEvent::MouseWheel { delta, .. } => {
                let lines = match delta {
                    MouseScrollDelta::LineDelta(_, y) => *y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
                };
                Some(InputEvent::Wheel {
                    lines,
                    position: self.pointer,
                })
            }
            _ => None,
        }
    }
}

fn key_from_code(code: KeyCode) -> Key {
    match code {
        KeyCode::Escape => Key::Escape,
        KeyCode::F1 => Key::F1,
        KeyCode::F12 => Key::F12,
        KeyCode::Space => Key::Space,
        KeyCode::Enter | KeyCode::NumpadEnter => Key::Enter,
        KeyCode::KeyH => Key::H,
        KeyCode::KeyP => Key::P,
        KeyCode::KeyR => Key::R,
        KeyCode::KeyS => Key::S,
        KeyCode::KeyF => Key::F,
        KeyCode::KeyB => Key::B,
        KeyCode::KeyN => Key::N,
        KeyCode::KeyX => Key::X,
        KeyCode::Delete => Key::Delete,
        KeyCode::ArrowUp => Key::ArrowUp,
        KeyCode::ArrowDown => Key::ArrowDown,
        KeyCode::ArrowLeft => Key::ArrowLeft,
        KeyCode::ArrowRight => Key::ArrowRight,
        KeyCode::KeyA => Key::A,
        KeyCode::KeyD => Key::D,
        KeyCode::KeyW => Key::W,
        _ => Key::Other,
    }
}

/// What the global state did with an event.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GlobalOutcome {
    /// Not a global key: egui, then the state on top, may have it.
    Pass,
    /// Handled here; nobody else sees it.
    Consumed,
    /// Escape: the state on top decides what "back" means (pause, resume, leave).
    Back,
}

/// The app-wide toggles the global keys flip (the states and the UI read them).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Toggles {
    /// F1: all UI shown.
    pub ui_visible: bool,
    /// H: the help window.
    pub help_visible: bool,
    /// F12 or P: save the next frame as a PNG.
    pub screenshot_requested: bool,
}

impl Default for Toggles {
    /// UI shown, no help, no screenshot pending.
    fn default() -> Self {
        Toggles {
            ui_visible: true,
            help_visible: false,
            screenshot_requested: false,
        }
    }
}

/// The global state: always active, whatever is on top, and first to see every input.
/// It flips the app-wide [`Toggles`]; it knows nothing of the states.
#[derive(Clone, Debug, Default)]
pub struct Global {
    /// Escape presses seen (all of them, whatever was on top or had focus).
    pub escapes: u64,
}

impl Global {
    /// Handles the keys that work everywhere. `egui_has_keyboard` is whether egui wants the
    /// keyboard (a text field has focus): then letters are typing, not shortcuts, and only the
    /// non-printing keys (Escape, F1, F12) act.
    pub fn handle(
        &mut self,
        event: &InputEvent,
        egui_has_keyboard: bool,
        toggles: &mut Toggles,
    ) -> GlobalOutcome {
        let InputEvent::Key {
            key,
            pressed: true,
            repeat,
        } = *event
        else {
            return GlobalOutcome::Pass;
        };
        match key {
            Key::Escape if !repeat => {
                self.escapes += 1;
                GlobalOutcome::Back
            }
            Key::F1 if !repeat => {
                toggles.ui_visible = !toggles.ui_visible;
                GlobalOutcome::Consumed
            }
            Key::F12 if !repeat => {
                toggles.screenshot_requested = true;
                GlobalOutcome::Consumed
            }
            Key::P if !repeat && !egui_has_keyboard => {
                toggles.screenshot_requested = true;
                GlobalOutcome::Consumed
            }
            Key::H if !repeat && !egui_has_keyboard => {
                toggles.help_visible = !toggles.help_visible;
                GlobalOutcome::Consumed
            }
            _ => GlobalOutcome::Pass,
        }
    }
}
