//! `tumble-bench report`: speed against error on the hard cases of issue 5.
//!
//! For each case (`report/cases.rs`) and each engine this build has (tumble; Box2D v3 and
//! Rapier2D with the `peers` feature), every knob setting of the sweep (`report/engines.rs`)
//! is one run of a fresh world: only the step calls are timed, and after every step a probe
//! reads poses and velocities (outside the clock) to compute the case's error metrics, the
//! same code for every engine. The report writes `REPORT.md` (machine, build, settings, a table
//! per case, the summary of the cheapest passing setting per case and engine), `report.csv`
//! (every point, long format) and one SVG per case (`report/chart.rs`).

mod cases;
mod chart;
mod engines;
mod joint_cases;
mod overlap;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use clap::Args;

use crate::csv::csv_field;
use crate::machine;
use cases::Case;
use engines::{Engine, Knobs};

/// Arguments of `tumble-bench report`.
#[derive(Debug, Args)]
pub struct ReportArgs {
    /// A tiny run for smoke tests: every case for 10 steps, two tumble settings and one per
    /// peer. Its numbers mean nothing.
    #[arg(long)]
    pub quick: bool,
    /// Where REPORT.md, report.csv and the SVGs go (created if missing).
    #[arg(long, value_name = "DIR", default_value = "docs/accuracy")]
    pub out_dir: PathBuf,
    /// Only these cases (keys as in report.csv, e.g. `large_pyramid,projectile`).
    #[arg(long, value_name = "A,B,..", value_delimiter = ',')]
    pub cases: Option<Vec<String>>,
    /// Only these engines (`tumble`, `box2d`, `rapier`) [default: every engine this build has].
    #[arg(long, value_name = "A,B,..", value_delimiter = ',')]
    pub engines: Option<Vec<String>>,
    /// Worker threads of every engine (1 keeps the comparison about the solvers, not the
    /// schedulers).
    #[arg(long, value_name = "T", default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=32))]
    pub threads: u32,
}

/// One run: a case, an engine, a setting.
struct Point {
    engine: Engine,
    knobs: Knobs,
    ms: f64,
    values: Vec<f64>,
    pass: bool,
    /// Set when the engine failed (an error, not a bad number).
    failed: Option<String>,
}

/// Runs the report.
pub fn run(args: &ReportArgs) -> Result<()> {
    let started = Instant::now();
    let load_before = machine::load_average();
    let mut all = cases::all(args.quick)?;
    if let Some(keys) = &args.cases {
        for k in keys {
            if !all.iter().any(|c| c.key == k) {
                bail!(
                    "no case {k:?}; cases: {}",
                    all.iter().map(|c| c.key).collect::<Vec<_>>().join(", ")
                );
            }
        }
        all.retain(|c| keys.iter().any(|k| k == c.key));
    }
    let mut engines = Engine::available();
    if let Some(keys) = &args.engines {
        for k in keys {
            if !engines.iter().any(|e| e.key() == k) {
                bail!(
                    "no engine {k:?} in this build; engines: {}",
                    engines
                        .iter()
                        .map(|e| e.key())
                        .collect::<Vec<_>>()
                        .join(", ")
                );
            }
        }
        engines.retain(|e| keys.iter().any(|k| k == e.key()));
    }
    let warnings = warnings();
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    std::fs::create_dir_all(&args.out_dir)
        .with_context(|| format!("cannot create {}", args.out_dir.display()))?;
    let threads = args.threads as usize;

    let mut results: Vec<(Case, Vec<Point>, f64)> = Vec::new();
    for case in all {
        let case_start = Instant::now();
        let mut points = Vec::new();
        for &engine in &engines {
            for knobs in engine.sweep(args.quick, &case.extras) {
                let point = run_point(&case, engine, knobs, threads);
                eprintln!(
                    "{:<18} {:<7} {:<22} {:>9.4} ms/step  {}{}",
                    case.key,
                    engine.title(),
                    knobs.label(),
                    point.ms,
                    case.metrics
                        .iter()
                        .zip(&point.values)
                        .filter(|(m, _)| m.plot)
                        .map(|(m, v)| format!("{} {}", m.key, fmt(*v)))
                        .collect::<Vec<_>>()
                        .join("  "),
                    match &point.failed {
                        Some(e) => format!("  FAILED: {e}"),
                        None if point.pass => "  pass".into(),
                        None => "  fail".into(),
                    }
                );
                points.push(point);
            }
        }
        let secs = case_start.elapsed().as_secs_f64();
        results.push((case, points, secs));
    }
    let load = format!("{load_before} before, {} after", machine::load_average());
    let wall = started.elapsed().as_secs_f64();

    let mut written = Vec::new();
    for (case, points, _) in &results {
        let path = args.out_dir.join(format!("{}.svg", case.key));
        chart::write(&path, &chart_title(case), &panels(case, points, &engines))?;
        written.push(path);
    }
    let csv = args.out_dir.join("report.csv");
    write(&csv, &csv_text(&results))?;
    written.push(csv);
    let md = args.out_dir.join("REPORT.md");
    let text = markdown(&results, &engines, args, &load, wall, &warnings);
    write(&md, &text)?;
    written.push(md);
    print!("{}", summary_text(&results, &engines));
    for p in &written {
        println!("wrote {}", p.display());
    }
    Ok(())
}

