//! `tumble-bench run`: one scene, N steps, one JSON document.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;
use serde::Serialize;
use serde::ser::SerializeMap;
use tumble_physics::{Event, EventCursor, Limits, World, default_thread_count};
use tumble_scene::sample::{Controller, KeyScript, Keys};
use tumble_scene::{DEFAULT_MAX_FILE_BYTES, LoadLimits};

/// Most worker threads a run may ask for; far more than any machine here has cores.
const MAX_THREADS: u32 = 1024;

/// Arguments of `tumble-bench run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// A `.ron` or `.json` scene file, or a built-in scene's name.
    #[arg(value_name = "SCENE")]
    pub scene: String,
    /// Steps to run [default: the scene's `steps`].
    #[arg(long, value_name = "N", allow_negative_numbers = true)]
    pub steps: Option<u32>,
    /// Worker threads for the step, >= 1 [default: all cores].
    #[arg(
        long,
        value_name = "T",
        allow_negative_numbers = true,
        value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_THREADS))
    )]
    pub threads: Option<u32>,
    /// Solver substeps per step, >= 1 [default: the scene's `substeps`].
    #[arg(
        long,
        value_name = "S",
        allow_negative_numbers = true,
        value_parser = clap::value_parser!(u32).range(1..)
    )]
    pub substeps: Option<u32>,
    /// Write the JSON to FILE instead of stdout.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Write the run's events to FILE, one JSON object a line (CONTRACT.md section 7).
    #[arg(long, value_name = "FILE")]
    pub events: Option<PathBuf>,
    /// Most bodies a scene may hold.
    #[arg(long, value_name = "N", default_value_t = Limits::default().max_bodies)]
    pub max_bodies: usize,
    /// Largest scene file accepted, in bytes.
    #[arg(long, value_name = "BYTES", default_value_t = DEFAULT_MAX_FILE_BYTES)]
    pub max_file_bytes: u64,
    /// Install a pre-solve hook that reads each contact's normal and lets every contact
    /// push (`World::set_pre_solve`): what the hook costs a step, with the same results as
    /// without it.
    #[arg(long)]
    pub pre_solve: bool,
    /// Keys for a played sample (the platformer), by step, as the viewer's `--keys` takes
    /// them: `STEP:KEY+` or `STEP:KEY-`, KEY one of left, right, jump, down, or `demo` (the
    /// sample's own run). A built-in with a controller runs it with or without keys, as the
    /// viewer does.
    #[arg(long, value_name = "SCRIPT")]
    pub keys: Option<String>,
}

/// The document `run` writes (CONTRACT.md, section 2). Field order is the contract's.
#[derive(Debug, Serialize)]
struct Report {
    scene: String,
    steps: u32,
    threads: usize,
    dt: f32,
    substeps: u32,
    /// Simulated seconds: steps × dt.
    time: f64,
    state_hash: String,
    bodies: Vec<BodyState>,
    profile: Profile,
    /// Contacts alive after the last step.
    contacts: usize,
    /// Bodies the engine's NaN guard had to stop over the whole run (CONTRACT.md section 6):
    /// 0 in a healthy run.
    non_finite_bodies: u64,
    /// Joints in the world after the last step (CONTRACT.md section 6).
    joints: usize,
    /// Bodies awake after the last step.
    awake_bodies: usize,
    /// Islands after the last step, and of those the awake ones.
    islands: [usize; 2],
    /// A played sample's state at the end (the platformer's character and score).
    sample: Option<Controller>,
}

/// One body after the last step. serde_json writes each f32 in the shortest form that reads
/// back to the same bits.
#[derive(Debug, Serialize)]
struct BodyState {
    position: [f32; 2],
    angle: f32,
    linear_velocity: [f32; 2],
    angular_velocity: f32,
    /// CONTRACT.md section 6.
    awake: bool,
}

