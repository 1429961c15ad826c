//! A scene in Box2D v3 through boxdd.
//!
//! Mapping: each tumble body is one Box2D body: its kind, frame (position and angle), velocity
//! (tumble's is the centre of mass's, Box2D's definition takes the origin's: converted),
//! damping, `gravity_scale`, `fixed_rotation` (`b2MotionLocks` on rotation), and one Box2D shape
//! per part ([`part_shape`]): boxes are `b2MakeBox`, or `b2MakeOffsetRoundedBox` at a part's
//! offset and angle or with a radius; polygons the hull of their vertices in the body's frame
//! (a body of one shape: tumble's centroid-recentred vertices), with their rounding radius;
//! circles at their centre; capsules, segments and chains (`b2CreateChain`, its material the
//! part's) as given. Each shape has its part's density, friction and restitution (Box2D mixes them as tumble does: friction
//! `sqrt(a * b)`, restitution `max(a, b)`), its filter as a `b2Filter` (`categoryBits`,
//! `maskBits`, `groupIndex`: Box2D's rule is tumble's; a group outside `i32` is refused) and
//! `isSensor` for a sensor part (with sensor events off: tumble's sensor today touches
//! nothing and reports nothing). Box2D computes the mass, centre of mass and inertia from the
//! shapes as tumble does.
//!
//! Sleep: the world's `enableSleep` is the scene's `sleep`; each body's `enableSleep` its
//! `enable_sleep`, `isAwake` its `awake` (a body starts asleep only in a world that sleeps, as
//! in tumble) and `sleepThreshold` the scene's `solver.sleep_threshold` (tumble's default,
//! Box2D's, 0.05 m/s). Box2D's time to sleep is the compile-time constant `B2_TIME_TO_SLEEP`
//! (0.5 s, tumble's default): a scene's other `solver.time_to_sleep` is not passed on.
//! Box2D solves a manifold's points one after the other: `solver.solve_points_together` (on by
//! default in tumble) has no counterpart, so the timing compares tumble's default against
//! Box2D's, and the cross-checks that hold tumble to Box2D's arithmetic turn it off.
//!
//! World: tumble's gravity, contact hertz, damping ratio, push-out speed, restitution threshold
//! and speed cap; continuous collision as tumble's world has it (the scene's `continuous`;
//! `bullet`s passed on as `isBullet`); the events tumble gathers on every shape (contact
//! begin and end, hits at the scene's `hit_speed`, sensor overlaps) on every shape; `threads`
//! workers (Box2D's own scheduler: the caller plus `threads - 1` threads). A scene with a
//! script ([`super::script`]) runs it before each step: junkyard's pusher through
//! `b2Body_SetTargetTransform`, rain's groups made as the scene's bodies and joints are, and
//! destroyed by `b2DestroyBody` (which takes their joints).
//!
//! Joints, created after the bodies from the joints tumble builds ([`super::scene_joints`]:
//! `JointDef::build`'s frames and defaults), as Box2D 3.2 takes them: each joint's
//! `localFrameA`/`localFrameB` are tumble's joint frames in each body's origin frame (the
//! anchor, and a slider's axis as the frame's x axis, put into the frame of the position and
//! angle the scene gives the body; both frames coincide in the world at the start, so a
//! revolute joint's angle and a slider's translation count from the start, as in tumble),
//! `collideConnected` the joint's `collide_connected`, and `constraintHertz` /
//! `constraintDampingRatio`, the stiffness of the rigid rows, the scene's
//! `solver.joint_hertz` / `joint_damping_ratio` (60 Hz and 2 by default; Box2D 3.2 sets them
//! per joint in `b2JointDef`, not in the world definition). Every flag is set explicitly (some
//! of Box2D's defaults are on). Per type:
//! - Revolute: `enableLimit`, `lowerAngle`, `upperAngle`; `enableMotor`, `motorSpeed`,
//!   `maxMotorTorque`; `enableSpring`, `hertz`, `dampingRatio`, `targetAngle` (0, the start).
//! - Prismatic: the same with `lowerTranslation`/`upperTranslation`, `maxMotorForce` and
//!   `targetTranslation` (0).
//! - Wheel: limit, angular motor (`maxMotorTorque`) and spring; a scene's wheel without a
//!   spring gets tumble's default, Box2D's own: 1 Hz, damping ratio 0.7.
//! - Distance: `length` (default: the anchors' distance at the start); with a spring,
//!   `enableSpring`, `hertz`, `dampingRatio`, and with a limit `enableLimit`, `minLength`,
//!   `maxLength`; without a spring, rigid. No motor.
//! - Weld: linear and angular hertz and damping ratios (0 Hz: rigid, the rigid rows).
//! - Motor: tumble's is Box2D v3.0's motor joint, a rigid row `Cdot + (c / h) C = 0` on
//!   each axis (`c` the correction factor, `h` the substep) bounded by `max_force` (on the
//!   linear impulse's length) and `max_torque`. Box2D 3.2 replaced it with a velocity part
//!   (`linearVelocity`, `maxVelocityForce`, ...) and a spring part (`linearHertz`,
//!   `linearDampingRatio`, `maxSpringForce`, ...) that pulls frame B onto frame A. Mapped:
//!   frame A is the target pose of B's origin in A's frame (`linear_offset`,
//!   `angular_offset`), frame B B's origin; with `c` > 0, linear and angular springs whose
//!   hertz and damping ratio give the bias rate `c / h` and a mass scale of 1 − 10⁻⁴
//!   ([`correction_spring`]: v3.0's row, softened by 10⁻⁴), bounded by `maxSpringForce =
//!   max_force` and `maxSpringTorque = max_torque`, the velocity part off; with `c` = 0, the
//!   velocity part only (target 0, `maxVelocityForce`, `maxVelocityTorque`), v3.0's row
//!   without correction.
//! - Filter: `b2FilterJointDef`.

