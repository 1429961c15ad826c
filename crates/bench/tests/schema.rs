//! The scene format's JSON Schema (`tumble-bench schema`, docs/scene.schema.json): it is the
//! command's output, every scene in assets/scenes/ passes it, and it refuses what the loader
//! refuses (checked with boon, a JSON-Schema validator).

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::{Value, json};
use tumble_scene::{Format, LoadLimits};

const BIN: &str = env!("CARGO_BIN_EXE_tumble-bench");
/// Where the schema sits for boon (it is never fetched: the text is added as a resource).
const SCHEMA_URL: &str = "file:///tumble/docs/scene.schema.json";

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn committed_schema_text() -> String {
    let path = repo().join("docs/scene.schema.json");
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The committed schema, compiled.
struct Validator {
    schemas: boon::Schemas,
    index: boon::SchemaIndex,
}

impl Validator {
    fn new() -> Validator {
        let schema: Value =
            serde_json::from_str(&committed_schema_text()).expect("the schema is JSON");
        let mut schemas = boon::Schemas::new();
        let mut compiler = boon::Compiler::new();
        compiler
            .add_resource(SCHEMA_URL, schema)
            .expect("boon takes the schema");
        let index = compiler
            .compile(SCHEMA_URL, &mut schemas)
            .unwrap_or_else(|e| panic!("the schema compiles: {e:#}"));
        Validator { schemas, index }
    }

    /// `Err` with boon's message when the schema refuses `doc`.
    fn check(&self, doc: &Value) -> Result<(), String> {
        self.schemas
            .validate(doc, self.index)
            .map_err(|e| format!("{e:#}"))
    }
}

/// What tumble's loader makes of `doc` as a `.json` file: `Err` with its message if refused.
fn load_json(doc: &Value, origin: &str) -> Result<tumble_physics::SceneDef, String> {
    let bytes = serde_json::to_vec(doc).expect("a Value renders");
    tumble_scene::parse(&bytes, Format::Json, origin, &LoadLimits::default())
        .map_err(|e| e.to_string())
}

/// A RON scene as the JSON document that says the same thing: structs and maps become objects,
/// tuples and lists arrays, a unit variant (`Static`) its name as a string, and a variant with
/// fields (`Circle(radius: 0.5)`) serde's external tag, `{"Circle": {"radius": 0.5}}`.
///
/// `ron::Value` drops variant names, so this deserializes into serde's own buffer for untagged
/// enums instead: ron recognises that buffer and hands it each identifier (its "JSON enum
/// semantics for JSON content"), and the buffer then becomes a `serde_json::Value`. The test
/// `ron_renderings_are_faithful` checks the result against the loader.
fn ron_to_json(text: &str) -> Result<Value, ron::error::SpannedError> {
    #[derive(serde::Deserialize)]
    #[serde(untagged)]
    enum AnyValue {
        Json(Value),
    }
    let AnyValue::Json(value) = ron::Options::default().from_str::<AnyValue>(text)?;
    Ok(value)
}

/// Every scene in assets/scenes/, as JSON: the `.json` files as they are, the `.ron` files
/// through [`ron_to_json`]. Names end in the original's extension.
fn asset_scenes() -> Vec<(PathBuf, Value)> {
    let dir = repo().join("assets/scenes");
    let mut paths: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|entry| entry.expect("a directory entry").path())
        .filter(|p| p.is_file())
        .collect();
    paths.sort();
    paths
        .into_iter()
        .map(|path| {
            let text = std::fs::read_to_string(&path)
                .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            let doc = match path.extension().and_then(|e| e.to_str()) {
                Some("json") => serde_json::from_str(&text)
                    .unwrap_or_else(|e| panic!("{}: {e}", path.display())),
                Some("ron") => {
                    ron_to_json(&text).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
                }
                _ => panic!(
                    "{}: a scene file that is neither .ron nor .json; teach this test its syntax",
                    path.display()
                ),
            };
            (path, doc)
        })
        .collect()
}

