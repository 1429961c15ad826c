//! A body's definition ([`BodyDef`], [`BodyKind`]), the parts of a body of several shapes
//! ([`PartDef`], resolved against the body's defaults as [`ResolvedPart`]), and the check of
//! a body's values.

use serde::{Deserialize, Serialize};

#[cfg(feature = "schema")]
use super::schema;
use super::{
    Filter, Limits, ShapeDef, finite2, is_false, is_one, is_true, one, pair, present,
    too_many_shapes, yes,
};
use crate::error::SceneError;

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

fn default_density() -> f32 {
    1.0
}
fn default_friction() -> f32 {
    0.6
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
    /// How fast the part's surface moves along itself (m/s; positive: clockwise around the
    /// shape, rightwards along its top): a conveyor belt. Friction drives what touches it to
    /// that speed (Box2D v3.1's `tangentSpeed`).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub tangent_speed: f32,
    /// How strongly the part resists rolling (≥ 0, usually 0 to 1; Box2D v3.1's
    /// `rollingResistance`): a contact of it brakes the two bodies' relative spin with a
    /// torque of at most this times the larger shape radius times the normal force, so a
    /// ball rolling on it slows and stops. Only round shapes (circles, capsules, rounded
    /// polygons) have a radius; 0 costs nothing.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub rolling_resistance: f32,
}

