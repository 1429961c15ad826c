//! A scene in Rapier2D (feature `parallel`).
//!
//! Mapping: each tumble body is one rigid body (fixed, dynamic, or kinematic velocity-based)
//! at the body frame's position and angle, with its velocity (both take the centre of mass's),
//! damping, `gravity_scale` and `fixed_rotation` (`lock_rotations`), and one collider per part
//! ([`part_shape`]) placed in the body's frame: boxes are cuboids at the part's offset and
//! angle, polygons convex polylines of their vertices in the body's frame (a body of one
//! shape: tumble's centroid-recentred vertices; counter-clockwise, as the scene requires),
//! circles balls at their centre; rounded boxes and polygons Rapier's round cuboids and round
//! convex polylines (the same core grown by the radius), capsules capsules between the same
//! centres, segments segments, chains oriented polylines (one-sided, pushing to the right of
//! each segment, as Box2D's chains; an open chain's two end points, Box2D's ghosts, left out).
//! Rapier computes the mass, centre of mass and inertia from
//! the colliders' densities as tumble does. Friction: each collider gets its part's coefficient
//! and `CoefficientCombineRule::GeometricMean`, which is exactly tumble's `sqrt(a * b)` for
//! every pair (equal coefficients or not). Restitution: `CoefficientCombineRule::Max`, tumble's
//! rule. A sensor part is a sensor collider (it still adds its mass, as in tumble and Box2D).
//!
//! Filters: Rapier's `InteractionGroups` are 32-bit `memberships` and `filter`, tested as
//! tumble tests `category` against `mask`. tumble's are 64-bit: the category bits the scene
//! uses are numbered into Rapier's 32 (kept as they are when they all lie in the low 32 bits;
//! a mask bit that no category uses can never match, so dropping it changes nothing), and a
//! scene whose categories use more than 32 distinct bits is refused. Box2D's group rule
//! (two shapes of one non-zero group always touch when it is positive, never when negative,
//! whatever their categories) has no counterpart in the groups: a collider of a non-zero group
//! gets all groups, and a contact pair filter hook (`ActiveHooks::FILTER_CONTACT_PAIRS`,
//! [`GroupRule`]) applies the whole rule to its pairs from each collider's filter packed into
//! `user_data`. Only scenes with a non-zero group step with the hook.
//!
//! Sleep: a world that does not sleep (`sleep: false`) and a body with `enable_sleep: false`
//! get `can_sleep(false)` (Rapier's thresholds at -1); a body with `awake: false` starts
//! asleep (`sleeping(true)`) where tumble starts it asleep (a dynamic body in a world that
//! sleeps), even when it may not fall asleep again. The thresholds: Rapier's
//! `normalized_linear_threshold` is the scene's `solver.sleep_threshold` (length unit 1 m;
//! 0.05 m/s, Box2D's and tumble's default, is also Rapier's) and `time_until_sleep` its
//! `time_to_sleep` (0.5 s, also Rapier's default). The tests differ: tumble and Box2D let a
//! body rest when `max(|v|, |w| · extent)` stays below the threshold, Rapier when half its
//! farthest point's displacement over the step, `(|v| + |w| · extent) · dt / 2` roughly
//! (solver position corrections included), stays below `threshold · dt`: between the same and
//! twice as lenient, so Rapier may fall asleep sooner. Its angular threshold only gates
//! collider-less bodies (and a π/2 rad/s cap), so it keeps its default. Islands sleep as a
//! whole in all three.
//!
//! Integration: `dt` is the scene's; `num_solver_iterations` = the scene's substeps (Rapier's
//! substeps); continuous collision as the scene says, as tumble's and Box2D's: with the
//! scene's `continuous` on, `max_ccd_substeps = 1` (the world-wide switch) and every dynamic
//! body `ccd_enabled` (Rapier sweeps such a body against every collider, where tumble and
//! Box2D sweep a body that is not a `bullet` against static shapes only); with it off, neither.
//! Every collider has `ActiveEvents::COLLISION_EVENTS` (contacts and sensor overlaps that
//! begin or end, the events tumble and Box2D gather), sent to a channel that each step
//! drains; Rapier has no hit event by approach speed (its contact force events are by force),
//! so hits are the one kind of event it does not gather here. All other integration
//! parameters are Rapier's defaults. A scene with a
//! script ([`super::script`]) runs it before each step: junkyard's target transform becomes
//! the velocity that reaches it in one step, computed as tumble's
//! `World::set_target_transform` does; rain's groups are made as the scene's bodies and
//! joints are, and removed with `remove_body` (which takes their colliders and joints). The step runs inside a rayon pool of `threads` threads.
//!
//! Joints: impulse joints (`ImpulseJointSet`), created after the bodies from the joints tumble
//! builds ([`super::scene_joints`]: `JointDef::build`'s frames and defaults). Each is a
//! `GenericJoint` whose `local_frame1`/`local_frame2` are tumble's joint frames in each body's
//! origin frame, positions and angles (Rapier's typed builders, `RevoluteJointBuilder` and
//! the rest, set only anchors and axes: the frames would keep the bodies' angles, and a
//! limit would count from A's angle, not from the start), with `contacts_enabled` the
//! joint's `collide_connected`. The locked rows keep Rapier's own softness (1 MHz, damping
//! ratio 1: rigid). The scene's `solver.joint_hertz` and `joint_damping_ratio` are not passed
//! on, as the contact stiffness is not: Rapier's softness of a natural frequency and damping
//! ratio has Box2D's bias rate and softening, but Rapier keeps the softening in its
//! stabilization passes (Box2D's and tumble's relax passes solve the rigid rows rigidly),
//! where it lets a row's accumulated impulse leak away: at 60 Hz and 2, joint_grid's 100
//! rows of discs hung 11 m lower than tumble's after 2 s, against 2 m with Rapier's softness.
//!
//! Springs are acceleration-based position motors of stiffness `ω²` and damping `2ζω`
//! ([`spring`]): that model scales both by the row's effective mass, so each row's bias and
//! softening are exactly Box2D's soft row of that hertz and damping ratio over the same
//! substep (Rapier's solver runs its joints with the substep as `dt`), and a motor keeps its
//! bias in the stabilization passes, as Box2D's springs act in its relax pass. A slack spring
//! (0 Hz, which acts on nothing in Box2D and tumble) is left out. Motors are velocity motors
//! of infinite strength (damping `f32::MAX`), bounded by their torque or force: Box2D's rigid
//! motor row. Rapier has one motor per axis of a joint: a spring and a motor on the same axis
//! become two joints of the same frames, the second locking nothing ([`drive`]). Per type:
//! - Revolute: the revolute axes locked, the limit on the angle, spring and motor on it.
//! - Prismatic: the prismatic axes locked (across the axis, and the angle), limit, spring and
//!   motor along the axis.
//! - Wheel: Rapier has no wheel joint; its pin-slot axes are one: only the direction across
//!   the axis locked, the suspension a spring along the axis (1 Hz, 0.7 when the scene gives
//!   none, as tumble and Box2D), the limit along it, the motor on the free angle.
//! - Distance: Rapier's coupled linear axes (its rope and spring joints'), the frames at the
//!   anchors. With a spring, the spring at the length and, with a limit, the coupled limit,
//!   which holds only an upper bound: a lower bound above the linear slop (5 mm, Box2D's
//!   least length) is refused with an error naming the joint. Without one, rigid: a position
//!   motor at the length as stiff as the rigid rows (the scene's joint hertz and damping ratio,
//!   capped at a quarter of the substep rate as in Box2D), as no coupled row holds a length
//!   both ways; a motor row keeps its bias in the stabilization passes, so this one does not
//!   leak.
//! - Weld: a rigid part (0 Hz) locked, a soft part a spring of its hertz and damping ratio
//!   (the linear one on each axis of A's frame: two rows, where Box2D solves one 2×2 block).
//! - Motor (Box2D v3.0's, tumble's): frame A at the target pose of B's origin in A's frame,
//!   frame B at B's origin, and on each of the three axes a position motor whose bias is
//!   `correction_factor / h` and softening 10⁻⁶, bounded by `max_force` on each linear axis
//!   of A's frame (Box2D bounds the linear impulse's length: Rapier's may reach √2 times it
//!   diagonally) and `max_torque`.
//! - Filter: a joint that locks nothing, with contacts off. Unlike Box2D's filter joint it
//!   ties the two bodies' islands.
//!
//! A joint that cannot be expressed is refused with an error naming the scene, the joint's
//! index and its type, never dropped.

