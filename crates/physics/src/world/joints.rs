//! The world's joints: made from a scene's definitions or between steps, destroyed with
//! either body, joined into their bodies' islands, kept from touching unless they ask, and
//! prepared each step for the solver (which colours them with the contacts).

use glam::Vec2;

use super::{World, WorldError, pair_key};
use crate::def::BodyKind;
use crate::id::{BodyId, JointId};
use crate::joint::chain::{self, Link};
use crate::joint::def::JointFrame;
use crate::joint::{Joint, JointBody, JointContext, JointDef, JointKind, Mouse};
use crate::math::Transform;
use crate::solver::{NOT_DYNAMIC, Touching};
use crate::threads::parallel::Spread;

/// Joints: made from a [`JointDef`] naming its bodies by id, read and changed by
/// [`JointId`], destroyed between steps.
///
/// ```
/// use tumble_physics::{BodyDef, BodyKind, JointDef, ShapeDef, StepSettings, World};
///
/// let mut world = World::new(StepSettings::default());
/// let pin = world.create_body(&BodyDef::new(ShapeDef::Circle { radius: 0.1 }).kind(BodyKind::Static).at(0.0, 5.0)).unwrap();
/// let bob = world.create_body(&BodyDef::new(ShapeDef::Circle { radius: 0.3 }).at(2.0, 5.0)).unwrap();
/// let hinge = world.create_joint(&JointDef::hinge([pin, bob], [0.0, 5.0])).unwrap();
/// for _ in 0..60 {
///     world.step(1.0 / 60.0, 4);
/// }
/// assert_eq!(world.joint_bodies(hinge), Ok([pin, bob]));
/// // The bob swings below the pin, 2 m from it.
/// let b = world.body(bob).unwrap().position;
/// assert!(b.y < 5.0 && (b.distance(tumble_physics::Vec2::new(0.0, 5.0)) - 2.0).abs() < 0.01);
/// ```
impl World {
    /// The frame (origin and rotation) of body `i`.
    pub(super) fn body_frame(&self, i: usize) -> Transform {
        let xf = self.bodies.sims[i].xf;
        Transform {
            p: xf.p - xf.q.apply(self.bodies.records[i].local_center),
            q: xf.q,
        }
    }

    /// Adds a joint between steps, defined as in a scene file (bodies by id, anchors
    /// in world coordinates at the bodies' current poses), checked as a scene's would be.
    /// Its rigid rows take the settings' `joint_hertz` and `joint_damping_ratio`.
    pub fn create_joint(&mut self, def: &JointDef) -> Result<JointId, WorldError> {
        // A stale or foreign id is named as such, before the definition's own checks.
        for body in def.bodies() {
            self.slot(body)?;
        }
        let index = self.joints.slots.next_index() as usize;
        let frames = |id: BodyId| {
            let i = id.index as usize;
            self.contains_body(id).then(|| JointFrame {
                frame: self.body_frame(i),
                dynamic: self.bodies.sims[i].kind == BodyKind::Dynamic,
            })
        };
        def.validate(index, &frames)?;
        let [a, b] = def.bodies();
        let joint = def.build(
            self.body_frame(a.index as usize),
            self.body_frame(b.index as usize),
            self.settings.joint_hertz,
            self.settings.joint_damping_ratio,
        );
        let id = self.insert_joint(joint);
        self.debug_validate();
        Ok(id)
    }

