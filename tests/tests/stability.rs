//! Stacking stability: columns and pyramids must stand still, overlap must be pushed apart
//! gently. Every assertion message carries the measured figure.

use tumble_physics::BodyId;
use tumble_physics::{BodyDef, BodyKind, SceneDef, ShapeDef, Vec2, World};
use tumble_tests::{all_finite, run, world};

fn builtin(name: &str) -> SceneDef {
    match tumble_scene::builtin::build(name) {
        Some(s) => s,
        None => panic!("no built-in scene {name}"),
    }
}

fn positions(world: &World) -> Vec<Vec2> {
    (0..world.body_count())
        .map(|i| world.body(BodyId::scene(i)).unwrap().position)
        .collect()
}

/// A column of `rows` unit boxes with friction `mu` on a static ground whose top is y = 0,
/// x alternating -0.01, +0.01 as in Box2D's Vertical Stack.
fn column(rows: usize, mu: f32) -> SceneDef {
    let mut scene = SceneDef::new("column");
    scene.push(
        BodyDef::new(ShapeDef::Box {
            half_extents: [20.0, 0.5],
            radius: 0.0,
        })
        .kind(BodyKind::Static)
        .at(0.0, -0.5)
        .friction(mu),
    );
    for i in 0..rows {
        let shift = if i % 2 == 0 { -0.01 } else { 0.01 };
        scene.push(
            BodyDef::new(ShapeDef::Box {
                half_extents: [0.5, 0.5],
                radius: 0.0,
            })
            .at(shift, 0.5 + i as f32)
            .friction(mu),
        );
    }
    scene
}

/// Runs a column scene for 10 s and checks the top box: horizontal drift < 0.1 m and height
/// within 0.1 m of its start.
fn check_column(scene: &SceneDef) {
    let mut w = world(scene);
    let top = scene.bodies.len() - 1;
    let start = w.body(BodyId::scene(top)).unwrap().position;
    // 10 s at the scene's 60 Hz.
    let steps = (10.0 / scene.dt).round() as u32;
    let mut worst_drift = 0.0_f32;
    let mut worst_dy = 0.0_f32;
    for _ in 0..steps {
        w.step(scene.dt, scene.substeps);
        let p = w.body(BodyId::scene(top)).unwrap().position;
        worst_drift = worst_drift.max((p.x - start.x).abs());
        worst_dy = worst_dy.max((p.y - start.y).abs());
    }
    assert!(all_finite(&w), "{}: non-finite state", scene.name);
    let p = w.body(BodyId::scene(top)).unwrap().position;
    let (drift, dy) = ((p.x - start.x).abs(), p.y - start.y);
    eprintln!(
        "{}: top box drift {drift} m (worst {worst_drift}), height change {dy} m (worst |dy| {worst_dy})",
        scene.name
    );
    // 0.1 m: a tenth of a box. A column that sways or leans to fall moves its top box by far
    // more than that within 10 s; one that stands drifts sideways by millimetres and sinks by
    // the soft contacts' steady-state overlap. Steady state: warm starting carries the load
    // lambda, velocities are zero, and the biased solve must add nothing, so
    // -m (massScale biasRate s) = impulseScale lambda, i.e. s = -iS lambda / (m mS biasRate).
    // Per corner point of a unit box pair, m = 1 / (1 + 1 + 6 (0.5^2) 2) = 0.2 kg and lambda =
    // k g h / 2 under k boxes; at 30 Hz (iS 0.0577, mS biasRate 8.545 /s) that is 0.70 mm per
    // box of load, summed over loads 1..14 gives 7.4 cm, plus 1.3 mm at the 60 Hz ground:
    // about 7.5 cm. Measured: 7.35 cm, drift 1 cm at worst; Box2D v3 HEAD (617d32ab), same
    // column, measured here: 7.346 cm and 1.02 cm. So the 0.1 m height bound has a 27% margin
    // at 30 Hz: softer contacts (or fewer substeps) will break it.
    assert!(
        worst_drift < 0.1,
        "{}: top box drifted {worst_drift} m sideways at worst (now {drift} m) in 10 s; bound 0.1 m",
        scene.name
    );
    assert!(
        worst_dy < 0.1,
        "{}: top box height changed by {worst_dy} m at worst (now {dy} m) in 10 s; bound 0.1 m",
        scene.name
    );
}

#[test]
fn fifteen_box_column_with_friction_0_6_stands_10_s() {
    check_column(&column(15, 0.6));
}

