//! The distance joint: a rigid rod, a spring of a rest length, and limits on the length
//! (a rope is a slack spring with an upper limit; Box2D v3's `distance_joint.c`).

use glam::Vec2;

use super::{JointContext, JointStep, Pair, Spring, anchors, inverse, limit_row};
use crate::math::{cross, dot, normalize_and_length};
use crate::softness::Softness;

/// Keeps two anchors a length apart.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Distance {
    /// The rest length (m).
    pub length: f32,
    /// Bounds of the length (m); meaningful with a spring.
    pub limit: Option<[f32; 2]>,
    /// Makes the length soft; a hertz of 0 is a slack spring (with a limit, a rope).
    pub spring: Option<Spring>,
    pub(super) impulse: f32,
    pub(super) lower_impulse: f32,
    pub(super) upper_impulse: f32,
    #[serde(skip)]
    pub(super) axial_mass: f32,
    #[serde(skip)]
    pub(super) spring_softness: Softness,
}

impl Distance {
    pub(super) fn prepare(&mut self, s: &JointStep, ctx: &JointContext) {
        let (ra, rb) = (s.frame_a.p, s.frame_b.p);
        let (axis, _) = normalize_and_length(rb - ra + s.delta_center);
        let (cra, crb) = (cross(ra, axis), cross(rb, axis));
        self.axial_mass =
            inverse(s.inv_mass_a + s.inv_mass_b + s.inv_i_a * cra * cra + s.inv_i_b * crb * crb);
        self.spring_softness = Spring::softness(self.spring, ctx.h);
        if !ctx.warm_starting {
            self.reset();
        }
    }

    pub(super) fn reset(&mut self) {
        self.impulse = 0.0;
        self.lower_impulse = 0.0;
        self.upper_impulse = 0.0;
    }

    fn total(&self) -> f32 {
        self.impulse + self.lower_impulse - self.upper_impulse
    }

    #[inline(always)]
    pub(super) fn warm_start(&self, s: &JointStep, p: &mut Pair) {
        let (ra, rb, d) = anchors(s, p);
        let (axis, _) = normalize_and_length(d);
        p.apply(s, ra, rb, self.total() * axis, 0.0);
    }

    /// Whether the length is soft: a spring, unless the limits pin it.
    fn soft(&self) -> bool {
        self.spring.is_some() && self.limit.is_none_or(|[lo, hi]| lo < hi)
    }

    #[inline(always)]
    pub(super) fn solve(&mut self, s: &JointStep, p: &mut Pair, ctx: &JointContext, bias: bool) {
        let (ra, rb, d) = anchors(s, p);
        let (axis, length) = normalize_and_length(d);
        let speed = |p: &Pair| dot(axis, p.relative_velocity(ra, rb));
        if self.soft() {
            if self.spring.is_some_and(|sp| sp.hertz > 0.0) {
                // A real spring: it acts in the relax pass too.
                let soft = self.spring_softness;
                let c = length - self.length;
                let delta = -soft.mass_scale * self.axial_mass * (speed(p) + soft.bias_rate * c)
                    - soft.impulse_scale * self.impulse;
                self.impulse += delta;
                p.apply(s, ra, rb, delta * axis, 0.0);
            }
            if let Some([lower, upper]) = self.limit {
                let (b, m, i) = limit_row(length - lower, bias, &s.softness, ctx.inv_h);
                let old = self.lower_impulse;
                let delta = -m * self.axial_mass * (speed(p) + b) - i * old;
                self.lower_impulse = (old + delta).max(0.0);
                p.apply(s, ra, rb, (self.lower_impulse - old) * axis, 0.0);
                let (b, m, i) = limit_row(upper - length, bias, &s.softness, ctx.inv_h);
                let old = self.upper_impulse;
                let delta = -m * self.axial_mass * (-speed(p) + b) - i * old;
                self.upper_impulse = (old + delta).max(0.0);
                p.apply(s, ra, rb, -(self.upper_impulse - old) * axis, 0.0);
            }
        } else {
            // Rigid: a rod of the rest length (or of the pinned limit).
            let rest = match (self.spring, self.limit) {
                (Some(_), Some([lo, _])) => lo,
                _ => self.length,
            };
            let (b, m, i) = if bias {
                let soft = &s.softness;
                (
                    soft.bias_rate * (length - rest),
                    soft.mass_scale,
                    soft.impulse_scale,
                )
            } else {
                (0.0, 1.0, 0.0)
            };
            let delta = -m * self.axial_mass * (speed(p) + b) - i * self.impulse;
            self.impulse += delta;
            p.apply(s, ra, rb, delta * axis, 0.0);
        }
    }

    pub(super) fn reaction(&self, s: &JointStep) -> (Vec2, f32) {
        let (axis, _) = normalize_and_length(s.frame_b.p - s.frame_a.p + s.delta_center);
        (self.total() * axis, 0.0)
    }
}
