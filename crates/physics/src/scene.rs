//! The scene schema: plain serde data that scene files, built-in scenes and code share. A
//! scene ([`SceneDef`]) holds world settings, its solver block ([`SolverDef`]), its joints and
//! its bodies, whose definitions ([`BodyDef`] and what it is made of) live in `crate::def`.
//!
//! This module knows no file format. The edges (the `tumble-scene` crate) parse RON or JSON
//! into these types and report syntax errors with line and column; [`SceneDef::validate`]
//! then checks the values and names the body index and field of anything it refuses.

use serde::{Deserialize, Serialize};

#[cfg(feature = "schema")]
use crate::def::schema;
use crate::def::{BodyDef, BodyKind, Limits, is_one, is_true, one, pair, too_many_shapes, yes};
use crate::error::SceneError;

fn default_gravity() -> [f32; 2] {
    [0.0, -10.0]
}
fn default_dt() -> f32 {
    1.0 / 60.0
}
fn default_substeps() -> u32 {
    4
}
fn default_steps() -> u32 {
    600
}

/// A scene: world settings and bodies, in order (a body's index is its id).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "schema", schemars(title = "tumble scene"))]
#[serde(deny_unknown_fields)]
pub struct SceneDef {
    /// Shown in the UI and in reports; the loader fills in the file's stem when absent.
    #[serde(default)]
    pub name: String,
    /// Gravity (m/s²).
    #[serde(default = "default_gravity", deserialize_with = "pair::one")]
    #[cfg_attr(feature = "schema", schemars(schema_with = "schema::pair"))]
    pub gravity: [f32; 2],
    /// Seconds per step, > 0.
    #[serde(default = "default_dt")]
    #[cfg_attr(feature = "schema", schemars(extend("exclusiveMinimum" = 0)))]
    pub dt: f32,
    /// Solver substeps per step, >= 1.
    #[serde(default = "default_substeps")]
    #[cfg_attr(feature = "schema", schemars(range(min = 1)))]
    pub substeps: u32,
    /// Length of a headless run when the runner is not told otherwise.
    #[serde(default = "default_steps")]
    pub steps: u32,
    /// The bodies, in id order.
    pub bodies: Vec<BodyDef>,
    /// The solver knobs this scene needs, where it needs other than the engine's defaults
    /// (CONTRACT.md section 5, `solver`).
    #[serde(default, skip_serializing_if = "SolverDef::is_empty")]
    #[cfg_attr(feature = "schema", schemars(extend("default" = {})))]
    pub solver: SolverDef,
    /// Bodies that rest fall asleep with their island and cost nothing until woken.
    #[serde(default = "yes")]
    pub sleep: bool,
    /// Continuous collision ([`crate::StepSettings::continuous`]).
    #[serde(default = "yes", skip_serializing_if = "is_true")]
    #[cfg_attr(feature = "schema", schemars(extend("default" = true)))]
    pub continuous: bool,
    /// Least approach speed of a `hit` event (m/s, >= 0; see [`crate::Event::Hit`]).
    #[serde(default = "one", skip_serializing_if = "is_one")]
    #[cfg_attr(feature = "schema", schemars(extend("default" = 1.0)))]
    pub hit_speed: f32,
    /// Joints between the bodies, in id order; anchors and axes in world coordinates at
    /// the poses the scene starts with.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub joints: Vec<crate::joint::JointDef>,
}

/// A scene's `solver` block: every field optional, an absent one keeps the engine's default
/// (Box2D v3's).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct SolverDef {
    /// Contact stiffness (Hz, > 0; default 30); contacts against static bodies get twice it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "schema", schemars(extend("exclusiveMinimum" = 0)))]
    pub contact_hertz: Option<f32>,
    /// Damping ratio of the contact spring (>= 0; default 10).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "schema", schemars(range(min = 0)))]
    pub contact_damping_ratio: Option<f32>,
    /// Rigid relax passes per substep (1 to 64; default 1). Friction is solved in them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "schema", schemars(range(min = 1, max = MAX_SOLVER_PASSES)))]
    pub relax_iterations: Option<u32>,
    /// Approach speed below which nothing bounces (m/s, >= 0; default 1): with
    /// `impacts_bounce`, nothing already pushing.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "schema", schemars(range(min = 0)))]
    pub restitution_threshold: Option<f32>,
    /// Restitution passes at the end of a step (1 to 64; default 1): exactly these with
    /// `impacts_bounce` false, else until the bounces hold, at most this or 16 and within
    /// a budget of visits (about twice the contacts that bounce).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "schema", schemars(range(min = 1, max = MAX_SOLVER_PASSES)))]
    pub restitution_iterations: Option<u32>,
    /// Fastest that overlap is pushed apart (m/s, > 0; default 3).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "schema", schemars(extend("exclusiveMinimum" = 0)))]
    pub max_push_speed: Option<f32>,
    /// Joint stiffness (Hz, >= 0; default 60; 0 is rigid).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "schema", schemars(range(min = 0)))]
    pub joint_hertz: Option<f32>,
    /// Joint damping ratio (>= 0; default 2).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "schema", schemars(range(min = 0)))]
    pub joint_damping_ratio: Option<f32>,
    /// Speed below which a body counts as resting (m/s, >= 0; default 0.05).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "schema", schemars(range(min = 0)))]
    pub sleep_threshold: Option<f32>,
    /// How long an island rests before it sleeps (s, >= 0; default 0.5).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "schema", schemars(range(min = 0)))]
    pub time_to_sleep: Option<f32>,
    /// Solve a manifold's two points together where they are well apart, so that a body
    /// dropped flat lands straight (default true; false: one after the other, as Box2D v3).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub solve_points_together: Option<bool>,
    /// Impacts bounce as their restitution says: the restitution threshold applies only to
    /// contacts already pushing, and the restitution passes repeat until the bounces hold
    /// (default true; false: Box2D v3's rule, the threshold for every contact and exactly
    /// `restitution_iterations` passes).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub impacts_bounce: Option<bool>,
}

