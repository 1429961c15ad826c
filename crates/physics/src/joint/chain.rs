//! Chains of hinges solved exactly: the point rows of a path of revolute joints as one
//! block-tridiagonal system, so that the whole chain's masses act in every joint.
//!
//! Why: a soft-step joint (Box2D's, and tumble's one joint at a time) is a spring of stiffness
//! m ω² along each row, with m the row's own effective mass. In a chain of light links
//! carrying a heavy load every joint carries the load's weight F on a light link's mass, so
//! each stretches F / (m_link ω²): a ball 1000 times a link's mass stretches a 10-link chain by
//! 1.5 m at the defaults, in Box2D as in tumble one joint at a time. Solving the chain's point
//! rows together makes the effective mass the whole chain's (K⁻¹, with K = J M⁻¹ Jᵀ), and in
//! a path K is block-tridiagonal (each joint couples only to the joints sharing its bodies),
//! so the solve is linear in the chain's length: the block Thomas algorithm (Golub and Van
//! Loan, "Matrix Computations", 4.5.1, block LU of a tridiagonal matrix), the path case of
//! Baraff's linear-time solve for acyclic constraint graphs ("Linear-time dynamics using
//! Lagrange multipliers", SIGGRAPH 1996). The soft step's terms (bias rate, mass scale,
//! impulse scale) apply to the block system exactly as to one joint's 2×2 block.

use glam::Vec2;

use super::{Joint, JointKind, JointStep, Pair};
use crate::threads::parallel::BodyStates;

/// Longest run solved as one system; a longer chain is solved in runs of this many joints,
/// one after the other (each run exact, the runs coupled by Gauss-Seidel): the elimination's
/// rounding grows with the length (measured: none to speak of at Solver2D's 160-plank bridge).
pub const MAX_RUN: usize = 256;

/// A 2×2 matrix, column-major as glam's would be: `[[a, c], [b, d]]` is `[a, b, c, d]`.
#[derive(Clone, Copy, Debug, Default)]
struct M2 {
    a: f32,
    b: f32,
    c: f32,
    d: f32,
}

impl M2 {
    fn sym([k11, k12, k22]: [f32; 3]) -> M2 {
        M2 {
            a: k11,
            b: k12,
            c: k12,
            d: k22,
        }
    }
    fn mul_v(self, v: Vec2) -> Vec2 {
        Vec2::new(self.a * v.x + self.c * v.y, self.b * v.x + self.d * v.y)
    }
    fn mul(self, o: M2) -> M2 {
        M2 {
            a: self.a * o.a + self.c * o.b,
            b: self.b * o.a + self.d * o.b,
            c: self.a * o.c + self.c * o.d,
            d: self.b * o.c + self.d * o.d,
        }
    }
    fn sub(self, o: M2) -> M2 {
        M2 {
            a: self.a - o.a,
            b: self.b - o.b,
            c: self.c - o.c,
            d: self.d - o.d,
        }
    }
    fn transpose(self) -> M2 {
        M2 {
            a: self.a,
            b: self.c,
            c: self.b,
            d: self.d,
        }
    }
    fn scale(self, k: f32) -> M2 {
        M2 {
            a: k * self.a,
            b: k * self.b,
            c: k * self.c,
            d: k * self.d,
        }
    }
    /// The adjugate: the inverse times the determinant.
    fn adjugate(self) -> M2 {
        M2 {
            a: self.d,
            b: -self.b,
            c: -self.c,
            d: self.a,
        }
    }
    /// 1 / the determinant, or zero where singular (a row no body can move along).
    fn inverse_det(self) -> f32 {
        let det = self.a * self.d - self.b * self.c;
        if det != 0.0 { 1.0 / det } else { 0.0 }
    }
}

/// Whether a joint's point rows can join a chain: a revolute joint without a limit, motor or
/// spring (those rows stay with the one-joint-at-a-time solve, so such a joint ends a chain).
pub fn eligible(joint: &Joint) -> bool {
    matches!(&joint.kind, JointKind::Revolute(r)
        if r.limit.is_none() && r.motor.is_none() && r.spring.is_none())
}