use anyhow::{Result, bail};
use boxdd::{
    BodyBuilder, BodyId, BodyType, ChainDef, Circle, ConstraintTuning, DistanceJointDef, Filter,
    FilterJointDef, Foundation, MotionLocks, MotorJointDef, Polygon, Position, PrismaticJointDef,
    RevoluteJointDef, Rot, ShapeDef, SurfaceMaterial, Transform, Vec2, WeldJointDef, WheelJointDef,
    WorkerCount, World, WorldBuilder, WorldTransform,
};
use std::collections::HashMap;

use tumble_physics::{BodyKind, JointKind, SceneDef, StepSettings};

use super::{PartShape, Peer, Script, Targets, ok, origin_velocity, part_shape, scene_joints};

/// A Box2D world holding a tumble scene.
pub struct Box2d {
    world: World,
    foundation: &'static Foundation,
    ids: Vec<BodyId>,
    dt: f32,
    substeps: i32,
    sleep: bool,
    settings: StepSettings,
    script: Option<Script>,
    steps: u64,
    /// The bodies each tag's group made ([`Targets::spawn`]).
    spawned: HashMap<u64, Vec<BodyId>>,
}

/// Box2D's version, e.g. "3.2.0".
pub fn version() -> String {
    match boxdd::version() {
        Ok(v) => format!("{}.{}.{}", v.major, v.minor, v.revision),
        Err(_) => "unknown".into(),
    }
}

