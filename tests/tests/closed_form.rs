//! Closed-form mechanics: the engine against formulas derived by hand.
//!
//! Each tolerance says where it comes from: either the exact discrete scheme (then the bound
//! is f32 round-off, counted from the number of operations) or a known, measured property of
//! the Soft Step solver.

use tumble_physics::BodyId;
use tumble_physics::{BodyDef, BodyKind, ShapeDef, StepSettings, Vec2, World};

const DT: f32 = 1.0 / 60.0;
const SUBSTEPS: u32 = 4;
const G: f64 = 10.0;

fn settings(gravity: [f32; 2]) -> StepSettings {
    StepSettings {
        gravity: Vec2::from(gravity),
        ..StepSettings::default()
    }
}

fn add(world: &mut World, def: BodyDef) -> BodyId {
    match world.create_body(&def) {
        Ok(i) => i,
        Err(e) => panic!("body refused: {e}"),
    }
}

fn circle(radius: f32) -> ShapeDef {
    ShapeDef::Circle { radius }
}

fn rect(hx: f32, hy: f32) -> ShapeDef {
    ShapeDef::Box {
        half_extents: [hx, hy],
        radius: 0.0,
    }
}

/// f32 unit round-off (half an ulp of 1).
const U: f64 = f32::EPSILON as f64 / 2.0;

#[test]
fn projectile_matches_symplectic_euler() {
    // Semi-implicit Euler, per substep h: v_{k+1} = v_k - g h, y_{k+1} = y_k + h v_{k+1}.
    // Summing, y_n = y0 + h * sum_{k=1..n} (v0 - g h k) = y0 + v0 n h - g h^2 n (n + 1) / 2,
    // and with t = n h: y_n = y0 + v0 t - g t^2 / 2 - g h t / 2. So the scheme lags the
    // continuous parabola by exactly g h t / 2, and x_n = x0 + vx t.
    let (x0, y0) = (1.0_f64, 2.0_f64);
    let (vx, vy) = (3.0_f64, 8.0_f64);
    let steps = 60_u32; // t = 1 s: up to the apex (t = 0.8 s) and a little back down.
    let mut world = World::new(settings([0.0, -10.0]));
    let id = add(
        &mut world,
        BodyDef::new(circle(0.25))
            .at(x0 as f32, y0 as f32)
            .velocity(vx as f32, vy as f32),
    );
    for _ in 0..steps {
        world.step(DT, SUBSTEPS);
    }
    assert_eq!(
        world.contact_count(),
        0,
        "the projectile must touch nothing"
    );
    let b = world.body(id).unwrap();
    // h as the engine computes it (dt / substeps in f32), carried exactly into f64.
    let h = f64::from(DT / SUBSTEPS as f32);
    let n = f64::from(steps * SUBSTEPS);
    let t = n * h;
    let y_discrete = y0 + vy * n * h - G * h * h * n * (n + 1.0) / 2.0;
    let x_discrete = x0 + vx * n * h;
    let y_continuous = y0 + vy * t - G * t * t / 2.0;
    let vy_discrete = vy - G * n * h;

    // Round-off bound: every substep does about 4 f32 roundings that touch the position path
    // (v += g h; dp += v h, two roundings; and each step p += dp), each at most U times the
    // largest magnitude involved (|p| <= 6 m, |v h| and |dp| smaller). With n = 240 substeps:
    // 4 * 240 * U * 6 m ~ 3.4e-4 m. The velocity path has one rounding per substep at |v| <= 8.
    let max_mag = 6.0;
    let pos_tol = 4.0 * n * U * max_mag;
    let vel_tol = 2.0 * n * U * 8.0;
    let (ex, ey) = (
        (f64::from(b.position.x) - x_discrete).abs(),
        (f64::from(b.position.y) - y_discrete).abs(),
    );
    let evy = (f64::from(b.linear_velocity.y) - vy_discrete).abs();
    eprintln!("projectile: |dx| {ex:e}, |dy| {ey:e}, |dvy| {evy:e} m vs bound {pos_tol:e}");
    assert!(
        ex <= pos_tol && ey <= pos_tol,
        "engine ({}, {}) vs discrete formula ({x_discrete}, {y_discrete}): errors {ex:e}, {ey:e} > round-off bound {pos_tol:e}",
        b.position.x,
        b.position.y
    );
    assert!(
        evy <= vel_tol,
        "vy {} vs {vy_discrete}: error {evy:e} > {vel_tol:e}",
        b.linear_velocity.y
    );

    // Deviation from the continuous closed form: g h t / 2 = 10 * (1/240) * 1 / 2 = 0.0208 m,
    // the same round-off bound around it (1.6% of the lag).
    let lag = y_continuous - f64::from(b.position.y);
    let expected_lag = G * h * t / 2.0;
    eprintln!("projectile: lag {lag} m vs g h t / 2 = {expected_lag} m");
    assert!(
        (lag - expected_lag).abs() <= pos_tol,
        "lag behind the parabola {lag} m, expected g h t / 2 = {expected_lag} m (tolerance {pos_tol:e})"
    );
}

