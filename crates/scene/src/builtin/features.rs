//! Small samples, one game feature each (issue 35): forces and torques, run-time material and
//! filter changes, conveyor belts, rolling resistance, one-way platforms, explosions,
//! breakable joints, sensors with their overlaps listed, ray and shape casts, contact events, sleep and
//! wake, bullets. Each is a scene and, where the feature is a call made between steps, a
//! [`Feature`] controller that makes it, built on the library's public calls only.

use serde::{Deserialize, Serialize};
use tumble_physics::{
    BodyDef, BodyId, BodyKind, Event, ExplosionDef, Filter, JointDef, PartDef, QueryFilter,
    SceneDef, ShapeId, Vec2, World,
};

use super::{circle as ball, rect};
use crate::sample::{self, Keys, scene_shape};

/// A scene named `name` with a 60 m floor whose top is y = 0 and walls at x = ±20, 12 m
/// tall (scene bodies 0, 1 and 2).
fn arena(name: &str) -> SceneDef {
    let mut scene = SceneDef::new(name);
    scene.push(
        BodyDef::new(rect(30.0, 0.5))
            .kind(BodyKind::Static)
            .at(0.0, -0.5),
    );
    for x in [-20.5, 20.5] {
        scene.push(
            BodyDef::new(rect(0.5, 6.0))
                .kind(BodyKind::Static)
                .at(x, 6.0),
        );
    }
    scene
}

/// The one-way platforms' filter category.
const ONE_WAY: u64 = 1 << 3;

/// Which feature a sample shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum Kind {
    /// A rocket steered by keys: force and torque.
    Forces,
    /// A ramp's friction and a gate's filter changed as it runs.
    Materials,
    /// Boxes kicked up through one-way platforms.
    OneWay,
    /// A pile blown apart.
    Explosions,
    /// A bridge whose hinges break under a falling crate.
    BreakableJoints,
    /// A sensor listing what overlaps it.
    Sensors,
    /// A ray sweeping the scene, its hits listed, and a ball cast down onto the pile.
    RayCasts,
    /// Contact begins, ends and hits counted.
    ContactEvents,
    /// A pile that sleeps and a ball that wakes it.
    SleepAndWake,
}

/// The state of a feature sample between steps: its counts and what it draws.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Feature {
    /// Which feature.
    pub kind: Kind,
    /// Counts the sample keeps (explosions, joints broken, contact begins, ends, hits...).
    pub counts: [u64; 4],
    /// What the panel shows now.
    pub lines: Vec<String>,
    /// A ray cast this step and the points it hit, to draw.
    pub ray: Option<(Vec2, Vec2, Vec<Vec2>)>,
    /// A ball cast this step, to draw.
    pub cast: Option<BallCast>,
}

/// A ball moved without turning from `from` along `translation` (`cast_shape_closest`), and
/// where it first meets a shape.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct BallCast {
    /// Where the ball's centre starts.
    pub from: Vec2,
    /// How far it is moved.
    pub translation: Vec2,
    /// Its radius (m).
    pub radius: f32,
    /// The first hit: the fraction of the translation, the point on the other shape and
    /// that shape's outward normal there.
    pub hit: Option<(f32, Vec2, Vec2)>,
}

impl BallCast {
    /// Where the ball's centre stops: at the first hit, or at the end of the translation.
    pub fn stop(&self) -> Vec2 {
        let t = self.hit.map_or(1.0, |(t, _, _)| t);
        self.from + t * self.translation
    }
}

impl Feature {
    /// A sample's controller at its start.
    pub fn new(kind: Kind) -> Feature {
        Feature {
            kind,
            counts: [0; 4],
            lines: Vec::new(),
            ray: None,
            cast: None,
        }
    }

    /// Sets the hooks the sample needs (the one-way platforms' pre-solve).
    pub fn install(&self, world: &mut World) {
        if self.kind != Kind::OneWay {
            return;
        }
        let decks: Vec<ShapeId> = [3, 4]
            .iter()
            .filter_map(|&i| scene_shape(world, i))
            .collect();
        world.set_pre_solve(Some(sample::one_way_platforms(decks)));
    }

