//! `cargo xtask TASK`: the project's own tasks, in plain Rust with std only.
//!
//! `cargo xtask test` runs every check CI runs (`.ci/run` calls it), in order, and installs
//! what a step needs first: a rustup component, or Debian packages. A task is a list of
//! [`Step`]s; to add a check, add a step to the list (with the packages it needs).

use std::env;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode, Stdio};
use std::time::Instant;

const USAGE: &str = "usage: cargo xtask TASK

tasks:
  test    cargo fmt --check, cargo clippy -D warnings, cargo test: every check CI runs
          (installs the rustfmt and clippy components when they are missing)";

fn main() -> ExitCode {
    let args: Vec<String> = env::args().skip(1).collect();
    match args.first().map(String::as_str) {
        Some("test") if args.len() == 1 => run_task("test", &test_steps()),
        Some("-h" | "--help" | "help") => {
            println!("{USAGE}");
            ExitCode::SUCCESS
        }
        Some("test") => {
            eprintln!("error: `cargo xtask test` takes no arguments\n\n{USAGE}");
            ExitCode::from(2)
        }
        Some(other) => {
            eprintln!("error: unknown task `{other}`\n\n{USAGE}");
            ExitCode::from(2)
        }
        None => {
            eprintln!("error: no task given\n\n{USAGE}");
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
}

impl Action {
    fn describe(&self) -> String {
        match self {
            Action::Cargo(args) => format!("cargo {}", args.join(" ")),
        }
    }

    fn run(&self, root: &Path) -> Result<(), String> {
        match self {
            Action::Cargo(args) => {
                let mut cmd = Command::new(cargo());
                cmd.args(*args).current_dir(root);
                run_status(&mut cmd, &self.describe())
            }
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
            name: "test",
            debian_packages: &[],
            components: &[],
            action: Action::Cargo(&["test", "--workspace", "-j2"]),
        },
    ]
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
