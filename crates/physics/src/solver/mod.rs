//! The solver stages of one step, in order (Box2D v3's `b2SolverStage` list):
//!
//! 1. **prepare**: colour the touching contacts, copy them into constraints ordered by colour
//!    (overflow first), compute effective masses and base separations;
//! 2. **substeps**, each: integrate velocities → warm start → solve (soft, with bias) →
//!    integrate positions → relax (rigid, no bias, with friction) × `relax_iterations`;
//! 3. **restitution** (skipped when no constraint bounces; `restitution_iterations` passes,
//!    or with `impacts_bounce` passes until the bounces hold),
//!    then **store** the accumulated impulses into the contacts for the next step's warm start.
//!
//! Each colour's constraints touch disjoint dynamic bodies; the passes walk colours in order,
//! each colour a stage of the plan that [`crate::threads::parallel::StageBoard`] runs on the
//! workers.

pub mod contact_solver;
pub mod graph_color;
pub mod lanes;
pub mod wide;
pub mod wide_hinge;

use std::ops::Range;
use std::sync::atomic::{AtomicU64, Ordering};

use glam::Vec2;

use crate::body::BodyState;
use crate::collision::Manifold;
use crate::joint::{Joint, JointBody, JointContext};
use crate::math::dot;
use crate::softness::Softness;
use crate::threads::parallel::{
    BodyMarks, BodyStates, SharedSlice, Spread, StageBoard, for_each_part, for_parts, worker_range,
};
use contact_solver::{BOUNCE_VISITS_MIN, BOUNCE_VISITS_PER_LISTED, BounceMarks};
use contact_solver::{ConstraintPoint, ContactConstraint, RESTITUTION_PASSES};
use graph_color::{COLOR_COUNT, GraphColoring, OVERFLOW};
use wide::{LANES, LaneIndex, LaneInput, LaneWriter, WideConstraint, WideSurface};

/// `lane_of` for a contact solved as a scalar constraint.
const NO_LANE: LaneIndex = u32::MAX;

/// What prepare needs to know of a body.
#[derive(Clone, Copy, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct SolverBody {
    /// Inverse mass (0 for static and kinematic bodies).
    pub inv_mass: f32,
    /// Inverse rotational inertia (0 for those and for fixed-rotation bodies).
    pub inv_inertia: f32,
    /// Whether the body is dynamic.
    pub dynamic: bool,
}

/// The contact data prepare reads.
#[derive(Clone, Copy)]
pub struct ContactInput<'a> {
    /// Bodies of the pair.
    pub body_a: u32,
    /// See `body_a`.
    pub body_b: u32,
    /// Mixed friction.
    pub friction: f32,
    /// Mixed restitution.
    pub restitution: f32,
    /// Its shapes (slots), for the surface materials.
    pub shapes: [u32; 2],
    /// The surfaces' speed along the tangent (m/s; a conveyor belt), the shapes' summed
    /// (filled by prepare from [`SurfaceOf`]; 0 without).
    pub tangent_speed: f32,
    /// The most rolling torque per newton of normal force (m; 0: none; as `tangent_speed`).
    pub rolling_resistance: f32,
    /// Last step's accumulated rolling impulse (warm start).
    pub rolling_impulse: f32,
    /// This step's manifold (with warm-start impulses).
    pub manifold: &'a Manifold,
    /// Both bodies' masses, as the contact keeps them (copied when it is made, and refreshed
    /// by the world's one mass update whenever a body's shapes or kind change, which
    /// `World::validate` checks), so neither prepare nor the colouring looks the bodies up.
    pub masses: [SolverBody; 2],
}

/// A contact's surface materials from its two shapes (slots): `(tangent speed, rolling
/// resistance)`, as the world mixes them. Given to prepare only by a world that has any.
pub type SurfaceOf<'a> = dyn Fn(u32, u32) -> (f32, f32) + Sync + 'a;

/// What prepare reads of `contact`, with its surface materials from its shapes where the
/// world has any (a world without reads nothing more of it than before they existed).
#[inline]
fn input_of<'c, C: SolverContact>(
    contact: &'c C,
    surface: Option<&SurfaceOf<'_>>,
) -> ContactInput<'c> {
    let mut c = contact.input();
    if let Some(f) = surface {
        (c.tangent_speed, c.rolling_resistance) = f(c.shapes[0], c.shapes[1]);
        c.rolling_impulse = contact.rolling_impulse();
    }
    c
}

/// `Touching::dynamic` for a body that is not dynamic.
pub const NOT_DYNAMIC: u32 = u32::MAX;

/// A touching contact as the colouring sees it.
#[derive(Clone, Copy, Debug, Default)]
pub struct Touching {
    /// Its index in the contact array.
    pub contact: u32,
    /// Its bodies, each `NOT_DYNAMIC` unless dynamic (only dynamic bodies conflict).
    pub dynamic: [u32; 2],
}

/// A contact the solver builds a constraint from (the world's contact type).
pub trait SolverContact: Sync {
    /// What prepare reads of it (surface materials and the rolling impulse as 0).
    fn input(&self) -> ContactInput<'_>;
    /// Last step's accumulated rolling impulse, read only where the world has surface
    /// materials.
    fn rolling_impulse(&self) -> f32;
}

/// Constraint buffers reused from step to step.
#[derive(Default, Debug, Clone)]
pub struct Solver {
    /// Constraints ordered by colour: overflow first, then colours 0..COLOR_COUNT-1.
    pub constraints: Vec<ContactConstraint>,
    /// `color_ranges[k]` is the range of `constraints` solved as stage k: k = 0 is the
    /// overflow, k = 1 + c is colour c.
    pub color_ranges: Vec<Range<usize>>,
    /// The coloured constraints packed eight to a wide constraint; `wide_ranges[k]` matches
    /// `color_ranges[k]` (the overflow, k = 0, is never packed).
    pub wide: Vec<WideConstraint>,
    /// See `wide`.
    pub wide_ranges: Vec<Range<usize>>,
    /// The wide constraints' surface materials, one each, in a world that has any; else
    /// empty (see [`WideSurface`]).
    wide_surfaces: Vec<WideSurface>,
    coloring: GraphColoring,
    /// For each touching contact (by position in `touching`), its colour and its rank among
    /// that colour's contacts, in contact order.
    color_of: Vec<u8>,
    rank_of: Vec<u32>,
    /// The order the colouring visits the touching contacts in (each entry's `contact` its
    /// index in `touching`), and each contact's bucket of that order.
    coloring_order: Vec<Touching>,
    order_bucket_of: Vec<u8>,
    /// The dynamic pairs the colouring was computed for, and the body count and `use_wide`.
    colored_pairs: Vec<[u32; 2]>,
    colored_for: Option<(usize, bool)>,
    /// For each scalar constraint slot, the index of the touching contact it is built from.
    slot_source: Vec<u32>,
    /// The stages of the last run of substeps (a buffer reused by the next run).
    plan: Vec<Stage>,
    /// What `plan` was laid out for (moving bodies, substeps, relax passes, workers,
    /// whether anything bounces, `impacts_bounce`, restitution passes); `None` once the
    /// colouring changed. A world whose colouring is kept steps on the same plan: laying
    /// it out again was 8% of a 15-box column's step.
    plan_key: Option<(usize, u32, u32, usize, bool, bool, u32)>,
    /// The stages of one restitution pass over the bouncing constraints
    /// ([`Solver::plan_bounces`]), a buffer kept beside `plan`.
    bounce_plan: Vec<Stage>,
    /// Restitution passes the last run of substeps took (0 when nothing bounced).
    restitution_passes: u32,
    /// With `impacts_bounce`, the constraints (wide ones where packed) that have a point to
    /// bounce, stage by stage: `bounce_ranges[k]` is colour stage k's part. Whether a point
    /// bounces is fixed once the substeps end, so the repeated passes walk this list alone.
    bouncing: Vec<u32>,
    bounce_ranges: Vec<Range<usize>>,
    /// Each listed constraint's bodies (a wide one's eight `a` then eight `b`; a scalar
    /// one's `a` and `b` repeated), streamed by the passes after the first to find the few
    /// constraints a pass moved a body of, without reading the constraints.
    bounce_bodies: Vec<[u32; 2 * wide::LANES]>,
    /// Each listed constraint's lanes that bounce (a scalar one's: bit 0).
    bounce_lanes: Vec<u8>,
    /// For each body, the last restitution pass a fast rebound moved it in
    /// ([`contact_solver::BounceMarks`]), and the last pass's number.
    bounce_marks: Vec<u32>,
    bounce_pass: u32,
    /// The board the last run on several workers used (its buffers reused by the next).
    board: StageBoard,
    /// For each wide constraint, its lanes in use.
    wide_lanes: Vec<u8>,
    /// For each touching contact (by position in `touching`), its lane of a wide
    /// constraint, or `NO_LANE` when it is a scalar constraint.
    lane_of: Vec<LaneIndex>,
    /// For each wide constraint, the index in `touching` of the contact in its lane 0 (the
    /// first of its contacts in contact order).
    first_lane_source: Vec<u32>,
    /// The wide constraints whose lanes two workers wrote in the last prepare (a buffer).
    straddlers: Vec<u32>,
    /// The awake joints' slots in stage order: `joint_order[joint_ranges[k]]` are solved in
    /// stage k with the contacts of `color_ranges[k]` (k = 0 the overflow).
    pub joint_order: Vec<u32>,
    /// See `joint_order`.
    pub joint_ranges: Vec<Range<usize>>,
    /// The chains of hinges (joint slots in path order), solved each as one system at the
    /// start of the overflow stage, and each chain's range there (and in `joint_order`).
    chain_order: Vec<u32>,
    chain_ranges: Vec<Range<usize>>,
    /// The chain solve's rows, enough for the longest chain (sized when the chains change).
    chain_rows: Vec<crate::joint::chain::Row>,
    /// The slots of `solver_joints`, in order: the stage order they were copied in; and for
    /// each slot its copy's index (`u32::MAX`: none).
    copy_order: Vec<u32>,
    copy_index: Vec<u32>,
    /// This step's copies of the awake joints, in stage order (`joint_order`), prepared: the
    /// passes stream through them as they do through the contact constraints, and
    /// [`Solver::store_joints`] writes them back.
    solver_joints: Vec<Joint>,
    /// The joints (slot and dynamic pair) the colouring was computed for.
    colored_joints: Vec<(u32, [u32; 2])>,
    /// Whether any constraint of this step has restitution.
    pub any_restitution: bool,
    /// Whether the last prepare coloured the graph (false: last step's colouring was kept).
    pub recolored: bool,
    /// Solve colours eight constraints at a time (else on the scalar path; same results).
    pub use_wide: bool,
    /// Run the eight-lane kernels in 256-bit AVX2 registers where the CPU has them (else as
    /// portable `f32x8`; same results). On by default; off only to test that equality.
    pub use_avx: bool,
    /// Run as many solver workers as asked even beyond the cores (they then wait on each
    /// other: slower, the same result). Off by default; tests of determinism turn it on to
    /// run 3 and 4 real workers on a 2-core machine.
    pub workers_beyond_cores: bool,
}

