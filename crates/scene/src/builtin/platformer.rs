//! The platformer: a level a person plays with the keyboard, built on the library's public
//! calls only, as a user's game would be.
//!
//! The character is Box2D v3's geometric mover (`samples/geometric_mover.cpp`): a capsule
//! that is not a body, moved by the mover calls (`World::collide_mover`,
//! [`solve_planes`], `World::cast_mover`, [`clip_vector`]) on the Quake ground and air model,
//! held above the ground by a "pogo": a ray down from its lower centre and a spring-damper
//! on its length, so it steps over what the spring can reach and stands on slopes up to
//! `MIN_GROUND_NORMAL_Y`. It pushes dynamic bodies with the impulse of a contact of infinite
//! mass, and leans on what it stands on with a small force. A kinematic "avatar" body
//! follows it, so the sensors (the coins and the flag) see it and the viewer draws it.
//!
//! The level, left to right: boxes to push by the start, a conveyor belt (tangent speed)
//! carrying crates, a 22-degree ramp, three steps, a heavy crate by a rope bridge whose
//! hinges break past a force threshold (push the crate onto it), a pit with a one-way
//! platform (the pre-solve hook) to climb out by, an elevator (a kinematic platform) up to
//! the ledge with the flag. Three coins (sensors) on the way.

use serde::{Deserialize, Serialize};
use tumble_physics::mover::{CollisionPlane, clip_vector, solve_planes};
use tumble_physics::{
    BodyDef, BodyId, BodyKind, Capsule, Event, Filter, JointDef, JointId, PartDef, QueryFilter,
    SceneDef, ShapeDef, ShapeId, Vec2, World,
};

use super::rect;
use crate::sample::{Keys, one_way_platforms, scene_shape};

/// Filter categories of the level. The ground keeps the default category (1).
pub const CHARACTER: u64 = 1 << 1;
/// The coins and the flag: sensors that only the character's avatar sets off.
pub const PICKUP: u64 = 1 << 2;
/// The one-way platform (in the pit, under the bridge, its top at 1.2 m): bodies pass it from below (the pre-solve hook), the mover's capsule
/// always passes it, and its pogo stands on it.
pub const ONE_WAY: u64 = 1 << 3;

/// Steps per second and substeps, Box2D's samples'.
pub const DT: f32 = 1.0 / 60.0;

// The mover's tuning: Box2D's geometric mover's defaults (`GeometricMover::GeometricMover`),
// with a jump of 11 m/s (Box2D: 10) so the pit's one-way platform can be climbed out of.
const JUMP_SPEED: f32 = 11.0;
const MAX_SPEED: f32 = 6.0;
const MIN_SPEED: f32 = 0.1;
const STOP_SPEED: f32 = 3.0;
const ACCELERATE: f32 = 20.0;
const AIR_STEER: f32 = 0.2;
const FRICTION: f32 = 8.0;
const GRAVITY: f32 = 30.0;
const POGO_REST_LENGTH: f32 = 0.9;
const POGO_HERTZ: f32 = 5.0;
const POGO_DAMPING_RATIO: f32 = 0.8;
const POGO_GROUND_FORCE: f32 = 50.0;
/// Steepest ground it stands on: a normal with y above this (45 degrees).
const MIN_GROUND_NORMAL_Y: f32 = 0.7;
/// The mover's capsule relative to its position (Box2D's sample's).
const CAPSULE_CENTER1: Vec2 = Vec2::new(0.0, -0.5);
const CAPSULE_CENTER2: Vec2 = Vec2::new(0.0, 0.5);
const CAPSULE_RADIUS: f32 = 0.3;

/// Where the character starts: its pogo at rest on the floor (y = 0).
pub const START: Vec2 = Vec2::new(-2.0, 1.4);
/// The floor of the bridge's bank and the bridge's deck (m).
const BANK: f32 = 2.75;
/// The ledge the flag stands on (m).
const LEDGE: f32 = 6.5;
/// The elevator's top between these heights (m), at this speed (m/s).
const ELEVATOR_LOW: f32 = BANK;
const ELEVATOR_HIGH: f32 = LEDGE;
const ELEVATOR_SPEED: f32 = 1.25;
/// Seconds the elevator waits at each end.
const ELEVATOR_DWELL: f32 = 1.0;
/// The flag's x (m): reaching it ends the level.
pub const FLAG_X: f32 = 55.0;
/// The belt's surface speed (m/s, rightwards along its top).
const BELT_SPEED: f32 = 2.0;
/// A bridge hinge breaks past this force (N): the bridge alone pulls about 130 N at rest,
/// the character crossing it adds a few hundred; the heavy crate pushed onto it breaks it.
pub const BRIDGE_BREAK_FORCE: f32 = 900.0;
const PLANKS: usize = 10;
/// The step from which the bridge's hinges can break.
const BRIDGE_SETTLED: u64 = 60;
/// How far the bridge's middle hangs below its ends (m).
const BRIDGE_SAG: f32 = 1.2;

