//! Transitions and input routing, with the real states and no window.

use glam::Vec2;

use super::*;
use crate::input::{Button, InputEvent, Key};
use crate::settings::Settings;

fn shared() -> Shared {
    let mut s = Shared::new(Settings::default(), Vec2::new(800.0, 600.0));
    s.settings.threads = 1;
    s
}

const NO_EGUI: EguiWants = EguiWants {
    pointer: false,
    keyboard: false,
};
const EGUI_KEYBOARD: EguiWants = EguiWants {
    pointer: false,
    keyboard: true,
};
const EGUI_POINTER: EguiWants = EguiWants {
    pointer: true,
    keyboard: false,
};

fn press(key: Key) -> InputEvent {
    InputEvent::press(key)
}

fn simulation(shared: &Shared) -> StateMachine {
    let sim = crate::sim::Sim::load("pyramid", 1).unwrap();
    StateMachine::new(Box::new(Simulation::new(sim, shared)))
}

fn steps(machine: &StateMachine) -> u64 {
    machine.sim().expect("a simulation state").steps
}

#[test]
fn intro_skips_to_the_menu_on_any_key_or_click_or_after_a_while() {
    let mut sh = shared();
    let mut m = StateMachine::new(Box::new(Intro::new(&sh)));
    assert_eq!(m.top_kind(), Some(StateKind::Intro));
    assert_eq!(m.input(press(Key::Other), NO_EGUI, &mut sh), Routed::State);
    assert_eq!(m.kinds(), vec![StateKind::MainMenu]);

    let mut m = StateMachine::new(Box::new(Intro::new(&sh)));
    let click = InputEvent::Button {
        button: Button::Left,
        pressed: true,
        position: Vec2::new(10.0, 10.0),
    };
    m.input(click, NO_EGUI, &mut sh);
    assert_eq!(m.kinds(), vec![StateKind::MainMenu]);

    let mut m = StateMachine::new(Box::new(Intro::new(&sh)));
    let mut t = 0.0;
    while t < intro::INTRO_SECONDS + 0.1 {
        m.update(1.0 / 60.0, &mut sh);
        t += 1.0 / 60.0;
    }
    assert_eq!(m.kinds(), vec![StateKind::MainMenu]);
    // The menu kept the intro's simulation running behind it.
    assert!(m.view().is_some());
}

#[test]
fn menu_starts_the_selected_scene_and_escape_quits() {
    let mut sh = shared();
    let mut m = StateMachine::new(Box::new(MainMenu::new(None)));
    // The samples by category, the characters first: Down picks the second.
    let second = main_menu::scene_entries()[1].source.clone();
    assert_eq!(second, "forces");
    m.input(press(Key::ArrowDown), NO_EGUI, &mut sh);
    m.input(press(Key::Enter), NO_EGUI, &mut sh);
    assert_eq!(m.kinds(), vec![StateKind::Simulation]);
    assert_eq!(sh.settings.scene, second);
    assert_eq!(m.sim().unwrap().scene.name, second);

    let mut m = StateMachine::new(Box::new(MainMenu::new(None)));
    assert!(!m.should_quit());
    m.input(press(Key::Escape), NO_EGUI, &mut sh);
    assert!(m.should_quit());
}

#[test]
fn escape_pauses_and_resumes_and_the_paused_world_is_frozen_but_drawn() {
    let mut sh = shared();
    let mut m = simulation(&sh);
    m.update(0.1, &mut sh);
    let before = steps(&m);
    assert!(before > 0);

    m.input(press(Key::Escape), NO_EGUI, &mut sh);
    assert_eq!(m.kinds(), vec![StateKind::Simulation, StateKind::Paused]);
    for _ in 0..10 {
        m.update(0.1, &mut sh);
    }
    assert_eq!(steps(&m), before, "the world under the pause must not move");
    // The pause shows no world of its own: the simulation under it is drawn.
    assert_eq!(m.view().map(|v| v.sim.steps), Some(before));

    m.input(press(Key::Escape), NO_EGUI, &mut sh);
    assert_eq!(m.kinds(), vec![StateKind::Simulation]);
    m.update(0.1, &mut sh);
    assert!(steps(&m) > before);
}

