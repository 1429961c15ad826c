//! Issue 5's pass criteria, asserted on the error metrics of `tumble-bench report`
//! (docs/accuracy/REPORT.md has every case's definition, its sweep and the peers' figures).
//!
//! Each test runs tumble's DEFAULT settings where they pass. Where the defaults fail a
//! criterion, the test runs the cheapest setting the report found to pass it, and its comment
//! names that setting and the default's figure. Never a time: only the state.
//!
//! Covered elsewhere, not repeated here: the 15-box vertical stack (drift and height change
//! < 0.1 m over 10 s) and the 20-row pyramid (every box within 0.1 m after 10 s) are asserted
//! at the defaults by `tests/tests/stability.rs`; the projectile against the exact discrete
//! scheme by `tests/tests/closed_form.rs`.
//!
//! Penetration here is tumble's own: the deepest negative manifold separation after the last
//! step. The report measures every engine from poses instead (the geometric overlap at the end
//! of the step); for tumble the two agree to a millimetre on these cases.

use tumble_physics::BodyId;
use tumble_physics::{BodyKind, SceneDef, StepSettings, Vec2, World};
use tumble_scene::builtin;
use tumble_tests::{all_finite, world};

fn scene(name: &str) -> SceneDef {
    match builtin::build(name) {
        Some(s) => s,
        None => panic!("no built-in scene {name}"),
    }
}

/// The knobs the report sweeps; `DEFAULT` is tumble's (Box2D's) step.
#[derive(Clone, Copy, Debug)]
struct Knobs {
    substeps: u32,
    hertz: f32,
    relax: u32,
    push: f32,
}

const DEFAULT: Knobs = Knobs {
    substeps: 4,
    hertz: 30.0,
    relax: 1,
    push: 3.0,
};

/// 12 substeps with the contact hertz at its clamp (an eighth of the 720 Hz substep rate): the
/// cheapest setting of the report's sweep that passes the 100-row pyramid, the 200-row pyramid
/// and the 1:1000 column. The contacts' steady-state overlap under a load goes as 1/ω², so
/// 90 Hz presses boxes into each other 9 times less than 30 Hz; the clamp lets the contact be
/// that stiff only from 12 substeps up.
const STIFF: Knobs = Knobs {
    substeps: 12,
    hertz: 90.0,
    ..DEFAULT
};

fn build(scene: &SceneDef, k: Knobs) -> World {
    let defaults = tumble_physics::StepSettings::default();
    assert_eq!(
        (
            defaults.contact_hertz,
            defaults.relax_iterations,
            defaults.max_push_speed
        ),
        (DEFAULT.hertz, DEFAULT.relax, DEFAULT.push),
        "the engine's defaults moved: update DEFAULT here and rerun the report"
    );
    assert_eq!(scene.substeps, DEFAULT.substeps);
    let mut w = world(scene);
    let s = w.settings_mut();
    s.contact_hertz = k.hertz;
    s.relax_iterations = k.relax;
    s.max_push_speed = k.push;
    w
}

/// The deepest overlap in the last step's manifolds (m, >= 0).
fn deepest_overlap(w: &World) -> f32 {
    -w.contacts()
        .flat_map(|c| c.manifold.points().iter().map(|p| p.separation))
        .fold(0.0_f32, f32::min)
}

/// Shortest turn between two angles (rad).
fn turn(a: f32, b: f32) -> f32 {
    let d = (a - b).rem_euclid(std::f32::consts::TAU);
    d.min(std::f32::consts::TAU - d)
}

