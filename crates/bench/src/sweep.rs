//! `tumble-bench sweep`: step time and its stages against thread count (per scene) and against
//! body count (the generated `pile_N` family), as a table, a CSV and SVG charts. With the
//! `peers` feature, Box2D v3 and Rapier2D are timed beside tumble on the body-count family,
//! built and timed by `compare`'s own functions.

use std::fmt::Write as _;
use std::fs;
use std::io::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use tumble_physics::{BodyKind, SceneDef};

use crate::compare::{ENGINES, Engine, MAX_PEER_THREADS};
use crate::csv::csv_field;
use crate::plot::{self, Chart, Series};
use crate::scenes;
use crate::timing::{self, median, min, parse_list};

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
    /// box), timed at 1 thread and at the largest of --threads, in tumble and (with the `peers`
    /// feature) in Box2D and Rapier. `none` skips the family.
    #[arg(
        long,
        value_name = "N,N,..|none",
        default_value = "10,30,100,300,1000,3000,10000,20000"
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
    /// The engines to time, tumble first; each repeat rotates the order.
    engines: Vec<Engine>,
}

/// One timed run of one engine.
struct Row {
    family: &'static str,
    scene: String,
    bodies: usize,
    dynamic: usize,
    threads: usize,
    engine: Engine,
    repeat: u32,
    /// Mean wall ms of one step call over the timed steps.
    step_ms: f64,
    /// Mean ms per step of each stage: tumble's `World::profile()` names for tumble, the common
    /// `peers::STAGES` names for a peer (none for Rapier).
    stages: Vec<(&'static str, f64)>,
    /// Mean contacts per timed step (tumble only).
    contacts: Option<f64>,
}

/// What one run measured.
struct Measured {
    step_ms: f64,
    stages: Vec<(&'static str, f64)>,
    contacts: Option<f64>,
}

/// The engines timed on the pile family at `threads`: all three with the `peers` feature
/// (where the peers take that many threads), else tumble alone.
fn body_engines(threads: usize) -> Vec<Engine> {
    if cfg!(feature = "peers") && threads <= MAX_PEER_THREADS as usize {
        ENGINES.to_vec()
    } else {
        vec![Engine::Tumble]
    }
}

/// Times one run of `engine`: a fresh world, `warmup` untimed steps, then `steps` timed ones.
fn measure(
    engine: Engine,
    scene: &SceneDef,
    threads: usize,
    warmup: u32,
    steps: u32,
) -> Result<Measured> {
    if engine == Engine::Tumble {
        let run = timing::time_tumble(scene, threads, warmup, steps)?;
        return Ok(Measured {
            step_ms: run.step_ms,
            stages: run.stages,
            contacts: Some(run.contacts),
        });
    }
    time_peer(engine, scene, threads, warmup, steps)
}

/// A peer built and timed as `tumble-bench compare` does it.
#[cfg(feature = "peers")]
fn time_peer(
    engine: Engine,
    scene: &SceneDef,
    threads: usize,
    warmup: u32,
    steps: u32,
) -> Result<Measured> {
    use crate::compare;
    let settings = compare::settings_of(scene)?;
    let mut peer = compare::build(engine, scene, &settings, threads)?;
    let (step_ms, stages) = compare::time_steps(peer.as_mut(), warmup, steps)?;
    Ok(Measured {
        step_ms,
        stages,
        contacts: None,
    })
}

#[cfg(not(feature = "peers"))]
fn time_peer(engine: Engine, _: &SceneDef, _: usize, _: u32, _: u32) -> Result<Measured> {
    bail!(
        "{} needs a tumble-bench built with the `peers` feature",
        engine.title()
    )
}

/// Said in the output when the pile family is tumble's alone.
const TUMBLE_ONLY: &str = "this tumble-bench was built without the `peers` feature, so the \
     body-count family times tumble only; rebuild with `--features peers` (see docs/bench/README.md) \
     to time Box2D and Rapier beside it";

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

