//! A one-way platform through the pre-solve hook: a box jumps up through a platform from
//! below and lands on top of it. The hook lets a contact push only while its normal, from
//! the platform towards the other shape, points up.
//!
//! `cargo run -p tumble-physics --example one_way_platform`

use tumble_physics::{BodyDef, BodyKind, ShapeDef, StepSettings, Vec2, World};

fn main() {
    let mut world = World::new(StepSettings::default());
    let ground = world
        .create_body(
            &BodyDef::new(ShapeDef::Box {
                half_extents: [10.0, 0.5],
                radius: 0.0,
            })
            .kind(BodyKind::Static)
            .at(0.0, -0.5),
        )
        .expect("ground");
    let platform = world
        .create_body(
            &BodyDef::new(ShapeDef::Box {
                half_extents: [3.0, 0.1],
                radius: 0.0,
            })
            .kind(BodyKind::Static)
            .at(0.0, 3.0),
        )
        .expect("platform");
    let deck = world
        .body_shapes(platform)
        .expect("platform")
        .next()
        .expect("a shape")
        .id;
    world.set_pre_solve(Some(Box::new(move |a, b, normal| {
        let up = if a == deck {
            normal
        } else if b == deck {
            -normal
        } else {
            return true;
        };
        up.y > 0.5
    })));
    let jumper = world
        .create_body(
            &BodyDef::new(ShapeDef::Box {
                half_extents: [0.25, 0.25],
                radius: 0.0,
            })
            .at(0.0, 0.25),
        )
        .expect("jumper");
    for _ in 0..30 {
        world.step(1.0 / 60.0, 4);
    }
    println!(
        "on the ground: y = {:.2}",
        world.body(jumper).expect("jumper").position.y
    );
    // A jump: up through the platform (its top at 3.1 m).
    world
        .apply_linear_impulse_to_center(
            jumper,
            Vec2::new(0.0, 9.0 * world.mass(jumper).expect("mass")),
            true,
        )
        .expect("jump");
    let mut top = 0.0f32;
    for _ in 0..120 {
        world.step(1.0 / 60.0, 4);
        top = top.max(world.body(jumper).expect("jumper").position.y);
    }
    let y = world.body(jumper).expect("jumper").position.y;
    println!("rose to {top:.2} m, rests at y = {y:.2} m");
    assert!(top > 3.5, "it should pass the platform");
    // On the platform: its top at 3.1 m, the box's half height 0.25 (1 cm: the solver's
    // linear slop).
    assert!((y - 3.35).abs() < 0.01, "{y}");
    let on = world.body_contacts(jumper).expect("contacts");
    assert!(on.len() == 1 && (on[0].body_a == platform || on[0].body_b == platform));
    assert!(on.iter().all(|c| c.body_a != ground && c.body_b != ground));
}