/// The knobs the solver reads each step.
#[derive(Clone, Copy, Debug)]
pub struct SolverParams {
    /// Spring for contacts between two dynamic bodies.
    pub contact_softness: Softness,
    /// Stiffer spring against static and kinematic bodies.
    pub static_softness: Softness,
    /// Whether last step's impulses seed this step.
    pub warm_starting: bool,
    /// Whether a manifold's two points well apart are solved together
    /// (`StepSettings::solve_points_together`).
    pub points_together: bool,
    /// Whether a contact that did not push last step bounces at any approach speed
    /// (`StepSettings::impacts_bounce`).
    pub impacts_bounce: bool,
}

impl SolverParams {
    /// The spring of a contact between these bodies: the stiffer one unless both are dynamic.
    #[inline]
    pub fn softness(&self, a: &SolverBody, b: &SolverBody) -> Softness {
        if a.dynamic && b.dynamic {
            self.contact_softness
        } else {
            self.static_softness
        }
    }
}

/// Bytes of wide constraints above which prepare prefetches each constraint before its
/// first lane is written (see `Solver::prepare`).
const COLD_CONSTRAINTS: usize = 4 << 20;
/// The same where the colouring was redone this step (see `Solver::prepare`): twice a core's
/// own cache (512 KB of L2 on the EPYC measured), a margin: no scene measured lies between.
const RECOLORED_COLD_CONSTRAINTS: usize = 1 << 20;

impl Solver {
    /// Empty buffers; AVX2 kernels on where the CPU has them.
    pub fn new() -> Solver {
        Solver {
            use_avx: true,
            ..Solver::default()
        }
    }

    /// Colours the touching contacts and builds their constraints; `touching` lists them in
    /// contact order, `body_count` is the world's. Its loops are split over `spread` when
    /// they hold at least `min_per_worker` touching contacts a worker.
    #[allow(clippy::too_many_arguments)]
    pub fn prepare<C: SolverContact>(
        &mut self,
        (joints, chains, chain_ranges): (&[Touching], &[u32], &[Range<usize>]),
        touching: &[Touching],
        contacts: &[C],
        body_count: usize,
        states: &[BodyState],
        params: &SolverParams,
        surface: Option<&SurfaceOf<'_>>,
        spread: Spread<'_>,
        min_per_worker: usize,
    ) {
        // The threshold in each loop's units: a loop that only compares a pair or a flag
        // splits at eight times the count of one that builds constraints (a proportion
        // assumed, not measured).
        let (min, min_check) = (min_per_worker, min_per_worker.saturating_mul(8));
        // The colouring is a function of the sequence of dynamic pairs alone (and of the
        // body count and whether colours are packed), so when that sequence is last step's
        // (a resting pile: 299 of 300 steps of large_pyramid) last step's colours, ranges and
        // lane assignment stand as they are: the same result, without the serial part.
        let key = (body_count, self.use_wide);
        let same = self.colored_for == Some(key)
            && touching.len() == self.colored_pairs.len()
            && joints.len() == self.colored_joints.len()
            && chains == self.chain_order.as_slice()
            && chain_ranges == self.chain_ranges.as_slice()
            && joints
                .iter()
                .zip(&self.colored_joints)
                .all(|(j, &(slot, pair))| j.contact == slot && j.dynamic == pair)
            && for_parts(
                spread,
                (touching, &self.colored_pairs[..]),
                min_check,
                &|_, (t, p): (&[Touching], &[[u32; 2]])| {
                    t.iter().zip(p).all(|(t, p)| t.dynamic == *p)
                },
                &|a, b| a && b,
            );
        if !same {
            self.chain_order.clear();
            self.chain_order.extend_from_slice(chains);
            self.chain_ranges.clear();
            self.chain_ranges.extend_from_slice(chain_ranges);
            let rows = chain_ranges
                .iter()
                .map(|r| crate::joint::chain::rows_needed(r.len()))
                .max()
                .unwrap_or(0);
            if self.chain_rows.len() < rows {
                self.chain_rows.resize(rows, Default::default());
            }
            self.color(joints, touching, body_count, spread, min_check);
            self.colored_for = Some(key);
        }
        self.recolored = !same;
        if !same {
            self.plan_key = None;
        }
        let scalar_len = self.slot_source.len();
        // Scalar constraints: the overflow always (it comes first), every colour when SIMD is
        // off. Each slot is built in parallel and written only by its own task.
        self.constraints
            .resize(scalar_len, ContactConstraint::default());
        let slot_source = &self.slot_source;
        for_each_part(
            spread,
            &mut self.constraints[..],
            min,
            &|offset, part: &mut [ContactConstraint]| {
                for (k, con) in part.iter_mut().enumerate() {
                    let contact_index = touching[slot_source[offset + k] as usize].contact;
                    let c = input_of(&contacts[contact_index as usize], surface);
                    *con = build_constraint(contact_index, &c, states, params);
                }
            },
        );

        // The wide constraints, lane by lane in contact order (the contacts stream in; a walk
        // by constraint read them scattered, 60 ns a lane on large_pyramid). The worker that
        // writes a constraint's last lane, having written all of them, completes it while it
        // is still in the cache: masks, tail and the point terms of all eight lanes at once
        // (a separate pass over the constraints read them back cold, a tenth of prepare on
        // washer). Every field of every lane is written, so the buffer is reused as it is
        // (a fresh 2 MB allocation each step costs page faults).
        self.wide
            .resize(self.wide_lanes.len(), WideConstraint::EMPTY);
        // Only a buffer well past the caches is cold at every lane's first store; below that
        // the prefetches cost more than they save (large_pyramid's 2 MB: +15% on this loop,
        // many_pyramids' 8 MB: -21%; a 2-vCPU EPYC). Unless the colouring was redone: each
        // contact's lane then moved, and a buffer well past the core's own cache is cold where
        // it goes (spinner, recoloured every step, 2.4 MB: prepare 0.85 to 0.89 of its time
        // without, 1 thread, interleaved; large_pyramid's 2.2 MB, coloured once and kept, took
        // 1.07 with prefetches in every step, and takes none in its kept steps).
        let bytes = self.wide.len() * std::mem::size_of::<WideConstraint>();
        let cold = bytes > COLD_CONSTRAINTS || (!same && bytes > RECOLORED_COLD_CONSTRAINTS);
        self.wide_surfaces.clear();
        // Beside the constraints, and only in a world that uses them.
        if surface.is_some() {
            self.wide_surfaces
                .resize(self.wide.len(), WideSurface::ZERO);
        }
        // A constraint whose lanes two workers wrote (its contacts straddle the boundary of
        // their parts; at most one per colour per boundary) is completed after the loop.
        self.straddlers
            .resize(crate::threads::parallel::MAX_PARTS * COLOR_COUNT, 0);
        let straddling = std::sync::atomic::AtomicUsize::new(0);
        let any_bounce = {
            let straddlers = SharedSlice::new(&mut self.straddlers);
            // SAFETY: every touching contact has its own lane (`lane_of` is injective on
            // the lanes it assigns); a constraint is completed once, by the one worker that
            // wrote all its lanes, or after the loop; nothing else touches `self.wide` until
            // `writer` is dropped at the end of this block.
            #[allow(unsafe_code)]
            let writer = unsafe { LaneWriter::shared(&mut self.wide, &mut self.wide_surfaces) };
            let (lane_of, first_lane_source, wide_lanes) =
                (&self.lane_of, &self.first_lane_source, &self.wide_lanes);
            let (use_avx, points_together) = (self.use_avx, params.points_together);
            let write_lane = |k: usize, first: usize| -> bool {
                // The touching contacts lie sparse in the contact array where many pairs
                // only overlap (smash: a third touch), which the hardware does not
                // prefetch: 30% of this loop waited on the contact's first line.
                if let Some(ahead) = touching.get(k + 8) {
                    crate::threads::parallel::prefetch(&contacts[ahead.contact as usize]);
                }
                let at = lane_of[k];
                if at == NO_LANE {
                    return false;
                }
                let (w, l) = ((at >> 3) as usize, (at & 7) as usize);
                // A colour's constraints fill in order, eight of its contacts each: while one
                // fills, an eighth of the next is fetched per lane, whose 18 cold lines would
                // otherwise stall the stores of its first lane (a fifth of this loop on
                // many_pyramids).
                if cold {
                    writer.prefetch(w + 1, l);
                }
                let contact = touching[k].contact;
                let input = input_of(&contacts[contact as usize], surface);
                let [a, b] = &input.masses;
                let softness = params.softness(a, b);
                let bounces = input.restitution > 0.0;
                let lane = LaneInput {
                    contact,
                    input,
                    softness,
                };
                writer.write(at, &lane, params);
                let lanes = wide_lanes[w] as usize;
                if l + 1 == lanes {
                    // Lanes fill in contact order, so lane 0 came first: in this part, this
                    // worker wrote them all.
                    if first_lane_source[w] as usize >= first {
                        // SAFETY: this worker wrote every lane of `w`, just now or before.
                        #[allow(unsafe_code)]
                        unsafe {
                            writer.complete(w, lanes, states, points_together, use_avx)
                        };
                    } else {
                        let slot = straddling.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                        // SAFETY: each slot is claimed once, by the fetch above.
                        #[allow(unsafe_code)]
                        unsafe {
                            *straddlers.at_mut(slot as u32) = w as u32
                        };
                    }
                }
                bounces
            };
            let any = for_parts(
                spread,
                0..touching.len(),
                min,
                &|_, part: Range<usize>| {
                    let first = part.start;
                    part.fold(false, |any, k| write_lane(k, first) | any)
                },
                &|a, b| a || b,
            );
            // Every worker is done: the straddlers' lanes are all written.
            for &w in &self.straddlers[..straddling.into_inner()] {
                let w = w as usize;
                // SAFETY: as above; the loop that wrote its lanes has joined.
                #[allow(unsafe_code)]
                unsafe {
                    writer.complete(
                        w,
                        self.wide_lanes[w] as usize,
                        states,
                        params.points_together,
                        use_avx,
                    )
                };
            }
            any
        };
        for (w, s) in self.wide.iter().zip(&mut self.wide_surfaces) {
            w.finish_surface(s);
        }
        self.any_restitution = any_bounce
            || for_parts(
                spread,
                &self.constraints[..],
                min_check,
                &|_, part: &[ContactConstraint]| part.iter().any(|c| c.restitution > 0.0),
                &|a, b| a || b,
            );
    }

