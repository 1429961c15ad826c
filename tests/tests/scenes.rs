//! Every built-in scene and every scene file in `assets/scenes/` loads, builds and runs with
//! all body states finite.

use std::path::{Path, PathBuf};
use std::time::Instant;

use tumble_physics::SceneDef;
use tumble_scene::LoadLimits;
use tumble_tests::{all_finite, run, world};

/// Steps per scene: 100 (1.7 s at 60 Hz) covers every scene's first impacts and settling,
/// including smash, whose block reaches the wall at step 69 (46 m at 40 m/s). No scene gets
/// fewer: with the physics crate optimised in the dev profile, the three largest take 0.6 s
/// (large_pyramid), 2.0 s (many_pyramids) and 1.3 s (smash) for 100 steps on 2 cores, about
/// 4 s for this whole file.
const STEPS: u32 = 100;

fn check(scene: &SceneDef) {
    let steps = STEPS;
    let t = Instant::now();
    let mut w = world(scene);
    assert!(
        all_finite(&w),
        "{}: non-finite state before stepping",
        scene.name
    );
    let built = t.elapsed();
    run(&mut w, scene, steps);
    eprintln!(
        "{}: {} bodies, built in {:.0} ms, {steps} steps in {:.0} ms, {} contacts",
        scene.name,
        w.body_count(),
        built.as_secs_f64() * 1e3,
        (t.elapsed() - built).as_secs_f64() * 1e3,
        w.contact_count()
    );
    assert_eq!(
        w.step_count(),
        u64::from(steps),
        "{}: steps taken",
        scene.name
    );
    assert!(
        all_finite(&w),
        "{}: a body's state is not finite after {steps} steps",
        scene.name
    );
}

#[test]
fn every_builtin_runs_finite() {
    let names = tumble_scene::builtin::names();
    assert!(!names.is_empty());
    for &name in names {
        let scene = match tumble_scene::load(name, &LoadLimits::default()) {
            Ok(s) => s,
            Err(e) => panic!("built-in {name} does not load: {e}"),
        };
        check(&scene);
    }
}

fn scene_files() -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/scenes");
    let entries = match std::fs::read_dir(&dir) {
        Ok(e) => e,
        Err(e) => panic!("cannot read {}: {e}", dir.display()),
    };
    let mut files: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            matches!(
                p.extension().and_then(|e| e.to_str()),
                Some("ron") | Some("json")
            )
        })
        .collect();
    files.sort();
    files
}

#[test]
fn every_scene_file_runs_finite() {
    let files = scene_files();
    // The repository ships five example scenes; an empty list would make this test vacuous.
    assert!(files.len() >= 5, "found only {files:?}");
    for path in files {
        let source = path.to_string_lossy();
        let scene = match tumble_scene::load(&source, &LoadLimits::default()) {
            Ok(s) => s,
            Err(e) => panic!("{source} does not load: {e}"),
        };
        check(&scene);
    }
}