/// The inverse mass and inertia of `body` in joint `j`.
fn masses(s: &JointStep, j: &Joint, body: u32) -> (f32, f32) {
    if j.body_b == body {
        (s.inv_mass_b, s.inv_i_b)
    } else {
        (s.inv_mass_a, s.inv_i_a)
    }
}

/// The body two consecutive joints of a chain share.
fn shared(a: &Joint, b: &Joint) -> u32 {
    if a.body_b == b.body_a || a.body_b == b.body_b {
        a.body_b
    } else {
        a.body_a
    }
}

/// One pass over a chain's point rows, solved together (see the module's note). `joints`
/// are consecutive along the path: each shares a dynamic body with the next.
/// `rows` holds at least the longest run's (`MAX_RUN` or the chain's length): the solver
/// keeps them, sized when the chains change, so a steady step allocates nothing on whatever
/// worker runs the chains.
pub fn solve(joints: &mut [Joint], states: &BodyStates<'_>, use_bias: bool, rows: &mut [Row]) {
    for run in joints.chunks_mut(MAX_RUN) {
        solve_rows(run, states, use_bias, rows);
    }
}

/// The rows a chain of `len` joints needs.
pub fn rows_needed(len: usize) -> usize {
    len.min(MAX_RUN)
}

/// One joint's row of the block system, and its bodies' state.
#[derive(Clone, Copy, Debug, Default)]
pub struct Row {
    /// K_ii, then D'_i of the elimination.
    diag: M2,
    /// D'_i⁻¹.
    inv: M2,
    /// K_i,i+1.
    upper: M2,
    /// Cdot + bias, then y_i of the elimination.
    rhs: Vec2,
    /// The current anchors on A and B.
    ra: Vec2,
    rb: Vec2,
    /// Whether the body shared with the joint before is this joint's B (else its A).
    prev_b: bool,
    /// Whether the body shared with the joint after is this joint's B.
    next_b: bool,
    /// The bodies' state as loaded, before this pass's impulses.
    pair: Pair,
}

