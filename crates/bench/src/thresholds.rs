//! `tumble-bench thresholds`: where splitting each stage of the step over the threads begins
//! to pay. Each size of the pile family is stepped twice on the same thread count, once with
//! every stage inline (`WideThresholds::NEVER`) and once with every stage split
//! (`WideThresholds::ALWAYS`), interleaved. Each stage's time in the two runs, against the
//! count it is split by, gives the smallest count from which on splitting that stage gains;
//! the whole step's time, against its contacts, the smallest from which on waking the pool
//! for the step gains at all. `WideThresholds::default()` is set from these.

use std::fmt::Write as _;
use std::fs;
use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;
use tumble_physics::{StepProfile, WideThresholds, World};

use crate::machine;
use crate::scenes;
use crate::timing::{median, parse_list};

/// Arguments of `tumble-bench thresholds`.
#[derive(Debug, Args)]
pub struct ThresholdsArgs {
    /// Body counts of the pile family to step.
    #[arg(
        long,
        value_name = "N,N,..",
        default_value = "25,50,100,200,400,800,1600,3200,6400"
    )]
    pub bodies: String,
    /// Threads of the split runs [default: every core].
    #[arg(long, value_name = "T", value_parser = clap::value_parser!(u32).range(2..=1024))]
    pub threads: Option<u32>,
    /// Runs of each configuration (inline and split alternate); medians are reported.
    #[arg(long, value_name = "R", default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..))]
    pub repeats: u32,
    /// Untimed steps first.
    #[arg(long, value_name = "N", default_value_t = 10)]
    pub warmup: u32,
    /// Timed steps per run.
    #[arg(long, value_name = "N", default_value_t = 200, value_parser = clap::value_parser!(u32).range(1..))]
    pub steps: u32,
    /// Where to write the markdown report (printed to stdout too).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

/// The stages a threshold governs, with the count each is split by.
const STAGES: [(&str, &str); 5] = [
    ("broad_phase", "moved"),
    ("narrow_phase", "contacts"),
    ("prepare", "touching"),
    ("solve", "touching"),
    ("finalize", "bodies"),
];

/// Means over one run's timed steps.
#[derive(Clone, Debug, Default)]
struct Sample {
    /// Each of `STAGES`' time (ms); `prepare` includes storing the impulses, which the same
    /// threshold governs.
    stage_ms: [f64; 5],
    /// Each of `STAGES`' count.
    count: [f64; 5],
    step_ms: f64,
    /// The step's time outside its stages: waking the pool and waiting for it, when split.
    outside_ms: f64,
}

impl Sample {
    fn add(&mut self, p: &StepProfile, wall_ms: f64) {
        let stage = [
            p.broad_phase_ms,
            p.narrow_phase_ms,
            p.prepare_ms + p.store_impulses_ms,
            p.solve_ms,
            p.finalize_ms,
        ];
        let count = [p.moved, p.contacts, p.touching, p.touching, p.bodies];
        for k in 0..5 {
            self.stage_ms[k] += stage[k];
            self.count[k] += count[k] as f64;
        }
        self.step_ms += wall_ms;
        self.outside_ms += wall_ms - stage.iter().sum::<f64>();
    }

    fn scaled(mut self, n: f64) -> Sample {
        for k in 0..5 {
            self.stage_ms[k] /= n;
            self.count[k] /= n;
        }
        self.step_ms /= n;
        self.outside_ms /= n;
        self
    }
}

fn time(n: usize, threads: usize, wide: WideThresholds, args: &ThresholdsArgs) -> Result<Sample> {
    let scene = scenes::pile(n, 1);
    let mut world = World::from_scene(&scene, &scenes::limits())
        .with_context(|| format!("{}: cannot build the world", scene.name))?;
    world.set_thread_count(threads);
    world.set_wide_thresholds(wide);
    for _ in 0..args.warmup {
        world.step(scene.dt, scene.substeps);
    }
    let mut sample = Sample::default();
    for _ in 0..args.steps {
        let t = std::time::Instant::now();
        world.step(scene.dt, scene.substeps);
        let wall = t.elapsed().as_secs_f64() * 1e3;
        sample.add(world.profile(), wall);
    }
    Ok(sample.scaled(f64::from(args.steps)))
}

/// Medians over the repeats, field by field.
fn median_of(samples: &[Sample]) -> Sample {
    let m = |f: &dyn Fn(&Sample) -> f64| median(&samples.iter().map(f).collect::<Vec<_>>());
    Sample {
        stage_ms: std::array::from_fn(|k| m(&|s| s.stage_ms[k])),
        count: std::array::from_fn(|k| m(&|s| s.count[k])),
        step_ms: m(&|s| s.step_ms),
        outside_ms: m(&|s| s.outside_ms),
    }
}

