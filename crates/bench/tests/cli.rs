//! The runner's command line, as a script would use it (CONTRACT.md, section 2).

use std::path::PathBuf;
use std::process::{Command, Output};
use std::sync::atomic::{AtomicUsize, Ordering};

use serde_json::Value;

const BIN: &str = env!("CARGO_BIN_EXE_tumble-bench");
/// Small and lively: circles raining on a box pyramid.
const SCENE: &str = "falling_circles";

fn bench(args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        // A backtrace must not appear even when one is asked for.
        .env("RUST_BACKTRACE", "1")
        .output()
        .expect("the tumble-bench binary runs")
}

fn stdout_json(out: &Output) -> Value {
    assert!(
        out.status.success(),
        "exit {:?}, stderr:\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("stdout is one JSON document")
}

/// A file under the temp dir with a name no other test (or test run) uses.
struct TempFile(PathBuf);

impl TempFile {
    fn new(name: &str, contents: &[u8]) -> TempFile {
        static COUNTER: AtomicUsize = AtomicUsize::new(0);
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        let path = std::env::temp_dir().join(format!(
            "tumble-bench-cli-{}-{n}-{name}",
            std::process::id()
        ));
        std::fs::write(&path, contents).expect("write a temp file");
        TempFile(path)
    }

    fn path(&self) -> &str {
        self.0.to_str().expect("temp paths are UTF-8 here")
    }
}

impl Drop for TempFile {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.0);
    }
}

/// Runs with `args`, expects a refusal whose stderr holds every one of `words` and no sign of a
/// panic; returns stderr.
#[track_caller]
fn refused(args: &[&str], words: &[&str]) -> String {
    let out = bench(args);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(
        !out.status.success(),
        "{args:?} should fail; stdout:\n{}",
        String::from_utf8_lossy(&out.stdout)
    );
    assert!(out.status.code().is_some(), "{args:?} died by a signal");
    assert!(out.stdout.is_empty(), "{args:?} wrote to stdout");
    for word in words {
        assert!(
            stderr.contains(word),
            "{args:?}: stderr lacks {word:?}:\n{stderr}"
        );
    }
    for bad in ["panicked", "backtrace", "RUST_BACKTRACE"] {
        assert!(
            !stderr.contains(bad),
            "{args:?}: stderr has {bad:?}:\n{stderr}"
        );
    }
    stderr
}

/// Runs a scene file with these contents and expects a refusal naming the file and `words`.
#[track_caller]
fn refused_file(name: &str, contents: &str, extra: &[&str], words: &[&str]) -> String {
    let file = TempFile::new(name, contents.as_bytes());
    let mut args = vec!["run", file.path(), "--steps", "1"];
    args.extend_from_slice(extra);
    let mut all = vec![file.path()];
    all.extend_from_slice(words);
    refused(&args, &all)
}

fn f32_of(v: &Value) -> f32 {
    let x = v.as_f64().unwrap_or_else(|| panic!("{v} is not a number"));
    assert!(x.is_finite(), "{v} is not finite");
    x as f32
}

