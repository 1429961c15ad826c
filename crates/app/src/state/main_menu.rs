//! The main menu: pick a scene (each with its description), start it, change settings, quit.
//! The intro's simulation keeps running behind it, dimmed.

use std::path::{Path, PathBuf};

use egui::{Align2, Color32, RichText};

use super::intro::Backdrop;
use super::{Shared, Simulation, State, StateKind, Transition, View};
use crate::input::{InputEvent, Key};
use crate::sim::Sim;
use tumble_scene::sample::Category;

/// One scene the menu offers.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneEntry {
    /// Shown in the list.
    pub label: String,
    /// What `tumble_scene::load` takes: a built-in name or a file path.
    pub source: String,
    /// Shown beside the list.
    pub description: String,
    /// Where the sample browser lists it.
    pub category: Category,
    /// The keys it reads and what each does (a sample a person plays).
    pub keys: &'static [(&'static str, &'static str)],
}

impl SceneEntry {
    /// Whether the search `query` (lower case) finds it: in its name, description or
    /// category.
    pub fn matches(&self, query: &str) -> bool {
        query.is_empty()
            || self.label.to_lowercase().contains(query)
            || self.description.to_lowercase().contains(query)
            || self.category.name().to_lowercase().contains(query)
    }
}

/// The built-in scenes by category (in [`Category::ALL`]'s order, each in the built-ins'
/// order), then the scene files of `assets/scenes` (looked up in the working directory, then
/// in the source tree this binary was built from).
pub fn scene_entries() -> Vec<SceneEntry> {
    let mut entries: Vec<SceneEntry> = tumble_scene::builtin::names()
        .iter()
        .map(|&name| SceneEntry {
            label: name.to_string(),
            source: name.to_string(),
            description: tumble_scene::builtin::describe(name)
                .unwrap_or("")
                .to_string(),
            category: tumble_scene::builtin::category(name).unwrap_or(Category::Files),
            keys: tumble_scene::builtin::keys(name),
        })
        .collect();
    let rank = |c: Category| Category::ALL.iter().position(|&a| a == c);
    // Stable: each category keeps the built-ins' order.
    entries.sort_by_key(|e| rank(e.category));
    let dirs = [
        PathBuf::from("assets/scenes"),
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/scenes"),
    ];
    if let Some(dir) = dirs.iter().find(|d| d.is_dir()) {
        let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
            .map(|rd| rd.filter_map(|e| e.ok().map(|e| e.path())).collect())
            .unwrap_or_default();
        files.retain(|p| matches!(p.extension().and_then(|e| e.to_str()), Some("ron" | "json")));
        files.sort();
        for path in files {
            let file = path
                .file_name()
                .map(|f| f.to_string_lossy().into_owned())
                .unwrap_or_default();
            entries.push(SceneEntry {
                label: file.clone(),
                source: path.to_string_lossy().into_owned(),
                description: format!("A scene file: {}.", path.display()),
                category: Category::Files,
                keys: &[],
            });
        }
    }
    entries
}

/// The main menu state.
pub struct MainMenu {
    backdrop: Option<Backdrop>,
    entries: Vec<SceneEntry>,
    selected: usize,
    settings_open: bool,
    error: Option<String>,
    /// The search box's text.
    search: String,
}

impl MainMenu {
    /// A menu over `backdrop` (the intro's simulation), or over a new one when `None`.
    pub fn new(backdrop: Option<Backdrop>) -> Self {
        Self {
            backdrop,
            entries: scene_entries(),
            selected: 0,
            settings_open: false,
            error: None,
            search: String::new(),
        }
    }

    /// The entry the list has selected.
    pub fn selected(&self) -> Option<&SceneEntry> {
        self.entries.get(self.selected)
    }

    /// Starts the selected scene: the simulation replaces the menu.
    pub fn start(&mut self, shared: &mut Shared) -> Transition {
        let Some(entry) = self.selected().cloned() else {
            return Transition::None;
        };
        match Sim::load(&entry.source, shared.settings.threads) {
            Ok(sim) => {
                shared.settings.scene = entry.source.clone();
                Transition::Replace(Box::new(Simulation::new(sim, shared)))
            }
            Err(e) => {
                self.error = Some(format!("{e:#}"));
                Transition::None
            }
        }
    }

    /// The entries the search leaves, by their place in the list.
    fn visible(&self) -> Vec<usize> {
        let query = self.search.trim().to_lowercase();
        (0..self.entries.len())
            .filter(|&i| self.entries[i].matches(&query))
            .collect()
    }

    /// Moves the selection `by` places among the visible entries (wrapping).
    fn step_selection(&mut self, by: isize) {
        let visible = self.visible();
        if visible.is_empty() {
            return;
        }
        let n = visible.len() as isize;
        let at = visible.iter().position(|&i| i == self.selected);
        let next = match at {
            Some(k) => (k as isize + by).rem_euclid(n),
            None => 0,
        };
        self.selected = visible[next as usize];
    }

    fn select_source(&mut self, source: &str) {
        if let Some(i) = self.entries.iter().position(|e| e.source == source) {
            self.selected = i;
        }
    }
}

impl State for MainMenu {
    fn kind(&self) -> StateKind {
        StateKind::MainMenu
    }

    fn on_back(&mut self, _shared: &mut Shared) -> Transition {
        Transition::Quit
    }

    fn on_input(&mut self, event: &InputEvent, shared: &mut Shared) -> Transition {
        let InputEvent::Key {
            key, pressed: true, ..
        } = *event
        else {
            return Transition::None;
        };
        match key {
            Key::ArrowUp => self.step_selection(-1),
            Key::ArrowDown => self.step_selection(1),
            Key::Enter => return self.start(shared),
            _ => {}
        }
        Transition::None
    }

