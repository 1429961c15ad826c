//! The windowed app: winit's event loop (`ApplicationHandler`), the wgpu surface, egui through
//! egui-winit and egui-wgpu, and the frame loop that ties them to the state machine.
//!
//! The platform enters through [`run`], which takes the executor that waits for wgpu's
//! asynchronous setup (pollster natively), so this file needs no `cfg`.

use std::future::Future;
use std::path::PathBuf;
use std::pin::Pin;
use std::sync::Arc;

use anyhow::{Context, Result, anyhow, bail};
use glam::Vec2;
use web_time::Instant;
use winit::application::ApplicationHandler;
use winit::dpi::LogicalSize;
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::window::{Window, WindowId};

use crate::cli::{Options, Stats};
use crate::input::Translator;
use crate::render::{self, EguiFrame, Image, SceneRenderer, Target};
use crate::settings::Settings;
use crate::sim::Sim;
use crate::state::{EguiWants, Intro, Shared, Simulation, StateMachine};

/// Graphics setup, as a future the platform's executor runs.
pub type GfxFuture = Pin<Box<dyn Future<Output = Result<Gfx>>>>;
/// Runs a [`GfxFuture`] to completion (natively: `pollster::block_on`).
pub type BlockOn = fn(GfxFuture) -> Result<Gfx>;

/// The window's initial size in logical pixels.
pub const WINDOW_SIZE: [u32; 2] = [1280, 800];

/// Opens the window and runs until the user quits or `--frames` frames were drawn. Returns
/// what `--stats` writes (and writes it, and the screenshot, when asked).
pub fn run(options: Options, block_on: BlockOn) -> Result<Stats> {
    let mut settings = if options.persist {
        Settings::load()
    } else {
        Settings::default()
    };
    if let Some(t) = options.threads {
        settings.threads = t;
    }
    if options.no_vsync {
        settings.vsync = false;
    }
    let size = Vec2::new(WINDOW_SIZE[0] as f32, WINDOW_SIZE[1] as f32);
    let mut shared = Shared::new(settings, size);
    let machine = initial_machine(&options, &mut shared)?;

    let event_loop = EventLoop::new()
        .context("cannot open a window (is there a display? without one, run under xvfb-run)")?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let mut app = App {
        options,
        shared,
        machine,
        gfx: None,
        block_on,
        egui: egui::Context::default(),
        translator: Translator::default(),
        frames: 0,
        started: Instant::now(),
        first_frame: None,
        last_frame: None,
        error: None,
        screenshot_written: false,
    };
    event_loop
        .run_app(&mut app)
        .context("the window's event loop failed")?;
    if let Some(e) = app.error.take() {
        return Err(e);
    }
    if app.options.persist {
        app.shared.settings.save();
    }
    let stats = app.stats();
    if let Some(path) = &app.options.stats {
        stats.write(path)?;
    }
    if let Some(path) = &app.options.screenshot
        && !app.screenshot_written
    {
        bail!(
            "--screenshot {}: no frame was drawn to capture",
            path.display()
        );
    }
    Ok(stats)
}

/// The states at start: the simulation when a scene was given, else the intro.
fn initial_machine(options: &Options, shared: &mut Shared) -> Result<StateMachine> {
    Ok(match &options.scene {
        Some(scene) => {
            let sim = Sim::new(Arc::clone(scene), shared.settings.threads)?;
            StateMachine::new(Box::new(Simulation::new(sim, shared)))
        }
        None => StateMachine::new(Box::new(Intro::new(shared))),
    })
}

/// Everything that needs the window: surface, device, our renderer, egui's.
pub struct Gfx {
    // Field order is drop order: the surface goes before the window it draws into.
    surface: wgpu::Surface<'static>,
    device: wgpu::Device,
    queue: wgpu::Queue,
    config: wgpu::SurfaceConfiguration,
    scene: SceneRenderer,
    egui_renderer: egui_wgpu::Renderer,
    egui_state: egui_winit::State,
    info: wgpu::AdapterInfo,
    window: Arc<Window>,
}

