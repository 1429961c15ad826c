//! Soft contact constraints: prepare, warm start, solve (with and without bias), relax with
//! friction, restitution, store. The math is Box2D v3's Soft Step (`contact_solver.c`), as
//! read in `docs/soft_step.md` sections 2.4 to 2.11.

use glam::Vec2;

use crate::body::BodyState;
use crate::math::{cross, cross_sv, dot, right_perp};
use crate::softness::Softness;
use crate::threads::parallel::BodyStates;

/// One point of a contact constraint.
#[derive(Clone, Copy, Debug, Default)]
pub struct ConstraintPoint {
    /// Fixed anchors relative to each centre of mass (the Jacobian uses these all step).
    pub anchor_a: Vec2,
    /// See `anchor_a`.
    pub anchor_b: Vec2,
    /// Separation minus the anchors' offset along the normal, so the current separation
    /// follows from the bodies' substep deltas alone (docs/soft_step.md 2.5).
    pub base_separation: f32,
    /// Normal velocity before the solve, for restitution.
    pub relative_velocity: f32,
    /// Accumulated impulses.
    pub normal_impulse: f32,
    /// Accumulated friction impulse.
    pub tangent_impulse: f32,
    /// Largest normal impulse during the step.
    pub total_normal_impulse: f32,
    /// Effective masses along the normal and the tangent.
    pub normal_mass: f32,
    /// See `normal_mass`.
    pub tangent_mass: f32,
}

/// A contact between two bodies, ready for the substep loop: everything the hot loop needs
/// is copied in, so it never touches the contact or the body's cold data.
#[derive(Clone, Copy, Debug, Default)]
pub struct ContactConstraint {
    /// Body indices.
    pub body_a: u32,
    /// See `body_a`.
    pub body_b: u32,
    /// Index of the contact this came from (to store impulses back).
    pub contact: u32,
    /// Whether each body is dynamic (only dynamic bodies are written).
    pub dynamic_a: bool,
    /// See `dynamic_a`.
    pub dynamic_b: bool,
    /// Inverse masses and inertias.
    pub inv_mass_a: f32,
    /// See `inv_mass_a`.
    pub inv_i_a: f32,
    /// See `inv_mass_a`.
    pub inv_mass_b: f32,
    /// See `inv_mass_a`.
    pub inv_i_b: f32,
    /// Normal from A to B, fixed for the step.
    pub normal: Vec2,
    /// Mixed friction, `sqrt(μa·μb)`.
    pub friction: f32,
    /// Mixed restitution, `max(ea, eb)`.
    pub restitution: f32,
    /// The surfaces' speed along the tangent (m/s): friction drives the relative tangent
    /// velocity to it rather than to 0 (Box2D's `tangentSpeed`, a conveyor belt).
    pub tangent_speed: f32,
    /// The most rolling torque per newton of normal force (m; Box2D v3.1's
    /// `rollingResistance`): the relative spin is braked by an angular impulse of at most
    /// this times the contact's normal impulse. 0: not solved.
    pub rolling_resistance: f32,
    /// Effective mass of the relative spin ([`super::rolling_mass`]).
    pub rolling_mass: f32,
    /// Accumulated rolling impulse (N·m·s).
    pub rolling_impulse: f32,
    /// The contact's spring.
    pub softness: Softness,
    /// Points used.
    pub count: usize,
    /// Its two points are solved from the same velocities ([`points_together`]).
    pub together: bool,
    /// The restitution threshold applies to it ([`threshold_applies`]).
    pub at_rest: bool,
    /// The points.
    pub points: [ConstraintPoint; 2],
}

/// Relative velocity of B's anchor with respect to A's.
#[inline]
fn relative_velocity(va: Vec2, wa: f32, ra: Vec2, vb: Vec2, wb: f32, rb: Vec2) -> Vec2 {
    (vb + cross_sv(wb, rb)) - (va + cross_sv(wa, ra))
}

/// Reads both bodies' states.
#[inline]
fn read(states: &BodyStates<'_>, c: &ContactConstraint) -> (BodyState, BodyState) {
    (states.get(c.body_a as usize), states.get(c.body_b as usize))
}

/// Writes back the velocities of the dynamic bodies only: static and kinematic bodies are
/// shared by many constraints of one colour and must never be written.
#[inline]
fn write(states: &BodyStates<'_>, c: &ContactConstraint, a: &BodyState, b: &BodyState) {
    if c.dynamic_a {
        states.set_velocity(c.body_a as usize, a.v, a.w);
    }
    if c.dynamic_b {
        states.set_velocity(c.body_b as usize, b.v, b.w);
    }
}

