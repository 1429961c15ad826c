//! Per-step timings of each named stage of the pipeline, plus counters.

/// Wall time of the last step, stage by stage, in milliseconds, and what the step saw.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepProfile {
    /// The whole step.
    pub step_ms: f64,
    /// Broad phase: rebuild the tree if fat boxes changed, find new pairs, create contacts.
    pub broad_phase_ms: f64,
    /// Narrow phase: a manifold for every contact; drop contacts whose boxes parted.
    pub narrow_phase_ms: f64,
    /// Colour the constraint graph and prepare the contact constraints.
    pub prepare_ms: f64,
    /// The substeps (integrate velocities, warm start, solve, integrate positions, relax),
    /// then the restitution passes.
    pub solve_ms: f64,
    /// Store the accumulated impulses into the contacts for the next step's warm start.
    pub store_impulses_ms: f64,
    /// Apply the substep deltas to transforms, update bounding boxes.
    pub finalize_ms: f64,
    /// Events: hits among the contacts that began, and each sensor's overlaps (nothing in a
    /// world without sensors where no contact began).
    pub events_ms: f64,
    /// Bodies in the world.
    pub bodies: usize,
    /// Contacts (pairs whose fat boxes overlap).
    pub contacts: usize,
    /// Contacts with at least one manifold point.
    pub touching: usize,
    /// Contacts the narrow phase walked: every contact while no island sleeps, otherwise
    /// the awake set's (a contact of two sleeping bodies is not walked).
    pub collided: usize,
    /// Bodies the body stages (integration, finalize) walked: the awake set's, dynamic and
    /// kinematic (a sleeping or static body is not walked).
    pub moving: usize,
    /// Graph colours in use (overflow not counted).
    pub colors: usize,
    /// Constraints that fitted no colour and were solved serially.
    pub overflow: usize,
    /// Restitution passes the step took (0 when nothing could bounce): exactly
    /// `StepSettings::restitution_iterations`, or with `impacts_bounce` until one moved no
    /// rebound faster than the threshold by more than 1 mm/s, at most 16 (or
    /// `restitution_iterations`, if more) and within the passes' visit budget.
    pub restitution_passes: u32,
    /// Proxies whose fat box changed in the last step.
    pub moved: usize,
    /// Workers that ran the substeps (1 below `WideThresholds::solve` touching contacts a
    /// worker, or where splitting them was timed and lost, `WideThresholds::solve_by_payoff`,
    /// which also runs a step or two the other way now and then to time it; never more than
    /// cores).
    pub solver_workers: usize,
    /// This step ran the substeps the other way from the choice `solve_by_payoff` holds (on
    /// one worker where they are split, or split where they run on one), to time it: its
    /// `solver_workers` is not the choice's.
    pub solver_probe: bool,
    /// The step ran inline on the caller's thread: one thread, or no stage reached its
    /// `WideThresholds` (the crew was not woken).
    pub inline: bool,
    /// Contacts whose manifold was recycled rather than recomputed.
    pub recycled: usize,
    /// Fast bodies continuous collision swept, and of those the ones it moved back to their
    /// time of impact.
    pub swept: usize,
    /// See `swept`.
    pub rewound: usize,
    /// Bodies whose state went non-finite in this step and were stopped at their last finite
    /// pose (zero unless something upstream is broken). This step only: a run's checks want
    /// `World::non_finite_bodies`, the total over every step.
    pub non_finite: usize,
}

/// Names of the timed stages, in pipeline order.
pub const STAGE_NAMES: [&str; 7] = [
    "broad_phase",
    "narrow_phase",
    "prepare",
    "solve",
    "store_impulses",
    "finalize",
    "events",
];

impl StepProfile {
    /// `(stage name, ms)` for each stage, in pipeline order.
    pub fn stages(&self) -> [(&'static str, f64); 7] {
        let ms = [
            self.broad_phase_ms,
            self.narrow_phase_ms,
            self.prepare_ms,
            self.solve_ms,
            self.store_impulses_ms,
            self.finalize_ms,
            self.events_ms,
        ];
        std::array::from_fn(|i| (STAGE_NAMES[i], ms[i]))
    }
}
