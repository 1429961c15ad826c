//! The hard cases of the accuracy report: each a scene, a number of steps, and a probe that
//! computes the case's error metrics from the engine's state (poses and velocities only, so the
//! same code measures every engine), with each metric's definition and pass bound.

use std::f64::consts::PI;

use anyhow::{Context, Result};
use tumble_physics::{BodyDef, BodyKind, SceneDef, Shape, ShapeDef};
use tumble_scene::builtin;

use super::engines::Knobs;
use super::overlap::Geometry;
use crate::peers::Peer;
use crate::scenes;

/// One column of a case's table.
#[derive(Clone, Debug)]
pub struct MetricDef {
    /// Column header, with the unit.
    pub name: &'static str,
    /// CSV key.
    pub key: &'static str,
    /// The case passes only if |value| <= bound for every bounded metric.
    pub bound: Option<f64>,
    /// Drawn in the case's chart (one panel per plotted metric).
    pub plot: bool,
}

impl MetricDef {
    pub(super) fn new(name: &'static str, key: &'static str) -> MetricDef {
        MetricDef {
            name,
            key,
            bound: None,
            plot: false,
        }
    }
    pub(super) fn bound(mut self, bound: f64) -> MetricDef {
        self.bound = Some(bound);
        self
    }
    pub(super) fn plot(mut self) -> MetricDef {
        self.plot = true;
        self
    }
}

/// What a run measures: fed after every step (outside the clock), asked for the metrics at
/// the end.
pub trait Probe {
    /// After step `step` (1-based).
    fn after_step(&mut self, sim: &mut dyn Peer, step: u32) -> Result<()>;
    /// The case's metrics, in the order of its `metrics`.
    fn finish(&mut self, sim: &mut dyn Peer) -> Result<Vec<f64>>;
}

/// A case of the report.
pub struct Case {
    /// Short name, used for the chart's file name and the CSV.
    pub key: &'static str,
    /// Heading.
    pub title: String,
    /// The scene every engine builds.
    pub scene: SceneDef,
    /// Steps of each run.
    pub steps: u32,
    /// What the scene is and how long it runs (markdown).
    pub setup: String,
    /// How the metrics are computed (markdown).
    pub definition: String,
    /// The pass criterion and where it comes from (markdown).
    pub criterion: String,
    /// The columns.
    pub metrics: Vec<MetricDef>,
    /// Settings swept in this case beyond the common sweep (the knob that governs it).
    pub extras: Vec<Knobs>,
    /// A fresh probe for one run.
    pub probe: Box<dyn Fn() -> Box<dyn Probe>>,
}

impl Case {
    /// Whether a run's metrics meet every bound (a non-finite metric never does).
    pub fn passes(&self, values: &[f64]) -> bool {
        self.passes_except(values, usize::MAX)
    }

    /// Whether a run's metrics meet every bound but that of metric `skip`.
    pub fn passes_except(&self, values: &[f64], skip: usize) -> bool {
        self.metrics
            .iter()
            .zip(values)
            .enumerate()
            .all(|(k, (m, v))| match m.bound {
                Some(b) if k != skip => v.is_finite() && v.abs() <= b,
                _ => true,
            })
    }
}

fn builtin_scene(name: &str) -> Result<SceneDef> {
    scenes::resolve(name).with_context(|| format!("built-in scene {name}"))
}

/// All cases, in report order. `quick` shortens every run to a handful of steps (a smoke test:
/// its numbers mean nothing).
pub fn all(quick: bool) -> Result<Vec<Case>> {
    let mut cases = vec![
        vertical_stack()?,
        pyramid()?,
        large_pyramid()?,
        pyramid_200()?,
    ];
    for (k, ratio) in builtin::MASS_RATIOS.into_iter().enumerate() {
        cases.push(mass_ratio_column(k, ratio)?);
    }
    cases.push(friction_incline()?);
    cases.push(restitution_drop()?);
    cases.push(projectile());
    cases.push(elastic_box(false)?);
    cases.push(elastic_box(true)?);
    cases.push(overlap_recovery()?);
    cases.push(far_from_origin()?);
    cases.push(chain_slide());
    cases.push(capsules());
    cases.push(flat_landing());
    cases.extend(super::joint_cases::all());
    if quick {
        for c in &mut cases {
            c.steps = c.steps.min(10);
        }
    }
    Ok(cases)
}

/// How far an angle has turned from its start (rad, the shortest way round; a box that has
/// turned is what this catches, so there is no folding by its symmetry).
fn turn(angle: f32, start: f32) -> f64 {
    let d = f64::from(angle) - f64::from(start);
    ((d + PI).rem_euclid(2.0 * PI) - PI).abs()
}

fn finite(p: &[f32; 3]) -> bool {
    p.iter().all(|v| v.is_finite())
}

fn gravity(scene: &SceneDef) -> f64 {
    f64::from(scene.gravity[0]).hypot(f64::from(scene.gravity[1]))
}

fn seconds(scene: &SceneDef, steps: u32) -> f64 {
    f64::from(steps) * f64::from(scene.dt)
}

// ---------------------------------------------------------------------------------------------
// Stacks: top sag, drift, displacement, tilt and penetration

/// What a stack probe measured over one run.
#[derive(Clone, Copy, Debug, Default)]
struct StackStats {
    /// Largest |x - x0| of the top body over the run (m).
    top_drift: f64,
    /// y0 - y of the top body at the end (m; positive when it sank).
    top_sag: f64,
    /// Largest |p - p0| of any dynamic body at the end (m).
    disp_end: f64,
    /// Largest |x - x0| of any dynamic body at the end (m).
    horizontal_end: f64,
    /// Largest |angle - angle0| of any dynamic body at the end (rad).
    tilt_end: f64,
    /// Largest |p - p0| of any dynamic body at any step (m), when watched every step.
    disp_run: f64,
    /// Largest |x - x0| of any dynamic body at any step (m), when watched every step.
    horizontal_run: f64,
    /// Largest |angle - angle0| of any dynamic body at any step (rad), when watched every step.
    tilt_run: f64,
    /// Largest y - y0 of any dynamic body at any step (m), when watched every step.
    rise_run: f64,
    /// Deepest overlap between any two bodies at the end (m).
    penetration: f64,
}

/// Watches a set of bodies of a scene (statics included, for the overlap) and its top body.
struct StackProbe {
    /// Scene indices of the bodies, in the order `geometry` knows them.
    bodies: Vec<usize>,
    /// Start poses of `bodies`.
    start: Vec<[f32; 3]>,
    /// Which of `bodies` are dynamic.
    dynamic: Vec<bool>,
    /// Position of the top body in `bodies`.
    top: usize,
    geometry: std::rc::Rc<Geometry>,
    /// Read every body's pose every step (small scenes), not only the top body's.
    every_step: bool,
    stats: StackStats,
    finite: bool,
}

/// A stack-like subset of a scene: the bodies and the shared geometry of that subset.
#[derive(Clone)]
struct Stack {
    bodies: Vec<usize>,
    start: Vec<[f32; 3]>,
    dynamic: Vec<bool>,
    top: usize,
    geometry: std::rc::Rc<Geometry>,
}

