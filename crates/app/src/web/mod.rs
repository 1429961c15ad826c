//! The web entry: the same app in a page's canvas (`web/index.html`, `web/main.js`).
//!
//! The page loads the module (its `main` installs the panic hooks), awaits
//! `initThreadPool(n)` ([`threads`]), then calls [`start`], which reads `?scene=NAME&threads=T`
//! from the URL and hands the app to the page's event loop. After every frame the app's state
//! is published on `window.tumble` (CONTRACT.md, section 4) for tests and the curious.

pub mod threads;

use std::sync::Arc;

use wasm_bindgen::JsCast;
use wasm_bindgen::prelude::*;
use winit::platform::web::{EventLoopExtWebSys, WindowAttributesExtWebSys};
use winit::window::Window;

use crate::app::{FrameReport, GfxFuture, GfxSlot, Platform};
use crate::cli::Options;

/// The id of the page's canvas.
pub const CANVAS_ID: &str = "tumble-canvas";
/// The id of the element that shows a fatal error over the page.
pub const ERROR_ID: &str = "tumble-error";

/// The module's `main`: runs once, on the page's thread, as the module is instantiated.
pub fn main() {
    std::panic::set_hook(Box::new(|info| {
        // The message, with its place, in the console...
        console_error_panic_hook::hook(info);
        // ...and over the page, where a person sees it. A worker has no page: it leaves the
        // message for the page's thread, which looks for one twice a second (`takePanic`).
        let message = format!(
            "tumble stopped: {info}\n\nThis is a bug in tumble; please report it with the \
             page's address and this message."
        );
        if web_sys::window().is_some() {
            show_error(&message);
        } else if let Ok(mut slot) = PANIC.try_lock() {
            slot.get_or_insert(message);
        }
    }));
}

/// A panic's message from a worker, for the page to show.
static PANIC: wasm_sync::Mutex<Option<String>> = wasm_sync::Mutex::new(None);

/// The message of a panic on a worker, once; `undefined` if there was none.
#[wasm_bindgen(js_name = takePanic)]
pub fn take_panic() -> Option<String> {
    PANIC.try_lock().ok().and_then(|mut slot| slot.take())
}

/// Panics on purpose, for the test that the message shows over the page.
#[wasm_bindgen(js_name = testPanic)]
#[doc(hidden)]
pub fn test_panic() {
    panic!("a test asked for this panic (testPanic)");
}

/// Shows `message` over the page, in the element `#tumble-error` (made if missing). Does
/// nothing where there is no page (in a worker).
pub fn show_error(message: &str) {
    let Some(document) = web_sys::window().and_then(|w| w.document()) else {
        return;
    };
    let element = document.get_element_by_id(ERROR_ID).or_else(|| {
        let element = document.create_element("pre").ok()?;
        element.set_id(ERROR_ID);
        document.body()?.append_child(&element).ok()?;
        Some(element)
    });
    if let Some(element) = element {
        element.set_text_content(Some(message));
        let _ = element.remove_attribute("hidden");
    }
}

/// Starts the app in the page's canvas. Call once, after `initThreadPool`.
#[wasm_bindgen]
pub fn start() -> Result<(), JsValue> {
    let error = |e: anyhow::Error| JsValue::from_str(&format!("{e:#}"));
    let window = web_sys::window().ok_or("no window: start() runs in a page")?;
    let document = window.document().ok_or("no document")?;
    let canvas = document
        .get_element_by_id(CANVAS_ID)
        .ok_or_else(|| format!("the page has no <canvas id=\"{CANVAS_ID}\">"))?
        .dyn_into::<web_sys::HtmlCanvasElement>()
        .map_err(|_| format!("#{CANVAS_ID} is not a canvas"))?;
    let options = url_options(&window.location().search()?).map_err(error)?;

    let threads_note = (!threads::enabled()).then(|| {
        if threads::cross_origin_isolated() {
            "One thread: this build has no thread support.".to_string()
        } else {
            "One thread: this page is not cross-origin isolated (no SharedArrayBuffer), so the \
             step cannot use Web Workers. Serve it with the COOP and COEP headers (docs/web.md)."
                .to_string()
        }
    });
    let platform = Platform {
        spawn_gfx,
        window: Window::default_attributes()
            .with_title("tumble")
            .with_canvas(Some(canvas))
            .with_prevent_default(true)
            .with_focusable(true),
        poll: false,
        can_quit: false,
        threads_note,
        on_frame: Some(Box::new(Publisher::new(&window)?.into_callback())),
        offload: threads::enabled().then_some(threads::spawn as crate::app::Offload),
    };
    let (event_loop, app) = crate::app::prepare(options, platform).map_err(error)?;
    event_loop.spawn_app(app);
    Ok(())
}

