//! The contact solver eight constraints at a time (Box2D v3's `b2ContactConstraintSIMD`):
//! each colour's constraints are packed into lanes of `f32x8`, bodies are gathered into
//! lanes, solved with the same per-lane arithmetic as the scalar path in
//! `contact_solver.rs`, and scattered back to dynamic bodies only.
//!
//! A colour never holds two constraints on one dynamic body, so lanes never conflict. The
//! overflow, whose constraints may share bodies, stays on the scalar path.

use glam::Vec2;
use wide::{f32x4, f32x8};

use super::PointResult;
use super::contact_solver::{BodyState, Softness};
#[cfg(target_arch = "x86_64")]
use super::lanes::Avx;
use super::lanes::Lanes;
use super::{ContactInput, SolverBody};
use crate::parallel::BodyStates;

/// Lanes per wide constraint.
pub const LANES: usize = 8;

/// What prepare reads for one lane: the contact, its bodies and its spring.
pub struct LaneInput<'c> {
    /// Index of the contact (to store impulses back).
    pub contact: u32,
    /// The contact's data.
    pub input: ContactInput<'c>,
    /// Body A's masses.
    pub body_a: SolverBody,
    /// Body B's masses.
    pub body_b: SolverBody,
    /// The contact's spring (stiffer against static bodies).
    pub softness: Softness,
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
    body_a: [u32; LANES],
    body_b: [u32; LANES],
    /// Lanes whose body is dynamic (the only ones written back).
    dynamic_a: u8,
    dynamic_b: u8,
    /// Lanes in use.
    lanes: u8,
    any_friction: bool,
    any_restitution: bool,
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
        body_a: [0; LANES],
        body_b: [0; LANES],
        dynamic_a: 0,
        dynamic_b: 0,
        lanes: 0,
        any_friction: false,
        any_restitution: false,
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

    /// Builds `lanes` constraints (1 to 8) of one colour straight into their lanes: the
    /// contact data is copied lane by lane, then the effective masses, base separations and
    /// pre-solve normal velocities are computed eight at a time. The arithmetic is the scalar
    /// `contact_solver::prepare_point`'s, operation for operation, so both paths agree bit
    /// for bit (and eight divisions cost one).
    ///
    /// Written in place: returning the 1.3 KB constraint by value cost a copy per constraint.
    pub fn prepare<'c>(
        &mut self,
        lanes: usize,
        states: &[BodyState],
        warm_starting: bool,
        mut lane: impl FnMut(usize) -> LaneInput<'c>,
    ) {
        debug_assert!((1..=LANES).contains(&lanes));
        let first = lane(0);
        let z = f32x8::ZERO;
        let w = self;
        *w = WideConstraint {
            // Tail lanes point at the first lane's bodies with zero masses: they read, never
            // write, and apply no impulse.
            body_a: [first.input.body_a; LANES],
            body_b: [first.input.body_b; LANES],
            lanes: lanes as u8,
            ..WideConstraint::EMPTY
        };
        // Per point: the manifold's separation, and whether the lane has that point.
        let mut separation = [[0.0f32; LANES]; 2];
        let mut used = [[0.0f32; LANES]; 2];
        let mut put = |w: &mut WideConstraint, l: usize, x: &LaneInput<'_>| {
            let c = &x.input;
            let m = c.manifold;
            w.contact[l] = x.contact;
            w.count[l] = m.count as u8;
            w.body_a[l] = c.body_a;
            w.body_b[l] = c.body_b;
            w.dynamic_a |= u8::from(x.body_a.dynamic) << l;
            w.dynamic_b |= u8::from(x.body_b.dynamic) << l;
            w.any_friction |= c.friction > 0.0;
            w.any_restitution |= c.restitution > 0.0;
            w.inv_mass_a.as_mut_array()[l] = x.body_a.inv_mass;
            w.inv_i_a.as_mut_array()[l] = x.body_a.inv_inertia;
            w.inv_mass_b.as_mut_array()[l] = x.body_b.inv_mass;
            w.inv_i_b.as_mut_array()[l] = x.body_b.inv_inertia;
            w.normal_x.as_mut_array()[l] = m.normal.x;
            w.normal_y.as_mut_array()[l] = m.normal.y;
            w.friction.as_mut_array()[l] = c.friction;
            w.restitution.as_mut_array()[l] = c.restitution;
            w.bias_rate.as_mut_array()[l] = x.softness.bias_rate;
            w.mass_scale.as_mut_array()[l] = x.softness.mass_scale;
            w.impulse_scale.as_mut_array()[l] = x.softness.impulse_scale;
            for (k, mp) in m.points().iter().enumerate() {
                let p = &mut w.points[k];
                p.r.ax.as_mut_array()[l] = mp.anchor_a.x;
                p.r.ay.as_mut_array()[l] = mp.anchor_a.y;
                p.r.bx.as_mut_array()[l] = mp.anchor_b.x;
                p.r.by.as_mut_array()[l] = mp.anchor_b.y;
                if warm_starting {
                    p.normal_impulse.as_mut_array()[l] = mp.normal_impulse;
                    p.tangent_impulse.as_mut_array()[l] = mp.tangent_impulse;
                }
                separation[k][l] = mp.separation;
                used[k][l] = 1.0;
            }
        };
        put(w, 0, &first);
        for l in 1..lanes {
            let x = lane(l);
            put(w, l, &x);
        }
        let a = gather_with::<f32x8>(|i| states[i], &w.body_a);
        let b = gather_with::<f32x8>(|i| states[i], &w.body_b);
        let m = w.masses::<f32x8>();
        let (nx, ny) = (w.normal_x, w.normal_y);
        let (tx, ty) = (ny, -nx);
        for (k, p) in w.points.iter_mut().enumerate() {
            let r = p.r.load::<f32x8>();
            let used = f32x8::new(used[k]).simd_gt(z);
            let base = f32x8::new(separation[k]) - ((r.bx - r.ax) * nx + (r.by - r.ay) * ny);
            let rna = r.ax * ny - r.ay * nx;
            let rnb = r.bx * ny - r.by * nx;
            let k_normal = m.ma + m.mb + m.ia * rna * rna + m.ib * rnb * rnb;
            let rta = r.ax * ty - r.ay * tx;
            let rtb = r.bx * ty - r.by * tx;
            let k_tangent = m.ma + m.mb + m.ia * rta * rta + m.ib * rtb * rtb;
            let (dvx, dvy) = relative_velocity(&a, &b, &r);
            // Unused points and tail lanes keep zeros, so they apply no impulse.
            p.base_separation = used.select(base, z);
            p.normal_mass = (used & k_normal.simd_gt(z)).select(f32x8::ONE / k_normal, z);
            p.tangent_mass = (used & k_tangent.simd_gt(z)).select(f32x8::ONE / k_tangent, z);
            p.relative_velocity = used.select(nx * dvx + ny * dvy, z);
        }
    }

    /// Whether any lane bounces.
    pub fn any_restitution(&self) -> bool {
        self.any_restitution
    }

    /// The contacts of the used lanes.
    pub fn contacts(&self) -> impl Iterator<Item = u32> + '_ {
        self.contact[..self.lanes as usize].iter().copied()
    }

    /// Calls `f(contact, point, impulses)` for each used lane's points, lane by lane (so a
    /// contact's points are stored together).
    #[inline]
    pub fn for_each_lane_result(&self, mut f: impl FnMut(u32, usize, &PointResult)) {
        let arrays = |p: &WidePoint| {
            (
                *p.normal_impulse.as_array(),
                *p.tangent_impulse.as_array(),
                *p.total_normal_impulse.as_array(),
                *p.relative_velocity.as_array(),
            )
        };
        let points = [arrays(&self.points[0]), arrays(&self.points[1])];
        for l in 0..self.lanes as usize {
            for (k, (n, t, total, rv)) in points.iter().enumerate().take(self.count[l] as usize) {
                f(
                    self.contact[l],
                    k,
                    &PointResult {
                        normal_impulse: n[l],
                        tangent_impulse: t[l],
                        total_normal_impulse: total[l],
                        relative_velocity: rv[l],
                    },
                );
            }
        }
    }
}

