//! `tumble-bench sweep`: step time and its stages against thread count (per scene) and against
//! body count (the generated `pile_N` family), as a table, a CSV and SVG charts.

use std::fmt::Write as _;
use std::fs;
use std::io::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use tumble_physics::{BodyKind, SceneDef};

use crate::plot::{self, Chart, Series};
use crate::scenes;
use crate::timing::{self, TumbleRun, median, min, parse_list};

/// Most threads a sweep may ask for.
const MAX_THREADS: i64 = 1024;

/// Arguments of `tumble-bench sweep`.
#[derive(Debug, Args)]
pub struct SweepArgs {
    /// Scenes to time against thread count: built-in names, scene files, or `pile_N`.
    #[arg(
        long,
        value_name = "A,B,..",
        value_delimiter = ',',
        default_value = "large_pyramid,many_pyramids,smash,tumbler"
    )]
    pub scenes: Vec<String>,
    /// Thread counts [default: 1 up to the number of cores].
    #[arg(
        long,
        value_name = "T,T,..",
        value_delimiter = ',',
        value_parser = clap::value_parser!(u32).range(1..=MAX_THREADS)
    )]
    pub threads: Option<Vec<u32>>,
    /// Runs of each configuration, each on a fresh world; the table and charts use the median.
    #[arg(long, value_name = "R", default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..))]
    pub repeats: u32,
    /// Timed steps per run.
    #[arg(long, value_name = "N", default_value_t = 300, value_parser = clap::value_parser!(u32).range(1..))]
    pub steps: u32,
    /// Untimed steps first, so the first contacts, the pool's threads and the allocations are
    /// not in the numbers.
    #[arg(long, value_name = "N", default_value_t = 10)]
    pub warmup: u32,
    /// Body counts of the generated pile family (seeded boxes and circles falling into a static
    /// box), timed at 1 thread and at the largest of --threads. `none` skips the family.
    #[arg(
        long,
        value_name = "N,N,..|none",
        default_value = "100,250,500,1000,2000,5000,10000,20000"
    )]
    pub bodies: String,
    /// Where the CSV and the SVG charts go (created if missing).
    #[arg(long, value_name = "DIR", default_value = "docs/bench")]
    pub out_dir: PathBuf,
}

/// One configuration to time.
struct Job {
    family: &'static str,
    scene: SceneDef,
    /// Dynamic bodies (the pile family's parameter; the x axis of the body-count chart).
    dynamic: usize,
    threads: usize,
}

/// One timed run.
struct Row {
    family: &'static str,
    scene: String,
    bodies: usize,
    dynamic: usize,
    threads: usize,
    repeat: u32,
    run: TumbleRun,
}

/// Runs the sweep and writes its files.
pub fn run(args: &SweepArgs) -> Result<()> {
    let threads: Vec<usize> = match &args.threads {
        Some(t) => t.iter().map(|&t| t as usize).collect(),
        None => (1..=crate::machine::cores()).collect(),
    };
    if args.scenes.is_empty() && args.bodies.trim() == "none" {
        bail!("nothing to do: give --scenes or --bodies");
    }
    let bodies: Vec<usize> = if args.bodies.trim() == "none" {
        Vec::new()
    } else {
        parse_list(&args.bodies).map_err(|e| anyhow::anyhow!("--bodies: {e}"))?
    };
    let max_threads = threads.iter().copied().max().unwrap_or(1);
    let mut body_threads = vec![1, max_threads];
    body_threads.dedup();

    let load_before = crate::machine::load_average();
    let mut jobs = Vec::new();
    for name in &args.scenes {
        let scene = scenes::resolve(name)?;
        let dynamic = count_dynamic(&scene);
        for &t in &threads {
            jobs.push(Job {
                family: "threads",
                scene: scene.clone(),
                dynamic,
                threads: t,
            });
        }
    }
    for &n in &bodies {
        let scene = scenes::pile(n, scenes::PILE_SEED);
        for &t in &body_threads {
            jobs.push(Job {
                family: "bodies",
                scene: scene.clone(),
                dynamic: n,
                threads: t,
            });
        }
    }
    fs::create_dir_all(&args.out_dir)
        .with_context(|| format!("cannot create {}", args.out_dir.display()))?;

    eprintln!(
        "sweep: {} configurations x {} repeats; each run: {} warm-up steps (not timed), then {} timed steps",
        jobs.len(),
        args.repeats,
        args.warmup,
        args.steps
    );
    let bar = ProgressBar::new(jobs.len() as u64 * u64::from(args.repeats));
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} (eta {eta}) {msg}",
        )
        .expect("a valid progress template"),
    );
    let mut rows = Vec::new();
    // Repeats outermost, so a slow spell of the machine spreads over all configurations.
    for repeat in 0..args.repeats {
        for job in &jobs {
            bar.set_message(format!(
                "{} t={} #{}",
                job.scene.name,
                job.threads,
                repeat + 1
            ));
            let run = timing::time_tumble(&job.scene, job.threads, args.warmup, args.steps)?;
            rows.push(Row {
                family: job.family,
                scene: job.scene.name.clone(),
                bodies: job.scene.bodies.len(),
                dynamic: job.dynamic,
                threads: job.threads,
                repeat,
                run,
            });
            bar.inc(1);
        }
    }
    bar.finish_and_clear();

    let csv = args.out_dir.join("sweep.csv");
    write_csv(&csv, &rows, args)?;
    let mut written = vec![csv];
    written.extend(write_charts(&args.out_dir, &rows, &body_threads)?);
    let table = table(&rows, args);
    let md = args.out_dir.join("sweep.md");
    let load = format!(
        "{load_before} before, {} after",
        crate::machine::load_average()
    );
    fs::write(&md, markdown(&table, &written, args, &load))
        .with_context(|| format!("cannot write {}", md.display()))?;
    written.push(md);
    print!("{table}");
    for path in &written {
        println!("wrote {}", path.display());
    }
    Ok(())
}