/// Times the step as `tumble-bench run SCENE --threads T --steps N` does natively: builds the
/// scene's world with `threads` workers, steps it `steps` times, and takes the mean of
/// `World::profile().step_ms` over the steps (ms). It runs on a worker, as the app's steps
/// do, so the page's thread sleeps meanwhile; [`bench_result`] has the answer once it is
/// done. No frames are drawn. The page runs it for `?bench=SCENE&threads=T&steps=N`
/// (`web/main.js`). With `warmup > 0` a throwaway world of the same scene takes that many
/// steps first, untimed: the browser compiles and re-optimises the module's hot code during
/// its first steps (measured: a second run in the same page took 0.5 to 0.8 times the first's
/// ms), which a native build paid for when it was compiled. The timed world is the same
/// either way, so its state hash is too.
#[wasm_bindgen(js_name = benchStart)]
pub fn bench_start(scene: &str, threads: usize, steps: u32, warmup: u32) -> Result<(), JsValue> {
    let error = |e: anyhow::Error| JsValue::from_str(&format!("{e:#}"));
    let limits = tumble_scene::LoadLimits::default();
    let scene = tumble_scene::load(scene, &limits).map_err(|e| error(e.into()))?;
    let mut world = crate::sim::build_world(&scene).map_err(error)?;
    world.set_thread_count(threads.max(1));
    let mut throwaway = if warmup > 0 {
        let mut w = crate::sim::build_world(&scene).map_err(error)?;
        w.set_thread_count(threads.max(1));
        Some(w)
    } else {
        None
    };
    let run = move || {
        if let Some(w) = throwaway.as_mut() {
            for _ in 0..warmup {
                w.step(scene.dt, scene.substeps);
            }
        }
        drop(throwaway);
        let mut total = 0.0;
        let mut stages: Vec<(&'static str, f64)> = Vec::new();
        for _ in 0..steps {
            world.step(scene.dt, scene.substeps);
            let profile = world.profile();
            total += profile.step_ms;
            for (i, (name, ms)) in profile.stages().into_iter().enumerate() {
                match stages.get_mut(i) {
                    Some(sum) => sum.1 += ms,
                    None => stages.push((name, ms)),
                }
            }
        }
        let mean = |sum: f64| {
            if steps == 0 {
                0.0
            } else {
                sum / f64::from(steps)
            }
        };
        // The state after the run, hashed as `tumble-bench run` reports it natively: the
        // browser tests check the two are equal, at 1 and at 2 threads.
        let mut json = format!(
            "{{\"step_ms_mean\": {}, \"state_hash\": \"{:016x}\"",
            mean(total),
            world.state_hash()
        );
        for (name, sum) in stages {
            json.push_str(&format!(", \"{name}_ms_mean\": {}", mean(sum)));
        }
        json.push('}');
        if let Ok(mut result) = BENCH.lock() {
            *result = Some(json);
        }
    };
    if let Err(run) = threads::spawn(Box::new(run)) {
        // No threads: here, on the page's thread.
        run();
    }
    Ok(())
}

static BENCH: wasm_sync::Mutex<Option<String>> = wasm_sync::Mutex::new(None);

/// The result of [`bench_start`], as JSON: the mean ms per step and per stage, as
/// `tumble-bench run` writes them in its `profile`, and the final `state_hash`; `undefined`
/// while it runs.
#[wasm_bindgen(js_name = benchResult)]
pub fn bench_result() -> Option<String> {
    BENCH.lock().ok().and_then(|r| r.clone())
}

/// The options a page's address gives: `?scene=NAME` starts that scene (skipping the intro
/// and the menu), `&threads=T` its thread count, `&keys=SCRIPT` keys for a played sample by
/// step (as the viewer's `--keys`), `&steps=S` stops the simulation at S steps.
pub fn url_options(search: &str) -> anyhow::Result<Options> {
    let params = web_sys::UrlSearchParams::new_with_str(search)
        .map_err(|_| anyhow::anyhow!("cannot read the page's address"))?;
    let scene = match params.get("scene").filter(|s| !s.is_empty()) {
        Some(name) => Some(Arc::new(tumble_scene::load(
            &name,
            &tumble_scene::LoadLimits::default(),
        )?)),
        None => None,
    };
    let threads = match params.get("threads") {
        Some(t) => {
            let n: usize = t
                .parse()
                .ok()
                .filter(|&n| n >= 1)
                .ok_or_else(|| anyhow::anyhow!("threads={t}: not a whole number >= 1"))?;
            Some(n.min(tumble_physics::default_thread_count()))
        }
        None => None,
    };
    let keys = match (params.get("keys").filter(|k| !k.is_empty()), &scene) {
        (Some(text), Some(scene)) => Some(
            tumble_scene::sample::KeyScript::for_scene(&text, scene)
                .map_err(|e| anyhow::anyhow!("keys={text}: {e}"))?,
        ),
        (Some(text), None) => anyhow::bail!("keys={text}: give the scene too (scene=platformer)"),
        (None, _) => None,
    };
    let steps = match params.get("steps") {
        Some(t) => Some(
            t.parse::<u64>()
                .ok()
                .filter(|&n| n >= 1)
                .ok_or_else(|| anyhow::anyhow!("steps={t}: not a whole number >= 1"))?,
        ),
        None => None,
    };
    let scripted = keys.is_some() || steps.is_some();
    Ok(Options {
        scene,
        threads,
        keys,
        steps,
        // A scripted page must not depend on or change what a person set.
        persist: !scripted,
        ..Options::default()
    })
}

/// The web awaits wgpu's setup on the page's event loop.
fn spawn_gfx(future: GfxFuture, slot: GfxSlot) {
    wasm_bindgen_futures::spawn_local(async move {
        let result = future.await;
        *slot.borrow_mut() = Some(result);
    });
}

/// Writes each frame's report into `window.tumble`.
struct Publisher {
    object: js_sys::Object,
    isolated: bool,
}

impl Publisher {
    fn new(window: &web_sys::Window) -> Result<Self, JsValue> {
        let object = js_sys::Object::new();
        js_sys::Reflect::set(window, &JsValue::from_str("tumble"), &object)?;
        Ok(Self {
            object,
            isolated: threads::cross_origin_isolated(),
        })
    }

    fn into_callback(self) -> impl FnMut(&FrameReport<'_>) {
        move |report| self.publish(report)
    }

    fn set(&self, key: &str, value: JsValue) {
        let _ = js_sys::Reflect::set(&self.object, &JsValue::from_str(key), &value);
    }

    fn publish(&self, r: &FrameReport<'_>) {
        let s = r.stats;
        let num = |v: f64| JsValue::from_f64(v);
        self.set("frames", num(s.frames as f64));
        self.set("steps", num(s.steps as f64));
        self.set("bodies", num(s.bodies as f64));
        self.set("awake_bodies", num(s.awake_bodies as f64));
        self.set("threads", num(s.threads as f64));
        self.set("backend", JsValue::from_str(&s.backend));
        self.set("scene", JsValue::from_str(&s.scene));
        self.set("step_ms_mean", num(s.step_ms_mean));
        self.set("cross_origin_isolated", JsValue::from_bool(self.isolated));
        self.set("non_finite_bodies", num(s.non_finite_bodies as f64));
        self.set("state_hash", JsValue::from_str(&s.state_hash));
        self.set("scene_steps", num(s.scene_steps as f64));
        self.set(
            "sample",
            s.sample
                .as_ref()
                .and_then(|c| serde_json::to_string(c).ok())
                .map_or(JsValue::NULL, |j| JsValue::from_str(&j)),
        );
        // Beyond the contract: what tests and the benchmark look at.
        self.set("threads_enabled", JsValue::from_bool(threads::enabled()));
        self.set("max_threads", num(r.max_threads as f64));
        self.set("frame_ms_mean", num(s.frame_ms_mean));
        self.set("fps", num(r.fps));
        self.set("adapter", JsValue::from_str(&s.adapter));
        self.set(
            "size",
            JsValue::from(js_sys::Array::of2(
                &num(s.size[0].into()),
                &num(s.size[1].into()),
            )),
        );
        self.set(
            "state",
            JsValue::from_str(&r.state.map_or(String::new(), |k| format!("{k:?}"))),
        );
        self.set("mean_y", num(r.mean_y));
        self.set("sim_time", num(r.sim_time));
        let slider = match r.threads_slider {
            Some(rect) => {
                let o = js_sys::Object::new();
                for (k, v) in [
                    ("x", rect.min.x),
                    ("y", rect.min.y),
                    ("width", rect.width()),
                    ("height", rect.height()),
                ] {
                    let _ = js_sys::Reflect::set(&o, &JsValue::from_str(k), &num(v.into()));
                }
                o.into()
            }
            None => JsValue::NULL,
        };
        self.set("threads_slider", slider);
        self.set(
            "threads_note",
            r.threads_note.map_or(JsValue::NULL, JsValue::from_str),
        );
    }
}
