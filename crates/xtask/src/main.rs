//! `cargo xtask TASK`: the project's own tasks, in plain Rust with std only.
//!
//! `cargo xtask test` runs every check CI runs (`.ci/run` calls it), in order, and installs
//! what a step needs first: a rustup component, or Debian packages. A task is a list of
//! [`Step`]s; to add a check, add a step to the list (with the packages it needs).

mod fuzz;
mod png;
mod web;

use std::env;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode, Stdio};
use std::time::Instant;

const USAGE_HEAD: &str = "usage: cargo xtask TASK [ARGS]

tasks:
  test    cargo fmt --check, cargo clippy -D warnings, cargo doc of the physics library
          with rustdoc's warnings as errors, cargo test, cargo package of the physics
          library and its examples, the viewer's offscreen rendering test, the
          viewer in a real window under Xvfb, the web build in chromium, and the peer
          comparison tests: every check CI runs (installs the rustfmt and clippy
          components, the web build's tools and the Debian packages the steps need when
          they are missing)";

fn usage() -> String {
    format!("{USAGE_HEAD}\n{}\n{}", web::USAGE, fuzz::USAGE)
}

/// What the viewer's steps need: Mesa's software Vulkan (lavapipe) and GL, so wgpu finds an
/// adapter with no GPU.
const MESA: &[&str] = &["mesa-vulkan-drivers", "libvulkan1"];

/// What a real window needs without a display: Xvfb, Mesa, and the X11/Wayland client
/// libraries winit loads at run time.
const XVFB_WINDOW: &[&str] = &[
    "xvfb",
    "xauth",
    "mesa-vulkan-drivers",
    "libgl1-mesa-dri",
    "libegl1",
    "libegl-mesa0",
    "libgles2",
    "libvulkan1",
    "libxkbcommon-x11-0",
    "libxcursor1",
    "libxrandr2",
    "libxi6",
    "libx11-xcb1",
    "libwayland-client0",
    "libwayland-egl1",
];

fn main() -> ExitCode {
    let args: Vec<String> = env::args().skip(1).collect();
    match args.first().map(String::as_str) {
        Some("test") if args.len() == 1 => run_task("test", &test_steps()),
        Some("web") => match web::task(&workspace_root(), &args[1..]) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("error: cargo xtask web: {e}");
                ExitCode::FAILURE
            }
        },
        Some("fuzz") => match fuzz::task(&workspace_root(), &args[1..]) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("error: cargo xtask fuzz: {e}");
                ExitCode::FAILURE
            }
        },
        Some("-h" | "--help" | "help") => {
            println!("{}", usage());
            ExitCode::SUCCESS
        }
        Some("test") => {
            eprintln!(
                "error: `cargo xtask test` takes no arguments\n\n{}",
                usage()
            );
            ExitCode::from(2)
        }
        Some(other) => {
            eprintln!("error: unknown task `{other}`\n\n{}", usage());
            ExitCode::from(2)
        }
        None => {
            eprintln!("error: no task given\n\n{}", usage());
            ExitCode::from(2)
        }
    }
}

/// One check of a task: what it needs, then what it runs.
struct Step {
    /// Short name, shown in the header and the summary.
    name: &'static str,
    /// Debian packages the step needs; missing ones are installed first (as root).
    debian_packages: &'static [&'static str],
    /// Rust toolchain components the step needs; missing ones are added with rustup.
    components: &'static [Component],
    /// What the step runs, from the workspace root.
    action: Action,
}

/// A rustup component and a command that succeeds only when it is installed.
struct Component {
    /// The name rustup knows it by.
    name: &'static str,
    /// Cargo arguments that succeed when the component is there.
    probe: &'static [&'static str],
}

const RUSTFMT: Component = Component {
    name: "rustfmt",
    probe: &["fmt", "--version"],
};
const CLIPPY: Component = Component {
    name: "clippy",
    probe: &["clippy", "--version"],
};

