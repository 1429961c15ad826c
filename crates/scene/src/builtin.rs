//! Built-in scenes, built in code: the benchmark scenes and the hard cases.
//!
//! Where a scene comes from Box2D v3 (`shared/benchmarks.c`, `samples/sample_stacking.cpp`,
//! `samples/sample_shapes.cpp`, `samples/sample_robustness.cpp`) or Solver2D, it uses the same
//! sizes, counts, spacing, friction, density, gravity and step settings, so that figures
//! compare. Box2D runs at 60 Hz with 4 substeps in both its benchmark and its samples.
//!
//! The scenes written before bodies could have several shapes give each of Box2D's ground
//! shapes its own static body (same contacts, same hashes as before); the newer ones
//! (`compounds`, `junkyard`) put them on one body as Box2D does. tumble has no segments yet,
//! so a segment becomes a thin box whose face lies on the segment (see [`segment`]).

pub mod features;
pub mod platformer;
pub mod rain;

use std::f32::consts::PI;

use tumble_physics::joint::AngularMotor;

use crate::sample::{Category, Controller};
use tumble_physics::{BodyDef, BodyId, BodyKind, Filter, JointDef, PartDef, SceneDef, ShapeDef};

/// One built-in scene, declared once: [`BUILTINS`] is the one list of them, and every
/// public function below reads it.
struct Builtin {
    /// The name that [`build`], [`crate::load`] and every command line take.
    name: &'static str,
    /// Builds the scene (named `name`).
    build: fn() -> SceneDef,
    /// Whether the scene keeps sleeping on. Box2D's benchmark turns sleeping off in its
    /// pyramids and keeps it on in smash, compounds, junkyard, spinner, tumbler, rain and
    /// washer; the hard cases measure a scene's motion to its end, which sleeping would stop,
    /// so every built-in but those runs awake.
    sleeps: bool,
    /// What the scene does between steps ([`script`]), if anything.
    script: Option<Script>,
    /// A one- or two-sentence menu description ([`describe`]).
    description: &'static str,
    /// Where the sample browser lists it.
    category: Category,
    /// The keys it reads and what each does, shown while it runs ([`keys`]).
    keys: &'static [(&'static str, &'static str)],
    /// Makes the controller of a sample a person plays ([`controller`]).
    controller: Option<fn() -> Controller>,
}

/// Every built-in scene, in menu order: a friendly default first, then the hard cases, then
/// the big benchmarks. A new built-in is one row here.
const BUILTINS: &[Builtin] = &[
    Builtin {
        name: "falling_circles",
        category: Category::Stacking,
        keys: &[],
        controller: None,
        build: falling_circles,
        sleeps: false,
        script: None,
        description: "A 15-row box pyramid with 180 circles of mixed sizes raining onto it (300 bodies). \
            A light, lively scene: mixed circle-box contacts, bouncing and rolling.",
    },
    Builtin {
        name: "pyramid",
        category: Category::Stacking,
        keys: &[],
        controller: None,
        build: pyramid,
        sleeps: false,
        script: None,
        description: "A 20-row pyramid of 210 unit boxes on a static ground (Solver2D's Pyramid). \
            Tests that a deep stack settles and stays standing without creeping.",
    },
    Builtin {
        name: "vertical_stack",
        category: Category::Stacking,
        keys: &[],
        controller: None,
        build: vertical_stack,
        sleeps: false,
        script: None,
        description: "A single column of 15 unit boxes, friction 0.3, next to a wall (Box2D's Vertical Stack). \
            Tests stacking stability: the column must not sway, jitter or topple.",
    },
    Builtin {
        name: "card_house",
        category: Category::Stacking,
        keys: &[],
        controller: None,
        build: card_house,
        sleeps: false,
        script: None,
        description: "A five-storey house of 40 leaning cards, 0.4 m tall and 2 mm thick, friction 0.7 (Box2D's Card House). \
            Tests friction and thin shapes: the house must stand.",
    },
    Builtin {
        name: "arch",
        category: Category::Stacking,
        keys: &[],
        controller: None,
        build: arch,
        sleeps: false,
        script: None,
        description: "A free-standing arch of 17 convex blocks carrying 4 boxes, friction 0.6 (Box2D's Arch). \
            Tests friction under load and polygon contacts: the arch must hold.",
    },
    Builtin {
        name: "friction_ramp",
        category: Category::Shapes,
        keys: &[],
        controller: None,
        build: friction_ramp,
        sleeps: false,
        script: None,
        description: "Five boxes with friction 0.75, 0.5, 0.35, 0.1 and 0 slide down a zig-zag of ramps (Box2D's Friction sample). \
            Tests Coulomb friction: the grippy boxes stop, the slippery ones slide on.",
    },
    Builtin {
        name: "mass_ratio",
        category: Category::Robustness,
        keys: &[],
        controller: None,
        build: mass_ratio,
        sleeps: false,
        script: None,
        description: "Three 10-row pyramids of light boxes, each capped by a box 100, 200 and 300 times denser (Box2D's HighMassRatio1). \
            Tests the solver under high mass ratios: the pyramids must not collapse.",
    },
    Builtin {
        name: "overlap_recovery",
        category: Category::Robustness,
        keys: &[],
        controller: None,
        build: overlap_recovery,
        sleeps: false,
        script: None,
        description: "Ten boxes spawned in a pyramid overlapping each other by a quarter of their size (Box2D's Overlap Recovery). \
            Tests that deep overlap is pushed apart gently, without an explosion.",
    },
    Builtin {
        name: "confined",
        category: Category::Robustness,
        keys: &[],
        controller: None,
        build: confined,
        sleeps: false,
        script: None,
        description: "625 circles packed, overlapping, into a closed box with no gravity (Box2D's Confined). \
            Tests a jammed, pressurised crowd: it must relax and stay calm inside the walls.",
    },
    Builtin {
        name: "far_from_origin",
        category: Category::Robustness,
        keys: &[],
        controller: None,
        build: far_from_origin,
        sleeps: false,
        script: None,
        description: "A 10-box stack standing at (10000, 10000), where f32 has a millimetre of precision. \
            Tests that precision loss far from the origin does not make the stack jitter or drift.",
    },
    Builtin {
        name: "mass_ratio_columns",
        category: Category::Robustness,
        keys: &[],
        controller: None,
        build: mass_ratio_columns,
        sleeps: false,
        script: None,
        description: "Three columns of three light unit boxes, each carrying a box 10, 100 and 1000 times denser. \
            Tests mass ratios along a chain of contacts: the columns must stand without sinking or jumping.",
    },
    Builtin {
        name: "friction_incline",
        category: Category::Shapes,
        keys: &[],
        controller: None,
        build: friction_incline,
        sleeps: false,
        script: None,
        description: "Three boxes on 20-degree slopes with friction 0.30, 0.35 and 0.40 (tan 20 deg = 0.364). \
            Tests Coulomb friction near the sticking point: two slide at g (sin - mu cos), one sticks.",
    },
    Builtin {
        name: "restitution_drop",
        category: Category::Continuous,
        keys: &[],
        controller: None,
        build: restitution_drop,
        sleeps: false,
        script: None,
        description: "Three frictionless balls of restitution 0.25, 0.5 and 0.75 dropped from 5 m. \
            Tests restitution: each must bounce back to e^2 times its drop height.",
    },
    Builtin {
        name: "elastic_box",
        category: Category::Continuous,
        keys: &[],
        controller: None,
        build: elastic_box,
        sleeps: false,
        script: None,
        description: "40 frictionless, perfectly elastic circles flying about a closed box, no gravity, no damping. \
            Tests energy conservation: their kinetic energy should stay put for a minute.",
    },
    Builtin {
        name: "large_pyramid",
        category: Category::Benchmark,
        keys: &[],
        controller: None,
        build: large_pyramid,
        sleeps: false,
        script: None,
        description: "Benchmark: a 100-row pyramid of 5050 boxes (Box2D's large_pyramid). \
            Tests raw solver throughput on one huge island of contacts.",
    },
    Builtin {
        name: "pyramid_200",
        category: Category::Stacking,
        keys: &[],
        controller: None,
        build: pyramid_200,
        sleeps: false,
        script: None,
        description: "A 200-row pyramid of 20100 unit boxes, twice Box2D's large_pyramid, on stiffer contacts (60 Hz, 8 substeps). \
            Tests the solver at the edge: a very deep, very wide stack must stand.",
    },
    Builtin {
        name: "many_pyramids",
        category: Category::Benchmark,
        keys: &[],
        controller: None,
        build: many_pyramids,
        sleeps: false,
        script: None,
        description: "Benchmark: 400 small 10-row pyramids on 20 ground segments, 22000 boxes (Box2D's many_pyramids). \
            Tests throughput and parallel scaling over many independent islands.",
    },
    Builtin {
        name: "smash",
        category: Category::Benchmark,
        keys: &[],
        controller: None,
        build: smash,
        sleeps: true,
        script: None,
        description: "Benchmark: a heavy 8 m block at 40 m/s smashes into a 120 x 80 wall of 9600 small boxes that start asleep, no gravity (Box2D's smash). \
            Tests waking, broad phase churn and contact creation under a violent impact.",
    },
    Builtin {
        name: "tumbler",
        category: Category::Benchmark,
        keys: &[],
        controller: None,
        build: tumbler,
        sleeps: true,
        script: None,
        description: "Benchmark: 2025 small boxes in a 20 m box of four heavy walls that a revolute motor turns at 25 deg/s (Box2D's tumbler). \
            Tests a motor driving a heavy body of several shapes against a churning pile.",
    },
    Builtin {
        name: "compounds",
        category: Category::Benchmark,
        keys: &[],
        controller: None,
        build: compounds,
        sleeps: true,
        script: None,
        description: "Benchmark: 3000 bodies, each of two triangles, pour into a 80 m box of 281 boxes on one static body (Box2D's compounds). \
            Tests bodies of several shapes, and sleeping as the pile settles.",
    },
    Builtin {
        name: "junkyard",
        category: Category::Benchmark,
        keys: &[],
        controller: None,
        build: junkyard,
        sleeps: true,
        script: Some(junkyard_step),
        description: "Benchmark: 8000 pentagons fall into a 160 m trough and a kinematic pusher sweeps them to and fro (Box2D's junkyard). \
            Tests a kinematic body driven to a target each step, and waking.",
    },
    Builtin {
        name: "spinner",
        category: Category::Benchmark,
        keys: &[],
        controller: None,
        build: spinner,
        sleeps: true,
        script: None,
        description: "Benchmark: 6076 capsules, circles and squares in a 40 m ring (a loop chain), stirred by a 40 m rounded paddle at 5 rad/s (Box2D's spinner). \
            The paddle is dynamic, turned by a revolute motor of unbounded torque, as Box2D's. \
            Tests chains, capsules, rounded boxes and a motor under a dense, churning load.",
    },
    Builtin {
        name: "joint_grid",
        category: Category::Benchmark,
        keys: &[],
        controller: None,
        build: joint_grid,
        sleeps: false,
        script: None,
        description: "Benchmark: a 100 x 100 grid of discs joined by 19794 revolute joints, hung from 7 static discs, no contacts (Box2D's joint_grid). \
            Tests joint throughput and the stretch of a large joint network under gravity.",
    },
    Builtin {
        name: "ball_and_chain",
        category: Category::Joints,
        keys: &[],
        controller: None,
        build: ball_and_chain,
        sleeps: false,
        script: None,
        description: "A chain of 40 capsule links (1 m, density 20) hinged to a fixed point carrying a ball of radius 8 m, 670 times a link's mass (Solver2D's Ball & Chain). \
            Tests joints under a high mass ratio: a soft-step chain stretches under the ball; how much is the measure.",
    },
    Builtin {
        name: "bridge",
        category: Category::Joints,
        keys: &[],
        controller: None,
        build: bridge,
        sleeps: false,
        script: None,
        description: "A 160 m bridge of 160 planks (1 m, density 20) hinged end to end and to the ground at both ends (Solver2D's Bridge). \
            Tests a long chain of joints: the bridge should sag and settle without stretching or jitter.",
    },
    Builtin {
        name: "stretched_chain",
        category: Category::Joints,
        keys: &[],
        controller: None,
        build: stretched_chain,
        sleeps: false,
        script: None,
        description: "A chain of 40 discs whose hinges want them 1 m apart, started 2 m apart and hung from a fixed point, touching nothing (Solver2D's Stretched Chain). \
            Tests joint error recovery: the chain should pull itself together without exploding.",
    },
    Builtin {
        name: "ragdoll",
        category: Category::Joints,
        keys: &[],
        controller: None,
        build: ragdoll,
        sleeps: false,
        script: None,
        description: "A ragdoll of 11 capsule bones on revolute joints with limits and motor friction falls onto the ground (Solver2D's Ragdoll, Box2D's human). \
            Tests a tree of limited joints under impact: the limbs must keep to their limits and settle without jitter.",
    },
    Builtin {
        name: "rain",
        category: Category::Benchmark,
        keys: &[],
        controller: None,
        build: rain::scene,
        sleeps: true,
        script: Some(rain::step),
        description: "Benchmark: groups of five ragdolls (capsule bones on limited, sprung, motor-braked hinges) rain onto five rows of 501 ground boxes; every 8 steps a column of groups is made, and once 40 columns stand, the oldest is destroyed and made again (Box2D's rain). \
            Tests making and destroying bodies and joints every few steps while 11,000 bodies and 10,000 joints fall, pile up and sleep.",
    },
    Builtin {
        name: "washer",
        category: Category::Benchmark,
        keys: &[],
        controller: None,
        build: washer,
        sleeps: true,
        script: None,
        description: "Benchmark: 8100 small boxes tumble in a 36 m drum of 40 shapes, one kinematic body turning at 25 deg/s (Box2D's washer, hit events on). \
            Tests a kinematic body of many shapes stirring a dense pile, with the contacts that begin every step reported as events.",
    },
    Builtin {
        name: "platformer",
        build: platformer::scene,
        sleeps: true,
        script: None,
        description: "A level to play: walk with Left and Right (or A and D), jump with Space. Ramps, steps, a conveyor belt, boxes to push, a rope bridge whose hinges break under a heavy crate, a pit with a one-way platform, an elevator, three coins and a flag. \
            The character is Box2D's geometric mover: a capsule moved by the mover calls, standing on a spring.",
        category: Category::Character,
        keys: platformer::KEYS,
        controller: Some(platformer_controller),
    },
    Builtin {
        name: "forces",
        build: features::forces,
        sleeps: true,
        script: None,
        description: "A rocket on the floor of a closed room: Space thrusts along its axis at twice its weight, Left and Right turn it with a torque. \
            Shows apply_force_to_center and apply_torque, called between steps.",
        category: Category::Character,
        keys: features::FORCES_KEYS,
        controller: Some(forces_controller),
    },
    Builtin {
        name: "materials",
        build: features::materials,
        sleeps: false,
        script: None,
        description: "Boxes on a 25-degree ramp whose friction changes every two seconds (0, 0.3, 1), and balls on a gate whose filter opens it every three. \
            Shows set_friction and set_filter at run time: the boxes slide, stop, slide; the balls drop through.",
        category: Category::Shapes,
        keys: &[],
        controller: Some(materials_controller),
    },
    Builtin {
        name: "conveyor_belts",
        build: features::conveyor_belts,
        sleeps: false,
        script: None,
        description: "Two conveyor belts, one running right at 2 m/s and one left, under falling crates. \
            Shows a part's tangent speed: friction carries what lands on a belt at its speed.",
        category: Category::Shapes,
        keys: &[],
        controller: None,
    },
    Builtin {
        name: "rolling_resistance",
        build: features::rolling_resistance,
        sleeps: false,
        script: None,
        description: "Four balls rolled at 6 m/s along the floor with rolling resistance 0, 0.02, 0.05 and 0.1. \
            Shows rolling resistance: the first rolls on, the others stop, sooner the more they resist.",
        category: Category::Shapes,
        keys: &[],
        controller: None,
    },
    Builtin {
        name: "one_way_platforms",
        build: features::one_way_platforms,
        sleeps: false,
        script: None,
        description: "Boxes kicked up every 1.5 s through two one-way platforms, on which they land. \
            Shows the pre-solve hook: a contact pushes only when it pushes the box up.",
        category: Category::Events,
        keys: &[],
        controller: Some(one_way_platforms_controller),
    },
    Builtin {
        name: "explosions",
        build: features::explosions,
        sleeps: false,
        script: None,
        description: "A pile of 40 boxes blown apart every four seconds, or when Space is pressed. \
            Shows World::explode: an impulse on every shape within the radius, falling off beyond.",
        category: Category::Events,
        keys: features::EXPLOSION_KEYS,
        controller: Some(explosions_controller),
    },
    Builtin {
        name: "breakable_joints",
        build: features::breakable_joints,
        sleeps: false,
        script: None,
        description: "A ten-plank bridge whose hinges break past 600 N, and a 60 kg crate falling on it. \
            Shows joint force thresholds, their events, and destroying the joints that pass them.",
        category: Category::Joints,
        keys: &[],
        controller: Some(breakable_joints_controller),
    },
    Builtin {
        name: "sensors",
        build: features::sensors,
        sleeps: false,
        script: None,
        description: "Bouncing balls crossing a sensor zone; the panel lists the shapes inside it each step. \
            Shows sensor_overlaps and sensor events.",
        category: Category::Events,
        keys: &[],
        controller: Some(sensors_controller),
    },
    Builtin {
        name: "ray_casts",
        build: features::ray_casts,
        sleeps: false,
        script: None,
        description: "A ray sweeping over a pile of boxes and balls from above, every hit listed and drawn, \
            and a ball cast down onto the pile from a place that drifts across it. Shows cast_ray_all \
            (each shape the ray crosses, where and how far along) and cast_shape_closest (where the ball \
            would first land, and the normal there).",
        category: Category::Events,
        keys: &[],
        controller: Some(ray_casts_controller),
    },
    Builtin {
        name: "contact_events",
        build: features::contact_events,
        sleeps: false,
        script: None,
        description: "Boxes and balls dropped into a pile; every contact begin, end and hit above 1 m/s is counted. \
            Shows the contact events and the hit speed threshold.",
        category: Category::Events,
        keys: &[],
        controller: Some(contact_events_controller),
    },
    Builtin {
        name: "sleep_and_wake",
        build: features::sleep_and_wake,
        sleeps: true,
        script: None,
        description: "A small pyramid that falls asleep, and every four seconds a ball dropped on it that wakes it. \
            Shows islands and sleep: the panel counts the awake bodies.",
        category: Category::Stacking,
        keys: &[],
        controller: Some(sleep_and_wake_controller),
    },
    Builtin {
        name: "bullets",
        build: features::bullets,
        sleeps: false,
        script: None,
        description: "Two balls fired at 120 m/s at rows of thin standing planks: the bullet stops at the first, the plain ball passes through. \
            Shows the bullet flag: continuous collision against moving bodies.",
        category: Category::Continuous,
        keys: &[],
        controller: None,
    },
    Builtin {
        name: "joint_kinds",
        build: features::joint_kinds,
        sleeps: false,
        script: None,
        description: "Each joint kind side by side: a revolute arm driven against its limit, a prismatic slider lifted to its limit, a sprung wheel spinning, a ball on a springy rope with length limits, a plank on a soft weld, a box held by a motor joint. \
            Shows every joint's limits, motors and springs, from a scene file.",
        category: Category::Joints,
        keys: &[],
        controller: None,
    },
];

