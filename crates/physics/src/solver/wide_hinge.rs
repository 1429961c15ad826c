//! Hinges (revolute joints) eight at a time: each lane does the arithmetic of
//! `Revolute::solve` and `Revolute::warm_start` in the same order, so the bits are the scalar
//! path's. A lane without a spring, motor or limit (or whose bodies cannot turn) leaves its
//! bodies as that row would not have touched them: the row is computed in every lane and
//! kept only where the joint has it. Box2D v3 solves every joint one at a time.
//!
//! Measured (interleaved runs, same state hashes): `joint_grid`'s 19,794 free hinges,
//! substeps 3.6 -> 2.0 ms at one thread; `rain`'s ragdolls (limit, spring and motor friction
//! on every hinge) 2.43 -> 1.52 ms at one thread and 1.38 -> 0.92 ms at two.

use glam::Vec2;
use wide::f32x8;

#[cfg(target_arch = "x86_64")]
use super::lanes::Avx;
use super::lanes::{Lanes, atan2};
use super::wide::{LANES, WideBody, gather, scatter};
use crate::joint::{Joint, JointContext, Revolute};
use crate::threads::parallel::BodyStates;

/// A pass of the joint solver: of each joint in turn, and of [`hinges`] eight at a time.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HingePass {
    /// Apply the accumulated impulses again.
    WarmStart,
    /// The soft solve, which also removes position error.
    Solve,
    /// The rigid relax pass.
    Relax,
}

