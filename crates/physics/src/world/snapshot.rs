//! Snapshots: everything that decides a world's future, as plain serde data.

use super::stores::AppliedForce;
use super::{
    BodyRecord, BodySim, Contact, ContactKey, NONE, ShapeRecord, StepSettings, World, pair_key,
};
use crate::body::BodyState;
use crate::def::BodyKind;
use crate::error::SceneError;
use crate::id::Slots;
use crate::island::Islands;
use crate::shape::{Aabb, Shape};
use crate::solver::{BodyMotion, SolverBody};

/// Everything that decides a world's future, as plain serde data: bodies, shapes, ids and
/// their free slots, contacts with their warm-start impulses and recycling caches, islands
/// and who sleeps, and the broad phase's pending moves. Restoring it and stepping gives
/// bit-identical states to never having stopped. The thread count is not part of it (it
/// never changes results). The encoding is the caller's choice.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct WorldSnapshot {
    pub(super) settings: StepSettings,
    body_slots: Slots,
    sims: Vec<BodySim>,
    pub(super) states: Vec<BodyState>,
    records: Vec<BodyRecord>,
    solver_bodies: Vec<SolverBody>,
    motion: Vec<BodyMotion>,
    awake: Vec<bool>,
    shape_slots: Slots,
    shapes: Vec<Shape>,
    shape_records: Vec<ShapeRecord>,
    fat_aabbs: Vec<Aabb>,
    core_aabbs: Vec<Aabb>,
    moved: Vec<u32>,
    contacts: Vec<Contact>,
    islands: Islands,
    steps: u64,
    /// The last step's length (absent from snapshots written before it was kept: 1/60).
    #[serde(default = "sixtieth")]
    last_dt: f32,
    speed_caps: u64,
    /// Bodies the numerical guard has stopped (see [`World::non_finite_bodies`]); absent
    /// from snapshots written before it was counted, which read as 0.
    #[serde(default)]
    non_finite_bodies: u64,
    /// Joints with their impulses (absent from snapshots written before joints: none).
    #[serde(default)]
    joint_slots: Slots,
    #[serde(default)]
    joints: Vec<crate::joint::Joint>,
    /// The last step's substep rate, which the joints' reaction forces are read with.
    #[serde(default)]
    last_inv_h: f32,
    /// Each sensor shape's overlaps (absent from snapshots written before sensors detected
    /// anything: every sensor then starts with none).
    #[serde(default)]
    sensors: super::events::SensorOverlaps,
    /// Contacts (by their shapes' pair, with the step they began) that began and have not
    /// pushed: hits still to judge.
    #[serde(default)]
    unpushed_hits: Vec<(u64, u64)>,
    /// Forces and torques applied since the last step, by body slot, in the order given.
    #[serde(default)]
    forces: Vec<(u32, AppliedForce)>,
}

impl WorldSnapshot {
    /// Bytes its arrays hold in memory (their lengths times their element sizes): what a
    /// caller keeping many snapshots (the viewer's replay) budgets with.
    pub fn approx_bytes(&self) -> usize {
        use std::mem::size_of_val;
        std::mem::size_of::<Self>()
            + size_of_val(&self.sims[..])
            + size_of_val(&self.states[..])
            + size_of_val(&self.records[..])
            + size_of_val(&self.solver_bodies[..])
            + size_of_val(&self.motion[..])
            + size_of_val(&self.awake[..])
            + size_of_val(&self.shapes[..])
            + size_of_val(&self.shape_records[..])
            + size_of_val(&self.fat_aabbs[..])
            + size_of_val(&self.core_aabbs[..])
            + size_of_val(&self.moved[..])
            + size_of_val(&self.contacts[..])
            + self
                .islands
                .islands
                .iter()
                .map(|i| 4 * i.bodies.len())
                .sum::<usize>()
            + 4 * self.islands.of_body.len()
    }

    /// Live bodies in the snapshot.
    pub fn body_count(&self) -> usize {
        self.body_slots.live()
    }
}