#[test]
fn a_good_run_writes_the_contract_document() {
    let out = bench(&["run", SCENE, "--steps", "20", "--threads", "2"]);
    let doc = stdout_json(&out);
    let expected = tumble_scene::builtin::build(SCENE).expect("the scene is built in");

    assert_eq!(doc["scene"], SCENE);
    assert_eq!(doc["steps"], 20);
    assert_eq!(doc["threads"], 2);
    assert_eq!(f32_of(&doc["dt"]), expected.dt);
    assert_eq!(doc["substeps"], expected.substeps);
    let time = doc["time"].as_f64().unwrap();
    assert!(
        (time - 20.0 * f64::from(expected.dt)).abs() < 1e-9,
        "{time}"
    );
    let hash = doc["state_hash"].as_str().unwrap();
    assert_eq!(hash.len(), 16, "{hash}");
    assert!(hash.bytes().all(|b| b.is_ascii_hexdigit()), "{hash}");

    let bodies = doc["bodies"].as_array().unwrap();
    assert_eq!(bodies.len(), expected.bodies.len());
    for body in bodies {
        let keys: Vec<&str> = body
            .as_object()
            .unwrap()
            .keys()
            .map(|k| k.as_str())
            .collect();
        for key in ["position", "angle", "linear_velocity", "angular_velocity"] {
            assert!(keys.contains(&key), "a body lacks {key}: {body}");
        }
        for pair in [&body["position"], &body["linear_velocity"]] {
            let pair = pair.as_array().unwrap();
            assert_eq!(pair.len(), 2);
            pair.iter().for_each(|v| {
                f32_of(v);
            });
        }
        f32_of(&body["angle"]);
        f32_of(&body["angular_velocity"]);
    }
    // Something fell: the dynamic bodies are not all where they started.
    let moved = bodies
        .iter()
        .zip(&expected.bodies)
        .any(|(b, d)| f32_of(&b["position"][1]) != d.position[1]);
    assert!(moved, "no body moved in 20 steps");

    // CONTRACT.md section 6: how often the engine had to stop a body whose state turned
    // non-finite over the whole run; a healthy run reports 0.
    assert_eq!(doc["non_finite_bodies"], 0, "{doc}");

    let profile = doc["profile"].as_object().unwrap();
    let mean = profile["step_ms_mean"].as_f64().unwrap();
    assert!(mean.is_finite() && mean >= 0.0, "{mean}");
    for (key, value) in profile {
        assert!(key.ends_with("_ms_mean"), "{key}");
        let v = value.as_f64().unwrap();
        assert!(v.is_finite() && v >= 0.0, "{key} = {v}");
    }
}

#[test]
fn the_json_reads_back_bit_for_bit() {
    let doc = stdout_json(&bench(&["run", SCENE, "--steps", "15", "--threads", "2"]));
    let scene = tumble_scene::load(SCENE, &tumble_scene::LoadLimits::default()).unwrap();
    let mut world =
        tumble_physics::World::from_scene(&scene, &tumble_physics::Limits::default()).unwrap();
    world.set_thread_count(1);
    for _ in 0..15 {
        world.step(scene.dt, scene.substeps);
    }
    assert_eq!(
        doc["state_hash"].as_str().unwrap(),
        format!("{:016x}", world.state_hash())
    );
    let bodies = doc["bodies"].as_array().unwrap();
    assert_eq!(bodies.len(), world.body_count());
    for (i, b) in bodies.iter().enumerate() {
        let v = world.body(tumble_physics::BodyId::scene(i)).unwrap();
        let read: f32 = serde_json::from_value(b["position"][0].clone()).unwrap();
        assert_eq!(read.to_bits(), v.position.x.to_bits(), "body {i} x");
        let read: f32 = serde_json::from_value(b["position"][1].clone()).unwrap();
        assert_eq!(read.to_bits(), v.position.y.to_bits(), "body {i} y");
        let read: f32 = serde_json::from_value(b["angle"].clone()).unwrap();
        assert_eq!(read.to_bits(), v.angle.to_bits(), "body {i} angle");
        let read: f32 = serde_json::from_value(b["linear_velocity"][0].clone()).unwrap();
        assert_eq!(read.to_bits(), v.linear_velocity.x.to_bits(), "body {i} vx");
        let read: f32 = serde_json::from_value(b["angular_velocity"].clone()).unwrap();
        assert_eq!(read.to_bits(), v.angular_velocity.to_bits(), "body {i} w");
    }
}

#[test]
fn one_and_two_threads_agree() {
    let one = stdout_json(&bench(&["run", SCENE, "--steps", "60", "--threads", "1"]));
    let two = stdout_json(&bench(&["run", SCENE, "--steps", "60", "--threads", "2"]));
    assert_eq!(one["threads"], 1);
    assert_eq!(two["threads"], 2);
    assert_eq!(one["state_hash"], two["state_hash"]);
    assert_eq!(one["bodies"], two["bodies"]);
}

