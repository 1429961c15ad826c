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
use crate::parallel::Spread;
use crate::solver::{NOT_DYNAMIC, Touching};

impl World {
    /// The frame (origin and rotation) of body `i`.
    pub(super) fn body_frame(&self, i: usize) -> Transform {
        let xf = self.sims[i].xf;
        Transform {
            p: xf.p - xf.q.apply(self.records[i].local_center),
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
        let index = self.joint_slots.next_index() as usize;
        let frames = |id: BodyId| {
            let i = id.index as usize;
            self.contains_body(id).then(|| JointFrame {
                frame: self.body_frame(i),
                dynamic: self.sims[i].kind == BodyKind::Dynamic,
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
        if self.sims[i].kind != BodyKind::Dynamic {
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
        self.sync_joints();
        self.joint_meta_stale = true;
        let (index, generation, fresh) = self.joint_slots.take();
        let (a, b) = (joint.body_a, joint.body_b);
        let keep_apart = !joint.collide_connected;
        let links = joint.links_islands();
        if fresh {
            self.joints.push(joint);
        } else {
            self.joints[index as usize] = joint;
        }
        for body in [a, b] {
            self.wake_body(body);
        }
        if links && self.is_dynamic(a) && self.is_dynamic(b) {
            self.islands.link(a, b);
        }
        if keep_apart {
            *self.no_collide.entry(pair_key(a, b)).or_insert(0) += 1;
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
                .iter()
                .any(|c| pair_key(c.body_a, c.body_b) == pair_key(a, b))
        };
        let (na, nb) = (
            self.shapes_of_body(a as usize).count(),
            self.shapes_of_body(b as usize).count(),
        );
        if na.saturating_mul(nb) > self.contacts.len() {
            return scan();
        }
        let found = self.shapes_of_body(a as usize).any(|sa| {
            self.shapes_of_body(b as usize)
                .any(|sb| self.pairs.contains_key(&pair_key(sa, sb)))
        });
        debug_assert_eq!(found, scan());
        found
    }

    fn is_dynamic(&self, body: u32) -> bool {
        self.sims[body as usize].kind == BodyKind::Dynamic
    }

    fn joint_slot(&self, id: JointId) -> Result<usize, WorldError> {
        if self.joint_slots.holds(id.index, id.generation) {
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
        self.sync_joints();
        self.joint_meta_stale = true;
        let joint = self.joints[k].clone();
        // The slot keeps an unsolved stand-in until it is reused.
        self.joints[k].kind = JointKind::Filter;
        self.joints[k].collide_connected = true;
        let (a, b) = (joint.body_a, joint.body_b);
        for body in [a, b] {
            self.wake_body(body);
        }
        if joint.links_islands() && self.is_dynamic(a) && self.is_dynamic(b) {
            self.islands.unlink(a, b);
        }
        if !joint.collide_connected {
            let key = pair_key(a, b);
            if let Some(n) = self.no_collide.get_mut(&key) {
                *n -= 1;
                if *n == 0 {
                    self.no_collide.remove(&key);
                }
            }
            // Their shapes look for each other again.
            for body in [a, b] {
                if !gone(body) {
                    self.refresh_shape_boxes(body);
                }
            }
        }
        self.joint_slots.release(k as u32);
    }

    /// Joints in the world.
    pub fn joint_count(&self) -> usize {
        self.joint_slots.live()
    }

    /// Every joint's id, in slot order.
    pub fn joint_ids(&self) -> impl Iterator<Item = JointId> + '_ {
        (0..self.joints.len())
            .filter(|&k| self.joint_slots.is_alive(k))
            .map(|k| JointId {
                index: k as u32,
                generation: self.joint_slots.generation(k),
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
        self.sync_joints();
        // A limit, motor or spring added or taken away changes whether it can join a chain.
        self.joint_meta_stale = true;
        let (a, b) = (self.joints[k].body_a, self.joints[k].body_b);
        self.wake_body(a);
        self.wake_body(b);
        Ok(&mut self.joints[k].kind)
    }

    /// A joint's two bodies, A and B (a mouse joint names its dragged body twice).
    pub fn joint_bodies(&self, id: JointId) -> Result<[BodyId; 2], WorldError> {
        let j = &self.joints[self.joint_slot(id)?];
        Ok([j.body_a, j.body_b].map(|b| BodyId {
            index: b,
            generation: self.body_slots.generation(b as usize),
        }))
    }

    /// The force (N, on body B) and torque (N·m) the joint applied in the last step.
    pub fn joint_reaction(&self, id: JointId) -> Result<(Vec2, f32), WorldError> {
        Ok(self.current(self.joint_slot(id)?).reaction(self.last_inv_h))
    }

    /// The joint's anchors in the world now: on body A and on body B (for a mouse joint,
    /// the target and the dragged point).
    pub fn joint_anchors(&self, id: JointId) -> Result<[Vec2; 2], WorldError> {
        let j = &self.joints[self.joint_slot(id)?];
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
        self.joint_list.clear();
        if self.joint_slots.live() == 0 {
            self.chain_list.clear();
            self.chain_ranges.clear();
            return;
        }
        // What the walk reads of each joint, kept compact (a joint is 200 bytes: reading each
        // one's kind and bodies every step missed the cache on half of `joint_grid`'s list).
        if self.joint_meta_stale {
            self.joint_meta.clear();
            self.joint_meta
                .extend(self.joints.iter().enumerate().map(|(k, j)| JointMeta {
                    bodies: [j.body_a, j.body_b],
                    solved: self.joint_slots.is_alive(k) && j.solved(),
                    mouse: matches!(j.kind, JointKind::Mouse(_)),
                    chain: chain::eligible(j),
                }));
            self.joint_meta_stale = false;
        }
        let awake_dynamic = |i: u32| {
            let i = i as usize;
            self.sims[i].kind == BodyKind::Dynamic && self.awake[i]
        };
        for (k, m) in self.joint_meta.iter().enumerate() {
            if !m.solved {
                continue;
            }
            let mouse = m.mouse;
            let [a, b] = m.bodies;
            if !(awake_dynamic(b) || (!mouse && awake_dynamic(a))) {
                continue;
            }
            let side = |i: u32| {
                if self.solver_bodies[i as usize].dynamic {
                    i
                } else {
                    NOT_DYNAMIC
                }
            };
            self.joint_list.push(Touching {
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
        let mut links = std::mem::take(&mut self.chain_scratch);
        links.clear();
        links.extend(
            self.joint_list
                .iter()
                .filter(|t| self.joint_meta[t.contact as usize].chain)
                .map(|t| Link {
                    slot: t.contact,
                    dynamic: t.dynamic,
                }),
        );
        let same = links.len() == self.chain_links.len()
            && links
                .iter()
                .zip(&self.chain_links)
                .all(|(a, b)| a.slot == b.slot && a.dynamic == b.dynamic);
        if !same {
            let (order, ranges) = chain::find(&links, self.sims.len());
            self.chain_list = order;
            self.chain_ranges = ranges;
            std::mem::swap(&mut self.chain_links, &mut links);
        }
        self.chain_scratch = links;
        if self.chain_list.is_empty() {
            return;
        }
        let mut in_chain = std::mem::take(&mut self.chain_flags);
        in_chain.clear();
        in_chain.resize(self.joints.len(), false);
        for &slot in &self.chain_list {
            in_chain[slot as usize] = true;
        }
        self.joint_list.retain(|t| !in_chain[t.contact as usize]);
        self.chain_flags = in_chain;
    }

    /// After the colouring: copies the awake joints into the solver in stage order and
    /// prepares them there (reads bodies' poses and masses; each copy written once).
    pub(super) fn prepare_solver_joints(&mut self, h: f32, spread: Spread<'_>, min: usize) {
        if self.joint_list.is_empty() && self.chain_list.is_empty() {
            return;
        }
        let ctx = JointContext {
            h,
            inv_h: 1.0 / h,
            warm_starting: self.settings.warm_starting,
        };
        if self.joint_copies {
            // The order changed (or not): the solver tells; the old copies go back first
            // when it will copy afresh.
            if self.solver.joint_order_changed() {
                self.solver.store_joints(&mut self.joints, spread, min);
                self.joint_copies = false;
            }
        }
        let copies = self.joint_copies;
        let (sims, records, masses) = (&self.sims, &self.records, &self.solver_bodies);
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
            .prepare_joints(&self.joints, copies, &body, &ctx, spread, min);
        self.joint_copies = true;
    }

    /// Writes the solver's live joint copies back, so the world's joints are current (before
    /// the world reads them whole or edits one).
    pub(super) fn sync_joints(&mut self) {
        if self.joint_copies {
            self.solver
                .store_joints(&mut self.joints, Spread::INLINE, usize::MAX);
            self.joint_copies = false;
        }
    }

    /// A joint as it is now: the solver's live copy if it holds one, else the world's.
    pub(super) fn current(&self, k: usize) -> &Joint {
        if self.joint_copies
            && let Some(j) = self.solver.joint_copy(k as u32)
        {
            return j;
        }
        &self.joints[k]
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
