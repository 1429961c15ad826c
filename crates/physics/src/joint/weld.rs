//! The weld joint: B glued to A, each of the linear and the angular part rigid (the joint
//! softness) or a spring of its own hertz (Box2D v3's `weld_joint.c`, solved as two blocks
//! since one 3×3 block goes wrong with mixed stiffness).

use glam::Vec2;

use super::{JointContext, JointStep, Pair, anchors, inverse, point_mass, relative_angle, solve22};
use crate::softness::Softness;

/// Glues B to A.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Weld {
    /// Linear stiffness (Hz; 0 is rigid).
    pub linear_hertz: f32,
    /// Angular stiffness (Hz; 0 is rigid).
    pub angular_hertz: f32,
    /// Linear damping ratio.
    pub linear_damping_ratio: f32,
    /// Angular damping ratio.
    pub angular_damping_ratio: f32,
    pub(super) linear_impulse: Vec2,
    pub(super) angular_impulse: f32,
    #[serde(skip)]
    pub(super) axial_mass: f32,
    #[serde(skip)]
    pub(super) linear_spring: Softness,
    #[serde(skip)]
    pub(super) angular_spring: Softness,
}

impl Weld {
    pub(super) fn prepare(&mut self, s: &JointStep, ctx: &JointContext) {
        self.axial_mass = inverse(s.inv_i_a + s.inv_i_b);
        let spring = |hertz: f32, zeta: f32| {
            if hertz == 0.0 {
                s.softness
            } else {
                Softness::new(hertz, zeta, ctx.h)
            }
        };
        self.linear_spring = spring(self.linear_hertz, self.linear_damping_ratio);
        self.angular_spring = spring(self.angular_hertz, self.angular_damping_ratio);
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
    pub(super) fn solve(&mut self, s: &JointStep, p: &mut Pair, bias: bool) {
        // Angular. A spring acts in the relax pass too; a rigid part only with bias.
        {
            let (b, m, i) = if bias || self.angular_hertz > 0.0 {
                let soft = &self.angular_spring;
                (
                    soft.bias_rate * relative_angle(s, p),
                    soft.mass_scale,
                    soft.impulse_scale,
                )
            } else {
                (0.0, 1.0, 0.0)
            };
            let cdot = p.wb - p.wa;
            let impulse = -m * self.axial_mass * (cdot + b) - i * self.angular_impulse;
            self.angular_impulse += impulse;
            p.turn(s, impulse);
        }
        // Linear.
        let (ra, rb, d) = anchors(s, p);
        let (b, m, i) = if bias || self.linear_hertz > 0.0 {
            let soft = &self.linear_spring;
            (soft.bias_rate * d, soft.mass_scale, soft.impulse_scale)
        } else {
            (Vec2::ZERO, 1.0, 0.0)
        };
        let cdot = p.relative_velocity(ra, rb);
        let x = solve22(point_mass(s, ra, rb), cdot + b);
        let impulse = -m * x - i * self.linear_impulse;
        self.linear_impulse += impulse;
        p.apply(s, ra, rb, impulse, 0.0);
    }

    pub(super) fn reaction(&self) -> (Vec2, f32) {
        (self.linear_impulse, self.angular_impulse)
    }
}