#[test]
fn a_pre_solve_hook_that_lets_every_contact_push_changes_nothing() {
    // `--pre-solve` measures the hook's cost: the hook is called (a pyramid has contacts
    // from its first step) and answers yes, so the state is the plain run's bit for bit.
    let plain = stdout_json(&bench(&[
        "run",
        "pyramid",
        "--steps",
        "60",
        "--threads",
        "2",
    ]));
    let hooked = stdout_json(&bench(&[
        "run",
        "pyramid",
        "--steps",
        "60",
        "--threads",
        "2",
        "--pre-solve",
    ]));
    assert!(plain["contacts"].as_u64().unwrap() > 0);
    assert_eq!(plain["state_hash"], hooked["state_hash"]);
}

#[test]
fn a_scene_file_runs_and_out_writes_the_file() {
    let scene = TempFile::new(
        "drop.ron",
        br#"(
    substeps: 2,
    steps: 5,
    bodies: [
        (kind: Static, position: (0.0, -1.0), shape: Box(half_extents: (5.0, 1.0))),
        (position: (0.0, 1.0), shape: Circle(radius: 0.5)),
        (position: (0.2, 3.0), shape: Polygon(vertices: [(-0.5, -0.5), (0.5, -0.5), (0.0, 0.5)])),
    ],
)"#,
    );
    let out_file = TempFile::new("report.json", b"");
    let out = bench(&[
        "run",
        scene.path(),
        "--out",
        out_file.path(),
        "--threads",
        "1",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.stdout.is_empty(), "with --out, stdout stays empty");
    let doc: Value = serde_json::from_slice(&std::fs::read(&out_file.0).unwrap()).unwrap();
    // The name is the file's stem; steps and substeps come from the scene.
    assert!(
        doc["scene"].as_str().unwrap().ends_with("drop"),
        "{}",
        doc["scene"]
    );
    assert_eq!(doc["steps"], 5);
    assert_eq!(doc["substeps"], 2);
    assert_eq!(doc["bodies"].as_array().unwrap().len(), 3);

    // --substeps overrides the scene's.
    let doc = stdout_json(&bench(&[
        "run",
        scene.path(),
        "--substeps",
        "3",
        "--steps",
        "2",
    ]));
    assert_eq!(doc["substeps"], 3);
    assert_eq!(doc["steps"], 2);
}

const CIRCLE: &str = "shape: Circle(radius: 1.0)";

fn one_body(fields: &str) -> String {
    format!("(bodies: [\n    ({fields}),\n])\n")
}

#[test]
fn syntax_error() {
    refused_file(
        "syntax.ron",
        "(bodies: [\n    (shape: Circle(radius: 1.0))\n    (shape: Circle(radius: 1.0)),\n])",
        &[],
        &[":3:", "comma", "hint"],
    );
    refused_file(
        "syntax.json",
        "{\"bodies\": [\n  {\"shape\": {\"Circle\": {\"radius\": 1.0}}},\n]}",
        &[],
        &[":3:", "trailing comma"],
    );
}

#[test]
fn unknown_field() {
    refused_file(
        "typo.ron",
        &one_body("shape: Circle(radius: 1.0), frictoin: 0.5"),
        &[],
        &[":2:", "frictoin", "`friction`", "`restitution`"],
    );
    refused_file(
        "typo.json",
        "{\"bodies\": [], \"substep\": 4}",
        &[],
        &[":1:", "substep", "`substeps`", "`gravity`"],
    );
}

#[test]
fn wrong_type() {
    refused_file(
        "type.json",
        "{\"substeps\": \"four\", \"bodies\": []}",
        &[],
        &[":1:", "u32"],
    );
    refused_file(
        "type.ron",
        &one_body("position: \"here\", shape: Circle(radius: 1.0)"),
        &[],
        &[":2:", "a pair of numbers", "[x, y]"],
    );
}

#[test]
fn negative_or_zero_size() {
    refused_file(
        "radius.ron",
        &one_body("shape: Circle(radius: -1.0)"),
        &[],
        &["body 0", "shape.Circle.radius", "-1", "> 0"],
    );
    refused_file(
        "box.json",
        "{\"bodies\": [{\"shape\": {\"Box\": {\"half_extents\": [1, 0]}}}]}",
        &[],
        &["body 0", "shape.Box.half_extents", "> 0"],
    );
}

