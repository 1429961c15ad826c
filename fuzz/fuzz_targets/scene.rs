//! Fuzzes the scene loader: any bytes, read as RON or JSON (the first byte picks), must be
//! refused with an error or accepted; what is accepted must build a world and simulate
//! without a panic or a non-finite number (nor a body the NaN guard had to stop).
#![no_main]

use libfuzzer_sys::fuzz_target;
use tumble_physics::{Limits, World};
use tumble_scene::{Format, LoadLimits, parse};

fuzz_target!(|data: &[u8]| {
    let Some((&first, text)) = data.split_first() else {
        return;
    };
    let format = if first & 1 == 0 {
        Format::Ron
    } else {
        Format::Json
    };
    // Small limits keep each input fast; the limits themselves are tested elsewhere.
    let limits = LoadLimits {
        max_file_bytes: 1 << 20,
        scene: Limits {
            max_bodies: 64,
            max_substeps: 8,
        },
    };
    let Ok(scene) = parse(text, format, "fuzz", &limits) else {
        return;
    };
    let mut world = match World::from_scene(&scene, &limits.scene) {
        Ok(w) => w,
        Err(e) => panic!("the loader accepted a scene the world refuses: {e}"),
    };
    for _ in 0..30 {
        world.step(scene.dt, scene.substeps);
    }
    for (id, b) in world.bodies() {
        assert!(
            b.position.is_finite()
                && b.linear_velocity.is_finite()
                && b.angular_velocity.is_finite(),
            "{id} went non-finite: {b:?}"
        );
    }
    // The step's NaN guard stops a body that turns non-finite and leaves it finite, so the
    // check above cannot fail on its own: the guard's running count must be 0 too.
    assert_eq!(
        world.non_finite_bodies(),
        0,
        "the NaN guard stopped {} bodies",
        world.non_finite_bodies()
    );
});