    /// Before step `step`, with `keys` held.
    pub fn before_step(&mut self, step: u64, keys: Keys, world: &mut World) {
        match self.kind {
            Kind::Forces => {
                let rocket = BodyId::scene(ROCKET);
                let Ok(view) = world.body(rocket) else { return };
                let mass = world.mass(rocket).unwrap_or(0.0);
                let inertia = world.inertia(rocket).unwrap_or(0.0);
                let up = view.rotation.apply(Vec2::Y);
                let thrust = keys.contains(Keys::JUMP);
                if thrust {
                    // Twice its weight, along its own axis, at its centre.
                    let _ = world.apply_force_to_center(rocket, 2.0 * 10.0 * mass * up, true);
                }
                let mut turn = 0.0;
                if keys.contains(Keys::LEFT) {
                    turn += 1.0;
                }
                if keys.contains(Keys::RIGHT) {
                    turn -= 1.0;
                }
                if turn != 0.0 {
                    let _ = world.apply_torque(rocket, turn * 20.0 * inertia, true);
                }
                self.lines = vec![
                    format!("Thrust: {}", if thrust { "on" } else { "off" }),
                    format!("Height: {:.2} m", view.position.y),
                ];
            }
            Kind::Materials => {
                // Every two seconds the ramp's friction takes the next of three values, and
                // every three the gate opens or closes (its filter touches nothing, or all).
                let friction = [0.0, 0.3, 1.0][((step / 120) % 3) as usize];
                if let Some(ramp) = scene_shape(world, MATERIAL_RAMP) {
                    let _ = world.set_friction(ramp, friction);
                }
                let open = (step / 180) % 2 == 1;
                if let Some(gate) = scene_shape(world, MATERIAL_GATE) {
                    let filter = Filter {
                        mask: if open { 0 } else { u64::MAX },
                        ..Filter::default()
                    };
                    let _ = world.set_filter(gate, filter);
                }
                self.lines = vec![
                    format!("Ramp friction: {friction}"),
                    format!("Gate: {}", if open { "open (mask 0)" } else { "closed" }),
                ];
            }
            Kind::OneWay => {
                // Every 1.5 s each box resting on the floor is kicked up.
                if step % 90 == 30 {
                    for k in 0..ONE_WAY_BOXES {
                        let id = BodyId::scene(5 + k);
                        if world.body(id).is_ok_and(|b| b.position.y < 0.5) {
                            let mass = world.mass(id).unwrap_or(0.0);
                            let _ = world.apply_linear_impulse_to_center(
                                id,
                                Vec2::new(0.0, 13.0 * mass),
                                true,
                            );
                        }
                    }
                }
                let above = (0..ONE_WAY_BOXES)
                    .filter(|&k| {
                        world
                            .body(BodyId::scene(5 + k))
                            .is_ok_and(|b| b.position.y > 3.0)
                    })
                    .count();
                self.lines = vec![format!(
                    "Boxes on the platforms: {above} of {ONE_WAY_BOXES}"
                )];
            }
            Kind::Explosions => {
                if keys.contains(Keys::JUMP) || step % 240 == 120 {
                    let def = ExplosionDef {
                        position: Vec2::new(0.0, 0.5),
                        radius: 6.0,
                        falloff: 2.0,
                        impulse_per_length: 8.0,
                        mask: u64::MAX,
                    };
                    if world.explode(&def).is_ok() {
                        self.counts[0] += 1;
                    }
                }
                self.lines = vec![format!("Explosions: {}", self.counts[0])];
            }
            Kind::RayCasts => {
                // A ray from above the pile, sweeping half a turn back and forth.
                let angle = -std::f32::consts::FRAC_PI_2 + 1.2 * ((step as f32) * 0.01).sin();
                let from = Vec2::new(0.0, 10.0);
                let to = from + 25.0 * Vec2::new(angle.cos(), angle.sin());
                let mut hits = world.cast_ray_all(from, to - from, &QueryFilter::default());
                hits.sort_by(|a, b| a.fraction.total_cmp(&b.fraction));
                self.lines = vec![format!("Hits: {}", hits.len())];
                for h in hits.iter().take(4) {
                    self.lines.push(format!(
                        "  {} at ({:.2}, {:.2}), {:.0}% along",
                        h.shape.body,
                        h.point.x,
                        h.point.y,
                        100.0 * h.fraction
                    ));
                }
                self.ray = Some((from, to, hits.iter().map(|h| h.point).collect()));
                // A ball dropped from above at a place that drifts over the pile: where it
                // would first land.
                let radius = 0.6;
                let ball_shape = tumble_physics::Shape::Circle(tumble_physics::Circle { radius });
                let from = Vec2::new(9.0 * ((step as f32) * 0.007).sin(), 9.0);
                let translation = Vec2::new(0.0, -8.9);
                let pose = tumble_physics::Transform {
                    p: from,
                    q: tumble_physics::Rot::IDENTITY,
                };
                let hit = world.cast_shape_closest(
                    &ball_shape,
                    pose,
                    translation,
                    &QueryFilter::default(),
                );
                let cast = BallCast {
                    from,
                    translation,
                    radius,
                    hit: hit.map(|h| (h.fraction, h.point, h.normal)),
                };
                self.lines.push(match (hit, cast.hit) {
                    (Some(h), Some((t, p, _))) => format!(
                        "Ball cast: meets {} at ({:.2}, {:.2}), {:.0}% down",
                        h.shape.body,
                        p.x,
                        p.y,
                        100.0 * t
                    ),
                    _ => "Ball cast: meets nothing".to_string(),
                });
                self.cast = Some(cast);
            }
            Kind::SleepAndWake => {
                // Every four seconds a ball is dropped on the pile, which wakes it.
                if step % 240 == 239 {
                    let x = ((step / 240) % 5) as f32 - 2.0;
                    let _ = world.create_body(&BodyDef::new(ball(0.4)).at(x, 10.0));
                }
                self.lines = vec![format!(
                    "Awake: {} of {} bodies",
                    world.awake_body_count(),
                    world.body_count()
                )];
            }
            Kind::BreakableJoints | Kind::Sensors | Kind::ContactEvents => {}
        }
    }