#[test]
fn non_finite_number() {
    refused_file(
        "nan.ron",
        &one_body(&format!("angle: NaN, {CIRCLE}")),
        &[],
        &["body 0", "angle", "NaN", "finite"],
    );
    refused_file(
        "inf.ron",
        &one_body(&format!("position: (0.0, -inf), {CIRCLE}")),
        &[],
        &["body 0", "position", "finite"],
    );
    refused_file(
        "big.json",
        "{\"bodies\": [{\"linear_velocity\": [1e39, 0], \"shape\": {\"Circle\": {\"radius\": 1}}}]}",
        &[],
        &["body 0", "linear_velocity", "finite"],
    );
}

#[test]
fn non_convex_polygon() {
    refused_file(
        "arrow.ron",
        &one_body("shape: Polygon(vertices: [(-1.0, -1.0), (0.0, 0.2), (1.0, -1.0), (0.0, 1.0)])"),
        &[],
        &[
            "body 0",
            "shape.Polygon.vertices",
            "convex",
            "counter-clockwise",
        ],
    );
}

#[test]
fn degenerate_polygon() {
    refused_file(
        "flat.ron",
        &one_body("shape: Polygon(vertices: [(0.0, 0.0), (1.0, 0.0), (2.0, 0.0)])"),
        &[],
        &["body 0", "shape.Polygon.vertices", "non-zero area"],
    );
}

#[test]
fn zero_density_dynamic_body() {
    refused_file(
        "density.ron",
        &one_body(&format!("density: 0.0, {CIRCLE}")),
        &[],
        &["body 0", "density", "> 0 for a dynamic body"],
    );
}

#[test]
fn dt_not_positive() {
    refused_file("dt.ron", "(dt: 0.0, bodies: [])", &[], &["`dt`", "> 0"]);
    refused_file(
        "dt.json",
        "{\"dt\": -1, \"bodies\": []}",
        &[],
        &["`dt`", "-1", "> 0"],
    );
}

#[test]
fn dt_subnormal() {
    // 1e-40 is above 0 but subnormal in f32: the step would refuse it and never move.
    refused_file(
        "tiny_dt.ron",
        "(dt: 1e-40, bodies: [])",
        &[],
        &["`dt`", "subnormal"],
    );
    // A normal dt that --substeps makes a subnormal substep.
    refused_file(
        "tiny_substep.ron",
        "(dt: 2e-38, substeps: 1, bodies: [])",
        &["--substeps", "8"],
        &["`dt`", "substep", "fewer substeps"],
    );
}

#[test]
fn mass_or_inertia_too_small_to_invert() {
    refused_file(
        "tiny_mass.ron",
        &one_body("shape: Circle(radius: 1e-20)"),
        &[],
        &[
            "body 0",
            "`density`",
            "mass",
            "raise the density or enlarge the shape",
        ],
    );
    refused_file(
        "tiny_inertia.ron",
        &one_body("shape: Circle(radius: 1e-10)"),
        &[],
        &["body 0", "`shape`", "rotational inertia", "fixed_rotation"],
    );
}

#[test]
fn substeps_zero() {
    refused_file(
        "substeps.ron",
        "(substeps: 0, bodies: [])",
        &[],
        &["`substeps`", "from 1 to"],
    );
}

