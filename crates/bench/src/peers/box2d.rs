//! A scene in Box2D v3 through boxdd.
//!
//! Mapping: each tumble body is one Box2D body with one shape. Boxes are `b2MakeBox` polygons
//! (radius 0), other polygons are the hull of tumble's centroid-recentred vertices, circles are
//! centred circles. Friction and restitution go on each shape's material; Box2D mixes them as
//! tumble does (friction `sqrt(a * b)`, restitution `max(a, b)`). World: tumble's gravity,
//! contact hertz, damping ratio, push-out speed, restitution threshold and speed cap; sleep off;
//! continuous collision off (tumble has none); contact events off (tumble produces none);
//! `threads` workers (Box2D's own scheduler: the caller plus `threads - 1` threads).

use anyhow::{Result, bail};
use boxdd::{
    BodyBuilder, BodyId, BodyType, Foundation, MotionLocks, Position, ShapeDef, SurfaceMaterial,
    Vec2, WorkerCount, World, WorldBuilder,
};
use tumble_physics::{BodyKind, SceneDef, Shape, ShapeDef as TumbleShape, StepSettings};

use super::{Peer, ok};

/// A Box2D world holding a tumble scene.
pub struct Box2d {
    world: World,
    ids: Vec<BodyId>,
    dt: f32,
    substeps: i32,
}

/// Box2D's version, e.g. "3.2.0".
pub fn version() -> String {
    match boxdd::version() {
        Ok(v) => format!("{}.{}.{}", v.major, v.minor, v.revision),
        Err(_) => "unknown".into(),
    }
}

impl Box2d {
    /// Builds the scene; `settings` are the tumble world's (for the numbers Box2D shares).
    pub fn new(scene: &SceneDef, settings: &StepSettings, threads: usize) -> Result<Box2d> {
        let f = ok(Foundation::initialize_default(), "Box2D foundation")?;
        let workers = ok(
            WorkerCount::new(u32::try_from(threads).unwrap_or(u32::MAX)),
            "Box2D worker count (1 to 32)",
        )?;
        let def = ok(
            WorldBuilder::from(f.world_def())
                .gravity(Vec2::new(scene.gravity[0], scene.gravity[1]))
                .enable_sleep(false)
                .enable_continuous(false)
                .contact_hertz(settings.contact_hertz)
                .contact_damping_ratio(settings.contact_damping_ratio)
                .contact_speed(settings.max_push_speed)
                .restitution_threshold(settings.restitution_threshold)
                .maximum_linear_speed(settings.max_linear_speed)
                .worker_count(workers)
                .build(),
            "Box2D world definition",
        )?;
        let mut world = ok(f.create_world(def), "Box2D world")?;
        let mut ids = Vec::with_capacity(scene.bodies.len());
        for (i, b) in scene.bodies.iter().enumerate() {
            let what = format!("Box2D body {i}");
            let kind = match b.kind {
                BodyKind::Static => BodyType::Static,
                BodyKind::Dynamic => BodyType::Dynamic,
                BodyKind::Kinematic => BodyType::Kinematic,
            };
            let body_def = ok(
                BodyBuilder::from(f.body_def())
                    .body_type(kind)
                    .position(Position::new(b.position[0], b.position[1]))
                    .angle(b.angle)
                    .linear_velocity(Vec2::new(b.linear_velocity[0], b.linear_velocity[1]))
                    .angular_velocity(b.angular_velocity)
                    .linear_damping(b.linear_damping)
                    .angular_damping(b.angular_damping)
                    .enable_sleep(false)
                    .motion_locks(MotionLocks::new(false, false, b.fixed_rotation))
                    .build(),
                &what,
            )?;
            let id = ok(world.create_body(body_def), &what)?;
            let material = ok(
                SurfaceMaterial::default()
                    .with_friction(b.friction)
                    .and_then(|m| m.with_restitution(b.restitution)),
                &what,
            )?;
            let shape_def = ok(
                ShapeDef::builder()
                    .density(b.density)
                    .material(material)
                    .enable_contact_events(false)
                    .build(),
                &what,
            )?;
            let mut body = ok(world.body(id), &what)?;
            match (&b.shape, ok(Shape::from_def(&b.shape), &what)?) {
                (TumbleShape::Box { half_extents }, _) => {
                    ok(
                        body.create_box(&shape_def, half_extents[0], half_extents[1]),
                        &what,
                    )?;
                }
                (_, Shape::Circle(c)) => {
                    ok(body.create_centered_circle(&shape_def, c.radius), &what)?;
                }
                (_, Shape::Polygon(p)) => {
                    let points: Vec<Vec2> =
                        p.points().iter().map(|v| Vec2::new(v.x, v.y)).collect();
                    ok(
                        body.create_polygon_from_points(&shape_def, points, 0.0),
                        &what,
                    )?;
                }
            }
            ids.push(id);
        }
        if scene.substeps > i32::MAX as u32 {
            bail!("too many substeps for Box2D");
        }
        Ok(Box2d {
            world,
            ids,
            dt: scene.dt,
            substeps: scene.substeps as i32,
        })
    }
}

impl Peer for Box2d {
    fn step(&mut self) -> Result<()> {
        ok(
            self.world.step(self.dt, self.substeps).map(|_| ()),
            "Box2D step",
        )
    }

    fn pose(&mut self, index: usize) -> Result<[f32; 3]> {
        let body = ok(self.world.body(self.ids[index]), "Box2D body")?;
        let p = ok(body.position(), "Box2D position")?;
        let q = ok(body.rotation(), "Box2D rotation")?;
        Ok([p.x, p.y, q.angle()])
    }