#[test]
fn builtin_vertical_stack_stands_10_s() {
    // The built-in differs from the column above: friction 0.3, a thin-box ground and a wall
    // 1.5 m to the right. Same bounds.
    check_column(&builtin("vertical_stack"));
}

/// The largest distance any body moved from `start`, and which body.
fn largest_displacement(world: &World, start: &[Vec2]) -> (f32, usize) {
    positions(world)
        .iter()
        .zip(start)
        .enumerate()
        .map(|(i, (p, s))| ((*p - *s).length(), i))
        .fold((0.0_f32, 0), |a, b| if b.0 > a.0 { b } else { a })
}

#[test]
fn pyramid_20_rows_holds_still_10_s() {
    let scene = builtin("pyramid");
    let mut w = world(&scene);
    let start = positions(&w);
    run(&mut w, &scene, 600);
    assert!(all_finite(&w), "pyramid: non-finite state");
    let (worst, body) = largest_displacement(&w, &start);
    eprintln!("pyramid: largest displacement {worst} m (body {body})");
    // 0.1 m: a tenth of a box. A pyramid that creeps or slumps moves its outer boxes by much
    // more in 10 s; a standing one settles by the soft contacts' steady-state overlap (see
    // the column test), less per row than a column as each box rests on two. Measured: the
    // top box sinks 3.1 cm; Box2D v3 HEAD, same pyramid, measured here: 2.98 cm.
    assert!(
        worst < 0.1,
        "pyramid: body {body} moved {worst} m from its start in 10 s; bound 0.1 m"
    );
}

#[test]
fn large_pyramid_does_not_lean() {
    // A pyramid is symmetric, so its top box moving sideways is a bias of the solve, not the
    // softness of the contacts (whose sag is vertical). Box2D v3.2 (boxdd 0.6), same scene and
    // settings, stepped beside tumble in one process: the top box's largest |x - x0| over
    // Box2D's 500 steps is 0.0707 m, at step 100. tumble, when it coloured the constraint
    // graph in contact order: 0.77 m (each box's lower-right support solved before its
    // lower-left one, see `solver::coloring_order`); colouring in a hashed order: 0.0065 m.
    // The bound is the target, 1.2 times Box2D's figure.
    let scene = builtin("large_pyramid");
    let mut w = world(&scene);
    let top = scene.bodies.len() - 1;
    let x0 = w.body(BodyId::scene(top)).unwrap().position.x;
    let mut drift = 0.0_f32;
    for _ in 0..scene.steps {
        w.step(scene.dt, scene.substeps);
        drift = drift.max((w.body(BodyId::scene(top)).unwrap().position.x - x0).abs());
    }
    assert!(all_finite(&w), "large_pyramid: non-finite state");
    eprintln!("large_pyramid: top box drift {drift} m");
    assert!(
        drift < 1.2 * 0.0707,
        "large_pyramid: the top box moved {drift} m sideways; bound 0.085 m (1.2 x Box2D's)"
    );
}

#[test]
fn card_house_stands_10_s() {
    let scene = builtin("card_house");
    let mut w = world(&scene);
    let start = positions(&w);
    run(&mut w, &scene, 600);
    assert!(all_finite(&w), "card_house: non-finite state");
    let (worst, body) = largest_displacement(&w, &start);
    eprintln!("card_house: largest displacement {worst} m (body {body})");
    // 0.1 m: a quarter of a card's 0.4 m height; a card that slips falls by a card height or
    // more. Measured: 3.6 cm (the top tent settling); Box2D v3.2 on the same scene, measured
    // here through boxdd: 3.3 cm. (Before the polygon collider followed Box2D's separated-case
    // rule, a vertex-vertex point was chosen for cards touching at their thin ends, and the
    // top tent slid apart within 2 s.)
    assert!(
        worst < 0.1,
        "card_house: body {body} moved {worst} m from its start in 10 s; bound 0.1 m"
    );
}

/// What one overlap_recovery run measured.
struct Recovery {
    /// Fastest any body left a step, and when and which.
    peak: f32,
    peak_step: usize,
    peak_body: usize,
    /// The top box: start, highest and final height.
    top_start: f32,
    top_max: f32,
    top_final: f32,
    /// Deepest overlap in the last step's manifolds (<= 0).
    deepest: f32,
}

