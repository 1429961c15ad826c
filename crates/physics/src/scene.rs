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
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
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
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub enum ShapeDef {
    /// A disc centred on the body.
    Circle {
        /// Radius in metres, > 0.
        #[cfg_attr(feature = "schema", schemars(extend("exclusiveMinimum" = 0)))]
        radius: f32,
    },
    /// A rectangle centred on the body, rounded by `radius`.
    Box {
        /// Half width and half height in metres, both > 0.
        #[serde(deserialize_with = "pair::one")]
        #[cfg_attr(feature = "schema", schemars(schema_with = "schema::positive_pair"))]
        half_extents: [f32; 2],
        /// Rounding radius (m, >= 0): the shape is every point within it of the rectangle.
        #[serde(default, skip_serializing_if = "is_zero")]
        #[cfg_attr(feature = "schema", schemars(range(min = 0)))]
        radius: f32,
    },
    /// A convex polygon, counter-clockwise, 3 to 8 vertices, non-zero area, rounded by
    /// `radius`.
    Polygon {
        /// Vertices in the body's frame; the loader recentres them on their centroid.
        #[serde(deserialize_with = "pair::list")]
        #[cfg_attr(feature = "schema", schemars(schema_with = "schema::polygon"))]
        vertices: Vec<[f32; 2]>,
        /// Rounding radius (m, >= 0).
        #[serde(default, skip_serializing_if = "is_zero")]
        #[cfg_attr(feature = "schema", schemars(range(min = 0)))]
        radius: f32,
    },
    /// Every point within `radius` of the segment between two centres; the loader recentres
    /// it on their midpoint.
    Capsule {
        /// One end of the core segment (m).
        #[serde(deserialize_with = "pair::one")]
        #[cfg_attr(feature = "schema", schemars(schema_with = "schema::pair"))]
        center1: [f32; 2],
        /// The other end, apart from the first.
        #[serde(deserialize_with = "pair::one")]
        #[cfg_attr(feature = "schema", schemars(schema_with = "schema::pair"))]
        center2: [f32; 2],
        /// Radius (m), > 0.
        #[cfg_attr(feature = "schema", schemars(extend("exclusiveMinimum" = 0)))]
        radius: f32,
    },
    /// A two-sided line segment, without area (no mass), in the body's frame as given.
    Segment {
        /// One end (m).
        #[serde(deserialize_with = "pair::one")]
        #[cfg_attr(feature = "schema", schemars(schema_with = "schema::pair"))]
        point1: [f32; 2],
        /// The other end, apart from the first.
        #[serde(deserialize_with = "pair::one")]
        #[cfg_attr(feature = "schema", schemars(schema_with = "schema::pair"))]
        point2: [f32; 2],
    },
    /// A chain of one-sided segments, without area (no mass): each pushes towards its
    /// right-hand side, so a loop that keeps things inside runs clockwise. An open chain's
    /// first and last points only shape its end segments (Box2D's ghost vertices); a loop of
    /// n points has n segments.
    Chain {
        /// At least 4 points, consecutive ones apart (m).
        #[serde(deserialize_with = "pair::list")]
        #[cfg_attr(feature = "schema", schemars(schema_with = "schema::chain"))]
        points: Vec<[f32; 2]>,
        /// Whether the last point joins the first.
        #[serde(rename = "loop", default, skip_serializing_if = "is_false")]
        #[cfg_attr(feature = "schema", schemars(extend("default" = false)))]
        looped: bool,
    },
}

impl ShapeDef {
    /// Whether the shape has area (and so can give a body mass).
    pub fn has_area(&self) -> bool {
        !matches!(self, ShapeDef::Segment { .. } | ShapeDef::Chain { .. })
    }
}

fn is_zero(x: &f32) -> bool {
    *x == 0.0
}

fn default_density() -> f32 {
    1.0
}
fn default_friction() -> f32 {
    0.6
}
/// A field that is `Some` when present, written without RON's `Some(..)`.
fn present<'de, D: serde::Deserializer<'de>, T: Deserialize<'de>>(
    d: D,
) -> Result<Option<T>, D::Error> {
    T::deserialize(d).map(Some)
}