    fn velocity(&mut self, index: usize) -> Result<[f32; 3]> {
        let body = ok(self.world.body(self.ids[index]), "Box2D body")?;
        let v = ok(body.linear_velocity(), "Box2D linear velocity")?;
        let w = ok(body.angular_velocity(), "Box2D angular velocity")?;
        Ok([v.x, v.y, w])
    }

    /// `b2World_GetProfile`, grouped: broad phase = `pairs + refit`, narrow phase =
    /// `collide`, prepare = `prepareStages + prepareConstraints`, substeps = `integrate
    /// velocities + warm start + solve + integrate positions + relax + restitution`, store =
    /// `storeImpulses`, finalize = `transforms + splitIslands + sleepIslands + bullets`.
    /// Box2D times its solver stages on the orchestrating thread, so they include its waits.
    fn stages(&mut self) -> Vec<(&'static str, f64)> {
        let Ok(p) = self.world.profile() else {
            return Vec::new();
        };
        let ms = |x: f32| f64::from(x);
        vec![
            ("broad phase", ms(p.pairs) + ms(p.refit)),
            ("narrow phase", ms(p.collide)),
            ("prepare", ms(p.solver_setup) + ms(p.prepare_constraints)),
            (
                "substeps",
                ms(p.integrate_velocities)
                    + ms(p.warm_start)
                    + ms(p.solve_impulses)
                    + ms(p.integrate_positions)
                    + ms(p.relax_impulses)
                    + ms(p.apply_restitution),
            ),
            ("store impulses", ms(p.store_impulses)),
            (
                "finalize",
                ms(p.transforms) + ms(p.split_islands) + ms(p.sleep_islands) + ms(p.bullets),
            ),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tumble_physics::{BodyDef, Limits, SceneDef, World};

    /// Bodies that each touch only the static ground, 5 m apart: a box at rest, a box sliding
    /// at 3 m/s, a box tipped on a corner and a circle thrown spinning. (A box dropped on
    /// its face with restitution 0.5 is left out: the two engines agree on it to 7e-7 m for
    /// its first steps, then part by 3e-5 m in one step as it bounces, a threshold decision
    /// flipped by a last-bit difference.) No two constraints share a dynamic body, so every
    /// order of solving them gives the same result. Each starts 1 mm above the ground: within
    /// the speculative distance (2 cm), which both engines use; a body approaching faster than
    /// that in a step meets it earlier in tumble, whose speculative margin also grows with the
    /// closing speed (Box2D has continuous collision for that, off in this comparison).
    fn apart() -> SceneDef {
        let mut scene = SceneDef::new("apart");
        let unit = TumbleShape::Box {
            half_extents: [0.5, 0.5],
        };
        scene.push(
            BodyDef::new(TumbleShape::Box {
                half_extents: [100.0, 1.0],
            })
            .kind(BodyKind::Static)
            .at(0.0, -1.0),
        );
        let gap = 0.001;
        scene.push(BodyDef::new(unit.clone()).at(-20.0, 0.5 + gap));
        scene.push(
            BodyDef::new(unit.clone())
                .at(-15.0, 0.5 + gap)
                .velocity(3.0, 0.0),
        );
        // Tipped by 0.2 rad: its lowest corner is 0.5 (cos 0.2 + sin 0.2) below its centre.
        let corner = 0.5 * (0.2f32.cos() + 0.2f32.sin());
        scene.push(BodyDef::new(unit).at(-5.0, corner + gap).angle(0.2));
        scene.push(
            BodyDef::new(TumbleShape::Circle { radius: 0.5 })
                .at(15.0, 0.5 + gap)
                .velocity(-2.0, 0.0)
                .spin(-8.0),
        );
        scene
    }

    #[test]
    fn bodies_on_the_ground_move_as_in_box2d() {
        // tumble runs Box2D v3's Soft Step: the same manifolds, the same solver arithmetic,
        // the same stages. Where the order of solving cannot matter, every pose agrees with
        // Box2D's after 120 steps (2 s: the tipped box falls onto its face, the slider stops,
        // the circle rolls) to within float round-off: the two compute the same terms in
        // places rounded differently (the anchors, the relative pose), and a tumbling box
        // grows a last-bit difference. The bound is ten of f32's steps at 20 m (1.9e-6 m)
        // from the origin; a real difference (a term left out, a clamp elsewhere) shows at
        // once, as the warm-start impulses alone move a resting box by 1e-4 m a step.
        let scene = apart();
        let mut tumble = World::from_scene(&scene, &Limits::default()).unwrap();
        tumble.set_thread_count(1);
        let mut box2d = Box2d::new(&scene, tumble.settings(), 1).unwrap();
        let mut worst = 0.0f32;
        for _ in 0..120 {
            tumble.step(scene.dt, scene.substeps);
            box2d.step().unwrap();
            for i in 1..scene.bodies.len() {
                let t = tumble.body(i);
                let b = box2d.pose(i).unwrap();
                let d = (t.position.x - b[0])
                    .abs()
                    .max((t.position.y - b[1]).abs())
                    .max((t.angle - b[2]).abs());
                worst = worst.max(d);
                assert!(d < 2e-5, "body {i}: tumble {t:?}, Box2D {b:?}");
            }
        }
        eprintln!("largest difference from Box2D: {worst:e}");
    }
}
