//! Events: contacts that began or ended touching, hits, sensor overlaps that began or ended,
//! and the bodies that moved, gathered each step and read after it (Box2D v3's contact,
//! sensor and body events, `box2d/types.h`).
//!
//! Their order never depends on the thread count: contact events come from the serial pass
//! over the contacts in contact order (`update_touching`), hits in the order their contacts
//! began, and sensor events sensor by sensor (by shape slot), each sensor's visitors by shape
//! slot, joint thresholds by joint slot. A step's list is, in that order: contact begins and
//! ends (interleaved in contact order), hits, sensor ends and begins (interleaved by
//! visitor), then joints past their thresholds.
//!
//! The list holds the last step's events and any made since by a change between steps
//! (destroying a touching body ends its contacts at once, as Box2D's `b2DestroyContact`
//! reports); the next step clears it.

use std::collections::BTreeMap;

use glam::Vec2;

use super::query::shapes_overlap;
use super::{NONE, World, pair_key};
use crate::def::BodyKind;
use crate::id::{BodyId, JointId, ShapeId};
use crate::math::{Rot, Transform};

/// A shape as an event names it: its id, its body's id, and its place among the body's parts
/// (a scene's `shapes` index; 0 for a body with `shape`). Kept whole in the event, so an event
/// about a shape destroyed since still says what it was.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct ShapeRef {
    /// The shape.
    pub shape: ShapeId,
    /// Its body.
    pub body: BodyId,
    /// Its place among its body's parts.
    pub part: u32,
}

/// Something that happened in a step (see the module's documentation for the order).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Event {
    /// Two shapes began touching (their manifold gained points): the shapes' bodies in
    /// increasing slot order.
    ContactBegin {
        /// The two shapes, by body slot.
        shapes: [ShapeRef; 2],
    },
    /// Two shapes stopped touching, or their contact was destroyed while they touched (a
    /// body or shape destroyed, a joint made between them that keeps them apart).
    ContactEnd {
        /// The two shapes, by body slot.
        shapes: [ShapeRef; 2],
    },
    /// A contact began this step at an approach speed of at least the settings'
    /// `hit_speed` (and pushed: a speculative point that never met gives none).
    Hit {
        /// The two shapes, by body slot.
        shapes: [ShapeRef; 2],
        /// Where (the manifold point that approached fastest, in the world after the step).
        point: Vec2,
        /// The contact normal, from the first body towards the second.
        normal: Vec2,
        /// How fast the point approached along the normal before the step's solve (m/s).
        approach_speed: f32,
    },
    /// A shape began overlapping a sensor.
    SensorBegin {
        /// The sensor.
        sensor: ShapeRef,
        /// The shape that entered it.
        visitor: ShapeRef,
    },
    /// A shape stopped overlapping a sensor (or was destroyed while in it).
    SensorEnd {
        /// The sensor.
        sensor: ShapeRef,
        /// The shape that left it.
        visitor: ShapeRef,
    },
    /// A joint's reaction in the step passed its `force_threshold` or `torque_threshold`
    /// (Box2D v3.1's joint event). The joint is not destroyed: the game decides.
    JointThreshold {
        /// The joint.
        joint: JointId,
        /// The size of its reaction force in the step (N).
        force: f32,
        /// The size of its reaction torque in the step (N·m).
        torque: f32,
    },
}

impl Event {
    /// The event's name in the runner's event file (CONTRACT.md section 7).
    pub fn name(&self) -> &'static str {
        match self {
            Event::ContactBegin { .. } => "contact_begin",
            Event::ContactEnd { .. } => "contact_end",
            Event::Hit { .. } => "hit",
            Event::SensorBegin { .. } => "sensor_begin",
            Event::SensorEnd { .. } => "sensor_end",
            Event::JointThreshold { .. } => "joint_threshold",
        }
    }

    /// The two shapes it names: a contact's by body slot, a sensor's sensor first; none
    /// for a joint's.
    pub fn shapes(&self) -> Option<[ShapeRef; 2]> {
        match *self {
            Event::ContactBegin { shapes }
            | Event::ContactEnd { shapes }
            | Event::Hit { shapes, .. } => Some(shapes),
            Event::SensorBegin { sensor, visitor } | Event::SensorEnd { sensor, visitor } => {
                Some([sensor, visitor])
            }
            Event::JointThreshold { .. } => None,
        }
    }
}