#[test]
fn elastic_head_on_collision_swaps_velocities() {
    // Equal discs, restitution 1, no friction, no gravity, approaching at 2 m/s each: the
    // closing speed 4 m/s is above the 1 m/s restitution threshold, so the restitution pass
    // applies e = 1 and the discs must swap velocities. They meet at t = 0.75 s; 2 s is plenty.
    let mut world = World::new(settings([0.0, 0.0]));
    let disc = |x: f32, vx: f32| {
        BodyDef::new(circle(0.5))
            .at(x, 0.0)
            .velocity(vx, 0.0)
            .friction(0.0)
            .restitution(1.0)
    };
    let a = add(&mut world, disc(-2.0, 2.0));
    let b = add(&mut world, disc(2.0, -2.0));
    let mut touched = false;
    for _ in 0..120 {
        world.step(DT, SUBSTEPS);
        touched |= world.contacts().any(|c| {
            c.manifold
                .points()
                .iter()
                .any(|p| p.total_normal_impulse > 0.0)
        });
    }
    assert!(touched, "the discs never pushed on each other");
    let (va, vb) = (
        world.body(a).unwrap().linear_velocity,
        world.body(b).unwrap().linear_velocity,
    );
    eprintln!("elastic: va {va}, vb {vb}");
    // Swap within 5% of the 2 m/s speed: the brief's bound. For an isolated pair the
    // restitution pass sets the rebound exactly (measured: -2 and 2 to f32 display precision).
    let tol = 0.05 * 2.0;
    assert!(
        (va.x + 2.0).abs() <= tol && (vb.x - 2.0).abs() <= tol,
        "after the collision va = {va}, vb = {vb}; expected (-2, 0) and (2, 0) within {tol}"
    );
    assert!(
        va.y.abs() <= tol && vb.y.abs() <= tol,
        "head-on collision gained sideways speed: va = {va}, vb = {vb}"
    );
    // Momentum: the total is 0; measure it against the momentum each disc carries (m * 2 m/s,
    // equal masses so the mass cancels): 1% of 2 m/s.
    let p = (va + vb).length();
    assert!(
        p <= 0.01 * 2.0,
        "total momentum per unit mass {p} m/s after the collision (bound 0.02)"
    );
}