/// What a step runs.
enum Action {
    /// `cargo` (the one running xtask) with these arguments.
    Cargo(&'static [&'static str]),
    /// A check written here, with what it does in a few words.
    Check(&'static str, fn(&Path) -> Result<(), String>),
}

impl Action {
    fn describe(&self) -> String {
        match self {
            Action::Cargo(args) => format!("cargo {}", args.join(" ")),
            Action::Check(what, _) => (*what).to_string(),
        }
    }

    fn run(&self, root: &Path) -> Result<(), String> {
        match self {
            Action::Cargo(args) => {
                let mut cmd = Command::new(cargo());
                cmd.args(*args).current_dir(root);
                // Mesa (the offscreen rendering tests) wants a runtime directory; a private
                // one keeps it quiet when the environment has none, as in CI.
                if env::var_os("XDG_RUNTIME_DIR").is_none() {
                    let runtime = env::temp_dir()
                        .join(format!("tumble-xtask-runtime-{}", std::process::id()));
                    if std::fs::create_dir_all(&runtime).is_ok() {
                        set_private(&runtime);
                        cmd.env("XDG_RUNTIME_DIR", runtime);
                    }
                }
                run_status(&mut cmd, &self.describe())
            }
            Action::Check(_, check) => check(root),
        }
    }
}

/// The steps of `cargo xtask test`, in order.
fn test_steps() -> Vec<Step> {
    vec![
        Step {
            name: "fmt",
            debian_packages: &[],
            components: &[RUSTFMT],
            action: Action::Cargo(&["fmt", "--all", "--", "--check"]),
        },
        Step {
            name: "clippy",
            debian_packages: &[],
            components: &[CLIPPY],
            action: Action::Cargo(&[
                "clippy",
                "--workspace",
                "--all-targets",
                "-j2",
                "--",
                "-D",
                "warnings",
            ]),
        },
        Step {
            // The library's documentation: every link resolves, every code block is valid
            // rustdoc, nothing is left unexplained (rustdoc's warnings are errors here).
            name: "doc",
            debian_packages: &[],
            components: &[],
            action: Action::Check(
                "RUSTDOCFLAGS=\"-D warnings\" cargo doc -p tumble-physics --no-deps -j2",
                physics_docs,
            ),
        },
        Step {
            // The viewer is tested in release below, with the build the window step runs:
            // building wgpu and egui in the dev profile too would cost CI minutes.
            name: "test",
            debian_packages: &[],
            components: &[],
            action: Action::Cargo(&["test", "--workspace", "--exclude", "tumble", "-j2"]),
        },
        Step {
            // The physics library packages as a crate of its own (its manifest, docs and
            // examples; the packaged copy builds on its own).
            name: "package",
            debian_packages: &[],
            components: &[],
            action: Action::Cargo(&["package", "-p", "tumble-physics", "--allow-dirty", "-j2"]),
        },
        Step {
            name: "examples",
            debian_packages: &[],
            components: &[],
            action: Action::Check(
                "run every example in crates/physics/examples (each checks what it prints)",
                physics_examples,
            ),
        },
        Step {
            // Unit tests (states, input routing, fixed step, layouts) and offscreen rendering
            // on a real wgpu device (Mesa's lavapipe without a GPU), compared with a
            // reference image.
            name: "viewer",
            debian_packages: MESA,
            components: &[],
            action: Action::Cargo(&["test", "--release", "-p", "tumble", "-j2"]),
        },
        Step {
            name: "viewer-window",
            debian_packages: XVFB_WINDOW,
            components: &[],
            action: Action::Check(
                "tumble --scene pyramid --frames 300 --threads 2 in a window under Xvfb; \
                 check its screenshot and stats; play the platformer by its scripted keys \
                 to the runner's state",
                viewer_window,
            ),
        },
        Step {
            // The same viewer in a browser: the threaded wasm build, served with the
            // cross-origin isolation headers, driven in Debian's chromium (WebGL2 through
            // SwiftShader, and WebGPU) by tests/browser/web.test.mjs.
            name: "web",
            debian_packages: &["chromium", "fonts-dejavu-core"],
            components: &[],
            action: Action::Check(
                "clippy on the wasm build; build the web bundle, serve it, and test it in \
                 chromium (WebGL2 and WebGPU, threads, the thread slider, the platformer \
                 by scripted and by real keys) with node --test and playwright-core",
                web::browser_tests,
            ),
        },
        Step {
            name: "peers",
            debian_packages: &[],
            components: &[],
            action: Action::Cargo(&["test", "-p", "tumble-bench", "--features", "peers", "-j2"]),
        },
    ]
}

