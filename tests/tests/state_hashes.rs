//! Every built-in scene and every scene file in `assets/scenes/` ends its first 100 steps in
//! the state it reached when its figure was set: `World::state_hash` (the exact bits of every
//! body's pose and velocities) after each step, folded together. The figures were first the
//! code's at 3349a60, before the redesign of issue 33 (one handle per object, the world's
//! stores), which left every one as it was; they moved twice since, when a manifold's two
//! points came to be solved together by default (issue 36, docs/accuracy/flat_landing.md),
//! and in the scenes where something bounces, when impacts came to bounce as their
//! restitution says by default (`StepSettings::impacts_bounce`, issue 36). A
//! change to the world's layout or its public API must leave the physics bit for bit as it
//! was; a change that means to move the physics updates this table and says why in its commit.

use std::path::Path;

use tumble_physics::SceneDef;
use tumble_scene::LoadLimits;
use tumble_tests::{all_finite, world};

/// Steps per scene, as `scenes.rs` takes them (every scene's first impacts).
const STEPS: u32 = 100;

/// (scene, hash of the per-step hashes), with the points solved together and impacts that
/// bounce; the scene files by their file name.
const EXPECTED: &[(&str, u64)] = &[
    ("falling_circles", 0xf0a1cf8dad23098d),
    ("pyramid", 0xb2b27a18ecaad2dd),
    ("vertical_stack", 0x5817495003236331),
    ("card_house", 0x9b95f2ac0faf22eb),
    ("arch", 0x4a1b67baa85401a2),
    ("friction_ramp", 0x7e9ee1301579a80c),
    ("mass_ratio", 0xbca87ff68938aa92),
    ("overlap_recovery", 0x4afc5a9d0c3b118c),
    ("confined", 0x82e6ce742de68b8b),
    ("far_from_origin", 0x246fa984e6be0ee2),
    ("mass_ratio_columns", 0x7ff82e1bcc1ec038),
    ("friction_incline", 0x7333dee7a55c432b),
    ("restitution_drop", 0x0cf75b09bd62d67b),
    ("elastic_box", 0x9cf849c69f68a4be),
    ("large_pyramid", 0x755eee2f0bfe705b),
    ("pyramid_200", 0x09ad7b7150b090e4),
    ("many_pyramids", 0x605a3e758856a5bf),
    ("smash", 0x1f0e0c843dd40345),
    ("tumbler", 0x9d01b07eb01832b9),
    ("compounds", 0xb779608689605ab5),
    ("junkyard", 0xe8275416dda6d02e),
    ("spinner", 0x9ed0f892290f406d),
    ("joint_grid", 0xeb92b48818b920c6),
    ("ball_and_chain", 0x99464a376e78c0d7),
    ("bridge", 0x75580eea575b07e2),
    ("stretched_chain", 0x2a4f2846c61bbb2a),
    ("ragdoll", 0x6a99776256bd2428),
    ("rain", 0x113a97d578931784),
    ("washer", 0x0a47e32a822aaa75),
    ("platformer", 0xc4b42448f7573b61),
    ("forces", 0xd786fdd173133f8f),
    ("materials", 0xc5531ca9057c0b05),
    ("conveyor_belts", 0x0247c94c639a0308),
    ("rolling_resistance", 0xab528edede71c1cf),
    ("one_way_platforms", 0xce2ae4beb4589b69),
    ("explosions", 0x07a7db5d1819058a),
    ("breakable_joints", 0x4cb9fa0269ec0116),
    ("sensors", 0x174f48b3d3cfb73e),
    ("ray_casts", 0x11c51f49cc1ca0d1),
    ("contact_events", 0x793c119c2f26ae58),
    ("sleep_and_wake", 0x828554250d2ca18e),
    ("bullets", 0xf50e9dbc637fe030),
    ("joint_kinds", 0x22ded22b9bcdfa6a),
    ("bouncing_balls.json", 0x07e8f1e0d3aab02d),
    ("capsule_stairs.ron", 0xea7e32b9d09c843e),
    ("car.ron", 0xcd8e9c87c1ec1a93),
    ("chain_slope.ron", 0x995db5a9d11daf69),
    ("compound_shapes.ron", 0xe49863b0ce7ed948),
    ("domino.ron", 0x68aced17a2fc631e),
    ("drawbridge.ron", 0x04c8f7c3f0b51a70),
    ("newtons_cradle.ron", 0x12173f0325e95bd6),
    ("newtons_cradle_strung.ron", 0x78eb852162b23c13),
    ("pinball.ron", 0xe7867e16ff3e5db0),
    ("polygons.ron", 0xd0a10f4168a95fbf),
    ("ramp.ron", 0xc9e008fd550a5b4d),
];

/// The step-by-step hashes of a scene's run, folded by FNV-1a: a difference at any step
/// shows, even one that a later step happens to undo.
fn run_hash(scene: &SceneDef) -> u64 {
    let mut w = world(scene);
    let script = tumble_scene::builtin::script_for(scene);
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for _ in 0..STEPS {
        if let Some(script) = script {
            script(w.step_count(), &mut w);
        }
        w.step(scene.dt, scene.substeps);
        for byte in w.state_hash().to_le_bytes() {
            h ^= u64::from(byte);
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    assert!(all_finite(&w), "{}: non-finite state", scene.name);
    h
}

/// Every scene this test covers: the built-ins by name, then the scene files by file name.
fn scenes() -> Vec<(String, SceneDef)> {
    let limits = LoadLimits::default();
    let mut out: Vec<(String, SceneDef)> = tumble_scene::builtin::names()
        .iter()
        .map(|&name| {
            let scene = tumble_scene::load(name, &limits)
                .unwrap_or_else(|e| panic!("built-in {name} does not load: {e}"));
            (name.to_string(), scene)
        })
        .collect();
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../assets/scenes");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", dir.display()))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| matches!(p.extension().and_then(|e| e.to_str()), Some("ron" | "json")))
        .collect();
    files.sort();
    for path in files {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let scene = tumble_scene::load(&path.to_string_lossy(), &limits)
            .unwrap_or_else(|e| panic!("{name} does not load: {e}"));
        out.push((name, scene));
    }
    out
}

#[test]
fn every_scene_keeps_its_state_hash() {
    let scenes = scenes();
    // More than the built-ins: the scene files were found too.
    assert!(scenes.len() > tumble_scene::builtin::names().len() + 5);
    let got: Vec<(String, u64)> = scenes
        .iter()
        .map(|(name, scene)| (name.clone(), run_hash(scene)))
        .collect();
    let table: String = got
        .iter()
        .map(|(name, h)| format!("    ({name:?}, 0x{h:016x}),\n"))
        .collect();
    let wrong: Vec<String> = got
        .iter()
        .filter_map(|(name, h)| {
            let want = EXPECTED.iter().find(|(n, _)| n == name).map(|&(_, h)| h);
            (want != Some(*h)).then(|| format!("{name}: 0x{h:016x}, expected {want:x?}"))
        })
        .collect();
    let stale: Vec<&str> = EXPECTED
        .iter()
        .filter(|(n, _)| !got.iter().any(|(name, _)| name == n))
        .map(|&(n, _)| n)
        .collect();
    assert!(
        wrong.is_empty() && stale.is_empty(),
        "state hashes moved: {wrong:#?}\nlisted but not found: {stale:?}\nthe table now:\n{table}"
    );
}