#[test]
fn pause_restart_and_back_to_menu() {
    let mut sh = shared();
    let mut m = simulation(&sh);
    m.update(0.1, &mut sh);
    m.input(press(Key::Escape), NO_EGUI, &mut sh);
    m.input(press(Key::R), NO_EGUI, &mut sh);
    assert_eq!(m.kinds(), vec![StateKind::Simulation]);
    assert_eq!(steps(&m), 0, "restart rebuilt the world");

    m.input(press(Key::Escape), NO_EGUI, &mut sh);
    m.apply(Transition::Reset(Box::new(MainMenu::new(None))), &mut sh);
    assert_eq!(m.kinds(), vec![StateKind::MainMenu]);
}

#[test]
fn global_state_sees_escape_in_every_state_even_when_egui_has_the_keyboard() {
    let mut sh = shared();
    let mut m = StateMachine::new(Box::new(Intro::new(&sh)));
    // Intro → menu.
    assert_eq!(
        m.input(press(Key::Escape), EGUI_KEYBOARD, &mut sh),
        Routed::Global
    );
    assert_eq!(m.top_kind(), Some(StateKind::MainMenu));
    // Simulation → pause → simulation, with a text field focused all along.
    let mut m2 = simulation(&sh);
    m2.global = m.global.clone();
    assert_eq!(
        m2.input(press(Key::Escape), EGUI_KEYBOARD, &mut sh),
        Routed::Global
    );
    assert_eq!(m2.top_kind(), Some(StateKind::Paused));
    assert_eq!(
        m2.input(press(Key::Escape), EGUI_KEYBOARD, &mut sh),
        Routed::Global
    );
    assert_eq!(m2.top_kind(), Some(StateKind::Simulation));
    assert_eq!(m2.global.escapes, 3);
    // Menu → quit.
    m.input(press(Key::Escape), EGUI_KEYBOARD, &mut sh);
    assert!(m.should_quit());
}

#[test]
fn the_simulation_never_sees_keys_egui_consumed() {
    let mut sh = shared();
    let mut m = simulation(&sh);
    let running = m.sim().unwrap().running;
    // Typing a space into a text field.
    assert_eq!(
        m.input(press(Key::Space), EGUI_KEYBOARD, &mut sh),
        Routed::Egui
    );
    assert_eq!(m.sim().unwrap().running, running);
    // Typing "s": no single step either.
    assert_eq!(m.input(press(Key::S), EGUI_KEYBOARD, &mut sh), Routed::Egui);
    assert_eq!(steps(&m), 0);
    // Typing "p": no screenshot.
    assert_eq!(m.input(press(Key::P), EGUI_KEYBOARD, &mut sh), Routed::Egui);
    assert!(!sh.toggles.screenshot_requested);
    // The same keys with no text field focused reach the simulation.
    assert_eq!(m.input(press(Key::Space), NO_EGUI, &mut sh), Routed::State);
    assert_eq!(m.sim().unwrap().running, !running);
    m.input(press(Key::S), NO_EGUI, &mut sh);
    assert_eq!(steps(&m), 1);
    assert_eq!(m.input(press(Key::P), NO_EGUI, &mut sh), Routed::Global);
    assert!(sh.toggles.screenshot_requested);
}

#[test]
fn pointer_over_a_panel_does_not_grab_bodies_but_releases_always_arrive() {
    let mut sh = shared();
    let mut m = simulation(&sh);
    m.update(0.0, &mut sh); // frames the scene
    // The pyramid's lowest box, on screen.
    let Some(View { sim, camera, .. }) = m.view() else {
        panic!("no view");
    };
    let (body, view) = sim
        .world
        .bodies()
        .find(|(_, b)| b.kind == tumble_physics::BodyKind::Dynamic)
        .unwrap();
    let at = camera.world_to_screen(view.position);
    let down = InputEvent::Button {
        button: Button::Left,
        pressed: true,
        position: at,
    };
    let up = InputEvent::Button {
        button: Button::Left,
        pressed: false,
        position: at,
    };
    assert_eq!(m.input(down, EGUI_POINTER, &mut sh), Routed::Egui);
    assert!(m.sim().unwrap().drag.is_none());
    assert_eq!(m.input(down, NO_EGUI, &mut sh), Routed::State);
    assert_eq!(m.sim().unwrap().drag.map(|d| d.body), Some(body));
    // Let go over a panel: the drag still ends.
    assert_eq!(m.input(up, EGUI_POINTER, &mut sh), Routed::State);
    assert!(m.sim().unwrap().drag.is_none());
}