fn count_dynamic(scene: &SceneDef) -> usize {
    scene
        .bodies
        .iter()
        .filter(|b| b.kind == BodyKind::Dynamic)
        .count()
}

/// The stage names, in pipeline order (the same for every run).
fn stage_names(rows: &[Row]) -> Vec<&'static str> {
    rows.first()
        .map(|r| r.run.stages.iter().map(|&(n, _)| n).collect())
        .unwrap_or_default()
}

fn write_csv(path: &Path, rows: &[Row], args: &SweepArgs) -> Result<()> {
    let mut text = String::from(
        "family,scene,bodies,dynamic_bodies,threads,repeat,warmup_steps,timed_steps,step_ms",
    );
    for name in stage_names(rows) {
        let _ = write!(text, ",{name}_ms");
    }
    text.push_str(",contacts\n");
    for r in rows {
        let _ = write!(
            text,
            "{},{},{},{},{},{},{},{},{:.6}",
            r.family,
            csv_field(&r.scene),
            r.bodies,
            r.dynamic,
            r.threads,
            r.repeat + 1,
            args.warmup,
            args.steps,
            r.run.step_ms
        );
        for (_, ms) in &r.run.stages {
            let _ = write!(text, ",{ms:.6}");
        }
        let _ = writeln!(text, ",{:.1}", r.run.contacts);
    }
    let mut file =
        fs::File::create(path).with_context(|| format!("cannot create {}", path.display()))?;
    file.write_all(text.as_bytes())
        .with_context(|| format!("cannot write {}", path.display()))
}

/// Quotes a CSV field that needs it.
pub fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// Groups of rows of one family, scene and thread count, in first-seen order.
fn groups<'a>(rows: &'a [Row], family: &str) -> Vec<Vec<&'a Row>> {
    let mut out: Vec<Vec<&Row>> = Vec::new();
    for r in rows.iter().filter(|r| r.family == family) {
        match out
            .iter_mut()
            .find(|g| g[0].scene == r.scene && g[0].threads == r.threads)
        {
            Some(g) => g.push(r),
            None => out.push(vec![r]),
        }
    }
    out
}

fn median_of(group: &[&Row], f: impl Fn(&Row) -> f64) -> f64 {
    median(&group.iter().map(|r| f(r)).collect::<Vec<_>>())
}

/// File-name-safe form of a scene name.
fn slug(name: &str) -> String {
    name.chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect()
}

fn write_charts(dir: &Path, rows: &[Row], body_threads: &[usize]) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    let stages = stage_names(rows);
    let thread_groups = groups(rows, "threads");
    let mut seen = Vec::new();
    for g in &thread_groups {
        let name = g[0].scene.clone();
        if seen.contains(&name) {
            continue;
        }
        seen.push(name.clone());
        let of_scene: Vec<&Vec<&Row>> = thread_groups
            .iter()
            .filter(|g| g[0].scene == name)
            .collect();
        let points = |f: &dyn Fn(&Row) -> f64| -> Vec<(f64, f64)> {
            let mut p: Vec<(f64, f64)> = of_scene
                .iter()
                .map(|g| (g[0].threads as f64, median_of(g, f)))
                .collect();
            p.sort_by(|a, b| a.0.total_cmp(&b.0));
            p
        };
        let mut series = vec![Series {
            label: "step (wall)".into(),
            points: points(&|r| r.run.step_ms),
            bold: true,
        }];
        for (i, stage) in stages.iter().enumerate() {
            series.push(Series {
                label: stage.to_string(),
                points: points(&|r| r.run.stages[i].1),
                bold: false,
            });
        }
        let title = format!(
            "tumble: {name} ({} bodies), ms per step against threads",
            g[0].bodies
        );
        let path = dir.join(format!("sweep_threads_{}.svg", slug(&name)));
        plot::linear(
            &path,
            &Chart {
                title: &title,
                x_label: "worker threads",
                y_label: "ms per step (median of repeats)",
                series: &series,
            },
        )?;
        written.push(path);
    }

    let body_groups = groups(rows, "bodies");
    if !body_groups.is_empty() {
        let series: Vec<Series> = body_threads
            .iter()
            .map(|&t| {
                let mut points: Vec<(f64, f64)> = body_groups
                    .iter()
                    .filter(|g| g[0].threads == t)
                    .map(|g| (g[0].dynamic as f64, median_of(g, |r| r.run.step_ms)))
                    .collect();
                points.sort_by(|a, b| a.0.total_cmp(&b.0));
                Series {
                    label: format!("{t} thread{}", if t == 1 { "" } else { "s" }),
                    points,
                    bold: t == 1,
                }
            })
            .collect();
        let path = dir.join("sweep_bodies.svg");
        plot::log_log(
            &path,
            &Chart {
                title: "tumble: ms per step against body count (pile_N: boxes and circles in a box)",
                x_label: "dynamic bodies",
                y_label: "ms per step (median of repeats)",
                series: &series,
            },
        )?;
        written.push(path);
    }
    Ok(written)
}