fn solve_rows(joints: &mut [Joint], states: &BodyStates<'_>, bias: bool, rows: &mut [Row]) {
    let n = joints.len();
    // One forward sweep: each joint's row (K_ii and the right-hand side Cdot + bias), its
    // coupling to the joint before, and the elimination step. One loop, not three, so that
    // the next rows are built while an elimination step waits on its division (the
    // elimination is a chain of dependent 2×2 inverses, latency-bound on its own).
    for i in 0..n {
        let j = &joints[i];
        let p = j.load(states);
        let (ra, rb, d) = super::anchors(&j.step, &p);
        let b = if bias {
            j.step.softness.bias_rate * d
        } else {
            Vec2::ZERO
        };
        rows[i] = Row {
            diag: M2::sym(super::point_mass(&j.step, ra, rb)),
            inv: M2::default(),
            upper: M2::default(),
            rhs: p.relative_velocity(ra, rb) + b,
            ra,
            rb,
            prev_b: false,
            next_b: false,
            pair: p,
        };
        if i == 0 {
            continue;
        }
        // K_i−1,i through the shared body s: σ_i−1 σ_i (m_s⁻¹ I + i_s⁻¹ perp(r_i−1) perp(r_i)ᵀ),
        // where σ is +1 where s is the joint's B and perp(r) = (−r.y, r.x).
        let before = &joints[i - 1];
        let s = shared(before, j);
        let (prev_b, this_b) = (before.body_b == s, j.body_b == s);
        let side = |row: &Row, b: bool| if b { (1.0, row.rb) } else { (-1.0, row.ra) };
        let (si, ri) = side(&rows[i - 1], prev_b);
        let (sn, rn) = side(&rows[i], this_b);
        let (m, inv_i) = masses(&before.step, before, s);
        let (ui, un) = (Vec2::new(-ri.y, ri.x), Vec2::new(-rn.y, rn.x));
        let sign = si * sn;
        rows[i - 1].upper = M2 {
            a: sign * (m + inv_i * ui.x * un.x),
            b: sign * (inv_i * ui.y * un.x),
            c: sign * (inv_i * ui.x * un.y),
            d: sign * (m + inv_i * ui.y * un.y),
        };
        rows[i - 1].next_b = prev_b;
        rows[i].prev_b = this_b;
        // Block LU, forward: D'_i = D_i − U_i−1ᵀ D'_i−1⁻¹ U_i−1, y_i = b_i − U_i−1ᵀ D'_i−1⁻¹ y_i−1,
        // with D'⁻¹ = adj(D') / det(D'): the products with the adjugate need not wait for
        // the division, which runs beside them (a shorter chain of dependent steps).
        let (prev, row) = (&rows[i - 1], &rows[i]);
        let inv_det = prev.diag.inverse_det();
        let l = prev.upper.transpose().mul(prev.diag.adjugate());
        let diag = row.diag.sub(l.mul(prev.upper).scale(inv_det));
        let rhs = row.rhs - inv_det * l.mul_v(prev.rhs);
        rows[i - 1].inv = prev.diag.adjugate().scale(inv_det);
        rows[i].diag = diag;
        rows[i].rhs = rhs;
    }
    rows[n - 1].inv = rows[n - 1]
        .diag
        .adjugate()
        .scale(rows[n - 1].diag.inverse_det());
    // Back: x_n = D'_n⁻¹ y_n, x_i = D'_i⁻¹ (y_i − U_i x_i+1), and each joint's impulse applied
    // as soon as it is known, so that the application fills the wait on the next x (a chain
    // of dependent products). Impulses add, so applying them last to first changes no more
    // than rounding. A joint's body shared with the joint after it has that joint's impulse,
    // carried over; its other body is as loaded (nothing else moves the chain's bodies during
    // its pass): the same sums as loading each joint again, without the loads.
    let mut next = Vec2::ZERO;
    let mut carried: Option<(Vec2, f32)> = None;
    for i in (0..n).rev() {
        let row = &rows[i];
        let x = if i + 1 < n {
            row.inv.mul_v(row.rhs - row.upper.mul_v(next))
        } else {
            row.inv.mul_v(row.rhs)
        };
        next = x;
        let j = &mut joints[i];
        let (mass_scale, impulse_scale) = if bias {
            (j.step.softness.mass_scale, j.step.softness.impulse_scale)
        } else {
            (1.0, 0.0)
        };
        let JointKind::Revolute(r) = &mut j.kind else {
            unreachable!("a chain holds revolute joints only");
        };
        let impulse = -mass_scale * x - impulse_scale * r.linear_impulse;
        r.linear_impulse += impulse;
        let mut p = row.pair;
        match carried {
            Some((v, w)) if row.next_b => (p.vb, p.wb) = (v, w),
            Some((v, w)) => (p.va, p.wa) = (v, w),
            None => {}
        }
        p.apply(&j.step, row.ra, row.rb, impulse, 0.0);
        j.store(states, &p);
        carried = Some(if row.prev_b {
            (p.vb, p.wb)
        } else {
            (p.va, p.wa)
        });
    }
}

/// An awake joint as the chain search sees it: its slot, its bodies, and whether each is
/// dynamic (only dynamic bodies join joints into a chain).
#[derive(Clone, Copy, Debug)]
pub struct Link {
    /// The joint's slot.
    pub slot: u32,
    /// Its bodies, `u32::MAX` where not dynamic.
    pub dynamic: [u32; 2],
}