impl Gfx {
    /// Sets up wgpu for `window`: an instance with the window's display, an adapter that can
    /// present to it, a device, and a non-sRGB surface format (egui blends in gamma space).
    pub async fn new(window: Arc<Window>, egui: egui::Context, vsync: bool) -> Result<Gfx> {
        // The window gives the instance its display (GL and Wayland need it).
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_with_display_handle_from_env(
                Box::new(Arc::clone(&window)),
            ));
        let surface = instance
            .create_surface(Arc::clone(&window))
            .context("cannot create a drawing surface for the window")?;
        let adapter = instance
            .request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                compatible_surface: Some(&surface),
                ..Default::default()
            })
            .await
            .map_err(|e| {
                anyhow!(
                    "no graphics adapter can draw to this window ({e}); without a GPU install \
                     Mesa's software Vulkan: apt-get install mesa-vulkan-drivers libvulkan1"
                )
            })?;
        let info = adapter.get_info();
        let (device, queue) = render::request_device(&adapter).await?;
        let size = window.inner_size();
        let mut config = surface
            .get_default_config(&adapter, size.width.max(1), size.height.max(1))
            .ok_or_else(|| anyhow!("the adapter cannot present to this window"))?;
        let caps = surface.get_capabilities(&adapter);
        config.format = render::pick_format(&caps.formats)
            .ok_or_else(|| anyhow!("the window offers no surface format"))?;
        config.present_mode = if vsync {
            wgpu::PresentMode::AutoVsync
        } else {
            wgpu::PresentMode::AutoNoVsync
        };
        config.view_formats = vec![];
        surface.configure(&device, &config);

        let scene = SceneRenderer::new(&device, config.format);
        let egui_renderer = egui_wgpu::Renderer::new(
            &device,
            config.format,
            egui_wgpu::RendererOptions::default(),
        );
        let max_texture = device.limits().max_texture_dimension_2d as usize;
        let egui_state = egui_winit::State::new(
            egui,
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            window.theme(),
            Some(max_texture),
        );
        Ok(Gfx {
            surface,
            device,
            queue,
            config,
            scene,
            egui_renderer,
            egui_state,
            info,
            window,
        })
    }

    fn resize(&mut self, width: u32, height: u32) {
        if width == 0 || height == 0 {
            return;
        }
        self.config.width = width;
        self.config.height = height;
        self.surface.configure(&self.device, &self.config);
    }

    /// Draws one frame to the window; with `capture`, draws the same frame into an offscreen
    /// texture too and returns it read back. Returns `Ok(None)` when no frame could be drawn
    /// (the surface was outdated or the window hidden).
    fn render(
        &mut self,
        view: Option<crate::state::View<'_>>,
        debug: &crate::settings::DebugDraw,
        primitives: &[egui::ClippedPrimitive],
        textures: &mut egui::TexturesDelta,
        pixels_per_point: f32,
        capture: bool,
    ) -> Result<Option<Image>> {
        // egui's texture updates first: the font atlas must be there even if this frame is
        // skipped.
        for (id, deltas) in &textures.set {
            for delta in deltas {
                self.egui_renderer
                    .update_texture(&self.device, &self.queue, *id, delta);
            }
        }
        let result = self.draw(view, debug, primitives, pixels_per_point, capture);
        for id in &textures.free {
            self.egui_renderer.free_texture(id);
        }
        textures.clear();
        result
    }

    fn draw(
        &mut self,
        view: Option<crate::state::View<'_>>,
        debug: &crate::settings::DebugDraw,
        primitives: &[egui::ClippedPrimitive],
        pixels_per_point: f32,
        capture: bool,
    ) -> Result<Option<Image>> {
        let frame = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(frame) => frame,
            wgpu::CurrentSurfaceTexture::Suboptimal(frame) => {
                // Draw this one, reconfigure for the next.
                self.surface.configure(&self.device, &self.config);
                frame
            }
            wgpu::CurrentSurfaceTexture::Timeout | wgpu::CurrentSurfaceTexture::Occluded => {
                return Ok(None);
            }
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                self.surface.configure(&self.device, &self.config);
                return Ok(None);
            }
            wgpu::CurrentSurfaceTexture::Validation => {
                bail!("the surface refused to give a frame (validation error)")
            }
        };
        self.scene.prepare(&self.device, &self.queue, view, debug);
        let screen = egui_wgpu::ScreenDescriptor {
            size_in_pixels: [self.config.width, self.config.height],
            pixels_per_point,
        };
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("frame"),
            });
        let user_buffers = self.egui_renderer.update_buffers(
            &self.device,
            &self.queue,
            &mut encoder,
            primitives,
            &screen,
        );
        let egui = EguiFrame {
            renderer: &self.egui_renderer,
            primitives,
            screen: &screen,
        };
        let target_view = frame
            .texture
            .create_view(&wgpu::TextureViewDescriptor::default());
        render::encode_frame(&mut encoder, &target_view, &self.scene, Some(&egui));
        // The same frame, recorded again into a texture we can copy from.
        let offscreen = capture.then(|| {
            let target = Target::new(
                &self.device,
                self.config.width,
                self.config.height,
                self.config.format,
            );
            render::encode_frame(&mut encoder, &target.view, &self.scene, Some(&egui));
            target
        });
        self.queue
            .submit(user_buffers.into_iter().chain([encoder.finish()]));
        self.window.pre_present_notify();
        self.queue.present(frame);
        match offscreen {
            Some(target) => Ok(Some(render::read_texture(
                &self.device,
                &self.queue,
                &target.texture,
            )?)),
            None => Ok(None),
        }
    }
}