/// A body that moved in the last step, as Box2D's `b2BodyMoveEvent`: every body the step
/// moved (the awake set's), with its pose after it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyMove {
    /// The body.
    pub body: BodyId,
    /// Its frame's origin (see [`super::BodyView::origin`]).
    pub origin: Vec2,
    /// Its orientation.
    pub rotation: Rot,
    /// It fell asleep at the end of the step (and will not move until woken).
    pub fell_asleep: bool,
}

/// Reads each of a world's events once: [`World::events`] holds the last step's events and
/// those made since (a body destroyed between steps ends its contacts at once), so a caller
/// that reads after each step and after its own changes would see some twice. The cursor
/// knows a step cleared the list by the world's step count.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EventCursor {
    /// The world's step count at the last read.
    step: u64,
    /// How many of its events were read then.
    read: usize,
}

impl EventCursor {
    /// The events `world` reported since this cursor last read it (all of them after a step).
    pub fn take<'w>(&mut self, world: &'w World) -> &'w [Event] {
        if world.step_count() != self.step {
            self.step = world.step_count();
            self.read = 0;
        }
        let events = world.events();
        let new = &events[self.read.min(events.len())..];
        self.read = events.len();
        new
    }
}

/// What the world keeps for its events.
#[derive(Clone, Debug, Default)]
pub(super) struct EventLog {
    /// The last step's events and those made since.
    pub events: Vec<Event>,
    /// The pairs (by `pair_key` of their shapes) whose contacts began touching and have not
    /// pushed yet, each with the world's step count when it began, in the order they began:
    /// the hit candidates (see `gather_hits`).
    pub unpushed: Vec<(u64, u64)>,
    /// The bodies the last step moved, ascending (read as `BodyMove`s by `World::body_moves`).
    pub body_moves: Vec<BodyId>,
    /// Scratch: a sensor's overlaps this step (kept, so that a steady step allocates
    /// nothing).
    pub found: Vec<ShapeRef>,
}

/// Each sensor shape (by slot) and the shapes overlapping it after the last step, sorted by
/// slot then generation. Part of a snapshot: a restored world reports no overlap again.
pub(super) type SensorOverlaps = BTreeMap<u32, Vec<ShapeRef>>;

/// Events: what the last step (and the changes made since) began, ended and hit, naming
/// shapes and bodies by id, in an order that is the same on any thread count.
///
/// ```
/// use tumble_physics::{BodyDef, BodyKind, Event, ShapeDef, StepSettings, World};
///
/// let mut world = World::new(StepSettings::default());
/// let ground = world
///     .create_body(&BodyDef::new(ShapeDef::Box { half_extents: [5.0, 0.5], radius: 0.0 }).kind(BodyKind::Static))
///     .unwrap();
/// let ball = world.create_body(&BodyDef::new(ShapeDef::Circle { radius: 0.5 }).at(0.0, 3.0)).unwrap();
/// let mut began = false;
/// for _ in 0..90 {
///     world.step(1.0 / 60.0, 4);
///     for event in world.events() {
///         if let Event::ContactBegin { shapes } = event {
///             assert_eq!([shapes[0].body, shapes[1].body], [ground, ball]);
///             began = true;
///         }
///     }
/// }
/// assert!(began);
/// ```
impl World {
    /// The last step's events, and any made since by changes between steps (see
    /// [`Event`] for what each means, and the module's documentation for their order,
    /// which is the same on any thread count). The next step clears them.
    pub fn events(&self) -> &[Event] {
        &self.events.events
    }