fn write(path: &Path, text: &str) -> Result<()> {
    std::fs::write(path, text).with_context(|| format!("cannot write {}", path.display()))
}

/// Runs whose steps take less than this in all (s) are timed again, [`SHORT_REPEATS`] times in
/// all, and keep the fastest: one scheduler hiccup is a large share of a few milliseconds.
const SHORT_RUN: f64 = 0.25;
/// Timing runs of a short run (the first one included).
const SHORT_REPEATS: u32 = 5;

/// One run of a case in an engine at a setting; an engine error is recorded, not raised.
/// The metrics come from the first run (every engine is deterministic on one thread); a
/// short run's ms/step is the fastest of [`SHORT_REPEATS`] runs.
fn run_point(case: &Case, engine: Engine, knobs: Knobs, threads: usize) -> Point {
    let steps = case.steps.max(1);
    let attempt = || -> Result<(f64, Vec<f64>)> {
        let mut sim = engines::build(engine, &case.scene, &knobs, threads)?;
        let mut probe = (case.probe)();
        let mut total = 0.0_f64;
        for step in 1..=steps {
            let t = Instant::now();
            sim.step()?;
            total += t.elapsed().as_secs_f64();
            probe.after_step(sim.as_mut(), step)?;
        }
        let values = guarded(probe.finish(sim.as_mut())?, sim.non_finite_bodies());
        let mut best = total;
        if total < SHORT_RUN {
            for _ in 1..SHORT_REPEATS {
                let mut sim = engines::build(engine, &case.scene, &knobs, threads)?;
                let mut again = 0.0_f64;
                for _ in 0..steps {
                    let t = Instant::now();
                    sim.step()?;
                    again += t.elapsed().as_secs_f64();
                }
                best = best.min(again);
            }
        }
        Ok((best * 1e3 / f64::from(steps), values))
    };
    match attempt() {
        Ok((ms, values)) => Point {
            engine,
            knobs,
            ms,
            pass: case.passes(&values),
            values,
            failed: None,
        },
        Err(e) => Point {
            engine,
            knobs,
            ms: f64::NAN,
            values: vec![f64::NAN; case.metrics.len()],
            pass: false,
            failed: Some(format!("{e:#}")),
        },
    }
}

/// A run's metrics, unless the engine's NaN guard stopped a body during it: then every metric
/// is NaN. A stopped body keeps its last finite pose, so metrics measured from it look finite
/// and may meet the bounds; the run's state did go non-finite, and a non-finite metric never
/// passes.
fn guarded(values: Vec<f64>, non_finite_bodies: u64) -> Vec<f64> {
    if non_finite_bodies == 0 {
        values
    } else {
        vec![f64::NAN; values.len()]
    }
}

/// What the build may spoil, said before the numbers.
fn warnings() -> Vec<String> {
    let mut w = Vec::new();
    if !machine::optimised() {
        w.push(
            "this is a debug build: its ms per step say nothing about any engine; use --release"
                .to_string(),
        );
    }
    #[cfg(feature = "peers")]
    {
        let cflags = machine::build_cflags();
        let has = |flag: &str| cflags.split_whitespace().any(|f| f == flag);
        if !(has("-O3") && has("-DNDEBUG")) {
            w.push(format!(
                "Box2D's C code was built with CFLAGS={cflags:?}, not \"-O3 -DNDEBUG\" (asserts \
                 on, -O2); rebuild as docs/bench/README.md says"
            ));
        }
        if machine::cpu_has_avx2() && !cfg!(feature = "simd-avx2") {
            w.push(
                "the CPU has AVX2 but Box2D was built without its AVX2 path; rebuild with \
                 `--features peers,simd-avx2`"
                    .to_string(),
            );
        }
    }
    w
}