struct App {
    options: Options,
    shared: Shared,
    machine: StateMachine,
    gfx: Option<Gfx>,
    block_on: BlockOn,
    egui: egui::Context,
    translator: Translator,
    frames: u64,
    started: Instant,
    first_frame: Option<Instant>,
    last_frame: Option<Instant>,
    error: Option<anyhow::Error>,
    screenshot_written: bool,
}

impl App {
    fn fail(&mut self, event_loop: &ActiveEventLoop, error: anyhow::Error) {
        if self.error.is_none() {
            self.error = Some(error);
        }
        event_loop.exit();
    }

    /// One frame: update the states, run egui, draw, count, and stop when scripted to.
    fn frame(&mut self, event_loop: &ActiveEventLoop, force_capture: bool) {
        let now = Instant::now();
        let frame_seconds = self
            .last_frame
            .map_or(0.0, |t| now.duration_since(t).as_secs_f64());
        self.last_frame = Some(now);
        self.first_frame.get_or_insert(now);
        self.shared.time = now.duration_since(self.started).as_secs_f64();
        if frame_seconds > 0.0 {
            let fps = 1.0 / frame_seconds;
            self.shared.fps = if self.shared.fps == 0.0 {
                fps
            } else {
                self.shared.fps * 0.95 + fps * 0.05
            };
        }

        self.machine.update(frame_seconds, &mut self.shared);

        let Some(gfx) = self.gfx.as_mut() else {
            return;
        };
        let raw = gfx.egui_state.take_egui_input(&gfx.window);
        let machine = &mut self.machine;
        let shared = &mut self.shared;
        let full = self.egui.run_ui(raw, |ui| machine.ui(ui, shared));
        gfx.egui_state
            .handle_platform_output(&gfx.window, full.platform_output);
        self.shared.pixels_per_point = full.pixels_per_point;
        let primitives = self.egui.tessellate(full.shapes, full.pixels_per_point);
        let mut textures = full.textures_delta;

        let last_scripted = self.options.frames == Some(self.frames + 1);
        let scripted_capture = last_scripted && self.options.screenshot.is_some();
        let capture = force_capture || scripted_capture || self.shared.screenshot_requested;
        let view = self.machine.view();
        let debug = self.shared.settings.debug;
        let drawn = gfx.render(
            view,
            &debug,
            &primitives,
            &mut textures,
            self.shared.pixels_per_point,
            capture,
        );
        let image = match drawn {
            Ok(image) => image,
            Err(e) => return self.fail(event_loop, e),
        };
        if image.is_some() || !capture {
            self.frames += 1;
        }
        if let Some(image) = image
            && let Err(e) = self.save_capture(&image, scripted_capture || force_capture)
        {
            return self.fail(event_loop, e);
        }
        if self.machine.should_quit() || self.options.frames.is_some_and(|n| self.frames >= n) {
            event_loop.exit();
        }
    }