/// The forces sample's controller.
fn forces_controller() -> Controller {
    Controller::Feature(Box::new(features::Feature::new(features::Kind::Forces)))
}

/// The materials sample's controller.
fn materials_controller() -> Controller {
    Controller::Feature(Box::new(features::Feature::new(features::Kind::Materials)))
}

/// The one_way_platforms sample's controller.
fn one_way_platforms_controller() -> Controller {
    Controller::Feature(Box::new(features::Feature::new(features::Kind::OneWay)))
}

/// The explosions sample's controller.
fn explosions_controller() -> Controller {
    Controller::Feature(Box::new(features::Feature::new(features::Kind::Explosions)))
}

/// The breakable_joints sample's controller.
fn breakable_joints_controller() -> Controller {
    Controller::Feature(Box::new(features::Feature::new(
        features::Kind::BreakableJoints,
    )))
}

/// The sensors sample's controller.
fn sensors_controller() -> Controller {
    Controller::Feature(Box::new(features::Feature::new(features::Kind::Sensors)))
}

/// The ray_casts sample's controller.
fn ray_casts_controller() -> Controller {
    Controller::Feature(Box::new(features::Feature::new(features::Kind::RayCasts)))
}

/// The contact_events sample's controller.
fn contact_events_controller() -> Controller {
    Controller::Feature(Box::new(features::Feature::new(
        features::Kind::ContactEvents,
    )))
}

/// The sleep_and_wake sample's controller.
fn sleep_and_wake_controller() -> Controller {
    Controller::Feature(Box::new(features::Feature::new(
        features::Kind::SleepAndWake,
    )))
}

/// The platformer's controller, at its start.
fn platformer_controller() -> Controller {
    Controller::Platformer(Box::default())
}

/// The names of [`BUILTINS`], in its order.
const NAMES: [&str; BUILTINS.len()] = {
    let mut names = [""; BUILTINS.len()];
    let mut i = 0;
    while i < names.len() {
        names[i] = BUILTINS[i].name;
        i += 1;
    }
    names
};

/// The named built-in's row.
fn find(name: &str) -> Option<&'static Builtin> {
    BUILTINS.iter().find(|b| b.name == name)
}

/// All built-in scene names, in menu order.
pub fn names() -> &'static [&'static str] {
    &NAMES
}

/// Builds the named built-in scene, or `None` if there is no such scene.
pub fn build(name: &str) -> Option<SceneDef> {
    let builtin = find(name)?;
    let mut scene = (builtin.build)();
    if !builtin.sleeps {
        scene.sleep = false;
    }
    Some(scene)
}

