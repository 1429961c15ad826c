//! What the world tells about itself: its bodies and shapes as views (by id), its contacts,
//! counts, energies and the state hash. Nothing here changes the world.

use glam::Vec2;

use super::{BodyView, Contact, ContactView, QueryFilter, ShapeRef, ShapeView, World, WorldError};
use crate::collision::broad_phase::BroadPhase;
use crate::def::BodyKind;
use crate::id::{BodyId, ShapeId};
use crate::island::NO_ISLAND;
use crate::profile::StepProfile;

/// Bodies: how many, which, and each one's state, by id.
///
/// ```
/// use tumble_physics::{BodyDef, BodyId, BodyKind, Limits, SceneDef, ShapeDef, World};
///
/// let mut scene = SceneDef::new("two");
/// scene.push(BodyDef::new(ShapeDef::Box { half_extents: [5.0, 0.5], radius: 0.0 }).kind(BodyKind::Static));
/// scene.push(BodyDef::new(ShapeDef::Circle { radius: 0.5 }).at(0.0, 3.0));
/// let world = World::from_scene(&scene, &Limits::default()).unwrap();
/// // A scene's bodies have the ids of their places in the file.
/// let ball = BodyId::scene(1);
/// assert_eq!(world.body(ball).unwrap().kind, BodyKind::Dynamic);
/// assert_eq!(world.body_ids().collect::<Vec<_>>(), [BodyId::scene(0), ball]);
/// for (id, body) in world.bodies() {
///     assert!(body.position.is_finite(), "{id}");
/// }
/// ```
impl World {
    /// Live bodies.
    pub fn body_count(&self) -> usize {
        self.bodies.slots.live()
    }

    /// Body slots ever made, live or free: one past the largest `BodyId::index` in use.
    pub(crate) fn body_slot_count(&self) -> usize {
        self.bodies.sims.len()
    }

    /// Whether `id` names a live body of this world.
    pub fn contains_body(&self, id: BodyId) -> bool {
        self.bodies.slots.holds(id.index, id.generation)
    }

    /// The id of the body in slot `index`, if it holds one.
    pub(crate) fn body_id(&self, index: usize) -> Option<BodyId> {
        self.bodies.slots.is_alive(index).then(|| BodyId {
            index: index as u32,
            generation: self.bodies.slots.generation(index),
        })
    }

    /// Every live body's id, in slot order (a scene's bodies in the file's order).
    pub fn body_ids(&self) -> impl Iterator<Item = BodyId> + '_ {
        (0..self.bodies.sims.len()).filter_map(|i| self.body_id(i))
    }

    /// Every live body with its state, in slot order.
    pub fn bodies(&self) -> impl Iterator<Item = (BodyId, BodyView)> + '_ {
        (0..self.bodies.sims.len())
            .filter_map(|i| self.body_id(i).map(|id| (id, self.body_view(i))))
    }

    pub(super) fn slot(&self, id: BodyId) -> Result<usize, WorldError> {
        if self.bodies.slots.holds(id.index, id.generation) {
            Ok(id.index as usize)
        } else {
            Err(WorldError::NoBody(id))
        }
    }

    pub(super) fn shape_slot(&self, id: ShapeId) -> Result<usize, WorldError> {
        if self.shapes.slots.holds(id.index, id.generation) {
            Ok(id.index as usize)
        } else {
            Err(WorldError::NoShape(id))
        }
    }

    /// A body's state.
    pub fn body(&self, id: BodyId) -> Result<BodyView, WorldError> {
        self.slot(id).map(|i| self.body_view(i))
    }

    /// The state of the body in slot `index` (a free slot reads as a static body at rest
    /// where it was).
    pub(crate) fn body_view(&self, index: usize) -> BodyView {
        let sim = &self.bodies.sims[index];
        let st = &self.bodies.states[index];
        let c = self.bodies.records[index].local_center;
        BodyView {
            position: sim.xf.p,
            origin: if c == Vec2::ZERO {
                sim.xf.p
            } else {
                sim.xf.p - sim.xf.q.apply(c)
            },
            angle: sim.xf.q.angle(),
            rotation: sim.xf.q,
            linear_velocity: st.v,
            angular_velocity: st.w,
            kind: sim.kind,
            awake: self.bodies.awake[index],
            bullet: self.bodies.records[index].bullet,
        }
    }

    /// Whether a body is awake (kinematic bodies always are, static bodies never).
    pub fn is_awake(&self, id: BodyId) -> Result<bool, WorldError> {
        self.slot(id).map(|i| self.bodies.awake[i])
    }

    /// Whether a body is a bullet (see [`World::set_bullet`]).
    pub fn is_bullet(&self, id: BodyId) -> Result<bool, WorldError> {
        self.slot(id).map(|i| self.bodies.records[i].bullet)
    }

    /// A body's mass (kg); zero for static and kinematic bodies.
    pub fn mass(&self, id: BodyId) -> Result<f32, WorldError> {
        self.slot(id).map(|i| self.slot_mass(i))
    }

    fn slot_mass(&self, index: usize) -> f32 {
        let inv = self.bodies.masses[index].inv_mass;
        if inv > 0.0 { 1.0 / inv } else { 0.0 }
    }

    /// A body's rotational inertia about its centre of mass (kg·m²; 0 for static, kinematic
    /// and fixed-rotation bodies).
    pub fn inertia(&self, id: BodyId) -> Result<f32, WorldError> {
        self.slot(id).map(|i| self.slot_inertia(i))
    }

    fn slot_inertia(&self, index: usize) -> f32 {
        let inv = self.bodies.masses[index].inv_inertia;
        if inv > 0.0 { 1.0 / inv } else { 0.0 }
    }

    /// A body's centre of mass in its own frame.
    pub fn local_center(&self, id: BodyId) -> Result<Vec2, WorldError> {
        self.slot(id).map(|i| self.bodies.records[i].local_center)
    }

    /// A body's island (`None` for static and kinematic bodies): a number shared by the
    /// bodies that touch or are jointed, directly or through others, for drawing islands.
    pub fn island_of(&self, id: BodyId) -> Result<Option<usize>, WorldError> {
        let i = self.slot(id)?;
        let k = self.islands.of_body.get(i).copied().unwrap_or(NO_ISLAND);
        Ok((k != NO_ISLAND).then_some(k as usize))
    }

    /// The body one of whose shapes contains the world point, if any (the last in shape
    /// order, which a viewer draws on top): a point query through the broad phase
    /// ([`World::overlap_point`]) that sees every shape.
    pub fn body_at(&self, point: Vec2) -> Option<BodyId> {
        let mut top: Option<ShapeRef> = None;
        self.overlap_point(point, &QueryFilter::ALL, |r| {
            if top.is_none_or(|t| r.shape.index > t.shape.index) {
                top = Some(r);
            }
            true
        });
        top.map(|r| r.body)
    }

    /// Awake bodies (kinematic and awake dynamic ones).
    pub fn awake_body_count(&self) -> usize {
        self.bodies.awake.iter().filter(|a| **a).count()
    }
}