use std::collections::HashMap;
use std::sync::mpsc::{Receiver, channel};

use anyhow::{Context, Result, bail};
use rapier2d::prelude::*;
use rapier2d::rayon;
use tumble_physics::{BodyKind, SceneDef};

use super::{PartShape, Peer, Script, Targets, part_shape, scene_joints, scene_settings};

/// A Rapier world holding a tumble scene.
pub struct Rapier {
    world: PhysicsWorld,
    handles: Vec<RigidBodyHandle>,
    pool: rayon::ThreadPool,
    /// Whether a collider has a non-zero group (the world steps with [`GroupRule`]).
    groups: bool,
    /// The scene's category bits in Rapier's numbering.
    bits: Bits,
    sleep: bool,
    settings: tumble_physics::StepSettings,
    /// The substep (s), for the joints made by a script.
    h: f32,
    script: Option<Script>,
    steps: u64,
    /// The bodies each tag's group made ([`Targets::spawn`]).
    spawned: HashMap<u64, Vec<RigidBodyHandle>>,
    /// Where Rapier sends its collision events (contacts and sensor overlaps that begin or
    /// end), read after each step as tumble's and Box2D's are.
    events: ChannelEventCollector,
    collisions: Receiver<CollisionEvent>,
    /// Kept so that the collector's other channels stay open (nothing asks for their events).
    _forces: Receiver<ContactForceEvent>,
    _tears: Receiver<SoftBodyTearEvent>,
    /// Collision events read so far: of contacts, of sensors (read by the tests).
    #[cfg_attr(not(test), allow(dead_code))]
    event_counts: [u64; 2],
}