    /// Drops the kept colouring, so the next prepare colours from scratch (the same result:
    /// the tests check that keeping it changes nothing).
    #[cfg(test)]
    pub fn forget_coloring(&mut self) {
        self.colored_for = None;
    }

    /// Greedy colouring in contact order, then the colour ranges and where each touching
    /// contact goes: its slot among the scalar constraints, or its lane of a wide one.
    fn color(
        &mut self,
        joints: &[Touching],
        touching: &[Touching],
        body_count: usize,
        spread: Spread<'_>,
        min: usize,
    ) {
        // The one serial part, so it reads only the compact `touching` records and the
        // per-body colour masks, never the contacts, and writes each contact's colour and
        // rank; the slots follow from those in parallel below.
        self.coloring.reset(body_count);
        let side = |d: u32| (d != NOT_DYNAMIC).then_some(d as usize);
        // Joints first, in slot order, in the same graph (Box2D colours both): the contacts
        // then fill the colours around them. With no joints this is the contact colouring
        // as it always was.
        self.color_joints(joints);
        // Colours are handed out in a scrambled order, not in contact order: see
        // `coloring_order`. Ranks stay in contact order, so each colour's lanes still stream.
        coloring_order(
            touching,
            &mut self.order_bucket_of,
            &mut self.coloring_order,
        );
        self.color_of.clear();
        self.color_of.resize(touching.len(), 0);
        for t in &self.coloring_order {
            let color = self.coloring.assign(side(t.dynamic[0]), side(t.dynamic[1]));
            self.color_of[t.contact as usize] = color as u8;
        }
        self.rank_of.clear();
        let mut counts = [0u32; COLOR_COUNT];
        for &color in &self.color_of {
            self.rank_of.push(counts[color as usize]);
            counts[color as usize] += 1;
        }
        self.colored_pairs.clear();
        self.colored_pairs
            .extend(touching.iter().map(|t| t.dynamic));
        // Stage order: overflow, then colours ascending.
        let order: Vec<usize> = std::iter::once(OVERFLOW).chain(0..OVERFLOW).collect();
        let mut start = [0usize; COLOR_COUNT];
        self.color_ranges.clear();
        let mut offset = 0;
        for &color in &order {
            let n = counts[color] as usize;
            start[color] = offset;
            self.color_ranges.push(offset..offset + n);
            offset += n;
        }
        // The colours are packed eight to a wide constraint; colour c's constraints fill
        // wide constraints `wide_ranges[1 + c]` in contact order.
        self.wide_ranges.clear();
        self.wide_lanes.clear();
        for (k, r) in self.color_ranges.iter().enumerate() {
            let first = self.wide_lanes.len();
            if k > 0 && self.use_wide {
                let full = r.len() / LANES;
                self.wide_lanes
                    .extend(std::iter::repeat_n(LANES as u8, full));
                if r.len() % LANES > 0 {
                    self.wide_lanes.push((r.len() % LANES) as u8);
                }
            }
            self.wide_ranges.push(first..self.wide_lanes.len());
        }
        // Scalar slots: the overflow's (first) when packing, else all of them.
        let use_wide = self.use_wide;
        let scalar_len = if use_wide {
            self.color_ranges[0].end
        } else {
            offset
        };
        self.slot_source.clear();
        self.slot_source.resize(scalar_len, 0);
        if scalar_len > 0 {
            for (k, (&color, &rank)) in self.color_of.iter().zip(&self.rank_of).enumerate() {
                let slot = start[color as usize] + rank as usize;
                if slot < scalar_len {
                    self.slot_source[slot] = k as u32;
                }
            }
        }
        let wide_start: [usize; COLOR_COUNT] =
            std::array::from_fn(|c| self.wide_ranges.get(1 + c).map_or(0, |r| r.start));
        self.lane_of.clear();
        self.lane_of.resize(touching.len(), NO_LANE);
        let lane = |color: u8, rank: u32| {
            let color = color as usize;
            if !use_wide || color == OVERFLOW {
                NO_LANE
            } else {
                let rank = rank as usize;
                let wide = wide_start[color] + rank / LANES;
                ((wide << 3) | (rank % LANES)) as LaneIndex
            }
        };
        for_each_part(
            spread,
            (&mut self.lane_of[..], &self.color_of[..], &self.rank_of[..]),
            min,
            &|_, (lanes, colors, ranks): (&mut [LaneIndex], &[u8], &[u32])| {
                for ((at, &color), &rank) in lanes.iter_mut().zip(colors).zip(ranks) {
                    *at = lane(color, rank);
                }
            },
        );
        self.first_lane_source.clear();
        self.first_lane_source
            .resize(self.wide_lanes.len(), u32::MAX);
        for (k, &at) in self.lane_of.iter().enumerate() {
            if at != NO_LANE && at & 7 == 0 {
                self.first_lane_source[(at >> 3) as usize] = k as u32;
            }
        }
    }

    /// Copies the awake joints into stage order and prepares each (after
    /// [`Solver::prepare`], which coloured them): `joints` by slot, `body(i)` what a joint
    /// reads of body `i`. Over `spread` where there are `min` joints a worker.
    ///
    /// The copies stay the joints' live state after the step: while the stage order holds
    /// (`copies` and no recolouring) the next step prepares them in place, without copying
    /// 200 bytes a joint in and out (a fifth of `joint_grid`'s step); [`Solver::store_joints`]
    /// writes them back when the order changes or the world reads or edits its joints.
    /// `copies`: the live copies stand (the caller writes them back and passes false when
    /// [`Solver::joint_order_changed`]). Returns whether it copied afresh.
    #[allow(clippy::too_many_arguments)]
    pub fn prepare_joints(
        &mut self,
        joints: &[Joint],
        copies: bool,
        body: &(dyn Fn(u32) -> JointBody + Sync),
        ctx: &JointContext,
        spread: Spread<'_>,
        min: usize,
    ) -> bool {
        let fresh = !copies;
        let order = &self.joint_order;
        if fresh {
            self.solver_joints
                .resize_with(order.len(), || joints[0].clone());
            self.copy_order.clone_from(order);
            self.copy_index.clear();
            self.copy_index.resize(joints.len(), u32::MAX);
            for (k, &slot) in order.iter().enumerate() {
                self.copy_index[slot as usize] = k as u32;
            }
        }
        for_each_part(
            spread,
            &mut self.solver_joints[..],
            min,
            &|offset, part: &mut [Joint]| {
                for (k, j) in part.iter_mut().enumerate() {
                    if fresh {
                        j.clone_from(&joints[order[offset + k] as usize]);
                    }
                    let (a, b) = (body(j.body_a), body(j.body_b));
                    j.prepare(&a, &b, ctx);
                }
            },
        );
        fresh
    }