/// Most relax or restitution passes a scene may ask for: each is a full pass over every
/// contact, so 64 already costs 64 times the default's solve.
pub const MAX_SOLVER_PASSES: u32 = 64;

impl SolverDef {
    /// Whether no field is set.
    pub fn is_empty(&self) -> bool {
        *self == SolverDef::default()
    }

    /// Sets the fields this block gives on `settings`, leaving the others as they are.
    pub fn apply(&self, settings: &mut crate::StepSettings) {
        fn set<T: Copy>(field: &mut T, value: Option<T>) {
            if let Some(v) = value {
                *field = v;
            }
        }
        set(&mut settings.contact_hertz, self.contact_hertz);
        set(
            &mut settings.contact_damping_ratio,
            self.contact_damping_ratio,
        );
        set(
            &mut settings.restitution_threshold,
            self.restitution_threshold,
        );
        set(&mut settings.max_push_speed, self.max_push_speed);
        set(&mut settings.relax_iterations, self.relax_iterations);
        set(
            &mut settings.restitution_iterations,
            self.restitution_iterations,
        );
        set(&mut settings.sleep_threshold, self.sleep_threshold);
        set(&mut settings.time_to_sleep, self.time_to_sleep);
        set(&mut settings.joint_hertz, self.joint_hertz);
        set(&mut settings.joint_damping_ratio, self.joint_damping_ratio);
        set(
            &mut settings.solve_points_together,
            self.solve_points_together,
        );
        set(&mut settings.impacts_bounce, self.impacts_bounce);
    }

    /// Checks each given field; the error names it as `solver.<field>`.
    pub fn validate(&self) -> Result<(), SceneError> {
        let err = |field: &str, value: String, allowed: &str| SceneError::Scene {
            field: format!("solver.{field}"),
            value,
            allowed: allowed.to_string(),
        };
        let number = |field: &str, value: Option<f32>, zero_ok: bool, what: &str| match value {
            Some(v) if !(v.is_finite() && (v > 0.0 || (zero_ok && v == 0.0))) => Err(err(
                field,
                v.to_string(),
                &format!(
                    "a finite number {} ({what}), or leave it out for the default",
                    if zero_ok { ">= 0" } else { "> 0" }
                ),
            )),
            _ => Ok(()),
        };
        number(
            "contact_hertz",
            self.contact_hertz,
            false,
            "Hz; 0 would switch the soft contact off",
        )?;
        number(
            "contact_damping_ratio",
            self.contact_damping_ratio,
            true,
            "10 is Box2D's",
        )?;
        number(
            "restitution_threshold",
            self.restitution_threshold,
            true,
            "m/s",
        )?;
        number("max_push_speed", self.max_push_speed, false, "m/s")?;
        number("joint_hertz", self.joint_hertz, true, "Hz; 0 is rigid")?;
        number(
            "joint_damping_ratio",
            self.joint_damping_ratio,
            true,
            "2 is Box2D's",
        )?;
        number("sleep_threshold", self.sleep_threshold, true, "m/s")?;
        number("time_to_sleep", self.time_to_sleep, true, "seconds")?;
        let passes = |field: &str, value: Option<u32>, why: &str| match value {
            Some(n) if n == 0 || n > MAX_SOLVER_PASSES => Err(err(
                field,
                n.to_string(),
                &format!("an integer from 1 to {MAX_SOLVER_PASSES} ({why})"),
            )),
            _ => Ok(()),
        };
        passes(
            "relax_iterations",
            self.relax_iterations,
            "friction is solved in the relax passes, so 0 would remove it",
        )?;
        passes(
            "restitution_iterations",
            self.restitution_iterations,
            "0 would stop every bounce",
        )?;
        Ok(())
    }
}

