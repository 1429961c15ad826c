//! Every built-in scene and every scene file in `assets/scenes/` ends its first 100 steps in
//! the state it reached before the redesign of issue 33 (one handle per object, the world's
//! stores): `World::state_hash` (the exact bits of every body's pose and velocities) after
//! each step, folded together, against the figure the code at 3349a60 gave. A change to the
//! world's layout or its public API must leave the physics bit for bit as it was; a change
//! that means to move the physics updates this table and says why in its commit.

use std::path::Path;

use tumble_physics::SceneDef;
use tumble_scene::LoadLimits;
use tumble_tests::{all_finite, world};

/// Steps per scene, as `scenes.rs` takes them (every scene's first impacts).
const STEPS: u32 = 100;

/// (scene, hash of the per-step hashes) at 3349a60; the scene files by their file name.
const EXPECTED: &[(&str, u64)] = &[
    ("falling_circles", 0x08b64b22a9fd2f3f),
    ("pyramid", 0x60e69229e6c0f004),
    ("vertical_stack", 0x378aefb2773209d1),
    ("card_house", 0x9b95f2ac0faf22eb),
    ("arch", 0x092af8922ee8dd5f),
    ("friction_ramp", 0x0a26de76a65070ae),
    ("mass_ratio", 0x70597ce2e7c691d1),
    ("overlap_recovery", 0x867682e539d44e79),
    ("confined", 0x82e6ce742de68b8b),
    ("far_from_origin", 0x641ca60d2b62d19b),
    ("mass_ratio_columns", 0x33744a65f7115ef6),
    ("friction_incline", 0x6b38ac02e6728116),
    ("restitution_drop", 0xf9a55c4f5cbe70e4),
    ("elastic_box", 0xd0501417a3235b9f),
    ("large_pyramid", 0x08ef8daa0c259921),
    ("pyramid_200", 0xabe70e9a0ffa9c49),
    ("many_pyramids", 0x3cf3412aa3e532d1),
    ("smash", 0x71dd62bd28585f16),
    ("tumbler", 0x367a234ea4a557b9),
    ("compounds", 0xabd1b10db6487dbf),
    ("junkyard", 0x557d74c5b1eef6c7),
    ("spinner", 0x5af16be4784545d3),
    ("joint_grid", 0xeb92b48818b920c6),
    ("ball_and_chain", 0x99464a376e78c0d7),
    ("bridge", 0x75580eea575b07e2),
    ("stretched_chain", 0x2a4f2846c61bbb2a),
    ("ragdoll", 0xd7f4c48b6afd0f3e),
    ("rain", 0x113a97d578931784),
    ("washer", 0x3f0d3b21a1620c17),
    // Added with the samples of issue 35, after the redesign: their own figures.
    ("platformer", 0x35275ced520670ac),
    // The feature samples (issue 35): their own figures.
    ("forces", 0x250840f7e525757c),
    ("materials", 0x44562269ee957d7a),
    ("conveyor_belts", 0xb98c619e8fc5e0ac),
    ("rolling_resistance", 0xab528edede71c1cf),
    ("one_way_platforms", 0x1e4d19b050fe7d23),
    ("explosions", 0x7ae4e1a9363baebb),
    ("breakable_joints", 0x469e7bea10649538),
    ("sensors", 0x3975bea4739c2bba),
    ("ray_casts", 0xe34c792deea31017),
    ("contact_events", 0xf3e98fe77d318071),
    ("sleep_and_wake", 0x84556d0ec3ea23b7),
    ("bullets", 0x14f41ac64de06719),
    ("joint_kinds", 0x22ded22b9bcdfa6a),
    ("bouncing_balls.json", 0xda16bb21533dbd40),
    ("capsule_stairs.ron", 0xc17a8132dc89062b),
    ("car.ron", 0xf3091bd9c1026f16),
    ("chain_slope.ron", 0x995db5a9d11daf69),
    ("compound_shapes.ron", 0x82ea01323d4d3a44),
    ("domino.ron", 0x155754ff3c84bfd2),
    ("drawbridge.ron", 0x04c8f7c3f0b51a70),
    ("newtons_cradle.ron", 0x3ab5ea2e38ed21ba),
    ("newtons_cradle_strung.ron", 0xb3810f246f46f05f),
    ("pinball.ron", 0xfbdfbb84e73220b6),
    ("polygons.ron", 0x0f97409a3e9c346d),
    ("ramp.ron", 0xf58ff4510d0b371a),
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