    /// Whether the stage order of the joints differs from that of the live copies.
    pub fn joint_order_changed(&self) -> bool {
        self.copy_order != self.joint_order
    }

    /// The live copy of the joint in `slot`, if the solver holds one (see
    /// [`Solver::prepare_joints`]).
    pub fn joint_copy(&self, slot: u32) -> Option<&Joint> {
        let k = *self.copy_index.get(slot as usize)?;
        self.solver_joints.get(k as usize)
    }

    /// Writes the live copies (their impulses, for the next warm start, and their step
    /// data, for reaction forces) back to their slots in `joints`.
    #[allow(unsafe_code)]
    pub fn store_joints(&self, joints: &mut [Joint], spread: Spread<'_>, min: usize) {
        let order = &self.copy_order;
        let out = SharedSlice::new(joints);
        for_each_part(
            spread,
            &self.solver_joints[..],
            min,
            &|offset, part: &[Joint]| {
                for (k, j) in part.iter().enumerate() {
                    // SAFETY: each slot is in `copy_order` once; the parts are disjoint.
                    let slot = unsafe { out.at_mut(order[offset + k]) };
                    // Only the impulses (in the kind) and the step data changed.
                    slot.kind.clone_from(&j.kind);
                    slot.step = j.step;
                }
            },
        );
    }

    /// Colours the joints (the first part of [`Solver::color`]) and lays out their stage
    /// order: the overflow's first, then each colour's, each in slot order.
    fn color_joints(&mut self, joints: &[Touching]) {
        let side = |d: u32| (d != NOT_DYNAMIC).then_some(d as usize);
        let mut counts = [0usize; COLOR_COUNT];
        let colors: Vec<u8> = joints
            .iter()
            .map(|j| {
                let c = self.coloring.assign(side(j.dynamic[0]), side(j.dynamic[1]));
                counts[c] += 1;
                c as u8
            })
            .collect();
        // The chains open the overflow's range.
        let chained = self.chain_order.len();
        let mut start = [0usize; COLOR_COUNT];
        self.joint_ranges.clear();
        let mut offset = 0;
        for color in std::iter::once(OVERFLOW).chain(0..OVERFLOW) {
            let extra = if color == OVERFLOW { chained } else { 0 };
            start[color] = offset + extra;
            self.joint_ranges
                .push(offset..offset + extra + counts[color]);
            offset += extra + counts[color];
        }
        self.joint_order.clear();
        self.joint_order.resize(chained + joints.len(), 0);
        self.joint_order[..chained].copy_from_slice(&self.chain_order);
        for (j, &c) in joints.iter().zip(&colors) {
            self.joint_order[start[c as usize]] = j.contact;
            start[c as usize] += 1;
        }
        self.colored_joints.clear();
        self.colored_joints
            .extend(joints.iter().map(|j| (j.contact, j.dynamic)));
    }

    /// Stores every constraint's impulses into its contact, over `spread` where there are
    /// `min_per_worker` contacts a worker: `store(contact, point, impulses)` is called for
    /// each point of each constraint solved in the last step, with `contact = &mut
    /// contacts[constraint's contact index]`. Each touching contact became exactly one
    /// constraint, so no two calls share a contact.
    #[allow(unsafe_code)]
    pub fn store_impulses<C: Send>(
        &self,
        contacts: &mut [C],
        spread: Spread<'_>,
        min_per_worker: usize,
        store: impl Fn(&mut C, usize, &PointResult) + Sync,
    ) {
        let contacts = SharedSlice::new(contacts);
        let overflow_end = self.color_ranges.first().map_or(0, |r| r.end);
        let scalar = if self.use_wide {
            &self.constraints[..overflow_end]
        } else {
            &self.constraints[..]
        };
        let store_scalar = |c: &ContactConstraint| {
            let i = c.contact as usize;
            // SAFETY: constraints come from distinct touching contacts (see above), so this
            // element is this task's alone.
            let contact = unsafe { &mut contacts.range_mut(i..i + 1)[0] };
            for (k, p) in c.points[..c.count].iter().enumerate() {
                store(
                    contact,
                    k,
                    &PointResult {
                        normal_impulse: p.normal_impulse,
                        tangent_impulse: p.tangent_impulse,
                        total_normal_impulse: p.total_normal_impulse,
                        relative_velocity: p.relative_velocity,
                        rolling_impulse: (c.rolling_resistance > 0.0).then_some(c.rolling_impulse),
                    },
                );
            }
        };
        for_each_part(
            spread,
            scalar,
            min_per_worker,
            &|_, part: &[ContactConstraint]| part.iter().for_each(store_scalar),
        );
        if self.use_wide {
            // In contact order, as prepare wrote the lanes: the contacts are written as a
            // stream and the lanes are read from one stream per colour.
            let (wide, lane_of, surfaces) = (&self.wide, &self.lane_of, &self.wide_surfaces);
            let store_lane = |k: usize| {
                // As in prepare: fetch a contact a few ahead, the stream is sparse.
                if let Some(&ahead) = lane_of.get(k + 8)
                    && ahead != NO_LANE
                {
                    let i = wide[(ahead >> 3) as usize].contact_of((ahead & 7) as usize);
                    crate::threads::parallel::prefetch_ptr(contacts.as_ptr_at(i as usize));
                }
                let at = lane_of[k];
                if at == NO_LANE {
                    return;
                }
                let w = &wide[(at >> 3) as usize];
                let lane = (at & 7) as usize;
                let i = w.contact_of(lane) as usize;
                // SAFETY: as above; a contact is in one lane of one wide constraint.
                let contact = unsafe { &mut contacts.range_mut(i..i + 1)[0] };
                let surface = surfaces.get((at >> 3) as usize);
                w.lane_results(lane, surface, |point, r| store(contact, point, r));
            };
            let all = 0..lane_of.len();
            for_each_part(spread, all, min_per_worker, &|_, part: Range<usize>| {
                part.for_each(store_lane)
            });
        }
    }

    /// `(contact index, colour)` of every constraint of the last step, overflow as 23.
    pub fn contact_colors(&self) -> Vec<(usize, u8)> {
        let mut out = Vec::new();
        for (k, r) in self.color_ranges.iter().enumerate() {
            let color = if k == 0 {
                OVERFLOW as u8
            } else {
                (k - 1) as u8
            };
            if k == 0 || !self.use_wide {
                out.extend(
                    self.constraints[r.clone()]
                        .iter()
                        .map(|c| (c.contact as usize, color)),
                );
            } else {
                for w in &self.wide[self.wide_ranges[k].clone()] {
                    out.extend(w.contacts().map(|c| (c as usize, color)));
                }
            }
        }
        out
    }

    /// Colours in use (by contacts or joints), overflow not counted.
    pub fn active_colors(&self) -> usize {
        (1..self.color_ranges.len())
            .filter(|&k| {
                !self.color_ranges[k].is_empty()
                    || self.joint_ranges.get(k).is_some_and(|r| !r.is_empty())
            })
            .count()
    }

    /// Constraints in the overflow (contacts and joints).
    pub fn overflow_count(&self) -> usize {
        self.color_ranges[0].len() + self.joint_ranges.first().map_or(0, |r| r.len())
    }