/// Knobs of Rapier's solver that the accuracy report sweeps; `None` keeps Rapier's default.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Tuning {
    /// Contact spring frequency (Hz) against dynamic bodies; contacts with a fixed body get
    /// twice it, as Rapier's defaults (30 and 60 Hz) and tumble do.
    pub contact_hertz: Option<f32>,
    /// `num_internal_stabilization_iterations`: Rapier's unbiased passes per substep, the
    /// counterpart of tumble's and Box2D's relax pass.
    pub stabilization_iterations: Option<usize>,
    /// `normalized_max_corrective_velocity` (m/s): how fast overlap is pushed out.
    pub max_corrective_velocity: Option<f32>,
}

/// rapier2d's crate version.
pub fn version() -> &'static str {
    rapier2d::VERSION
}

/// tumble's 64-bit category bits numbered into Rapier's 32 groups.
struct Bits {
    /// The category bits some part of the scene uses, in order; `None`: all lie in the low
    /// 32 bits and keep their places.
    used: Option<Vec<u32>>,
}

impl Bits {
    fn of(scene: &SceneDef) -> Result<Bits> {
        let mut all = 0u64;
        for b in &scene.bodies {
            for p in b.parts() {
                all |= p.filter.category;
            }
        }
        if all >> 32 == 0 {
            return Ok(Bits { used: None });
        }
        if all.count_ones() > 32 {
            bail!(
                "the scene's filters use {} category bits; Rapier's interaction groups have 32",
                all.count_ones()
            );
        }
        Ok(Bits {
            used: Some((0..64).filter(|k| all >> k & 1 == 1).collect()),
        })
    }

    /// `bits` in Rapier's numbering (bits no category uses are dropped).
    fn map(&self, bits: u64) -> u32 {
        match &self.used {
            None => bits as u32,
            Some(used) => used
                .iter()
                .enumerate()
                .filter(|&(_, &k)| bits >> k & 1 == 1)
                .fold(0, |out, (i, _)| out | 1 << i),
        }
    }
}

/// A collider's filter in its `user_data`: Rapier-numbered category (bits 0-31) and mask
/// (32-63), and the group (64-127).
fn pack(category: u32, mask: u32, group: i64) -> u128 {
    u128::from(category) | u128::from(mask) << 32 | u128::from(group as u64) << 64
}

fn unpack(data: u128) -> (u32, u32, i64) {
    (data as u32, (data >> 32) as u32, (data >> 64) as u64 as i64)
}

/// Box2D's group rule as a Rapier contact pair filter (`b2ShouldShapesCollide`, tumble's
/// `Filter::should_collide`), on the filters packed into the colliders' `user_data`.
struct GroupRule;