    /// After step `step`: what the sample reads of the step (events, overlaps).
    pub fn after_step(&mut self, _step: u64, world: &mut World) {
        match self.kind {
            Kind::BreakableJoints => {
                let broken: Vec<_> = world
                    .events()
                    .iter()
                    .filter_map(|e| match *e {
                        Event::JointThreshold { joint, .. } => Some(joint),
                        _ => None,
                    })
                    .collect();
                for joint in broken {
                    if world.destroy_joint(joint).is_ok() {
                        self.counts[0] += 1;
                    }
                }
                self.lines = vec![
                    format!("Hinges broken: {}", self.counts[0]),
                    format!("Hinges left: {}", world.joint_count()),
                ];
            }
            Kind::Sensors => {
                let Some(sensor) = scene_shape(world, SENSOR) else {
                    return;
                };
                let overlaps = world.sensor_overlaps(sensor).unwrap_or_default();
                self.lines = vec![format!("In the sensor: {}", overlaps.len())];
                for shape in overlaps.iter().take(6) {
                    if let Ok(s) = world.shape(*shape) {
                        self.lines.push(format!("  {} ({})", s.body, shape));
                    }
                }
            }
            Kind::ContactEvents => {
                for event in world.events() {
                    match event {
                        Event::ContactBegin { .. } => self.counts[0] += 1,
                        Event::ContactEnd { .. } => self.counts[1] += 1,
                        Event::Hit { .. } => self.counts[2] += 1,
                        _ => {}
                    }
                }
                self.lines = vec![
                    format!("Contact begins: {}", self.counts[0]),
                    format!("Contact ends: {}", self.counts[1]),
                    format!("Hits (faster than 1 m/s): {}", self.counts[2]),
                    format!("Touching now: {}", world.contact_count()),
                ];
            }
            _ => {}
        }
    }

    /// Draws the ray and its hits (the ray casts sample).
    pub fn draw(&self, draw: &mut impl tumble_physics::draw::DebugDraw) {
        use tumble_physics::draw::colors;
        if let Some((from, to, hits)) = &self.ray {
            draw.draw_segment(*from, *to, colors::LIMIT);
            for &p in hits {
                draw.draw_point(p, 0.15, colors::TOUCHING);
            }
        }
        if let Some(cast) = &self.cast {
            let stop = cast.stop();
            draw.draw_segment(cast.from, stop, colors::AXIS);
            ring(draw, cast.from, cast.radius, colors::AXIS);
            ring(draw, stop, cast.radius, colors::LIMIT);
            if let Some((_, p, n)) = cast.hit {
                draw.draw_point(p, 0.15, colors::TOUCHING);
                draw.draw_segment(p, p + 0.5 * n, colors::NORMAL);
            }
        }
    }
}

/// A circle's outline, 24 sides.
fn ring(
    draw: &mut impl tumble_physics::draw::DebugDraw,
    centre: Vec2,
    radius: f32,
    color: [f32; 4],
) {
    let at = |k: usize| {
        let a = k as f32 * std::f32::consts::TAU / 24.0;
        centre + radius * Vec2::new(a.cos(), a.sin())
    };
    for k in 0..24 {
        draw.draw_segment(at(k), at(k + 1), color);
    }
}