#[test]
fn restitution_bounce_reaches_e_squared_height() {
    // A disc dropped from rest with its bottom `drop` above the ground comes back up to e^2 *
    // drop: impact speed sqrt(2 g drop), rebound e times that, apex (e v)^2 / (2 g).
    let e = 0.5_f32;
    let r = 0.5_f32;
    let drop = 5.0_f32;
    let mut world = World::new(settings([0.0, -10.0]));
    add(
        &mut world,
        BodyDef::new(rect(10.0, 0.5))
            .kind(BodyKind::Static)
            .at(0.0, -0.5),
    );
    let ball = add(
        &mut world,
        BodyDef::new(circle(r))
            .at(0.0, r + drop)
            .restitution(e)
            .friction(0.0),
    );
    // Falling 5 m takes 1 s; the rebound to 1.25 m takes 0.5 s. Run 2.5 s.
    let mut bounced = false;
    let mut apex = f32::NEG_INFINITY;
    for _ in 0..150 {
        world.step(DT, SUBSTEPS);
        let b = world.body(ball).unwrap();
        // Only a contact can turn the fall upwards: the first upward velocity marks the bounce.
        bounced |= b.linear_velocity.y > 0.0;
        if bounced {
            apex = apex.max(b.position.y - r);
        }
    }
    assert!(bounced, "the ball never bounced");
    let expected = e * e * drop;
    eprintln!("bounce: apex {apex} m vs e^2 h = {expected} m");
    // 10%: the brief's bound. The scheme lands short of e^2 h, by about 4% (measured 1.198 m
    // for 1.25 m): restitution uses the approach speed stored at the start of the impact step
    // (docs/soft_step.md 2.10), before that step's gravity, which loses up to g dt = 0.17 m/s of
    // the 10 m/s impact speed (up to 3.3% of the apex); the discrete lag g h t / 2 on the way down
    // and up costs about 1 cm each; sampling the apex only at step ends, under 1 mm. (Box2D v3
    // HEAD, same drop, measured here: 1.223 m. The likely reason: its manifolds keep points only
    // within 0.02 m, with no velocity-based margin, so its ball enters the ground within the
    // impact step and is pushed back out.)
    assert!(
        (apex - expected).abs() <= 0.1 * expected,
        "apex after the first bounce {apex} m, expected e^2 h = {expected} m within 10%"
    );
}

/// A unit box on a static slope of angle `theta`, both with friction `mu`. Returns the world,
/// the box's id and the downhill unit vector.
fn incline(theta: f32, mu: f32) -> (World, BodyId, Vec2) {
    let mut world = World::new(settings([0.0, -10.0]));
    let (s, c) = theta.sin_cos();
    let normal = Vec2::new(-s, c);
    let downhill = Vec2::new(-c, -s);
    // Slope: a 30 m x 1 m box centred on the origin, turned by theta; its top face passes
    // 0.5 m along the normal from the origin.
    add(
        &mut world,
        BodyDef::new(rect(15.0, 0.5))
            .kind(BodyKind::Static)
            .angle(theta)
            .friction(mu),
    );
    // The 1 m box sits on the face: its centre 0.5 + 0.5 m along the normal, turned by theta.
    let centre = normal * 1.0;
    let id = add(
        &mut world,
        BodyDef::new(rect(0.5, 0.5))
            .at(centre.x, centre.y)
            .angle(theta)
            .friction(mu),
    );
    (world, id, downhill)
}

#[test]
fn box_sticks_on_incline_when_friction_exceeds_tan_theta() {
    let theta = 20.0_f32.to_radians();
    let mu = 0.6; // > tan 20 deg = 0.364
    let (mut world, id, downhill) = incline(theta, mu);
    let start = world.body(id).unwrap().position;
    for _ in 0..120 {
        world.step(DT, SUBSTEPS);
    }
    let b = world.body(id).unwrap();
    let along = (b.position - start).dot(downhill);
    eprintln!(
        "incline stick: moved {along} m down the slope, angle {} vs {theta}",
        b.angle
    );
    // 5 mm (one linear slop) over 2 s: a sticking box should not creep. Static friction is
    // solved rigidly in the relax pass, so the only slip is the first contact's settling
    // within a step (measured 0.15 mm).
    assert!(
        along.abs() < 0.005,
        "box with mu {mu} on a {}-degree slope moved {along} m down the slope in 2 s (bound 0.005 m); v = {}",
        theta.to_degrees(),
        b.linear_velocity
    );
    assert!(
        (b.angle - theta).abs() < 0.01,
        "box turned on the slope: angle {} rad, slope {theta} rad",
        b.angle
    );
}