/// Shapes: each one's geometry, pose and body, by id.
///
/// ```
/// use tumble_physics::{BodyDef, ShapeDef, StepSettings, World};
///
/// let mut world = World::new(StepSettings::default());
/// let ball = world.create_body(&BodyDef::new(ShapeDef::Circle { radius: 0.5 }).at(1.0, 2.0)).unwrap();
/// let view = world.body_shapes(ball).unwrap().next().unwrap();
/// assert_eq!(view.body, ball);
/// assert_eq!(world.shape(view.id).unwrap().transform.p, tumble_physics::Vec2::new(1.0, 2.0));
/// ```
impl World {
    /// Live shapes.
    pub fn shape_count(&self) -> usize {
        self.shapes.slots.live()
    }

    /// Whether `id` names a live shape of this world.
    pub fn contains_shape(&self, id: ShapeId) -> bool {
        self.shapes.slots.holds(id.index, id.generation)
    }

    /// A shape: its geometry, its pose in the world, its body.
    pub fn shape(&self, id: ShapeId) -> Result<ShapeView<'_>, WorldError> {
        self.shape_slot(id).map(|s| self.shape_view(s))
    }

    /// A body's shapes, each with its pose in the world, in the order they were made.
    pub fn body_shapes(
        &self,
        id: BodyId,
    ) -> Result<impl Iterator<Item = ShapeView<'_>> + '_, WorldError> {
        let i = self.slot(id)?;
        Ok(self
            .shapes_of_body(i)
            .map(move |s| self.shape_view(s as usize)))
    }

    pub(super) fn shape_view(&self, s: usize) -> ShapeView<'_> {
        let r = &self.shapes.records[s];
        let b = r.body as usize;
        let xf = self.bodies.sims[b].xf;
        ShapeView {
            id: ShapeId {
                index: s as u32,
                generation: self.shapes.slots.generation(s),
            },
            body: BodyId {
                index: r.body,
                generation: self.bodies.slots.generation(b),
            },
            shape: &self.shapes.geometry[s],
            transform: r.pose(xf),
            part: r.part as usize,
            sensor: r.sensor,
            fat_aabb: self.shapes.swept_boxes[s],
        }
    }

    /// Every live shape, in slot order.
    pub fn shapes(&self) -> impl Iterator<Item = ShapeView<'_>> + '_ {
        (0..self.shapes.geometry.len())
            .filter(|&s| self.shapes.slots.is_alive(s))
            .map(|s| self.shape_view(s))
    }

    /// The broad phase's tree, for debug drawing.
    pub fn broad_phase(&self) -> &BroadPhase {
        &self.shapes.tree
    }
}

/// Contacts, islands, counters and measures of the whole world.
impl World {
    /// Contacts (pairs of shapes whose fat boxes overlap, touching or not).
    pub fn contact_count(&self) -> usize {
        self.contacts.list.len()
    }

