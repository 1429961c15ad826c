//! `tumble-bench compare`: the same scenes in tumble, Box2D v3 (boxdd) and Rapier2D, one engine
//! after another in this process, each engine's step timed alone. Needs the `peers` feature.

use std::path::PathBuf;

use anyhow::Result;
use clap::Args;

/// Default `--warmup`: steps untimed before a run's timed ones.
const WARMUP_STEPS: u32 = 10;

/// Default scenes: Box2D's own benchmark scenes, all ten, that tumble builds the same way
/// (smash, compounds, junkyard, spinner, tumbler, rain and washer sleeping, as Box2D's
/// benchmark runs them; junkyard's pusher driven and rain's ragdolls made and destroyed in
/// every engine; spinner's paddle and tumbler's drum turned by revolute motors, joint_grid's
/// 19794 revolute joints, washer's kinematic drum, in every engine).
const DEFAULT_SCENES: &str = "large_pyramid,many_pyramids,smash,compounds,junkyard,spinner,\
                              joint_grid,tumbler,rain,washer";

/// Most threads the peers take (Box2D's worker count is 1 to 32).
pub(crate) const MAX_PEER_THREADS: u32 = 32;

/// The engines, in the order each configuration runs them (rotated from repeat to repeat).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Engine {
    Tumble,
    Box2d,
    Rapier,
}

/// Every engine, tumble first (the ratios are tumble's ms over each of the others').
pub(crate) const ENGINES: [Engine; 3] = [Engine::Tumble, Engine::Box2d, Engine::Rapier];

impl Engine {
    /// Lower-case name, for CSV files.
    pub(crate) fn key(self) -> &'static str {
        match self {
            Engine::Tumble => "tumble",
            Engine::Box2d => "box2d",
            Engine::Rapier => "rapier",
        }
    }
    /// Name as the tables and charts write it.
    pub(crate) fn title(self) -> &'static str {
        match self {
            Engine::Tumble => "tumble",
            Engine::Box2d => "Box2D",
            Engine::Rapier => "Rapier",
        }
    }
}

/// The helpers `sweep` shares: building each engine from a `SceneDef`, timing its steps, and
/// what the build may spoil.
#[cfg(feature = "peers")]
pub(crate) use imp::{build, build_warnings, peer_rows, settings_of, time_steps};

/// Arguments of `tumble-bench compare`.
#[derive(Debug, Args)]
pub struct CompareArgs {
    /// Scenes: built-in names, scene files, or `pile_N`.
    #[arg(long, value_name = "A,B,..", value_delimiter = ',', default_value = DEFAULT_SCENES)]
    pub scenes: Vec<String>,
    /// Thread counts, each engine given the same [default: 1 and the number of cores].
    #[arg(
        long,
        value_name = "T,T,..",
        value_delimiter = ',',
        value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_PEER_THREADS))
    )]
    pub threads: Option<Vec<u32>>,
    /// Runs of each engine, scene and thread count, each on a fresh world; the report gives the
    /// minimum and the median of the runs' mean ms per step.
    #[arg(long, value_name = "R", default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..))]
    pub repeats: u32,
    /// Timed steps per run, after the warm-up [default: each scene's own `steps`].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    pub steps: Option<u32>,
    /// Untimed steps each run takes first: the first steps of a fresh world create every
    /// contact and fill every buffer, which no later step repeats.
    #[arg(long, value_name = "N", default_value_t = WARMUP_STEPS)]
    pub warmup: u32,
    /// Steps of the 20-row `pyramid` cross-check (0 skips it).
    #[arg(long, value_name = "N", default_value_t = 600)]
    pub check_steps: u32,
    /// Where compare.md, compare.csv, compare_runs.csv and the charts go (created if missing).
    #[arg(long, value_name = "DIR", default_value = "docs/bench")]
    pub out_dir: PathBuf,
}

/// Runs the comparison.
pub fn run(args: &CompareArgs) -> Result<()> {
    #[cfg(feature = "peers")]
    {
        imp::run(args)
    }
    #[cfg(not(feature = "peers"))]
    {
        let _ = args;
        anyhow::bail!(
            "this tumble-bench was built without the `peers` feature, so it has no Box2D or Rapier \
             to compare with; rebuild with `--features peers`, e.g. \
             CFLAGS=\"-O3 -DNDEBUG\" cargo run --release -p tumble-bench --features peers -- compare \
             (see docs/bench/README.md)"
        )
    }
}

