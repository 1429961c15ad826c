//! The same scene in Box2D v3 (boxdd) and Rapier2D, built from the same `SceneDef` numbers that
//! tumble's `World::from_scene` reads, with tumble's step settings where the peer has them.
//!
//! The [`Peer`] trait is always compiled (the accuracy report steps tumble through it too); the
//! peers themselves only with the `peers` feature.
//!
//! What both peers share lives here: each body part's geometry in its body's frame
//! ([`part_shape`]), the scene's joints as tumble builds them, frames in each body's frame
//! and defaults filled in ([`scene_joints`]; each peer's module says how it maps them), and
//! the per-scene scripts ([`script`]) that do between steps what a built-in's
//! `tumble_scene::builtin::script` does in tumble (junkyard's pusher), through the one call
//! each peer has for it ([`Targets`]).

#[cfg(feature = "peers")]
pub mod box2d;
#[cfg(feature = "peers")]
pub mod rapier;

use anyhow::Result;

/// A peer engine's world, stepped with the scene's `dt` and substeps.
pub trait Peer {
    /// One step (what is timed).
    fn step(&mut self) -> Result<()>;
    /// Body `index` of the scene: its frame's origin and angle (x, y, angle). For a body of
    /// one shape that is its centre of mass (the scene places it so); for a body of several
    /// parts (`shapes`), the point the scene placed, as `tumble-bench run` reports it
    /// (tumble's `BodyView::origin`, Box2D's `b2Body_GetPosition`, Rapier's `translation`).
    fn pose(&mut self, index: usize) -> Result<[f32; 3]>;
    /// Body `index` of the scene: linear velocity of its centre of mass and angular velocity
    /// (vx, vy, w).
    fn velocity(&mut self, index: usize) -> Result<[f32; 3]>;
    /// The last step's time per stage in ms, under the common names of [`STAGES`] (a peer
    /// that cannot tell returns nothing).
    #[cfg_attr(not(feature = "peers"), allow(dead_code))]
    fn stages(&mut self) -> Vec<(&'static str, f64)> {
        Vec::new()
    }
    /// Bodies the engine had to stop so far because their state turned non-finite, hiding
    /// the bad numbers from the poses (tumble's NaN guard, `World::non_finite_bodies`); 0 for
    /// an engine without such a guard, whose bad numbers show in its poses.
    fn non_finite_bodies(&mut self) -> u64 {
        0
    }
}

/// Stage names comparable across engines, in step order: finding new pairs (and refitting
/// the tree), the narrow phase, preparing constraints, the substep loop (integration, warm
/// start, solve, relax, restitution), storing impulses for the next warm start, finalizing
/// bodies, events (hits, sensor overlaps). What each engine counts in each is said where it
/// reports them.
#[cfg_attr(not(feature = "peers"), allow(dead_code))]
pub const STAGES: [&str; 7] = [
    "broad phase",
    "narrow phase",
    "prepare",
    "substeps",
    "store impulses",
    "finalize",
    "events",
];

/// A peer error as an `anyhow` error (the peers' error types are not all `Send + Sync`).
#[cfg(feature = "peers")]
pub(crate) fn ok<T, E: std::fmt::Display>(r: Result<T, E>, what: &str) -> Result<T> {
    r.map_err(|e| anyhow::anyhow!("{what}: {e}"))
}

/// What a peer's script may do to its world between steps.
#[cfg(feature = "peers")]
pub trait Targets {
    /// Bodies in the world (the scene's, in order).
    fn body_count(&self) -> usize;
    /// Box2D's `b2Body_SetTargetTransform` (tumble's `World::set_target_transform`): gives
    /// body `index` the velocity that brings its frame to `position` and `angle` in one step
    /// of `dt`, and wakes it.
    fn set_target_transform(
        &mut self,
        index: usize,
        position: [f32; 2],
        angle: f32,
        dt: f32,
    ) -> Result<()>;
    /// Makes `group`'s bodies and joints (a scene of its own, its bodies numbered from 0)
    /// and remembers them under `tag` (tumble: `tumble_scene::builtin::rain::spawn`).
    fn spawn(&mut self, tag: u64, group: &tumble_physics::SceneDef) -> Result<()>;
    /// Destroys the bodies made under `tag`, with their joints.
    fn despawn(&mut self, tag: u64) -> Result<()>;
}

/// A peer's per-step script: the steps taken so far and the world. The peers' counterpart of
/// `tumble_scene::builtin::Script`.
#[cfg(feature = "peers")]
pub type Script = fn(u64, &mut dyn Targets) -> Result<()>;

/// The peers' script of the scene named `name`: the same name as the built-in whose
/// `tumble_scene::builtin::script` it mirrors, and the same calls, so that every engine runs
/// the same scene (tested against tumble's in `tests::peer_scripts_do_what_tumbles_do`). A
/// scene without one returns `None`.
#[cfg(feature = "peers")]
pub fn script(name: &str) -> Option<Script> {
    match name {
        "junkyard" => Some(junkyard),
        "rain" => Some(rain),
        _ => None,
    }
}

