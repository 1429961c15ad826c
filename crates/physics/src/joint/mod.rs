//! Joints: soft constraints between two bodies, solved in the same substep loop as the
//! contacts (warm start, solve with bias, relax without), in the same graph colours (Box2D
//! v3's `joint.c` and its per-type files; Catto, "Solver2D", 2024, soft step).
//!
//! A joint keeps its anchors as frames in each body's own frame (origin-relative, so a body
//! whose centre of mass moves keeps its joints where they were put). Each step, `prepare`
//! turns them into world-oriented frames relative to each centre of mass and the
//! separation of the centres; the substeps then read only the bodies' substep deltas, so the
//! current error follows without a transform (docs/soft_step.md 2.5). Accumulated impulses carry
//! over from step to step (warm starting), as a contact's do.

pub(crate) mod chain;
pub mod def;
mod distance;
mod motor;
mod prismatic;
mod revolute;
mod weld;

pub use def::{AngularMotor, JointDef, LinearMotor, Spring};
pub use distance::Distance;
pub use motor::{Motor, Mouse};
pub use prismatic::{Prismatic, Wheel};
pub use revolute::Revolute;
pub use weld::Weld;

use glam::Vec2;

use crate::body::BodyState;
use crate::math::{Rot, Transform, cross, cross_sv};
use crate::softness::Softness;
use crate::threads::parallel::BodyStates;

/// What a joint does, with its settings and its accumulated impulses.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum JointKind {
    /// A hinge at one point, with an optional limit, motor and spring on the angle.
    Revolute(Revolute),
    /// A slider along an axis fixed in body A, without relative rotation.
    Prismatic(Prismatic),
    /// A slider on a spring along an axis fixed in body A, turning freely (a wheel).
    Wheel(Wheel),
    /// Keeps two points a length apart: a rod, a spring or a rope.
    Distance(Distance),
    /// Glues body B to body A, rigidly or through springs.
    Weld(Weld),
    /// Drives body B towards a pose in body A's frame with bounded force and torque.
    Motor(Motor),
    /// Only stops the two bodies from touching.
    Filter,
    /// Pulls a point of body B towards a target (the viewer's drag); body A is not used.
    Mouse(Mouse),
}

impl JointKind {
    /// The name used in scene files and messages.
    pub fn name(&self) -> &'static str {
        match self {
            JointKind::Revolute(_) => "Revolute",
            JointKind::Prismatic(_) => "Prismatic",
            JointKind::Wheel(_) => "Wheel",
            JointKind::Distance(_) => "Distance",
            JointKind::Weld(_) => "Weld",
            JointKind::Motor(_) => "Motor",
            JointKind::Filter => "Filter",
            JointKind::Mouse(_) => "Mouse",
        }
    }
}

fn infinite() -> f32 {
    f32::INFINITY
}

/// JSON has no infinity: a threshold of none is left out.
fn is_infinite(x: &f32) -> bool {
    *x == f32::INFINITY
}

/// One joint as the world keeps it.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Joint {
    /// Body A's slot (unused by a mouse joint, which names body B twice); read through
    /// [`crate::World::joint_bodies`].
    pub(crate) body_a: u32,
    /// Body B's slot.
    pub(crate) body_b: u32,
    /// The joint frame in body A's frame: the anchor, and the axes (x is a slider's axis).
    pub local_a: Transform,
    /// The joint frame in body B's frame; at creation both frames coincide in the world.
    pub local_b: Transform,
    /// Whether the two bodies may touch.
    pub collide_connected: bool,
    /// Stiffness of the rigid rows (Hz; the scene's `joint_hertz`; 0 is rigid).
    pub hertz: f32,
    /// Damping ratio of the rigid rows (the scene's `joint_damping_ratio`).
    pub damping_ratio: f32,
    /// The type, its settings and impulses.
    pub kind: JointKind,
    /// Reaction force (N) past which a step reports [`crate::Event::JointThreshold`].
    #[serde(default = "infinite", skip_serializing_if = "is_infinite")]
    pub force_threshold: f32,
    /// Reaction torque (N·m) past which a step reports one.
    #[serde(default = "infinite", skip_serializing_if = "is_infinite")]
    pub torque_threshold: f32,
    /// The caller's tag ([`crate::World::set_joint_user_data`]); the step never reads it.
    #[serde(default)]
    pub user_data: u64,
    /// What this step's prepare computed (kept in snapshots: the reaction forces read it).
    #[serde(default)]
    pub(crate) step: JointStep,
}