#[cfg(feature = "peers")]
mod imp {
    use std::fmt::Write as _;
    use std::path::{Path, PathBuf};
    use std::time::Instant;

    use anyhow::{Context, Result, bail};
    use indicatif::{ProgressBar, ProgressStyle};
    use tumble_physics::{BodyId, SceneDef, StepSettings, World};

    use super::{CompareArgs, ENGINES, Engine};
    use crate::csv::csv_field;
    use crate::machine;
    use crate::peers::Peer;
    use crate::peers::box2d::{self, Box2d};
    use crate::peers::rapier::{self, Rapier};
    use crate::plot::{self, Chart, Series};
    use crate::scenes;
    use crate::timing::{median, min};

    /// One run's result.
    struct Measure {
        scene: String,
        bodies: usize,
        threads: usize,
        engine: Engine,
        repeat: u32,
        steps: u32,
        ms: f64,
        /// Mean ms per step of each stage the engine reports (`peers::STAGES` names).
        stages: Vec<(&'static str, f64)>,
    }

    /// The tumble settings of a scene (what the peers are told where they have the knob).
    pub(crate) fn settings_of(scene: &SceneDef) -> Result<StepSettings> {
        crate::peers::scene_settings(scene)
    }

    pub(crate) fn build(
        engine: Engine,
        scene: &SceneDef,
        settings: &StepSettings,
        threads: usize,
    ) -> Result<Box<dyn Peer>> {
        Ok(match engine {
            Engine::Tumble => Box::new(TumblePeer::new(scene, threads)?),
            Engine::Box2d => Box::new(Box2d::new(scene, settings, threads)?),
            Engine::Rapier => Box::new(Rapier::new(scene, threads)?),
        })
    }

    /// tumble behind the same trait, so every engine is timed by the same loop.
    struct TumblePeer {
        world: World,
        dt: f32,
        substeps: u32,
        /// The built-in's script (junkyard's pusher), run before each step as `tumble-bench
        /// run` does; the peers run theirs (`peers::script`, chosen by the same name).
        script: Option<tumble_scene::builtin::Script>,
    }

    impl TumblePeer {
        fn new(scene: &SceneDef, threads: usize) -> Result<TumblePeer> {
            let mut world = World::from_scene(scene, &scenes::limits())
                .with_context(|| format!("{}: cannot build the tumble world", scene.name))?;
            world.set_thread_count(threads);
            Ok(TumblePeer {
                world,
                dt: scene.dt,
                substeps: scene.substeps,
                script: tumble_scene::builtin::script(&scene.name),
            })
        }
    }

    impl Peer for TumblePeer {
        fn step(&mut self) -> Result<()> {
            if let Some(script) = self.script {
                script(self.world.step_count(), &mut self.world);
            }
            self.world.step(self.dt, self.substeps);
            Ok(())
        }
        /// The body frame's origin, as the peers and the runner report it (the centre of mass
        /// for a body of one shape).
        fn pose(&mut self, index: usize) -> Result<[f32; 3]> {
            let b = self.world.body(BodyId::scene(index))?;
            Ok([b.origin.x, b.origin.y, b.angle])
        }
        fn velocity(&mut self, index: usize) -> Result<[f32; 3]> {
            let b = self.world.body(BodyId::scene(index))?;
            Ok([b.linear_velocity.x, b.linear_velocity.y, b.angular_velocity])
        }
        fn stages(&mut self) -> Vec<(&'static str, f64)> {
            // tumble's own stages are the common ones, in the same step order (both arrays
            // are seven long, so a stage added to one without the other fails to compile).
            let names: [&'static str; 7] = crate::peers::STAGES;
            let stages: [(&str, f64); 7] = self.world.profile().stages();
            names
                .into_iter()
                .zip(stages)
                .map(|(name, (_, ms))| (name, ms))
                .collect()
        }
    }