impl Stack {
    /// `bodies` of `scene`; the top body is the dynamic one that starts highest (the last
    /// such in scene order).
    fn new(scene: &SceneDef, bodies: Vec<usize>) -> Stack {
        let sub = SceneDef {
            bodies: bodies.iter().map(|&i| scene.bodies[i].clone()).collect(),
            ..scene.clone()
        };
        let start: Vec<[f32; 3]> = sub
            .bodies
            .iter()
            .map(|b| [b.position[0], b.position[1], b.angle])
            .collect();
        let dynamic: Vec<bool> = sub
            .bodies
            .iter()
            .map(|b| b.kind == BodyKind::Dynamic)
            .collect();
        let top = (0..sub.bodies.len())
            .filter(|&i| dynamic[i])
            .fold(None, |best: Option<usize>, i| match best {
                Some(b) if start[b][1] > start[i][1] => Some(b),
                _ => Some(i),
            })
            .expect("a stack has a dynamic body");
        Stack {
            geometry: std::rc::Rc::new(Geometry::new(&sub)),
            bodies,
            start,
            dynamic,
            top,
        }
    }

    fn whole(scene: &SceneDef) -> Stack {
        Stack::new(scene, (0..scene.bodies.len()).collect())
    }

    fn probe(&self, every_step: bool) -> StackProbe {
        StackProbe {
            bodies: self.bodies.clone(),
            start: self.start.clone(),
            dynamic: self.dynamic.clone(),
            top: self.top,
            geometry: self.geometry.clone(),
            every_step,
            stats: StackStats::default(),
            finite: true,
        }
    }
}

impl StackProbe {
    fn displacement(&self, k: usize, p: &[f32; 3]) -> f64 {
        let s = self.start[k];
        (f64::from(p[0]) - f64::from(s[0])).hypot(f64::from(p[1]) - f64::from(s[1]))
    }

    fn observe(&mut self, sim: &mut dyn Peer) -> Result<()> {
        let top = sim.pose(self.bodies[self.top])?;
        self.finite &= finite(&top);
        let drift = (f64::from(top[0]) - f64::from(self.start[self.top][0])).abs();
        self.stats.top_drift = self.stats.top_drift.max(drift);
        if self.every_step {
            for k in 0..self.bodies.len() {
                if self.dynamic[k] {
                    let p = sim.pose(self.bodies[k])?;
                    self.finite &= finite(&p);
                    let s = self.start[k];
                    let disp = self.displacement(k, &p);
                    let st = &mut self.stats;
                    st.disp_run = st.disp_run.max(disp);
                    st.horizontal_run = st
                        .horizontal_run
                        .max((f64::from(p[0]) - f64::from(s[0])).abs());
                    st.tilt_run = st.tilt_run.max(turn(p[2], s[2]));
                    st.rise_run = st.rise_run.max(f64::from(p[1]) - f64::from(s[1]));
                }
            }
        }
        Ok(())
    }

    fn end(&mut self, sim: &mut dyn Peer) -> Result<StackStats> {
        self.observe(sim)?;
        let mut poses = Vec::with_capacity(self.bodies.len());
        for &i in &self.bodies {
            poses.push(sim.pose(i)?);
        }
        let s = &mut self.stats;
        let top = poses[self.top];
        s.top_sag = f64::from(self.start[self.top][1]) - f64::from(top[1]);
        for (k, p) in poses.iter().enumerate() {
            if !self.dynamic[k] {
                continue;
            }
            self.finite &= finite(p);
            let st = self.start[k];
            let dx = f64::from(p[0]) - f64::from(st[0]);
            let dy = f64::from(p[1]) - f64::from(st[1]);
            s.disp_end = s.disp_end.max(dx.hypot(dy));
            s.horizontal_end = s.horizontal_end.max(dx.abs());
            s.tilt_end = s.tilt_end.max(turn(p[2], st[2]));
        }
        s.disp_run = s.disp_run.max(s.disp_end);
        s.horizontal_run = s.horizontal_run.max(s.horizontal_end);
        s.tilt_run = s.tilt_run.max(s.tilt_end);
        s.penetration = self.geometry.deepest_overlap(&poses);
        let mut out = *s;
        if !self.finite {
            out = StackStats {
                top_drift: f64::NAN,
                top_sag: f64::NAN,
                disp_end: f64::NAN,
                horizontal_end: f64::NAN,
                tilt_end: f64::NAN,
                disp_run: f64::NAN,
                horizontal_run: f64::NAN,
                tilt_run: f64::NAN,
                rise_run: f64::NAN,
                penetration: f64::NAN,
            };
        }
        Ok(out)
    }
}

/// A probe over stacks that maps their stats to the case's metrics.
struct Stacks {
    probes: Vec<StackProbe>,
    select: fn(&[StackStats]) -> Vec<f64>,
}

impl Probe for Stacks {
    fn after_step(&mut self, sim: &mut dyn Peer, _step: u32) -> Result<()> {
        for p in &mut self.probes {
            p.observe(sim)?;
        }
        Ok(())
    }
    fn finish(&mut self, sim: &mut dyn Peer) -> Result<Vec<f64>> {
        let mut stats = Vec::new();
        for p in &mut self.probes {
            stats.push(p.end(sim)?);
        }
        Ok((self.select)(&stats))
    }
}

fn stacks_probe(
    stacks: Vec<Stack>,
    every_step: bool,
    select: fn(&[StackStats]) -> Vec<f64>,
) -> Box<dyn Fn() -> Box<dyn Probe>> {
    Box::new(move || {
        Box::new(Stacks {
            probes: stacks.iter().map(|s| s.probe(every_step)).collect(),
            select,
        })
    })
}

const PENETRATION_TEXT: &str = "**penetration**: the deepest overlap between any two bodies \
    at the end, from the poses alone: every pair whose bounding boxes overlap goes through \
    tumble's narrow phase (Box2D v3's manifold routines) and the most negative point separation \
    counts. The same code measures all three engines (their own contact data differ in when \
    they are taken).";

fn vertical_stack() -> Result<Case> {
    let scene = builtin_scene("vertical_stack")?;
    let stack = Stack::whole(&scene);
    Ok(Case {
        key: "vertical_stack",
        title: "Vertical stack of 15 boxes".into(),
        steps: 600,
        setup:
            "Built-in `vertical_stack`: 15 unit boxes (friction 0.3) in a column, x alternating \
                ±1 cm, next to a wall (Box2D's Vertical Stack). 600 steps (10 s)."
                .into(),
        definition: format!(
            "**drift**: the largest |x − x₀| of the top box over the run. **sag**: y₀ − y of the \
             top box at the end (how far the column has compressed). **max displacement**: the \
             largest |p − p₀| of any box at the end. {PENETRATION_TEXT}"
        ),
        criterion: "drift < 0.1 m (the issue) and |sag| < 0.1 m, the bounds of \
                    `tests/tests/stability.rs`, which asserts them at the defaults (there on \
                    the worst height change over the run; here on the final one)."
            .into(),
        metrics: vec![
            MetricDef::new("drift (m)", "drift_m").bound(0.1).plot(),
            MetricDef::new("sag (m)", "sag_m").bound(0.1).plot(),
            MetricDef::new("max displacement (m)", "max_displacement_m"),
            MetricDef::new("penetration (m)", "penetration_m"),
        ],
        extras: Vec::new(),
        probe: stacks_probe(vec![stack], false, |s| {
            vec![
                s[0].top_drift,
                s[0].top_sag,
                s[0].disp_end,
                s[0].penetration,
            ]
        }),
        scene,
    })
}