/// Box2D's `StepRain` (tumble's `rain::step`): every 8 steps a column of groups, one per row,
/// made; once the 40 columns are full, the oldest column's groups destroyed (all rows, then)
/// and made again, row by row.
#[cfg(feature = "peers")]
fn rain(steps: u64, world: &mut dyn Targets) -> Result<()> {
    use tumble_scene::builtin::rain;
    let Some((column, replace)) = rain::wave(steps) else {
        return Ok(());
    };
    if replace {
        for row in 0..rain::ROWS {
            world.despawn(rain::tag(row, column))?;
        }
    }
    for row in 0..rain::ROWS {
        world.spawn(rain::tag(row, column), &rain::group(row, column))?;
    }
    Ok(())
}

/// Box2D's `StepJunkyard`, as tumble's script states it (`junkyard_target`): the pusher,
/// by its index in the scene, aims for its target, reached in one step.
#[cfg(feature = "peers")]
fn junkyard(steps: u64, world: &mut dyn Targets) -> Result<()> {
    use tumble_scene::builtin::{JUNKYARD_PUSHER, junkyard_target};
    let (position, angle, dt) = junkyard_target(steps);
    if JUNKYARD_PUSHER >= world.body_count() {
        return Ok(());
    }
    world.set_target_transform(JUNKYARD_PUSHER, position, angle, dt)
}

/// A body part's geometry in its body's frame, as both peers build it.
#[cfg(feature = "peers")]
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum PartShape {
    /// A disc.
    Circle { center: [f32; 2], radius: f32 },
    /// A rectangle of these half extents, centred at `center`, turned by `angle` (Box2D's
    /// `b2MakeOffsetBox`; `b2MakeBox` when both are zero), rounded by `radius`.
    Box {
        half_extents: [f32; 2],
        center: [f32; 2],
        angle: f32,
        radius: f32,
    },
    /// A convex polygon, counter-clockwise, rounded by the radius.
    Polygon(Vec<[f32; 2]>, f32),
    /// A capsule between two centres.
    Capsule {
        center1: [f32; 2],
        center2: [f32; 2],
        radius: f32,
    },
    /// A two-sided segment.
    Segment { point1: [f32; 2], point2: [f32; 2] },
    /// A one-sided chain (Box2D's `b2ChainDef`: an open chain's end points are ghosts).
    Chain { points: Vec<[f32; 2]>, looped: bool },
}

/// A part's shape in its body's frame. A body of one shape (`part.single`) keeps tumble's
/// placement: a polygon is recentred on its centroid (the body's position is its centre of
/// mass). A part of `shapes` sits at its offset and angle, a polygon's vertices where they are
/// in the part's frame (CONTRACT.md section 5; Box2D's `b2MakePolygon` of a hull does the
/// same), so the centre of mass follows from the parts in every engine.
#[cfg(feature = "peers")]
pub(crate) fn part_shape(part: &tumble_physics::ResolvedPart<'_>) -> Result<PartShape> {
    use tumble_physics::{Rot, Shape, ShapeDef, Vec2};
    let q = Rot::from_angle(part.angle);
    let place = |v: Vec2| -> [f32; 2] {
        if part.single {
            v.into()
        } else {
            (Vec2::from(part.offset) + q.apply(v)).into()
        }
    };
    Ok(match part.shape {
        ShapeDef::Circle { radius } => PartShape::Circle {
            center: place(Vec2::ZERO),
            radius: *radius,
        },
        ShapeDef::Box {
            half_extents,
            radius,
        } => PartShape::Box {
            half_extents: *half_extents,
            center: place(Vec2::ZERO),
            angle: if part.single { 0.0 } else { part.angle },
            radius: *radius,
        },
        ShapeDef::Polygon { vertices, radius } => {
            if part.single {
                let Shape::Polygon(p) =
                    Shape::from_def(part.shape).map_err(|e| anyhow::anyhow!("bad polygon: {e}"))?
                else {
                    anyhow::bail!("a polygon that does not build as one");
                };
                PartShape::Polygon(p.points().iter().map(|v| [v.x, v.y]).collect(), *radius)
            } else {
                PartShape::Polygon(
                    vertices.iter().map(|&v| place(Vec2::from(v))).collect(),
                    *radius,
                )
            }
        }
        ShapeDef::Capsule {
            center1, center2, ..
        } => {
            // A body of one capsule is centred on its midpoint, as tumble loads it.
            let Shape::Capsule(c) =
                Shape::from_def(part.shape).map_err(|e| anyhow::anyhow!("bad capsule: {e}"))?
            else {
                anyhow::bail!("a capsule that does not build as one");
            };
            let (c1, c2) = if part.single {
                (c.center1, c.center2)
            } else {
                (Vec2::from(*center1), Vec2::from(*center2))
            };
            PartShape::Capsule {
                center1: place(c1),
                center2: place(c2),
                radius: c.radius,
            }
        }
        ShapeDef::Segment { point1, point2 } => PartShape::Segment {
            point1: place(Vec2::from(*point1)),
            point2: place(Vec2::from(*point2)),
        },
        ShapeDef::Chain { points, looped } => PartShape::Chain {
            points: points.iter().map(|&v| place(Vec2::from(v))).collect(),
            looped: *looped,
        },
    })
}

