//! Errors the library returns. Files, lines and columns are added at the edges.

use thiserror::Error;

/// Why a scene, or a body built from user data, was refused.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SceneError {
    /// A scene-level field is out of range.
    #[error("field `{field}` is {value}; allowed: {allowed}")]
    Scene {
        /// The field's name.
        field: String,
        /// The value that was given.
        value: String,
        /// What is allowed instead.
        allowed: String,
    },
    /// A body's field is out of range.
    #[error("body {index}: field `{field}` is {value}; allowed: {allowed}")]
    Body {
        /// The body's index in the scene's `bodies` list.
        index: usize,
        /// The field's name (`shape.Circle.radius` for nested fields).
        field: String,
        /// The value that was given.
        value: String,
        /// What is allowed instead.
        allowed: String,
    },
    /// A joint's field is out of range, or it names bodies it cannot join.
    #[error("joint {index}: field `{field}` is {value}; allowed: {allowed}")]
    Joint {
        /// The joint's index in the scene's `joints` list.
        index: usize,
        /// The field's name (`Revolute.limit` for a variant's field).
        field: String,
        /// The value that was given.
        value: String,
        /// What is allowed instead.
        allowed: String,
    },
    /// The scene has more bodies than the limit allows.
    #[error(
        "the scene has {count} bodies, more than the limit of {max}; raise the limit (runner flag --max-bodies) if you mean it"
    )]
    TooManyBodies {
        /// Bodies in the scene.
        count: usize,
        /// The limit in force.
        max: usize,
    },
    /// The step settings that come with the scene or snapshot are out of range.
    #[error("{0}")]
    Settings(#[from] SettingsError),
}

/// Why [`StepSettings::validate`](crate::StepSettings::validate) refused a setting: values
/// that would make the step produce non-finite numbers or silently drop a feature.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("step setting `{field}` is {value}; allowed: {allowed}")]
pub struct SettingsError {
    /// The field of `StepSettings`.
    pub field: &'static str,
    /// The value that was given.
    pub value: String,
    /// What is allowed instead, and why.
    pub allowed: String,
}

/// A polygon that cannot be used as a convex shape.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Error)]
pub enum PolygonError {
    /// Fewer than 3 or more than 8 vertices.
    #[error("it has {0} vertices")]
    VertexCount(usize),
    /// A vertex is NaN or infinite.
    #[error("vertex {0} is not finite")]
    NonFinite(usize),
    /// Two vertices coincide, or three are collinear.
    #[error("vertices {0} and {1} are too close or collinear with their neighbour")]
    Degenerate(usize, usize),
    /// The vertices turn clockwise somewhere.
    #[error("the turn at vertex {0} is clockwise or concave")]
    NotConvex(usize),
    /// The area is zero or negative.
    #[error("its area is not positive")]
    ZeroArea,
}
