//! The joint cases of the accuracy report: a pendulum and a hinged rod against closed forms,
//! a hanging ball and chain at three mass ratios, Solver2D's bridge and Box2D's joint grid. Every metric comes
//! from the bodies' poses (the joints' anchors are put back on the bodies from the scene's
//! joint definitions), so the same probe measures every engine.

use std::f64::consts::PI;

use anyhow::Result;
use tumble_physics::joint::JointDef;
use tumble_physics::{BodyDef, BodyId, SceneDef, ShapeDef};
use tumble_scene::builtin::anchor_body;

use super::cases::{Case, MetricDef, Probe};
use super::engines::Knobs;
use crate::peers::Peer;

const G: f64 = 10.0;

/// The joint cases, in report order.
pub fn all() -> Vec<Case> {
    let mut cases = vec![pendulum(), hinged_rod()];
    for ratio in [10.0, 100.0, 1000.0] {
        cases.push(ball_and_chain(ratio));
    }
    cases.push(bridge());
    cases.push(joint_grid());
    cases
}

/// The joint hertz swept beyond the common sweep: softer, and stiffer where the quarter of the
/// substep rate lets it act.
fn joint_extras() -> Vec<Knobs> {
    let d = Knobs::DEFAULT;
    vec![
        Knobs {
            joint_hertz: 30.0,
            ..d
        },
        Knobs {
            substeps: 8,
            joint_hertz: 120.0,
            ..d
        },
        Knobs {
            substeps: 16,
            joint_hertz: 240.0,
            ..d
        },
    ]
}

/// The complete elliptic integral of the first kind K(k), by the arithmetic-geometric mean:
/// K = π / (2 AGM(1, √(1 − k²))) (Abramowitz and Stegun 17.6).
fn elliptic_k(k: f64) -> f64 {
    let (mut a, mut b) = (1.0f64, (1.0 - k * k).sqrt());
    for _ in 0..40 {
        let (an, bn) = (0.5 * (a + b), (a * b).sqrt());
        a = an;
        b = bn;
    }
    PI / (2.0 * a)
}

/// Times the bob crosses below the hinge going left, and the arm's largest error.
struct PendulumProbe {
    arm: f64,
    last_x: f64,
    crossings: Vec<f64>,
    arm_error: f64,
    dt: f64,
    period: f64,
}

impl Probe for PendulumProbe {
    fn after_step(&mut self, sim: &mut dyn Peer, step: u32) -> Result<()> {
        let [x, y, _] = sim.pose(1)?;
        let (x, y) = (f64::from(x), f64::from(y));
        if self.last_x > 0.0 && x <= 0.0 {
            let f = self.last_x / (self.last_x - x);
            self.crossings.push((f64::from(step) - 1.0 + f) * self.dt);
        }
        self.last_x = x;
        self.arm_error = self
            .arm_error
            .max(((x * x + y * y).sqrt() - self.arm).abs());
        Ok(())
    }
    fn finish(&mut self, _sim: &mut dyn Peer) -> Result<Vec<f64>> {
        let c = &self.crossings;
        let period = if c.len() >= 2 {
            (c[c.len() - 1] - c[0]) / (c.len() - 1) as f64
        } else {
            f64::NAN
        };
        Ok(vec![period / self.period - 1.0, self.arm_error, period])
    }
}