fn yes() -> bool {
    true
}
fn is_true(b: &bool) -> bool {
    *b
}
fn is_false(b: &bool) -> bool {
    !*b
}
fn one() -> f32 {
    1.0
}
fn is_one(x: &f32) -> bool {
    *x == 1.0
}

/// Which shapes may touch (CONTRACT.md section 5, Box2D's rule): two shapes touch when each
/// one's `category` meets the other's `mask`, except that two shapes of the same non-zero
/// `group` always touch when it is positive and never when it is negative.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct Filter {
    /// The categories this shape belongs to (bits).
    #[serde(default = "Filter::default_category")]
    pub category: u64,
    /// The categories this shape touches (bits).
    #[serde(default = "Filter::default_mask")]
    pub mask: u64,
    /// Shapes of one non-zero group always touch (positive) or never do (negative).
    #[serde(default)]
    pub group: i64,
}

impl Filter {
    fn default_category() -> u64 {
        1
    }
    fn default_mask() -> u64 {
        u64::MAX
    }

    /// Whether shapes with these filters may touch (Box2D's `b2ShouldShapesCollide`).
    #[inline]
    pub fn should_collide(&self, other: &Filter) -> bool {
        if self.group == other.group && self.group != 0 {
            return self.group > 0;
        }
        (self.category & other.mask) != 0 && (other.category & self.mask) != 0
    }

    /// Whether this is the default filter (category 1, mask all, group 0).
    pub fn is_default(&self) -> bool {
        *self == Filter::default()
    }
}

impl Default for Filter {
    fn default() -> Self {
        Filter {
            category: 1,
            mask: u64::MAX,
            group: 0,
        }
    }
}

/// One shape of a body of several (`shapes`), placed in the body's frame. Only `shape` is
/// required; the material and filter fields default to the body's.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(deny_unknown_fields)]
pub struct PartDef {
    /// The shape, in the part's frame (a polygon is not recentred: its vertices are where
    /// they are in that frame).
    pub shape: ShapeDef,
    /// Where the part's frame sits in the body's frame (m).
    #[serde(default, deserialize_with = "pair::one")]
    #[cfg_attr(feature = "schema", schemars(schema_with = "schema::pair"))]
    pub offset: [f32; 2],
    /// The part frame's angle in the body's frame (rad).
    #[serde(default)]
    pub angle: f32,
    /// Area density (kg/m²); the body's when absent.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "present"
    )]
    #[cfg_attr(feature = "schema", schemars(range(min = 0)))]
    pub density: Option<f32>,
    /// Friction; the body's when absent.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "present"
    )]
    #[cfg_attr(feature = "schema", schemars(range(min = 0)))]
    pub friction: Option<f32>,
    /// Restitution; the body's when absent.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "present"
    )]
    #[cfg_attr(feature = "schema", schemars(range(min = 0)))]
    pub restitution: Option<f32>,
    /// Filter; the body's when absent.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "present"
    )]
    pub filter: Option<Filter>,
    /// A sensor detects overlaps ([`crate::Event::SensorBegin`] and `SensorEnd`) and never
    /// pushes anything.
    #[serde(default, skip_serializing_if = "is_false")]
    #[cfg_attr(feature = "schema", schemars(extend("default" = false)))]
    pub sensor: bool,
}

impl PartDef {
    /// A part of this shape at the body's origin, with the body's material.
    pub fn new(shape: ShapeDef) -> PartDef {
        PartDef {
            shape,
            offset: [0.0, 0.0],
            angle: 0.0,
            density: None,
            friction: None,
            restitution: None,
            filter: None,
            sensor: false,
        }
    }
    /// Builder: offset and angle in the body's frame.
    pub fn at(mut self, x: f32, y: f32, angle: f32) -> PartDef {
        self.offset = [x, y];
        self.angle = angle;
        self
    }
    /// Builder: density.
    pub fn density(mut self, density: f32) -> PartDef {
        self.density = Some(density);
        self
    }
    /// Builder: filter.
    pub fn filter(mut self, filter: Filter) -> PartDef {
        self.filter = Some(filter);
        self
    }
    /// Builder: a sensor (see [`PartDef::sensor`]'s field).
    pub fn sensor(mut self, sensor: bool) -> PartDef {
        self.sensor = sensor;
        self
    }
}

