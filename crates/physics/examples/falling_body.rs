//! A box dropped onto the ground: the smallest tumble program.
//!
//! `cargo run -p tumble-physics --example falling_body`

use tumble_physics::{BodyDef, BodyKind, ShapeDef, StepSettings, World};

fn main() {
    // A world with Box2D's defaults: gravity (0, -10), 4 substeps a step is usual.
    let mut world = World::new(StepSettings::default());
    // Static ground, 20 m wide, its top at y = 0.
    world
        .create_body(
            &BodyDef::new(ShapeDef::Box {
                half_extents: [10.0, 0.5],
                radius: 0.0,
            })
            .kind(BodyKind::Static)
            .at(0.0, -0.5),
        )
        .expect("a valid body");
    // A 1 m box, its bottom 4 m up.
    let b = world
        .create_body(
            &BodyDef::new(ShapeDef::Box {
                half_extents: [0.5, 0.5],
                radius: 0.0,
            })
            .at(0.0, 4.5),
        )
        .expect("a valid body");
    for step in 1..=90 {
        world.step(1.0 / 60.0, 4);
        if step % 15 == 0 {
            let body = world.body(b).expect("the body");
            println!(
                "t = {:.2} s: y = {:.3} m, vy = {:.2} m/s",
                step as f32 / 60.0,
                body.position.y,
                body.linear_velocity.y
            );
        }
    }
    // It fell √(2 · 4 / 10) ≈ 0.9 s and rests on the ground, its centre 0.5 m up.
    let y = world.body(b).expect("the body").position.y;
    assert!((y - 0.5).abs() < 0.02, "the box rests at y = {y}");
}