/// The keys the forces sample reads.
pub const FORCES_KEYS: &[(&str, &str)] = &[
    ("Space / Up / W", "thrust (twice the weight)"),
    ("Left / A, Right / D", "turn (a torque)"),
];
/// The keys the explosions sample reads.
pub const EXPLOSION_KEYS: &[(&str, &str)] = &[("Space / Up / W", "explode now")];

/// The forces sample's rocket (scene body).
const ROCKET: usize = 4;

/// A rocket (a 1 x 2 m box) on the floor: Space thrusts along its axis, Left and Right turn
/// it (`apply_force_to_center`, `apply_torque`).
pub fn forces() -> SceneDef {
    let mut scene = arena("forces");
    scene.push(
        BodyDef::new(rect(30.0, 0.5))
            .kind(BodyKind::Static)
            .at(0.0, 12.5),
    );
    let rocket = scene.push(BodyDef::new(rect(0.5, 1.0)).at(0.0, 1.0).damping(0.2, 2.0));
    debug_assert_eq!(rocket, ROCKET);
    scene
}

const MATERIAL_RAMP: usize = 3;
const MATERIAL_GATE: usize = 4;

/// Three boxes on a 25-degree ramp whose friction changes every two seconds (0, 0.3, 1:
/// tan 25 deg = 0.47), and balls on a gate whose filter opens it every three
/// (`set_friction`, `set_filter`).
pub fn materials() -> SceneDef {
    let mut scene = arena("materials");
    let ramp = scene.push(
        BodyDef::new(rect(6.0, 0.25))
            .kind(BodyKind::Static)
            .at(-8.0, 4.0)
            .angle(-25f32.to_radians()),
    );
    let gate = scene.push(
        BodyDef::new(rect(3.0, 0.2))
            .kind(BodyKind::Static)
            .at(8.0, 4.0),
    );
    debug_assert_eq!((ramp, gate), (MATERIAL_RAMP, MATERIAL_GATE));
    // Three boxes resting on the ramp's face, 2 m apart along it.
    let (sin, cos) = 25f32.to_radians().sin_cos();
    for k in 0..3 {
        let along = -4.0 + 2.0 * k as f32;
        let out = 0.25 + 0.4 + 0.005;
        scene.push(
            BodyDef::new(rect(0.4, 0.4))
                .at(
                    -8.0 + along * cos + out * sin,
                    4.0 - along * sin + out * cos,
                )
                .angle(-25f32.to_radians()),
        );
    }
    for k in 0..5 {
        scene.push(BodyDef::new(ball(0.3)).at(6.0 + k as f32, 5.0));
    }
    scene
}

/// Two belts, one running right at 2 m/s and one left, under falling crates (a part's
/// `tangent_speed`).
pub fn conveyor_belts() -> SceneDef {
    let mut scene = arena("conveyor_belts");
    for (x, y, speed) in [(-6.0, 3.0, 2.0), (6.0, 1.5, -2.0)] {
        scene.push(
            BodyDef::compound(vec![PartDef::new(rect(5.0, 0.2)).tangent_speed(speed)])
                .kind(BodyKind::Static)
                .friction(0.8)
                .at(x, y),
        );
    }
    for k in 0..6 {
        let x = -9.0 + 3.5 * k as f32;
        scene.push(
            BodyDef::new(rect(0.4, 0.4))
                .at(x, 6.0 + 0.5 * k as f32)
                .friction(0.8),
        );
    }
    scene
}

/// Four balls rolled at 6 m/s along the floor, their rolling resistance 0, 0.02, 0.05 and
/// 0.1 (a part's `rolling_resistance`): the first rolls on, the others stop in turn.
pub fn rolling_resistance() -> SceneDef {
    let mut scene = arena("rolling_resistance");
    for c in [0.0, 0.02, 0.05, 0.1] {
        scene.push(
            // Side by side in depth: a shared negative group keeps them from touching.
            BodyDef::compound(vec![PartDef::new(ball(0.5)).rolling_resistance(c).filter(
                Filter {
                    group: -1,
                    ..Filter::default()
                },
            )])
            .at(-18.0, 0.5)
            .velocity(6.0, 0.0)
            .spin(-12.0),
        );
    }
    scene
}

