//! Surface materials: a conveyor belt (tangent speed) carries crates at its speed and drops
//! them off its end; beside it a ball rolls onto a rubber mat (rolling resistance) and stops
//! where the energy balance says it should.
//!
//! `cargo run -p tumble-physics --example conveyor`

use tumble_physics::{BodyDef, BodyKind, PartDef, ShapeDef, StepSettings, World};

const DT: f32 = 1.0 / 60.0;

fn main() {
    let mut world = World::new(StepSettings::default());
    world
        .create_body(
            &BodyDef::new(ShapeDef::Box {
                half_extents: [40.0, 0.5],
                radius: 0.0,
            })
            .kind(BodyKind::Static)
            .at(0.0, -0.5),
        )
        .expect("ground");
    // The belt: 10 m long, its top 1 m up, moving right at 1.5 m/s.
    let belt_speed = 1.5;
    world
        .create_body(
            &BodyDef::compound(vec![
                PartDef::new(ShapeDef::Box {
                    half_extents: [5.0, 0.25],
                    radius: 0.0,
                })
                .tangent_speed(belt_speed),
            ])
            .kind(BodyKind::Static)
            .at(-10.0, 0.75),
        )
        .expect("belt");
    let crates: Vec<_> = (0..3)
        .map(|k| {
            world
                .create_body(
                    &BodyDef::new(ShapeDef::Box {
                        half_extents: [0.3, 0.3],
                        radius: 0.0,
                    })
                    .at(-14.0 + 2.0 * k as f32, 1.35),
                )
                .expect("crate")
        })
        .collect();

    // The mat: a rubber strip on the ground from x = 5 on, and a ball coming at 3 m/s.
    let resistance = 0.15;
    world
        .create_body(
            &BodyDef::compound(vec![
                PartDef::new(ShapeDef::Box {
                    half_extents: [10.0, 0.05],
                    radius: 0.0,
                })
                .rolling_resistance(resistance),
            ])
            .kind(BodyKind::Static)
            .at(15.0, 0.05),
        )
        .expect("mat");
    let radius = 0.4;
    let ball = world
        .create_body(
            &BodyDef::compound(vec![
                PartDef::new(ShapeDef::Circle { radius }).rolling_resistance(resistance),
            ])
            .at(5.0, 0.1 + radius)
            .velocity(3.0, 0.0)
            .spin(-3.0 / radius),
        )
        .expect("ball");
    let start = world.body(ball).expect("ball").position.x;

    // One second in, the crates ride at the belt's speed.
    for _ in 0..60 {
        world.step(DT, 4);
    }
    for &c in &crates {
        let v = world.body(c).expect("crate").linear_velocity;
        println!("crate on the belt: {:.3} m/s", v.x);
        assert!((v.x - belt_speed).abs() < 0.01 && v.y.abs() < 0.01);
    }
    // Ten seconds on, every crate has come off the belt's end (x = -5): past it and below
    // its top (they land on the ground or on one another).
    for _ in 0..600 {
        world.step(DT, 4);
    }
    for &c in &crates {
        let p = world.body(c).expect("crate").position;
        println!("crate off the end at x = {:.2}, y = {:.2}", p.x, p.y);
        assert!(p.x > -5.0 && p.y < 1.0, "{p}");
    }
    // The ball: rolling without slipping, a resistance torque c·r·N brakes the energy
    // ¾mv² of a rolling disc at c·g·m·v, so it stops after 3v²/(4·c·g) = 4.5 m (the mat's
    // and the ball's coefficient are alike; the lever is the ball's radius).
    let g = 10.0;
    let expected = 3.0 * 3.0f32.powi(2) / (4.0 * resistance * g);
    let ball_now = world.body(ball).expect("ball");
    let rolled = ball_now.position.x - start;
    println!("ball rolled {rolled:.3} m on the mat (energy balance: {expected:.3} m)");
    assert!(ball_now.linear_velocity.length() < 1e-3, "it stops");
    // 3%: the soft contact's give and the discrete steps (the library's own test holds 2%).
    assert!((rolled - expected).abs() < 0.03 * expected);
}
