//! The step: a pipeline of named, timed stages, each saying what it reads and writes.
//!
//! broad phase → narrow phase → touch changes (islands, waking) → prepare → substeps (solve)
//! → restitution → store → finalize → sleep.
//!
//! A step runs on the caller's thread; when it is large enough (`WideThresholds`) its
//! stages are shared with the world's crew of worker threads. Shared stages write only their
//! own index's slot or part, so their results are the same on any thread count; the stages
//! that change islands run serially in contact order.

#[cfg(not(target_arch = "wasm32"))]
use std::time::Instant;

use glam::Vec2;
// `std::time::Instant` panics on the web; web-time's reads `performance.now()` there.
#[cfg(target_arch = "wasm32")]
use web_time::Instant;

use super::{BodySim, Contact, ContactCache, ContactKey, ShapeRecord, World, pair_key, stores};
use crate::SPECULATIVE_DISTANCE;
use crate::body::BodyState;
use crate::collision::{Manifold, collide};
use crate::def::BodyKind;
use crate::id::ShapeId;
use crate::math::{Transform, cross_sv, dot};
use crate::profile::StepProfile;
use crate::shape::{Aabb, Shape};
use crate::softness::Softness;
use crate::solver::{NOT_DYNAMIC, SolverParams, SubstepParams, Touching};
use crate::threads::parallel::{SharedSlice, Spread, for_each_part, for_parts};

/// Contacts whose relative pose moved less than this keep their manifold (Box2D's
/// `B2_CONTACT_RECYCLE_DISTANCE`, 10 slops).
const RECYCLE_DISTANCE: f32 = 10.0 * crate::LINEAR_SLOP;
/// ...and whose bodies each turned less than about 11.5° (`B2_CONTACT_RECYCLE_COS_ANGLE`).
const RECYCLE_COS_ANGLE: f32 = 0.98;
/// A manifold is computed out to the gap a pair closing this many times faster than now
/// could cross in a step; the points past the step's own reach are dropped below (the kept
/// points are those of a margin without headroom, but for a spinning pair's point that the
/// narrower margin missed), and the manifold stays good for `recycle` while a tumbling pair's
/// closing bound (which jitters step to step) at most doubles. Measured on washer: twice
/// recycles 88% of its contacts (81% at once), three times no more.
const CLOSING_HEADROOM: f32 = 2.0;

/// The step, and whether a step length can be taken.
///
/// ```
/// use tumble_physics::{BodyDef, ShapeDef, StepSettings, World};
///
/// let mut world = World::new(StepSettings::default());
/// let ball = world.create_body(&BodyDef::new(ShapeDef::Circle { radius: 0.5 }).at(0.0, 10.0)).unwrap();
/// world.step(1.0 / 60.0, 4);
/// // A free fall under the default gravity, -10 m/s²: one step of 1/60 s.
/// assert!((world.body(ball).unwrap().linear_velocity.y + 10.0 / 60.0).abs() < 1e-5);
/// assert!(!World::steppable(0.0, 4));
/// ```
impl World {
    /// Advances the world by `dt` seconds in `substeps` solver substeps.
    ///
    /// Does nothing (no step is counted, the profile is zeroed) for a `dt` that
    /// [`World::steppable`] refuses: not finite, not > 0, subnormal, or so small that one
    /// substep `dt / substeps` is subnormal (its inverse, the substep rate, would overflow to
    /// infinity and turn the state non-finite); nor for `substeps == 0`. Scene validation
    /// refuses such a scene's `dt` with a message.
    pub fn step(&mut self, dt: f32, substeps: u32) {
        let start = Instant::now();
        let mut profile = StepProfile::default();
        if !World::steppable(dt, substeps) {
            self.stats.profile = profile;
            return;
        }
        self.stats.last_dt = dt;
        self.clear_events();
        // Sleeping switched off while islands slept: they wake (Box2D's b2World_EnableSleeping).
        if !self.settings.enable_sleep && self.islands.awake_count() < self.islands.count() {
            self.wake_all();
        }
        // Nothing awake and nothing moved: no contact can change and no body can move (every
        // dynamic body sleeps, and static ones never move), so the step is only counted. A
        // pile at rest costs nothing.
        if self.islands.awake_count() == 0
            && self.bodies.kinematic_count == 0
            && self.shapes.moved_proxies.is_empty()
        {
            self.events.body_moves.clear();
            self.bodies.clear_forces();
            // A shape destroyed in a sensor still ends its overlap.
            self.overlap_sensors();
            self.stats.steps += 1;
            profile.bodies = self.bodies.slots.live();
            profile.contacts = self.contacts.list.len();
            profile.step_ms = ms(start);
            self.stats.profile = profile;
            return;
        }
        // Only a wide step touches the crew (an inline one takes not even its reference
        // count). The step runs on this thread either way; a wide one's stages are shared.
        let crew = if self.goes_wide() {
            self.workers.crew.clone()
        } else {
            None
        };
        let spread = crew.as_deref().map_or(Spread::INLINE, Spread::over);

        let t = Instant::now();
        self.update_pairs(spread);
        profile.broad_phase_ms = ms(t);

        let t = Instant::now();
        let (changes, collided) = self.collide(dt, spread);
        self.clear_moved_flags();
        profile.collided = collided;
        self.update_touching(changes);
        profile.narrow_phase_ms = ms(t);

        // Waking (above) and sleeping (last step) change the awake set's bodies.
        self.refresh_moving();
        self.solve(dt, substeps, spread, &mut profile);

        let t = Instant::now();
        self.finalize(dt, spread);
        self.note_body_moves();
        self.update_sleep();
        profile.finalize_ms = ms(t);

        let t = Instant::now();
        if !self.events.unpushed.is_empty() {
            self.gather_hits(dt);
        }
        self.overlap_sensors();
        self.gather_joint_thresholds();
        profile.events_ms = ms(t);

        profile.inline = crew.is_none();
        self.stats.steps += 1;
        profile.bodies = self.bodies.slots.live();
        profile.contacts = self.contacts.list.len();
        profile.moved = self.shapes.moved_proxies.len();
        profile.moving = self.bodies.awake_set.len();
        profile.recycled = self.stats.recycled;
        profile.swept = self.sweeps.fast_bodies.len();
        profile.rewound = self.stats.rewound;
        profile.non_finite = self.stats.guarded_last_step;
        profile.step_ms = ms(start);
        self.stats.profile = profile;
    }