    /// Mean wall ms of `peer.step()` over `steps` steps after `warmup` untimed ones (nothing
    /// else is inside the clock), and the mean of each stage the peer reports.
    pub(crate) fn time_steps(
        peer: &mut dyn Peer,
        warmup: u32,
        steps: u32,
    ) -> Result<(f64, Vec<(&'static str, f64)>)> {
        for _ in 0..warmup {
            peer.step()?;
        }
        let mut total = 0.0;
        let mut stages: Vec<(&'static str, f64)> = Vec::new();
        for _ in 0..steps {
            let t = Instant::now();
            peer.step()?;
            total += t.elapsed().as_secs_f64();
            for (k, (name, ms)) in peer.stages().into_iter().enumerate() {
                match stages.get_mut(k) {
                    Some(s) => s.1 += ms,
                    None => stages.push((name, ms)),
                }
            }
        }
        let n = f64::from(steps.max(1));
        for s in &mut stages {
            s.1 /= n;
        }
        Ok((total * 1e3 / n, stages))
    }

    /// What the build and the machine may spoil, said before the numbers.
    pub(crate) fn build_warnings() -> Result<Vec<String>> {
        let mut warnings = Vec::new();
        if !machine::optimised() {
            warnings.push(
                "this is a debug build: its timings say nothing about any engine; use --release"
                    .to_string(),
            );
        }
        let cflags = machine::build_cflags();
        let has = |flag: &str| cflags.split_whitespace().any(|f| f == flag);
        if !(has("-O3") && has("-DNDEBUG")) {
            warnings.push(format!(
                "Box2D's C code was built with CFLAGS={cflags:?}, not \"-O3 -DNDEBUG\": boxdd then \
                 compiles it at -O2 with Box2D's asserts on (about 9% slower than Box2D's Release \
                 build); rebuild as docs/bench/README.md says"
            ));
        }
        let avx2_cpu = machine::cpu_has_avx2();
        let avx2_build = cfg!(feature = "simd-avx2");
        if avx2_build && !avx2_cpu {
            bail!(
                "built with the simd-avx2 feature but this CPU has no AVX2: Box2D would crash; \
                 rebuild with `--features peers` only"
            );
        }
        if avx2_cpu && !avx2_build {
            warnings.push(
                "the CPU has AVX2 but Box2D was built without it (its default SSE2 path); rebuild \
                 with `--features peers,simd-avx2`"
                    .to_string(),
            );
        }
        Ok(warnings)
    }

    pub fn run(args: &CompareArgs) -> Result<()> {
        let load_before = machine::load_average();
        let warnings = build_warnings()?;
        for w in &warnings {
            eprintln!("warning: {w}");
        }
        let threads: Vec<usize> = match &args.threads {
            Some(t) => t.iter().map(|&t| t as usize).collect(),
            None => {
                let mut t = vec![1, machine::cores().min(super::MAX_PEER_THREADS as usize)];
                t.dedup();
                t
            }
        };
        let mut list = Vec::new();
        for name in &args.scenes {
            let scene = scenes::resolve(name)?;
            let settings = settings_of(&scene)?;
            let steps = args.steps.unwrap_or(scene.steps).max(1);
            list.push((scene, settings, steps));
        }
        if list.is_empty() {
            bail!("no scenes given");
        }
        std::fs::create_dir_all(&args.out_dir)
            .with_context(|| format!("cannot create {}", args.out_dir.display()))?;

        eprintln!(
            "compare: {} scenes x threads {:?} x {} repeats x 3 engines; each run steps {} times \
             untimed, then times its steps; world building is not timed; the engines' order \
             rotates from run to run",
            list.len(),
            threads,
            args.repeats,
            args.warmup
        );
        let total = list.len() * threads.len() * args.repeats as usize * ENGINES.len();
        let bar = ProgressBar::new(total as u64);
        bar.set_style(
            ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} (eta {eta}) {msg}",
            )
            .expect("a valid progress template"),
        );
        let mut measures = Vec::new();
        for repeat in 0..args.repeats {
            for (scene, settings, steps) in &list {
                for &t in &threads {
                    // Rotated each run, so no engine always runs first (after a world was
                    // dropped, on a cold cache) or last.
                    let mut order = ENGINES;
                    order.rotate_left(repeat as usize % ENGINES.len());
                    for engine in order {
                        bar.set_message(format!(
                            "{} {} t={t} #{}",
                            engine.title(),
                            scene.name,
                            repeat + 1
                        ));
                        let mut peer = build(engine, scene, settings, t)?;
                        let (ms, stages) = time_steps(peer.as_mut(), args.warmup, *steps)?;
                        drop(peer);
                        measures.push(Measure {
                            scene: scene.name.clone(),
                            bodies: scene.bodies.len(),
                            threads: t,
                            engine,
                            repeat,
                            steps: *steps,
                            ms,
                            stages,
                        });
                        bar.inc(1);
                    }
                }
            }
        }
        bar.finish_and_clear();

        let check = if args.check_steps > 0 {
            Some(cross_check(args.check_steps)?)
        } else {
            None
        };

        let load = format!("{load_before} before, {} after", machine::load_average());
        let summary = summarise(&measures, &list, &threads);
        print!("{}", text_table(&summary, args.repeats));
        print!("\n{}", stage_table(&measures, &summary));
        if let Some(c) = &check {
            print!("{}", c.text());
        }
        let mut written = Vec::new();
        let md = args.out_dir.join("compare.md");
        write(
            &md,
            &markdown(
                &measures,
                &summary,
                check.as_ref(),
                &warnings,
                args,
                &threads,
                &load,
            ),
        )?;
        written.push(md);
        let csv = args.out_dir.join("compare.csv");
        write(&csv, &summary_csv(&summary, args.repeats))?;
        written.push(csv);
        let runs = args.out_dir.join("compare_runs.csv");
        write(&runs, &runs_csv(&measures))?;
        written.push(runs);
        if threads.len() > 1 {
            written.extend(charts(&args.out_dir, &summary)?);
        }
        for p in &written {
            println!("wrote {}", p.display());
        }
        Ok(())
    }

