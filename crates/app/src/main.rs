//! `tumble`: the desktop viewer. With no arguments it opens at the intro; `--scene`,
//! `--threads`, `--frames`, `--screenshot` and `--stats` script it (CONTRACT.md, section 3).
//!
//! The only platform code of the app is here: the native entry (pollster waits for wgpu's
//! setup) and the web entry, which hands over to `tumble_app::web`.

#[cfg(not(target_arch = "wasm32"))]
fn main() -> std::process::ExitCode {
    native::main()
}

/// The web build's `main` runs as the module is instantiated: it installs the panic hooks.
/// The page then awaits `initThreadPool(n)` and calls `start()` (`tumble_app::web`).
#[cfg(target_arch = "wasm32")]
fn main() {
    tumble_app::web::main();
}

#[cfg(not(target_arch = "wasm32"))]
mod native {
    use std::process::ExitCode;

    use clap::Parser;
    use tumble_app::app::{GfxFuture, GfxSlot, Platform};
    use tumble_app::cli::Cli;

    /// Natively wgpu's setup is simply waited for.
    fn block_on(future: GfxFuture, slot: GfxSlot) {
        *slot.borrow_mut() = Some(pollster::block_on(future));
    }

    pub fn main() -> ExitCode {
        tumble_scene::cli::install_panic_hook("tumble");
        let cli = match Cli::try_parse() {
            Ok(cli) => cli,
            Err(e) => {
                let _ = e.print();
                return if e.use_stderr() {
                    ExitCode::from(2)
                } else {
                    ExitCode::SUCCESS
                };
            }
        };
        let result = cli
            .into_options()
            .and_then(|options| tumble_app::app::run(options, Platform::native(block_on)));
        match result {
            Ok(_) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("error: {}", tumble_scene::cli::one_line(e.as_ref()));
                ExitCode::from(2)
            }
        }
    }
}
