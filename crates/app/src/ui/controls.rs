//! The simulation's side panel (collapsible): scene picker, play/pause/step/restart, live
//! threads, solver settings, gravity, debug drawing and counters; and the bottom profile
//! panel.

use egui::{Color32, RichText};
use glam::Vec2;

use crate::state::{MainMenu, Shared, Simulation, Transition};

/// The simulation's whole UI; records the part of the window the panels leave free.
pub fn simulation_ui(ui: &mut egui::Ui, st: &mut Simulation, shared: &mut Shared) -> Transition {
    let mut transition = Transition::None;
    if shared.ui_visible {
        let mut open = shared.settings.panel_open;
        egui::Panel::left("controls")
            .resizable(true)
            .default_size(280.0)
            .show_collapsible(ui, &mut open, |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| {
                    controls(ui, st, shared, &mut transition);
                });
            });
        if !open {
            egui::Area::new(egui::Id::unique("open-controls"))
                .fixed_pos([8.0, 8.0])
                .show(ui.ctx(), |ui| {
                    if ui.button("Controls").clicked() {
                        open = true;
                    }
                });
        }
        shared.settings.panel_open = open;
        if shared.settings.profile_open {
            egui::Panel::bottom("profile")
                .resizable(true)
                .default_size(220.0)
                .show(ui, |ui| {
                    super::profiler::profile_ui(ui, &st.sim, &mut st.sweep);
                });
        }
    }
    let free = ui.available_rect_before_wrap();
    let ppp = ui.ctx().pixels_per_point();
    shared.view_area = (
        Vec2::new(free.min.x, free.min.y) * ppp,
        Vec2::new(free.max.x, free.max.y) * ppp,
    );
    transition
}

fn controls(ui: &mut egui::Ui, st: &mut Simulation, shared: &mut Shared, out: &mut Transition) {
    ui.heading(&st.sim.scene.name);

    // Scene picker.
    let current = shared.settings.scene.clone();
    let mut pick: Option<String> = None;
    egui::ComboBox::from_id_salt("scene")
        .selected_text(&st.sim.scene.name)
        .width(ui.available_width() - 8.0)
        .show_ui(ui, |ui| {
            for entry in &st.entries {
                if ui
                    .selectable_label(entry.source == current, &entry.label)
                    .on_hover_text(&entry.description)
                    .clicked()
                {
                    pick = Some(entry.source.clone());
                }
            }
        });
    if let Some(source) = pick {
        st.load(&source, shared);
    }
    if let Some(err) = &st.error {
        ui.colored_label(Color32::from_rgb(255, 120, 100), err);
    }

    ui.horizontal_wrapped(|ui| {
        let play = if st.sim.running { "Pause" } else { "Play" };
        if ui.button(play).on_hover_text("Space").clicked() {
            st.toggle_running();
        }
        if ui.button("Step").on_hover_text("S").clicked() {
            st.step_once();
        }
        if ui.button("Restart").on_hover_text("R").clicked() {
            st.sim.restart();
        }
        if ui.button("Fit").on_hover_text("F").clicked() {
            st.fit(shared);
        }
    });

    ui.separator();
    let cores = tumble_physics::default_thread_count().max(1);
    egui::Grid::new("solver")
        .num_columns(2)
        .spacing([8.0, 4.0])
        .show(ui, |ui| {
            ui.label("Threads");
            let mut threads = st.sim.world.thread_count();
            let slider = ui
                .add(egui::Slider::new(&mut threads, 1..=cores))
                .on_hover_text("Worker threads for the step; the result does not change.");
            shared.threads_slider = Some(slider.rect);
            if slider.changed() {
                st.sim.world.set_thread_count(threads);
                shared.settings.threads = threads;
            }
            ui.end_row();

            ui.label("Substeps");
            ui.add(egui::Slider::new(&mut st.sim.substeps, 1..=16));
            ui.end_row();

            let settings = st.sim.world.settings_mut();
            ui.label("Relax iterations");
            ui.add(egui::Slider::new(&mut settings.relax_iterations, 0..=8));
            ui.end_row();

            ui.label("Contact hertz");
            ui.add(egui::Slider::new(&mut settings.contact_hertz, 1.0..=120.0));
            ui.end_row();

            ui.label("Damping ratio");
            ui.add(egui::Slider::new(
                &mut settings.contact_damping_ratio,
                0.0..=20.0,
            ));
            ui.end_row();

            ui.label("Gravity");
            ui.horizontal(|ui| {
                ui.add(
                    egui::DragValue::new(&mut settings.gravity.x)
                        .speed(0.1)
                        .prefix("x "),
                );
                ui.add(
                    egui::DragValue::new(&mut settings.gravity.y)
                        .speed(0.1)
                        .prefix("y "),
                );
            });
            ui.end_row();
        });
    if let Some(note) = &shared.threads_note {
        ui.add(
            egui::Label::new(
                RichText::new(note)
                    .small()
                    .color(Color32::from_rgb(255, 200, 120)),
            )
            .wrap(),
        );
    }
    if ui.button("Scene's settings").clicked() {
        let g = st.sim.scene.gravity;
        let settings = st.sim.world.settings_mut();
        *settings = tumble_physics::StepSettings::default();
        settings.gravity = Vec2::new(g[0], g[1]);
        st.sim.substeps = st.sim.scene.substeps;
    }

    ui.separator();
    ui.label(RichText::new("Debug drawing").strong());
    let d = &mut shared.settings.debug;
    ui.columns(2, |c| {
        c[0].checkbox(&mut d.contacts, "Contacts");
        c[0].checkbox(&mut d.normals, "Normals");
        c[0].checkbox(&mut d.aabbs, "AABBs");
        c[0].checkbox(&mut d.tree, "Tree");
        c[1].checkbox(&mut d.graph_colors, "Graph colours");
        c[1].checkbox(&mut d.center_of_mass, "Centres of mass");
        c[1].checkbox(&mut d.grid, "Grid");
        c[1].checkbox(&mut d.color_by_speed, "Colour by speed");
    });

    ui.separator();
    let p = st.sim.world.profile();
    let recent: Vec<f64> = st.sim.history.iter().map(|s| s.step_ms).collect();
    let recent_mean = if recent.is_empty() {
        0.0
    } else {
        recent.iter().sum::<f64>() / recent.len() as f64
    };
    egui::Grid::new("counters")
        .num_columns(2)
        .striped(true)
        .show(ui, |ui| {
            let mut row = |k: &str, v: String| {
                ui.label(k);
                ui.label(RichText::new(v).monospace());
                ui.end_row();
            };
            row("bodies", st.sim.world.body_count().to_string());
            row(
                "contacts",
                format!("{} ({} touching)", p.contacts, p.touching),
            );
            row(
                "colours",
                format!("{} (+{} overflow)", p.colors, p.overflow),
            );
            row("fps", format!("{:.0}", shared.fps));
            row(
                "ms / step",
                format!(
                    "{:.2} (last {:.0} s: {recent_mean:.2})",
                    p.step_ms,
                    crate::sim::HISTORY_SECONDS
                ),
            );
            row("steps", st.sim.steps.to_string());
            row("time", format!("{:.2} s", st.sim.time()));
            row("backend", shared.backend.clone());
        });

    ui.separator();
    ui.checkbox(&mut shared.settings.profile_open, "Profile panel");
    ui.horizontal(|ui| {
        if ui.button("Help (H)").clicked() {
            shared.help_visible = !shared.help_visible;
        }
        if ui.button("Back to menu").clicked() {
            *out = Transition::Reset(Box::new(MainMenu::new(None)));
        }
    });
}