/// A disc on a hinge released at 1 rad: the period against the exact one.
fn pendulum() -> Case {
    let (l, r, theta) = (2.0f64, 0.1f64, 1.0f64);
    let mut scene = SceneDef::new("pendulum");
    scene.sleep = false;
    scene.push(anchor_body());
    scene.push(
        BodyDef::new(ShapeDef::Circle { radius: r as f32 })
            .at((l * theta.sin()) as f32, (-l * theta.cos()) as f32),
    );
    scene
        .joints
        .push(JointDef::hinge([0, 1].map(BodyId::scene), [0.0, 0.0]));
    // Compound pendulum: I about the hinge = m (r²/2 + L²); small swings have
    // ω0² = m g L / I; at amplitude θ0 the period is 4 K(sin(θ0/2)) / ω0.
    let omega0 = (G * l / (0.5 * r * r + l * l)).sqrt();
    let period = 4.0 * elliptic_k((0.5 * theta).sin()) / omega0;
    let steps = 600;
    Case {
        key: "pendulum",
        title: "A pendulum released at 1 rad".into(),
        steps,
        setup: format!(
            "A disc of radius {r} m on a revolute joint {l} m above its centre, released from \
             rest at {theta} rad (57°) from the vertical; {steps} steps (10 s, about 3.4 \
             swings)."
        ),
        definition: format!(
            "Closed form: the compound pendulum's period at amplitude θ0, T = 4 K(sin(θ0/2)) / \
             ω0 with ω0² = g L / (r²/2 + L²) and K the complete elliptic integral of the first \
             kind (by the arithmetic-geometric mean): T = {period:.6} s, 7.3% longer than the \
             small-swing period. **period error**: the mean time between the bob's leftward \
             crossings below the hinge (interpolated between steps), relative to T; **arm \
             error**: the largest |distance from the hinge − L| over the run, how far the \
             hinge gives."
        ),
        criterion: "period error ≤ 0.5% and arm error ≤ 1 cm: the joint holds the bob on its \
                    circle and the integration keeps the swing's energy."
            .into(),
        metrics: vec![
            MetricDef::new("period error (relative)", "period_error")
                .bound(5e-3)
                .plot(),
            MetricDef::new("arm error (m)", "arm_error_m")
                .bound(0.01)
                .plot(),
            MetricDef::new("period (s)", "period_s"),
        ],
        extras: joint_extras(),
        probe: Box::new(move || {
            Box::new(PendulumProbe {
                arm: l,
                last_x: l * theta.sin(),
                crossings: Vec::new(),
                arm_error: 0.0,
                dt: 1.0 / 60.0,
                period,
            })
        }),
        scene,
    }
}

/// The rod's angular speed as it first passes straight down.
struct RodProbe {
    expected: f64,
    last: Option<(f64, f64)>,
    at_bottom: Option<f64>,
}

impl Probe for RodProbe {
    fn after_step(&mut self, sim: &mut dyn Peer, _step: u32) -> Result<()> {
        if self.at_bottom.is_some() {
            return Ok(());
        }
        let angle = f64::from(sim.pose(1)?[2]);
        let w = f64::from(sim.velocity(1)?[2]);
        let bottom = -0.5 * PI;
        if angle <= bottom
            && let Some((a0, w0)) = self.last
        {
            let f = (a0 - bottom) / (a0 - angle);
            self.at_bottom = Some(w0 + f * (w - w0));
        }
        self.last = Some((angle, w));
        Ok(())
    }
    fn finish(&mut self, _sim: &mut dyn Peer) -> Result<Vec<f64>> {
        let w = self.at_bottom.map_or(f64::NAN, |w| -w);
        Ok(vec![w / self.expected - 1.0, w])
    }
}

/// A rod hinged at one end, released horizontal: its speed at the bottom.
fn hinged_rod() -> Case {
    let (l, t) = (2.0f64, 0.05f64);
    let mut scene = SceneDef::new("hinged_rod");
    scene.sleep = false;
    scene.push(anchor_body());
    scene.push(
        BodyDef::new(ShapeDef::Box {
            half_extents: [(l / 2.0) as f32, (t / 2.0) as f32],
            radius: 0.0,
        })
        .at((l / 2.0) as f32, 0.0),
    );
    scene
        .joints
        .push(JointDef::hinge([0, 1].map(BodyId::scene), [0.0, 0.0]));
    // Energy: m g L/2 = ½ I ω², I = m (L² + t²)/12 + m (L/2)² about the hinge.
    let i_over_m = (l * l + t * t) / 12.0 + l * l / 4.0;
    let expected = (G * l / i_over_m).sqrt();
    let steps = 90;
    Case {
        key: "hinged_rod",
        title: "A rod hinged at one end, released horizontal".into(),
        steps,
        setup: format!(
            "A rod {l} m long and {t} m thick on a revolute joint at its left end, released \
             from rest horizontal; {steps} steps (it reaches the bottom in about 0.5 s)."
        ),
        definition: format!(
            "Closed form: energy, m g L/2 = ½ I ω² with I = m (L² + t²)/12 + m L²/4 about the \
             hinge, so ω = {expected:.6} rad/s at the bottom (√(3g/L) = {:.6} for a thin rod). \
             **ω error**: the angular speed when the rod first passes straight down \
             (interpolated between steps), relative to that.",
            (3.0 * G / l).sqrt()
        ),
        criterion: "ω error ≤ 1%: the hinge neither takes nor adds energy over a quarter \
                    swing."
            .into(),
        metrics: vec![
            MetricDef::new("ω error (relative)", "omega_error")
                .bound(0.01)
                .plot(),
            MetricDef::new("ω at the bottom (rad/s)", "omega_radps"),
        ],
        extras: joint_extras(),
        probe: Box::new(move || {
            Box::new(RodProbe {
                expected,
                last: None,
                at_bottom: None,
            })
        }),
        scene,
    }
}