#[test]
fn pyramid_100_rows_top_sag_below_10_cm_and_overlap_below_2_cm() {
    // Setting: 12 substeps at 90 Hz (STIFF). At the defaults the report measures 0.74 m of top
    // sag and 1.8 cm of overlap (Box2D v3: 0.73 m, 2.1 cm; Rapier: about the same): a 100-row
    // pyramid's bottom contacts carry about 50 boxes each, and the soft contact's steady-state
    // overlap is load / (m ω²), summed over 100 rows. More substeps at 30 Hz do not help (16
    // substeps: 0.65 m); stiffer contacts do, as 1/ω²: 0.082 m at 90 Hz, 0.046 m at 120 Hz.
    let scene = scene("large_pyramid");
    let mut w = build(&scene, STIFF);
    let top = scene.bodies.len() - 1;
    let start = w.body(BodyId::scene(top)).unwrap().position;
    // The scene's 500 steps (Box2D's benchmark length); the sag has settled by step 400.
    for _ in 0..scene.steps {
        w.step(scene.dt, STIFF.substeps);
    }
    assert!(all_finite(&w), "large_pyramid: non-finite state");
    let sag = start.y - w.body(BodyId::scene(top)).unwrap().position.y;
    let overlap = deepest_overlap(&w);
    eprintln!("large_pyramid at 12 substeps, 90 Hz: top sag {sag} m, deepest overlap {overlap} m");
    // Bounds: the issue's. Measured: 0.082 m and 2.0 mm, so 18% margin on the sag (the
    // estimate 0.74 m × (30/90)² = 0.082 m is the same figure, so this is no accident of
    // timing), and 10x on the overlap.
    assert!(
        sag < 0.1,
        "100-row pyramid: top box sank {sag} m in {} steps; bound 0.1 m",
        scene.steps
    );
    assert!(
        overlap < 0.02,
        "100-row pyramid: deepest overlap {overlap} m; bound 0.02 m"
    );
}

#[test]
fn pyramid_200_rows_stands() {
    // Setting: the scene's own, from its `solver` block: 60 Hz contacts at 8 substeps (the
    // hertz is clamped to an eighth of the substep rate, so 60 Hz needs 8). At the defaults
    // (4 substeps, 30 Hz) the 200-row pyramid slumps: 0.56 m sideways after 300 steps (Box2D
    // 0.61 m); at its own setting the report measures 0.18 m (Box2D 0.19 m) and a 0.76 m sag.
    //
    // "Stands", as the report defines it: no box has moved sideways by more than 0.5 m (half a
    // box) and none has turned by more than 0.1 rad. A slumping pyramid spreads at the base and
    // its flanks slide out by far more than half a box; a tipping box turns. Uniform
    // compression (the sag) is not collapse.
    //
    // Length: 150 steps, not the report's 300: 20100 boxes at 8 substeps cost about 15 ms a
    // step even with the physics crate optimised, and 150 steps is enough to tell: a collapse
    // shows by step 100 (1 and 2 substeps: metres sideways), and a standing pyramid has
    // settled by step 150.
    let scene = scene("pyramid_200");
    let mut w = world(&scene);
    assert_eq!(
        (w.settings().contact_hertz, scene.substeps),
        (60.0, 8),
        "the scene's solver block is what the world runs"
    );
    let start: Vec<(Vec2, f32)> = (0..w.body_count())
        .map(|i| {
            (
                w.body(BodyId::scene(i)).unwrap().position,
                w.body(BodyId::scene(i)).unwrap().angle,
            )
        })
        .collect();
    for _ in 0..150 {
        w.step(scene.dt, scene.substeps);
    }
    assert!(all_finite(&w), "pyramid_200: non-finite state");
    let (mut sideways, mut tilt, mut worst) = (0.0_f32, 0.0_f32, 0);
    for (i, (p0, a0)) in start.iter().enumerate() {
        let b = w.body(BodyId::scene(i)).unwrap();
        if b.kind != BodyKind::Dynamic {
            continue;
        }
        let dx = (b.position.x - p0.x).abs();
        if dx > sideways {
            (sideways, worst) = (dx, i);
        }
        tilt = tilt.max(turn(b.angle, *a0));
    }
    let top = scene.bodies.len() - 1;
    let sag = start[top].0.y - w.body(BodyId::scene(top)).unwrap().position.y;
    eprintln!(
        "pyramid_200 at its own 8 substeps, 60 Hz, 150 steps: sideways {sideways} m (body {worst}), tilt {tilt} rad, top sag {sag} m"
    );
    assert!(
        sideways < 0.5,
        "200-row pyramid: body {worst} moved {sideways} m sideways; bound 0.5 m (half a box)"
    );
    assert!(
        tilt < 0.1,
        "200-row pyramid: a box turned by {tilt} rad; bound 0.1 rad"
    );
}

