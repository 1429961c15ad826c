//! `tumble`: until the wgpu viewer lands, runs a scene headless and prints a short summary.
//!
//! `cargo run --release` runs the default scene (`falling_circles`); `--scene`, `--threads` and
//! `--steps` are the names the viewer will take too (CONTRACT.md, section 3).

use std::process::ExitCode;
use std::time::Instant;

use anyhow::{Context, Result};
use clap::Parser;
use tumble_physics::{World, default_thread_count};
use tumble_scene::LoadLimits;

/// The scene run when none is given.
const DEFAULT_SCENE: &str = "falling_circles";

/// tumble, a 2D rigid-body physics engine. For now this runs a scene headless and prints a
/// summary; the interactive viewer comes later.
#[derive(Debug, Parser)]
#[command(name = "tumble", version, about)]
struct Cli {
    /// A `.ron` or `.json` scene file, or a built-in scene's name.
    #[arg(long, value_name = "SCENE", default_value = DEFAULT_SCENE)]
    scene: String,
    /// Worker threads for the step, >= 1 [default: all cores].
    #[arg(
        long,
        value_name = "T",
        allow_negative_numbers = true,
        value_parser = clap::value_parser!(u32).range(1..=1024)
    )]
    threads: Option<u32>,
    /// Steps to run [default: the scene's `steps`].
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    steps: Option<u32>,
}

fn main() -> ExitCode {
    install_panic_hook();
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
    match run(&cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", message(&e));
            ExitCode::from(2)
        }
    }
}

fn run(cli: &Cli) -> Result<()> {
    let limits = LoadLimits::default();
    let scene = tumble_scene::load(&cli.scene, &limits)?;
    let mut world = World::from_scene(&scene, &limits.scene)
        .with_context(|| format!("{}: cannot build the world", cli.scene))?;
    let threads = cli
        .threads
        .map_or_else(default_thread_count, |t| t as usize);
    world.set_thread_count(threads.max(1));
    let steps = cli.steps.unwrap_or(scene.steps);

    let started = Instant::now();
    let mut step_ms = 0.0;
    let mut stages: Vec<(&'static str, f64)> = Vec::new();
    for _ in 0..steps {
        world.step(scene.dt, scene.substeps);
        let profile = world.profile();
        step_ms += profile.step_ms;
        let now = profile.stages();
        if stages.is_empty() {
            stages = now.iter().map(|&(name, _)| (name, 0.0)).collect();
        }
        for (sum, (_, ms)) in stages.iter_mut().zip(now.iter()) {
            sum.1 += ms;
        }
    }
    let wall = started.elapsed().as_secs_f64();
    let mean = |total: f64| {
        if steps == 0 {
            0.0
        } else {
            total / f64::from(steps)
        }
    };

    println!("tumble (headless; the viewer comes later)");
    println!("scene      {}", scene.name);
    println!("bodies     {}", world.body_count());
    println!(
        "steps      {steps} of {:.4} s, {} substeps ({:.2} s simulated in {wall:.2} s)",
        scene.dt,
        scene.substeps,
        f64::from(steps) * f64::from(scene.dt)
    );
    println!("threads    {}", world.thread_count());
    println!("step       {:.3} ms mean", mean(step_ms));
    let width = stages.iter().map(|(name, _)| name.len()).max().unwrap_or(0);
    for (name, total) in &stages {
        println!("  {name:<width$} {:.3} ms", mean(*total));
    }
    println!("contacts   {}", world.contact_count());
    println!("state hash {:016x}", world.state_hash());
    Ok(())
}

/// The error and its causes on one line, leaving out a cause its parent already spells out.
fn message(e: &anyhow::Error) -> String {
    let mut text = String::new();
    for cause in e.chain() {
        let part = cause.to_string();
        if text.contains(&part) {
            continue;
        }
        if !text.is_empty() {
            text.push_str(": ");
        }
        text.push_str(&part);
    }
    text
}

/// A bug must still end in one line a person can report, never in a wall of runtime output.
fn install_panic_hook() {
    std::panic::set_hook(Box::new(|info| {
        let payload = info.payload();
        let what = payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown failure".to_string());
        let place = info
            .location()
            .map(|l| format!(" at {}:{}", l.file(), l.line()))
            .unwrap_or_default();
        eprintln!(
            "error: internal error{place}: {what} (a bug in tumble; please report it with the command that was run)"
        );
    }));
}