/// A tumble filter as Box2D's (the same bits; Box2D's group is an `i32`).
fn filter(f: &tumble_physics::Filter) -> Result<Filter> {
    let Ok(group_index) = i32::try_from(f.group) else {
        bail!(
            "filter group {} does not fit Box2D's 32-bit groupIndex",
            f.group
        );
    };
    Ok(Filter {
        category_bits: f.category,
        mask_bits: f.mask,
        group_index,
    })
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
                .enable_sleep(scene.sleep)
                .enable_continuous(settings.continuous)
                .hit_event_threshold(settings.hit_speed)
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
            ids.push(create_body(&mut world, f, i, b, scene.sleep, settings)?);
        }
        if scene.substeps > i32::MAX as u32 {
            bail!("too many substeps for Box2D");
        }
        let h = scene.dt / scene.substeps.max(1) as f32;
        create_joints(&mut world, &ids, scene, settings, h)?;
        Ok(Box2d {
            world,
            foundation: f,
            ids,
            dt: scene.dt,
            substeps: scene.substeps as i32,
            sleep: scene.sleep,
            settings: *settings,
            script: super::script(&scene.name),
            steps: 0,
            spawned: HashMap::new(),
        })
    }

    /// Bodies and joints in the world (`b2World_GetCounters`).
    #[cfg(test)]
    pub fn counts(&self) -> Result<(usize, usize)> {
        let c = ok(self.world.counters(), "Box2D counters")?;
        Ok((c.body_count as usize, c.joint_count as usize))
    }

    /// Whether body `index` is awake (`b2Body_IsAwake`).
    #[cfg(test)]
    pub fn is_awake(&mut self, index: usize) -> Result<bool> {
        let body = ok(self.world.body(self.ids[index]), "Box2D body")?;
        ok(body.is_awake(), "Box2D awake")
    }

    /// Body `index`'s mass and centre of mass in its frame (`b2Body_GetMass`,
    /// `b2Body_GetLocalCenterOfMass`).
    #[cfg(test)]
    pub fn mass(&mut self, index: usize) -> Result<(f32, [f32; 2])> {
        let body = ok(self.world.body(self.ids[index]), "Box2D body")?;
        let m = ok(body.mass(), "Box2D mass")?;
        let c = ok(body.local_center_of_mass(), "Box2D centre of mass")?;
        Ok((m, [c.x, c.y]))
    }
}

/// Creates tumble body `b` (the scene's `i`-th) with its shapes (see the module's
/// documentation), in a world that sleeps when `sleep` is on.
fn create_body(
    world: &mut World,
    f: &Foundation,
    i: usize,
    b: &tumble_physics::BodyDef,
    sleep: bool,
    settings: &StepSettings,
) -> Result<BodyId> {
    let what = format!("Box2D body {i}");
    let kind = match b.kind {
        BodyKind::Static => BodyType::Static,
        BodyKind::Dynamic => BodyType::Dynamic,
        BodyKind::Kinematic => BodyType::Kinematic,
    };
    // tumble starts a body asleep only when the world sleeps and the body is dynamic;
    // Box2D would put any body defined asleep into a sleeping set.
    let asleep = !b.awake && sleep && b.kind == BodyKind::Dynamic;
    let v = origin_velocity(b);
    let body_def = ok(
        BodyBuilder::from(f.body_def())
            .body_type(kind)
            .position(Position::new(b.position[0], b.position[1]))
            .angle(b.angle)
            .linear_velocity(Vec2::new(v[0], v[1]))
            .angular_velocity(b.angular_velocity)
            .linear_damping(b.linear_damping)
            .angular_damping(b.angular_damping)
            .gravity_scale(b.gravity_scale)
            .enable_sleep(b.enable_sleep)
            .sleep_threshold(settings.sleep_threshold)
            .awake(!asleep)
            .bullet(b.bullet)
            .motion_locks(MotionLocks::new(false, false, b.fixed_rotation))
            .build(),
        &what,
    )?;
    let id = ok(world.create_body(body_def), &what)?;
    let mut body = ok(world.body(id), &what)?;
    for (k, part) in b.parts().iter().enumerate() {
        let what = format!("Box2D body {i}, part {k}");
        let material = ok(
            SurfaceMaterial::default()
                .with_friction(part.friction)
                .and_then(|m| m.with_restitution(part.restitution)),
            &what,
        )?;
        let shape_def = ok(
            ShapeDef::builder()
                .density(part.density)
                .material(material)
                .filter(filter(&part.filter).map_err(|e| anyhow::anyhow!("{what}: {e}"))?)
                .sensor(part.sensor)
                // The events tumble gathers on every shape: contact begin and end, hits
                // (Box2D's washer turns them on for its boxes), sensor overlaps.
                .enable_sensor_events(true)
                .enable_contact_events(true)
                .enable_hit_events(true)
                .build(),
            &what,
        )?;
        let shape = part_shape(part).map_err(|e| anyhow::anyhow!("{what}: {e}"))?;
        match shape {
            PartShape::Box {
                half_extents: [hx, hy],
                center: [0.0, 0.0],
                angle: 0.0,
                radius: 0.0,
            } => {
                ok(body.create_box(&shape_def, hx, hy), &what)?;
            }
            PartShape::Box {
                half_extents: [hx, hy],
                center,
                angle,
                radius,
            } => {
                let xf = ok(Transform::from_pos_angle(center, angle), &what)?;
                let polygon = ok(
                    Polygon::offset_rounded_box_polygon(hx, hy, radius, xf),
                    &what,
                )?;
                ok(body.create_polygon(&shape_def, &polygon), &what)?;
            }
            PartShape::Circle { center, radius } => {
                let circle = ok(Circle::new(center, radius), &what)?;
                ok(body.create_circle(&shape_def, &circle), &what)?;
            }
            PartShape::Polygon(points, radius) => {
                ok(
                    body.create_polygon_from_points(&shape_def, points, radius),
                    &what,
                )?;
            }
            PartShape::Capsule {
                center1,
                center2,
                radius,
            } => {
                ok(
                    body.create_capsule_between(&shape_def, center1, center2, radius),
                    &what,
                )?;
            }
            PartShape::Segment { point1, point2 } => {
                ok(
                    body.create_segment_between(&shape_def, point1, point2),
                    &what,
                )?;
            }
            PartShape::Chain { points, looped } => {
                let chain = ok(
                    ChainDef::builder()
                        .points(points)
                        .is_loop(looped)
                        .single_material(&material)
                        .filter(filter(&part.filter).map_err(|e| anyhow::anyhow!("{what}: {e}"))?)
                        .build(),
                    &what,
                )?;
                ok(body.create_chain(&chain), &what)?;
            }
        }
    }
    Ok(id)
}