    /// Whether [`World::step`] steps with this `dt` and `substeps`: `dt` a finite, normal
    /// (not subnormal) number > 0, at least one substep, and `dt / substeps` normal too.
    pub fn steppable(dt: f32, substeps: u32) -> bool {
        dt > 0.0 && dt.is_normal() && substeps > 0 && (dt / substeps as f32).is_normal()
    }

    /// Whether this step shares its stages with the crew: when there is one, the step has
    /// [`super::WideThresholds::step`]'s contacts and moved proxies, and some stage of it
    /// would be split, judged on the counts the step starts from (a stage whose count
    /// crosses its threshold during the step runs on one thread until the next step).
    fn goes_wide(&self) -> bool {
        let Some(crew) = &self.workers.crew else {
            return false;
        };
        let all = Spread::over(crew);
        let (w, contacts) = (&self.wide, self.contacts.keys.len());
        // Joints are constraints as contacts are (last step's awake ones; the first step
        // counts every joint).
        let joints = if self.stats.steps == 0 {
            self.joints.slots.live()
        } else {
            self.joints.awake.len()
        };
        let split = all.goes_wide(self.shapes.moved_proxies.len(), w.broad_phase)
            || all.goes_wide(contacts, w.narrow_phase)
            || all.goes_wide(
                self.contacts.touching.len() + joints,
                w.prepare.min(w.solve),
            )
            || all.goes_wide(self.bodies.sims.len(), w.finalize);
        // A new scene's first step has no contacts yet, but its moved proxies will make them.
        split && all.goes_wide(contacts + self.shapes.moved_proxies.len() + joints, w.step)
    }

    /// Broad phase (reads fat boxes, filters, bodies' kinds; writes contacts and pairs):
    /// rebuild the tree if a fat box changed, then find the new pairs of every moved proxy
    /// (in parallel, each into its own list) and create their contacts serially in moved
    /// order.
    fn update_pairs(&mut self, spread: Spread<'_>) {
        if self.shapes.moved_proxies.is_empty() {
            return;
        }
        self.refresh_tree();
        self.find_new_pairs(spread);
    }

    /// Brings the broad phase's tree up to date with the fat boxes (reads fat boxes and
    /// moved proxies; writes the tree).
    pub(super) fn refresh_tree(&mut self) {
        if self.shapes.tree_dirty {
            // A cheap refit (of the nodes above the moved proxies), and a full rebuild (serial,
            // O(n log n): 3.4 ms of a 20,000-body pile's 16 ms step when it ran every step)
            // only when proxies were added or removed, or the refitted tree has grown a
            // quarter costlier than a fresh one, or its last walk against itself tested
            // twice the boxes a pair of its best (`BroadPhase::walks_slowly`):
            // bodies that move together (a falling pile, a drifting cloud) keep a refitted
            // tree good. The tree's shape never changes which pairs are found, nor their
            // order (both are sorted).
            let (slots, records) = (&self.shapes.slots, &self.shapes.records);
            // A disabled body's shapes are in no tree.
            let in_tree = |s: u32| slots.is_alive(s as usize) && !records[s as usize].disabled;
            if self.shapes.proxies_changed {
                self.shapes.tree.rebuild(&self.shapes.swept_boxes, in_tree);
                self.shapes.proxies_changed = false;
            } else {
                self.shapes
                    .tree
                    .refit_moved(&self.shapes.swept_boxes, &self.shapes.moved_proxies);
                if self.shapes.tree.looseness() > 1.25 || self.shapes.tree.walks_slowly() {
                    self.shapes.tree.rebuild(&self.shapes.swept_boxes, in_tree);
                }
            }
            self.shapes.tree_dirty = false;
        }
    }

