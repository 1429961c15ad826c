//! Extreme input the step must survive: no NaN, no explosion, no tunnelling where the
//! speculative margin promises none.

use tumble_physics::BodyId;
use tumble_physics::{BodyDef, BodyKind, Limits, SceneDef, ShapeDef, StepSettings, Vec2, World};
use tumble_tests::all_finite;

fn boxed(hx: f32, hy: f32) -> ShapeDef {
    ShapeDef::Box {
        half_extents: [hx, hy],
        radius: 0.0,
    }
}

fn ground(scene: &mut SceneDef, x: f32, y: f32, half_width: f32) {
    scene.push(
        BodyDef::new(boxed(half_width, 0.5))
            .kind(BodyKind::Static)
            .at(x, y - 0.5),
    );
}

fn run(scene: &SceneDef, steps: u32) -> World {
    let mut w = World::from_scene(scene, &Limits::default()).expect("valid scene");
    for _ in 0..steps {
        w.step(scene.dt, scene.substeps);
        assert!(
            all_finite(&w),
            "{}: non-finite state at step {}",
            scene.name,
            w.step_count()
        );
        assert_eq!(
            w.non_finite_bodies(),
            0,
            "{}: the NaN guard fired",
            scene.name
        );
    }
    w
}

#[test]
fn mass_ratio_one_to_a_million_stays_finite_and_bounded() {
    let mut scene = SceneDef::new("ratio");
    ground(&mut scene, 0.0, 0.0, 10.0);
    scene.push(BodyDef::new(boxed(0.5, 0.5)).at(0.0, 0.5).density(1.0));
    scene.push(BodyDef::new(boxed(0.5, 0.5)).at(0.0, 1.5).density(1.0e6));
    let w = run(&scene, 300);
    // The heavy box may crush into the light one (soft contacts at 1:1e6 are far beyond
    // what any iterative solver resolves), but nothing may fly off: both stay within a few
    // metres of where they started, and speeds stay below free fall from that height.
    for i in 1..3 {
        let b = w.body(BodyId::scene(i)).unwrap();
        assert!(b.position.length() < 5.0, "body {i} at {:?}", b.position);
        assert!(
            b.linear_velocity.length() < 10.0,
            "body {i} speed {:?}",
            b.linear_velocity
        );
    }
}

#[test]
fn tiny_and_huge_shapes_share_a_world() {
    let mut scene = SceneDef::new("scales");
    // A 2 km wide static slab, a 1 km boulder and 1 mm pebbles.
    ground(&mut scene, 0.0, 0.0, 1000.0);
    scene.push(BodyDef::new(ShapeDef::Circle { radius: 500.0 }).at(-700.0, 520.0));
    for i in 0..20 {
        scene.push(BodyDef::new(ShapeDef::Circle { radius: 0.001 }).at(i as f32 * 0.01, 0.01));
        scene.push(BodyDef::new(boxed(0.001, 0.001)).at(i as f32 * 0.01, 0.05));
    }
    let w = run(&scene, 300);
    // Everything rests on the slab (top at y = 0): nothing fell through it, within the
    // 5 mm slop of soft contacts under the boulder's weight.
    for i in 1..w.body_count() {
        let b = w.body(BodyId::scene(i)).unwrap();
        assert!(
            b.position.y > -0.005,
            "body {i} fell through: {:?}",
            b.position
        );
    }
}

#[test]
fn bodies_spawned_inside_each_other_separate_gently() {
    let mut scene = SceneDef::new("inside");
    ground(&mut scene, 0.0, 0.0, 10.0);
    // Five boxes at exactly the same place, and a circle inside them.
    for _ in 0..5 {
        scene.push(BodyDef::new(boxed(0.5, 0.5)).at(0.0, 0.5));
    }
    scene.push(BodyDef::new(ShapeDef::Circle { radius: 0.4 }).at(0.0, 0.5));
    let w = run(&scene, 600);
    // Push-out is capped at 3 m/s per contact (Box2D's contactSpeed); six bodies stacked
    // in one place can add a few of those up, never an explosion.
    for i in 1..w.body_count() {
        let b = w.body(BodyId::scene(i)).unwrap();
        assert!(
            b.position.length() < 15.0,
            "body {i} thrown to {:?}",
            b.position
        );
        assert!(
            b.linear_velocity.length() < 1.0,
            "body {i} still moving {:?}",
            b.linear_velocity
        );
    }
}

#[test]
fn a_stack_a_thousand_kilometres_out_stays_finite() {
    let mut scene = SceneDef::new("far");
    let (x, y) = (1.0e6, 1.0e6);
    ground(&mut scene, x, y, 10.0);
    for i in 0..5 {
        scene.push(BodyDef::new(boxed(0.5, 0.5)).at(x, y + 0.5 + i as f32));
    }
    let w = run(&scene, 300);
    // f32 resolves 1e6 m to 6 cm: the stack cannot be precise, but it must not fall through
    // or fly apart; each box stays within a few ulps (6.25 cm each) of its start.
    for i in 1..w.body_count() {
        let b = w.body(BodyId::scene(i)).unwrap();
        let start = Vec2::new(x, y + 0.5 + (i - 1) as f32);
        assert!(
            (b.position - start).length() < 0.5,
            "body {i} at {:?}",
            b.position
        );
    }
}

#[test]
fn ten_kilometres_a_second_into_a_thin_wall_does_not_tunnel() {
    let mut scene = SceneDef::new("bullet");
    scene.gravity = [0.0, 0.0];
    // A 2 cm thick wall at x = 20, and a 0.2 m ball fired at it at 1e4 m/s. The step caps
    // speed at 400 m/s (Box2D's maxLinearSpeed), 6.7 m per step: far more than the wall's
    // thickness, so only the speculative margin (swept boxes, closing speed) can stop it.
    scene.push(
        BodyDef::new(boxed(0.01, 5.0))
            .kind(BodyKind::Static)
            .at(20.0, 0.0),
    );
    scene.push(
        BodyDef::new(ShapeDef::Circle { radius: 0.1 })
            .at(0.0, 0.0)
            .velocity(1.0e4, 0.0),
    );
    let mut w = World::from_scene(&scene, &Limits::default()).unwrap();
    let max_speed = StepSettings::default().max_linear_speed;
    for _ in 0..120 {
        w.step(scene.dt, scene.substeps);
        let b = w.body(BodyId::scene(1)).unwrap();
        assert!(all_finite(&w));
        assert!(
            b.linear_velocity.length() <= max_speed * 1.0001,
            "speed {:?}",
            b.linear_velocity
        );
        assert!(b.position.x < 20.0, "tunnelled to {:?}", b.position);
    }
    assert!(w.speed_cap_count() > 0, "the speed cap never bit");
    // It reached the wall and stopped there (no restitution), not short of it.
    let x = w.body(BodyId::scene(1)).unwrap().position.x;
    assert!(x > 19.8, "stopped at {x}");
}
