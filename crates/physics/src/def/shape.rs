//! A shape's definition ([`ShapeDef`]), which shapes may touch ([`Filter`]), and the check
//! of a shape's numbers.

use serde::{Deserialize, Serialize};

#[cfg(feature = "schema")]
use super::schema;
use super::{finite2, is_false, is_zero, pair};
use crate::error::SceneError;

/// Largest polygon a scene may use (Box2D's `B2_MAX_POLYGON_VERTICES`).
pub const MAX_POLYGON_VERTICES: usize = 8;

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

    /// Checks the shape's numbers; an error names body `index` and the shape's `field`
    /// (`shape` or `shapes[k].shape`) and the value within it.
    pub(crate) fn validate(&self, index: usize, field: &str) -> Result<(), SceneError> {
        let err: &dyn Fn(&str, String, &str) -> SceneError =
            &|field: &str, value: String, allowed: &str| SceneError::Body {
                index,
                field: field.to_string(),
                value,
                allowed: allowed.to_string(),
            };
        match self {
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