fn is_zero(x: &f32) -> bool {
    *x == 0.0
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
            tangent_speed: 0.0,
            rolling_resistance: 0.0,
        }
    }

    /// The part's surface moving along itself at `speed` (m/s; see
    /// [`PartDef::tangent_speed`]).
    pub fn tangent_speed(mut self, speed: f32) -> PartDef {
        self.tangent_speed = speed;
        self
    }
    /// The part resisting rolling by `coefficient` (see [`PartDef::rolling_resistance`]).
    pub fn rolling_resistance(mut self, coefficient: f32) -> PartDef {
        self.rolling_resistance = coefficient;
        self
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

    /// Checks the part's own numbers as part `k` of body `index` (the error names
    /// `shapes[k].<field>`): its shape, where it sits, and the material it gives (an absent
    /// one is the body's, which the body checks).
    pub(crate) fn validate(&self, index: usize, k: usize) -> Result<(), SceneError> {
        let err = |field: &str, value: String, allowed: &str| SceneError::Body {
            index,
            field: field.to_string(),
            value,
            allowed: allowed.to_string(),
        };
        let field = |name: &str| format!("shapes[{k}].{name}");
        self.shape.validate(index, &field("shape"))?;
        if !finite2(self.offset) {
            return Err(err(
                &field("offset"),
                format!("{:?}", self.offset),
                "two finite numbers (m, in the body's frame)",
            ));
        }
        if !self.angle.is_finite() {
            return Err(err(
                &field("angle"),
                self.angle.to_string(),
                "a finite number",
            ));
        }
        if !self.tangent_speed.is_finite() {
            return Err(err(
                &field("tangent_speed"),
                self.tangent_speed.to_string(),
                "a finite number (m/s)",
            ));
        }
        for (name, v) in [
            ("density", self.density),
            ("friction", self.friction),
            ("rolling_resistance", Some(self.rolling_resistance)),
            ("restitution", self.restitution),
        ] {
            if let Some(v) = v
                && !(v.is_finite() && v >= 0.0)
            {
                return Err(err(&field(name), v.to_string(), "a finite number >= 0"));
            }
        }
        Ok(())
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
    /// Surface speed along itself (m/s).
    pub tangent_speed: f32,
    /// Rolling resistance coefficient.
    pub rolling_resistance: f32,
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
                tangent_speed: 0.0,
                rolling_resistance: 0.0,
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
                tangent_speed: p.tangent_speed,
                rolling_resistance: p.rolling_resistance,
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

    /// Checks every value of the body that the schema cannot express, as a scene's body
    /// `index` (the error names it and the field): its numbers, its shapes and parts, and,
    /// for a dynamic body, a mass and rotational inertia the step can invert. `limits`
    /// bounds its shapes (a chain is one per segment).
    pub fn validate(&self, index: usize, limits: &Limits) -> Result<(), SceneError> {
        let shapes = self.shape_count();
        if shapes > limits.max_bodies {
            return Err(too_many_shapes(shapes, limits));
        }
        let err = |field: &str, value: String, allowed: &str| SceneError::Body {
            index,
            field: field.to_string(),
            value,
            allowed: allowed.to_string(),
        };
        if !finite2(self.position) {
            return Err(err(
                "position",
                format!("{:?}", self.position),
                "two finite numbers",
            ));
        }
        if !self.angle.is_finite() {
            return Err(err("angle", self.angle.to_string(), "a finite number"));
        }
        if !finite2(self.linear_velocity) {
            return Err(err(
                "linear_velocity",
                format!("{:?}", self.linear_velocity),
                "two finite numbers",
            ));
        }
        if !self.angular_velocity.is_finite() {
            return Err(err(
                "angular_velocity",
                self.angular_velocity.to_string(),
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
        non_negative("friction", self.friction)?;
        non_negative("restitution", self.restitution)?;
        non_negative("linear_damping", self.linear_damping)?;
        non_negative("angular_damping", self.angular_damping)?;
        if !self.density.is_finite() || self.density < 0.0 {
            return Err(err(
                "density",
                self.density.to_string(),
                "a finite number >= 0 (and > 0 for a dynamic body)",
            ));
        }
        if self.kind == BodyKind::Dynamic && self.shape.is_some() && self.density <= 0.0 {
            return Err(err(
                "density",
                self.density.to_string(),
                "a finite number > 0 for a dynamic body (only static and kinematic bodies may have zero density)",
            ));
        }
        if !self.gravity_scale.is_finite() {
            return Err(err(
                "gravity_scale",
                self.gravity_scale.to_string(),
                "a finite number (1 is ordinary gravity)",
            ));
        }
        match (&self.shape, self.shapes.is_empty()) {
            (Some(_), false) => {
                return Err(err(
                    "shapes",
                    format!("{} parts beside `shape`", self.shapes.len()),
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
        let parts = self.parts();
        for (k, part) in parts.iter().enumerate() {
            let prefix = if part.single {
                String::new()
            } else {
                format!("shapes[{k}].")
            };
            let field = |name: &str| format!("{prefix}{name}");
            if part.single {
                part.shape.validate(index, "shape")?;
            } else {
                // A part's absent density, friction and restitution are the body's, checked
                // above.
                self.shapes[k].validate(index, k)?;
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
        if self.kind != BodyKind::Dynamic {
            return Ok(());
        }
        if !parts.iter().any(|p| p.shape.has_area()) {
            return Err(err(
                if self.shape.is_some() {
                    "shape"
                } else {
                    "shapes"
                },
                "segments and chains only".into(),
                "at least one part with area (Circle, Box, Polygon or Capsule) on a dynamic body: segments and chains give no mass",
            ));
        }
        let md = crate::body::BodyMass::of_def(self);
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
                        self.density, md.area, md.mass
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
            let rotates = !self.fixed_rotation;
            if rotates && !invertible(md.inertia) {
                return Err(err(
                    "shape",
                    format!(
                        "of largest radius {extent:e} m, whose rotational inertia at density {} \
                         is {:e} kg·m², which f32 cannot invert",
                        self.density, md.inertia
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

    /// How many shapes the body builds: one a part, a chain one per point.
    pub(crate) fn shape_count(&self) -> usize {
        let part_shapes = |shape: &ShapeDef| match shape {
            ShapeDef::Chain { points, .. } => points.len().max(1),
            _ => 1,
        };
        self.shape.as_ref().map_or(0, part_shapes)
            + self
                .shapes
                .iter()
                .map(|p| part_shapes(&p.shape))
                .sum::<usize>()
    }
}