/// A metric value for a table: four significant digits, or "—" when it is not a number.
fn fmt(v: f64) -> String {
    if !v.is_finite() {
        return "—".into();
    }
    let a = v.abs();
    if a == 0.0 {
        "0".into()
    } else if a >= 100.0 {
        format!("{v:.1}")
    } else if a >= 1e-4 {
        let digits = (3 - a.log10().floor() as i32).max(0) as usize;
        format!("{v:.digits$}")
    } else {
        format!("{v:.2e}")
    }
}

fn fmt_ms(ms: f64) -> String {
    if !ms.is_finite() {
        "—".into()
    } else if ms >= 10.0 {
        format!("{ms:.1}")
    } else if ms >= 0.1 {
        format!("{ms:.3}")
    } else {
        format!("{ms:.4}")
    }
}

fn chart_title(case: &Case) -> String {
    format!("{}: error against ms per step", case.title)
}

fn panels(case: &Case, points: &[Point], engines: &[Engine]) -> Vec<chart::Panel> {
    case.metrics
        .iter()
        .enumerate()
        .filter(|(_, m)| m.plot)
        .map(|(k, m)| {
            let mut series = Vec::new();
            for &engine in engines {
                let pts: Vec<chart::ChartPoint> = points
                    .iter()
                    .filter(|p| p.engine == engine)
                    .map(|p| chart::ChartPoint {
                        ms: p.ms,
                        error: p.values[k].abs(),
                        label: p.knobs.short(),
                        pass: p.pass,
                        on_front: case.passes_except(&p.values, k),
                    })
                    .collect();
                if !pts.is_empty() {
                    series.push(chart::EngineSeries {
                        name: engine.title().to_string(),
                        points: pts,
                    });
                }
            }
            chart::Panel {
                y_label: m.name.to_string(),
                bound: m.bound,
                series,
            }
        })
        .collect()
}

/// Points whose ms/step are within this fraction of the fastest passing point's count as
/// equally cheap: one run's timing noise is a few per cent.
const TIE: f64 = 0.05;

/// The cheapest passing point of an engine in a case: the lowest ms/step, where points within
/// [`TIE`] of it are told apart by nominal work (solver passes per step), then by ms/step.
fn cheapest(points: &[Point], engine: Engine) -> Option<&Point> {
    let passing: Vec<&Point> = points
        .iter()
        .filter(|p| p.engine == engine && p.pass && p.ms.is_finite())
        .collect();
    let fastest = passing.iter().map(|p| p.ms).reduce(f64::min)?;
    passing
        .into_iter()
        .filter(|p| p.ms <= fastest * (1.0 + TIE))
        .min_by(|a, b| {
            a.knobs
                .work()
                .cmp(&b.knobs.work())
                .then(b.knobs.is_default().cmp(&a.knobs.is_default()))
                .then(a.ms.total_cmp(&b.ms))
        })
}

/// The first bounded metric's value, for the summary ("sag 0.046").
fn headline(case: &Case, p: &Point) -> String {
    case.metrics
        .iter()
        .zip(&p.values)
        .find(|(m, _)| m.bound.is_some())
        .map(|(m, v)| format!("{} {}", m.name, fmt(*v)))
        .unwrap_or_default()
}

fn summary_cell(case: &Case, points: &[Point], engine: Engine) -> String {
    match cheapest(points, engine) {
        Some(p) => format!(
            "{} — {} ms ({})",
            p.knobs.label(),
            fmt_ms(p.ms),
            headline(case, p)
        ),
        None => "none in the sweep".into(),
    }
}

fn default_cell(case: &Case, points: &[Point]) -> String {
    match points
        .iter()
        .find(|p| p.engine == Engine::Tumble && p.knobs.is_default())
    {
        Some(p) => format!(
            "{} ({})",
            if p.pass { "passes" } else { "fails" },
            headline(case, p)
        ),
        None => "—".into(),
    }
}

