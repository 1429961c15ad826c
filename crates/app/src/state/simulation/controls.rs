//! The simulation state's side panel (collapsible): scene picker, play/pause/step/restart,
//! live threads, solver settings, gravity, debug drawing and counters; and the bottom profile
//! panel. The state owns what it shows: this module is the state's, and draws the widgets of
//! [`crate::ui`], which know no state.

use egui::{Color32, RichText};
use glam::Vec2;
use tumble_physics::{StepSettings, World};

use crate::state::{MainMenu, Shared, Simulation, Tool, Transition};

/// The simulation's whole UI; records the part of the window the panels leave free.
pub fn simulation_ui(ui: &mut egui::Ui, st: &mut Simulation, shared: &mut Shared) -> Transition {
    let mut transition = Transition::None;
    if shared.toggles.ui_visible {
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
                    crate::ui::profiler::profile_ui(ui, &st.sim, &mut st.sweep);
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

/// The sliders stay in range, but a typed gravity may not be a number the step can use: if
/// the settings the panel left fail [`StepSettings::validate`], puts back `before` (this
/// frame's start) and says why in a toast.
fn keep_valid_settings(world: &mut World, before: StepSettings, shared: &mut Shared) {
    if let Err(e) = world.settings().validate() {
        *world.settings_mut() = before;
        shared.toast(e.to_string());
    }
}

fn controls(ui: &mut egui::Ui, st: &mut Simulation, shared: &mut Shared, out: &mut Transition) {
    ui.heading(&st.sim.scene.name);

    // Scene picker.
    let current = shared.settings.scene.clone();
    let mut pick: Option<String> = None;
    egui::ComboBox::from_id_salt("scene")
        .selected_text(&st.sim.scene.name)
        .width(ui.available_width() - 8.0)
        .height(480.0)
        .show_ui(ui, |ui| {
            let mut category = None;
            for entry in &st.entries {
                if category != Some(entry.category) {
                    category = Some(entry.category);
                    ui.label(RichText::new(entry.category.name()).small().strong());
                }
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

    sample_ui(ui, st);

    ui.separator();
    let cores = tumble_physics::default_thread_count().max(1);
    let before = *st.sim.world.settings();
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
            ui.add(egui::Slider::new(&mut settings.relax_iterations, 1..=8))
                .on_hover_text("Friction is solved in the relax pass, so there is at least one.");
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

            ui.label("Manifold points");
            ui.checkbox(&mut settings.solve_points_together, "solved together")
                .on_hover_text(
                    "Solve a contact's two points from the same velocities where they are well \
                     apart: a body dropped flat lands straight. Off: one after the other, as \
                     Box2D v3 does, and the first point takes the whole impact.",
                );
            ui.end_row();

            ui.label("Restitution threshold");
            ui.add(
                egui::Slider::new(&mut settings.restitution_threshold, 0.0..=2.0).suffix(" m/s"),
            )
            .on_hover_text("Slower approaches do not bounce.");
            ui.end_row();

            ui.label("Impacts");
            ui.checkbox(&mut settings.impacts_bounce, "bounce as restitution says")
                .on_hover_text(
                    "The threshold only for contacts already pushing, so an impact bounces \
                     however slowly it arrives and a body at rest does not jitter; the \
                     passes repeat until every bounce holds. Off: Box2D v3's rule, every \
                     approach slower than the threshold inelastic, and exactly the passes \
                     below.",
                );
            ui.end_row();

            ui.label("Restitution passes");
            ui.add(egui::Slider::new(
                &mut settings.restitution_iterations,
                1..=32,
            ))
            .on_hover_text(
                "Exactly this many; more keep bounces elastic when a body hits two others \
                     in one step. With impacts bouncing, passes until the bounces hold, at most \
                     16 (or this, if more).",
            );
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
    keep_valid_settings(&mut st.sim.world, before, shared);
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
        st.sim.scene.solver.apply(settings);
        st.sim.substeps = st.sim.scene.substeps;
    }

    ui.separator();
    replay_ui(ui, st, shared);

    ui.separator();
    tools_ui(ui, st);

    ui.separator();
    events_ui(ui, st);

    ui.separator();
    ui.label(RichText::new("Debug drawing").strong());
    let d = &mut shared.settings.debug;
    ui.columns(2, |c| {
        c[0].checkbox(&mut d.contacts, "Contacts");
        c[0].checkbox(&mut d.normals, "Normals")
            .on_hover_text("Contact normals, and the side each chain segment pushes towards.");
        c[0].checkbox(&mut d.aabbs, "AABBs");
        c[0].checkbox(&mut d.tree, "Tree");
        c[0].checkbox(&mut d.islands, "Islands")
            .on_hover_text("Dynamic bodies coloured by their island (sleeping ones faded).");
        c[1].checkbox(&mut d.graph_colors, "Graph colours");
        c[1].checkbox(&mut d.center_of_mass, "Centres of mass");
        c[1].checkbox(&mut d.grid, "Grid");
        c[1].checkbox(&mut d.color_by_speed, "Colour by speed");
        c[1].checkbox(&mut d.joint_forces, "Joint forces")
            .on_hover_text(
                "Each joint's reaction force on its second body (1 px per newton, \
                            capped), from the last step.",
            );
    });

    ui.separator();
    let p = st.sim.world.profile();
    let recent: Vec<f64> = st.sim.history.iter().map(|s| s.step_ms).collect();
    let recent_mean = if recent.is_empty() {
        0.0
    } else {
        recent.iter().sum::<f64>() / recent.len() as f64
    };
    let m = &st.sim.metrics;
    // The error bought at these settings, beside what they cost (ms / step).
    let case = m.case_row().map(|(name, text, pass)| {
        let colour = if pass {
            Color32::from_rgb(140, 220, 140)
        } else {
            Color32::from_rgb(255, 170, 90)
        };
        (name, RichText::new(text).monospace().color(colour))
    });
    let world = &st.sim.world;
    let (islands, awake_islands) = world.island_counts();
    let rows = [
        ("bodies", world.body_count().to_string()),
        ("awake bodies", world.awake_body_count().to_string()),
        ("islands", format!("{awake_islands} awake / {islands}")),
        (
            "contacts",
            format!("{} ({} touching)", p.contacts, p.touching),
        ),
        (
            "colours",
            format!("{} (+{} overflow)", p.colors, p.overflow),
        ),
        // Fewer than the threads where the solve is too small to share, or where sharing it
        // was timed and did not pay on this machine (`WideThresholds::solve_by_payoff`).
        (
            "solver workers",
            format!(
                "{} of {} threads{}",
                p.solver_workers,
                world.thread_count(),
                if p.solver_probe {
                    " (timing the other way)"
                } else {
                    ""
                }
            ),
        ),
        ("fps", format!("{:.0}", shared.fps)),
        (
            "ms / step",
            format!(
                "{:.2} (last {:.0} s: {recent_mean:.2})",
                p.step_ms,
                crate::sim::HISTORY_SECONDS
            ),
        ),
    ];
    let error_rows = [
        (
            "deepest overlap",
            format!("{:.1} mm", 1000.0 * m.deepest_overlap),
        ),
        ("kinetic energy", format!("{:.3} J", m.energy)),
        ("steps", st.sim.steps.to_string()),
        ("time", format!("{:.2} s", st.sim.time())),
        ("backend", shared.backend.clone()),
    ];
    // Bodies the NaN guard stopped since the scene started (0 unless something is broken):
    // such a body freezes where it was, so only this count tells.
    let stopped = st.sim.world.non_finite_bodies();
    let mut stopped_text = RichText::new(stopped.to_string()).monospace();
    if stopped > 0 {
        stopped_text = stopped_text.color(Color32::from_rgb(255, 120, 90));
    }
    let stopped_row = ("non-finite stopped", stopped_text);
    egui::Grid::new("counters")
        .num_columns(2)
        .striped(true)
        .show(ui, |ui| {
            let plain = |(k, v): (&'static str, String)| (k, RichText::new(v).monospace());
            let all = rows
                .into_iter()
                .map(plain)
                .chain(std::iter::once(stopped_row))
                .chain(case)
                .chain(error_rows.into_iter().map(plain));
            for (k, v) in all {
                ui.label(k);
                ui.label(v);
                ui.end_row();
            }
        });

    ui.separator();
    ui.checkbox(&mut shared.settings.profile_open, "Profile panel");
    ui.horizontal(|ui| {
        if ui.button("Help (H)").clicked() {
            shared.toggles.help_visible = !shared.toggles.help_visible;
        }
        if ui.button("Back to menu").clicked() {
            *out = Transition::Reset(Box::new(MainMenu::new(None)));
        }
    });
}

/// What a left drag does, and what the ray tool's ray hits.
/// A played sample: the keys it reads (shown while it runs) and what its controller says
/// (the platformer's coins, flag, footing).
fn sample_ui(ui: &mut egui::Ui, st: &Simulation) {
    let keys = tumble_scene::builtin::keys(&st.sim.scene.name);
    let Some(controller) = &st.sim.controller else {
        return;
    };
    ui.separator();
    ui.label(RichText::new("Play").strong());
    crate::state::main_menu::keys_ui(ui, keys);
    for line in controller.status() {
        ui.label(line);
    }
    if st.sim.key_script.is_some() {
        ui.label(RichText::new("Keys scripted (--keys)").small().weak());
    }
}

fn tools_ui(ui: &mut egui::Ui, st: &mut Simulation) {
    ui.horizontal(|ui| {
        ui.label(RichText::new("Left drag").strong());
        ui.radio_value(&mut st.tool, Tool::Grab, "pulls a body");
        ui.radio_value(&mut st.tool, Tool::Ray, "casts a ray")
            .on_hover_text(
                "Drag out a ray: every shape it passes is marked where it enters, with its \
                 normal; the nearest in red.",
            );
    });
    if st.tool != Tool::Ray {
        return;
    }
    let Some((from, to)) = st.sim.ray else {
        ui.label("Drag in the world to cast a ray.");
        return;
    };
    let hits = st
        .sim
        .world
        .cast_ray_all(from, to - from, &tumble_physics::QueryFilter::default());
    match hits.first() {
        Some(hit) => {
            ui.label(
                RichText::new(format!(
                    "{} hits; nearest: body {} (part {}) at ({:.2}, {:.2}), {:.0}% along, \
                     normal ({:.2}, {:.2})",
                    hits.len(),
                    hit.shape.body.index,
                    hit.shape.part,
                    hit.point.x,
                    hit.point.y,
                    100.0 * hit.fraction,
                    hit.normal.x,
                    hit.normal.y
                ))
                .monospace(),
            );
        }
        None => {
            ui.label("The ray hits nothing.");
        }
    }
    if ui.button("Clear the ray").clicked() {
        st.sim.ray = None;
    }
}

/// The event log: counts since the scene started, and the last events of the kinds ticked,
/// newest first.
fn events_ui(ui: &mut egui::Ui, st: &mut Simulation) {
    const KINDS: [&str; 6] = ["begin", "end", "hit", "sensor in", "sensor out", "joint"];
    egui::CollapsingHeader::new(RichText::new("Events").strong())
        .id_salt("events")
        .show(ui, |ui| {
            let counts = st.sim.events.counts;
            ui.horizontal_wrapped(|ui| {
                for (k, name) in KINDS.iter().enumerate() {
                    ui.checkbox(&mut st.event_filter[k], format!("{name} {}", counts[k]));
                }
            });
            egui::ScrollArea::vertical()
                .id_salt("event-log")
                .max_height(160.0)
                .show(ui, |ui| {
                    let shown = st
                        .sim
                        .events
                        .entries
                        .iter()
                        .rev()
                        .filter(|(_, e)| st.event_filter[crate::sim::EventLog::kind(e)])
                        .take(60);
                    for (step, event) in shown {
                        ui.label(RichText::new(event_line(*step, event)).monospace());
                    }
                });
        });
}

/// One line of the event log.
fn event_line(step: u64, event: &tumble_physics::Event) -> String {
    let mut line = match (event, event.shapes()) {
        (_, Some([a, b])) => format!(
            "{step:>6} {:<13} {}.{} {}.{}",
            event.name(),
            a.body.index,
            a.part,
            b.body.index,
            b.part
        ),
        (
            tumble_physics::Event::JointThreshold {
                joint,
                force,
                torque,
            },
            None,
        ) => format!(
            "{step:>6} {:<13} joint {} {force:.0} N {torque:.0} N·m",
            event.name(),
            joint.index
        ),
        (_, None) => format!("{step:>6} {}", event.name()),
    };
    if let tumble_physics::Event::Hit { approach_speed, .. } = event {
        line.push_str(&format!(" {approach_speed:.1} m/s"));
    }
    line
}

/// Replay of the last seconds, and save / load of the whole world.
fn replay_ui(ui: &mut egui::Ui, st: &mut Simulation, shared: &mut Shared) {
    ui.label(RichText::new("Replay and snapshots").strong());
    let dt = f64::from(st.sim.scene.dt);
    ui.horizontal_wrapped(|ui| {
        if let Some(replay) = st.sim.replay {
            ui.label(format!(
                "replaying {:.1} of {:.1} s",
                (st.sim.steps - replay.from) as f64 * dt,
                (replay.until - replay.from) as f64 * dt
            ));
            if ui
                .button("Stop replay")
                .on_hover_text("Go on live from here; the recorded rest is dropped.")
                .clicked()
            {
                st.sim.stop_replay();
            }
        } else {
            let seconds = st.sim.recording.seconds(st.sim.scene.dt);
            let replay = ui
                .add_enabled(
                    seconds > 0.0,
                    egui::Button::new(format!("Replay last {seconds:.0} s")),
                )
                .on_hover_text(
                    "Go back and play the last seconds again, mouse included; it ends exactly \
                     where the run was.",
                );
            if replay.clicked() && st.sim.start_replay() {
                st.sim.running = true;
            }
        }
    });
    ui.horizontal_wrapped(|ui| {
        if ui
            .button("Save snapshot")
            .on_hover_text("The whole world, to go back to (natively also tumble-snapshot.json).")
            .clicked()
        {
            st.save_snapshot(shared);
        }
        if ui
            .button("Load snapshot")
            .on_hover_text("Back to the saved world; it goes on exactly as it would have.")
            .clicked()
        {
            st.load_snapshot(shared);
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::settings::Settings;

    #[test]
    fn settings_the_step_cannot_use_are_put_back_with_a_message() {
        let mut shared = Shared::new(Settings::default(), Vec2::new(800.0, 600.0));
        let mut world = World::new(StepSettings::default());
        let before = *world.settings();
        // A usable change stays.
        world.settings_mut().gravity.y = -3.0;
        keep_valid_settings(&mut world, before, &mut shared);
        assert_eq!(world.settings().gravity.y, -3.0);
        assert!(shared.notices.toast.is_none());
        // A gravity typed as "inf" does not.
        let before = *world.settings();
        world.settings_mut().gravity.x = f32::INFINITY;
        keep_valid_settings(&mut world, before, &mut shared);
        assert_eq!(*world.settings(), before);
        let (text, _) = shared.notices.toast.expect("a message");
        assert!(text.contains("`gravity`"), "{text}");
    }
}