    /// The pair search of [`World::update_pairs`], the tree up to date.
    fn find_new_pairs(&mut self, spread: Spread<'_>) {
        // Past one proxy in eight moved, a walk of the tree against itself that leaves out
        // the subtrees where nothing moved beats a query per moved proxy, which walks the
        // upper levels again each time (junkyard, a quarter to all of its 8,000 moving:
        // 1.26 against 1.60 ms; large_pyramid, 1 to 3% moving: queries, 0.11 ms; measured
        // on a 2-vCPU Xeon, 300 steps, 1 thread).
        let walk_tree = self.shapes.moved_proxies.len() * 8 > self.shapes.tree.proxy_count();
        let walk = spread.for_stage(self.shapes.moved_proxies.len(), self.wide.broad_phase);
        if walk_tree {
            let tree = &mut self.shapes.tree;
            tree.prepare_walk(&self.shapes.moved_proxies, walk.workers());
        }
        let bp = &self.shapes.tree;
        let aabbs = &self.shapes.swept_boxes;
        let cores = &self.shapes.unswept_boxes;
        // Whether each body is dynamic, from the 12-byte solver records rather than the
        // body sims (a cache line each, read at random for every overlapping pair).
        let dynamic = &self.bodies.masses;
        let body_of = &self.shapes.body;
        let records = &self.shapes.records;
        let moved_flags = &self.shapes.moved_flags;
        let pairs = &self.contacts.pairs;
        let shapes = &self.shapes.geometry;
        // A new contact only for a pair of shapes of two bodies, one of them dynamic (no
        // other pair can ever push anything), whose core boxes overlap too (always, with a
        // static shape), whose filters let them touch, neither a sensor, that has none yet.
        // Cheapest refusals first: in a resting pile nearly every pair a moved proxy finds
        // has its contact already, and the searched boxes (below) or the map say so before
        // the shapes are read.
        let no_collide = &self.joints.no_collide;
        let custom_filter = self.hooks.custom_filter.as_deref();
        let shape_slots = &self.shapes.slots;
        let shape_id = |s: u32| ShapeId {
            index: s,
            generation: shape_slots.generation(s as usize),
        };
        // A pair whose boxes at the last search that took each overlapped by the pair rule
        // has had every test then (when the later of the two came into that overlap) and has
        // its contact if it wants one: none of the tests below can have changed since but by a
        // change that forgets the searched boxes (`Shapes::searched_boxes`), and the narrow
        // phase removes a contact only when its boxes part. Such pairs, most of what a
        // tumbling pile finds, skip the pair map (a cache miss each where there are tens of
        // thousands of contacts). Not while a custom filter may refuse a pair one step and
        // let it through the next (it is asked again whenever the pair is found again).
        let searched = &self.shapes.searched_boxes;
        let skip_searched = custom_filter.is_none();
        let searched_overlap = |p: u32, q: u32| {
            let ([sp, cp], [sq, cq]) = (&searched[p as usize], &searched[q as usize]);
            sp.overlaps(sq) && cp.overlaps(cq)
        };
        // The tests of a new contact after its bodies', its cores' and the pair map's, the
        // cheapest first.
        let would_touch = |p: u32, q: u32, bp_: u32, bq: u32| {
            (no_collide.is_empty() || !no_collide.contains_key(&pair_key(bp_, bq)))
                && {
                    let (rp, rq) = (&records[p as usize], &records[q as usize]);
                    !rp.sensor && !rq.sensor && rp.filter.should_collide(&rq.filter)
                }
                && Shape::pair_collides(&shapes[p as usize], &shapes[q as usize])
                // The game's say last: it is asked only of pairs that would touch.
                && custom_filter.is_none_or(|f| f(shape_id(p.min(q)), shape_id(p.max(q))))
        };
        let wants_contact = |p: u32, q: u32| {
            let (bp_, bq) = (body_of[p as usize], body_of[q as usize]);
            // Two moving shapes' swept boxes overlap far more often than their cores (two
            // bodies falling side by side): the cores first, then the rest.
            if bp_ == bq
                || !(dynamic[bp_ as usize].dynamic || dynamic[bq as usize].dynamic)
                || !cores[p as usize].overlaps(&cores[q as usize])
            {
                return false;
            }
            if skip_searched && searched_overlap(p, q) {
                debug_assert!(
                    pairs.contains_key(&pair_key(p, q)) || !would_touch(p, q, bp_, bq),
                    "shapes {p} and {q} overlapped at their last search but have no contact"
                );
                return false;
            }
            !pairs.contains_key(&pair_key(p, q)) && would_touch(p, q, bp_, bq)
        };
        if walk_tree {
            // Many proxies moved (smash, an explosion, the first step): walk the tree against
            // itself once instead of querying it per proxy. The same pairs as the queries
            // would find, created in the same order (each by its finder's place in `moved`,
            // then the other's id), so the results do not depend on which way was taken.
            let mut rank = std::mem::take(&mut self.shapes.moved_rank);
            rank.clear();
            rank.resize(aabbs.len(), u32::MAX);
            for (k, &i) in self.shapes.moved_proxies.iter().enumerate() {
                rank[i as usize] = k as u32;
            }
            let keep = |p: u32, q: u32| {
                let (mp, mq) = (moved_flags[p as usize], moved_flags[q as usize]);
                if !(mp || mq) || !wants_contact(p, q) {
                    return None;
                }
                // The finder is the moved one; of two moved, the larger id (as below).
                let (finder, other) = if mp && mq {
                    (p.max(q), p.min(q))
                } else if mp {
                    (p, q)
                } else {
                    (q, p)
                };
                Some((u64::from(rank[finder as usize]) << 32) | u64::from(other))
            };
            let (mut found, effort) = bp.overlapping_pairs_parallel(walk, &keep);
            self.shapes.tree.note_walk(effort);
            // Each task's pairs come sorted: a merge sort joins the runs in O(n log tasks).
            found.sort();
            let moved = std::mem::take(&mut self.shapes.moved_proxies);
            for key in found {
                let (finder, other) = (moved[(key >> 32) as usize], key as u32);
                self.create_contact(finder, other);
            }
            self.shapes.moved_rank = rank;
            self.finish_moved(moved);
            return;
        }
        // Each part of the moved proxies lists its new pairs in moved order, each proxy's
        // sorted by the other's id; the parts are joined in order.
        let found = for_parts(
            spread,
            &self.shapes.moved_proxies[..],
            self.wide.broad_phase,
            &|_, part: &[u32]| {
                let mut out = Vec::new();
                for &i in part {
                    let start = out.len();
                    bp.query(&aabbs[i as usize], aabbs, |j| {
                        // A pair of moved proxies is found from the larger id only.
                        if j != i && !(moved_flags[j as usize] && j > i) && wants_contact(i, j) {
                            out.push((i, j));
                        }
                    });
                    out[start..].sort_unstable();
                }
                out
            },
            &|mut a, b| {
                a.extend(b);
                a
            },
        );
        for (i, j) in found {
            self.create_contact(i, j);
        }
        let moved = std::mem::take(&mut self.shapes.moved_proxies);
        self.finish_moved(moved);
    }

    /// Hands the moved proxies, their pairs made, to the narrow phase (their flags stay set
    /// for it), noting the boxes they were searched with, and gives `moved` the other buffer
    /// for finalize to fill.
    fn finish_moved(&mut self, moved: Vec<u32>) {
        debug_assert!(self.shapes.moved_done.is_empty());
        let shapes = &mut self.shapes;
        for &s in &moved {
            let s = s as usize;
            shapes.searched_boxes[s] = [shapes.swept_boxes[s], shapes.unswept_boxes[s]];
        }
        self.shapes.moved_proxies = std::mem::replace(&mut self.shapes.moved_done, moved);
    }

    /// Clears the flags of the proxies the pair search took, once the narrow phase has
    /// retested their contacts.
    fn clear_moved_flags(&mut self) {
        for &i in &self.shapes.moved_done {
            self.shapes.moved_flags[i as usize] = false;
        }
        self.shapes.moved_done.clear();
    }