fn summary_text(results: &[(Case, Vec<Point>, f64)], engines: &[Engine]) -> String {
    let mut out = String::from("\ncheapest passing setting per case:\n");
    for (case, points, _) in results {
        let _ = writeln!(out, "  {}:", case.key);
        for &e in engines {
            let _ = writeln!(
                out,
                "    {:<7} {}",
                e.title(),
                summary_cell(case, points, e)
            );
        }
    }
    out
}

fn csv_text(results: &[(Case, Vec<Point>, f64)]) -> String {
    let mut out = String::from(
        "case,engine,setting,substeps,relax,hertz,push,steps,ms_per_step,pass,metric,value\n",
    );
    for (case, points, _) in results {
        for p in points {
            for (m, v) in case.metrics.iter().zip(&p.values) {
                let _ = writeln!(
                    out,
                    "{},{},{},{},{},{},{},{},{:.6},{},{},{:e}",
                    case.key,
                    p.engine.key(),
                    csv_field(&p.knobs.label()),
                    p.knobs.substeps,
                    p.knobs.relax,
                    p.knobs.hertz,
                    p.knobs.push,
                    case.steps,
                    p.ms,
                    p.pass,
                    m.key,
                    v
                );
            }
        }
    }
    out
}

fn markdown(
    results: &[(Case, Vec<Point>, f64)],
    engines: &[Engine],
    args: &ReportArgs,
    load: &str,
    wall: f64,
    warnings: &[String],
) -> String {
    let mut md = String::new();
    let _ = writeln!(
        md,
        "# Speed against error: tumble{} on the hard cases\n",
        if engines.len() > 1 {
            ", Box2D v3 and Rapier2D"
        } else {
            ""
        }
    );
    let _ = writeln!(
        md,
        "Written by `tumble-bench report` (issue 5). Each point is one run of a fresh world of \
         the case's scene at one knob setting: only the engine's step calls are inside the \
         clock (building the world and measuring are not), ms/step is the mean over the run \
         (for a run whose steps take under 0.25 s in all, the fastest of 5 runs), \
         and the error metrics are computed by code from the engine's poses and velocities \
         after each step, the same code for every engine. Every engine runs on {} thread{}. \
         The machine is shared with other work, so ms/step carries some noise (a few per \
         cent on the pyramids, more on the tiny scenes, whose steps take microseconds); the \
         errors are deterministic (each engine gives the same state run after run on one \
         thread). A non-finite metric never passes; a run in which tumble's NaN guard had to \
         stop a body (`World::non_finite_bodies` > 0: the body keeps its last finite pose, so \
         its metrics would look finite) counts as non-finite: its metrics show as —. [Summary](#summary-the-cheapest-setting-that-passes) at the \
         end. To regenerate (docs/bench/README.md explains the flags):\n\n\
         ```sh\n\
         grep -q avx2 /proc/cpuinfo && FEATURES=peers,simd-avx2 || FEATURES=peers\n\
         CFLAGS=\"-O3 -DNDEBUG\" cargo run --release -p tumble-bench --features $FEATURES -- report\n\
         ```\n",
        args.threads,
        if args.threads == 1 { "" } else { "s" }
    );
    if args.quick {
        let _ = writeln!(
            md,
            "> **Quick run** (`--quick`): every case ran for at most 10 steps with a reduced \
             sweep; the numbers below are a smoke test and mean nothing.\n"
        );
    }
    if !cfg!(feature = "peers") {
        let _ = writeln!(
            md,
            "> **tumble only**: this tumble-bench was built without the `peers` feature, so \
             Box2D and Rapier are not in this report. Rebuild with `--features peers` (see \
             docs/bench/README.md) to add them.\n"
        );
    }
    for w in warnings {
        let _ = writeln!(md, "> **Warning:** {w}\n");
    }
    machine::write_host_rows(&mut md);
    let _ = writeln!(md, "| rustc | `{}` |", machine::rustc_version());
    let _ = writeln!(
        md,
        "| tumble's 8-lane solver | {} |",
        machine::tumble_kernel()
    );
    peer_rows(&mut md);
    machine::write_build_row(&mut md);
    let _ = writeln!(md, "| threads per engine | {} |", args.threads);
    let _ = writeln!(md, "| load average (1, 5, 15 min) | {load} |");
    let _ = writeln!(
        md,
        "| wall time of the report | {:.1} min ({:.0} s) |",
        wall / 60.0,
        wall
    );
    let command: Vec<String> = std::env::args().skip(1).collect();
    let _ = writeln!(md, "| command | `tumble-bench {}` |\n", command.join(" "));

    let _ = writeln!(md, "## Settings\n");
    let d = Knobs::DEFAULT;
    let _ = writeln!(
        md,
        "Defaults (tumble's, which are Box2D v3's and Rapier 0.36's too): {} substeps per 1/60 s step, \
         {} relax pass per substep, contacts at {} Hz (twice that against static bodies) with \
         damping ratio 10, push-out at most {} m/s, restitution above {} m/s of approach; \
         tumble also solves a manifold's two points together where they are well apart (its \
         default, `solve_points_together`; Box2D and Rapier solve them in turn, which the \
         flat landing's `points in turn` row shows in tumble, chart label `it`). The \
         sweep: substeps 1, 2, 4, 8, 12 and 16 at the other defaults; then, at 4 substeps, one \
         knob at a time: relax passes 2 and 4, contact hertz 15. tumble and Box2D v3.2 clamp \
         the contact hertz to an eighth of the substep rate (Rapier does not clamp), so a \
         stiffer contact needs more substeps: the sweep has 60, 90 and 120 Hz at 8, 12 and 16 \
         substeps, each at its clamp. Overlap recovery also sweeps the push-out speed (1 and \
         2 m/s), the elastic box the restitution threshold (0 and 0.25 m/s), the joint cases \
         the joints' hertz (Box2D's 60 Hz by default, clamped by tumble and Box2D to a quarter \
         of the substep rate: 30 Hz at 4 substeps, 120 at 8, 240 at 16; Rapier's joints are \
         rigid, with no such knob). Chart labels: a number is the substeps, `r2` 2 relax \
         passes, `15Hz` the contact hertz, `16/120Hz` 16 substeps at 120 Hz, `p1` the push-out \
         speed, `t0` the restitution threshold, `8/j120Hz` the joints at 120 Hz on 8 \
         substeps.\n",
        d.substeps, d.relax, d.hertz, d.push, d.threshold
    );
    for &e in engines {
        let _ = writeln!(md, "- **{}**: {}.", e.title(), e.knob_names());
    }
    let _ = writeln!(
        md,
        "\nms/step across engines: tumble's step has a fixed cost per call (its staged pipeline \
         runs on a thread pool even at 1 thread) of a few hundredths of a millisecond, which \
         dominates the scenes of a few bodies, where Box2D's step takes a few microseconds. \
         The pyramids compare what the solvers cost; the small cases compare errors."
    );
    let _ = writeln!(
        md,
        "\nEach engine builds the scene from the same `SceneDef` as `tumble-bench compare` \
         does (docs/bench/README.md: same bodies, shapes, densities, friction `sqrt(a·b)`, \
         restitution `max(a, b)`, gravity, dt = 1/60 s; Box2D with sleep off and continuous \
         collision as tumble's (on; a body is swept only in a step where it moves more than half its \
         thickness); Rapier with sleep off and continuous collision as the scene says).\n"
    );

    for (n, (case, points, secs)) in results.iter().enumerate() {
        case_section(&mut md, n + 1, case, points, *secs);
    }

    let _ = writeln!(md, "## Not measured: orbit-like motion\n");
    let _ = writeln!(
        md,
        "Uniform circular motion needs a central force: a joint gives one (the report's joint \
         cases are the next step). The other way, a frictionless ball running round the inside of a \
         bowl, needs a round bowl: tumble has one convex shape of at most 8 vertices per body, \
         so a bowl is a ring of flat static boxes, and at every corner between two faces the \
         ball meets the next face with the normal part of its velocity, v·sin(turn), which the \
         contact removes (a small plastic impact, restitution being applied only above 1 m/s). \
         With 128 faces round the circle that is sin²(2.8°) = 0.24% of the kinetic energy per \
         corner, about 10% per swing through 40 corners: the faceting, not the solver, would \
         decide the position error against the pendulum's closed form. The projectile case \
         above measures the integrator against a closed form instead.\n"
    );

    let _ = writeln!(md, "## Summary: the cheapest setting that passes\n");
    let _ = writeln!(
        md,
        "Per case and engine, the setting of the sweep with the lowest ms/step that meets the \
         case's pass criterion (with its ms/step and its first bounded metric), or \"none in \
         the sweep\". Points within 15% of the fastest passing one count as equally cheap (one \
         run's timing noise on a shared machine, and in the scenes of a few bodies a fixed \
         cost per step that makes every setting cost the same) and are told apart by nominal \
         work, substeps × (1 + relax passes). The last column: whether tumble passes at its defaults.\n"
    );
    let mut header = String::from("| case | criterion |");
    let mut rule = String::from("|---|---|");
    for e in engines {
        let _ = write!(header, " {} |", e.title());
        rule.push_str("---|");
    }
    header.push_str(" tumble at defaults |");
    rule.push_str("---|");
    let _ = writeln!(md, "{header}\n{rule}");
    for (case, points, _) in results {
        let mut row = format!("| {} | {} |", case.title, short_criterion(case));
        for &e in engines {
            let _ = write!(row, " {} |", summary_cell(case, points, e));
        }
        let _ = write!(row, " {} |", default_cell(case, points));
        let _ = writeln!(md, "{row}");
    }
    let _ = writeln!(md);
    md
}