/// What a built-in does between steps (Box2D's benchmark `Step*` functions): the steps taken
/// so far, and the world to change. Scenes without one return `None` from [`script`].
pub type Script = fn(u64, &mut tumble_physics::World);

/// The named built-in's per-step script, if it has one: the runner, `compare` and the viewer
/// call it before every step.
pub fn script(name: &str) -> Option<Script> {
    find(name)?.script
}

/// The per-step script of `scene` if it is a built-in as the built-in builds it, whatever its
/// source: a scene under a built-in's name with other bodies or settings gets none.
pub fn script_for(scene: &SceneDef) -> Option<Script> {
    let script = script(&scene.name)?;
    (build(&scene.name)? == *scene).then_some(script)
}

/// Where the sample browser lists the named built-in.
pub fn category(name: &str) -> Option<Category> {
    Some(find(name)?.category)
}

/// The keys the named built-in reads, with what each does (none for most).
pub fn keys(name: &str) -> &'static [(&'static str, &'static str)] {
    find(name).map_or(&[], |b| b.keys)
}

/// Makes the controller of the named built-in, if a person plays it (see
/// [`Controller::for_scene`], which also checks the scene is the built-in's).
pub fn controller(name: &str) -> Option<fn() -> Controller> {
    find(name)?.controller
}

/// A one- or two-sentence menu description of the named scene.
pub fn describe(name: &str) -> Option<&'static str> {
    Some(find(name)?.description)
}

// ---------------------------------------------------------------------------------------------
// Helpers

/// A box shape of the given half extents.
fn rect(hx: f32, hy: f32) -> ShapeDef {
    ShapeDef::Box {
        half_extents: [hx, hy],
        radius: 0.0,
    }
}

/// A circle shape.
fn circle(radius: f32) -> ShapeDef {
    ShapeDef::Circle { radius }
}

/// A static box centred at (x, y).
fn static_box(hx: f32, hy: f32, x: f32, y: f32) -> BodyDef {
    BodyDef::new(rect(hx, hy)).kind(BodyKind::Static).at(x, y)
}

/// Half thickness of the thin box that stands in for a Box2D segment. Thick enough not to
/// tunnel at the speeds these scenes reach, thin enough to leave the shelves of
/// many_pyramids 0.5 m clear of the pyramids below.
const SEGMENT_HALF_THICKNESS: f32 = 0.25;

/// A static thin box standing in for Box2D's segment from `a` to `b`: its face lies on the
/// segment and the solid is on the segment's right (clockwise) side, so bodies placed on the
/// left side touch the face exactly where they would touch the segment.
fn segment(a: [f32; 2], b: [f32; 2]) -> BodyDef {
    let d = [b[0] - a[0], b[1] - a[1]];
    let length = (d[0] * d[0] + d[1] * d[1]).sqrt();
    let half_length = 0.5 * length;
    let mid = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
    // The right-hand normal of a -> b.
    let right = [d[1] / length, -d[0] / length];
    let t = SEGMENT_HALF_THICKNESS;
    let centre = [mid[0] + right[0] * t, mid[1] + right[1] * t];
    // Axis-aligned segments become axis-aligned boxes, so that no rounding of an angle creeps in.
    let body = if d[1] == 0.0 {
        BodyDef::new(rect(half_length, t))
    } else if d[0] == 0.0 {
        BodyDef::new(rect(t, half_length))
    } else {
        BodyDef::new(rect(half_length, t)).angle(d[1].atan2(d[0]))
    };
    body.kind(BodyKind::Static).at(centre[0], centre[1])
}

/// A dynamic convex polygon body from vertices given in world coordinates (as Box2D's samples
/// give them): the body sits at the polygon's centroid and its vertices are made relative to
/// it, in counter-clockwise order.
fn world_polygon(world: &[[f64; 2]]) -> BodyDef {
    let n = world.len();
    let mut area2 = 0.0;
    let mut cx = 0.0;
    let mut cy = 0.0;
    for i in 0..n {
        let p = world[i];
        let q = world[(i + 1) % n];
        let cross = p[0] * q[1] - q[0] * p[1];
        area2 += cross;
        cx += (p[0] + q[0]) * cross;
        cy += (p[1] + q[1]) * cross;
    }
    let (cx, cy) = (cx / (3.0 * area2), cy / (3.0 * area2));
    let mut vertices: Vec<[f32; 2]> = world
        .iter()
        .map(|p| [(p[0] - cx) as f32, (p[1] - cy) as f32])
        .collect();
    if area2 < 0.0 {
        vertices.reverse();
    }
    BodyDef::new(ShapeDef::Polygon {
        vertices,
        radius: 0.0,
    })
    .at(cx as f32, cy as f32)
}

/// The pyramid of Box2D's `CreateLargePyramid` and Solver2D's `Pyramid`: `base_count` boxes of
/// half size `h` on the bottom row, rows touching, the base centred on x = 0 and resting on y = 0.
fn push_pyramid(scene: &mut SceneDef, base_count: usize, h: f32) {
    for i in 0..base_count {
        let y = (2.0 * i as f32 + 1.0) * h;
        for j in i..base_count {
            let x = (i as f32 + 1.0) * h + 2.0 * (j - i) as f32 * h - h * base_count as f32;
            scene.push(BodyDef::new(rect(h, h)).at(x, y));
        }
    }
}

/// The soak pile (`tumble-bench soak` and the soak test): `n` circles and boxes dropped in a
/// loose staggered grid into an open-topped box of static walls. They fall, pile up, slide
/// and keep touching, so contacts are created and destroyed all along; one body in seven
/// bounces. The box widens with the square root of `n` so the pile stays about as tall as it
/// is wide (2,000 bodies: 50 columns, 40 m wide).
pub fn soak_pile(n: usize) -> SceneDef {
    let mut scene = SceneDef::new("soak");
    let columns = ((n as f32 / 2000.0).sqrt() * 50.0).round().max(10.0) as usize;
    let rows = n.div_ceil(columns);
    let x0 = -19.0 * columns as f32 / 50.0;
    let half_width = -x0 + 1.5;
    let wall_half_height = (rows as f32 * 0.75).max(30.0);
    scene.push(static_box(half_width + 0.5, 0.5, 0.0, -0.5));
    scene.push(static_box(
        0.5,
        wall_half_height,
        -half_width,
        wall_half_height,
    ));
    scene.push(static_box(
        0.5,
        wall_half_height,
        half_width,
        wall_half_height,
    ));
    for i in 0..n {
        let stagger = if (i / columns).is_multiple_of(2) {
            0.0
        } else {
            0.3
        };
        let x = x0 + (i % columns) as f32 * 0.78 + stagger;
        let y = 1.0 + (i / columns) as f32 * 0.9;
        let shape = if i.is_multiple_of(3) {
            rect(0.3, 0.25)
        } else {
            circle(0.22 + 0.1 * (i % 5) as f32 / 5.0)
        };
        let restitution = if i.is_multiple_of(7) { 0.5 } else { 0.0 };
        scene.push(BodyDef::new(shape).at(x, y).restitution(restitution));
    }
    scene
}

// ---------------------------------------------------------------------------------------------
// Showcase

/// Our own default scene: a 15-row pyramid of unit boxes with 180 circles (radius 0.25 to 0.5,
/// restitution 0.3) falling on it from 18 m up, in a staggered grid.
fn falling_circles() -> SceneDef {
    let mut scene = SceneDef::new("falling_circles");
    scene.steps = 600;
    scene.push(static_box(40.0, 1.0, 0.0, -1.0));
    push_pyramid(&mut scene, 15, 0.5);
    let (columns, rows) = (12, 15);
    let spacing = 1.2;
    for row in 0..rows {
        // Stagger odd rows so the circles do not land in neat columns.
        let stagger = if row % 2 == 0 { 0.0 } else { 0.5 * spacing };
        for column in 0..columns {
            let size_class = (column * 7 + row * 3) % 5;
            let radius = 0.25 + 0.0625 * size_class as f32;
            let x =
                (column as f32 - 0.5 * (columns - 1) as f32) * spacing + stagger - 0.25 * spacing;
            let y = 18.0 + row as f32 * spacing;
            scene.push(BodyDef::new(circle(radius)).at(x, y).restitution(0.3));
        }
    }
    scene
}

// ---------------------------------------------------------------------------------------------
// Hard cases

/// Solver2D samples/collection/sample_contact.cpp `Pyramid` (debug size): 20 rows, half size
/// 0.5, density 1, friction 0.6; ground a 100 x 1 half-size static box at (0, -1).
fn pyramid() -> SceneDef {
    let mut scene = SceneDef::new("pyramid");
    scene.steps = 600;
    scene.push(static_box(100.0, 1.0, 0.0, -1.0));
    push_pyramid(&mut scene, 20, 0.5);
    scene
}

/// Box2D samples/sample_stacking.cpp `VerticalStack`: boxes of outer half size 0.5 (Box2D's
/// 0.45 box rounded by 0.05; we have no rounding) at x = 8 +/- 0.01 alternately, y = 0.5 + i,
/// density 1, friction 0.3; ground segment from x = -30 to 30 and a wall segment at x = 10
/// up to y = 20 (friction 0.6). Box2D's sample opens with 12 rows; Solver2D's has 15, as here.
fn vertical_stack() -> SceneDef {
    let mut scene = SceneDef::new("vertical_stack");
    scene.steps = 600;
    scene.push(segment([-30.0, 0.0], [30.0, 0.0]));
    // Bottom to top on the wall's left: the solid lies at x > 10.
    scene.push(segment([10.0, 0.0], [10.0, 20.0]));
    let rows = 15;
    let offset = 0.01;
    for i in 0..rows {
        let shift = if i % 2 == 0 { -offset } else { offset };
        scene.push(
            BodyDef::new(rect(0.5, 0.5))
                .at(8.0 + shift, 0.5 + i as f32)
                .friction(0.3),
        );
    }
    scene
}

/// Box2D samples/sample_stacking.cpp `CardHouse` (from PEEL): cards of half size 0.001 x 0.2,
/// friction 0.7 everywhere, leaning at +/-25 degrees with flat cards across; 5 storeys;
/// ground a 40 x 2 half-size box at (0, -2).
fn card_house() -> SceneDef {
    let mut scene = SceneDef::new("card_house");
    scene.steps = 600;
    let friction = 0.7;
    scene.push(static_box(40.0, 2.0, 0.0, -2.0).friction(friction));

    let card_height = 0.2;
    let card_thickness = 0.001;
    let lean_right = 25.0 * PI / 180.0;
    let lean_left = -25.0 * PI / 180.0;
    let flat = 0.5 * PI;
    let card = |x: f32, y: f32, angle: f32| {
        BodyDef::new(rect(card_thickness, card_height))
            .at(x, y)
            .angle(angle)
            .friction(friction)
    };

    let mut count = 5;
    let mut z0 = 0.0;
    let mut y = card_height - 0.02;
    while count > 0 {
        let mut z = z0;
        for i in 0..count {
            if i != count - 1 {
                scene.push(card(z + 0.25, y + card_height - 0.015, flat));
            }
            scene.push(card(z, y, lean_left));
            z += 0.175;
            scene.push(card(z, y, lean_right));
            z += 0.175;
        }
        y += card_height * 2.0 - 0.03;
        z0 += 0.175;
        count -= 1;
    }
    scene
}