    /// The bodies the last step moved (every awake body; ascending slot), with their pose
    /// now and whether they fell asleep. A body destroyed since is left out.
    pub fn body_moves(&self) -> impl Iterator<Item = BodyMove> + '_ {
        self.events
            .body_moves
            .iter()
            .filter(|id| self.bodies.slots.holds(id.index, id.generation))
            .map(|&id| {
                let view = self.body_view(id.index as usize);
                BodyMove {
                    body: id,
                    origin: view.origin,
                    rotation: view.rotation,
                    fell_asleep: !view.awake && view.kind == BodyKind::Dynamic,
                }
            })
    }

    /// How shape slot `s` is named in an event.
    pub(super) fn shape_ref(&self, s: u32) -> ShapeRef {
        let r = &self.shapes.records[s as usize];
        ShapeRef {
            shape: ShapeId {
                index: s,
                generation: self.shapes.slots.generation(s as usize),
            },
            body: BodyId {
                index: r.body,
                generation: self.bodies.slots.generation(r.body as usize),
            },
            part: r.part,
        }
    }

    /// A contact's shapes as its events name them: by body slot.
    fn contact_shapes(&self, shape_a: u32, shape_b: u32) -> [ShapeRef; 2] {
        let (a, b) = (self.shape_ref(shape_a), self.shape_ref(shape_b));
        if a.body.index < b.body.index {
            [a, b]
        } else {
            [b, a]
        }
    }

    /// Records that the contact of shapes `shape_a` and `shape_b` began (`touching`) or
    /// stopped touching.
    pub(super) fn touch_changed(&mut self, shape_a: u32, shape_b: u32, touching: bool) {
        let shapes = self.contact_shapes(shape_a, shape_b);
        let event = if touching {
            let key = pair_key(shape_a, shape_b);
            self.events.unpushed.push((key, self.stats.steps));
            Event::ContactBegin { shapes }
        } else {
            Event::ContactEnd { shapes }
        };
        self.events.events.push(event);
    }

    /// Shape slot `s`'s pose in the world.
    pub(super) fn shape_pose(&self, s: u32) -> Transform {
        let r = &self.shapes.records[s as usize];
        r.pose(self.bodies.sims[r.body as usize].xf)
    }

    /// The step's first act: last step's events go.
    pub(super) fn clear_events(&mut self) {
        self.events.events.clear();
    }

    /// Hits (after the solve, which stored each point's approach speed): a contact that began
    /// is a hit the first step one of its points pushes (a speculative point that has not met
    /// yet pushes nothing), if that point approached at `hit_speed` or more. Box2D's
    /// `b2SolverStep` looks only in the step a contact began, and misses a hit whose
    /// speculative point met a step later. Here a contact stays a candidate while a point
    /// approaching at `hit_speed` could still be crossing its margin (the speculative
    /// distance plus one step's approach: a step more than `SPECULATIVE_DISTANCE / hit_speed`
    /// takes), which keeps this stage's cost to the contacts that began lately.
    pub(super) fn gather_hits(&mut self, dt: f32) {
        let threshold = self.settings.hit_speed;
        let window = if threshold > 0.0 {
            (crate::SPECULATIVE_DISTANCE / (threshold * dt)).ceil() as u64 + 1
        } else {
            u64::MAX
        };
        let mut candidates = std::mem::take(&mut self.events.unpushed);
        let mut keep = 0;
        for n in 0..candidates.len() {
            let (key, began) = candidates[n];
            if self.stats.steps - began > window {
                continue;
            }
            // Gone, ended, or already judged (a pair listed twice: its contact was destroyed
            // and made again between steps).
            let Some(&k) = self.contacts.pairs.get(&key) else {
                continue;
            };
            let c = &self.contacts.list[k as usize];
            if !(c.touched && c.hit_pending) {
                continue;
            }
            let m = &c.manifold;
            let mut best: Option<(f32, Vec2)> = None;
            for p in m.points() {
                let approach = -p.normal_velocity;
                if p.total_normal_impulse > 0.0 && best.is_none_or(|(s, _)| approach > s) {
                    best = Some((approach, p.anchor_a));
                }
            }
            let Some((approach_speed, anchor)) = best else {
                candidates[keep] = (key, began);
                keep += 1;
                continue;
            };
            if approach_speed >= threshold {
                let shapes = self.contact_shapes(c.shape_a, c.shape_b);
                // The manifold's normal points from shape A to shape B; the event's from the
                // first body to the second.
                let normal = if c.body_a < c.body_b {
                    m.normal
                } else {
                    -m.normal
                };
                let point = self.bodies.sims[c.body_a as usize].xf.p + anchor;
                self.events.events.push(Event::Hit {
                    shapes,
                    point,
                    normal,
                    approach_speed,
                });
            }
            self.contacts.list[k as usize].hit_pending = false;
        }
        candidates.truncate(keep);
        self.events.unpushed = candidates;
    }

    /// Notes the bodies this step moved (the awake set finalize walked).
    pub(super) fn note_body_moves(&mut self) {
        let log = &mut self.events;
        log.body_moves.clear();
        log.body_moves
            .extend(self.bodies.awake_set.iter().map(|&b| BodyId {
                index: b,
                generation: self.bodies.slots.generation(b as usize),
            }));
    }

    /// Starts tracking shape `s` as a sensor (it has no overlaps yet).
    pub(super) fn add_sensor(&mut self, s: u32) {
        self.sensors.insert(s, Vec::new());
    }

    /// Sensor overlaps (after finalize; reads poses, shapes, filters and the broad phase's
    /// tree; writes each sensor's overlaps and the sensor events): each sensor's box is
    /// queried in the tree, each candidate tested exactly, and the sorted result compared with
    /// the last step's (Box2D's `b2OverlapSensors`). A sensor detects the shapes of other
    /// bodies that are not sensors and whose filters let them touch, by `shapes_overlap`: a
    /// segment sensor (a tripwire) detects what crosses it, segments and chain segments too,
    /// and a chain segment is detected from either side. A world with no sensor skips this
    /// stage.
    pub(super) fn overlap_sensors(&mut self) {
        if self.sensors.is_empty() {
            return;
        }
        // The tree must hold this step's boxes (the next pair search would refit it anyway).
        self.refresh_tree();
        let mut sensors = std::mem::take(&mut self.sensors);
        let mut found = std::mem::take(&mut self.events.found);
        for (&s, overlaps) in sensors.iter_mut() {
            found.clear();
            let sensor = &self.shapes.records[s as usize];
            let pose = self.shape_pose(s);
            let aabb = self.shapes.geometry[s as usize].aabb(pose);
            // A disabled sensor sees nothing (its overlaps end); a disabled visitor is in no
            // tree.
            let live = !sensor.disabled;
            self.shapes
                .tree
                .query(&aabb, &self.shapes.swept_boxes, |v| {
                    if !live {
                        return;
                    }
                    let r = &self.shapes.records[v as usize];
                    if r.body == sensor.body
                        || r.body == NONE
                        || r.sensor
                        || !sensor.filter.should_collide(&r.filter)
                    {
                        return;
                    }
                    let (a, b) = (
                        &self.shapes.geometry[s as usize],
                        &self.shapes.geometry[v as usize],
                    );
                    if shapes_overlap(a, self.shape_pose(s), b, self.shape_pose(v)) {
                        found.push(self.shape_ref(v));
                    }
                });
            found.sort_unstable_by_key(|r| (r.shape.index, r.shape.generation));
            if found != *overlaps {
                let sensor = self.shape_ref(s);
                merge_changes(overlaps, &found, |visitor, began| {
                    self.events.events.push(if began {
                        Event::SensorBegin { sensor, visitor }
                    } else {
                        Event::SensorEnd { sensor, visitor }
                    });
                });
                overlaps.clone_from(&found);
            }
        }
        self.sensors = sensors;
        self.events.found = found;
    }
}