    /// A contact between shapes `i` and `j`.
    fn create_contact(&mut self, i: u32, j: u32) {
        // Shape A is the one later in Box2D's order of shape types (so each pair of types
        // has one manifold routine); of two of a type, the lower id.
        let (mut a, mut b) = if i < j { (i, j) } else { (j, i) };
        if self.shapes.geometry[a as usize].rank() < self.shapes.geometry[b as usize].rank() {
            std::mem::swap(&mut a, &mut b);
        }
        let (ra, rb) = (
            &self.shapes.records[a as usize],
            &self.shapes.records[b as usize],
        );
        let contact = Contact {
            shape_a: a,
            shape_b: b,
            body_a: ra.body,
            body_b: rb.body,
            friction: ShapeRecord::mixed_friction(ra, rb),
            restitution: ShapeRecord::mixed_restitution(ra, rb),
            manifold: Manifold::default(),
            cache: None,
            touched: false,
            hit_pending: false,
            rolling_impulse: 0.0,
            masses: [
                self.bodies.masses[ra.body as usize],
                self.bodies.masses[rb.body as usize],
            ],
        };
        self.contacts.push(contact, &self.bodies.awake);
    }

    /// Narrow phase (reads poses, velocities, shapes, fat boxes; writes each contact's
    /// manifold and key): every contact not frozen by sleep computes its manifold into its
    /// own slot, carrying impulses over by feature id. Returns how many contacts began or
    /// stopped touching, or parted (`update_touching` then handles them serially), and how
    /// many contacts it walked. While an island sleeps it walks the awake set's contacts, so
    /// a frozen one costs nothing.
    #[allow(unsafe_code)]
    fn collide(&mut self, dt: f32, spread: Spread<'_>) -> (usize, usize) {
        let listed = self.walk_awake_contacts();
        self.contacts.size_marks();
        let (changed, one_sided) = (&self.contacts.changed, &self.contacts.one_sided);
        let kinematic = self.bodies.kinematic_count > 0;
        // What the touch update will walk: the contacts that changed, and in a world with a
        // kinematic body the touching ones of one dynamic body.
        let note = |k: usize, key: &ContactKey| {
            if key.remove || key.touching != key.touched {
                stores::mark(changed, k);
            }
            if kinematic
                && key.touching
                && ((key.dynamic[0] == NOT_DYNAMIC) != (key.dynamic[1] == NOT_DYNAMIC))
            {
                stores::mark(one_sided, k);
            }
        };
        let sims = &self.bodies.sims;
        let states = &self.bodies.states;
        let shapes = &self.shapes.geometry;
        let records = &self.shapes.records;
        let aabbs = &self.shapes.swept_boxes;
        let cores = &self.shapes.unswept_boxes;
        let moved = &self.shapes.moved_flags;
        let recycling = self.settings.contact_recycling;
        let pre_solve = self.hooks.pre_solve.as_deref();
        let shape_slots = &self.shapes.slots;
        // The game's pre-solve: a contact it refuses has no points this step, and no cache
        // (recycling would keep the empty manifold).
        let ask = |c: &mut Contact| {
            if let Some(f) = pre_solve
                && c.manifold.count > 0
            {
                let id = |s: u32| ShapeId {
                    index: s,
                    generation: shape_slots.generation(s as usize),
                };
                if !f(id(c.shape_a), id(c.shape_b), c.manifold.normal) {
                    c.manifold.count = 0;
                    c.cache = None;
                }
            }
        };
        let collide_one = |c: &mut Contact, key: &mut ContactKey| -> (usize, usize) {
            if key.frozen {
                return (0, 0);
            }
            let (sa, sb) = (c.shape_a as usize, c.shape_b as usize);
            // Boxes that did not change since the last test overlap as they did then (a
            // byte each, where the boxes are 32 scattered bytes each): a resting pile
            // retests only the contacts of the few proxies that moved.
            if key.retest || moved[sa] || moved[sb] {
                key.retest = false;
                // The pair rule (both fat boxes overlap, swept and core) in two reads, not four:
                // a core fat box lies inside its swept one (they are grown together), so two
                // moving shapes need only their cores tested, and a static or bullet shape (core
                // everywhere) only the swept boxes.
                let (ca, cb) = (&cores[sa], &cores[sb]);
                let overlaps = if *ca == Aabb::EVERYWHERE || *cb == Aabb::EVERYWHERE {
                    aabbs[sa].overlaps(&aabbs[sb])
                } else {
                    ca.overlaps(cb)
                };
                if !overlaps {
                    key.remove = true;
                    return (0, 1);
                }
            }
            let (a, b) = (c.body_a as usize, c.body_b as usize);
            let (xa, xb) = (sims[a].xf, sims[b].xf);
            // Whether it touched after the last narrow phase: the key says so as the contact
            // does (`World::validate` checks it), without reading the contact's last line.
            let was = key.touching;
            debug_assert_eq!(was, key.touched);
            // How fast the pair can close: the bound on any point's approach speed.
            let closing = || {
                let (va, vb) = (&states[a], &states[b]);
                (vb.v - va.v).length() + va.w.abs() * sims[a].extent + vb.w.abs() * sims[b].extent
            };
            if recycling && recycle(c, &sims[a], &sims[b], dt, closing) {
                ask(c);
                key.touching = c.manifold.count > 0;
                return (1, usize::from(key.touching != was));
            }
            // Speculative margin: how far the pair can close in one step, so bodies meet
            // without tunnelling at ordinary speeds (with headroom: see `CLOSING_HEADROOM`).
            let (va, vb) = (&states[a], &states[b]);
            let closing = closing();
            let max_distance = SPECULATIVE_DISTANCE + dt * closing * CLOSING_HEADROOM;
            let old = c.manifold;
            let (ra, rb) = (&records[sa], &records[sb]);
            // A shape off its body's centre collides at its own pose; its anchors are then
            // moved to be relative to the body's centre, as the solver wants them.
            let (pose_a, pose_b) = (ra.pose(xa), rb.pose(xb));
            let mut m = collide(&shapes[sa], pose_a, &shapes[sb], pose_b, max_distance);
            for p in &mut m.points[..m.count] {
                if ra.offset {
                    p.anchor_a += pose_a.p - xa.p;
                }
                if rb.offset {
                    p.anchor_b += pose_b.p - xb.p;
                }
                p.base_separation = p.separation;
                if let Some(o) = old.points().iter().find(|o| o.id == p.id) {
                    p.normal_impulse = o.normal_impulse;
                    p.tangent_impulse = o.tangent_impulse;
                    p.persisted = true;
                }
            }
            // The margin above bounds how fast any point of the pair can close; each point
            // is kept only if its own gap can close in this step: within the speculative
            // distance, or approaching along the normal fast enough (at the bodies' present
            // velocities) to cross the rest. A point farther and not closing could not push
            // this step (Box2D keeps a point only within the speculative distance, and sweeps
            // what is faster): a turning drum's rim, fast along its surface but not towards
            // it, then makes no speculative points for every body near it.
            let mut kept = 0;
            // How far the pair may close in a step (its closing bound times dt) while this
            // manifold still holds every point the filter below would keep: a point at gap g
            // stays out while that is under (g - speculative distance) / lever(g), for the
            // points not computed (g past `max_distance`) and for each one dropped. A point's
            // anchors lie midway across its gap, up to g/2 past the body's extent that the
            // closing bound turns on, so its own approach is at most the bound times `lever`.
            let lever = |gap: f32| 1.0 + gap / (2.0 * sims[a].extent.min(sims[b].extent));
            let mut closing_reach = (max_distance - SPECULATIVE_DISTANCE) / lever(max_distance);
            for k in 0..m.count {
                let p = m.points[k];
                let dv = (vb.v + cross_sv(vb.w, p.anchor_b)) - (va.v + cross_sv(va.w, p.anchor_a));
                let approach = dot(dv, m.normal).min(0.0);
                if p.separation + dt * approach <= SPECULATIVE_DISTANCE {
                    m.points[kept] = p;
                    kept += 1;
                } else {
                    // One ulp under: at exactly this reach the filter would keep the point.
                    let reach = (p.separation - SPECULATIVE_DISTANCE) / lever(p.separation);
                    closing_reach = closing_reach.min(reach.next_down());
                }
            }
            m.count = kept;
            c.manifold = m;
            c.cache = Some(ContactCache {
                q_a: xa.q,
                q_b: xb.q,
                relative: xa.inv_mul(xb),
                closing_reach,
            });
            ask(c);
            key.touching = c.manifold.count > 0;
            (0, usize::from(key.touching != was))
        };
        let sum = |a: (usize, usize), b: (usize, usize)| (a.0 + b.0, a.1 + b.1);
        let (recycled, changes) = if listed {
            let contacts = SharedSlice::new(&mut self.contacts.list[..]);
            let keys = SharedSlice::new(&mut self.contacts.keys[..]);
            for_parts(
                spread,
                &self.contacts.awake[..],
                self.wide.narrow_phase,
                &|_, part: &[u32]| {
                    part.iter()
                        .map(|&k| {
                            // SAFETY: the awake list holds each contact once, so no two
                            // parts (nor two items of one) reach the same slot.
                            let (c, key) = unsafe { (contacts.at_mut(k), keys.at_mut(k)) };
                            let r = collide_one(c, key);
                            note(k as usize, key);
                            r
                        })
                        .fold((0, 0), sum)
                },
                &sum,
            )
        } else {
            for_parts(
                spread,
                (&mut self.contacts.list[..], &mut self.contacts.keys[..]),
                self.wide.narrow_phase,
                &|offset, (contacts, keys): (&mut [Contact], &mut [ContactKey])| {
                    contacts
                        .iter_mut()
                        .zip(keys)
                        .enumerate()
                        .map(|(i, (c, key))| {
                            let r = collide_one(c, key);
                            note(offset + i, key);
                            r
                        })
                        .fold((0, 0), sum)
                },
                &sum,
            )
        };
        self.stats.recycled = recycled;
        let walked = if listed {
            self.contacts.awake.len()
        } else {
            self.contacts.list.len()
        };
        (changes, walked)
    }

