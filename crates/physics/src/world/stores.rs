//! The world's stores: bodies, shapes (with their broad-phase proxies), contacts and joints,
//! each owning its rows (flat arrays by slot, which the step's stages split across threads)
//! and the flags that say what changed since the step last looked. A change goes through the
//! store's own methods, which raise those flags themselves (Rapier's `RigidBodySet` records
//! its changes the same way), so a new setter on `World` cannot forget one.
//!
//! Islands are a store of their own (`crate::island::Islands`); the world's counters, the
//! worker threads and continuous collision's buffers are the small structs at the end.

use std::ops::Range;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

use glam::Vec2;
use rustc_hash::FxHashMap;

use super::joints::JointMeta;
use super::{BodyRecord, BodySim, Contact, ContactKey, ShapeRecord, pair_key};
use crate::body::BodyState;
use crate::collision::broad_phase::BroadPhase;
use crate::def::BodyKind;
use crate::id::Slots;
use crate::joint::Joint;
use crate::joint::chain::Link;
use crate::math::Transform;
use crate::profile::StepProfile;
use crate::shape::{Aabb, Shape};
use crate::solver::{BodyMotion, ForceAcceleration, SolverBody, Touching};
use crate::threads::crew::Crew;

/// Bodies, by slot (a body's id's `index`).
#[derive(Default)]
pub(super) struct Bodies {
    /// Which slots hold a body, and each slot's generation.
    pub slots: Slots,
    /// What the step reads but the substeps do not: pose, kind, extents, sleep timer.
    pub sims: Vec<BodySim>,
    /// Velocities and substep deltas: what the substeps read and write.
    pub states: Vec<BodyState>,
    /// What the step does not read every step: local centre, shapes, damping, user data.
    pub records: Vec<BodyRecord>,
    /// Inverse mass and inertia as the solver reads them.
    pub masses: Vec<SolverBody>,
    /// How each body moves (integrated, kinematic, fixed rotation).
    pub motion: Vec<BodyMotion>,
    /// Awake: kinematic bodies and awake dynamic ones (never static ones or free slots).
    pub awake: Vec<bool>,
    /// The awake set's bodies (Box2D's awake solver set, as a list of slots): every body
    /// whose `motion.moves`, ascending. The body stages walk it, so a sleeping body costs
    /// them nothing. Rebuilt at the next step when `awake_set_stale`.
    pub awake_set: Vec<u32>,
    pub awake_set_stale: bool,
    /// Kinematic bodies in the world (their motion keeps what they touch awake).
    pub kinematic_count: usize,
    /// Forces and torques applied since the last step, by slot (zero where none): they act
    /// through the next step and are then cleared (Box2D's rule).
    pub forces: Vec<AppliedForce>,
    /// The bodies with a force in `forces`, each once, in the order first given one.
    pub forced: Vec<u32>,
    /// Scratch: each body's acceleration from its force, filled for `forced` at a step.
    pub force_accels: Vec<ForceAcceleration>,
}

/// A force and torque applied to a body for the next step.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub(super) struct AppliedForce {
    /// N, through the centre of mass.
    pub force: Vec2,
    /// N·m.
    pub torque: f32,
    /// The body is in `Bodies::forced`.
    pub listed: bool,
}

impl Bodies {
    /// The integration flags of body `i` from its kind, mass and sleep state; the awake
    /// set is rebuilt at the next step if whether it moves changed.
    pub fn refresh_motion(&mut self, i: u32) {
        let i = i as usize;
        let kind = self.sims[i].kind;
        let r = &self.records[i];
        let awake = self.awake[i];
        if self.motion[i].moves != (kind != BodyKind::Static && awake) {
            self.awake_set_stale = true;
        }
        self.motion[i] = BodyMotion {
            dynamic: kind == BodyKind::Dynamic && awake,
            moves: kind != BodyKind::Static && awake,
            rotates: match kind {
                BodyKind::Static => false,
                BodyKind::Kinematic => true,
                BodyKind::Dynamic => self.sims[i].inv_inertia > 0.0,
            },
            linear_damping: r.linear_damping,
            angular_damping: r.angular_damping,
            gravity_scale: r.gravity_scale,
        };
    }

    /// Adds a force and torque to body `i`'s for the next step.
    pub fn add_force(&mut self, i: u32, force: Vec2, torque: f32) {
        let f = &mut self.forces[i as usize];
        if !f.listed {
            f.listed = true;
            self.forced.push(i);
        }
        f.force += force;
        f.torque += torque;
    }