/// Builds the physics library's documentation with rustdoc's warnings as errors (a broken
/// intra-doc link, a bad code block, a private item linked from a public one).
fn physics_docs(root: &Path) -> Result<(), String> {
    let mut cmd = Command::new(cargo());
    cmd.current_dir(root)
        .args(["doc", "-p", "tumble-physics", "--no-deps", "-j2"])
        .env("RUSTDOCFLAGS", "-D warnings");
    run_status(
        &mut cmd,
        "RUSTDOCFLAGS=\"-D warnings\" cargo doc -p tumble-physics --no-deps -j2",
    )
}

/// Runs each example of the physics library (`crates/physics/examples/*.rs`, in name order):
/// each asserts what it shows, so a failing one exits non-zero.
fn physics_examples(root: &Path) -> Result<(), String> {
    let dir = root.join("crates/physics/examples");
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .map_err(|e| format!("cannot list {}: {e}", dir.display()))?
        .filter_map(|entry| {
            let path = entry.ok()?.path();
            (path.extension()? == "rs").then(|| path.file_stem()?.to_str().map(String::from))?
        })
        .collect();
    names.sort();
    if names.is_empty() {
        return Err(format!("no examples in {}", dir.display()));
    }
    for name in names {
        let mut cmd = Command::new(cargo());
        cmd.current_dir(root).args([
            "run",
            "-q",
            "-j2",
            "-p",
            "tumble-physics",
            "--example",
            &name,
        ]);
        run_status(
            &mut cmd,
            &format!("cargo run -p tumble-physics --example {name}"),
        )?;
    }
    Ok(())
}

/// Frames the scripted window run draws.
const WINDOW_FRAMES: u64 = 300;