    /// A mouse joint: pulls the point of `body` now at `target` towards wherever
    /// [`World::set_mouse_target`] moves the target, as a spring of `hertz` and
    /// `damping_ratio` no stronger than `max_force` (the viewer's drag).
    pub fn create_mouse_joint(
        &mut self,
        body: BodyId,
        target: Vec2,
        hertz: f32,
        damping_ratio: f32,
        max_force: f32,
    ) -> Result<JointId, WorldError> {
        let i = self.slot(body)?;
        let finite = target.is_finite() && hertz.is_finite() && damping_ratio.is_finite();
        if !(finite && hertz > 0.0 && damping_ratio >= 0.0 && max_force >= 0.0) {
            return Err(WorldError::Invalid {
                what: format!(
                    "mouse joint: target {target:?}, hertz {hertz}, damping ratio \
                     {damping_ratio}, max force {max_force}"
                ),
                why: "a finite target, hertz > 0, damping ratio >= 0, max force >= 0".into(),
            });
        }
        if self.bodies.sims[i].kind != BodyKind::Dynamic {
            return Err(WorldError::Invalid {
                what: format!("mouse joint on {body}"),
                why: "only a dynamic body can be dragged".into(),
            });
        }
        let frame = self.body_frame(i);
        let local = Transform {
            p: frame.q.apply_inv(target - frame.p),
            q: crate::Rot::IDENTITY,
        };
        let joint = Joint {
            body_a: i as u32,
            body_b: i as u32,
            local_a: local,
            local_b: local,
            collide_connected: true,
            hertz: 0.0,
            damping_ratio: 0.0,
            kind: JointKind::Mouse(Mouse::new(target, hertz, damping_ratio, max_force)),
            force_threshold: f32::INFINITY,
            torque_threshold: f32::INFINITY,
            user_data: 0,
            step: Default::default(),
        };
        let id = self.insert_joint(joint);
        self.debug_validate();
        Ok(id)
    }

    /// Moves a mouse joint's target.
    pub fn set_mouse_target(&mut self, id: JointId, target: Vec2) -> Result<(), WorldError> {
        if !target.is_finite() {
            return Err(WorldError::Invalid {
                what: format!("mouse target {target:?}"),
                why: "a finite point".into(),
            });
        }
        match self.joint_kind_mut(id)? {
            JointKind::Mouse(m) => {
                m.target = target;
                Ok(())
            }
            other => Err(WorldError::Invalid {
                what: format!("{id}, a {} joint", other.name()),
                why: "only a mouse joint has a target".into(),
            }),
        }
    }

    /// Puts a built joint in a slot, links its bodies' islands and keeps them apart unless
    /// it lets them touch. The caller checks the stores afterwards (`debug_validate`).
    pub(super) fn insert_joint(&mut self, joint: Joint) -> JointId {
        self.edit_joints();
        let (index, generation, fresh) = self.joints.slots.take();
        let (a, b) = (joint.body_a, joint.body_b);
        let keep_apart = !joint.collide_connected;
        let links = joint.links_islands();
        if fresh {
            self.joints.list.push(joint);
        } else {
            self.joints.list[index as usize] = joint;
        }
        for body in [a, b] {
            self.wake_body(body);
        }
        if links && self.links_islands_of(a, b) {
            self.islands.link(a, b);
        }
        if keep_apart {
            *self.joints.no_collide.entry(pair_key(a, b)).or_insert(0) += 1;
            if self.have_contacts(a, b) {
                self.remove_contacts_where(|c| pair_key(c.body_a, c.body_b) == pair_key(a, b));
            }
        }
        JointId { index, generation }
    }

    /// Whether bodies `a` and `b` have a contact: their shape pairs looked up in the pair map
    /// (a joint made between steps, often of new bodies, need not scan every contact).
    fn have_contacts(&self, a: u32, b: u32) -> bool {
        let scan = || {
            self.contacts
                .list
                .iter()
                .any(|c| pair_key(c.body_a, c.body_b) == pair_key(a, b))
        };
        let (na, nb) = (
            self.shapes_of_body(a as usize).count(),
            self.shapes_of_body(b as usize).count(),
        );
        if na.saturating_mul(nb) > self.contacts.list.len() {
            return scan();
        }
        let found = self.shapes_of_body(a as usize).any(|sa| {
            self.shapes_of_body(b as usize)
                .any(|sb| self.contacts.pairs.contains_key(&pair_key(sa, sb)))
        });
        debug_assert_eq!(found, scan());
        found
    }