    /// Fills `force_accels` for each forced body, for the step's integration; false when
    /// no body has a force (the integration is then told of none, at no cost).
    pub fn refresh_force_accelerations(&mut self) -> bool {
        if self.forced.is_empty() {
            return false;
        }
        self.force_accels
            .resize(self.forces.len(), ForceAcceleration::default());
        for &i in &self.forced {
            let (f, m) = (self.forces[i as usize], self.masses[i as usize]);
            self.force_accels[i as usize] = ForceAcceleration {
                linear: f.force * m.inv_mass,
                angular: f.torque * m.inv_inertia,
            };
        }
        true
    }

    /// Clears every applied force (after the step they acted through).
    pub fn clear_forces(&mut self) {
        for i in self.forced.drain(..) {
            self.forces[i as usize] = AppliedForce::default();
            if let Some(a) = self.force_accels.get_mut(i as usize) {
                *a = ForceAcceleration::default();
            }
        }
    }

    /// Keeps the count of kinematic bodies as a body goes from kind `old` to `new` (a new
    /// body comes from, and a destroyed one goes to, `Static`, which is not counted).
    pub fn count_kind(&mut self, old: BodyKind, new: BodyKind) {
        if old == BodyKind::Kinematic {
            self.kinematic_count -= 1;
        }
        if new == BodyKind::Kinematic {
            self.kinematic_count += 1;
        }
    }
}

/// Shapes, by slot, with the broad phase's proxies (one per shape, by the same slot).
#[derive(Default)]
pub(super) struct Shapes {
    /// Which slots hold a shape, and each slot's generation.
    pub slots: Slots,
    /// Each shape's geometry, centred on its own frame.
    pub geometry: Vec<Shape>,
    /// Each shape's body, frame, material, filter and place in its body's list.
    pub records: Vec<ShapeRecord>,
    /// Each shape's body (a compact copy of `ShapeRecord::body` for the broad phase).
    pub body: Vec<u32>,
    /// Each shape's fat box, swept along its body's velocity over a step: the broad phase's
    /// proxies. A pair with a static body needs these to overlap, so that a fast body meets
    /// a wall a step early and its speculative contact stops it.
    pub swept_boxes: Vec<Aabb>,
    /// Each shape's fat box without the sweep along its velocity. A pair of two moving
    /// bodies needs these to overlap too (Box2D's pairs: fat boxes, no sweep): bodies that
    /// fall side by side then make no pair. A shape of a static body or a bullet has
    /// [`Aabb::EVERYWHERE`], so its pairs go by the swept boxes alone.
    pub unswept_boxes: Vec<Aabb>,
    /// Each proxy's swept and core boxes at the last pair search that took it, or
    /// [`Aabb::NOWHERE`] twice where every pair of it must be looked up again (a new or
    /// enabled shape, one whose filter, kind or contacts changed between steps). Two proxies
    /// whose searched boxes overlap by the pair rule have their contact, if they want one
    /// (see `World::find_new_pairs`): the pair search then skips the pair map for them.
    pub searched_boxes: Vec<[Aabb; 2]>,
    /// Proxies whose boxes changed since the last pair search.
    pub moved_proxies: Vec<u32>,
    /// Per proxy: whether it is in `moved_proxies` (or in `moved_done`, until the narrow
    /// phase has retested its contacts' boxes).
    pub moved_flags: Vec<bool>,
    /// The proxies the pair search just took from `moved_proxies`: their flags stay set
    /// until the narrow phase has retested their contacts' boxes, then are cleared (the
    /// buffers of the two lists take turns, so a steady step allocates nothing).
    pub moved_done: Vec<u32>,
    /// Scratch: each moved proxy's place in `moved_proxies` (the tree walk's creation order).
    pub moved_rank: Vec<u32>,
    /// A proxy was added or removed: the tree must be rebuilt, not refitted.
    pub proxies_changed: bool,
    /// A proxy's box changed: the tree must be refitted (or rebuilt).
    pub tree_dirty: bool,
    /// The broad phase's tree of every proxy's swept box.
    pub tree: BroadPhase,
    /// A tree of the static shapes alone, which a fast body is swept against (Box2D keeps a
    /// tree per body type): rebuilt when a static shape is added, removed or moved.
    pub static_tree: BroadPhase,
    pub static_tree_stale: bool,
    /// Some shape has had a tangent speed or rolling resistance: prepare reads contacts'
    /// surface materials from their shapes (set, never cleared but by a snapshot's restore).
    pub any_surface: bool,
}