#[test]
fn committed_schema_is_the_commands_output() {
    let committed = committed_schema_text();
    let out = Command::new(BIN)
        .arg("schema")
        .output()
        .expect("the tumble-bench binary runs");
    assert!(
        out.status.success(),
        "`tumble-bench schema` failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let printed = String::from_utf8(out.stdout).expect("the schema is UTF-8");
    if printed != committed {
        let line = printed
            .lines()
            .zip(committed.lines())
            .position(|(a, b)| a != b)
            .unwrap_or_else(|| printed.lines().count().min(committed.lines().count()));
        panic!(
            "docs/scene.schema.json is stale (from line {}: the command prints {:?}, the file has \
             {:?}); regenerate it with\n  cargo run -p tumble-bench -- schema --out docs/scene.schema.json",
            line + 1,
            printed.lines().nth(line).unwrap_or("the end"),
            committed.lines().nth(line).unwrap_or("the end"),
        );
    }

    // `--out FILE` writes the same bytes.
    let path =
        std::env::temp_dir().join(format!("tumble-bench-schema-{}.json", std::process::id()));
    let out = Command::new(BIN)
        .args(["schema", "--out"])
        .arg(&path)
        .output()
        .expect("the tumble-bench binary runs");
    let written = std::fs::read_to_string(&path);
    let _ = std::fs::remove_file(&path);
    assert!(
        out.status.success() && out.stdout.is_empty(),
        "`schema --out`: exit {:?}, stdout {:?}, stderr {}",
        out.status,
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(written.expect("--out wrote the file"), committed);
}

#[test]
fn every_asset_scene_passes_the_schema() {
    let validator = Validator::new();
    let scenes = asset_scenes();
    for ext in ["json", "ron"] {
        assert!(
            scenes
                .iter()
                .any(|(p, _)| p.extension().is_some_and(|e| e == ext)),
            "assets/scenes/ has no .{ext} scene left to check"
        );
    }
    for (path, doc) in &scenes {
        if let Err(e) = validator.check(doc) {
            panic!("{} fails the schema:\n{e}", path.display());
        }
    }
}

/// The JSON each RON scene became loads as exactly the scene the RON file loads as (and has
/// the variant names as serde's JSON writes them), so the schema checked the real file.
#[test]
fn ron_renderings_are_faithful() {
    let mut checked = 0;
    for (path, doc) in asset_scenes() {
        if path.extension().is_none_or(|e| e != "ron") {
            continue;
        }
        let origin = path.to_str().expect("UTF-8 paths");
        let from_ron = tumble_scene::load(origin, &LoadLimits::default())
            .unwrap_or_else(|e| panic!("{origin}: {e}"));
        let from_json = load_json(&doc, origin)
            .unwrap_or_else(|e| panic!("{origin}: its JSON rendering does not load: {e}\n{doc:#}"));
        assert_eq!(from_json, from_ron, "{origin}: the JSON rendering differs");
        let bodies = doc["bodies"].as_array().expect("bodies is a list");
        // Each body's shape, or each of its parts' shapes.
        let shapes = bodies.iter().flat_map(|b| match b["shapes"].as_array() {
            Some(parts) => parts.iter().map(|p| &p["shape"]).collect::<Vec<_>>(),
            None => vec![&b["shape"]],
        });
        for shape in shapes {
            assert!(
                shape.as_object().is_some_and(|o| o.len() == 1),
                "{origin}: a shape that is not {{\"Variant\": {{..}}}}: {shape}"
            );
        }
        checked += 1;
    }
    assert!(checked > 0, "no .ron scene in assets/scenes/");

    // The same with every construct spelled out, against the JSON serde itself writes.
    let ron = r#"(bodies: [(kind: Static, position: [1, 2.5], shape: Box(half_extents: (1.0, 0.5))),
        (shapes: [(shape: Polygon(vertices: [(0, 0), (1, 0), (0, 1)]), density: Some(2.0))])])"#;
    let expected = json!({"bodies": [
        {"kind": "Static", "position": [1, 2.5], "shape": {"Box": {"half_extents": [1.0, 0.5]}}},
        {"shapes": [{"shape": {"Polygon": {"vertices": [[0, 0], [1, 0], [0, 1]]}}, "density": 2.0}]}
    ]});
    assert_eq!(ron_to_json(ron).expect("the RON parses"), expected);
}