/// Inverse masses and inertias of both sides.
#[derive(Clone, Copy)]
struct Masses {
    ma: f32,
    ia: f32,
    mb: f32,
    ib: f32,
}

impl ContactConstraint {
    #[inline(always)]
    fn masses(&self) -> Masses {
        Masses {
            ma: self.inv_mass_a,
            ia: self.inv_i_a,
            mb: self.inv_mass_b,
            ib: self.inv_i_b,
        }
    }
}

/// Applies impulse `p` at anchors `ra` (to A, negated) and `rb` (to B).
#[inline(always)]
fn apply(m: Masses, a: &mut BodyState, b: &mut BodyState, ra: Vec2, rb: Vec2, p: Vec2) {
    a.v -= p * m.ma;
    a.w -= m.ia * cross(ra, p);
    b.v += p * m.mb;
    b.w += m.ib * cross(rb, p);
}

/// Adds `impulse` to a point's accumulated normal impulse, clamped so the contact only
/// pushes; returns the part actually applied.
#[inline(always)]
fn accumulate_normal(p: &mut ConstraintPoint, impulse: f32) -> f32 {
    let new_impulse = (p.normal_impulse + impulse).max(0.0);
    let applied = new_impulse - p.normal_impulse;
    p.normal_impulse = new_impulse;
    p.total_normal_impulse = p.total_normal_impulse.max(new_impulse);
    applied
}

/// Computes effective masses, base separations and the pre-solve normal velocity.
pub fn prepare_point(
    c: &ContactConstraint,
    p: &mut ConstraintPoint,
    sa: &BodyState,
    sb: &BodyState,
    separation: f32,
) {
    let prepared = point_terms(
        c.normal,
        [c.inv_mass_a, c.inv_i_a, c.inv_mass_b, c.inv_i_b],
        p.anchor_a,
        p.anchor_b,
        sa,
        sb,
        separation,
    );
    p.base_separation = prepared.base_separation;
    p.normal_mass = prepared.normal_mass;
    p.tangent_mass = prepared.tangent_mass;
    p.total_normal_impulse = 0.0;
    p.relative_velocity = prepared.relative_velocity;
}

/// Whether a two-point manifold's points are solved from the same velocities (each from
/// the velocities before either pushes, the impulses then applied in turn) rather than one
/// after the other. In turn, the first point of an impact takes all of it and the second
/// none, and a box dropped flat lands turning (docs/accuracy/flat_landing.md); together,
/// the two rows converge as fast as they are apart, so only rows well apart are: coupling
/// `ρ² = k12² / (k11·k22) ≤ 1/4` (a flat box's ρ is 0.2, a capsule lying down 0.38; two
/// points close along the surface make ρ near 1, where together would stall and in turn
/// converges as ρ²). `masses` as in [`point_terms`]; `anchors` each point's `[ra, rb]`.
#[inline(always)]
pub fn points_together(n: Vec2, masses: [f32; 4], anchors: [[Vec2; 2]; 2]) -> bool {
    let [ma, ia, mb, ib] = masses;
    let [[r1a, r1b], [r2a, r2b]] = anchors;
    let (c1a, c1b) = (cross(r1a, n), cross(r1b, n));
    let (c2a, c2b) = (cross(r2a, n), cross(r2b, n));
    let k11 = ma + mb + ia * c1a * c1a + ib * c1b * c1b;
    let k22 = ma + mb + ia * c2a * c2a + ib * c2b * c2b;
    let k12 = ma + mb + ia * c1a * c2a + ib * c1b * c2b;
    4.0 * k12 * k12 <= k11 * k22
}

/// What prepare computes for one contact point (docs/soft_step.md 2.4).
#[derive(Clone, Copy, Debug)]
pub struct PointTerms {
    /// Separation minus the anchors' offset along the normal.
    pub base_separation: f32,
    /// Effective mass along the normal (0 when neither body responds).
    pub normal_mass: f32,
    /// Effective mass along the tangent.
    pub tangent_mass: f32,
    /// Normal relative velocity before the solve.
    pub relative_velocity: f32,
}