const ONE_WAY_BOXES: usize = 6;

/// Boxes kicked up every 1.5 s through two one-way platforms, onto which they land (the
/// pre-solve hook).
pub fn one_way_platforms() -> SceneDef {
    let mut scene = arena("one_way_platforms");
    let deck = Filter {
        category: ONE_WAY,
        ..Filter::default()
    };
    for (x, y) in [(-4.0, 3.0), (4.0, 5.0)] {
        scene.push(
            BodyDef::new(rect(3.5, 0.15))
                .kind(BodyKind::Static)
                .filter(deck)
                .at(x, y),
        );
    }
    for k in 0..ONE_WAY_BOXES {
        let x = -6.5 + 2.6 * k as f32;
        scene.push(BodyDef::new(rect(0.3, 0.3)).at(x, 0.3));
    }
    scene
}

/// A pile of 40 boxes blown apart every four seconds, or when Space is pressed
/// (`World::explode`).
pub fn explosions() -> SceneDef {
    let mut scene = arena("explosions");
    for row in 0..5 {
        for col in 0..8 {
            let x = -3.5 + col as f32 + 0.5 * (row % 2) as f32;
            scene.push(BodyDef::new(rect(0.45, 0.45)).at(x, 0.45 + 0.9 * row as f32));
        }
    }
    scene
}

/// A ten-plank bridge hung between two posts, its hinges breaking past 600 N, and a 60 kg
/// crate falling on it (`JointDef::with_thresholds`, `Event::JointThreshold`,
/// `destroy_joint`).
pub fn breakable_joints() -> SceneDef {
    let mut scene = arena("breakable_joints");
    let posts = [
        scene.push(
            BodyDef::new(rect(0.2, 0.2))
                .kind(BodyKind::Static)
                .at(-5.0, 4.0),
        ),
        scene.push(
            BodyDef::new(rect(0.2, 0.2))
                .kind(BodyKind::Static)
                .at(5.0, 4.0),
        ),
    ];
    let sag = 1.0;
    let corner = |k: usize| [-5.0 + k as f32, 4.0 - sag * (k.min(10 - k) as f32) / 5.0];
    let first = scene.bodies.len();
    for k in 0..10 {
        let ([x0, y0], [x1, y1]) = (corner(k), corner(k + 1));
        let half = 0.5 * ((x1 - x0).powi(2) + (y1 - y0).powi(2)).sqrt();
        scene.push(
            BodyDef::new(rect(half, 0.08))
                .density(4.0)
                .damping(1.0, 1.0)
                .at(0.5 * (x0 + x1), 0.5 * (y0 + y1))
                .angle((y1 - y0).atan2(x1 - x0)),
        );
    }
    for k in 0..=10 {
        let a = if k == 0 { posts[0] } else { first + k - 1 };
        let b = if k == 10 { posts[1] } else { first + k };
        scene.joints.push(
            JointDef::hinge([BodyId::scene(a), BodyId::scene(b)], corner(k))
                .with_thresholds(600.0, f32::INFINITY),
        );
    }
    scene.push(BodyDef::new(rect(0.5, 0.5)).density(60.0).at(0.5, 12.0));
    scene
}

const SENSOR: usize = 3;

/// Bouncing balls through a sensor zone in the middle; the panel lists what overlaps it
/// (`sensor_overlaps`).
pub fn sensors() -> SceneDef {
    let mut scene = arena("sensors");
    let zone = scene.push(
        BodyDef::compound(vec![PartDef::new(rect(3.0, 2.0)).sensor(true)])
            .kind(BodyKind::Static)
            .at(0.0, 2.0),
    );
    debug_assert_eq!(zone, SENSOR);
    for k in 0..8 {
        let x = -16.0 + 4.0 * k as f32;
        let vx = if k % 2 == 0 { 5.0 } else { -5.0 };
        scene.push(
            BodyDef::new(ball(0.4))
                .at(x, 3.0 + 0.5 * (k % 3) as f32)
                .velocity(vx, 0.0)
                .restitution(0.9)
                .friction(0.0),
        );
    }
    scene
}

/// A ray sweeping over a pile of boxes and balls from above, every hit listed and drawn
/// (`cast_ray_all`), and a ball cast down onto the pile (`cast_shape_closest`).
pub fn ray_casts() -> SceneDef {
    let mut scene = arena("ray_casts");
    for k in 0..12 {
        let x = -8.0 + 1.5 * k as f32;
        let body = if k % 2 == 0 {
            BodyDef::new(rect(0.5, 0.5))
        } else {
            BodyDef::new(ball(0.5))
        };
        scene.push(body.at(x, 0.5 + (k % 3) as f32));
    }
    scene
}