    /// Runs the substeps, then the restitution passes, over `spread`: this thread and its
    /// crew's followers, or inline on this thread with no synchronisation. Returns how often
    /// a speed cap bit, and the workers used.
    ///
    /// The stages (Box2D v3's `b2SolverStage` list) are laid out once as a plan; one worker
    /// walks it and the others help with each stage through a [`StageBoard`]: a stage's
    /// blocks are bodies (integration) or one colour's constraints, and each colour's
    /// overflow is solved by the leading worker alone before the colours. The result does
    /// not depend on `workers` nor on who runs which block: each colour's constraints touch
    /// disjoint bodies, so their order within a colour is moot.
    /// `moving` lists the bodies that move (each once; the body stages walk only them);
    /// `forced`, when some body has a force or torque applied this step, each body's
    /// acceleration from it (by slot; `None` costs the integration nothing).
    pub fn run_substeps(
        &mut self,
        states: &mut [BodyState],
        motion: &[BodyMotion],
        moving: &[u32],
        forced: Option<&[ForceAcceleration]>,
        step: &SubstepParams,
        spread: Spread<'_>,
        bounce_min_per_worker: usize,
    ) -> (u64, usize) {
        // Spinning workers beyond the core count only wait on each other: cap them there.
        let cores = if self.workers_beyond_cores {
            usize::MAX
        } else {
            crate::default_thread_count()
        };
        let workers = spread.workers().min(cores);
        // The plan's buffer is kept from run to run: a steady scene's step allocates nothing.
        let mut plan = std::mem::take(&mut self.plan);
        let key = (
            moving.len(),
            step.substeps,
            step.relax_iterations,
            workers,
            self.any_restitution,
            step.impacts_bounce,
            step.restitution_iterations,
        );
        if self.plan_key != Some(key) {
            self.plan_into(&mut plan, moving.len(), step, workers);
            self.plan_key = Some(key);
        }
        let bodies = Bodies {
            motion,
            moving,
            forced,
        };
        let mut joints = std::mem::take(&mut self.solver_joints);
        let result = self.run_plan(
            &plan,
            &mut joints,
            states,
            &bodies,
            step,
            spread,
            workers,
            None,
        );
        // The fixed passes ran at the plan's end (`plan_into`).
        self.restitution_passes = if self.any_restitution && !step.impacts_bounce {
            step.restitution_iterations.max(1)
        } else {
            0
        };
        if self.any_restitution && step.impacts_bounce {
            // Restitution passes until one moves no fast rebound by more than the tolerance
            // (`contact_solver::bounce_moved`), at most `RESTITUTION_PASSES` (or
            // `restitution_iterations`, if more): a body that hits two others in one step is
            // bounced off one and sent back into it by the other, and each further pass
            // carries the bounces on, as Gauss-Seidel does, until they hold for every contact
            // at once. Each pass is a run of its own, since whether another follows is known
            // only at its end: a count summed over the constraints, each computed alike on
            // any number of workers, so the pass count is the same on any too.
            //
            // The passes walk only the constraints with a point that bounces (in `spinner`,
            // a churning pile, a third of them), on one worker unless those are many, and
            // after the first only the lanes whose bodies a fast rebound has just moved
            // (`contact_solver::BounceMarks`). Where many bounce at once, the passes stop
            // once they have visited `BOUNCE_VISITS_PER_LISTED` times the listed
            // constraints: a dense pile of fast impacts converges a few per cent a pass
            // (spinner's bounces ran all 16 passes in 191 of its first 200 steps, and its
            // solve took 1.34 times as long as with Box2D's rule; 1.15 with the budget).
            let listed = self.list_bouncing(step.restitution_threshold);
            if listed > 0 {
                // Each pass on one worker unless the one before visited many contacts (the
                // first: unless many are listed); a pass after the first visits only those
                // near a rebound, and waking the crew for each of its stages costs more.
                let spread_for = |contacts: usize| {
                    if spread.goes_wide(contacts, bounce_min_per_worker) {
                        (spread, workers)
                    } else {
                        (Spread::INLINE, 1)
                    }
                };
                let (mut pass_spread, mut pass_workers) = spread_for(listed);
                let mut bounce_plan = std::mem::take(&mut self.bounce_plan);
                self.plan_bounces(&mut bounce_plan, workers);
                self.bounce_marks.resize(states.len(), 0);
                let passes = step.restitution_iterations.max(RESTITUTION_PASSES);
                // Pass numbers run on from step to step, so no mark needs clearing; a mark
                // older than this step's first pass never asks for a visit.
                if self.bounce_pass >= u32::MAX.saturating_sub(passes) {
                    self.bounce_marks.fill(0);
                    self.bounce_pass = 0;
                }
                let first = self.bounce_pass + 1;
                let budget = (BOUNCE_VISITS_PER_LISTED * listed as u64).max(BOUNCE_VISITS_MIN);
                let mut visited = 0;
                for _ in 0..passes {
                    self.bounce_pass += 1;
                    let bounce = Some((self.bounce_pass, self.bounce_pass == first));
                    let (count, _) = self.run_plan(
                        &bounce_plan,
                        &mut joints,
                        states,
                        &bodies,
                        step,
                        pass_spread,
                        pass_workers,
                        bounce,
                    );
                    let (moved, visits) = (count & 0xffff_ffff, count >> 32);
                    visited += visits;
                    (pass_spread, pass_workers) = spread_for(visits as usize);
                    self.restitution_passes += 1;
                    if moved == 0 || visited > budget {
                        break;
                    }
                }
                self.bounce_plan = bounce_plan;
            }
        }
        self.solver_joints = joints;
        self.plan = plan;
        result
    }

    /// Restitution passes the last [`Solver::run_substeps`] took.
    pub fn restitution_passes(&self) -> u32 {
        self.restitution_passes
    }

    /// Runs the stages of `plan` on `workers` workers; see [`Solver::run_substeps`].
    #[allow(unsafe_code)]
    #[allow(clippy::too_many_arguments)]
    fn run_plan(
        &mut self,
        plan: &[Stage],
        joints: &mut [Joint],
        states: &mut [BodyState],
        bodies: &Bodies<'_>,
        step: &SubstepParams,
        spread: Spread<'_>,
        workers: usize,
        bounce: Option<(u32, bool)>,
    ) -> (u64, usize) {
        let bounce = bounce.map(|(pass, first)| BounceMarks {
            // SAFETY: marks are read (by `Passes::run`, choosing the lanes to solve) and
            // written (by the restitution kernels) only for the bodies of the constraint
            // being solved, and only dynamic bodies' are written: the contract of
            // `BodyStates::shared`, which the colouring keeps.
            moved_in: unsafe { BodyMarks::shared(&mut self.bounce_marks) },
            pass,
            first,
        });
        let passes = Passes {
            scalar: SharedSlice::new(&mut self.constraints),
            wide: SharedSlice::new(&mut self.wide),
            surfaces: SharedSlice::new(&mut self.wide_surfaces),
            use_wide: self.use_wide,
            use_avx: self.use_avx,
            joints: SharedSlice::new(joints),
            chains: &self.chain_ranges,
            chain_rows: SharedSlice::new(&mut self.chain_rows),
            bouncing: &self.bouncing,
            bounce_bodies: &self.bounce_bodies,
            bounce_lanes: &self.bounce_lanes,
            bounce: bounce.as_ref(),
        };
        if workers == 1 {
            let states = BodyStates::exclusive(states);
            let caps = plan
                .iter()
                .map(|stage| {
                    passes.run_joints(stage, stage.joints.clone(), &states, step);
                    passes.run(stage, stage.items.clone(), &states, bodies, step)
                })
                .sum();
            return (caps, 1);
        }
        // SAFETY: a block is bodies of an integration stage (`moving` lists each once), or
        // constraints of one colour (which touch disjoint dynamic bodies and write no other
        // body), and the blocks of one stage are disjoint; the board runs the stages one
        // after another.
        let states = unsafe { BodyStates::shared(states) };
        let crew = spread.crew().expect("several workers come with a crew");
        let mut board = std::mem::take(&mut self.board);
        board.reset(plan.iter().map(|stage| stage.blocks), workers);
        // Each worker's speed-cap count; a sum of integers, so who counted which is moot.
        let caps = AtomicU64::new(0);
        crew.run(&|| {
            let mut mine = 0;
            let mut run = |s: usize, block: usize| {
                let stage = &plan[s];
                // A colour's joint blocks come first, then its contact blocks; a stage of
                // one block (the overflow) solves its joints, then its contacts.
                let jb = stage.joint_blocks;
                if block < jb {
                    let joints = worker_range(&stage.joints, block, jb);
                    passes.run_joints(stage, joints, &states, step);
                    return;
                }
                if jb == 0 {
                    passes.run_joints(stage, stage.joints.clone(), &states, step);
                }
                let items = worker_range(&stage.items, block - jb, stage.blocks - jb);
                mine += passes.run(stage, items, &states, bodies, step);
            };
            match board.join() {
                Some(0) => {
                    for s in 0..plan.len() {
                        board.lead(s, &mut run);
                    }
                    board.finish();
                }
                Some(share) => board.follow(share, &mut run),
                None => {}
            }
            caps.fetch_add(mine, Ordering::Relaxed);
        });
        self.board = board;
        (caps.into_inner(), workers)
    }

    /// Lists, stage by stage, the constraints with a point that bounces
    /// ([`contact_solver::may_bounce`], [`wide::bounce_lane_bits`]), with the lanes that do
    /// (a scalar constraint's: bit 0); returns how many contacts bounce, the same count
    /// whether the colours are packed eight to a constraint or not.
    fn list_bouncing(&mut self, threshold: f32) -> usize {
        self.bouncing.clear();
        self.bounce_ranges.clear();
        self.bounce_bodies.clear();
        self.bounce_lanes.clear();
        let mut contacts = 0;
        for (k, r) in self.color_ranges.iter().enumerate() {
            let start = self.bouncing.len();
            if k == 0 || !self.use_wide {
                for i in r.clone() {
                    let c = &self.constraints[i];
                    if contact_solver::may_bounce(c, threshold) {
                        self.bouncing.push(i as u32);
                        let mut bodies = [c.body_a; 2 * wide::LANES];
                        bodies[wide::LANES..].fill(c.body_b);
                        self.bounce_bodies.push(bodies);
                        self.bounce_lanes.push(1);
                        contacts += 1;
                    }
                }
            } else {
                for i in self.wide_ranges[k].clone() {
                    let c = &self.wide[i];
                    let lanes = wide::bounce_lane_bits(c, threshold);
                    if lanes != 0 {
                        self.bouncing.push(i as u32);
                        self.bounce_bodies.push(c.lane_bodies());
                        self.bounce_lanes.push(lanes);
                        contacts += lanes.count_ones() as usize;
                    }
                }
            }
            self.bounce_ranges.push(start..self.bouncing.len());
        }
        contacts
    }