/// The spring of Box2D 3.2's motor joint that acts as v3.0's position correction (tumble's
/// motor joint): v3.0 solves `Cdot + (correction_factor / h) C = 0` rigidly, for a substep
/// `h`; a soft row `b2MakeSoft(hertz, zeta, h)` has the bias rate `ω / (2ζ + hω)` and the mass
/// scale `x (2ζ + x) / (1 + x (2ζ + x))` with `x = hω`. With `ζ = x (1 − c) / (2c)` the bias
/// rate is `c / h` for any `x`, and the mass scale `(x² / c) / (1 + x² / c)`: `x² = 10⁴ c`
/// makes it 1 − 10⁻⁴ (and the impulse scale 10⁻⁴), v3.0's rigid row to that. Returns
/// (hertz, damping ratio); `c` > 0.
fn correction_spring(correction_factor: f32, h: f32) -> (f32, f32) {
    let c = correction_factor;
    let x = (1.0e4 * c).sqrt();
    let omega = x / h;
    (
        omega / (2.0 * std::f32::consts::PI),
        x * (1.0 - c) / (2.0 * c),
    )
}

/// Creates the scene's joints (see the module's documentation) between the bodies `ids`.
fn create_joints(
    world: &mut World,
    ids: &[BodyId],
    scene: &SceneDef,
    settings: &StepSettings,
    h: f32,
) -> Result<()> {
    for (index, (joint, [body_a, body_b])) in scene_joints(scene, settings)?.iter().enumerate() {
        let what = format!(
            "scene {:?}, Box2D joint {index} ({})",
            scene.name,
            joint.kind.name()
        );
        let frame = |t: &tumble_physics::Transform| {
            ok(
                Transform::from_pos_angle(Vec2::new(t.p.x, t.p.y), t.q.angle()),
                &what,
            )
        };
        let base = ok(world.joint_base(ids[*body_a], ids[*body_b]), &what)?
            .with_local_frames(frame(&joint.local_a)?, frame(&joint.local_b)?)
            .with_collide_connected(joint.collide_connected)
            .with_constraint_tuning(ok(
                ConstraintTuning::new(joint.hertz, joint.damping_ratio),
                &what,
            )?);
        // Every flag is set, off or on: some of Box2D's defaults are on (the wheel's spring).
        let created = match &joint.kind {
            JointKind::Revolute(r) => {
                let [lower, upper] = r.limit.unwrap_or([0.0; 2]);
                let motor = r.motor.unwrap_or(tumble_physics::joint::AngularMotor {
                    speed: 0.0,
                    max_torque: 0.0,
                });
                let spring = r.spring.unwrap_or(tumble_physics::joint::Spring {
                    hertz: 0.0,
                    damping_ratio: 0.0,
                });
                world.create_revolute_joint(
                    &RevoluteJointDef::new(base)
                        .enable_limit(r.limit.is_some())
                        .lower_angle(lower)
                        .upper_angle(upper)
                        .enable_motor(r.motor.is_some())
                        .motor_speed(motor.speed)
                        .max_motor_torque(motor.max_torque)
                        .enable_spring(r.spring.is_some())
                        .hertz(spring.hertz)
                        .damping_ratio(spring.damping_ratio)
                        .target_angle(r.target_angle),
                )
            }
            JointKind::Prismatic(p) => {
                let [lower, upper] = p.limit.unwrap_or([0.0; 2]);
                let motor = p.motor.unwrap_or(tumble_physics::joint::LinearMotor {
                    speed: 0.0,
                    max_force: 0.0,
                });
                let spring = p.spring.unwrap_or(tumble_physics::joint::Spring {
                    hertz: 0.0,
                    damping_ratio: 0.0,
                });
                world.create_prismatic_joint(
                    &PrismaticJointDef::new(base)
                        .enable_limit(p.limit.is_some())
                        .lower_translation(lower)
                        .upper_translation(upper)
                        .enable_motor(p.motor.is_some())
                        .motor_speed(motor.speed)
                        .max_motor_force(motor.max_force)
                        .enable_spring(p.spring.is_some())
                        .hertz(spring.hertz)
                        .damping_ratio(spring.damping_ratio)
                        .translation(p.target_translation),
                )
            }
            JointKind::Wheel(w) => {
                let [lower, upper] = w.limit.unwrap_or([0.0; 2]);
                let motor = w.motor.unwrap_or(tumble_physics::joint::AngularMotor {
                    speed: 0.0,
                    max_torque: 0.0,
                });
                let spring = w.spring.unwrap_or(tumble_physics::joint::Spring {
                    hertz: 0.0,
                    damping_ratio: 0.0,
                });
                world.create_wheel_joint(
                    &WheelJointDef::new(base)
                        .enable_limit(w.limit.is_some())
                        .lower_translation(lower)
                        .upper_translation(upper)
                        .enable_motor(w.motor.is_some())
                        .motor_speed(motor.speed)
                        .max_motor_torque(motor.max_torque)
                        .enable_spring(w.spring.is_some())
                        .hertz(spring.hertz)
                        .damping_ratio(spring.damping_ratio),
                )
            }
            JointKind::Distance(d) => {
                let mut def = DistanceJointDef::new(base)
                    .length(d.length)
                    .enable_motor(false)
                    .enable_spring(d.spring.is_some())
                    .enable_limit(d.limit.is_some());
                if let Some(s) = d.spring {
                    def = def.hertz(s.hertz).damping_ratio(s.damping_ratio);
                }
                if let Some([min, max]) = d.limit {
                    def = def.min_length(min).max_length(max);
                }
                world.create_distance_joint(&def)
            }
            JointKind::Weld(w) => world.create_weld_joint(
                &WeldJointDef::new(base)
                    .linear_hertz(w.linear_hertz)
                    .angular_hertz(w.angular_hertz)
                    .linear_damping_ratio(w.linear_damping_ratio)
                    .angular_damping_ratio(w.angular_damping_ratio),
            ),
            JointKind::Motor(m) => {
                // Box2D 3.2's spring pulls frame B onto frame A: frame A is the target pose of
                // B's origin in A's frame, frame B B's origin.
                let target = ok(
                    Transform::from_pos_angle(
                        Vec2::new(m.linear_offset.x, m.linear_offset.y),
                        m.angular_offset,
                    ),
                    &what,
                )?;
                let base = base.with_local_frames(target, Transform::IDENTITY);
                let def = MotorJointDef::new(base)
                    .linear_velocity(Vec2::new(0.0, 0.0))
                    .angular_velocity(0.0);
                let def = if m.correction_factor > 0.0 {
                    let (hertz, zeta) = correction_spring(m.correction_factor, h);
                    def.linear_hertz(hertz)
                        .linear_damping_ratio(zeta)
                        .max_spring_force(m.max_force)
                        .angular_hertz(hertz)
                        .angular_damping_ratio(zeta)
                        .max_spring_torque(m.max_torque)
                        .max_velocity_force(0.0)
                        .max_velocity_torque(0.0)
                } else {
                    // No correction: v3.0's row only holds the relative velocity at 0.
                    def.linear_hertz(0.0)
                        .angular_hertz(0.0)
                        .max_spring_force(0.0)
                        .max_spring_torque(0.0)
                        .max_velocity_force(m.max_force)
                        .max_velocity_torque(m.max_torque)
                };
                world.create_motor_joint(&def)
            }
            JointKind::Filter => world.create_filter_joint(&FilterJointDef::new(base)),
            JointKind::Mouse(_) => bail!("{what}: a scene has no mouse joints"),
        };
        ok(created, &what)?;
    }
    Ok(())
}

