//! The revolute joint: a shared point, with an optional spring, motor and limit on the angle
//! of B relative to A (Box2D v3's `revolute_joint.c`).

use glam::Vec2;

use super::{
    AngularMotor, JointContext, JointStep, Pair, Spring, anchors, inverse, limit_row, point_mass,
    relative_angle, solve22, unwind,
};
use crate::softness::Softness;

/// A hinge.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Revolute {
    /// Bounds of the angle of B relative to A, counted from the start (rad).
    pub limit: Option<[f32; 2]>,
    /// Drives the angle's rate.
    pub motor: Option<AngularMotor>,
    /// Pulls the angle back to `target_angle`.
    pub spring: Option<Spring>,
    /// The spring's rest angle (rad; 0 is the start).
    pub target_angle: f32,
    pub(crate) linear_impulse: Vec2,
    pub(crate) spring_impulse: f32,
    pub(crate) motor_impulse: f32,
    pub(crate) lower_impulse: f32,
    pub(crate) upper_impulse: f32,
    #[serde(skip)]
    pub(crate) axial_mass: f32,
    #[serde(skip)]
    pub(crate) spring_softness: Softness,
    /// Which angular rows `solve` runs this step ([`Revolute::SPRING`], [`Revolute::MOTOR`],
    /// [`Revolute::LIMIT`]): none where neither body can turn. Set by `prepare`.
    #[serde(skip)]
    pub(crate) rows: u8,
}

impl Revolute {
    /// A free hinge.
    pub fn new() -> Revolute {
        Revolute::default()
    }

    /// `rows`' bit for the spring.
    pub(crate) const SPRING: u8 = 1;
    /// `rows`' bit for the motor.
    pub(crate) const MOTOR: u8 = 2;
    /// `rows`' bit for the limit.
    pub(crate) const LIMIT: u8 = 4;

    pub(super) fn prepare(&mut self, s: &JointStep, ctx: &JointContext) {
        self.axial_mass = inverse(s.inv_i_a + s.inv_i_b);
        let turns = s.inv_i_a + s.inv_i_b != 0.0;
        let row = |on: bool, bit: u8| if on && turns { bit } else { 0 };
        self.rows = row(self.spring.is_some(), Self::SPRING)
            | row(self.motor.is_some(), Self::MOTOR)
            | row(self.limit.is_some(), Self::LIMIT);
        self.spring_softness = Spring::softness(self.spring, ctx.h);
        if !ctx.warm_starting {
            self.reset();
        }
    }

    pub(super) fn reset(&mut self) {
        self.linear_impulse = Vec2::ZERO;
        self.spring_impulse = 0.0;
        self.motor_impulse = 0.0;
        self.lower_impulse = 0.0;
        self.upper_impulse = 0.0;
    }

    #[inline(always)]
    pub(super) fn warm_start(&self, s: &JointStep, p: &mut Pair) {
        let ra = p.dqa.apply(s.frame_a.p);
        let rb = p.dqb.apply(s.frame_b.p);
        let axial =
            self.spring_impulse + self.motor_impulse + self.lower_impulse - self.upper_impulse;
        p.apply(s, ra, rb, self.linear_impulse, axial);
    }

    #[inline(always)]
    pub(super) fn solve(&mut self, s: &JointStep, p: &mut Pair, ctx: &JointContext, bias: bool) {
        let fixed_rotation = s.inv_i_a + s.inv_i_b == 0.0;
        // The angle costs an arctangent: only the spring and the limit read it.
        let angle = if self.spring.is_some() || self.limit.is_some() {
            relative_angle(s, p)
        } else {
            0.0
        };
        if self.spring.is_some() && !fixed_rotation {
            // A real spring: it acts in the relax pass too.
            let c = unwind(angle - self.target_angle);
            let soft = self.spring_softness;
            let cdot = p.wb - p.wa;
            let impulse = -soft.mass_scale * self.axial_mass * (cdot + soft.bias_rate * c)
                - soft.impulse_scale * self.spring_impulse;
            self.spring_impulse += impulse;
            p.turn(s, impulse);
        }
        if let (Some(motor), false) = (self.motor, fixed_rotation) {
            let cdot = p.wb - p.wa - motor.speed;
            let max = ctx.h * motor.max_torque;
            let old = self.motor_impulse;
            self.motor_impulse = crate::math::clamp_within(old - self.axial_mass * cdot, max);
            p.turn(s, self.motor_impulse - old);
        }
        if let (Some([lower, upper]), false) = (self.limit, fixed_rotation) {
            let (bias_l, mass_l, imp_l) = limit_row(angle - lower, bias, &s.softness, ctx.inv_h);
            let cdot = p.wb - p.wa;
            let old = self.lower_impulse;
            let impulse = -mass_l * self.axial_mass * (cdot + bias_l) - imp_l * old;
            self.lower_impulse = (old + impulse).max(0.0);
            p.turn(s, self.lower_impulse - old);
            // The upper bound with signs flipped, so C and the impulse stay positive.
            let (bias_u, mass_u, imp_u) = limit_row(upper - angle, bias, &s.softness, ctx.inv_h);
            let cdot = p.wa - p.wb;
            let old = self.upper_impulse;
            let impulse = -mass_u * self.axial_mass * (cdot + bias_u) - imp_u * old;
            self.upper_impulse = (old + impulse).max(0.0);
            p.turn(s, -(self.upper_impulse - old));
        }
        // The shared point, as one 2×2 block.
        let (ra, rb, d) = anchors(s, p);
        let cdot = p.relative_velocity(ra, rb);
        let (b, mass_scale, impulse_scale) = if bias {
            let soft = &s.softness;
            (soft.bias_rate * d, soft.mass_scale, soft.impulse_scale)
        } else {
            (Vec2::ZERO, 1.0, 0.0)
        };
        let x = solve22(point_mass(s, ra, rb), cdot + b);
        let impulse = -mass_scale * x - impulse_scale * self.linear_impulse;
        self.linear_impulse += impulse;
        p.apply(s, ra, rb, impulse, 0.0);
    }

    pub(super) fn reaction(&self) -> (Vec2, f32) {
        (
            self.linear_impulse,
            self.motor_impulse + self.lower_impulse - self.upper_impulse,
        )
    }

    /// The motor's last impulse per substep times the substep rate: its torque.
    pub fn motor_impulse(&self) -> f32 {
        self.motor_impulse
    }
}
