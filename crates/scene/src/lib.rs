//! Loading tumble scenes: a `.ron` or `.json` file, or a built-in scene by name.
//!
//! [`load`] is what the runner, the viewer and the tests call; [`parse`] is the part that
//! turns bytes into a validated [`SceneDef`] and is what fuzzers call. Neither panics on any
//! input: every refusal is a [`LoadError`] whose `Display` is a complete message for a person,
//! naming the file, the place (`line:column` and the field's path, such as
//! `bodies[3].shapes[1].filter.category`, or `body N` and the field) and what is allowed.

pub mod builtin;
pub mod cli;
pub mod sample;

use std::fmt;
use std::fs::File;
use std::io::Read;
use std::path::Path;

use thiserror::Error;
use tumble_physics::{Limits, SceneDef, SceneError};

/// Default for [`LoadLimits::max_file_bytes`]: 64 MiB.
pub const DEFAULT_MAX_FILE_BYTES: u64 = 64 * 1024 * 1024;

/// The name of the command-line flag that raises [`LoadLimits::max_file_bytes`]; error
/// messages point at it.
pub const MAX_FILE_BYTES_FLAG: &str = "--max-file-bytes";

/// Limits on untrusted scene input.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LoadLimits {
    /// Largest scene file accepted, in bytes (default 64 MiB).
    pub max_file_bytes: u64,
    /// Limits checked by [`SceneDef::validate`] (bodies, substeps).
    pub scene: Limits,
}

impl Default for LoadLimits {
    fn default() -> Self {
        Self {
            max_file_bytes: DEFAULT_MAX_FILE_BYTES,
            scene: Limits::default(),
        }
    }
}

/// The syntax of a scene file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Rusty Object Notation, `.ron`.
    Ron,
    /// JSON, `.json`.
    Json,
}

impl Format {
    /// The format for a file extension (without the dot, case-insensitive), if it is one.
    pub fn from_extension(ext: &str) -> Option<Format> {
        if ext.eq_ignore_ascii_case("ron") {
            Some(Format::Ron)
        } else if ext.eq_ignore_ascii_case("json") {
            Some(Format::Json)
        } else {
            None
        }
    }

    /// The format of a path, from its extension.
    pub fn from_path(path: &Path) -> Option<Format> {
        path.extension()
            .and_then(|e| e.to_str())
            .and_then(Format::from_extension)
    }
}

impl fmt::Display for Format {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Format::Ron => "RON",
            Format::Json => "JSON",
        })
    }
}

/// Why a scene could not be loaded. `Display` is the whole message for a person.
#[derive(Debug, Error)]
pub enum LoadError {
    /// The path's extension is neither `.ron` nor `.json`.
    #[error(
        "{path}: unknown scene file extension `.{extension}`; allowed: `.ron` or `.json` files, or a built-in scene name ({builtins})"
    )]
    UnknownExtension {
        /// The path as given.
        path: String,
        /// Its extension.
        extension: String,
        /// The built-in names, comma-separated.
        builtins: String,
    },
    /// Neither a built-in name nor a path with a scene extension.
    #[error(
        "`{name}` is not a built-in scene, nor a `.ron` or `.json` file; built-in scenes: {builtins}"
    )]
    UnknownScene {
        /// The source as given.
        name: String,
        /// The built-in names, comma-separated.
        builtins: String,
    },
    /// The file could not be opened or read.
    #[error("{path}: cannot read the scene file: {source}")]
    Io {
        /// The path as given.
        path: String,
        /// What the system said.
        #[source]
        source: std::io::Error,
    },
    /// The path names a directory or some other thing that is not a plain file.
    #[error("{path}: not a regular file; allowed: a `.ron` or `.json` scene file")]
    NotAFile {
        /// The path as given.
        path: String,
    },
    /// The file is larger than [`LoadLimits::max_file_bytes`].
    #[error(
        "{path}: the file is {size} bytes, more than the limit of {max} bytes; raise the limit (flag {flag}, or `LoadLimits::max_file_bytes`) if you mean it"
    )]
    TooLarge {
        /// The path as given.
        path: String,
        /// The file's size in bytes (at least; reading stops past the limit).
        size: u64,
        /// The limit in force.
        max: u64,
        /// The flag that raises it.
        flag: &'static str,
    },
    /// The bytes are not UTF-8 text.
    #[error(
        "{origin}:{line}:{column}: the file is not UTF-8 text (invalid byte sequence here); allowed: a UTF-8 encoded {format} scene"
    )]
    NotUtf8 {
        /// The file (or other origin) of the bytes.
        origin: String,
        /// Line of the first bad byte, from 1.
        line: usize,
        /// Column of the first bad byte, from 1.
        column: usize,
        /// The format being read.
        format: Format,
    },
    /// A syntax error, an unknown field or a value of the wrong type.
    #[error("{origin}:{line}:{column}: {}{message}\n  hint: {hint}", path_prefix(.path))]
    Syntax {
        /// The file (or other origin) of the bytes.
        origin: String,
        /// Line of the error, from 1.
        line: usize,
        /// Column of the error, from 1.
        column: usize,
        /// The field being read when the error came, from the top of the scene
        /// (`bodies[3].shapes[1].filter.category`), or empty at the top level.
        path: String,
        /// What went wrong, as the parser says it.
        message: String,
        /// What to do about it: for unknown fields, the allowed fields.
        hint: String,
    },
    /// The scene parsed but a value is out of range (validation failed).
    #[error("{origin}: {source}")]
    Invalid {
        /// The file (or built-in name) of the scene.
        origin: String,
        /// Which body, which field, which value, and what is allowed.
        #[source]
        source: SceneError,
    },
}

/// `path: ` before a message, or nothing for the top level.
fn path_prefix(path: &str) -> String {
    if path.is_empty() {
        String::new()
    } else {
        format!("{path}: ")
    }
}

/// The path `serde_path_to_error` tracked, as `bodies[3].shapes[1].filter.category`; empty at
/// the top level (which the crate writes as `.`).
fn field_path(path: &serde_path_to_error::Path) -> String {
    if path.iter().next().is_none() {
        String::new()
    } else {
        path.to_string()
    }
}

impl LoadError {
    /// The field path of a syntax or type error (`bodies[3].shapes[1].filter.category`), if
    /// this is one and the error is inside the scene's top level.
    pub fn path(&self) -> Option<&str> {
        match self {
            LoadError::Syntax { path, .. } if !path.is_empty() => Some(path),
            _ => None,
        }
    }

    /// The `line:column` of a syntax error, if this is one.
    pub fn position(&self) -> Option<(usize, usize)> {
        match self {
            LoadError::Syntax { line, column, .. } | LoadError::NotUtf8 { line, column, .. } => {
                Some((*line, *column))
            }
            _ => None,
        }
    }
}

fn builtin_list() -> String {
    let names = builtin::names();
    if names.is_empty() {
        "none".to_string()
    } else {
        names.join(", ")
    }
}