/// What a body looks like to a joint's prepare.
#[derive(Clone, Copy, Debug)]
pub(crate) struct JointBody {
    /// Centre of mass, world.
    pub center: Vec2,
    /// Rotation.
    pub q: Rot,
    /// Centre of mass in the body's frame.
    pub local_center: Vec2,
    /// Inverse mass (0 unless dynamic).
    pub inv_mass: f32,
    /// Inverse rotational inertia (0 unless dynamic and free to turn).
    pub inv_inertia: f32,
    /// Whether the solver may write its velocity.
    pub dynamic: bool,
}

/// Per-step data of a joint: both bodies' masses, the frames turned into the world and taken
/// relative to the centres of mass, and the separation of the centres at the step's start.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub(crate) struct JointStep {
    pub inv_mass_a: f32,
    pub inv_mass_b: f32,
    pub inv_i_a: f32,
    pub inv_i_b: f32,
    pub dynamic_a: bool,
    pub dynamic_b: bool,
    /// Frame A: world rotation, anchor relative to A's centre of mass (world-oriented).
    pub frame_a: Transform,
    /// Frame B, likewise.
    pub frame_b: Transform,
    /// Centre of B less centre of A at the step's start.
    pub delta_center: Vec2,
    /// The rigid rows' softness for this substep length.
    pub softness: Softness,
}

/// The substep knobs a joint reads.
#[derive(Clone, Copy, Debug)]
pub(crate) struct JointContext {
    /// Substep length.
    pub h: f32,
    /// Its inverse.
    pub inv_h: f32,
    /// Whether last step's impulses are applied first.
    pub warm_starting: bool,
}

/// Two bodies' velocities and substep deltas as one joint row sees them.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Pair {
    pub va: Vec2,
    pub wa: f32,
    pub vb: Vec2,
    pub wb: f32,
    /// Body A's substep translation and rotation.
    pub dpa: Vec2,
    pub dqa: Rot,
    /// Body B's.
    pub dpb: Vec2,
    pub dqb: Rot,
}

impl Pair {
    /// Relative velocity of the anchors `rb` on B and `ra` on A.
    #[inline]
    pub fn relative_velocity(&self, ra: Vec2, rb: Vec2) -> Vec2 {
        self.vb + cross_sv(self.wb, rb) - self.va - cross_sv(self.wa, ra)
    }

    /// Applies `impulse` at anchors `ra`, `rb` (towards B) with an extra `torque` impulse.
    #[inline]
    pub fn apply(&mut self, s: &JointStep, ra: Vec2, rb: Vec2, impulse: Vec2, torque: f32) {
        self.va -= s.inv_mass_a * impulse;
        self.wa -= s.inv_i_a * (cross(ra, impulse) + torque);
        self.vb += s.inv_mass_b * impulse;
        self.wb += s.inv_i_b * (cross(rb, impulse) + torque);
    }

    /// Applies an angular impulse only.
    #[inline]
    pub fn turn(&mut self, s: &JointStep, impulse: f32) {
        self.wa -= s.inv_i_a * impulse;
        self.wb += s.inv_i_b * impulse;
    }
}

/// Effective-mass matrix of a point-to-point row (Box2D's K for `J = [-I -ra× I rb×]`),
/// as its three distinct entries.
#[inline]
pub(crate) fn point_mass(s: &JointStep, ra: Vec2, rb: Vec2) -> [f32; 3] {
    let (ma, mb, ia, ib) = (s.inv_mass_a, s.inv_mass_b, s.inv_i_a, s.inv_i_b);
    [
        ma + mb + ra.y * ra.y * ia + rb.y * rb.y * ib,
        -ra.y * ra.x * ia - rb.y * rb.x * ib,
        ma + mb + ra.x * ra.x * ia + rb.x * rb.x * ib,
    ]
}

/// Solves the symmetric 2×2 system `[k11 k12; k12 k22] x = b` (zero where singular).
#[inline]
pub(crate) fn solve22([k11, k12, k22]: [f32; 3], b: Vec2) -> Vec2 {
    let det = k11 * k22 - k12 * k12;
    let inv = if det != 0.0 { 1.0 / det } else { 0.0 };
    Vec2::new(inv * (k22 * b.x - k12 * b.y), inv * (k11 * b.y - k12 * b.x))
}

