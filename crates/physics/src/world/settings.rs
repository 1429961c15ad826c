//! The step's settings: the knobs that trade speed for accuracy, and where the step's stages
//! are shared with the worker threads.

use glam::Vec2;

use crate::error::SettingsError;
pub use crate::solver::contact_solver::RESTITUTION_PASSES;

/// The knobs of the step that trade speed for accuracy. Defaults are Box2D v3's, but for a
/// manifold's two points, solved together (`solve_points_together`).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StepSettings {
    /// Gravity (m/s²).
    pub gravity: Vec2,
    /// Stiffness of contacts (Hz); clamped to an eighth of the substep rate, which keeps low
    /// substep counts stable (Box2D HEAD, docs/soft_step.md 2.3). Contacts against static bodies
    /// use twice it. Box2D's 30 Hz: at 60 Hz (with a quarter-rate clamp) the 100-row pyramid
    /// was measured to jitter at 0.4 m/s after 500 steps, against 0.13 m/s at 30 Hz.
    pub contact_hertz: f32,
    /// Damping ratio of the contact spring (Box2D: 10, heavily over-damped).
    pub contact_damping_ratio: f32,
    /// Fastest that overlap is pushed apart (m/s), Box2D's `contactSpeed`.
    pub max_push_speed: f32,
    /// Rigid relax passes per substep after the soft solve (Box2D: 1).
    pub relax_iterations: u32,
    /// Approach speed (m/s) below which restitution is not applied: to every contact (Box2D's
    /// rule), or with `impacts_bounce` only to contacts that were already pushing.
    pub restitution_threshold: f32,
    /// Impacts bounce as their restitution says. The restitution threshold applies only to
    /// a contact that pushed in the last step (one at rest, whose tiny bounces would be
    /// jitter), so a contact that begins to push bounces at any approach speed (Rapier's rule
    /// too); and the restitution passes repeat until none moves a rebound faster than the
    /// threshold by more than 1 mm/s (see `restitution_iterations`), so the bounces that
    /// count hold for every contact at once (after the first pass, only the contacts whose
    /// bodies a fast rebound has just moved, the passes ending once they have visited about
    /// twice as many contacts as bounce, or 1,024: a dense pile struck fast converges
    /// slowly). On by default:
    /// off is Box2D v3's restitution, the threshold for every contact, so that every
    /// collision slower than it is inelastic (a gas of elastic balls cools ever faster as
    /// it slows: 91% of the elastic box's energy is lost in 60 s, 2% with this on;
    /// docs/accuracy/REPORT.md), and exactly `restitution_iterations` passes. What it costs:
    /// nothing where nothing bounces; in `spinner` (restitution 0.1 on 6,076 bodies, a paddle
    /// at up to 100 m/s) about 3% of the step at one thread (its solve 12%; docs/history.md).
    #[serde(default = "yes")]
    pub impacts_bounce: bool,
    /// Passes of the restitution stage at the end of the step. One pass (Box2D's) applies
    /// each contact's bounce once, in colour order, so a body that hits two others in one
    /// step (a wall and a ball) is sent back into the first by the second; more passes
    /// converge to bounces that hold for every contact at once. With `impacts_bounce` off,
    /// exactly this many; on, as many as it takes for a pass to move no rebound faster than
    /// the threshold by more than 1 mm/s, up to this or [`RESTITUTION_PASSES`], whichever is
    /// more, and within the visit budget (`impacts_bounce`). Skipped when nothing bounces.
    #[serde(default = "one")]
    pub restitution_iterations: u32,
    /// Speed cap (m/s), Box2D's `maxLinearSpeed`.
    pub max_linear_speed: f32,
    /// Seed each step's solve with the last step's impulses.
    pub warm_starting: bool,
    /// Keep a contact's manifold while its pair barely moves (Box2D v3's contact recycling):
    /// cheaper narrow phase and steadier stacks.
    pub contact_recycling: bool,
    /// Solve the two points of a manifold from the same velocities where their rows are well
    /// apart: a body dropped flat then lands straight, where solved one after the other, as
    /// Box2D v3 does, the first point takes the whole impact and the body lands sideways and
    /// turning (docs/accuracy/flat_landing.md). On by default; off is Box2D's Soft Step
    /// exactly, the reference the peer cross-checks hold tumble to (on costs about 1% of the
    /// step, up to 5% of a large pile's at 2 threads; measured in that document).
    #[serde(default = "yes")]
    pub solve_points_together: bool,
    /// Solve each colour eight constraints at a time with SIMD. Off runs the scalar path,
    /// which gives bit-identical results; it exists to measure what SIMD buys.
    pub simd: bool,
    /// Islands whose bodies all rested for `time_to_sleep` fall asleep and cost nothing
    /// until something wakes them (a scene's `sleep`; Box2D's `enableSleep`, on by default).
    #[serde(default = "yes")]
    pub enable_sleep: bool,
    /// Speed below which a body counts as resting (m/s; Box2D's `b2_linearSleepTolerance`
    /// as a body's `sleepThreshold`, 0.05).
    #[serde(default = "sleep_threshold")]
    pub sleep_threshold: f32,
    /// How long (s) every body of an island must rest before it sleeps (Box2D's
    /// `B2_TIME_TO_SLEEP`, 0.5).
    #[serde(default = "time_to_sleep")]
    pub time_to_sleep: f32,
    /// Stiffness of a joint's rigid rows (Hz; Box2D's 60), given to each joint as it is
    /// made; clamped to a quarter of the substep rate. 0 is rigid.
    #[serde(default = "joint_hertz")]
    pub joint_hertz: f32,
    /// Damping ratio of a joint's rigid rows (Box2D's 2), given to each joint as it is made.
    #[serde(default = "joint_damping_ratio")]
    pub joint_damping_ratio: f32,
    /// Least approach speed (m/s) of a contact that begins for it to be a hit event (a
    /// scene's `hit_speed`; Box2D's `hitEventThreshold`, 1 m/s).
    #[serde(default = "hit_speed")]
    pub hit_speed: f32,
    /// Continuous collision: a dynamic body that moves more than half its thickness in a
    /// step is swept against the static shapes (a bullet against every body), so that none
    /// passes through (a scene's `continuous`; Box2D's `enableContinuous`, on by default).
    #[serde(default = "yes")]
    pub continuous: bool,
}

