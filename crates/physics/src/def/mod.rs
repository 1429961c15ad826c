//! What a scene is made of, one concept a file: a body and its parts ([`BodyDef`],
//! [`BodyKind`], [`PartDef`]) in `body.rs`, a shape and its collision filter ([`ShapeDef`],
//! [`Filter`]) in `shape.rs`. Each definition checks its own values beside it
//! ([`BodyDef::validate`]), so a scene ([`crate::SceneDef`], which holds them) and
//! [`crate::World::create_body`] check a body by the same code.
//!
//! Plain serde data: the loader's own deserializers (`pair`, `present`) and what they accept
//! as JSON Schema (`schema`) are here too, shared with the scene.

mod body;
pub(crate) mod pair;
#[cfg(feature = "schema")]
pub(crate) mod schema;
mod shape;

pub use body::{BodyDef, BodyKind, PartDef, ResolvedPart};
pub use shape::{Filter, MAX_POLYGON_VERTICES, ShapeDef};

use serde::Deserialize;

use crate::error::SceneError;

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

/// The error of a scene, or a body, whose shapes pass the body limit.
pub(crate) fn too_many_shapes(shapes: usize, limits: &Limits) -> SceneError {
    SceneError::Scene {
        field: "bodies".to_string(),
        value: format!("{shapes} shapes in all (the parts of its bodies)"),
        allowed: format!(
            "at most {} shapes, the body limit; raise it (runner flag --max-bodies) if \
             you mean it",
            limits.max_bodies
        ),
    }
}

fn finite2(v: [f32; 2]) -> bool {
    v[0].is_finite() && v[1].is_finite()
}

fn is_zero(x: &f32) -> bool {
    *x == 0.0
}

/// A field that is `Some` when present, written without RON's `Some(..)`.
fn present<'de, D: serde::Deserializer<'de>, T: Deserialize<'de>>(
    d: D,
) -> Result<Option<T>, D::Error> {
    T::deserialize(d).map(Some)
}

pub(crate) fn yes() -> bool {
    true
}
pub(crate) fn is_true(b: &bool) -> bool {
    *b
}
fn is_false(b: &bool) -> bool {
    !*b
}
pub(crate) fn one() -> f32 {
    1.0
}
pub(crate) fn is_one(x: &f32) -> bool {
    *x == 1.0
}