impl World {
    /// Joint thresholds (after the solve; reads the joints with a finite threshold, their
    /// reactions and their bodies' awake flags; writes joint events): an awake joint whose
    /// reaction force or torque in the step passed its threshold is reported, by joint slot
    /// (Box2D v3.1's `b2JointEvent`). A world with no threshold skips this.
    pub(super) fn gather_joint_thresholds(&mut self) {
        if self.joints.thresholded.is_empty() {
            return;
        }
        let inv_h = self.joints.last_inv_h;
        for n in 0..self.joints.thresholded.len() {
            let k = self.joints.thresholded[n] as usize;
            let j = self.current(k);
            let (awake, records) = (&self.bodies.awake, &self.bodies.records);
            let (a, b) = (j.body_a as usize, j.body_b as usize);
            // Neither asleep nor (a joint to a disabled body is not solved) disabled.
            if !(awake[a] || awake[b]) || records[a].disabled || records[b].disabled {
                continue;
            }
            let (f, t) = j.reaction(inv_h);
            let (force, torque) = (f.length(), t.abs());
            if force > j.force_threshold || torque > j.torque_threshold {
                let joint = JointId {
                    index: k as u32,
                    generation: self.joints.slots.generation(k),
                };
                self.events.events.push(Event::JointThreshold {
                    joint,
                    force,
                    torque,
                });
            }
        }
    }
}