fn hit_speed() -> f32 {
    1.0
}

fn joint_hertz() -> f32 {
    60.0
}
fn joint_damping_ratio() -> f32 {
    2.0
}

fn yes() -> bool {
    true
}
fn sleep_threshold() -> f32 {
    0.05
}
fn time_to_sleep() -> f32 {
    0.5
}

fn one() -> u32 {
    1
}

impl Default for StepSettings {
    fn default() -> Self {
        Self {
            gravity: Vec2::new(0.0, -10.0),
            contact_hertz: 30.0,
            contact_damping_ratio: 10.0,
            max_push_speed: 3.0,
            relax_iterations: 1,
            restitution_threshold: 1.0,
            restitution_iterations: 1,
            impacts_bounce: true,
            max_linear_speed: 400.0,
            warm_starting: true,
            contact_recycling: true,
            solve_points_together: true,
            simd: true,
            enable_sleep: true,
            sleep_threshold: sleep_threshold(),
            time_to_sleep: time_to_sleep(),
            joint_hertz: joint_hertz(),
            joint_damping_ratio: joint_damping_ratio(),
            hit_speed: hit_speed(),
            continuous: true,
        }
    }
}

impl StepSettings {
    /// Checks every knob for a value the step cannot use: a non-finite or negative number
    /// (gravity, contact hertz, damping ratio, push-out speed, restitution threshold) turns
    /// the state non-finite or pulls bodies together; zero relax passes silently drop
    /// friction (friction is solved in the relax pass); zero restitution passes drop every
    /// bounce; a speed cap that is not a finite number > 0 stops every body or caps nothing.
    /// [`World::from_scene`](crate::World::from_scene) and
    /// [`World::from_snapshot`](crate::World::from_snapshot) call it; so should anything that
    /// takes settings from outside (flags, sliders, files) before
    /// [`World::settings_mut`](crate::World::settings_mut).
    pub fn validate(&self) -> Result<(), SettingsError> {
        let err = |field: &'static str, value: String, allowed: &str| SettingsError {
            field,
            value,
            allowed: allowed.to_string(),
        };
        if !self.gravity.is_finite() {
            return Err(err(
                "gravity",
                format!("{:?}", <[f32; 2]>::from(self.gravity)),
                "two finite numbers (m/s²)",
            ));
        }
        let non_negative = |field: &'static str, v: f32, unit: &str| {
            if v.is_finite() && v >= 0.0 {
                Ok(())
            } else {
                Err(err(
                    field,
                    v.to_string(),
                    &format!("a finite number >= 0 ({unit})"),
                ))
            }
        };
        non_negative(
            "contact_hertz",
            self.contact_hertz,
            "Hz; Box2D's default is 30",
        )?;
        non_negative(
            "contact_damping_ratio",
            self.contact_damping_ratio,
            "Box2D's default is 10",
        )?;
        non_negative(
            "max_push_speed",
            self.max_push_speed,
            "m/s; Box2D's default is 3",
        )?;
        non_negative(
            "restitution_threshold",
            self.restitution_threshold,
            "m/s; Box2D's default is 1",
        )?;
        non_negative(
            "sleep_threshold",
            self.sleep_threshold,
            "m/s; Box2D's default is 0.05",
        )?;
        non_negative(
            "time_to_sleep",
            self.time_to_sleep,
            "s; Box2D's default is 0.5",
        )?;
        non_negative(
            "joint_hertz",
            self.joint_hertz,
            "Hz; 0 is rigid; Box2D's is 60",
        )?;
        non_negative(
            "joint_damping_ratio",
            self.joint_damping_ratio,
            "Box2D's default is 2",
        )?;
        non_negative("hit_speed", self.hit_speed, "m/s; Box2D's default is 1")?;
        if !(self.max_linear_speed.is_finite() && self.max_linear_speed > 0.0) {
            return Err(err(
                "max_linear_speed",
                self.max_linear_speed.to_string(),
                "a finite number > 0 (m/s; 0 would stop every body; Box2D's default is 400)",
            ));
        }
        if self.relax_iterations == 0 {
            return Err(err(
                "relax_iterations",
                "0".into(),
                "1 or more (friction is solved in the relax pass, so 0 would silently remove \
                 it; Box2D's default is 1)",
            ));
        }
        if self.restitution_iterations == 0 {
            return Err(err(
                "restitution_iterations",
                "0".into(),
                "1 or more (0 would silently remove every bounce; Box2D's default is 1)",
            ));
        }
        Ok(())
    }
}