/// What the report measures on one mass-ratio column, over every step of a run.
struct Column {
    sideways: f32,
    tilt: f32,
    rise: f32,
    sag: f32,
    overlap: f32,
}

/// Runs `mass_ratio_columns` for its 600 steps at `k` and measures column `column` (0: 1:10,
/// 1: 1:100, 2: 1:1000). The columns stand 6 m apart and never touch.
fn mass_ratio_column(k: Knobs, column: usize) -> Column {
    let scene = scene("mass_ratio_columns");
    let per = builtin::MASS_RATIO_LIGHT_BOXES + 1;
    let ids: Vec<usize> = (0..per).map(|j| 1 + column * per + j).collect();
    let mut w = build(&scene, k);
    let start: Vec<(Vec2, f32)> = ids
        .iter()
        .map(|&i| {
            (
                w.body(BodyId::scene(i)).unwrap().position,
                w.body(BodyId::scene(i)).unwrap().angle,
            )
        })
        .collect();
    let mut c = Column {
        sideways: 0.0,
        tilt: 0.0,
        rise: 0.0,
        sag: 0.0,
        overlap: 0.0,
    };
    for _ in 0..scene.steps {
        w.step(scene.dt, k.substeps);
        for (&i, (p0, a0)) in ids.iter().zip(&start) {
            let b = w.body(BodyId::scene(i)).unwrap();
            c.sideways = c.sideways.max((b.position.x - p0.x).abs());
            c.tilt = c.tilt.max(turn(b.angle, *a0));
            c.rise = c.rise.max(b.position.y - p0.y);
        }
    }
    assert!(all_finite(&w), "mass_ratio_columns: non-finite state");
    let heavy = *ids.last().unwrap_or(&0);
    c.sag = start[per - 1].0.y - w.body(BodyId::scene(heavy)).unwrap().position.y;
    c.overlap = -w
        .contacts()
        .filter(|v| {
            [v.body_a, v.body_b]
                .iter()
                .any(|b| ids.contains(&(b.index as usize)))
        })
        .flat_map(|v| v.manifold.points().iter().map(|p| p.separation))
        .fold(0.0_f32, f32::min);
    c
}

/// "Stable", as the report defines it: over 10 s no box moved sideways, or rose, by more than
/// 0.1 m, none turned by more than 0.1 rad, and at the end no two boxes overlap by more than
/// 0.1 m (a tenth of a box, the bound of the pyramids): the column neither topples, nor is
/// thrown, nor lets the heavy box sink into the light one.
fn assert_stable(c: &Column, what: &str) {
    eprintln!(
        "{what}: sideways {} m, tilt {} rad, rise {} m, heavy sag {} m, overlap {} m",
        c.sideways, c.tilt, c.rise, c.sag, c.overlap
    );
    assert!(
        c.sideways < 0.1,
        "{what}: a box moved {} m sideways",
        c.sideways
    );
    assert!(c.tilt < 0.1, "{what}: a box turned by {} rad", c.tilt);
    assert!(c.rise < 0.1, "{what}: a box rose {} m", c.rise);
    assert!(
        c.overlap < 0.1,
        "{what}: two boxes overlap by {} m; bound 0.1 m",
        c.overlap
    );
}

#[test]
fn mass_ratio_columns_1_to_10_and_1_to_100_are_stable_at_the_defaults() {
    // Measured at the defaults: 1:10 overlaps by 8 mm, 1:100 by 7.2 cm (the soft contact's
    // overlap grows with the load, about 0.7 mm per light-box weight), neither moves sideways.
    assert_stable(&mass_ratio_column(DEFAULT, 0), "1:10 column, defaults");
    assert_stable(&mass_ratio_column(DEFAULT, 1), "1:100 column, defaults");
}