/// Snapshots: the whole world as plain data, to save, restore and continue bit for bit.
///
/// ```
/// use tumble_physics::{BodyDef, ShapeDef, StepSettings, World};
///
/// let mut world = World::new(StepSettings::default());
/// world.create_body(&BodyDef::new(ShapeDef::Circle { radius: 0.5 }).at(0.0, 3.0)).unwrap();
/// world.step(1.0 / 60.0, 4);
/// let mut copy = World::from_snapshot(world.snapshot()).unwrap();
/// for _ in 0..30 {
///     world.step(1.0 / 60.0, 4);
///     copy.step(1.0 / 60.0, 4);
/// }
/// assert_eq!(world.state_hash(), copy.state_hash());
/// ```
impl World {
    /// The world's state, to save and restore (see [`WorldSnapshot`]).
    pub fn snapshot(&self) -> WorldSnapshot {
        WorldSnapshot {
            settings: self.settings,
            body_slots: self.bodies.slots.clone(),
            sims: self.bodies.sims.clone(),
            states: self.bodies.states.clone(),
            records: self.bodies.records.clone(),
            solver_bodies: self.bodies.masses.clone(),
            motion: self.bodies.motion.clone(),
            awake: self.bodies.awake.clone(),
            shape_slots: self.shapes.slots.clone(),
            shapes: self.shapes.geometry.clone(),
            shape_records: self.shapes.records.clone(),
            fat_aabbs: self.shapes.swept_boxes.clone(),
            core_aabbs: self.shapes.unswept_boxes.clone(),
            moved: self.shapes.moved_proxies.clone(),
            contacts: self.contacts.list.clone(),
            islands: self.islands.clone(),
            steps: self.stats.steps,
            last_dt: self.stats.last_dt,
            speed_caps: self.stats.speed_caps,
            non_finite_bodies: self.stats.non_finite_bodies,
            joint_slots: self.joints.slots.clone(),
            // The solver's live copies where it holds them (their impulses are current).
            joints: (0..self.joints.list.len())
                .map(|k| self.current(k).clone())
                .collect(),
            last_inv_h: self.joints.last_inv_h,
            sensors: self.sensors.clone(),
            unpushed_hits: self.events.unpushed.clone(),
            forces: self
                .bodies
                .forced
                .iter()
                .map(|&i| (i, self.bodies.forces[i as usize]))
                .collect(),
        }
    }