    /// Prepare, the substep loop, restitution and storing impulses (reads the touching,
    /// awake contacts and the bodies' states; writes states and impulses).
    fn solve(&mut self, dt: f32, substeps: u32, spread: Spread<'_>, profile: &mut StepProfile) {
        let t = Instant::now();
        let h = dt / substeps as f32;
        let inv_h = 1.0 / h;
        let s = self.settings;
        // Soft contacts no stiffer than an eighth of the substep rate (Box2D HEAD).
        let hertz = s.contact_hertz.min(0.125 * inv_h);
        let params = SolverParams {
            contact_softness: Softness::new(hertz, s.contact_damping_ratio, h),
            static_softness: Softness::new(2.0 * hertz, s.contact_damping_ratio, h),
            warm_starting: s.warm_starting,
            points_together: s.solve_points_together,
            impacts_bounce: s.impacts_bounce,
        };
        // The touching contacts of awake bodies in contact order, each with what the serial
        // colouring needs, so that it never reads the contacts. Serial, into the kept
        // buffer: a scan of the small keys costs about a nanosecond a contact, and rayon's
        // parallel extend allocates a list of vectors each step (issue 14: a steady step
        // allocates nothing).
        //
        // Each candidate is written, and the count advanced only if it touches: whether a
        // contact touches is a coin toss in a churning pile, which a branch mispredicted
        // about half the time.
        let listed = self.walk_awake_contacts();
        let keys = &self.contacts.keys;
        let candidates = if listed {
            self.contacts.awake.len()
        } else {
            keys.len()
        };
        self.contacts.touching.clear();
        self.contacts
            .touching
            .resize(candidates, Touching::default());
        let mut count = 0;
        for n in 0..candidates {
            let k = if listed {
                self.contacts.awake[n]
            } else {
                n as u32
            };
            let key = &keys[k as usize];
            self.contacts.touching[count] = Touching {
                contact: k,
                dynamic: key.dynamic,
            };
            count += usize::from(key.touching & !key.sleeping);
        }
        self.contacts.touching.truncate(count);
        profile.touching = self.contacts.touching.len();
        self.list_awake_joints();
        self.joints.last_inv_h = inv_h;
        self.solver.use_wide = s.simd;
        // Surface materials (conveyors, rolling resistance) from the contact's shapes, read
        // only in a world that has any: the others pay nothing for them.
        let (records, geometry) = (&self.shapes.records, &self.shapes.geometry);
        let surface = |a: u32, b: u32| {
            let (ra, rb) = (&records[a as usize], &records[b as usize]);
            let (sa, sb) = (&geometry[a as usize], &geometry[b as usize]);
            (
                ShapeRecord::mixed_tangent_speed(ra, rb),
                ShapeRecord::mixed_rolling_resistance(ra, sa, rb, sb),
            )
        };
        let surface: Option<&crate::solver::SurfaceOf<'_>> =
            self.shapes.any_surface.then_some(&surface);
        self.solver.prepare(
            (
                &self.joints.awake,
                &self.joints.chain_list,
                &self.joints.chain_ranges,
            ),
            &self.contacts.touching,
            &self.contacts.list,
            self.bodies.masses.len(),
            &self.bodies.states,
            &params,
            surface,
            spread,
            self.wide.prepare,
        );
        self.prepare_solver_joints(h, spread, self.wide.prepare);
        profile.colors = self.solver.active_colors();
        profile.overflow = self.solver.overflow_count();
        profile.prepare_ms = ms(t);

        let t = Instant::now();
        let step = SubstepParams {
            substeps,
            h,
            gravity: s.gravity,
            relax_iterations: s.relax_iterations,
            max_push_speed: s.max_push_speed,
            max_linear_speed: s.max_linear_speed,
            restitution_threshold: s.restitution_threshold,
            restitution_iterations: s.restitution_iterations,
            impacts_bounce: s.impacts_bounce,
        };
        // Below its threshold the solver runs on one worker: waking the others for every
        // stage (a hundred a step) costs more than their share of a small colour.
        let constraints =
            self.contacts.touching.len() + self.joints.awake.len() + self.joints.chain_list.len();
        let mut solve_spread = spread.for_stage(constraints, self.wide.solve);
        // Where splitting the substeps is timed against one worker, and lost (see
        // `threads::payoff`), they run on one.
        // The workers it would run on are capped at the cores (`Solver::run_substeps`): on
        // one core "split" and "one worker" are the same thing, and nothing is timed.
        let solve_workers = solve_spread
            .workers()
            .min(crate::threads::default_thread_count());
        let timed =
            self.wide.solve_by_payoff && !self.solver.workers_beyond_cores && solve_workers > 1;
        // What else sets the substeps' cost: times taken under other settings are not
        // weighed against these.
        let work = (u64::from(substeps) << 32)
            | (u64::from(s.relax_iterations.min(0xffff)) << 16)
            | (u64::from(s.restitution_iterations.min(0xff)) << 8)
            | (u64::from(s.impacts_bounce) << 3)
            | (u64::from(s.solve_points_together) << 2)
            | (u64::from(self.solver.use_wide) << 1)
            | u64::from(self.solver.use_avx);
        let split = !timed
            || self
                .workers
                .solve_payoff
                .split(solve_workers, work, self.stats.steps);
        let probe = timed && self.workers.solve_payoff.probing();
        if !split {
            solve_spread = Spread::INLINE;
        }
        let forced = self.bodies.refresh_force_accelerations();
        let (caps, workers) = self.solver.run_substeps(
            &mut self.bodies.states,
            &self.bodies.motion,
            &self.bodies.awake_set,
            forced.then_some(&self.bodies.force_accels[..]),
            &step,
            solve_spread,
            self.wide.solve,
        );
        self.bodies.clear_forces();
        self.stats.speed_caps += caps;
        profile.solver_workers = workers;
        profile.solver_probe = probe;
        profile.restitution_passes = self.solver.restitution_passes();
        profile.solve_ms = ms(t);
        if timed {
            self.workers.solve_payoff.record(split, profile.solve_ms);
        }

        let t = Instant::now();
        self.solver.store_impulses(
            &mut self.contacts.list,
            spread,
            self.wide.prepare,
            |contact, k, r| {
                let mp = &mut contact.manifold.points[k];
                mp.normal_impulse = r.normal_impulse;
                mp.tangent_impulse = r.tangent_impulse;
                mp.total_normal_impulse = r.total_normal_impulse;
                mp.normal_velocity = r.relative_velocity;
                if let Some(rolling) = r.rolling_impulse {
                    contact.rolling_impulse = rolling;
                }
            },
        );
        profile.store_impulses_ms = ms(t);
    }