impl SceneDef {
    /// An empty scene with the contract's defaults.
    pub fn new(name: impl Into<String>) -> Self {
        Self {
            name: name.into(),
            gravity: default_gravity(),
            dt: default_dt(),
            substeps: default_substeps(),
            steps: default_steps(),
            bodies: Vec::new(),
            solver: SolverDef::default(),
            sleep: true,
            continuous: true,
            hit_speed: 1.0,
            joints: Vec::new(),
        }
    }

    /// Appends a body and returns its id (index).
    pub fn push(&mut self, body: BodyDef) -> usize {
        self.bodies.push(body);
        self.bodies.len() - 1
    }

    /// Checks every value the schema cannot express; the error names the field and body index.
    pub fn validate(&self, limits: &Limits) -> Result<(), SceneError> {
        let scene_err = |field: &str, value: String, allowed: &str| SceneError::Scene {
            field: field.to_string(),
            value,
            allowed: allowed.to_string(),
        };
        if !(self.gravity[0].is_finite() && self.gravity[1].is_finite()) {
            return Err(scene_err(
                "gravity",
                format!("{:?}", self.gravity),
                "two finite numbers",
            ));
        }
        if !(self.dt.is_finite() && self.dt > 0.0) {
            return Err(scene_err(
                "dt",
                self.dt.to_string(),
                "a finite number > 0 (seconds per step)",
            ));
        }
        if !self.dt.is_normal() {
            return Err(scene_err(
                "dt",
                format!("{:e} (a subnormal f32, which the step refuses)", self.dt),
                &format!(
                    "a finite number > 0 of at least {:e} seconds per step (1/60 is usual)",
                    f32::MIN_POSITIVE
                ),
            ));
        }
        if !(self.hit_speed.is_finite() && self.hit_speed >= 0.0) {
            return Err(scene_err(
                "hit_speed",
                self.hit_speed.to_string(),
                "a finite number >= 0 (m/s; a contact beginning at least this fast is a hit \
                 event; the default is 1)",
            ));
        }
        if self.substeps == 0 || self.substeps > limits.max_substeps {
            return Err(scene_err(
                "substeps",
                self.substeps.to_string(),
                &format!("an integer from 1 to {}", limits.max_substeps),
            ));
        }
        if !(self.dt / self.substeps as f32).is_normal() {
            return Err(scene_err(
                "dt",
                format!(
                    "{:e}, which makes a substep of dt / {} = {:e} s (a subnormal f32, whose \
                     inverse overflows; the step refuses it)",
                    self.dt,
                    self.substeps,
                    self.dt / self.substeps as f32
                ),
                &format!(
                    "a dt of at least {:e} s for {} substeps (1/60 is usual), or fewer substeps",
                    f32::MIN_POSITIVE * self.substeps as f32,
                    self.substeps
                ),
            ));
        }
        if self.bodies.len() > limits.max_bodies {
            return Err(SceneError::TooManyBodies {
                count: self.bodies.len(),
                max: limits.max_bodies,
            });
        }
        // A shape costs the step what a body of one shape does: the body limit bounds the
        // shapes of all bodies too (a few bodies of a million parts each are refused).
        // A chain is one shape per segment.
        let shapes: usize = self.bodies.iter().map(BodyDef::shape_count).sum();
        if shapes > limits.max_bodies {
            return Err(too_many_shapes(shapes, limits));
        }
        self.solver.validate()?;
        for (index, body) in self.bodies.iter().enumerate() {
            body.validate(index, limits)?;
        }
        // A joint costs the step about what a contact does: the body limit bounds them too.
        if self.joints.len() > limits.max_bodies {
            return Err(scene_err(
                "joints",
                format!("{} joints", self.joints.len()),
                &format!(
                    "at most {} joints, the body limit; raise it (runner flag --max-bodies) if \
                     you mean it",
                    limits.max_bodies
                ),
            ));
        }
        // A scene's joints name its bodies by index: generation 0.
        let frames = |id: crate::BodyId| {
            let body = (id.generation == 0).then(|| self.bodies.get(id.index as usize));
            body.flatten().map(|b| crate::joint::def::JointFrame {
                frame: crate::Transform {
                    p: glam::Vec2::from(b.position),
                    q: crate::Rot::from_angle(b.angle),
                },
                dynamic: b.kind == BodyKind::Dynamic,
            })
        };
        for (index, joint) in self.joints.iter().enumerate() {
            joint.validate(index, &frames)?;
        }
        Ok(())
    }
}

/// The JSON Schema (draft 2020-12) of a scene file: what [`SceneDef`]'s loader accepts, with
/// each field's default and description, and the ranges [`SceneDef::validate`] checks where a
/// schema can say them simply. `tumble-bench schema` prints it; docs/scene.schema.json is it.
#[cfg(feature = "schema")]
pub fn scene_schema() -> schemars::Schema {
    let mut schema = schemars::schema_for!(SceneDef);
    if let Some(object) = schema.as_object_mut() {
        for value in object.values_mut() {
            schema::short_defaults(value, false);
        }
    }
    schema
}