/// The one definition of a point's prepare terms, shared by the scalar and the 8-lane
/// constraints so both agree bit for bit; `masses` is `[inv_mass_a, inv_i_a, inv_mass_b,
/// inv_i_b]`.
#[inline(always)]
pub fn point_terms(
    n: Vec2,
    masses: [f32; 4],
    ra: Vec2,
    rb: Vec2,
    sa: &BodyState,
    sb: &BodyState,
    separation: f32,
) -> PointTerms {
    let [ma, ia, mb, ib] = masses;
    let t = right_perp(n);
    let rna = cross(ra, n);
    let rnb = cross(rb, n);
    let k_normal = ma + mb + ia * rna * rna + ib * rnb * rnb;
    let rta = cross(ra, t);
    let rtb = cross(rb, t);
    let k_tangent = ma + mb + ia * rta * rta + ib * rtb * rtb;
    PointTerms {
        base_separation: separation - dot(rb - ra, n),
        normal_mass: if k_normal > 0.0 { 1.0 / k_normal } else { 0.0 },
        tangent_mass: if k_tangent > 0.0 {
            1.0 / k_tangent
        } else {
            0.0
        },
        relative_velocity: dot(n, relative_velocity(sa.v, sa.w, ra, sb.v, sb.w, rb)),
    }
}

/// Applies last step's accumulated impulses again at the start of a substep.
pub fn warm_start(constraints: &[ContactConstraint], states: &BodyStates<'_>) {
    for c in constraints {
        let (mut a, mut b) = read(states, c);
        let m = c.masses();
        let n = c.normal;
        let t = right_perp(n);
        for p in &c.points[..c.count] {
            let impulse = n * p.normal_impulse + t * p.tangent_impulse;
            apply(m, &mut a, &mut b, p.anchor_a, p.anchor_b, impulse);
        }
        if c.rolling_resistance > 0.0 {
            a.w -= m.ia * c.rolling_impulse;
            b.w += m.ib * c.rolling_impulse;
        }
        write(states, c, &a, &b);
    }
}

/// One pass of the normal constraints, soft with bias (`use_bias`) or rigid without (relax);
/// the relax pass also solves friction (Box2D HEAD does friction in relax only).
pub fn solve(
    constraints: &mut [ContactConstraint],
    states: &BodyStates<'_>,
    inv_h: f32,
    use_bias: bool,
    max_push_speed: f32,
) {
    for c in constraints {
        let (mut a, mut b) = read(states, c);
        let m = c.masses();
        let n = c.normal;
        let dp = b.dp - a.dp;
        // The velocities before either point pushes, for the second point of a manifold
        // solved together (`points_together`).
        let before = c.together.then_some((a, b));
        for (k, p) in c.points[..c.count].iter_mut().enumerate() {
            // Current separation from the substep deltas; the normal stays fixed.
            let prb = b.dq.apply(p.anchor_b);
            let pra = a.dq.apply(p.anchor_a);
            let d = dp + (prb - pra);
            let s = dot(d, n) + p.base_separation;
            let (bias, mass_scale, impulse_scale) = if s > 0.0 {
                // Speculative: close the gap within this substep, no softness.
                (s * inv_h, 1.0, 0.0)
            } else if use_bias {
                (
                    (c.softness.mass_scale * c.softness.bias_rate * s).max(-max_push_speed),
                    c.softness.mass_scale,
                    c.softness.impulse_scale,
                )
            } else {
                (0.0, 1.0, 0.0)
            };
            let (ra, rb) = (p.anchor_a, p.anchor_b);
            let (va, vb) = match &before {
                Some((a0, b0)) if k == 1 => (a0, b0),
                _ => (&a, &b),
            };
            let vn = dot(relative_velocity(va.v, va.w, ra, vb.v, vb.w, rb), n);
            let impulse =
                -p.normal_mass * (mass_scale * vn + bias) - impulse_scale * p.normal_impulse;
            let applied = accumulate_normal(p, impulse);
            apply(m, &mut a, &mut b, ra, rb, n * applied);
        }
        // Rolling resistance, in the relax pass before friction as Box2D v3.1's wide solver
        // has it (`contact_solver.c`): the relative spin braked, the accumulated angular
        // impulse within the resistance times the points' normal impulses summed.
        if !use_bias && c.rolling_resistance > 0.0 {
            let total: f32 = c.points[..c.count].iter().map(|p| p.normal_impulse).sum();
            let delta = c.rolling_mass * (a.w - b.w);
            let max = c.rolling_resistance * total;
            let old = c.rolling_impulse;
            c.rolling_impulse = crate::math::clamp_within(old + delta, max);
            let applied = c.rolling_impulse - old;
            a.w -= m.ia * applied;
            b.w += m.ib * applied;
        }
        // Friction: skipped outright for frictionless pairs (model only what a scene needs).
        if !use_bias && c.friction > 0.0 {
            let t = right_perp(n);
            for p in &mut c.points[..c.count] {
                let (ra, rb) = (p.anchor_a, p.anchor_b);
                let mut vt = dot(relative_velocity(a.v, a.w, ra, b.v, b.w, rb), t);
                if c.tangent_speed != 0.0 {
                    vt -= c.tangent_speed;
                }
                let impulse = -p.tangent_mass * vt;
                let max_friction = c.friction * p.normal_impulse;
                let new_impulse =
                    crate::math::clamp_within(p.tangent_impulse + impulse, max_friction);
                let applied = new_impulse - p.tangent_impulse;
                p.tangent_impulse = new_impulse;
                apply(m, &mut a, &mut b, ra, rb, t * applied);
            }
        }
        write(states, c, &a, &b);
    }
}

