//! tumble's desktop viewer: a winit window, our own wgpu pipelines for the bodies, egui for the
//! panels, and a stack of states (intro, main menu, simulation, pause) under a global state
//! that sees every input first.
//!
//! The crate is a library plus a thin binary (`main.rs`), so that the state machine, the
//! fixed-step clock and the offscreen renderer are testable without a window. Nothing here
//! knows about the platform except the entry points, the thread setup ([`spawn_thread`] and
//! `web::threads`), the settings' storage and the clock (`web_time`). The same code builds
//! for the browser (`wasm32-unknown-unknown`), whose entry is the `web` module.
//!
//! A frame, in order: input events are routed (global state, then egui, then the state on
//! top) → the top state updates (the simulation steps its fixed-step clock) → egui builds the
//! UI → the scene renderer uploads instances → one render pass draws the world (one draw call
//! per shape kind, one for debug lines) and then egui on top.

pub mod app;
pub mod camera;
pub mod cli;
pub mod input;
pub mod metrics;
pub mod render;
pub mod settings;
pub mod sim;
pub mod state;
pub mod ui;
#[cfg(target_arch = "wasm32")]
pub mod web;

/// The scene the intro and the main menu run in the background, and the menu's default pick.
pub const DEFAULT_SCENE: &str = "falling_circles";

/// Starts a background thread: a std thread natively, a Web Worker on the web (where
/// `std::thread` cannot start one).
pub fn spawn_thread(name: &str, f: impl FnOnce() + Send + 'static) -> std::io::Result<()> {
    #[cfg(target_arch = "wasm32")]
    {
        let _ = name;
        web::threads::spawn(Box::new(f)).map_err(|_| {
            std::io::Error::new(
                std::io::ErrorKind::Unsupported,
                "no threads: the page is not cross-origin isolated",
            )
        })
    }
    #[cfg(not(target_arch = "wasm32"))]
    {
        std::thread::Builder::new()
            .name(name.to_string())
            .spawn(f)
            .map(drop)
    }
}