    fn write(path: &Path, text: &str) -> Result<()> {
        std::fs::write(path, text).with_context(|| format!("cannot write {}", path.display()))
    }

    /// One scene and thread count: each engine's minimum and median ms per step.
    struct Line {
        scene: String,
        bodies: usize,
        threads: usize,
        steps: u32,
        /// (min, median) per engine, in `ENGINES` order.
        ms: [(f64, f64); 3],
        /// Per peer (index 1 and 2 as in `ENGINES`), tumble's ms ÷ the peer's of each run:
        /// both taken in the same repeat, minutes apart at most, so the machine's load
        /// drifts less between them than across the whole comparison.
        ratios: [Vec<f64>; 3],
    }

    impl Line {
        /// The median of the runs' ratios, tumble ÷ the peer.
        fn ratio(&self, peer: usize) -> f64 {
            median(&self.ratios[peer])
        }
        /// The smallest and largest of the runs' ratios.
        fn spread(&self, peer: usize) -> (f64, f64) {
            let v = &self.ratios[peer];
            (min(v), v.iter().copied().fold(f64::MIN, f64::max))
        }
        /// tumble's minimum over the peer's minimum.
        fn ratio_min(&self, peer: usize) -> f64 {
            self.ms[0].0 / self.ms[peer].0
        }
        /// "median (least–most)" ratio cell.
        fn ratio_cell(&self, peer: usize) -> String {
            let (lo, hi) = self.spread(peer);
            format!("{:.2} ({lo:.2}–{hi:.2})", self.ratio(peer))
        }
    }

    fn summarise(
        measures: &[Measure],
        list: &[(SceneDef, StepSettings, u32)],
        threads: &[usize],
    ) -> Vec<Line> {
        let repeats = measures.iter().map(|m| m.repeat).max().map_or(0, |r| r + 1);
        let mut out = Vec::new();
        for (scene, _, steps) in list {
            for &t in threads {
                let ms = ENGINES.map(|engine| {
                    let v: Vec<f64> = measures
                        .iter()
                        .filter(|m| m.scene == scene.name && m.threads == t && m.engine == engine)
                        .map(|m| m.ms)
                        .collect();
                    (min(&v), median(&v))
                });
                let run_ms = |engine: Engine, repeat: u32| {
                    measures
                        .iter()
                        .find(|m| {
                            m.scene == scene.name
                                && m.threads == t
                                && m.engine == engine
                                && m.repeat == repeat
                        })
                        .map(|m| m.ms)
                };
                let ratios = std::array::from_fn(|peer| {
                    (0..repeats)
                        .filter_map(|r| Some(run_ms(ENGINES[0], r)? / run_ms(ENGINES[peer], r)?))
                        .collect()
                });
                out.push(Line {
                    scene: scene.name.clone(),
                    bodies: scene.bodies.len(),
                    threads: t,
                    steps: *steps,
                    ms,
                    ratios,
                });
            }
        }
        out
    }

