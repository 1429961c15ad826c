//! The contact solver eight constraints at a time (Box2D v3's `b2ContactConstraintSIMD`):
//! each colour's constraints are packed into lanes of `f32x8`, bodies are gathered into
//! lanes, solved with the same per-lane arithmetic as the scalar path in
//! `contact_solver.rs`, and scattered back to dynamic bodies only.
//!
//! A colour never holds two constraints on one dynamic body, so lanes never conflict. The
//! overflow, whose constraints may share bodies, stays on the scalar path.
//!
//! Hinges go eight at a time too, in `wide_hinge.rs`, on the gather and scatter here.

use std::marker::PhantomData;

use wide::{f32x4, f32x8};

use super::ContactInput;
use super::PointResult;
use super::contact_solver::BounceMarks;
#[cfg(target_arch = "x86_64")]
use super::lanes::Avx;
use super::lanes::Lanes;
use crate::body::BodyState;
use crate::softness::Softness;
use crate::threads::parallel::BodyStates;

/// Lanes per wide constraint.
pub const LANES: usize = 8;

/// What prepare reads for one lane: the contact, its bodies and its spring.
pub struct LaneInput<'c> {
    /// Index of the contact (to store impulses back).
    pub contact: u32,
    /// The contact's data (with both bodies' masses).
    pub input: ContactInput<'c>,
    /// The contact's spring (stiffer against static bodies).
    pub softness: Softness,
}

/// Wide constraints whose lanes workers fill concurrently, one lane per contact, walking
/// the contacts in their own order (so the contacts stream from memory, where a walk in
/// constraint order would read them scattered: the colours interleave in the contact array).
pub struct LaneWriter<'a> {
    ptr: *mut WideConstraint,
    len: usize,
    /// The constraints' surface materials, one per constraint, or none (a world without).
    surfaces: *mut WideSurface,
    surfaces_len: usize,
    _borrow: PhantomData<&'a mut [WideConstraint]>,
}

// SAFETY: access follows the contract of `LaneWriter::shared`.
#[allow(unsafe_code)]
unsafe impl Send for LaneWriter<'_> {}
// SAFETY: as above.
#[allow(unsafe_code)]
unsafe impl Sync for LaneWriter<'_> {}

/// `lane` packed with its constraint: `wide << 3 | lane`.
pub type LaneIndex = u32;

/// Each set of lanes as a vector mask: entry `bits` is all ones in lane `l` where bit `l` of
/// `bits` is set (8 KB, read by the constraints that solve two points together).
static LANE_MASKS: [[u32; LANES]; 256] = {
    let mut table = [[0u32; LANES]; 256];
    let mut bits = 0;
    while bits < 256 {
        let mut l = 0;
        while l < LANES {
            if bits >> l & 1 != 0 {
                table[bits][l] = u32::MAX;
            }
            l += 1;
        }
        bits += 1;
    }
    table
};

/// The lanes set in `bits`, as a mask ([`LANE_MASKS`]).
#[inline(always)]
fn lane_mask<V: Lanes>(bits: u8) -> V {
    V::load(wide::bytemuck::cast(LANE_MASKS[bits as usize]))
}

#[allow(unsafe_code)]
impl<'a> LaneWriter<'a> {
    /// Shared access for concurrent lane writes.
    ///
    /// # Safety
    /// While it lives, each lane of each constraint is written by at most one call of
    /// [`write`](Self::write), and nothing else reads or writes the constraints.
    /// `surfaces` is empty, or holds one entry per constraint (then every contact with a
    /// surface material writes its lane there).
    pub unsafe fn shared(wide: &'a mut [WideConstraint], surfaces: &'a mut [WideSurface]) -> Self {
        Self {
            ptr: wide.as_mut_ptr(),
            len: wide.len(),
            surfaces: surfaces.as_mut_ptr(),
            surfaces_len: surfaces.len(),
            _borrow: PhantomData,
        }
    }

