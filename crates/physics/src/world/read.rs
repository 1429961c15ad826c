//! What the world tells about itself: counts, bodies, shapes and contacts as views, queries,
//! energies and the state hash.

use glam::Vec2;

use super::{BodyView, ContactView, QueryFilter, ShapeRef, ShapeView, World, WorldError};
use crate::collision::broad_phase::BroadPhase;
use crate::id::{BodyId, ShapeId};
use crate::island::NO_ISLAND;
use crate::profile::StepProfile;
use crate::scene::BodyKind;
use crate::shape::{Aabb, Shape};

impl World {
    /// Body slots (live bodies and free slots): valid indices are `0..body_count()` where
    /// [`World::is_body`] holds. Without destroyed bodies, every slot is a body.
    pub fn body_count(&self) -> usize {
        self.sims.len()
    }

    /// Live bodies.
    pub fn live_body_count(&self) -> usize {
        self.body_slots.live()
    }

    /// Whether slot `index` holds a body.
    pub fn is_body(&self, index: usize) -> bool {
        self.body_slots.is_alive(index)
    }

    /// The id of the body in slot `index`, if it holds one.
    pub fn body_id(&self, index: usize) -> Option<BodyId> {
        self.is_body(index).then(|| BodyId {
            index: index as u32,
            generation: self.body_slots.generation(index),
        })
    }