/// Box2D samples/sample_stacking.cpp `Arch`: the inner and outer curves below, scaled by 0.25,
/// give 8 quadrilateral blocks per side and a keystone; 4 boxes of half size 2 x 0.5 are
/// stacked on the keystone; friction 0.6; ground a segment from x = -100 to 100.
fn arch() -> SceneDef {
    // Inner (PS1) and outer (PS2) curves of the right half, in Box2D's unscaled units.
    const PS1: [[f64; 2]; 9] = [
        [16.0, 0.0],
        [14.93803712795643, 5.133601056842984],
        [13.79871746027416, 10.24928069555078],
        [12.56252963284711, 15.34107019122473],
        [11.20040987372525, 20.39856541571217],
        [9.66521217819836, 25.40369899225096],
        [7.87179930638133, 30.3179337000085],
        [5.635199558196225, 35.03820717801641],
        [2.405937953536585, 39.09554102558315],
    ];
    const PS2: [[f64; 2]; 9] = [
        [24.0, 0.0],
        [22.33619528222415, 6.02299846205841],
        [20.54936888969905, 12.00964361211476],
        [18.60854610798073, 17.9470321677465],
        [16.46769273811807, 23.81367936585418],
        [14.05325025774858, 29.57079353071012],
        [11.23551045834022, 35.13775818285372],
        [7.752568160730571, 40.30450679009583],
        [3.016931552701656, 44.28891593799322],
    ];
    // Box2D scales the curves in f32; do the same so the blocks match it bit for bit.
    let scale = |p: [f64; 2]| [(0.25 * p[0] as f32) as f64, (0.25 * p[1] as f32) as f64];
    let ps1 = PS1.map(scale);
    let ps2 = PS2.map(scale);
    let mirror = |p: [f64; 2]| [-p[0], p[1]];
    let friction = 0.6;

    let mut scene = SceneDef::new("arch");
    scene.steps = 600;
    scene.push(segment([-100.0, 0.0], [100.0, 0.0]).friction(friction));
    for i in 0..8 {
        let block = [ps1[i], ps2[i], ps2[i + 1], ps1[i + 1]];
        scene.push(world_polygon(&block).friction(friction));
    }
    for i in 0..8 {
        let block = [
            mirror(ps2[i]),
            mirror(ps1[i]),
            mirror(ps1[i + 1]),
            mirror(ps2[i + 1]),
        ];
        scene.push(world_polygon(&block).friction(friction));
    }
    let keystone = [ps1[8], ps2[8], mirror(ps2[8]), mirror(ps1[8])];
    scene.push(world_polygon(&keystone).friction(friction));
    let top = ps2[8][1] as f32;
    for i in 0..4 {
        scene.push(
            BodyDef::new(rect(2.0, 0.5))
                .at(0.0, 0.5 + top + i as f32)
                .friction(friction),
        );
    }
    scene
}

/// Box2D samples/sample_shapes.cpp `Friction`: three 13 x 0.25 half-size ramps tilted by
/// -/+0.25 rad with two 0.25 x 1 stops, all static with friction 0.2, over a ground segment;
/// five unit boxes of density 25 dropped from y = 28 with friction 0.75, 0.5, 0.35, 0.1, 0.
fn friction_ramp() -> SceneDef {
    let mut scene = SceneDef::new("friction_ramp");
    scene.steps = 600;
    let ground_friction = 0.2;
    scene.push(segment([-40.0, 0.0], [40.0, 0.0]).friction(ground_friction));
    let ramp = |x: f32, y: f32, angle: f32| {
        static_box(13.0, 0.25, x, y)
            .angle(angle)
            .friction(ground_friction)
    };
    scene.push(ramp(-4.0, 22.0, -0.25));
    scene.push(static_box(0.25, 1.0, 10.5, 19.0).friction(ground_friction));
    scene.push(ramp(4.0, 14.0, 0.25));
    scene.push(static_box(0.25, 1.0, -10.5, 11.0).friction(ground_friction));
    scene.push(ramp(-4.0, 6.0, -0.25));

    let frictions = [0.75, 0.5, 0.35, 0.1, 0.0];
    for (i, friction) in frictions.into_iter().enumerate() {
        scene.push(
            BodyDef::new(rect(0.5, 0.5))
                .at(-15.0 + 4.0 * i as f32, 28.0)
                .density(25.0)
                .friction(friction),
        );
    }
    scene
}

/// Box2D samples/sample_robustness.cpp `HighMassRatio1` (also Solver2D's): three pyramids
/// with a 10-box base of half size 1, density 1, each capped by a box of density 100, 200 and
/// 300 dropped from 2 m above its place; ground a 50 x 1 half-size box at (0, -1).
fn mass_ratio() -> SceneDef {
    let mut scene = SceneDef::new("mass_ratio");
    scene.steps = 600;
    let extent = 1.0;
    scene.push(static_box(50.0, 1.0, 0.0, -1.0));
    for j in 0..3 {
        let base_count = 10;
        let offset = -20.0 * extent + 2.0 * (base_count as f32 + 1.0) * extent * j as f32;
        let mut y = extent;
        for count in (1..=base_count).rev() {
            for i in 0..count {
                let coeff = i as f32 - 0.5 * count as f32;
                let (yy, density) = if count == 1 {
                    (y + 2.0, (j as f32 + 1.0) * 100.0)
                } else {
                    (y, 1.0)
                };
                scene.push(
                    BodyDef::new(rect(extent, extent))
                        .at(2.0 * coeff * extent + offset, yy)
                        .density(density),
                );
            }
            y += 2.0 * extent;
        }
    }
    scene
}

/// Box2D samples/sample_robustness.cpp `OverlapRecovery`: a 4-box-base pyramid of half size
/// 0.5 whose spacing is shrunk by 25% so neighbours overlap by 0.25 m; ground segment from
/// x = -40 to 40. Box2D also sets the contact tuning (30 Hz, damping ratio 10, push-out
/// 3 m/s); a scene cannot, so this runs with the engine's own.
fn overlap_recovery() -> SceneDef {
    let mut scene = SceneDef::new("overlap_recovery");
    scene.steps = 600;
    scene.push(segment([-40.0, 0.0], [40.0, 0.0]));
    let base_count = 4;
    let extent = 0.5;
    let fraction = 1.0 - 0.25;
    let mut y = extent;
    for i in 0..base_count {
        let mut x = fraction * extent * (i as f32 - base_count as f32);
        for _ in i..base_count {
            scene.push(BodyDef::new(rect(extent, extent)).at(x, y));
            x += 2.0 * fraction * extent;
        }
        y += 2.0 * fraction * extent;
    }
    scene
}

/// Box2D samples/sample_stacking.cpp `Confined`: 25 x 25 circles of radius 0.5 on a 0.72 m
/// grid from (-8.75, 1.5), so neighbours overlap, inside four walls (Box2D's capsules of radius
/// 0.5 along x = +/-10.5 and y = 0, 20.5, here boxes of the same thickness). Box2D turns the
/// circles' gravity off; here the scene's gravity is zero.
fn confined() -> SceneDef {
    let mut scene = SceneDef::new("confined");
    scene.steps = 600;
    scene.gravity = [0.0, 0.0];
    let r = 0.5;
    scene.push(static_box(10.5 + r, r, 0.0, 0.0));
    scene.push(static_box(r, 10.25 + r, -10.5, 10.25));
    scene.push(static_box(r, 10.25 + r, 10.5, 10.25));
    scene.push(static_box(10.5 + r, r, 0.0, 20.5));
    let grid_count = 25;
    let spacing = 18.0 / grid_count as f32;
    for column in 0..grid_count {
        for row in 0..grid_count {
            let x = -8.75 + column as f32 * spacing;
            let y = 1.5 + row as f32 * spacing;
            scene.push(BodyDef::new(circle(0.5)).at(x, y));
        }
    }
    scene
}

/// Our own, after Solver2D's samples/collection/sample_far.cpp `FarStack`: a column of 10 unit
/// boxes on a 10 x 1 half-size static ground, all offset to (10000, 10000), where the spacing
/// of f32 values is about 1 mm.
fn far_from_origin() -> SceneDef {
    let mut scene = SceneDef::new("far_from_origin");
    scene.steps = 600;
    let (ox, oy) = (10_000.0, 10_000.0);
    scene.push(static_box(10.0, 1.0, ox, oy - 1.0));
    for i in 0..10 {
        scene.push(BodyDef::new(rect(0.5, 0.5)).at(ox, oy + 0.5 + i as f32));
    }
    scene
}

/// Our own hard case: three columns, 6 m apart, of three light unit boxes (density 1) on a
/// static ground, each capped by a unit box of density 10, 100 and 1000, so the light boxes
/// carry 10, 100 and 1000 times their own weight along a chain of contacts. Friction 0.6, the
/// boxes start exactly touching. Bodies: the ground, then each column bottom to top.
fn mass_ratio_columns() -> SceneDef {
    let mut scene = SceneDef::new("mass_ratio_columns");
    scene.steps = 600;
    scene.push(static_box(20.0, 0.5, 0.0, -0.5));
    for (column, ratio) in MASS_RATIOS.into_iter().enumerate() {
        let x = -6.0 + 6.0 * column as f32;
        for row in 0..MASS_RATIO_LIGHT_BOXES {
            scene.push(BodyDef::new(rect(0.5, 0.5)).at(x, 0.5 + row as f32));
        }
        scene.push(
            BodyDef::new(rect(0.5, 0.5))
                .at(x, 0.5 + MASS_RATIO_LIGHT_BOXES as f32)
                .density(ratio),
        );
    }
    scene
}

/// The heavy box's density in each column of `mass_ratio_columns` (the light boxes' is 1).
pub const MASS_RATIOS: [f32; 3] = [10.0, 100.0, 1000.0];
/// Light boxes under each heavy one in `mass_ratio_columns`.
pub const MASS_RATIO_LIGHT_BOXES: usize = 3;

/// Slope angle of `friction_incline` (degrees).
pub const INCLINE_DEGREES: f32 = 20.0;
/// Friction of each box of `friction_incline` and of its own slope, so the pair's mixed
/// coefficient `sqrt(a * b)` is exactly this.
pub const INCLINE_FRICTIONS: [f32; 3] = [0.30, 0.35, 0.40];

