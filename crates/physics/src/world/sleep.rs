//! Touching, islands and sleep (Box2D v3's `island.c` and `solver_set.c`, in flat arrays):
//! contacts that begin touching join their bodies' islands and wake a sleeping one; contacts
//! that stop touching mark their island for a split; an island whose bodies all rested for
//! `time_to_sleep` falls asleep, and then costs nothing: its bodies are not integrated, not
//! finalized and not moved in the broad phase, and its contacts are neither collided nor
//! solved (their manifolds and impulses wait for it to wake).
//!
//! Everything here is serial, in contact or body order, so it is the same on any thread count.

use glam::Vec2;

use super::{World, stores};
use crate::def::BodyKind;
use crate::island::NO_ISLAND;

impl World {
    /// Touch changes (reads each contact's key; writes islands, awake flags, the contact
    /// list): after the narrow phase, in contact order, a contact that began touching wakes
    /// a sleeping body of it and links two dynamic bodies' islands; one that stopped (or
    /// parted) unlinks them. Then parted contacts are removed in descending index order, so
    /// the surviving order is deterministic. `changes` is the narrow phase's count of such
    /// contacts: with none, nothing is walked.
    pub(super) fn update_touching(&mut self, changes: usize) {
        if self.bodies.kinematic_count > 0 {
            self.keep_touched_by_kinematic_awake();
        }
        if changes == 0 {
            return;
        }
        let mut woke = false;
        let mut changed = std::mem::take(&mut self.contacts.changed);
        let mut parted = std::mem::take(&mut self.contacts.parted);
        parted.clear();
        // In contact order, as a walk over every contact would meet them.
        for k in stores::drain_marks(&mut changed, self.contacts.list.len().div_ceil(64)) {
            let key = &mut self.contacts.keys[k];
            if key.remove {
                parted.push(k as u32);
            }
            let now = key.touching && !key.remove;
            if now == key.touched {
                continue;
            }
            key.touched = now;
            let c = &mut self.contacts.list[k];
            c.touched = now;
            c.hit_pending = now;
            let (a, b) = (c.body_a, c.body_b);
            let dynamic = (c.masses[0].dynamic, c.masses[1].dynamic);
            let (shape_a, shape_b) = (c.shape_a, c.shape_b);
            self.touch_changed(shape_a, shape_b, now);
            if now {
                for body in [a, b] {
                    if self.bodies.sims[body as usize].kind == BodyKind::Dynamic
                        && !self.bodies.awake[body as usize]
                    {
                        self.wake_island_of(body);
                        woke = true;
                    }
                }
                if dynamic.0 && dynamic.1 {
                    self.islands.link(a, b);
                }
            } else if dynamic.0 && dynamic.1 {
                self.islands.unlink(a, b);
            }
        }
        self.contacts.changed = changed;
        self.contacts.remove_parted(&parted);
        self.contacts.parted = parted;
        if woke {
            self.refresh_contact_keys();
        }
    }

    /// A kinematic body that moves keeps the dynamic bodies it touches from resting (it
    /// would otherwise push them after they fell asleep under it).
    fn keep_touched_by_kinematic_awake(&mut self) {
        let threshold = self.settings.sleep_threshold;
        let mut woke = false;
        // Only a touching contact of one dynamic body and one that is not can be a kinematic
        // body's: the narrow phase marked those (washer: its drum's, among 38,000), in
        // contact order.
        let mut one_sided = std::mem::take(&mut self.contacts.one_sided);
        let words = self.contacts.list.len().div_ceil(64);
        for k in stores::drain_marks(&mut one_sided, words) {
            let c = &self.contacts.list[k];
            for (mover, other) in [(c.body_a, c.body_b), (c.body_b, c.body_a)] {
                let (m, o) = (mover as usize, other as usize);
                if self.bodies.sims[m].kind != BodyKind::Kinematic
                    || self.bodies.sims[o].kind != BodyKind::Dynamic
                {
                    continue;
                }
                let st = &self.bodies.states[m];
                if st.v.length().max(self.bodies.sims[m].extent * st.w.abs()) > threshold {
                    self.bodies.sims[o].sleep_time = 0.0;
                    if !self.bodies.awake[o] {
                        self.wake_island_of(other);
                        woke = true;
                    }
                }
            }
        }
        self.contacts.one_sided = one_sided;
        if woke {
            self.refresh_contact_keys();
        }
    }

