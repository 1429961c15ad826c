//! Persistent islands (Box2D v3's `island.c`): groups of dynamic bodies joined by touching
//! contacts and by joints. Two islands merge when a contact between them begins touching
//! or a joint joins them; an island is split only when it is about to sleep and a constraint
//! inside it has gone since it was last whole, because splitting costs a walk of the island
//! and most islands that lose a contact never sleep. Static and kinematic bodies belong to
//! no island, so a pile on the ground is not one island with everything else on the ground.
//!
//! Every change here runs serially between the step's parallel stages, in the order of the
//! contacts, so islands are the same on any thread count.

/// No island (static and kinematic bodies; a free slot).
pub const NO_ISLAND: u32 = u32::MAX;

/// One island.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Island {
    /// Its bodies, in the order they joined.
    pub bodies: Vec<u32>,
    /// Constraints inside it that went since it was last whole: it must be split before it
    /// may sleep.
    pub constraints_removed: u32,
    /// Whether its bodies are awake.
    pub awake: bool,
}

impl Island {
    /// Whether it is in the awake set: in use (it has bodies) and awake.
    fn in_awake_set(&self) -> bool {
        self.awake && !self.bodies.is_empty()
    }
}

/// Every island, by slot, and each body's island.
#[derive(Clone, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct Islands {
    /// Islands by slot; a free slot has no bodies.
    pub islands: Vec<Island>,
    /// Free slots, highest first.
    free: Vec<u32>,
    /// Each body's island (`NO_ISLAND` when it has none).
    pub of_body: Vec<u32>,
    /// Islands in use that are awake (kept by every method that changes one's sleep).
    #[serde(skip)]
    awake: usize,
    /// The awake islands in use, ascending (the awake set's islands): the sleep stage walks
    /// these rather than every slot. Valid after [`Islands::refresh_awake_list`].
    #[serde(skip)]
    pub awake_list: Vec<u32>,
    /// An island was created, released, woken or put to sleep since the list was made.
    #[serde(skip)]
    awake_list_stale: bool,
}

impl Islands {
    /// Grows `of_body` to `bodies` slots.
    pub fn grow(&mut self, bodies: usize) {
        if self.of_body.len() < bodies {
            self.of_body.resize(bodies, NO_ISLAND);
        }
    }

    /// A new island of one body.
    pub fn create(&mut self, body: u32, awake: bool) -> u32 {
        let island = Island {
            bodies: vec![body],
            constraints_removed: 0,
            awake,
        };
        self.awake += usize::from(awake);
        self.awake_list_stale = true;
        let k = match self.free.pop() {
            Some(k) => {
                self.islands[k as usize] = island;
                k
            }
            None => {
                self.islands.push(island);
                (self.islands.len() - 1) as u32
            }
        };
        self.grow(body as usize + 1);
        self.of_body[body as usize] = k;
        k
    }

    fn release(&mut self, k: u32) {
        self.awake -= usize::from(self.islands[k as usize].awake);
        self.awake_list_stale = true;
        self.islands[k as usize] = Island::default();
        let at = self.free.partition_point(|&f| f > k);
        self.free.insert(at, k);
    }

    /// Islands in use.
    pub fn count(&self) -> usize {
        self.islands.len() - self.free.len()
    }

    /// Islands in use that are awake.
    pub fn awake_count(&self) -> usize {
        self.awake
    }

    /// Wakes island `k` or puts it to sleep (its bodies are the caller's to change).
    pub fn set_awake(&mut self, k: u32, awake: bool) {
        let island = &mut self.islands[k as usize];
        if island.awake != awake {
            island.awake = awake;
            self.awake_list_stale = true;
            if awake {
                self.awake += 1;
            } else {
                self.awake -= 1;
            }
        }
    }

    /// Rebuilds [`Islands::awake_list`] if an island changed its sleep or its slot since.
    pub fn refresh_awake_list(&mut self) {
        if self.awake_list_stale {
            let islands = &self.islands;
            self.awake_list.clear();
            self.awake_list
                .extend((0..islands.len() as u32).filter(|&k| islands[k as usize].in_awake_set()));
            self.awake_list_stale = false;
        }
    }

    /// Recounts the awake islands (after a snapshot was read).
    pub fn recount(&mut self) {
        self.awake_list_stale = true;
        self.awake = self.islands.iter().filter(|i| i.in_awake_set()).count();
    }