    /// A world in the state of `snapshot`, on all cores. Fails if the snapshot's arrays do
    /// not agree (a corrupt or foreign file: lengths, contacts or shapes naming bodies it
    /// lacks, a broken island), or if its settings are out of range
    /// ([`StepSettings::validate`]).
    pub fn from_snapshot(mut snapshot: WorldSnapshot) -> Result<World, SceneError> {
        snapshot.settings.validate()?;
        let corrupt = |why: String| SceneError::Scene {
            field: "snapshot".into(),
            value: format!("inconsistent ({why})"),
            allowed: "a snapshot written by World::snapshot".into(),
        };
        let n = snapshot.sims.len();
        let body_lengths = [
            snapshot.states.len(),
            snapshot.records.len(),
            snapshot.solver_bodies.len(),
            snapshot.motion.len(),
            snapshot.awake.len(),
            snapshot.body_slots.len(),
        ];
        if body_lengths.iter().any(|&l| l != n) {
            return Err(corrupt("body arrays of different lengths".into()));
        }
        let m = snapshot.shapes.len();
        if [
            snapshot.shape_records.len(),
            snapshot.fat_aabbs.len(),
            snapshot.core_aabbs.len(),
            snapshot.shape_slots.len(),
        ]
        .iter()
        .any(|&l| l != m)
        {
            return Err(corrupt("shape arrays of different lengths".into()));
        }
        let live_shape = |s: u32| snapshot.shape_slots.is_alive(s as usize);
        let bad_shape = snapshot.shapes.iter().enumerate().any(|(s, shape)| {
            let r = &snapshot.shape_records[s];
            let bad_geometry = match shape {
                Shape::Polygon(p) => {
                    !((3..=crate::MAX_POLYGON_VERTICES).contains(&p.count)
                        && p.radius.is_finite()
                        && p.radius >= 0.0)
                }
                Shape::Circle(c) => !(c.radius.is_finite() && c.radius > 0.0),
                Shape::Capsule(c) => {
                    !(c.radius.is_finite() && c.radius > 0.0)
                        || (c.center2 - c.center1).length() < crate::LINEAR_SLOP
                }
                Shape::Segment(seg) => (seg.point2 - seg.point1).length() < crate::LINEAR_SLOP,
                Shape::ChainSegment(c) => {
                    (c.segment.point2 - c.segment.point1).length() < crate::LINEAR_SLOP
                }
            };
            live_shape(s as u32)
                && (bad_geometry
                    || r.body as usize >= n
                    || !snapshot.body_slots.is_alive(r.body as usize)
                    || (r.next != NONE && !live_shape(r.next)))
        });
        let bad_contact = snapshot.contacts.iter().any(|c| {
            !live_shape(c.shape_a)
                || !live_shape(c.shape_b)
                || c.body_a as usize >= n
                || c.body_b as usize >= n
                || c.manifold.count > 2
        });
        let bad_list = snapshot.records.iter().enumerate().any(|(i, r)| {
            snapshot.body_slots.is_alive(i) && r.first_shape != NONE && !live_shape(r.first_shape)
        });
        if bad_shape || bad_contact || bad_list || snapshot.moved.iter().any(|&s| !live_shape(s)) {
            return Err(corrupt(
                "a shape or contact names what does not exist".into(),
            ));
        }
        if snapshot.islands.of_body.len() > n
            || snapshot
                .islands
                .islands
                .iter()
                .flat_map(|i| &i.bodies)
                .any(|&b| b as usize >= n)
        {
            return Err(corrupt("an island names a body that does not exist".into()));
        }
        let bad_joint = snapshot.joints.len() != snapshot.joint_slots.len()
            || snapshot.joints.iter().enumerate().any(|(k, j)| {
                let live = |b: u32| (b as usize) < n && snapshot.body_slots.is_alive(b as usize);
                snapshot.joint_slots.is_alive(k) && !(live(j.body_a) && live(j.body_b))
            });
        if bad_joint {
            return Err(corrupt("a joint names a body that does not exist".into()));
        }
        if !World::steppable(snapshot.last_dt, 1) {
            return Err(corrupt(format!("last step length {}", snapshot.last_dt)));
        }
        snapshot.islands.recount();
        snapshot.islands.check().map_err(corrupt)?;
        let mut world = World::new(snapshot.settings);
        let mut moved_flags = vec![false; m];
        for &s in &snapshot.moved {
            moved_flags[s as usize] = true;
        }
        world.contacts.pairs = snapshot
            .contacts
            .iter()
            .enumerate()
            .map(|(k, c)| (pair_key(c.shape_a, c.shape_b), k as u32))
            .collect();
        world.bodies.slots = snapshot.body_slots;
        world.bodies.sims = snapshot.sims;
        world.bodies.states = snapshot.states;
        world.bodies.records = snapshot.records;
        world.bodies.masses = snapshot.solver_bodies;
        world.bodies.motion = snapshot.motion;
        world.bodies.awake = snapshot.awake;
        world.bodies.forces = vec![AppliedForce::default(); n];
        for &(i, f) in &snapshot.forces {
            let live = (i as usize) < n && world.bodies.slots.is_alive(i as usize);
            if live && f.force.is_finite() && f.torque.is_finite() {
                world.bodies.add_force(i, f.force, f.torque);
            }
        }
        world.bodies.kinematic_count = (0..n)
            .filter(|&i| {
                world.bodies.slots.is_alive(i) && world.bodies.sims[i].kind == BodyKind::Kinematic
            })
            .count();
        world.shapes.body = snapshot.shape_records.iter().map(|r| r.body).collect();
        world.shapes.slots = snapshot.shape_slots;
        world.shapes.geometry = snapshot.shapes;
        world.shapes.records = snapshot.shape_records;
        world.shapes.swept_boxes = snapshot.fat_aabbs;
        world.shapes.unswept_boxes = snapshot.core_aabbs;
        world.shapes.moved_proxies = snapshot.moved;
        world.shapes.moved_flags = moved_flags;
        world.shapes.searched_boxes = vec![[Aabb::NOWHERE; 2]; m];
        world.contacts.list = snapshot.contacts;
        for c in &mut world.contacts.list {
            c.masses = [
                world.bodies.masses[c.body_a as usize],
                world.bodies.masses[c.body_b as usize],
            ];
        }
        world.contacts.keys = world
            .contacts
            .list
            .iter()
            .map(|c| ContactKey::of(c, &world.bodies.awake))
            .collect();
        world.islands = snapshot.islands;
        world.islands.grow(n);
        world.stats.steps = snapshot.steps;
        world.stats.last_dt = snapshot.last_dt;
        world.stats.speed_caps = snapshot.speed_caps;
        world.stats.non_finite_bodies = snapshot.non_finite_bodies;
        for (k, j) in snapshot.joints.iter().enumerate() {
            if snapshot.joint_slots.is_alive(k) && !j.collide_connected {
                *world
                    .joints
                    .no_collide
                    .entry(pair_key(j.body_a, j.body_b))
                    .or_insert(0) += 1;
            }
        }
        world.joints.last_inv_h = snapshot.last_inv_h;
        // Every live sensor shape, and no other, is tracked.
        world.sensors = snapshot.sensors;
        world.events.unpushed = snapshot.unpushed_hits;
        let is_sensor = |s: usize| world.shapes.slots.is_alive(s) && world.shapes.records[s].sensor;
        world.sensors.retain(|&s, _| is_sensor(s as usize));
        for s in 0..world.shapes.geometry.len() {
            if is_sensor(s) {
                world.sensors.entry(s as u32).or_default();
            }
        }
        world.joints.slots = snapshot.joint_slots;
        world.joints.list = snapshot.joints;
        world.shapes.proxies_changed = true;
        world.shapes.static_tree_stale = true;
        world.shapes.tree_dirty = true;
        let live = |s: &usize| world.shapes.slots.is_alive(*s);
        world.shapes.any_surface = (0..world.shapes.records.len()).filter(live).any(|s| {
            let r = &world.shapes.records[s];
            r.tangent_speed != 0.0 || r.rolling_resistance > 0.0
        });
        Ok(world)
    }
}

/// A sixtieth of a second: the step length a snapshot without one assumes.
fn sixtieth() -> f32 {
    1.0 / 60.0
}