/// The bounds of a case as one line: "top sag (m) ≤ 0.1, penetration (m) ≤ 0.02".
fn short_criterion(case: &Case) -> String {
    case.metrics
        .iter()
        .filter_map(|m| m.bound.map(|b| format!("{} ≤ {}", m.name, b)))
        .collect::<Vec<_>>()
        .join(", ")
}

fn case_section(md: &mut String, n: usize, case: &Case, points: &[Point], secs: f64) {
    let _ = writeln!(md, "## {n}. {}\n", case.title);
    let _ = writeln!(md, "{}\n", case.setup);
    let _ = writeln!(md, "Metrics. {}\n", case.definition);
    let _ = writeln!(md, "Pass: {}\n", case.criterion);
    let _ = writeln!(md, "![{}]({}.svg)\n", chart_title(case), case.key);
    let mut header = String::from("| engine | setting | ms/step |");
    let mut rule = String::from("|---|---|--:|");
    for m in &case.metrics {
        let bound = m.bound.map(|b| format!(" (≤ {b})")).unwrap_or_default();
        let _ = write!(header, " {}{bound} |", m.name);
        rule.push_str("--:|");
    }
    header.push_str(" pass |");
    rule.push_str(":-:|");
    let _ = writeln!(md, "{header}\n{rule}");
    for p in points {
        let mut row = format!(
            "| {} | {} | {} |",
            p.engine.title(),
            p.knobs.label(),
            fmt_ms(p.ms)
        );
        for v in &p.values {
            let _ = write!(row, " {} |", fmt(*v));
        }
        let verdict = match &p.failed {
            Some(e) => format!("error: {}", e.replace('|', "/")),
            None if p.pass => "✓".into(),
            None => "✗".into(),
        };
        let _ = write!(row, " {verdict} |");
        let _ = writeln!(md, "{row}");
    }
    let _ = writeln!(
        md,
        "\n{} steps per run; this case took {:.0} s of the report.\n",
        case.steps, secs
    );
}

fn peer_rows(md: &mut String) {
    #[cfg(feature = "peers")]
    {
        let _ = writeln!(
            md,
            "| Box2D | {} via boxdd {}; CFLAGS `{}`; AVX2 path {} |",
            crate::peers::box2d::version(),
            env!("TUMBLE_BENCH_BOXDD_VERSION"),
            machine::build_cflags(),
            if cfg!(feature = "simd-avx2") {
                "on (`simd-avx2`)"
            } else {
                "off"
            }
        );
        let _ = writeln!(
            md,
            "| Rapier | rapier2d {} (feature `parallel`) |",
            crate::peers::rapier::version()
        );
    }
    #[cfg(not(feature = "peers"))]
    {
        let _ = writeln!(md, "| peers | not built (no `peers` feature) |");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_run_whose_guard_fired_never_passes() {
        let cases = cases::all(true).unwrap();
        let case = &cases[0];
        let good = vec![0.0; case.metrics.len()];
        assert!(case.passes(&good));
        assert_eq!(guarded(good.clone(), 0), good);
        let hidden = guarded(good, 1);
        assert!(hidden.iter().all(|v| v.is_nan()));
        assert!(!case.passes(&hidden));
        assert!(!case.passes_except(&hidden, 0));
    }
}