/// Builds the viewer in release, runs it in a real window under Xvfb for
/// [`WINDOW_FRAMES`] frames with a screenshot and stats, and checks both: the stats report
/// every frame and some steps, and the screenshot is a real picture (many colours, and the
/// saturated colours of bodies, not only the greys of the background and the panels).
fn viewer_window(root: &Path) -> Result<(), String> {
    let mut build = Command::new(cargo());
    build
        .args(["build", "--release", "-p", "tumble", "-j2"])
        .current_dir(root);
    run_status(&mut build, "cargo build --release -p tumble -j2")?;

    let dir = env::temp_dir().join(format!("tumble-xtask-window-{}", std::process::id()));
    let runtime = dir.join("runtime");
    std::fs::create_dir_all(&runtime)
        .map_err(|e| format!("cannot create {}: {e}", runtime.display()))?;
    set_private(&runtime);
    let shot = dir.join("shot.png");
    let stats = dir.join("stats.json");
    // Where cargo put it: `CARGO_TARGET_DIR` when set, else `target/`.
    let binary = web::target_dir(root).join("release/tumble");
    let frames = WINDOW_FRAMES.to_string();
    let mut run = Command::new("xvfb-run");
    run.args(["-a", "-s", "-screen 0 1280x800x24"])
        .arg(&binary)
        .args(["--scene", "pyramid", "--frames", &frames, "--threads", "2"])
        .arg("--screenshot")
        .arg(&shot)
        .arg("--stats")
        .arg(&stats)
        .current_dir(root)
        // Mesa and winit look for a runtime directory; a private one keeps them quiet.
        .env("XDG_RUNTIME_DIR", &runtime)
        // The scripted run must not read or write the user's settings either way.
        .env("TUMBLE_CONFIG_DIR", dir.join("config"));
    let started = Instant::now();
    run_status(&mut run, "xvfb-run ... tumble --scene pyramid --frames 300")?;
    let secs = started.elapsed().as_secs_f64();

    let text = std::fs::read_to_string(&stats)
        .map_err(|e| format!("no stats at {}: {e}", stats.display()))?;
    let frames_seen = json_number(&text, "frames")?;
    let steps = json_number(&text, "steps")?;
    let frame_ms = json_number(&text, "frame_ms_mean").unwrap_or(0.0);
    if frames_seen != WINDOW_FRAMES as f64 {
        return Err(format!(
            "stats report {frames_seen} frames, not {WINDOW_FRAMES}: {text}"
        ));
    }
    if steps <= 0.0 {
        return Err(format!("stats report no physics steps: {text}"));
    }
    for key in ["bodies", "threads", "step_ms_mean"] {
        json_number(&text, key)?;
    }
    // The NaN guard keeps every pose finite, so only its count shows a broken step.
    if json_number(&text, "non_finite_bodies")? != 0.0 {
        return Err(format!("the step's NaN guard stopped bodies: {text}"));
    }

    let bytes =
        std::fs::read(&shot).map_err(|e| format!("no screenshot at {}: {e}", shot.display()))?;
    let image = png::decode(&bytes).map_err(|e| format!("{}: {e}", shot.display()))?;
    let mut colours = std::collections::HashSet::new();
    let mut saturated = 0usize;
    for p in image.rgba.chunks_exact(4) {
        colours.insert([p[0], p[1], p[2]]);
        let (max, min) = (p[0].max(p[1]).max(p[2]), p[0].min(p[1]).min(p[2]));
        if max - min > 60 {
            saturated += 1;
        }
    }
    println!(
        "window: {frames_seen} frames, {steps} steps, {frame_ms:.1} ms per frame, {secs:.1} s; \
         screenshot {}x{}, {} colours, {saturated} body-coloured pixels",
        image.width,
        image.height,
        colours.len()
    );
    if (image.width, image.height) != (1280, 800) {
        return Err(format!(
            "screenshot is {}x{}, not the 1280x800 window",
            image.width, image.height
        ));
    }
    if colours.len() < 16 {
        return Err(format!(
            "screenshot looks blank: {} distinct colours",
            colours.len()
        ));
    }
    if saturated < 500 {
        return Err(format!(
            "screenshot shows no bodies: {saturated} pixels of body colours"
        ));
    }
    platformer_window(root, &binary, &dir, &runtime)?;
    let _ = std::fs::remove_dir_all(&dir);
    Ok(())
}