/// Whether the restitution threshold applies to a contact: to every one by Box2D's rule;
/// with `impacts_bounce`, only to one that pushed in the last step (a point of its manifold
/// kept an impulse), so that an impact bounces at any approach speed while a resting
/// contact's tiny approaches do not set it jittering. One definition for the scalar and the
/// 8-lane constraints.
#[inline(always)]
pub fn threshold_applies(impacts_bounce: bool, manifold: &crate::collision::Manifold) -> bool {
    !impacts_bounce || manifold.points().iter().any(|p| p.normal_impulse > 0.0)
}

/// Most restitution passes `StepSettings::impacts_bounce` takes for the bounces to hold
/// (unless `restitution_iterations` allows more): the elastic box's worst step took 15
/// (tests/tests/accuracy.rs).
pub const RESTITUTION_PASSES: u32 = 16;

/// A restitution pass that changes no fast rebound's normal velocity by more than this
/// (m/s) ends the passes ([`bounce_moved`]): those bounces hold for every contact at once,
/// to a millimetre a second.
pub const RESTITUTION_TOLERANCE: f32 = 1e-3;

/// Whether a restitution impulse keeps the passes going: it changed its point's normal
/// velocity by more than [`RESTITUTION_TOLERANCE`] (`|Δλ| / m > tol`, written without the
/// division: an effective mass of 0 means no body responds), and the point's rebound
/// `e·|vn|` is faster than the restitution threshold. Slower rebounds are solved again when
/// a fast one moves their bodies, but do not ask for another pass: in a dense, churning pile
/// (`spinner`, restitution 0.1) thousands of slow rebounds still move after 16 passes, each
/// pass costing a tenth of the solve, for bounces Box2D's rule would not even give.
#[inline(always)]
pub fn bounce_moved(
    applied: f32,
    normal_mass: f32,
    restitution: f32,
    relative_velocity: f32,
    threshold: f32,
) -> bool {
    applied.abs() > RESTITUTION_TOLERANCE * normal_mass
        && -(restitution * relative_velocity) > threshold
}

/// The repeated restitution passes of `impacts_bounce` stop once they have visited (a wide
/// constraint counts once) this many times as many constraints as have a point to bounce,
/// the first pass's visits included...
pub const BOUNCE_VISITS_PER_LISTED: u64 = 2;
/// ...or this many, if more: a small world's passes run until the bounces hold (the elastic
/// box's 40 balls list one or two constraints a step and visit at most 4 in a pass).
pub const BOUNCE_VISITS_MIN: u64 = 1024;

/// What the repeated restitution passes of `impacts_bounce` keep beside the velocities: for
/// each body, the last pass (numbered on from step to step) in which a fast rebound moved it
/// ([`bounce_moved`]). After a step's first pass, a contact is solved again only if a body
/// of it was moved in the pass before or earlier in this one: the others' bodies are as
/// they left them, up to slow rebounds, which do not ask for another pass either. A dense,
/// churning pile (`spinner`) has a third of its constraints bouncing, a few hundred of them
/// visited again after the first pass.
pub struct BounceMarks<'a> {
    /// Each body's last pass moved, by slot.
    pub moved_in: crate::threads::parallel::BodyMarks<'a>,
    /// This pass's number.
    pub pass: u32,
    /// Whether it is the step's first pass (every constraint with a point to bounce is
    /// solved).
    pub first: bool,
}