/// The scene's bodies, by their place in the scene (each is `BodyId::scene(index)`).
#[derive(Clone, Copy, Debug)]
pub struct Layout {
    /// The static ground (many parts).
    pub ground: usize,
    /// The conveyor belt.
    pub belt: usize,
    /// The one-way platform.
    pub one_way: usize,
    /// The elevator.
    pub elevator: usize,
    /// The coins, in order along the level.
    pub coins: [usize; 3],
    /// The flag.
    pub flag: usize,
    /// The character's avatar.
    pub avatar: usize,
    /// The bridge's first plank (the others follow).
    pub first_plank: usize,
    /// The heavy crate by the bridge.
    pub heavy_crate: usize,
}

/// A part of the ground: an axis-aligned box from `x0` to `x1` whose top is at `top`,
/// reaching down to y = -1.
fn floor(x0: f32, x1: f32, top: f32) -> PartDef {
    let bottom = -1.0;
    PartDef::new(rect(0.5 * (x1 - x0), 0.5 * (top - bottom))).at(
        0.5 * (x0 + x1),
        0.5 * (top + bottom),
        0.0,
    )
}

/// Builds the level and says where its bodies are.
pub fn build() -> (SceneDef, Layout) {
    let mut scene = SceneDef::new("platformer");
    scene.dt = DT;
    scene.substeps = 4;
    scene.steps = 1800;
    scene.sleep = true;
    let ramp = PartDef::new(ShapeDef::Polygon {
        vertices: vec![[16.0, 0.0], [16.0, -1.0], [21.0, -1.0], [21.0, 2.0]],
        radius: 0.0,
    });
    let ground = scene.push(
        BodyDef::compound(vec![
            floor(-13.0, -12.0, 8.0),
            floor(-12.0, 16.0, 0.0),
            ramp,
            floor(21.0, 24.0, 2.0),
            floor(24.0, 24.75, 2.25),
            floor(24.75, 25.5, 2.5),
            // The banks stop 10 cm short of the bridge's posts, so its end planks swing free.
            floor(25.5, 27.9, BANK),
            floor(27.9, 38.1, 0.0),
            floor(38.1, 44.0, BANK),
            floor(44.0, 47.0, BANK - 0.3),
            floor(47.0, 59.0, LEDGE),
            floor(59.0, 60.0, 12.0),
        ])
        .kind(BodyKind::Static)
        .friction(0.6),
    );
    let belt = scene.push(
        BodyDef::compound(vec![PartDef::new(rect(3.0, 0.1)).tangent_speed(BELT_SPEED)])
            .kind(BodyKind::Static)
            .friction(0.8)
            .at(9.0, 0.1),
    );
    let one_way_filter = Filter {
        category: ONE_WAY,
        ..Filter::default()
    };
    let one_way = scene.push(
        BodyDef::new(rect(2.0, 0.1))
            .kind(BodyKind::Static)
            .filter(one_way_filter)
            .at(35.5, 1.1),
    );
    let elevator = scene.push(
        BodyDef::new(rect(1.3, 0.15))
            .kind(BodyKind::Kinematic)
            .at(45.5, ELEVATOR_LOW - 0.15),
    );
    let pickup = Filter {
        category: PICKUP,
        mask: CHARACTER,
        group: 0,
    };
    let coin = |x: f32, y: f32| {
        BodyDef::compound(vec![
            PartDef::new(ShapeDef::Circle { radius: 0.3 })
                .filter(pickup)
                .sensor(true),
        ])
        .kind(BodyKind::Static)
        .at(x, y)
    };
    let coins = [
        scene.push(coin(3.0, 1.6)),
        scene.push(coin(41.0, BANK + 1.6)),
        scene.push(coin(51.0, LEDGE + 1.6)),
    ];
    let flag = scene.push(
        BodyDef::compound(vec![
            PartDef::new(rect(0.3, 1.5)).filter(pickup).sensor(true),
        ])
        .kind(BodyKind::Static)
        .at(FLAG_X, LEDGE + 1.5),
    );
    // The avatar: the capsule and, below it, the pogo's reach (the legs), seen only by the
    // pickups.
    let legs = (POGO_REST_LENGTH - (CAPSULE_RADIUS)) * 0.5;
    let avatar_filter = Filter {
        category: CHARACTER,
        mask: PICKUP,
        group: 0,
    };
    let avatar = scene.push(
        BodyDef::compound(vec![
            PartDef::new(ShapeDef::Capsule {
                center1: CAPSULE_CENTER1.to_array(),
                center2: CAPSULE_CENTER2.to_array(),
                radius: CAPSULE_RADIUS,
            })
            .filter(avatar_filter),
            PartDef::new(rect(0.08, legs))
                .at(0.0, CAPSULE_CENTER1.y - CAPSULE_RADIUS - legs, 0.0)
                .filter(avatar_filter),
        ])
        .kind(BodyKind::Kinematic)
        .at(START.x, START.y),
    );
    // Boxes to push by the start, crates on the belt.
    for (x, y) in [(-9.0, 0.4), (-8.0, 0.4), (-8.5, 1.2)] {
        scene.push(BodyDef::new(rect(0.4, 0.4)).at(x, y).friction(0.6));
    }
    for x in [7.0, 8.5] {
        scene.push(BodyDef::new(rect(0.25, 0.25)).at(x, 0.45).friction(0.8));
    }
    // The bridge: planks hinged end to end from bank to bank, laid in a shallow V that sags
    // BRIDGE_SAG in the middle (a taut chain would pull without bound under its own weight).
    let first_plank = scene.bodies.len();
    let half = PLANKS as f32 / 2.0;
    let corner = |k: usize| {
        let down = (k.min(PLANKS - k) as f32) * BRIDGE_SAG / half;
        [28.0 + k as f32, BANK - 0.1 - down]
    };
    for k in 0..PLANKS {
        let ([x0, y0], [x1, y1]) = (corner(k), corner(k + 1));
        let half_length = 0.5 * ((x1 - x0).powi(2) + (y1 - y0).powi(2)).sqrt();
        scene.push(
            BodyDef::new(rect(half_length, 0.1))
                .density(5.0)
                .friction(0.8)
                // A rope bridge's ropes and boards damp its swing.
                .damping(1.0, 1.0)
                .at(0.5 * (x0 + x1), 0.5 * (y0 + y1))
                .angle((y1 - y0).atan2(x1 - x0)),
        );
    }
    // Each end hangs from a post of its own (drawn joints go from a body's centre to the
    // anchor: the ground's centre is far away).
    let post = |x: f32| {
        BodyDef::new(rect(0.1, 0.1))
            .kind(BodyKind::Static)
            .at(x, BANK - 0.1)
    };
    let (left_post, right_post) = (scene.push(post(28.0)), scene.push(post(38.0)));
    for k in 0..=PLANKS {
        let a = if k == 0 {
            left_post
        } else {
            first_plank + k - 1
        };
        let b = if k == PLANKS {
            right_post
        } else {
            first_plank + k
        };
        scene.joints.push(JointDef::hinge(
            [BodyId::scene(a), BodyId::scene(b)],
            corner(k),
        ));
    }
    // The heavy crate on the bank by the bridge (336 kg, taller than the character's legs
    // reach, so it is pushed, not climbed): jump over it to cross, or push it onto the bridge
    // to break it.
    let heavy_crate = scene.push(
        BodyDef::new(rect(0.6, 0.7))
            .density(200.0)
            .friction(0.6)
            .at(27.4, BANK + 0.7),
    );
    let layout = Layout {
        ground,
        belt,
        one_way,
        elevator,
        coins,
        flag,
        avatar,
        first_plank,
        heavy_crate,
    };
    (scene, layout)
}

