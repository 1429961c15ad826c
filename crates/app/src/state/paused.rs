//! The pause state: drawn over the simulation, which stays visible, frozen and dimmed.
//! Resume (Escape, Space, Enter), restart (R), or go back to the menu.

use egui::{Align2, Color32, Id, LayerId, Order};

use super::{MainMenu, Shared, Signal, State, StateKind, Transition};
use crate::input::{InputEvent, Key};

/// The pause state. It owns nothing: the simulation below keeps its own data.
#[derive(Debug, Default)]
pub struct Paused;

impl Paused {
    /// A pause overlay.
    pub fn new() -> Self {
        Self
    }
}

impl State for Paused {
    fn kind(&self) -> StateKind {
        StateKind::Paused
    }

    fn is_overlay(&self) -> bool {
        true
    }

    fn on_back(&mut self, _shared: &mut Shared) -> Transition {
        Transition::Pop
    }

    fn on_input(&mut self, event: &InputEvent, _shared: &mut Shared) -> Transition {
        match *event {
            InputEvent::Key {
                key: Key::Space | Key::Enter,
                pressed: true,
                repeat: false,
            } => Transition::Pop,
            InputEvent::Key {
                key: Key::R,
                pressed: true,
                repeat: false,
            } => Transition::PopWith(Signal::Restart),
            _ => Transition::None,
        }
    }

    fn ui(&mut self, ui: &mut egui::Ui, _shared: &mut Shared) -> Transition {
        let ctx = ui.ctx().clone();
        // Dim everything drawn so far (the world); the window below goes on top.
        ctx.layer_painter(LayerId::new(Order::Background, Id::unique("pause-dim")))
            .rect_filled(ctx.content_rect(), 0.0, Color32::from_black_alpha(150));
        let mut transition = Transition::None;
        egui::Window::new("Paused")
            .resizable(false)
            .collapsible(false)
            .anchor(Align2::CENTER_CENTER, [0.0, 0.0])
            .show(&ctx, |ui| {
                ui.set_min_width(220.0);
                ui.vertical_centered_justified(|ui| {
                    if ui.button("Resume (Esc)").clicked() {
                        transition = Transition::Pop;
                    }
                    if ui.button("Restart (R)").clicked() {
                        transition = Transition::PopWith(Signal::Restart);
                    }
                    if ui.button("Back to menu").clicked() {
                        transition = Transition::Reset(Box::new(MainMenu::new(None)));
                    }
                });
            });
        transition
    }
}
