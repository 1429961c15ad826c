//! Scene-level joint cases: the built-in jointed scenes do what their joints promise.

use tumble_physics::{BodyId, JointDef, World};
use tumble_tests::{all_finite, run, world};

/// The relative angle of a revolute joint's bodies (both started at angle 0).
fn relative_angle(w: &World, [a, b]: [BodyId; 2]) -> f32 {
    let d = w.body(b).unwrap().angle - w.body(a).unwrap().angle;
    (d + std::f32::consts::PI).rem_euclid(std::f32::consts::TAU) - std::f32::consts::PI
}

#[test]
fn the_ragdoll_falls_keeps_its_limits_and_comes_to_rest() {
    // Box2D's human dropped from 4 m: every hinge stays within its limits (a limit is soft
    // once passed, at the joint hertz: 0.05 rad allows its give under the impact) and the
    // bones end at rest on the ground.
    let scene = tumble_scene::builtin::build("ragdoll").expect("ragdoll");
    let mut w = world(&scene);
    let mut worst = 0.0f32;
    for _ in 0..scene.steps {
        w.step(scene.dt, scene.substeps);
        for joint in &scene.joints {
            let JointDef::Revolute {
                bodies,
                limit: Some([lower, upper]),
                ..
            } = joint
            else {
                continue;
            };
            let a = relative_angle(&w, *bodies);
            worst = worst.max(lower - a).max(a - upper);
        }
    }
    assert!(all_finite(&w));
    assert!(worst < 0.05, "a limit was passed by {worst} rad");
    for i in 1..w.body_count() {
        let b = w.body(BodyId::scene(i)).unwrap();
        assert!(
            b.position.y > -0.05 && b.position.y < 0.5,
            "bone {i} at {}",
            b.position
        );
        assert!(b.linear_velocity.length() < 0.05, "bone {i} still moves");
    }
}

#[test]
fn the_stretched_chain_pulls_itself_together_and_the_bridge_holds() {
    // 40 discs whose hinges start 1 m apart: after 10 s the chain hangs 1 m a link from
    // (0, 39.5), its last disc at y = 0 less the chain's own sag under its weight (solved
    // as one chain: measured 0.1 mm).
    let scene = tumble_scene::builtin::build("stretched_chain").expect("stretched_chain");
    let mut w = world(&scene);
    run(&mut w, &scene, 600);
    let last = w.body(BodyId::scene(40)).unwrap().position;
    assert!(
        last.x.abs() < 0.01 && last.y.abs() < 0.01,
        "last disc at {last}"
    );
    // Solver2D's bridge at the defaults: 160 planks spanning exactly their length sag only
    // by the joints' give: 2.8 m at 5 s in the report (Box2D 5.6 m); 4 m bounds it.
    let scene = tumble_scene::builtin::build("bridge").expect("bridge");
    let mut w = world(&scene);
    run(&mut w, &scene, 300);
    let sag = 20.0 - w.body(BodyId::scene(80)).unwrap().position.y;
    assert!(all_finite(&w));
    assert!((0.0..4.0).contains(&sag), "the bridge sags {sag} m");
}