/// `step_ms_mean` first, then `<stage>_ms_mean` per named stage in pipeline order. A map of our
/// own so the order is kept without serde_json's `preserve_order` feature.
#[derive(Debug)]
struct Profile(Vec<(String, f64)>);

impl Serialize for Profile {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut map = serializer.serialize_map(Some(self.0.len()))?;
        for (key, value) in &self.0 {
            map.serialize_entry(key, value)?;
        }
        map.end()
    }
}

/// Runs the scene and writes the report.
pub fn run(args: &RunArgs) -> Result<()> {
    let limits = LoadLimits {
        max_file_bytes: args.max_file_bytes,
        scene: Limits {
            max_bodies: args.max_bodies,
            ..Limits::default()
        },
    };
    // `pile_N` (the sweep's generated family) as every other bench command takes it, unless a
    // file of that name exists.
    let generated = args.scene.starts_with(crate::scenes::PILE_PREFIX)
        && !std::path::Path::new(&args.scene).exists();
    let mut scene = if generated {
        crate::scenes::resolve(&args.scene)?
    } else {
        tumble_scene::load(&args.scene, &limits)?
    };
    if let Some(substeps) = args.substeps {
        if substeps > limits.scene.max_substeps {
            bail!(
                "--substeps {substeps} is too many; allowed: 1 to {}",
                limits.scene.max_substeps
            );
        }
        scene.substeps = substeps;
    }
    let steps = args.steps.unwrap_or(scene.steps);
    let mut world = World::from_scene(&scene, &limits.scene)
        .with_context(|| format!("{}: cannot build the world", args.scene))?;
    let threads = args
        .threads
        .map_or_else(default_thread_count, |t| t as usize)
        .max(1);
    world.set_thread_count(threads);
    if args.pre_solve {
        // A real call through the hook, reading its arguments, whose answer is always yes
        // for a finite world (the step never makes a normal that is not).
        world.set_pre_solve(Some(Box::new(|_, _, normal| normal.is_finite())));
    }

    let mut step_ms = 0.0f64;
    let mut stage_ms: Vec<(&'static str, f64)> = Vec::new();
    // A long run (a million bodies steps slowly) shows its progress; indicatif draws nothing
    // when stderr is not a terminal, so scripts see only the JSON.
    let bar = indicatif::ProgressBar::new(u64::from(steps));
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} steps, eta {eta}")
            .expect("a valid template"),
    );
    // A built-in that moves things between steps (junkyard's pusher) does so here too.
    let is_file = std::path::Path::new(&args.scene).exists();
    let script = tumble_scene::builtin::script(&args.scene).filter(|_| !generated && !is_file);
    let mut controller = Controller::for_scene(&scene).filter(|_| !generated && !is_file);
    let key_script = match &args.keys {
        Some(text) => {
            KeyScript::for_scene(text, &scene).map_err(|e| anyhow::anyhow!("--keys: {e}"))?
        }
        None => KeyScript::default(),
    };
    if !key_script.is_empty() && controller.is_none() {
        bail!(
            "--keys: {} reads no keys (a sample a person plays does: platformer)",
            args.scene
        );
    }
    if let Some(c) = &controller {
        c.install(&mut world);
    }
    let mut keys = Keys::NONE;
    let mut events = match &args.events {
        Some(path) => Some(EventFile::create(path)?),
        None => None,
    };
    for _ in 0..steps {
        bar.inc(1);
        // Steps count from 1 in the event file; a script's changes before step k (a body
        // destroyed while touching) are reported with it, before the step's own.
        let k = world.step_count() + 1;
        if let Some(script) = script {
            script(world.step_count(), &mut world);
            if let Some(file) = &mut events {
                file.write_new(&world, k)?;
            }
        }
        if let Some(c) = &mut controller {
            keys = key_script.keys_at(world.step_count(), keys);
            c.before_step(world.step_count(), keys, &mut world);
        }
        world.step(scene.dt, scene.substeps);
        if let Some(c) = &mut controller {
            c.after_step(world.step_count() - 1, &mut world);
        }
        if let Some(file) = &mut events {
            file.write_new(&world, k)?;
        }
        let profile = world.profile();
        step_ms += profile.step_ms;
        let stages = profile.stages();
        if stage_ms.is_empty() {
            stage_ms = stages.iter().map(|&(name, _)| (name, 0.0)).collect();
        }
        for (sum, (_, ms)) in stage_ms.iter_mut().zip(stages.iter()) {
            sum.1 += ms;
        }
    }
    bar.finish_and_clear();
    if let Some(file) = events {
        file.finish()?;
    }
    let mean = |total: f64| {
        if steps == 0 {
            0.0
        } else {
            total / f64::from(steps)
        }
    };
    let mut profile = vec![("step_ms_mean".to_string(), mean(step_ms))];
    profile.extend(
        stage_ms
            .iter()
            .map(|&(name, total)| (format!("{name}_ms_mean"), mean(total))),
    );

    // The file names a body by its index in the scene, which is its id's index: a body a
    // script destroys is made again in its slot before the step (rain's waves), so every
    // index is live at the end. The position is the body frame's origin: for a body of one
    // shape its centre of mass, for a body of several where the scene placed its frame
    // (CONTRACT.md section 5).
    if let Some((k, id)) = world
        .body_ids()
        .enumerate()
        .find(|(k, id)| id.index as usize != *k)
    {
        anyhow::bail!(
            "scene {:?}: no body at index {k} at the end of the run ({id} follows)",
            scene.name
        );
    }
    let bodies = world
        .bodies()
        .map(|(_, b)| BodyState {
            position: [b.origin.x, b.origin.y],
            angle: b.angle,
            linear_velocity: [b.linear_velocity.x, b.linear_velocity.y],
            angular_velocity: b.angular_velocity,
            awake: b.awake,
        })
        .collect();
    let report = Report {
        scene: scene.name.clone(),
        steps,
        threads: world.thread_count(),
        dt: scene.dt,
        substeps: scene.substeps,
        time: f64::from(steps) * f64::from(scene.dt),
        state_hash: format!("{:016x}", world.state_hash()),
        bodies,
        profile: Profile(profile),
        contacts: world.contact_count(),
        non_finite_bodies: world.non_finite_bodies(),
        joints: world.joint_count(),
        awake_bodies: world.awake_body_count(),
        islands: {
            let (all, awake) = world.island_counts();
            [all, awake]
        },
        sample: controller,
    };
    write_report(&report, args.out.as_ref())
}

