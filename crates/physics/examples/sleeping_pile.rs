//! A pile of boxes that settles and falls asleep: a resting island costs the step nothing
//! until something wakes it.
//!
//! `cargo run -p tumble-physics --example sleeping_pile`

use tumble_physics::{BodyDef, BodyKind, ShapeDef, StepSettings, World};

fn main() {
    let mut world = World::new(StepSettings::default());
    world
        .create_body(
            &BodyDef::new(ShapeDef::Box {
                half_extents: [10.0, 0.5],
                radius: 0.0,
            })
            .kind(BodyKind::Static)
            .at(0.0, -0.5),
        )
        .expect("ground");
    // A small pyramid of 15 boxes.
    let rows = 5;
    for row in 0..rows {
        for i in 0..rows - row {
            let x = (i as f32 - 0.5 * (rows - row - 1) as f32) * 1.05;
            world
                .create_body(
                    &BodyDef::new(ShapeDef::Box {
                        half_extents: [0.5, 0.5],
                        radius: 0.0,
                    })
                    .at(x, 0.5 + row as f32),
                )
                .expect("box");
        }
    }
    let mut asleep_at = None;
    for step in 1..=600 {
        world.step(1.0 / 60.0, 4);
        if asleep_at.is_none() && world.awake_body_count() == 0 {
            asleep_at = Some(step);
            println!("step {step}: every box is asleep");
        }
    }
    let step = asleep_at.expect("the pile never fell asleep");
    // Asleep, a step only counts itself: its profile says no body moved.
    world.step(1.0 / 60.0, 4);
    println!(
        "a step of the sleeping pile: {:.4} ms",
        world.profile().step_ms
    );
    assert_eq!(world.profile().moving, 0);
    // Every body must rest 0.5 s (Box2D's time to sleep), 30 steps, before the island sleeps.
    assert!(step >= 30, "asleep at step {step}");
}