/// Boxes and balls dropped into a pile, every contact begin, end and hit (above 1 m/s)
/// counted (`Event`).
pub fn contact_events() -> SceneDef {
    let mut scene = arena("contact_events");
    scene.hit_speed = 1.0;
    for k in 0..20 {
        let x = -5.0 + (k % 10) as f32;
        let y = 3.0 + 2.0 * (k / 10) as f32 + 0.3 * (k % 3) as f32;
        let body = if k % 2 == 0 {
            BodyDef::new(rect(0.4, 0.4))
        } else {
            BodyDef::new(ball(0.4))
        };
        scene.push(body.at(x, y).restitution(0.3));
    }
    scene
}

/// A pyramid that falls asleep, and every four seconds a ball dropped on it that wakes it
/// (islands and sleep).
pub fn sleep_and_wake() -> SceneDef {
    let mut scene = arena("sleep_and_wake");
    for row in 0..6 {
        for col in 0..(6 - row) {
            let x = -2.5 + col as f32 + 0.5 * row as f32;
            scene.push(BodyDef::new(rect(0.5, 0.5)).at(x, 0.5 + row as f32));
        }
    }
    scene
}

/// Balls fired at 120 m/s at a row of thin planks: bullets (left) stop at the first plank,
/// the plain balls (right) tunnel through the thin dynamic planks (continuous collision
/// against moving bodies is a bullet's).
pub fn bullets() -> SceneDef {
    let mut scene = arena("bullets");
    scene.push(
        BodyDef::new(rect(30.0, 0.5))
            .kind(BodyKind::Static)
            .at(0.0, 12.5),
    );
    for row in [0.0, 6.0] {
        // A shelf for each row and its thin planks standing on it.
        scene.push(
            BodyDef::new(rect(10.0, 0.25))
                .kind(BodyKind::Static)
                .at(5.0, row + 2.0),
        );
        for k in 0..4 {
            scene.push(BodyDef::new(rect(0.05, 1.0)).at(2.0 + 2.0 * k as f32, row + 3.25));
        }
    }
    for bullet in [true, false] {
        let y = if bullet { 3.0 } else { 9.0 };
        scene.push(
            BodyDef::new(ball(0.1))
                .at(-15.0, y)
                .velocity(120.0, 0.0)
                .gravity_scale(0.0)
                .bullet(bullet),
        );
    }
    scene
}

