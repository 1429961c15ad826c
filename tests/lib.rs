//! Helpers shared by the scene-level tests in `tests/tests/`.

use tumble_physics::{Limits, SceneDef, World};

/// Builds a world from a scene, panicking with the scene's error (tests only).
pub fn world(scene: &SceneDef) -> World {
    match World::from_scene(scene, &Limits::default()) {
        Ok(w) => w,
        Err(e) => panic!("scene {} refused: {e}", scene.name),
    }
}

/// Steps a world `n` times at the scene's settings.
pub fn run(world: &mut World, scene: &SceneDef, n: u32) {
    // A built-in's script (junkyard's pusher, rain's ragdolls) runs before each step, as in
    // the runner, `compare` and the viewer; only for the built-in itself, not a scene changed
    // from it.
    let script = tumble_scene::builtin::script_for(scene);
    for _ in 0..n {
        if let Some(script) = script {
            script(world.step_count(), world);
        }
        world.step(scene.dt, scene.substeps);
    }
}

/// Whether every body's state is finite and stayed so: the step's NaN guard stops a body
/// whose state turns non-finite and leaves it finite, so `is_finite` alone cannot fail; the
/// world's running count of the bodies the guard stopped must be 0 too.
pub fn all_finite(world: &World) -> bool {
    world.is_finite() && world.non_finite_bodies() == 0
}
