//! The intro: the title tumbles in, letter by letter, over a live simulation; after a few
//! seconds, or at any key or click, the main menu takes over (and keeps the simulation
//! running behind it).

use std::sync::Arc;

use egui::{Align2, Color32, FontId, Id, LayerId, Order, Pos2};
use glam::Vec2;

use super::{MainMenu, Shared, State, StateKind, Transition, View};
use crate::camera::{Camera, world_bounds};
use crate::input::InputEvent;
use crate::sim::Sim;

/// How long the intro lasts when nothing is pressed (s).
pub const INTRO_SECONDS: f64 = 4.0;

/// A simulation running behind the intro and the menu, dimmed.
pub struct Backdrop {
    /// The simulation.
    pub sim: Sim,
    /// Its camera, refitted when the window changes size.
    pub camera: Camera,
    fitted_for: Vec2,
}

impl Backdrop {
    /// The default scene, or `None` if it cannot be built (it always can).
    pub fn new(threads: usize) -> Option<Self> {
        let scene = tumble_scene::builtin::build(crate::DEFAULT_SCENE)?;
        let sim = Sim::new(Arc::new(scene), threads).ok()?;
        Some(Self {
            sim,
            camera: Camera::new(Vec2::ZERO, 10.0, Vec2::ONE),
            fitted_for: Vec2::ZERO,
        })
    }

    /// Steps the simulation; keeps the scene framed; restarts it once it has settled.
    pub fn update(&mut self, frame_seconds: f64, shared: &Shared) {
        if self.fitted_for != shared.viewport {
            self.camera.viewport = shared.viewport;
            self.camera
                .fit(world_bounds(&self.sim.world), (Vec2::ZERO, shared.viewport));
            self.fitted_for = shared.viewport;
        }
        self.sim.advance(frame_seconds);
        if self.sim.time() > 12.0 {
            self.sim.restart();
        }
    }

    /// The view the renderer draws.
    pub fn view(&self, dim: f32) -> View<'_> {
        View {
            sim: &self.sim,
            camera: &self.camera,
            debug: false,
            dim,
        }
    }
}

/// The intro state.
pub struct Intro {
    backdrop: Option<Backdrop>,
    elapsed: f64,
}

impl Intro {
    /// An intro with its backdrop simulation.
    pub fn new(shared: &Shared) -> Self {
        Self {
            backdrop: Backdrop::new(shared.settings.threads),
            elapsed: 0.0,
        }
    }

    fn leave_for_menu(&mut self) -> Transition {
        Transition::Replace(Box::new(MainMenu::new(self.backdrop.take())))
    }
}

impl State for Intro {
    fn kind(&self) -> StateKind {
        StateKind::Intro
    }

    fn on_back(&mut self, _shared: &mut Shared) -> Transition {
        self.leave_for_menu()
    }

    fn on_input(&mut self, event: &InputEvent, _shared: &mut Shared) -> Transition {
        if event.is_press() {
            self.leave_for_menu()
        } else {
            Transition::None
        }
    }

    fn update(&mut self, frame_seconds: f64, shared: &mut Shared) -> Transition {
        self.elapsed += frame_seconds.min(0.1);
        if let Some(b) = &mut self.backdrop {
            b.update(frame_seconds, shared);
        }
        if self.elapsed >= INTRO_SECONDS {
            self.leave_for_menu()
        } else {
            Transition::None
        }
    }

    fn ui(&mut self, ui: &mut egui::Ui, _shared: &mut Shared) -> Transition {
        draw_title(ui.ctx(), self.elapsed as f32);
        Transition::None
    }

    fn view(&self) -> Option<View<'_>> {
        self.backdrop.as_ref().map(|b| b.view(0.25))
    }

    fn sim(&self) -> Option<&crate::sim::Sim> {
        self.backdrop.as_ref().map(|b| &b.sim)
    }
}

/// "tumble": each letter falls in turning, bounces and settles, one after another; then the
/// subtitle and the hint fade in.
fn draw_title(ctx: &egui::Context, t: f32) {
    let painter = ctx.layer_painter(LayerId::new(Order::Foreground, Id::unique("intro-title")));
    let screen = ctx.content_rect();
    let center = screen.center() - egui::vec2(0.0, screen.height() * 0.08);
    let size = (screen.width() * 0.12).clamp(48.0, 160.0);
    let font = FontId::proportional(size);
    let title = "tumble";
    let galleys: Vec<_> = title
        .chars()
        .map(|c| painter.layout_no_wrap(c.to_string(), font.clone(), Color32::WHITE))
        .collect();
    let total: f32 = galleys.iter().map(|g| g.size().x).sum();
    let mut x = center.x - total * 0.5;
    for (i, galley) in galleys.into_iter().enumerate() {
        let start = 0.15 + i as f32 * 0.12;
        let local = ((t - start) / 0.9).clamp(0.0, 1.0);
        let w = galley.size().x;
        if t >= start {
            // Fall with a bounce (an ease-out "bounce" curve), turning a full turn on the way.
            let fall = 1.0 - bounce(local);
            let y = center.y - galley.size().y * 0.5 - fall * screen.height() * 0.6;
            let angle = fall * std::f32::consts::TAU * if i % 2 == 0 { 1.0 } else { -1.0 };
            let alpha = (local * 4.0).min(1.0);
            let hue = i as f32 / 6.0;
            let color = letter_color(hue, alpha);
            painter.add(
                egui::epaint::TextShape::new(Pos2::new(x, y), galley, color)
                    .with_angle_and_anchor(angle, Align2::CENTER_CENTER)
                    .with_override_text_color(color),
            );
        }
        x += w;
    }
    let fade = |from: f32| ((t - from) / 0.6).clamp(0.0, 1.0);
    let sub = fade(1.2);
    painter.text(
        Pos2::new(screen.center().x, center.y + size * 0.75),
        Align2::CENTER_CENTER,
        "2D rigid-body physics, on every core",
        FontId::proportional((size * 0.22).max(16.0)),
        Color32::from_white_alpha((sub * 220.0) as u8),
    );
    let hint = fade(1.8) * (0.6 + 0.4 * (t * 3.0).sin().abs());
    painter.text(
        Pos2::new(screen.center().x, screen.bottom() - 48.0),
        Align2::CENTER_CENTER,
        "press any key",
        FontId::proportional(18.0),
        Color32::from_white_alpha((hint * 160.0) as u8),
    );
}

/// Robert Penner's ease-out bounce: 0 → 1 with three shrinking bounces.
fn bounce(x: f32) -> f32 {
    let n = 7.5625;
    let d = 2.75;
    if x < 1.0 / d {
        n * x * x
    } else if x < 2.0 / d {
        let x = x - 1.5 / d;
        n * x * x + 0.75
    } else if x < 2.5 / d {
        let x = x - 2.25 / d;
        n * x * x + 0.9375
    } else {
        let x = x - 2.625 / d;
        n * x * x + 0.984375
    }
}

fn letter_color(hue: f32, alpha: f32) -> Color32 {
    let [r, g, b] = crate::render::hsv(0.55 + hue * 0.5, 0.45, 1.0);
    Color32::from_rgba_unmultiplied(
        (r * 255.0) as u8,
        (g * 255.0) as u8,
        (b * 255.0) as u8,
        (alpha * 255.0) as u8,
    )
}