#[test]
fn too_many_bodies() {
    let text = format!("(bodies: [({CIRCLE}), ({CIRCLE}), ({CIRCLE})])");
    refused_file(
        "many.ron",
        &text,
        &["--max-bodies", "2"],
        &["3 bodies", "limit of 2", "--max-bodies"],
    );
    // Raising the limit lets it through.
    let file = TempFile::new("many_ok.ron", text.as_bytes());
    let out = bench(&["run", file.path(), "--steps", "1", "--max-bodies", "3"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn too_large_file() {
    refused_file(
        "large.ron",
        &one_body(CIRCLE),
        &["--max-file-bytes", "16"],
        &["more than the limit of 16 bytes", "--max-file-bytes"],
    );
}

#[test]
fn not_utf8() {
    let file = TempFile::new("binary.ron", b"(bodies: [\xff\xfe])");
    refused(&["run", file.path()], &[file.path(), ":1:11", "UTF-8"]);
}

#[test]
fn missing_file_and_unknown_extension() {
    let missing =
        std::env::temp_dir().join(format!("tumble-bench-cli-{}-nope.ron", std::process::id()));
    let missing = missing.to_str().unwrap();
    refused(&["run", missing], &[missing, "cannot read"]);
    let file = TempFile::new("scene.yaml", b"bodies: []");
    refused(&["run", file.path()], &[file.path(), "`.ron` or `.json`"]);
}

#[test]
fn unknown_scene_lists_the_built_ins() {
    let stderr = refused(
        &["run", "no_such_scene"],
        &["no_such_scene", "built-in scenes:"],
    );
    for name in tumble_scene::builtin::names() {
        assert!(stderr.contains(name), "stderr lacks {name}:\n{stderr}");
    }
}

#[test]
fn bad_flags() {
    refused(&["run", SCENE, "--threads", "0"], &["--threads", "0"]);
    refused(&["run", SCENE, "--threads", "-2"], &["--threads"]);
    refused(&["run", SCENE, "--threads", "many"], &["--threads", "many"]);
    refused(&["run", SCENE, "--steps", "-1"], &["--steps", "-1"]);
    refused(&["run", SCENE, "--steps", "1.5"], &["--steps"]);
    refused(&["run", SCENE, "--substeps", "0"], &["--substeps", "0"]);
    refused(
        &["run", SCENE, "--substeps", "100000"],
        &["--substeps", "1 to"],
    );
    refused(&["run", SCENE, "--bogus"], &["--bogus"]);
    refused(&["run"], &["SCENE"]);
    refused(&["walk", SCENE], &["walk"]);
    refused(&[], &["Usage"]);
    let dir = std::env::temp_dir().join(format!("tumble-bench-cli-{}-no-dir", std::process::id()));
    let out = dir.join("report.json");
    refused(
        &["run", SCENE, "--steps", "1", "--out", out.to_str().unwrap()],
        &["cannot create the output file", "report.json"],
    );
}

#[test]
fn help_exits_zero() {
    let out = bench(&["run", "--help"]);
    assert!(out.status.success());
    let help = String::from_utf8_lossy(&out.stdout);
    for flag in [
        "--steps",
        "--threads",
        "--substeps",
        "--out",
        "--max-bodies",
    ] {
        assert!(help.contains(flag), "help lacks {flag}:\n{help}");
    }
}

#[test]
fn soak_reports_memory_and_finiteness_at_each_checkpoint() {
    // A small pile, long enough for it to fall and touch: 300 bodies for 300 steps.
    let out_file = TempFile::new("soak.json", b"");
    let out = bench(&[
        "soak",
        "--bodies",
        "300",
        "--steps",
        "300",
        "--threads",
        "2",
        "--checkpoints",
        "3",
        "--out",
        out_file.path(),
    ]);
    assert!(
        out.status.success(),
        "exit {:?}, stderr:\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert_eq!(stdout.lines().filter(|l| l.starts_with("step ")).count(), 3);
    let summary: Value =
        serde_json::from_slice(&std::fs::read(&out_file.0).unwrap()).expect("JSON summary");
    // 300 dynamic bodies plus the ground and two walls.
    assert_eq!(summary["bodies"], 303);
    assert_eq!(summary["steps"], 300);
    assert_eq!(summary["finite"], true);
    assert_eq!(summary["guard_fired"], 0);
    let checkpoints = summary["checkpoints"].as_array().unwrap();
    assert_eq!(checkpoints.len(), 3);
    assert_eq!(checkpoints[2]["step"], 300);
    // The pile has formed by the end: most bodies touch one or two others.
    assert!(checkpoints[2]["contacts"].as_u64().unwrap() > 300);
    // The kernel's high-water mark is at least the resident size it was taken beside.
    let peak = summary["peak_resident_kb"].as_u64().unwrap();
    assert!(peak >= checkpoints[2]["resident_kb"].as_u64().unwrap() && peak > 0);
}

#[test]
fn soak_refuses_a_bad_flag() {
    let out = bench(&["soak", "--bodies", "0"]);
    assert_eq!(out.status.code(), Some(2));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("--bodies"), "{stderr}");
    assert!(!stderr.contains("panicked"), "{stderr}");
}