fn write_report(report: &Report, out: Option<&PathBuf>) -> Result<()> {
    match out {
        Some(path) => {
            let file = File::create(path)
                .with_context(|| format!("cannot create the output file {}", path.display()))?;
            write_json(file, report)
                .with_context(|| format!("cannot write the output file {}", path.display()))
        }
        None => write_json(std::io::stdout().lock(), report)
            .context("cannot write the report to stdout"),
    }
}

/// Pretty JSON, but one line per body: a report of 20 000 bodies stays readable and small.
fn write_json(w: impl Write, report: &Report) -> std::io::Result<()> {
    use serde_json::to_string as json;
    let mut w = BufWriter::new(w);
    writeln!(w, "{{")?;
    writeln!(w, "  \"scene\": {},", json(&report.scene)?)?;
    writeln!(w, "  \"steps\": {},", report.steps)?;
    writeln!(w, "  \"threads\": {},", report.threads)?;
    writeln!(w, "  \"dt\": {},", json(&report.dt)?)?;
    writeln!(w, "  \"substeps\": {},", report.substeps)?;
    writeln!(w, "  \"time\": {},", json(&report.time)?)?;
    writeln!(w, "  \"state_hash\": {},", json(&report.state_hash)?)?;
    write!(w, "  \"bodies\": [")?;
    for (i, body) in report.bodies.iter().enumerate() {
        let sep = if i == 0 { "" } else { "," };
        write!(w, "{sep}\n    {}", json(body)?)?;
    }
    let close = if report.bodies.is_empty() { "" } else { "\n  " };
    writeln!(w, "{close}],")?;
    write!(w, "  \"profile\": {{")?;
    for (i, (key, value)) in report.profile.0.iter().enumerate() {
        let sep = if i == 0 { "" } else { "," };
        write!(w, "{sep}\n    {}: {}", json(key)?, json(value)?)?;
    }
    writeln!(w, "\n  }},")?;
    writeln!(w, "  \"contacts\": {},", report.contacts)?;
    writeln!(w, "  \"non_finite_bodies\": {},", report.non_finite_bodies)?;
    writeln!(w, "  \"joints\": {},", report.joints)?;
    writeln!(w, "  \"awake_bodies\": {},", report.awake_bodies)?;
    match &report.sample {
        Some(sample) => {
            writeln!(w, "  \"islands\": {:?},", report.islands)?;
            writeln!(w, "  \"sample\": {}", json(sample)?)?;
        }
        None => writeln!(w, "  \"islands\": {:?}", report.islands)?,
    }
    writeln!(w, "}}")?;
    w.flush()
}

