//! The egui side, as widgets that know no state: the profile panel with its plots, and the
//! global UI every state gets (the help window and short messages). A state draws them with
//! what they show, passed in (the simulation's own panel is the simulation state's:
//! `state/simulation/controls.rs`).

pub mod profiler;

use egui::{Align2, Color32, RichText};

/// Messages the UI shows over every state: a short notice, and a recovered internal error.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Notices {
    /// A short message shown until the time given (app seconds), e.g. where a screenshot
    /// went.
    pub toast: Option<(String, f64)>,
    /// The message of a panic the machine recovered from (a bug), shown until dismissed.
    pub crash: Option<String>,
    /// Panics recovered from in this run (for `--stats`).
    pub crashes: u32,
}

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

/// The help window (H, `help_visible`) and the message of the moment, whatever state is on
/// top; `time` is the app's clock, which a toast's deadline is on.
pub fn global_ui(ui: &mut egui::Ui, help_visible: &mut bool, notices: &mut Notices, time: f64) {
    let ctx = ui.ctx().clone();
    if *help_visible {
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
        *help_visible = open;
    }
    if let Some(what) = notices.crash.clone() {
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
                    notices.crash = None;
                }
            });
    }
    if let Some((text, until)) = &notices.toast {
        if time > *until {
            notices.toast = None;
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