fn pyramid() -> Result<Case> {
    let scene = builtin_scene("pyramid")?;
    let stack = Stack::whole(&scene);
    Ok(Case {
        key: "pyramid",
        title: "Pyramid of 20 rows".into(),
        steps: 600,
        setup: "Built-in `pyramid`: 20 rows, 210 unit boxes, friction 0.6 (Solver2D's Pyramid). \
                600 steps (10 s)."
            .into(),
        definition: format!(
            "**max displacement**: the largest |p − p₀| of any box at the end. **sag** and \
             **drift** of the top box as for the vertical stack. {PENETRATION_TEXT}"
        ),
        criterion: "every box within 0.1 m of its start (the issue; asserted at the defaults by \
                    `tests/tests/stability.rs`)."
            .into(),
        metrics: vec![
            MetricDef::new("max displacement (m)", "max_displacement_m")
                .bound(0.1)
                .plot(),
            MetricDef::new("top sag (m)", "sag_m"),
            MetricDef::new("top drift (m)", "drift_m"),
            MetricDef::new("penetration (m)", "penetration_m").plot(),
        ],
        extras: Vec::new(),
        probe: stacks_probe(vec![stack], false, |s| {
            vec![
                s[0].disp_end,
                s[0].top_sag,
                s[0].top_drift,
                s[0].penetration,
            ]
        }),
        scene,
    })
}

fn large_pyramid() -> Result<Case> {
    let scene = builtin_scene("large_pyramid")?;
    let stack = Stack::whole(&scene);
    Ok(Case {
        key: "large_pyramid",
        title: "Large pyramid of 100 rows".into(),
        steps: 500,
        setup: "Built-in `large_pyramid`: 100 rows, 5050 unit boxes (Box2D's benchmark). 500 \
                steps (8.3 s), Box2D's benchmark length."
            .into(),
        definition: format!(
            "**sag**: y₀ − y of the top box at the end. **drift**: its largest |x − x₀| over the \
             run. **max displacement**: the largest |p − p₀| of any box at the end. \
             {PENETRATION_TEXT}"
        ),
        criterion: "top sag < 0.1 m and penetration < 0.02 m (the issue).".into(),
        metrics: vec![
            MetricDef::new("top sag (m)", "sag_m").bound(0.1).plot(),
            MetricDef::new("penetration (m)", "penetration_m")
                .bound(0.02)
                .plot(),
            MetricDef::new("top drift (m)", "drift_m"),
            MetricDef::new("max displacement (m)", "max_displacement_m"),
        ],
        extras: Vec::new(),
        probe: stacks_probe(vec![stack], false, |s| {
            vec![
                s[0].top_sag,
                s[0].penetration,
                s[0].top_drift,
                s[0].disp_end,
            ]
        }),
        scene,
    })
}

/// Largest horizontal displacement of any box for the 200-row pyramid to count as standing.
pub const STANDS_HORIZONTAL: f64 = 0.5;
/// Largest turn of any box for the 200-row pyramid to count as standing (rad).
pub const STANDS_TILT: f64 = 0.1;

fn pyramid_200() -> Result<Case> {
    let scene = builtin_scene("pyramid_200")?;
    let stack = Stack::whole(&scene);
    Ok(Case {
        key: "pyramid_200",
        title: "Pyramid of 200 rows".into(),
        steps: 300,
        setup: "Built-in `pyramid_200`: 200 rows, 20100 unit boxes, friction 0.6, on a static \
                ground. 300 steps (5 s): shortened from the scene's 500, because a collapse \
                shows within 100 steps (several metres sideways at 1 and 2 substeps) and a \
                standing pyramid has settled by step 150 (at 16 substeps and 120 Hz its sag at \
                150, 300 and 500 steps agrees within 3 mm). The scene's own `solver` block asks \
                for 60 Hz contacts at 8 substeps: that is the `8 sub, 60 Hz` row; every row \
                sets its knobs explicitly."
            .into(),
        definition: format!(
            "**horizontal displacement**: the largest |x − x₀| of any box at the end. **tilt**: \
             the largest |angle − angle₀| of any box at the end. **top sag**: y₀ − y of the top \
             box at the end. {PENETRATION_TEXT}"
        ),
        criterion: format!(
            "*stands*: no box has moved sideways by more than {STANDS_HORIZONTAL} m (half a box) \
             and none has turned by more than {STANDS_TILT} rad (5.7°). A pyramid that slumps \
             spreads at its base and its flanks slide out, sideways, by more than half a box; a \
             box that tips turns. Uniform compression (sag) is not collapse and is reported, not \
             bounded."
        ),
        metrics: vec![
            MetricDef::new("horizontal displacement (m)", "horizontal_m")
                .bound(STANDS_HORIZONTAL)
                .plot(),
            MetricDef::new("tilt (rad)", "tilt_rad").bound(STANDS_TILT),
            MetricDef::new("top sag (m)", "sag_m").plot(),
            MetricDef::new("penetration (m)", "penetration_m"),
        ],
        extras: Vec::new(),
        probe: stacks_probe(vec![stack], false, |s| {
            vec![
                s[0].horizontal_end,
                s[0].tilt_end,
                s[0].top_sag,
                s[0].penetration,
            ]
        }),
        scene,
    })
}

/// Bound on a mass-ratio column's boxes for it to count as stable: sideways move, rise and
/// final overlap (m), turn (rad); a tenth of a box.
pub const COLUMN_STABLE: f64 = 0.1;

fn mass_ratio_column(column: usize, ratio: f32) -> Result<Case> {
    let all = builtin_scene("mass_ratio_columns")?;
    let per = builtin::MASS_RATIO_LIGHT_BOXES + 1;
    // The ground and this column only: the columns do not interact, and each case times its
    // own column.
    let mut scene = SceneDef {
        bodies: vec![all.bodies[0].clone()],
        ..all.clone()
    };
    scene.name = format!("mass_ratio_column_{ratio}");
    for k in 0..per {
        scene.push(all.bodies[1 + column * per + k].clone());
    }
    let stack = Stack::whole(&scene);
    let key = match column {
        0 => "mass_ratio_10",
        1 => "mass_ratio_100",
        _ => "mass_ratio_1000",
    };
    Ok(Case {
        key,
        title: format!("Mass-ratio column 1:{ratio}"),
        steps: 600,
        setup: format!(
            "One column of built-in `mass_ratio_columns`: three light unit boxes (density 1) on a \
             static ground carrying a unit box of density {ratio}, all starting exactly touching, \
             friction 0.6. 600 steps (10 s)."
        ),
        definition: format!(
            "Every box's pose is read after every step. **sideways**: the largest |x − x₀| of \
             any box at any step; **tilt**: the largest turn of any box at any step; **rise**: \
             the largest y − y₀ of any box at any step (thrown up). **heavy sag**: y₀ − y of \
             the heavy box at the end: how far the light boxes under it are crushed into each \
             other. {PENETRATION_TEXT}"
        ),
        criterion: format!(
            "*stable*: no box moved sideways, or rose, by more than {COLUMN_STABLE} m, none \
             turned by more than {COLUMN_STABLE} rad, at any step, and no two boxes overlap by \
             more than {COLUMN_STABLE} m at the end: the column neither topples, nor is thrown, \
             nor explodes, nor lets the heavy box sink into the light one (a tenth of a box, \
             the bound of the pyramid). Sinking is the soft contacts' compression: the \
             steady-state overlap of a contact is about F / (m ω²), F the load, m the light \
             box's share of the effective mass and ω = 2π × the contact hertz, so it grows with \
             the mass ratio and falls with the square of the hertz; substeps alone do not \
             change it."
        ),
        metrics: vec![
            MetricDef::new("sideways (m)", "sideways_m")
                .bound(COLUMN_STABLE)
                .plot(),
            MetricDef::new("tilt (rad)", "tilt_rad").bound(COLUMN_STABLE),
            MetricDef::new("rise (m)", "rise_m").bound(COLUMN_STABLE),
            MetricDef::new("heavy sag (m)", "sag_m"),
            MetricDef::new("penetration (m)", "penetration_m")
                .bound(COLUMN_STABLE)
                .plot(),
        ],
        extras: Vec::new(),
        probe: stacks_probe(vec![stack], true, |s| {
            vec![
                s[0].horizontal_run,
                s[0].tilt_run,
                s[0].rise_run,
                s[0].top_sag,
                s[0].penetration,
            ]
        }),
        scene,
    })
}