/// `1/k`, or 0 where `k` is 0 (a row no body can move along).
#[inline]
pub(crate) fn inverse(k: f32) -> f32 {
    if k > 0.0 { 1.0 / k } else { 0.0 }
}

/// The soft or rigid row of a limit: a speculative bound while the limit is not reached
/// (no push, only no overshoot this substep), the rigid rows' softness once past it, and
/// nothing extra in the relax pass (Box2D's limit rows).
#[inline]
pub(crate) fn limit_row(c: f32, use_bias: bool, soft: &Softness, inv_h: f32) -> (f32, f32, f32) {
    if c > 0.0 {
        (c * inv_h, 1.0, 0.0)
    } else if use_bias {
        (soft.bias_rate * c, soft.mass_scale, soft.impulse_scale)
    } else {
        (0.0, 1.0, 0.0)
    }
}

impl Joint {
    /// Computes this step's frames and masses from the bodies at the step's start.
    pub(crate) fn prepare(&mut self, a: &JointBody, b: &JointBody, ctx: &JointContext) {
        // Joints no stiffer than a quarter of the substep rate (Box2D's `b2PrepareJoint`).
        let hertz = self.hertz.min(0.25 * ctx.inv_h);
        let s = JointStep {
            inv_mass_a: a.inv_mass,
            inv_mass_b: b.inv_mass,
            inv_i_a: a.inv_inertia,
            inv_i_b: b.inv_inertia,
            dynamic_a: a.dynamic,
            dynamic_b: b.dynamic,
            frame_a: Transform {
                p: a.q.apply(self.local_a.p - a.local_center),
                q: a.q.then_from(self.local_a.q),
            },
            frame_b: Transform {
                p: b.q.apply(self.local_b.p - b.local_center),
                q: b.q.then_from(self.local_b.q),
            },
            delta_center: b.center - a.center,
            softness: Softness::new(hertz, self.damping_ratio, ctx.h),
        };
        self.step = s;
        match &mut self.kind {
            JointKind::Revolute(j) => j.prepare(&s, ctx),
            JointKind::Prismatic(j) => j.prepare(&s, ctx),
            JointKind::Wheel(j) => j.prepare(&s, ctx),
            JointKind::Distance(j) => j.prepare(&s, ctx),
            JointKind::Weld(j) => j.prepare(&s, ctx),
            JointKind::Motor(j) => j.prepare(&s, ctx, a, b),
            JointKind::Mouse(j) => j.prepare(&mut self.step, ctx, b),
            JointKind::Filter => {}
        }
    }

    /// A hinge's (revolute joint's) angular rows this step (`Revolute::rows`), or `None`
    /// for another joint: the solver takes hinges eight at a time
    /// (`solver::wide_hinge::hinges`).
    #[inline]
    pub(crate) fn hinge_rows(&self) -> Option<u8> {
        match &self.kind {
            JointKind::Revolute(r) => Some(r.rows),
            _ => None,
        }
    }

    /// This joint's hinge; only for a revolute joint.
    #[inline(always)]
    pub(crate) fn hinge(&self) -> &Revolute {
        let JointKind::Revolute(r) = &self.kind else {
            unreachable!("only a hinge is solved as one")
        };
        r
    }

    /// This joint's hinge, to write; only for a revolute joint.
    #[inline(always)]
    pub(crate) fn hinge_mut(&mut self) -> &mut Revolute {
        let JointKind::Revolute(r) = &mut self.kind else {
            unreachable!("only a hinge is solved as one")
        };
        r
    }

    /// Whether the solver passes touch this joint at all.
    pub(crate) fn solved(&self) -> bool {
        !matches!(self.kind, JointKind::Filter)
    }

    fn load(&self, states: &BodyStates<'_>) -> Pair {
        let sb = states.get(self.body_b as usize);
        let sa = if matches!(self.kind, JointKind::Mouse(_)) {
            BodyState::default()
        } else {
            states.get(self.body_a as usize)
        };
        Pair {
            va: sa.v,
            wa: sa.w,
            vb: sb.v,
            wb: sb.w,
            dpa: sa.dp,
            dqa: sa.dq,
            dpb: sb.dp,
            dqb: sb.dq,
        }
    }

    fn store(&self, states: &BodyStates<'_>, p: &Pair) {
        let s = &self.step;
        if s.dynamic_a && !matches!(self.kind, JointKind::Mouse(_)) {
            states.set_velocity(self.body_a as usize, p.va, p.wa);
        }
        if s.dynamic_b {
            states.set_velocity(self.body_b as usize, p.vb, p.wb);
        }
    }