/// A part with every default resolved: what the world builds a shape from.
#[derive(Clone, Debug, PartialEq)]
pub struct ResolvedPart<'a> {
    /// The shape in the part's frame.
    pub shape: &'a ShapeDef,
    /// Offset in the body's frame.
    pub offset: [f32; 2],
    /// Angle in the body's frame.
    pub angle: f32,
    /// Density.
    pub density: f32,
    /// Friction.
    pub friction: f32,
    /// Restitution.
    pub restitution: f32,
    /// Filter.
    pub filter: Filter,
    /// Sensor.
    pub sensor: bool,
    /// Whether the part comes from `shape` (a body of one shape: a polygon is recentred and
    /// the body's position is its centre of mass) rather than from `shapes`.
    pub single: bool,
}

/// One body of a scene. Every field but the shape has a default (see CONTRACT.md); a body
/// has exactly one of `shape` and `shapes`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[cfg_attr(feature = "schema", schemars(transform = schema::shape_or_shapes))]
#[serde(deny_unknown_fields)]
pub struct BodyDef {
    /// Static, dynamic or kinematic.
    #[serde(default)]
    pub kind: BodyKind,
    /// With `shape`: the centre of mass in the world. With `shapes`: the body frame's origin
    /// (m).
    #[serde(default, deserialize_with = "pair::one")]
    #[cfg_attr(feature = "schema", schemars(schema_with = "schema::pair"))]
    pub position: [f32; 2],
    /// Orientation (rad, counter-clockwise).
    #[serde(default)]
    pub angle: f32,
    /// Initial velocity of the centre of mass (m/s).
    #[serde(default, deserialize_with = "pair::one")]
    #[cfg_attr(feature = "schema", schemars(schema_with = "schema::pair"))]
    pub linear_velocity: [f32; 2],
    /// Initial angular velocity (rad/s).
    #[serde(default)]
    pub angular_velocity: f32,
    /// Collision shape (a body of one shape). Written as the shape itself, not `Some(..)`.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "present"
    )]
    #[cfg_attr(feature = "schema", schemars(with = "ShapeDef"))]
    pub shape: Option<ShapeDef>,
    /// Several shapes fixed to the body, instead of `shape`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    #[cfg_attr(feature = "schema", schemars(extend("default" = [])))]
    pub shapes: Vec<PartDef>,
    /// Area density (kg/m²), > 0 for a dynamic body.
    #[serde(default = "default_density")]
    #[cfg_attr(feature = "schema", schemars(range(min = 0)))]
    pub density: f32,
    /// Coulomb friction coefficient, >= 0; pairs mix as `sqrt(a * b)`.
    #[serde(default = "default_friction")]
    #[cfg_attr(feature = "schema", schemars(range(min = 0)))]
    pub friction: f32,
    /// Coefficient of restitution, >= 0; pairs mix as `max(a, b)`.
    #[serde(default)]
    #[cfg_attr(feature = "schema", schemars(range(min = 0)))]
    pub restitution: f32,
    /// Linear damping per second of simulated time.
    #[serde(default)]
    #[cfg_attr(feature = "schema", schemars(range(min = 0)))]
    pub linear_damping: f32,
    /// Angular damping per second of simulated time.
    #[serde(default)]
    #[cfg_attr(feature = "schema", schemars(range(min = 0)))]
    pub angular_damping: f32,
    /// Whether the body may not rotate.
    #[serde(default)]
    pub fixed_rotation: bool,
    /// `false`: the body starts asleep (when the scene's `sleep` is on).
    #[serde(default = "yes", skip_serializing_if = "is_true")]
    #[cfg_attr(feature = "schema", schemars(extend("default" = true)))]
    pub awake: bool,
    /// `false`: this body never sleeps, nor does its island.
    #[serde(default = "yes", skip_serializing_if = "is_true")]
    #[cfg_attr(feature = "schema", schemars(extend("default" = true)))]
    pub enable_sleep: bool,
    /// A dynamic body that never passes through other dynamic bodies either: its pairs with
    /// moving bodies are found by its swept box, as every body's are with static ones
    /// ([`World::set_bullet`](crate::World::set_bullet)). Time of impact is not built yet.
    #[serde(default, skip_serializing_if = "is_false")]
    #[cfg_attr(feature = "schema", schemars(extend("default" = false)))]
    pub bullet: bool,
    /// Multiplies gravity for this body.
    #[serde(default = "one", skip_serializing_if = "is_one")]
    #[cfg_attr(feature = "schema", schemars(extend("default" = 1.0)))]
    pub gravity_scale: f32,
    /// Which shapes this body's shapes touch (each part may override it).
    #[serde(default, skip_serializing_if = "Filter::is_default")]
    #[cfg_attr(feature = "schema", schemars(extend("default" = { "category": 1, "mask": u64::MAX, "group": 0 })))]
    pub filter: Filter,
}