impl PhysicsHooks for GroupRule {
    fn filter_contact_pair(&self, context: &PairFilterContext<'_>) -> Option<SolverFlags> {
        let (c1, m1, g1) = unpack(context.colliders[context.collider1].user_data);
        let (c2, m2, g2) = unpack(context.colliders[context.collider2].user_data);
        let touch = if g1 == g2 && g1 != 0 {
            g1 > 0
        } else {
            c1 & m2 != 0 && c2 & m1 != 0
        };
        touch.then_some(SolverFlags::COMPUTE_RIGID_IMPULSES)
    }
}

impl Rapier {
    /// Builds the scene.
    pub fn new(scene: &SceneDef, threads: usize) -> Result<Rapier> {
        Rapier::tuned(scene, threads, &Tuning::default())
    }

    /// Builds the scene with some of Rapier's solver knobs set (see [`Tuning`]).
    pub fn tuned(scene: &SceneDef, threads: usize, tuning: &Tuning) -> Result<Rapier> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .thread_name(|i| format!("rapier-bench-{i}"))
            .build()
            .context("cannot start Rapier's thread pool")?;
        let settings = scene_settings(scene)?;
        let mut world = PhysicsWorld {
            gravity: Vector::new(scene.gravity[0], scene.gravity[1]),
            ..PhysicsWorld::default()
        };
        let params = &mut world.integration_parameters;
        params.dt = scene.dt;
        params.num_solver_iterations = scene.substeps as usize;
        // Continuous collision as the scene says (see the module's note).
        params.max_ccd_substeps = usize::from(settings.continuous);
        if let Some(hertz) = tuning.contact_hertz {
            params.contact_softness.natural_frequency = hertz;
            params.static_contact_softness.natural_frequency = 2.0 * hertz;
        }
        if let Some(n) = tuning.stabilization_iterations {
            params.num_internal_stabilization_iterations = n;
        }
        if let Some(v) = tuning.max_corrective_velocity {
            params.normalized_max_corrective_velocity = v;
        }
        let bits = Bits::of(scene)?;
        let mut groups = false;
        let mut handles = Vec::with_capacity(scene.bodies.len());
        for (i, b) in scene.bodies.iter().enumerate() {
            let handle = create_body(&mut world, &bits, i, b, scene.sleep, &settings, &mut groups)?;
            handles.push(handle);
        }
        let h = scene.dt / scene.substeps.max(1) as f32;
        create_joints(&mut world, &handles, scene, &settings, h)?;
        let (collision_send, collisions) = channel();
        let (force_send, forces) = channel();
        let (tear_send, tears) = channel();
        Ok(Rapier {
            world,
            handles,
            pool,
            groups,
            bits,
            sleep: scene.sleep,
            settings,
            h,
            script: super::script(&scene.name),
            steps: 0,
            spawned: HashMap::new(),
            events: ChannelEventCollector::new(collision_send, force_send, tear_send),
            collisions,
            _forces: forces,
            _tears: tears,
            event_counts: [0; 2],
        })
    }

    /// Collision events read so far: contacts that began or ended touching, and sensor
    /// overlaps that began or ended.
    #[cfg(test)]
    pub fn event_counts(&self) -> [u64; 2] {
        self.event_counts
    }

    /// Bodies and impulse joints in the world.
    #[cfg(test)]
    pub fn counts(&self) -> (usize, usize) {
        (self.world.bodies.len(), self.world.impulse_joints.len())
    }

    /// Whether body `index` is awake (not `is_sleeping`).
    #[cfg(test)]
    pub fn is_awake(&self, index: usize) -> bool {
        !self.world.bodies[self.handles[index]].is_sleeping()
    }

    /// Body `index`'s mass and centre of mass in its frame.
    #[cfg(test)]
    pub fn mass(&self, index: usize) -> (f32, [f32; 2]) {
        let body = &self.world.bodies[self.handles[index]];
        let c = body.local_center_of_mass();
        (body.mass(), [c.x, c.y])
    }
}

