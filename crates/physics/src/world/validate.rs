//! The invariants between the world's stores, checked in one place: tests call
//! [`World::validate`] after every change and step, and debug builds after every API change.

use super::{ContactKey, NONE, World, pair_key};
use crate::def::BodyKind;
use crate::island::NO_ISLAND;
use crate::shape::Aabb;

impl World {
    /// Checks every invariant between the stores: ids and free slots; each body's shape
    /// list against each shape's body; mass data against a fresh computation from the
    /// shapes; contacts against their shapes, bodies, pair map and keys; islands against
    /// bodies and touching contacts; sleeping bodies at rest and out of every stage; the
    /// broad phase's moved list. Returns the first broken one, described.
    pub fn validate(&self) -> Result<(), String> {
        self.body_slots
            .check()
            .map_err(|e| format!("body slots: {e}"))?;
        self.shape_slots
            .check()
            .map_err(|e| format!("shape slots: {e}"))?;
        // The sensors tracked are the live sensor shapes.
        let sensor_shapes = (0..self.shapes.len())
            .filter(|&s| self.shape_slots.is_alive(s) && self.shape_records[s].sensor)
            .map(|s| s as u32);
        if !sensor_shapes.eq(self.sensors.keys().copied()) {
            return Err("the tracked sensors are not the live sensor shapes".into());
        }
        let n = self.sims.len();
        let mut owner = vec![NONE; self.shapes.len()];
        for i in 0..n {
            let alive = self.body_slots.is_alive(i);
            let kind = self.sims[i].kind;
            if !alive {
                if self.records[i].first_shape != NONE || self.awake[i] || self.motion[i].moves {
                    return Err(format!("free body slot {i} has shapes or moves"));
                }
                continue;
            }
            let mut count = 0;
            for s in self.shapes_of_body(i) {
                let su = s as usize;
                if !self.shape_slots.is_alive(su) {
                    return Err(format!("body {i} lists free shape slot {s}"));
                }
                if owner[su] != NONE || self.shape_records[su].body as usize != i {
                    return Err(format!(
                        "shape {s} is listed by body {i} but belongs elsewhere"
                    ));
                }
                if self.shape_body[su] as usize != i {
                    return Err(format!("shape {s}'s compact body copy is stale"));
                }
                if self.sweeps_every_pair(i) != (self.core_aabbs[su] == Aabb::EVERYWHERE) {
                    return Err(format!(
                        "shape {s}'s core box does not match its body ({kind:?}, bullet {})",
                        self.records[i].bullet
                    ));
                }
                owner[su] = i as u32;
                count += 1;
            }
            if count == 0 {
                return Err(format!("body {i} has no shape"));
            }
            // Mass data: exactly what a fresh computation gives.
            let md = self.shapes_mass(i);
            let sb = self.solver_bodies[i];
            let dynamic = kind == BodyKind::Dynamic;
            let inv_mass = if dynamic && md.mass > 0.0 {
                1.0 / md.mass
            } else {
                0.0
            };
            if sb.inv_mass != inv_mass || sb.dynamic != dynamic {
                return Err(format!(
                    "body {i}'s mass is stale ({} vs {inv_mass})",
                    sb.inv_mass
                ));
            }
            let center = if dynamic { md.center } else { glam::Vec2::ZERO };
            if self.records[i].local_center != center {
                return Err(format!("body {i}'s centre of mass is stale"));
            }
            // Awake and motion flags.
            let island = self.islands.of_body.get(i).copied().unwrap_or(NO_ISLAND);
            match kind {
                BodyKind::Static => {
                    if self.awake[i] || island != NO_ISLAND {
                        return Err(format!("static body {i} is awake or in an island"));
                    }
                }
                BodyKind::Kinematic => {
                    if !self.awake[i] || island != NO_ISLAND {
                        return Err(format!("kinematic body {i} sleeps or is in an island"));
                    }
                }
                BodyKind::Dynamic => {
                    if island == NO_ISLAND {
                        return Err(format!("dynamic body {i} is in no island"));
                    }
                    if self.islands.islands[island as usize].awake != self.awake[i] {
                        return Err(format!(
                            "body {i} and its island {island} disagree on sleep"
                        ));
                    }
                    let st = &self.states[i];
                    if !self.awake[i] && (st.v != glam::Vec2::ZERO || st.w != 0.0) {
                        return Err(format!("sleeping body {i} moves"));
                    }
                }
            }
            let m = self.motion[i];
            if m.moves != (kind != BodyKind::Static && self.awake[i])
                || m.dynamic != (dynamic && self.awake[i])
            {
                return Err(format!("body {i}'s motion flags are stale"));
            }
        }
        for (s, &o) in owner.iter().enumerate() {
            if self.shape_slots.is_alive(s) && o == NONE {
                return Err(format!("live shape {s} is on no body's list"));
            }
        }
        self.islands.check()?;
        // Contacts.
        if self.contact_keys.len() != self.contacts.len() || self.pairs.len() != self.contacts.len()
        {
            return Err("contact arrays and pair map differ in length".into());
        }
        for (k, (c, key)) in self.contacts.iter().zip(&self.contact_keys).enumerate() {
            for (s, b) in [(c.shape_a, c.body_a), (c.shape_b, c.body_b)] {
                if !self.shape_slots.is_alive(s as usize)
                    || self.shape_records[s as usize].body != b
                {
                    return Err(format!("contact {k} names shape {s} not on body {b}"));
                }
            }
            if self.pairs.get(&pair_key(c.shape_a, c.shape_b)) != Some(&(k as u32)) {
                return Err(format!("contact {k} is not in the pair map at its place"));
            }
            let masses = [
                self.solver_bodies[c.body_a as usize],
                self.solver_bodies[c.body_b as usize],
            ];
            if masses.iter().zip(&c.masses).any(|(a, b)| {
                a.inv_mass != b.inv_mass || a.inv_inertia != b.inv_inertia || a.dynamic != b.dynamic
            }) {
                return Err(format!("contact {k}'s copy of its bodies' masses is stale"));
            }
            let fresh = ContactKey::of(c, &self.awake);
            if fresh.dynamic != key.dynamic
                || fresh.frozen != key.frozen
                || fresh.sleeping != key.sleeping
            {
                return Err(format!("contact {k}'s key is stale"));
            }
            // A contact not due for a retest, neither of whose shapes moved since, must still
            // overlap by the pair rule (the narrow phase skips its test); a frozen one is
            // always due.
            let (sa, sb) = (c.shape_a as usize, c.shape_b as usize);
            if key.frozen && !key.retest {
                return Err(format!("frozen contact {k} is not due for a retest"));
            }
            let untested = !key.retest && !self.moved_flags[sa] && !self.moved_flags[sb];
            let overlap = self.fat_aabbs[sa].overlaps(&self.fat_aabbs[sb])
                && self.core_aabbs[sa].overlaps(&self.core_aabbs[sb]);
            if untested && !overlap {
                return Err(format!("contact {k}'s boxes parted untested"));
            }
            if key.touching != (c.manifold.count > 0)
                || c.touched != key.touching
                || key.touched != c.touched
            {
                return Err(format!("contact {k}'s touching flags disagree"));
            }
            if c.touched && c.masses[0].dynamic && c.masses[1].dynamic {
                let (ia, ib) = (
                    self.islands.of_body[c.body_a as usize],
                    self.islands.of_body[c.body_b as usize],
                );
                if ia != ib {
                    return Err(format!(
                        "contact {k} touches bodies {} and {} of islands {ia} and {ib}",
                        c.body_a, c.body_b
                    ));
                }
            }
        }
        // The awake set's lists, unless marked for a rebuild.
        if !self.moving_stale {
            let fresh = (0..self.motion.len() as u32).filter(|&i| self.motion[i as usize].moves);
            if !fresh.eq(self.moving.iter().copied()) {
                return Err("the awake set's body list is stale".into());
            }
        }
        if !self.awake_contacts_stale {
            let keys = &self.contact_keys;
            let fresh = (0..keys.len() as u32).filter(|&k| !keys[k as usize].frozen);
            if !fresh.eq(self.awake_contacts.iter().copied()) {
                return Err("the awake set's contact list is stale".into());
            }
        }
        // Each live shape's core fat box lies inside its swept one, or is everywhere (the
        // narrow phase tests one or the other on that ground).
        for s in 0..self.fat_aabbs.len() {
            let (fat, core) = (&self.fat_aabbs[s], &self.core_aabbs[s]);
            if self.shape_slots.is_alive(s) && *core != Aabb::EVERYWHERE && !fat.contains(core) {
                return Err(format!("shape {s}'s core box is not inside its fat box"));
            }
        }
        // Moved proxies: the list holds exactly the flagged shapes, each once.
        let mut listed = vec![false; self.moved_flags.len()];
        for &m in &self.moved {
            if std::mem::replace(&mut listed[m as usize], true) {
                return Err(format!("shape {m} is on the moved list twice"));
            }
        }
        for (s, &f) in self.moved_flags.iter().enumerate() {
            if f != listed[s] {
                return Err(format!(
                    "shape {s}'s moved flag disagrees with the moved list"
                ));
            }
            if f && !self.shape_slots.is_alive(s) {
                return Err(format!("free shape slot {s} is moved"));
            }
        }
        Ok(())
    }
}
