//! Asking the world a question: what does a ray from the left hit first, and what does it
//! pass through on the way?
//!
//! `cargo run -p tumble-physics --example ray_cast`

use tumble_physics::{BodyDef, BodyKind, QueryFilter, ShapeDef, StepSettings, Vec2, World};

fn main() {
    let mut world = World::new(StepSettings::default());
    // A row of posts at x = 2, 4, 6, 8, of growing height.
    for i in 1..=4 {
        let height = i as f32;
        world
            .create_body(
                &BodyDef::new(ShapeDef::Box {
                    half_extents: [0.25, 0.5 * height],
                    radius: 0.0,
                })
                .kind(BodyKind::Static)
                .at(2.0 * i as f32, 0.5 * height),
            )
            .expect("post");
    }
    let filter = QueryFilter::default();
    // A ray at 2.5 m from the left passes over the two short posts.
    let (origin, translation) = (Vec2::new(0.0, 2.5), Vec2::new(10.0, 0.0));
    let hit = world
        .cast_ray_closest(origin, translation, &filter)
        .expect("the ray hits a post");
    println!(
        "first hit: body {} at {} (normal {}, {:.0}% along the ray)",
        hit.shape.body.index,
        hit.point,
        hit.normal,
        100.0 * hit.fraction
    );
    // The third post's left face, x = 6 - 0.25.
    assert_eq!(hit.shape.body.index, 2);
    assert!((hit.point.x - 5.75).abs() < 1e-5);
    // Every post a lower ray crosses, nearest first.
    for hit in world.cast_ray_all(Vec2::new(0.0, 0.5), translation, &filter) {
        println!(
            "passes body {} at x = {:.2}",
            hit.shape.body.index, hit.point.x
        );
    }
    // What stands around a point (the shapes whose boxes overlap a 3 m square).
    let mut near = Vec::new();
    world.overlap_aabb(
        &tumble_physics::Aabb {
            min: Vec2::new(3.0, 0.0),
            max: Vec2::new(6.0, 3.0),
        },
        &filter,
        |shape| {
            near.push(shape.body.index);
            true
        },
    );
    println!("near (3..6, 0..3): bodies {near:?}");
    assert_eq!(near.len(), 2);
}