/// A spring of `hertz` and damping ratio `zeta` as the stiffness and damping of Rapier's
/// acceleration-based motor model: `(ω², 2ζω)`, `ω = 2π hertz`. That model scales both by
/// the row's effective mass, so its bias `k / (hk + c) = ω / (hω + 2ζ)` and its softening
/// `1 / (h²k + hc) = 1 / (hω (hω + 2ζ))` are exactly Box2D's (and tumble's) soft row of that
/// hertz and damping ratio over the same substep `h`. `None` for a slack spring (hertz 0,
/// which acts on nothing in Box2D and tumble; Rapier's motor of zero stiffness and damping
/// would instead hold the rate rigidly).
fn spring(s: Option<tumble_physics::joint::Spring>) -> Option<(f32, f32)> {
    let s = s.filter(|s| s.hertz > 0.0)?;
    let omega = 2.0 * std::f32::consts::PI * s.hertz;
    Some((omega * omega, 2.0 * s.damping_ratio * omega))
}

/// Box2D's spring and motor on one axis of a joint: a position motor towards `target`
/// (`spring`: acceleration-based stiffness and damping, unbounded) and a velocity motor
/// (`motor`: speed and most force or torque) of infinite strength (damping `f32::MAX`: no
/// softening, Box2D's rigid motor row). Rapier has one motor per axis of a joint, so with both
/// the velocity motor goes on `bare`, a second joint of the same frames that locks nothing,
/// as Box2D solves them as two rows (the spring's unbounded); returns that joint when used.
fn drive(
    joint: &mut GenericJointBuilder,
    bare: impl FnOnce() -> GenericJointBuilder,
    axis: JointAxis,
    target: f32,
    spring: Option<(f32, f32)>,
    motor: Option<(f32, f32)>,
) -> Option<GenericJointBuilder> {
    let velocity = |j: GenericJointBuilder, (speed, max): (f32, f32)| {
        j.motor_model(axis, MotorModel::AccelerationBased)
            .motor_velocity(axis, speed, f32::MAX)
            .motor_max_force(axis, max)
    };
    if let Some((k, c)) = spring {
        *joint = (*joint)
            .motor_model(axis, MotorModel::AccelerationBased)
            .motor_position(axis, target, k, c);
        return motor.map(|m| velocity(bare(), m));
    }
    if let Some(m) = motor {
        *joint = velocity(*joint, m);
    }
    None
}