/// The platformer's scene.
pub fn scene() -> SceneDef {
    build().0
}

/// A run through the level, as `--keys` and the page's `keys=` take it: right from the
/// start, a jump over the heavy crate onto the bridge, a wait on the bank for the
/// elevator, a ride up, and right to the flag (reached at step 814 of [`SCRIPT_STEPS`]).
pub const SCRIPT: &str = "0:right+,266:jump+,270:jump-,430:right-,482:right+,505:right-,725:right+";
/// Steps the scripted run takes.
pub const SCRIPT_STEPS: u64 = 900;

/// The keys the platformer uses, for the viewer to show.
pub const KEYS: &[(&str, &str)] = &[
    ("Left / A", "walk left"),
    ("Right / D", "walk right"),
    ("Space / Up / W", "jump"),
];

/// The character and the level's score: everything the level keeps between steps that the
/// world does not (a replay or a snapshot keeps it beside the world).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Platformer {
    /// The mover's position (the capsule's origin).
    pub position: Vec2,
    /// Its velocity (m/s), the pogo's apart.
    pub velocity: Vec2,
    /// The pogo spring's velocity (m/s, up).
    pub pogo_velocity: f32,
    /// Standing on ground (the pogo's ray hits ground flat enough).
    pub on_ground: bool,
    /// The pogo's ray as last cast: origin, translation, fraction of it where it hit (1 if
    /// not), for drawing.
    pub pogo: (Vec2, Vec2, f32),
    /// The planes that held the capsule in the last update (point, normal), for drawing.
    pub planes: Vec<(Vec2, Vec2)>,
    /// Coins picked up.
    pub coins: u32,
    /// The flag was reached, at this step.
    pub reached_flag: Option<u64>,
    /// Bridge hinges broken.
    pub broken_hinges: u32,
    /// The deepest the capsule was found inside anything (m, ≥ 0), over the run.
    pub deepest: f32,
}

