//! `tumble-bench`: tumble's headless runner.
//!
//! `tumble-bench run SCENE [--steps N] [--threads T] [--substeps S] [--out FILE]` runs a scene
//! and writes one JSON document (see CONTRACT.md, section 2). `tumble-bench sweep` times scenes
//! against thread and body counts (table, CSV, SVG charts); `tumble-bench compare` (feature
//! `peers`) times the same scenes in tumble, Box2D v3 and Rapier2D; `tumble-bench report` measures
//! speed against error on the hard cases (docs/accuracy/REPORT.md); `tumble-bench schema`
//! prints the JSON Schema of scene files (docs/scene.schema.json). Each subcommand lives in its
//! own module; `main` only parses the command line and turns errors into a message and exit
//! code 2 (1 for a soak that found a non-finite state).

mod compare;
mod csv;
mod machine;
mod peers;
mod plot;
mod rays;
mod report;
mod run;
mod scenes;
mod schema;
mod soak;
mod sweep;
mod thresholds;
mod timing;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// tumble's headless runner: runs scenes without a window and reports what happened.
#[derive(Debug, Parser)]
#[command(name = "tumble-bench", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Run one scene for N steps; write the final state and the step's profile as JSON.
    Run(run::RunArgs),
    /// Time scenes against thread counts and a generated pile against body counts; print a
    /// table and write sweep.csv and SVG charts.
    Sweep(sweep::SweepArgs),
    /// Time the same scenes in tumble, Box2D v3 and Rapier2D (needs `--features peers`); write
    /// compare.md and compare.csv.
    Compare(compare::CompareArgs),
    /// Speed against error on the hard cases: sweep substeps, relax iterations and contact
    /// hertz, measure each case's error from the state, and write REPORT.md with one SVG per
    /// case (with `--features peers`, Box2D v3 and Rapier2D on the same cases).
    Report(report::ReportArgs),
    /// A long run of a pile of circles and boxes (default 20,000 bodies, 100,000 steps) that
    /// reports resident memory, contacts and finiteness at checkpoints; exits 1 if anything
    /// went non-finite.
    Soak(soak::SoakArgs),
    /// Where splitting each stage of the step over the threads begins to pay: the pile family
    /// stepped with every stage inline and with every stage split; writes a markdown table and
    /// the crossovers `WideThresholds::default()` is set from.
    Thresholds(thresholds::ThresholdsArgs),
    /// What a ray cast costs through the broad phase's tree against a scan of every shape, on
    /// a scene after it has run; both must find the same nearest hit.
    Rays(rays::RaysArgs),
    /// Print the JSON Schema of scene files (draft 2020-12), for editors; docs/scene.schema.json
    /// is its output.
    Schema(schema::SchemaArgs),
}

fn main() -> ExitCode {
    tumble_scene::cli::install_panic_hook("tumble-bench");
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            // clap writes "error: ..." with a usage line; --help and --version go to stdout.
            let _ = e.print();
            return if e.use_stderr() {
                ExitCode::from(2)
            } else {
                ExitCode::SUCCESS
            };
        }
    };
    let result = match cli.command {
        Command::Run(args) => run::run(&args),
        Command::Sweep(args) => sweep::run(&args),
        Command::Compare(args) => compare::run(&args),
        Command::Report(args) => report::run(&args),
        Command::Soak(args) => soak::run(&args),
        Command::Thresholds(args) => thresholds::run(&args),
        Command::Rays(args) => rays::run(&args),
        Command::Schema(args) => schema::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", tumble_scene::cli::one_line(e.as_ref()));
            ExitCode::from(exit_code(&e))
        }
    }
}

/// 1 for a soak that ran and found a non-finite state or a body the NaN guard stopped; 2 for
/// every other error (bad input, bad flags, I/O).
fn exit_code(e: &anyhow::Error) -> u8 {
    if e.is::<soak::Unhealthy>() { 1 } else { 2 }
}