/// Creates tumble body `b` (the scene's `i`-th) with its colliders (see the module's
/// documentation), in a world that sleeps when `sleep` is on; sets `groups` when a collider
/// needs the group rule.
fn create_body(
    world: &mut PhysicsWorld,
    bits: &Bits,
    i: usize,
    b: &tumble_physics::BodyDef,
    sleep: bool,
    settings: &tumble_physics::StepSettings,
    groups: &mut bool,
) -> Result<RigidBodyHandle> {
    let builder = match b.kind {
        BodyKind::Static => RigidBodyBuilder::fixed(),
        BodyKind::Dynamic => RigidBodyBuilder::dynamic(),
        BodyKind::Kinematic => RigidBodyBuilder::kinematic_velocity_based(),
    };
    let asleep = !b.awake && sleep && b.kind == BodyKind::Dynamic;
    let mut builder = builder
        .translation(Vector::new(b.position[0], b.position[1]))
        .rotation(b.angle)
        .linvel(Vector::new(b.linear_velocity[0], b.linear_velocity[1]))
        .angvel(b.angular_velocity)
        .linear_damping(b.linear_damping)
        .angular_damping(b.angular_damping)
        .gravity_scale(b.gravity_scale)
        .can_sleep(true)
        .sleeping(asleep)
        .ccd_enabled(settings.continuous && b.kind == BodyKind::Dynamic);
    if b.fixed_rotation {
        builder = builder.lock_rotations();
    }
    let handle = world.insert_body(builder);
    for (k, part) in b.parts().iter().enumerate() {
        let what = || format!("Rapier body {i}, part {k}");
        let collider = match part_shape(part).with_context(what)? {
            PartShape::Box {
                half_extents: [hx, hy],
                center,
                angle,
                radius,
            } => if radius > 0.0 {
                ColliderBuilder::round_cuboid(hx, hy, radius)
            } else {
                ColliderBuilder::cuboid(hx, hy)
            }
            .translation(Vector::from(center))
            .rotation(angle),
            PartShape::Circle { center, radius } => {
                ColliderBuilder::ball(radius).translation(Vector::from(center))
            }
            PartShape::Polygon(points, radius) => {
                let points = points.into_iter().map(Vector::from).collect();
                if radius > 0.0 {
                    ColliderBuilder::round_convex_polyline(points, radius)
                } else {
                    ColliderBuilder::convex_polyline(points)
                }
                .with_context(|| format!("{}: the polygon is not convex for Rapier", what()))?
            }
            PartShape::Capsule {
                center1,
                center2,
                radius,
            } => ColliderBuilder::capsule_from_endpoints(
                Vector::from(center1),
                Vector::from(center2),
                radius,
            ),
            PartShape::Segment { point1, point2 } => {
                ColliderBuilder::segment(Vector::from(point1), Vector::from(point2))
            }
            PartShape::Chain { points, looped } => {
                // Rapier's oriented polyline: one-sided, pushing towards the right of
                // each segment, as a chain does, with pseudo-normals at its vertices
                // in place of ghost vertices. An open chain's end points, which only
                // shape Box2D's and tumble's end segments, are left out; a loop closes
                // by its indices.
                let mut vertices: Vec<Vector> = points.into_iter().map(Vector::from).collect();
                if !looped {
                    vertices.pop();
                    vertices.remove(0);
                }
                let n = vertices.len() as u32;
                let edges = if looped { n } else { n - 1 };
                let indices = (0..edges).map(|i| [i, (i + 1) % n]).collect();
                ColliderBuilder::oriented_polyline(vertices, Some(indices))
            }
        };
        let f = part.filter;
        let (category, mask) = (bits.map(f.category), bits.map(f.mask));
        let collider = collider
            .density(part.density)
            .friction(part.friction)
            .friction_combine_rule(CoefficientCombineRule::GeometricMean)
            .restitution(part.restitution)
            .restitution_combine_rule(CoefficientCombineRule::Max)
            .sensor(part.sensor)
            .active_events(ActiveEvents::COLLISION_EVENTS)
            .user_data(pack(category, mask, f.group));
        let collider = if f.group == 0 {
            collider.collision_groups(InteractionGroups::new(
                Group::from_bits_retain(category),
                Group::from_bits_retain(mask),
                InteractionTestMode::And,
            ))
        } else {
            *groups = true;
            collider
                .collision_groups(InteractionGroups::all())
                .active_hooks(ActiveHooks::FILTER_CONTACT_PAIRS)
        };
        world.insert_collider(collider, Some(handle));
    }
    // After the colliders (which could wake it): whether and when it may sleep.
    let activation = world.bodies[handle].activation_mut();
    if sleep && b.enable_sleep {
        activation.normalized_linear_threshold = settings.sleep_threshold;
        activation.time_until_sleep = settings.time_to_sleep;
    } else {
        activation.normalized_linear_threshold = -1.0;
        activation.angular_threshold = -1.0;
    }
    Ok(handle)
}