/// The settings a tumble world built from `scene` runs with (the defaults with the scene's
/// `solver` block applied): what the peers are told where they have the knob.
#[cfg(feature = "peers")]
pub(crate) fn scene_settings(
    scene: &tumble_physics::SceneDef,
) -> Result<tumble_physics::StepSettings> {
    // A world of the settings only: `from_scene` fills in the defaults and the solver block.
    let mut empty = scene.clone();
    empty.bodies.clear();
    empty.joints.clear();
    Ok(*tumble_physics::World::from_scene(&empty, &crate::scenes::limits())?.settings())
}

/// The scene's joints as tumble builds them (`JointDef::build`, checked by
/// `JointDef::validate` first): each one's frames in its two bodies' frames (the origins and
/// angles the scene gives the bodies), with the defaults filled in (a distance joint's length,
/// a wheel's 1 Hz spring, a motor joint's offsets) and the rigid rows' stiffness, `settings`'
/// `joint_hertz` and `joint_damping_ratio`. Both peers build theirs from these, so the three
/// engines start from the same numbers.
#[cfg(feature = "peers")]
pub(crate) fn scene_joints(
    scene: &tumble_physics::SceneDef,
    settings: &tumble_physics::StepSettings,
) -> Result<Vec<(tumble_physics::joint::Joint, [usize; 2])>> {
    use tumble_physics::joint::def::JointFrame;
    use tumble_physics::{BodyKind, Rot, Transform, Vec2};
    let frame = |id: tumble_physics::BodyId| {
        let body = (id.generation == 0).then(|| scene.bodies.get(id.index as usize));
        body.flatten().map(|b| JointFrame {
            frame: Transform {
                p: Vec2::from(b.position),
                q: Rot::from_angle(b.angle),
            },
            dynamic: b.kind == BodyKind::Dynamic,
        })
    };
    let mut joints = Vec::with_capacity(scene.joints.len());
    for (index, def) in scene.joints.iter().enumerate() {
        def.validate(index, &frame)
            .map_err(|e| anyhow::anyhow!("scene {:?}: {e}", scene.name))?;
        let [a, b] = def.bodies();
        let (Some(a), Some(b)) = (frame(a), frame(b)) else {
            unreachable!("validate checks the bodies");
        };
        let bodies = def.bodies().map(|id| id.index as usize);
        let joint = def.build(
            a.frame,
            b.frame,
            settings.joint_hertz,
            settings.joint_damping_ratio,
        );
        joints.push((joint, bodies));
    }
    Ok(joints)
}

/// The velocity of a body's centre of mass from the velocity the scene gives it: tumble's
/// `linear_velocity` is the centre of mass's, Box2D's `b2BodyDef::linearVelocity` the
/// origin's (`b2UpdateBodyMassData` adds `w × (centre − origin)`). This returns what to give
/// Box2D: `v − w × r`, with `r` the centre of mass's offset from the origin in the world.
#[cfg(feature = "peers")]
pub(crate) fn origin_velocity(b: &tumble_physics::BodyDef) -> [f32; 2] {
    let [vx, vy] = b.linear_velocity;
    let w = b.angular_velocity;
    if w == 0.0 || b.shape.is_some() {
        return [vx, vy];
    }
    let c = tumble_physics::BodyMass::of_def(b).center;
    let r = tumble_physics::Rot::from_angle(b.angle).apply(c);
    // w × r = (-w r.y, w r.x).
    [vx + w * r.y, vy - w * r.x]
}

#[cfg(all(test, feature = "peers"))]
mod tests {
    use super::box2d::Box2d;
    use super::rapier::Rapier;
    use super::*;
    use serde_json::json;
    use tumble_physics::{
        BodyDef, BodyId, BodyKind, Event, JointDef, Limits, PartDef, SceneDef, ShapeDef, Vec2,
        World,
    };