/// The least work per worker for which a stage of the step is split over the world's threads:
/// below it the stage runs on one thread, and a step none of whose stages reaches its
/// threshold runs inline on the caller's thread without waking the crew. Results never depend
/// on these (the tests of determinism run with [`WideThresholds::ALWAYS`] and the defaults).
///
/// The defaults come from measurement on this project's 2-core machine: `tumble-bench
/// thresholds` (docs/bench/thresholds.md) for where splitting each stage over two workers
/// begins to pay, and for prepare and finalize interleaved A/Bs of whole steps on piles
/// (`Default for WideThresholds`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WideThresholds {
    /// Contacts (and moved proxies, which make contacts), for the step to leave the caller's
    /// thread at all: below it every stage runs inline (each split stage costs a hand-off to
    /// the followers and a wait for the last part).
    pub step: usize,
    /// Moved proxies, for the broad phase's queries.
    pub broad_phase: usize,
    /// Contacts, for the narrow phase.
    pub narrow_phase: usize,
    /// Touching contacts, for building, storing and checking the constraints.
    pub prepare: usize,
    /// Touching contacts, for the substeps and restitution (the solver's stage board).
    pub solve: usize,
    /// Bodies, for finalize.
    pub finalize: usize,
    /// Whether the substeps, once `solve` splits them, are also timed on one worker now and
    /// then (two steps after the first 8, then at intervals that double or grow fourfold, up
    /// to 256 steps), and run there while that is clearly faster on this machine, now
    /// (`threads::payoff`; the profile's `solver_workers` says which ran). The results are
    /// the same either way. Off in [`WideThresholds::ALWAYS`] and where
    /// [`crate::World::set_workers_beyond_cores`] asks for every worker.
    pub solve_by_payoff: bool,
}

impl WideThresholds {
    /// Every stage of more than one item is split (for tests and measurement).
    pub const ALWAYS: WideThresholds = WideThresholds {
        step: 1,
        broad_phase: 1,
        narrow_phase: 1,
        prepare: 1,
        solve: 1,
        finalize: 1,
        solve_by_payoff: false,
    };
    /// No stage is ever split: every step runs inline.
    pub const NEVER: WideThresholds = WideThresholds {
        step: usize::MAX / 2,
        broad_phase: usize::MAX / 2,
        narrow_phase: usize::MAX / 2,
        prepare: usize::MAX / 2,
        solve: usize::MAX / 2,
        finalize: usize::MAX / 2,
        solve_by_payoff: false,
    };
}

impl Default for WideThresholds {
    fn default() -> Self {
        // docs/bench/thresholds.md: about half of each crossover measured on 2 cores (the
        // lower of two runs where one size's outlier moved a crossover, rounded); prepare
        // and finalize then halved (from 1200 and 1000), so that a pile of 1,000 bodies
        // splits its prepare: at 2 threads its step took 0.94 of the time, its prepare 0.83
        // (interleaved, 16 rounds); 700 bodies 1.00 (prepare 0.90), 500 the same code. Solve
        // at 600 was slower split at 700 bodies (1.33), so it stays (docs/history.md).
        WideThresholds {
            step: 750,
            broad_phase: 120,
            narrow_phase: 630,
            prepare: 600,
            solve: 950,
            finalize: 500,
            solve_by_payoff: true,
        }
    }
}