/// Creates the scene's joints (see the module's documentation) between the bodies `handles`.
fn create_joints(
    world: &mut PhysicsWorld,
    handles: &[RigidBodyHandle],
    scene: &SceneDef,
    settings: &tumble_physics::StepSettings,
    h: f32,
) -> Result<()> {
    use tumble_physics::JointKind;
    for (index, (joint, [body_a, body_b])) in scene_joints(scene, settings)?.iter().enumerate() {
        let what = || {
            format!(
                "scene {:?}, Rapier joint {index} ({})",
                scene.name,
                joint.kind.name()
            )
        };
        let frame =
            |t: &tumble_physics::Transform| Pose::new(Vector::new(t.p.x, t.p.y), t.q.angle());
        let generic = |locked: JointAxesMask| {
            GenericJointBuilder::new(locked)
                .local_frame1(frame(&joint.local_a))
                .local_frame2(frame(&joint.local_b))
                .contacts_enabled(joint.collide_connected)
        };
        let bare = || generic(JointAxesMask::empty());
        let mut built = Vec::with_capacity(2);
        match &joint.kind {
            JointKind::Revolute(r) => {
                let mut j = generic(JointAxesMask::LOCKED_REVOLUTE_AXES);
                if let Some(limit) = r.limit {
                    j = j.limits(JointAxis::AngX, limit);
                }
                let motor = r.motor.map(|m| (m.speed, m.max_torque));
                let extra = drive(
                    &mut j,
                    bare,
                    JointAxis::AngX,
                    r.target_angle,
                    spring(r.spring),
                    motor,
                );
                built.push(j);
                built.extend(extra);
            }
            JointKind::Prismatic(p) => {
                let mut j = generic(JointAxesMask::LOCKED_PRISMATIC_AXES);
                if let Some(limit) = p.limit {
                    j = j.limits(JointAxis::LinX, limit);
                }
                let motor = p.motor.map(|m| (m.speed, m.max_force));
                let extra = drive(
                    &mut j,
                    bare,
                    JointAxis::LinX,
                    p.target_translation,
                    spring(p.spring),
                    motor,
                );
                built.push(j);
                built.extend(extra);
            }
            JointKind::Wheel(w) => {
                // Rapier's pin-slot axes: only the direction across the axis is locked.
                let mut j = generic(JointAxesMask::LOCKED_PIN_SLOT_AXES);
                if let Some(limit) = w.limit {
                    j = j.limits(JointAxis::LinX, limit);
                }
                drive(&mut j, bare, JointAxis::LinX, 0.0, spring(w.spring), None);
                let motor = w.motor.map(|m| (m.speed, m.max_torque));
                drive(&mut j, bare, JointAxis::AngX, 0.0, None, motor);
                built.push(j);
            }
            JointKind::Distance(d) => {
                // The anchors' distance: Rapier's coupled linear axes (as its rope and spring
                // joints), the frames at the anchors.
                let mut j = bare().coupled_axes(JointAxesMask::LIN_AXES);
                let soft = d.spring.is_some() && d.limit.is_none_or(|[lo, hi]| lo < hi);
                if soft {
                    if let Some([lower, upper]) = d.limit {
                        if lower > tumble_physics::LINEAR_SLOP {
                            bail!(
                                "{}: a distance limit's lower bound ({lower} m) cannot be \
                                 expressed: Rapier's coupled linear limit holds only the upper \
                                 one",
                                what()
                            );
                        }
                        j = j.limits(JointAxis::LinX, [0.0, upper]);
                    }
                    drive(
                        &mut j,
                        bare,
                        JointAxis::LinX,
                        d.length,
                        spring(d.spring),
                        None,
                    );
                } else {
                    // A rod: a position motor of unbounded force at the length, as stiff as
                    // the rigid rows (Rapier's coupled limit holds only an upper bound).
                    let rod = Some(tumble_physics::joint::Spring {
                        hertz: joint.hertz.min(0.25 / h),
                        damping_ratio: joint.damping_ratio,
                    });
                    drive(&mut j, bare, JointAxis::LinX, d.length, spring(rod), None);
                }
                built.push(j);
            }
            JointKind::Weld(w) => {
                // A part of 0 Hz is locked; a soft part is a position motor (a spring that,
                // as Box2D's, also acts in the stabilization passes), on each of frame A's
                // axes for the linear part.
                let mut locked = JointAxesMask::empty();
                if w.linear_hertz == 0.0 {
                    locked |= JointAxesMask::LIN_AXES;
                }
                if w.angular_hertz == 0.0 {
                    locked |= JointAxesMask::ANG_AXES;
                }
                let mut j = generic(locked);
                let linear = spring(Some(tumble_physics::joint::Spring {
                    hertz: w.linear_hertz,
                    damping_ratio: w.linear_damping_ratio,
                }));
                for axis in [JointAxis::LinX, JointAxis::LinY] {
                    drive(&mut j, bare, axis, 0.0, linear, None);
                }
                let angular = spring(Some(tumble_physics::joint::Spring {
                    hertz: w.angular_hertz,
                    damping_ratio: w.angular_damping_ratio,
                }));
                drive(&mut j, bare, JointAxis::AngX, 0.0, angular, None);
                built.push(j);
            }
            JointKind::Motor(m) => {
                // Box2D v3.0's motor joint (tumble's): frame A at the target pose of B's
                // origin in A's frame, frame B at B's origin, and on each of the three axes a
                // row `Cdot + (correction / h) C = 0` bounded by the force or torque. Rapier's
                // acceleration-based position motor `(k, c)` has the bias `k / (hk + c)` and
                // the softening `1 / (h²k + hc)`: `k = c_f / (h² ε)`, `c = (1 − c_f) / (h ε)`
                // give the bias `c_f / h` and a softening `ε`, here 10⁻⁶ (rigid). Rapier bounds
                // each linear axis of frame A on its own: the force may reach √2 × max_force
                // diagonally, where Box2D bounds its length.
                const EPSILON: f32 = 1.0e-6;
                let cf = m.correction_factor;
                let (k, c) = (cf / (h * h * EPSILON), (1.0 - cf) / (h * EPSILON));
                let target = Pose::new(
                    Vector::new(m.linear_offset.x, m.linear_offset.y),
                    m.angular_offset,
                );
                let mut j = bare().local_frame1(target).local_frame2(Pose::IDENTITY);
                for (axis, max) in [
                    (JointAxis::LinX, m.max_force),
                    (JointAxis::LinY, m.max_force),
                    (JointAxis::AngX, m.max_torque),
                ] {
                    j = j
                        .motor_model(axis, MotorModel::AccelerationBased)
                        .motor_position(axis, 0.0, k, c)
                        .motor_max_force(axis, max);
                }
                built.push(j);
            }
            JointKind::Filter => {
                // Nothing locked: only keeps the two bodies from touching.
                built.push(bare().contacts_enabled(false));
            }
            JointKind::Mouse(_) => bail!("{}: a scene has no mouse joints", what()),
        }
        let (a, b) = (handles[*body_a], handles[*body_b]);
        for j in built {
            world.insert_impulse_joint(a, b, j.build());
        }
    }
    Ok(())
}