#[test]
fn keys_drop_and_remove_bodies_at_the_pointer() {
    let mut sh = shared();
    let mut m = simulation(&sh);
    m.update(0.0, &mut sh); // frames the scene
    let (camera, bodies) = {
        let View { sim, camera, .. } = m.view().expect("a view");
        (*camera, sim.world.body_count())
    };
    let live = |m: &StateMachine| m.sim().unwrap().world.body_count();
    let moved = |p: Vec2| InputEvent::PointerMoved {
        position: camera.world_to_screen(p),
        delta: Vec2::ZERO,
    };
    // No pointer seen yet: nothing happens.
    m.input(press(Key::B), NO_EGUI, &mut sh);
    assert_eq!(live(&m), bodies);
    // Empty space above the pyramid.
    let above = Vec2::new(-15.0, 25.0);
    m.input(moved(above), NO_EGUI, &mut sh);
    m.input(press(Key::B), NO_EGUI, &mut sh);
    assert_eq!(live(&m), bodies + 1);
    let world = &m.sim().unwrap().world;
    let dropped = world.body_at(above).expect("the box is under the pointer");
    assert!(matches!(
        world.body_shapes(dropped).unwrap().next().unwrap().shape,
        tumble_physics::Shape::Polygon(_)
    ));
    // A held key's repeats drop nothing more.
    let repeat = InputEvent::Key {
        key: Key::N,
        pressed: true,
        repeat: true,
    };
    m.input(moved(above + Vec2::new(3.0, 0.0)), NO_EGUI, &mut sh);
    m.input(repeat, NO_EGUI, &mut sh);
    assert_eq!(live(&m), bodies + 1);
    m.input(press(Key::N), NO_EGUI, &mut sh);
    assert_eq!(live(&m), bodies + 2);
    let world = &m.sim().unwrap().world;
    let ball = world.body_at(above + Vec2::new(3.0, 0.0)).unwrap();
    assert!(matches!(
        world.body_shapes(ball).unwrap().next().unwrap().shape,
        tumble_physics::Shape::Circle(_)
    ));
    // X removes the box, Delete the ball.
    m.input(moved(above), NO_EGUI, &mut sh);
    m.input(press(Key::X), NO_EGUI, &mut sh);
    assert_eq!(live(&m), bodies + 1);
    assert!(!m.sim().unwrap().world.contains_body(dropped));
    m.input(moved(above + Vec2::new(3.0, 0.0)), NO_EGUI, &mut sh);
    m.input(press(Key::Delete), NO_EGUI, &mut sh);
    assert_eq!(live(&m), bodies);
    // The ground stays, and says so.
    assert!(sh.notices.toast.is_none());
    m.input(moved(Vec2::new(-40.0, -1.0)), NO_EGUI, &mut sh);
    m.input(press(Key::X), NO_EGUI, &mut sh);
    assert_eq!(live(&m), bodies);
    assert!(
        sh.notices
            .toast
            .as_ref()
            .is_some_and(|(t, _)| t.contains("Static"))
    );
    // While a text field has the keyboard, the letters are typing.
    m.input(moved(above), NO_EGUI, &mut sh);
    assert_eq!(m.input(press(Key::B), EGUI_KEYBOARD, &mut sh), Routed::Egui);
    assert_eq!(live(&m), bodies);
}

#[test]
fn global_toggles_work_whatever_is_on_top() {
    let mut sh = shared();
    let mut m = StateMachine::new(Box::new(MainMenu::new(None)));
    assert!(sh.toggles.ui_visible);
    assert_eq!(
        m.input(press(Key::F1), EGUI_KEYBOARD, &mut sh),
        Routed::Global
    );
    assert!(!sh.toggles.ui_visible);
    assert_eq!(m.input(press(Key::F12), NO_EGUI, &mut sh), Routed::Global);
    assert!(sh.toggles.screenshot_requested);
    m.input(press(Key::H), NO_EGUI, &mut sh);
    assert!(sh.toggles.help_visible);
    // None of them reached the menu (F1 did not start anything).
    assert_eq!(m.kinds(), vec![StateKind::MainMenu]);
}

