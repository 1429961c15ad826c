//! The windowed app: winit's event loop (`ApplicationHandler`), the wgpu surface, egui through
//! egui-winit and egui-wgpu, and the frame loop that ties them to the state machine.
//!
//! The platform enters through [`run`] (native: the event loop runs until the window closes)
//! or [`prepare`] (the web: the page's event loop takes the app and returns at once), with a
//! [`Platform`] that says how to wait for wgpu's asynchronous setup, what to draw into, and
//! what to do after each frame, so this file needs no `cfg`.

use std::cell::RefCell;
use std::future::Future;
use std::path::PathBuf;
use std::pin::Pin;
use std::rc::Rc;
use std::sync::{Arc, Mutex};

use anyhow::{Context, Result, anyhow, bail};
use glam::Vec2;
use web_time::Instant;
use winit::application::ApplicationHandler;
use winit::dpi::LogicalSize;
use winit::event::WindowEvent;
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::window::{Window, WindowAttributes, WindowId};

use crate::cli::{Options, Stats};
use crate::input::Translator;
use crate::render::{self, EguiFrame, Image, SceneRenderer, Target};
use crate::settings::Settings;
use crate::sim::Sim;
use crate::state::{EguiWants, Intro, Shared, Simulation, StateKind, StateMachine};

/// Graphics setup, as a future the platform's executor runs.
pub type GfxFuture = Pin<Box<dyn Future<Output = Result<Gfx>>>>;
/// Where the platform puts the finished graphics setup; the frame loop takes it from there.
pub type GfxSlot = Rc<RefCell<Option<Result<Gfx>>>>;

/// Runs a [`GfxFuture`] and puts its result in the slot, natively by blocking on it
/// (`pollster`); the web cannot block, so it spawns the future and the frame loop picks the
/// result up when it is there.
pub type SpawnGfx = fn(GfxFuture, GfxSlot);

/// The window's initial size in logical pixels.
pub const WINDOW_SIZE: [u32; 2] = [1280, 800];

/// What the frame loop reports after each frame, for a platform to publish (the web build
/// puts it on `window.tumble`).
pub struct FrameReport<'a> {
    /// What `--stats` would write now.
    pub stats: &'a Stats,
    /// The state on top.
    pub state: Option<StateKind>,
    /// Mean height of the dynamic bodies (m): falls while they fall.
    pub mean_y: f64,
    /// Simulated time since the world was (re)built (s).
    pub sim_time: f64,
    /// The most threads the thread slider offers.
    pub max_threads: usize,
    /// Frames per second, smoothed.
    pub fps: f64,
    /// The thread slider's rectangle in egui points (the page's CSS pixels), when it is shown.
    pub threads_slider: Option<egui::Rect>,
    /// Why the platform limits threads, as the UI says it.
    pub threads_note: Option<&'a str>,
}

/// Work for another thread.
pub type Job = Box<dyn FnOnce() + Send>;

/// Runs a job on another thread, or hands it back if it cannot.
pub type Offload = fn(Job) -> std::result::Result<(), Job>;

/// The states and shared data, coming back from an update that ran elsewhere.
type UpdateSlot = Arc<Mutex<Option<(StateMachine, Shared)>>>;

/// Input that arrived while the states were away (see [`Platform::offload`]).
enum Deferred {
    Input(crate::input::InputEvent, EguiWants),
    Viewport(Vec2),
}

