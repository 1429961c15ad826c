//! The scene schema: plain serde data that scene files, built-in scenes and code share.
//!
//! This module knows no file format. The edges (the `tumble-scene` crate) parse RON or JSON
//! into these types and report syntax errors with line and column; [`SceneDef::validate`]
//! then checks the values and names the body index and field of anything it refuses.

use serde::{Deserialize, Serialize};

use crate::error::SceneError;

/// Largest polygon a scene may use (Box2D's `B2_MAX_POLYGON_VERTICES`).
pub const MAX_POLYGON_VERTICES: usize = 8;

/// How a body moves.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub enum BodyKind {
    /// Never moves; infinite mass.
    Static,
    /// Moved by forces and contacts.
    #[default]
    Dynamic,
    /// Moves with its set velocity; infinite mass, pushes dynamic bodies.
    Kinematic,
}

/// A body's collision shape, in the body's own frame.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum ShapeDef {
    /// A disc centred on the body.
    Circle {
        /// Radius in metres, > 0.
        radius: f32,
    },
    /// A rectangle centred on the body.
    Box {
        /// Half width and half height in metres, both > 0.
        #[serde(deserialize_with = "pair::one")]
        half_extents: [f32; 2],
    },
    /// A convex polygon, counter-clockwise, 3 to 8 vertices, non-zero area.
    Polygon {
        /// Vertices in the body's frame; the loader recentres them on their centroid.
        #[serde(deserialize_with = "pair::list")]
        vertices: Vec<[f32; 2]>,
    },
}

fn default_density() -> f32 {
    1.0
}
fn default_friction() -> f32 {
    0.6
}

/// One body of a scene. Every field but `shape` has a default (see CONTRACT.md).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodyDef {
    /// Static, dynamic or kinematic.
    #[serde(default)]
    pub kind: BodyKind,
    /// Centre of mass in the world (m).
    #[serde(default, deserialize_with = "pair::one")]
    pub position: [f32; 2],
    /// Orientation (rad, counter-clockwise).
    #[serde(default)]
    pub angle: f32,
    /// Initial velocity of the centre of mass (m/s).
    #[serde(default, deserialize_with = "pair::one")]
    pub linear_velocity: [f32; 2],
    /// Initial angular velocity (rad/s).
    #[serde(default)]
    pub angular_velocity: f32,
    /// Collision shape.
    pub shape: ShapeDef,
    /// Area density (kg/m²), > 0 for a dynamic body.
    #[serde(default = "default_density")]
    pub density: f32,
    /// Coulomb friction coefficient, >= 0; pairs mix as `sqrt(a * b)`.
    #[serde(default = "default_friction")]
    pub friction: f32,
    /// Coefficient of restitution, >= 0; pairs mix as `max(a, b)`.
    #[serde(default)]
    pub restitution: f32,
    /// Linear damping per second of simulated time.
    #[serde(default)]
    pub linear_damping: f32,
    /// Angular damping per second of simulated time.
    #[serde(default)]
    pub angular_damping: f32,
    /// Whether the body may not rotate.
    #[serde(default)]
    pub fixed_rotation: bool,
}

impl BodyDef {
    /// A dynamic body of the given shape at the origin with every other field at its default.
    pub fn new(shape: ShapeDef) -> Self {
        Self {
            kind: BodyKind::Dynamic,
            position: [0.0, 0.0],
            angle: 0.0,
            linear_velocity: [0.0, 0.0],
            angular_velocity: 0.0,
            shape,
            density: default_density(),
            friction: default_friction(),
            restitution: 0.0,
            linear_damping: 0.0,
            angular_damping: 0.0,
            fixed_rotation: false,
        }
    }

    /// Builder: body kind.
    pub fn kind(mut self, kind: BodyKind) -> Self {
        self.kind = kind;
        self
    }
    /// Builder: position.
    pub fn at(mut self, x: f32, y: f32) -> Self {
        self.position = [x, y];
        self
    }
    /// Builder: angle.
    pub fn angle(mut self, angle: f32) -> Self {
        self.angle = angle;
        self
    }
    /// Builder: linear velocity.
    pub fn velocity(mut self, vx: f32, vy: f32) -> Self {
        self.linear_velocity = [vx, vy];
        self
    }
    /// Builder: angular velocity.
    pub fn spin(mut self, w: f32) -> Self {
        self.angular_velocity = w;
        self
    }
    /// Builder: density.
    pub fn density(mut self, density: f32) -> Self {
        self.density = density;
        self
    }
    /// Builder: friction.
    pub fn friction(mut self, friction: f32) -> Self {
        self.friction = friction;
        self
    }
    /// Builder: restitution.
    pub fn restitution(mut self, restitution: f32) -> Self {
        self.restitution = restitution;
        self
    }
    /// Builder: linear and angular damping per second.
    pub fn damping(mut self, linear: f32, angular: f32) -> Self {
        self.linear_damping = linear;
        self.angular_damping = angular;
        self
    }
    /// Builder: fixed rotation.
    pub fn fixed_rotation(mut self, fixed: bool) -> Self {
        self.fixed_rotation = fixed;
        self
    }
}

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
#[serde(deny_unknown_fields)]
pub struct SceneDef {
    /// Shown in the UI and in reports; the loader fills in the file's stem when absent.
    #[serde(default)]
    pub name: String,
    /// Gravity (m/s²).
    #[serde(default = "default_gravity", deserialize_with = "pair::one")]
    pub gravity: [f32; 2],
    /// Seconds per step, > 0.
    #[serde(default = "default_dt")]
    pub dt: f32,
    /// Solver substeps per step, >= 1.
    #[serde(default = "default_substeps")]
    pub substeps: u32,
    /// Length of a headless run when the runner is not told otherwise.
    #[serde(default = "default_steps")]
    pub steps: u32,
    /// The bodies, in id order.
    pub bodies: Vec<BodyDef>,
    /// The solver knobs this scene needs, where it needs other than the engine's defaults
    /// (CONTRACT.md section 5, `solver`).
    #[serde(default, skip_serializing_if = "SolverDef::is_empty")]
    pub solver: SolverDef,
}

