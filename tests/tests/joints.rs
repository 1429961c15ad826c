//! Scene-level joint cases: the built-in jointed scenes do what their joints promise.

use tumble_physics::{BodyId, JointDef, World};
use tumble_tests::{all_finite, run, world};

/// The relative angle of a revolute joint's bodies (both started at angle 0).
fn relative_angle(w: &World, [a, b]: [BodyId; 2]) -> f32 {
    let d = w.body(b).unwrap().angle - w.body(a).unwrap().angle;
    (d + std::f32::consts::PI).rem_euclid(std::f32::consts::TAU) - std::f32::consts::PI
}

/// Box2D's human dropped from 4 m at `substeps` and `joint_hertz` (the scene's where `None`):
/// the world after its steps and the furthest any hinge passed its limits (rad).
fn ragdoll_fall(substeps: Option<u32>, joint_hertz: Option<f32>) -> (World, f32) {
    let mut scene = tumble_scene::builtin::build("ragdoll").expect("ragdoll");
    scene.substeps = substeps.unwrap_or(scene.substeps);
    scene.solver.joint_hertz = joint_hertz.or(scene.solver.joint_hertz);
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
    (w, worst)
}

#[test]
fn the_ragdoll_falls_keeps_its_limits_and_comes_to_rest() {
    // Box2D's human dropped from 4 m: every hinge stays near its limits and the bones end at
    // rest on the ground. A limit is a soft spring once passed (the joint hertz: 60 Hz at 4
    // substeps, damping ratio 2), so the landing pushes a hinge past it by the spring's give,
    // which shrinks as the spring stiffens. Measured with the defaults (a manifold's points
    // solved together: a bone landing flat stops flat and its neighbours take the stop):
    // 0.094 rad at 60 Hz, 0.060 at 120 Hz on 8 substeps, 0.020 at 240 Hz on 16, 0.166 at
    // 30 Hz (solved in turn, Box2D's rule: 0.049 at 60 Hz). Bounds: the defaults' give and a
    // quarter, and a give that falls with the hertz as a spring's does (to at most 0.75 of it
    // at twice the hertz, 0.4 at four times), which a pass from anything but the limit's
    // softness would not.
    let (w, worst) = ragdoll_fall(None, None);
    let (_, stiffer) = ragdoll_fall(Some(8), Some(120.0));
    let (_, stiffest) = ragdoll_fall(Some(16), Some(240.0));
    assert!(
        stiffer < 0.75 * worst && stiffest < 0.4 * worst,
        "the give does not follow the limit's hertz: {worst} rad at 60 Hz, {stiffer} at 120, \
         {stiffest} at 240"
    );
    assert!(all_finite(&w));
    assert!(worst < 0.12, "a limit was passed by {worst} rad");
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