/// What the platform does after each frame.
pub type OnFrame = Box<dyn FnMut(&FrameReport<'_>)>;

/// What the platform supplies to the app.
pub struct Platform {
    /// How wgpu's asynchronous setup is awaited.
    pub spawn_gfx: SpawnGfx,
    /// The window to open (on the web: the page's canvas).
    pub window: WindowAttributes,
    /// Keep the event loop spinning (natively, for frame rates past vsync) or wait for events
    /// and redraws (the web, whose redraws follow the display).
    pub poll: bool,
    /// Whether the app may end its event loop (not on the web: the page would stop).
    pub can_quit: bool,
    /// Shown beside the thread slider when the platform limits threads (the web without
    /// cross-origin isolation).
    pub threads_note: Option<String>,
    /// Called after every frame.
    pub on_frame: Option<OnFrame>,
    /// Where each frame's update (the physics steps) runs. `None`: in the frame, on the
    /// event loop's thread (natively: the thread sleeps while the step's workers run). The
    /// web sets a Web Worker here: the page's thread cannot sleep, it would spin beside the
    /// workers; instead it draws the last update's result and returns to the browser.
    pub offload: Option<Offload>,
}

impl Platform {
    /// A native window of [`WINDOW_SIZE`], setup awaited with `spawn_gfx`.
    pub fn native(spawn_gfx: SpawnGfx) -> Self {
        Self {
            spawn_gfx,
            window: Window::default_attributes()
                .with_title("tumble")
                .with_inner_size(LogicalSize::new(WINDOW_SIZE[0], WINDOW_SIZE[1])),
            poll: true,
            can_quit: true,
            threads_note: None,
            on_frame: None,
            offload: None,
        }
    }
}

/// Opens the window and runs until the user quits or `--frames` frames were drawn. Returns
/// what `--stats` writes (and writes it, and the screenshot, when asked).
pub fn run(options: Options, platform: Platform) -> Result<Stats> {
    let (event_loop, mut app) = prepare(options, platform)?;
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

/// Loads the settings, builds the first states and the event loop: what [`run`] runs, and
/// what the web entry hands to the page's event loop.
pub fn prepare(options: Options, platform: Platform) -> Result<(EventLoop<()>, App)> {
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
    shared.threads_note = platform.threads_note.clone();
    let machine = initial_machine(&options, &mut shared)?;

    let event_loop = EventLoop::new()
        .context("cannot open a window (is there a display? without one, run under xvfb-run)")?;
    event_loop.set_control_flow(if platform.poll {
        ControlFlow::Poll
    } else {
        ControlFlow::Wait
    });
    let saved = shared.settings.clone();
    let app = App {
        options,
        shared,
        machine,
        gfx: None,
        gfx_slot: Rc::new(RefCell::new(None)),
        window: None,
        platform,
        egui: egui::Context::default(),
        translator: Translator::default(),
        frames: 0,
        started: Instant::now(),
        first_frame: None,
        last_frame: None,
        error: None,
        screenshot_written: false,
        saved,
        saved_at: 0.0,
        updating: None,
        deferred: Vec::new(),
    };
    Ok((event_loop, app))
}

/// The states at start: the simulation when a scene was given, else the intro.
fn initial_machine(options: &Options, shared: &mut Shared) -> Result<StateMachine> {
    Ok(match &options.scene {
        Some(scene) => {
            let mut sim = Sim::new(Arc::clone(scene), shared.settings.threads)?;
            sim.key_script = options.keys.clone();
            sim.step_limit = options.steps;
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
        // The window gives the instance its display (GL and Wayland need it). In a browser
        // with no WebGPU adapter this leaves WebGPU out, so WebGL2 is used instead.
        let instance = wgpu::util::new_instance_with_webgpu_detection(
            wgpu::InstanceDescriptor::new_with_display_handle_from_env(Box::new(Arc::clone(
                &window,
            ))),
        )
        .await;
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
        view: Option<crate::render::View<'_>>,
        debug: &crate::settings::DebugLayers,
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
        view: Option<crate::render::View<'_>>,
        debug: &crate::settings::DebugLayers,
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

/// The app as the event loop drives it.
pub struct App {
    options: Options,
    shared: Shared,
    machine: StateMachine,
    gfx: Option<Gfx>,
    /// Where the platform puts the graphics once they are set up.
    gfx_slot: GfxSlot,
    /// The window, from its creation (the graphics may come later).
    window: Option<Arc<Window>>,
    platform: Platform,
    egui: egui::Context,
    translator: Translator,
    frames: u64,
    started: Instant,
    first_frame: Option<Instant>,
    last_frame: Option<Instant>,
    error: Option<anyhow::Error>,
    screenshot_written: bool,
    /// The settings as last saved, and when (s since start).
    saved: Settings,
    saved_at: f64,
    /// An update running elsewhere ([`Platform::offload`]); the states are away meanwhile.
    updating: Option<UpdateSlot>,
    /// Input that arrived meanwhile, applied when the states are back.
    deferred: Vec<Deferred>,
}

/// The name the contract gives a backend: wgpu's, except "WebGpu" for the browser's WebGPU.
pub fn backend_name(backend: wgpu::Backend) -> String {
    match backend {
        wgpu::Backend::BrowserWebGpu => "WebGpu".to_string(),
        other => format!("{other:?}"),
    }
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
        if self.updating.is_some() {
            if !self.take_update_back() {
                // The update is still running elsewhere: no frame yet.
                return;
            }
            self.apply_deferred(event_loop);
        }
        let frame_seconds = self.tick();
        match self.platform.offload {
            Some(offload) if !force_capture => {
                // Show what the last update left, then start the next one elsewhere; the page's
                // thread is free meanwhile.
                self.draw(event_loop, false);
                self.start_update(offload, frame_seconds);
            }
            _ => {
                self.machine.update(frame_seconds, &mut self.shared);
                self.draw(event_loop, force_capture);
            }
        }
    }

    /// Starts the states' update on another thread, handing them over; where that fails
    /// (no threads), updates here.
    fn start_update(&mut self, offload: Offload, frame_seconds: f64) {
        let mut machine = std::mem::take(&mut self.machine);
        let mut shared = std::mem::replace(
            &mut self.shared,
            Shared::new(Settings::default(), Vec2::ZERO),
        );
        let slot: UpdateSlot = Arc::new(Mutex::new(None));
        let back = Arc::clone(&slot);
        let job = Box::new(move || {
            machine.update(frame_seconds, &mut shared);
            if let Ok(mut back) = back.lock() {
                *back = Some((machine, shared));
            }
        });
        self.updating = Some(slot);
        if let Err(job) = offload(job) {
            // No thread took it: update here, and from now on.
            job();
            self.platform.offload = None;
            self.take_update_back();
        }
    }

    /// Takes the states back from a finished update; false while it runs.
    fn take_update_back(&mut self) -> bool {
        let Some(slot) = &self.updating else {
            return true;
        };
        // Never wait here: the page's thread may not block.
        let back = slot.try_lock().ok().and_then(|mut s| s.take());
        let Some((machine, shared)) = back else {
            return false;
        };
        self.machine = machine;
        self.shared = shared;
        self.updating = None;
        true
    }

    /// Applies what arrived while the update ran elsewhere.
    fn apply_deferred(&mut self, event_loop: &ActiveEventLoop) {
        for deferred in std::mem::take(&mut self.deferred) {
            match deferred {
                Deferred::Input(input, wants) => {
                    self.machine.input(input, wants, &mut self.shared);
                }
                Deferred::Viewport(viewport) => self.shared.viewport = viewport,
            }
        }
        if self.quit_requested() {
            event_loop.exit();
        }
    }

    /// Advances the frame clock: the seconds since the last frame (0 for the first).
    fn tick(&mut self) -> f64 {
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
        frame_seconds
    }

    /// Runs egui, draws the frame, counts it, reports it, and stops when scripted to.
    fn draw(&mut self, event_loop: &ActiveEventLoop, force_capture: bool) {
        let Some(gfx) = self.gfx.as_mut() else {
            return;
        };
        let raw = gfx.egui_state.take_egui_input(&gfx.window);
        let machine = &mut self.machine;
        let shared = &mut self.shared;
        shared.threads_slider = None;
        let full = self.egui.run_ui(raw, |ui| machine.ui(ui, shared));
        gfx.egui_state
            .handle_platform_output(&gfx.window, full.platform_output);
        self.shared.pixels_per_point = full.pixels_per_point;
        let primitives = self.egui.tessellate(full.shapes, full.pixels_per_point);
        let mut textures = full.textures_delta;

        let steps_done = self
            .options
            .steps
            .is_some_and(|n| self.machine.sim().is_some_and(|s| s.steps >= n));
        let last_scripted = self.options.frames == Some(self.frames + 1) || steps_done;
        let scripted_capture = last_scripted && self.options.screenshot.is_some();
        let capture = force_capture || scripted_capture || self.shared.toggles.screenshot_requested;
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
        self.save_settings_when_changed();
        if let Some(on_frame) = self.platform.on_frame.as_mut() {
            let sim = self
                .machine
                .sim()
                .or_else(|| self.machine.view().map(|v| v.sim));
            let stats = Self::stats_of(
                self.frames,
                self.first_frame,
                self.last_frame,
                sim,
                &self.shared,
                self.gfx.as_ref(),
            );
            let report = FrameReport {
                stats: &stats,
                state: self.machine.top_kind(),
                mean_y: sim.map_or(0.0, mean_dynamic_height),
                sim_time: sim.map_or(0.0, Sim::time),
                max_threads: tumble_physics::default_thread_count(),
                fps: self.shared.fps,
                threads_slider: self.shared.threads_slider,
                threads_note: self.shared.threads_note.as_deref(),
            };
            on_frame(&report);
        }
        if self.quit_requested()
            || self.options.frames.is_some_and(|n| self.frames >= n)
            || self.steps_done()
        {
            event_loop.exit();
        }
    }

    /// Whether `--steps` was given and the simulation has taken them.
    fn steps_done(&self) -> bool {
        self.options
            .steps
            .is_some_and(|n| self.machine.sim().is_some_and(|s| s.steps >= n))
    }

    /// Whether the app should end now: a state asked to, and the platform allows it.
    fn quit_requested(&self) -> bool {
        self.platform.can_quit && self.machine.should_quit()
    }

    /// Saves the settings when they changed, at most twice a second (the web has no "on
    /// exit": a page is simply closed).
    fn save_settings_when_changed(&mut self) {
        if !self.options.persist
            || self.shared.settings == self.saved
            || self.shared.time - self.saved_at < 0.5
        {
            return;
        }
        self.shared.settings.save();
        self.saved = self.shared.settings.clone();
        self.saved_at = self.shared.time;
    }

    /// Takes the graphics from their slot once the platform has set them up.
    fn poll_gfx(&mut self, event_loop: &ActiveEventLoop) {
        let Some(result) = self.gfx_slot.borrow_mut().take() else {
            return;
        };
        match result {
            Ok(gfx) => {
                self.shared.backend = backend_name(gfx.info.backend);
                let size = gfx.window.inner_size();
                self.shared.viewport = Vec2::new(size.width as f32, size.height as f32);
                self.shared.view_area = (Vec2::ZERO, self.shared.viewport);
                gfx.window.request_redraw();
                self.gfx = Some(gfx);
            }
            Err(e) => self.fail(event_loop, e),
        }
    }

    /// Writes a captured frame: to `--screenshot` for a scripted capture, else to a
    /// time-stamped file in the working directory (F12 / P).
    fn save_capture(&mut self, image: &Image, scripted: bool) -> Result<()> {
        if scripted && let Some(path) = self.options.screenshot.clone() {
            image.save_png(&path)?;
            self.screenshot_written = true;
        }
        if self.shared.toggles.screenshot_requested {
            self.shared.toggles.screenshot_requested = false;
            let secs = web_time::SystemTime::now()
                .duration_since(web_time::UNIX_EPOCH)
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
        Self::stats_of(
            self.frames,
            self.first_frame,
            self.last_frame,
            sim,
            &self.shared,
            self.gfx.as_ref(),
        )
    }

    fn stats_of(
        frames: u64,
        first_frame: Option<Instant>,
        last_frame: Option<Instant>,
        sim: Option<&Sim>,
        shared: &Shared,
        gfx: Option<&Gfx>,
    ) -> Stats {
        let elapsed = match (first_frame, last_frame) {
            (Some(a), Some(b)) if frames > 1 => {
                b.duration_since(a).as_secs_f64() * 1000.0 / (frames - 1) as f64
            }
            _ => 0.0,
        };
        let (width, height) = gfx.map_or((0, 0), |g| (g.config.width, g.config.height));
        Stats {
            frames,
            steps: sim.map_or(0, |s| s.total_steps),
            bodies: sim.map_or(0, |s| s.world.body_count()),
            awake_bodies: sim.map_or(0, |s| s.world.awake_body_count()),
            threads: sim.map_or(0, |s| s.world.thread_count()),
            backend: shared.backend.clone(),
            step_ms_mean: sim.map_or(0.0, Sim::step_ms_mean),
            scene: sim.map_or_else(String::new, |s| s.scene.name.clone()),
            frame_ms_mean: elapsed,
            adapter: gfx.map_or_else(String::new, |g| g.info.name.clone()),
            size: [width, height],
            state_hash: sim.map_or_else(String::new, |s| format!("{:016x}", s.world.state_hash())),
            non_finite_bodies: sim.map_or(0, |s| s.world.non_finite_bodies()),
            scene_steps: sim.map_or(0, |s| s.steps),
            sample: sim.and_then(|s| s.controller.clone()),
        }
    }
}

/// Mean height of the dynamic bodies (m); 0 when there are none.
fn mean_dynamic_height(sim: &Sim) -> f64 {
    let world = &sim.world;
    let (mut sum, mut n) = (0.0f64, 0usize);
    for (_, body) in world.bodies() {
        if body.kind == tumble_physics::BodyKind::Dynamic {
            sum += f64::from(body.position.y);
            n += 1;
        }
    }
    if n == 0 { 0.0 } else { sum / n as f64 }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_some() {
            return;
        }
        let window = match event_loop.create_window(self.platform.window.clone()) {
            Ok(w) => Arc::new(w),
            Err(e) => return self.fail(event_loop, anyhow!("cannot create the window: {e}")),
        };
        self.window = Some(Arc::clone(&window));
        self.egui.set_theme(egui::Theme::Dark);
        let future = Gfx::new(
            Arc::clone(&window),
            self.egui.clone(),
            self.shared.settings.vsync,
        );
        (self.platform.spawn_gfx)(Box::pin(future), Rc::clone(&self.gfx_slot));
        // Natively the graphics are there now; on the web they come in a later frame.
        self.poll_gfx(event_loop);
        window.request_redraw();
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        if self.gfx.is_none() {
            self.poll_gfx(event_loop);
        }
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
                let viewport = Vec2::new(size.width as f32, size.height as f32);
                if self.updating.is_some() {
                    self.deferred.push(Deferred::Viewport(viewport));
                } else {
                    self.shared.viewport = viewport;
                }
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
            if self.updating.is_some() {
                self.deferred.push(Deferred::Input(input, wants));
                return;
            }
            self.machine.input(input, wants, &mut self.shared);
            if self.quit_requested() {
                event_loop.exit();
            }
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        if self.gfx.is_none() {
            self.poll_gfx(event_loop);
        }
        // Keep frames coming (while the graphics are being set up, too, so that the frame
        // loop looks for them again).
        if let Some(window) = &self.window {
            window.request_redraw();
        }
    }
}