/// One body count's medians: inline and split.
struct Size {
    bodies: usize,
    inline: Sample,
    wide: Sample,
    /// Medians over the repeats of each pair's gain (inline minus split, run back to back, so
    /// a slow spell of the machine falls on both): per stage, and the step's.
    stage_gain: [f64; 5],
    step_gain: f64,
}

impl Size {
    fn of(bodies: usize, inline: &[Sample], wide: &[Sample]) -> Size {
        let paired = |f: &dyn Fn(&Sample) -> f64| {
            let gains: Vec<f64> = inline.iter().zip(wide).map(|(a, b)| f(a) - f(b)).collect();
            median(&gains)
        };
        Size {
            bodies,
            inline: median_of(inline),
            wide: median_of(wide),
            stage_gain: std::array::from_fn(|k| paired(&|s| s.stage_ms[k])),
            step_gain: paired(&|s| s.step_ms),
        }
    }
}

/// The smallest `count` from which on (at that size and every larger one) `gain` is
/// positive; `None` when it is not at the largest size.
fn crossover(
    sizes: &[Size],
    count: impl Fn(&Size) -> f64,
    gain: impl Fn(&Size) -> f64,
) -> Option<f64> {
    let first = (0..sizes.len())
        .rev()
        .take_while(|&i| gain(&sizes[i]) > 0.0)
        .last()?;
    Some(count(&sizes[first]))
}

/// What a step's threshold counts: its contacts and moved proxies (`World` judges a step by
/// the same sum).
fn step_count(s: &Size) -> f64 {
    s.inline.count[0] + s.inline.count[1]
}

/// Stage `k`'s gain from splitting it (ms a step).
fn stage_gain(s: &Size, k: usize) -> f64 {
    s.stage_gain[k]
}

/// The whole step's gain from running it on the pool with every stage split (ms a step).
fn step_gain(s: &Size) -> f64 {
    s.step_gain
}

/// Runs the measurement and writes the report.
pub fn run(args: &ThresholdsArgs) -> Result<()> {
    let bodies = parse_list(&args.bodies).map_err(|e| anyhow::anyhow!("--bodies: {e}"))?;
    let threads = args.threads.map_or_else(machine::cores, |t| t as usize);
    if threads < 2 {
        bail!(
            "this machine has one core: there is nothing to split over (give --threads 2 to measure anyway)"
        );
    }
    let load_before = machine::load_average();
    let mut sizes = Vec::new();
    for &n in &bodies {
        let (mut inline, mut wide) = (Vec::new(), Vec::new());
        for r in 0..args.repeats {
            // Alternate which runs first, so neither always meets a cold cache or a busy core.
            for first in [r % 2 == 0, r % 2 == 1] {
                if first {
                    inline.push(time(n, threads, WideThresholds::NEVER, args)?);
                } else {
                    wide.push(time(n, threads, WideThresholds::ALWAYS, args)?);
                }
            }
        }
        eprintln!("pile_{n}: done");
        sizes.push(Size::of(n, &inline, &wide));
    }
    let text = report(args, threads, &sizes, &load_before);
    print!("{text}");
    if let Some(path) = &args.out {
        fs::write(path, &text).with_context(|| format!("cannot write {}", path.display()))?;
    }
    Ok(())
}