impl Targets for Rapier {
    fn body_count(&self) -> usize {
        self.handles.len()
    }

    /// As tumble's `World::set_target_transform`: the centre of mass's velocity to reach the
    /// target's centre of mass in `dt`, and the short way round to its angle.
    fn set_target_transform(
        &mut self,
        index: usize,
        position: [f32; 2],
        angle: f32,
        dt: f32,
    ) -> Result<()> {
        if !(dt.is_normal() && dt > 0.0) {
            bail!("Rapier target transform: a time step > 0, not {dt}");
        }
        let body = &mut self.world.bodies[self.handles[index]];
        let q = Rotation::new(angle);
        let target = Vector::from(position) + q * body.local_center_of_mass();
        let v = (target - body.center_of_mass()) / dt;
        let turn = body.rotation().inverse() * q;
        let w = turn.sin().atan2(turn.cos()) / dt;
        body.set_linvel(v, true);
        body.set_angvel(w, true);
        Ok(())
    }

    fn spawn(&mut self, tag: u64, group: &SceneDef) -> Result<()> {
        // Its filters are numbered as the scene's: a category the scene does not use would
        // be lost.
        let mut used = 0u64;
        for b in &group.bodies {
            for p in b.parts() {
                used |= p.filter.category;
            }
        }
        if self.bits.map(used).count_ones() != used.count_ones() {
            bail!("Rapier: a group made at run time uses category bits the scene does not");
        }
        let mut handles = Vec::with_capacity(group.bodies.len());
        for (i, b) in group.bodies.iter().enumerate() {
            let handle = create_body(
                &mut self.world,
                &self.bits,
                i,
                b,
                self.sleep,
                &self.settings,
                &mut self.groups,
            )?;
            handles.push(handle);
        }
        create_joints(&mut self.world, &handles, group, &self.settings, self.h)?;
        self.spawned.entry(tag).or_default().extend(handles);
        Ok(())
    }

    fn despawn(&mut self, tag: u64) -> Result<()> {
        for handle in self.spawned.remove(&tag).unwrap_or_default() {
            // With its colliders and joints.
            self.world.remove_body(handle);
        }
        Ok(())
    }
}

impl Peer for Rapier {
    fn step(&mut self) -> Result<()> {
        if let Some(script) = self.script {
            script(self.steps, self)?;
        }
        self.steps += 1;
        let (world, events) = (&mut self.world, &self.events);
        if self.groups {
            self.pool
                .install(|| world.step_with_events(&GroupRule, events));
        } else {
            self.pool.install(|| world.step_with_events(&(), events));
        }
        // The step's events, read as tumble's runner and Box2D's peer read theirs.
        while let Ok(event) = self.collisions.try_recv() {
            self.event_counts[usize::from(event.sensor())] += 1;
        }
        Ok(())
    }

    fn pose(&mut self, index: usize) -> Result<[f32; 3]> {
        let body = &self.world.bodies[self.handles[index]];
        let p = body.translation();
        Ok([p.x, p.y, body.rotation().angle()])
    }

    fn velocity(&mut self, index: usize) -> Result<[f32; 3]> {
        let body = &self.world.bodies[self.handles[index]];
        let v = body.linvel();
        Ok([v.x, v.y, body.angvel()])
    }
}