impl Default for Platformer {
    fn default() -> Self {
        Platformer {
            position: START,
            velocity: Vec2::ZERO,
            pogo_velocity: 0.0,
            on_ground: false,
            pogo: (
                START + CAPSULE_CENTER1,
                Vec2::new(0.0, -POGO_REST_LENGTH),
                1.0,
            ),
            planes: Vec::new(),
            coins: 0,
            reached_flag: None,
            broken_hinges: 0,
            deepest: 0.0,
        }
    }
}

impl Platformer {
    fn layout() -> Layout {
        static LAYOUT: std::sync::LazyLock<Layout> = std::sync::LazyLock::new(|| build().1);
        *LAYOUT
    }

    /// The capsule at `position`.
    fn capsule(position: Vec2) -> Capsule {
        Capsule {
            center1: position + CAPSULE_CENTER1,
            center2: position + CAPSULE_CENTER2,
            radius: CAPSULE_RADIUS,
        }
    }

    /// What the capsule collides with: not itself, no pickups, not the one-way platform.
    fn capsule_filter() -> QueryFilter {
        QueryFilter {
            category: CHARACTER,
            mask: !(CHARACTER | PICKUP | ONE_WAY),
            sensors: false,
            exclude_body: Some(BodyId::scene(Self::layout().avatar)),
        }
    }

    /// What the pogo stands on: the one-way platform too (a ray from inside or below it does
    /// not hit its top).
    fn pogo_filter() -> QueryFilter {
        QueryFilter {
            mask: !(CHARACTER | PICKUP),
            ..Self::capsule_filter()
        }
    }

    /// Sets the world's hooks (they are not part of a snapshot): the one-way platform lets a
    /// body through unless the contact pushes it up.
    pub fn install(world: &mut World) {
        if let Some(deck) = scene_shape(world, Self::layout().one_way) {
            world.set_pre_solve(Some(one_way_platforms(vec![deck])));
        }
    }

    /// Before step `step`: moves the elevator and the character by the keys held.
    pub fn before_step(&mut self, step: u64, keys: Keys, world: &mut World) {
        let layout = Self::layout();
        // The elevator waits a second at the bottom, rises, waits a second at the top and
        // comes down, at a constant speed, by the clock.
        let travel = ((ELEVATOR_HIGH - ELEVATOR_LOW) / ELEVATOR_SPEED / DT).round() as u64;
        let dwell = (ELEVATOR_DWELL / DT).round() as u64;
        let phase = step % (2 * (travel + dwell));
        let speed = if phase < dwell {
            0.0
        } else if phase < dwell + travel {
            ELEVATOR_SPEED
        } else if phase < 2 * dwell + travel {
            0.0
        } else {
            -ELEVATOR_SPEED
        };
        if step == BRIDGE_SETTLED {
            // The hinges pull up to several times their resting force while the bridge
            // settles from its V; its threshold applies from then on.
            let hinges: Vec<JointId> = world
                .joint_ids()
                .filter(|&j| Self::is_bridge_hinge(world, j))
                .collect();
            for joint in hinges {
                let _ = world.set_joint_thresholds(joint, BRIDGE_BREAK_FORCE, f32::INFINITY);
            }
        }
        let elevator = BodyId::scene(layout.elevator);
        let _ = world.set_velocity(elevator, Vec2::new(0.0, speed), 0.0);

        if keys.contains(Keys::JUMP) && self.on_ground {
            self.velocity.y = JUMP_SPEED;
            self.on_ground = false;
        }
        let mut throttle = 0.0;
        if keys.contains(Keys::LEFT) {
            throttle -= 1.0;
        }
        if keys.contains(Keys::RIGHT) {
            throttle += 1.0;
        }
        self.update(world, throttle);
        let avatar = BodyId::scene(layout.avatar);
        let _ = world.set_transform(avatar, self.position, 0.0);
    }