fn report(args: &ThresholdsArgs, threads: usize, sizes: &[Size], load_before: &str) -> String {
    let mut md = String::new();
    let _ = writeln!(
        md,
        "# tumble: where a stage's split over the threads pays\n"
    );
    let _ = writeln!(
        md,
        "Written by `tumble-bench thresholds`. Each size of the pile family (`pile_N`: N seeded boxes and circles dropped into a static box) is stepped {} times {} untimed steps, then {} timed, on {threads} threads twice, interleaved: every stage inline on the caller's thread (`WideThresholds::NEVER`), and every stage split over the threads (`WideThresholds::ALWAYS`). Figures are medians over the runs of per-step means from `World::profile()`; a gain is the median of the paired runs' differences (each pair run back to back). *outside* is the step's wall time outside its stages: in the split runs it holds waking the pool and handing the step back. A stage's split **pays** at a size when it gains (the stage is faster split); the step **pays** when the whole step is faster on the pool, wake included.\n",
        args.repeats, args.warmup, args.steps
    );
    machine::write_host_rows(&mut md);
    let _ = writeln!(
        md,
        "| load average (1, 5, 15 min) | {load_before} before, {} after |",
        machine::load_average()
    );
    let _ = writeln!(md, "| rustc | `{}` |", machine::rustc_version());
    machine::write_build_row(&mut md);
    let _ = writeln!(
        md,
        "| command | `tumble-bench thresholds --bodies {} --repeats {} --steps {}` |\n",
        args.bodies, args.repeats, args.steps
    );
    let _ = writeln!(md, "```text");
    let _ = writeln!(
        md,
        "{:>6} {:<13} {:>9} {:>10} {:>10} {:>8} {:>5}",
        "bodies", "stage", "count", "inline ms", "split ms", "gain ms", "pays"
    );
    let pays = |gain: f64| if gain > 0.0 { "yes" } else { "no" };
    for s in sizes {
        for (k, (stage, _)) in STAGES.iter().enumerate() {
            let gain = stage_gain(s, k);
            let _ = writeln!(
                md,
                "{:>6} {:<13} {:>9.0} {:>10.4} {:>10.4} {:>8.4} {:>5}",
                s.bodies,
                stage,
                s.inline.count[k],
                s.inline.stage_ms[k],
                s.wide.stage_ms[k],
                gain,
                pays(gain)
            );
        }
        let _ = writeln!(
            md,
            "{:>6} {:<13} {:>9} {:>10.4} {:>10.4} {:>8.4}",
            s.bodies,
            "outside",
            "",
            s.inline.outside_ms,
            s.wide.outside_ms,
            s.inline.outside_ms - s.wide.outside_ms
        );
        let _ = writeln!(
            md,
            "{:>6} {:<13} {:>9.0} {:>10.4} {:>10.4} {:>8.4} {:>5}\n",
            s.bodies,
            "step",
            step_count(s),
            s.inline.step_ms,
            s.wide.step_ms,
            step_gain(s),
            pays(step_gain(s))
        );
    }
    let _ = writeln!(md, "```\n");
    let _ = writeln!(
        md,
        "Crossovers: the smallest count from which on the split pays at every size measured, and the threshold it suggests: half that count (`WideThresholds` counts work per worker, and a stage splits when two workers get that much each). The step's count is its contacts and moved proxies. The defaults are `WideThresholds::default()` in the build measured.\n"
    );
    let _ = writeln!(
        md,
        "| stage | split by | crossover | suggested per worker | default |"
    );
    let _ = writeln!(md, "|---|---|---:|---:|---:|");
    let d = WideThresholds::default();
    let rows = [
        ("step", "contacts + moved", d.step),
        ("broad_phase", "moved", d.broad_phase),
        ("narrow_phase", "contacts", d.narrow_phase),
        ("prepare", "touching", d.prepare),
        ("solve", "touching", d.solve),
        ("finalize", "bodies", d.finalize),
    ];
    for (row, (stage, unit, default)) in rows.iter().enumerate() {
        let cross = if row == 0 {
            crossover(sizes, step_count, step_gain)
        } else {
            let k = row - 1;
            crossover(sizes, |s| s.inline.count[k], |s| stage_gain(s, k))
        };
        let (cross, suggested) = match cross {
            Some(c) => (format!("{c:.0}"), format!("{:.0}", (c / 2.0).ceil())),
            None => ("not at the largest size".into(), "-".into()),
        };
        let _ = writeln!(
            md,
            "| {stage} | {unit} | {cross} | {suggested} | {default} |"
        );
    }
    md
}

#[cfg(test)]
mod tests {
    use super::*;

    fn size(bodies: usize, count: f64, inline_ms: f64, wide_ms: f64, wake: f64) -> Size {
        let sample = |ms: f64, outside: f64| Sample {
            stage_ms: [ms; 5],
            count: [count; 5],
            step_ms: 5.0 * ms + outside,
            outside_ms: outside,
        };
        Size::of(
            bodies,
            &[sample(inline_ms, 0.001)],
            &[sample(wide_ms, 0.001 + wake)],
        )
    }

    #[test]
    fn the_crossover_is_where_the_split_pays_from_on() {
        // Stage gains 0.001, -0.01, 0.004, 0.05, 0.2: the split pays from the third size on,
        // whose count is 200. Step gains (5 stages, a wake of 0.01): -0.005, -0.06, 0.01,
        // 0.24, 0.99: from the third on as well, whose contacts and moved make 400.
        let sizes = [
            size(25, 50.0, 0.002, 0.001, 0.01),
            size(50, 100.0, 0.02, 0.03, 0.01),
            size(100, 200.0, 0.006, 0.002, 0.01),
            size(200, 400.0, 0.08, 0.03, 0.01),
            size(400, 800.0, 0.3, 0.1, 0.01),
        ];
        assert_eq!(
            crossover(&sizes, |s| s.inline.count[0], |s| stage_gain(s, 0)),
            Some(200.0)
        );
        assert_eq!(crossover(&sizes, step_count, step_gain), Some(400.0));
        // A split that does not pay at the largest size has no crossover.
        let never = [size(25, 50.0, 0.002, 0.003, 0.01)];
        assert_eq!(
            crossover(&never, |s| s.inline.count[2], |s| stage_gain(s, 2)),
            None
        );
    }
}