/// Each joint kind with its limits, motors and springs, side by side: a revolute arm driven
/// against its limit, a prismatic slider lifted to its limit, a sprung wheel spinning, a ball
/// on a springy rope with length limits, a plank on a soft weld, a box held by a motor joint.
/// The scene is data: `joint_kinds.ron`, beside this file.
pub fn joint_kinds() -> SceneDef {
    crate::parse(
        include_bytes!("joint_kinds.ron"),
        crate::Format::Ron,
        "joint_kinds.ron (built-in)",
        &crate::LoadLimits::default(),
    )
    .expect("the built-in joint_kinds.ron is a valid scene")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sample::{Controller, KeyScript, play};

    fn run(name: &str, keys: &str, steps: u64) -> (World, Option<Controller>) {
        let scene = crate::builtin::build(name).unwrap();
        let script = KeyScript::parse(keys).unwrap();
        play(&scene, &script, steps, 1, |_, w, _| {
            assert!(w.is_finite(), "{name}")
        })
        .unwrap()
    }

    fn body(world: &World, index: usize) -> tumble_physics::BodyView {
        world.body(BodyId::scene(index)).unwrap()
    }

    #[test]
    fn every_feature_sample_runs_finite_and_the_same_on_one_and_two_threads() {
        for name in [
            "forces",
            "materials",
            "conveyor_belts",
            "rolling_resistance",
            "one_way_platforms",
            "explosions",
            "breakable_joints",
            "sensors",
            "ray_casts",
            "contact_events",
            "sleep_and_wake",
            "bullets",
            "joint_kinds",
        ] {
            let scene = crate::builtin::build(name).unwrap();
            let script = KeyScript::parse("0:jump+,30:jump-,30:left+,45:left-").unwrap();
            let one = play(&scene, &script, 300, 1, |_, _, _| {}).unwrap();
            let two = play(&scene, &script, 300, 2, |_, _, _| {}).unwrap();
            assert!(one.0.is_finite(), "{name}");
            assert_eq!(one.0.state_hash(), two.0.state_hash(), "{name}");
            assert_eq!(one.1, two.1, "{name}");
        }
    }

    #[test]
    fn every_joint_kind_holds_its_limit_or_its_target() {
        let (world, _) = run("joint_kinds", "", 240);
        let joints: Vec<_> = world.joint_ids().collect();
        // The revolute motor drives the arm to its upper limit (0.5 rad), within the soft
        // step's limit error of a few hundredths.
        let angle = world.revolute_angle(joints[0]).unwrap();
        assert!((angle - 0.5).abs() < 0.05, "{angle}");
        // The prismatic motor lifts the slider to its upper limit (1 m).
        let t = world.prismatic_translation(joints[1]).unwrap();
        assert!((t - 1.0).abs() < 0.02, "{t}");
        // The wheel spins at its motor's speed.
        let w = body(&world, 6).angular_velocity;
        assert!((w - 5.0).abs() < 0.1, "{w}");
        // The rope stays within its limits.
        let l = world.distance_length(joints[3]).unwrap();
        assert!((1.5 - 0.02..=2.5 + 0.02).contains(&l), "{l}");
        // The motor joint holds its box at (16, 4.5) within 2 cm.
        let p = body(&world, 11).position;
        assert!((p - Vec2::new(16.0, 4.5)).length() < 0.02, "{p}");
    }

    #[test]
    fn thrust_lifts_the_rocket_and_a_torque_turns_it() {
        let (world, _) = run("forces", "0:jump+,60:jump-", 60);
        assert!(
            body(&world, ROCKET).position.y > 3.0,
            "{:?}",
            body(&world, ROCKET).position
        );
        let (world, _) = run("forces", "0:left+", 30);
        assert!(body(&world, ROCKET).angular_velocity > 1.0);
    }

    #[test]
    fn an_open_gate_lets_the_balls_through_and_a_closed_one_holds_them() {
        // Closed for the first three seconds: the balls rest on it (top at 4.2 m).
        let (world, _) = run("materials", "", 170);
        assert!((0..5).all(|k| body(&world, 8 + k).position.y > 4.0));
        // Open from then on: they fall to the floor.
        let (world, _) = run("materials", "", 300);
        assert!((0..5).all(|k| body(&world, 8 + k).position.y < 1.0));
    }

    #[test]
    fn a_crate_on_a_belt_moves_at_the_belts_speed() {
        let (world, _) = run("conveyor_belts", "", 180);
        // The first crate fell on the right-running belt (top at 3.2 m).
        let c = body(&world, 5);
        assert!(
            (c.linear_velocity.x - 2.0).abs() < 0.1,
            "{:?}",
            c.linear_velocity
        );
    }

    #[test]
    fn more_rolling_resistance_stops_a_ball_sooner() {
        let (world, _) = run("rolling_resistance", "", 240);
        let x: Vec<f32> = (0..4).map(|k| body(&world, 3 + k).position.x).collect();
        assert!(x[0] > x[1] && x[1] > x[2] && x[2] > x[3], "{x:?}");
    }

    #[test]
    fn kicked_boxes_pass_up_through_the_platforms_and_land_on_them() {
        let (world, c) = run("one_way_platforms", "", 400);
        let on = (0..ONE_WAY_BOXES)
            .filter(|&k| body(&world, 5 + k).position.y > 3.0)
            .count();
        assert!(on >= 2, "{on} on the platforms; {c:?}");
    }

    #[test]
    fn an_explosion_throws_the_pile_outwards() {
        let (world, c) = run("explosions", "", 125);
        let Some(Controller::Feature(f)) = c else {
            panic!()
        };
        assert_eq!(f.counts[0], 1);
        let outward = (0..40)
            .filter(|&k| {
                let b = body(&world, 3 + k);
                b.linear_velocity.x * b.position.x > 0.0
            })
            .count();
        assert!(outward > 30, "{outward} of 40 move away from the centre");
    }

    #[test]
    fn the_crate_breaks_the_bridge() {
        let (world, c) = run("breakable_joints", "", 240);
        let Some(Controller::Feature(f)) = c else {
            panic!()
        };
        assert!(f.counts[0] > 0 && world.joint_count() < 11, "{f:?}");
    }

    #[test]
    fn the_sensor_lists_the_balls_inside_it() {
        let mut seen = 0;
        let scene = crate::builtin::build("sensors").unwrap();
        play(&scene, &KeyScript::default(), 240, 1, |_, w, c| {
            let Some(Controller::Feature(f)) = c else {
                return;
            };
            let n: usize = f.lines[0]
                .trim_start_matches("In the sensor: ")
                .parse()
                .unwrap();
            let sensor = scene_shape(w, SENSOR).unwrap();
            assert_eq!(n, w.sensor_overlaps(sensor).unwrap().len());
            seen = seen.max(n);
        })
        .unwrap();
        assert!(seen > 0);
    }

    #[test]
    fn the_ray_lists_hits_that_lie_on_it() {
        let (_, c) = run("ray_casts", "", 60);
        let Some(Controller::Feature(f)) = c else {
            panic!()
        };
        let (from, to, hits) = f.ray.clone().unwrap();
        assert!(!hits.is_empty());
        let d = (to - from).normalize();
        for p in hits {
            assert!((p - from).perp_dot(d).abs() < 1e-3, "{p} off the ray");
        }
    }

    #[test]
    fn the_cast_ball_stops_touching_what_it_meets() {
        // Every 20 steps once the pile has settled (2 s), over the ball's drift across it:
        // where it meets something, its centre stops a radius from the hit point (to 1 cm:
        // the cast stops rounded surfaces a linear slop, 5 mm, into each other), the hit
        // below it, the normal up, and nothing overlaps the ball lifted by that centimetre.
        let (mut looked, mut met) = (0, 0);
        let scene = crate::builtin::build("ray_casts").unwrap();
        play(&scene, &KeyScript::default(), 600, 1, |step, world, c| {
            if step < 120 || step % 20 != 0 {
                return;
            }
            let Some(Controller::Feature(f)) = c else {
                panic!()
            };
            let cast = f.cast.unwrap();
            looked += 1;
            let Some((t, p, n)) = cast.hit else { return };
            met += 1;
            let stop = cast.stop();
            assert!((0.0..=1.0).contains(&t));
            assert!(((stop - p).length() - cast.radius).abs() < 0.01, "{cast:?}");
            assert!(p.y < stop.y && n.y > 0.0, "{cast:?}");
            let pose = tumble_physics::Transform {
                p: stop + Vec2::new(0.0, 0.01),
                q: tumble_physics::Rot::IDENTITY,
            };
            let ball = tumble_physics::Shape::Circle(tumble_physics::Circle {
                radius: cast.radius,
            });
            let mut overlaps = 0;
            world.overlap_shape(&ball, pose, &QueryFilter::default(), |_| {
                overlaps += 1;
                true
            });
            assert_eq!(overlaps, 0, "step {step}: {cast:?}");
        })
        .unwrap();
        // The floor is under the whole drift, so the ball always meets something.
        assert_eq!((looked, met), (24, 24));
    }

    #[test]
    fn contact_events_are_counted_and_ends_never_outnumber_begins() {
        let (_, c) = run("contact_events", "", 240);
        let Some(Controller::Feature(f)) = c else {
            panic!()
        };
        assert!(f.counts[0] > 20 && f.counts[2] > 0, "{f:?}");
        assert!(f.counts[1] <= f.counts[0]);
    }

    #[test]
    fn the_pile_sleeps_and_the_dropped_ball_wakes_it() {
        let (world, _) = run("sleep_and_wake", "", 235);
        assert_eq!(world.awake_body_count(), 0, "asleep before the ball");
        // The ball, dropped at 4 s from 10 m, lands on the pile a second later.
        let (world, _) = run("sleep_and_wake", "", 330);
        assert!(world.awake_body_count() > 1, "the ball woke the pile");
    }

    #[test]
    fn a_bullet_hits_the_thin_planks_and_a_plain_ball_tunnels_through_them() {
        let scene = crate::builtin::build("bullets").unwrap();
        let (world, _) = run("bullets", "", 30);
        let n = world.body_count();
        let moved = |k: usize| {
            let start = scene.bodies[k].position;
            let now = body(&world, k).position;
            (now - Vec2::from(start)).length()
        };
        // Bodies 5 to 8 are the bullet's row of planks, 10 to 13 the plain ball's.
        assert!(moved(5) > 0.01, "the bullet knocked the first plank");
        assert!(
            (10..14).all(|k| moved(k) < 1e-4),
            "the plain ball went through untouched"
        );
        assert!(body(&world, n - 1).position.x > 9.0);
    }
}