    /// Every contact, in the deterministic order the solver sees them.
    pub fn contacts(&self) -> impl Iterator<Item = ContactView<'_>> {
        self.contacts.list.iter().map(|c| self.contact_view(c))
    }

    pub(super) fn contact_view<'w>(&'w self, c: &'w Contact) -> ContactView<'w> {
        let centre = self.bodies.sims[c.body_a as usize].xf.p;
        let m = &c.manifold;
        let body = |b: u32| BodyId {
            index: b,
            generation: self.bodies.slots.generation(b as usize),
        };
        let shape = |s: u32| ShapeId {
            index: s,
            generation: self.shapes.slots.generation(s as usize),
        };
        ContactView {
            body_a: body(c.body_a),
            body_b: body(c.body_b),
            shape_a: shape(c.shape_a),
            shape_b: shape(c.shape_b),
            manifold: m,
            points: [centre + m.points[0].anchor_a, centre + m.points[1].anchor_a],
        }
    }

    /// Islands, and of those the awake ones.
    pub fn island_counts(&self) -> (usize, usize) {
        (self.islands.count(), self.islands.awake_count())
    }

    /// Steps taken so far.
    pub fn step_count(&self) -> u64 {
        self.stats.steps
    }

    /// How often a body's speed was clamped to the caps, over all steps.
    pub fn speed_cap_count(&self) -> u64 {
        self.stats.speed_caps
    }

    /// How many times, over the world's whole life (kept by [`World::snapshot`]), the
    /// numerical guard of the step had to stop a body whose state turned non-finite (NaN or
    /// infinite): the body keeps its last finite pose and loses its velocity, so
    /// [`World::is_finite`] stays true and only this count tells. A healthy world reports 0;
    /// every "stays finite" check should require it. [`StepProfile::non_finite`] counts the
    /// last step only.
    pub fn non_finite_bodies(&self) -> u64 {
        self.stats.non_finite_bodies
    }

    /// Whether every body's pose and velocities are finite numbers now. The step's
    /// numerical guard keeps them so (it stops a body that turns non-finite), so on its own
    /// this cannot fail after a step: checks of a run require
    /// [`World::non_finite_bodies`] to be 0 as well.
    pub fn is_finite(&self) -> bool {
        self.bodies
            .sims
            .iter()
            .zip(&self.bodies.states)
            .all(|(sim, st)| {
                sim.xf.p.is_finite()
                    && sim.xf.q.c.is_finite()
                    && sim.xf.q.s.is_finite()
                    && st.v.is_finite()
                    && st.w.is_finite()
            })
    }

    /// Kinetic energy of the dynamic bodies, translational and rotational (J), summed in f64:
    /// what the energy checks of the tests, the report and the viewer measure.
    pub fn kinetic_energy(&self) -> f64 {
        (0..self.body_slot_count())
            .filter(|&i| self.bodies.sims[i].kind == BodyKind::Dynamic)
            .map(|i| {
                let st = &self.bodies.states[i];
                let linear = 0.5 * f64::from(self.slot_mass(i)) * f64::from(st.v.length_squared());
                linear + 0.5 * f64::from(self.slot_inertia(i)) * f64::from(st.w).powi(2)
            })
            .sum()
    }
    /// `(contact index, graph colour)` for every touching contact of the last step, where the
    /// index is a position in [`World::contacts`] and colour 23 is the overflow; for debug
    /// drawing of the constraint graph.
    pub fn contact_colors(&self) -> Vec<(usize, u8)> {
        self.solver.contact_colors()
    }

    /// Which kernels solve the 8-lane colours: `"avx2"` (256-bit registers, chosen at run
    /// time where the CPU has AVX2), `"portable"` (`f32x8`, on x86-64 two SSE halves), or
    /// `"scalar"` when [`StepSettings::simd`](crate::StepSettings::simd) is off. All give the same results bit for bit.
    pub fn simd_kernel(&self) -> &'static str {
        if !self.settings.simd {
            "scalar"
        } else if self.solver.use_avx && crate::solver::lanes::avx2_available() {
            "avx2"
        } else {
            "portable"
        }
    }

    /// The last step's per-stage profile.
    pub fn profile(&self) -> &StepProfile {
        &self.stats.profile
    }

    /// FNV-1a, 64-bit, over the exact bits of every live body's position, rotation (cos,
    /// sin), linear and angular velocity, in slot order.
    pub fn state_hash(&self) -> u64 {
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        let mut eat = |x: f32| {
            for byte in x.to_bits().to_le_bytes() {
                h ^= u64::from(byte);
                h = h.wrapping_mul(0x0000_0100_0000_01b3);
            }
        };
        for (i, (sim, st)) in self.bodies.sims.iter().zip(&self.bodies.states).enumerate() {
            if !self.bodies.slots.is_alive(i) {
                continue;
            }
            eat(sim.xf.p.x);
            eat(sim.xf.p.y);
            eat(sim.xf.q.c);
            eat(sim.xf.q.s);
            eat(st.v.x);
            eat(st.v.y);
            eat(st.w);
        }
        h
    }
}