/// The platformer played by its scripted keys (`--keys demo`) in a real window: it must end
/// exactly where the native runner's run ends (the same state hash), with its three coins and
/// the flag, never having sunk a centimetre into the ground, and its step well under a
/// millisecond.
fn platformer_window(root: &Path, binary: &Path, dir: &Path, runtime: &Path) -> Result<(), String> {
    let stats = dir.join("platformer.json");
    let steps = web::PLATFORMER_STEPS.to_string();
    let mut run = Command::new("xvfb-run");
    run.args(["-a", "-s", "-screen 0 1280x800x24"])
        .arg(binary)
        .args(["--scene", "platformer", "--keys", "demo", "--steps", &steps])
        .args(["--threads", "2", "--stats"])
        .arg(&stats)
        .current_dir(root)
        .env("XDG_RUNTIME_DIR", runtime)
        .env("TUMBLE_CONFIG_DIR", dir.join("config"));
    run_status(
        &mut run,
        "xvfb-run ... tumble --scene platformer --keys demo --steps 900",
    )?;
    let text = std::fs::read_to_string(&stats)
        .map_err(|e| format!("no stats at {}: {e}", stats.display()))?;
    let native = web::native_state_hash(root, &web::platformer_run())?;
    let hash = web::state_hash_of(&text).ok_or_else(|| format!("no state_hash: {text}"))?;
    if hash != native {
        return Err(format!(
            "the platformer in the window ends at state {hash}, the runner's run at {native}: {text}"
        ));
    }
    if json_number(&text, "scene_steps")? != web::PLATFORMER_STEPS as f64 {
        return Err(format!("the window did not stop at its --steps: {text}"));
    }
    if json_number(&text, "coins")? != 3.0 {
        return Err(format!(
            "the character did not take the three coins: {text}"
        ));
    }
    let reached = json_number(&text, "reached_flag")
        .map_err(|e| format!("the character did not reach the flag ({e}): {text}"))?;
    let deepest = json_number(&text, "deepest")?;
    if deepest > 0.01 {
        return Err(format!(
            "the character sank {deepest} m into the ground: {text}"
        ));
    }
    println!(
        "platformer window: the flag at step {reached}, 3 coins, deepest {deepest} m, state {hash} as natively, {:.3} ms a step",
        json_number(&text, "step_ms_mean")?
    );
    Ok(())
}

/// Makes a directory private to its owner (XDG requires it of a runtime directory).
fn set_private(dir: &Path) {
    let _ = Command::new("chmod").arg("700").arg(dir).status();
}

/// The number after `"key":` in a flat JSON object.
fn json_number(text: &str, key: &str) -> Result<f64, String> {
    let pattern = format!("\"{key}\"");
    let start = text
        .find(&pattern)
        .ok_or_else(|| format!("stats have no \"{key}\": {text}"))?
        + pattern.len();
    let rest = text[start..]
        .trim_start()
        .trim_start_matches(':')
        .trim_start();
    let end = rest
        .find(|c: char| !(c.is_ascii_digit() || "+-.eE".contains(c)))
        .unwrap_or(rest.len());
    rest[..end]
        .parse()
        .map_err(|_| format!("stats' \"{key}\" is not a number: {text}"))
}

/// Runs every step (a failed step does not stop the later ones, so one run shows every
/// problem), then prints one summary line. Fails if any step failed.
fn run_task(task: &str, steps: &[Step]) -> ExitCode {
    let root = workspace_root();
    let started = Instant::now();
    let mut failed: Vec<&str> = Vec::new();
    for (i, step) in steps.iter().enumerate() {
        println!(
            "\n==> [{}/{}] {}: {}",
            i + 1,
            steps.len(),
            step.name,
            step.action.describe()
        );
        let step_started = Instant::now();
        let result = prepare(step).and_then(|()| step.action.run(&root));
        let secs = step_started.elapsed().as_secs_f64();
        match result {
            Ok(()) => println!("==> {} ok ({secs:.1} s)", step.name),
            Err(e) => {
                println!("==> {} FAILED ({secs:.1} s): {e}", step.name);
                failed.push(step.name);
            }
        }
    }
    let secs = started.elapsed().as_secs_f64();
    let names: Vec<&str> = steps.iter().map(|s| s.name).collect();
    if failed.is_empty() {
        println!(
            "\n==> xtask {task}: OK, every step succeeded ({}) in {secs:.1} s",
            names.join(", ")
        );
        ExitCode::SUCCESS
    } else {
        println!(
            "\n==> xtask {task}: FAILED: {} ({} of {} steps succeeded) in {secs:.1} s",
            failed.join(", "),
            steps.len() - failed.len(),
            steps.len()
        );
        ExitCode::FAILURE
    }
}