    fn update(&mut self, frame_seconds: f64, shared: &mut Shared) -> Transition {
        if self.backdrop.is_none() {
            self.backdrop = Backdrop::new(shared.settings.threads);
            let last = shared.settings.scene.clone();
            self.select_source(&last);
        }
        if let Some(b) = &mut self.backdrop {
            b.update(frame_seconds, shared);
        }
        Transition::None
    }

    fn ui(&mut self, ui: &mut egui::Ui, shared: &mut Shared) -> Transition {
        let mut transition = Transition::None;
        let mut start_now = false;
        let ctx = ui.ctx().clone();
        let size = ctx.content_rect().size();
        let width = (size.x * 0.7).clamp(320.0, 760.0);
        let height = (size.y * 0.6).clamp(240.0, 460.0);
        egui::Window::new("tumble")
            .title_bar(false)
            .resizable(false)
            .collapsible(false)
            .anchor(Align2::CENTER_CENTER, [0.0, 0.0])
            .fixed_size([width, height])
            .show(&ctx, |ui| {
                ui.vertical_centered(|ui| {
                    ui.label(RichText::new("tumble").size(36.0).strong());
                    ui.label("Pick a sample: Up and Down choose, Enter starts; type to search.");
                });
                ui.separator();
                ui.columns(2, |cols| {
                    let ui = &mut cols[0];
                    let search = ui.add(
                        egui::TextEdit::singleline(&mut self.search)
                            .hint_text("Search samples")
                            .desired_width(f32::INFINITY),
                    );
                    if search.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter)) {
                        start_now = !self.visible().is_empty();
                    }
                    if search.changed() {
                        let visible = self.visible();
                        if !visible.contains(&self.selected)
                            && let Some(&first) = visible.first()
                        {
                            self.selected = first;
                        }
                    }
                    let visible = self.visible();
                    let searching = !self.search.trim().is_empty();
                    egui::ScrollArea::vertical()
                        .id_salt("scenes")
                        .max_height(height - 150.0)
                        .show(ui, |ui| {
                            if visible.is_empty() {
                                ui.label("Nothing matches.");
                            }
                            for category in Category::ALL {
                                let members: Vec<usize> = visible
                                    .iter()
                                    .copied()
                                    .filter(|&i| self.entries[i].category == category)
                                    .collect();
                                if members.is_empty() {
                                    continue;
                                }
                                let holds_selected = members.contains(&self.selected);
                                egui::CollapsingHeader::new(format!(
                                    "{} ({})",
                                    category.name(),
                                    members.len()
                                ))
                                .id_salt(category.name())
                                .default_open(true)
                                .open((searching || holds_selected).then_some(true))
                                .show(ui, |ui| {
                                    for i in members {
                                        let entry = &self.entries[i];
                                        let r =
                                            ui.selectable_label(i == self.selected, &entry.label);
                                        if r.clicked() {
                                            self.selected = i;
                                            self.error = None;
                                        }
                                        if r.double_clicked() {
                                            self.selected = i;
                                            start_now = true;
                                        }
                                    }
                                });
                            }
                        });
                    let ui = &mut cols[1];
                    if let Some(entry) = self.entries.get(self.selected) {
                        ui.heading(&entry.label);
                        ui.label(RichText::new(entry.category.name()).small().weak());
                        ui.label(&entry.description);
                        keys_ui(ui, entry.keys);
                    }
                    ui.add_space(12.0);
                    if let Some(err) = &self.error {
                        ui.colored_label(Color32::from_rgb(255, 120, 100), err);
                    }
                    ui.add_space(8.0);
                    let start = ui.add_sized([140.0, 32.0], egui::Button::new("Start"));
                    let settings = ui.add_sized([140.0, 28.0], egui::Button::new("Settings"));
                    let quit = ui.add_sized([140.0, 28.0], egui::Button::new("Quit"));
                    if settings.clicked() {
                        self.settings_open = !self.settings_open;
                    }
                    if quit.clicked() {
                        transition = Transition::Quit;
                    }
                    if start.clicked() {
                        start_now = true;
                    }
                    if self.settings_open {
                        ui.separator();
                        settings_ui(ui, shared);
                    }
                });
            });
        if start_now {
            transition = self.start(shared);
        }
        transition
    }

    fn view(&self) -> Option<View<'_>> {
        self.backdrop.as_ref().map(|b| b.view(0.55))
    }

    fn sim(&self) -> Option<&Sim> {
        self.backdrop.as_ref().map(|b| &b.sim)
    }
}

/// The keys a sample reads, as a small table (nothing for a sample that reads none).
pub fn keys_ui(ui: &mut egui::Ui, keys: &[(&str, &str)]) {
    if keys.is_empty() {
        return;
    }
    ui.add_space(4.0);
    egui::Grid::new("sample-keys")
        .num_columns(2)
        .show(ui, |ui| {
            for (key, what) in keys {
                ui.label(RichText::new(*key).strong());
                ui.label(*what);
                ui.end_row();
            }
        });
}

/// The settings the menu offers (they persist).
fn settings_ui(ui: &mut egui::Ui, shared: &mut Shared) {
    let cores = tumble_physics::default_thread_count();
    let mut threads = if shared.settings.threads == 0 {
        cores
    } else {
        shared.settings.threads
    };
    ui.horizontal(|ui| {
        ui.label("Threads at start");
        if ui
            .add(egui::Slider::new(&mut threads, 1..=cores.max(1)))
            .changed()
        {
            shared.settings.threads = threads;
        }
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
    ui.checkbox(&mut shared.settings.vsync, "Vsync (applies at next start)");
    ui.checkbox(&mut shared.settings.debug.grid, "Metre grid");
    if ui.button("Reset all settings").clicked() {
        shared.settings = crate::settings::Settings::default();
    }
}
