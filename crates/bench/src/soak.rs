//! `tumble-bench soak`: a long run of the soak pile (by default 20,000 bodies for 100,000
//! steps, about half an hour on 2 cores) that reports memory and finiteness as it goes, and
//! exits 1 if a body's state went non-finite: seen at a checkpoint, or stopped by the step's
//! NaN guard at any step (`World::non_finite_bodies`, which a frozen body leaves as the only
//! trace). For a person to run, not CI; the short version is `tests/tests/soak.rs`.

use std::io::Write;
use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use serde::Serialize;
use tumble_physics::{Limits, World, default_thread_count};
use tumble_scene::builtin::soak_pile;

/// Arguments of `tumble-bench soak`.
#[derive(Debug, Args)]
pub struct SoakArgs {
    /// Dynamic bodies in the pile.
    #[arg(long, value_name = "N", default_value_t = 20_000,
          value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
    pub bodies: u32,
    /// Steps to run.
    #[arg(long, value_name = "N", default_value_t = 100_000,
          value_parser = clap::value_parser!(u64).range(1..))]
    pub steps: u64,
    /// Worker threads for the step [default: all cores].
    #[arg(long, value_name = "T", value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub threads: Option<u32>,
    /// Checkpoints over the run (a line each: memory, contacts, finiteness, ms/step).
    #[arg(long, value_name = "N", default_value_t = 10,
          value_parser = clap::value_parser!(u64).range(1..=10_000))]
    pub checkpoints: u64,
    /// Also write the summary as JSON to FILE.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

/// One checkpoint of the run.
#[derive(Debug, Serialize)]
struct Checkpoint {
    step: u64,
    wall_s: f64,
    resident_kb: u64,
    peak_resident_kb: u64,
    contacts: usize,
    finite: bool,
    /// Bodies the numerical guard stopped since the last checkpoint.
    guard_fired: u64,
    /// Mean ms per step since the last checkpoint.
    step_ms_mean: f64,
}

/// What `soak` writes with `--out`.
#[derive(Debug, Serialize)]
struct Summary {
    bodies: usize,
    steps: u64,
    threads: usize,
    /// Resident memory after the first checkpoint, when the pile has formed (KB).
    warm_resident_kb: u64,
    /// The process's peak resident memory over the run (KB, the kernel's high-water mark).
    peak_resident_kb: u64,
    /// Whether every body stayed finite at every checkpoint.
    finite: bool,
    /// Bodies the numerical guard stopped over the run (`World::non_finite_bodies`); the
    /// soak fails unless it is 0.
    guard_fired: u64,
    /// Times a speed cap bit (a body in a substep), over the run.
    speed_caps: u64,
    checkpoints: Vec<Checkpoint>,
}

/// A field of `/proc/self/status` in KB (`VmRSS`, `VmHWM`); 0 where there is no /proc.
fn status_kb(field: &str) -> u64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|text| {
            text.lines()
                .find(|l| l.starts_with(field))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|v| v.parse().ok())
        })
        .unwrap_or(0)
}

/// Why a soak failed after running to the end: a body's state went non-finite. `main` exits 1
/// for it (2 is for bad input and other errors).
#[derive(Debug)]
pub struct Unhealthy(String);