/// Finds the chains among `links` (the eligible awake joints, in slot order): the connected
/// sets of joints whose dynamic bodies each hold at most two of them, without a cycle, of at
/// least two joints. Returns the chains' slots, each chain in path order, and each chain's
/// range in that list. Deterministic: chains in the order of their first joint's slot, each
/// walked from its end of lowest slot. `body_count` bounds the body indices.
pub fn find(links: &[Link], body_count: usize) -> (Vec<u32>, Vec<std::ops::Range<usize>>) {
    const NONE: u32 = u32::MAX;
    let mut order = Vec::new();
    let mut ranges = Vec::new();
    if links.len() < 2 {
        return (order, ranges);
    }
    // Each dynamic body's joints among the links (by position in `links`), up to two; a
    // third marks it a hub, which no chain passes.
    let mut held = vec![[NONE; 2]; body_count];
    let mut hub = vec![false; body_count];
    for (k, l) in links.iter().enumerate() {
        for b in l.dynamic {
            if b == NONE {
                continue;
            }
            let h = &mut held[b as usize];
            if h[0] == NONE {
                h[0] = k as u32;
            } else if h[1] == NONE {
                h[1] = k as u32;
            } else {
                hub[b as usize] = true;
            }
        }
    }
    // The other joint at `body` than `k`, if any.
    let other = |body: u32, k: u32| {
        let h = held[body as usize];
        if h[0] == k { h[1] } else { h[0] }
    };
    let mut seen = vec![false; links.len()];
    let mut component = Vec::new();
    for start in 0..links.len() {
        if seen[start] {
            continue;
        }
        // The component, by a walk over shared dynamic bodies.
        component.clear();
        component.push(start as u32);
        seen[start] = true;
        let mut ok = true;
        let mut i = 0;
        while i < component.len() {
            let k = component[i];
            for b in links[k as usize].dynamic {
                if b == NONE {
                    continue;
                }
                ok &= !hub[b as usize];
                for n in held[b as usize] {
                    if n != NONE && !seen[n as usize] {
                        seen[n as usize] = true;
                        component.push(n);
                    }
                }
            }
            i += 1;
        }
        if !ok || component.len() < 2 {
            continue;
        }
        // An end: a joint with a side that leads nowhere (a body that is not dynamic, or a
        // dynamic body holding only it). None: a cycle.
        component.sort_unstable();
        let is_end = |k: u32| {
            links[k as usize]
                .dynamic
                .iter()
                .any(|&b| b == NONE || other(b, k) == NONE)
        };
        let Some(&first) = component.iter().find(|&&k| is_end(k)) else {
            continue;
        };
        // Walk from the end across each shared body.
        let begin = order.len();
        let mut k = first;
        let mut from = links[k as usize]
            .dynamic
            .into_iter()
            .find(|&b| b == NONE || other(b, k) == NONE)
            .unwrap_or(NONE);
        loop {
            order.push(links[k as usize].slot);
            let [a, b] = links[k as usize].dynamic;
            // Leave by the side that did not bring us here.
            let out = if a == from && a != NONE || (from == NONE && a == NONE) {
                b
            } else {
                a
            };
            if out == NONE {
                break;
            }
            let next = other(out, k);
            if next == NONE {
                break;
            }
            from = out;
            k = next;
        }
        if order.len() - begin == component.len() {
            ranges.push(begin..order.len());
        } else {
            // Not a simple path after all: leave it to the one-joint solve.
            order.truncate(begin);
        }
    }
    (order, ranges)
}

#[cfg(test)]
mod tests {
    use super::*;

    const N: u32 = u32::MAX;

    fn link(slot: u32, a: u32, b: u32) -> Link {
        Link {
            slot,
            dynamic: [a, b],
        }
    }

    #[test]
    fn paths_are_chains_in_order_and_hubs_and_cycles_are_not() {
        // A bridge: static, 1, 2, 3, static (slots out of path order).
        let bridge = [
            link(10, N, 1),
            link(11, 2, 3),
            link(12, 1, 2),
            link(13, 3, N),
        ];
        let (order, ranges) = find(&bridge, 8);
        assert_eq!(order, vec![10, 12, 11, 13]);
        assert_eq!(ranges, vec![0..4]);
        // A hub (body 1 holds three joints): no chain.
        let star = [link(0, 1, 2), link(1, 1, 3), link(2, 1, 4)];
        assert!(find(&star, 8).1.is_empty());
        // A ring of three dynamic bodies: no end, no chain.
        let ring = [link(0, 1, 2), link(1, 2, 3), link(2, 3, 1)];
        assert!(find(&ring, 8).1.is_empty());
        // Two chains, and a lone joint left alone.
        let two = [
            link(0, N, 1),
            link(1, 1, 2),
            link(2, 5, 6),
            link(3, N, 7),
            link(4, 6, N),
        ];
        let (order, ranges) = find(&two, 8);
        assert_eq!(order, vec![0, 1, 2, 4]);
        assert_eq!(ranges, vec![0..2, 2..4]);
    }
}
