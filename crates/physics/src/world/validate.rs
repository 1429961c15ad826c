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
        self.bodies
            .slots
            .check()
            .map_err(|e| format!("body slots: {e}"))?;
        self.shapes
            .slots
            .check()
            .map_err(|e| format!("shape slots: {e}"))?;
        // The sensors tracked are the live sensor shapes.
        let sensor_shapes = (0..self.shapes.geometry.len())
            .filter(|&s| self.shapes.slots.is_alive(s) && self.shapes.records[s].sensor)
            .map(|s| s as u32);
        if !sensor_shapes.eq(self.sensors.keys().copied()) {
            return Err("the tracked sensors are not the live sensor shapes".into());
        }
        let n = self.bodies.sims.len();
        if self.bodies.forces.len() != n {
            return Err(format!(
                "{} applied forces for {n} body slots",
                self.bodies.forces.len()
            ));
        }
        let mut owner = vec![NONE; self.shapes.geometry.len()];
        for i in 0..n {
            let alive = self.bodies.slots.is_alive(i);
            let kind = self.bodies.sims[i].kind;
            if !alive {
                if self.bodies.records[i].first_shape != NONE
                    || self.bodies.awake[i]
                    || self.bodies.motion[i].moves
                {
                    return Err(format!("free body slot {i} has shapes or moves"));
                }
                continue;
            }
            let mut count = 0;
            for s in self.shapes_of_body(i) {
                let su = s as usize;
                if !self.shapes.slots.is_alive(su) {
                    return Err(format!("body {i} lists free shape slot {s}"));
                }
                if owner[su] != NONE || self.shapes.records[su].body as usize != i {
                    return Err(format!(
                        "shape {s} is listed by body {i} but belongs elsewhere"
                    ));
                }
                if self.shapes.body[su] as usize != i {
                    return Err(format!("shape {s}'s compact body copy is stale"));
                }
                if self.shapes.records[su].disabled != self.bodies.records[i].disabled {
                    return Err(format!("shape {s}'s disabled flag differs from body {i}'s"));
                }
                if self.shapes.records[su].disabled && self.shapes.moved_flags[su] {
                    return Err(format!("disabled shape {s} is queued for the pair search"));
                }
                let searched = self.shapes.searched_boxes[su];
                let boxes = [self.shapes.swept_boxes[su], self.shapes.unswept_boxes[su]];
                if !self.shapes.moved_flags[su]
                    && !self.shapes.records[su].disabled
                    && searched != [Aabb::NOWHERE; 2]
                    && searched != boxes
                {
                    return Err(format!(
                        "shape {s}'s boxes changed since its pair search, but it is not queued"
                    ));
                }
                if self.sweeps_every_pair(i) != (self.shapes.unswept_boxes[su] == Aabb::EVERYWHERE)
                {
                    return Err(format!(
                        "shape {s}'s core box does not match its body ({kind:?}, bullet {})",
                        self.bodies.records[i].bullet
                    ));
                }
                owner[su] = i as u32;
                count += 1;
            }
            if count == 0 {
                return Err(format!("body {i} has no shape"));
            }
            // Mass data: exactly what a fresh computation gives, unless the caller gave them
            // (then only a dynamic body has mass).
            let sb = self.bodies.masses[i];
            let dynamic = kind == BodyKind::Dynamic;
            if self.bodies.records[i].custom_mass {
                if !dynamic || sb.inv_mass <= 0.0 || !sb.dynamic {
                    return Err(format!("body {i} has given mass data but is not dynamic"));
                }
            } else {
                let md = self.shapes_mass(i);
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
                if self.bodies.records[i].local_center != center {
                    return Err(format!("body {i}'s centre of mass is stale"));
                }
            }
            // Awake and motion flags.
            let island = self.islands.of_body.get(i).copied().unwrap_or(NO_ISLAND);
            if self.bodies.records[i].disabled {
                // Out of everything: asleep, in no island, not integrated.
                if self.bodies.awake[i] || island != NO_ISLAND || self.bodies.motion[i].moves {
                    return Err(format!(
                        "disabled body {i} is awake, moves or is in an island"
                    ));
                }
                continue;
            }
            match kind {
                BodyKind::Static => {
                    if self.bodies.awake[i] || island != NO_ISLAND {
                        return Err(format!("static body {i} is awake or in an island"));
                    }
                }
                BodyKind::Kinematic => {
                    if !self.bodies.awake[i] || island != NO_ISLAND {
                        return Err(format!("kinematic body {i} sleeps or is in an island"));
                    }
                }
                BodyKind::Dynamic => {
                    if island == NO_ISLAND {
                        return Err(format!("dynamic body {i} is in no island"));
                    }
                    if self.islands.islands[island as usize].awake != self.bodies.awake[i] {
                        return Err(format!(
                            "body {i} and its island {island} disagree on sleep"
                        ));
                    }
                    let st = &self.bodies.states[i];
                    if !self.bodies.awake[i] && (st.v != glam::Vec2::ZERO || st.w != 0.0) {
                        return Err(format!("sleeping body {i} moves"));
                    }
                }
            }
            let m = self.bodies.motion[i];
            if m.moves != (kind != BodyKind::Static && self.bodies.awake[i])
                || m.dynamic != (dynamic && self.bodies.awake[i])
            {
                return Err(format!("body {i}'s motion flags are stale"));
            }
        }
        for (s, &o) in owner.iter().enumerate() {
            if self.shapes.slots.is_alive(s) && o == NONE {
                return Err(format!("live shape {s} is on no body's list"));
            }
        }
        self.islands.check()?;
        // Contacts.
        if self.contacts.keys.len() != self.contacts.list.len()
            || self.contacts.pairs.len() != self.contacts.list.len()
        {
            return Err("contact arrays and pair map differ in length".into());
        }
        // The narrow phase's change marks are drained by the same step's touch update: one
        // left set would replay a change next step, on whatever contact then has its index.
        let marked = |bits: &[std::sync::atomic::AtomicU64]| {
            bits.iter()
                .position(|w| w.load(std::sync::atomic::Ordering::Relaxed) != 0)
        };
        for (name, bits) in [
            ("changed", &self.contacts.changed),
            ("one-sided", &self.contacts.one_sided),
        ] {
            if let Some(w) = marked(bits) {
                return Err(format!(
                    "a {name} contact mark outlived its step (word {w})"
                ));
            }
        }
        for (k, (c, key)) in self
            .contacts
            .list
            .iter()
            .zip(&self.contacts.keys)
            .enumerate()
        {
            for (s, b) in [(c.shape_a, c.body_a), (c.shape_b, c.body_b)] {
                if !self.shapes.slots.is_alive(s as usize)
                    || self.shapes.records[s as usize].body != b
                {
                    return Err(format!("contact {k} names shape {s} not on body {b}"));
                }
                if self.bodies.records[b as usize].disabled {
                    return Err(format!("contact {k} is of disabled body {b}"));
                }
            }
            if self.contacts.pairs.get(&pair_key(c.shape_a, c.shape_b)) != Some(&(k as u32)) {
                return Err(format!("contact {k} is not in the pair map at its place"));
            }
            let masses = [
                self.bodies.masses[c.body_a as usize],
                self.bodies.masses[c.body_b as usize],
            ];
            if masses.iter().zip(&c.masses).any(|(a, b)| {
                a.inv_mass != b.inv_mass || a.inv_inertia != b.inv_inertia || a.dynamic != b.dynamic
            }) {
                return Err(format!("contact {k}'s copy of its bodies' masses is stale"));
            }
            let fresh = ContactKey::of(c, &self.bodies.awake);
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
            let untested =
                !key.retest && !self.shapes.moved_flags[sa] && !self.shapes.moved_flags[sb];
            let overlap = self.shapes.swept_boxes[sa].overlaps(&self.shapes.swept_boxes[sb])
                && self.shapes.unswept_boxes[sa].overlaps(&self.shapes.unswept_boxes[sb]);
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
        if !self.bodies.awake_set_stale {
            let fresh = (0..self.bodies.motion.len() as u32)
                .filter(|&i| self.bodies.motion[i as usize].moves);
            if !fresh.eq(self.bodies.awake_set.iter().copied()) {
                return Err("the awake set's body list is stale".into());
            }
        }
        if !self.contacts.awake_stale {
            let keys = &self.contacts.keys;
            let fresh = (0..keys.len() as u32).filter(|&k| !keys[k as usize].frozen);
            if !fresh.eq(self.contacts.awake.iter().copied()) {
                return Err("the awake set's contact list is stale".into());
            }
        }
        // Each live shape's core fat box lies inside its swept one, or is everywhere (the
        // narrow phase tests one or the other on that ground).
        for s in 0..self.shapes.swept_boxes.len() {
            let (fat, core) = (&self.shapes.swept_boxes[s], &self.shapes.unswept_boxes[s]);
            if self.shapes.slots.is_alive(s) && *core != Aabb::EVERYWHERE && !fat.contains(core) {
                return Err(format!("shape {s}'s core box is not inside its fat box"));
            }
        }
        // Moved proxies: the list holds exactly the flagged shapes, each once.
        let mut listed = vec![false; self.shapes.moved_flags.len()];
        for &m in &self.shapes.moved_proxies {
            if std::mem::replace(&mut listed[m as usize], true) {
                return Err(format!("shape {m} is on the moved list twice"));
            }
        }
        for (s, &f) in self.shapes.moved_flags.iter().enumerate() {
            if f != listed[s] {
                return Err(format!(
                    "shape {s}'s moved flag disagrees with the moved list"
                ));
            }
            if f && !self.shapes.slots.is_alive(s) {
                return Err(format!("free shape slot {s} is moved"));
            }
        }
        Ok(())
    }
}