    fn text_table(lines: &[Line], repeats: u32) -> String {
        let mut out = String::new();
        let _ = writeln!(
            out,
            "\nms per step, min / median of {repeats} runs; ratio = tumble / peer per run: median (least-most)"
        );
        let header = format!(
            "{:<16} {:>6} {:>3} {:>5} {:>17} {:>17} {:>17} {:>17} {:>17}",
            "scene",
            "bodies",
            "thr",
            "steps",
            "tumble",
            "Box2D",
            "Rapier",
            "tumble/Box2D",
            "tumble/Rapier"
        );
        let _ = writeln!(out, "{header}");
        let _ = writeln!(out, "{}", "-".repeat(header.len()));
        for l in lines {
            let cell = |(lo, med): (f64, f64)| format!("{lo:.3} / {med:.3}");
            let _ = writeln!(
                out,
                "{:<16} {:>6} {:>3} {:>5} {:>17} {:>17} {:>17} {:>17} {:>17}",
                l.scene,
                l.bodies,
                l.threads,
                l.steps,
                cell(l.ms[0]),
                cell(l.ms[1]),
                cell(l.ms[2]),
                l.ratio_cell(1),
                l.ratio_cell(2)
            );
        }
        out
    }

    fn summary_csv(lines: &[Line], repeats: u32) -> String {
        let mut out = String::from(
            "scene,bodies,threads,steps,repeats,tumble_min_ms,tumble_median_ms,box2d_min_ms,\
             box2d_median_ms,rapier_min_ms,rapier_median_ms,tumble_over_box2d,tumble_over_rapier,\
             tumble_over_box2d_min,tumble_over_rapier_min,tumble_over_box2d_least,\
             tumble_over_box2d_most,tumble_over_rapier_least,tumble_over_rapier_most\n",
        );
        for l in lines {
            let _ = writeln!(
                out,
                "{},{},{},{},{},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4},{:.4}",
                csv_field(&l.scene),
                l.bodies,
                l.threads,
                l.steps,
                repeats,
                l.ms[0].0,
                l.ms[0].1,
                l.ms[1].0,
                l.ms[1].1,
                l.ms[2].0,
                l.ms[2].1,
                l.ratio(1),
                l.ratio(2),
                l.ratio_min(1),
                l.ratio_min(2),
                l.spread(1).0,
                l.spread(1).1,
                l.spread(2).0,
                l.spread(2).1
            );
        }
        out
    }

    fn runs_csv(measures: &[Measure]) -> String {
        let mut out = String::from("scene,bodies,threads,engine,repeat,steps,ms_per_step\n");
        for m in measures {
            let _ = writeln!(
                out,
                "{},{},{},{},{},{},{:.6}",
                csv_field(&m.scene),
                m.bodies,
                m.threads,
                m.engine.key(),
                m.repeat + 1,
                m.steps,
                m.ms
            );
        }
        out
    }

    fn charts(dir: &Path, lines: &[Line]) -> Result<Vec<PathBuf>> {
        let mut written = Vec::new();
        let mut names: Vec<&str> = Vec::new();
        for l in lines {
            if !names.contains(&l.scene.as_str()) {
                names.push(&l.scene);
            }
        }
        for name in names {
            let of: Vec<&Line> = lines.iter().filter(|l| l.scene == name).collect();
            let series: Vec<Series> = ENGINES
                .iter()
                .enumerate()
                .map(|(i, e)| Series {
                    label: e.title().to_string(),
                    points: of.iter().map(|l| (l.threads as f64, l.ms[i].1)).collect(),
                    bold: i == 0,
                })
                .collect();
            let slug: String = name
                .chars()
                .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
                .collect();
            let path = dir.join(format!("compare_{slug}.svg"));
            let title = format!(
                "{name} ({} bodies): ms per step against threads",
                of[0].bodies
            );
            plot::linear(
                &path,
                &Chart {
                    title: &title,
                    x_label: "worker threads",
                    y_label: "ms per step (median of runs)",
                    series: &series,
                },
            )?;
            written.push(path);
        }
        Ok(written)
    }

