//! Hooks: the game's say in which pairs touch (a custom filter, asked when the broad phase
//! finds a pair) and which touching contacts push in a step (pre-solve, asked after the
//! narrow phase computes a contact's manifold), as Box2D v3's `b2World_SetCustomFilterCallback`
//! and `b2World_SetPreSolveCallback`. Both are asked from the worker threads, so each must
//! answer from its arguments alone (and what it captures, unchanged during the step): then
//! the step gives the same bits on any thread count. Unset, each costs a branch.

use glam::Vec2;

use super::World;
use crate::id::ShapeId;

/// Decides whether two shapes whose filters let them touch may touch at all.
pub type CustomFilter = Box<dyn Fn(ShapeId, ShapeId) -> bool + Send + Sync>;

/// Decides whether a touching contact pushes in this step, given its shapes and its normal
/// (from the first shape towards the second).
pub type PreSolve = Box<dyn Fn(ShapeId, ShapeId, Vec2) -> bool + Send + Sync>;

/// The world's hooks.
#[derive(Default)]
pub(super) struct Hooks {
    pub custom_filter: Option<CustomFilter>,
    pub pre_solve: Option<PreSolve>,
}

/// Hooks: a custom filter and a pre-solve callback.
///
/// A one-way platform: a box falling onto a platform lands on it; a box rising through it
/// (its contact's normal points from the platform down into the box) passes.
///
/// ```
/// use tumble_physics::{BodyDef, BodyKind, ShapeDef, StepSettings, Vec2, World};
///
/// let mut world = World::new(StepSettings::default());
/// let platform = world
///     .create_body(&BodyDef::new(ShapeDef::Box { half_extents: [3.0, 0.1], radius: 0.0 }).kind(BodyKind::Static))
///     .unwrap();
/// let deck = world.body_shapes(platform).unwrap().next().unwrap().id;
/// world.set_pre_solve(Some(Box::new(move |a, b, normal| {
///     // The normal from the platform towards the other shape must point up.
///     let up = if a == deck { normal } else if b == deck { -normal } else { return true };
///     up.y > 0.5
/// })));
/// let jumper = world.create_body(&BodyDef::new(ShapeDef::Box { half_extents: [0.25, 0.25], radius: 0.0 }).at(0.0, -1.0)).unwrap();
/// world.set_velocity(jumper, Vec2::new(0.0, 8.0), 0.0).unwrap();
/// for _ in 0..120 {
///     world.step(1.0 / 60.0, 4);
/// }
/// // Through from below, then landed on top.
/// let y = world.body(jumper).unwrap().position.y;
/// assert!((y - 0.35).abs() < 0.02, "{y}");
/// ```
impl World {
    /// Sets (or with `None` removes) the custom filter: asked once for each pair of shapes
    /// the broad phase finds whose filters let them touch; `false` and the pair makes no
    /// contact (it is asked again when the pair is found again). A change applies to pairs
    /// found from the next step; contacts that exist are kept.
    pub fn set_custom_filter(&mut self, filter: Option<CustomFilter>) {
        self.hooks.custom_filter = filter;
        // Pairs it refused may now be let through, and the pair search skips the pairs it
        // saw before only while no filter can refuse (see `Shapes::searched_boxes`).
        self.shapes.forget_searched();
    }

    /// Sets (or with `None` removes) the pre-solve callback: asked for each contact whose
    /// manifold has points, each step, before the solve; `false` and the contact has no
    /// points this step (it pushes nothing, and counts as not touching: a contact end event
    /// if it touched), and its manifold is computed afresh next step.
    pub fn set_pre_solve(&mut self, pre_solve: Option<PreSolve>) {
        self.hooks.pre_solve = pre_solve;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::def::{BodyDef, BodyKind, ShapeDef};
    use crate::world::{StepSettings, WideThresholds};

    const DT: f32 = 1.0 / 60.0;

    fn small_box() -> ShapeDef {
        ShapeDef::Box {
            half_extents: [0.25, 0.25],
            radius: 0.0,
        }
    }

    /// A static floor and `n` boxes in rows of 40 above it.
    fn pile(n: usize) -> World {
        let mut w = World::new(StepSettings::default());
        w.create_body(
            &BodyDef::new(ShapeDef::Box {
                half_extents: [20.0, 0.5],
                radius: 0.0,
            })
            .kind(BodyKind::Static)
            .at(0.0, -0.5),
        )
        .unwrap();
        for k in 0..n {
            let (col, row) = ((k % 40) as f32, (k / 40) as f32);
            w.create_body(
                &BodyDef::new(small_box())
                    .at(col * 0.6 - 12.0 + 0.1 * (row % 2.0), 0.3 + row * 0.55),
            )
            .unwrap();
        }
        w
    }

    #[test]
    fn a_pair_the_custom_filter_refuses_never_touches_and_the_others_do() {
        let mut w = pile(2);
        let [_, ghost, solid] = [0, 1, 2].map(crate::BodyId::scene);
        let ghost_shape = w.body_shapes(ghost).unwrap().next().unwrap().id;
        w.set_custom_filter(Some(Box::new(move |a, b| {
            a != ghost_shape && b != ghost_shape
        })));
        for _ in 0..60 {
            w.step(DT, 4);
        }
        assert!(w.body_contacts(ghost).unwrap().is_empty());
        assert!(w.body(ghost).unwrap().position.y < -2.0);
        assert_eq!(w.body_contacts(solid).unwrap().len(), 1);
        // Removed, the filter asks no more: the next pair found touches.
        w.set_custom_filter(None);
        w.set_transform(ghost, glam::Vec2::new(5.0, 1.0), 0.0)
            .unwrap();
        w.set_velocity(ghost, glam::Vec2::ZERO, 0.0).unwrap();
        for _ in 0..60 {
            w.step(DT, 4);
        }
        assert_eq!(w.body_contacts(ghost).unwrap().len(), 1);
    }

    #[test]
    fn hooks_on_two_thousand_bodies_give_the_same_bits_on_one_and_four_workers() {
        let run = |workers: usize, hooked: bool| {
            let mut w = pile(2000);
            w.set_workers_beyond_cores(true);
            w.set_wide_thresholds(WideThresholds::ALWAYS);
            w.set_thread_count(workers);
            // Answers from the arguments alone: about one pair in eleven never touches, and
            // one contact in seven pushes nothing in a step where its normal leans left.
            if hooked {
                w.set_custom_filter(Some(Box::new(|a, b| (a.index ^ b.index) % 11 != 0)));
                w.set_pre_solve(Some(Box::new(|a, b, n| {
                    (a.index + b.index) % 7 != 0 || n.x >= 0.0
                })));
            }
            let mut hashes = Vec::new();
            for _ in 0..90 {
                w.step(DT, 4);
                hashes.push(w.state_hash());
            }
            assert!(w.profile().contacts > 2000);
            assert!(w.is_finite());
            (hashes, w.events().to_vec())
        };
        let one = run(1, true);
        assert!(
            one == run(4, true),
            "the hooks made the step depend on the thread count"
        );
        // And they did bite: without them the pile moves otherwise.
        assert_ne!(one.0.last(), run(1, false).0.last());
    }
}
