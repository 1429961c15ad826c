//! `tumble-bench run --events FILE` (CONTRACT.md sections 6 and 7): one JSON object a line, the
//! same file on 1 and 2 threads, and the events a small scene must make, each checked against
//! what the scene's closed forms say.

use std::path::PathBuf;
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_tumble-bench");

/// Body 0: static ground (top at y = 0); body 1: a box dropped from 5 m (its bottom at 5);
/// body 2: static, a solid disc (part 0) and a sensor box spanning y in [2, 4] (part 1) to
/// the right; body 3: a ball falling through that sensor from y = 10.
const SCENE: &str = r#"{
  "name": "events",
  "steps": 150,
  "hit_speed": 1,
  "bodies": [
    {"kind": "Static", "position": [0, -0.5], "shape": {"Box": {"half_extents": [4, 0.5]}}},
    {"position": [0, 5.5], "shape": {"Box": {"half_extents": [0.5, 0.5]}}},
    {"kind": "Static", "position": [10, 3], "shapes": [
      {"shape": {"Circle": {"radius": 0.2}}, "offset": [3, 0]},
      {"shape": {"Box": {"half_extents": [1, 1]}}, "sensor": true}
    ]},
    {"position": [10, 10], "shape": {"Circle": {"radius": 0.25}}}
  ]
}"#;

struct Temp(PathBuf);

impl Drop for Temp {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

fn run(dir: &std::path::Path, threads: u32) -> Vec<serde_json::Value> {
    let events = dir.join(format!("events-{threads}.jsonl"));
    let out = Command::new(BIN)
        .args(["run", dir.join("events.json").to_str().unwrap()])
        .args(["--threads", &threads.to_string(), "--out"])
        .arg(dir.join(format!("run-{threads}.json")))
        .arg("--events")
        .arg(&events)
        .output()
        .expect("the tumble-bench binary runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&events).unwrap();
    text.lines()
        .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("{l}: {e}")))
        .collect()
}

#[test]
fn the_runner_writes_each_event_as_a_json_line_the_same_on_any_thread_count() {
    let dir = Temp(std::env::temp_dir().join(format!("tumble-events-{}", std::process::id())));
    std::fs::create_dir_all(&dir.0).unwrap();
    std::fs::write(dir.0.join("events.json"), SCENE).unwrap();
    let one = run(&dir.0, 1);
    let two = run(&dir.0, 2);
    assert_eq!(one, two, "the event file depends on the thread count");
    let kinds: Vec<&str> = one.iter().map(|e| e["type"].as_str().unwrap()).collect();
    assert_eq!(
        kinds,
        ["contact_begin", "hit", "sensor_begin", "sensor_end"],
        "{one:#?}"
    );
    let step = |i: usize| one[i]["step"].as_u64().unwrap();
    // The box lands after falling 5 m: t = √(2h/g) = 1 s = 60 steps; the contact begins within
    // the speculative margin (a step or two early) and hits when it first pushes.
    let (begin, hit) = (&one[0], &one[1]);
    assert!((58..=61).contains(&step(0)), "{begin}");
    assert!(step(1) >= step(0) && step(1) <= 61, "{hit}");
    for e in [begin, hit] {
        assert_eq!(e["bodies"], serde_json::json!([0, 1]));
        assert_eq!(e["shapes"], serde_json::json!([0, 0]));
    }
    // Free fall to 10 m/s (√(2 g h)), less up to two steps of gravity (see the physics
    // crate's own test of hits).
    let v = hit["approach_speed"].as_f64().unwrap();
    assert!(v <= 10.001 && v > 10.0 - 2.0 * 10.0 / 60.0, "{hit}");
    assert_eq!(hit["normal"], serde_json::json!([0.0, 1.0]));
    assert!(hit["point"][1].as_f64().unwrap() >= -0.005);
    assert!(begin.get("point").is_none(), "only a hit has a point");
    // The ball: enters the sensor's top (y = 4) when its centre is below 4.25, after
    // √(2 · 5.75 / 10) = 1.07 s (step 65); leaves its bottom (2) below 1.75, after
    // √(2 · 8.25 / 10) = 1.28 s (step 77). Sensor (body 2, part 1) first.
    for (i, expected) in [(2, 65), (3, 77)] {
        let s = step(i) as i64;
        assert!((s - expected).abs() <= 1, "{}", one[i]);
        assert_eq!(one[i]["bodies"], serde_json::json!([2, 3]));
        assert_eq!(one[i]["shapes"], serde_json::json!([1, 0]));
    }
}

/// Body 0: a static pin; body 1: a 1 kg box hanging 2 m below it on a hinge (joint 0) that
/// reports past 9 N; body 2: a box swinging on a hinge (joint 1) that never reports.
const BRIDGE: &str = r#"{
  "name": "thresholds",
  "steps": 20,
  "bodies": [
    {"kind": "Static", "position": [0, 5], "shape": {"Circle": {"radius": 0.1}}},
    {"position": [0, 3], "shape": {"Box": {"half_extents": [0.5, 0.5]}}},
    {"position": [6, 5], "shape": {"Box": {"half_extents": [0.5, 0.5]}}}
  ],
  "joints": [
    {"Revolute": {"bodies": [0, 1], "anchor": [0, 5], "force_threshold": 9}},
    {"Revolute": {"bodies": [0, 2], "anchor": [4, 5], "torque_threshold": 1000}}
  ]
}"#;

#[test]
fn a_joint_past_its_threshold_is_a_joint_threshold_line_on_any_thread_count() {
    let dir =
        Temp(std::env::temp_dir().join(format!("tumble-joint-events-{}", std::process::id())));
    std::fs::create_dir_all(&dir.0).unwrap();
    std::fs::write(dir.0.join("events.json"), BRIDGE).unwrap();
    let one = run(&dir.0, 1);
    assert_eq!(
        one,
        run(&dir.0, 2),
        "the event file depends on the thread count"
    );
    // The hanging box pulls with its weight, 10 N (default gravity), from the first step:
    // one line a step, joint 0, no bodies or shapes.
    assert_eq!(one.len(), 20, "{one:#?}");
    for (k, e) in one.iter().enumerate() {
        assert_eq!(e["step"].as_u64(), Some(k as u64 + 1));
        assert_eq!(e["type"], "joint_threshold");
        assert_eq!(e["joint"], 0);
        assert!(
            e.get("bodies").is_none() && e.get("shapes").is_none(),
            "{e}"
        );
        let force = e["force"].as_f64().unwrap();
        assert!(force > 9.0 && force < 11.0, "{e}");
        assert!(e["torque"].as_f64().unwrap().abs() < 1e-3, "{e}");
    }
}
