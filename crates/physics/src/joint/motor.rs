//! Joints that drive a body towards a pose: the motor joint (B towards an offset pose in A's
//! frame, with bounded force and torque: Box2D v3.0's `motor_joint.c`) and the mouse joint
//! (a point of B towards a target, a soft spring with a bounded force, and a little angular
//! damping so a dragged body does not spin up: v3.0's `mouse_joint.c`).

use glam::Vec2;

use super::{JointBody, JointContext, JointStep, Pair, inverse, point_mass, solve22, unwind};
use crate::softness::Softness;

/// Drives B towards a pose relative to A.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Motor {
    /// Where B's origin should be, in A's frame (m).
    pub linear_offset: Vec2,
    /// B's angle less A's that it should have (rad).
    pub angular_offset: f32,
    /// Most force (N).
    pub max_force: f32,
    /// Most torque (N·m).
    pub max_torque: f32,
    /// The share of the pose error corrected per second's worth of substeps (0 to 1).
    pub correction_factor: f32,
    pub(super) linear_impulse: Vec2,
    pub(super) angular_impulse: f32,
    #[serde(skip)]
    pub(super) angular_mass: f32,
    /// The angle error at the step's start.
    #[serde(skip)]
    pub(super) delta_angle: f32,
    /// The pose error of the centres at the step's start.
    #[serde(skip)]
    pub(super) delta_center: Vec2,
}

impl Motor {
    pub(super) fn prepare(
        &mut self,
        s: &JointStep,
        ctx: &JointContext,
        a: &JointBody,
        b: &JointBody,
    ) {
        self.angular_mass = inverse(s.inv_i_a + s.inv_i_b);
        // The joint frames sit at each body's origin, so frame B less frame A is the
        // origins' offset; the target offset, turned into the world, is taken off it.
        self.delta_center = s.delta_center - a.q.apply(self.linear_offset);
        self.delta_angle = unwind(a.q.inv_mul(b.q).angle() - self.angular_offset);
        if !ctx.warm_starting {
            self.reset();
        }
    }

    pub(super) fn reset(&mut self) {
        self.linear_impulse = Vec2::ZERO;
        self.angular_impulse = 0.0;
    }

    #[inline(always)]
    pub(super) fn warm_start(&self, s: &JointStep, p: &mut Pair) {
        let ra = p.dqa.apply(s.frame_a.p);
        let rb = p.dqb.apply(s.frame_b.p);
        p.apply(s, ra, rb, self.linear_impulse, self.angular_impulse);
    }

    #[inline(always)]
    pub(super) fn solve(&mut self, s: &JointStep, p: &mut Pair, ctx: &JointContext) {
        let k = self.correction_factor * ctx.inv_h;
        {
            let angle = unwind(self.delta_angle + p.dqa.inv_mul(p.dqb).angle());
            let cdot = p.wb - p.wa + k * angle;
            let max = ctx.h * self.max_torque;
            let old = self.angular_impulse;
            self.angular_impulse = crate::math::clamp_within(old - self.angular_mass * cdot, max);
            p.turn(s, self.angular_impulse - old);
        }
        let ra = p.dqa.apply(s.frame_a.p);
        let rb = p.dqb.apply(s.frame_b.p);
        let separation = (p.dpb - p.dpa) + (rb - ra) + self.delta_center;
        let cdot = p.relative_velocity(ra, rb) + k * separation;
        let impulse = -solve22(point_mass(s, ra, rb), cdot);
        let old = self.linear_impulse;
        let max = ctx.h * self.max_force;
        self.linear_impulse = (old + impulse).clamp_length_max(max);
        p.apply(s, ra, rb, self.linear_impulse - old, 0.0);
    }

    pub(super) fn reaction(&self) -> (Vec2, f32) {
        (self.linear_impulse, self.angular_impulse)
    }
}

/// Pulls a point of B towards a target in the world.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Mouse {
    /// Where the point is pulled to (m, world).
    pub target: Vec2,
    /// Stiffness (Hz).
    pub hertz: f32,
    /// Damping ratio.
    pub damping_ratio: f32,
    /// Most force (N).
    pub max_force: f32,
    pub(super) linear_impulse: Vec2,
    pub(super) angular_impulse: f32,
    #[serde(skip)]
    pub(super) linear_softness: Softness,
    #[serde(skip)]
    pub(super) angular_softness: Softness,
    #[serde(skip)]
    pub(super) angular_mass: f32,
}

impl Mouse {
    /// A pull towards `target` of `hertz` and `damping_ratio`, at most `max_force`.
    pub fn new(target: Vec2, hertz: f32, damping_ratio: f32, max_force: f32) -> Mouse {
        Mouse {
            target,
            hertz,
            damping_ratio,
            max_force,
            ..Mouse::default()
        }
    }

    pub(super) fn prepare(&mut self, s: &mut JointStep, ctx: &JointContext, b: &JointBody) {
        // Only B takes part: A's terms vanish.
        s.inv_mass_a = 0.0;
        s.inv_i_a = 0.0;
        s.dynamic_a = false;
        s.frame_a.p = Vec2::ZERO;
        s.delta_center = b.center - self.target;
        self.linear_softness = Softness::new(self.hertz, self.damping_ratio, ctx.h);
        // A soft brake on B's spin (Box2D's 0.5 Hz, damping ratio 0.1).
        self.angular_softness = Softness::new(0.5, 0.1, ctx.h);
        self.angular_mass = inverse(s.inv_i_b);
        if !ctx.warm_starting {
            self.reset();
        }
    }

    pub(super) fn reset(&mut self) {
        self.linear_impulse = Vec2::ZERO;
        self.angular_impulse = 0.0;
    }

    #[inline(always)]
    pub(super) fn warm_start(&self, s: &JointStep, p: &mut Pair) {
        let rb = p.dqb.apply(s.frame_b.p);
        p.apply(s, Vec2::ZERO, rb, self.linear_impulse, self.angular_impulse);
    }

    #[inline(always)]
    pub(super) fn solve(&mut self, s: &JointStep, p: &mut Pair, ctx: &JointContext) {
        {
            let soft = &self.angular_softness;
            let impulse = -soft.mass_scale * self.angular_mass * p.wb
                - soft.impulse_scale * self.angular_impulse;
            self.angular_impulse += impulse;
            p.turn(s, impulse);
        }
        let rb = p.dqb.apply(s.frame_b.p);
        let cdot = p.vb + crate::math::cross_sv(p.wb, rb);
        let separation = p.dpb + rb + s.delta_center;
        let soft = &self.linear_softness;
        let x = solve22(
            point_mass(s, Vec2::ZERO, rb),
            cdot + soft.bias_rate * separation,
        );
        let old = self.linear_impulse;
        let impulse = -soft.mass_scale * x - soft.impulse_scale * old;
        let max = ctx.h * self.max_force;
        self.linear_impulse = (old + impulse).clamp_length_max(max);
        p.apply(s, Vec2::ZERO, rb, self.linear_impulse - old, 0.0);
    }

    pub(super) fn reaction(&self) -> (Vec2, f32) {
        (self.linear_impulse, self.angular_impulse)
    }
}