/// The distance from the pivot to the ball's attachment point, less the chain's length.
struct ChainProbe {
    ball: usize,
    ball_radius: f64,
    pivot: [f64; 2],
    length: f64,
    largest: f64,
    last: f64,
}

impl ChainProbe {
    fn stretch(&self, sim: &mut dyn Peer) -> Result<f64> {
        let [x, y, a] = sim.pose(self.ball)?;
        let (x, y, a) = (f64::from(x), f64::from(y), f64::from(a));
        // The attachment is the ball's top at the start: (0, r) in its frame.
        let (ax, ay) = (
            x - self.ball_radius * a.sin(),
            y + self.ball_radius * a.cos(),
        );
        let d = ((ax - self.pivot[0]).powi(2) + (ay - self.pivot[1]).powi(2)).sqrt();
        Ok(d - self.length)
    }
}

impl Probe for ChainProbe {
    fn after_step(&mut self, sim: &mut dyn Peer, _step: u32) -> Result<()> {
        let s = self.stretch(sim)?;
        self.largest = self.largest.max(s.abs());
        self.last = s;
        Ok(())
    }
    fn finish(&mut self, _sim: &mut dyn Peer) -> Result<Vec<f64>> {
        Ok(vec![self.last, self.largest])
    }
}

/// A chain of 10 capsule links hanging straight down from a pivot with a ball `ratio` times a
/// link's mass at its end, at rest: how much the chain stretches under the ball.
fn ball_and_chain(ratio: f64) -> Case {
    const LINKS: usize = 10;
    let (hx, radius, density) = (0.5f32, 0.125f32, 20.0f32);
    // A link: a 1 m × 0.25 m rectangle and two half discs of radius 0.125.
    let link_mass = f64::from(density)
        * (2.0 * f64::from(hx) * 2.0 * f64::from(radius) + PI * f64::from(radius).powi(2));
    let ball_radius = 1.0f64;
    let ball_density = ratio * link_mass / (PI * ball_radius * ball_radius);
    let mut scene = SceneDef::new(format!("ball_and_chain_{ratio}"));
    scene.sleep = false;
    let top = 20.0f32;
    let ground = scene.push(anchor_body());
    let mut prev = ground;
    for i in 0..LINKS {
        let y = top - (2 * i + 1) as f32 * hx;
        let link = scene.push(
            BodyDef::new(ShapeDef::Capsule {
                center1: [0.0, -hx],
                center2: [0.0, hx],
                radius,
            })
            .at(0.0, y)
            .density(density),
        );
        scene.joints.push(JointDef::hinge(
            [prev, link].map(BodyId::scene),
            [0.0, y + hx],
        ));
        prev = link;
    }
    let bottom = top - LINKS as f32 * 2.0 * hx;
    let ball = scene.push(
        BodyDef::new(ShapeDef::Circle {
            radius: ball_radius as f32,
        })
        .at(0.0, bottom - ball_radius as f32)
        .density(ball_density as f32),
    );
    scene.joints.push(JointDef::hinge(
        [prev, ball].map(BodyId::scene),
        [0.0, bottom],
    ));
    let steps = 180;
    let key: &'static str = match ratio as u32 {
        10 => "ball_and_chain_10",
        100 => "ball_and_chain_100",
        _ => "ball_and_chain_1000",
    };
    Case {
        key,
        title: format!("A ball {ratio}:1 hanging on a chain"),
        steps,
        setup: format!(
            "A chain of {LINKS} capsule links (1 m between hinges, radius {radius} m, density \
             {density}: {link_mass:.2} kg each) hangs straight down from a fixed hinge, a ball \
             of radius {ball_radius} m and {:.0} kg ({ratio}:1) hinged to its end, all at rest \
             in place; {steps} steps (3 s). Solver2D's ball and chain, hanging, at three mass \
             ratios.",
            ratio * link_mass
        ),
        definition: "Closed form: the links and hinges are rigid, so the ball's attachment point \
                     stays 10 m below the pivot. **stretch**: the pivot-to-attachment distance \
                     less 10 m at the end; **largest stretch**: its largest magnitude over the \
                     run (the first sag as the load comes on)."
            .into(),
        criterion: "stretch ≤ 1 cm (0.1%): a chain that stretches more than that under a heavy \
                    load is visibly elastic. Soft-step joints (tumble's and Box2D's) give as a \
                    spring of stiffness m ω² per joint with m the joint's effective mass, a \
                    light link's: the stretch grows with the mass ratio."
            .into(),
        metrics: vec![
            MetricDef::new("stretch (m)", "stretch_m")
                .bound(0.01)
                .plot(),
            MetricDef::new("largest stretch (m)", "largest_stretch_m").plot(),
        ],
        extras: joint_extras(),
        probe: Box::new(move || {
            Box::new(ChainProbe {
                ball,
                ball_radius,
                pivot: [0.0, f64::from(top)],
                length: f64::from(bottom - top).abs(),
                largest: 0.0,
                last: 0.0,
            })
        }),
        scene,
    }
}

