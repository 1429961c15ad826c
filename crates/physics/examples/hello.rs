//! The program of the README: a ball dropped on the ground, its landing as an event, and a
//! ray cast down at it. `tests/tests/readme.rs` keeps the README's copy equal to this file.
//!
//! `cargo run -p tumble-physics --example hello`

use tumble_physics::{BodyDef, BodyKind, Event, QueryFilter, ShapeDef, StepSettings, Vec2, World};

fn main() {
    let mut world = World::new(StepSettings::default()); // gravity (0, -10) m/s²
    let ground = ShapeDef::Box {
        half_extents: [10.0, 0.5],
        radius: 0.0,
    };
    let ground = world.create_body(&BodyDef::new(ground).kind(BodyKind::Static).at(0.0, -0.5));
    let ball = world.create_body(&BodyDef::new(ShapeDef::Circle { radius: 0.5 }).at(0.0, 4.0));
    let (ground, ball) = (ground.unwrap(), ball.unwrap());
    let mut hits = 0;
    for _ in 0..120 {
        world.step(1.0 / 60.0, 4); // dt, substeps
        for event in world.events() {
            if let Event::Hit { shapes, .. } = event {
                assert_eq!([shapes[0].body, shapes[1].body], [ground, ball]);
                hits += 1;
            }
        }
    }
    // Two seconds on, the ball rests on the ground: a ray cast down meets its top at y = 1 m.
    let down = Vec2::new(0.0, -10.0);
    let hit = world.cast_ray_closest(Vec2::new(0.0, 5.0), down, &QueryFilter::default());
    let hit = hit.expect("the ray meets the ball");
    assert!(hits == 1 && hit.shape.body == ball && (hit.point.y - 1.0).abs() < 0.01);
    let top = hit.point.y;
    println!("the ball landed once; its top rests at y = {top:.3} m");
}