    #[cfg(feature = "peers")]
    let warnings = if bodies.is_empty() {
        Vec::new()
    } else {
        crate::compare::build_warnings()?
    };
    #[cfg(not(feature = "peers"))]
    let warnings: Vec<String> = Vec::new();
    for w in &warnings {
        eprintln!("warning: {w}");
    }

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
                engines: vec![Engine::Tumble],
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
                engines: body_engines(t),
            });
        }
    }
    fs::create_dir_all(&args.out_dir)
        .with_context(|| format!("cannot create {}", args.out_dir.display()))?;

    let runs: usize = jobs.iter().map(|j| j.engines.len()).sum();
    eprintln!(
        "sweep: {} configurations ({runs} engine runs) x {} repeats; each run: {} warm-up steps (not timed), then {} timed steps",
        jobs.len(),
        args.repeats,
        args.warmup,
        args.steps
    );
    let notes = peer_notes(&bodies, &body_threads);
    for n in &notes {
        eprintln!("sweep: {n}");
    }
    let bar = ProgressBar::new(runs as u64 * u64::from(args.repeats));
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
            // Rotated each repeat, as in `compare`, so no engine always runs first (after a
            // world was dropped, on a cold cache) or last.
            let mut order = job.engines.clone();
            let len = order.len();
            order.rotate_left(repeat as usize % len);
            for engine in order {
                bar.set_message(format!(
                    "{} {} t={} #{}",
                    engine.title(),
                    job.scene.name,
                    job.threads,
                    repeat + 1
                ));
                let m = measure(engine, &job.scene, job.threads, args.warmup, args.steps)?;
                rows.push(Row {
                    family: job.family,
                    scene: job.scene.name.clone(),
                    bodies: job.scene.bodies.len(),
                    dynamic: job.dynamic,
                    threads: job.threads,
                    engine,
                    repeat,
                    step_ms: m.step_ms,
                    stages: m.stages,
                    contacts: m.contacts,
                });
                bar.inc(1);
            }
        }
    }
    bar.finish_and_clear();

    let csv = args.out_dir.join("sweep.csv");
    write_csv(&csv, &rows, args)?;
    let mut written = vec![csv];
    written.extend(write_charts(&args.out_dir, &rows, &body_threads)?);
    let table = table(&rows, args);
    let bodies_table = body_table(&rows, &body_threads);
    let md = args.out_dir.join("sweep.md");
    let load = format!(
        "{load_before} before, {} after",
        crate::machine::load_average()
    );
    let report = Report {
        table: &table,
        bodies: &bodies_table,
        notes: &notes,
        warnings: &warnings,
        files: &written,
        load: &load,
    };
    fs::write(&md, markdown(&report, args))
        .with_context(|| format!("cannot write {}", md.display()))?;
    written.push(md);
    print!("{table}");
    if !bodies_table.lines.is_empty() {
        print!("{}", bodies_table.text(args.repeats));
    }
    for n in &notes {
        println!("note: {n}");
    }
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

/// What the output says about the peers: why the body-count family is tumble's alone, or at
/// which thread count the peers sit out.
fn peer_notes(bodies: &[usize], body_threads: &[usize]) -> Vec<String> {
    let mut notes = Vec::new();
    if bodies.is_empty() {
        return notes;
    }
    if !cfg!(feature = "peers") {
        notes.push(TUMBLE_ONLY.to_string());
        return notes;
    }
    for &t in body_threads {
        if t > MAX_PEER_THREADS as usize {
            notes.push(format!(
                "Box2D and Rapier sit out at {t} threads (Box2D takes 1 to {MAX_PEER_THREADS} workers)"
            ));
        }
    }
    notes
}

/// The stage names, in pipeline order (the same for every tumble run).
fn stage_names(rows: &[Row]) -> Vec<&'static str> {
    rows.iter()
        .find(|r| r.engine == Engine::Tumble)
        .map(|r| r.stages.iter().map(|&(n, _)| n).collect())
        .unwrap_or_default()
}

/// A row's value for each of the `columns` stage columns: tumble's own stages; a peer's under
/// the common `peers::STAGES` names, which are tumble's stages in the same order (as `compare`
/// pairs them), and nothing where the peer does not report one.
fn stage_cells(row: &Row, columns: usize) -> Vec<Option<f64>> {
    (0..columns)
        .map(|i| {
            if row.engine == Engine::Tumble {
                row.stages.get(i).map(|s| s.1)
            } else {
                let name = crate::peers::STAGES.get(i)?;
                row.stages.iter().find(|(n, _)| n == name).map(|s| s.1)
            }
        })
        .collect()
}