    /// Box2D's `GeometricMover::Update`: the Quake ground and air model
    /// (`QW/client/pmove.c`), the pogo, then up to five rounds of collide, solve planes, cast.
    fn update(&mut self, world: &mut World, throttle: f32) {
        let dt = DT;
        // Friction.
        let speed = self.velocity.length();
        if speed < MIN_SPEED {
            self.velocity = Vec2::ZERO;
        } else if self.on_ground {
            let control = speed.max(STOP_SPEED);
            let drop = control * FRICTION * dt;
            let new_speed = (speed - drop).max(0.0);
            self.velocity *= new_speed / speed;
        }
        // Accelerate towards the throttle's speed.
        let desired = Vec2::new(MAX_SPEED * throttle, 0.0);
        let desired_speed = desired.length().min(MAX_SPEED);
        let direction = desired.normalize_or_zero();
        let add = desired_speed - self.velocity.dot(direction);
        if add > 0.0 {
            let steer = if self.on_ground { 1.0 } else { AIR_STEER };
            let accel = (steer * ACCELERATE * MAX_SPEED * dt).min(add);
            self.velocity += accel * direction;
        }

        // The pogo reaches past its rest length while standing, so the spring can stretch.
        let ray_length = if self.on_ground {
            2.0 * POGO_REST_LENGTH
        } else {
            POGO_REST_LENGTH
        };
        let origin = self.position + CAPSULE_CENTER1;
        let translation = Vec2::new(0.0, -ray_length);
        let hit = world.cast_ray_closest(origin, translation, &Self::pogo_filter());
        self.pogo = (origin, translation, hit.map_or(1.0, |h| h.fraction));
        // No snapping to the ground while still going up.
        let ground = hit.filter(|h| h.normal.y > MIN_GROUND_NORMAL_Y);
        self.on_ground = if self.on_ground {
            ground.is_some()
        } else {
            ground.is_some() && self.velocity.y <= 0.01
        };
        let mut carried = Vec2::ZERO;
        match ground {
            Some(h) if self.on_ground => {
                self.velocity.y = 0.0;
                let offset = h.fraction * ray_length - POGO_REST_LENGTH;
                self.pogo_velocity = spring_damper(
                    POGO_HERTZ,
                    POGO_DAMPING_RATIO,
                    offset,
                    self.pogo_velocity,
                    dt,
                );
                let _ = world.apply_force(
                    h.shape.body,
                    Vec2::new(0.0, -POGO_GROUND_FORCE),
                    h.point,
                    true,
                );
                carried = ground_velocity(world, h.shape.body, h.shape.shape, h.point, h.normal);
            }
            _ => {
                self.velocity.y -= GRAVITY * dt;
                self.pogo_velocity = 0.0;
            }
        }

        let target =
            self.position + dt * (self.velocity + carried) + dt * self.pogo_velocity * Vec2::Y;
        let tolerance = 0.01;
        let filter = Self::capsule_filter();
        let mut planes: Vec<CollisionPlane> = Vec::new();
        let mut points: Vec<(Vec2, Vec2, BodyId)> = Vec::new();
        for _ in 0..5 {
            planes.clear();
            points.clear();
            let capsule = Self::capsule(self.position);
            for result in world.collide_mover(&capsule, &filter) {
                self.deepest = self.deepest.max(-result.plane.offset);
                planes.push(CollisionPlane::new(result.plane));
                points.push((result.point, result.plane.normal, result.shape.body));
            }
            let solved = solve_planes(target - self.position, &mut planes);
            let fraction = world.cast_mover(&capsule, solved.translation, &filter);
            let delta = fraction * solved.translation;
            self.position += delta;
            if delta.length_squared() < tolerance * tolerance {
                break;
            }
        }
        self.push_bodies(world, &points);
        // No pushing into surfaces: speed cannot build up against a wall.
        self.velocity = clip_vector(self.velocity, &planes);
        self.planes = points.iter().map(|&(p, n, _)| (p, n)).collect();
    }