#[test]
fn mass_ratio_column_1_to_1000_is_stable() {
    // Setting: 12 substeps at 90 Hz (STIFF). At the defaults the heavy box sinks 0.7 m into
    // the light box under it and topples off the column (3 m away by the end); so does Box2D
    // v3. At 90 Hz the overlap is 7.9 cm, 9 times less, and nothing moves sideways (1.7 cm).
    // The 7.9 cm against the 0.1 m bound is the tightest margin in this file: it is the
    // soft-contact formula's figure (0.72 m × (30/90)²), not a fluctuation.
    assert_stable(
        &mass_ratio_column(STIFF, 2),
        "1:1000 column, 12 substeps at 90 Hz",
    );
}

#[test]
fn friction_ramp_slides_within_10_percent_of_closed_form() {
    // Defaults pass. Three unit boxes on 20-degree slopes, friction 0.30, 0.35 and 0.40 around
    // tan 20 deg = 0.364, released at rest; after 3 s the two that slide have gone
    // s = g (sin - mu cos) t^2 / 2 and the third has not moved.
    let scene = scene("friction_incline");
    let mut w = build(&scene, DEFAULT);
    let theta = builtin::INCLINE_DEGREES.to_radians();
    let downhill = Vec2::new(-theta.cos(), -theta.sin());
    let boxes: Vec<usize> = (0..scene.bodies.len())
        .filter(|&i| scene.bodies[i].kind == BodyKind::Dynamic)
        .collect();
    let start: Vec<Vec2> = boxes
        .iter()
        .map(|&i| w.body(BodyId::scene(i)).unwrap().position)
        .collect();
    let steps = 180;
    for _ in 0..steps {
        w.step(scene.dt, DEFAULT.substeps);
    }
    let t = steps as f32 * scene.dt;
    for (k, &i) in boxes.iter().enumerate() {
        let mu = scene.bodies[i].friction;
        let s = (w.body(BodyId::scene(i)).unwrap().position - start[k]).dot(downhill);
        let a = 10.0 * (theta.sin() - mu * theta.cos());
        if a > 0.0 {
            let expected = 0.5 * a * t * t;
            eprintln!("friction {mu}: slid {s} m, closed form {expected} m");
            // 10%: the bound. Measured: 4.6% short for mu = 0.35 (the worst), 1.5%
            // for 0.30. The error halves with each doubling of substeps (1 substep: 19%), so
            // it is the scheme's O(h), not noise; near tan theta the slide is a small
            // difference of two large forces, which magnifies it.
            assert!(
                (s - expected).abs() <= 0.1 * expected,
                "friction {mu}: slid {s} m in {t} s; closed form {expected} m, bound 10%"
            );
        } else {
            eprintln!("friction {mu}: moved {s} m (sticks)");
            // "Within 10% of 0" needs an absolute bound: one linear slop (5 mm), as the stick
            // test of closed_form.rs. Measured: 0.25 mm.
            assert!(
                s.abs() < 0.005,
                "friction {mu} >= tan theta: the box moved {s} m; bound 0.005 m"
            );
        }
    }
}

#[test]
fn restitution_apexes_within_10_percent_of_e_squared_h() {
    // Defaults pass. Balls of restitution 0.25, 0.5 and 0.75 dropped from 5 m: each must
    // bounce back to e^2 h. closed_form.rs tests e = 0.5 on its own scene; this is the report's.
    let scene = scene("restitution_drop");
    let mut w = build(&scene, DEFAULT);
    let h = builtin::DROP_HEIGHT;
    let n = scene.bodies.len();
    let (mut rising, mut done, mut apex) = (vec![false; n], vec![false; n], vec![0.0_f32; n]);
    for _ in 0..180 {
        w.step(scene.dt, DEFAULT.substeps);
        for i in 1..n {
            let b = w.body(BodyId::scene(i)).unwrap();
            if done[i] {
                continue;
            }
            rising[i] |= b.linear_velocity.y > 0.0;
            if rising[i] {
                // The ground's top is y = 0 and the balls' radius 0.5 m.
                apex[i] = apex[i].max(b.position.y - 0.5);
                done[i] = b.linear_velocity.y <= 0.0;
            }
        }
    }
    for i in 1..n {
        let e = scene.bodies[i].restitution;
        let expected = e * e * h;
        eprintln!("e = {e}: apex {} m, e^2 h = {expected} m", apex[i]);
        // 10%: closed_form.rs's bound. Measured: 5% short for every e: restitution restores
        // the approach speed measured before the impact step's gravity (g dt = 0.17 m/s of
        // 10 m/s, 3.3% of the apex) plus the integrator's lag on the way down and up.
        assert!(
            rising[i] && (apex[i] - expected).abs() <= 0.1 * expected,
            "e = {e}: apex {} m after the first bounce, expected {expected} m within 10%",
            apex[i]
        );
    }
}