/// Our own hard case: three static slopes (30 x 1 m) at 20 degrees, one above the other 8 m
/// apart, each with a unit box resting on it 10 m up from its centre, box and slope of friction
/// 0.30, 0.35 and 0.40 around tan 20 deg = 0.364. Bodies: slope, box, slope, box, ...
/// The boxes start at rest on the face (no gap, no overlap), turned with the slope.
fn friction_incline() -> SceneDef {
    let mut scene = SceneDef::new("friction_incline");
    scene.steps = 180;
    let theta = INCLINE_DEGREES.to_radians();
    let (s, c) = theta.sin_cos();
    // Along the slope (uphill) and out of it.
    let (along, normal) = ([c, s], [-s, c]);
    for (k, mu) in INCLINE_FRICTIONS.into_iter().enumerate() {
        let centre = [0.0, -8.0 * k as f32];
        scene.push(
            BodyDef::new(rect(15.0, 0.5))
                .kind(BodyKind::Static)
                .at(centre[0], centre[1])
                .angle(theta)
                .friction(mu),
        );
        // 10 m uphill of the slope's centre, its centre 0.5 + 0.5 m out of the slope's.
        let up = 10.0;
        scene.push(
            BodyDef::new(rect(0.5, 0.5))
                .at(
                    centre[0] + up * along[0] + normal[0],
                    centre[1] + up * along[1] + normal[1],
                )
                .angle(theta)
                .friction(mu),
        );
    }
    scene
}

/// Restitution of each ball of `restitution_drop`.
pub const DROP_RESTITUTIONS: [f32; 3] = [0.25, 0.5, 0.75];
/// How far the bottom of each ball of `restitution_drop` starts above the ground (m).
pub const DROP_HEIGHT: f32 = 5.0;

/// Our own hard case: three frictionless balls of radius 0.5 and restitution 0.25, 0.5 and
/// 0.75, 3 m apart, their bottoms 5 m above a static ground of restitution 0 (pairs mix as
/// `max`), dropped from rest. Bodies: the ground, then the balls.
fn restitution_drop() -> SceneDef {
    let mut scene = SceneDef::new("restitution_drop");
    scene.steps = 180;
    scene.push(static_box(20.0, 0.5, 0.0, -0.5).friction(0.0));
    for (k, e) in DROP_RESTITUTIONS.into_iter().enumerate() {
        scene.push(
            BodyDef::new(circle(0.5))
                .at(-3.0 + 3.0 * k as f32, 0.5 + DROP_HEIGHT)
                .restitution(e)
                .friction(0.0),
        );
    }
    scene
}

/// Our own hard case: 40 circles of radius 0.3 (density 1) on a 8 x 5 grid, 1 m apart, with
/// seeded velocities of 2 to 6 m/s in every direction, inside a closed static box of 10 x 10 m
/// inside, without gravity; everything frictionless and of restitution 1, no damping. Kinetic
/// energy should stay constant. The circles are bullets: each meeting is found a step early,
/// so the speculative contact bounces them where they touch rather than after they overlap.
/// Bodies: the four walls (floor, left, right, roof), then the circles.
fn elastic_box() -> SceneDef {
    let mut scene = SceneDef::new("elastic_box");
    scene.steps = 3600;
    scene.gravity = [0.0, 0.0];
    let wall =
        |hx: f32, hy: f32, x: f32, y: f32| static_box(hx, hy, x, y).friction(0.0).restitution(1.0);
    let (half, t) = (5.0, 0.5);
    scene.push(wall(half + 2.0 * t, t, 0.0, -t));
    scene.push(wall(t, half + 2.0 * t, -half - t, half));
    scene.push(wall(t, half + 2.0 * t, half + t, half));
    scene.push(wall(half + 2.0 * t, t, 0.0, 2.0 * half + t));
    // A small seeded generator (SplitMix64), so the scene is the same everywhere.
    let mut state: u64 = 0x0065_6c61_7374_6963; // "elastic"
    let mut unit = move || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 40) as f32 / (1u64 << 24) as f32
    };
    for row in 0..5 {
        for column in 0..8 {
            let speed = 2.0 + 4.0 * unit();
            let direction = 2.0 * PI * unit();
            scene.push(
                BodyDef::new(circle(0.3))
                    .at(-3.5 + column as f32, 1.5 + 1.5 * row as f32)
                    .velocity(speed * direction.cos(), speed * direction.sin())
                    .friction(0.0)
                    .restitution(1.0)
                    .bullet(true),
            );
        }
    }
    scene
}

// ---------------------------------------------------------------------------------------------
// Benchmarks (Box2D shared/benchmarks.c, step counts from benchmark/main.c)

/// Box2D `CreateLargePyramid`: 100 rows, half size 0.5, density 1, friction 0.6; ground a
/// 100 x 1 half-size static box at (0, -1); 500 steps. Box2D disables sleep; tumble has none.
fn large_pyramid() -> SceneDef {
    let mut scene = SceneDef::new("large_pyramid");
    scene.steps = 500;
    scene.push(static_box(100.0, 1.0, 0.0, -1.0));
    push_pyramid(&mut scene, 100, 0.5);
    scene
}

/// Twice Box2D's `CreateLargePyramid`: 200 rows (20100 boxes) of half size 0.5, density 1,
/// friction 0.6, on a 150 x 1 half-size static ground at (0, -1); 500 steps. It asks for
/// stiffer contacts than the defaults: 60 Hz at 8 substeps (the hertz is clamped to an eighth
/// of the substep rate, so 60 Hz needs 8). At the defaults (4 substeps, 30 Hz) it slumps, in
/// Box2D too; at 8 substeps and 60 Hz its boxes stay within 0.18 m of their start and it
/// sags 0.76 m instead of 2.5 m (docs/accuracy/REPORT.md).
fn pyramid_200() -> SceneDef {
    let mut scene = SceneDef::new("pyramid_200");
    scene.steps = 500;
    scene.substeps = 8;
    scene.solver.contact_hertz = Some(60.0);
    scene.push(static_box(150.0, 1.0, 0.0, -1.0));
    push_pyramid(&mut scene, 200, 0.5);
    scene
}

/// Box2D `CreateManyPyramids`: a 20 x 20 grid of 10-row pyramids of half size 0.5; each row
/// of pyramids stands on a 220 m ground segment, the 20 segments 11 m apart and all parts of
/// one static body; 200 steps, sleep off.
fn many_pyramids() -> SceneDef {
    let mut scene = SceneDef::new("many_pyramids");
    scene.steps = 200;
    let base_count = 10;
    let extent = 0.5;
    let (rows, columns) = (20, 20);
    let ground_dy = 2.0 * extent * (base_count as f32 + 1.0);
    let ground_width = 2.0 * extent * columns as f32 * (base_count as f32 + 1.0);
    let ground: Vec<PartDef> = (0..rows)
        .map(|i| {
            let y = i as f32 * ground_dy;
            PartDef::new(ShapeDef::Segment {
                point1: [-0.5 * ground_width, y],
                point2: [0.5 * ground_width, y],
            })
        })
        .collect();
    scene.push(BodyDef::compound(ground).kind(BodyKind::Static));
    let base_width = 2.0 * extent * base_count as f32;
    for row in 0..rows {
        let base_y = row as f32 * ground_dy;
        for column in 0..columns {
            let centre_x =
                -0.5 * ground_width + column as f32 * (base_width + 2.0 * extent) + 2.0 * extent;
            for i in 0..base_count {
                let y = (2.0 * i as f32 + 1.0) * extent + base_y;
                for j in i..base_count {
                    let x =
                        (i as f32 + 1.0) * extent + 2.0 * (j - i) as f32 * extent + centre_x - 0.5;
                    scene.push(BodyDef::new(rect(extent, extent)).at(x, y));
                }
            }
        }
    }
    scene
}

/// Box2D `CreateSmash`: no gravity; a 4 x 4 half-size box of density 8 at (-20, 0) moving at
/// 40 m/s into a 120 x 80 grid of touching 0.2 half-size boxes starting at x = 30, centred on
/// y = 0; 300 steps. The grid starts asleep, as Box2D creates it: the block wakes what it hits.
fn smash() -> SceneDef {
    let mut scene = SceneDef::new("smash");
    scene.steps = 300;
    scene.gravity = [0.0, 0.0];
    scene.push(
        BodyDef::new(rect(4.0, 4.0))
            .at(-20.0, 0.0)
            .velocity(40.0, 0.0)
            .density(8.0),
    );
    let d = 0.4;
    let (columns, rows) = (120, 80);
    for i in 0..columns {
        for j in 0..rows {
            let x = i as f32 * d + 30.0;
            let y = (j as f32 - rows as f32 / 2.0) * d;
            scene.push(BodyDef::new(rect(0.5 * d, 0.5 * d)).at(x, y).awake(false));
        }
    }
    scene
}

/// A box of half extents `hx`, `hy` centred at (x, y) as a part of a body (Box2D's
/// `b2MakeOffsetBox`).
fn offset_box(hx: f32, hy: f32, x: f32, y: f32) -> PartDef {
    PartDef::new(rect(hx, hy)).at(x, y, 0.0)
}

/// Box2D's benchmark container, one static body of boxes: a floor of `floor` boxes from
/// x = -`half` and two walls of `wall` boxes at x = ±`half` (grid size 1 m).
fn container(half: f32, floor: usize, wall: usize) -> Vec<PartDef> {
    let mut parts = Vec::new();
    let mut x = -half;
    for _ in 0..floor {
        parts.push(offset_box(0.55, 0.5, x, 0.0));
        x += 1.0;
    }
    for side in [-half, half] {
        let mut y = 1.0;
        for _ in 0..wall {
            parts.push(offset_box(0.5, 0.55, side, y));
            y += 1.0;
        }
    }
    parts
}

/// Box2D `CreateCompounds` (its samples' barrel benchmark, compound branch): a static
/// container of 281 boxes (floor of 81, walls of 100) and a segment 80 m below, and 20 x 150 dynamic bodies of two triangles each (friction 0.5), alternating
/// 0.25 m left and right; 1000 steps, sleeping on.
fn compounds() -> SceneDef {
    let mut scene = SceneDef::new("compounds");
    scene.steps = 1000;
    let mut ground = container(40.0, 81, 100);
    ground.push(PartDef::new(ShapeDef::Segment {
        point1: [-800.0, -80.0],
        point2: [800.0, -80.0],
    }));
    scene.push(BodyDef::compound(ground).kind(BodyKind::Static));
    let tri = |points: [[f32; 2]; 3]| {
        PartDef::new(ShapeDef::Polygon {
            vertices: points.to_vec(),
            radius: 0.0,
        })
    };
    // Box2D's hulls of these points, counter-clockwise.
    let left = tri([[-1.0, 0.0], [0.5, 1.0], [0.0, 2.0]]);
    let right = tri([[1.0, 0.0], [0.0, 2.0], [-0.5, 1.0]]);
    let (columns, rows) = (20, 150);
    let (shift, extra_y) = (2.0f32, 0.25f32);
    let mut side = 0.25f32;
    let center_x = shift * columns as f32 / 2.0 - 1.0;
    let center_y = 1.15 / 2.0;
    let y_start = 5.0;
    for i in 0..columns {
        let x = i as f32 * shift - center_x;
        for j in 0..rows {
            let y = j as f32 * (shift + extra_y) + center_y + y_start;
            let body = BodyDef::compound(vec![left.clone(), right.clone()])
                .at(x + side, y)
                .friction(0.5);
            side = -side;
            scene.push(body);
        }
    }
    scene
}

