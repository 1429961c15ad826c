//! Bodies and shapes: creating, destroying and changing them between steps, and the one place
//! a body's mass data are computed and every copy of them refreshed.

use glam::Vec2;

use super::stores::AppliedForce;
use super::{BodyRecord, BodySim, Contact, NONE, ShapeRecord, World, WorldError, step};
use crate::AABB_MARGIN;
use crate::body::{BodyMass, BodyState, part_geometry};
use crate::def::{BodyDef, BodyKind, Limits, PartDef};
use crate::error::SceneError;
use crate::id::{BodyId, ShapeId};
use crate::math::{Rot, Transform};
use crate::shape::{Aabb, Shape};
use crate::solver::{BodyMotion, SolverBody};

/// Bodies and shapes: created, changed and destroyed between steps, each named by its id;
/// impulses and velocities set directly. A stale id is refused with
/// [`WorldError::NoBody`] or [`WorldError::NoShape`], and a value the call cannot use with
/// [`WorldError::Invalid`], the world unchanged.
///
/// ```
/// use tumble_physics::{BodyDef, PartDef, ShapeDef, StepSettings, Vec2, World, WorldError};
///
/// let mut world = World::new(StepSettings::default());
/// let ball = world.create_body(&BodyDef::new(ShapeDef::Circle { radius: 0.5 }).at(0.0, 4.0)).unwrap();
/// world.apply_linear_impulse_to_center(ball, Vec2::new(2.0, 0.0), true).unwrap();
/// let handle = world.create_shape(ball, &PartDef::new(ShapeDef::Circle { radius: 0.2 }).at(0.6, 0.0, 0.0)).unwrap();
/// assert!(world.mass(ball).unwrap() > 0.8);
/// world.destroy_shape(handle).unwrap();
/// world.destroy_body(ball).unwrap();
/// assert_eq!(world.set_velocity(ball, Vec2::ZERO, 0.0), Err(WorldError::NoBody(ball)));
/// ```
impl World {
    /// Creates a body (between steps), checked as a scene body would be (the error names
    /// the slot it would have taken), and returns its id. It takes the lowest free slot.
    pub fn create_body(&mut self, def: &BodyDef) -> Result<BodyId, SceneError> {
        let index = self.bodies.slots.next_index() as usize;
        def.validate(index, &Limits::default())?;
        let id = self.insert_body(def, index);
        self.debug_validate();
        Ok(id)
    }