    /// Applies last step's impulses at the start of a substep.
    pub(crate) fn warm_start(&mut self, states: &BodyStates<'_>) {
        if !self.solved() {
            return;
        }
        let mut p = self.load(states);
        // Split borrows: the step data is read in place, not copied (a copy per joint per
        // pass showed as a memmove in the profile).
        let Joint { step: s, kind, .. } = self;
        match kind {
            JointKind::Revolute(j) => j.warm_start(s, &mut p),
            JointKind::Prismatic(j) => j.warm_start(s, &mut p),
            JointKind::Wheel(j) => j.warm_start(s, &mut p),
            JointKind::Distance(j) => j.warm_start(s, &mut p),
            JointKind::Weld(j) => j.warm_start(s, &mut p),
            JointKind::Motor(j) => j.warm_start(s, &mut p),
            JointKind::Mouse(j) => j.warm_start(s, &mut p),
            JointKind::Filter => {}
        }
        self.store(states, &p);
    }

    /// One pass over the joint's rows: with `use_bias` the soft solve that also removes
    /// position error, without it the rigid relax pass.
    pub(crate) fn solve(&mut self, states: &BodyStates<'_>, ctx: &JointContext, use_bias: bool) {
        if !self.solved() {
            return;
        }
        let mut p = self.load(states);
        let Joint { step: s, kind, .. } = self;
        // Each kind's `solve` and `warm_start` is inlined here (`#[inline(always)]`), so the
        // pair's velocities stay in registers from load to store: called, the pair went
        // through memory between them, and joint_grid's substeps took 5.1 ms, not 3.5.
        match kind {
            JointKind::Revolute(j) => j.solve(s, &mut p, ctx, use_bias),
            JointKind::Prismatic(j) => j.solve(s, &mut p, ctx, use_bias),
            JointKind::Wheel(j) => j.solve(s, &mut p, ctx, use_bias),
            JointKind::Distance(j) => j.solve(s, &mut p, ctx, use_bias),
            JointKind::Weld(j) => j.solve(s, &mut p, use_bias),
            JointKind::Motor(j) => j.solve(s, &mut p, ctx),
            JointKind::Mouse(j) => j.solve(s, &mut p, ctx),
            JointKind::Filter => {}
        }
        self.store(states, &p);
    }

    /// The force (N, on body B, world) and torque (N·m) the joint applied over the last
    /// substep of the last step, from its accumulated impulses (Box2D's
    /// `b2Joint_GetConstraintForce` and `...Torque`).
    pub(crate) fn reaction(&self, inv_h: f32) -> (Vec2, f32) {
        let s = &self.step;
        let (impulse, torque) = match &self.kind {
            JointKind::Revolute(j) => j.reaction(),
            JointKind::Prismatic(j) => j.reaction(s),
            JointKind::Wheel(j) => j.reaction(s),
            JointKind::Distance(j) => j.reaction(s),
            JointKind::Weld(j) => j.reaction(),
            JointKind::Motor(j) => j.reaction(),
            JointKind::Mouse(j) => j.reaction(),
            JointKind::Filter => (Vec2::ZERO, 0.0),
        };
        (impulse * inv_h, torque * inv_h)
    }
}

/// The angle of `q` after `delta`, in (-π, π] (Box2D's `b2UnwindAngle` for one turn).
#[inline]
pub(crate) fn unwind(angle: f32) -> f32 {
    use std::f32::consts::PI;
    if angle < -PI {
        angle + 2.0 * PI
    } else if angle > PI {
        angle - 2.0 * PI
    } else {
        angle
    }
}

/// Current anchors (rotated by the substep rotations) and the current separation of the
/// anchors, B less A.
#[inline]
pub(crate) fn anchors(s: &JointStep, p: &Pair) -> (Vec2, Vec2, Vec2) {
    let ra = p.dqa.apply(s.frame_a.p);
    let rb = p.dqb.apply(s.frame_b.p);
    let d = (p.dpb - p.dpa) + s.delta_center + (rb - ra);
    (ra, rb, d)
}

/// The current angle of frame B relative to frame A.
#[inline]
pub(crate) fn relative_angle(s: &JointStep, p: &Pair) -> f32 {
    let qa = p.dqa.then_from(s.frame_a.q);
    let qb = p.dqb.then_from(s.frame_b.q);
    qa.inv_mul(qb).angle()
}

#[cfg(test)]
mod tests;