    /// tumble's world behind [`Targets`], to run the peers' script on it.
    struct Tumble<'a>(&'a mut World);

    impl Targets for Tumble<'_> {
        fn body_count(&self) -> usize {
            self.0.body_count()
        }
        fn set_target_transform(
            &mut self,
            index: usize,
            position: [f32; 2],
            angle: f32,
            dt: f32,
        ) -> Result<()> {
            // The peers' scripts name a scene's bodies by index (generation 0).
            let id = BodyId::scene(index);
            self.0
                .set_target_transform(id, Vec2::from(position), angle, dt)
                .map_err(|e| anyhow::anyhow!("{e}"))
        }
        fn spawn(&mut self, tag: u64, group: &SceneDef) -> Result<()> {
            tumble_scene::builtin::rain::spawn(self.0, tag, group)
                .map_err(|e| anyhow::anyhow!("{e}"))
        }
        fn despawn(&mut self, tag: u64) -> Result<()> {
            let ids: Vec<_> = self
                .0
                .body_ids()
                .filter(|&id| self.0.user_data(id).unwrap() == tag)
                .collect();
            for id in ids {
                self.0
                    .destroy_body(id)
                    .map_err(|e| anyhow::anyhow!("{e}"))?;
            }
            Ok(())
        }
    }

    #[test]
    fn peer_scripts_do_what_tumbles_do() {
        // Every built-in with a tumble script has a peer script that makes the same calls:
        // two tumble worlds, one driven by each, move every body identically.
        for &name in tumble_scene::builtin::names() {
            let Some(theirs) = tumble_scene::builtin::script(name) else {
                assert!(
                    script(name).is_none(),
                    "{name}: a peer script but no tumble one"
                );
                continue;
            };
            let ours = script(name).unwrap_or_else(|| panic!("{name}: no peer script"));
            let scene = tumble_scene::builtin::build(name).unwrap();
            let limits = Limits {
                max_bodies: 1_000_000,
                ..Limits::default()
            };
            let mut a = World::from_scene(&scene, &limits).unwrap();
            let mut b = World::from_scene(&scene, &limits).unwrap();
            // rain's waves: the first two columns, then the one that replaces column 0.
            for step in [0u64, 1, 7, 8, 100, 320, 999] {
                theirs(step, &mut a);
                ours(step, &mut Tumble(&mut b)).unwrap();
                assert_eq!(a.body_count(), b.body_count(), "{name}, step {step}");
                assert_eq!(a.joint_count(), b.joint_count(), "{name}, step {step}");
                assert!(a.bodies().eq(b.bodies()), "{name}, step {step}");
            }
        }
    }

    #[test]
    fn rain_makes_and_replaces_its_groups_in_box2d_and_rapier() {
        // Two waves (columns 0 and 1), then the wave that replaces column 0: the same bodies
        // and joints as before it, as in tumble (`peer_scripts_do_what_tumbles_do`).
        let scene = tumble_scene::builtin::build("rain").unwrap();
        let settings = scene_settings(&scene).unwrap();
        let per_wave =
            tumble_scene::builtin::rain::ROWS * tumble_scene::builtin::rain::GROUP_SIZE * 11;
        let mut b = Box2d::new(&scene, &settings, 1).unwrap();
        let mut r = Rapier::new(&scene, 1).unwrap();
        for step in [0, 8] {
            rain(step, &mut b).unwrap();
            rain(step, &mut r).unwrap();
        }
        let (b_bodies, b_joints) = b.counts().unwrap();
        let (r_bodies, r_joints) = r.counts();
        assert_eq!(b_bodies, 1 + 2 * per_wave);
        assert_eq!(r_bodies, 1 + 2 * per_wave);
        // Ten hinges a human; Rapier's hinge with a spring and a motor is two joints.
        assert_eq!(b_joints, 2 * per_wave / 11 * 10);
        assert_eq!(r_joints, 2 * b_joints);
        rain(320, &mut b).unwrap();
        rain(320, &mut r).unwrap();
        assert_eq!(b.counts().unwrap(), (b_bodies, b_joints));
        assert_eq!(r.counts(), (r_bodies, r_joints));
        // Both step what was made and destroyed (each step runs wave 0 first: more groups).
        b.step().unwrap();
        r.step().unwrap();
    }

    /// A body of two parts off its origin (an offset, turned box of density 2 and a triangle
    /// whose vertices sit away from its part's frame), placed at an angle and spinning, in a
    /// world without gravity.
    fn compound() -> SceneDef {
        let mut scene = SceneDef::new("compound");
        scene.gravity = [0.0, 0.0];
        scene.sleep = false;
        let parts = vec![
            PartDef::new(ShapeDef::Box {
                half_extents: [0.5, 0.25],
                radius: 0.0,
            })
            .at(1.0, 0.5, 0.3)
            .density(2.0),
            PartDef::new(ShapeDef::Polygon {
                vertices: vec![[-1.0, 0.0], [0.5, 1.0], [0.0, 2.0]],
                radius: 0.0,
            })
            .at(-0.5, 0.0, 0.0),
        ];
        scene.push(
            BodyDef::compound(parts)
                .at(3.0, 4.0)
                .angle(0.7)
                .velocity(1.0, -0.5)
                .spin(2.0),
        );
        scene
    }

    #[test]
    fn a_compound_body_has_the_same_mass_centre_and_motion_everywhere() {
        let scene = compound();
        let tumble = World::from_scene(&scene, &Limits::default()).unwrap();
        let settings = *tumble.settings();
        let (mass, center) = (
            tumble.mass(BodyId::scene(0)).unwrap(),
            tumble.local_center(BodyId::scene(0)).unwrap(),
        );
        // The part geometry's own numbers: a box of 0.5 m² at density 2 (1 kg) and a triangle
        // of 1 m² at density 1.
        assert!((mass - 2.0).abs() < 1e-5, "tumble mass {mass}");
        let mut box2d = Box2d::new(&scene, &settings, 1).unwrap();
        let (m, c) = box2d.mass(0).unwrap();
        assert!(
            (m - mass).abs() <= 1e-6 * mass,
            "Box2D mass {m}, tumble {mass}"
        );
        assert!(
            (Vec2::from(c) - center).length() < 1e-6,
            "Box2D centre {c:?}, tumble {center}"
        );
        let mut rapier = Rapier::new(&scene, 1).unwrap();
        let (m, c) = rapier.mass(0);
        assert!(
            (m - mass).abs() <= 1e-5 * mass,
            "Rapier mass {m}, tumble {mass}"
        );
        assert!(
            (Vec2::from(c) - center).length() < 1e-5,
            "Rapier centre {c:?}, tumble {center}"
        );
        // Both start where the scene put the frame, with the centre of mass's velocity, and
        // turn about the centre of mass: the frames' origins follow the same path.
        let mut tumble = tumble;
        for step in 0..=60 {
            let t = tumble.body(BodyId::scene(0)).unwrap();
            let b = box2d.pose(0).unwrap();
            let r = rapier.pose(0).unwrap();
            let dt = |p: [f32; 3]| {
                (t.origin.x - p[0])
                    .abs()
                    .max((t.origin.y - p[1]).abs())
                    .max((t.angle - p[2]).abs())
            };
            assert!(dt(b) < 1e-4, "step {step}: tumble {t:?}, Box2D {b:?}");
            assert!(dt(r) < 1e-3, "step {step}: tumble {t:?}, Rapier {r:?}");
            let v = box2d.velocity(0).unwrap();
            assert!(
                (t.linear_velocity - Vec2::new(v[0], v[1])).length() < 1e-4,
                "step {step}: tumble {t:?}, Box2D velocity {v:?}"
            );
            tumble.step(scene.dt, scene.substeps);
            box2d.step().unwrap();
            rapier.step().unwrap();
        }
    }

    #[test]
    fn a_body_created_asleep_stays_asleep_until_touched() {
        // Gravity on; two boxes in mid-air far apart, nothing under them: one created
        // asleep (it must not fall), one awake (it falls).
        let mut scene = SceneDef::new("asleep");
        let unit = ShapeDef::Box {
            half_extents: [0.5, 0.5],
            radius: 0.0,
        };
        scene.push(BodyDef::new(unit.clone()).at(0.0, 10.0).awake(false));
        scene.push(BodyDef::new(unit.clone()).at(10.0, 10.0));
        scene.push(
            BodyDef::new(unit)
                .kind(BodyKind::Static)
                .at(-10.0, 0.0)
                .awake(false),
        );
        for sleep in [true, false] {
            scene.sleep = sleep;
            let mut tumble = World::from_scene(&scene, &Limits::default()).unwrap();
            let settings = *tumble.settings();
            let mut box2d = Box2d::new(&scene, &settings, 1).unwrap();
            let mut rapier = Rapier::new(&scene, 1).unwrap();
            tumble.step(scene.dt, scene.substeps);
            box2d.step().unwrap();
            rapier.step().unwrap();
            // With sleep off, `awake: false` is ignored: everything dynamic is awake.
            let asleep = sleep;
            assert_eq!(
                tumble.body(BodyId::scene(0)).unwrap().awake,
                !asleep,
                "tumble, sleep {sleep}"
            );
            assert_eq!(box2d.is_awake(0).unwrap(), !asleep, "Box2D, sleep {sleep}");
            assert_eq!(rapier.is_awake(0), !asleep, "Rapier, sleep {sleep}");
            assert!(
                tumble.body(BodyId::scene(1)).unwrap().awake
                    && box2d.is_awake(1).unwrap()
                    && rapier.is_awake(1)
            );
            let still = |y: f32| (y == 10.0) == asleep;
            assert!(
                still(tumble.body(BodyId::scene(0)).unwrap().position.y),
                "tumble, sleep {sleep}"
            );
            assert!(still(box2d.pose(0).unwrap()[1]), "Box2D, sleep {sleep}");
            assert!(still(rapier.pose(0).unwrap()[1]), "Rapier, sleep {sleep}");
        }
    }

    #[test]
    fn rapier_gathers_the_contact_and_sensor_events_tumble_gathers() {
        // A ball (restitution 0) falls through a static sensor box spanning y in [2, 4] onto
        // a static ground: one sensor overlap begins and ends, one contact begins and stays,
        // in tumble and in Rapier alike (Rapier's collision events, read after each step).
        let mut scene = SceneDef::new("events");
        scene.push(
            BodyDef::new(ShapeDef::Box {
                half_extents: [10.0, 0.5],
                radius: 0.0,
            })
            .kind(BodyKind::Static)
            .at(0.0, -0.5),
        );
        scene.push(
            BodyDef::compound(vec![
                PartDef::new(ShapeDef::Box {
                    half_extents: [1.0, 1.0],
                    radius: 0.0,
                })
                .sensor(true),
            ])
            .kind(BodyKind::Static)
            .at(0.0, 3.0),
        );
        scene.push(BodyDef::new(ShapeDef::Circle { radius: 0.25 }).at(0.0, 6.0));
        let mut tumble = World::from_scene(&scene, &Limits::default()).unwrap();
        let mut rapier = Rapier::new(&scene, 1).unwrap();
        let mut cursor = tumble_physics::EventCursor::default();
        let mut ours = [0u64; 2];
        for _ in 0..120 {
            tumble.step(scene.dt, scene.substeps);
            rapier.step().unwrap();
            for e in cursor.take(&tumble) {
                match e {
                    Event::ContactBegin { .. } | Event::ContactEnd { .. } => ours[0] += 1,
                    Event::SensorBegin { .. } | Event::SensorEnd { .. } => ours[1] += 1,
                    _ => {}
                }
            }
        }
        assert_eq!(ours, [1, 2], "tumble");
        assert_eq!(rapier.event_counts(), [1, 2], "Rapier");
    }

    #[test]
    fn filters_and_groups_keep_the_same_pairs_apart() {
        // Four boxes dropped on a ground, each pair of parts testing one rule: category/mask
        // that refuse the ground (falls through), a negative group shared with the ground
        // (falls through), a positive group shared with the ground whose mask refuses it
        // (the group wins: it lands), and a default filter (lands).
        let mut scene = SceneDef::new("filters");
        scene.sleep = false;
        let ground = tumble_physics::Filter {
            category: 1 << 40,
            mask: u64::MAX,
            group: 0,
        };
        let grouped = |group: i64| tumble_physics::Filter {
            category: 1 << 40,
            mask: u64::MAX,
            group,
        };
        scene.push(
            BodyDef::compound(vec![
                PartDef::new(ShapeDef::Box {
                    half_extents: [3.0, 0.5],
                    radius: 0.0,
                })
                .at(-9.0, 0.0, 0.0)
                .filter(ground),
                PartDef::new(ShapeDef::Box {
                    half_extents: [3.0, 0.5],
                    radius: 0.0,
                })
                .at(-3.0, 0.0, 0.0)
                .filter(grouped(-2)),
                PartDef::new(ShapeDef::Box {
                    half_extents: [3.0, 0.5],
                    radius: 0.0,
                })
                .at(3.0, 0.0, 0.0)
                .filter(grouped(3)),
                PartDef::new(ShapeDef::Box {
                    half_extents: [3.0, 0.5],
                    radius: 0.0,
                })
                .at(9.0, 0.0, 0.0)
                .filter(ground),
            ])
            .kind(BodyKind::Static),
        );
        let unit = ShapeDef::Box {
            half_extents: [0.5, 0.5],
            radius: 0.0,
        };
        let filters = [
            tumble_physics::Filter {
                category: 2,
                mask: 2,
                group: 0,
            },
            tumble_physics::Filter {
                category: 1 << 40,
                mask: u64::MAX,
                group: -2,
            },
            tumble_physics::Filter {
                category: 2,
                mask: 2,
                group: 3,
            },
            tumble_physics::Filter::default(),
        ];
        for (k, f) in filters.into_iter().enumerate() {
            scene.push(
                BodyDef::new(unit.clone())
                    .at(-9.0 + 6.0 * k as f32, 1.6)
                    .filter(f),
            );
        }
        let lands = [false, false, true, true];
        let mut tumble = World::from_scene(&scene, &Limits::default()).unwrap();
        let settings = *tumble.settings();
        let mut peers: Vec<(&str, Box<dyn Peer>)> = vec![
            ("Box2D", Box::new(Box2d::new(&scene, &settings, 1).unwrap())),
            ("Rapier", Box::new(Rapier::new(&scene, 1).unwrap())),
        ];
        for _ in 0..90 {
            tumble.step(scene.dt, scene.substeps);
            for (_, p) in &mut peers {
                p.step().unwrap();
            }
        }
        for (k, &land) in lands.iter().enumerate() {
            let i = k + 1;
            let y = tumble.body(BodyId::scene(i)).unwrap().position.y;
            assert_eq!(y > 0.0, land, "tumble, box {k}: y {y}");
            for (name, p) in &mut peers {
                let y = p.pose(i).unwrap()[1];
                assert_eq!(y > 0.0, land, "{name}, box {k}: y {y}");
            }
        }
    }

    /// A joint as a scene file gives it (the fields left out take their defaults).
    fn joint(def: serde_json::Value) -> JointDef {
        serde_json::from_value(def).expect("a joint definition")
    }

    /// A disc of radius 0.25 on a 2 m arm: a revolute joint at the centre of a static disc,
    /// the dynamic one 2 m to its right, released with the arm horizontal.
    fn pendulum() -> SceneDef {
        let mut scene = SceneDef::new("pendulum");
        scene.sleep = false;
        scene.push(
            BodyDef::new(ShapeDef::Circle { radius: 0.1 })
                .kind(BodyKind::Static)
                .at(0.0, 10.0),
        );
        scene.push(BodyDef::new(ShapeDef::Circle { radius: 0.25 }).at(2.0, 10.0));
        scene.joints.push(joint(json!({"Revolute": {
            "bodies": [0, 1],
            "anchor": [0.0, 10.0],
        }})));
        scene
    }

    #[test]
    fn a_pendulum_keeps_its_length_in_every_peer() {
        // The joint holds: over a second of swinging down from horizontal, the disc stays
        // 2 m from the hinge within 1 cm in Box2D and Rapier (and in tumble, for reference),
        // and it does swing (it falls more than a metre).
        let scene = pendulum();
        let settings = scene_settings(&scene).unwrap();
        let mut tumble = World::from_scene(&scene, &Limits::default()).unwrap();
        let mut peers: Vec<(&str, Box<dyn Peer>)> = vec![
            ("Box2D", Box::new(Box2d::new(&scene, &settings, 1).unwrap())),
            ("Rapier", Box::new(Rapier::new(&scene, 1).unwrap())),
        ];
        let hinge = Vec2::new(0.0, 10.0);
        for step in 1..=60 {
            tumble.step(scene.dt, scene.substeps);
            let t = tumble.body(BodyId::scene(1)).unwrap().position;
            assert!(
                ((t - hinge).length() - 2.0).abs() < 0.01,
                "tumble, step {step}: {t}"
            );
            for (name, p) in &mut peers {
                p.step().unwrap();
                let [x, y, _] = p.pose(1).unwrap();
                let arm = (Vec2::new(x, y) - hinge).length();
                assert!((arm - 2.0).abs() < 0.01, "{name}, step {step}: arm {arm} m");
                if step == 60 {
                    assert!(y < 9.0, "{name}: the disc did not swing (y {y})");
                    let gap = (Vec2::new(x, y) - t).length();
                    eprintln!("{name}: {gap:e} m from tumble's disc after 60 steps");
                }
            }
        }
    }

    #[test]
    fn joint_grid_builds_and_stays_finite_in_every_peer() {
        let scene = tumble_scene::builtin::build("joint_grid").expect("a built-in");
        assert!(!scene.joints.is_empty());
        let settings = scene_settings(&scene).unwrap();
        let peers: Vec<(&str, Box<dyn Peer>)> = vec![
            ("Box2D", Box::new(Box2d::new(&scene, &settings, 2).unwrap())),
            ("Rapier", Box::new(Rapier::new(&scene, 2).unwrap())),
        ];
        for (name, mut p) in peers {
            for _ in 0..10 {
                p.step().unwrap();
            }
            for i in 0..scene.bodies.len() {
                let pose = p.pose(i).unwrap();
                assert!(
                    pose.iter().all(|x| x.is_finite()),
                    "{name}, body {i}: {pose:?}"
                );
            }
        }
    }

    /// One joint of every type, each between a static post and a dynamic box (or two boxes),
    /// far enough apart that nothing touches: revolute with a limit, motor and spring,
    /// prismatic with all three, wheel with a motor and its default spring, a rigid distance,
    /// a rope (a slack spring with an upper limit), a soft weld, a motor joint and a filter.
    fn every_joint() -> SceneDef {
        let mut scene = SceneDef::new("every joint");
        scene.sleep = false;
        let post = |scene: &mut SceneDef, x: f32| {
            scene.push(
                BodyDef::new(ShapeDef::Circle { radius: 0.1 })
                    .kind(BodyKind::Static)
                    .at(x, 10.0),
            )
        };
        let unit = ShapeDef::Box {
            half_extents: [0.5, 0.25],
            radius: 0.0,
        };
        let spring = json!({"hertz": 2.0, "damping_ratio": 0.5});
        let mut x = 0.0;
        let mut pair = |scene: &mut SceneDef, dx: f32, dy: f32| {
            x += 10.0;
            let a = post(scene, x);
            let b = scene.push(BodyDef::new(unit.clone()).at(x + dx, 10.0 + dy).angle(0.3));
            (a, b, [x, 10.0])
        };
        let (a, b, anchor) = pair(&mut scene, 1.0, 0.0);
        scene.joints.push(joint(json!({"Revolute": {
            "bodies": [a, b],
            "anchor": anchor,
            "limit": [-0.5, 0.5],
            "motor": {"speed": 1.0, "max_torque": 5.0},
            "spring": spring,
        }})));
        let (a, b, anchor) = pair(&mut scene, 1.0, -1.0);
        scene.joints.push(joint(json!({"Prismatic": {
            "bodies": [a, b],
            "anchor": anchor,
            "axis": [1.0, -1.0],
            "limit": [-1.0, 2.0],
            "motor": {"speed": 0.5, "max_force": 3.0},
            "spring": spring,
        }})));
        let (a, b, [x0, _]) = pair(&mut scene, 0.0, -1.0);
        scene.joints.push(joint(json!({"Wheel": {
            "bodies": [a, b],
            "anchor": [x0, 9.0],
            "axis": [0.0, 1.0],
            "limit": [-0.5, 0.5],
            "motor": {"speed": 2.0, "max_torque": 10.0},
        }})));
        let (a, b, anchor) = pair(&mut scene, 1.5, -1.5);
        scene.joints.push(joint(json!({"Distance": {
            "bodies": [a, b],
            "anchors": [anchor, [anchor[0] + 1.0, 8.5]],
        }})));
        let (a, b, anchor) = pair(&mut scene, 2.0, 0.0);
        scene.joints.push(joint(json!({"Distance": {
            "bodies": [a, b],
            "anchors": [anchor, [anchor[0] + 1.5, 10.0]],
            "limit": [0.0, 2.5],
            "spring": {"hertz": 0.0, "damping_ratio": 0.0},
        }})));
        let (a, b, anchor) = pair(&mut scene, 1.0, 0.0);
        scene.joints.push(joint(json!({"Weld": {
            "bodies": [a, b],
            "anchor": anchor,
            "linear_hertz": 5.0,
            "angular_hertz": 3.0,
            "linear_damping_ratio": 0.7,
            "angular_damping_ratio": 0.7,
        }})));
        let (a, b, _) = pair(&mut scene, 1.0, 0.0);
        scene.joints.push(joint(json!({"Motor": {
            "bodies": [a, b],
            "linear_offset": [0.0, -1.0],
            "angular_offset": 0.0,
            "max_force": 50.0,
            "max_torque": 20.0,
            "correction_factor": 0.3,
        }})));
        // Two dynamic boxes overlapping, kept apart only by the filter joint's rule: they
        // fall together without pushing each other.
        x += 10.0;
        let a = scene.push(BodyDef::new(unit.clone()).at(x, 10.0));
        let b = scene.push(BodyDef::new(unit).at(x + 0.2, 10.0));
        scene
            .joints
            .push(joint(json!({"Filter": {"bodies": [a, b]}})));
        scene
    }

    #[test]
    fn every_joint_type_builds_and_moves_as_in_tumble() {
        // Each joint drives its box the way tumble's does after a second. Box2D runs the
        // same rows (its motor joint's spring standing in for v3.0's correction): within
        // round-off (4e-6 m at worst). Rapier's solver differs (its rigid rows, its
        // stabilization passes): 7e-2 rad at worst, the rope's box swinging.
        let scene = every_joint();
        let settings = scene_settings(&scene).unwrap();
        let mut tumble = World::from_scene(&scene, &Limits::default()).unwrap();
        let mut box2d = Box2d::new(&scene, &settings, 1).unwrap();
        let mut rapier = Rapier::new(&scene, 1).unwrap();
        let mut worst = [0.0f32; 2];
        for _ in 0..60 {
            tumble.step(scene.dt, scene.substeps);
            box2d.step().unwrap();
            rapier.step().unwrap();
        }
        for i in 0..scene.bodies.len() {
            let t = tumble.body(BodyId::scene(i)).unwrap();
            for (k, (name, p)) in [
                ("Box2D", &mut box2d as &mut dyn Peer),
                ("Rapier", &mut rapier as &mut dyn Peer),
            ]
            .into_iter()
            .enumerate()
            {
                let [x, y, angle] = p.pose(i).unwrap();
                let d = (Vec2::new(x, y) - t.origin).length();
                let turn = (angle - t.angle).sin().abs();
                eprintln!("body {i}: {name} {d:.2e} m, {turn:.2e} rad from tumble");
                worst[k] = worst[k].max(d).max(turn);
            }
        }
        assert!(worst[0] < 1e-4, "Box2D: {worst:?}");
        assert!(worst[1] < 0.1, "Rapier: {worst:?}");
        // The filter joint's boxes fell together, overlapping, untouched by each other.
        let n = scene.bodies.len();
        let (a, b) = (
            tumble.body(BodyId::scene(n - 2)).unwrap(),
            tumble.body(BodyId::scene(n - 1)).unwrap(),
        );
        assert!((b.origin.x - a.origin.x - 0.2).abs() < 1e-4 && a.origin.y < 9.0);
    }

    #[test]
    fn rapier_refuses_a_distance_lower_limit_naming_the_joint() {
        let mut scene = pendulum();
        scene.joints[0] = joint(json!({"Distance": {
            "bodies": [0, 1],
            "anchors": [[0.0, 10.0], [2.0, 10.0]],
            "limit": [1.0, 3.0],
            "spring": {"hertz": 1.0, "damping_ratio": 0.5},
        }}));
        let e = Rapier::new(&scene, 1).err().expect("refused").to_string();
        assert!(e.contains("joint 0 (Distance)"), "{e}");
        // Box2D has the limit.
        let settings = scene_settings(&scene).unwrap();
        Box2d::new(&scene, &settings, 1).unwrap();
    }
}