    /// Writes a captured frame: to `--screenshot` for a scripted capture, else to a
    /// time-stamped file in the working directory (F12 / P).
    fn save_capture(&mut self, image: &Image, scripted: bool) -> Result<()> {
        if scripted && let Some(path) = self.options.screenshot.clone() {
            image.save_png(&path)?;
            self.screenshot_written = true;
        }
        if self.shared.screenshot_requested {
            self.shared.screenshot_requested = false;
            let secs = std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map_or(0, |d| d.as_millis());
            let path = PathBuf::from(format!("tumble-{secs}.png"));
            match image.save_png(&path) {
                Ok(()) => self
                    .shared
                    .toast(format!("Screenshot saved: {}", path.display())),
                Err(e) => self.shared.toast(format!("Screenshot failed: {e:#}")),
            }
        }
        Ok(())
    }

    fn stats(&self) -> Stats {
        let sim = self
            .machine
            .sim()
            .or_else(|| self.machine.view().map(|v| v.sim));
        let elapsed = match (self.first_frame, self.last_frame) {
            (Some(a), Some(b)) if self.frames > 1 => {
                b.duration_since(a).as_secs_f64() * 1000.0 / (self.frames - 1) as f64
            }
            _ => 0.0,
        };
        let (width, height) = self
            .gfx
            .as_ref()
            .map_or((0, 0), |g| (g.config.width, g.config.height));
        Stats {
            frames: self.frames,
            steps: sim.map_or(0, |s| s.total_steps),
            bodies: sim.map_or(0, |s| s.world.body_count()),
            threads: sim.map_or(0, |s| s.world.thread_count()),
            backend: self.shared.backend.clone(),
            step_ms_mean: sim.map_or(0.0, Sim::step_ms_mean),
            scene: sim.map_or_else(String::new, |s| s.scene.name.clone()),
            frame_ms_mean: elapsed,
            adapter: self
                .gfx
                .as_ref()
                .map_or_else(String::new, |g| g.info.name.clone()),
            size: [width, height],
            state_hash: sim.map_or_else(String::new, |s| format!("{:016x}", s.world.state_hash())),
        }
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.gfx.is_some() {
            return;
        }
        let attributes = Window::default_attributes()
            .with_title("tumble")
            .with_inner_size(LogicalSize::new(WINDOW_SIZE[0], WINDOW_SIZE[1]));
        let window = match event_loop.create_window(attributes) {
            Ok(w) => Arc::new(w),
            Err(e) => return self.fail(event_loop, anyhow!("cannot create the window: {e}")),
        };
        self.egui.set_theme(egui::Theme::Dark);
        let future = Gfx::new(
            Arc::clone(&window),
            self.egui.clone(),
            self.shared.settings.vsync,
        );
        match (self.block_on)(Box::pin(future)) {
            Ok(gfx) => {
                self.shared.backend = format!("{:?}", gfx.info.backend);
                let size = window.inner_size();
                self.shared.viewport = Vec2::new(size.width as f32, size.height as f32);
                self.shared.view_area = (Vec2::ZERO, self.shared.viewport);
                self.gfx = Some(gfx);
                window.request_redraw();
            }
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(gfx) = self.gfx.as_mut() else {
            return;
        };
        let _ = gfx.egui_state.on_window_event(&gfx.window, &event);
        match &event {
            WindowEvent::CloseRequested => {
                // A screenshot was asked for but the run ends early: capture this last frame.
                let pending = self.options.screenshot.is_some() && !self.screenshot_written;
                if pending {
                    self.frame(event_loop, true);
                }
                event_loop.exit();
                return;
            }
            WindowEvent::Resized(size) => {
                gfx.resize(size.width, size.height);
                self.shared.viewport = Vec2::new(size.width as f32, size.height as f32);
            }
            WindowEvent::RedrawRequested => {
                self.frame(event_loop, false);
                return;
            }
            _ => {}
        }
        if let Some(input) = self.translator.translate(&event) {
            let wants = EguiWants {
                pointer: self.egui.egui_wants_pointer_input(),
                keyboard: self.egui.egui_wants_keyboard_input(),
            };
            self.machine.input(input, wants, &mut self.shared);
            if self.machine.should_quit() {
                event_loop.exit();
            }
        }
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(gfx) = &self.gfx {
            gfx.window.request_redraw();
        }
    }
}