impl Shapes {
    /// Puts a shape in slot `s` (taken from `slots`; `new`: the slot is new, at the end),
    /// with empty boxes until its body fits them. The tree is rebuilt at the next step.
    pub fn put(&mut self, s: u32, new: bool, shape: Shape, record: ShapeRecord) {
        let empty = Aabb {
            min: glam::Vec2::ZERO,
            max: glam::Vec2::ZERO,
        };
        let body = record.body;
        self.any_surface |= record.tangent_speed != 0.0 || record.rolling_resistance > 0.0;
        if new {
            self.geometry.push(shape);
            self.records.push(record);
            self.body.push(body);
            self.swept_boxes.push(empty);
            self.unswept_boxes.push(empty);
            self.moved_flags.push(false);
            self.searched_boxes.push([Aabb::NOWHERE; 2]);
        } else {
            let su = s as usize;
            self.geometry[su] = shape;
            self.records[su] = record;
            self.body[su] = body;
            self.swept_boxes[su] = empty;
            self.unswept_boxes[su] = empty;
            self.moved_flags[su] = false;
            self.searched_boxes[su] = [Aabb::NOWHERE; 2];
        }
        self.proxies_changed = true;
        self.static_tree_stale = true;
        self.tree_dirty = true;
    }

    /// Frees slot `s` (its body has already unlinked it) and drops its proxy.
    pub fn release(&mut self, s: u32) {
        let su = s as usize;
        if self.moved_flags[su] {
            self.moved_flags[su] = false;
            self.moved_proxies.retain(|&m| m != s);
        }
        self.records[su].next = super::NONE;
        self.records[su].body = super::NONE;
        self.body[su] = super::NONE;
        self.slots.release(s);
        self.proxies_changed = true;
        self.static_tree_stale = true;
        self.tree_dirty = true;
    }

    /// Gives proxy `s` new boxes and queues it for the next pair search; `is_static` says
    /// whether its body is static (the static tree is then stale too).
    /// A disabled shape's boxes are kept for when it comes back, but it is not queued.
    pub fn set_boxes(&mut self, s: u32, swept: Aabb, unswept: Aabb, is_static: bool) {
        let su = s as usize;
        self.swept_boxes[su] = swept;
        self.unswept_boxes[su] = unswept;
        if self.records[su].disabled {
            return;
        }
        self.mark_moved(s);
        self.tree_dirty = true;
        if is_static {
            self.static_tree_stale = true;
        }
    }

    /// Takes shape `s` out of the broad phase (`disabled`) or puts it back: the trees are
    /// rebuilt without or with it at their next use, and a disabled shape leaves the moved
    /// list (an enabled one is queued by its body's new boxes).
    pub fn set_disabled(&mut self, s: u32, disabled: bool) {
        let su = s as usize;
        self.records[su].disabled = disabled;
        self.searched_boxes[su] = [Aabb::NOWHERE; 2];
        if disabled && self.moved_flags[su] {
            self.moved_flags[su] = false;
            self.moved_proxies.retain(|&m| m != s);
        }
        self.proxies_changed = true;
        self.static_tree_stale = true;
        self.tree_dirty = true;
    }

    /// Forgets every proxy's searched boxes (see `searched_boxes`): the next pair search
    /// looks up every pair it finds.
    pub fn forget_searched(&mut self) {
        self.searched_boxes.fill([Aabb::NOWHERE; 2]);
    }

    /// Queues proxy `s` for the next pair search (once, however often it moves), which looks
    /// up every pair of it (a change made between steps may have removed its contacts or
    /// changed which pairs want one; finalize's moves, which change neither, queue a proxy
    /// without this).
    pub fn mark_moved(&mut self, s: u32) {
        let su = s as usize;
        self.searched_boxes[su] = [Aabb::NOWHERE; 2];
        if !self.moved_flags[su] {
            self.moved_flags[su] = true;
            self.moved_proxies.push(s);
        }
    }
}

/// Contacts, in the deterministic order the solver sees them.
#[derive(Default)]
pub(super) struct Contacts {
    pub list: Vec<Contact>,
    /// One per contact, in the same order: what the passes over every contact read.
    pub keys: Vec<ContactKey>,
    /// The awake set's contacts: every contact not `frozen`, ascending. While an island
    /// sleeps, the contact stages walk it instead of every contact. Rebuilt when needed
    /// once `awake_stale`.
    pub awake: Vec<u32>,
    pub awake_stale: bool,
    /// Each contact's place in `list`, by its shapes' `pair_key`.
    pub pairs: FxHashMap<u64, u32>,
    /// This step's touching contacts, in contact order (reused).
    pub touching: Vec<Touching>,
    /// One bit per contact, set by the narrow phase where a contact began or stopped
    /// touching or parted, and cleared by the touch update that handles it: that update
    /// walks what changed (a few hundred of washer's 38,000 contacts), not every contact.
    pub changed: Vec<AtomicU64>,
    /// One bit per contact, set by the narrow phase (in a world with a kinematic body) where
    /// a touching contact has one dynamic body: the ones a kinematic body may hold awake.
    pub one_sided: Vec<AtomicU64>,
    /// The parted contacts of this step's touch update, ascending (reused).
    pub parted: Vec<u32>,
}