/// Box2D `CreateJunkyard`: a static trough of 261 boxes (floor of 161, walls of 50),
/// 200 x 40 pentagons of radius 0.25 (Fibonacci-sphere points) from y = 15, and a kinematic
/// 4 x 8 m pusher whose target each step is x = 60 sin(0.2 t) ([`junkyard_step`]); 1000
/// steps, sleeping on. The pusher is the last body.
fn junkyard() -> SceneDef {
    let mut scene = SceneDef::new("junkyard");
    scene.steps = 1000;
    scene.push(BodyDef::compound(container(80.0, 161, 50)).kind(BodyKind::Static));
    let radius = 0.25f32;
    let phi = PI * (5.0f32.sqrt() - 1.0);
    let mut points: Vec<[f32; 2]> = (0..5)
        .map(|i| {
            let theta = phi * i as f32;
            [radius * theta.cos(), radius * theta.sin()]
        })
        .collect();
    // Box2D's hull: counter-clockwise around the centre.
    points.sort_by(|a, b| a[1].atan2(a[0]).total_cmp(&b[1].atan2(b[0])));
    let pentagon = ShapeDef::Polygon {
        vertices: points,
        radius: 0.0,
    };
    let (columns, rows) = (200, 40);
    let mut side = -0.1f32;
    for i in 0..columns {
        let x = 1.5 * (2.0 * i as f32 - columns as f32) * radius;
        for j in 0..rows {
            let y = 4.0 * j as f32 * radius + 15.0;
            // A polygon part keeps its vertices where they are: the body is at (x, y).
            scene.push(BodyDef::compound(vec![PartDef::new(pentagon.clone())]).at(x + side, y));
            side = -side;
        }
    }
    scene.push(BodyDef::compound(vec![offset_box(2.0, 4.0, 0.0, 4.0)]).kind(BodyKind::Kinematic));
    scene
}

/// The junkyard's pusher: after the trough and the 200 x 40 pentagons.
/// The junkyard's pusher: its index in the scene (the last body).
pub const JUNKYARD_PUSHER: usize = 1 + 200 * 40;

/// Box2D `StepJunkyard`: where the pusher aims before step `steps` (its target position and
/// angle), reached in one step of the returned length: x = 60 sin(0.2 t), at angle 0. The
/// one statement of the script, which tumble's script below and the peers' both follow.
pub fn junkyard_target(steps: u64) -> ([f32; 2], f32, f32) {
    let dt = 1.0 / 60.0;
    let t = dt * steps as f32;
    ([60.0 * (0.2 * t).sin(), 0.0], 0.0, dt)
}

/// Box2D `StepJunkyard` on a tumble world (see [`junkyard_target`]).
fn junkyard_step(steps: u64, world: &mut tumble_physics::World) {
    let (position, angle, dt) = junkyard_target(steps);
    // The scene's pusher, by its scene id: once it is destroyed (in the viewer) the id is
    // stale and the call refused, so no body that took its slot is driven instead.
    let pusher = tumble_physics::BodyId::scene(JUNKYARD_PUSHER);
    let _ = world.set_target_transform(pusher, position.into(), angle, dt);
}

/// Box2D `CreateTumbler`: a 45 x 45 grid of 0.125 half-size boxes, 0.4 m apart, inside a
/// 20 m drum of four 0.5 m thick walls (one dynamic body of four shapes, density 50) centred
/// at (0, 10), hinged there to the ground by a revolute motor at 25°/s with 1e8 N·m; 750
/// steps. Box2D's ground body has no shape; `anchor_body` stands in for it.
fn tumbler() -> SceneDef {
    let mut scene = SceneDef::new("tumbler");
    scene.steps = 750;
    // Box2D's ground body has no shape: see `anchor_body`.
    scene.push(anchor_body());
    let (cx, cy) = (0.0, 10.0);
    let wall =
        |hx: f32, hy: f32, x: f32, y: f32| PartDef::new(rect(hx, hy)).at(x, y, 0.0).density(50.0);
    let drum = scene.push(
        BodyDef::compound(vec![
            wall(0.5, 10.0, 10.0, 0.0),
            wall(0.5, 10.0, -10.0, 0.0),
            wall(10.0, 0.5, 0.0, 10.0),
            wall(10.0, 0.5, 0.0, -10.0),
        ])
        .at(cx, cy),
    );
    scene.joints.push(JointDef::Revolute {
        force_threshold: f32::INFINITY,
        torque_threshold: f32::INFINITY,
        bodies: [0, drum].map(BodyId::scene),
        anchor: [cx, cy],
        limit: None,
        motor: Some(AngularMotor {
            speed: 25.0f32.to_radians(),
            max_torque: 1e8,
        }),
        spring: None,
        collide_connected: false,
        anchor_b: None,
    });
    let grid_count = 45;
    let mut y = -0.2 * grid_count as f32 + 10.0;
    for _ in 0..grid_count {
        let mut x = -0.2 * grid_count as f32;
        for _ in 0..grid_count {
            scene.push(BodyDef::new(rect(0.125, 0.125)).at(x, y));
            x += 0.4;
        }
        y += 0.4;
    }
    scene
}

/// Box2D `CreateWasher` (as its benchmark runs it, the drum kinematic): a drum centred at
/// (0, 10) turning at 25°/s and drifting at (0.001, -0.002) m/s, one kinematic body of 40
/// quadrilaterals: 36 around a ring from radius 16 to 18, each spanning its 10° and a tenth
/// of that more on either side (so neighbours overlap), and 4 paddles from radius 14 to 16
/// every 90°; inside it a 90 x 90 grid of 0.1 half-size boxes 0.21 m apart from (-9.9, 0.1),
/// whose hit events Box2D turns on (tumble reports hits always); no ground; 500 steps.
fn washer() -> SceneDef {
    let mut scene = SceneDef::new("washer");
    scene.steps = 500;
    let (r0, r1, r2) = (14.0f32, 16.0f32, 18.0f32);
    // Box2D turns unit vectors by f32 rotations, one after another.
    let angle = PI / 18.0;
    let (q, qo) = (
        (angle.cos(), angle.sin()),
        ((0.1 * angle).cos(), (0.1 * angle).sin()),
    );
    let turn = |(c, s): (f32, f32), v: [f32; 2]| [c * v[0] - s * v[1], s * v[0] + c * v[1]];
    let turn_back = |(c, s): (f32, f32), v: [f32; 2]| [c * v[0] + s * v[1], -s * v[0] + c * v[1]];
    let scale = |r: f32, v: [f32; 2]| [r * v[0], r * v[1]];
    // The quadrilateral between radii `inner` and `outer` from direction `a1` to `a2` (a2 is
    // counter-clockwise of a1), counter-clockwise.
    let quad = |inner: f32, outer: f32, a1: [f32; 2], a2: [f32; 2]| {
        PartDef::new(ShapeDef::Polygon {
            vertices: vec![
                scale(inner, a1),
                scale(outer, a1),
                scale(outer, a2),
                scale(inner, a2),
            ],
            radius: 0.0,
        })
    };
    let mut parts = Vec::new();
    let mut u1 = [1.0f32, 0.0];
    for i in 0..36 {
        let u2 = if i == 35 { [1.0, 0.0] } else { turn(q, u1) };
        parts.push(quad(r1, r2, turn_back(qo, u1), turn(qo, u2)));
        if i % 9 == 0 {
            parts.push(quad(r0, r1, u1, u2));
        }
        u1 = u2;
    }
    scene.push(
        BodyDef::compound(parts)
            .kind(BodyKind::Kinematic)
            .at(0.0, 10.0)
            .velocity(0.001, -0.002)
            .spin(25.0f32.to_radians()),
    );
    let (grid_count, a) = (90, 0.1f32);
    let mut y = -1.1 * a * grid_count as f32 + 10.0;
    for _ in 0..grid_count {
        let mut x = -1.1 * a * grid_count as f32;
        for _ in 0..grid_count {
            scene.push(BodyDef::new(rect(a, a)).at(x, y));
            x += 2.1 * a;
        }
        y += 2.1 * a;
    }
    scene
}

/// Box2D `CreateJointGrid`: a 100 x 100 grid of discs (radius 0.4, density 1) 1 m apart,
/// column k at x = k, row i at y = -i, each joined to the one above and the one to its left
/// by a revolute joint halfway between them; the top discs of the 7 middle columns are
/// static; the discs' filter (category 2, mask all but 2) keeps them from touching; 500
/// steps, sleeping off. Box2D also joins the static discs to each other, six joints that
/// move nothing; a scene refuses a joint between bodies that cannot move, so they are left
/// out (19794 joints).
fn joint_grid() -> SceneDef {
    let mut scene = SceneDef::new("joint_grid");
    scene.steps = 500;
    const N: usize = 100;
    let filter = Filter {
        category: 2,
        mask: !2,
        group: 0,
    };
    for k in 0..N {
        for i in 0..N {
            let fixed = (N / 2 - 3..=N / 2 + 3).contains(&k) && i == 0;
            let kind = if fixed {
                BodyKind::Static
            } else {
                BodyKind::Dynamic
            };
            let (x, y) = (k as f32, -(i as f32));
            let body = scene.push(
                BodyDef::new(circle(0.4))
                    .kind(kind)
                    .at(x, y)
                    .density(1.0)
                    .filter(filter),
            );
            if i > 0 {
                scene.joints.push(JointDef::hinge(
                    [body - 1, body].map(BodyId::scene),
                    [x, y + 0.5],
                ));
            }
            let left_fixed = k > 0 && (N / 2 - 3..=N / 2 + 3).contains(&(k - 1)) && i == 0;
            if k > 0 && !(fixed && left_fixed) {
                scene.joints.push(JointDef::hinge(
                    [body - N, body].map(BodyId::scene),
                    [x - 0.5, y],
                ));
            }
        }
    }
    scene
}

/// A static body standing in for Box2D's ground body without shapes, which joints hang from:
/// a scene's body needs a shape, so it carries a 0.1 m disc 1 km below, where nothing reaches.
pub fn anchor_body() -> BodyDef {
    BodyDef::new(circle(0.1))
        .kind(BodyKind::Static)
        .at(0.0, -1000.0)
}

/// Solver2D's `BallAndChain`: 40 capsules (core ±0.5, radius 0.125, density 20, damping 0.1
/// linear and angular) laid horizontally at y = 20 from the pivot (0, 20), hinged end to end,
/// the last one hinged to a disc of radius 8 (density 20) beside it; 600 steps.
fn ball_and_chain() -> SceneDef {
    let mut scene = SceneDef::new("ball_and_chain");
    scene.steps = 600;
    const COUNT: usize = 40;
    let hx = 0.5f32;
    let y = COUNT as f32 * hx;
    let ground = scene.push(anchor_body());
    let mut prev = ground;
    let damped = |b: BodyDef| b.density(20.0).damping(0.1, 0.1);
    for i in 0..COUNT {
        let link = scene.push(damped(
            BodyDef::new(ShapeDef::Capsule {
                center1: [-hx, 0.0],
                center2: [hx, 0.0],
                radius: 0.125,
            })
            .at((1.0 + 2.0 * i as f32) * hx, y),
        ));
        scene.joints.push(JointDef::hinge(
            [prev, link].map(BodyId::scene),
            [2.0 * i as f32 * hx, y],
        ));
        prev = link;
    }
    let radius = 8.0;
    let ball = scene.push(damped(
        BodyDef::new(circle(radius)).at((1.0 + 2.0 * COUNT as f32) * hx + radius - hx, y),
    ));
    scene.joints.push(JointDef::hinge(
        [prev, ball].map(BodyId::scene),
        [2.0 * COUNT as f32 * hx, y],
    ));
    scene
}

