//! Sliders along an axis fixed in body A: the prismatic joint (no relative rotation; Box2D
//! v3's `prismatic_joint.c`) and the wheel joint (free rotation, a suspension spring along
//! the axis; `wheel_joint.c`).

use glam::Vec2;

use super::{
    AngularMotor, JointContext, JointStep, LinearMotor, Pair, Spring, anchors, inverse, limit_row,
    relative_angle,
};
use crate::math::{cross, dot};
use crate::softness::Softness;

/// The axis in the world this substep, and the lever arms of a force along it and across it.
struct Axis {
    pub(super) axis: Vec2,
    pub(super) translation: f32,
    /// Lever arms of the axial force on A (from A's centre to B's anchor) and on B.
    a1: f32,
    a2: f32,
    /// Those of the perpendicular force.
    s1: f32,
    s2: f32,
    pub(super) perp: Vec2,
    pub(super) d: Vec2,
}

/// The axis fixed in A and its left perpendicular, in the world at the step's start (for
/// the reaction force).
fn start_axes(s: &JointStep) -> (Vec2, Vec2) {
    let axis = s.frame_a.q.apply(Vec2::X);
    (axis, Vec2::new(-axis.y, axis.x))
}

fn axis(s: &JointStep, p: &Pair) -> Axis {
    let (ra, rb, d) = anchors(s, p);
    let axis = p.dqa.apply(s.frame_a.q.apply(Vec2::X));
    let perp = Vec2::new(-axis.y, axis.x);
    Axis {
        axis,
        translation: dot(axis, d),
        a1: cross(d + ra, axis),
        a2: cross(rb, axis),
        s1: cross(d + ra, perp),
        s2: cross(rb, perp),
        perp,
        d,
    }
}

/// The relative speed along a direction with lever arms `l1`, `l2`.
#[inline]
fn speed_along(p: &Pair, dir: Vec2, l1: f32, l2: f32) -> f32 {
    dot(dir, p.vb - p.va) + l2 * p.wb - l1 * p.wa
}

/// Applies an impulse along `dir` with lever arms `l1`, `l2` and an extra torque impulse.
#[inline]
fn push_along(s: &JointStep, p: &mut Pair, dir: Vec2, l1: f32, l2: f32, impulse: f32, torque: f32) {
    let f = impulse * dir;
    p.va -= s.inv_mass_a * f;
    p.wa -= s.inv_i_a * (impulse * l1 + torque);
    p.vb += s.inv_mass_b * f;
    p.wb += s.inv_i_b * (impulse * l2 + torque);
}

/// The effective mass along a direction with lever arms `l1`, `l2`.
#[inline]
fn mass_along(s: &JointStep, l1: f32, l2: f32) -> f32 {
    inverse(s.inv_mass_a + s.inv_mass_b + s.inv_i_a * l1 * l1 + s.inv_i_b * l2 * l2)
}

/// The lower and upper limit rows along the axis (Box2D's, with a speculative range of a
/// quarter of the limit's span).
#[allow(clippy::too_many_arguments)]
fn limits(
    s: &JointStep,
    p: &mut Pair,
    ax: &Axis,
    [lower, upper]: [f32; 2],
    impulses: &mut [f32; 2],
    mass: f32,
    ctx: &JointContext,
    bias: bool,
) {
    let speculative = 0.25 * (upper - lower);
    let c = ax.translation - lower;
    if c < speculative {
        // A speculative bound no faster than a metre a substep (Box2D's `safe` length).
        let (b, m, i) = limit_row(c.min(1.0), bias, &s.softness, ctx.inv_h);
        let old = impulses[0];
        let cdot = speed_along(p, ax.axis, ax.a1, ax.a2);
        impulses[0] = (old - m * mass * (cdot + b) - i * old).max(0.0);
        push_along(s, p, ax.axis, ax.a1, ax.a2, impulses[0] - old, 0.0);
    } else {
        impulses[0] = 0.0;
    }
    let c = upper - ax.translation;
    if c < speculative {
        let (b, m, i) = limit_row(c.min(1.0), bias, &s.softness, ctx.inv_h);
        let old = impulses[1];
        let cdot = -speed_along(p, ax.axis, ax.a1, ax.a2);
        impulses[1] = (old - m * mass * (cdot + b) - i * old).max(0.0);
        push_along(s, p, ax.axis, ax.a1, ax.a2, -(impulses[1] - old), 0.0);
    } else {
        impulses[1] = 0.0;
    }
}

/// A spring row along the axis towards `target`; it acts in the relax pass too.
fn spring_row(
    s: &JointStep,
    p: &mut Pair,
    ax: &Axis,
    soft: &Softness,
    target: f32,
    impulse: &mut f32,
    mass: f32,
) {
    let c = ax.translation - target;
    let cdot = speed_along(p, ax.axis, ax.a1, ax.a2);
    let delta =
        -soft.mass_scale * mass * (cdot + soft.bias_rate * c) - soft.impulse_scale * *impulse;
    *impulse += delta;
    push_along(s, p, ax.axis, ax.a1, ax.a2, delta, 0.0);
}