/// A small scene that passes both the schema and the loader, to break one way at a time.
fn good() -> Value {
    json!({
        "name": "good",
        "gravity": [0, -9.81],
        "solver": {"relax_iterations": 2, "contact_hertz": 30},
        "bodies": [
            {"kind": "Static", "position": [0.0, -0.5], "shape": {"Box": {"half_extents": [10.0, 0.5]}}},
            {"position": [0.0, 2.0], "shape": {"Circle": {"radius": 0.5}}, "awake": false},
            {"position": [1.0, 3.0], "shape": {"Polygon": {"vertices": [[-0.5, -0.4], [0.5, -0.4], [0.0, 0.6]]}}, "shapes": []},
            {
                "position": [3.0, 3.0],
                "filter": {"category": 2, "mask": 18446744073709551615u64, "group": -1},
                "shapes": [
                    {"shape": {"Box": {"half_extents": [0.5, 0.1]}}},
                    {"shape": {"Circle": {"radius": 0.2}}, "offset": [0.5, 0], "density": 2, "sensor": true}
                ]
            }
        ]
    })
}

#[test]
fn schema_accepts_what_the_loader_accepts() {
    let validator = Validator::new();
    let doc = good();
    load_json(&doc, "good.json").expect("the loader takes the good scene");
    validator
        .check(&doc)
        .expect("the schema takes the good scene");
    // Every default left out.
    let minimal = json!({"bodies": [{"shape": {"Circle": {"radius": 1}}}]});
    load_json(&minimal, "minimal.json").expect("the loader takes the minimal scene");
    validator
        .check(&minimal)
        .expect("the schema takes the minimal scene");
}

#[test]
fn schema_refuses_bad_documents() {
    let validator = Validator::new();
    // (what is wrong, how to break the good scene, a word of boon's message)
    type Break = fn(&mut Value);
    let cases: [(&str, Break, &str); 12] = [
        (
            "an unknown scene field",
            |d| d["gravty"] = json!([0, -10]),
            "gravty",
        ),
        (
            "an unknown body field",
            |d| d["bodies"][1]["frictoin"] = json!(0.3),
            "frictoin",
        ),
        (
            "an unknown field in a shape",
            |d| d["bodies"][1]["shape"] = json!({"Circle": {"radius": 0.5, "radus": 1}}),
            "radus",
        ),
        (
            "a shape of an unknown variant",
            |d| d["bodies"][1]["shape"] = json!({"Triangle": {"radius": 0.5}}),
            "/bodies/1/shape",
        ),
        (
            "a pair of three numbers",
            |d| d["bodies"][1]["position"] = json!([0.0, 2.0, 1.0]),
            "/bodies/1/position",
        ),
        (
            "a pair of one number",
            |d| d["gravity"] = json!([-10]),
            "/gravity",
        ),
        (
            "a part without `shape`",
            |d| d["bodies"][3]["shapes"][0] = json!({"offset": [0, 0]}),
            "shape",
        ),
        (
            "a body with both `shape` and `shapes`",
            |d| d["bodies"][3]["shape"] = json!({"Circle": {"radius": 0.5}}),
            "/bodies/3",
        ),
        (
            "a body with neither `shape` nor `shapes`",
            |d| {
                d["bodies"][1]
                    .as_object_mut()
                    .expect("a body")
                    .remove("shape");
            },
            "/bodies/1",
        ),
        (
            "a `shape` of null",
            |d| d["bodies"][1]["shape"] = Value::Null,
            "/bodies/1/shape",
        ),
        (
            "a circle of radius 0",
            |d| d["bodies"][1]["shape"] = json!({"Circle": {"radius": 0}}),
            "/bodies/1/shape",
        ),
        (
            "an unknown body kind",
            |d| d["bodies"][0]["kind"] = json!("Frozen"),
            "/bodies/0/kind",
        ),
    ];
    // Every case is tried; the failures are reported together.
    let mut failures = Vec::new();
    for (what, spoil, word) in cases {
        let mut doc = good();
        spoil(&mut doc);
        assert_ne!(doc, good(), "{what}: the case changed nothing");
        match validator.check(&doc) {
            Ok(()) => failures.push(format!("the schema takes {what}:\n{doc}")),
            Err(message) if !message.contains(word) => {
                failures.push(format!("{what}: boon's message lacks {word:?}:\n{message}"))
            }
            Err(_) => {}
        }
        if load_json(&doc, "bad.json").is_ok() {
            failures.push(format!(
                "the loader takes {what}, which this test expects refused:\n{doc}"
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}