#[test]
fn ui_of_every_state_runs_headless() {
    // One egui pass per state, with a real egui context and no window: no panics, and the
    // menu's Start button is laid out.
    let ctx = egui::Context::default();
    let mut sh = shared();
    let mut machines = vec![
        StateMachine::new(Box::new(Intro::new(&sh))),
        StateMachine::new(Box::new(MainMenu::new(None))),
        simulation(&sh),
    ];
    let mut paused = simulation(&sh);
    paused.input(press(Key::Escape), NO_EGUI, &mut sh);
    machines.push(paused);
    sh.toggles.help_visible = true;
    sh.settings.profile_open = true;
    for m in &mut machines {
        for _ in 0..2 {
            m.update(1.0 / 60.0, &mut sh);
            let input = egui::RawInput {
                screen_rect: Some(egui::Rect::from_min_size(
                    egui::Pos2::ZERO,
                    egui::vec2(800.0, 600.0),
                )),
                ..Default::default()
            };
            let out = ctx.run_ui(input, |ui| m.ui(ui, &mut sh));
            assert!(!out.shapes.is_empty());
            out.drop_without_applying_deltas();
        }
    }
}

/// A state with a bug: it panics in its update or its UI.
struct Buggy {
    in_ui: bool,
}

impl State for Buggy {
    fn kind(&self) -> StateKind {
        StateKind::Simulation
    }

    fn update(&mut self, _frame_seconds: f64, _shared: &mut Shared) -> Transition {
        assert!(self.in_ui, "a bug in update");
        Transition::None
    }

    fn ui(&mut self, _ui: &mut egui::Ui, _shared: &mut Shared) -> Transition {
        panic!("a bug in the UI");
    }
}

#[test]
fn a_panicking_state_gives_the_menu_and_a_message_not_a_dead_app() {
    let mut sh = shared();
    let mut m = StateMachine::new(Box::new(Buggy { in_ui: false }));
    m.update(1.0 / 60.0, &mut sh);
    assert_eq!(m.kinds(), vec![StateKind::MainMenu]);
    assert_eq!(sh.notices.crash.as_deref(), Some("a bug in update"));
    assert_eq!(sh.notices.crashes, 1);
    // The menu goes on working.
    m.update(1.0 / 60.0, &mut sh);
    assert_eq!(m.kinds(), vec![StateKind::MainMenu]);

    // A panic in the UI pass: the frame still ends, with the message window in it.
    let mut m = StateMachine::new(Box::new(Buggy { in_ui: true }));
    m.update(1.0 / 60.0, &mut sh);
    let ctx = egui::Context::default();
    let out = ctx.run_ui(egui::RawInput::default(), |ui| m.ui(ui, &mut sh));
    assert!(!out.shapes.is_empty());
    out.drop_without_applying_deltas();
    assert_eq!(m.kinds(), vec![StateKind::MainMenu]);
    assert_eq!(sh.notices.crash.as_deref(), Some("a bug in the UI"));
    assert_eq!(sh.notices.crashes, 2);
}