/// One pass over eight hinges of one colour (no two share a dynamic body), whose angular
/// rows are `rows` (`Revolute::rows`, lane by lane). The joints' data is read into lanes as
/// it is used (the joints stay the solver's live copies).
pub fn hinges(
    group: &mut [Joint],
    rows: [u8; LANES],
    states: &BodyStates<'_>,
    pass: HingePass,
    ctx: &JointContext,
    use_avx: bool,
) {
    // Free hinges (no lane has an angular row, as in `joint_grid`) get a kernel without
    // those rows: with them compiled in, joint_grid's substeps took 2.15 ms, not 1.9.
    let free = rows == [0; LANES];
    #[cfg(target_arch = "x86_64")]
    if use_avx && super::lanes::avx2_available() {
        // SAFETY: the CPU has AVX2 (checked just above).
        #[allow(unsafe_code)]
        return unsafe {
            if free {
                hinges_avx2::<false>(group, rows, states, pass, ctx)
            } else {
                hinges_avx2::<true>(group, rows, states, pass, ctx)
            }
        };
    }
    let _ = use_avx;
    if free {
        hinges_with::<f32x8, false>(group, rows, states, pass, ctx)
    } else {
        hinges_with::<f32x8, true>(group, rows, states, pass, ctx)
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn hinges_avx2<const ANGULAR: bool>(
    group: &mut [Joint],
    rows: [u8; LANES],
    states: &BodyStates<'_>,
    pass: HingePass,
    ctx: &JointContext,
) {
    hinges_with::<Avx, ANGULAR>(group, rows, states, pass, ctx)
}

#[inline(always)]
fn hinges_with<V: Lanes, const ANGULAR: bool>(
    group: &mut [Joint],
    rows: [u8; LANES],
    states: &BodyStates<'_>,
    pass: HingePass,
    ctx: &JointContext,
) {
    debug_assert!(group.len() == LANES && group.iter().all(|j| j.hinge_rows().is_some()));
    // One field of the eight joints, in lanes.
    macro_rules! lanes {
        ($j:ident => $e:expr) => {
            V::load(f32x8::new(std::array::from_fn(|l| {
                let $j: &Joint = &group[l];
                $e
            })))
        };
    }
    let body_a: [u32; LANES] = std::array::from_fn(|l| group[l].body_a);
    let body_b: [u32; LANES] = std::array::from_fn(|l| group[l].body_b);
    let dynamic = |side: fn(&Joint) -> bool| {
        (0..LANES).fold(0u8, |m, l| m | (u8::from(side(&group[l])) << l))
    };
    let (dynamic_a, dynamic_b) = (dynamic(|j| j.step.dynamic_a), dynamic(|j| j.step.dynamic_b));
    let mut a: WideBody<V> = gather::<V>(states, &body_a);
    let mut b: WideBody<V> = gather::<V>(states, &body_b);
    let (ma, ia) = (lanes!(j => j.step.inv_mass_a), lanes!(j => j.step.inv_i_a));
    let (mb, ib) = (lanes!(j => j.step.inv_mass_b), lanes!(j => j.step.inv_i_b));
    let (fax, fay) = (
        lanes!(j => j.step.frame_a.p.x),
        lanes!(j => j.step.frame_a.p.y),
    );
    let (fbx, fby) = (
        lanes!(j => j.step.frame_b.p.x),
        lanes!(j => j.step.frame_b.p.y),
    );
    // The anchors turned by the substep rotations (`Rot::apply`).
    let (rax, ray) = (a.dqc * fax - a.dqs * fay, a.dqs * fax + a.dqc * fay);
    let (rbx, rby) = (b.dqc * fbx - b.dqs * fby, b.dqs * fbx + b.dqc * fby);
    let (lix, liy) = (
        lanes!(j => j.hinge().linear_impulse.x),
        lanes!(j => j.hinge().linear_impulse.y),
    );
    let (px, py, torque) = match pass {
        HingePass::WarmStart => {
            let axial = lanes!(j => {
                let r = j.hinge();
                r.spring_impulse + r.motor_impulse + r.lower_impulse - r.upper_impulse
            });
            (lix, liy, axial)
        }
        HingePass::Solve | HingePass::Relax => {
            let zero = V::splat(0.0);
            let one = V::splat(1.0);
            let bias = pass == HingePass::Solve;
            // The rigid rows' softness (`JointStep::softness`); the relax pass has none.
            let (rate, soft_mass, soft_impulse) = if bias {
                (
                    lanes!(j => j.step.softness.bias_rate),
                    lanes!(j => j.step.softness.mass_scale),
                    lanes!(j => j.step.softness.impulse_scale),
                )
            } else {
                (zero, one, zero)
            };
            if ANGULAR {
                let soft = (rate, soft_mass, soft_impulse);
                angular_rows(group, rows, (&mut a, &mut b), (ia, ib), bias, ctx, soft);
            }
            // `anchors`: the anchors' separation, B less A.
            let dcx = lanes!(j => j.step.delta_center.x);
            let dcy = lanes!(j => j.step.delta_center.y);
            let dx = ((b.dpx - a.dpx) + dcx) + (rbx - rax);
            let dy = ((b.dpy - a.dpy) + dcy) + (rby - ray);
            // `Pair::relative_velocity`, with `cross_sv(w, r) = (-w·r.y, w·r.x)`.
            let cx = ((b.vx + (-b.w) * rby) - a.vx) - (-a.w) * ray;
            let cy = ((b.vy + b.w * rbx) - a.vy) - a.w * rax;
            let (bx, by, mass_scale, impulse_scale) = if bias {
                (rate * dx, rate * dy, soft_mass, soft_impulse)
            } else {
                (zero, zero, one, zero)
            };
            let (ux, uy) = (cx + bx, cy + by);
            // `point_mass` and `solve22`.
            let k11 = ((ma + mb) + ray * ray * ia) + rby * rby * ib;
            let k12 = (-ray) * rax * ia - rby * rbx * ib;
            let k22 = ((ma + mb) + rax * rax * ia) + rbx * rbx * ib;
            let det = k11 * k22 - k12 * k12;
            let inv = det.ne(zero).select(one / det, zero);
            let (xx, xy) = (inv * (k22 * ux - k12 * uy), inv * (k11 * uy - k12 * ux));
            let px = (-mass_scale) * xx - impulse_scale * lix;
            let py = (-mass_scale) * xy - impulse_scale * liy;
            let (nx, ny) = ((lix + px).store(), (liy + py).store());
            for (l, j) in group.iter_mut().enumerate() {
                j.hinge_mut().linear_impulse = Vec2::new(nx.as_array()[l], ny.as_array()[l]);
            }
            (px, py, zero)
        }
    };
    // `Pair::apply`.
    a.vx -= ma * px;
    a.vy -= ma * py;
    a.w -= ia * ((rax * py - ray * px) + torque);
    b.vx += mb * px;
    b.vy += mb * py;
    b.w += ib * ((rbx * py - rby * px) + torque);
    scatter(states, &body_a, dynamic_a, &a);
    scatter(states, &body_b, dynamic_b, &b);
}

/// `Revolute::solve`'s spring, motor and limit rows, in its order, in the lanes whose joint
/// has each (`soft`: the rigid rows' softness, read by the limit in the solve pass).
#[inline(always)]
fn angular_rows<V: Lanes>(
    group: &mut [Joint],
    rows: [u8; LANES],
    (a, b): (&mut WideBody<V>, &mut WideBody<V>),
    (ia, ib): (V, V),
    bias: bool,
    ctx: &JointContext,
    (rate, soft_mass, soft_impulse): (V, V, V),
) {
    use std::f32::consts::PI;
    // The lanes that have a row, as bits.
    let bits = |row: u8| (0..LANES).fold(0u8, |m, l| m | (u8::from(rows[l] & row != 0) << l));
    let spring = bits(Revolute::SPRING);
    let motor = bits(Revolute::MOTOR);
    let limit = bits(Revolute::LIMIT);
    let on = |bits: u8| {
        let set = f32::from_bits(u32::MAX);
        V::load(f32x8::new(std::array::from_fn(|l| {
            if bits & (1 << l) != 0 { set } else { 0.0 }
        })))
    };
    // One field of the eight hinges (or of their steps), in lanes.
    macro_rules! lanes {
        ($r:ident => $e:expr) => {
            V::load(f32x8::new(std::array::from_fn(|l| {
                let $r: &Revolute = group[l].hinge();
                $e
            })))
        };
        (step $s:ident => $e:expr) => {
            V::load(f32x8::new(std::array::from_fn(|l| {
                let $s = &group[l].step;
                $e
            })))
        };
    }
    // Writes each lane of `$v` whose bit is set in `$bits` to its hinge's field.
    macro_rules! store {
        ($v:expr, $bits:expr, $r:ident => $field:expr) => {{
            let v = $v.store();
            for (l, j) in group.iter_mut().enumerate() {
                if $bits & (1 << l) != 0 {
                    let $r = j.hinge_mut();
                    $field = v.as_array()[l];
                }
            }
        }};
    }
    // `Pair::turn` in the lanes that have the row.
    let turn = |a: &mut WideBody<V>, b: &mut WideBody<V>, rows: V, impulse: V| {
        a.w = rows.select(a.w - ia * impulse, a.w);
        b.w = rows.select(b.w + ib * impulse, b.w);
    };
    let (zero, one) = (V::splat(0.0), V::splat(1.0));
    let axial_mass = lanes!(r => r.axial_mass);
    let angle = if spring | limit != 0 {
        // `relative_angle`: each frame turned by its body's substep rotation (`then_from`),
        // then B's relative to A's (`inv_mul`).
        let (fac, fas) = (
            lanes!(step s => s.frame_a.q.c),
            lanes!(step s => s.frame_a.q.s),
        );
        let (fbc, fbs) = (
            lanes!(step s => s.frame_b.q.c),
            lanes!(step s => s.frame_b.q.s),
        );
        let (qac, qas) = (a.dqc * fac - a.dqs * fas, a.dqs * fac + a.dqc * fas);
        let (qbc, qbs) = (b.dqc * fbc - b.dqs * fbs, b.dqs * fbc + b.dqc * fbs);
        atan2(qac * qbs - qas * qbc, qac * qbc + qas * qbs)
    } else {
        zero
    };
    if spring != 0 {
        // `unwind`
        let c = angle - lanes!(r => r.target_angle);
        let wrapped = c.gt(V::splat(PI)).select(c - V::splat(2.0 * PI), c);
        let c = V::splat(-PI).gt(c).select(c + V::splat(2.0 * PI), wrapped);
        let sr = lanes!(r => r.spring_softness.bias_rate);
        let sm = lanes!(r => r.spring_softness.mass_scale);
        let si = lanes!(r => r.spring_softness.impulse_scale);
        let old = lanes!(r => r.spring_impulse);
        let cdot = b.w - a.w;
        let impulse = ((-sm) * axial_mass) * (cdot + sr * c) - si * old;
        store!(old + impulse, spring, r => r.spring_impulse);
        turn(a, b, on(spring), impulse);
    }
    if motor != 0 {
        let speed = lanes!(r => r.motor.map_or(0.0, |m| m.speed));
        let max = V::splat(ctx.h) * lanes!(r => r.motor.map_or(0.0, |m| m.max_torque));
        let old = lanes!(r => r.motor_impulse);
        let cdot = (b.w - a.w) - speed;
        // `math::clamp_within`: below the least, then above the most.
        let x = old - axial_mass * cdot;
        let x = (-max).gt(x).select(-max, x);
        let x = x.gt(max).select(max, x);
        store!(x, motor, r => r.motor_impulse);
        turn(a, b, on(motor), x - old);
    }
    if limit != 0 {
        let rows = on(limit);
        let inv_h = V::splat(ctx.inv_h);
        // `limit_row`
        let row = |c: V| {
            let ahead = c.gt(zero);
            if bias {
                (
                    ahead.select(c * inv_h, rate * c),
                    ahead.select(one, soft_mass),
                    ahead.select(zero, soft_impulse),
                )
            } else {
                (ahead.select(c * inv_h, zero), one, zero)
            }
        };
        let lower = lanes!(r => r.limit.map_or(0.0, |l| l[0]));
        let upper = lanes!(r => r.limit.map_or(0.0, |l| l[1]));
        // The two sides are written out: one closure for both (the same bits) made rain's
        // substeps 1.49 -> 1.96 ms, the compiler keeping less in registers.
        let (bias_l, mass_l, imp_l) = row(angle - lower);
        let cdot = b.w - a.w;
        let old = lanes!(r => r.lower_impulse);
        let impulse = ((-mass_l) * axial_mass) * (cdot + bias_l) - imp_l * old;
        let new = (old + impulse).fast_max(zero);
        store!(new, limit, r => r.lower_impulse);
        turn(a, b, rows, new - old);
        let (bias_u, mass_u, imp_u) = row(upper - angle);
        let cdot = a.w - b.w;
        let old = lanes!(r => r.upper_impulse);
        let impulse = ((-mass_u) * axial_mass) * (cdot + bias_u) - imp_u * old;
        let new = (old + impulse).fast_max(zero);
        store!(new, limit, r => r.upper_impulse);
        turn(a, b, rows, -(new - old));
    }
}