    /// Finalize (reads each awake body's substep deltas; writes its pose, sleep time and
    /// its shapes' fat boxes): applies the deltas to the transform, resets them, and grows
    /// the fat box of any shape that left it (those become the next step's moved proxies).
    /// It walks the awake set's bodies only: a sleeping or static body costs it nothing.
    #[allow(unsafe_code)]
    fn finalize(&mut self, dt: f32, spread: Spread<'_>) {
        let sleep = self.settings.enable_sleep;
        let threshold = self.settings.sleep_threshold;
        let continuous = self.settings.continuous;
        // Returns whether the numerical guard stopped the body, and for a fast dynamic body
        // to be swept (continuous collision), its pose at the step's start.
        let finalize_one = |sim: &mut BodySim, st: &mut BodyState| -> (bool, Option<Transform>) {
            // Box2D `b2FinalizeBodiesTask`: a body that moved more than half its thickness
            // is fast, and its contacts are recomputed rather than recycled unless both
            // bodies are dynamic and can close no farther in this step than the manifold
            // covers (see `recycle`).
            let max_motion = (st.dp.length() + st.dq.s.abs() * sim.extent)
                .max((st.v.length() + st.w.abs() * sim.extent) * dt);
            sim.fast = max_motion > 0.5 * sim.min_extent;
            // Resting: slower than the threshold at every point of the body (Box2D's sleep
            // velocity, the larger of |v| and the extent's speed of turning).
            let sleep_velocity = st.v.length().max(sim.extent * st.w.abs());
            sim.sleep_time = if sleep && sleep_velocity <= threshold {
                sim.sleep_time + dt
            } else {
                0.0
            };
            let p = sim.xf.p + st.dp;
            let q = st.dq.then_from(sim.xf.q).normalize();
            st.dp = Vec2::ZERO;
            st.dq = crate::math::Rot::IDENTITY;
            // Numerical guard: a body whose state went non-finite (it cannot with finite
            // input, but a guard costs four compares) keeps its last finite pose and stops,
            // rather than spreading NaN through its contacts.
            if p.is_finite()
                && q.c.is_finite()
                && q.s.is_finite()
                && st.v.is_finite()
                && st.w.is_finite()
            {
                let start = sim.xf;
                sim.xf.p = p;
                sim.xf.q = q;
                let swept = continuous && sim.fast && sim.kind == BodyKind::Dynamic;
                (false, swept.then_some(start))
            } else {
                st.v = Vec2::ZERO;
                st.w = 0.0;
                (true, None)
            }
        };
        // Each fast dynamic body's pose at the step's start, in its own slot of a kept
        // buffer (grown only when the world is), for continuous collision.
        if self.sweeps.starts.len() < self.bodies.sims.len() {
            self.sweeps
                .starts
                .resize(self.bodies.sims.len(), Transform::IDENTITY);
        }
        // The guard's count, and how many bodies are to be swept.
        let (guarded, swept) = {
            let sims = SharedSlice::new(&mut self.bodies.sims[..]);
            let states = SharedSlice::new(&mut self.bodies.states[..]);
            let starts = SharedSlice::new(&mut self.sweeps.starts[..]);
            for_parts(
                spread,
                &self.bodies.awake_set[..],
                self.wide.finalize,
                &|_, part: &[u32]| {
                    let mut counts = (0, 0);
                    for &b in part {
                        // SAFETY: the awake set lists each body once, so no two parts (nor
                        // two items of one) reach the same slot.
                        let (sim, st) = unsafe { (sims.at_mut(b), states.at_mut(b)) };
                        let (stopped, start) = finalize_one(sim, st);
                        counts.0 += usize::from(stopped);
                        if let Some(start) = start {
                            // SAFETY: as above, this body's own slot.
                            unsafe { *starts.at_mut(b) = start };
                            counts.1 += 1;
                        }
                    }
                    counts
                },
                &|a, b| (a.0 + b.0, a.1 + b.1),
            )
        };
        // Continuous collision: fast bodies swept against the static shapes, before their
        // boxes are fitted (in slot order; each reads only what does not move here).
        let mut fast = std::mem::take(&mut self.sweeps.fast_bodies);
        fast.clear();
        if swept > 0 {
            fast.extend(self.bodies.awake_set.iter().copied().filter(|&b| {
                let sim = &self.bodies.sims[b as usize];
                sim.fast && sim.kind == BodyKind::Dynamic
            }));
            debug_assert_eq!(fast.len(), swept);
            self.stats.rewound = self.solve_continuous(&fast, false, spread);
        } else {
            self.stats.rewound = 0;
        }
        // Each shape of a body that moves: its core box, and that box swept along next
        // step's motion; a fat box is grown again when its box leaves it.
        let (sims, states, motion) = (&self.bodies.sims, &self.bodies.states, &self.bodies.motion);
        let (shapes, shape_records) = (&self.shapes.geometry, &self.shapes.records);
        let fit = |shape: &Shape, r: &ShapeRecord, fat: &mut Aabb, core_fat: &mut Aabb| {
            let b = r.body as usize;
            fit_proxy(shape, r, &sims[b], &states[b], dt, fat, core_fat)
        };
        // The moved proxies go into `moved` by id (the pair search creates contacts in this
        // order). The pair search emptied it; nothing has added to it since.
        debug_assert!(self.shapes.moved_proxies.is_empty());
        if self.bodies.awake_set.len() * 2 >= self.bodies.sims.len() {
            // Most bodies move: a stream through every shape, and a scan of the flags (a
            // byte a shape), beat walking each moving body's list of shapes.
            type ShapeBoxes<'a> = (
                &'a [Shape],
                &'a [ShapeRecord],
                &'a mut [Aabb],
                &'a mut [Aabb],
                &'a mut [bool],
            );
            let shape_part = |_: usize, (shapes, records, fats, cores, moved): ShapeBoxes<'_>| {
                let each = shapes.iter().zip(records).zip(fats).zip(cores).zip(moved);
                for ((((shape, r), fat), core_fat), moved) in each {
                    // A free slot's record names no body.
                    if r.body != super::NONE && motion[r.body as usize].moves {
                        *moved = fit(shape, r, fat, core_fat);
                    }
                }
            };
            let all = (
                &shapes[..],
                &shape_records[..],
                &mut self.shapes.swept_boxes[..],
                &mut self.shapes.unswept_boxes[..],
                &mut self.shapes.moved_flags[..],
            );
            for_each_part(spread, all, self.wide.finalize, &shape_part);
            let flags = self.shapes.moved_flags.iter().enumerate();
            self.shapes
                .moved_proxies
                .extend(flags.filter(|(_, m)| **m).map(|(s, _)| s as u32));
        } else {
            // Few move: only their shapes, reached through their bodies' lists.
            let records = &self.bodies.records;
            let fats = SharedSlice::new(&mut self.shapes.swept_boxes[..]);
            let cores = SharedSlice::new(&mut self.shapes.unswept_boxes[..]);
            let moved = SharedSlice::new(&mut self.shapes.moved_flags[..]);
            let shape_part = |_: usize, part: &[u32]| {
                for &b in part {
                    let mut s = records[b as usize].first_shape;
                    while s != super::NONE {
                        let r = &shape_records[s as usize];
                        // SAFETY: a shape is on one body's list, and the awake set lists each
                        // body once, so no two parts (nor two items of one) reach the same
                        // shape.
                        let (fat, core_fat, moved) =
                            unsafe { (fats.at_mut(s), cores.at_mut(s), moved.at_mut(s)) };
                        *moved = fit(&shapes[s as usize], r, fat, core_fat);
                        s = r.next;
                    }
                }
            };
            for_each_part(
                spread,
                &self.bodies.awake_set[..],
                self.wide.finalize,
                &shape_part,
            );
            for &b in &self.bodies.awake_set {
                let mut s = records[b as usize].first_shape;
                while s != super::NONE {
                    if self.shapes.moved_flags[s as usize] {
                        self.shapes.moved_proxies.push(s);
                    }
                    s = shape_records[s as usize].next;
                }
            }
            self.shapes.moved_proxies.sort_unstable();
        }
        // Bullets, against every body's final pose (the boxes just fitted); one moved back
        // has its boxes fitted again.
        let bullets_rewound = if fast.iter().any(|&b| self.bodies.records[b as usize].bullet) {
            self.solve_continuous(&fast, true, spread)
        } else {
            0
        };
        self.stats.rewound += bullets_rewound;
        if bullets_rewound > 0 {
            for &b in &fast {
                if self.bodies.records[b as usize].bullet {
                    self.refit_body_boxes(b, dt);
                }
            }
            self.shapes.moved_proxies.sort_unstable();
        }
        self.sweeps.fast_bodies = fast;
        if !self.shapes.moved_proxies.is_empty() {
            self.shapes.tree_dirty = true;
        }
        self.stats.guarded_last_step = guarded;
        self.stats.non_finite_bodies += guarded as u64;
    }
}