/// Installs what a step needs.
fn prepare(step: &Step) -> Result<(), String> {
    if !step.debian_packages.is_empty() {
        ensure_debian_packages(step.debian_packages)?;
    }
    for component in step.components {
        ensure_component(component)?;
    }
    Ok(())
}

/// The cargo that runs us (`cargo xtask` sets `CARGO`), else the one on the PATH.
fn cargo() -> String {
    env::var("CARGO").unwrap_or_else(|_| "cargo".to_string())
}

/// The workspace root: two levels above this crate's manifest.
fn workspace_root() -> PathBuf {
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
    manifest
        .ancestors()
        .nth(2)
        .map(Path::to_path_buf)
        .unwrap_or_else(|| manifest.to_path_buf())
}

/// Runs a command with inherited output; an error says what failed and how.
fn run_status(cmd: &mut Command, what: &str) -> Result<(), String> {
    match cmd.status() {
        Ok(status) if status.success() => Ok(()),
        Ok(status) => Err(format!("`{what}` failed ({status})")),
        Err(e) => Err(format!("cannot run `{what}`: {e}")),
    }
}

/// Whether a command runs and exits 0, with its output hidden.
fn succeeds(cmd: &mut Command) -> bool {
    cmd.stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// Adds a rustup component when it is missing.
fn ensure_component(component: &Component) -> Result<(), String> {
    if succeeds(Command::new(cargo()).args(component.probe)) {
        return Ok(());
    }
    println!(
        "{} is missing; installing it: rustup component add {}",
        component.name, component.name
    );
    let what = format!("rustup component add {}", component.name);
    run_status(
        Command::new("rustup").args(["component", "add", component.name]),
        &what,
    )
    .map_err(|e| {
        format!(
            "{e}; the step needs the {} component of the Rust toolchain",
            component.name
        )
    })?;
    if succeeds(Command::new(cargo()).args(component.probe)) {
        Ok(())
    } else {
        Err(format!(
            "{} is still missing after `{what}`",
            component.name
        ))
    }
}

/// Whether a Debian package is installed, as `dpkg -s` reports it.
fn debian_package_installed(package: &str) -> Result<bool, String> {
    let output = Command::new("dpkg")
        .args(["-s", package])
        .stderr(Stdio::null())
        .output()
        .map_err(|e| format!("cannot run `dpkg -s {package}` ({e}); is this Debian?"))?;
    Ok(output.status.success()
        && String::from_utf8_lossy(&output.stdout).contains("Status: install ok installed"))
}

fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
}

/// Makes sure these Debian packages are installed: checks each with `dpkg -s`, and installs
/// the missing ones with `apt-get update` and `apt-get install -y` when running as root.
/// Otherwise it fails, naming what is missing and the command that installs it.
fn ensure_debian_packages(packages: &[&str]) -> Result<(), String> {
    let mut missing = Vec::new();
    for package in packages {
        if !debian_package_installed(package)? {
            missing.push(*package);
        }
    }
    if missing.is_empty() {
        return Ok(());
    }
    let list = missing.join(" ");
    if !is_root() {
        return Err(format!(
            "missing Debian packages: {list}; install them with:\n    sudo apt-get update && sudo apt-get install -y {list}"
        ));
    }
    println!("installing missing Debian packages: {list}");
    run_status(
        Command::new("apt-get")
            .arg("update")
            .env("DEBIAN_FRONTEND", "noninteractive"),
        "apt-get update",
    )?;
    run_status(
        Command::new("apt-get")
            .args(["install", "-y"])
            .args(&missing)
            .env("DEBIAN_FRONTEND", "noninteractive"),
        &format!("apt-get install -y {list}"),
    )?;
    let still: Vec<&str> = missing
        .iter()
        .copied()
        .filter(|p| !debian_package_installed(p).unwrap_or(false))
        .collect();
    if still.is_empty() {
        Ok(())
    } else {
        Err(format!(
            "still missing after apt-get install: {}",
            still.join(" ")
        ))
    }
}