    /// One restitution pass over the listed constraints ([`Solver::list_bouncing`]): a
    /// stage per colour that has any, the overflow's on one worker.
    fn plan_bounces(&self, plan: &mut Vec<Stage>, workers: usize) {
        plan.clear();
        for (k, r) in self.bounce_ranges.iter().enumerate() {
            if r.is_empty() {
                continue;
            }
            let min = if k == 0 {
                usize::MAX
            } else if self.use_wide {
                4
            } else {
                32
            };
            plan.push(Stage {
                pass: Pass::Bounce,
                color: k,
                items: r.clone(),
                blocks: (r.len() / min).clamp(1, 8 * workers),
                joints: 0..0,
                joint_blocks: 0,
            });
        }
    }

    /// The stages of one run of substeps, in order: per substep, integrate velocities, warm
    /// start, solve, integrate positions and relax (each colour pass as one stage per colour,
    /// the overflow first), then `restitution_iterations` restitution passes when any
    /// constraint bounces (with `impacts_bounce` off, else [`Solver::plan_bounces`]).
    fn plan_into(
        &self,
        plan: &mut Vec<Stage>,
        bodies: usize,
        step: &SubstepParams,
        workers: usize,
    ) {
        // Blocks small enough that a worker that finishes early can take a slow one's last
        // blocks, large enough that claiming one (an atomic add) stays negligible.
        let blocks = |len: usize, min: usize| (len / min).clamp(1, 8 * workers);
        plan.clear();
        let bodies_stage = |pass| Stage {
            pass,
            color: 0,
            items: 0..bodies,
            blocks: blocks(bodies, 128),
            joints: 0..0,
            joint_blocks: 0,
        };
        let colors = |plan: &mut Vec<Stage>, pass| {
            for (k, r) in self.color_ranges.iter().enumerate() {
                // Restitution is the contacts' alone.
                let joints = match (pass, self.joint_ranges.get(k)) {
                    (Pass::Restitution, _) | (_, None) => 0..0,
                    (_, Some(j)) => j.clone(),
                };
                if r.is_empty() && joints.is_empty() {
                    continue;
                }
                let some = |len: usize, min: usize| if len == 0 { 0 } else { blocks(len, min) };
                let (items, contact_blocks) = if k == 0 {
                    // The overflow: its constraints may share bodies, so one worker alone.
                    (r.clone(), 1)
                } else if self.use_wide {
                    let items = self.wide_ranges[k].clone();
                    let n = some(items.len(), 4);
                    (items, n)
                } else {
                    (r.clone(), some(r.len(), 32))
                };
                let joint_blocks = if k == 0 { 0 } else { some(joints.len(), 16) };
                plan.push(Stage {
                    pass,
                    color: k,
                    items,
                    blocks: joint_blocks + contact_blocks,
                    joints,
                    joint_blocks,
                });
            }
        };
        for _ in 0..step.substeps {
            plan.push(bodies_stage(Pass::IntegrateVelocities));
            colors(plan, Pass::WarmStart);
            colors(plan, Pass::Solve);
            plan.push(bodies_stage(Pass::IntegratePositions));
            for _ in 0..step.relax_iterations {
                colors(plan, Pass::Relax);
            }
        }
        // With `impacts_bounce` the passes run apart, each its own plan (`run_substeps`).
        if self.any_restitution && !step.impacts_bounce {
            for _ in 0..step.restitution_iterations.max(1) {
                colors(plan, Pass::Restitution);
            }
        }
    }
}

/// Builds one constraint from its contact: copies what the substeps need and computes the
/// effective masses and base separations (docs/soft_step.md 2.4).
fn build_constraint(
    contact_index: u32,
    c: &ContactInput<'_>,
    states: &[BodyState],
    params: &SolverParams,
) -> ContactConstraint {
    let [ba, bb] = c.masses;
    let m = c.manifold;
    let mut con = ContactConstraint {
        body_a: c.body_a,
        body_b: c.body_b,
        contact: contact_index,
        dynamic_a: ba.dynamic,
        dynamic_b: bb.dynamic,
        inv_mass_a: ba.inv_mass,
        inv_i_a: ba.inv_inertia,
        inv_mass_b: bb.inv_mass,
        inv_i_b: bb.inv_inertia,
        normal: m.normal,
        friction: c.friction,
        restitution: c.restitution,
        tangent_speed: c.tangent_speed,
        rolling_resistance: c.rolling_resistance,
        rolling_mass: rolling_mass(ba.inv_inertia, bb.inv_inertia),
        rolling_impulse: if params.warm_starting && c.rolling_resistance > 0.0 {
            c.rolling_impulse
        } else {
            0.0
        },
        softness: params.softness(&ba, &bb),
        count: m.count,
        together: params.points_together
            && m.count == 2
            && contact_solver::points_together(
                m.normal,
                [ba.inv_mass, ba.inv_inertia, bb.inv_mass, bb.inv_inertia],
                [
                    [m.points[0].anchor_a, m.points[0].anchor_b],
                    [m.points[1].anchor_a, m.points[1].anchor_b],
                ],
            ),
        at_rest: contact_solver::threshold_applies(params.impacts_bounce, m),
        points: [ConstraintPoint::default(); 2],
    };
    let sa = &states[c.body_a as usize];
    let sb = &states[c.body_b as usize];
    for (i, mp) in m.points().iter().enumerate() {
        let mut p = ConstraintPoint {
            anchor_a: mp.anchor_a,
            anchor_b: mp.anchor_b,
            ..ConstraintPoint::default()
        };
        if params.warm_starting {
            p.normal_impulse = mp.normal_impulse;
            p.tangent_impulse = mp.tangent_impulse;
        }
        contact_solver::prepare_point(&con, &mut p, sa, sb, mp.separation);
        con.points[i] = p;
    }
    con
}

/// The effective mass of the relative spin that rolling resistance brakes:
/// `1 / (1/Ia + 1/Ib)` from the inverse inertias, 0 when neither turns (Box2D's
/// `rollingMass`). One definition for the scalar and the 8-lane constraints.
#[inline(always)]
pub fn rolling_mass(inv_i_a: f32, inv_i_b: f32) -> f32 {
    let k = inv_i_a + inv_i_b;
    if k > 0.0 { 1.0 / k } else { 0.0 }
}

/// The acceleration a body's applied force and torque give it through one step (the
/// force times its inverse mass, the torque times its inverse inertia).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ForceAcceleration {
    /// m/s².
    pub linear: Vec2,
    /// rad/s².
    pub angular: f32,
}

/// What the integration stages need of a body.
#[derive(Clone, Copy, Debug, Default, serde::Serialize, serde::Deserialize)]
pub struct BodyMotion {
    /// Gravity and damping act on it, and the speed cap.
    pub dynamic: bool,
    /// It moves at all (dynamic or kinematic).
    pub moves: bool,
    /// It turns (kinematic, or dynamic with non-zero inverse inertia).
    pub rotates: bool,
    /// Damping per second.
    pub linear_damping: f32,
    /// Damping per second.
    pub angular_damping: f32,
    /// Multiplies gravity.
    #[serde(default = "one")]
    pub gravity_scale: f32,
}

fn one() -> f32 {
    1.0
}

/// What one contact point ends a step with.
#[derive(Clone, Copy, Debug)]
pub struct PointResult {
    /// Accumulated normal impulse.
    pub normal_impulse: f32,
    /// Accumulated friction impulse.
    pub tangent_impulse: f32,
    /// Largest normal impulse of the step.
    pub total_normal_impulse: f32,
    /// Normal velocity before the solve.
    pub relative_velocity: f32,
    /// The contact's accumulated rolling-resistance impulse (the same for each of its
    /// points), where it resists rolling: a contact without leaves its own untouched, so
    /// the store writes nothing more for it.
    pub rolling_impulse: Option<f32>,
}

/// The knobs of one run of substeps.
#[derive(Clone, Copy, Debug)]
pub struct SubstepParams {
    /// Substeps in the step.
    pub substeps: u32,
    /// Substep length.
    pub h: f32,
    /// Gravity.
    pub gravity: Vec2,
    /// Relax passes per substep.
    pub relax_iterations: u32,
    /// Push-out speed cap.
    pub max_push_speed: f32,
    /// Linear speed cap.
    pub max_linear_speed: f32,
    /// Restitution threshold.
    pub restitution_threshold: f32,
    /// Restitution passes: exactly these, or with `impacts_bounce` until the bounces hold.
    pub restitution_iterations: u32,
    /// `StepSettings::impacts_bounce`.
    pub impacts_bounce: bool,
}

/// What a stage does.
#[derive(Clone, Copy, Debug)]
enum Pass {
    IntegrateVelocities,
    WarmStart,
    Solve,
    IntegratePositions,
    Relax,
    Restitution,
    /// A restitution pass over the listed constraints ([`Solver::list_bouncing`]): the
    /// stage's items index that list.
    Bounce,
}

/// One stage of the plan: a pass over bodies, or over one colour's constraints.
#[derive(Clone, Debug)]
struct Stage {
    pass: Pass,
    /// For a constraint pass, the colour's index in `color_ranges` (0: the overflow).
    color: usize,
    /// Bodies, or the colour's constraints (wide ones when packed).
    items: Range<usize>,
    /// Blocks it is cut into: the joints' first, then the items'.
    blocks: usize,
    /// The colour's joints (a range of `Solver::joint_order`).
    joints: Range<usize>,
    /// Blocks of joints; 0 when the stage's one block solves its joints before its items.
    joint_blocks: usize,
}