    /// Joins the islands of two bodies (a contact between them began touching): the smaller
    /// moves into the larger (the lower slot on a tie). Returns the surviving island.
    pub fn link(&mut self, a: u32, b: u32) -> u32 {
        let (ia, ib) = (self.of_body[a as usize], self.of_body[b as usize]);
        debug_assert!(ia != NO_ISLAND && ib != NO_ISLAND);
        if ia == ib {
            return ia;
        }
        let (na, nb) = (
            self.islands[ia as usize].bodies.len(),
            self.islands[ib as usize].bodies.len(),
        );
        let (keep, gone) = if na > nb || (na == nb && ia < ib) {
            (ia, ib)
        } else {
            (ib, ia)
        };
        let moved = std::mem::take(&mut self.islands[gone as usize].bodies);
        let removed = self.islands[gone as usize].constraints_removed;
        for &body in &moved {
            self.of_body[body as usize] = keep;
        }
        let island = &mut self.islands[keep as usize];
        island.bodies.extend(moved);
        island.constraints_removed += removed;
        self.release(gone);
        keep
    }

    /// A constraint between two bodies of one island went (a contact stopped touching).
    pub fn unlink(&mut self, a: u32, b: u32) {
        let (ia, ib) = (self.of_body[a as usize], self.of_body[b as usize]);
        if ia != NO_ISLAND && ia == ib {
            self.islands[ia as usize].constraints_removed += 1;
        }
    }

    /// Takes a body out of its island (destroyed, or no longer dynamic); the island, if left
    /// with bodies, must be split before it sleeps.
    pub fn remove_body(&mut self, body: u32) {
        let k = self.of_body[body as usize];
        if k == NO_ISLAND {
            return;
        }
        self.of_body[body as usize] = NO_ISLAND;
        let island = &mut self.islands[k as usize];
        island.bodies.retain(|&b| b != body);
        if island.bodies.is_empty() {
            self.release(k);
        } else {
            island.constraints_removed += 1;
        }
    }

    /// Splits island `k` into its connected parts, given the touching links between its
    /// bodies (each pair once, in contact order). The part holding the island's first body
    /// keeps the slot; the others get new islands, in order of their first body. Returns the
    /// islands it is now made of.
    pub fn split(&mut self, k: u32, links: &[(u32, u32)]) -> Vec<u32> {
        self.awake_list_stale = true;
        let bodies = std::mem::take(&mut self.islands[k as usize].bodies);
        let awake = self.islands[k as usize].awake;
        // Adjacency in compressed rows, over the island's bodies by their place in it.
        let place: rustc_hash::FxHashMap<u32, u32> = bodies
            .iter()
            .enumerate()
            .map(|(i, &b)| (b, i as u32))
            .collect();
        let n = bodies.len();
        let mut degree = vec![0u32; n + 1];
        for &(a, b) in links {
            degree[place[&a] as usize + 1] += 1;
            degree[place[&b] as usize + 1] += 1;
        }
        for i in 0..n {
            degree[i + 1] += degree[i];
        }
        let mut fill = degree.clone();
        let mut next = vec![0u32; 2 * links.len()];
        for &(a, b) in links {
            let (pa, pb) = (place[&a] as usize, place[&b] as usize);
            next[fill[pa] as usize] = pb as u32;
            fill[pa] += 1;
            next[fill[pb] as usize] = pa as u32;
            fill[pb] += 1;
        }
        let mut part = vec![u32::MAX; n];
        let mut parts: Vec<Vec<u32>> = Vec::new();
        let mut stack = Vec::new();
        for seed in 0..n {
            if part[seed] != u32::MAX {
                continue;
            }
            let id = parts.len() as u32;
            part[seed] = id;
            stack.push(seed);
            let mut members = Vec::new();
            while let Some(i) = stack.pop() {
                members.push(bodies[i]);
                for &j in &next[degree[i] as usize..degree[i + 1] as usize] {
                    if part[j as usize] == u32::MAX {
                        part[j as usize] = id;
                        stack.push(j as usize);
                    }
                }
            }
            parts.push(members);
        }
        let mut out = Vec::with_capacity(parts.len());
        for (i, members) in parts.into_iter().enumerate() {
            let slot = if i == 0 {
                self.islands[k as usize] = Island {
                    bodies: Vec::new(),
                    constraints_removed: 0,
                    awake,
                };
                k
            } else {
                let first = members[0];
                let slot = self.create(first, awake);
                self.islands[slot as usize].bodies.clear();
                slot
            };
            for &b in &members {
                self.of_body[b as usize] = slot;
            }
            self.islands[slot as usize].bodies = members;
            out.push(slot);
        }
        out
    }

