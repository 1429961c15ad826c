//! A chain of ten links hung from a fixed point by revolute joints, swinging down from the
//! horizontal; tumble solves a chain of hinges as one system, so it does not stretch.
//!
//! `cargo run -p tumble-physics --example joint_chain`

use tumble_physics::{BodyDef, BodyKind, JointDef, ShapeDef, StepSettings, World};

fn main() {
    let mut world = World::new(StepSettings::default());
    let anchor = world
        .create_body(
            &BodyDef::new(ShapeDef::Circle { radius: 0.1 })
                .kind(BodyKind::Static)
                .at(0.0, 10.0),
        )
        .expect("anchor");
    // Ten capsule links 1 m long, laid out to the right of the anchor.
    let mut previous = anchor;
    for i in 0..10 {
        let link = world
            .create_body(
                &BodyDef::new(ShapeDef::Capsule {
                    center1: [-0.5, 0.0],
                    center2: [0.5, 0.0],
                    radius: 0.1,
                })
                .at(0.5 + i as f32, 10.0),
            )
            .expect("link");
        // Hinged at the point the two share, in world coordinates.
        world
            .create_joint(&JointDef::Revolute {
                force_threshold: f32::INFINITY,
                torque_threshold: f32::INFINITY,
                bodies: [previous, link],
                anchor: [i as f32, 10.0],
                limit: None,
                motor: None,
                spring: None,
                collide_connected: false,
                anchor_b: None,
            })
            .expect("joint");
        previous = link;
    }
    for step in 1..=240 {
        world.step(1.0 / 60.0, 4);
        if step % 60 == 0 {
            let end = world.body(previous).expect("the last link").position;
            println!("t = {} s: the last link's centre is at {end}", step / 60);
        }
    }
    // However it swings, each hinge holds: the last link's centre stays within 9.5 m of the
    // anchor (with a 1 cm allowance for the soft joints).
    let end = world.body(previous).expect("the last link").position;
    let reach = (end - tumble_physics::Vec2::new(0.0, 10.0)).length();
    assert!(reach <= 9.51, "the chain stretched to {reach} m");
    assert_eq!(world.joint_count(), 10);
}
