//! Printing the events a game reacts to: contacts beginning and ending, hits fast enough to
//! make a sound, and a sensor that sees a ball pass through it.
//!
//! `cargo run -p tumble-physics --example hits`

use tumble_physics::{BodyDef, BodyKind, Event, PartDef, ShapeDef, StepSettings, World};

fn main() {
    let mut world = World::new(StepSettings {
        // Contacts that begin at 2 m/s or more are hits (a scene's `hit_speed`).
        hit_speed: 2.0,
        ..StepSettings::default()
    });
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
    // A sensor box 3 m up: it detects what passes and never pushes.
    world
        .create_body(
            &BodyDef::compound(vec![
                PartDef::new(ShapeDef::Box {
                    half_extents: [1.0, 0.25],
                    radius: 0.0,
                })
                .sensor(true),
            ])
            .kind(BodyKind::Static)
            .at(0.0, 3.0),
        )
        .expect("sensor");
    // Two balls: one falls through the sensor onto the ground, one drops gently beside it.
    world
        .create_body(
            &BodyDef::new(ShapeDef::Circle { radius: 0.25 })
                .at(0.0, 6.0)
                .restitution(0.5),
        )
        .expect("ball");
    world
        .create_body(&BodyDef::new(ShapeDef::Circle { radius: 0.25 }).at(4.0, 0.3))
        .expect("ball");
    let (mut hits, mut sensed) = (0, 0);
    for step in 1..=180 {
        world.step(1.0 / 60.0, 4);
        for event in world.events() {
            let Some([a, b]) = event.shapes() else {
                continue;
            };
            match event {
                Event::Hit {
                    approach_speed,
                    point,
                    ..
                } => {
                    hits += 1;
                    println!(
                        "step {step}: hit, body {} on body {} at {point} ({approach_speed:.1} m/s)",
                        b.body.index, a.body.index
                    );
                }
                Event::SensorBegin { .. } | Event::SensorEnd { .. } => {
                    sensed += 1;
                    println!("step {step}: {} (body {})", event.name(), b.body.index);
                }
                _ => println!(
                    "step {step}: {}, bodies {} and {}",
                    event.name(),
                    a.body.index,
                    b.body.index
                ),
            }
        }
    }
    // The falling ball hits the ground (and bounces; the gentle one never makes a hit) and
    // passes through the sensor once, in and out.
    assert!(hits >= 1, "no hit");
    assert_eq!(sensed, 2, "the sensor saw the ball enter and leave");
}