impl World {
    /// Fits body `b`'s shapes' fat boxes to its pose again (after continuous collision moved
    /// it back), as finalize does, listing any that left its box as moved.
    fn refit_body_boxes(&mut self, b: u32, dt: f32) {
        let bu = b as usize;
        let mut s = self.bodies.records[bu].first_shape;
        while s != super::NONE {
            let su = s as usize;
            let shapes = &mut self.shapes;
            let r = &shapes.records[su];
            let moved = fit_proxy(
                &shapes.geometry[su],
                r,
                &self.bodies.sims[bu],
                &self.bodies.states[bu],
                dt,
                &mut shapes.swept_boxes[su],
                &mut shapes.unswept_boxes[su],
            );
            s = r.next;
            if moved {
                shapes.mark_moved(su as u32);
            }
        }
    }
}

/// Fits a shape's two fat boxes (see `Shapes::swept_boxes`) to its body's pose now and its
/// motion over the next step of `dt`, if its boxes left them; returns whether they changed
/// (its proxy moved). Both are grown again when either is left, so that a resting body
/// (whose two boxes nearly coincide) moves in the tree once, not once for each box; a box
/// that covers everything (a static body's or a bullet's unswept box) stays so.
pub(super) fn fit_proxy(
    shape: &Shape,
    r: &ShapeRecord,
    sim: &BodySim,
    st: &BodyState,
    dt: f32,
    swept_box: &mut Aabb,
    unswept_box: &mut Aabb,
) -> bool {
    let (core, swept) = shape_boxes(shape, r, sim, st, dt);
    if swept_box.contains(&swept) && unswept_box.contains(&core) {
        return false;
    }
    *swept_box = swept.grown(sim.margin);
    if *unswept_box != Aabb::EVERYWHERE {
        *unswept_box = core.grown(sim.margin);
    }
    true
}