#[test]
fn overlap_recovery_peak_speed_below_3_m_s() {
    // Setting: push-out capped at 1 m/s instead of the default 3 m/s. At the defaults the
    // report measures a peak of 3.48 m/s (Box2D v3: 3.42; Rapier 3.51): the cap bounds each
    // contact's push, and the pushes add up along the 4 rows. Capped at 1 m/s the peak is
    // 1.68 m/s; 2 relax passes (1.52 m/s) or 15 Hz contacts (1.66 m/s) pass as well, but cost
    // more or soften every contact; the cap changes only how fast overlap is pushed out.
    let scene = scene("overlap_recovery");
    let k = Knobs {
        push: 1.0,
        ..DEFAULT
    };
    let mut w = build(&scene, k);
    let (mut peak, mut when) = (0.0_f32, 0);
    // 300 steps, the report's: the fastest moment is within the first second in every run.
    for step in 0..300 {
        w.step(scene.dt, k.substeps);
        for i in 0..w.body_count() {
            let v = w.body(BodyId::scene(i)).unwrap().linear_velocity.length();
            if v > peak {
                (peak, when) = (v, step);
            }
        }
    }
    assert!(all_finite(&w), "overlap_recovery: non-finite state");
    let left = deepest_overlap(&w);
    eprintln!(
        "overlap_recovery, push-out 1 m/s: peak speed {peak} m/s at step {when}, overlap left {left} m"
    );
    // 3 m/s: the bound; measured 1.68.
    assert!(
        peak < 3.0,
        "overlap_recovery: peak speed {peak} m/s at step {when}; bound 3 m/s"
    );
    // And it did separate: 1 cm, the bound of stability.rs.
    assert!(left < 0.01, "overlap_recovery: {left} m of overlap left");
}

/// Largest |E - E0| / E0 of the kinetic energy over `steps` steps of `scene` (no gravity, so
/// kinetic energy is all the energy; the circles are frictionless and never spin), at
/// `threshold` and `passes` restitution passes: exactly those under Box2D's rule
/// (`impacts_bounce` off), else at most those or 16, within the bounce passes' budget.
fn energy_drift(
    scene: &SceneDef,
    threshold: f32,
    passes: u32,
    impacts_bounce: bool,
    steps: u32,
) -> f64 {
    let mut w = build(scene, DEFAULT);
    w.settings_mut().restitution_threshold = threshold;
    w.settings_mut().restitution_iterations = passes;
    w.settings_mut().impacts_bounce = impacts_bounce;
    let e0 = w.kinetic_energy();
    let mut worst = 0.0_f64;
    for _ in 0..steps {
        w.step(scene.dt, DEFAULT.substeps);
        worst = worst.max((w.kinetic_energy() / e0 - 1.0).abs());
    }
    worst
}

#[test]
fn elastic_bounces_keep_their_energy_for_60_s() {
    // At the defaults one frictionless circle of restitution 1 bouncing round the elastic box
    // for 60 s (about 60 wall bounces) keeps its kinetic energy to rounding (measured: 7e-7),
    // and two circles that also meet each other keep it too once the restitution threshold is
    // 0 (measured: 9e-7; at the default 1 m/s, a meeting slower than that is inelastic by
    // design: 5.0% lost over 60 s).
    let mut one = scene("elastic_box");
    one.bodies.truncate(5);
    let drift = energy_drift(&one, 1.0, 1, true, 3600);
    eprintln!("one circle, defaults: energy drift {drift}");
    // 1e-4: f32 rounding of velocities that are only ever reflected or exchanged, two orders
    // above what is measured.
    assert!(
        drift < 1e-4,
        "one circle lost {drift} of its energy in 60 s"
    );
    let mut two = scene("elastic_box");
    two.bodies.truncate(6);
    let drift = energy_drift(&two, 0.0, 1, true, 3600);
    eprintln!("two circles, threshold 0: energy drift {drift}");
    assert!(
        drift < 1e-4,
        "two circles lost {drift} of their energy in 60 s"
    );
}