    /// The top box of the 20-row `pyramid` after N steps in each engine, at 1 thread.
    struct Check {
        steps: u32,
        rows: usize,
        start: [f32; 3],
        /// (x, y, angle) per engine, in `ENGINES` order.
        poses: Vec<[f32; 3]>,
    }

    impl Check {
        fn text(&self) -> String {
            let mut out = format!(
                "\ncross-check: pyramid ({} rows), top box after {} steps (starts at x {:.4}, y {:.4}):\n",
                self.rows, self.steps, self.start[0], self.start[1]
            );
            for (e, p) in ENGINES.iter().zip(&self.poses) {
                let _ = writeln!(
                    out,
                    "  {:<7} x {:>9.5}  y {:>9.5}  angle {:>10.6}",
                    e.title(),
                    p[0],
                    p[1],
                    p[2]
                );
            }
            out
        }
    }

    fn cross_check(steps: u32) -> Result<Check> {
        let scene = scenes::resolve("pyramid")?;
        let settings = settings_of(&scene)?;
        let top = scene.bodies.len() - 1;
        let b = &scene.bodies[top];
        let start = [b.position[0], b.position[1], b.angle];
        // Rows: the dynamic bodies form a triangle of n(n+1)/2 boxes.
        let dynamic = scene.bodies.len() - 1;
        let rows = ((((8 * dynamic + 1) as f64).sqrt() - 1.0) / 2.0).round() as usize;
        let mut poses = Vec::new();
        for engine in ENGINES {
            let mut peer = build(engine, &scene, &settings, 1)?;
            for _ in 0..steps {
                peer.step()?;
            }
            poses.push(peer.pose(top)?);
        }
        Ok(Check {
            steps,
            rows,
            start,
            poses,
        })
    }

    /// Per scene and thread count, the stages of each engine's fastest run (the least
    /// disturbed), as mean ms per step; "other" is the step's time outside the stages.
    fn stage_table(measures: &[Measure], lines: &[Line]) -> String {
        let mut md = String::new();
        let _ = writeln!(
            md,
            "## Where the time goes (ms per step, each engine's fastest run)\n"
        );
        let _ = writeln!(
            md,
            "Stages as each engine times them (tumble's `StepProfile`; Box2D's `b2Profile`, \
             grouped as `peers/box2d.rs` says; Rapier reports none here). The stage that holds \
             tumble back is the one with the largest difference. The stages do not hold quite the \
             same work: Box2D colours the constraint graph inside its collide stage (a contact \
             that begins touching is added to a colour in `b2Collide`'s serial tail, and keeps \
             it), tumble in prepare (from scratch when the touching pairs changed, else kept); \
             Box2D's broad phase is `pairs + refit`, its tree rebuild running beside the collide \
             stage; Box2D's substep timers are taken on the orchestrating thread and include its \
             waits, as tumble's are.\n"
        );
        let _ = write!(md, "| scene | threads | engine | step |");
        for s in crate::peers::STAGES {
            let _ = write!(md, " {s} |");
        }
        let _ = writeln!(md, " other |");
        let _ = writeln!(md, "|---|--:|---|--:|{}--:|", "--:|".repeat(STAGES_LEN));
        for l in lines {
            for engine in [Engine::Tumble, Engine::Box2d] {
                let fastest = measures
                    .iter()
                    .filter(|m| m.scene == l.scene && m.threads == l.threads && m.engine == engine)
                    .min_by(|a, b| a.ms.total_cmp(&b.ms));
                let Some(m) = fastest else { continue };
                if m.stages.is_empty() {
                    continue;
                }
                let _ = write!(
                    md,
                    "| {} | {} | {} | {:.3} |",
                    l.scene,
                    l.threads,
                    engine.title(),
                    m.ms
                );
                let mut inside = 0.0;
                for name in crate::peers::STAGES {
                    let ms = m
                        .stages
                        .iter()
                        .find(|(n, _)| *n == name)
                        .map_or(0.0, |s| s.1);
                    inside += ms;
                    let _ = write!(md, " {ms:.3} |");
                }
                let _ = writeln!(md, " {:.3} |", m.ms - inside);
            }
        }
        let _ = writeln!(md);
        md
    }