/// The sag of the bridge's middle plank.
struct SagProbe {
    middle: usize,
    height: f64,
    largest: f64,
    last: f64,
}

impl Probe for SagProbe {
    fn after_step(&mut self, sim: &mut dyn Peer, _step: u32) -> Result<()> {
        let y = f64::from(sim.pose(self.middle)?[1]);
        self.last = self.height - y;
        self.largest = self.largest.max(self.last);
        Ok(())
    }
    fn finish(&mut self, _sim: &mut dyn Peer) -> Result<Vec<f64>> {
        Ok(vec![self.last, self.largest])
    }
}

/// Solver2D's bridge: 160 hinged planks spanning exactly their length.
fn bridge() -> Case {
    let mut scene = tumble_scene::builtin::build("bridge").expect("the built-in bridge");
    scene.sleep = false;
    let steps = 300;
    Case {
        key: "bridge",
        title: "Solver2D's bridge".into(),
        steps,
        setup: format!(
            "160 planks 1 m long (density 20, damping 0.1) hinged end to end, the first and \
             last hinged to fixed points exactly 160 m apart; {steps} steps (5 s)."
        ),
        definition: "Closed form: the planks span exactly the gap, so rigid links and hinges \
                     cannot sag at all: every centimetre of sag is the joints' give. **sag**: \
                     how far the middle plank's centre is below 20 m at the end; **largest \
                     sag**: over the run."
            .into(),
        criterion: "sag ≤ 0.5 m. Every joint carries the bridge's tension and a soft joint \
                    lengthens under it; a 160 m span whose length grows by δ sags by about \
                    √(3·160·δ/8) (a shallow parabola), so 0.5 m of sag is 4 mm of stretch over \
                    its 161 joints: a strict bound."
            .into(),
        metrics: vec![
            MetricDef::new("sag (m)", "sag_m").bound(0.5).plot(),
            MetricDef::new("largest sag (m)", "largest_sag_m"),
        ],
        extras: joint_extras(),
        probe: Box::new(|| {
            Box::new(SagProbe {
                middle: 80,
                height: 20.0,
                largest: 0.0,
                last: 0.0,
            })
        }),
        scene,
    }
}

/// The larger of `a` and `b`, NaN if either is (`f64::max` drops a NaN: a run that went
/// non-finite must fail).
fn max_keeping_nan(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.max(b)
    }
}

/// How far apart each hinge's two anchors have come (the anchors put back on the bodies from
/// the scene's joints), read from every body's pose.
struct GapProbe {
    /// Per hinge: body A, the anchor in A's frame, body B, the anchor in B's frame.
    hinges: Vec<(usize, [f64; 2], usize, [f64; 2])>,
    bodies: usize,
    /// Steps between two readings during the run (every pose through the engine's API).
    every: u32,
    largest: f64,
}