/// A scene's `solver` block: every field optional, an absent one keeps the engine's default
/// (Box2D v3's). The joint and sleep fields are accepted, validated and kept for the joints
/// and sleeping that will read them; today's step has neither.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolverDef {
    /// Contact stiffness (Hz, > 0; default 30); contacts against static bodies get twice it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_hertz: Option<f32>,
    /// Damping ratio of the contact spring (>= 0; default 10).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_damping_ratio: Option<f32>,
    /// Rigid relax passes per substep (1 to 64; default 1). Friction is solved in them.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub relax_iterations: Option<u32>,
    /// Approach speed below which nothing bounces (m/s, >= 0; default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub restitution_threshold: Option<f32>,
    /// Restitution passes at the end of a step (1 to 64; default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub restitution_iterations: Option<u32>,
    /// Fastest that overlap is pushed apart (m/s, > 0; default 3).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_push_speed: Option<f32>,
    /// Joint stiffness (Hz, >= 0; default 60). Kept for joints.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub joint_hertz: Option<f32>,
    /// Joint damping ratio (>= 0; default 2). Kept for joints.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub joint_damping_ratio: Option<f32>,
    /// Speed below which a body counts as resting (m/s, >= 0; default 0.05). Kept for
    /// sleeping.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sleep_threshold: Option<f32>,
    /// How long an island rests before it sleeps (s, >= 0; default 0.5). Kept for sleeping.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time_to_sleep: Option<f32>,
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
        self.solver.validate()?;
        for (index, body) in self.bodies.iter().enumerate() {
            validate_body(index, body)?;
        }
        Ok(())
    }
}

/// Limits on untrusted input. Raise them deliberately for huge scenes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// Most bodies a scene may hold.
    pub max_bodies: usize,
    /// Most substeps a scene may ask for.
    pub max_substeps: u32,
}

impl Default for Limits {
    fn default() -> Self {
        Self {
            max_bodies: 200_000,
            max_substeps: 256,
        }
    }
}

/// `[x, y]` pairs read from either a list or a tuple, so RON files may write `(x, y)` (how
/// serde names a fixed array) or `[x, y]` (how the contract writes it); JSON has lists only.
mod pair {
    use serde::de::{Deserializer, Error, SeqAccess, Visitor};
    use std::fmt;

    struct PairVisitor;

    impl<'de> Visitor<'de> for PairVisitor {
        type Value = [f32; 2];

        fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            f.write_str("a pair of numbers, written [x, y] (or (x, y) in RON)")
        }

        fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<[f32; 2], A::Error> {
            let x = seq
                .next_element::<f32>()?
                .ok_or_else(|| A::Error::invalid_length(0, &self))?;
            let y = seq
                .next_element::<f32>()?
                .ok_or_else(|| A::Error::invalid_length(1, &self))?;
            if seq.next_element::<serde::de::IgnoredAny>()?.is_some() {
                return Err(A::Error::invalid_length(3, &self));
            }
            Ok([x, y])
        }
    }

    /// One pair.
    pub fn one<'de, D: Deserializer<'de>>(d: D) -> Result<[f32; 2], D::Error> {
        d.deserialize_any(PairVisitor)
    }

    struct Pair([f32; 2]);

    impl<'de> serde::Deserialize<'de> for Pair {
        fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Pair, D::Error> {
            one(d).map(Pair)
        }
    }

    struct ListVisitor;

    impl<'de> Visitor<'de> for ListVisitor {
        type Value = Vec<[f32; 2]>;

        fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            f.write_str("a list of [x, y] pairs")
        }

        fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
            let mut out = Vec::new();
            while let Some(Pair(p)) = seq.next_element::<Pair>()? {
                // Polygons have at most 8 vertices; stop early on absurd input.
                if out.len() > 1024 {
                    return Err(A::Error::custom("more than 1024 vertices"));
                }
                out.push(p);
            }
            Ok(out)
        }
    }

    /// A list of pairs.
    pub fn list<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<[f32; 2]>, D::Error> {
        d.deserialize_seq(ListVisitor)
    }
}

fn finite2(v: [f32; 2]) -> bool {
    v[0].is_finite() && v[1].is_finite()
}