    const STAGES_LEN: usize = crate::peers::STAGES.len();

    /// The Box2D and Rapier rows of a report's machine table (markdown, one line each);
    /// `settings` names where the engines' settings are written out.
    pub(crate) fn peer_rows(settings: &str) -> String {
        let mut md = String::new();
        let _ = writeln!(
            md,
            "| Box2D | {} via boxdd {}; CFLAGS `{}`; AVX2 path {} |",
            box2d::version(),
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
            "| Rapier | rapier2d {} (feature `parallel`; its 4-lane SIMD solver is always on, see {settings}) |",
            rapier::version()
        );
        md
    }

    fn markdown(
        measures: &[Measure],
        lines: &[Line],
        check: Option<&Check>,
        warnings: &[String],
        args: &CompareArgs,
        threads: &[usize],
        load: &str,
    ) -> String {
        let mut md = String::new();
        let _ = writeln!(md, "# tumble against Box2D v3 and Rapier2D\n");
        let _ = writeln!(
            md,
            "Written by `tumble-bench compare`. Each engine builds the same scene from the same \
             `SceneDef` (every body, shape, density, friction, restitution, velocity, damping, \
             gravity, dt and substeps) and runs one after another in one process; only each \
             engine's step call is inside the clock (world building is not). A run first steps {} \
             times untimed (the first steps of a fresh world create every contact and fill every \
             buffer), then times each of its steps; the engines' order rotates from run to run, \
             so none always runs first. The table gives the minimum and the median, over {} runs, \
             of a run's mean ms per step. Ratio = tumble ÷ the peer of the same run, as the median \
             over the runs with the least and the most in brackets; below 1, tumble is faster. The \
             machine is shared with other work, so a run can be slowed by it: the spread says how \
             much. Figures from another host are not comparable with these.\n",
            args.warmup, args.repeats
        );
        let _ = writeln!(md, "| | |\n|---|---|");
        let _ = writeln!(md, "| CPU | {} |", machine::cpu_model());
        let _ = writeln!(
            md,
            "| cores | {} (thread counts run: {}) |",
            machine::cores(),
            threads
                .iter()
                .map(|t| t.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        );
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
        md.push_str(&peer_rows("Settings"));
        machine::write_build_row(&mut md);
        let command: Vec<String> = std::env::args().skip(1).collect();
        let _ = writeln!(md, "| command | `tumble-bench {}` |\n", command.join(" "));
        for w in warnings {
            let _ = writeln!(md, "> **Warning:** {w}\n");
        }

        let _ = writeln!(
            md,
            "## ms per step (min / median); ratio: median (least–most) of the runs\n"
        );
        let _ = writeln!(
            md,
            "| scene | bodies | threads | steps | tumble | Box2D | Rapier | tumble ÷ Box2D | tumble ÷ Rapier |"
        );
        let _ = writeln!(md, "|---|--:|--:|--:|--:|--:|--:|--:|--:|");
        for l in lines {
            let cell = |(lo, med): (f64, f64)| format!("{lo:.3} / {med:.3}");
            let _ = writeln!(
                md,
                "| {} | {} | {} | {} | {} | {} | {} | {} | {} |",
                l.scene,
                l.bodies,
                l.threads,
                l.steps,
                cell(l.ms[0]),
                cell(l.ms[1]),
                cell(l.ms[2]),
                l.ratio_cell(1),
                l.ratio_cell(2)
            );
        }
        let _ = writeln!(md);

        md.push_str(&stage_table(measures, lines));

        if let Some(c) = check {
            let _ = writeln!(md, "## Cross-check: do they simulate the same thing?\n");
            let _ = writeln!(
                md,
                "`pyramid` ({} rows of 1 m boxes on a static ground), 1 thread, {} steps: the top \
                 box, which starts at x = {:.4} m, y = {:.4} m.\n",
                c.rows, c.steps, c.start[0], c.start[1]
            );
            let _ = writeln!(
                md,
                "| engine | x (m) | y (m) | angle (rad) |\n|---|--:|--:|--:|"
            );
            for (e, p) in ENGINES.iter().zip(&c.poses) {
                let _ = writeln!(
                    md,
                    "| {} | {:.5} | {:.5} | {:.6} |",
                    e.title(),
                    p[0],
                    p[1],
                    p[2]
                );
            }
            let _ = writeln!(md);
        }

        let _ = writeln!(md, "## Settings\n");
        let _ = writeln!(
            md,
            "- **Every engine**: each body with all its parts (one shape or collider per part, at \
             its offset and angle, with its own density, friction, restitution and filter), its \
             kind, `gravity_scale`, `fixed_rotation` and damping; sleeping as the scene says \
             (its `sleep`, each body's `enable_sleep` and `awake`, the `solver` block's \
             `sleep_threshold`; `peers/box2d.rs` and `peers/rapier.rs` say what each maps and \
             how Rapier's sleep test differs); a built-in with a script (junkyard's pusher) runs \
             it before every step in every engine (Box2D through `b2Body_SetTargetTransform`, \
             Rapier and tumble with the velocity that reaches the target in one step). Poses \
             are the body frame's origin.\n\
             - **tumble**: `World::from_scene` defaults (contact 30 Hz, damping ratio 10, push-out \
             3 m/s, 1 relax pass, warm starting, restitution threshold 1 m/s, speed cap 400 m/s, \
             sleep threshold 0.05 m/s after 0.5 s) and the scene's `solver` block; \
             `set_thread_count(threads)`.\n\
             - **Box2D**: tumble's gravity, contact hertz, damping ratio, push-out speed \
             (`contactSpeed`), restitution threshold, speed cap and sleep threshold (its time to \
             sleep is fixed at 0.5 s); continuous collision as the scene says (on by default, as in \
             tumble); contact, hit (at the scene's `hit_speed`) and sensor events on for every \
             shape, the events tumble gathers; `workerCount = threads` (Box2D's own \
             scheduler: the caller plus threads − 1). Boxes are `b2MakeBox` (`b2MakeOffsetBox` \
             for an offset part), other polygons the hull of their vertices, radius 0. Friction \
             mixes as `sqrt(a·b)` and restitution as `max(a, b)`, as in tumble.\n\
             - **Rapier**: `dt` = the scene's, `num_solver_iterations` = the scene's substeps \
             (Rapier's substeps), all other integration parameters Rapier's defaults; \
             continuous collision as the scene says (`max_ccd_substeps = 1` and every dynamic \
             body `ccd_enabled` when it is on, as it is by default; Rapier then sweeps every \
             dynamic body against every collider); collision events (contact and sensor begin \
             and end) on for every collider and read after each step (Rapier has no hit event \
             by approach speed); sleep \
             threshold and time as tumble's; filters as interaction groups (a non-zero group by \
             a contact filter hook); friction: each collider its part's coefficient with \
             `CoefficientCombineRule::GeometricMean`, which is `sqrt(a·b)` for every pair, \
             exactly tumble's rule (not `Multiply`, which would give `a·b`); restitution \
             `CoefficientCombineRule::Max`. The step runs inside a rayon pool of `threads` \
             threads (`ThreadPool::install`). Rapier 0.36 solves its contacts 4 at a time \
             with SIMD (`wide`) in every build; its one SIMD feature, `simd8`, makes that 8 at \
             a time, but without a `target-cpu` flag for the whole build (which neither tumble, \
             choosing AVX2 at run time, nor Box2D, built with `-mavx2` by boxdd, needs) its \
             8-lane type is two 4-lane halves: measured at `38c3da0` on a 2-vCPU AMD EPYC, \
             interleaved, 3 runs each at 1 thread, `simd8` made Rapier slower (large_pyramid \
             7.7 → 8.2 ms, smash 19.8 → 21.7 ms, medians), so it stays off."
        );
        md
    }
}