impl std::fmt::Display for Unhealthy {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Unhealthy {}

/// The soak's verdict: an [`Unhealthy`] error if a checkpoint saw a non-finite state or the
/// NaN guard stopped any body over the run.
fn verdict(finite: bool, guard_fired: u64) -> Result<(), Unhealthy> {
    if !finite {
        return Err(Unhealthy(
            "soak: a body's state went non-finite (see the checkpoints above)".into(),
        ));
    }
    if guard_fired > 0 {
        return Err(Unhealthy(format!(
            "soak: the NaN guard had to stop {guard_fired} bodies whose state turned non-finite \
             (see the checkpoints above)"
        )));
    }
    Ok(())
}

/// Runs the soak; exits non-zero (through the error, an [`Unhealthy`] one) if any body went
/// non-finite or the NaN guard stopped any.
pub fn run(args: &SoakArgs) -> Result<()> {
    let scene = soak_pile(args.bodies as usize);
    let limits = Limits {
        max_bodies: scene.bodies.len(),
        ..Limits::default()
    };
    let mut world = World::from_scene(&scene, &limits).context("soak: cannot build the world")?;
    let threads = args
        .threads
        .map_or_else(default_thread_count, |t| t as usize);
    world.set_thread_count(threads);
    eprintln!(
        "soak: {} bodies ({} dynamic), {} steps of {:.4} s, {} substeps, {} threads",
        scene.bodies.len(),
        args.bodies,
        args.steps,
        scene.dt,
        scene.substeps,
        world.thread_count()
    );
    let bar = ProgressBar::new(args.steps);
    bar.set_style(
        ProgressStyle::with_template("{bar:40} {pos}/{len} steps, {elapsed} elapsed, eta {eta}")
            .expect("a valid template"),
    );
    let every = (args.steps / args.checkpoints).max(1);
    let start = Instant::now();
    let mut checkpoints = Vec::new();
    let (mut guard_before, mut ms_since, mut steps_since) = (0u64, 0.0, 0u64);
    for step in 1..=args.steps {
        world.step(scene.dt, scene.substeps);
        let profile = world.profile();
        ms_since += profile.step_ms;
        steps_since += 1;
        if step.is_multiple_of(every) || step == args.steps {
            let c = Checkpoint {
                step,
                wall_s: start.elapsed().as_secs_f64(),
                resident_kb: status_kb("VmRSS:"),
                peak_resident_kb: status_kb("VmHWM:"),
                contacts: world.contact_count(),
                finite: world.is_finite(),
                guard_fired: world.non_finite_bodies() - guard_before,
                step_ms_mean: ms_since / steps_since as f64,
            };
            bar.suspend(|| {
                println!(
                    "step {}: {:.0} s, resident {} KB (peak {} KB), {} contacts, finite {}, guard fired {}, {:.2} ms/step",
                    c.step,
                    c.wall_s,
                    c.resident_kb,
                    c.peak_resident_kb,
                    c.contacts,
                    c.finite,
                    c.guard_fired,
                    c.step_ms_mean
                );
            });
            guard_before = world.non_finite_bodies();
            (ms_since, steps_since) = (0.0, 0);
            checkpoints.push(c);
        }
        bar.inc(1);
    }
    bar.finish_and_clear();
    let summary = Summary {
        bodies: scene.bodies.len(),
        steps: args.steps,
        threads: world.thread_count(),
        warm_resident_kb: checkpoints.first().map_or(0, |c| c.resident_kb),
        peak_resident_kb: status_kb("VmHWM:"),
        finite: checkpoints.iter().all(|c| c.finite),
        guard_fired: world.non_finite_bodies(),
        speed_caps: world.speed_cap_count(),
        checkpoints,
    };
    println!(
        "soak: peak resident {} KB (after the first checkpoint {} KB), finite {}, guard fired {} times, speed cap bit {} times",
        summary.peak_resident_kb,
        summary.warm_resident_kb,
        summary.finite,
        summary.guard_fired,
        summary.speed_caps
    );
    if let Some(path) = &args.out {
        let mut file = std::fs::File::create(path)
            .with_context(|| format!("cannot create the output file {}", path.display()))?;
        serde_json::to_writer_pretty(&mut file, &summary)
            .map_err(std::io::Error::from)
            .and_then(|()| writeln!(file))
            .with_context(|| format!("cannot write the output file {}", path.display()))?;
    }
    verdict(summary.finite, summary.guard_fired)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_soak_fails_when_the_guard_fired_even_if_every_state_is_finite() {
        assert!(verdict(true, 0).is_ok());
        let e = verdict(true, 3).unwrap_err().to_string();
        assert!(e.contains("NaN guard") && e.contains('3'), "{e}");
        assert!(verdict(false, 0).is_err());
        // What main turns into exit code 1.
        let e = anyhow::Error::from(verdict(true, 1).unwrap_err());
        assert!(e.is::<Unhealthy>());
    }
}