#[test]
fn the_elastic_gas_keeps_its_energy_within_5_percent_for_60_s() {
    // Setting: Box2D's restitution rule (`impacts_bounce` off), restitution threshold 0 and
    // 16 restitution passes. The whole 40-circle box loses 91% of its energy under Box2D's
    // rule at the other defaults (Box2D 95%, Rapier 50%: REPORT.md) and 64% at threshold 0
    // with one pass: a ball that meets a wall and another ball in one step is bounced off
    // one and then sent back into it by the other. Repeated passes converge to bounces that
    // hold for every contact at once: 4 passes lose 10%, 16 passes about 1%.
    let gas = scene("elastic_box");
    let drift = energy_drift(&gas, 0.0, 16, false, 3600);
    eprintln!("40 circles, threshold 0, 16 restitution passes: energy drift {drift}");
    // The bound.
    assert!(drift < 0.05, "the gas lost {drift} of its energy in 60 s");
    // And the pass count is what does it: one pass at threshold 0 fails the bound.
    let one_pass = energy_drift(&gas, 0.0, 1, false, 3600);
    assert!(one_pass > 0.05, "one pass: drift {one_pass}");
}

#[test]
fn impacts_that_bounce_keep_the_elastic_gas_within_5_percent_for_60_s() {
    // The defaults: `impacts_bounce` (issue 36), at the default threshold (1 m/s) and pass
    // count. The threshold applies only to contacts that pushed in the step before, so every meeting
    // of two balls bounces however slow, and the restitution passes repeat until the bounces
    // hold. Measured: 1.8% lost over 60 s (Box2D's rule at the defaults: 91%), most steps
    // taking 2 passes and the worst 11 (2.2% and 15 when every pass solved every bouncing
    // constraint, before the passes after the first took only those a rebound had moved).
    assert!(StepSettings::default().impacts_bounce, "the default");
    let gas = scene("elastic_box");
    let mut w = build(&gas, DEFAULT);
    let e0 = w.kinetic_energy();
    let (mut drift, mut most, mut several) = (0.0_f64, 0, 0);
    for _ in 0..3600 {
        w.step(gas.dt, DEFAULT.substeps);
        drift = drift.max((w.kinetic_energy() / e0 - 1.0).abs());
        let passes = w.profile().restitution_passes;
        most = most.max(passes);
        several += u32::from(passes > 1);
    }
    eprintln!(
        "impacts bounce: energy drift {drift}, most passes {most}, steps with more than one {several}"
    );
    // The bound.
    assert!(drift < 0.05, "the gas lost {drift} of its energy in 60 s");
    // The passes stop once the bounces hold, before the cap (measured: 15 at most), and the
    // repeats are what does it: more than one pass in most steps.
    assert!(most < tumble_physics::RESTITUTION_PASSES, "{most} passes");
    assert!(several > 1800, "{several} steps took more than one pass");
}

#[test]
fn a_dense_pile_of_impacts_stops_its_bounce_passes_at_their_budget() {
    // `spinner` (6,076 bodies of restitution 0.1 stirred by a paddle) with `impacts_bounce`:
    // a third of its constraints bounce in a step, and their passes converge a few per cent
    // a pass, so every step would run all 16. The passes after the first take only the
    // lanes whose bodies a fast rebound just moved, and stop once they have visited twice
    // as many contacts as bounce (`BOUNCE_VISITS_PER_LISTED`). Measured over these 90 steps:
    // 7.0 passes a step, the most 16 (without the budget, all 16 in 191 of its first 200
    // steps); the bound is half the cap.
    let scene = scene("spinner");
    let mut w = build(&scene, DEFAULT);
    w.settings_mut().impacts_bounce = true;
    let (mut total, mut most) = (0, 0);
    let steps = 90;
    for _ in 0..steps {
        w.step(scene.dt, DEFAULT.substeps);
        let passes = w.profile().restitution_passes;
        total += passes;
        most = most.max(passes);
    }
    let mean = f64::from(total) / f64::from(steps);
    eprintln!("spinner, impacts bounce: {mean} passes a step, most {most}");
    assert!(most > 1, "the passes never repeated");
    assert!(mean < 8.0, "{mean} passes a step");
}

