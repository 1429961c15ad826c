//! An explosion beside a stack of crates (`World::explode`, Box2D v3.1's `b2World_Explode`):
//! the crates near the blast fly off, those beyond its reach stay put, and the sleeping
//! ones it reaches wake up.
//!
//! `cargo run -p tumble-physics --example explosion`

use tumble_physics::{BodyDef, BodyKind, ExplosionDef, ShapeDef, StepSettings, Vec2, World};

fn main() {
    let mut world = World::new(StepSettings::default());
    world
        .create_body(
            &BodyDef::new(ShapeDef::Box {
                half_extents: [30.0, 0.5],
                radius: 0.0,
            })
            .kind(BodyKind::Static)
            .at(0.0, -0.5),
        )
        .expect("ground");
    // Two stacks of five crates: at x = 2 (near the blast) and at x = 25 (beyond it, and
    // beyond where the near crates land).
    let mut near = Vec::new();
    let mut far = Vec::new();
    for (x, list) in [(2.0, &mut near), (25.0, &mut far)] {
        for k in 0..5 {
            list.push(
                world
                    .create_body(
                        &BodyDef::new(ShapeDef::Box {
                            half_extents: [0.5, 0.5],
                            radius: 0.0,
                        })
                        .at(x, 0.5 + k as f32),
                    )
                    .expect("crate"),
            );
        }
    }
    // Let them settle and sleep.
    for _ in 0..120 {
        world.step(1.0 / 60.0, 4);
    }
    assert!(
        near.iter()
            .chain(&far)
            .all(|&b| world.is_awake(b) == Ok(false))
    );
    let before: Vec<Vec2> = far
        .iter()
        .map(|&b| world.body(b).expect("crate").position)
        .collect();
    world
        .explode(&ExplosionDef {
            position: Vec2::new(0.0, 1.0),
            radius: 3.0,
            falloff: 3.0,
            impulse_per_length: 10.0,
            ..ExplosionDef::default()
        })
        .expect("a valid blast");
    for _ in 0..60 {
        world.step(1.0 / 60.0, 4);
    }
    let moved: Vec<f32> = near
        .iter()
        .map(|&b| world.body(b).expect("crate").position.x - 2.0)
        .collect();
    println!("the near stack, pushed (m): {moved:.2?}");
    assert!(moved.iter().all(|&dx| dx > 1.0), "the near crates fly off");
    for (&b, p) in far.iter().zip(before) {
        assert_eq!(
            world.body(b).expect("crate").position,
            p,
            "beyond the blast nothing moves"
        );
    }
    println!("the far stack did not move");
}