/// The `--events` file: each event as one JSON line (CONTRACT.md section 7), written as the
/// run makes them.
struct EventFile {
    path: PathBuf,
    out: BufWriter<File>,
    /// What of `World::events` is written.
    cursor: EventCursor,
}

/// One line of the event file; field order is the contract's: a shape event names
/// `bodies` and `shapes`, a joint's `joint`, `force` and `torque`.
#[derive(Serialize)]
struct EventLine {
    step: u64,
    #[serde(rename = "type")]
    kind: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    bodies: Option<[u32; 2]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    shapes: Option<[u32; 2]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    point: Option<[f32; 2]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    normal: Option<[f32; 2]>,
    #[serde(skip_serializing_if = "Option::is_none")]
    approach_speed: Option<f32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    joint: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    force: Option<f32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    torque: Option<f32>,
}

impl EventLine {
    fn of(step: u64, event: &Event) -> EventLine {
        let shapes = event.shapes();
        let (point, normal, approach_speed) = match *event {
            Event::Hit {
                point,
                normal,
                approach_speed,
                ..
            } => (
                Some(point.to_array()),
                Some(normal.to_array()),
                Some(approach_speed),
            ),
            _ => (None, None, None),
        };
        // A scene's joint is its index in `joints`: the id's index for the joints a scene
        // makes (in order, none destroyed before them).
        let (joint, force, torque) = match *event {
            Event::JointThreshold {
                joint,
                force,
                torque,
            } => (Some(joint.index), Some(force), Some(torque)),
            _ => (None, None, None),
        };
        EventLine {
            step,
            kind: event.name(),
            bodies: shapes.map(|[a, b]| [a.body.index, b.body.index]),
            shapes: shapes.map(|[a, b]| [a.part, b.part]),
            point,
            normal,
            approach_speed,
            joint,
            force,
            torque,
        }
    }
}

impl EventFile {
    fn create(path: &PathBuf) -> Result<EventFile> {
        let file = File::create(path)
            .with_context(|| format!("cannot create the events file {}", path.display()))?;
        Ok(EventFile {
            path: path.clone(),
            out: BufWriter::new(file),
            cursor: EventCursor::default(),
        })
    }

    /// Writes the world's events not yet written, as step `step`'s.
    fn write_new(&mut self, world: &World, step: u64) -> Result<()> {
        for event in self.cursor.take(world) {
            serde_json::to_writer(&mut self.out, &EventLine::of(step, event))
                .map_err(std::io::Error::from)
                .and_then(|()| self.out.write_all(b"\n"))
                .with_context(|| format!("cannot write the events file {}", self.path.display()))?;
        }
        Ok(())
    }

    fn finish(mut self) -> Result<()> {
        self.out
            .flush()
            .with_context(|| format!("cannot write the events file {}", self.path.display()))
    }
}