#[test]
fn the_ray_tool_drags_out_a_ray_and_grabs_nothing() {
    let mut sh = shared();
    let sim = crate::sim::Sim::load("pyramid", 1).unwrap();
    let mut st = Simulation::new(sim, &sh);
    st.update(0.0, &mut sh); // frames the scene
    st.tool = Tool::Ray;
    // Across the pyramid's bottom row.
    let (a, b) = (Vec2::new(-25.0, 0.5), Vec2::new(25.0, 0.5));
    let camera = st.camera;
    let button = |pressed: bool, p: Vec2| InputEvent::Button {
        button: Button::Left,
        pressed,
        position: camera.world_to_screen(p),
    };
    let (down, up) = (button(true, a), button(false, b));
    let moved = InputEvent::PointerMoved {
        position: camera.world_to_screen(b),
        delta: Vec2::ZERO,
    };
    st.on_input(&down, &mut sh);
    assert!(st.sim.drag.is_none(), "the ray tool grabbed a body");
    st.on_input(&moved, &mut sh);
    st.on_input(&up, &mut sh);
    let (from, to) = st.sim.ray.expect("a ray");
    // Screen pixels and back: within a thousandth of a metre.
    assert!(
        (from - a).length() < 1e-3 && (to - b).length() < 1e-3,
        "{from} {to}"
    );
    let hits = st
        .sim
        .world
        .cast_ray_all(from, to - from, &Default::default());
    assert_eq!(hits.len(), 20, "the 20-box bottom row");
    // The pointer moving after the release leaves the ray as it is.
    let later = InputEvent::PointerMoved {
        position: Vec2::new(1.0, 1.0),
        delta: Vec2::ZERO,
    };
    st.on_input(&later, &mut sh);
    assert_eq!(st.sim.ray, Some((from, to)));
    // Back to grabbing: a press grabs again.
    st.tool = Tool::Grab;
    let body = st
        .sim
        .world
        .body(tumble_physics::BodyId::scene(1))
        .unwrap()
        .position;
    st.on_input(&button(true, body), &mut sh);
    assert!(st.sim.drag.is_some());
}

#[test]
fn the_menu_lists_samples_by_category_and_its_search_finds_by_name_description_or_category() {
    let entries = main_menu::scene_entries();
    assert_eq!(entries[0].label, "platformer");
    let ranks: Vec<usize> = entries
        .iter()
        .map(|e| {
            tumble_scene::sample::Category::ALL
                .iter()
                .position(|&c| c == e.category)
                .unwrap()
        })
        .collect();
    assert!(
        ranks.is_sorted(),
        "grouped by category in the browser's order"
    );
    let find = |q: &str| -> Vec<&str> {
        entries
            .iter()
            .filter(|e| e.matches(q))
            .map(|e| e.label.as_str())
            .collect()
    };
    assert!(find("pyramid").contains(&"many_pyramids"));
    assert!(find("benchmark").contains(&"washer"), "by category");
    assert!(find("conveyor").contains(&"platformer"), "by description");
    assert!(find("no such thing").is_empty());
    // Box2D's benchmark scenes keep their names, under Benchmark.
    for name in [
        "large_pyramid",
        "many_pyramids",
        "rain",
        "smash",
        "spinner",
        "tumbler",
    ] {
        let e = entries.iter().find(|e| e.label == name).unwrap();
        assert_eq!(
            e.category,
            tumble_scene::sample::Category::Benchmark,
            "{name}"
        );
    }
}

#[test]
fn in_the_platformer_the_arrows_and_space_steer_the_character_not_the_viewer() {
    let mut sh = shared();
    let sim = crate::sim::Sim::load("platformer", 1).unwrap();
    let mut m = StateMachine::new(Box::new(Simulation::new(sim, &sh)));
    let start = m
        .sim()
        .unwrap()
        .controller
        .clone()
        .unwrap()
        .focus()
        .unwrap();
    m.input(press(Key::ArrowRight), NO_EGUI, &mut sh);
    m.input(press(Key::Space), NO_EGUI, &mut sh);
    for _ in 0..30 {
        m.update(1.0 / 60.0, &mut sh);
    }
    let sim = m.sim().unwrap();
    // Space jumped instead of pausing.
    assert!(sim.running);
    let now = sim.controller.as_ref().unwrap().focus().unwrap();
    assert!(now.x > start.x + 2.0, "walked right: {start} -> {now}");
    let release = InputEvent::Key {
        key: Key::ArrowRight,
        pressed: false,
        repeat: false,
    };
    m.input(release, NO_EGUI, &mut sh);
    assert!(
        !m.sim()
            .unwrap()
            .keys
            .contains(tumble_scene::sample::Keys::RIGHT)
    );
    // In a scene without a character Space still pauses.
    let mut m = simulation(&sh);
    m.input(press(Key::Space), NO_EGUI, &mut sh);
    assert!(!m.sim().unwrap().running);
}