fn validate_body(index: usize, body: &BodyDef) -> Result<(), SceneError> {
    let err = |field: &str, value: String, allowed: &str| SceneError::Body {
        index,
        field: field.to_string(),
        value,
        allowed: allowed.to_string(),
    };
    if !finite2(body.position) {
        return Err(err(
            "position",
            format!("{:?}", body.position),
            "two finite numbers",
        ));
    }
    if !body.angle.is_finite() {
        return Err(err("angle", body.angle.to_string(), "a finite number"));
    }
    if !finite2(body.linear_velocity) {
        return Err(err(
            "linear_velocity",
            format!("{:?}", body.linear_velocity),
            "two finite numbers",
        ));
    }
    if !body.angular_velocity.is_finite() {
        return Err(err(
            "angular_velocity",
            body.angular_velocity.to_string(),
            "a finite number",
        ));
    }
    let non_negative = |field: &str, v: f32| {
        if v.is_finite() && v >= 0.0 {
            Ok(())
        } else {
            Err(err(field, v.to_string(), "a finite number >= 0"))
        }
    };
    non_negative("friction", body.friction)?;
    non_negative("restitution", body.restitution)?;
    non_negative("linear_damping", body.linear_damping)?;
    non_negative("angular_damping", body.angular_damping)?;
    if !body.density.is_finite() || body.density < 0.0 {
        return Err(err(
            "density",
            body.density.to_string(),
            "a finite number >= 0 (and > 0 for a dynamic body)",
        ));
    }
    if body.kind == BodyKind::Dynamic && body.density <= 0.0 {
        return Err(err(
            "density",
            body.density.to_string(),
            "a finite number > 0 for a dynamic body (only static and kinematic bodies may have zero density)",
        ));
    }
    match &body.shape {
        ShapeDef::Circle { radius } => {
            if !(radius.is_finite() && *radius > 0.0) {
                return Err(err(
                    "shape.Circle.radius",
                    radius.to_string(),
                    "a finite number > 0 (metres)",
                ));
            }
        }
        ShapeDef::Box { half_extents } => {
            if !(finite2(*half_extents) && half_extents[0] > 0.0 && half_extents[1] > 0.0) {
                return Err(err(
                    "shape.Box.half_extents",
                    format!("{half_extents:?}"),
                    "two finite numbers > 0 (half width, half height in metres)",
                ));
            }
        }
        ShapeDef::Polygon { vertices } => {
            crate::shape::Polygon::from_vertices(vertices).map_err(|problem| {
                err(
                    "shape.Polygon.vertices",
                    format!("{vertices:?}"),
                    &format!(
                        "a convex, counter-clockwise polygon of 3 to {MAX_POLYGON_VERTICES} finite vertices with non-zero area ({problem})"
                    ),
                )
            })?;
        }
    }
    // Validation above has checked the polygon, so this cannot fail.
    let Ok(shape) = crate::shape::Shape::from_def(&body.shape) else {
        return Ok(());
    };
    // The world's step works in f32; shapes beyond this scale lose all precision.
    let extent = shape.extent();
    if extent > 1.0e5 {
        return Err(err(
            "shape",
            format!("extent {extent} m"),
            "shapes up to 100 km across",
        ));
    }
    if body.kind == BodyKind::Dynamic {
        // The step divides by the mass and the rotational inertia: each must be a normal f32
        // (not zero, not subnormal, not infinite), or its inverse is infinite or zero and the
        // body's state turns non-finite in its first contact.
        let md = shape.mass(body.density);
        let invertible = |x: f32| x.is_normal() && (1.0 / x).is_normal();
        if !invertible(md.mass) {
            return Err(err(
                "density",
                format!(
                    "{}, which with this shape (area {:e} m²) gives a mass of {:e} kg, which \
                     f32 cannot invert",
                    body.density,
                    md.mass / body.density,
                    md.mass
                ),
                &format!(
                    "a density and size whose mass (density × area) lies between {:e} and {:e} \
                     kg: {} the density or {} the shape",
                    f32::MIN_POSITIVE,
                    1.0 / f32::MIN_POSITIVE,
                    if md.mass.is_finite() {
                        "raise"
                    } else {
                        "lower"
                    },
                    if md.mass.is_finite() {
                        "enlarge"
                    } else {
                        "shrink"
                    },
                ),
            ));
        }
        let rotates = !body.fixed_rotation;
        if rotates && !invertible(md.inertia) {
            return Err(err(
                "shape",
                format!(
                    "of largest radius {extent:e} m, whose rotational inertia at density {} \
                     is {:e} kg·m², which f32 cannot invert",
                    body.density, md.inertia
                ),
                &format!(
                    "a shape and density whose rotational inertia lies between {:e} and {:e} \
                     kg·m²: {}, or set `fixed_rotation: true`",
                    f32::MIN_POSITIVE,
                    1.0 / f32::MIN_POSITIVE,
                    if md.inertia.is_finite() {
                        "enlarge the shape or raise the density"
                    } else {
                        "shrink the shape or lower the density"
                    },
                ),
            ));
        }
    }
    Ok(())
}