/// What the body stages walk: the moving bodies, and every body's integration flags.
struct Bodies<'a> {
    motion: &'a [BodyMotion],
    /// Slots of the bodies that move, each once: the body stages' items index it.
    moving: &'a [u32],
    /// Each body's acceleration from applied forces, by slot, when any body has one.
    forced: Option<&'a [ForceAcceleration]>,
}

/// The constraint arrays the workers share.
struct Passes<'a> {
    scalar: SharedSlice<'a, ContactConstraint>,
    wide: SharedSlice<'a, WideConstraint>,
    /// The wide constraints' surface materials: empty, or one per constraint.
    surfaces: SharedSlice<'a, WideSurface>,
    use_wide: bool,
    use_avx: bool,
    joints: SharedSlice<'a, Joint>,
    /// The chains' ranges of the joints (in the overflow stage's).
    chains: &'a [Range<usize>],
    /// Their solve's rows (the overflow stage's one worker uses them).
    chain_rows: SharedSlice<'a, crate::joint::chain::Row>,
    /// The constraints with a point that bounces ([`Pass::Bounce`]'s items index it).
    bouncing: &'a [u32],
    /// Their bodies ([`Solver::bounce_bodies`]).
    bounce_bodies: &'a [[u32; 2 * wide::LANES]],
    /// Their bouncing lanes ([`Solver::bounce_lanes`]).
    bounce_lanes: &'a [u8],
    /// With `impacts_bounce`, which bodies the last passes moved.
    bounce: Option<&'a BounceMarks<'a>>,
}

impl Passes<'_> {
    /// Runs `stage`'s pass over the joints `range` (of the solver's stage-ordered copies).
    #[allow(unsafe_code)]
    fn run_joints(
        &self,
        stage: &Stage,
        range: Range<usize>,
        states: &BodyStates<'_>,
        p: &SubstepParams,
    ) {
        let ctx = JointContext {
            h: p.h,
            inv_h: 1.0 / p.h,
            warm_starting: true,
        };
        // The chains open the overflow stage, whose one block holds them all.
        let mut range = range;
        if stage.color == 0
            && let Some(last) = self.chains.last()
            && range.start == 0
            && range.end >= last.end
        {
            // SAFETY: the overflow stage runs on one worker, alone.
            let rows = unsafe { self.chain_rows.range_mut(0..self.chain_rows.len()) };
            for chain in self.chains {
                // SAFETY: as above.
                let joints = unsafe { self.joints.range_mut(chain.clone()) };
                match stage.pass {
                    Pass::WarmStart => joints.iter_mut().for_each(|j| j.warm_start(states)),
                    Pass::Solve => crate::joint::chain::solve(joints, states, true, rows),
                    Pass::Relax => crate::joint::chain::solve(joints, states, false, rows),
                    _ => {}
                }
            }
            range.start = last.end;
        }
        // SAFETY: the blocks of a stage are disjoint ranges of the joints, whose bodies no
        // other block of the stage writes (the colouring).
        let joints = unsafe { self.joints.range_mut(range) };
        let pass = match stage.pass {
            Pass::WarmStart => wide_hinge::HingePass::WarmStart,
            Pass::Solve => wide_hinge::HingePass::Solve,
            Pass::Relax => wide_hinge::HingePass::Relax,
            _ => return,
        };
        let one = |joint: &mut Joint| match pass {
            wide_hinge::HingePass::WarmStart => joint.warm_start(states),
            wide_hinge::HingePass::Solve => joint.solve(states, &ctx, true),
            wide_hinge::HingePass::Relax => joint.solve(states, &ctx, false),
        };
        // A colour's hinges eight at a time where eight come in a row (the same bits as
        // one at a time); the overflow's joints may share bodies, so they stay one by one.
        if !self.use_wide || stage.color == 0 {
            joints.iter_mut().for_each(one);
            return;
        }
        let mut k = 0;
        while k < joints.len() {
            let group = k..k + LANES;
            let rows = joints.get(group.clone()).and_then(|g| {
                let g: &[Joint; LANES] = g.try_into().ok()?;
                let rows = g.each_ref().map(Joint::hinge_rows);
                rows.iter()
                    .all(Option::is_some)
                    .then(|| rows.map(|r| r.unwrap_or(0)))
            });
            if let Some(rows) = rows {
                let group = &mut joints[group];
                wide_hinge::hinges(group, rows, states, pass, &ctx, self.use_avx);
                k += LANES;
            } else {
                one(&mut joints[k]);
                k += 1;
            }
        }
    }

    /// Runs `stage` over `items`, a block of its items (all of them on one thread). Returns
    /// how often a speed cap bit (position integration); for a [`Pass::Bounce`], how many
    /// points (a wide constraint: point rows with a lane) it moved
    /// (`contact_solver::bounce_moved`) in the low 32 bits and the bouncing contacts it
    /// visited in the high 32 (such a pass is a plan of its own); 0 for the other passes,
    /// and the fixed restitution passes, which end the substeps' plan, whose sum counts the
    /// caps.
    #[allow(unsafe_code)]
    fn run(
        &self,
        stage: &Stage,
        items: Range<usize>,
        states: &BodyStates<'_>,
        bodies: &Bodies<'_>,
        p: &SubstepParams,
    ) -> u64 {
        let motion = bodies.motion;
        let inv_h = 1.0 / p.h;
        let avx = self.use_avx;
        let push = p.max_push_speed;
        let mut count = 0;
        // The overflow, and every colour when SIMD is off, are scalar constraints.
        let scalar = stage.color == 0 || !self.use_wide;
        match stage.pass {
            Pass::IntegrateVelocities => {
                for &i in &bodies.moving[items] {
                    let i = i as usize;
                    let m = &motion[i];
                    if m.dynamic {
                        let mut s = states.get(i);
                        let (lin, ang) = (m.linear_damping, m.angular_damping);
                        // A scale of 1 leaves gravity's bits as they are.
                        let g = if m.gravity_scale == 1.0 {
                            p.gravity
                        } else {
                            p.gravity * m.gravity_scale
                        };
                        match bodies.forced {
                            // Box2D `b2IntegrateVelocitiesTask`: the force's acceleration
                            // joins gravity's, undamped; the torque's adds to the spin.
                            Some(forced) if forced[i] != ForceAcceleration::default() => {
                                let a = forced[i];
                                integrate_velocity(&mut s, g + a.linear, p.h, lin, ang);
                                s.w += p.h * a.angular;
                            }
                            _ => integrate_velocity(&mut s, g, p.h, lin, ang),
                        }
                        states.set(i, s);
                    }
                }
            }
            Pass::IntegratePositions => {
                // Eight bodies at a time: the rotation's square root and division, one body
                // at a time, were most of this pass.
                count += wide::integrate_positions(
                    &bodies.moving[items],
                    motion,
                    states,
                    p.h,
                    p.max_linear_speed,
                    avx,
                );
            }
            Pass::Bounce => {
                let threshold = p.restitution_threshold;
                let bodies = &self.bounce_bodies[items.clone()];
                let bouncing = &self.bounce_lanes[items.clone()];
                let listed = self.bouncing[items].iter().zip(bodies).zip(bouncing);
                for ((&i, bodies), &bouncing) in listed {
                    // The bouncing lanes this pass solves (a scalar constraint's bodies fill
                    // all eight lanes, so its mask is all or none, and its bit 0 stands for
                    // it): counted in contacts, as the budget is, alike packed or not.
                    let lanes = self.bounce.map_or(u8::MAX, |m| m.visit_lanes(bodies)) & bouncing;
                    if lanes == 0 {
                        continue;
                    }
                    let marks = self.bounce.map(|m| (m, lanes));
                    let i = i as usize;
                    // SAFETY: the listed constraints of one stage are distinct and of one
                    // colour (or the overflow's, on one worker); blocks split the list.
                    let moved = if scalar {
                        let c = unsafe { self.scalar.range_mut(i..i + 1) };
                        contact_solver::apply_restitution(c, states, threshold, marks)
                    } else {
                        let c = unsafe { self.wide.range_mut(i..i + 1) };
                        wide::apply_restitution(c, states, threshold, marks, avx)
                    };
                    // The contacts visited in the high half of the count, the moved points
                    // in the low (`Solver::run_substeps` splits them).
                    count += moved + (u64::from(lanes.count_ones()) << 32);
                }
            }
            pass if scalar => {
                // SAFETY: the blocks of one stage are disjoint (see `run_substeps`).
                let c = unsafe { self.scalar.range_mut(items) };
                match pass {
                    Pass::WarmStart => contact_solver::warm_start(c, states),
                    Pass::Solve => contact_solver::solve(c, states, inv_h, true, push),
                    Pass::Relax => contact_solver::solve(c, states, inv_h, false, push),
                    _ => {
                        let moved = contact_solver::apply_restitution(
                            c,
                            states,
                            p.restitution_threshold,
                            None,
                        );
                        count += restitution_count(p, moved);
                    }
                }
            }
            pass => {
                // SAFETY: as above.
                let c = unsafe { self.wide.range_mut(items.clone()) };
                // SAFETY: as above; the surfaces, where there are any, match the constraints
                // one for one.
                let s = if self.surfaces.len() == 0 {
                    &mut [][..]
                } else {
                    unsafe { self.surfaces.range_mut(items) }
                };
                match pass {
                    Pass::WarmStart => wide::warm_start(c, s, states, avx),
                    Pass::Solve => wide::solve(c, s, states, inv_h, true, push, avx),
                    Pass::Relax => wide::solve(c, s, states, inv_h, false, push, avx),
                    _ => {
                        let moved =
                            wide::apply_restitution(c, states, p.restitution_threshold, None, avx);
                        count += restitution_count(p, moved);
                    }
                }
            }
        }
        count
    }
}