impl Targets for Box2d {
    fn body_count(&self) -> usize {
        self.ids.len()
    }

    fn set_target_transform(
        &mut self,
        index: usize,
        position: [f32; 2],
        angle: f32,
        dt: f32,
    ) -> Result<()> {
        let what = "Box2D target transform";
        let q = ok(Rot::from_radians(angle), what)?;
        let target = ok(
            WorldTransform::new(Position::new(position[0], position[1]), q),
            what,
        )?;
        let mut body = ok(self.world.body(self.ids[index]), what)?;
        ok(body.set_target_transform(target, dt, true), what)
    }

    fn spawn(&mut self, tag: u64, group: &SceneDef) -> Result<()> {
        let mut ids = Vec::with_capacity(group.bodies.len());
        for (i, b) in group.bodies.iter().enumerate() {
            let id = create_body(
                &mut self.world,
                self.foundation,
                i,
                b,
                self.sleep,
                &self.settings,
            )?;
            ids.push(id);
        }
        let h = self.dt / self.substeps.max(1) as f32;
        create_joints(&mut self.world, &ids, group, &self.settings, h)?;
        self.spawned.entry(tag).or_default().extend(ids);
        Ok(())
    }

    fn despawn(&mut self, tag: u64) -> Result<()> {
        for id in self.spawned.remove(&tag).unwrap_or_default() {
            let body = ok(self.world.body(id), "Box2D body of a group")?;
            ok(body.destroy(), "Box2D body destroyed")?;
        }
        Ok(())
    }
}