impl BodyDef {
    /// A dynamic body of the given shape at the origin with every other field at its default.
    pub fn new(shape: ShapeDef) -> Self {
        Self {
            shape: Some(shape),
            ..Self::compound(Vec::new())
        }
    }

    /// A dynamic body of several parts at the origin with every other field at its default.
    pub fn compound(parts: Vec<PartDef>) -> Self {
        Self {
            kind: BodyKind::Dynamic,
            position: [0.0, 0.0],
            angle: 0.0,
            linear_velocity: [0.0, 0.0],
            angular_velocity: 0.0,
            shape: None,
            shapes: parts,
            density: default_density(),
            friction: default_friction(),
            restitution: 0.0,
            linear_damping: 0.0,
            angular_damping: 0.0,
            fixed_rotation: false,
            awake: true,
            enable_sleep: true,
            bullet: false,
            gravity_scale: 1.0,
            filter: Filter::default(),
        }
    }

    /// The body's parts with the body's defaults filled in: its `shape` as one part at its
    /// origin, or each of `shapes`.
    pub fn parts(&self) -> Vec<ResolvedPart<'_>> {
        if let Some(shape) = &self.shape {
            return vec![ResolvedPart {
                shape,
                offset: [0.0, 0.0],
                angle: 0.0,
                density: self.density,
                friction: self.friction,
                restitution: self.restitution,
                filter: self.filter,
                sensor: false,
                single: true,
            }];
        }
        self.shapes
            .iter()
            .map(|p| ResolvedPart {
                shape: &p.shape,
                offset: p.offset,
                angle: p.angle,
                density: p.density.unwrap_or(self.density),
                friction: p.friction.unwrap_or(self.friction),
                restitution: p.restitution.unwrap_or(self.restitution),
                filter: p.filter.unwrap_or(self.filter),
                sensor: p.sensor,
                single: false,
            })
            .collect()
    }

    /// The shape of a body of one shape, or the first part's.
    pub fn first_shape(&self) -> Option<&ShapeDef> {
        self.shape
            .as_ref()
            .or_else(|| self.shapes.first().map(|p| &p.shape))
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
    /// Builder: starts awake or asleep.
    pub fn awake(mut self, awake: bool) -> Self {
        self.awake = awake;
        self
    }
    /// Builder: filter of every part.
    pub fn filter(mut self, filter: Filter) -> Self {
        self.filter = filter;
        self
    }
    /// Builder: gravity scale.
    pub fn gravity_scale(mut self, scale: f32) -> Self {
        self.gravity_scale = scale;
        self
    }
    /// Builder: a bullet (see [`BodyDef::bullet`]).
    pub fn bullet(mut self, bullet: bool) -> Self {
        self.bullet = bullet;
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
    /// Approach speed below which nothing bounces (m/s, >= 0; default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[cfg_attr(feature = "schema", schemars(range(min = 0)))]
    pub restitution_threshold: Option<f32>,
    /// Restitution passes at the end of a step (1 to 64; default 1).
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
        let part_shapes = |shape: &ShapeDef| match shape {
            ShapeDef::Chain { points, .. } => points.len().max(1),
            _ => 1,
        };
        let shapes: usize = self
            .bodies
            .iter()
            .map(|b| {
                b.shape.as_ref().map_or(0, part_shapes)
                    + b.shapes
                        .iter()
                        .map(|p| part_shapes(&p.shape))
                        .sum::<usize>()
            })
            .sum();
        if shapes > limits.max_bodies {
            return Err(scene_err(
                "bodies",
                format!("{shapes} shapes in all (the parts of its bodies)"),
                &format!(
                    "at most {} shapes, the body limit; raise it (runner flag --max-bodies) if \
                     you mean it",
                    limits.max_bodies
                ),
            ));
        }
        self.solver.validate()?;
        for (index, body) in self.bodies.iter().enumerate() {
            validate_body(index, body)?;
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

    /// Most points one list may hold.
    const MAX_LIST: usize = 100_000;

    struct ListVisitor;

    impl<'de> Visitor<'de> for ListVisitor {
        type Value = Vec<[f32; 2]>;

        fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            f.write_str("a list of [x, y] pairs")
        }

        fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
            let mut out = Vec::new();
            while let Some(Pair(p)) = seq.next_element::<Pair>()? {
                // Polygons have at most 8 vertices and chains rarely thousands of points;
                // stop early on absurd input.
                if out.len() >= MAX_LIST {
                    return Err(A::Error::custom(format!(
                        "more than {MAX_LIST} points (split the chain)"
                    )));
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

/// What the loader's own deserializers (`pair`, `present`) accept, for `schemars`.
#[cfg(feature = "schema")]
mod schema {
    use std::borrow::Cow;

    use schemars::{JsonSchema, Schema, SchemaGenerator, json_schema};
    use serde_json::json;

    use super::MAX_POLYGON_VERTICES;

    /// `pair::one`: `[x, y]`, a list of exactly two numbers (one `$defs` entry, `Pair`).
    struct Pair;

    impl JsonSchema for Pair {
        fn schema_name() -> Cow<'static, str> {
            "Pair".into()
        }

        fn json_schema(_: &mut SchemaGenerator) -> Schema {
            json_schema!({
                "description": "`[x, y]`: a list of exactly two numbers.",
                "type": "array",
                "items": { "type": "number" },
                "minItems": 2,
                "maxItems": 2
            })
        }
    }

    /// A field read by `pair::one`.
    pub fn pair(generator: &mut SchemaGenerator) -> Schema {
        generator.subschema_for::<Pair>()
    }

    /// A box's half extents: a pair of numbers > 0.
    pub fn positive_pair(_: &mut SchemaGenerator) -> Schema {
        json_schema!({
            "type": "array",
            "items": { "type": "number", "exclusiveMinimum": 0 },
            "minItems": 2,
            "maxItems": 2
        })
    }

    /// A chain's points (`pair::list`): at least 4 pairs.
    pub fn chain(generator: &mut SchemaGenerator) -> Schema {
        json_schema!({
            "type": "array",
            "items": pair(generator),
            "minItems": 4
        })
    }

    /// A polygon's vertices (`pair::list`): 3 to 8 pairs.
    pub fn polygon(generator: &mut SchemaGenerator) -> Schema {
        json_schema!({
            "type": "array",
            "items": pair(generator),
            "minItems": 3,
            "maxItems": MAX_POLYGON_VERTICES
        })
    }

    /// Writes each number in a `default` as its `f32`'s shortest form (`0.016666668`, not
    /// the `0.01666666753590107` that widening it to `f64` gives), so it reads back to the
    /// same `f32`.
    pub fn short_defaults(value: &mut serde_json::Value, in_default: bool) {
        use serde_json::Value;
        match value {
            Value::Number(n) if in_default => {
                if let Some(x) = n.as_f64().filter(|_| n.is_f64()) {
                    let single = x as f32;
                    if f64::from(single) == x
                        && let Ok(short) = single.to_string().parse::<f64>()
                        && let Some(short) = serde_json::Number::from_f64(short)
                    {
                        *n = short;
                    }
                }
            }
            Value::Array(items) => {
                for item in items {
                    short_defaults(item, in_default);
                }
            }
            Value::Object(map) => {
                for (key, item) in map.iter_mut() {
                    short_defaults(item, in_default || key == "default");
                }
            }
            _ => {}
        }
    }

    /// A body has exactly one of `shape` and a non-empty `shapes` (an empty `shapes` beside
    /// `shape` is allowed, as the loader allows it).
    pub fn shape_or_shapes(schema: &mut Schema) {
        schema.insert(
            "oneOf".into(),
            json!([
                {
                    "required": ["shape"],
                    "properties": { "shapes": { "maxItems": 0 } }
                },
                {
                    "required": ["shapes"],
                    "not": { "required": ["shape"] },
                    "properties": { "shapes": { "minItems": 1 } }
                }
            ]),
        );
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
    if body.kind == BodyKind::Dynamic && body.shape.is_some() && body.density <= 0.0 {
        return Err(err(
            "density",
            body.density.to_string(),
            "a finite number > 0 for a dynamic body (only static and kinematic bodies may have zero density)",
        ));
    }
    if !body.gravity_scale.is_finite() {
        return Err(err(
            "gravity_scale",
            body.gravity_scale.to_string(),
            "a finite number (1 is ordinary gravity)",
        ));
    }
    match (&body.shape, body.shapes.is_empty()) {
        (Some(_), false) => {
            return Err(err(
                "shapes",
                format!("{} parts beside `shape`", body.shapes.len()),
                "exactly one of `shape` (one shape) and `shapes` (a list of parts): remove one",
            ));
        }
        (None, true) => {
            return Err(err(
                "shape",
                "missing".into(),
                "exactly one of `shape` (one shape) and `shapes` (a non-empty list of parts)",
            ));
        }
        _ => {}
    }
    let parts = body.parts();
    for (k, part) in parts.iter().enumerate() {
        let prefix = if part.single {
            String::new()
        } else {
            format!("shapes[{k}].")
        };
        let field = |name: &str| format!("{prefix}{name}");
        validate_shape(part.shape, &field("shape"), &err)?;
        if !part.single {
            if !finite2(part.offset) {
                return Err(err(
                    &field("offset"),
                    format!("{:?}", part.offset),
                    "two finite numbers (m, in the body's frame)",
                ));
            }
            if !part.angle.is_finite() {
                return Err(err(
                    &field("angle"),
                    part.angle.to_string(),
                    "a finite number",
                ));
            }
            for (name, v) in [
                ("density", part.density),
                ("friction", part.friction),
                ("restitution", part.restitution),
            ] {
                if !(v.is_finite() && v >= 0.0) {
                    return Err(err(&field(name), v.to_string(), "a finite number >= 0"));
                }
            }
        }
        // Validation above has checked the geometry, so this cannot fail.
        let Ok(shapes) = crate::body::part_geometry(part) else {
            return Ok(());
        };
        // The world's step works in f32; shapes beyond this scale lose all precision. A
        // part's reach from the body's origin counts (its offset and, for a polygon given
        // away from its frame, its centroid).
        for (shape, local) in &shapes {
            let extent = shape.extent() + local.p.length();
            if extent > 1.0e5 {
                return Err(err(
                    &field("shape"),
                    format!("extent {extent} m"),
                    "shapes up to 100 km across",
                ));
            }
        }
    }
    if body.kind != BodyKind::Dynamic {
        return Ok(());
    }
    if !parts.iter().any(|p| p.shape.has_area()) {
        return Err(err(
            if body.shape.is_some() {
                "shape"
            } else {
                "shapes"
            },
            "segments and chains only".into(),
            "at least one part with area (Circle, Box, Polygon or Capsule) on a dynamic body: segments and chains give no mass",
        ));
    }
    let md = crate::body::BodyMass::of_def(body);
    let extent = md.extent;
    if parts.iter().all(|p| p.density == 0.0) {
        return Err(err(
            "density",
            "0 for every part".into(),
            "a finite number > 0 for at least one part of a dynamic body",
        ));
    }
    // The step divides by the mass and the rotational inertia: each must be a normal f32
    // (not zero, not subnormal, not infinite), or its inverse is infinite or zero and the
    // body's state turns non-finite in its first contact.
    let invertible = crate::body::BodyMass::invertible;
    {
        if !invertible(md.mass) {
            return Err(err(
                "density",
                format!(
                    "{}, which with this shape (area {:e} m²) gives a mass of {:e} kg, which \
                     f32 cannot invert",
                    body.density, md.area, md.mass
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

/// Checks one shape's numbers; `field` names it (`shape` or `shapes[k].shape`).
fn validate_shape(
    shape: &ShapeDef,
    field: &str,
    err: &dyn Fn(&str, String, &str) -> SceneError,
) -> Result<(), SceneError> {
    match shape {
        ShapeDef::Circle { radius } => {
            if !(radius.is_finite() && *radius > 0.0) {
                return Err(err(
                    &format!("{field}.Circle.radius"),
                    radius.to_string(),
                    "a finite number > 0 (metres)",
                ));
            }
        }
        ShapeDef::Box {
            half_extents,
            radius,
        } => {
            if !(finite2(*half_extents) && half_extents[0] > 0.0 && half_extents[1] > 0.0) {
                return Err(err(
                    &format!("{field}.Box.half_extents"),
                    format!("{half_extents:?}"),
                    "two finite numbers > 0 (half width, half height in metres)",
                ));
            }
            rounding(radius, &format!("{field}.Box.radius"), err)?;
        }
        ShapeDef::Polygon { vertices, radius } => {
            crate::shape::Polygon::from_vertices(vertices).map_err(|problem| {
                err(
                    &format!("{field}.Polygon.vertices"),
                    format!("{vertices:?}"),
                    &format!(
                        "a convex, counter-clockwise polygon of 3 to {MAX_POLYGON_VERTICES} finite vertices with non-zero area ({problem})"
                    ),
                )
            })?;
            rounding(radius, &format!("{field}.Polygon.radius"), err)?;
        }
        ShapeDef::Capsule {
            center1,
            center2,
            radius,
        } => {
            finite_point(center1, &format!("{field}.Capsule.center1"), err)?;
            finite_point(center2, &format!("{field}.Capsule.center2"), err)?;
            if !(radius.is_finite() && *radius > 0.0) {
                return Err(err(
                    &format!("{field}.Capsule.radius"),
                    radius.to_string(),
                    "a finite number > 0 (metres)",
                ));
            }
            apart(
                *center1,
                *center2,
                &format!("{field}.Capsule.center2"),
                "the centres",
                "(a capsule whose centres meet is a circle: use Circle)",
                err,
            )?;
        }
        ShapeDef::Segment { point1, point2 } => {
            finite_point(point1, &format!("{field}.Segment.point1"), err)?;
            finite_point(point2, &format!("{field}.Segment.point2"), err)?;
            apart(
                *point1,
                *point2,
                &format!("{field}.Segment.point2"),
                "the points",
                "",
                err,
            )?;
        }
        ShapeDef::Chain { points, looped } => {
            if points.len() < 4 {
                return Err(err(
                    &format!("{field}.Chain.points"),
                    format!("{} points", points.len()),
                    "at least 4 points (an open chain's first and last points only shape its end segments; for one segment use Segment)",
                ));
            }
            for (k, p) in points.iter().enumerate() {
                finite_point(p, &format!("{field}.Chain.points[{k}]"), err)?;
            }
            let n = points.len();
            let pairs = if *looped { n } else { n - 1 };
            for k in 0..pairs {
                let next = (k + 1) % n;
                apart(
                    points[k],
                    points[next],
                    &format!("{field}.Chain.points[{next}]"),
                    &format!("points {k} and {next}"),
                    "(remove the repeated point)",
                    err,
                )?;
            }
        }
    }
    Ok(())
}

/// A point: two finite numbers.
fn finite_point(
    p: &[f32; 2],
    field: &str,
    err: &dyn Fn(&str, String, &str) -> SceneError,
) -> Result<(), SceneError> {
    if finite2(*p) {
        Ok(())
    } else {
        Err(err(field, format!("{p:?}"), "two finite numbers (m)"))
    }
}

/// A rounding radius: finite and >= 0.
fn rounding(
    radius: &f32,
    field: &str,
    err: &dyn Fn(&str, String, &str) -> SceneError,
) -> Result<(), SceneError> {
    if radius.is_finite() && *radius >= 0.0 {
        Ok(())
    } else {
        Err(err(
            field,
            radius.to_string(),
            "a finite number >= 0 (metres; 0 is sharp)",
        ))
    }
}

/// Two points at least the linear slop apart (Box2D asserts as much of a segment's ends).
fn apart(
    a: [f32; 2],
    b: [f32; 2],
    field: &str,
    what: &str,
    hint: &str,
    err: &dyn Fn(&str, String, &str) -> SceneError,
) -> Result<(), SceneError> {
    let d = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
    if d >= crate::LINEAR_SLOP {
        Ok(())
    } else {
        Err(err(
            field,
            format!("{b:?}, {d} m from {a:?}"),
            &format!("{what} at least {} m apart {hint}", crate::LINEAR_SLOP),
        ))
    }
}