    /// Checks that each body's island lists it once, each island lists only its own bodies,
    /// and the free slots are exactly the empty islands.
    pub fn check(&self) -> Result<(), String> {
        let mut listed = vec![false; self.of_body.len()];
        let mut free = vec![false; self.islands.len()];
        for &k in &self.free {
            free[k as usize] = true;
        }
        for (k, island) in self.islands.iter().enumerate() {
            for &b in &island.bodies {
                if self.of_body.get(b as usize) != Some(&(k as u32)) {
                    return Err(format!(
                        "island {k} lists body {b}, whose island is another"
                    ));
                }
                if std::mem::replace(&mut listed[b as usize], true) {
                    return Err(format!("body {b} is listed twice"));
                }
            }
            if free[k] != island.bodies.is_empty() {
                return Err(format!("island {k} is free and has bodies, or neither"));
            }
        }
        let awake = self.islands.iter().filter(|i| i.in_awake_set()).count();
        if awake != self.awake {
            return Err(format!(
                "{} awake islands counted, {awake} found",
                self.awake
            ));
        }
        if !self.awake_list_stale {
            let fresh =
                (0..self.islands.len() as u32).filter(|&k| self.islands[k as usize].in_awake_set());
            if !fresh.eq(self.awake_list.iter().copied()) {
                return Err("the awake island list is stale".into());
            }
        }
        for (b, &k) in self.of_body.iter().enumerate() {
            if k != NO_ISLAND && !listed[b] {
                return Err(format!("body {b} is in island {k}, which does not list it"));
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linking_merges_and_splitting_finds_the_parts() {
        let mut s = Islands::default();
        for b in 0..5 {
            s.create(b, true);
        }
        // 0-1-2 and 3-4.
        s.link(0, 1);
        s.link(1, 2);
        let k = s.link(3, 4);
        assert_eq!(s.count(), 2);
        assert_eq!(s.of_body[3], k);
        let big = s.link(2, 3);
        assert_eq!(s.count(), 1);
        assert_eq!(s.islands[big as usize].bodies.len(), 5);
        assert_eq!(s.check(), Ok(()));
        // The link 2-3 goes: two parts again.
        s.unlink(2, 3);
        assert_eq!(s.islands[big as usize].constraints_removed, 1);
        let parts = s.split(big, &[(0, 1), (1, 2), (3, 4)]);
        assert_eq!(parts.len(), 2);
        assert_eq!(s.count(), 2);
        assert_eq!(s.of_body[0], s.of_body[2]);
        assert_ne!(s.of_body[0], s.of_body[3]);
        assert_eq!(s.check(), Ok(()));
        s.remove_body(3);
        s.remove_body(4);
        assert_eq!(s.count(), 1);
        assert_eq!(s.check(), Ok(()));
    }

    #[test]
    fn the_awake_list_follows_every_change_of_sleep_and_slot() {
        let mut s = Islands::default();
        for b in 0..6 {
            s.create(b, true);
        }
        s.refresh_awake_list();
        assert_eq!(s.awake_list, [0, 1, 2, 3, 4, 5]);
        // Merging frees a slot; sleeping takes an island off; both in slot order.
        let k = s.link(0, 1);
        s.set_awake(s.of_body[4], false);
        s.refresh_awake_list();
        let mut expected: Vec<u32> = (0..6)
            .map(|b| s.of_body[b])
            .filter(|&i| i != s.of_body[4])
            .collect();
        expected.sort();
        expected.dedup();
        assert_eq!(s.awake_list, expected);
        assert_eq!(s.check(), Ok(()));
        // A split makes a new awake island; waking brings one back; removing the last body
        // frees its slot.
        s.unlink(0, 1);
        let parts = s.split(k, &[]);
        assert_eq!(parts.len(), 2);
        s.set_awake(s.of_body[4], true);
        s.remove_body(5);
        s.refresh_awake_list();
        let mut expected: Vec<u32> = (0..5).map(|b| s.of_body[b]).collect();
        expected.sort();
        assert_eq!(s.awake_list, expected);
        assert_eq!(s.check(), Ok(()));
    }
}