// ---------------------------------------------------------------------------------------------
// Friction, restitution, projectile, energy

/// Bound on the creep of the box that should stick (m): one linear slop, as in
/// `tests/tests/closed_form.rs`.
pub const STICK_CREEP: f64 = 0.005;

/// Closed-form slide distance (m) of a box released at rest on a slope of `theta` with
/// friction `mu` after `t` seconds: ½ g (sin θ − μ cos θ) t², or 0 when μ ≥ tan θ.
pub fn slide_distance(g: f64, theta: f64, mu: f64, t: f64) -> f64 {
    let a = g * (theta.sin() - mu * theta.cos());
    if a > 0.0 { 0.5 * a * t * t } else { 0.0 }
}

struct InclineProbe {
    boxes: Vec<usize>,
    start: Vec<[f32; 3]>,
    expected: Vec<f64>,
    downhill: [f64; 2],
}

impl Probe for InclineProbe {
    fn after_step(&mut self, _sim: &mut dyn Peer, _step: u32) -> Result<()> {
        Ok(())
    }
    fn finish(&mut self, sim: &mut dyn Peer) -> Result<Vec<f64>> {
        let mut slides = Vec::new();
        for (k, &i) in self.boxes.iter().enumerate() {
            let p = sim.pose(i)?;
            let s = self.start[k];
            let d = [
                f64::from(p[0]) - f64::from(s[0]),
                f64::from(p[1]) - f64::from(s[1]),
            ];
            slides.push(d[0] * self.downhill[0] + d[1] * self.downhill[1]);
        }
        let mut worst_rel = 0.0_f64;
        let mut creep = 0.0_f64;
        for (s, e) in slides.iter().zip(&self.expected) {
            if !s.is_finite() {
                worst_rel = f64::NAN;
                creep = f64::NAN;
            } else if *e > 0.0 {
                worst_rel = worst_rel.max((s - e).abs() / e);
            } else {
                creep = creep.max(s.abs());
            }
        }
        let mut out = vec![worst_rel, creep];
        out.extend(slides);
        Ok(out)
    }
}

fn friction_incline() -> Result<Case> {
    let scene = builtin_scene("friction_incline")?;
    let steps = 180;
    let theta = f64::from(builtin::INCLINE_DEGREES).to_radians();
    let g = gravity(&scene);
    let t = seconds(&scene, steps);
    let boxes: Vec<usize> = (0..scene.bodies.len())
        .filter(|&i| scene.bodies[i].kind == BodyKind::Dynamic)
        .collect();
    let mus: Vec<f64> = boxes
        .iter()
        .map(|&i| f64::from(scene.bodies[i].friction))
        .collect();
    let expected: Vec<f64> = mus
        .iter()
        .map(|&mu| slide_distance(g, theta, mu, t))
        .collect();
    let start: Vec<[f32; 3]> = boxes
        .iter()
        .map(|&i| {
            let b = &scene.bodies[i];
            [b.position[0], b.position[1], b.angle]
        })
        .collect();
    let downhill = [-theta.cos(), -theta.sin()];
    let closed: Vec<String> = mus
        .iter()
        .zip(&expected)
        .map(|(mu, s)| format!("μ = {mu:.2}: s = {s:.4} m"))
        .collect();
    let probe = {
        let (boxes, start, expected) = (boxes.clone(), start.clone(), expected.clone());
        Box::new(move || {
            Box::new(InclineProbe {
                boxes: boxes.clone(),
                start: start.clone(),
                expected: expected.clone(),
                downhill,
            }) as Box<dyn Probe>
        })
    };
    Ok(Case {
        key: "friction_incline",
        title: "Friction ramp".into(),
        steps,
        setup: format!(
            "Built-in `friction_incline`: three unit boxes resting on 20° static slopes, box and \
             slope of friction 0.30, 0.35 and 0.40 (tan 20° = 0.364), released at rest. {steps} \
             steps ({t:.0} s)."
        ),
        definition: format!(
            "**slide** s: the displacement of each box's centre along the slope, downhill, at \
             t = {t:.0} s. Closed form: s = ½·g·(sin θ − μ cos θ)·t² when μ < tan θ, else 0 \
             ({}). **relative error**: the largest |s − s*| / s* over the boxes that slide. \
             **creep**: |s| of the box that should stick.",
            closed.join("; ")
        ),
        criterion: format!(
            "relative error ≤ 10% (the issue) and creep < {STICK_CREEP} m (one linear slop; \
             \"within 10% of 0\" needs an absolute bound)."
        ),
        metrics: vec![
            MetricDef::new("relative error", "relative_error")
                .bound(0.1)
                .plot(),
            MetricDef::new("creep μ=0.40 (m)", "creep_m")
                .bound(STICK_CREEP)
                .plot(),
            MetricDef::new("s μ=0.30 (m)", "slide_030_m"),
            MetricDef::new("s μ=0.35 (m)", "slide_035_m"),
            MetricDef::new("s μ=0.40 (m)", "slide_040_m"),
        ],
        extras: Vec::new(),
        probe,
        scene,
    })
}

/// One ball of the restitution case: falling, rising after the first bounce, then done.
#[derive(Clone, Copy)]
struct Ball {
    index: usize,
    radius: f64,
    rising: bool,
    done: bool,
    apex: f64,
}

struct DropProbe {
    balls: Vec<Ball>,
    ground_top: f64,
    expected: Vec<f64>,
}

impl Probe for DropProbe {
    fn after_step(&mut self, sim: &mut dyn Peer, _step: u32) -> Result<()> {
        for b in &mut self.balls {
            if b.done {
                continue;
            }
            let v = sim.velocity(b.index)?;
            let p = sim.pose(b.index)?;
            // Only a contact turns the fall upward: the first upward velocity is the bounce;
            // the first step that no longer rises after it ends the first rebound.
            if v[1] > 0.0 {
                b.rising = true;
            }
            if b.rising {
                b.apex = b.apex.max(f64::from(p[1]) - b.radius - self.ground_top);
                if v[1] <= 0.0 {
                    b.done = true;
                }
            }
        }
        Ok(())
    }
    fn finish(&mut self, _sim: &mut dyn Peer) -> Result<Vec<f64>> {
        let mut worst = 0.0_f64;
        let mut apexes = Vec::new();
        for (b, e) in self.balls.iter().zip(&self.expected) {
            let apex = if b.rising { b.apex } else { f64::NAN };
            worst = if apex.is_finite() {
                worst.max((apex - e).abs() / e)
            } else {
                f64::NAN
            };
            apexes.push(apex);
        }
        let mut out = vec![worst];
        out.extend(apexes);
        Ok(out)
    }
}