/// Runs the built-in `overlap_recovery` for 10 s with the contact spring at `hertz` (ratio
/// and push-out speed at their defaults, Box2D's 10 and 3 m/s).
fn overlap_recovery(hertz: f32) -> Recovery {
    let scene = builtin("overlap_recovery");
    let mut w = world(&scene);
    w.settings_mut().contact_hertz = hertz;
    let top = scene.bodies.len() - 1;
    let mut r = Recovery {
        peak: 0.0,
        peak_step: 0,
        peak_body: 0,
        top_start: scene.bodies[top].position[1],
        top_max: f32::NEG_INFINITY,
        top_final: 0.0,
        deepest: 0.0,
    };
    for step in 0..600 {
        w.step(scene.dt, scene.substeps);
        for i in 0..w.body_count() {
            let v = w.body(BodyId::scene(i)).unwrap().linear_velocity.length();
            if v > r.peak {
                (r.peak, r.peak_step, r.peak_body) = (v, step, i);
            }
        }
        r.top_max = r
            .top_max
            .max(w.body(BodyId::scene(top)).unwrap().position.y);
    }
    assert!(
        all_finite(&w),
        "overlap_recovery at {hertz} Hz: non-finite state"
    );
    r.top_final = w.body(BodyId::scene(top)).unwrap().position.y;
    r.deepest = w
        .contacts()
        .flat_map(|c| c.manifold.points().iter().map(|p| p.separation))
        .fold(0.0_f32, f32::min);
    eprintln!(
        "overlap_recovery at {hertz} Hz: peak speed {} m/s (step {}, body {}); top box start {}, max {}, final {}; deepest overlap {} m",
        r.peak, r.peak_step, r.peak_body, r.top_start, r.top_max, r.top_final, -r.deepest
    );
    r
}

/// The checks shared by both tunings.
fn check_recovery(r: &Recovery, label: &str) {
    // Reference: Box2D v3 HEAD (617d32ab), its OverlapRecovery sample's tuning (30 Hz, damping
    // ratio 10, push-out 3 m/s, 4 substeps at 60 Hz), measured for this report: peak body speed
    // 3.417 m/s (step 0), top box rising monotonically to 3.497 m and staying there. The 3 m/s
    // push-out cap bounds each contact's push, not a body's speed: pushes add up along the
    // 4-row chain, so even Box2D exceeds 3 m/s. Bound: Box2D's peak + 10%.
    let peak_bound = 3.417 * 1.1;
    assert!(
        r.peak < peak_bound,
        "{label}: peak speed {} m/s at step {} (body {}); bound {peak_bound} m/s (Box2D's 3.417 + 10%)",
        r.peak,
        r.peak_step,
        r.peak_body
    );
    // Not thrown: the top box rises as the rows part (2.75 m to its resting 3.5 m) and should
    // not overshoot its final height by more than 5 cm (Box2D: no overshoot at all).
    assert!(
        r.top_max - r.top_final < 0.05,
        "{label}: top box thrown to y = {} m, {} m above where it came to rest ({} m); bound 0.05 m",
        r.top_max,
        r.top_max - r.top_final,
        r.top_final
    );
    // Separated: the top box has not sunk; it is above its start height less the 0.25 m the
    // scene overlaps each row by.
    let overlap = 0.25;
    assert!(
        r.top_final > r.top_start - overlap,
        "{label}: top box at y = {}, start {}; expected above {}",
        r.top_final,
        r.top_start,
        r.top_start - overlap
    );
    // Overlap resolved: 1 cm (two linear slops) is far below the 0.25 m spawned with and above
    // what the soft contacts keep under a 4-row pyramid (measured 0.2 mm at 60 Hz, 2.4 mm at
    // 30 Hz).
    assert!(
        r.deepest > -0.01,
        "{label}: a contact still overlaps by {} m after 10 s; bound 0.01 m",
        -r.deepest
    );
}

#[test]
fn overlap_recovery_separates_without_exploding() {
    // The engine's defaults, as the app runs the scene. They are Box2D's 30 Hz today (the
    // other test pins that); this one guards whatever the defaults become.
    let hertz = tumble_physics::StepSettings::default().contact_hertz;
    check_recovery(&overlap_recovery(hertz), "engine defaults");
}

#[test]
fn overlap_recovery_at_box2d_tuning_matches_box2d() {
    // Box2D's sample sets the contact tuning to 30 Hz; the engine then runs Box2D's numbers.
    check_recovery(&overlap_recovery(30.0), "Box2D tuning (30 Hz)");
}