/// Loads a scene from `source`: a path to a `.ron` or `.json` file, or a built-in scene's name.
///
/// The scene is validated against `limits.scene`; a file's scene with an empty `name` is named
/// after the file's stem.
pub fn load(source: &str, limits: &LoadLimits) -> Result<SceneDef, LoadError> {
    let path = Path::new(source);
    let extension = path.extension().and_then(|e| e.to_str());
    if let Some(format) = extension.and_then(Format::from_extension) {
        let bytes = read_file(source, limits.max_file_bytes)?;
        return parse(&bytes, format, source, limits);
    }
    if let Some(scene) = builtin::build(source) {
        let mut scene = scene;
        if scene.name.is_empty() {
            scene.name = source.to_string();
        }
        scene
            .validate(&limits.scene)
            .map_err(|e| LoadError::Invalid {
                origin: format!("built-in scene `{source}`"),
                source: e,
            })?;
        return Ok(scene);
    }
    match path.extension() {
        Some(ext) => Err(LoadError::UnknownExtension {
            path: source.to_string(),
            extension: ext.to_string_lossy().into_owned(),
            builtins: builtin_list(),
        }),
        None => Err(LoadError::UnknownScene {
            name: source.to_string(),
            builtins: builtin_list(),
        }),
    }
}

/// Reads at most `max + 1` bytes so that a huge (or endless) file is refused without reading it.
fn read_file(path: &str, max: u64) -> Result<Vec<u8>, LoadError> {
    let io_err = |source| LoadError::Io {
        path: path.to_string(),
        source,
    };
    let file = File::open(path).map_err(io_err)?;
    let meta = file.metadata().map_err(io_err)?;
    if !meta.is_file() {
        return Err(LoadError::NotAFile {
            path: path.to_string(),
        });
    }
    let too_large = |size| LoadError::TooLarge {
        path: path.to_string(),
        size,
        max,
        flag: MAX_FILE_BYTES_FLAG,
    };
    if meta.len() > max {
        return Err(too_large(meta.len()));
    }
    let mut bytes = Vec::with_capacity(usize::try_from(meta.len()).unwrap_or(0));
    file.take(max.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(io_err)?;
    if bytes.len() as u64 > max {
        return Err(too_large(bytes.len() as u64));
    }
    Ok(bytes)
}

/// Parses and validates a scene from `bytes` in `format`. `origin` names the bytes in messages
/// (a path, normally) and, when the scene's `name` is empty, gives it its stem as the name.
pub fn parse(
    bytes: &[u8],
    format: Format,
    origin: &str,
    limits: &LoadLimits,
) -> Result<SceneDef, LoadError> {
    if bytes.len() as u64 > limits.max_file_bytes {
        return Err(LoadError::TooLarge {
            path: origin.to_string(),
            size: bytes.len() as u64,
            max: limits.max_file_bytes,
            flag: MAX_FILE_BYTES_FLAG,
        });
    }
    let text = match std::str::from_utf8(bytes) {
        Ok(text) => text,
        Err(e) => {
            // The prefix up to the bad byte is valid UTF-8 by definition.
            let valid = std::str::from_utf8(&bytes[..e.valid_up_to()]).unwrap_or_default();
            let (line, column) = end_position(valid);
            return Err(LoadError::NotUtf8 {
                origin: origin.to_string(),
                line,
                column,
                format,
            });
        }
    };
    // Editors on some systems start UTF-8 files with a byte-order mark; neither parser wants it.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut scene = match format {
        Format::Ron => parse_ron(text, origin)?,
        Format::Json => parse_json(text, origin)?,
    };
    if scene.name.is_empty() {
        scene.name = Path::new(origin)
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
    }
    scene
        .validate(&limits.scene)
        .map_err(|source| LoadError::Invalid {
            origin: origin.to_string(),
            source,
        })?;
    Ok(scene)
}

/// The 1-based line and column just past the end of `text` (columns count characters).
fn end_position(text: &str) -> (usize, usize) {
    let line = 1 + text.bytes().filter(|&b| b == b'\n').count();
    let last_line = text.rsplit('\n').next().unwrap_or("");
    (line, 1 + last_line.chars().count())
}

const SCHEMA_HINT: &str = "see docs/scenes.md for the fields, their types and defaults";

fn parse_ron(text: &str, origin: &str) -> Result<SceneDef, LoadError> {
    // The default options keep ron's recursion limit, so deep nesting is an error, not a crash.
    let options = ron::Options::default();
    let syntax = |e: ron::error::SpannedError, path: String| LoadError::Syntax {
        origin: origin.to_string(),
        line: e.span.start.line.max(1),
        column: e.span.start.col.max(1),
        path,
        message: ron_message(&e.code),
        hint: ron_hint(&e.code),
    };
    // What `Options::from_str` does, with the path of the field tracked on the way.
    let mut de = ron::Deserializer::from_str_with_options(text, &options)
        .map_err(|e| syntax(e, String::new()))?;
    let scene = serde_path_to_error::deserialize::<_, SceneDef>(&mut de).map_err(|e| {
        let path = field_path(e.path());
        syntax(de.span_error(e.into_inner()), path)
    })?;
    de.end()
        .map_err(|e| syntax(de.span_error(e), String::new()))?;
    Ok(scene)
}

/// ron's own message, less the list of alternatives that the hint gives.
fn ron_message(code: &ron::Error) -> String {
    let place = |outer: &Option<String>| {
        outer
            .as_deref()
            .map(|o| format!(" in `{o}`"))
            .unwrap_or_default()
    };
    match code {
        ron::Error::NoSuchStructField { found, outer, .. } => {
            format!("unknown field `{found}`{}", place(outer))
        }
        ron::Error::NoSuchEnumVariant { found, outer, .. } => {
            format!("unknown variant `{found}`{}", place(outer))
        }
        other => other.to_string(),
    }
}

fn quoted_list(names: &[&str]) -> String {
    if names.is_empty() {
        return "none".to_string();
    }
    names
        .iter()
        .map(|n| format!("`{n}`"))
        .collect::<Vec<_>>()
        .join(", ")
}

fn ron_hint(code: &ron::Error) -> String {
    use ron::Error as E;
    match code {
        E::NoSuchStructField {
            expected, outer, ..
        } => {
            let place = outer
                .as_deref()
                .map(|o| format!(" in `{o}`"))
                .unwrap_or_default();
            format!(
                "allowed fields{place}: {}; field names are case-sensitive",
                quoted_list(expected)
            )
        }
        E::NoSuchEnumVariant { expected, .. } => {
            format!(
                "allowed here: {}; names are case-sensitive",
                quoted_list(expected)
            )
        }
        E::MissingStructField { field, outer } => {
            let place = outer
                .as_deref()
                .map(|o| format!(" in `{o}`"))
                .unwrap_or_default();
            format!("`{field}` is required{place}; {SCHEMA_HINT}")
        }
        E::DuplicateStructField { field, .. } => {
            format!("give `{field}` only once")
        }
        E::ExpectedStructLike | E::ExpectedArray => format!(
            "in RON, pairs such as `position`, `gravity` and `half_extents` are written `(x, y)` or `[x, y]`, lists such as `bodies` and `vertices` `[a, b, ...]`, a scene or body `( field: value, ... )`, a shape `Circle(radius: 0.5)`; {SCHEMA_HINT}"
        ),
        E::ExceededRecursionLimit => {
            "the input nests too deeply; a scene is at most a few levels deep".to_string()
        }
        E::ExpectedFloat | E::ExpectedInteger | E::IntegerOutOfBounds => format!(
            "numbers are plain decimals such as `1`, `-0.5` or `2e3`; counts (`substeps`, `steps`) are whole numbers >= 0; {SCHEMA_HINT}"
        ),
        E::Eof
        | E::ExpectedComma
        | E::ExpectedStructLikeEnd
        | E::ExpectedArrayEnd
        | E::TrailingCharacters
        | E::UnexpectedChar(_)
        | E::ExpectedStringEnd => {
            format!(
                "check for a missing comma, bracket or parenthesis just before this place; {SCHEMA_HINT}"
            )
        }
        _ => SCHEMA_HINT.to_string(),
    }
}

