//! The command line (CONTRACT.md, section 3): with no arguments the viewer opens at its intro;
//! `--scene` skips to the simulation; `--frames`, `--screenshot` and `--stats` script it.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use anyhow::{Result, bail};
use clap::Parser;
use serde::Serialize;
use tumble_physics::SceneDef;
use tumble_scene::LoadLimits;
use tumble_scene::sample::KeyScript;

/// tumble, a 2D rigid-body physics engine: the desktop viewer.
///
/// With no arguments it opens at the intro. For scripts, tests and screenshots:
/// `tumble --scene pyramid --frames 300 --screenshot shot.png --stats stats.json`.
#[derive(Debug, Parser)]
#[command(name = "tumble", version, about)]
pub struct Cli {
    /// A `.ron` or `.json` scene file, or a built-in scene's name: skips the intro and the
    /// menu and starts that scene.
    #[arg(long, value_name = "SCENE")]
    pub scene: Option<String>,
    /// Worker threads for the step at start, >= 1 [default: the saved setting, else all
    /// cores].
    #[arg(
        long,
        value_name = "T",
        allow_negative_numbers = true,
        value_parser = clap::value_parser!(u32).range(1..=1024)
    )]
    pub threads: Option<u32>,
    /// Draw N frames, then exit with code 0.
    #[arg(
        long,
        value_name = "N",
        allow_negative_numbers = true,
        value_parser = clap::value_parser!(u64).range(1..)
    )]
    pub frames: Option<u64>,
    /// Write the last frame, as the window showed it, to FILE as PNG.
    #[arg(long, value_name = "FILE")]
    pub screenshot: Option<PathBuf>,
    /// Write, on exit, a JSON object with frames, steps, bodies, threads, backend and
    /// step_ms_mean (and more) to FILE.
    #[arg(long, value_name = "FILE")]
    pub stats: Option<PathBuf>,
    /// Do not wait for the display's refresh (to measure frame times).
    #[arg(long)]
    pub no_vsync: bool,
    /// Keys for a played sample, by step: `STEP:KEY+` (down) or `STEP:KEY-` (up), separated
    /// by commas, KEY one of left, right, jump, down (e.g. `0:right+,266:jump+,270:jump-`),
    /// or `demo` for the sample's own run through its level. Steps, not frames: the run is
    /// the same whatever the frame rate.
    #[arg(long, value_name = "SCRIPT")]
    pub keys: Option<String>,
    /// Stop the simulation at S steps since the scene started and exit once there (the
    /// screenshot and stats are of that step).
    #[arg(
        long,
        value_name = "S",
        allow_negative_numbers = true,
        value_parser = clap::value_parser!(u64).range(1..)
    )]
    pub steps: Option<u64>,
}

/// What the app runs with, checked.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// The scene to start in the simulation state (skipping intro and menu).
    pub scene: Option<Arc<SceneDef>>,
    /// Threads at start.
    pub threads: Option<usize>,
    /// Frames to draw before exiting.
    pub frames: Option<u64>,
    /// Where the last frame goes.
    pub screenshot: Option<PathBuf>,
    /// Where the stats go.
    pub stats: Option<PathBuf>,
    /// Vsync off, whatever the settings say.
    pub no_vsync: bool,
    /// Scripted keys for a played sample.
    pub keys: Option<KeyScript>,
    /// Steps to stop and exit at.
    pub steps: Option<u64>,
    /// Load and save the user's settings file (not for scripted runs, which must not depend on
    /// or change what a person set).
    pub persist: bool,
}

impl Cli {
    /// Loads the scene and checks the output paths, so a bad flag fails before any window
    /// opens.
    pub fn into_options(self) -> Result<Options> {
        let scene = match &self.scene {
            Some(source) => Some(Arc::new(tumble_scene::load(
                source,
                &LoadLimits::default(),
            )?)),
            None => None,
        };
        for (flag, path) in [("--screenshot", &self.screenshot), ("--stats", &self.stats)] {
            if let Some(path) = path {
                check_writable_parent(flag, path)?;
            }
        }
        let keys = match (&self.keys, &scene) {
            (Some(text), Some(scene)) => Some(
                KeyScript::for_scene(text, scene).map_err(|e| anyhow::anyhow!("--keys: {e}"))?,
            ),
            (Some(_), None) => {
                bail!(
                    "--keys: give the scene that reads them with --scene (e.g. --scene platformer)"
                )
            }
            (None, _) => None,
        };
        if self.steps.is_some() && self.scene.is_none() {
            bail!("--steps: give the scene to run with --scene");
        }
        let scripted = self.frames.is_some() || self.steps.is_some();
        Ok(Options {
            scene,
            threads: self.threads.map(|t| t as usize),
            frames: self.frames,
            screenshot: self.screenshot,
            stats: self.stats,
            no_vsync: self.no_vsync,
            keys,
            steps: self.steps,
            persist: !scripted,
        })
    }
}

fn check_writable_parent(flag: &str, path: &Path) -> Result<()> {
    if path.as_os_str().is_empty() || path.is_dir() {
        bail!("{flag} {}: not a file name", path.display());
    }
    let parent = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    if !parent.is_dir() {
        bail!(
            "{flag} {}: the directory {} does not exist",
            path.display(),
            parent.display()
        );
    }
    Ok(())
}

/// What `--stats` writes (CONTRACT.md section 3, plus a few more fields).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Stats {
    /// Frames drawn.
    pub frames: u64,
    /// Physics steps taken by the simulation.
    pub steps: u64,
    /// Bodies in the world (live ones: the user may have dropped and removed some).
    pub bodies: usize,
    /// Awake bodies at exit (kinematic ones and awake dynamic ones).
    pub awake_bodies: usize,
    /// Worker threads at exit.
    pub threads: usize,
    /// The graphics backend, as wgpu names it ("Vulkan", "Gl", ...).
    pub backend: String,
    /// Mean wall time of one step (ms).
    pub step_ms_mean: f64,
    /// The scene's name.
    pub scene: String,
    /// Mean wall time between frames (ms).
    pub frame_ms_mean: f64,
    /// The adapter's name (e.g. "llvmpipe (LLVM 15.0.6, 256 bits)").
    pub adapter: String,
    /// The window's size in physical pixels.
    pub size: [u32; 2],
    /// The world's state hash at exit, hex.
    pub state_hash: String,
    /// Steps since the scene (re)started.
    pub scene_steps: u64,
    /// A played sample's state at exit (the platformer's character and score), if any.
    pub sample: Option<tumble_scene::sample::Controller>,
    /// Bodies the step's NaN guard stopped since the scene started (0 in a healthy run):
    /// such a body keeps its last finite pose, so only this count tells.
    pub non_finite_bodies: u64,
}

impl Stats {
    /// Writes the stats as one JSON object.
    pub fn write(&self, path: &Path) -> Result<()> {
        let text = serde_json::to_string_pretty(self)?;
        std::fs::write(path, text + "\n")
            .map_err(|e| anyhow::anyhow!("cannot write {}: {e}", path.display()))
    }
}