impl BounceMarks<'_> {
    /// The lanes of a constraint solved in this pass (bit l for lane l), from its bodies as
    /// [`WideConstraint::lane_bodies`](super::wide::WideConstraint::lane_bodies) lists them:
    /// those with a body moved in the pass before or earlier in this one. Lane by lane, so
    /// that the eight-lane and the scalar constraints solve the same contacts.
    #[inline(always)]
    pub fn visit_lanes(&self, bodies: &[u32; 2 * super::wide::LANES]) -> u8 {
        if self.first {
            return u8::MAX;
        }
        let recent = |b: u32| self.moved_in.get(b as usize) + 1 >= self.pass;
        let (a, b) = bodies.split_at(super::wide::LANES);
        a.iter().zip(b).enumerate().fold(0, |bits, (l, (&a, &b))| {
            bits | (u8::from(recent(a) || recent(b)) << l)
        })
    }

    /// Marks a dynamic body as moved in this pass.
    #[inline(always)]
    pub fn mark(&self, body: usize) {
        self.moved_in.set(body, self.pass);
    }
}

/// Whether a point gets a restitution impulse: it approached strictly faster than
/// `threshold` (0 where the threshold does not apply), as the 8-lane kernel's comparison
/// (a point that did not approach at all has nothing to bounce), and it pushed. It depends
/// on the constraint alone, so it is the same in every restitution pass.
#[inline(always)]
fn point_bounces(p: &ConstraintPoint, threshold: f32) -> bool {
    p.relative_velocity < -threshold && p.total_normal_impulse != 0.0
}

/// Whether any point of `c` gets a restitution impulse ([`apply_restitution`] passes over
/// the others without reading their bodies).
pub fn may_bounce(c: &ContactConstraint, threshold: f32) -> bool {
    let threshold = if c.at_rest { threshold } else { 0.0 };
    c.restitution != 0.0
        && c.points[..c.count]
            .iter()
            .any(|p| point_bounces(p, threshold))
}

/// One restitution pass, after the substeps: points that approached faster than the
/// threshold (or at all, where it does not apply: [`threshold_applies`]) and actually pushed
/// get their rebound velocity `-e·vn` (docs/soft_step.md 2.10). Returns how many points'
/// impulses keep the passes going ([`bounce_moved`]); with `impacts_bounce` they repeat
/// until none.
pub fn apply_restitution(
    constraints: &mut [ContactConstraint],
    states: &BodyStates<'_>,
    threshold: f32,
    marks: Option<(&BounceMarks<'_>, u8)>,
) -> u64 {
    let mut moved = 0;
    let base_threshold = threshold;
    for c in constraints {
        // A constraint with no point to bounce is passed over before its bodies are read.
        if !may_bounce(c, threshold) {
            continue;
        }
        let mut moved_here = false;
        let threshold = if c.at_rest { threshold } else { 0.0 };
        let bounces = |p: &ConstraintPoint| point_bounces(p, threshold);
        let (mut a, mut b) = read(states, c);
        let m = c.masses();
        let n = c.normal;
        let before = c.together.then_some((a, b));
        for (k, p) in c.points[..c.count].iter_mut().enumerate() {
            if !bounces(p) {
                continue;
            }
            let (ra, rb) = (p.anchor_a, p.anchor_b);
            // As in `solve`: the second point of a manifold solved together sees the
            // velocities before the first pushed.
            let (va, vb) = match &before {
                Some((a0, b0)) if k == 1 => (a0, b0),
                _ => (&a, &b),
            };
            let vn = dot(relative_velocity(va.v, va.w, ra, vb.v, vb.w, rb), n);
            let impulse = -p.normal_mass * (vn + c.restitution * p.relative_velocity);
            let applied = accumulate_normal(p, impulse);
            let still = bounce_moved(
                applied,
                p.normal_mass,
                c.restitution,
                p.relative_velocity,
                base_threshold,
            );
            moved += u64::from(still);
            moved_here |= still;
            apply(m, &mut a, &mut b, ra, rb, n * applied);
        }
        write(states, c, &a, &b);
        if moved_here && let Some((marks, _)) = marks {
            for (body, dynamic) in [(c.body_a, c.dynamic_a), (c.body_b, c.dynamic_b)] {
                if dynamic {
                    marks.mark(body as usize);
                }
            }
        }
    }
    moved
}