/// Solver2D's `Bridge`: 160 planks (half extents 0.5 x 0.125, density 20, damping 0.1 linear
/// and angular) from x = -80 at y = 20, hinged end to end and to the ground at both ends;
/// 600 steps.
fn bridge() -> SceneDef {
    let mut scene = SceneDef::new("bridge");
    scene.steps = 600;
    const COUNT: usize = 160;
    let base = -80.0f32;
    let ground = scene.push(anchor_body());
    let mut prev = ground;
    for i in 0..COUNT {
        let plank = scene.push(
            BodyDef::new(rect(0.5, 0.125))
                .at(base + 0.5 + i as f32, 20.0)
                .density(20.0)
                .damping(0.1, 0.1),
        );
        scene.joints.push(JointDef::hinge(
            [prev, plank].map(BodyId::scene),
            [base + i as f32, 20.0],
        ));
        prev = plank;
    }
    scene.joints.push(JointDef::hinge(
        [prev, ground].map(BodyId::scene),
        [base + COUNT as f32, 20.0],
    ));
    scene
}

/// Solver2D's `StretchedChain`: 40 discs (radius 0.2, touching nothing) at x = 0, from
/// y = 38 down 2 m apart, each hinged 0.5 m above itself to 0.5 m below the one above (to the
/// fixed point (0, 39.5) for the first), so every hinge starts 1 m apart; 600 steps.
fn stretched_chain() -> SceneDef {
    let mut scene = SceneDef::new("stretched_chain");
    scene.steps = 600;
    const COUNT: usize = 40;
    let (length, base) = (1.0f32, 40.0f32);
    let ground = scene.push(anchor_body());
    let mut prev = ground;
    let mut above = [0.0, base - 0.5 * length];
    let mut y = base - 2.0 * length;
    let apart = Filter {
        category: 1,
        mask: 0,
        group: 0,
    };
    for _ in 0..COUNT {
        let disc = scene.push(BodyDef::new(circle(0.2)).at(0.0, y).filter(apart));
        scene.joints.push(JointDef::Revolute {
            force_threshold: f32::INFINITY,
            torque_threshold: f32::INFINITY,
            bodies: [prev, disc].map(BodyId::scene),
            anchor: above,
            limit: None,
            motor: None,
            spring: None,
            collide_connected: false,
            anchor_b: Some([0.0, y + 0.5 * length]),
        });
        prev = disc;
        above = [0.0, y - 0.5 * length];
        y -= 2.0 * length;
    }
    scene
}

/// One bone of Box2D's ragdoll (`shared/human.c`, `CreateHuman`) at scale 1: its parent,
/// its centre, its capsule's half core length and radius (vertical), its linear damping, the
/// share of the joint friction its hinge gets, the hinge's height and its limits (× π), and
/// whether it carries a foot.
struct Bone {
    parent: Option<usize>,
    y: f32,
    core: (f32, f32),
    radius: f32,
    damping: f32,
    friction: f32,
    pivot: f32,
    limit: [f32; 2],
    foot: bool,
}

/// Box2D's human: hip, torso, head, left leg (upper, lower), right leg, left arm (upper,
/// lower), right arm, in that order.
const BONES: [Bone; 11] = [
    Bone {
        parent: None,
        y: 0.95,
        core: (-0.02, 0.02),
        radius: 0.095,
        damping: 0.0,
        friction: 1.0,
        pivot: 0.0,
        limit: [0.0, 0.0],
        foot: false,
    },
    Bone {
        parent: Some(0),
        y: 1.2,
        core: (-0.135, 0.135),
        radius: 0.09,
        damping: 0.0,
        friction: 0.5,
        pivot: 1.0,
        limit: [-0.25, 0.0],
        foot: false,
    },
    Bone {
        parent: Some(1),
        y: 1.475,
        core: (-0.038, 0.039),
        radius: 0.075,
        damping: 0.1,
        friction: 0.25,
        pivot: 1.4,
        limit: [-0.3, 0.1],
        foot: false,
    },
    Bone {
        parent: Some(0),
        y: 0.775,
        core: (-0.125, 0.125),
        radius: 0.06,
        damping: 0.0,
        friction: 1.0,
        pivot: 0.9,
        limit: [-0.05, 0.4],
        foot: false,
    },
    Bone {
        parent: Some(3),
        y: 0.475,
        core: (-0.155, 0.125),
        radius: 0.045,
        damping: 0.0,
        friction: 0.5,
        pivot: 0.625,
        limit: [-0.5, -0.02],
        foot: true,
    },
    Bone {
        parent: Some(0),
        y: 0.775,
        core: (-0.125, 0.125),
        radius: 0.06,
        damping: 0.0,
        friction: 1.0,
        pivot: 0.9,
        limit: [-0.05, 0.4],
        foot: false,
    },
    Bone {
        parent: Some(5),
        y: 0.475,
        core: (-0.155, 0.125),
        radius: 0.045,
        damping: 0.0,
        friction: 0.5,
        pivot: 0.625,
        limit: [-0.5, -0.02],
        foot: true,
    },
    Bone {
        parent: Some(1),
        y: 1.225,
        core: (-0.125, 0.125),
        radius: 0.035,
        damping: 0.0,
        friction: 0.5,
        pivot: 1.35,
        limit: [-0.1, 0.8],
        foot: false,
    },
    Bone {
        parent: Some(7),
        y: 0.975,
        core: (-0.125, 0.125),
        radius: 0.03,
        damping: 0.1,
        friction: 0.1,
        pivot: 1.1,
        limit: [-0.2, 0.3],
        foot: false,
    },
    Bone {
        parent: Some(1),
        y: 1.225,
        core: (-0.125, 0.125),
        radius: 0.035,
        damping: 0.0,
        friction: 0.5,
        pivot: 1.35,
        limit: [-0.1, 0.8],
        foot: false,
    },
    Bone {
        parent: Some(9),
        y: 0.975,
        core: (-0.125, 0.125),
        radius: 0.03,
        damping: 0.1,
        friction: 0.1,
        pivot: 1.1,
        limit: [-0.2, 0.3],
        foot: false,
    },
];

/// Adds Box2D's human at `at` (its feet's level) to `scene`: capsule bones (friction 0.2,
/// filter group −`group` so one human's bones never touch, category 2, mask 1 | 2), feet of
/// a rounded quadrilateral that touch only the ground (category 2, mask 1, friction 0.05),
/// each bone hinged to its parent with its limits and motor friction (a motor at 0 rad/s of
/// `friction_torque` × the bone's share) and, with `hertz` > 0, a spring.
fn human(
    scene: &mut SceneDef,
    at: [f32; 2],
    friction_torque: f32,
    hertz: f32,
    damping_ratio: f32,
    group: i64,
) {
    use tumble_physics::joint::Spring;
    let body_filter = Filter {
        category: 2,
        mask: 1 | 2,
        group: -group,
    };
    let foot_filter = Filter {
        category: 2,
        mask: 1,
        group: -group,
    };
    let first = scene.bodies.len();
    for bone in &BONES {
        let mut capsule = PartDef::new(ShapeDef::Capsule {
            center1: [0.0, bone.core.0],
            center2: [0.0, bone.core.1],
            radius: bone.radius,
        });
        capsule.friction = Some(0.2);
        capsule.filter = Some(body_filter);
        let mut parts = vec![capsule];
        if bone.foot {
            let mut foot = PartDef::new(ShapeDef::Polygon {
                vertices: vec![
                    [-0.03, -0.185],
                    [0.11, -0.185],
                    [0.11, -0.16],
                    [-0.03, -0.14],
                ],
                radius: 0.015,
            });
            foot.friction = Some(0.05);
            foot.filter = Some(foot_filter);
            parts.push(foot);
        }
        let index = scene.push(
            BodyDef::compound(parts)
                .at(at[0], at[1] + bone.y)
                .damping(bone.damping, 0.0)
                .filter(body_filter),
        );
        if let Some(parent) = bone.parent {
            scene.joints.push(JointDef::Revolute {
                force_threshold: f32::INFINITY,
                torque_threshold: f32::INFINITY,
                bodies: [first + parent, index].map(BodyId::scene),
                anchor: [at[0], at[1] + bone.pivot],
                limit: Some([bone.limit[0] * PI, bone.limit[1] * PI]),
                motor: Some(AngularMotor {
                    speed: 0.0,
                    max_torque: bone.friction * friction_torque,
                }),
                spring: (hertz > 0.0).then_some(Spring {
                    hertz,
                    damping_ratio,
                }),
                collide_connected: false,
                anchor_b: None,
            });
        }
    }
}

/// Solver2D's `Ragdoll`: a 40 × 2 m ground box with its top at 0, and Box2D's human
/// (`human`) standing at (0, 4) with Solver2D's joint friction of 0.025 N·m and no springs;
/// 300 steps.
fn ragdoll() -> SceneDef {
    let mut scene = SceneDef::new("ragdoll");
    scene.steps = 300;
    scene.push(static_box(20.0, 1.0, 0.0, -1.0));
    human(&mut scene, [0.0, 4.0], 0.025, 0.0, 0.0, 1);
    scene
}