/// Eight bodies' states, one per lane.
struct WideBody<V> {
    vx: V,
    vy: V,
    w: V,
    dpx: V,
    dpy: V,
    dqc: V,
    dqs: V,
}

/// Loads eight bodies' states into lanes: each state's two 16-byte halves are loaded whole and
/// transposed four at a time (Box2D's `b2GatherBodies` does the same with SSE), rather than
/// assembled float by float, which stalls on store forwarding.
#[inline(always)]
fn gather<V: Lanes>(states: &BodyStates<'_>, index: &[u32; LANES]) -> WideBody<V> {
    gather_with(|i| states.get(i), index)
}

/// `gather` from any reader of states.
#[inline(always)]
fn gather_with<V: Lanes>(get: impl Fn(usize) -> BodyState, index: &[u32; LANES]) -> WideBody<V> {
    let mut motion = [[f32x4::ZERO; 4]; 2];
    let mut delta = [[f32x4::ZERO; 4]; 2];
    for l in 0..LANES {
        let s = get(index[l] as usize);
        motion[l / 4][l % 4] = f32x4::new([s.v.x, s.v.y, s.w, 0.0]);
        delta[l / 4][l % 4] = f32x4::new([s.dp.x, s.dp.y, s.dq.c, s.dq.s]);
    }
    let [m0, m1] = motion.map(f32x4::transpose);
    let [d0, d1] = delta.map(f32x4::transpose);
    WideBody {
        vx: V::join(m0[0], m1[0]),
        vy: V::join(m0[1], m1[1]),
        w: V::join(m0[2], m1[2]),
        dpx: V::join(d0[0], d1[0]),
        dpy: V::join(d0[1], d1[1]),
        dqc: V::join(d0[2], d1[2]),
        dqs: V::join(d0[3], d1[3]),
    }
}