fn parse_json(text: &str, origin: &str) -> Result<SceneDef, LoadError> {
    // What `serde_json::from_str` does, with the path of the field tracked on the way.
    // serde_json keeps its default recursion limit (128), so deep nesting is an error.
    let mut de = serde_json::Deserializer::from_str(text);
    let parsed = match serde_path_to_error::deserialize::<_, SceneDef>(&mut de) {
        Ok(scene) => de.end().map(|()| scene).map_err(|e| (String::new(), e)),
        Err(e) => Err((field_path(e.path()), e.into_inner())),
    };
    parsed.map_err(|(path, e)| {
        let full = e.to_string();
        let (line, column) = if e.line() == 0 {
            end_position(text)
        } else {
            (e.line(), e.column().max(1))
        };
        let suffix = format!(" at line {} column {}", e.line(), e.column());
        let message = full.strip_suffix(&suffix).unwrap_or(&full);
        let hint = json_hint(message, e.classify());
        // The hint lists what is allowed; the message need not say it twice.
        let message = match message.split_once(", expected ") {
            Some((head, _)) if message.starts_with("unknown ") => head.to_string(),
            _ => negative_unsigned(message).unwrap_or_else(|| message.to_string()),
        };
        LoadError::Syntax {
            origin: origin.to_string(),
            line,
            column,
            path,
            message,
            hint,
        }
    })
}

/// serde's "invalid value: integer `-1`, expected u64" said plainly: "-1 is not an unsigned
/// integer (u64)".
fn negative_unsigned(message: &str) -> Option<String> {
    let rest = message.strip_prefix("invalid value: integer `")?;
    let (value, expected) = rest.split_once("`, expected ")?;
    let unsigned = matches!(expected, "u8" | "u16" | "u32" | "u64" | "u128" | "usize");
    (value.starts_with('-') && unsigned)
        .then(|| format!("{value} is not an unsigned integer ({expected})"))
}