    /// Builds a validated body into the stores.
    pub(super) fn insert_body(&mut self, def: &BodyDef, expected: usize) -> BodyId {
        let (index, generation, new) = self.bodies.slots.take();
        debug_assert_eq!(index as usize, expected);
        let i = index as usize;
        let xf = Transform {
            p: Vec2::from(def.position),
            q: Rot::from_angle(def.angle),
        };
        let sim = BodySim {
            xf,
            kind: def.kind,
            inv_inertia: 0.0,
            extent: 0.0,
            margin: 0.0,
            min_extent: 0.0,
            fast: false,
            sleep_time: 0.0,
        };
        let record = BodyRecord {
            local_center: Vec2::ZERO,
            first_shape: NONE,
            parts: 0,
            fixed_rotation: def.fixed_rotation,
            linear_damping: def.linear_damping,
            angular_damping: def.angular_damping,
            gravity_scale: def.gravity_scale,
            enable_sleep: def.enable_sleep,
            bullet: def.bullet,
            user_data: 0,
            custom_mass: false,
            disabled: false,
        };
        let rotates = !(def.kind == BodyKind::Dynamic && def.fixed_rotation);
        let state = BodyState {
            v: Vec2::from(def.linear_velocity),
            w: if rotates { def.angular_velocity } else { 0.0 },
            ..BodyState::default()
        };
        if new {
            self.bodies.sims.push(sim);
            self.bodies.records.push(record);
            self.bodies.states.push(state);
            self.bodies.masses.push(SolverBody::default());
            self.bodies.motion.push(BodyMotion::default());
            self.bodies.awake.push(false);
            self.bodies.forces.push(AppliedForce::default());
        } else {
            // (A slot still in the forced list stays listed, with no force.)
            let listed = self.bodies.forces[i].listed;
            self.bodies.forces[i] = AppliedForce {
                listed,
                ..AppliedForce::default()
            };
            self.bodies.sims[i] = sim;
            self.bodies.records[i] = record;
            self.bodies.states[i] = state;
        }
        self.islands.grow(i + 1);
        self.bodies.count_kind(BodyKind::Static, def.kind);
        let parts = def.parts();
        for (k, part) in parts.iter().enumerate() {
            // Validation has checked every shape, so this cannot fail.
            let Ok(shapes) = part_geometry(part) else {
                continue;
            };
            // Every shape of a part (a chain's segments) carries the part's index.
            self.bodies.records[i].parts = k as u32;
            for (shape, local) in shapes {
                self.insert_shape(index, shape, local, part);
            }
        }
        self.bodies.records[i].parts = parts.len() as u32;
        // A body of one shape: its position is its centre of mass (its one shape is centred
        // there). A body of several: its position is its frame's origin, and `update_mass`
        // moves the centre to where the parts put it. It has no contacts to tell.
        debug_assert!(
            !self
                .contacts
                .list
                .iter()
                .any(|c| c.body_a == index || c.body_b == index)
        );
        self.compute_mass_data(index);
        let asleep = !def.awake && self.settings.enable_sleep && def.kind == BodyKind::Dynamic;
        if def.kind == BodyKind::Dynamic {
            self.islands.create(index, !asleep);
        }
        self.bodies.awake[i] = def.kind != BodyKind::Static && !asleep;
        if asleep {
            let st = &mut self.bodies.states[i];
            st.v = Vec2::ZERO;
            st.w = 0.0;
        }
        self.bodies.refresh_motion(index);
        self.refresh_shape_boxes(index);
        BodyId { index, generation }
    }

    /// Adds one shape at the end of body `body`'s list, with a fat box to come.
    pub(super) fn insert_shape(
        &mut self,
        body: u32,
        shape: Shape,
        local: Transform,
        part: &crate::def::ResolvedPart<'_>,
    ) -> ShapeId {
        let (index, generation, new) = self.shapes.slots.take();
        let record = ShapeRecord {
            body,
            local,
            from_center: local,
            offset: local != Transform::IDENTITY,
            density: part.density,
            friction: part.friction,
            restitution: part.restitution,
            filter: part.filter,
            sensor: part.sensor,
            next: NONE,
            part: self.bodies.records[body as usize].parts,
            user_data: 0,
            tangent_speed: part.tangent_speed,
            rolling_resistance: part.rolling_resistance,
            disabled: self.bodies.records[body as usize].disabled,
        };
        // Appended: a body's shapes are listed in part order.
        match self.shapes_of_body(body as usize).last() {
            None => self.bodies.records[body as usize].first_shape = index,
            Some(last) => self.shapes.records[last as usize].next = index,
        }
        self.shapes.put(index, new, shape, record);
        if part.sensor {
            self.add_sensor(index);
        }
        ShapeId { index, generation }
    }

    /// In debug builds, checks every invariant between the stores after an API change
    /// (an internal bug, not bad input, if it fails).
    pub(super) fn debug_validate(&self) {
        #[cfg(debug_assertions)]
        if let Err(e) = self.validate() {
            panic!("tumble: the world's stores disagree after a change: {e}");
        }
    }