impl Peer for Box2d {
    fn step(&mut self) -> Result<()> {
        if let Some(script) = self.script {
            script(self.steps, self)?;
        }
        self.steps += 1;
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
            (
                "events",
                ms(p.sensors) + ms(p.sensor_hits) + ms(p.hit_events) + ms(p.joint_events),
            ),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tumble_physics::{BodyDef, BodyId, Limits, SceneDef, ShapeDef as TumbleShape, World};

    /// Bodies that each touch only the static ground, 5 m apart: a box at rest, a box sliding
    /// at 3 m/s, a box tipped on a corner and a circle thrown spinning. (A box dropped on
    /// its face with restitution 0.5 is left out: the two engines agree on it to 7e-7 m for
    /// its first steps, then part by 3e-5 m in one step as it bounces, a threshold decision
    /// flipped by a last-bit difference.) No two constraints share a dynamic body, so every
    /// order of solving them gives the same result. Each starts 1 mm above the ground: within
    /// the speculative distance (2 cm), which both engines use; a body approaching faster than
    /// that in a step meets it earlier in tumble, whose speculative margin also grows with the
    /// closing speed (both sweep fast bodies too, but none here is fast).
    fn apart() -> SceneDef {
        let mut scene = SceneDef::new("apart");
        // The solver's motion only: nothing falls asleep part way.
        scene.sleep = false;
        let unit = TumbleShape::Box {
            half_extents: [0.5, 0.5],
            radius: 0.0,
        };
        scene.push(
            BodyDef::new(TumbleShape::Box {
                half_extents: [100.0, 1.0],
                radius: 0.0,
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
        // Box2D solves a manifold's points one after the other.
        tumble.settings_mut().solve_points_together = false;
        let mut box2d = Box2d::new(&scene, tumble.settings(), 1).unwrap();
        let mut worst = 0.0f32;
        for _ in 0..120 {
            tumble.step(scene.dt, scene.substeps);
            box2d.step().unwrap();
            for i in 1..scene.bodies.len() {
                let t = tumble.body(BodyId::scene(i)).unwrap();
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