/// A slider without rotation.
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Prismatic {
    /// Bounds of the translation along the axis (m).
    pub limit: Option<[f32; 2]>,
    /// Drives the speed along the axis.
    pub motor: Option<LinearMotor>,
    /// Pulls the translation back to `target_translation`.
    pub spring: Option<Spring>,
    /// The spring's rest translation (m).
    pub target_translation: f32,
    /// Across the axis and the angle.
    pub(super) impulse: Vec2,
    pub(super) spring_impulse: f32,
    pub(super) motor_impulse: f32,
    /// Lower, upper.
    pub(super) limit_impulse: [f32; 2],
    #[serde(skip)]
    pub(super) spring_softness: Softness,
}

impl Prismatic {
    pub(super) fn prepare(&mut self, _s: &JointStep, ctx: &JointContext) {
        self.spring_softness = Spring::softness(self.spring, ctx.h);
        if !ctx.warm_starting {
            self.reset();
        }
    }

    pub(super) fn reset(&mut self) {
        self.impulse = Vec2::ZERO;
        self.spring_impulse = 0.0;
        self.motor_impulse = 0.0;
        self.limit_impulse = [0.0; 2];
    }

    #[inline(always)]
    pub(super) fn warm_start(&self, s: &JointStep, p: &mut Pair) {
        let ax = axis(s, p);
        let axial = self.spring_impulse + self.motor_impulse + self.limit_impulse[0]
            - self.limit_impulse[1];
        push_along(s, p, ax.axis, ax.a1, ax.a2, axial, 0.0);
        push_along(s, p, ax.perp, ax.s1, ax.s2, self.impulse.x, self.impulse.y);
    }

    #[inline(always)]
    pub(super) fn solve(&mut self, s: &JointStep, p: &mut Pair, ctx: &JointContext, bias: bool) {
        let ax = axis(s, p);
        let axial_mass = mass_along(s, ax.a1, ax.a2);
        if self.spring.is_some() {
            let soft = self.spring_softness;
            let target = self.target_translation;
            spring_row(
                s,
                p,
                &ax,
                &soft,
                target,
                &mut self.spring_impulse,
                axial_mass,
            );
        }
        if let Some(motor) = self.motor {
            let cdot = speed_along(p, ax.axis, ax.a1, ax.a2);
            let max = ctx.h * motor.max_force;
            let old = self.motor_impulse;
            self.motor_impulse =
                crate::math::clamp_within(old + axial_mass * (motor.speed - cdot), max);
            push_along(s, p, ax.axis, ax.a1, ax.a2, self.motor_impulse - old, 0.0);
        }
        if let Some(limit) = self.limit {
            limits(
                s,
                p,
                &ax,
                limit,
                &mut self.limit_impulse,
                axial_mass,
                ctx,
                bias,
            );
        }
        // Across the axis and the angle, as one 2×2 block.
        let cdot = Vec2::new(speed_along(p, ax.perp, ax.s1, ax.s2), p.wb - p.wa);
        let (b, mass_scale, impulse_scale) = if bias {
            let soft = &s.softness;
            let c = Vec2::new(dot(ax.perp, ax.d), relative_angle(s, p));
            (soft.bias_rate * c, soft.mass_scale, soft.impulse_scale)
        } else {
            (Vec2::ZERO, 1.0, 0.0)
        };
        let k11 =
            s.inv_mass_a + s.inv_mass_b + s.inv_i_a * ax.s1 * ax.s1 + s.inv_i_b * ax.s2 * ax.s2;
        let k12 = s.inv_i_a * ax.s1 + s.inv_i_b * ax.s2;
        // Bodies that cannot turn: the angular row is moot, keep the matrix invertible.
        let k22 = match s.inv_i_a + s.inv_i_b {
            0.0 => 1.0,
            k => k,
        };
        let x = super::solve22([k11, k12, k22], cdot + b);
        let impulse = -mass_scale * x - impulse_scale * self.impulse;
        self.impulse += impulse;
        push_along(s, p, ax.perp, ax.s1, ax.s2, impulse.x, impulse.y);
    }

    pub(super) fn reaction(&self, s: &JointStep) -> (Vec2, f32) {
        let (axis, perp) = start_axes(s);
        let axial = self.spring_impulse + self.motor_impulse + self.limit_impulse[0]
            - self.limit_impulse[1];
        (self.impulse.x * perp + axial * axis, self.impulse.y)
    }
}