/// What a restitution stage adds to its plan's count: the points it moved where
/// `impacts_bounce` reads them (its passes run apart), else nothing, as the fixed passes end
/// the substeps' plan, whose count is the speed caps.
#[inline]
fn restitution_count(p: &SubstepParams, moved: u64) -> u64 {
    if p.impacts_bounce { moved } else { 0 }
}

/// Integrates one dynamic body's velocity over a substep: damping as the Padé approximation
/// `1/(1 + h·c)` of `exp(-c·h)`, so it is defined per second whatever the step (Box2D
/// `b2IntegrateVelocitiesTask`); gravity added undamped.
#[inline]
pub fn integrate_velocity(
    s: &mut BodyState,
    gravity: Vec2,
    h: f32,
    linear_damping: f32,
    angular_damping: f32,
) {
    let mut v = s.v;
    let mut w = s.w;
    if linear_damping > 0.0 {
        v *= 1.0 / (1.0 + h * linear_damping);
    }
    if angular_damping > 0.0 {
        w *= 1.0 / (1.0 + h * angular_damping);
    }
    s.v = v + gravity * h;
    s.w = w;
}

/// [`integrate_position`] for one body of the substeps' position pass: its speed capped at
/// `max_linear_speed` where it is dynamic (never where it is not), its spin where it
/// rotates. Returns whether a cap bit a dynamic body (what the pass counts).
#[inline]
pub fn integrate_body_position(
    s: &mut BodyState,
    m: &BodyMotion,
    h: f32,
    max_linear_speed: f32,
) -> bool {
    let cap = if m.dynamic {
        max_linear_speed
    } else {
        f32::INFINITY
    };
    integrate_position(s, h, cap, m.rotates) && m.dynamic
}

/// Advances a body's substep deltas; speeds beyond the caps are clamped first (Box2D's
/// `maxLinearSpeed`, and at most a quarter turn per substep so the first-order rotation
/// stays accurate). Returns whether a cap bit.
#[inline]
pub fn integrate_position(s: &mut BodyState, h: f32, max_linear_speed: f32, rotates: bool) -> bool {
    let mut capped = false;
    let speed2 = dot(s.v, s.v);
    if speed2 > max_linear_speed * max_linear_speed {
        s.v *= max_linear_speed / speed2.sqrt();
        capped = true;
    }
    s.dp += s.v * h;
    if rotates {
        let max_w = 0.25 * std::f32::consts::PI / h;
        if s.w.abs() > max_w {
            s.w = s.w.clamp(-max_w, max_w);
            capped = true;
        }
        s.dq = s.dq.integrate(h * s.w);
    }
    capped
}

/// Buckets of the colouring order: 8 bits of a hash of the pair.
const ORDER_BUCKETS: usize = 256;

/// The order in which the greedy colouring visits the touching contacts: by a hash of each
/// contact's pair of bodies (256 buckets, contact order within a bucket).
///
/// Why not contact order: within a colour the order of solving does not matter, but between
/// colours it does (Gauss-Seidel: a constraint solved later in a pass wins), and greedy
/// first-fit in contact order gives the contacts created first the low colours. Contacts are
/// created in a spatially regular order, so in a pyramid the box below and to the right
/// of a box was solved before the one to the left in 4876 of large_pyramid's 4950 boxes,
/// and the pyramid leaned: its top box drifted 0.77 m, ten times Box2D's 0.07 m (Box2D
/// colours in the order of its broad-phase tree, 2713 to 2237 there). A hashed order makes
/// that choice a coin toss per box, so the leans cancel instead of adding up (randomised
/// Gauss-Seidel: Leventhal and Lewis, "Randomized methods for linear constraints",
/// Math. Oper. Res. 35(3), 2010). The hash depends only on the pair, so the colouring is
/// still a function of the sequence of pairs, as keeping last step's colouring requires.
///
/// Each entry carries its pair, so the colouring reads the order alone, in sequence, not
/// `touching` scattered; each contact's bucket is hashed once, into `bucket_of`.
fn coloring_order(touching: &[Touching], bucket_of: &mut Vec<u8>, order: &mut Vec<Touching>) {
    const _: () = assert!(ORDER_BUCKETS == 1 << 8);
    bucket_of.clear();
    bucket_of.extend(touching.iter().map(|t| (pair_hash(t.dynamic) >> 24) as u8));
    let mut next = [0u32; ORDER_BUCKETS];
    for &b in bucket_of.iter() {
        next[b as usize] += 1;
    }
    let mut start = 0;
    for n in next.iter_mut() {
        let count = *n;
        *n = start;
        start += count;
    }
    order.clear();
    order.resize(touching.len(), Touching::default());
    for (k, (t, &b)) in touching.iter().zip(bucket_of.iter()).enumerate() {
        let slot = &mut next[b as usize];
        // `contact` here is the entry's index in `touching`.
        order[*slot as usize] = Touching {
            contact: k as u32,
            dynamic: t.dynamic,
        };
        *slot += 1;
    }
}

/// A 32-bit hash of a pair of body indices (the finaliser of SplitMix64: Steele, Lea and
/// Flood, "Fast splittable pseudorandom number generators", OOPSLA 2014).
#[inline]
fn pair_hash(pair: [u32; 2]) -> u32 {
    let mut x = (u64::from(pair[0]) << 32) | u64::from(pair[1]);
    x = (x ^ (x >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    (x ^ (x >> 31)) as u32
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The touching contacts of a resting pyramid of `rows` rows on a static ground, in the
    /// order the world creates them (each box, in index order, with the bodies of lower index
    /// it touches, ascending: ground, lower left, lower right, left neighbour), and for each
    /// box above the base the positions of its lower-left and lower-right support contacts.
    fn pyramid_contacts(rows: usize) -> (Vec<Touching>, Vec<(usize, usize)>, usize) {
        // Body 0 is the ground; boxes are numbered row by row from the base, left to right.
        let mut id = vec![Vec::new(); rows];
        let mut next = 1u32;
        for (r, row) in id.iter_mut().enumerate() {
            for _ in 0..rows - r {
                row.push(next);
                next += 1;
            }
        }
        let mut touching = Vec::new();
        let mut at = std::collections::HashMap::new();
        let mut push = |a: u32, b: u32, touching: &mut Vec<Touching>| {
            at.insert((a, b), touching.len());
            let dynamic = [if a == 0 { NOT_DYNAMIC } else { a }, b];
            touching.push(Touching {
                contact: touching.len() as u32,
                dynamic,
            });
        };
        for r in 0..rows {
            for j in 0..rows - r {
                let me = id[r][j];
                if r == 0 {
                    push(0, me, &mut touching);
                } else {
                    push(id[r - 1][j], me, &mut touching);
                    push(id[r - 1][j + 1], me, &mut touching);
                }
                if j > 0 {
                    push(id[r][j - 1], me, &mut touching);
                }
            }
        }
        let mut supports = Vec::new();
        for r in 1..rows {
            for j in 0..rows - r {
                let me = id[r][j];
                supports.push((at[&(id[r - 1][j], me)], at[&(id[r - 1][j + 1], me)]));
            }
        }
        (touching, supports, next as usize)
    }

    #[test]
    fn the_colouring_favours_neither_side_of_a_pyramid() {
        // Colours are solved in ascending order and the later constraint of a Gauss-Seidel
        // pass wins, so a box whose two supports are always solved in the same order leans.
        // Coloured in contact order, the lower-right support of 4876 of large_pyramid's 4950
        // boxes came first and its top drifted 0.77 m (Box2D's 0.07 m, at 2713 to 2237; see
        // `coloring_order`). A 60-row pyramid has 1770 supported boxes: a fair coin per box
        // puts the left-first share within 0.5 +- 0.012 (one standard deviation), so 0.45 to
        // 0.55 is four deviations wide; contact order gives 0.025.
        let (touching, supports, bodies) = pyramid_contacts(60);
        let mut solver = Solver::new();
        solver.use_wide = true;
        solver.color(&[], &touching, bodies, Spread::INLINE, 1);
        assert_eq!(solver.overflow_count(), 0);
        let left_first = supports
            .iter()
            .filter(|&&(left, right)| solver.color_of[left] < solver.color_of[right])
            .count();
        let share = left_first as f64 / supports.len() as f64;
        assert!(
            (0.45..=0.55).contains(&share),
            "the lower-left support is solved first for {left_first} of {} boxes ({share:.3})",
            supports.len()
        );
        // The colouring is still valid: no colour holds two constraints of one dynamic body.
        let mut seen = std::collections::HashSet::new();
        for (k, t) in touching.iter().enumerate() {
            for d in t.dynamic {
                if d != NOT_DYNAMIC && solver.color_of[k] as usize != OVERFLOW {
                    assert!(
                        seen.insert((solver.color_of[k], d)),
                        "colour repeats body {d}"
                    );
                }
            }
        }
    }
}