    /// The shapes of body `i`, in part order.
    pub(super) fn shapes_of_body(&self, i: usize) -> impl Iterator<Item = u32> + '_ {
        let mut s = self.bodies.records[i].first_shape;
        std::iter::from_fn(move || {
            if s == NONE {
                return None;
            }
            let here = s;
            s = self.shapes.records[s as usize].next;
            Some(here)
        })
    }

    /// The mass data of body `i`'s shapes as they are placed on it.
    pub(super) fn shapes_mass(&self, i: usize) -> BodyMass {
        BodyMass::of_shapes(self.shapes_of_body(i).map(|s| {
            let r = &self.shapes.records[s as usize];
            (&self.shapes.geometry[s as usize], r.local, r.density)
        }))
    }

    /// The one place a body's mass data are computed from its shapes and kind, and every
    /// copy refreshed: the solver's masses, the motion flags, each shape's pose relative to
    /// the centre, and the masses the body's contacts keep. The centre of mass keeps its
    /// place in the body's frame: the frame stays where it is and the centre moves.
    pub(super) fn update_mass(&mut self, body: u32) {
        self.compute_mass_data(body);
        self.refresh_contact_masses(body);
    }

    /// [`World::update_mass`] without telling the contacts: for a body just made, which has
    /// none (a scan of every contact per body made would cost a world making many).
    fn compute_mass_data(&mut self, body: u32) {
        let md = self.shapes_mass(body as usize);
        self.bodies.records[body as usize].custom_mass = false;
        self.apply_mass(body, md.mass, md.center, md.inertia, md.min_extent);
    }

    /// Gives body `body` a mass (kg), centre (in its frame) and inertia about that centre
    /// (kg·m²), from its shapes or the caller, and refreshes every copy but the contacts'.
    /// The centre of mass keeps its place in the body's frame: the frame stays where it is.
    pub(super) fn apply_mass(
        &mut self,
        body: u32,
        mass: f32,
        center: Vec2,
        inertia: f32,
        min_extent: f32,
    ) {
        let i = body as usize;
        let kind = self.bodies.sims[i].kind;
        let shape_ids: Vec<u32> = self.shapes_of_body(i).collect();
        let dynamic = kind == BodyKind::Dynamic;
        let center = if dynamic { center } else { Vec2::ZERO };
        // Keep the frame's origin where it is.
        let old_center = self.bodies.records[i].local_center;
        if old_center != center {
            let q = self.bodies.sims[i].xf.q;
            self.bodies.sims[i].xf.p += q.apply(center - old_center);
        }
        self.bodies.records[i].local_center = center;
        let (inv_mass, inv_inertia) = if dynamic && mass > 0.0 {
            let inv_i = if self.bodies.records[i].fixed_rotation || inertia <= 0.0 {
                0.0
            } else {
                1.0 / inertia
            };
            (1.0 / mass, inv_i)
        } else {
            (0.0, 0.0)
        };
        // Extents about the centre actually used (for other than dynamic bodies, the origin).
        let extent = shape_ids.iter().fold(0.0f32, |e, &s| {
            let r = &self.shapes.records[s as usize];
            e.max((r.local.p - center).length() + self.shapes.geometry[s as usize].extent())
        });
        let sim = &mut self.bodies.sims[i];
        sim.inv_inertia = inv_inertia;
        sim.extent = extent;
        sim.min_extent = min_extent;
        sim.margin = match kind {
            BodyKind::Static => 0.0,
            // Box2D `b2ComputeShapeMargin`: small shapes get proportionally small margins.
            _ => AABB_MARGIN.min(0.125 * extent),
        };
        self.bodies.masses[i] = SolverBody {
            inv_mass,
            inv_inertia,
            dynamic,
        };
        for &s in &shape_ids {
            let r = &mut self.shapes.records[s as usize];
            r.from_center = Transform {
                p: r.local.p - center,
                q: r.local.q,
            };
            r.offset = r.from_center != Transform::IDENTITY;
        }
        self.bodies.refresh_motion(body);
    }

    /// Contacts keep a copy of their bodies' masses (prepare reads no body): refreshes body
    /// `body`'s. A body just made has no contacts yet and skips this scan of them all.
    pub(super) fn refresh_contact_masses(&mut self, body: u32) {
        // (The colouring needs no telling: it is checked against the touching pairs.)
        self.contacts
            .refresh_masses(body, &self.bodies.masses, &self.bodies.awake);
    }

    /// Whether every pair of body `i`'s shapes goes by swept boxes alone: a static body's
    /// (only moving bodies sweep, so this is as for any pair with it) and a bullet's.
    pub(super) fn sweeps_every_pair(&self, i: usize) -> bool {
        self.bodies.sims[i].kind == BodyKind::Static || self.bodies.records[i].bullet
    }

    /// Makes a body a bullet or not (between steps): a bullet's pairs with moving bodies are
    /// found by its swept box, a step before they meet, so that its speculative contacts
    /// stop it however fast it closes on them, as they stop every body at a static wall.
    /// Other pairs of moving bodies (Box2D's rule) are found when their unswept fat boxes
    /// meet: cheaper where many bodies move together, and a fast meeting overlaps before it
    /// is pushed apart.
    pub fn set_bullet(&mut self, id: BodyId, bullet: bool) -> Result<(), WorldError> {
        let i = self.slot(id)?;
        if self.bodies.records[i].bullet != bullet {
            self.bodies.records[i].bullet = bullet;
            // New pairs come from its moved proxies; pairs no longer wanted part in the
            // narrow phase.
            self.refresh_shape_boxes(i as u32);
        }
        self.debug_validate();
        Ok(())
    }

    /// Tags a body with a number of the caller's choosing (Box2D's `b2Body_SetUserData`,
    /// Rapier's `user_data`): what a game keeps to find its own object from a body. A new body
    /// carries 0; snapshots keep the tag; the step never reads it.
    pub fn set_user_data(&mut self, id: BodyId, user_data: u64) -> Result<(), WorldError> {
        let i = self.slot(id)?;
        self.bodies.records[i].user_data = user_data;
        Ok(())
    }

    /// The tag [`World::set_user_data`] gave a body (0 if none).
    pub fn user_data(&self, id: BodyId) -> Result<u64, WorldError> {
        self.slot(id).map(|i| self.bodies.records[i].user_data)
    }

    /// Recomputes the fat boxes of a body's shapes and marks them moved (after the body was
    /// created or teleported).
    pub(super) fn refresh_shape_boxes(&mut self, body: u32) {
        let i = body as usize;
        // Swept over a step as long as the last (the next is not known yet).
        let dt = self.stats.last_dt;
        let unswept_everywhere = self.sweeps_every_pair(i);
        let is_static = self.bodies.sims[i].kind == BodyKind::Static;
        let ids: Vec<u32> = self.shapes_of_body(i).collect();
        for s in ids {
            let su = s as usize;
            let sim = &self.bodies.sims[i];
            let (core, swept) = step::shape_boxes(
                &self.shapes.geometry[su],
                &self.shapes.records[su],
                sim,
                &self.bodies.states[i],
                dt,
            );
            let unswept = if unswept_everywhere {
                Aabb::EVERYWHERE
            } else {
                core.grown(sim.margin)
            };
            let swept = swept.grown(sim.margin);
            self.shapes.set_boxes(s, swept, unswept, is_static);
        }
    }

    /// Sets a body's velocities (a mouse drag, a jump) and wakes it. A static body keeps
    /// still (Box2D's rule); a body that cannot turn keeps its angular velocity at 0.
    pub fn set_velocity(
        &mut self,
        id: BodyId,
        linear: Vec2,
        angular: f32,
    ) -> Result<(), WorldError> {
        let i = self.slot(id)?;
        if !(linear.is_finite() && angular.is_finite()) {
            return Err(WorldError::Invalid {
                what: format!("velocity {linear:?}, {angular}"),
                why: "velocities must be finite".into(),
            });
        }
        if self.bodies.sims[i].kind == BodyKind::Static {
            return Ok(());
        }
        self.wake_body(i as u32);
        let s = &mut self.bodies.states[i];
        s.v = linear;
        if self.bodies.sims[i].inv_inertia > 0.0 || self.bodies.sims[i].kind == BodyKind::Kinematic
        {
            s.w = angular;
        }
        Ok(())
    }

    /// Applies an impulse (N·s) at a world point: the body's velocities change at once (a
    /// kick, a mouse spring). Only dynamic bodies respond; with `wake` false a sleeping body
    /// is left as it is (Box2D's `b2Body_ApplyLinearImpulse`).
    pub fn apply_linear_impulse(
        &mut self,
        id: BodyId,
        impulse: Vec2,
        point: Vec2,
        wake: bool,
    ) -> Result<(), WorldError> {
        let i = self.slot(id)?;
        finite("impulse", impulse)?;
        finite("point", point)?;
        if self.impulse_target(i, wake) {
            let body = self.bodies.masses[i];
            let r = point - self.bodies.sims[i].xf.p;
            let s = &mut self.bodies.states[i];
            s.v += impulse * body.inv_mass;
            s.w += body.inv_inertia * crate::math::cross(r, impulse);
        }
        Ok(())
    }

    /// Applies an impulse (N·s) at the body's centre of mass: it changes the body's speed,
    /// not its spin. See [`World::apply_linear_impulse`] for `wake`.
    pub fn apply_linear_impulse_to_center(
        &mut self,
        id: BodyId,
        impulse: Vec2,
        wake: bool,
    ) -> Result<(), WorldError> {
        let i = self.slot(id)?;
        finite("impulse", impulse)?;
        if self.impulse_target(i, wake) {
            let inv_mass = self.bodies.masses[i].inv_mass;
            self.bodies.states[i].v += impulse * inv_mass;
        }
        Ok(())
    }

    /// Applies an angular impulse (N·m·s): it changes the body's spin at once. See
    /// [`World::apply_linear_impulse`] for `wake`.
    pub fn apply_angular_impulse(
        &mut self,
        id: BodyId,
        impulse: f32,
        wake: bool,
    ) -> Result<(), WorldError> {
        let i = self.slot(id)?;
        if !impulse.is_finite() {
            return Err(WorldError::Invalid {
                what: format!("angular impulse {impulse}"),
                why: "it must be finite".into(),
            });
        }
        if self.impulse_target(i, wake) {
            let inv_inertia = self.bodies.masses[i].inv_inertia;
            self.bodies.states[i].w += inv_inertia * impulse;
        }
        Ok(())
    }

    /// Whether an impulse moves body `i`: it is dynamic and awake, or woken now.
    pub(super) fn impulse_target(&mut self, i: usize, wake: bool) -> bool {
        if !self.bodies.masses[i].dynamic {
            return false;
        }
        if wake {
            // Also restarts its rest timer, as a touch does.
            self.wake_body(i as u32);
        }
        self.bodies.awake[i]
    }

    /// Moves a body's frame to `position` and `angle` (between steps): it teleports, keeps
    /// its velocity, and is awake. Its contacts are recomputed next step.
    pub fn set_transform(
        &mut self,
        id: BodyId,
        position: Vec2,
        angle: f32,
    ) -> Result<(), WorldError> {
        let i = self.slot(id)?;
        if !(position.is_finite() && angle.is_finite()) {
            return Err(WorldError::Invalid {
                what: format!("pose {position:?}, {angle}"),
                why: "a position and angle must be finite".into(),
            });
        }
        let q = Rot::from_angle(angle);
        let c = self.bodies.records[i].local_center;
        self.bodies.sims[i].xf = Transform {
            p: position + q.apply(c),
            q,
        };
        // The move is not motion the recycling could follow.
        for c in self.contacts.list.iter_mut() {
            if c.body_a as usize == i || c.body_b as usize == i {
                c.cache = None;
            }
        }
        // What rested on it (a static ground moved away) must notice.
        self.wake_touching(&[i as u32], |b| b == i as u32);
        self.refresh_shape_boxes(i as u32);
        self.debug_validate();
        Ok(())
    }

    /// Box2D's `b2Body_SetTargetTransform`: gives a (kinematic or dynamic) body the
    /// velocity that brings its frame to `position` and `angle` in one step of `dt`, so a
    /// kinematic pusher follows a path and still pushes what it meets.
    pub fn set_target_transform(
        &mut self,
        id: BodyId,
        position: Vec2,
        angle: f32,
        dt: f32,
    ) -> Result<(), WorldError> {
        let i = self.slot(id)?;
        if !(position.is_finite() && angle.is_finite() && dt.is_normal() && dt > 0.0) {
            return Err(WorldError::Invalid {
                what: format!("target {position:?}, {angle} in {dt} s"),
                why: "a finite pose and a time step > 0".into(),
            });
        }
        if self.bodies.sims[i].kind == BodyKind::Static {
            return Err(WorldError::Invalid {
                what: format!("{id}"),
                why: "a static body does not move; make it kinematic first".into(),
            });
        }
        let sim = self.bodies.sims[i];
        let c = self.bodies.records[i].local_center;
        let q = Rot::from_angle(angle);
        let target_center = position + q.apply(c);
        let v = (target_center - sim.xf.p) / dt;
        // The turn from the current angle to the target's, the short way round.
        let dq = sim.xf.q.inv_mul(q);
        let w = dq.s.atan2(dq.c) / dt;
        self.wake_body(i as u32);
        let st = &mut self.bodies.states[i];
        st.v = v;
        st.w = w;
        Ok(())
    }

    /// Changes a body's kind (between steps); its mass data, islands and contacts follow.
    pub fn set_kind(&mut self, id: BodyId, kind: BodyKind) -> Result<(), WorldError> {
        let i = self.slot(id)?;
        let old = self.bodies.sims[i].kind;
        if old == kind {
            return Ok(());
        }
        if kind == BodyKind::Dynamic {
            let md = self.shapes_mass(i);
            if !BodyMass::invertible(md.mass) {
                return Err(WorldError::Invalid {
                    what: format!("{id} made dynamic"),
                    why: format!(
                        "its shapes give a mass of {:e} kg, which f32 cannot invert: give a shape density",
                        md.mass
                    ),
                });
            }
        }
        // Its contacts' touching state and islands are rebuilt as if they were new.
        self.wake_touching(&[i as u32], |b| b == i as u32);
        self.islands.remove_body(i as u32);
        self.bodies.count_kind(old, kind);
        self.bodies.sims[i].kind = kind;
        if old == BodyKind::Static || kind == BodyKind::Static {
            self.shapes.static_tree_stale = true;
        }
        if kind == BodyKind::Static {
            self.bodies.states[i].v = Vec2::ZERO;
            self.bodies.states[i].w = 0.0;
        }
        self.bodies.awake[i] = kind != BodyKind::Static;
        self.bodies.sims[i].sleep_time = 0.0;
        if kind == BodyKind::Dynamic {
            self.islands.create(i as u32, true);
        }
        if self.bodies.records[i].disabled {
            // It keeps out of everything until enabled, whatever its kind.
            self.islands.remove_body(i as u32);
            self.bodies.awake[i] = false;
        }
        self.update_mass(i as u32);
        // Contacts of this body are made afresh: pairs that may no longer touch (two
        // static bodies) go, and new ones are found from its moved proxies.
        self.remove_contacts_of(i as u32);
        self.refresh_shape_boxes(i as u32);
        self.debug_validate();
        Ok(())
    }

    /// Destroys a body and its shapes (between steps). Bodies it touched wake up, and its
    /// slot is free for the next body under a new generation.
    pub fn destroy_body(&mut self, id: BodyId) -> Result<(), WorldError> {
        self.destroy_bodies(&[id])
    }

    /// Destroys several bodies at once (between steps), each as [`World::destroy_body`]
    /// would: their joints, contacts and shapes go, and the bodies they touched wake. One pass
    /// over the world's joints and one over its contacts serve them all, where a body at a
    /// time takes a pass each: the call for a game that removes a group (a ragdoll, a wreck).
    /// All or nothing: a stale or repeated id refuses the whole call and changes nothing.
    pub fn destroy_bodies(&mut self, ids: &[BodyId]) -> Result<(), WorldError> {
        let mut doomed = vec![false; self.bodies.sims.len()];
        let mut slots = Vec::with_capacity(ids.len());
        for &id in ids {
            let i = self.slot(id)?;
            if std::mem::replace(&mut doomed[i], true) {
                return Err(WorldError::Invalid {
                    what: format!("{id}"),
                    why: "a body given twice to destroy_bodies".into(),
                });
            }
            slots.push(i as u32);
        }
        let gone = |b: u32| doomed[b as usize];
        for k in 0..self.joints.list.len() {
            let j = &self.joints.list[k];
            if self.joints.slots.is_alive(k) && (gone(j.body_a) || gone(j.body_b)) {
                self.remove_joint(k, gone);
            }
        }
        self.wake_touching(&slots, gone);
        self.remove_contacts_where(|c| gone(c.body_a) || gone(c.body_b));
        for &i in &slots {
            self.release_body(i as usize);
        }
        self.debug_validate();
        Ok(())
    }

    /// Frees slot `i` of a body whose joints and contacts are gone.
    fn release_body(&mut self, i: usize) {
        self.islands.remove_body(i as u32);
        let shapes: Vec<u32> = self.shapes_of_body(i).collect();
        for s in shapes {
            self.release_shape(s);
        }
        self.bodies
            .count_kind(self.bodies.sims[i].kind, BodyKind::Static);
        self.bodies.records[i].first_shape = NONE;
        self.bodies.sims[i].kind = BodyKind::Static;
        self.bodies.states[i] = BodyState::default();
        self.bodies.awake[i] = false;
        self.bodies.masses[i] = SolverBody::default();
        self.bodies.refresh_motion(i as u32);
        self.bodies.slots.release(i as u32);
    }

    /// Adds a shape to a body (between steps), checked as a scene part would be; the body's
    /// mass data follow. A chain is several shapes: use [`World::create_shapes`].
    pub fn create_shape(&mut self, body: BodyId, part: &PartDef) -> Result<ShapeId, WorldError> {
        if matches!(part.shape, crate::def::ShapeDef::Chain { .. }) {
            return Err(WorldError::Invalid {
                what: "shape".into(),
                why: "a chain is one shape per segment: add it with create_shapes".into(),
            });
        }
        self.create_shapes(body, part).map(|ids| ids[0])
    }

    /// Adds a part to a body (between steps): one shape, or one per segment of a chain, in
    /// order. Checked as a scene part would be; the body's mass data follow.
    pub fn create_shapes(
        &mut self,
        body: BodyId,
        part: &PartDef,
    ) -> Result<Vec<ShapeId>, WorldError> {
        let i = self.slot(body)?;
        // Check it as the part of a one-part body of this kind.
        let mut def = BodyDef::compound(vec![part.clone()]);
        def.kind = self.bodies.sims[i].kind;
        if !part.shape.has_area() && def.kind == BodyKind::Dynamic {
            // A segment or chain gives no mass: it may join a dynamic body that has some,
            // which the destroy rule below keeps so; check its numbers as a static part's.
            def.kind = BodyKind::Static;
        }
        def.validate(0, &Limits::default())?;
        let parts = def.parts();
        let resolved = &parts[0];
        let shapes = part_geometry(resolved).map_err(|e| WorldError::Invalid {
            what: "shape".into(),
            why: e.to_string(),
        })?;
        // Appended as the body's last part.
        let ids: Vec<ShapeId> = shapes
            .into_iter()
            .map(|(shape, local)| self.insert_shape(i as u32, shape, local, resolved))
            .collect();
        self.bodies.records[i].parts += 1;
        self.wake_body(i as u32);
        self.update_mass(i as u32);
        self.refresh_shape_boxes(i as u32);
        self.debug_validate();
        Ok(ids)
    }

    /// Destroys one shape (between steps). A dynamic body keeps at least one shape with
    /// area (destroy the body instead).
    pub fn destroy_shape(&mut self, id: ShapeId) -> Result<(), WorldError> {
        let s = self.shape_slot(id)?;
        let body = self.shapes.records[s].body;
        let i = body as usize;
        if self.bodies.sims[i].kind == BodyKind::Dynamic {
            let others = self
                .shapes_of_body(i)
                .filter(|&o| {
                    o as usize != s
                        && self.shapes.records[o as usize].density > 0.0
                        && self.shapes.geometry[o as usize].has_area()
                })
                .count();
            if others == 0 {
                return Err(WorldError::Invalid {
                    what: format!("{id}"),
                    why: "the last shape with mass of a dynamic body; destroy the body instead"
                        .into(),
                });
            }
        }
        self.wake_touching(&[body], |b| b == body);
        // Its contacts go.
        self.remove_contacts_where(|c| c.shape_a as usize == s || c.shape_b as usize == s);
        // Unlink it from the body's list.
        let next = self.shapes.records[s].next;
        if self.bodies.records[i].first_shape == s as u32 {
            self.bodies.records[i].first_shape = next;
        } else {
            let mut k = self.bodies.records[i].first_shape;
            while self.shapes.records[k as usize].next != s as u32 {
                k = self.shapes.records[k as usize].next;
            }
            self.shapes.records[k as usize].next = next;
        }
        self.release_shape(s as u32);
        self.islands.unlink(body, body);
        self.update_mass(body);
        self.refresh_shape_boxes(body);
        self.debug_validate();
        Ok(())
    }

    /// Frees a shape's slot and drops it from the broad phase.
    pub(super) fn release_shape(&mut self, s: u32) {
        if self.shapes.records[s as usize].sensor {
            self.sensors.remove(&s);
        }
        self.shapes.release(s);
    }

    /// Removes every contact of body `i` (its islands were told by the caller).
    pub(super) fn remove_contacts_of(&mut self, body: u32) {
        self.remove_contacts_where(|c| c.body_a == body || c.body_b == body);
    }

    /// Removes the contacts `gone` picks, keeping the others' order; a touching one unlinks
    /// its bodies' island and ends its touch (a contact end event).
    pub(super) fn remove_contacts_where(&mut self, gone: impl Fn(&Contact) -> bool) {
        let mut keep = 0;
        for k in 0..self.contacts.list.len() {
            let c = self.contacts.list[k];
            if gone(&c) {
                // The pair may want its contact again (see `Shapes::searched_boxes`).
                for s in [c.shape_a, c.shape_b] {
                    self.shapes.searched_boxes[s as usize] = [Aabb::NOWHERE; 2];
                }
                if c.touched {
                    self.islands.unlink(c.body_a, c.body_b);
                    self.touch_changed(c.shape_a, c.shape_b, false);
                }
                continue;
            }
            self.contacts.list[keep] = c;
            self.contacts.keys[keep] = self.contacts.keys[k];
            keep += 1;
        }
        self.contacts.truncate(keep);
    }
}

/// Refuses `value` for object `id`'s `what`: the error names the object and the value.
pub(super) fn invalid(id: impl std::fmt::Display, what: &str, value: f32, why: &str) -> WorldError {
    WorldError::Invalid {
        what: format!("{what} {value} for {id}"),
        why: why.into(),
    }
}

/// `Ok` for a finite value ≥ 0 (a damping, a friction, a density), else the error that names
/// object `id` and the value.
pub(super) fn non_negative(
    id: impl std::fmt::Display,
    what: &str,
    value: f32,
) -> Result<(), WorldError> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(invalid(id, what, value, "it must be finite and >= 0"))
    }
}

/// `Ok` if both coordinates are finite, else the error that names the value.
pub(super) fn finite(what: &str, v: Vec2) -> Result<(), WorldError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(WorldError::Invalid {
            what: format!("{what} {v:?}"),
            why: "it must be finite".into(),
        })
    }
}