    /// Box2D's `GeometricMover::PushBodies`: for each dynamic body the capsule touches, the
    /// normal impulse of a contact with an infinitely heavy mover, pushing only.
    fn push_bodies(&self, world: &mut World, points: &[(Vec2, Vec2, BodyId)]) {
        for &(point, plane_normal, body) in points {
            let Ok(view) = world.body(body) else {
                continue;
            };
            if view.kind != BodyKind::Dynamic {
                continue;
            }
            // Plane normals point at the mover; the push points into the body.
            let normal = -plane_normal;
            let mass = world.mass(body).unwrap_or(0.0);
            let inertia = world.inertia(body).unwrap_or(0.0);
            let inv_mass = if mass > 0.0 { 1.0 / mass } else { 0.0 };
            let inv_inertia = if inertia > 0.0 { 1.0 / inertia } else { 0.0 };
            let r = point - view.position;
            let rn = r.perp_dot(normal);
            let k = inv_mass + inv_inertia * rn * rn;
            let normal_mass = if k > 0.0 { 1.0 / k } else { 0.0 };
            let v = view.linear_velocity + view.angular_velocity * r.perp();
            let vn = (v - self.velocity).dot(normal);
            let impulse = (-normal_mass * vn).max(0.0);
            if impulse > 0.0 {
                let _ = world.apply_linear_impulse(body, impulse * normal, point, true);
            }
        }
    }

    /// After a step: picks up (disables) the coins the avatar touched, notes the flag, and removes
    /// the bridge hinges that broke.
    pub fn after_step(&mut self, step: u64, world: &mut World) {
        let layout = Self::layout();
        let avatar = BodyId::scene(layout.avatar);
        let mut taken = Vec::new();
        let mut broken: Vec<JointId> = Vec::new();
        for event in world.events() {
            match *event {
                Event::SensorBegin { sensor, visitor } if visitor.body == avatar => {
                    if layout
                        .coins
                        .iter()
                        .any(|&c| BodyId::scene(c) == sensor.body)
                    {
                        taken.push(sensor.body);
                    } else if sensor.body == BodyId::scene(layout.flag) {
                        self.reached_flag.get_or_insert(step);
                    }
                }
                Event::JointThreshold { joint, .. } if Self::is_bridge_hinge(world, joint) => {
                    broken.push(joint);
                }
                _ => {}
            }
        }
        for body in taken {
            // Disabled, not destroyed: out of the world (no sensor, no drawing) while every
            // body keeps its place in the scene's numbering.
            if world.is_enabled(body) == Ok(true) && world.set_enabled(body, false).is_ok() {
                self.coins += 1;
            }
        }
        for joint in broken {
            if world.destroy_joint(joint).is_ok() {
                self.broken_hinges += 1;
            }
        }
    }

    /// Whether `joint` is one of the bridge's hinges (not, say, the viewer's mouse joint).
    fn is_bridge_hinge(world: &World, joint: JointId) -> bool {
        let first = Self::layout().first_plank;
        world.joint_bodies(joint).is_ok_and(|bodies| {
            bodies
                .iter()
                .any(|&b| (first..first + PLANKS).any(|k| BodyId::scene(k) == b))
        })
    }

    /// Lines for the panel: the score and the character's state.
    pub fn status(&self) -> Vec<String> {
        let mut lines = vec![
            format!("Coins: {} of 3", self.coins),
            match self.reached_flag {
                Some(step) => format!("Flag reached at step {step}"),
                None => "Flag: not yet".to_string(),
            },
            format!(
                "On ground: {}   speed {:.1} m/s",
                if self.on_ground { "yes" } else { "no" },
                self.velocity.length()
            ),
        ];
        if self.broken_hinges > 0 {
            lines.push(format!("Bridge hinges broken: {}", self.broken_hinges));
        }
        lines
    }

    /// Draws the pogo's ray and the planes that held the capsule (the avatar body is drawn
    /// with the world).
    pub fn draw(&self, draw: &mut impl tumble_physics::draw::DebugDraw) {
        use tumble_physics::draw::colors;
        let (origin, translation, fraction) = self.pogo;
        let end = origin + fraction * translation;
        let color = if self.on_ground {
            colors::FORCE
        } else {
            colors::ASLEEP
        };
        draw.draw_segment(origin, end, color);
        for &(point, normal) in &self.planes {
            draw.draw_segment(point, point + 0.5 * normal, colors::NORMAL);
        }
    }
}