/// The table printed at the end: medians over repeats, and the speed-up over 1 thread.
fn table(rows: &[Row], args: &SweepArgs) -> String {
    let stages = stage_names(rows);
    let mut out = String::new();
    let _ = writeln!(
        out,
        "\nms per step: median (min) of {} repeats; {} timed steps after {} warm-up steps; stages are World::profile() means",
        args.repeats, args.steps, args.warmup
    );
    let mut header = format!(
        "{:<8} {:<16} {:>7} {:>3} {:>17} {:>7}",
        "family", "scene", "bodies", "thr", "step ms", "speedup"
    );
    for s in &stages {
        let short: String = s.chars().take(10).collect();
        let _ = write!(header, " {short:>10}");
    }
    let _ = writeln!(out, "{header}");
    let _ = writeln!(out, "{}", "-".repeat(header.len()));
    for family in ["threads", "bodies"] {
        let gs = groups(rows, family);
        for g in &gs {
            let step = median_of(g, |r| r.run.step_ms);
            let best = min(&g.iter().map(|r| r.run.step_ms).collect::<Vec<_>>());
            let one = gs
                .iter()
                .find(|o| o[0].scene == g[0].scene && o[0].threads == 1)
                .map(|o| median_of(o, |r| r.run.step_ms));
            let speedup = one.map_or("-".to_string(), |o| format!("{:.2}x", o / step));
            let mut line = format!(
                "{:<8} {:<16} {:>7} {:>3} {:>8.3} ({:>6.3}) {:>7}",
                family, g[0].scene, g[0].bodies, g[0].threads, step, best, speedup
            );
            for i in 0..stages.len() {
                let _ = write!(line, " {:>10.3}", median_of(g, |r| r.run.stages[i].1));
            }
            let _ = writeln!(out, "{line}");
        }
    }
    out
}

/// sweep.md: the machine, the table and the charts.
fn markdown(table: &str, files: &[PathBuf], args: &SweepArgs, load: &str) -> String {
    use crate::machine;
    let mut md = String::from("# tumble: step time against threads and body count\n\n");
    let _ = writeln!(
        md,
        "Written by `tumble-bench sweep`. Each run builds a fresh world, steps it {} times \
         untimed (warm-up), then times {} steps: the wall time of each `World::step` call, and \
         each stage from `World::profile()`. Numbers are the median (and min) over {} runs. \
         The body-count family is `pile_N`: N seeded boxes and circles dropped into a static \
         box, at 1 thread and at the most threads asked for.\n",
        args.warmup, args.steps, args.repeats
    );
    let _ = writeln!(md, "| | |\n|---|---|");
    let _ = writeln!(md, "| CPU | {} |", machine::cpu_model());
    let _ = writeln!(md, "| cores | {} |", machine::cores());
    let _ = writeln!(
        md,
        "| tumble revision (built from) | `{}` |",
        machine::git_revision()
    );
    let _ = writeln!(md, "| load average (1, 5, 15 min) | {load} |");
    let _ = writeln!(md, "| rustc | `{}` |", machine::rustc_version());
    let _ = writeln!(
        md,
        "| tumble's 8-lane solver | {} |",
        machine::tumble_kernel()
    );
    let _ = writeln!(
        md,
        "| build | {} |",
        if machine::optimised() {
            "release"
        } else {
            "debug (timings meaningless)"
        }
    );
    let command: Vec<String> = std::env::args().skip(1).collect();
    let _ = writeln!(md, "| command | `tumble-bench {}` |\n", command.join(" "));
    let _ = writeln!(md, "```text{table}```\n");
    for f in files {
        if f.extension().is_some_and(|e| e == "svg")
            && let Some(name) = f.file_name().and_then(|n| n.to_str())
        {
            let _ = writeln!(md, "![{name}]({name})\n");
        }
    }
    md
}