/// Box2D `CreateSpinner`: a loop chain of 360 points, a circle of radius 40 centred at
/// (0, 32), walked clockwise so it keeps things inside (friction 0.1); a paddle, a box of half
/// extents 0.4 x 20 rounded by 0.2 (friction 0), spinning at 5 rad/s about (0, 12); and 6076
/// bodies in rows from (-23, 2), 0.5 m apart, in turn a capsule (core ±0.25, radius 0.25), a
/// circle of radius 0.35 and a square of half size 0.35 (density 0.25, friction 0.1,
/// restitution 0.1); 500 steps. The paddle is dynamic (density 1, never sleeping), turned
/// by a revolute motor at 5 rad/s of unbounded torque about its centre.
fn spinner() -> SceneDef {
    let mut scene = SceneDef::new("spinner");
    scene.steps = 500;
    const POINTS: usize = 360;
    // Box2D rotates one point by -2π/360 at a time, in f32.
    let step = -2.0 * std::f64::consts::PI / POINTS as f64;
    let (c, s) = (step.cos() as f32, step.sin() as f32);
    let mut p = [40.0f32, 0.0];
    let mut points = Vec::with_capacity(POINTS);
    for _ in 0..POINTS {
        points.push([p[0], p[1] + 32.0]);
        p = [c * p[0] - s * p[1], s * p[0] + c * p[1]];
    }
    let mut ring = PartDef::new(ShapeDef::Chain {
        points,
        looped: true,
    });
    ring.friction = Some(0.1);
    scene.push(BodyDef::compound(vec![ring]).kind(BodyKind::Static));
    let mut paddle = BodyDef::new(ShapeDef::Box {
        half_extents: [0.4, 20.0],
        radius: 0.2,
    })
    .at(0.0, 12.0)
    .friction(0.0);
    paddle.enable_sleep = false;
    let paddle = scene.push(paddle);
    scene.joints.push(JointDef::Revolute {
        force_threshold: f32::INFINITY,
        torque_threshold: f32::INFINITY,
        bodies: [0, paddle].map(BodyId::scene),
        anchor: [0.0, 12.0],
        limit: None,
        motor: Some(AngularMotor {
            speed: 5.0,
            max_torque: f32::MAX,
        }),
        spring: None,
        collide_connected: false,
        anchor_b: None,
    });
    let capsule = ShapeDef::Capsule {
        center1: [-0.25, 0.0],
        center2: [0.25, 0.0],
        radius: 0.25,
    };
    let (mut x, mut y) = (-23.0f32, 2.0f32);
    for i in 0..2 * 3038 {
        let shape = match i % 3 {
            0 => capsule.clone(),
            1 => circle(0.35),
            _ => rect(0.35, 0.35),
        };
        scene.push(
            BodyDef::new(shape)
                .at(x, y)
                .density(0.25)
                .friction(0.1)
                .restitution(0.1),
        );
        x += 0.5;
        if x >= 23.0 {
            x = -23.0;
            y += 0.5;
        }
    }
    scene
}

#[cfg(test)]
mod tests {
    use super::*;
    use tumble_physics::Limits;

    fn count(scene: &SceneDef, kind: BodyKind) -> usize {
        scene.bodies.iter().filter(|b| b.kind == kind).count()
    }

    #[test]
    fn every_name_builds_describes_and_validates() {
        assert_eq!(names().len(), 43);
        for &name in names() {
            let scene = build(name).unwrap_or_else(|| panic!("{name} does not build"));
            assert_eq!(scene.name, name);
            assert!(describe(name).is_some(), "{name} has no description");
            assert!(!scene.bodies.is_empty(), "{name} is empty");
            // What moves is the scene's, or what its script makes before the first step
            // (rain's ragdolls).
            let mut moving = count(&scene, BodyKind::Dynamic);
            if let Some(script) = script(name) {
                let mut world = tumble_physics::World::from_scene(&scene, &Limits::default())
                    .unwrap_or_else(|e| panic!("{name}: {e}"));
                script(0, &mut world);
                moving = world
                    .body_ids()
                    .filter(|&id| world.body(id).unwrap().kind == BodyKind::Dynamic)
                    .count();
            }
            assert!(moving > 0, "{name} has nothing moving");
            // Box2D's 4 substeps, but where a scene's file asks for stiffer contacts.
            let substeps = if name == "pyramid_200" { 8 } else { 4 };
            assert!(scene.steps > 0 && scene.substeps == substeps, "{name}");
            assert!((scene.dt - 1.0 / 60.0).abs() < 1e-9);
            if let Err(e) = scene.validate(&Limits::default()) {
                panic!("{name} does not validate: {e}");
            }
        }
        assert!(build("no_such_scene").is_none());
        assert!(describe("no_such_scene").is_none());
    }

    #[test]
    fn names_are_unique() {
        let mut sorted = names().to_vec();
        sorted.sort_unstable();
        sorted.dedup();
        assert_eq!(sorted.len(), names().len());
    }

    #[test]
    fn every_row_is_what_the_public_functions_give() {
        assert_eq!(names().len(), BUILTINS.len());
        for (b, &name) in BUILTINS.iter().zip(names()) {
            assert_eq!(b.name, name);
            assert_eq!(describe(name), Some(b.description));
            assert!(!b.description.is_empty(), "{name}");
            assert_eq!(script(name).is_some(), b.script.is_some(), "{name}");
            assert_eq!(category(name), Some(b.category), "{name}");
            assert_eq!(keys(name), b.keys, "{name}");
            // A sample that reads keys has a controller to read them.
            assert!(b.keys.is_empty() || controller(name).is_some(), "{name}");
            // Sleeping is on exactly where the row says so.
            assert_eq!(build(name).unwrap().sleep, b.sleeps, "{name}");
        }
        let sleeping: Vec<_> = BUILTINS
            .iter()
            .filter(|b| b.sleeps)
            .map(|b| b.name)
            .collect();
        // Box2D's benchmark keeps sleeping on in these, and a game level does; every other
        // built-in runs awake.
        assert_eq!(
            sleeping,
            [
                "smash",
                "tumbler",
                "compounds",
                "junkyard",
                "spinner",
                "rain",
                "washer",
                "platformer",
                "forces",
                "sleep_and_wake"
            ]
        );
        let scripted: Vec<_> = BUILTINS
            .iter()
            .filter(|b| b.script.is_some())
            .map(|b| b.name)
            .collect();
        assert_eq!(scripted, ["junkyard", "rain"]);
        assert!(script("no_such_scene").is_none());
    }

    #[test]
    fn body_counts_match_box2d() {
        let expect = [
            ("large_pyramid", 5050, 1),
            ("pyramid", 210, 1),
            ("many_pyramids", 22_000, 1),
            ("spinner", 6077, 1),
            ("joint_grid", 9993, 7),
            ("smash", 9601, 0),
            ("tumbler", 2026, 1),
            ("vertical_stack", 15, 2),
            ("card_house", 40, 1),
            ("arch", 21, 1),
            ("friction_ramp", 5, 6),
            ("mass_ratio", 165, 1),
            ("overlap_recovery", 10, 1),
            ("confined", 625, 4),
            ("far_from_origin", 10, 1),
            ("falling_circles", 300, 1),
            ("mass_ratio_columns", 12, 1),
            ("friction_incline", 3, 3),
            ("restitution_drop", 3, 1),
            ("elastic_box", 40, 4),
            ("pyramid_200", 20_100, 1),
        ];
        // washer: one kinematic drum, 8100 boxes, no ground.
        let washer = build("washer").unwrap();
        assert_eq!(count(&washer, BodyKind::Dynamic), 8100);
        assert_eq!(count(&washer, BodyKind::Kinematic), 1);
        assert_eq!(washer.bodies[0].parts().len(), 40);
        for (name, dynamic, fixed) in expect {
            let scene = build(name).unwrap();
            assert_eq!(count(&scene, BodyKind::Dynamic), dynamic, "{name} dynamic");
            assert_eq!(count(&scene, BodyKind::Static), fixed, "{name} static");
            let kinematic = 0;
            assert_eq!(
                count(&scene, BodyKind::Kinematic),
                kinematic,
                "{name} kinematic"
            );
            assert_eq!(
                scene.bodies.len(),
                dynamic + fixed + kinematic,
                "{name} total"
            );
        }
    }

    #[test]
    fn joint_counts_match_box2d() {
        // joint_grid: 100 columns of 99 vertical joints, 99 columns of 100 horizontal ones,
        // less the 6 between static discs.
        for (name, joints) in [
            ("joint_grid", 2 * 100 * 99 - 6),
            ("tumbler", 1),
            ("spinner", 1),
        ] {
            let scene = build(name).unwrap();
            assert_eq!(scene.joints.len(), joints, "{name}");
            scene.validate(&Limits::default()).expect(name);
        }
    }

    #[test]
    fn polygons_are_convex_ccw_and_small() {
        for &name in names() {
            for (index, body) in build(name).unwrap().bodies.iter().enumerate() {
                let Some(ShapeDef::Polygon { vertices, .. }) = &body.shape else {
                    continue;
                };
                let n = vertices.len();
                assert!((3..=8).contains(&n), "{name} body {index}: {n} vertices");
                let mut area2 = 0.0;
                for i in 0..n {
                    let (a, b, c) = (vertices[i], vertices[(i + 1) % n], vertices[(i + 2) % n]);
                    area2 += a[0] * b[1] - b[0] * a[1];
                    let turn = (b[0] - a[0]) * (c[1] - b[1]) - (b[1] - a[1]) * (c[0] - b[0]);
                    assert!(turn > 0.0, "{name} body {index}: turn at vertex {i}");
                }
                assert!(area2 > 0.0, "{name} body {index}: signed area {area2}");
                // Centred on the centroid: the body's position is its centre of mass.
                let c = centroid(vertices);
                assert!(
                    c[0].abs() < 1e-4 && c[1].abs() < 1e-4,
                    "{name} body {index}: {c:?}"
                );
            }
        }
    }

    fn centroid(v: &[[f32; 2]]) -> [f32; 2] {
        let (mut a, mut cx, mut cy) = (0.0, 0.0, 0.0);
        for i in 0..v.len() {
            let (p, q) = (v[i], v[(i + 1) % v.len()]);
            let cross = p[0] * q[1] - q[0] * p[1];
            a += cross;
            cx += (p[0] + q[0]) * cross;
            cy += (p[1] + q[1]) * cross;
        }
        [cx / (3.0 * a), cy / (3.0 * a)]
    }

    #[test]
    fn arch_keystone_meets_its_neighbours() {
        // The keystone's lower corners are the top corners of the highest blocks of each side.
        let scene = build("arch").unwrap();
        let world = |body: &BodyDef| -> Vec<[f32; 2]> {
            let Some(ShapeDef::Polygon { vertices, .. }) = &body.shape else {
                panic!("arch block is not a polygon")
            };
            vertices
                .iter()
                .map(|v| [v[0] + body.position[0], v[1] + body.position[1]])
                .collect()
        };
        let keystone = world(&scene.bodies[17]);
        for side in [8, 16] {
            let block = world(&scene.bodies[side]);
            let shared = block
                .iter()
                .filter(|c| {
                    keystone
                        .iter()
                        .any(|k| (k[0] - c[0]).abs() < 1e-4 && (k[1] - c[1]).abs() < 1e-4)
                })
                .count();
            assert_eq!(
                shared, 2,
                "block {side} {block:?} and keystone {keystone:?}"
            );
        }
    }

    #[test]
    fn segments_put_their_face_on_the_line() {
        let floor = segment([-30.0, 0.0], [30.0, 0.0]);
        assert_eq!(floor.position, [0.0, -SEGMENT_HALF_THICKNESS]);
        let wall = segment([10.0, 0.0], [10.0, 20.0]);
        assert_eq!(wall.position, [10.0 + SEGMENT_HALF_THICKNESS, 10.0]);
        assert_eq!(
            wall.shape,
            Some(ShapeDef::Box {
                half_extents: [SEGMENT_HALF_THICKNESS, 10.0],
                radius: 0.0
            })
        );
    }

    #[test]
    fn pyramid_rows_touch_and_sit_on_the_ground() {
        let scene = build("pyramid").unwrap();
        let lowest = scene.bodies[1..]
            .iter()
            .map(|b| b.position[1])
            .fold(f32::INFINITY, f32::min);
        assert_eq!(lowest, 0.5);
        let top = scene.bodies.last().unwrap();
        assert_eq!(top.position, [0.0, 19.5]);
    }
}