#[test]
fn box_slides_on_incline_with_coulomb_acceleration() {
    let theta = 20.0_f32.to_radians();
    let mu = 0.1_f32; // < tan 20 deg = 0.364
    let (mut world, id, downhill) = incline(theta, mu);
    // Settle a quarter second (contact established, warm start built up), then measure the
    // velocity gain along the slope over one second.
    for _ in 0..15 {
        world.step(DT, SUBSTEPS);
    }
    let v0 = world.body(id).unwrap().linear_velocity.dot(downhill);
    let steps = 60;
    for _ in 0..steps {
        world.step(DT, SUBSTEPS);
    }
    let v1 = world.body(id).unwrap().linear_velocity.dot(downhill);
    let measured = (v1 - v0) / (steps as f32 * DT);
    let expected = 10.0 * (theta.sin() - mu * theta.cos());
    eprintln!("incline slide: a {measured} vs {expected} m/s^2");
    // 10%: the brief's bound. Friction is rigid Coulomb in the relax pass, so a sliding box
    // sees mu * N almost exactly (measured 2.4805 vs 2.4805 m/s^2).
    assert!(
        (measured - expected).abs() <= 0.1 * expected,
        "slide acceleration {measured} m/s^2, expected g (sin - mu cos) = {expected} m/s^2 within 10%"
    );
    let b = world.body(id).unwrap();
    assert!(
        (b.angle - theta).abs() < 0.01,
        "sliding box tipped: angle {} rad, slope {theta} rad",
        b.angle
    );
}

#[test]
fn linear_damping_converges_to_exponential() {
    // v <- v / (1 + h c) per substep: after n substeps v = v0 (1 + h c)^-n, which tends to
    // v0 exp(-c t) as h -> 0; relative error about c^2 h t / 2 = 0.1% at h = 1/240, t = 2 s.
    let c = 0.5_f32;
    let v0 = 10.0_f32;
    let speed_at = |dt: f32| -> f32 {
        let mut world = World::new(settings([0.0, 0.0]));
        let id = add(
            &mut world,
            BodyDef::new(circle(0.5)).velocity(v0, 0.0).damping(c, 0.0),
        );
        let steps = (2.0 / dt).round() as u32;
        for _ in 0..steps {
            world.step(dt, SUBSTEPS);
        }
        world.body(id).unwrap().linear_velocity.length()
    };
    let v60 = speed_at(1.0 / 60.0);
    let v120 = speed_at(1.0 / 120.0);
    let exact = v0 * (-c * 2.0_f32).exp();
    eprintln!("damping: v(1/60) {v60}, v(1/120) {v120}, exact {exact}");
    // 2%: the brief's bound; the Padé error above is 0.1% and 0.05% (measured 3.6827 and
    // 3.6807 against 3.6788).
    assert!(
        (v60 - v120).abs() <= 0.02 * v120,
        "speed after 2 s: {v60} at dt 1/60 vs {v120} at dt 1/120 (bound 2%)"
    );
    for (label, v) in [("1/60", v60), ("1/120", v120)] {
        assert!(
            (v - exact).abs() <= 0.02 * exact,
            "speed after 2 s at dt {label}: {v}, exact 10 e^-1 = {exact} (bound 2%)"
        );
    }
    // And the discrete Padé product itself, in f64, to f32 round-off: 480 (or 960) divisions
    // each off by at most 2 U relative (reciprocal, product), i.e. 2 n U ~ 1e-4 relative.
    for (dt, v) in [(1.0_f64 / 60.0, v60), (1.0 / 120.0, v120)] {
        let h = dt / f64::from(SUBSTEPS);
        let n = (2.0 / dt).round() * f64::from(SUBSTEPS);
        let pade = f64::from(v0) * (1.0 + h * f64::from(c)).powf(-n);
        let tol = 4.0 * n * U * pade;
        assert!(
            (f64::from(v) - pade).abs() <= tol,
            "speed {v} vs discrete Padé product {pade} at dt {dt} (bound {tol:e})"
        );
    }
}