fn json_hint(message: &str, category: serde_json::error::Category) -> String {
    use serde_json::error::Category;
    if message.starts_with("unknown field") {
        let allowed = message
            .split_once(", expected ")
            .map(|(_, rest)| rest.trim_start_matches("one of ").to_string())
            .unwrap_or_else(|| "none".to_string());
        return format!("allowed fields here: {allowed}; field names are case-sensitive");
    }
    if message.starts_with("unknown variant") {
        let allowed = message
            .split_once(", expected ")
            .map(|(_, rest)| rest.trim_start_matches("one of ").to_string())
            .unwrap_or_else(|| "none".to_string());
        return format!("allowed here: {allowed}; names are case-sensitive");
    }
    if message.starts_with("missing field") {
        return format!("that field is required here; {SCHEMA_HINT}");
    }
    if message.contains("recursion limit") {
        return "the input nests too deeply; a scene is at most a few levels deep".to_string();
    }
    match category {
        Category::Data => format!(
            "pairs such as `position` are `[x, y]`, numbers are plain decimals, counts (`substeps`, `steps`) whole numbers >= 0, a shape is `{{\"Circle\": {{\"radius\": 0.5}}}}`; {SCHEMA_HINT}"
        ),
        Category::Eof | Category::Syntax => format!(
            "check for a missing comma, bracket, brace or quote just before this place; JSON allows no trailing commas or comments; {SCHEMA_HINT}"
        ),
        Category::Io => SCHEMA_HINT.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tumble_physics::ShapeDef;

    const GOOD_RON: &str = r#"// A small scene.
(
    name: "",
    gravity: (0, -10),
    dt: 0.0166666,
    substeps: 4,
    bodies: [
        (kind: Static, position: (0.0, -1.0), shape: Box(half_extents: (10.0, 1.0))),
        (position: (0.0, 2.0), shape: Circle(radius: 0.5), friction: 0.3),
        (position: (1.0, 4.0), angle: 0.5,
         shape: Polygon(vertices: [(-0.5, -0.5), (0.5, -0.5), (0.0, 0.5)])),
    ],
)
"#;

    const GOOD_JSON: &str = r#"{
  "gravity": [0, -10],
  "dt": 0.0166666,
  "substeps": 4,
  "bodies": [
    {"kind": "Static", "position": [0.0, -1.0], "shape": {"Box": {"half_extents": [10.0, 1.0]}}},
    {"position": [0.0, 2.0], "shape": {"Circle": {"radius": 0.5}}, "friction": 0.3},
    {"position": [1.0, 4.0], "angle": 0.5,
     "shape": {"Polygon": {"vertices": [[-0.5, -0.5], [0.5, -0.5], [0.0, 0.5]]}}}
  ]
}
"#;

    fn ron(text: &str, origin: &str) -> Result<SceneDef, LoadError> {
        parse(text.as_bytes(), Format::Ron, origin, &LoadLimits::default())
    }

    fn json(text: &str, origin: &str) -> Result<SceneDef, LoadError> {
        parse(
            text.as_bytes(),
            Format::Json,
            origin,
            &LoadLimits::default(),
        )
    }

    /// The error's message, after checking that it contains every one of `words`.
    #[track_caller]
    fn expect_err(result: Result<SceneDef, LoadError>, words: &[&str]) -> String {
        let message = match result {
            Ok(scene) => panic!("expected an error, got a scene: {scene:?}"),
            Err(e) => e.to_string(),
        };
        for word in words {
            assert!(message.contains(word), "message lacks {word:?}:\n{message}");
        }
        message
    }

    /// A RON scene with one dynamic body whose body fields are `fields`.
    fn one_body_ron(fields: &str) -> String {
        format!(
            "(bodies: [\n    (kind: Static, shape: Circle(radius: 1.0)),\n    ({fields}),\n])\n"
        )
    }

    #[test]
    fn parts_filters_and_sleep_fields_load_and_bad_ones_name_the_part() {
        // Good: two parts with their own material and filter, a body filter, sleep fields.
        let text = one_body_ron(
            "awake: false, enable_sleep: false, gravity_scale: 0.5, \
             filter: (category: 2, mask: 5, group: -1), shapes: [\
             (shape: Circle(radius: 0.5), offset: (1.0, 0.0), density: 2.0), \
             (shape: Box(half_extents: [0.2, 0.3]), angle: 0.5, filter: (group: 3), sensor: true)]",
        );
        let scene = ron(&text, "parts.ron").expect("loads");
        let body = &scene.bodies[1];
        assert_eq!(body.shapes.len(), 2);
        assert_eq!(body.shapes[0].density, Some(2.0));
        assert_eq!(body.shapes[1].filter.map(|f| f.group), Some(3));
        assert!(!body.awake && !body.enable_sleep && body.gravity_scale == 0.5);
        assert!(scene.sleep, "a scene sleeps unless it says otherwise");
        let parts = body.parts();
        // A part without a filter takes the body's.
        assert_eq!(parts[0].filter.category, 2);
        assert!(parts[1].sensor);
        // Bad: each names the file, the body and the part's field.
        let bad = [
            (
                "shapes: [(shape: Circle(radius: 1.0)), (shape: Circle(radius: -2.0))]",
                "shapes[1].shape.Circle.radius",
            ),
            (
                "shapes: [(shape: Circle(radius: 1.0), offset: (inf, 0.0))]",
                "shapes[0].offset",
            ),
            (
                "shapes: [(shape: Circle(radius: 1.0), friction: -1.0)]",
                "shapes[0].friction",
            ),
            (
                "shape: Circle(radius: 1.0), shapes: [(shape: Circle(radius: 1.0))]",
                "`shapes`",
            ),
            ("shapes: []", "`shape`"),
            (
                "shapes: [(shape: Circle(radius: 1.0), density: 0.0)]",
                "`density`",
            ),
            (
                "gravity_scale: NaN, shape: Circle(radius: 1.0)",
                "`gravity_scale`",
            ),
        ];
        for (fields, field) in bad {
            expect_err(
                ron(&one_body_ron(fields), "bad.ron"),
                &["bad.ron", "body 1", field],
            );
        }
        // The body limit bounds the shapes of all bodies too.
        let many = format!(
            "(bodies: [(shapes: [{}])])",
            "(shape: Circle(radius: 1.0)),".repeat(Limits::default().max_bodies + 1)
        );
        expect_err(
            ron(&many, "many.ron"),
            &["many.ron", "200001 shapes", "--max-bodies"],
        );
        // A typo in a part's field lists the allowed ones.
        expect_err(
            ron(
                &one_body_ron("shapes: [(shape: Circle(radius: 1.0), ofset: (1, 2))]"),
                "typo.ron",
            ),
            &["typo.ron:", "ofset", "offset"],
        );
    }

    #[test]
    fn capsules_segments_chains_and_rounding_load_and_bad_ones_name_the_field() {
        let text = one_body_ron(
            "kind: Static, shapes: [\
             (shape: Segment(point1: (-5, 0), point2: (5, 0))), \
             (shape: Chain(points: [(4, 1), (2, 1), (0, 1), (-2, 1)], loop: true)), \
             (shape: Capsule(center1: (0, 2), center2: (1, 2), radius: 0.25)), \
             (shape: Box(half_extents: (0.5, 0.5), radius: 0.1)), \
             (shape: Polygon(vertices: [(0, 0), (1, 0), (0, 1)], radius: 0.05))]",
        );
        let scene = ron(&text, "new_shapes.ron").expect("loads");
        assert!(matches!(
            scene.bodies[1].shapes[1].shape,
            ShapeDef::Chain { looped: true, ref points } if points.len() == 4
        ));
        // JSON writes the contract's `loop` key.
        let json_text = r#"{"bodies": [{"kind": "Static", "shape": {"Chain": {"points": [[0, 0], [1, 0], [2, 0], [3, 0]], "loop": false}}}]}"#;
        let scene = json(json_text, "chain.json").expect("loads");
        assert!(matches!(
            scene.bodies[0].shape,
            Some(ShapeDef::Chain { looped: false, .. })
        ));
        let bad = [
            (
                "shape: Capsule(center1: (0, 0), center2: (0, 0), radius: 0.5)",
                "shape.Capsule.center2",
            ),
            (
                "shape: Capsule(center1: (0, 0), center2: (1, 0), radius: -0.5)",
                "shape.Capsule.radius",
            ),
            (
                "kind: Static, shape: Segment(point1: (1, 1), point2: (1, 1))",
                "shape.Segment.point2",
            ),
            (
                "kind: Static, shape: Chain(points: [(0, 0), (1, 0), (2, 0)])",
                "shape.Chain.points",
            ),
            (
                "kind: Static, shape: Chain(points: [(0, 0), (1, 0), (1, 0), (2, 0)])",
                "shape.Chain.points[2]",
            ),
            (
                "kind: Static, shape: Chain(points: [(0, 0), (1, 0), (NaN, 0), (2, 0)])",
                "shape.Chain.points[2]",
            ),
            (
                "shape: Box(half_extents: (1, 1), radius: -0.1)",
                "shape.Box.radius",
            ),
            (
                "shape: Polygon(vertices: [(0, 0), (1, 0), (0, 1)], radius: inf)",
                "shape.Polygon.radius",
            ),
            // A dynamic body of segments only has no mass.
            (
                "shapes: [(shape: Segment(point1: (0, 0), point2: (1, 0)))]",
                "`shapes`",
            ),
            (
                "shape: Chain(points: [(0, 0), (1, 0), (2, 0), (3, 0)])",
                "`shape`",
            ),
        ];
        for (fields, field) in bad {
            expect_err(
                ron(&one_body_ron(fields), "bad.ron"),
                &["bad.ron", "body 1", field],
            );
        }
        // A chain's points count against the body limit.
        let points: String = (0..Limits::default().max_bodies + 1)
            .map(|i| format!("({i}, 0),"))
            .collect();
        expect_err(
            ron(
                &format!("(bodies: [(kind: Static, shape: Chain(points: [{points}]))])"),
                "long.ron",
            ),
            &["long.ron", "points"],
        );
    }

    fn unique_temp(name: &str) -> std::path::PathBuf {
        use std::sync::atomic::{AtomicUsize, Ordering};
        static COUNTER: AtomicUsize = AtomicUsize::new(0);
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        std::env::temp_dir().join(format!(
            "tumble-scene-test-{}-{n}-{name}",
            std::process::id()
        ))
    }

    #[test]
    fn good_ron_and_json_agree_and_fill_defaults() {
        let a = ron(GOOD_RON, "scenes/small.ron").unwrap();
        let b = json(GOOD_JSON, "scenes/small.json").unwrap();
        assert_eq!(a.name, "small", "an empty name becomes the file's stem");
        assert_eq!(a, b);
        assert_eq!(a.bodies.len(), 3);
        assert_eq!(a.steps, 600);
        assert_eq!(a.bodies[1].density, 1.0);
        assert_eq!(a.bodies[2].friction, 0.6);
        assert_eq!(a.bodies[0].kind, tumble_physics::BodyKind::Static);
    }

    #[test]
    fn a_given_name_is_kept_and_a_bom_is_skipped() {
        let scene = ron("\u{feff}(name: \"pile\", bodies: [])", "x/y.ron").unwrap();
        assert_eq!(scene.name, "pile");
    }

    #[test]
    fn syntax_error_names_file_line_and_column() {
        // Missing comma after the first body.
        let text =
            "(bodies: [\n    (shape: Circle(radius: 1.0))\n    (shape: Circle(radius: 1.0)),\n])";
        let m = expect_err(ron(text, "broken.ron"), &["broken.ron:3:", "comma"]);
        assert!(m.contains("hint:"), "{m}");
        let text = "{\"bodies\": [\n  {\"shape\": {\"Circle\": {\"radius\": 1.0}}},\n]}";
        expect_err(
            json(text, "broken.json"),
            &["broken.json:3:", "trailing comma"],
        );
        // Cut short.
        expect_err(ron("(bodies: [", "short.ron"), &["short.ron:1:"]);
        expect_err(json("{\"bodies\": [", "short.json"), &["short.json:1:"]);
        expect_err(json("", "empty.json"), &["empty.json:1:1"]);
    }

    #[test]
    fn a_solver_block_sets_the_step_settings_and_is_validated() {
        use tumble_physics::{Limits, World};
        let text = r#"{"bodies": [], "substeps": 8,
            "solver": {"contact_hertz": 60, "relax_iterations": 2, "joint_hertz": 50,
                       "solve_points_together": false}}"#;
        let scene = json(text, "stiff.json").unwrap_or_else(|e| panic!("{e}"));
        let world = World::from_scene(&scene, &Limits::default()).unwrap();
        let s = world.settings();
        assert_eq!((s.contact_hertz, s.relax_iterations), (60.0, 2));
        assert!(!s.solve_points_together);
        // Absent fields keep the defaults (Box2D's, but for the points solved together).
        assert_eq!((s.contact_damping_ratio, s.max_push_speed), (10.0, 3.0));
        assert!(World::default().settings().solve_points_together);
        // A typo lists the allowed fields; a bad value names the field and the fix.
        expect_err(
            json(
                r#"{"bodies": [], "solver": {"contact_herz": 60}}"#,
                "typo.json",
            ),
            &[
                "typo.json:1:",
                "contact_herz",
                "`contact_hertz`",
                "`time_to_sleep`",
            ],
        );
        for (field, value, words) in [
            ("relax_iterations", "0", "remove it"),
            ("contact_hertz", "0", "> 0"),
            ("max_push_speed", "-1", "> 0"),
            ("restitution_iterations", "65", "1 to 64"),
            ("time_to_sleep", "-0.5", ">= 0"),
        ] {
            let text = format!(r#"{{"bodies": [], "solver": {{"{field}": {value}}}}}"#);
            expect_err(
                json(&text, "bad.json"),
                &["bad.json", &format!("solver.{field}"), value, words],
            );
        }
        // The built-in scene that needs stiffer contacts says so.
        let p200 = builtin::build("pyramid_200").unwrap();
        assert_eq!((p200.substeps, p200.solver.contact_hertz), (8, Some(60.0)));
    }

    #[test]
    fn unknown_field_lists_the_allowed_fields() {
        let text = one_body_ron("shape: Circle(radius: 1.0), frictoin: 0.3");
        let m = expect_err(
            ron(&text, "typo.ron"),
            &[
                "typo.ron:3:",
                "frictoin",
                "friction",
                "restitution",
                "fixed_rotation",
            ],
        );
        assert!(m.contains("hint: allowed fields"), "{m}");
        let text = one_body_ron("shape: Circle(radiuss: 1.0)");
        expect_err(
            ron(&text, "typo2.ron"),
            &["typo2.ron:3:", "radiuss", "`radius`"],
        );
        let text = "{\"bodies\": [], \"gravty\": [0, -10]}";
        expect_err(
            json(text, "typo.json"),
            &[
                "typo.json:1:",
                "gravty",
                "`gravity`",
                "`substeps`",
                "`bodies`",
            ],
        );
        // An unknown shape.
        let text = one_body_ron("shape: Triangle(radius: 1.0)");
        expect_err(
            ron(&text, "shape.ron"),
            &["shape.ron:3:", "Circle", "Box", "Polygon"],
        );
        let text = "{\"bodies\": [{\"shape\": {\"Square\": {}}}]}";
        expect_err(
            json(text, "shape.json"),
            &["shape.json:1:", "Circle", "Box", "Polygon"],
        );
        // A missing required field.
        expect_err(
            ron("(gravity: (0, 1))", "nobodies.ron"),
            &["nobodies.ron:", "bodies"],
        );
        // No shape: refused by validation, naming the body and both ways to give one.
        let text = "{\"bodies\": [{\"position\": [1, 2]}]}";
        expect_err(
            json(text, "noshape.json"),
            &["noshape.json", "body 0", "`shape`", "`shapes`"],
        );
    }

    #[test]
    fn wrong_type_names_the_place() {
        let m = expect_err(
            ron("(substeps: \"four\", bodies: [])", "type.ron"),
            &["type.ron:1:"],
        );
        assert!(m.contains("hint:"), "{m}");
        expect_err(
            json("{\"substeps\": \"four\", \"bodies\": []}", "type.json"),
            &["type.json:1:", "u32", "string"],
        );
        expect_err(
            json("{\"substeps\": 2.5, \"bodies\": []}", "frac.json"),
            &["frac.json:1:"],
        );
        expect_err(
            json("{\"substeps\": -1, \"bodies\": []}", "neg.json"),
            &["neg.json:1:", "-1"],
        );
        // A pair of the wrong shape in RON: the message says how pairs are written.
        let text = one_body_ron("position: (1.0, 2.0, 3.0), shape: Circle(radius: 1.0)");
        expect_err(ron(&text, "pair.ron"), &["pair.ron:3:", "[x, y]", "(x, y)"]);
        // A pair of the wrong length.
        let text = "{\"gravity\": [0, -10, 3], \"bodies\": []}";
        expect_err(json(text, "len.json"), &["len.json:1:"]);
        let text =
            "{\"bodies\": [{\"fixed_rotation\": 1, \"shape\": {\"Circle\": {\"radius\": 1}}}]}";
        expect_err(json(text, "bool.json"), &["bool.json:1:", "bool"]);
    }

    #[test]
    fn negative_or_zero_size() {
        let text = one_body_ron("shape: Circle(radius: -1.0)");
        expect_err(
            ron(&text, "neg.ron"),
            &["neg.ron", "body 1", "shape.Circle.radius", "-1", "> 0"],
        );
        let text = one_body_ron("shape: Circle(radius: 0)");
        expect_err(
            ron(&text, "zero.ron"),
            &["zero.ron", "body 1", "radius", "> 0"],
        );
        let text = one_body_ron("shape: Box(half_extents: (1.0, 0.0))");
        expect_err(
            ron(&text, "box.ron"),
            &[
                "box.ron",
                "body 1",
                "shape.Box.half_extents",
                "[1.0, 0.0]",
                "> 0",
            ],
        );
        let text = "{\"bodies\": [{\"shape\": {\"Box\": {\"half_extents\": [-1, 1]}}}]}";
        expect_err(
            json(text, "box.json"),
            &["box.json", "body 0", "half_extents", "> 0"],
        );
    }

    #[test]
    fn non_finite_numbers() {
        let text = one_body_ron("angle: NaN, shape: Circle(radius: 1.0)");
        expect_err(
            ron(&text, "nan.ron"),
            &["nan.ron", "body 1", "angle", "NaN", "finite"],
        );
        let text = one_body_ron("position: (inf, 0.0), shape: Circle(radius: 1.0)");
        expect_err(
            ron(&text, "inf.ron"),
            &["inf.ron", "body 1", "position", "inf", "finite"],
        );
        // Too large for f32: becomes infinite, then refused by validation.
        let text = one_body_ron("linear_velocity: (1e39, 0.0), shape: Circle(radius: 1.0)");
        expect_err(
            ron(&text, "big.ron"),
            &["big.ron", "body 1", "linear_velocity", "finite"],
        );
        let text = one_body_ron("angular_velocity: 1e999999, shape: Circle(radius: 1.0)");
        expect_err(ron(&text, "huge.ron"), &["huge.ron"]);
        let text = "{\"bodies\": [{\"density\": 1e39, \"shape\": {\"Circle\": {\"radius\": 1}}}]}";
        expect_err(
            json(text, "big.json"),
            &["big.json", "body 0", "density", "finite"],
        );
        // Beyond f64: serde_json refuses it at the number.
        let text = "{\"bodies\": [{\"density\": 1e999, \"shape\": {\"Circle\": {\"radius\": 1}}}]}";
        expect_err(json(text, "huge.json"), &["huge.json:1:", "out of range"]);
        expect_err(
            ron("(gravity: (0.0, -inf), bodies: [])", "g.ron"),
            &["g.ron", "gravity", "finite"],
        );
        expect_err(
            ron("(bodies: [], substeps: 99999999999999999999)", "int.ron"),
            &["int.ron:1:"],
        );
    }

    #[test]
    fn non_convex_polygon() {
        // An arrow head: the vertex at (0, 0.2) turns clockwise.
        let text = one_body_ron(
            "shape: Polygon(vertices: [(-1.0, -1.0), (0.0, 0.2), (1.0, -1.0), (0.0, 1.0)])",
        );
        expect_err(
            ron(&text, "arrow.ron"),
            &[
                "arrow.ron",
                "body 1",
                "shape.Polygon.vertices",
                "convex",
                "counter-clockwise",
            ],
        );
        // Clockwise winding.
        let text = one_body_ron("shape: Polygon(vertices: [(0.0, 0.0), (0.0, 1.0), (1.0, 0.0)])");
        expect_err(
            ron(&text, "cw.ron"),
            &["cw.ron", "body 1", "vertices", "counter-clockwise"],
        );
    }

    #[test]
    fn degenerate_polygon() {
        // Three collinear points: no area.
        let text = one_body_ron("shape: Polygon(vertices: [(0.0, 0.0), (1.0, 0.0), (2.0, 0.0)])");
        expect_err(
            ron(&text, "flat.ron"),
            &[
                "flat.ron",
                "body 1",
                "shape.Polygon.vertices",
                "non-zero area",
            ],
        );
        // Too few and too many vertices.
        let text = one_body_ron("shape: Polygon(vertices: [(0.0, 0.0), (1.0, 0.0)])");
        expect_err(ron(&text, "two.ron"), &["two.ron", "body 1", "3 to 8"]);
        let nine: Vec<String> = (0..9)
            .map(|i| {
                let a = i as f32 * std::f32::consts::TAU / 9.0;
                format!("[{}, {}]", a.cos(), a.sin())
            })
            .collect();
        let text = format!(
            "{{\"bodies\": [{{\"shape\": {{\"Polygon\": {{\"vertices\": [{}]}}}}}}]}}",
            nine.join(", ")
        );
        expect_err(json(&text, "nine.json"), &["nine.json", "body 0", "3 to 8"]);
        // Two coincident vertices.
        let text = one_body_ron(
            "shape: Polygon(vertices: [(0.0, 0.0), (1.0, 0.0), (1.0, 0.0), (0.0, 1.0)])",
        );
        expect_err(ron(&text, "dup.ron"), &["dup.ron", "body 1", "vertices"]);
    }

    #[test]
    fn zero_density_dynamic_body() {
        let text = one_body_ron("density: 0.0, shape: Circle(radius: 1.0)");
        expect_err(
            ron(&text, "light.ron"),
            &[
                "light.ron",
                "body 1",
                "density",
                "0",
                "> 0 for a dynamic body",
            ],
        );
        // Static and kinematic bodies may have zero density.
        let text = "(bodies: [(kind: Kinematic, density: 0, shape: Circle(radius: 1.0))])";
        ron(text, "kin.ron").unwrap();
    }

    #[test]
    fn dt_must_be_positive() {
        expect_err(
            ron("(dt: 0.0, bodies: [])", "dt.ron"),
            &["dt.ron", "`dt`", "0", "> 0"],
        );
        expect_err(
            json("{\"dt\": -0.01, \"bodies\": []}", "dt.json"),
            &["dt.json", "`dt`", "-0.01", "> 0"],
        );
    }

    #[test]
    fn dt_must_not_be_subnormal() {
        // Above 0 but subnormal in f32: the step would refuse it and the scene never move.
        expect_err(
            ron("(dt: 1e-40, bodies: [])", "dt.ron"),
            &["dt.ron", "`dt`", "subnormal", "at least 1.1754944e-38"],
        );
        // Normal, but a substep of it is not.
        expect_err(
            json(
                "{\"dt\": 2e-38, \"substeps\": 8, \"bodies\": []}",
                "dt.json",
            ),
            &["dt.json", "`dt`", "substep", "fewer substeps"],
        );
        ron("(dt: 1e-30, substeps: 8, bodies: [])", "small.ron").unwrap();
    }

    #[test]
    fn a_dynamic_body_needs_a_mass_and_inertia_f32_can_invert() {
        expect_err(
            ron(
                "(bodies: [(shape: Circle(radius: 1.0)), (shape: Circle(radius: 1e-20))])",
                "tiny.ron",
            ),
            &[
                "tiny.ron",
                "body 1",
                "`density`",
                "mass",
                "raise the density",
            ],
        );
        expect_err(
            ron(
                "(bodies: [(density: 1e36, shape: Box(half_extents: (100.0, 100.0)))])",
                "heavy.ron",
            ),
            &["heavy.ron", "body 0", "`density`", "lower the density"],
        );
        expect_err(
            ron("(bodies: [(shape: Circle(radius: 1e-10))])", "spin.ron"),
            &[
                "spin.ron",
                "body 0",
                "`shape`",
                "rotational inertia",
                "fixed_rotation",
            ],
        );
        // Without rotation only the mass matters; static bodies have none to invert.
        ron(
            "(bodies: [(fixed_rotation: true, shape: Circle(radius: 1e-10))])",
            "fixed.ron",
        )
        .unwrap();
        ron(
            "(bodies: [(kind: Static, shape: Circle(radius: 1e-20))])",
            "static.ron",
        )
        .unwrap();
    }

    #[test]
    fn substeps_must_be_at_least_one() {
        expect_err(
            ron("(substeps: 0, bodies: [])", "sub.ron"),
            &["sub.ron", "`substeps`", "0", "from 1 to 256"],
        );
    }

    #[test]
    fn too_many_bodies() {
        let limits = LoadLimits {
            scene: Limits {
                max_bodies: 2,
                ..Limits::default()
            },
            ..LoadLimits::default()
        };
        let text = "(bodies: [(shape: Circle(radius: 1)), (shape: Circle(radius: 1)), (shape: Circle(radius: 1))])";
        expect_err(
            parse(text.as_bytes(), Format::Ron, "many.ron", &limits),
            &["many.ron", "3 bodies", "limit of 2", "--max-bodies"],
        );
    }

    #[test]
    fn too_large_file() {
        let path = unique_temp("large.ron");
        std::fs::write(&path, GOOD_RON).unwrap();
        let limits = LoadLimits {
            max_file_bytes: 100,
            ..LoadLimits::default()
        };
        let source = path.to_str().unwrap();
        let m = load(source, &limits).unwrap_err().to_string();
        std::fs::remove_file(&path).ok();
        for word in [
            source,
            "more than the limit of 100 bytes",
            "--max-file-bytes",
        ] {
            assert!(m.contains(word), "message lacks {word:?}:\n{m}");
        }
        // The default limit is 64 MiB and the same file passes it.
        assert_eq!(LoadLimits::default().max_file_bytes, 64 * 1024 * 1024);
        expect_err(
            parse(GOOD_RON.as_bytes(), Format::Ron, "big.ron", &limits),
            &["big.ron", "limit of 100 bytes", "--max-file-bytes"],
        );
    }

    #[test]
    fn files_on_disk() {
        let path = unique_temp("disk.ron");
        std::fs::write(&path, GOOD_RON).unwrap();
        let scene = load(path.to_str().unwrap(), &LoadLimits::default()).unwrap();
        std::fs::remove_file(&path).ok();
        assert!(scene.name.ends_with("disk"), "{}", scene.name);
        assert_eq!(scene.bodies.len(), 3);

        let path = unique_temp("disk.JSON");
        std::fs::write(&path, GOOD_JSON).unwrap();
        let scene = load(path.to_str().unwrap(), &LoadLimits::default()).unwrap();
        std::fs::remove_file(&path).ok();
        assert_eq!(scene.bodies.len(), 3);
    }

    #[test]
    fn missing_file_unknown_extension_and_unknown_name() {
        let missing = unique_temp("missing.ron");
        let source = missing.to_str().unwrap();
        let m = load(source, &LoadLimits::default())
            .unwrap_err()
            .to_string();
        assert!(m.contains(source) && m.contains("cannot read"), "{m}");

        let m = load("scene.yaml", &LoadLimits::default())
            .unwrap_err()
            .to_string();
        assert!(
            m.contains("scene.yaml") && m.contains("`.ron` or `.json`"),
            "{m}"
        );

        let m = load("no_such_builtin_scene", &LoadLimits::default())
            .unwrap_err()
            .to_string();
        assert!(
            m.contains("no_such_builtin_scene") && m.contains("built-in scenes:"),
            "{m}"
        );
        for name in builtin::names() {
            assert!(m.contains(name), "message lacks built-in {name:?}:\n{m}");
        }

        let dir = unique_temp("dir.ron");
        std::fs::create_dir_all(&dir).unwrap();
        let m = load(dir.to_str().unwrap(), &LoadLimits::default())
            .unwrap_err()
            .to_string();
        std::fs::remove_dir(&dir).ok();
        assert!(
            m.contains("dir.ron") && m.contains("not a regular file"),
            "{m}"
        );
    }

    #[test]
    fn every_builtin_loads_and_validates() {
        for name in builtin::names() {
            let scene = load(name, &LoadLimits::default())
                .unwrap_or_else(|e| panic!("built-in {name} does not load: {e}"));
            assert!(!scene.name.is_empty());
            assert!(
                builtin::describe(name).is_some(),
                "{name} has no description"
            );
        }
    }

    #[test]
    fn not_utf8() {
        let mut bytes = b"(name: \"a\",\n  bodies: [], // caf".to_vec();
        bytes.extend_from_slice(&[0xff, 0xfe, b'\n', b')']);
        let e = parse(&bytes, Format::Ron, "bin.ron", &LoadLimits::default()).unwrap_err();
        let m = e.to_string();
        assert!(m.contains("bin.ron:2:") && m.contains("UTF-8"), "{m}");
        assert_eq!(e.position(), Some((2, 21)));
        let e = parse(&bytes, Format::Json, "bin.json", &LoadLimits::default()).unwrap_err();
        assert!(e.to_string().contains("bin.json:2:21"), "{e}");
    }

    #[test]
    fn deep_nesting_is_an_error_not_a_crash() {
        let depth = 100_000;
        let text = format!("(bodies: {}{})", "[".repeat(depth), "]".repeat(depth));
        expect_err(ron(&text, "deep.ron"), &["deep.ron:1:"]);
        let text = format!("{{\"bodies\": {}{}}}", "[".repeat(depth), "]".repeat(depth));
        expect_err(json(&text, "deep.json"), &["deep.json:1:"]);
        let text = format!("{}{}", "(".repeat(depth), ")".repeat(depth));
        expect_err(ron(&text, "parens.ron"), &["parens.ron:1:"]);
        let text = format!(
            "{{\"name\": {}{}}}",
            "{\"a\":".repeat(depth),
            "}".repeat(depth)
        );
        expect_err(json(&text, "obj.json"), &["obj.json:1:"]);
    }

    /// Mutated scenes, byte by byte: any result is fine, a panic fails the test.
    #[test]
    fn mutations_never_panic() {
        let mut state: u64 = 0x9e37_79b9_7f4a_7c15;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let inserts: &[&[u8]] = &[
            b"NaN",
            b"inf",
            b"-",
            b"1e39",
            b"1e999",
            b"0",
            b"(",
            b")",
            b"[",
            b"]",
            b",",
            b"\"",
            b"\xff",
            b"\xc3",
            b"//",
            b"/*",
            b"#![enable(implicit_some)]",
            b"99999999999999999999",
        ];
        for (text, format) in [(GOOD_RON, Format::Ron), (GOOD_JSON, Format::Json)] {
            for _ in 0..3000 {
                let mut bytes = text.as_bytes().to_vec();
                for _ in 0..1 + next() % 4 {
                    let at = (next() as usize) % (bytes.len() + 1);
                    match next() % 3 {
                        0 => {
                            if at < bytes.len() {
                                bytes.remove(at);
                            }
                        }
                        1 => {
                            let ins = inserts[(next() as usize) % inserts.len()];
                            bytes.splice(at..at, ins.iter().copied());
                        }
                        _ => {
                            if at < bytes.len() {
                                bytes[at] = next() as u8;
                            }
                        }
                    }
                }
                let _ = parse(&bytes, format, "fuzz", &LoadLimits::default());
            }
        }
    }

    #[test]
    fn ron_pairs_read_as_tuples_or_lists() {
        let tuple = "(gravity: (0, -9.8), bodies: [(shape: Box(half_extents: (0.5, 0.25)), position: (1, 2))])";
        let list = "(gravity: [0, -9.8], bodies: [(shape: Box(half_extents: [0.5, 0.25]), position: [1, 2])])";
        let a = parse(
            tuple.as_bytes(),
            Format::Ron,
            "t.ron",
            &LoadLimits::default(),
        )
        .unwrap();
        let b = parse(
            list.as_bytes(),
            Format::Ron,
            "l.ron",
            &LoadLimits::default(),
        )
        .unwrap();
        assert_eq!(a.gravity, [0.0, -9.8]);
        assert_eq!(a.bodies, b.bodies);
        assert_eq!(a.bodies[0].position, [1.0, 2.0]);
        let mixed = "(bodies: [(shape: Polygon(vertices: [(0, 0), [1, 0], (0, 1)]))])";
        let m = parse(
            mixed.as_bytes(),
            Format::Ron,
            "m.ron",
            &LoadLimits::default(),
        )
        .unwrap();
        assert!(
            matches!(&m.bodies[0].shape, Some(tumble_physics::ShapeDef::Polygon { vertices, radius: 0.0 }) if vertices.len() == 3)
        );
    }

    /// Four bodies, the fourth of two parts whose second has `filter` as its filter.
    fn fourth_body_second_part_json(filter: &str) -> String {
        let circle = r#"{"shape": {"Circle": {"radius": 1}}}"#;
        format!(
            "{{\"bodies\": [\n  {circle},\n  {circle},\n  {circle},\n  {{\"shapes\": [{circle}, \
             {{\"shape\": {{\"Circle\": {{\"radius\": 1}}}}, \"filter\": {filter}}}]}}\n]}}"
        )
    }

    fn fourth_body_second_part_ron(filter: &str) -> String {
        let circle = "(shape: Circle(radius: 1))";
        format!(
            "(bodies: [\n  {circle},\n  {circle},\n  {circle},\n  \
             (shapes: [{circle}, (shape: Circle(radius: 1), filter: {filter})]),\n])"
        )
    }

    /// Two circles and a revolute joint whose fields are `fields`.
    fn one_joint_json(fields: &str) -> String {
        let circle = r#"{"shape": {"Circle": {"radius": 1}}}"#;
        format!(r#"{{"bodies": [{circle}, {circle}], "joints": [{{"Revolute": {{{fields}}}}}]}}"#)
    }

    fn one_joint_ron(fields: &str) -> String {
        let circle = "(shape: Circle(radius: 1))";
        format!("(bodies: [{circle}, {circle}], joints: [Revolute({fields})])")
    }

    #[test]
    fn a_negative_category_names_the_field_path() {
        let path = "bodies[3].shapes[1].filter.category";
        let e = json(
            &fourth_body_second_part_json(r#"{"category": -1}"#),
            "neg.json",
        )
        .unwrap_err();
        assert_eq!(e.path(), Some(path));
        let m = e.to_string();
        assert!(
            m.starts_with(&format!(
                "neg.json:5:114: {path}: -1 is not an unsigned integer (u64)\n  hint: "
            )),
            "{m}"
        );
        let e = ron(&fourth_body_second_part_ron("(category: -1)"), "neg.ron").unwrap_err();
        assert_eq!(e.path(), Some(path));
        let m = e.to_string();
        assert!(
            m.starts_with("neg.ron:5:") && m.contains(&format!(": {path}: ")),
            "{m}"
        );
        // A good category loads, so the error was the sign alone.
        json(
            &fourth_body_second_part_json(r#"{"category": 2}"#),
            "ok.json",
        )
        .unwrap();
        ron(&fourth_body_second_part_ron("(category: 2)"), "ok.ron").unwrap();
    }

    #[test]
    fn a_string_for_a_number_in_a_joint_names_the_field_path() {
        let m = expect_err(
            json(
                &one_joint_json(r#""bodies": [0, 1], "anchor": [0, "zero"]"#),
                "joint.json",
            ),
            &[
                "joint.json:1:",
                ": joints[0].Revolute.anchor[1]: ",
                "string \"zero\"",
                "hint:",
            ],
        );
        assert!(m.contains("f32"), "{m}");
        expect_err(
            ron(
                &one_joint_ron(r#"bodies: (0, 1), anchor: (0, "zero")"#),
                "joint.ron",
            ),
            &["joint.ron:1:", ": joints[0].Revolute.anchor[1]: ", "hint:"],
        );
        // A body named by a string rather than its index.
        expect_err(
            json(
                &one_joint_json(r#""bodies": [0, "one"], "anchor": [0, 0]"#),
                "body.json",
            ),
            &[
                "body.json:1:",
                ": joints[0].Revolute.bodies[1]: ",
                "\"one\"",
            ],
        );
        expect_err(
            ron(
                &one_joint_ron(r#"bodies: (0, "one"), anchor: (0, 0)"#),
                "body.ron",
            ),
            &["body.ron:1:", ": joints[0].Revolute.bodies[1]: "],
        );
    }

    #[test]
    fn an_unknown_field_names_the_field_path() {
        let m = expect_err(
            json(
                &fourth_body_second_part_json(r#"{"categroy": 2}"#),
                "typo.json",
            ),
            &[
                "typo.json:5:",
                ": bodies[3].shapes[1].filter.categroy: unknown field `categroy`",
                "hint: allowed fields here: `category`, `mask`, `group`",
            ],
        );
        assert!(!m.contains("expected"), "the hint lists the fields: {m}");
        expect_err(
            ron(&fourth_body_second_part_ron("(categroy: 2)"), "typo.ron"),
            &[
                "typo.ron:5:",
                ": bodies[3].shapes[1].filter.categroy: unknown field `categroy`",
                "`category`, `mask`, `group`",
            ],
        );
        let m = expect_err(
            json(
                &one_joint_json(r#""bodies": [0, 1], "anchor": [0, 0], "ancor_b": [0, 0]"#),
                "joint.json",
            ),
            &[
                "joint.json:1:",
                ": joints[0].Revolute.ancor_b: unknown field",
            ],
        );
        assert!(m.contains("`anchor_b`"), "{m}");
        expect_err(
            ron(
                &one_joint_ron("bodies: (0, 1), anchor: (0, 0), ancor_b: (0, 0)"),
                "joint.ron",
            ),
            &[
                "joint.ron:1:",
                ": joints[0].Revolute.ancor_b: unknown field",
                "`anchor_b`",
            ],
        );
        // A top-level field is its own path; past the end of the scene there is none.
        let e = json(r#"{"bodies": [], "gravty": [0, -10]}"#, "top.json").unwrap_err();
        assert_eq!(e.path(), Some("gravty"));
        let e = json(r#"{"bodies": []} x"#, "tail.json").unwrap_err();
        assert_eq!(e.path(), None);
        assert!(e.to_string().starts_with("tail.json:1:16: trailing"), "{e}");
        let e = ron("(bodies: []) x", "tail.ron").unwrap_err();
        assert_eq!(e.path(), None);
    }
}