/// A wheel on a suspension: B slides along the axis on a spring and turns freely.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Wheel {
    /// Bounds of the translation along the axis (m).
    pub limit: Option<[f32; 2]>,
    /// Drives B's rotation relative to A.
    pub motor: Option<AngularMotor>,
    /// The suspension; `None` makes the axis rigid.
    pub spring: Option<Spring>,
    pub(super) perp_impulse: f32,
    pub(super) spring_impulse: f32,
    pub(super) motor_impulse: f32,
    pub(super) limit_impulse: [f32; 2],
    #[serde(skip)]
    pub(super) spring_softness: Softness,
    #[serde(skip)]
    pub(super) motor_mass: f32,
}

impl Default for Wheel {
    /// Box2D's default wheel: a 1 Hz suspension with damping ratio 0.7.
    fn default() -> Wheel {
        Wheel {
            limit: None,
            motor: None,
            spring: Some(Spring {
                hertz: 1.0,
                damping_ratio: 0.7,
            }),
            perp_impulse: 0.0,
            spring_impulse: 0.0,
            motor_impulse: 0.0,
            limit_impulse: [0.0; 2],
            spring_softness: Softness::default(),
            motor_mass: 0.0,
        }
    }
}

impl Wheel {
    pub(super) fn prepare(&mut self, s: &JointStep, ctx: &JointContext) {
        self.spring_softness = Spring::softness(self.spring, ctx.h);
        self.motor_mass = inverse(s.inv_i_a + s.inv_i_b);
        if !ctx.warm_starting {
            self.reset();
        }
    }

    pub(super) fn reset(&mut self) {
        self.perp_impulse = 0.0;
        self.spring_impulse = 0.0;
        self.motor_impulse = 0.0;
        self.limit_impulse = [0.0; 2];
    }

    #[inline(always)]
    pub(super) fn warm_start(&self, s: &JointStep, p: &mut Pair) {
        let ax = axis(s, p);
        let axial = self.spring_impulse + self.limit_impulse[0] - self.limit_impulse[1];
        push_along(s, p, ax.axis, ax.a1, ax.a2, axial, self.motor_impulse);
        push_along(s, p, ax.perp, ax.s1, ax.s2, self.perp_impulse, 0.0);
    }

    #[inline(always)]
    pub(super) fn solve(&mut self, s: &JointStep, p: &mut Pair, ctx: &JointContext, bias: bool) {
        let ax = axis(s, p);
        let axial_mass = mass_along(s, ax.a1, ax.a2);
        if let (Some(motor), false) = (self.motor, s.inv_i_a + s.inv_i_b == 0.0) {
            let cdot = p.wb - p.wa - motor.speed;
            let max = ctx.h * motor.max_torque;
            let old = self.motor_impulse;
            self.motor_impulse = crate::math::clamp_within(old - self.motor_mass * cdot, max);
            p.turn(s, self.motor_impulse - old);
        }
        if self.spring.is_some() {
            let soft = self.spring_softness;
            spring_row(s, p, &ax, &soft, 0.0, &mut self.spring_impulse, axial_mass);
        }
        if let Some(limit) = self.limit {
            limits(
                s,
                p,
                &ax,
                limit,
                &mut self.limit_impulse,
                axial_mass,
                ctx,
                bias,
            );
        }
        // Across the axis: the wheel stays on its line.
        let cdot = speed_along(p, ax.perp, ax.s1, ax.s2);
        let (b, mass_scale, impulse_scale) = if bias {
            let soft = &s.softness;
            (
                soft.bias_rate * dot(ax.perp, ax.d),
                soft.mass_scale,
                soft.impulse_scale,
            )
        } else {
            (0.0, 1.0, 0.0)
        };
        let mass = mass_along(s, ax.s1, ax.s2);
        let impulse = -mass_scale * mass * (cdot + b) - impulse_scale * self.perp_impulse;
        self.perp_impulse += impulse;
        push_along(s, p, ax.perp, ax.s1, ax.s2, impulse, 0.0);
        // Without a spring the axis is rigid: a second row along it.
        if self.spring.is_none() {
            let cdot = speed_along(p, ax.axis, ax.a1, ax.a2);
            let (b, m, i) = if bias {
                let soft = &s.softness;
                (
                    soft.bias_rate * ax.translation,
                    soft.mass_scale,
                    soft.impulse_scale,
                )
            } else {
                (0.0, 1.0, 0.0)
            };
            let impulse = -m * axial_mass * (cdot + b) - i * self.spring_impulse;
            self.spring_impulse += impulse;
            push_along(s, p, ax.axis, ax.a1, ax.a2, impulse, 0.0);
        }
    }

    pub(super) fn reaction(&self, s: &JointStep) -> (Vec2, f32) {
        let (axis, perp) = start_axes(s);
        let axial = self.spring_impulse + self.limit_impulse[0] - self.limit_impulse[1];
        (self.perp_impulse * perp + axial * axis, self.motor_impulse)
    }
}