#[test]
fn a_bouncy_pyramid_falls_asleep_with_impacts_that_bounce() {
    // `impacts_bounce` lets a contact that begins bounce at any speed; one that pushed in the
    // step before is at rest and keeps the threshold, so a stack of bouncy boxes does not
    // jitter: the 20-row pyramid with every box of restitution 0.9 falls asleep, as it does
    // under Box2D's rule. Measured: asleep at step 54 either way; with every contact taken
    // for an impact, the solver's residue in the stack bounces back every step and it never
    // falls asleep (as with the threshold at 0 and one pass: the pyramid flies apart at
    // 10.7 m/s; 16 passes hold it, asleep at step 74).
    let mut pyramid = scene("pyramid");
    for b in &mut pyramid.bodies {
        b.restitution = 0.9;
    }
    pyramid.sleep = true;
    for impacts in [false, true] {
        let mut w = build(&pyramid, DEFAULT);
        w.settings_mut().impacts_bounce = impacts;
        let mut asleep_at = None;
        for step in 0..600 {
            w.step(pyramid.dt, DEFAULT.substeps);
            if w.awake_body_count() == 0 {
                asleep_at = Some(step);
                break;
            }
        }
        eprintln!("bouncy pyramid, impacts bounce {impacts}: asleep at step {asleep_at:?}");
        assert!(
            asleep_at.is_some(),
            "impacts bounce {impacts}: never fell asleep in 10 s"
        );
    }
}

#[test]
fn far_from_origin_stack_matches_the_same_stack_at_the_origin() {
    // Defaults pass. The built-in 10-box stack at (10 km, 10 km), where f32 positions are
    // 0.98 mm apart, against the same stack moved to the origin.
    let far = scene("far_from_origin");
    let mut near = far.clone();
    let (ox, oy) = (far.bodies[0].position[0], far.bodies[0].position[1] + 1.0);
    for b in &mut near.bodies {
        b.position = [b.position[0] - ox, b.position[1] - oy];
    }
    let measure = |scene: &SceneDef| {
        let mut w = build(scene, DEFAULT);
        let top = scene.bodies.len() - 1;
        let start = w.body(BodyId::scene(top)).unwrap().position;
        let mut drift = 0.0_f32;
        for _ in 0..600 {
            w.step(scene.dt, DEFAULT.substeps);
            drift = drift.max((w.body(BodyId::scene(top)).unwrap().position.x - start.x).abs());
        }
        assert!(all_finite(&w), "{}: non-finite state", scene.name);
        (
            drift,
            start.y - w.body(BodyId::scene(top)).unwrap().position.y,
        )
    };
    let (far_drift, far_sag) = measure(&far);
    let (near_drift, near_sag) = measure(&near);
    eprintln!(
        "far: drift {far_drift} m, sag {far_sag} m; origin: drift {near_drift} m, sag {near_sag} m"
    );
    // The far stack stands (0.1 m, the vertical stack's bound; measured 0), and its sag and
    // drift differ from the origin stack's by less than 1 cm, ten f32 spacings at 10 km
    // (measured: 5.2 mm of sag, 0 of drift; the sag of a stack is the sum of ten contacts'
    // overlaps, each known to half a spacing there).
    assert!(far_drift < 0.1, "far stack drifted {far_drift} m");
    assert!(
        (far_sag - near_sag).abs() < 0.01,
        "far stack sag {far_sag} m against {near_sag} m at the origin; bound 1 cm"
    );
    assert!(
        (far_drift - near_drift).abs() < 0.01,
        "far stack drift {far_drift} m against {near_drift} m at the origin; bound 1 cm"
    );
}