fn write_csv(path: &Path, rows: &[Row], args: &SweepArgs) -> Result<()> {
    let stages = stage_names(rows);
    let mut text = String::from(
        "family,engine,scene,bodies,dynamic_bodies,threads,repeat,warmup_steps,timed_steps,step_ms",
    );
    for name in &stages {
        let _ = write!(text, ",{name}_ms");
    }
    text.push_str(",contacts\n");
    for r in rows {
        let _ = write!(
            text,
            "{},{},{},{},{},{},{},{},{},{:.6}",
            r.family,
            r.engine.key(),
            csv_field(&r.scene),
            r.bodies,
            r.dynamic,
            r.threads,
            r.repeat + 1,
            args.warmup,
            args.steps,
            r.step_ms
        );
        for ms in stage_cells(r, stages.len()) {
            match ms {
                Some(ms) => {
                    let _ = write!(text, ",{ms:.6}");
                }
                None => text.push(','),
            }
        }
        match r.contacts {
            Some(c) => {
                let _ = writeln!(text, ",{c:.1}");
            }
            None => text.push_str(",\n"),
        }
    }
    let mut file =
        fs::File::create(path).with_context(|| format!("cannot create {}", path.display()))?;
    file.write_all(text.as_bytes())
        .with_context(|| format!("cannot write {}", path.display()))
}