    /// Sleep (reads bodies' sleep times and islands; writes awake flags, velocities, motion
    /// flags, contact keys): after finalize, every awake island whose bodies all rested for
    /// `time_to_sleep` falls asleep, unless a constraint inside it went since it was whole;
    /// then the largest such island is split this step (Box2D splits one per step too), and
    /// its parts may sleep from the next.
    pub(super) fn update_sleep(&mut self) {
        if !self.settings.enable_sleep {
            return;
        }
        let time_to_sleep = self.settings.time_to_sleep;
        let mut sleepy = Vec::new();
        let mut split: Option<(usize, u32)> = None;
        // The awake islands only, in slot order: a sleeping one costs this stage nothing.
        self.islands.refresh_awake_list();
        for &k in &self.islands.awake_list {
            let island = &self.islands.islands[k as usize];
            let rested = island.bodies.iter().all(|&b| {
                self.bodies.sims[b as usize].sleep_time >= time_to_sleep
                    && self.bodies.records[b as usize].enable_sleep
            });
            if !rested {
                continue;
            }
            if island.constraints_removed > 0 {
                let size = island.bodies.len();
                if split.is_none_or(|(s, _)| size > s) {
                    split = Some((size, k));
                }
            } else {
                sleepy.push(k);
            }
        }
        if let Some((_, k)) = split {
            self.split_island(k);
        }
        if sleepy.is_empty() {
            return;
        }
        for k in sleepy {
            self.sleep_island(k);
        }
        self.refresh_contact_keys();
    }

    /// Puts island `k` to sleep, its bodies stopped (without refreshing the contact keys:
    /// the caller does, once).
    fn sleep_island(&mut self, k: u32) {
        self.islands.set_awake(k, false);
        let bodies = std::mem::take(&mut self.islands.islands[k as usize].bodies);
        for &b in &bodies {
            let i = b as usize;
            self.bodies.awake[i] = false;
            let st = &mut self.bodies.states[i];
            st.v = Vec2::ZERO;
            st.w = 0.0;
            self.bodies.refresh_motion(b);
        }
        self.islands.islands[k as usize].bodies = bodies;
    }

    /// Puts the island of dynamic body `body` to sleep now (Box2D's `b2Body_SetAwake` with
    /// false): an island that lost a constraint since it was whole is split first, and only
    /// the part holding `body` sleeps. A body touching a kinematic one, or an island
    /// jointed to one, wakes again at the next step as it would from any sleep.
    pub(super) fn sleep_island_of(&mut self, body: u32) {
        let k = self.islands.of_body[body as usize];
        if k == NO_ISLAND || !self.islands.islands[k as usize].awake {
            return;
        }
        if self.islands.islands[k as usize].constraints_removed > 0 {
            self.split_island(k);
        }
        let k = self.islands.of_body[body as usize];
        self.sleep_island(k);
        self.refresh_contact_keys();
    }

    /// Splits island `k` into the parts its touching contacts hold together.
    fn split_island(&mut self, k: u32) {
        let of = &self.islands.of_body;
        let links: Vec<(u32, u32)> = self
            .contacts
            .list
            .iter()
            .zip(&self.contacts.keys)
            .filter(|(c, key)| {
                key.touching
                    && c.masses[0].dynamic
                    && c.masses[1].dynamic
                    && of[c.body_a as usize] == k
                    && of[c.body_b as usize] == k
            })
            .map(|(c, _)| (c.body_a, c.body_b))
            .chain(
                self.joints
                    .list
                    .iter()
                    .enumerate()
                    .filter_map(|(j, joint)| {
                        let (a, b) = (joint.body_a, joint.body_b);
                        (self.joints.slots.is_alive(j)
                            && joint.links_islands()
                            && of[a as usize] == k
                            && of[b as usize] == k)
                            .then_some((a, b))
                    }),
            )
            .collect();
        self.islands.split(k, &links);
    }

