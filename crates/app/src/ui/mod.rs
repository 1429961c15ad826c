//! The egui side: the simulation's control panel, the profile panel with its plots, and the
//! global UI every state gets (the help window and short messages).

pub mod controls;
pub mod profiler;

use egui::{Align2, Color32, RichText};

use crate::state::{Shared, StateKind};

/// The keys, as the help window lists them.
pub const KEYS: &[(&str, &str)] = &[
    ("Esc", "pause / resume; in the menu: quit"),
    ("F1", "hide / show all UI"),
    ("H", "this help"),
    ("F12 or P", "screenshot (PNG in the working directory)"),
    ("Space", "play / pause"),
    ("S", "single step"),
    ("R", "restart the scene"),
    ("F", "fit the scene in view"),
    ("B", "drop a 0.5 m box at the pointer"),
    ("N", "drop a 0.25 m ball (radius) at the pointer"),
    (
        "X or Delete",
        "remove the body under the pointer (not static ones)",
    ),
    ("Left drag", "pull a body on a spring"),
    ("Right drag", "pan"),
    ("Wheel", "zoom at the pointer"),
];

/// The help window (H) and the message of the moment, whatever state is on top.
pub fn global_ui(ui: &mut egui::Ui, shared: &mut Shared, _top: Option<StateKind>) {
    let ctx = ui.ctx().clone();
    if shared.help_visible {
        let mut open = true;
        egui::Window::new("Help")
            .open(&mut open)
            .resizable(false)
            .collapsible(false)
            .anchor(Align2::RIGHT_TOP, [-12.0, 12.0])
            .show(&ctx, |ui| {
                egui::Grid::new("keys").striped(true).show(ui, |ui| {
                    for (key, what) in KEYS {
                        ui.label(RichText::new(*key).strong());
                        ui.label(*what);
                        ui.end_row();
                    }
                });
            });
        shared.help_visible = open;
    }
    if let Some(what) = shared.crash.clone() {
        egui::Window::new("tumble hit an internal error")
            .resizable(false)
            .collapsible(false)
            .anchor(Align2::CENTER_CENTER, [0.0, 0.0])
            .show(&ctx, |ui| {
                ui.label(RichText::new(&what).monospace());
                ui.label(
                    "This is a bug in tumble. The viewer went back to the menu; what you were \
                     doing is lost. Please report the message above with the scene you ran.",
                );
                if ui.button("OK").clicked() {
                    shared.crash = None;
                }
            });
    }
    if let Some((text, until)) = &shared.toast {
        if shared.time > *until {
            shared.toast = None;
        } else {
            egui::Area::new(egui::Id::unique("toast"))
                .anchor(Align2::CENTER_BOTTOM, [0.0, -24.0])
                .interactable(false)
                .show(&ctx, |ui| {
                    egui::Frame::popup(ui.style()).show(ui, |ui| {
                        ui.label(RichText::new(text).color(Color32::WHITE));
                    });
                });
        }
    }
}