impl GapProbe {
    fn new(scene: &SceneDef, every: u32) -> GapProbe {
        let frame = |i: usize| {
            let b = &scene.bodies[i];
            (
                [f64::from(b.position[0]), f64::from(b.position[1])],
                f64::from(b.angle),
            )
        };
        let local = |i: usize, p: [f32; 2]| {
            let ([x, y], a) = frame(i);
            let (dx, dy) = (f64::from(p[0]) - x, f64::from(p[1]) - y);
            let (s, c) = a.sin_cos();
            [c * dx + s * dy, -s * dx + c * dy]
        };
        let hinges = scene
            .joints
            .iter()
            .filter_map(|j| match j {
                JointDef::Revolute {
                    bodies: [a, b],
                    anchor,
                    anchor_b: None,
                    ..
                } => {
                    let (a, b) = (a.index as usize, b.index as usize);
                    Some((a, local(a, *anchor), b, local(b, *anchor)))
                }
                _ => None,
            })
            .collect();
        GapProbe {
            hinges,
            bodies: scene.bodies.len(),
            every,
            largest: 0.0,
        }
    }

    /// The largest and the mean gap now.
    fn gaps(&self, sim: &mut dyn Peer) -> Result<(f64, f64)> {
        let mut poses = Vec::with_capacity(self.bodies);
        for i in 0..self.bodies {
            let [x, y, a] = sim.pose(i)?;
            poses.push((f64::from(x), f64::from(y), f64::from(a)));
        }
        let world = |i: usize, p: [f64; 2]| {
            let (x, y, a) = poses[i];
            let (s, c) = a.sin_cos();
            [x + c * p[0] - s * p[1], y + s * p[0] + c * p[1]]
        };
        let (mut largest, mut sum) = (0.0f64, 0.0f64);
        for &(a, pa, b, pb) in &self.hinges {
            let (wa, wb) = (world(a, pa), world(b, pb));
            let gap = (wa[0] - wb[0]).hypot(wa[1] - wb[1]);
            // A NaN pose makes the gap NaN: kept, so the run fails.
            largest = max_keeping_nan(largest, gap);
            sum += gap;
        }
        Ok((largest, sum / self.hinges.len().max(1) as f64))
    }
}

impl Probe for GapProbe {
    fn after_step(&mut self, sim: &mut dyn Peer, step: u32) -> Result<()> {
        if step.is_multiple_of(self.every) {
            let (largest, _) = self.gaps(sim)?;
            self.largest = max_keeping_nan(self.largest, largest);
        }
        Ok(())
    }
    fn finish(&mut self, sim: &mut dyn Peer) -> Result<Vec<f64>> {
        let (largest, mean) = self.gaps(sim)?;
        Ok(vec![largest, mean, max_keeping_nan(self.largest, largest)])
    }
}

/// Box2D's joint grid: 10,000 discs hung by 19,794 hinges from 7 fixed discs, swinging down.
fn joint_grid() -> Case {
    let scene = tumble_scene::builtin::build("joint_grid").expect("the built-in joint_grid");
    let steps = 300;
    let every = 10;
    let probe_scene = scene.clone();
    Case {
        key: "joint_grid",
        title: "Box2D's joint grid".into(),
        steps,
        setup: format!(
            "A 100 × 100 grid of discs (radius 0.4 m, density 1) 1 m apart, each hinged to the \
             one above and the one to its left ({} hinges), the top discs of the 7 middle \
             columns fixed; the rest falls and swings down as a net hanging from them, its \
             top hinges carrying up to 100 rows; {steps} steps (5 s). Box2D's `joint_grid` \
             benchmark.",
            GapProbe::new(&scene, every).hinges.len()
        ),
        definition: format!(
            "Closed form: rigid hinges keep each hinge's two anchors together. **gap**: the \
             distance between a hinge's anchor on one disc and on the other (each put back on \
             its disc from the scene's definition and the disc's pose); **largest gap** and \
             **mean gap** over all hinges at the end; **largest gap over the run**: read every \
             {every} steps and at the end."
        ),
        criterion: "largest gap ≤ 1 cm, as for the ball and chain: a net whose hinges open by \
                    more is visibly elastic. The hinges near the fixed discs hold the weight of \
                    the rows below (up to 100 discs of 0.5 kg on a few hinges), through disc \
                    masses of 0.5 kg: the soft step's give (load / (m ω²)) is largest there."
            .into(),
        metrics: vec![
            MetricDef::new("largest gap (m)", "largest_gap_m")
                .bound(0.01)
                .plot(),
            MetricDef::new("mean gap (m)", "mean_gap_m"),
            MetricDef::new("largest gap over the run (m)", "largest_gap_run_m").plot(),
        ],
        extras: joint_extras(),
        probe: Box::new(move || Box::new(GapProbe::new(&probe_scene, every))),
        scene,
    }
}