    /// The slots of the live joints of body `body`, in slot order.
    pub(super) fn joints_of_body(&self, body: u32) -> impl Iterator<Item = u32> + '_ {
        (0..self.joints.list.len() as u32).filter(move |&k| {
            let j = &self.joints.list[k as usize];
            self.joints.slots.is_alive(k as usize) && (j.body_a == body || j.body_b == body)
        })
    }

    /// Whether a joint between bodies `a` and `b` joins their islands: both are dynamic and
    /// enabled (a disabled body has no island).
    pub(super) fn links_islands_of(&self, a: u32, b: u32) -> bool {
        let joins = |i: u32| {
            self.bodies.sims[i as usize].kind == BodyKind::Dynamic
                && !self.bodies.records[i as usize].disabled
        };
        joins(a) && joins(b)
    }

    pub(super) fn joint_slot(&self, id: JointId) -> Result<usize, WorldError> {
        if self.joints.slots.holds(id.index, id.generation) {
            Ok(id.index as usize)
        } else {
            Err(WorldError::NoJoint(id))
        }
    }

    /// Removes a joint between steps; its bodies wake, and may touch again if it kept them
    /// apart.
    pub fn destroy_joint(&mut self, id: JointId) -> Result<(), WorldError> {
        let k = self.joint_slot(id)?;
        self.remove_joint(k, |_| false);
        self.debug_validate();
        Ok(())
    }

    /// Removes joint `k`; `gone(b)` says whether body `b` is being destroyed with it (its
    /// shapes need not look for new pairs).
    pub(super) fn remove_joint(&mut self, k: usize, gone: impl Fn(u32) -> bool) {
        self.edit_joints();
        let joint = self.joints.list[k].clone();
        // The slot keeps an unsolved stand-in until it is reused.
        self.joints.list[k].kind = JointKind::Filter;
        self.joints.list[k].collide_connected = true;
        let (a, b) = (joint.body_a, joint.body_b);
        for body in [a, b] {
            self.wake_body(body);
        }
        if joint.links_islands() && self.links_islands_of(a, b) {
            self.islands.unlink(a, b);
        }
        if !joint.collide_connected {
            let key = pair_key(a, b);
            if let Some(n) = self.joints.no_collide.get_mut(&key) {
                *n -= 1;
                if *n == 0 {
                    self.joints.no_collide.remove(&key);
                }
            }
            // Their shapes look for each other again.
            for body in [a, b] {
                if !gone(body) {
                    self.refresh_shape_boxes(body);
                }
            }
        }
        self.joints.slots.release(k as u32);
    }

    /// Joints in the world.
    pub fn joint_count(&self) -> usize {
        self.joints.slots.live()
    }

    /// Every joint's id, in slot order.
    pub fn joint_ids(&self) -> impl Iterator<Item = JointId> + '_ {
        (0..self.joints.list.len())
            .filter(|&k| self.joints.slots.is_alive(k))
            .map(|k| JointId {
                index: k as u32,
                generation: self.joints.slots.generation(k),
            })
    }

    /// A joint: its bodies, frames, settings and impulses.
    pub fn joint(&self, id: JointId) -> Result<&Joint, WorldError> {
        Ok(self.current(self.joint_slot(id)?))
    }

    /// A joint's type and settings, to change between steps (a motor's speed, a limit);
    /// its bodies wake.
    pub fn joint_kind_mut(&mut self, id: JointId) -> Result<&mut JointKind, WorldError> {
        let k = self.joint_slot(id)?;
        // A limit, motor or spring added or taken away changes whether it can join a chain.
        self.edit_joints();
        let (a, b) = (self.joints.list[k].body_a, self.joints.list[k].body_b);
        self.wake_body(a);
        self.wake_body(b);
        Ok(&mut self.joints.list[k].kind)
    }

    /// A joint's two bodies, A and B (a mouse joint names its dragged body twice).
    pub fn joint_bodies(&self, id: JointId) -> Result<[BodyId; 2], WorldError> {
        let j = &self.joints.list[self.joint_slot(id)?];
        Ok([j.body_a, j.body_b].map(|b| BodyId {
            index: b,
            generation: self.bodies.slots.generation(b as usize),
        }))
    }

    /// The force (N, on body B) and torque (N·m) the joint applied in the last step.
    pub fn joint_reaction(&self, id: JointId) -> Result<(Vec2, f32), WorldError> {
        Ok(self
            .current(self.joint_slot(id)?)
            .reaction(self.joints.last_inv_h))
    }

    /// The joint's anchors in the world now: on body A and on body B (for a mouse joint,
    /// the target and the dragged point).
    pub fn joint_anchors(&self, id: JointId) -> Result<[Vec2; 2], WorldError> {
        let j = &self.joints.list[self.joint_slot(id)?];
        let on_b = self.body_frame(j.body_b as usize).apply(j.local_b.p);
        let on_a = match &j.kind {
            JointKind::Mouse(m) => m.target,
            _ => self.body_frame(j.body_a as usize).apply(j.local_a.p),
        };
        Ok([on_a, on_b])
    }

    /// Lists the awake joints in slot order, with their dynamic bodies, for the colouring,
    /// less those that chains take (reads the joints and the bodies' kinds and awake flags;
    /// writes the joint list and the chains).
    pub(super) fn list_awake_joints(&mut self) {
        self.joints.awake.clear();
        if self.joints.slots.live() == 0 {
            self.joints.chain_list.clear();
            self.joints.chain_ranges.clear();
            return;
        }
        // What the walk reads of each joint, kept compact (a joint is 200 bytes: reading each
        // one's kind and bodies every step missed the cache on half of `joint_grid`'s list).
        if self.joints.meta_stale {
            self.joints.meta.clear();
            self.joints
                .meta
                .extend(self.joints.list.iter().enumerate().map(|(k, j)| JointMeta {
                    bodies: [j.body_a, j.body_b],
                    // A joint to a disabled body is kept but not solved.
                    solved: self.joints.slots.is_alive(k)
                        && j.solved()
                        && !self.bodies.records[j.body_a as usize].disabled
                        && !self.bodies.records[j.body_b as usize].disabled,
                    mouse: matches!(j.kind, JointKind::Mouse(_)),
                    chain: chain::eligible(j),
                }));
            self.joints.thresholded.clear();
            let (slots, list) = (&self.joints.slots, &self.joints.list);
            self.joints
                .thresholded
                .extend((0..list.len() as u32).filter(|&k| {
                    let j = &list[k as usize];
                    slots.is_alive(k as usize)
                        && (j.force_threshold < f32::INFINITY || j.torque_threshold < f32::INFINITY)
                }));
            self.joints.meta_stale = false;
        }
        let awake_dynamic = |i: u32| {
            let i = i as usize;
            self.bodies.sims[i].kind == BodyKind::Dynamic && self.bodies.awake[i]
        };
        for (k, m) in self.joints.meta.iter().enumerate() {
            if !m.solved {
                continue;
            }
            let mouse = m.mouse;
            let [a, b] = m.bodies;
            if !(awake_dynamic(b) || (!mouse && awake_dynamic(a))) {
                continue;
            }
            let side = |i: u32| {
                if self.bodies.masses[i as usize].dynamic {
                    i
                } else {
                    NOT_DYNAMIC
                }
            };
            self.joints.awake.push(Touching {
                contact: k as u32,
                dynamic: [if mouse { NOT_DYNAMIC } else { side(a) }, side(b)],
            });
        }
        self.find_chains();
    }

    /// Takes the chains of hinges out of the joint list (see `joint::chain`), searching
    /// again only when the awake eligible joints differ from last step's.
    fn find_chains(&mut self) {
        // Into a kept buffer: a steady step allocates nothing.
        let mut links = std::mem::take(&mut self.joints.chain_scratch);
        links.clear();
        links.extend(
            self.joints
                .awake
                .iter()
                .filter(|t| self.joints.meta[t.contact as usize].chain)
                .map(|t| Link {
                    slot: t.contact,
                    dynamic: t.dynamic,
                }),
        );
        let same = links.len() == self.joints.chain_links.len()
            && links
                .iter()
                .zip(&self.joints.chain_links)
                .all(|(a, b)| a.slot == b.slot && a.dynamic == b.dynamic);
        if !same {
            let (order, ranges) = chain::find(&links, self.bodies.sims.len());
            self.joints.chain_list = order;
            self.joints.chain_ranges = ranges;
            std::mem::swap(&mut self.joints.chain_links, &mut links);
        }
        self.joints.chain_scratch = links;
        if self.joints.chain_list.is_empty() {
            return;
        }
        let mut in_chain = std::mem::take(&mut self.joints.chain_flags);
        in_chain.clear();
        in_chain.resize(self.joints.list.len(), false);
        for &slot in &self.joints.chain_list {
            in_chain[slot as usize] = true;
        }
        self.joints.awake.retain(|t| !in_chain[t.contact as usize]);
        self.joints.chain_flags = in_chain;
    }

    /// After the colouring: copies the awake joints into the solver in stage order and
    /// prepares them there (reads bodies' poses and masses; each copy written once).
    pub(super) fn prepare_solver_joints(&mut self, h: f32, spread: Spread<'_>, min: usize) {
        if self.joints.awake.is_empty() && self.joints.chain_list.is_empty() {
            return;
        }
        let ctx = JointContext {
            h,
            inv_h: 1.0 / h,
            warm_starting: self.settings.warm_starting,
        };
        if self.joints.solver_holds_impulses {
            // The order changed (or not): the solver tells; the old copies go back first
            // when it will copy afresh.
            if self.solver.joint_order_changed() {
                self.solver.store_joints(&mut self.joints.list, spread, min);
                self.joints.solver_holds_impulses = false;
            }
        }
        let copies = self.joints.solver_holds_impulses;
        let (sims, records, masses) =
            (&self.bodies.sims, &self.bodies.records, &self.bodies.masses);
        let body = |i: u32| {
            let i = i as usize;
            JointBody {
                center: sims[i].xf.p,
                q: sims[i].xf.q,
                local_center: records[i].local_center,
                inv_mass: masses[i].inv_mass,
                inv_inertia: masses[i].inv_inertia,
                dynamic: masses[i].dynamic,
            }
        };
        self.solver
            .prepare_joints(&self.joints.list, copies, &body, &ctx, spread, min);
        self.joints.solver_holds_impulses = true;
    }

    /// Readies the joint store for a change: the solver's live impulses are written back
    /// first, and the step's walk over the joints (`Joints::meta`, the chains) is rebuilt at
    /// the next step. Every change to a joint, its kind or the set of joints comes here.
    pub(super) fn edit_joints(&mut self) {
        self.sync_joints();
        self.joints.meta_stale = true;
    }

    /// Writes the solver's live joint copies back, so the world's joints are current (before
    /// the world reads them whole).
    pub(super) fn sync_joints(&mut self) {
        if self.joints.solver_holds_impulses {
            self.solver
                .store_joints(&mut self.joints.list, Spread::INLINE, usize::MAX);
            self.joints.solver_holds_impulses = false;
        }
    }

    /// A joint as it is now: the solver's live copy if it holds one, else the world's.
    pub(super) fn current(&self, k: usize) -> &Joint {
        if self.joints.solver_holds_impulses
            && let Some(j) = self.solver.joint_copy(k as u32)
        {
            return j;
        }
        &self.joints.list[k]
    }
}

/// What the step's walk over the joints reads of each (see `list_awake_joints`).
#[derive(Clone, Copy, Debug)]
pub(super) struct JointMeta {
    bodies: [u32; 2],
    /// Alive and not a filter joint.
    solved: bool,
    mouse: bool,
    /// It may join a chain (`joint::chain::eligible`).
    chain: bool,
}

impl Joint {
    /// Whether it joins its bodies' islands (a filter only keeps them apart; a mouse joint
    /// names one body).
    pub(crate) fn links_islands(&self) -> bool {
        !matches!(self.kind, JointKind::Filter | JointKind::Mouse(_))
    }
}