    /// Starts loading an eighth of wide constraint `wide` (its `part`th, `part < LANES`) into
    /// the cache (a hint: nothing happens past the end). Its lines are cold: the last step's
    /// solve walked the whole buffer since they were written. An eighth at a time, so that
    /// the prefetches do not crowd out the loads of the contacts being read.
    #[inline]
    pub fn prefetch(&self, wide: usize, part: usize) {
        #[cfg(target_arch = "x86_64")]
        if wide < self.len {
            use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
            const LINES: usize = std::mem::size_of::<WideConstraint>().div_ceil(64);
            const PER_PART: usize = LINES.div_ceil(LANES);
            let start = self.ptr.wrapping_add(wide).cast::<i8>().cast_const();
            for line in part * PER_PART..((part + 1) * PER_PART).min(LINES) {
                // SAFETY: prefetching any address is sound: a hint that cannot fault.
                #[allow(unsafe_code)]
                unsafe {
                    _mm_prefetch::<_MM_HINT_T0>(start.wrapping_add(64 * line))
                };
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = (wide, part);
    }

    /// Completes constraint `wide`, whose first `lanes` lanes are written:
    /// [`WideConstraint::build`] on it (`points_together`: the world's setting).
    ///
    /// # Safety
    /// Every one of its lanes was written by a [`write`](Self::write) that happened before
    /// this call (on this thread, or joined since), and no other call reaches this
    /// constraint until the writer is dropped.
    #[inline]
    pub unsafe fn complete(
        &self,
        wide: usize,
        lanes: usize,
        states: &[BodyState],
        points_together: bool,
        use_avx: bool,
    ) {
        assert!(wide < self.len);
        // SAFETY: in bounds (asserted); exclusive by the caller's contract.
        let w = unsafe { &mut *self.ptr.add(wide) };
        w.build(lanes, states, points_together, use_avx);
    }

    /// Writes the copied fields of one lane from its contact (masses, normal, materials,
    /// spring, anchors, warm-start impulses; zeros for a point the manifold lacks), and each
    /// point's separation where [`WideConstraint::build`] reads it.
    #[inline]
    pub fn write(&self, at: LaneIndex, x: &LaneInput<'_>, params: &super::SolverParams) {
        let warm_starting = params.warm_starting;
        let (wide, l) = ((at >> 3) as usize, (at & 7) as usize);
        assert!(wide < self.len);
        let c = &x.input;
        let m = c.manifold;
        let [body_a, body_b] = &c.masses;
        let masses = [
            body_a.inv_mass,
            body_a.inv_inertia,
            body_b.inv_mass,
            body_b.inv_inertia,
        ];
        let flags = u8::from(body_a.dynamic)
            | (u8::from(body_b.dynamic) << 1)
            | (u8::from(c.friction > 0.0) << 2)
            | (u8::from(c.restitution > 0.0) << 3)
            | (u8::from(c.tangent_speed != 0.0) << 4)
            | (u8::from(c.rolling_resistance > 0.0) << 5)
            | (u8::from(super::contact_solver::threshold_applies(
                params.impacts_bounce,
                m,
            )) << 7);
        // SAFETY: `wide` is in bounds (asserted) and `l < LANES`; each write goes through a
        // raw pointer to this lane's own element of a lane array, which no other call
        // touches (contract of `shared`), and no reference to the shared constraint is made.
        unsafe {
            let w = self.ptr.add(wide);
            macro_rules! put {
                ($field:expr, $ty:ty, $value:expr) => {
                    std::ptr::addr_of_mut!($field)
                        .cast::<$ty>()
                        .add(l)
                        .write($value)
                };
            }
            put!((*w).contact, u32, x.contact);
            put!((*w).count, u8, m.count as u8);
            put!((*w).flags, u8, flags);
            put!((*w).body_a, u32, c.body_a);
            put!((*w).body_b, u32, c.body_b);
            put!((*w).inv_mass_a, f32, masses[0]);
            put!((*w).inv_i_a, f32, masses[1]);
            put!((*w).inv_mass_b, f32, masses[2]);
            put!((*w).inv_i_b, f32, masses[3]);
            put!((*w).normal_x, f32, m.normal.x);
            put!((*w).normal_y, f32, m.normal.y);
            put!((*w).friction, f32, c.friction);
            put!((*w).restitution, f32, c.restitution);
            // Surface materials only where the lane has one, into the side array:
            // `finish_surface` zeroes the other lanes of a constraint that needs them, and one
            // that does not never reads them.
            if c.tangent_speed != 0.0 || c.rolling_resistance > 0.0 {
                assert!(
                    wide < self.surfaces_len,
                    "a surface material without its array"
                );
                let s = self.surfaces.add(wide);
                put!((*s).tangent_speed, f32, c.tangent_speed);
                put!((*s).rolling_resistance, f32, c.rolling_resistance);
                put!(
                    (*s).rolling_mass,
                    f32,
                    super::rolling_mass(body_a.inv_inertia, body_b.inv_inertia)
                );
                let rolls = warm_starting && c.rolling_resistance > 0.0;
                put!(
                    (*s).rolling_impulse,
                    f32,
                    if rolls { c.rolling_impulse } else { 0.0 }
                );
            }
            put!((*w).bias_rate, f32, x.softness.bias_rate);
            put!((*w).mass_scale, f32, x.softness.mass_scale);
            put!((*w).impulse_scale, f32, x.softness.impulse_scale);
            for k in 0..2 {
                // ax, ay, bx, by, separation, normal and tangent impulse; zeros for a point
                // the manifold lacks. `WideConstraint::build` computes the rest.
                let v = match m.points().get(k) {
                    Some(mp) => {
                        let (normal, tangent) = if warm_starting {
                            (mp.normal_impulse, mp.tangent_impulse)
                        } else {
                            (0.0, 0.0)
                        };
                        [
                            mp.anchor_a.x,
                            mp.anchor_a.y,
                            mp.anchor_b.x,
                            mp.anchor_b.y,
                            mp.separation,
                            normal,
                            tangent,
                        ]
                    }
                    None => [0.0; 7],
                };
                let p = std::ptr::addr_of_mut!((*w).points[k]);
                put!((*p).r.ax, f32, v[0]);
                put!((*p).r.ay, f32, v[1]);
                put!((*p).r.bx, f32, v[2]);
                put!((*p).r.by, f32, v[3]);
                put!((*p).base_separation, f32, v[4]);
                put!((*p).normal_impulse, f32, v[5]);
                put!((*p).tangent_impulse, f32, v[6]);
            }
        }
    }
}

impl WideConstraint {
    /// Completes a constraint whose first `lanes` lanes were written by
    /// [`LaneWriter::write`]: clears the unused tail lanes (their bodies are lane
    /// 0's, with zero masses: they read, never write, and apply no impulse), folds the lanes'
    /// flags into the masks, and computes every lane's point terms at once, with the
    /// operations of `contact_solver::point_terms` in its order (the scalar constraints'
    /// own function, so both agree bit for bit), and with `points_together` which lanes
    /// solve their two points together (`contact_solver::points_together`'s test, likewise).
    /// Called while the constraint's lines are still in the cache from its lane writes
    /// (`LaneWriter::complete`).
    pub fn build(
        &mut self,
        lanes: usize,
        states: &[BodyState],
        points_together: bool,
        use_avx: bool,
    ) {
        debug_assert!((1..=LANES).contains(&lanes));
        self.lanes = lanes as u8;
        let (mut dynamic_a, mut dynamic_b, mut at_rest) = (0u8, 0u8, 0u8);
        let mut any = 0u8;
        // Lanes holding each point: lane l has point k when `count[l] > k`.
        let mut has_point = [0u8; 2];
        for l in 0..lanes {
            let f = self.flags[l];
            dynamic_a |= (f & 1) << l;
            dynamic_b |= ((f >> 1) & 1) << l;
            at_rest |= (f >> 7) << l;
            any |= f;
            for (k, bits) in has_point.iter_mut().enumerate() {
                *bits |= u8::from(self.count[l] as usize > k) << l;
            }
        }
        self.at_rest = at_rest;
        self.dynamic_a = dynamic_a;
        self.dynamic_b = dynamic_b;
        self.any_friction = any & 4 != 0;
        self.any_restitution = any & 8 != 0;
        self.any_tangent_speed = any & 16 != 0;
        self.any_rolling = any & 32 != 0;
        for l in lanes..LANES {
            self.contact[l] = 0;
            self.count[l] = 0;
            self.flags[l] = 0;
            self.body_a[l] = self.body_a[0];
            self.body_b[l] = self.body_b[0];
            for x in [
                &mut self.inv_mass_a,
                &mut self.inv_i_a,
                &mut self.inv_mass_b,
                &mut self.inv_i_b,
                &mut self.normal_x,
                &mut self.normal_y,
                &mut self.friction,
                &mut self.restitution,
                &mut self.bias_rate,
                &mut self.mass_scale,
                &mut self.impulse_scale,
            ] {
                x.as_mut_array()[l] = 0.0;
            }
            for p in &mut self.points {
                for x in [
                    &mut p.r.ax,
                    &mut p.r.ay,
                    &mut p.r.bx,
                    &mut p.r.by,
                    &mut p.base_separation,
                    &mut p.normal_impulse,
                    &mut p.tangent_impulse,
                ] {
                    x.as_mut_array()[l] = 0.0;
                }
            }
        }
        // Only lanes with two points can solve them together.
        let pairs = if points_together { has_point[1] } else { 0 };
        self.together = wide_point_terms(self, states, has_point, pairs, use_avx);
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn point_terms_avx2(
    c: &mut WideConstraint,
    states: &[BodyState],
    has_point: [u8; 2],
    pairs: u8,
) -> u8 {
    point_terms_with::<Avx>(c, states, has_point, pairs)
}

/// `contact_solver::point_terms` in eight lanes, operation for operation; the separation is
/// read from `base_separation`, where `write_lane` left it. Lanes without the point get
/// zeros, as the scalar build gives them. Returns which of the lanes `pairs` (two points
/// each) solve them together: `contact_solver::points_together`'s test, operation for
/// operation, from the normal masses' terms computed here anyway (taken lane by lane in
/// `write_lane` it measured the same, once both builds' functions were aligned:
/// docs/history.md, "Every function on a cache line").
#[inline(always)]
fn point_terms_with<V: Lanes>(
    c: &mut WideConstraint,
    states: &[BodyState],
    has_point: [u8; 2],
    pairs: u8,
) -> u8 {
    let a = transpose_bodies::<V>(|i| states[i], &c.body_a);
    let b = transpose_bodies::<V>(|i| states[i], &c.body_b);
    let Masses { ma, ia, mb, ib } = c.masses::<V>();
    let (nx, ny) = (V::load(c.normal_x), V::load(c.normal_y));
    let zero = V::splat(0.0);
    let one = V::splat(1.0);
    // Each point's lever terms and normal mass term, for the coupling test below.
    let mut levers = [(zero, zero); 2];
    let mut k_normals = [zero; 2];
    for ((p, &bits), (lever, k_n)) in c
        .points
        .iter_mut()
        .zip(&has_point)
        .zip(levers.iter_mut().zip(&mut k_normals))
    {
        let present: V = lane_mask(bits);
        let r = p.r.load::<V>();
        // t = right_perp(n) = (ny, −nx).
        let (tx, ty) = (ny, -nx);
        let rna = r.ax * ny - r.ay * nx;
        let rnb = r.bx * ny - r.by * nx;
        let k_normal = ma + mb + ia * rna * rna + ib * rnb * rnb;
        (*lever, *k_n) = ((rna, rnb), k_normal);
        let rta = r.ax * ty - r.ay * tx;
        let rtb = r.bx * ty - r.by * tx;
        let k_tangent = ma + mb + ia * rta * rta + ib * rtb * rtb;
        let separation = V::load(p.base_separation);
        let base_separation = separation - ((r.bx - r.ax) * nx + (r.by - r.ay) * ny);
        let normal_mass = k_normal.gt(zero).select(one / k_normal, zero);
        let tangent_mass = k_tangent.gt(zero).select(one / k_tangent, zero);
        // (vb + w_b × rb) − (va + w_a × ra), with w × r = (−w·ry, w·rx).
        let dvx = (b.vx + -b.w * r.by) - (a.vx + -a.w * r.ay);
        let dvy = (b.vy + b.w * r.bx) - (a.vy + a.w * r.ax);
        let relative_velocity = nx * dvx + ny * dvy;
        p.base_separation = present.select(base_separation, zero).store();
        p.normal_mass = present.select(normal_mass, zero).store();
        p.tangent_mass = present.select(tangent_mass, zero).store();
        p.relative_velocity = present.select(relative_velocity, zero).store();
        p.total_normal_impulse = zero.store();
    }
    if pairs == 0 {
        return 0;
    }
    // k12² · 4 ≤ k11 · k22, as `points_together` computes it.
    let [(c1a, c1b), (c2a, c2b)] = levers;
    let k12 = ma + mb + ia * c1a * c2a + ib * c1b * c2b;
    let coupling = (V::splat(4.0) * k12 * k12).store();
    let product = (k_normals[0] * k_normals[1]).store();
    let mut together = 0u8;
    for l in 0..LANES {
        together |= u8::from(coupling.as_array()[l] <= product.as_array()[l]) << l;
    }
    together & pairs
}
/// One contact point in eight lanes.
#[derive(Clone, Copy, Debug)]
pub struct WidePoint {
    r: Anchors,
    base_separation: f32x8,
    normal_impulse: f32x8,
    tangent_impulse: f32x8,
    total_normal_impulse: f32x8,
    normal_mass: f32x8,
    tangent_mass: f32x8,
    relative_velocity: f32x8,
}

/// Contact anchors relative to each body's centre of mass, one point per lane.
#[derive(Clone, Copy, Debug)]
struct Anchors {
    ax: f32x8,
    ay: f32x8,
    bx: f32x8,
    by: f32x8,
}

/// Eight contact constraints, one per lane. Unused tail lanes have zero masses, so they
/// apply no impulse.
#[derive(Clone, Copy, Debug)]
pub struct WideConstraint {
    /// The contact each lane came from.
    contact: [u32; LANES],
    /// Manifold points per lane.
    count: [u8; LANES],
    /// Per lane: bit 0 body A dynamic, 1 body B dynamic, 2 friction, 3 restitution, 4
    /// tangent speed, 5 rolling resistance, 7 restitution threshold applies (bit 6 is free:
    /// whether the points are solved together is `build`'s to decide) (what
    /// `build` folds into the masks below; lanes are written one by one, possibly by
    /// different workers, so nothing per-constraint is written while lanes are).
    flags: [u8; LANES],
    body_a: [u32; LANES],
    body_b: [u32; LANES],
    /// Lanes whose body is dynamic (the only ones written back).
    dynamic_a: u8,
    dynamic_b: u8,
    /// Lanes in use.
    lanes: u8,
    any_friction: bool,
    any_restitution: bool,
    /// A lane's surfaces move along the tangent (a conveyor): friction reads `tangent_speed`.
    any_tangent_speed: bool,
    /// A lane resists rolling (its [`WideSurface`] is valid in every lane).
    any_rolling: bool,
    /// The lanes whose two points are solved together (`contact_solver::points_together`),
    /// one bit each: an index into [`LANE_MASKS`]. In the constraint's padding, where a
    /// vector mask would cost every constraint 32 bytes more (and every world, 2 to 4% of
    /// the step, docs/accuracy/flat_landing.md).
    together: u8,
    /// The lanes the restitution threshold applies to
    /// (`contact_solver::threshold_applies`), one bit each, in the padding as `together`.
    at_rest: u8,
    inv_mass_a: f32x8,
    inv_i_a: f32x8,
    inv_mass_b: f32x8,
    inv_i_b: f32x8,
    normal_x: f32x8,
    normal_y: f32x8,
    friction: f32x8,
    restitution: f32x8,
    bias_rate: f32x8,
    mass_scale: f32x8,
    impulse_scale: f32x8,
    points: [WidePoint; 2],
}

/// The surface materials of a wide constraint's lanes (conveyor speed, rolling resistance),
/// kept beside the constraints rather than in them, and only in a world that has any: the
/// solve streams every constraint each pass, and 128 bytes more in each of them cost the
/// worlds without these materials too.
#[derive(Clone, Copy, Debug)]
pub struct WideSurface {
    /// The surfaces' speed along the tangent (m/s).
    tangent_speed: f32x8,
    /// The most rolling torque per newton of normal force (m).
    rolling_resistance: f32x8,
    /// Effective mass of the relative spin.
    rolling_mass: f32x8,
    /// Accumulated rolling impulse.
    rolling_impulse: f32x8,
}

impl WideSurface {
    /// No material in any lane.
    pub const ZERO: WideSurface = WideSurface {
        tangent_speed: f32x8::ZERO,
        rolling_resistance: f32x8::ZERO,
        rolling_mass: f32x8::ZERO,
        rolling_impulse: f32x8::ZERO,
    };
}

impl WidePoint {
    const ZERO: WidePoint = WidePoint {
        r: Anchors {
            ax: f32x8::ZERO,
            ay: f32x8::ZERO,
            bx: f32x8::ZERO,
            by: f32x8::ZERO,
        },
        base_separation: f32x8::ZERO,
        normal_impulse: f32x8::ZERO,
        tangent_impulse: f32x8::ZERO,
        total_normal_impulse: f32x8::ZERO,
        normal_mass: f32x8::ZERO,
        tangent_mass: f32x8::ZERO,
        relative_velocity: f32x8::ZERO,
    };
}

impl WideConstraint {
    /// No lanes in use.
    pub const EMPTY: WideConstraint = WideConstraint {
        contact: [0; LANES],
        count: [0; LANES],
        flags: [0; LANES],
        body_a: [0; LANES],
        body_b: [0; LANES],
        dynamic_a: 0,
        dynamic_b: 0,
        lanes: 0,
        any_friction: false,
        any_restitution: false,
        any_tangent_speed: false,
        any_rolling: false,
        together: 0,
        at_rest: 0,
        inv_mass_a: f32x8::ZERO,
        inv_i_a: f32x8::ZERO,
        inv_mass_b: f32x8::ZERO,
        inv_i_b: f32x8::ZERO,
        normal_x: f32x8::ZERO,
        normal_y: f32x8::ZERO,
        friction: f32x8::ZERO,
        restitution: f32x8::ZERO,
        bias_rate: f32x8::ZERO,
        mass_scale: f32x8::ZERO,
        impulse_scale: f32x8::ZERO,
        points: [WidePoint::ZERO; 2],
    };

    /// Completes the constraint's surface materials after [`WideConstraint::build`]: the
    /// lanes that have none were not written, and get zeros (they then apply none).
    pub fn finish_surface(&self, s: &mut WideSurface) {
        if !(self.any_tangent_speed || self.any_rolling) {
            return;
        }
        for l in 0..LANES {
            if l >= self.lanes as usize || self.flags[l] & 48 == 0 {
                for x in [
                    &mut s.tangent_speed,
                    &mut s.rolling_resistance,
                    &mut s.rolling_mass,
                    &mut s.rolling_impulse,
                ] {
                    x.as_mut_array()[l] = 0.0;
                }
            }
        }
    }

    /// The contacts of the used lanes.
    pub fn contacts(&self) -> impl Iterator<Item = u32> + '_ {
        self.contact[..self.lanes as usize].iter().copied()
    }

    /// The contact lane `lane` came from.
    pub fn contact_of(&self, lane: usize) -> u32 {
        self.contact[lane]
    }

    /// Calls `f(point, impulses)` for each point of lane `lane`; `surface` is the
    /// constraint's [`WideSurface`] where the world has one.
    #[inline]
    pub fn lane_results(
        &self,
        lane: usize,
        surface: Option<&WideSurface>,
        mut f: impl FnMut(usize, &PointResult),
    ) {
        for (k, p) in self
            .points
            .iter()
            .enumerate()
            .take(self.count[lane] as usize)
        {
            f(
                k,
                &PointResult {
                    normal_impulse: p.normal_impulse.as_array()[lane],
                    tangent_impulse: p.tangent_impulse.as_array()[lane],
                    total_normal_impulse: p.total_normal_impulse.as_array()[lane],
                    relative_velocity: p.relative_velocity.as_array()[lane],
                    rolling_impulse: surface
                        .filter(|_| self.flags[lane] & 32 != 0)
                        .map(|s| s.rolling_impulse.as_array()[lane]),
                },
            );
        }
    }
}

/// Eight bodies' states, one per lane.
pub(super) struct WideBody<V> {
    pub vx: V,
    pub vy: V,
    pub w: V,
    /// The states' padding word as loaded (its bits, untouched), so that the velocities go
    /// back as whole 16-byte rows ([`scatter`]).
    pub pad: V,
    pub dpx: V,
    pub dpy: V,
    pub dqc: V,
    pub dqs: V,
}

/// Loads eight bodies' states into lanes: each state's two 16-byte halves are loaded whole and
/// transposed four at a time (Box2D's `b2GatherBodies` does the same with SSE), rather than
/// assembled float by float, which stalls on store forwarding.
#[inline(always)]
pub(super) fn gather<V: Lanes>(states: &BodyStates<'_>, index: &[u32; LANES]) -> WideBody<V> {
    transpose_bodies(|i| states.get(i), index)
}

/// [`gather`] from any source of states.
#[inline(always)]
fn transpose_bodies<V: Lanes>(
    state: impl Fn(usize) -> BodyState,
    index: &[u32; LANES],
) -> WideBody<V> {
    let mut motion = [[f32x4::ZERO; 4]; 2];
    let mut delta = [[f32x4::ZERO; 4]; 2];
    for l in 0..LANES {
        let s = state(index[l] as usize);
        motion[l / 4][l % 4] = f32x4::new([s.v.x, s.v.y, s.w, f32::from_bits(s.flags)]);
        delta[l / 4][l % 4] = f32x4::new([s.dp.x, s.dp.y, s.dq.c, s.dq.s]);
    }
    let [m0, m1] = motion.map(f32x4::transpose);
    let [d0, d1] = delta.map(f32x4::transpose);
    WideBody {
        vx: V::join(m0[0], m1[0]),
        vy: V::join(m0[1], m1[1]),
        w: V::join(m0[2], m1[2]),
        pad: V::join(m0[3], m1[3]),
        dpx: V::join(d0[0], d1[0]),
        dpy: V::join(d0[1], d1[1]),
        dqc: V::join(d0[2], d1[2]),
        dqs: V::join(d0[3], d1[3]),
    }
}

/// Writes the velocities of the dynamic lanes back (static and kinematic bodies are shared
/// between lanes and constraints of a colour, and are never written).
#[inline(always)]
pub(super) fn scatter<V: Lanes>(
    states: &BodyStates<'_>,
    index: &[u32; LANES],
    dynamic: u8,
    b: &WideBody<V>,
) {
    if dynamic == 0 {
        return;
    }
    // Each body's velocities and padding word as one 16-byte store: the next gather of the
    // body loads those 16 bytes whole, which a store of the velocity (8 bytes) and one of
    // the spin (4) cannot forward to (the load waits for both to reach the cache).
    let (vx, vy, w, pad) = (b.vx.halves(), b.vy.halves(), b.w.halves(), b.pad.halves());
    for g in 0..2 {
        let rows = f32x4::transpose([vx[g], vy[g], w[g], pad[g]]);
        for (k, row) in rows.iter().enumerate() {
            let l = g * 4 + k;
            if dynamic & (1 << l) != 0 {
                states.set_motion_row(index[l] as usize, *row);
            }
        }
    }
}

/// Inverse masses and inertias of both sides.
#[derive(Clone, Copy)]
struct Masses<V> {
    ma: V,
    ia: V,
    mb: V,
    ib: V,
}

impl WideConstraint {
    #[inline(always)]
    fn masses<V: Lanes>(&self) -> Masses<V> {
        Masses {
            ma: V::load(self.inv_mass_a),
            ia: V::load(self.inv_i_a),
            mb: V::load(self.inv_mass_b),
            ib: V::load(self.inv_i_b),
        }
    }
}

/// Anchors loaded into lanes.
#[derive(Clone, Copy)]
struct R<V> {
    ax: V,
    ay: V,
    bx: V,
    by: V,
}

impl Anchors {
    #[inline(always)]
    fn load<V: Lanes>(&self) -> R<V> {
        R {
            ax: V::load(self.ax),
            ay: V::load(self.ay),
            bx: V::load(self.bx),
            by: V::load(self.by),
        }
    }
}

/// Applies an impulse `(px, py)` at anchors `r` to both bodies (negated on A).
#[inline(always)]
fn apply<V: Lanes>(m: Masses<V>, a: &mut WideBody<V>, b: &mut WideBody<V>, r: &R<V>, px: V, py: V) {
    a.vx -= m.ma * px;
    a.vy -= m.ma * py;
    a.w -= m.ia * (r.ax * py - r.ay * px);
    b.vx += m.mb * px;
    b.vy += m.mb * py;
    b.w += m.ib * (r.bx * py - r.by * px);
}

/// Relative velocity of B's anchor with respect to A's: `(vB + wB × rB) − (vA + wA × rA)`.
#[inline(always)]
fn relative_velocity<V: Lanes>(a: &WideBody<V>, b: &WideBody<V>, r: &R<V>) -> (V, V) {
    let dvx = (b.vx - b.w * r.by) - (a.vx - a.w * r.ay);
    let dvy = (b.vy + b.w * r.bx) - (a.vy + a.w * r.ax);
    (dvx, dvy)
}

/// Adds `impulse` to the accumulated normal impulse of the lanes in `active`, clamped so
/// contacts only push; returns what was applied.
/// The second point's normal velocity before either point pushes, where some lane solves
/// its two points together (`c.together`; as the scalar `contact_solver::solve`).
///
/// An `if`, not a `bool::then` closure: a closure is compiled without the kernel's AVX2, and
/// where it is not inlined its lane operations become calls (measured: the whole solve 1.8
/// times slower once, when a second instance of the kernel stopped inlining it).
#[inline(always)]
fn second_point_velocity<V: Lanes>(
    c: &WideConstraint,
    a: &WideBody<V>,
    b: &WideBody<V>,
    nx: V,
    ny: V,
) -> Option<V> {
    if c.together != 0 {
        let (dvx, dvy) = relative_velocity(a, b, &c.points[1].r.load::<V>());
        Some(dvx * nx + dvy * ny)
    } else {
        None
    }
}

#[inline(always)]
fn accumulate_normal<V: Lanes>(p: &mut WidePoint, impulse: V, active: Option<V>) -> V {
    let old = V::load(p.normal_impulse);
    let clamped = (old + impulse).fast_max(V::splat(0.0));
    let new_impulse = match active {
        Some(mask) => mask.select(clamped, old),
        None => clamped,
    };
    p.normal_impulse = new_impulse.store();
    p.total_normal_impulse = V::load(p.total_normal_impulse)
        .fast_max(new_impulse)
        .store();
    new_impulse - old
}

/// Runs `$kernel::<Avx>` when the CPU has AVX2 and `use_avx` asks for it, else
/// `$kernel::<f32x8>`; the results are the same bit for bit (`lanes.rs`).
macro_rules! dispatch {
    ($use_avx:expr, $kernel:ident, $avx_kernel:ident, ($($arg:expr),*)) => {{
        #[cfg(target_arch = "x86_64")]
        if $use_avx && super::lanes::avx2_available() {
            // SAFETY: the CPU has AVX2 (checked just above).
            #[allow(unsafe_code)]
            return unsafe { $avx_kernel($($arg),*) };
        }
        let _ = $use_avx;
        $kernel::<f32x8>($($arg),*)
    }};
}

/// Position integration (`solver::integrate_body_position`) of the bodies `moving`, eight at a
/// time, operation for operation as the scalar function, so the bits are the same; a tail
/// under eight goes through the scalar function. Each body's speed is capped at
/// `max_linear_speed` where it is dynamic, its spin where it rotates. Returns how many
/// dynamic bodies a cap bit (as the scalar loop counts them). `moving` holds each body once.
pub(super) fn integrate_positions(
    moving: &[u32],
    motion: &[super::BodyMotion],
    states: &BodyStates<'_>,
    h: f32,
    max_linear_speed: f32,
    use_avx: bool,
) -> u64 {
    dispatch!(
        use_avx,
        integrate_positions_with,
        integrate_positions_avx2,
        (moving, motion, states, h, max_linear_speed)
    )
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn integrate_positions_avx2(
    moving: &[u32],
    motion: &[super::BodyMotion],
    states: &BodyStates<'_>,
    h: f32,
    max_linear_speed: f32,
) -> u64 {
    integrate_positions_with::<Avx>(moving, motion, states, h, max_linear_speed)
}

#[inline(always)]
fn integrate_positions_with<V: Lanes>(
    moving: &[u32],
    motion: &[super::BodyMotion],
    states: &BodyStates<'_>,
    h: f32,
    max_linear_speed: f32,
) -> u64 {
    let mut count = 0u64;
    let chunks = moving.chunks_exact(LANES);
    for &i in chunks.remainder() {
        let i = i as usize;
        let mut s = states.get(i);
        count += u64::from(super::integrate_body_position(
            &mut s,
            &motion[i],
            h,
            max_linear_speed,
        ));
        states.set(i, s);
    }
    let (zero, one) = (V::splat(0.0), V::splat(1.0));
    let hv = V::splat(h);
    let cap = V::splat(max_linear_speed);
    let cap2 = V::splat(max_linear_speed * max_linear_speed);
    // As `integrate_position`: a quarter turn a substep at most.
    let max_w = V::splat(0.25 * std::f32::consts::PI / h);
    for index in chunks {
        let index: &[u32; LANES] = index.try_into().expect("a chunk of eight");
        let (mut dynamic, mut rotates) = (0u8, 0u8);
        for (l, &i) in index.iter().enumerate() {
            let m = &motion[i as usize];
            dynamic |= u8::from(m.dynamic) << l;
            rotates |= u8::from(m.rotates) << l;
        }
        let b = gather::<V>(states, index);
        // The speed cap, dynamic bodies only (the scalar loop caps the others at infinity,
        // which no speed exceeds).
        let speed2 = b.vx * b.vx + b.vy * b.vy;
        let over = speed2.gt(cap2) & lane_mask::<V>(dynamic);
        let scale = cap / speed2.sqrt();
        let vx = over.select(b.vx * scale, b.vx);
        let vy = over.select(b.vy * scale, b.vy);
        let dpx = b.dpx + vx * hv;
        let dpy = b.dpy + vy * hv;
        // The spin cap and the rotation, bodies that rotate only.
        let turns = lane_mask::<V>(rotates);
        let spun = b.w.abs().gt(max_w) & turns;
        let w = spun.select(b.w.fast_min(max_w).fast_max(-max_w), b.w);
        let delta = hv * w;
        let c = b.dqc - delta * b.dqs;
        let s = b.dqs + delta * b.dqc;
        let mag = (c * c + s * s).sqrt();
        let inv = mag.gt(zero).select(one / mag, zero);
        let dqc = turns.select(c * inv, b.dqc);
        let dqs = turns.select(s * inv, b.dqs);
        count += u64::from(((over.bits() | spun.bits()) & dynamic).count_ones());
        let (vx, vy, w, pad) = (vx.halves(), vy.halves(), w.halves(), b.pad.halves());
        let (dpx, dpy, dqc, dqs) = (dpx.halves(), dpy.halves(), dqc.halves(), dqs.halves());
        for g in 0..2 {
            let motion_rows = f32x4::transpose([vx[g], vy[g], w[g], pad[g]]);
            let delta_rows = f32x4::transpose([dpx[g], dpy[g], dqc[g], dqs[g]]);
            for k in 0..4 {
                let i = index[g * 4 + k] as usize;
                states.set_motion_row(i, motion_rows[k]);
                states.set_delta_row(i, delta_rows[k]);
            }
        }
    }
    count
}

/// [`point_terms_with`] on the lanes `use_avx` picks (as `dispatch!` picks them).
fn wide_point_terms(
    c: &mut WideConstraint,
    states: &[BodyState],
    has_point: [u8; 2],
    pairs: u8,
    use_avx: bool,
) -> u8 {
    dispatch!(
        use_avx,
        point_terms_with,
        point_terms_avx2,
        (c, states, has_point, pairs)
    )
}

/// Warm start: apply the accumulated impulses again. `surfaces` is empty (a world without
/// surface materials) or the constraints' own, one each.
pub fn warm_start(
    constraints: &[WideConstraint],
    surfaces: &[WideSurface],
    states: &BodyStates<'_>,
    use_avx: bool,
) {
    dispatch!(
        use_avx,
        warm_start_with,
        warm_start_avx2,
        (constraints, surfaces, states)
    )
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn warm_start_avx2(
    constraints: &[WideConstraint],
    surfaces: &[WideSurface],
    states: &BodyStates<'_>,
) {
    warm_start_with::<Avx>(constraints, surfaces, states)
}

#[inline(always)]
fn warm_start_with<V: Lanes>(
    constraints: &[WideConstraint],
    surfaces: &[WideSurface],
    states: &BodyStates<'_>,
) {
    for (k, c) in constraints.iter().enumerate() {
        let mut a = gather::<V>(states, &c.body_a);
        let mut b = gather::<V>(states, &c.body_b);
        let m = c.masses();
        let (nx, ny) = (V::load(c.normal_x), V::load(c.normal_y));
        for p in &c.points {
            // P = λn·n + λt·t with t = (ny, −nx).
            let (normal, tangent) = (V::load(p.normal_impulse), V::load(p.tangent_impulse));
            let px = normal * nx + tangent * ny;
            let py = normal * ny - tangent * nx;
            apply(m, &mut a, &mut b, &p.r.load(), px, py);
        }
        if c.any_rolling {
            let rolling = V::load(surfaces[k].rolling_impulse);
            a.w -= m.ia * rolling;
            b.w += m.ib * rolling;
        }
        scatter(states, &c.body_a, c.dynamic_a, &a);
        scatter(states, &c.body_b, c.dynamic_b, &b);
    }
}

/// One solve (`use_bias`) or relax pass; relax also solves friction. `surfaces` as for
/// [`warm_start`].
pub fn solve(
    constraints: &mut [WideConstraint],
    surfaces: &mut [WideSurface],
    states: &BodyStates<'_>,
    inv_h: f32,
    use_bias: bool,
    max_push: f32,
    use_avx: bool,
) {
    dispatch!(
        use_avx,
        solve_with,
        solve_avx2,
        (constraints, surfaces, states, inv_h, use_bias, max_push)
    )
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn solve_avx2(
    constraints: &mut [WideConstraint],
    surfaces: &mut [WideSurface],
    states: &BodyStates<'_>,
    inv_h: f32,
    use_bias: bool,
    max_push: f32,
) {
    solve_with::<Avx>(constraints, surfaces, states, inv_h, use_bias, max_push)
}

#[inline(always)]
fn solve_with<V: Lanes>(
    constraints: &mut [WideConstraint],
    surfaces: &mut [WideSurface],
    states: &BodyStates<'_>,
    inv_h: f32,
    use_bias: bool,
    max_push: f32,
) {
    let inv_h = V::splat(inv_h);
    let neg_push = V::splat(-max_push);
    let zero = V::splat(0.0);
    let one = V::splat(1.0);
    for (k, c) in constraints.iter_mut().enumerate() {
        let mut a = gather::<V>(states, &c.body_a);
        let mut b = gather::<V>(states, &c.body_b);
        let m = c.masses();
        let (nx, ny) = (V::load(c.normal_x), V::load(c.normal_y));
        let dpx = b.dpx - a.dpx;
        let dpy = b.dpy - a.dpy;
        let (c_mass_scale, c_bias_rate, c_impulse_scale) = (
            V::load(c.mass_scale),
            V::load(c.bias_rate),
            V::load(c.impulse_scale),
        );
        // The second point's normal velocity before either point pushes, for the lanes that
        // solve their two points together (as the scalar `contact_solver::solve`): one value
        // kept across the first point, not the six velocities.
        let vn_before = second_point_velocity(c, &a, &b, nx, ny);
        for (j, p) in c.points.iter_mut().enumerate() {
            let r = p.r.load::<V>();
            // Current separation from the substep deltas (rotated anchors), normal fixed.
            let prax = a.dqc * r.ax - a.dqs * r.ay;
            let pray = a.dqs * r.ax + a.dqc * r.ay;
            let prbx = b.dqc * r.bx - b.dqs * r.by;
            let prby = b.dqs * r.bx + b.dqc * r.by;
            let dx = dpx + (prbx - prax);
            let dy = dpy + (prby - pray);
            let s = (dx * nx + dy * ny) + V::load(p.base_separation);
            let speculative = s.gt(zero);
            let (bias, mass_scale, impulse_scale) = if use_bias {
                let soft = (c_mass_scale * c_bias_rate * s).fast_max(neg_push);
                (
                    speculative.select(s * inv_h, soft),
                    speculative.select(one, c_mass_scale),
                    speculative.select(zero, c_impulse_scale),
                )
            } else {
                (speculative.select(s * inv_h, zero), one, zero)
            };
            let (dvx, dvy) = relative_velocity(&a, &b, &r);
            let mut vn = dvx * nx + dvy * ny;
            if j == 1
                && let Some(before) = vn_before
            {
                vn = lane_mask::<V>(c.together).select(before, vn);
            }
            let impulse = -V::load(p.normal_mass) * (mass_scale * vn + bias)
                - impulse_scale * V::load(p.normal_impulse);
            let applied = accumulate_normal(p, impulse, None);
            apply(m, &mut a, &mut b, &r, applied * nx, applied * ny);
        }
        // Rolling resistance (as the scalar `contact_solver::solve`): relax pass, before
        // friction.
        if !use_bias && c.any_rolling {
            let s = &mut surfaces[k];
            let [p0, p1] = &c.points;
            let total = V::load(p0.normal_impulse) + V::load(p1.normal_impulse);
            let delta = V::load(s.rolling_mass) * (a.w - b.w);
            let max = V::load(s.rolling_resistance) * total;
            let old = V::load(s.rolling_impulse);
            let new_impulse = (old + delta).fast_min(max).fast_max(-max);
            let applied = new_impulse - old;
            s.rolling_impulse = new_impulse.store();
            a.w -= m.ia * applied;
            b.w += m.ib * applied;
        }
        if !use_bias && c.any_friction {
            let (tx, ty) = (ny, -nx);
            let friction = V::load(c.friction);
            for p in &mut c.points {
                let r = p.r.load::<V>();
                let (dvx, dvy) = relative_velocity(&a, &b, &r);
                let mut vt = dvx * tx + dvy * ty;
                if c.any_tangent_speed {
                    vt -= V::load(surfaces[k].tangent_speed);
                }
                let impulse = -V::load(p.tangent_mass) * vt;
                let max_friction = friction * V::load(p.normal_impulse);
                let old = V::load(p.tangent_impulse);
                let new_impulse = (old + impulse)
                    .fast_min(max_friction)
                    .fast_max(-max_friction);
                let applied = new_impulse - old;
                p.tangent_impulse = new_impulse.store();
                apply(m, &mut a, &mut b, &r, applied * tx, applied * ty);
            }
        }
        scatter(states, &c.body_a, c.dynamic_a, &a);
        scatter(states, &c.body_b, c.dynamic_b, &b);
    }
}

/// One restitution pass; wide constraints with no bouncing lane are skipped whole. With
/// `marks` (`impacts_bounce`'s repeated passes), only the lanes its mask lets through are
/// solved, and the bodies a fast rebound moved are marked. Returns
/// how many (constraint, point) pairs have a lane that keeps the passes going
/// (`contact_solver::bounce_moved`; unlike the scalar pass's count of points, it is only
/// ever compared with 0).
pub fn apply_restitution(
    constraints: &mut [WideConstraint],
    states: &BodyStates<'_>,
    threshold: f32,
    marks: Option<(&BounceMarks<'_>, u8)>,
    use_avx: bool,
) -> u64 {
    dispatch!(
        use_avx,
        apply_restitution_with,
        apply_restitution_avx2,
        (constraints, states, threshold, marks)
    )
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn apply_restitution_avx2(
    constraints: &mut [WideConstraint],
    states: &BodyStates<'_>,
    threshold: f32,
    marks: Option<(&BounceMarks<'_>, u8)>,
) -> u64 {
    apply_restitution_with::<Avx>(constraints, states, threshold, marks)
}

impl WideConstraint {
    /// The bodies of the lanes in use, `a` then `b` (the unused lanes repeat lane 0's).
    pub fn lane_bodies(&self) -> [u32; 2 * LANES] {
        let mut bodies = [0; 2 * LANES];
        for l in 0..LANES {
            let k = if l < self.lanes as usize { l } else { 0 };
            bodies[l] = self.body_a[k];
            bodies[LANES + l] = self.body_b[k];
        }
        bodies
    }
}

/// Each point's lanes that get a restitution impulse: they approached faster than the
/// threshold (at any speed in lanes it does not apply to,
/// `contact_solver::threshold_applies`) and pushed. It depends on the constraint alone, so it
/// is the same in every restitution pass.
#[inline(always)]
fn bounce_lanes<V: Lanes>(c: &WideConstraint, threshold: f32) -> [V; 2] {
    let zero = V::splat(0.0);
    let neg_threshold = lane_mask::<V>(c.at_rest).select(V::splat(-threshold), zero);
    let restitution = V::load(c.restitution);
    c.points.each_ref().map(|p| {
        neg_threshold.gt(V::load(p.relative_velocity))
            & V::load(p.total_normal_impulse).gt(zero)
            & restitution.gt(zero)
    })
}

/// The lanes of `c` that get a restitution impulse (bit l for lane l; [`apply_restitution`]
/// passes over a constraint with none without reading its bodies).
pub fn bounce_lane_bits(c: &WideConstraint, threshold: f32) -> u8 {
    if !c.any_restitution {
        return 0;
    }
    let [p0, p1] = bounce_lanes::<f32x8>(c, threshold);
    p0.bits() | p1.bits()
}

#[inline(always)]
fn apply_restitution_with<V: Lanes>(
    constraints: &mut [WideConstraint],
    states: &BodyStates<'_>,
    threshold: f32,
    marks: Option<(&BounceMarks<'_>, u8)>,
) -> u64 {
    let zero = V::splat(0.0);
    let tolerance = V::splat(super::contact_solver::RESTITUTION_TOLERANCE);
    let base_threshold = V::splat(threshold);
    let mut moved = 0;
    for c in constraints {
        if !c.any_restitution {
            continue;
        }
        // A constraint with no lane to bounce is passed over before its bodies are read.
        let mut active = bounce_lanes::<V>(c, threshold);
        if let Some((_, lanes)) = marks {
            let visit = lane_mask::<V>(lanes);
            active = active.map(|a| a & visit);
        }
        if !active[0].any() && !active[1].any() {
            continue;
        }
        // Only the lanes that bounce are written back, as the scalar pass writes only the
        // constraints that do: another lane's velocities come back with a zero impulse
        // added, which turns a -0.0 into a +0.0.
        let touched = active[0].bits() | active[1].bits();
        let mut moved_lanes = 0u8;
        let restitution = V::load(c.restitution);
        let mut a = gather::<V>(states, &c.body_a);
        let mut b = gather::<V>(states, &c.body_b);
        let m = c.masses();
        let (nx, ny) = (V::load(c.normal_x), V::load(c.normal_y));
        let vn_before = second_point_velocity(c, &a, &b, nx, ny);
        for (j, (p, active)) in c.points.iter_mut().zip(active).enumerate() {
            let relative = V::load(p.relative_velocity);
            if !active.any() {
                continue;
            }
            let r = p.r.load::<V>();
            let (dvx, dvy) = relative_velocity(&a, &b, &r);
            let mut vn = dvx * nx + dvy * ny;
            if j == 1
                && let Some(before) = vn_before
            {
                vn = lane_mask::<V>(c.together).select(before, vn);
            }
            let normal_mass = V::load(p.normal_mass);
            let impulse = -normal_mass * (vn + restitution * relative);
            let applied = accumulate_normal(p, impulse, Some(active));
            // `contact_solver::bounce_moved`, lane by lane (inactive lanes applied 0):
            // `|Δλ| > tol·m` and `-(e·vn) > threshold`.
            let rebound = zero - restitution * relative;
            let still = applied.abs().gt(tolerance * normal_mass) & rebound.gt(base_threshold);
            if still.any() {
                moved += 1;
                moved_lanes |= still.bits();
            }
            apply(m, &mut a, &mut b, &r, applied * nx, applied * ny);
        }
        scatter(states, &c.body_a, c.dynamic_a & touched, &a);
        scatter(states, &c.body_b, c.dynamic_b & touched, &b);
        if moved_lanes != 0
            && let Some((marks, _)) = marks
        {
            for l in 0..LANES {
                if moved_lanes & c.dynamic_a & (1 << l) != 0 {
                    marks.mark(c.body_a[l] as usize);
                }
                if moved_lanes & c.dynamic_b & (1 << l) != 0 {
                    marks.mark(c.body_b[l] as usize);
                }
            }
        }
    }
    moved
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Rot;
    use crate::solver::{BodyMotion, integrate_body_position};
    use glam::Vec2;

    /// The words of a state, for a comparison that tells NaNs apart by their bits.
    fn bits(s: &BodyState) -> [u32; 8] {
        [
            s.v.x,
            s.v.y,
            s.w,
            f32::from_bits(s.flags),
            s.dp.x,
            s.dp.y,
            s.dq.c,
            s.dq.s,
        ]
        .map(f32::to_bits)
    }

    /// Position integration eight bodies at a time against `integrate_body_position` one at a
    /// time, bit for bit, with the same count of caps: 27 bodies (three chunks of eight and a
    /// tail of three) in a scrambled order, dynamic ones that turn and that do not, kinematic
    /// ones (never speed-capped, spin-capped, not counted), speeds and spins over the caps, a
    /// rotation of zero length (normalised to zero), and a NaN velocity (passed through).
    #[test]
    fn positions_integrate_in_lanes_as_one_at_a_time() {
        let (h, max_speed) = (1.0 / 240.0, 400.0);
        let n = 27;
        let mut states = Vec::new();
        let mut motion = Vec::new();
        for k in 0..n {
            let (f, kind) = (k as f32, k % 4);
            // Speeds and spins: kind 2 (kinematic) and 3 past the caps (400 m/s and a
            // quarter turn a substep, 188 rad/s here).
            let speed = [3.0, 3.0, 500.0, 900.0][kind];
            let spin = [2.0, 0.0, 400.0, -300.0][kind];
            states.push(BodyState {
                v: Vec2::new((1.7 * f).sin(), (0.9 * f).cos()) * speed,
                w: spin * (1.3 * f + 0.5).sin(),
                flags: k as u32,
                dp: Vec2::new(0.01 * f, -0.02 * f),
                dq: Rot::from_angle(0.3 * f),
            });
            motion.push(BodyMotion {
                dynamic: kind != 2,
                moves: true,
                rotates: kind != 1,
                ..BodyMotion::default()
            });
        }
        states[5].dq = Rot { c: 0.0, s: 0.0 };
        states[5].w = 0.0;
        states[9].v.x = f32::NAN;
        let moving: Vec<u32> = (0..n as u32).map(|k| (7 * k) % n as u32).collect();

        let mut want = states.clone();
        let mut want_count = 0;
        for &i in &moving {
            let (s, m) = (&mut want[i as usize], &motion[i as usize]);
            want_count += u64::from(integrate_body_position(s, m, h, max_speed));
        }
        // Every body of kind 3 (six) is capped and counted; the kinematic ones' spins are
        // capped too, uncounted.
        assert_eq!(want_count, 6);
        let max_w = 0.25 * std::f32::consts::PI / h;
        assert!(want.iter().skip(2).step_by(4).any(|s| s.w.abs() == max_w));

        let kernels: &[bool] = if crate::solver::lanes::avx2_available() {
            &[false, true]
        } else {
            &[false]
        };
        for &use_avx in kernels {
            let mut got = states.clone();
            let count = integrate_positions(
                &moving,
                &motion,
                &BodyStates::exclusive(&mut got),
                h,
                max_speed,
                use_avx,
            );
            assert_eq!(count, want_count, "use_avx {use_avx}");
            for (k, (g, w)) in got.iter().zip(&want).enumerate() {
                assert_eq!(bits(g), bits(w), "body {k}, use_avx {use_avx}");
            }
        }
    }
}