fn restitution_drop() -> Result<Case> {
    let scene = builtin_scene("restitution_drop")?;
    let steps = 180;
    let h = f64::from(builtin::DROP_HEIGHT);
    let ground = &scene.bodies[0];
    let Some(ShapeDef::Box { half_extents, .. }) = ground.shape else {
        anyhow::bail!("restitution_drop: the ground is not a box");
    };
    let ground_top = f64::from(ground.position[1]) + f64::from(half_extents[1]);
    let mut balls = Vec::new();
    let mut expected = Vec::new();
    for (i, b) in scene.bodies.iter().enumerate().skip(1) {
        let Some(ShapeDef::Circle { radius }) = b.shape else {
            anyhow::bail!("restitution_drop: body {i} is not a ball");
        };
        balls.push(Ball {
            index: i,
            radius: f64::from(radius),
            rising: false,
            done: false,
            apex: f64::NEG_INFINITY,
        });
        let e = f64::from(b.restitution);
        expected.push(e * e * h);
    }
    let probe = {
        let expected = expected.clone();
        Box::new(move || {
            Box::new(DropProbe {
                balls: balls.clone(),
                ground_top,
                expected: expected.clone(),
            }) as Box<dyn Probe>
        })
    };
    Ok(Case {
        key: "restitution_drop",
        title: "Restitution".into(),
        steps,
        setup: format!(
            "Built-in `restitution_drop`: frictionless balls (radius 0.5 m) of restitution 0.25, \
             0.5 and 0.75 dropped from rest with their bottoms {h} m above a static ground of \
             restitution 0 (pairs mix as max). {steps} steps (3 s)."
        ),
        definition: format!(
            "**apex**: the highest the ball's bottom gets above the ground between the first \
             bounce (its first upward velocity) and the first step after it that no longer \
             rises, sampled at step ends. Closed form: e²·h = {}. **relative error**: the \
             largest |apex − e²h| / e²h of the three.",
            expected
                .iter()
                .map(|x| format!("{x:.4} m"))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        criterion: "relative error ≤ 10% (the bound of `tests/tests/closed_form.rs`).".into(),
        metrics: vec![
            MetricDef::new("relative error", "relative_error")
                .bound(0.1)
                .plot(),
            MetricDef::new("apex e=0.25 (m)", "apex_025_m"),
            MetricDef::new("apex e=0.5 (m)", "apex_050_m"),
            MetricDef::new("apex e=0.75 (m)", "apex_075_m"),
        ],
        extras: Vec::new(),
        probe,
        scene,
    })
}

/// Launch velocity of the projectile (m/s).
const LAUNCH: [f64; 2] = [5.0, 10.0];

struct ProjectileProbe {
    start: [f64; 2],
    g: [f64; 2],
    t: f64,
}

impl Probe for ProjectileProbe {
    fn after_step(&mut self, _sim: &mut dyn Peer, _step: u32) -> Result<()> {
        Ok(())
    }
    fn finish(&mut self, sim: &mut dyn Peer) -> Result<Vec<f64>> {
        let p = sim.pose(0)?;
        let t = self.t;
        let x = self.start[0] + LAUNCH[0] * t + 0.5 * self.g[0] * t * t;
        let y = self.start[1] + LAUNCH[1] * t + 0.5 * self.g[1] * t * t;
        let error = (f64::from(p[0]) - x).hypot(f64::from(p[1]) - y);
        let range = (x - self.start[0]).hypot(y - self.start[1]);
        Ok(vec![error, error / range])
    }
}

fn projectile() -> Case {
    let mut scene = SceneDef::new("projectile");
    scene.push(
        BodyDef::new(ShapeDef::Circle { radius: 0.25 })
            .velocity(LAUNCH[0] as f32, LAUNCH[1] as f32),
    );
    let steps = 120;
    let t = seconds(&scene, steps);
    let g = [f64::from(scene.gravity[0]), f64::from(scene.gravity[1])];
    Case {
        key: "projectile",
        title: "Projectile".into(),
        steps,
        setup: format!(
            "A ball launched from the origin at ({}, {}) m/s under g = 10 m/s², touching \
             nothing. {steps} steps ({t:.0} s): up to the apex and back to the launch height, \
             10 m downrange.",
            LAUNCH[0], LAUNCH[1]
        ),
        definition: "**position error**: |p − p*| at the end, against the parabola p* = p₀ + \
                     v₀t + ½gt². Every engine integrates with symplectic Euler per substep, which \
                     lags the parabola by g·h·t/2 (h the substep): 4.2 cm at 4 substeps. \
                     **relative**: the error over the distance from the launch point."
            .into(),
        criterion: "position error < 1% of the 10 m range, 0.1 m: the ball lands within a \
                    hundredth of where it should."
            .into(),
        metrics: vec![
            MetricDef::new("position error (m)", "position_error_m")
                .bound(0.1)
                .plot(),
            MetricDef::new("relative", "relative_error"),
        ],
        extras: Vec::new(),
        probe: Box::new(move || {
            Box::new(ProjectileProbe {
                start: [0.0, 0.0],
                g,
                t,
            })
        }),
        scene,
    }
}

// ---------------------------------------------------------------------------------------------
// Chains and capsules

/// Speed of the box sliding along the chain (m/s).
const SLIDE_SPEED: f32 = 5.0;

/// Watches body `index` every step for its largest departure from uniform level motion at
/// `speed` along x.
struct SlideProbe {
    index: usize,
    speed: f64,
    speed_error: f64,
    tilt: f64,
    vertical: f64,
}

impl Probe for SlideProbe {
    fn after_step(&mut self, sim: &mut dyn Peer, _step: u32) -> Result<()> {
        let p = sim.pose(self.index)?;
        let v = sim.velocity(self.index)?;
        let worse = |now: f64, worst: f64| {
            if now.is_finite() && worst.is_finite() {
                worst.max(now)
            } else {
                f64::NAN
            }
        };
        self.speed_error = worse((f64::from(v[0]) - self.speed).abs(), self.speed_error);
        self.tilt = worse(f64::from(p[2]).abs(), self.tilt);
        self.vertical = worse(f64::from(v[1]).abs(), self.vertical);
        Ok(())
    }
    fn finish(&mut self, _sim: &mut dyn Peer) -> Result<Vec<f64>> {
        Ok(vec![self.speed_error, self.tilt, self.vertical])
    }
}

/// A frictionless unit box sliding at 5 m/s along a flat chain of 1000 segments 0.1 m long.
fn chain_slide() -> Case {
    let mut scene = SceneDef::new("chain_slide");
    // Right to left, so the chain pushes up; one ghost point beyond each end.
    let mut points = vec![[50.1f32, 0.0]];
    points.extend((0..=1000).map(|i| [50.0 - 0.1 * i as f32, 0.0]));
    points.push([-50.1, 0.0]);
    let mut ground = BodyDef::compound(vec![tumble_physics::PartDef::new(ShapeDef::Chain {
        points,
        looped: false,
    })])
    .kind(BodyKind::Static);
    ground.friction = 0.0;
    scene.push(ground);
    let mut bx = BodyDef::new(ShapeDef::Box {
        half_extents: [0.5, 0.5],
        radius: 0.0,
    })
    .at(-40.0, 0.5)
    .velocity(SLIDE_SPEED, 0.0);
    bx.friction = 0.0;
    scene.push(bx);
    let steps = 300;
    Case {
        key: "chain_slide",
        title: "A box sliding along a chain".into(),
        steps,
        setup: format!(
            "A frictionless unit box sliding at {SLIDE_SPEED} m/s along flat ground made of one \
             chain of 1000 segments 0.1 m long (Box2D's chain with ghost vertices; Rapier's \
             oriented polyline, one-sided with pseudo-normals at its vertices). {steps} steps (5 \
             s): 25 m, across 250 joints between segments."
        ),
        definition: "Closed form: uniform, level motion at 5 m/s (no friction, a flat floor). \
                     Watched every step: **speed error**, the largest |vx − 5|; **tilt**, the \
                     largest |angle|; **vertical speed**, the largest |vy|. A joint the box \
                     catches on (a ghost collision) shows in all three."
            .into(),
        criterion: "speed error ≤ 0.05 m/s (1%) and tilt ≤ 0.01 rad: the joints are not felt. \
                    (Separate two-sided segments fail this in tumble: the box trips over the first \
                    joint, `tests/tests/shapes.rs`.)"
            .into(),
        metrics: vec![
            MetricDef::new("speed error (m/s)", "speed_error_mps")
                .bound(0.05)
                .plot(),
            MetricDef::new("tilt (rad)", "tilt_rad").bound(0.01).plot(),
            MetricDef::new("vertical speed (m/s)", "vertical_speed_mps"),
        ],
        extras: Vec::new(),
        probe: Box::new(|| {
            Box::new(SlideProbe {
                index: 1,
                speed: f64::from(SLIDE_SPEED),
                speed_error: 0.0,
                tilt: 0.0,
                vertical: 0.0,
            })
        }),
        scene,
    }
}

/// Capsules: one resting on the ground, two meeting head on.
struct CapsuleProbe {
    radius: f64,
    /// (index, velocity it should leave with) of the two colliding capsules.
    exchange: [(usize, f64); 2],
    closing: f64,
}

impl Probe for CapsuleProbe {
    fn after_step(&mut self, _sim: &mut dyn Peer, _step: u32) -> Result<()> {
        Ok(())
    }
    fn finish(&mut self, sim: &mut dyn Peer) -> Result<Vec<f64>> {
        let rest = f64::from(sim.pose(1)?[1]) - self.radius;
        let mut error = 0.0f64;
        let mut out = Vec::new();
        for (index, want) in self.exchange {
            let v = f64::from(sim.velocity(index)?[0]);
            error = error.max((v - want).abs());
            out.push(v);
        }
        Ok(vec![rest, error / self.closing, out[0], out[1]])
    }
}

/// Drop height of the flat-landing case: the bodies' bottoms above the ground (m).
const FLAT_DROP: f32 = 3.0;

/// A box, a capsule lying down and a rounded box dropped flat onto flat ground (issue 36).
fn flat_landing() -> Case {
    let mut scene = SceneDef::new("flat_landing");
    scene.push(
        BodyDef::new(ShapeDef::Box {
            half_extents: [40.0, 0.5],
            radius: 0.0,
        })
        .kind(BodyKind::Static)
        .at(0.0, -0.5),
    );
    // (shape, half height), 15 m apart.
    let shapes = [
        (
            ShapeDef::Box {
                half_extents: [1.0, 1.0],
                radius: 0.0,
            },
            1.0,
        ),
        (
            ShapeDef::Capsule {
                center1: [-0.75, 0.0],
                center2: [0.75, 0.0],
                radius: 0.25,
            },
            0.25,
        ),
        (
            ShapeDef::Box {
                half_extents: [0.9, 0.9],
                radius: 0.1,
            },
            1.0,
        ),
    ];
    let mut starts = Vec::new();
    for (k, (shape, half_height)) in shapes.into_iter().enumerate() {
        let x = -15.0 + 15.0 * k as f32;
        scene.push(
            BodyDef::new(shape)
                .at(x, FLAT_DROP + half_height)
                .friction(0.6),
        );
        starts.push((k + 1, f64::from(x)));
    }
    let steps = 400;
    Case {
        key: "flat_landing",
        title: "Flat landing".into(),
        steps,
        setup: format!(
            "A 2 × 2 m box, a capsule lying down (core 1.5 m, radius 0.25 m) and a 1.8 m box \
             rounded by 0.1 m, density 1, friction 0.6, dropped flat from rest with their \
             bottoms {FLAT_DROP} m above a flat static ground, 15 m apart. {steps} steps (6.7 s). \
             A symmetric impact should give a symmetric response: no sideways motion, no turn \
             (docs/accuracy/flat_landing.md)."
        ),
        definition: "**sideways**: the largest |vx| of any of the three at any step. **spin**: \
                     the largest |ω|. **offset**: the largest |x − x₀| at the end. **angle**: the \
                     largest turn at the end."
            .into(),
        criterion: "sideways ≤ 0.05 m/s, offset ≤ 0.01 m and angle ≤ 0.01 rad (issue 36's \
                    bounds, which `tests/tests/landing.rs` asserts at 1, 3, 10 and 20 m)."
            .into(),
        metrics: vec![
            MetricDef::new("sideways (m/s)", "sideways_mps")
                .bound(0.05)
                .plot(),
            MetricDef::new("spin (rad/s)", "spin_radps"),
            MetricDef::new("offset (m)", "offset_m").bound(0.01).plot(),
            MetricDef::new("angle (rad)", "angle_rad").bound(0.01),
        ],
        extras: vec![Knobs {
            together: false,
            ..Knobs::DEFAULT
        }],
        probe: Box::new(move || {
            Box::new(LandingProbe {
                starts: starts.clone(),
                sideways: 0.0,
                spin: 0.0,
            })
        }),
        scene,
    }
}

struct LandingProbe {
    /// Each dropped body's index and starting x.
    starts: Vec<(usize, f64)>,
    sideways: f64,
    spin: f64,
}

impl Probe for LandingProbe {
    fn after_step(&mut self, sim: &mut dyn Peer, _step: u32) -> Result<()> {
        for &(i, _) in &self.starts {
            let v = sim.velocity(i)?;
            self.sideways = self.sideways.max(f64::from(v[0]).abs());
            self.spin = self.spin.max(f64::from(v[2]).abs());
        }
        Ok(())
    }
    fn finish(&mut self, sim: &mut dyn Peer) -> Result<Vec<f64>> {
        let (mut offset, mut angle) = (0.0f64, 0.0f64);
        for &(i, x0) in &self.starts {
            let p = sim.pose(i)?;
            if !finite(&p) {
                return Ok(vec![f64::NAN; 4]);
            }
            offset = offset.max((f64::from(p[0]) - x0).abs());
            angle = angle.max(turn(p[2], 0.0));
        }
        Ok(vec![self.sideways, self.spin, offset, angle])
    }
}

/// A capsule's rest height and a head-on elastic collision of two capsules.
fn capsules() -> Case {
    let mut scene = SceneDef::new("capsules");
    let mut ground = BodyDef::new(ShapeDef::Box {
        half_extents: [30.0, 0.5],
        radius: 0.0,
    })
    .kind(BodyKind::Static)
    .at(0.0, -0.5);
    ground.friction = 0.0;
    scene.push(ground);
    let radius = 0.25f32;
    let capsule = ShapeDef::Capsule {
        center1: [-0.5, 0.0],
        center2: [0.5, 0.0],
        radius,
    };
    let body = |x: f32, vx: f32| {
        let mut b = BodyDef::new(capsule.clone())
            .at(x, radius)
            .velocity(vx, 0.0)
            .restitution(1.0);
        b.friction = 0.0;
        b
    };
    // At rest, lying on the ground, away from the others.
    let mut resting = body(-20.0, 0.0);
    resting.restitution = 0.0;
    scene.push(resting);
    let (v1, v2) = (3.0f32, -1.0f32);
    scene.push(body(-2.0, v1));
    scene.push(body(2.0, v2));
    let steps = 120;
    Case {
        key: "capsules",
        title: "Capsules: rest height and an elastic collision".into(),
        steps,
        setup: format!(
            "Frictionless capsules (core 1 m, radius {radius} m) lying on a static box: one at \
             rest; two meeting end to end, at {v1} and {v2} m/s along their common axis, with \
             restitution 1. {steps} steps (2 s); they meet after 0.6 s."
        ),
        definition: "**rest height error**: the resting capsule's centre height less its radius \
                     (closed form 0; the Soft Step lets a resting contact sink by up to the linear \
                     slop, 5 mm, before it pushes back). **exchange error**: equal masses in a 1-D \
                     elastic collision swap velocities (momentum and energy conservation); the \
                     largest |v − v*| of the two over their closing speed."
            .into(),
        criterion:
            "|rest height error| ≤ 6 mm (the slop and a millimetre) and exchange error ≤ 2%.".into(),
        metrics: vec![
            MetricDef::new("rest height error (m)", "rest_height_error_m")
                .bound(0.006)
                .plot(),
            MetricDef::new("exchange error", "exchange_error")
                .bound(0.02)
                .plot(),
            MetricDef::new("v1 after (m/s)", "v1_after_mps"),
            MetricDef::new("v2 after (m/s)", "v2_after_mps"),
        ],
        extras: Vec::new(),
        probe: Box::new(move || {
            Box::new(CapsuleProbe {
                radius: f64::from(radius),
                exchange: [(2, f64::from(v2)), (3, f64::from(v1))],
                closing: f64::from(v1 - v2),
            })
        }),
        scene,
    }
}

struct EnergyProbe {
    /// (index, mass, rotational inertia) of each dynamic body.
    bodies: Vec<(usize, f64, f64)>,
    gravity: [f64; 2],
    /// Height of the floor's top, where potential energy is zero.
    floor: f64,
    e0: f64,
    worst: f64,
    last: f64,
}

impl EnergyProbe {
    fn energy(&self, sim: &mut dyn Peer) -> Result<f64> {
        let mut e = 0.0;
        for &(i, m, inertia) in &self.bodies {
            let p = sim.pose(i)?;
            let v = sim.velocity(i)?;
            let (vx, vy, w) = (f64::from(v[0]), f64::from(v[1]), f64::from(v[2]));
            e += 0.5 * m * (vx * vx + vy * vy) + 0.5 * inertia * w * w;
            e -= m
                * (self.gravity[0] * f64::from(p[0])
                    + self.gravity[1] * (f64::from(p[1]) - self.floor));
        }
        Ok(e)
    }
}

impl Probe for EnergyProbe {
    fn after_step(&mut self, sim: &mut dyn Peer, _step: u32) -> Result<()> {
        let e = self.energy(sim)?;
        let rel = (e - self.e0) / self.e0;
        self.last = rel;
        self.worst = if rel.is_finite() {
            self.worst.max(rel.abs())
        } else {
            f64::NAN
        };
        Ok(())
    }
    fn finish(&mut self, _sim: &mut dyn Peer) -> Result<Vec<f64>> {
        Ok(vec![self.worst, self.last])
    }
}

/// The elastic box, as built in (no gravity), or under gravity (then the energy counts the
/// potential energy above the floor).
fn elastic_box(with_gravity: bool) -> Result<Case> {
    let mut scene = builtin_scene("elastic_box")?;
    if with_gravity {
        scene.gravity = [0.0, -10.0];
        scene.name = "elastic_box_gravity".into();
    }
    let steps = 3600;
    let floor = {
        let b = &scene.bodies[0];
        let Some(ShapeDef::Box { half_extents, .. }) = b.shape else {
            anyhow::bail!("elastic_box: the floor is not a box");
        };
        f64::from(b.position[1]) + f64::from(half_extents[1])
    };
    let mut bodies = Vec::new();
    let mut e0 = 0.0;
    let gravity = [f64::from(scene.gravity[0]), f64::from(scene.gravity[1])];
    for (i, b) in scene.bodies.iter().enumerate() {
        if b.kind != BodyKind::Dynamic {
            continue;
        }
        let md = Shape::from_def(b.first_shape().expect("a validated body has a shape"))
            .map_err(|e| anyhow::anyhow!("elastic_box body {i}: {e}"))?
            .mass(b.density);
        let (m, inertia) = (f64::from(md.mass), f64::from(md.inertia));
        let (vx, vy) = (
            f64::from(b.linear_velocity[0]),
            f64::from(b.linear_velocity[1]),
        );
        let w = f64::from(b.angular_velocity);
        e0 += 0.5 * m * (vx * vx + vy * vy) + 0.5 * inertia * w * w
            - m * (gravity[0] * f64::from(b.position[0])
                + gravity[1] * (f64::from(b.position[1]) - floor));
        bodies.push((i, m, inertia));
    }
    let probe = Box::new(move || {
        Box::new(EnergyProbe {
            bodies: bodies.clone(),
            gravity,
            floor,
            e0,
            worst: 0.0,
            last: 0.0,
        }) as Box<dyn Probe>
    });
    let (key, title, setup, definition) = if with_gravity {
        (
            "elastic_box_gravity",
            "Energy under gravity: the elastic box with g = 10 m/s²",
            format!(
                "The same box and circles as `elastic_box`, with gravity 10 m/s² down. {steps} \
                 steps (60 s). Initial energy {e0:.1} J, of which potential about two thirds."
            ),
            "**energy** E = Σ ½mv² + ½Iω² + m·g·(y − y_floor), y_floor the floor's top, from \
             the poses and velocities after every step. **drift**: the largest |E − E₀| / E₀ \
             over the run; **final**: (E − E₀) / E₀ at 60 s, signed. Besides the collisions' \
             losses (previous case), every bounce here loses about m·v·g·dt: restitution \
             restores the approach speed measured before the step's gravity was added (Box2D \
             does the same), so each bounce returns a ball g·dt = 0.17 m/s slower; substeps do \
             not help, as restitution is applied once per step.",
        )
    } else {
        (
            "elastic_box",
            "Energy: an elastic box of bouncing circles",
            format!(
                "Built-in `elastic_box`: 40 frictionless circles of restitution 1 (radius 0.3 m) \
                 with seeded velocities of 2 to 6 m/s inside a closed, frictionless, elastic \
                 10 × 10 m box, no gravity, no damping. {steps} steps (60 s). Initial energy \
                 {e0:.1} J."
            ),
            "**energy** E = Σ ½mv² + ½Iω², from the velocities after every step, masses and \
             inertias from the shapes (the same in the three engines). **drift**: the largest \
             |E − E₀| / E₀ over the run; **final**: (E − E₀) / E₀ at 60 s, signed. Gravity is \
             off so that only the contacts can change the energy (the next case turns it on). \
             Box2D's restitution loses it two ways: a collision slower than the restitution \
             threshold (1 m/s) is inelastic, which cools the gas ever faster as it slows; and \
             a ball that touches two others (or a wall) within one step gets its restitution \
             impulses one contact after the other, once per step (Box2D's single restitution \
             pass), so the second sends it back into the first, whose soft contact then stops \
             it. tumble's `impacts_bounce` (its default; the rows `Box2D's restitution` turn it \
             off) applies the threshold only to contacts that already pushed in the step \
             before (at rest), so an impact bounces at any speed, and repeats the restitution \
             pass until one moves no rebound faster than the threshold by more than 1 mm/s \
             (at most 16 passes), so the bounces hold for every contact at once. Repeated \
             passes at threshold 0 under Box2D's rule also converge, but a fixed number of \
             them, and a resting contact bounces too.",
        )
    };
    Ok(Case {
        key,
        title: title.into(),
        steps,
        setup,
        definition: definition.into(),
        criterion: "drift < 5% over 60 s (the issue).".into(),
        metrics: vec![
            MetricDef::new("energy drift", "energy_drift")
                .bound(0.05)
                .plot(),
            MetricDef::new("final change", "energy_final"),
        ],
        // The restitution threshold (which the peers take too); Box2D's rule in tumble
        // (its default is impacts that bounce), alone and with 4 and 16 passes at
        // threshold 0 (one pass bounces a ball off a wall and back into it when it meets
        // another ball in the same step).
        extras: [
            (0.0, 1, true),
            (0.25, 1, true),
            (1.0, 1, false),
            (0.0, 4, false),
            (0.0, 16, false),
        ]
        .map(|(threshold, restitution_passes, impacts)| Knobs {
            threshold,
            restitution_passes,
            impacts,
            ..Knobs::DEFAULT
        })
        .to_vec(),
        probe,
        scene,
    })
}

/// What the overlap-recovery probe tracks.
struct RecoveryProbe {
    /// Bodies in the scene.
    count: usize,
    dynamic: Vec<usize>,
    top: usize,
    geometry: std::rc::Rc<Geometry>,
    peak: f64,
    top_max: f64,
}

impl Probe for RecoveryProbe {
    fn after_step(&mut self, sim: &mut dyn Peer, _step: u32) -> Result<()> {
        for &i in &self.dynamic {
            let v = sim.velocity(i)?;
            let speed = f64::from(v[0]).hypot(f64::from(v[1]));
            self.peak = if speed.is_finite() {
                self.peak.max(speed)
            } else {
                f64::NAN
            };
        }
        self.top_max = self.top_max.max(f64::from(sim.pose(self.top)?[1]));
        Ok(())
    }
    fn finish(&mut self, sim: &mut dyn Peer) -> Result<Vec<f64>> {
        let mut poses = Vec::with_capacity(self.count);
        for i in 0..self.count {
            poses.push(sim.pose(i)?);
        }
        let overshoot = self.top_max - f64::from(poses[self.top][1]);
        Ok(vec![
            self.peak,
            self.geometry.deepest_overlap(&poses),
            overshoot,
        ])
    }
}

fn overlap_recovery() -> Result<Case> {
    let scene = builtin_scene("overlap_recovery")?;
    let geometry = std::rc::Rc::new(Geometry::new(&scene));
    let dynamic: Vec<usize> = (0..scene.bodies.len())
        .filter(|&i| scene.bodies[i].kind == BodyKind::Dynamic)
        .collect();
    let top = *dynamic.last().context("overlap_recovery has boxes")?;
    let count = scene.bodies.len();
    let probe = Box::new(move || {
        Box::new(RecoveryProbe {
            count,
            dynamic: dynamic.clone(),
            top,
            geometry: geometry.clone(),
            peak: 0.0,
            top_max: f64::NEG_INFINITY,
        }) as Box<dyn Probe>
    });
    Ok(Case {
        key: "overlap_recovery",
        title: "Overlap recovery".into(),
        steps: 300,
        setup: "Built-in `overlap_recovery`: a 4-row pyramid of unit boxes spawned with each \
                neighbour overlapping by a quarter box (Box2D's Overlap Recovery). 300 steps \
                (5 s): in every run the fastest moment is within the first second, and the \
                boxes have come to rest well before 5 s."
            .into(),
        definition: "**peak speed**: the largest |v| of any box after any step (m/s; lower is \
                     gentler). **overlap left**: the deepest overlap at the end (as for the \
                     stacks). **overshoot**: how far the top box rose above where it came to \
                     rest."
            .into(),
        criterion: "peak speed < 3 m/s (the issue). The push-out speed cap (3 m/s by default, \
                    Box2D's `contactSpeed`) bounds each contact's push, not a body's speed: \
                    pushes add up along the rows. This case also sweeps that cap."
            .into(),
        metrics: vec![
            MetricDef::new("peak speed (m/s)", "peak_speed")
                .bound(3.0)
                .plot(),
            MetricDef::new("overlap left (m)", "overlap_m"),
            MetricDef::new("overshoot (m)", "overshoot_m"),
        ],
        extras: [1.0, 2.0]
            .map(|push| Knobs {
                push,
                ..Knobs::DEFAULT
            })
            .to_vec(),
        probe,
        scene,
    })
}

/// Bound on how much the far stack's sag and drift may differ from the origin stack's (m).
pub const FAR_DIFFERENCE: f64 = 0.01;

fn far_from_origin() -> Result<Case> {
    let far = builtin_scene("far_from_origin")?;
    let n = far.bodies.len();
    let (ox, oy) = (far.bodies[0].position[0], far.bodies[0].position[1] + 1.0);
    // The same stack again, at the origin, in the same world: 10 km apart they never meet, and
    // both run with the same knobs in the same steps.
    let mut scene = far.clone();
    scene.name = "far_and_origin".into();
    for b in &far.bodies {
        let mut copy = b.clone();
        copy.position = [b.position[0] - ox, b.position[1] - oy];
        scene.push(copy);
    }
    let stacks = vec![
        Stack::new(&scene, (0..n).collect()),
        Stack::new(&scene, (n..2 * n).collect()),
    ];
    Ok(Case {
        key: "far_from_origin",
        title: "Far from the origin".into(),
        steps: 600,
        setup: "Built-in `far_from_origin` (a column of 10 unit boxes on a static ground at \
                (10 km, 10 km), where an f32 is 0.98 mm apart from the next) and the same \
                stack at the origin, in one world. 600 steps (10 s). ms/step is for both stacks."
            .into(),
        definition: format!(
            "For each stack, **drift** and **sag** of its top box as for the vertical stack. \
             **Δ sag**, **Δ drift**: |far − origin|. {PENETRATION_TEXT} (Pairs are measured \
             relative to one body of the pair, in f64, so the far stack is measured as \
             precisely as the near one.)"
        ),
        criterion: format!(
            "the far stack stands (drift < 0.1 m, as the 15-box stack) and its sag and drift \
             differ from the origin stack's by less than {FAR_DIFFERENCE} m, ten f32 spacings \
             at 10 km: precision loss may show as millimetres, not as a different outcome."
        ),
        metrics: vec![
            MetricDef::new("Δ sag (m)", "delta_sag_m")
                .bound(FAR_DIFFERENCE)
                .plot(),
            MetricDef::new("Δ drift (m)", "delta_drift_m").bound(FAR_DIFFERENCE),
            MetricDef::new("far drift (m)", "far_drift_m")
                .bound(0.1)
                .plot(),
            MetricDef::new("far sag (m)", "far_sag_m"),
            MetricDef::new("origin drift (m)", "origin_drift_m"),
            MetricDef::new("origin sag (m)", "origin_sag_m"),
            MetricDef::new("far penetration (m)", "far_penetration_m"),
            MetricDef::new("origin penetration (m)", "origin_penetration_m"),
        ],
        extras: Vec::new(),
        probe: stacks_probe(stacks, false, |s| {
            let (far, near) = (&s[0], &s[1]);
            vec![
                (far.top_sag - near.top_sag).abs(),
                (far.top_drift - near.top_drift).abs(),
                far.top_drift,
                far.top_sag,
                near.top_drift,
                near.top_sag,
                far.penetration,
                near.penetration,
            ]
        }),
        scene,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closed_forms() {
        let theta = 20f64.to_radians();
        assert_eq!(slide_distance(10.0, theta, 0.4, 3.0), 0.0);
        let s = slide_distance(10.0, theta, 0.3, 3.0);
        assert!((s - 0.5 * 10.0 * (theta.sin() - 0.3 * theta.cos()) * 9.0).abs() < 1e-12);
    }

    #[test]
    fn every_case_builds_with_its_metrics() {
        let cases = all(true).unwrap();
        assert!(cases.len() >= 14);
        for c in &cases {
            assert!(c.metrics.iter().any(|m| m.plot), "{}", c.key);
            assert!(c.metrics.iter().any(|m| m.bound.is_some()), "{}", c.key);
            c.scene.validate(&scenes::limits()).unwrap();
        }
    }
}