/// Sets bit `k` of a bitmap that workers share (each contact is one worker's; two parts
/// may share a word, hence the atomic).
#[inline]
pub(super) fn mark(bits: &[AtomicU64], k: usize) {
    bits[k >> 6].fetch_or(1 << (k & 63), Ordering::Relaxed);
}

/// The set bits of `bits`' first `words` words, ascending, each cleared as it is read.
pub(super) fn drain_marks(
    bits: &mut [AtomicU64],
    words: usize,
) -> impl Iterator<Item = usize> + '_ {
    bits[..words].iter_mut().enumerate().flat_map(|(w, word)| {
        let mut b = std::mem::take(word.get_mut());
        std::iter::from_fn(move || {
            (b != 0).then(|| {
                let k = w * 64 + b.trailing_zeros() as usize;
                b &= b - 1;
                k
            })
        })
    })
}

impl Contacts {
    /// Appends a new contact, with its key and its pair, and lists it awake unless its
    /// bodies sleep.
    pub fn push(&mut self, contact: Contact, awake: &[bool]) {
        let k = self.list.len() as u32;
        self.pairs
            .insert(pair_key(contact.shape_a, contact.shape_b), k);
        let key = ContactKey::of(&contact, awake);
        // The newest contact comes last, so the ascending list stays ascending.
        if !key.frozen && !self.awake_stale {
            self.awake.push(k);
        }
        self.keys.push(key);
        self.list.push(contact);
    }

    /// Sizes the change bitmaps for the narrow phase (they only grow: a steady step
    /// allocates nothing). Every bit is clear: the touch update clears what it reads.
    pub fn size_marks(&mut self) {
        let words = self.list.len().div_ceil(64);
        if self.changed.len() < words {
            self.changed.resize_with(words, || AtomicU64::new(0));
            self.one_sided.resize_with(words, || AtomicU64::new(0));
        }
    }

    /// Removes the contacts `parted` (ascending, each marked `remove`), from the last down,
    /// each replaced by the last contact (so the order is the same on any thread count, and
    /// the same as a walk over every contact from the last down).
    pub fn remove_parted(&mut self, parted: &[u32]) {
        for &k in parted.iter().rev() {
            let k = k as usize;
            debug_assert!(self.keys[k].remove);
            self.awake_stale = true;
            self.keys.swap_remove(k);
            let c = self.list.swap_remove(k);
            self.pairs.remove(&pair_key(c.shape_a, c.shape_b));
            if k < self.list.len() {
                let moved = &self.list[k];
                self.pairs
                    .insert(pair_key(moved.shape_a, moved.shape_b), k as u32);
            }
        }
    }

    /// Keeps the first `keep` contacts (the caller has moved the ones it keeps there, in
    /// order) and maps the pairs to their places again.
    pub fn truncate(&mut self, keep: usize) {
        if keep != self.list.len() {
            self.awake_stale = true;
            self.list.truncate(keep);
            self.keys.truncate(keep);
            self.pairs = self
                .list
                .iter()
                .enumerate()
                .map(|(k, c)| (pair_key(c.shape_a, c.shape_b), k as u32))
                .collect();
        }
    }

    /// Recomputes each contact's `frozen` and `sleeping` flags from the bodies' awake flags.
    pub fn refresh_sleep(&mut self, awake: &[bool]) {
        self.awake_stale = true;
        for (c, key) in self.list.iter().zip(&mut self.keys) {
            let fresh = ContactKey::of(c, awake);
            key.frozen = fresh.frozen;
            key.sleeping = fresh.sleeping;
            key.retest |= fresh.frozen;
        }
    }

    /// Copies body `body`'s masses into its contacts again (prepare reads no body).
    pub fn refresh_masses(&mut self, body: u32, masses: &[SolverBody], awake: &[bool]) {
        self.awake_stale = true;
        for (c, key) in self.list.iter_mut().zip(&mut self.keys) {
            if c.body_a == body || c.body_b == body {
                c.masses = [masses[c.body_a as usize], masses[c.body_b as usize]];
                *key = ContactKey {
                    touching: key.touching,
                    ..ContactKey::of(c, awake)
                };
            }
        }
    }
}