    /// Every live body's id, in slot order.
    pub fn body_ids(&self) -> impl Iterator<Item = BodyId> + '_ {
        (0..self.sims.len()).filter_map(|i| self.body_id(i))
    }

    pub(super) fn slot(&self, id: BodyId) -> Result<usize, WorldError> {
        if self.body_slots.holds(id.index, id.generation) {
            Ok(id.index as usize)
        } else {
            Err(WorldError::NoBody(id))
        }
    }

    pub(super) fn shape_slot(&self, id: ShapeId) -> Result<usize, WorldError> {
        if self.shape_slots.holds(id.index, id.generation) {
            Ok(id.index as usize)
        } else {
            Err(WorldError::NoShape(id))
        }
    }

    /// Contacts (pairs of overlapping fat boxes).
    pub fn contact_count(&self) -> usize {
        self.contacts.len()
    }

    /// Islands, and of those the awake ones.
    pub fn island_counts(&self) -> (usize, usize) {
        (self.islands.count(), self.islands.awake_count())
    }

    /// Body `index`'s island slot (`None` for static and kinematic bodies), for drawing.
    pub fn island_of(&self, index: usize) -> Option<usize> {
        let k = *self.islands.of_body.get(index)?;
        (k != NO_ISLAND).then_some(k as usize)
    }

    /// Awake bodies (kinematic and awake dynamic ones).
    pub fn awake_body_count(&self) -> usize {
        self.awake.iter().filter(|a| **a).count()
    }

    /// Steps taken so far.
    pub fn step_count(&self) -> u64 {
        self.steps
    }

    /// How often a body's speed was clamped to the caps, over all steps.
    pub fn speed_cap_count(&self) -> u64 {
        self.speed_caps
    }

    /// How many times, over the world's whole life (kept by [`World::snapshot`]), the
    /// numerical guard of the step had to stop a body whose state turned non-finite (NaN or
    /// infinite): the body keeps its last finite pose and loses its velocity, so
    /// [`World::is_finite`] stays true and only this count tells. A healthy world reports 0;
    /// every "stays finite" check should require it. [`StepProfile::non_finite`] counts the
    /// last step only.
    pub fn non_finite_bodies(&self) -> u64 {
        self.non_finite_bodies
    }

    /// The state of the body in slot `index` (see [`World::is_body`]; a free slot reads as
    /// a static body at rest where it was). [`World::get`] takes an id.
    pub fn body(&self, index: usize) -> BodyView {
        let sim = &self.sims[index];
        let st = &self.states[index];
        let c = self.records[index].local_center;
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
            awake: self.awake[index],
            bullet: self.records[index].bullet,
        }
    }

    /// Whether the body in slot `index` is a bullet (a cheap read of [`BodyView::bullet`]).
    pub fn is_bullet(&self, index: usize) -> bool {
        self.records[index].bullet
    }

    /// A body's state by id, or why not.
    pub fn get(&self, id: BodyId) -> Result<BodyView, WorldError> {
        self.slot(id).map(|i| self.body(i))
    }

    /// The first shape of the body in slot `index`, in its own frame (see
    /// [`World::body_shapes`] for every shape and where it sits).
    pub fn shape(&self, index: usize) -> &Shape {
        &self.shapes[self.records[index].first_shape as usize]
    }

    /// The shapes of the body in slot `index`, each with its pose in the world.
    pub fn body_shapes(&self, index: usize) -> impl Iterator<Item = ShapeView<'_>> + '_ {
        self.shapes_of_body(index)
            .map(move |s| self.shape_view(s as usize))
    }

    pub(super) fn shape_view(&self, s: usize) -> ShapeView<'_> {
        let r = &self.shape_records[s];
        let xf = self.sims[r.body as usize].xf;
        ShapeView {
            id: ShapeId {
                index: s as u32,
                generation: self.shape_slots.generation(s),
            },
            body: r.body as usize,
            shape: &self.shapes[s],
            transform: if r.offset {
                xf.compose(r.from_center)
            } else {
                xf
            },
            part: r.part as usize,
            sensor: r.sensor,
            fat_aabb: self.fat_aabbs[s],
        }
    }

    /// Every live shape, in slot order.
    pub fn shapes(&self) -> impl Iterator<Item = ShapeView<'_>> + '_ {
        (0..self.shapes.len())
            .filter(|&s| self.shape_slots.is_alive(s))
            .map(|s| self.shape_view(s))
    }

    /// The fat bounding box of the first shape of body `index`, as the broad phase sees it.
    pub fn fat_aabb(&self, index: usize) -> Aabb {
        self.fat_aabbs[self.records[index].first_shape as usize]
    }

    /// The broad phase's tree, for debug drawing.
    pub fn broad_phase(&self) -> &BroadPhase {
        &self.broad_phase
    }

    /// Every contact, in the deterministic order the solver sees them.
    pub fn contacts(&self) -> impl Iterator<Item = ContactView<'_>> {
        self.contacts.iter().map(|c| {
            let centre = self.sims[c.body_a as usize].xf.p;
            let m = &c.manifold;
            ContactView {
                body_a: c.body_a as usize,
                body_b: c.body_b as usize,
                shape_a: c.shape_a as usize,
                shape_b: c.shape_b as usize,
                manifold: m,
                points: [centre + m.points[0].anchor_a, centre + m.points[1].anchor_a],
            }
        })
    }

    /// A body's mass (kg) by slot; zero for static and kinematic bodies.
    pub fn mass(&self, index: usize) -> f32 {
        let inv = self.solver_bodies[index].inv_mass;
        if inv > 0.0 { 1.0 / inv } else { 0.0 }
    }

    /// A body's centre of mass in its own frame.
    pub fn local_center(&self, index: usize) -> Vec2 {
        self.records[index].local_center
    }

    /// Whether every body's pose and velocities are finite numbers now. The step's
    /// numerical guard keeps them so (it stops a body that turns non-finite), so on its own
    /// this cannot fail after a step: checks of a run require
    /// [`World::non_finite_bodies`] to be 0 as well.
    pub fn is_finite(&self) -> bool {
        self.sims.iter().zip(&self.states).all(|(sim, st)| {
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
        (0..self.body_count())
            .filter(|&i| self.sims[i].kind == BodyKind::Dynamic)
            .map(|i| {
                let st = &self.states[i];
                let linear = 0.5 * f64::from(self.mass(i)) * f64::from(st.v.length_squared());
                linear + 0.5 * f64::from(self.inertia(i)) * f64::from(st.w).powi(2)
            })
            .sum()
    }

    /// A body's rotational inertia about its centre of mass (kg·m²; 0 for static, kinematic
    /// and fixed-rotation bodies).
    pub fn inertia(&self, index: usize) -> f32 {
        let inv = self.solver_bodies[index].inv_inertia;
        if inv > 0.0 { 1.0 / inv } else { 0.0 }
    }

    /// Applies an impulse (N·s) at a world point to a dynamic body: its velocities change at
    /// once (a mouse spring, an explosion), and it wakes. Ignored for other bodies and
    /// non-finite input.
    pub fn apply_linear_impulse(&mut self, index: usize, impulse: Vec2, point: Vec2) {
        let body = self.solver_bodies[index];
        if !body.dynamic || !impulse.is_finite() || !point.is_finite() {
            return;
        }
        self.wake_body(index as u32);
        let r = point - self.sims[index].xf.p;
        let s = &mut self.states[index];
        s.v += impulse * body.inv_mass;
        s.w += body.inv_inertia * crate::math::cross(r, impulse);
    }

    /// The slot of a body one of whose shapes contains the world point, if any (the last in
    /// shape order, which a viewer draws on top): a point query through the broad phase
    /// ([`World::overlap_point`]) that sees every shape.
    pub fn body_at(&self, point: Vec2) -> Option<usize> {
        let mut top: Option<ShapeRef> = None;
        self.overlap_point(point, &QueryFilter::ALL, |r| {
            if top.is_none_or(|t| r.shape.index > t.shape.index) {
                top = Some(r);
            }
            true
        });
        top.map(|r| r.body.index as usize)
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
        &self.profile
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
        for (i, (sim, st)) in self.sims.iter().zip(&self.states).enumerate() {
            if !self.body_slots.is_alive(i) {
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