    /// Wakes the island of dynamic body `body` (without refreshing the contact keys: the
    /// caller does, once).
    fn wake_island_of(&mut self, body: u32) {
        let k = self.islands.of_body[body as usize];
        if k == NO_ISLAND || self.islands.islands[k as usize].awake {
            return;
        }
        self.islands.set_awake(k, true);
        let bodies = std::mem::take(&mut self.islands.islands[k as usize].bodies);
        for &b in &bodies {
            self.bodies.awake[b as usize] = true;
            self.bodies.sims[b as usize].sleep_time = 0.0;
            self.bodies.refresh_motion(b);
        }
        self.islands.islands[k as usize].bodies = bodies;
    }

    /// Wakes every island.
    pub(super) fn wake_all(&mut self) {
        for k in 0..self.islands.islands.len() {
            if let Some(&first) = self.islands.islands[k].bodies.first() {
                self.wake_island_of(first);
            }
        }
        self.refresh_contact_keys();
    }

    /// Wakes a body's island (an API call changed it), and resets its rest.
    pub(super) fn wake_body(&mut self, body: u32) {
        let i = body as usize;
        self.bodies.sims[i].sleep_time = 0.0;
        if self.bodies.sims[i].kind == BodyKind::Dynamic && !self.bodies.awake[i] {
            self.wake_island_of(body);
            self.refresh_contact_keys();
        }
    }

    /// Wakes `bodies` and every body touching one of them (they are about to change or go,
    /// and what rests on them must notice); `among(b)` says whether body `b` is one of them.
    pub(super) fn wake_touching(&mut self, bodies: &[u32], among: impl Fn(u32) -> bool) {
        for &body in bodies {
            self.wake_body(body);
        }
        let mut others = Vec::new();
        for (c, key) in self.contacts.list.iter().zip(&self.contacts.keys) {
            if key.touching && among(c.body_a) != among(c.body_b) {
                others.push(if among(c.body_a) { c.body_b } else { c.body_a });
            }
        }
        let mut woke = false;
        for o in others {
            let i = o as usize;
            self.bodies.sims[i].sleep_time = 0.0;
            if self.bodies.sims[i].kind == BodyKind::Dynamic && !self.bodies.awake[i] {
                self.wake_island_of(o);
                woke = true;
            }
        }
        if woke {
            self.refresh_contact_keys();
        }
    }

    /// Recomputes each contact's `frozen` and `sleeping` flags from the awake flags.
    pub(super) fn refresh_contact_keys(&mut self) {
        self.contacts.refresh_sleep(&self.bodies.awake);
    }

    /// Rebuilds the awake set's body list if it is stale.
    pub(super) fn refresh_moving(&mut self) {
        if self.bodies.awake_set_stale {
            let motion = &self.bodies.motion;
            self.bodies.awake_set.clear();
            self.bodies
                .awake_set
                .extend((0..motion.len() as u32).filter(|&i| motion[i as usize].moves));
            self.bodies.awake_set_stale = false;
        }
    }

    /// Whether the contact stages walk the awake set's contacts (rebuilt first if stale)
    /// rather than every contact: only while some island sleeps. With none asleep every
    /// contact is awake, and a walk of the array itself is cheaper than one through a list.
    pub(super) fn walk_awake_contacts(&mut self) -> bool {
        if self.islands.awake_count() == self.islands.count() {
            return false;
        }
        if self.contacts.awake_stale {
            let keys = &self.contacts.keys;
            self.contacts.awake.clear();
            self.contacts
                .awake
                .extend((0..keys.len() as u32).filter(|&k| !keys[k as usize].frozen));
            self.contacts.awake_stale = false;
        }
        true
    }
}