/// Joints, by slot, and what the step derives from them.
#[derive(Default)]
pub(super) struct Joints {
    pub slots: Slots,
    /// Joints by slot (a free slot holds its last joint, unsolved).
    pub list: Vec<Joint>,
    /// Pairs of bodies (by `pair_key`) that joints keep from touching, with how many do.
    pub no_collide: FxHashMap<u64, u32>,
    /// This step's awake joints, for the colouring (less those the chains take).
    pub awake: Vec<Touching>,
    /// Last step's substep rate, for the joints' reaction forces.
    pub last_inv_h: f32,
    /// This step's chains of hinges (slots in path order) and each chain's range.
    pub chain_list: Vec<u32>,
    pub chain_ranges: Vec<Range<usize>>,
    /// The eligible joints the chains were found among (searched again when they change),
    /// and per-slot scratch.
    pub chain_links: Vec<Link>,
    pub chain_scratch: Vec<Link>,
    pub chain_flags: Vec<bool>,
    /// The solver holds the awake joints' live state (impulses): `list` is stale for them
    /// until `World::sync_joints` (see `Solver::prepare_joints`).
    pub solver_holds_impulses: bool,
    /// Each joint slot's bodies and kind flags, for the step's walk; rebuilt when a joint is
    /// made, destroyed or edited (`meta_stale`).
    pub meta: Vec<JointMeta>,
    pub meta_stale: bool,
    /// Live joints with a finite force or torque threshold, by slot (rebuilt with `meta`).
    pub thresholded: Vec<u32>,
}

/// What the world counts over its life and measures each step.
pub(super) struct Stats {
    pub steps: u64,
    /// The last step's length (s; 1/60 before the first): a body made or moved between
    /// steps has its boxes swept over a step this long.
    pub last_dt: f32,
    /// How often a body's speed was clamped to the caps.
    pub speed_caps: u64,
    /// Bodies the numerical guard stopped in the last step.
    pub guarded_last_step: usize,
    /// Every body the guard has stopped, over the world's whole life (snapshots keep it).
    pub non_finite_bodies: u64,
    /// The last step's per-stage profile.
    pub profile: StepProfile,
    /// Contacts whose manifold the last step recycled, for the profile.
    pub recycled: usize,
    /// Bodies continuous collision moved back in the last step, for the profile.
    pub rewound: usize,
}

impl Default for Stats {
    fn default() -> Stats {
        Stats {
            steps: 0,
            last_dt: 1.0 / 60.0,
            speed_caps: 0,
            guarded_last_step: 0,
            non_finite_bodies: 0,
            profile: StepProfile::default(),
            recycled: 0,
            rewound: 0,
        }
    }
}

/// Continuous collision's kept buffers.
#[derive(Default)]
pub(super) struct Sweeps {
    /// Each fast body's pose at the step's start (by slot).
    pub starts: Vec<Transform>,
    /// This step's fast bodies.
    pub fast_bodies: Vec<u32>,
    /// Each fast body's time of impact in this pass, by its place in `fast_bodies`.
    pub impacts: Vec<f32>,
}

/// The threads that help the caller's with a wide step.
pub(super) struct Workers {
    /// `None` at one thread, and where the platform has no threads (see
    /// [`super::set_thread_source`]): every step is then inline.
    pub crew: Option<Arc<Crew>>,
    pub threads: usize,
    /// Whether the substeps pay split over the crew, as timed (`WideThresholds::solve_by_payoff`).
    pub solve_payoff: crate::threads::payoff::Payoff,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The touch update meets the marked contacts in ascending order, each once, and leaves
    /// every bit clear for the next step (a bit left set would replay a change).
    #[test]
    fn marks_drain_in_contact_order_and_clear() {
        let bits: Vec<AtomicU64> = (0..3).map(|_| AtomicU64::new(0)).collect();
        for k in [130, 0, 63, 64, 7, 63] {
            mark(&bits, k);
        }
        let mut bits = bits;
        let drained: Vec<usize> = drain_marks(&mut bits, 3).collect();
        assert_eq!(drained, vec![0, 7, 63, 64, 130]);
        assert!(bits.iter_mut().all(|w| *w.get_mut() == 0));
        assert_eq!(drain_marks(&mut bits, 3).count(), 0);
    }
}