/// What the ground under the character moves at, at `point`: a moving body's velocity there,
/// and a conveyor's surface speed along its top (clockwise about the shape, as
/// `World::set_tangent_speed` has it).
fn ground_velocity(world: &World, body: BodyId, shape: ShapeId, point: Vec2, normal: Vec2) -> Vec2 {
    let mut v = Vec2::ZERO;
    if let Ok(view) = world.body(body)
        && view.kind != BodyKind::Static
    {
        v = view.linear_velocity + view.angular_velocity * (point - view.position).perp();
    }
    let surface = world.tangent_speed(shape).unwrap_or(0.0);
    v + surface * Vec2::new(normal.y, -normal.x)
}

/// Box2D's `b2SpringDamper` (`include/box2d/math_functions.h`): the spring-damper's new
/// velocity after `dt`, implicit in the position term so it is stable at any stiffness.
fn spring_damper(hertz: f32, damping_ratio: f32, position: f32, velocity: f32, dt: f32) -> f32 {
    let omega = 2.0 * std::f32::consts::PI * hertz;
    let omega_h = omega * dt;
    (velocity - omega * omega_h * position)
        / (1.0 + 2.0 * damping_ratio * omega_h + omega_h * omega_h)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sample::{Controller, KeyScript, Keys, play};

    /// Plays the level with `script` on `threads` threads; the world, the character and the
    /// deepest its capsule went into anything at any step.
    fn run(script: &str, steps: u64, threads: usize) -> (World, Platformer) {
        let script = KeyScript::parse(script).unwrap();
        let (world, controller) = play(&scene(), &script, steps, threads, |_, w, _| {
            assert!(w.is_finite());
        })
        .unwrap();
        let Some(Controller::Platformer(p)) = controller else {
            panic!("the platformer has its controller");
        };
        (world, *p)
    }

    /// Plays from a character put at `at`, holding `keys` for `steps` steps.
    fn from(at: Vec2, keys: Keys, hold: u64, steps: u64) -> (World, Platformer) {
        let scene = scene();
        let mut world = World::from_scene(&scene, &tumble_physics::Limits::default()).unwrap();
        Platformer::install(&mut world);
        let mut p = Platformer {
            position: at,
            ..Platformer::default()
        };
        for step in 0..steps {
            let held = if step < hold { keys } else { Keys::NONE };
            p.before_step(step, held, &mut world);
            world.step(scene.dt, scene.substeps);
            p.after_step(step, &mut world);
        }
        (world, p)
    }

    #[test]
    fn the_scripted_run_takes_every_coin_and_reaches_the_flag_without_sinking() {
        let (world, p) = run(SCRIPT, SCRIPT_STEPS, 1);
        assert_eq!(p.coins, 3, "{p:?}");
        let reached = p.reached_flag.expect("the flag is reached");
        assert!(reached < SCRIPT_STEPS, "{reached}");
        assert_eq!(p.broken_hinges, 0, "the bridge holds the character");
        // The bound: never more than a centimetre into the ground.
        assert!(p.deepest <= 0.01, "sank {} m", p.deepest);
        // On the ledge, its pogo at rest: position = ledge + rest length + 0.5 (the centre).
        assert!(
            (p.position.y - (LEDGE + 1.4)).abs() < 0.02,
            "{:?}",
            p.position
        );
        assert!(p.position.x > FLAG_X);
        // The avatar follows the mover, exactly.
        let avatar = world.body(BodyId::scene(build().1.avatar)).unwrap();
        assert_eq!(avatar.origin, p.position);
    }

    #[test]
    fn the_scripted_run_is_bit_identical_on_any_thread_count() {
        let (w1, p1) = run(SCRIPT, 400, 1);
        for threads in [2, 4] {
            let (w, p) = run(SCRIPT, 400, threads);
            assert_eq!(w.state_hash(), w1.state_hash(), "{threads} threads");
            assert_eq!(p, p1);
        }
    }

    #[test]
    fn walking_into_the_heavy_crate_pushes_it_onto_the_bridge_which_breaks() {
        // No jump: the character pushes the 100 kg crate (it pushes as a body of infinite
        // mass would) off the bank onto the bridge.
        let (world, p) = run("0:right+", 420, 1);
        assert!(p.broken_hinges > 0, "{p:?}");
        let layout = build().1;
        let crate_ = world.body(BodyId::scene(layout.heavy_crate)).unwrap();
        assert!(
            crate_.position.x > 28.0 && crate_.position.y < BANK,
            "off the bank, into the pit: {:?}",
            crate_.position
        );
        assert!(world.joint_count() < PLANKS + 1);
    }

    #[test]
    fn from_the_pit_a_jump_goes_up_through_the_one_way_platform_and_stands_on_it() {
        // With the bridge gone (as the heavy crate leaves it), under the platform (its top
        // at 1.2 m), on the pit's floor: one jump.
        let scene = scene();
        let mut world = World::from_scene(&scene, &tumble_physics::Limits::default()).unwrap();
        Platformer::install(&mut world);
        let layout = build().1;
        for k in 0..PLANKS {
            world
                .destroy_body(BodyId::scene(layout.first_plank + k))
                .unwrap();
        }
        let mut p = Platformer {
            position: Vec2::new(35.5, 1.4),
            ..Platformer::default()
        };
        let mut highest = 0.0f32;
        for step in 0..150 {
            let keys = if step < 5 { Keys::JUMP } else { Keys::NONE };
            p.before_step(step, keys, &mut world);
            world.step(scene.dt, scene.substeps);
            p.after_step(step, &mut world);
            highest = highest.max(p.position.y);
        }
        assert!(highest > 1.2 + 1.4, "went above the platform: {highest}");
        assert!(p.on_ground, "{p:?}");
        // Standing on it: its pogo at rest, 1.4 m above its top.
        assert!(
            (p.position.y - (1.2 + 1.4)).abs() < 0.02,
            "{:?}",
            p.position
        );
        // A box dropped onto it stays on it (the pre-solve hook lets the contacts that push
        // it up act); one thrown up from below goes through.
        let dropped = world
            .create_body(&BodyDef::new(rect(0.2, 0.2)).at(36.5, 3.0))
            .unwrap();
        let thrown = world
            .create_body(
                &BodyDef::new(rect(0.2, 0.2))
                    .at(34.5, 0.2)
                    .velocity(0.0, 8.0),
            )
            .unwrap();
        let mut thrown_highest = 0.0f32;
        for _ in 0..90 {
            world.step(DT, 4);
            thrown_highest = thrown_highest.max(world.body(thrown).unwrap().position.y);
        }
        let y = world.body(dropped).unwrap().position.y;
        assert!((y - 1.4).abs() < 0.02, "{y}");
        assert!(thrown_highest > 1.5, "{thrown_highest}");
    }

    #[test]
    fn only_the_bridge_hinges_get_the_threshold_and_break() {
        // A mouse joint (the viewer's) pulling a box hard from before the bridge settles.
        let scene = scene();
        let mut world = World::from_scene(&scene, &tumble_physics::Limits::default()).unwrap();
        Platformer::install(&mut world);
        let boxed = world
            .bodies()
            .find(|(_, b)| b.kind == BodyKind::Dynamic && b.position.x < -7.0)
            .map(|(id, _)| id)
            .unwrap();
        let mouse = world
            .create_mouse_joint(boxed, Vec2::new(-8.0, 0.4), 5.0, 0.7, 1e5)
            .unwrap();
        world.set_mouse_target(mouse, Vec2::new(-8.0, 6.0)).unwrap();
        let mut p = Platformer::default();
        for step in 0..120 {
            p.before_step(step, Keys::NONE, &mut world);
            world.step(DT, 4);
            p.after_step(step, &mut world);
        }
        assert_eq!(
            world.joint_thresholds(mouse),
            Ok((f32::INFINITY, f32::INFINITY))
        );
        let hinges = world.joint_ids().filter(|&j| j != mouse).count();
        assert_eq!(hinges, PLANKS + 1);
        for j in world.joint_ids().filter(|&j| j != mouse) {
            assert_eq!(
                world.joint_thresholds(j),
                Ok((BRIDGE_BREAK_FORCE, f32::INFINITY))
            );
        }
    }

    #[test]
    fn the_belt_carries_a_character_standing_on_it_at_its_speed() {
        // On the belt (its top at 0.2 m), no key held: half a second at 2 m/s.
        let (_, p0) = from(Vec2::new(10.0, 1.6), Keys::NONE, 0, 30);
        let (_, p1) = from(Vec2::new(10.0, 1.6), Keys::NONE, 0, 60);
        let moved = p1.position.x - p0.position.x;
        assert!((moved - 0.5 * BELT_SPEED).abs() < 0.05, "{moved}");
    }

    #[test]
    fn walking_left_pushes_the_boxes_by_the_start() {
        let (world, _) = run("0:left+", 150, 1);
        // The lowest of the three boxes started at x = -8 and is pushed towards the wall.
        let moved: Vec<f32> = world
            .bodies()
            .filter(|(_, v)| {
                v.kind == BodyKind::Dynamic && v.position.x < -8.5 && v.position.y < 1.0
            })
            .map(|(_, v)| v.position.x)
            .collect();
        assert!(!moved.is_empty(), "a box was pushed left");
    }
}