/// Writes the velocities of the dynamic lanes back (static and kinematic bodies are shared
/// between lanes and constraints of a colour, and are never written).
#[inline(always)]
fn scatter<V: Lanes>(states: &BodyStates<'_>, index: &[u32; LANES], dynamic: u8, b: &WideBody<V>) {
    if dynamic == 0 {
        return;
    }
    let (vx, vy, w) = (b.vx.halves(), b.vy.halves(), b.w.halves());
    for g in 0..2 {
        let rows = f32x4::transpose([vx[g], vy[g], w[g], f32x4::ZERO]);
        for (k, row) in rows.iter().enumerate() {
            let l = g * 4 + k;
            if dynamic & (1 << l) != 0 {
                let r = row.as_array();
                states.set_velocity(index[l] as usize, Vec2::new(r[0], r[1]), r[2]);
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

/// Warm start: apply the accumulated impulses again.
pub fn warm_start(constraints: &[WideConstraint], states: &BodyStates<'_>, use_avx: bool) {
    dispatch!(
        use_avx,
        warm_start_with,
        warm_start_avx2,
        (constraints, states)
    )
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn warm_start_avx2(constraints: &[WideConstraint], states: &BodyStates<'_>) {
    warm_start_with::<Avx>(constraints, states)
}

#[inline(always)]
fn warm_start_with<V: Lanes>(constraints: &[WideConstraint], states: &BodyStates<'_>) {
    for c in constraints {
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
        scatter(states, &c.body_a, c.dynamic_a, &a);
        scatter(states, &c.body_b, c.dynamic_b, &b);
    }
}

/// One solve (`use_bias`) or relax pass; relax also solves friction.
pub fn solve(
    constraints: &mut [WideConstraint],
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
        (constraints, states, inv_h, use_bias, max_push)
    )
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn solve_avx2(
    constraints: &mut [WideConstraint],
    states: &BodyStates<'_>,
    inv_h: f32,
    use_bias: bool,
    max_push: f32,
) {
    solve_with::<Avx>(constraints, states, inv_h, use_bias, max_push)
}

#[inline(always)]
fn solve_with<V: Lanes>(
    constraints: &mut [WideConstraint],
    states: &BodyStates<'_>,
    inv_h: f32,
    use_bias: bool,
    max_push: f32,
) {
    let inv_h = V::splat(inv_h);
    let neg_push = V::splat(-max_push);
    let zero = V::splat(0.0);
    let one = V::splat(1.0);
    for c in constraints {
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
        for p in &mut c.points {
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
            let vn = dvx * nx + dvy * ny;
            let impulse = -V::load(p.normal_mass) * (mass_scale * vn + bias)
                - impulse_scale * V::load(p.normal_impulse);
            let applied = accumulate_normal(p, impulse, None);
            apply(m, &mut a, &mut b, &r, applied * nx, applied * ny);
        }
        if !use_bias && c.any_friction {
            let (tx, ty) = (ny, -nx);
            let friction = V::load(c.friction);
            for p in &mut c.points {
                let r = p.r.load::<V>();
                let (dvx, dvy) = relative_velocity(&a, &b, &r);
                let vt = dvx * tx + dvy * ty;
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

/// Restitution once per step; wide constraints with no bouncing lane are skipped whole.
pub fn apply_restitution(
    constraints: &mut [WideConstraint],
    states: &BodyStates<'_>,
    threshold: f32,
    use_avx: bool,
) {
    dispatch!(
        use_avx,
        apply_restitution_with,
        apply_restitution_avx2,
        (constraints, states, threshold)
    )
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn apply_restitution_avx2(
    constraints: &mut [WideConstraint],
    states: &BodyStates<'_>,
    threshold: f32,
) {
    apply_restitution_with::<Avx>(constraints, states, threshold)
}

#[inline(always)]
fn apply_restitution_with<V: Lanes>(
    constraints: &mut [WideConstraint],
    states: &BodyStates<'_>,
    threshold: f32,
) {
    let neg_threshold = V::splat(-threshold);
    let zero = V::splat(0.0);
    for c in constraints {
        if !c.any_restitution {
            continue;
        }
        let mut a = gather::<V>(states, &c.body_a);
        let mut b = gather::<V>(states, &c.body_b);
        let m = c.masses();
        let (nx, ny) = (V::load(c.normal_x), V::load(c.normal_y));
        let restitution = V::load(c.restitution);
        for p in &mut c.points {
            let relative = V::load(p.relative_velocity);
            // Lanes that approached slower than the threshold, or never pushed, are left alone.
            let active = neg_threshold.gt(relative)
                & V::load(p.total_normal_impulse).gt(zero)
                & restitution.gt(zero);
            if !active.any() {
                continue;
            }
            let r = p.r.load::<V>();
            let (dvx, dvy) = relative_velocity(&a, &b, &r);
            let vn = dvx * nx + dvy * ny;
            let impulse = -V::load(p.normal_mass) * (vn + restitution * relative);
            let applied = accumulate_normal(p, impulse, Some(active));
            apply(m, &mut a, &mut b, &r, applied * nx, applied * ny);
        }
        scatter(states, &c.body_a, c.dynamic_a, &a);
        scatter(states, &c.body_b, c.dynamic_b, &b);
    }
}
