//! What the loader's own deserializers (`pair`, `present`) accept, for `schemars`.

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