/// Groups of one engine's rows of one family, scene and thread count, in first-seen order.
fn groups<'a>(rows: &'a [Row], family: &str, engine: Engine) -> Vec<Vec<&'a Row>> {
    let mut out: Vec<Vec<&Row>> = Vec::new();
    for r in rows
        .iter()
        .filter(|r| r.family == family && r.engine == engine)
    {
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

/// A ms cell of the body-count table: three decimals, four below 0.1 ms (a 10-body pile
/// steps in microseconds).
fn ms_cell(ms: f64) -> String {
    if ms < 0.1 {
        format!("{ms:.4}")
    } else {
        format!("{ms:.3}")
    }
}

fn threads_label(t: usize) -> String {
    format!("{t} thread{}", if t == 1 { "" } else { "s" })
}

fn write_charts(dir: &Path, rows: &[Row], body_threads: &[usize]) -> Result<Vec<PathBuf>> {
    let mut written = Vec::new();
    let stages = stage_names(rows);
    let thread_groups = groups(rows, "threads", Engine::Tumble);
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
            points: points(&|r| r.step_ms),
            bold: true,
        }];
        for (i, stage) in stages.iter().enumerate() {
            series.push(Series {
                label: stage.to_string(),
                points: points(&|r| r.stages[i].1),
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

    let table = body_table(rows, body_threads);
    if !table.lines.is_empty() {
        let series = body_series(&table);
        let title = if table.engines.len() > 1 {
            "pile_N (boxes and circles in a box): ms per step against body count"
        } else {
            "tumble only: ms per step against body count (pile_N: boxes and circles in a box)"
        };
        let path = dir.join("sweep_bodies.svg");
        plot::log_log(
            &path,
            &Chart {
                title,
                x_label: "dynamic bodies",
                y_label: "ms per step (median of repeats)",
                series: &series,
            },
        )?;
        written.push(path);
    }
    Ok(written)
}

/// One line per engine and thread count of the body-count chart (tumble's drawn bold).
fn body_series(table: &BodyTable) -> Vec<Series> {
    let mut series = Vec::new();
    for (e, engine) in table.engines.iter().enumerate() {
        for (t, &threads) in table.threads.iter().enumerate() {
            let mut points: Vec<(f64, f64)> = table
                .lines
                .iter()
                .filter_map(|l| Some((l.dynamic as f64, l.ms[e][t]?)))
                .collect();
            if points.is_empty() {
                continue;
            }
            points.sort_by(|a, b| a.0.total_cmp(&b.0));
            series.push(Series {
                label: format!("{}, {}", engine.title(), threads_label(threads)),
                points,
                bold: *engine == Engine::Tumble,
            });
        }
    }
    series
}

/// The body-count family as a table: per body count, each engine's median ms per step at each
/// thread count, and tumble's per-run ratio to each peer.
struct BodyTable {
    /// The engines that ran, in `ENGINES` order (tumble first).
    engines: Vec<Engine>,
    /// The thread counts (1 and the most asked for).
    threads: Vec<usize>,
    /// One per body count, in the order they were asked for.
    lines: Vec<BodyLine>,
}

/// One body count of [`BodyTable`].
struct BodyLine {
    dynamic: usize,
    bodies: usize,
    /// `[engine][thread]`: the median ms per step of the runs; `None` where it did not run.
    ms: Vec<Vec<Option<f64>>>,
    /// `[peer][thread]`, peer `p` being `engines[p + 1]`: tumble's ms ÷ the peer's, one per
    /// repeat in which both ran (minutes apart at most, so the machine's load drifts less
    /// between them than across the sweep).
    ratios: Vec<Vec<Vec<f64>>>,
}

impl BodyLine {
    /// The median of the runs' ratios, tumble ÷ peer `p` at thread column `t`.
    fn ratio(&self, p: usize, t: usize) -> Option<f64> {
        let v = &self.ratios[p][t];
        (!v.is_empty()).then(|| median(v))
    }
    /// The smallest and largest of the runs' ratios.
    fn spread(&self, p: usize, t: usize) -> Option<(f64, f64)> {
        let v = &self.ratios[p][t];
        (!v.is_empty()).then(|| (min(v), v.iter().copied().fold(f64::MIN, f64::max)))
    }
}

/// Builds the [`BodyTable`] of the rows of the `bodies` family.
fn body_table(rows: &[Row], threads: &[usize]) -> BodyTable {
    let of: Vec<&Row> = rows.iter().filter(|r| r.family == "bodies").collect();
    let engines: Vec<Engine> = ENGINES
        .into_iter()
        .filter(|e| of.iter().any(|r| r.engine == *e))
        .collect();
    let mut counts: Vec<(usize, usize)> = Vec::new();
    for r in &of {
        if !counts.iter().any(|&(d, _)| d == r.dynamic) {
            counts.push((r.dynamic, r.bodies));
        }
    }
    let repeats = of.iter().map(|r| r.repeat).max().map_or(0, |r| r + 1);
    let lines = counts
        .into_iter()
        .map(|(dynamic, bodies)| {
            let runs = |engine: Engine, t: usize| -> Vec<&Row> {
                of.iter()
                    .copied()
                    .filter(|r| r.dynamic == dynamic && r.threads == t && r.engine == engine)
                    .collect()
            };
            let ms = engines
                .iter()
                .map(|&e| {
                    threads
                        .iter()
                        .map(|&t| {
                            let g = runs(e, t);
                            (!g.is_empty()).then(|| median_of(&g, |r| r.step_ms))
                        })
                        .collect()
                })
                .collect();
            let run_ms = |engine: Engine, t: usize, repeat: u32| {
                runs(engine, t)
                    .into_iter()
                    .find(|r| r.repeat == repeat)
                    .map(|r| r.step_ms)
            };
            let ratios = engines
                .iter()
                .skip(1)
                .map(|&peer| {
                    threads
                        .iter()
                        .map(|&t| {
                            (0..repeats)
                                .filter_map(|k| {
                                    Some(run_ms(Engine::Tumble, t, k)? / run_ms(peer, t, k)?)
                                })
                                .collect()
                        })
                        .collect()
                })
                .collect();
            BodyLine {
                dynamic,
                bodies,
                ms,
                ratios,
            }
        })
        .collect();
    BodyTable {
        engines,
        threads: threads.to_vec(),
        lines,
    }
}

impl BodyTable {
    /// The peers (every engine but tumble).
    fn peers(&self) -> &[Engine] {
        &self.engines[1.min(self.engines.len())..]
    }

    /// The printed form: medians, and the median ratio.
    fn text(&self, repeats: u32) -> String {
        let mut out = String::new();
        let _ = write!(out, "\npile_N: ms per step, median of {repeats} repeats");
        if self.peers().is_empty() {
            let _ = writeln!(out, "; tumble only");
        } else {
            let _ = writeln!(
                out,
                "; t/peer = tumble / peer, median of the per-repeat ratios (<1: tumble faster)"
            );
        }
        let mut cols: Vec<String> = Vec::new();
        for e in &self.engines {
            for t in &self.threads {
                cols.push(format!("{} {t}t", e.title()));
            }
        }
        for p in self.peers() {
            for t in &self.threads {
                cols.push(format!("t/{} {t}t", p.title()));
            }
        }
        let width = cols.iter().map(String::len).max().unwrap_or(0).max(9);
        let mut header = format!("{:>7}", "dynamic");
        for c in &cols {
            let _ = write!(header, " {c:>width$}");
        }
        let _ = writeln!(out, "{header}");
        let _ = writeln!(out, "{}", "-".repeat(header.len()));
        for l in &self.lines {
            let mut line = format!("{:>7}", l.dynamic);
            for e in &l.ms {
                for ms in e {
                    let cell = ms.map_or("-".to_string(), ms_cell);
                    let _ = write!(line, " {cell:>width$}");
                }
            }
            for p in 0..self.peers().len() {
                for t in 0..self.threads.len() {
                    let cell = l.ratio(p, t).map_or("-".to_string(), |v| format!("{v:.2}"));
                    let _ = write!(line, " {cell:>width$}");
                }
            }
            let _ = writeln!(out, "{line}");
        }
        out
    }

    /// The markdown form: medians, and the median ratio with the least and the most.
    fn markdown(&self) -> String {
        let mut md = String::from("| dynamic bodies | bodies |");
        let mut align = String::from("|--:|--:|");
        for e in &self.engines {
            for &t in &self.threads {
                let _ = write!(md, " {}, {} |", e.title(), threads_label(t));
                align.push_str("--:|");
            }
        }
        for p in self.peers() {
            for &t in &self.threads {
                let _ = write!(md, " tumble ÷ {}, {} |", p.title(), threads_label(t));
                align.push_str("--:|");
            }
        }
        let _ = writeln!(md, "\n{align}");
        for l in &self.lines {
            let _ = write!(md, "| {} | {} |", l.dynamic, l.bodies);
            for e in &l.ms {
                for ms in e {
                    let cell = ms.map_or("–".to_string(), ms_cell);
                    let _ = write!(md, " {cell} |");
                }
            }
            for p in 0..self.peers().len() {
                for t in 0..self.threads.len() {
                    let cell = match (l.ratio(p, t), l.spread(p, t)) {
                        (Some(r), Some((lo, hi))) if l.ratios[p][t].len() > 1 => {
                            format!("{r:.2} ({lo:.2}–{hi:.2})")
                        }
                        (Some(r), _) => format!("{r:.2}"),
                        _ => "–".to_string(),
                    };
                    let _ = write!(md, " {cell} |");
                }
            }
            md.push('\n');
        }
        md
    }
}

/// tumble's table printed at the end: medians over repeats, and the speed-up over 1 thread.
fn table(rows: &[Row], args: &SweepArgs) -> String {
    let stages = stage_names(rows);
    let mut out = String::new();
    let _ = writeln!(
        out,
        "\ntumble: ms per step: median (min) of {} repeats; {} timed steps after {} warm-up steps; stages are World::profile() means",
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
        let gs = groups(rows, family, Engine::Tumble);
        for g in &gs {
            let step = median_of(g, |r| r.step_ms);
            let best = min(&g.iter().map(|r| r.step_ms).collect::<Vec<_>>());
            let one = gs
                .iter()
                .find(|o| o[0].scene == g[0].scene && o[0].threads == 1)
                .map(|o| median_of(o, |r| r.step_ms));
            let speedup = one.map_or("-".to_string(), |o| format!("{:.2}x", o / step));
            let mut line = format!(
                "{:<8} {:<16} {:>7} {:>3} {:>8.3} ({:>6.3}) {:>7}",
                family, g[0].scene, g[0].bodies, g[0].threads, step, best, speedup
            );
            for i in 0..stages.len() {
                let _ = write!(line, " {:>10.3}", median_of(g, |r| r.stages[i].1));
            }
            let _ = writeln!(out, "{line}");
        }
    }
    out
}

/// What sweep.md is made of.
struct Report<'a> {
    /// tumble's table (as printed).
    table: &'a str,
    /// The body-count family, every engine.
    bodies: &'a BodyTable,
    /// What the output says about the peers.
    notes: &'a [String],
    /// What the build may spoil (from `compare`).
    warnings: &'a [String],
    /// The files written (the charts are linked).
    files: &'a [PathBuf],
    /// Load average before and after.
    load: &'a str,
}

/// sweep.md: the machine, the tables and the charts.
fn markdown(report: &Report<'_>, args: &SweepArgs) -> String {
    use crate::machine;
    let mut md = String::from("# tumble: step time against threads and body count\n\n");
    let _ = writeln!(
        md,
        "Written by `tumble-bench sweep`. Each run builds a fresh world, steps it {} times \
         untimed (warm-up), then times {} steps: the wall time of each `World::step` call, and \
         each stage from `World::profile()`. Numbers are the median (and min) over {} runs. \
         The body-count family is `pile_N`: N seeded boxes and circles dropped into a static \
         box, at 1 thread and at the most threads asked for. With the `peers` feature, Box2D v3 \
         and Rapier2D run the same `pile_N` scenes at the same thread counts, each built from \
         the same `SceneDef` and timed as `tumble-bench compare` does (only the engine's step \
         call inside the clock; world building is not timed), with the same warm-up and timed \
         steps; the engines' order rotates from repeat to repeat, so none always runs first. \
         Ratio = tumble ÷ the peer of the same repeat, the median over the repeats (with the \
         least and the most in brackets); below 1, tumble is faster.\n",
        args.warmup, args.steps, args.repeats
    );
    machine::write_host_rows(&mut md);
    let _ = writeln!(md, "| load average (1, 5, 15 min) | {} |", report.load);
    let _ = writeln!(md, "| rustc | `{}` |", machine::rustc_version());
    let _ = writeln!(
        md,
        "| tumble's 8-lane solver | {} |",
        machine::tumble_kernel()
    );
    #[cfg(feature = "peers")]
    md.push_str(&crate::compare::peer_rows("compare.md, Settings"));
    machine::write_build_row(&mut md);
    let command: Vec<String> = std::env::args().skip(1).collect();
    let _ = writeln!(md, "| command | `tumble-bench {}` |\n", command.join(" "));
    for w in report.warnings {
        let _ = writeln!(md, "> **Warning:** {w}\n");
    }
    for n in report.notes {
        let _ = writeln!(md, "> **Note:** {n}\n");
    }
    let _ = writeln!(md, "## tumble: ms per step and its stages\n");
    let _ = writeln!(md, "```text{}```\n", report.table);
    if !report.bodies.lines.is_empty() {
        let title = if report.bodies.engines.len() > 1 {
            "## pile_N: tumble, Box2D and Rapier (ms per step, median of the repeats)"
        } else {
            "## pile_N: tumble only (ms per step, median of the repeats)"
        };
        let _ = writeln!(md, "{title}\n");
        let _ = writeln!(md, "{}", report.bodies.markdown());
    }
    for f in report.files {
        if f.extension().is_some_and(|e| e == "svg")
            && let Some(name) = f.file_name().and_then(|n| n.to_str())
        {
            let _ = writeln!(md, "![{name}]({name})\n");
        }
    }
    md
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(engine: Engine, dynamic: usize, threads: usize, repeat: u32, step_ms: f64) -> Row {
        Row {
            family: "bodies",
            scene: format!("pile_{dynamic}"),
            bodies: dynamic + 3,
            dynamic,
            threads,
            engine,
            repeat,
            step_ms,
            stages: Vec::new(),
            contacts: None,
        }
    }

    /// Three repeats of two engines at 10 bodies, 1 and 2 threads, and one lone tumble run
    /// at 100 bodies: medians per engine, and ratios taken per repeat, then the median.
    fn sample() -> Vec<Row> {
        let mut rows = Vec::new();
        for (k, (tumble, box2d)) in [(1.0, 2.0), (2.0, 1.0), (6.0, 3.0)].into_iter().enumerate() {
            rows.push(row(Engine::Tumble, 10, 1, k as u32, tumble));
            rows.push(row(Engine::Box2d, 10, 1, k as u32, box2d));
            rows.push(row(Engine::Tumble, 10, 2, k as u32, tumble / 2.0));
            rows.push(row(Engine::Box2d, 10, 2, k as u32, 1.0));
        }
        rows.push(row(Engine::Tumble, 100, 1, 0, 8.0));
        rows.push(Row {
            family: "threads",
            ..row(Engine::Tumble, 10, 1, 0, 100.0)
        });
        rows
    }

    #[test]
    fn body_table_takes_medians_and_per_repeat_ratios() {
        let t = body_table(&sample(), &[1, 2]);
        assert_eq!(t.engines, vec![Engine::Tumble, Engine::Box2d]);
        assert_eq!(t.peers(), &[Engine::Box2d]);
        assert_eq!(t.lines.len(), 2);
        let l = &t.lines[0];
        assert_eq!((l.dynamic, l.bodies), (10, 13));
        // The `threads` family's 100 ms run is not in it.
        assert_eq!(l.ms[0], vec![Some(2.0), Some(1.0)]);
        assert_eq!(l.ms[1], vec![Some(2.0), Some(1.0)]);
        // Per repeat 0.5, 2, 2: the median is 2, not the ratio of the medians (1).
        assert_eq!(l.ratios[0][0], vec![0.5, 2.0, 2.0]);
        assert_eq!(l.ratio(0, 0), Some(2.0));
        assert_eq!(l.spread(0, 0), Some((0.5, 2.0)));
        assert_eq!(l.ratios[0][1], vec![0.5, 1.0, 3.0]);
        assert_eq!(l.ratio(0, 1), Some(1.0));
        // 100 bodies: tumble at 1 thread only, so no ratio.
        let l = &t.lines[1];
        assert_eq!(l.ms[0], vec![Some(8.0), None]);
        assert_eq!(l.ms[1], vec![None, None]);
        assert_eq!(l.ratio(0, 0), None);

        let md = t.markdown();
        assert!(md.starts_with(
            "| dynamic bodies | bodies | tumble, 1 thread | tumble, 2 threads | Box2D, 1 thread \
             | Box2D, 2 threads | tumble ÷ Box2D, 1 thread | tumble ÷ Box2D, 2 threads |\n"
        ));
        assert!(md.contains(
            "| 10 | 13 | 2.000 | 1.000 | 2.000 | 1.000 | 2.00 (0.50–2.00) | 1.00 (0.50–3.00) |\n"
        ));
        assert!(md.contains("| 100 | 103 | 8.000 | – | – | – | – | – |\n"));
        let text = t.text(3);
        assert!(text.contains("t/Box2D 2t"));
        assert!(text.contains(
            "\n     10      2.000      1.000      2.000      1.000       2.00       1.00\n"
        ));

        let series = body_series(&t);
        let labels: Vec<&str> = series.iter().map(|s| s.label.as_str()).collect();
        assert_eq!(
            labels,
            [
                "tumble, 1 thread",
                "tumble, 2 threads",
                "Box2D, 1 thread",
                "Box2D, 2 threads"
            ]
        );
        assert_eq!(series[0].points, vec![(10.0, 2.0), (100.0, 8.0)]);
        assert!(series[0].bold && !series[2].bold);
    }

    #[test]
    fn small_times_keep_four_decimals() {
        assert_eq!(ms_cell(0.00339), "0.0034");
        assert_eq!(ms_cell(0.25), "0.250");
        assert_eq!(ms_cell(12.3456), "12.346");
    }

    #[test]
    fn tumble_alone_has_no_ratio_columns() {
        let rows = vec![
            row(Engine::Tumble, 10, 1, 0, 1.5),
            row(Engine::Tumble, 10, 1, 1, 0.5),
        ];
        let t = body_table(&rows, &[1]);
        assert_eq!(t.engines, vec![Engine::Tumble]);
        assert!(t.peers().is_empty());
        assert_eq!(
            t.markdown(),
            "| dynamic bodies | bodies | tumble, 1 thread |\n|--:|--:|--:|\n| 10 | 13 | 1.000 |\n"
        );
    }

    #[test]
    fn peer_stages_fill_tumble_columns_by_common_name() {
        let mut r = row(Engine::Box2d, 10, 1, 0, 1.0);
        r.stages = vec![("narrow phase", 0.25), ("substeps", 0.5)];
        assert_eq!(
            stage_cells(&r, 6),
            vec![None, Some(0.25), None, Some(0.5), None, None]
        );
        let mut r = row(Engine::Tumble, 10, 1, 0, 1.0);
        r.stages = vec![("broad_phase", 0.125), ("narrow_phase", 0.25)];
        assert_eq!(stage_cells(&r, 2), vec![Some(0.125), Some(0.25)]);
    }
}