/// Contact recycling (Box2D v3 `b2CollideTask`): when the pair's relative pose barely
/// changed since the manifold was computed (and, for a fast body, under the rule below),
/// keep its normal, anchors, ids and impulses, and refresh only each point's separation from
/// the motion since, as the substeps do. This skips most of the narrow phase in resting
/// piles and removes jitter.
fn recycle(
    c: &mut Contact,
    sa: &BodySim,
    sb: &BodySim,
    dt: f32,
    closing: impl FnOnce() -> f32,
) -> bool {
    let Some(cache) = c.cache else {
        return false;
    };
    // A fast body's contacts with what the solver does not move (static and kinematic
    // shapes, which continuous collision sweeps it against) are recomputed every step, as
    // Box2D does for every contact of a fast body since its "Tunable ccd" change (PR #1093).
    // Two fast dynamic bodies moving together (washer's tumbling pile) keep their manifold,
    // as Box2D v3.2's `b2CollideTask` keeps it, while it still covers how far they can
    // close in this step: tumble's manifold holds the points within its speculative margin,
    // which grows with the closing speed it was made at, less any point it left out for not
    // approaching then (`ContactCache::closing_reach`); a pair that can now close farther in
    // a step (faster, or over a longer step) is recomputed.
    if sa.fast || sb.fast {
        let dynamic = sa.kind == BodyKind::Dynamic && sb.kind == BodyKind::Dynamic;
        if !dynamic || dt * closing() > cache.closing_reach {
            return false;
        }
    }
    let (xa, xb) = (sa.xf, sb.xf);
    let relative = xa.inv_mul(xb);
    let cos_a = xa.q.c * cache.q_a.c + xa.q.s * cache.q_a.s;
    let cos_b = xb.q.c * cache.q_b.c + xb.q.s * cache.q_b.s;
    let extent_a = if sa.kind == BodyKind::Static {
        0.0
    } else {
        sa.extent
    };
    let extent_b = if sb.kind == BodyKind::Static {
        0.0
    } else {
        sb.extent
    };
    let max_extent = extent_a.max(extent_b);
    let distance = (relative.p - cache.relative.p).length();
    let turn = relative.q.inv_mul(cache.relative.q);
    // Non-touching pairs get a tighter tolerance so that a new touch is not missed.
    let tolerance = if c.manifold.count > 0 {
        RECYCLE_DISTANCE
    } else {
        RECYCLE_DISTANCE.min(SPECULATIVE_DISTANCE)
    };
    if cos_a.min(cos_b) <= RECYCLE_COS_ANGLE || distance + max_extent * turn.s.abs() >= tolerance {
        return false;
    }
    let dq_a = cache.q_a.inv_mul(xa.q);
    let dq_b = cache.q_b.inv_mul(xb.q);
    let normal = c.manifold.normal;
    let dc = xb.p - xa.p;
    for p in &mut c.manifold.points[..c.manifold.count] {
        let ra = dq_a.apply(p.anchor_a);
        let rb = dq_b.apply(p.anchor_b);
        p.separation = p.base_separation + crate::math::dot(dc + (rb - ra), normal);
        p.persisted = true;
    }
    true
}

/// The shape's core box (its box grown by the speculative distance and by how far its
/// farthest point turns in a step) and that box stretched along the motion expected in the
/// next step: the broad phase then pairs what the speculative margin needs.
pub(super) fn shape_boxes(
    shape: &Shape,
    r: &ShapeRecord,
    sim: &BodySim,
    st: &BodyState,
    dt: f32,
) -> (Aabb, Aabb) {
    let pose = r.pose(sim.xf);
    let core = shape
        .aabb(pose)
        .grown(SPECULATIVE_DISTANCE + st.w.abs() * dt * sim.extent);
    let d = st.v * dt;
    let swept = Aabb {
        min: core.min + d.min(Vec2::ZERO),
        max: core.max + d.max(Vec2::ZERO),
    };
    (core, swept)
}

pub(super) fn ms(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}