/// Walks two sorted overlap lists, calling `f(visitor, began)` for each shape in `new` only
/// (began) or in `old` only (ended), in slot order; a slot held by another generation is one
/// shape ending and another beginning.
fn merge_changes(old: &[ShapeRef], new: &[ShapeRef], mut f: impl FnMut(ShapeRef, bool)) {
    let key = |r: &ShapeRef| (r.shape.index, r.shape.generation);
    let (mut i, mut j) = (0, 0);
    while i < old.len() || j < new.len() {
        match (old.get(i), new.get(j)) {
            (Some(o), Some(n)) if key(o) == key(n) => {
                i += 1;
                j += 1;
            }
            (Some(o), Some(n)) if key(o) < key(n) => {
                f(*o, false);
                i += 1;
            }
            (Some(o), None) => {
                f(*o, false);
                i += 1;
            }
            (_, Some(n)) => {
                f(*n, true);
                j += 1;
            }
            (None, None) => unreachable!("the loop runs while either list has items"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn r(index: u32, generation: u32) -> ShapeRef {
        ShapeRef {
            shape: ShapeId { index, generation },
            body: BodyId {
                index: 0,
                generation: 0,
            },
            part: 0,
        }
    }

    #[test]
    fn merging_overlap_lists_reports_ends_and_begins_in_slot_order() {
        // 1 stays, 3 ends, 4 begins, slot 5 changes hands (generation 0 ends, 1 begins).
        let old = [r(1, 0), r(3, 0), r(5, 0)];
        let new = [r(1, 0), r(4, 0), r(5, 1)];
        let mut seen = Vec::new();
        merge_changes(&old, &new, |v, began| {
            seen.push((v.shape.index, v.shape.generation, began))
        });
        assert_eq!(
            seen,
            [(3, 0, false), (4, 0, true), (5, 0, false), (5, 1, true)]
        );
    }
}

#[cfg(test)]
mod world_tests {
    use super::*;
    use crate::def::{BodyDef, Filter, PartDef, ShapeDef};
    use crate::world::StepSettings;

    const DT: f32 = 1.0 / 60.0;
    const G: f32 = 10.0;

    fn ground(w: &mut World) -> BodyId {
        w.create_body(
            &BodyDef::new(ShapeDef::Box {
                half_extents: [10.0, 0.5],
                radius: 0.0,
            })
            .kind(BodyKind::Static),
        )
        .unwrap()
    }

    fn unit_box() -> ShapeDef {
        ShapeDef::Box {
            half_extents: [0.5, 0.5],
            radius: 0.0,
        }
    }

    /// Steps once and returns the step's events.
    fn step(w: &mut World) -> Vec<Event> {
        w.step(DT, 4);
        w.events().to_vec()
    }

    #[test]
    fn a_dropped_box_begins_one_contact_and_hits_at_the_speed_it_fell_to() {
        let mut w = World::new(StepSettings::default());
        let g = ground(&mut w);
        // Its bottom 5 m above the ground's top (y = 0.5).
        let drop = 5.0;
        let b = w
            .create_body(&BodyDef::new(unit_box()).at(0.0, 1.0 + drop))
            .unwrap();
        let mut begins = Vec::new();
        let mut hits = Vec::new();
        for k in 1..=120 {
            for e in step(&mut w) {
                match e {
                    Event::ContactBegin { shapes } => begins.push((k, shapes)),
                    Event::Hit { .. } => hits.push((k, e)),
                    Event::ContactEnd { .. } => panic!("step {k}: {e:?}"),
                    _ => panic!("step {k}: no sensor here, yet {e:?}"),
                }
            }
        }
        assert_eq!(begins.len(), 1, "{begins:?}");
        let [first, second] = begins[0].1;
        assert_eq!((first.body, second.body), (g, b), "by body slot");
        assert_eq!((first.part, second.part), (0, 0));
        assert_eq!(hits.len(), 1, "{hits:?}");
        let (
            k,
            Event::Hit {
                shapes,
                point,
                normal,
                approach_speed,
            },
        ) = hits[0]
        else {
            unreachable!()
        };
        assert!(k >= begins[0].0, "the hit comes when the contact has begun");
        assert_eq!(shapes, begins[0].1);
        // Free fall: v = √(2 g h) = 10 m/s; the speed is read at a step boundary before the
        // impact, so up to one step's gravity (g dt) less, and the soft step's speculative
        // push may have begun (another g dt).
        let expected = (2.0 * G * drop).sqrt();
        assert!(
            approach_speed <= expected + 1e-3 && approach_speed > expected - 2.0 * G * DT,
            "approach {approach_speed} vs {expected}"
        );
        // From the ground (first) up to the box; the point where the manifold put it, midway
        // between the two faces when the contact was computed, up to a step's fall and the
        // speculative distance apart.
        assert!((normal - Vec2::Y).length() < 1e-6, "{normal}");
        let gap = crate::SPECULATIVE_DISTANCE + expected * DT;
        assert!(
            point.y >= 0.5 - crate::LINEAR_SLOP && point.y <= 0.5 + gap / 2.0,
            "{point}"
        );
        assert!(point.x.abs() <= 0.5 + 1e-4, "{point}");
        // Lifted off the ground between steps: the contact ends at the next step.
        w.set_transform(b, Vec2::new(0.0, 5.0), 0.0).unwrap();
        let events = step(&mut w);
        assert!(
            matches!(events[..], [Event::ContactEnd { shapes }] if shapes == begins[0].1),
            "{events:?}"
        );
    }

    #[test]
    fn a_slow_touch_begins_a_contact_without_a_hit() {
        let mut w = World::new(StepSettings::default());
        ground(&mut w);
        // Resting 1 cm above the ground: it meets it at ~0.45 m/s, under the 1 m/s default.
        w.create_body(&BodyDef::new(unit_box()).at(0.0, 1.01))
            .unwrap();
        let all: Vec<Event> = (0..60).flat_map(|_| step(&mut w)).collect();
        assert!(matches!(all[..], [Event::ContactBegin { .. }]), "{all:?}");
        // The threshold is the settings' (the scene's `hit_speed`): at 0.1 m/s it is a hit.
        let mut w = World::new(StepSettings {
            hit_speed: 0.1,
            ..StepSettings::default()
        });
        ground(&mut w);
        w.create_body(&BodyDef::new(unit_box()).at(0.0, 1.01))
            .unwrap();
        let all: Vec<Event> = (0..60).flat_map(|_| step(&mut w)).collect();
        assert!(
            matches!(all[..], [Event::ContactBegin { .. }, Event::Hit { .. }]),
            "{all:?}"
        );
    }

    /// A foot sensor on chain ground: a kinematic body at rest whose one shape is a sensor
    /// box of `width` x `height` centred `dy` above a chain along y = 0, stepped `steps`
    /// times. Returns the sensor events and the sensor's overlaps at the end.
    fn foot_on_chain(width: f32, height: f32, dy: f32, steps: usize) -> (Vec<Event>, usize) {
        let mut w = World::new(StepSettings::default());
        w.create_body(
            &BodyDef::compound(vec![PartDef::new(ShapeDef::Chain {
                points: vec![[-5.0, 0.0], [-1.0, 0.0], [1.0, 0.0], [5.0, 0.0]],
                looped: false,
            })])
            .kind(BodyKind::Static),
        )
        .unwrap();
        let foot = w
            .create_body(
                &BodyDef::compound(vec![
                    PartDef::new(ShapeDef::Box {
                        half_extents: [0.5 * width, 0.5 * height],
                        radius: 0.0,
                    })
                    .sensor(true),
                ])
                .kind(BodyKind::Kinematic)
                .at(0.3, dy),
            )
            .unwrap();
        let events: Vec<Event> = (0..steps).flat_map(|_| step(&mut w)).collect();
        let sensor = w.body_shapes(foot).unwrap().next().unwrap();
        (events, w.sensors.get(&sensor.id.index).map_or(0, Vec::len))
    }

    #[test]
    fn a_sensor_sees_chain_ground_under_a_box_of_any_size_from_either_side() {
        // The sizes the issue found blind (only 0.5 x 0.5 worked); the box straddles the
        // chain, its centre 1 cm above it or below it (a chain is one-sided; a sensor is not).
        for (width, height) in [(0.3, 0.05), (0.3, 0.3), (0.5, 0.1), (1.0, 0.1), (0.5, 0.5)] {
            for dy in [0.01, -0.01] {
                let (events, overlaps) = foot_on_chain(width, height, dy, 30);
                assert!(
                    matches!(events[..], [Event::SensorBegin { .. }]),
                    "{width} x {height} at {dy}: {events:?}"
                );
                assert_eq!(overlaps, 1, "{width} x {height} at {dy}");
            }
        }
        // 1 mm clear of the chain, it sees nothing.
        let (events, overlaps) = foot_on_chain(0.3, 0.05, 0.026, 30);
        assert!(events.is_empty() && overlaps == 0, "{events:?}");
    }

    /// A static sensor box spanning y in [2, 4], and a ball of radius 0.25 falling through it
    /// from y = 10 (nothing below).
    fn sensor_and_ball(ball_filter: Filter) -> (World, BodyId, BodyId) {
        let mut w = World::new(StepSettings::default());
        let sensor = w
            .create_body(
                &BodyDef::compound(vec![
                    PartDef::new(ShapeDef::Box {
                        half_extents: [1.0, 1.0],
                        radius: 0.0,
                    })
                    .sensor(true),
                ])
                .kind(BodyKind::Static)
                .at(0.0, 3.0),
            )
            .unwrap();
        let ball = w
            .create_body(
                &BodyDef::new(ShapeDef::Circle { radius: 0.25 })
                    .at(0.0, 10.0)
                    .filter(ball_filter),
            )
            .unwrap();
        (w, sensor, ball)
    }

    #[test]
    fn a_ball_falling_through_a_sensor_begins_and_ends_once_and_is_never_pushed() {
        let (mut w, sensor, ball) = sensor_and_ball(Filter::default());
        let mut seen = Vec::new();
        let mut heights = vec![10.0f32];
        for k in 1..=120 {
            for e in step(&mut w) {
                seen.push((k, e));
            }
            heights.push(w.body_view(ball.index as usize).position.y);
        }
        // Exactly when the world's own poses overlap the sensor (strictly: the ball's bottom
        // below the box's top, its top above the box's bottom).
        let inside = |y: f32| y - 0.25 < 4.0 && y + 0.25 > 2.0;
        let enter = (1..heights.len()).find(|&k| inside(heights[k])).unwrap();
        let leave = (enter..heights.len())
            .find(|&k| !inside(heights[k]))
            .unwrap();
        let refs = |e: &Event| e.shapes().unwrap().map(|r| r.body);
        assert_eq!(seen.len(), 2, "{seen:?}");
        assert!(matches!(seen[0].1, Event::SensorBegin { .. }));
        assert!(matches!(seen[1].1, Event::SensorEnd { .. }));
        assert_eq!((seen[0].0, seen[1].0), (enter, leave));
        assert_eq!(refs(&seen[0].1), [sensor, ball], "the sensor first");
        assert_eq!(refs(&seen[1].1), [sensor, ball]);
        // Free fall throughout: semi-implicit Euler over 4 substeps a step gives
        // y = y0 - g h² N(N+1)/2 after N substeps (f64 closed form; 1e-3 m covers f32
        // rounding over 480 substeps).
        let h = f64::from(DT) / 4.0;
        for (k, &y) in heights.iter().enumerate() {
            let n = 4.0 * k as f64;
            let closed = 10.0 - f64::from(G) * h * h * n * (n + 1.0) / 2.0;
            assert!(
                (f64::from(y) - closed).abs() < 1e-3,
                "step {k}: {y} vs {closed}"
            );
        }
    }

    #[test]
    fn a_segment_tripwire_detects_a_segment_it_crosses() {
        // A kinematic horizontal segment sensor from x = -1 to 1, rising at 1 m/s from
        // y = -2.01, sweeps across a static vertical segment spanning y in [-0.5, 0.5] at x = 0.
        // Neither has area: they overlap while they cross (Box2D's sensors test the distance),
        // from the first step the tripwire is at y ≥ -0.5 (step 91: -2.01 + 91/60 = -0.493)
        // to the first at y > 0.5 (step 151: 0.507); no step lands within 1e-4 m of an end.
        let mut w = World::new(StepSettings::default());
        let wire = w
            .create_body(
                &BodyDef::compound(vec![
                    PartDef::new(ShapeDef::Segment {
                        point1: [-1.0, 0.0],
                        point2: [1.0, 0.0],
                    })
                    .sensor(true),
                ])
                .kind(BodyKind::Kinematic)
                .at(0.0, -2.01)
                .velocity(0.0, 1.0),
            )
            .unwrap();
        let post = w
            .create_body(
                &BodyDef::new(ShapeDef::Segment {
                    point1: [0.0, -0.5],
                    point2: [0.0, 0.5],
                })
                .kind(BodyKind::Static),
            )
            .unwrap();
        let mut seen = Vec::new();
        for k in 1..=200 {
            for e in step(&mut w) {
                seen.push((k, e));
            }
        }
        let refs = |e: &Event| e.shapes().unwrap().map(|r| r.body);
        assert_eq!(seen.len(), 2, "{seen:?}");
        assert!(matches!(seen[0].1, Event::SensorBegin { .. }));
        assert!(matches!(seen[1].1, Event::SensorEnd { .. }));
        assert_eq!((seen[0].0, seen[1].0), (91, 151));
        assert_eq!(refs(&seen[0].1), [wire, post]);
        w.validate().unwrap();
    }

    #[test]
    fn a_sensor_skips_what_its_filter_refuses_and_its_own_body() {
        let apart = Filter {
            group: -1,
            ..Filter::default()
        };
        let (mut w, sensor, _) = sensor_and_ball(Filter {
            group: -1,
            ..Filter::default()
        });
        // The sensor's body in the same negative group: the pair never touches.
        w.destroy_body(sensor).unwrap();
        w.create_body(
            &BodyDef::compound(vec![
                PartDef::new(ShapeDef::Box {
                    half_extents: [1.0, 1.0],
                    radius: 0.0,
                })
                .sensor(true)
                .filter(apart),
                // A solid part of its own body, inside it (and out of the ball's way): never a
                // visitor.
                PartDef::new(ShapeDef::Circle { radius: 0.25 }).at(0.6, 0.0, 0.0),
            ])
            .kind(BodyKind::Static)
            .at(0.0, 3.0),
        )
        .unwrap();
        let all: Vec<Event> = (0..120).flat_map(|_| step(&mut w)).collect();
        assert!(all.is_empty(), "{all:?}");
        w.validate().unwrap();
    }

    #[test]
    fn destroying_touching_bodies_ends_their_contacts_and_sensor_overlaps() {
        let mut w = World::new(StepSettings::default());
        let g = ground(&mut w);
        let b = w
            .create_body(&BodyDef::new(unit_box()).at(0.0, 1.0))
            .unwrap();
        let s = w
            .create_body(
                &BodyDef::compound(vec![
                    PartDef::new(ShapeDef::Circle { radius: 2.0 }).sensor(true),
                ])
                .kind(BodyKind::Static)
                .at(0.0, 1.0),
            )
            .unwrap();
        let first = step(&mut w);
        assert_eq!(first.len(), 3, "{first:?}");
        assert!(matches!(first[0], Event::ContactBegin { .. }));
        // The sensor sees the ground and the box, by shape slot.
        assert!(matches!(first[1], Event::SensorBegin { visitor, .. } if visitor.body == g));
        assert!(matches!(first[2], Event::SensorBegin { visitor, .. } if visitor.body == b));
        w.destroy_body(b).unwrap();
        // At once, before any step, after the step's events, as Box2D's b2DestroyBody
        // reports it.
        assert!(
            matches!(w.events(), [_, _, _, Event::ContactEnd { shapes }] if shapes[1].body == b),
            "{:?}",
            w.events()
        );
        let next = step(&mut w);
        assert!(
            matches!(next[..], [Event::SensorEnd { sensor, visitor }]
                if sensor.body == s && visitor.body == b),
            "{next:?}"
        );
        // A snapshot keeps the overlaps: restored, it reports no overlap again.
        let mut restored = World::from_snapshot(w.snapshot()).unwrap();
        assert!(step(&mut restored).is_empty());
        // Destroying the sensor drops its overlaps without events (as Box2D's).
        w.destroy_body(s).unwrap();
        assert!(step(&mut w).is_empty());
        w.validate().unwrap();
    }
}
