//! Whether splitting a stage over the workers pays on this machine, now: found by timing the
//! stage both ways now and then, and kept while the timings agree.
//!
//! Why: the thresholds of [`crate::WideThresholds`] are crossovers measured once, on one
//! machine. On another, or on the same one under other load, a second worker can cost more
//! than it gives: on a 2-vCPU AMD EPYC VM whose cores hand cache lines to each other slowly,
//! the solver's ~100 stages a step on two workers took `pile_1000`'s substeps from 0.19 ms to
//! 0.38 and `junkyard`'s from 1.46 to 1.99, while `large_pyramid`'s still gained (1.91 to
//! 1.43): which way pays depends on the machine and the scene, and only a clock can tell.
//! Results never depend on it: a step's state is the same bits on any number of workers.

/// Steps between probes at first and after a switch; an interval doubles each time a probe
/// confirms the choice (grows fourfold where it lost by [`WIDE_LOSS`]), up to
/// [`MAX_INTERVAL`].
const FIRST_INTERVAL: u32 = 8;
/// The longest interval between probes: 256 steps (4.3 s at 60 Hz), so a scene that grows
/// into the other regime is caught within seconds, and a probe that loses (two steps the
/// slower way) costs under 1% of the steps.
const MAX_INTERVAL: u32 = 256;
/// Steps a probe runs the other way, and steps of the current way it is weighed against:
/// the fastest of each counts, so one step the OS preempted does not decide.
const PROBE_STEPS: usize = 2;
/// The other way is taken only when its fastest step took at most this fraction of the
/// current way's fastest: two consecutive steps of a scene in motion differ by a few per
/// cent, and a switch back and forth on noise would cost a probe each time.
const SWITCH_BELOW: f64 = 0.9;
/// A probe that took this many times the current way's time lost by so much that the next is
/// put off four times as long, not twice: where a second worker halves the solve, each probe
/// step costs as much as a step again (measured interleaved at 300 steps, 2 threads, with
/// doubling alone: many_pyramids 1.025, joint_grid 1.017 of the step without probes).
const WIDE_LOSS: f64 = 1.5;

/// The choice, for one stage, between splitting it over the workers and running it on one.
/// It starts by splitting (what the thresholds asked for), and every so often runs a couple
/// of steps the other way; if those were clearly faster, it switches.
#[derive(Clone, Debug)]
pub struct Payoff {
    /// The workers and the work the choice was made for (`(0, 0)`: none yet); others start
    /// afresh, as their times are not comparable with these.
    made_for: (usize, u64),
    /// The step of the last [`Payoff::split`]: a step that is not the next one (the stage
    /// went untimed in between: one thread, a scene below the threshold) drops the times
    /// and any probe under way, which were of another scene, and keeps the choice.
    last_step: Option<u64>,
    /// Whether the stage is split (the current choice).
    split: bool,
    /// The last [`PROBE_STEPS`] times (ms) of the current choice, newest at `recent_at`.
    recent: [f64; PROBE_STEPS],
    recent_count: usize,
    recent_at: usize,
    /// Steps of the current choice until the next probe, and the interval it was set from.
    until_probe: u32,
    interval: u32,
    /// Steps of the probe still to run (0: not probing), and the fastest it has taken.
    probe_left: usize,
    probe_best: f64,
}

impl Default for Payoff {
    fn default() -> Self {
        Payoff::fresh((0, 0))
    }
}

impl Payoff {
    fn fresh(made_for: (usize, u64)) -> Payoff {
        Payoff {
            made_for,
            last_step: None,
            split: true,
            recent: [f64::INFINITY; PROBE_STEPS],
            recent_count: 0,
            recent_at: 0,
            until_probe: FIRST_INTERVAL,
            interval: FIRST_INTERVAL,
            probe_left: 0,
            probe_best: f64::INFINITY,
        }
    }

    /// Whether this step's stage is split over `workers` workers (more than one) or runs on
    /// one; the caller times it and hands the time to [`Payoff::record`]. `work` stands for
    /// whatever sets what a step of the stage costs beside the scene (the solver's substeps
    /// and relax passes): a different value, like a different worker count, starts afresh.
    /// `step` counts the world's steps.
    pub fn split(&mut self, workers: usize, work: u64, step: u64) -> bool {
        if self.made_for != (workers, work) {
            *self = Payoff::fresh((workers, work));
        }
        if self
            .last_step
            .is_some_and(|last| step != last.wrapping_add(1))
        {
            self.recent_count = 0;
            self.probe_left = 0;
            self.until_probe = self.until_probe.max(PROBE_STEPS as u32);
        }
        self.last_step = Some(step);
        if self.probe_left > 0 {
            !self.split
        } else {
            self.split
        }
    }

    /// Whether the step [`Payoff::split`] was just asked about runs the other way from the
    /// choice, to time it.
    pub fn probing(&self) -> bool {
        self.probe_left > 0
    }

    /// Whether the stage is split between probes.
    #[cfg(test)]
    fn splits(&self) -> bool {
        self.split
    }

    /// The stage took `ms` milliseconds, split or not as `split` said: a step of the current
    /// choice or of a probe.
    pub fn record(&mut self, split: bool, ms: f64) {
        // A time that is not a time (a clock gone backwards, a NaN) counts for nothing: a
        // probe it fell in runs a step longer.
        if !(ms.is_finite() && ms >= 0.0) {
            return;
        }
        if self.probe_left > 0 && split != self.split {
            self.probe_best = self.probe_best.min(ms);
            self.probe_left -= 1;
            if self.probe_left == 0 {
                let current = self.recent.iter().copied().fold(f64::INFINITY, f64::min);
                if self.probe_best < SWITCH_BELOW * current {
                    self.split = !self.split;
                    // The probe's times are the new choice's first.
                    self.recent = [self.probe_best; PROBE_STEPS];
                    self.recent_count = PROBE_STEPS;
                    self.interval = FIRST_INTERVAL;
                } else {
                    let growth = if self.probe_best >= WIDE_LOSS * current {
                        4
                    } else {
                        2
                    };
                    self.interval = (self.interval * growth).min(MAX_INTERVAL);
                }
                self.until_probe = self.interval;
            }
            return;
        }
        if split != self.split {
            // Not asked for (a caller that overrode the choice): not this choice's time.
            return;
        }
        self.recent_at = (self.recent_at + 1) % PROBE_STEPS;
        self.recent[self.recent_at] = ms;
        self.recent_count = (self.recent_count + 1).min(PROBE_STEPS);
        self.until_probe = self.until_probe.saturating_sub(1);
        if self.until_probe == 0 && self.recent_count == PROBE_STEPS {
            self.probe_left = PROBE_STEPS;
            self.probe_best = f64::INFINITY;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One step on 2 workers, the step after the last, taking `ms(split)`; whether it split.
    fn step(p: &mut Payoff, ms: impl Fn(bool) -> f64) -> bool {
        let split = p.split(2, 8, p.last_step.map_or(0, |s| s + 1));
        p.record(split, ms(split));
        split
    }

    /// Runs `steps` steps against a stage that takes `split_ms` split and `alone_ms` on one
    /// worker; returns how many steps ran split.
    fn run(p: &mut Payoff, steps: usize, split_ms: f64, alone_ms: f64) -> usize {
        (0..steps)
            .filter(|_| step(p, |split| if split { split_ms } else { alone_ms }))
            .count()
    }

    #[test]
    fn a_split_that_pays_stays_and_probes_ever_more_rarely() {
        let mut p = Payoff::default();
        // One worker loses by more than `WIDE_LOSS`: probes of 2 steps after 8, 32, 128 and
        // then every 256 split steps: 6 probes, 12 steps, in the first 1,000.
        let split = run(&mut p, 1000, 1.0, 1.6);
        assert!(p.splits());
        assert_eq!(1000 - split, 12, "steps on one worker");
        // Losing by less, the interval only doubles: after 8, 16, 32, 64, 128, 256, 256.
        let mut p = Payoff::default();
        let split = run(&mut p, 1000, 1.0, 1.3);
        assert!(p.splits());
        assert_eq!(1000 - split, 14, "steps on one worker");
    }

    #[test]
    fn a_split_that_costs_is_dropped_at_the_first_probe() {
        let mut p = Payoff::default();
        // 8 split steps, then the 2-step probe finds one worker faster and stays there.
        let split = run(&mut p, 10, 0.38, 0.19);
        assert_eq!(split, 8);
        assert!(!p.splits());
        // From then on, split only in probes: 2 steps after 8 and then 32 on one worker (the
        // split lost by more than `WIDE_LOSS`).
        let split = run(&mut p, 100, 0.38, 0.19);
        assert_eq!(split, 4, "probe steps split in 100: after 8 and 32 alone");
        assert!(!p.splits());
    }

    #[test]
    fn a_difference_within_the_noise_switches_nothing() {
        // One worker 5% faster: within `SWITCH_BELOW`, the split stays.
        let mut p = Payoff::default();
        run(&mut p, 600, 1.0, 0.95);
        assert!(p.splits());
    }

    #[test]
    fn one_preempted_step_does_not_decide() {
        // The split pays (1.0 against 1.6 ms), but the step before the first probe was
        // preempted (9 ms): the other recent step still holds the split's time.
        let mut p = Payoff::default();
        for k in 0..10 {
            step(&mut p, |split| match (split, k) {
                (true, 7) => 9.0,
                (true, _) => 1.0,
                (false, _) => 1.6,
            });
        }
        assert!(p.splits());
    }

    #[test]
    fn the_choice_follows_the_scene_into_the_other_regime() {
        let mut p = Payoff::default();
        run(&mut p, 50, 0.38, 0.19);
        assert!(!p.splits());
        // The scene grows: splitting now pays; the next probe (within 256 steps) finds it.
        run(&mut p, 300, 1.4, 1.9);
        assert!(p.splits());
    }

    #[test]
    fn another_worker_count_starts_afresh_and_bad_times_decide_nothing() {
        let mut p = Payoff::default();
        run(&mut p, 50, 0.38, 0.19);
        assert!(!p.splits());
        assert!(p.split(3, 8, 0), "a new worker count starts split");
        run(&mut p, 50, 0.38, 0.19);
        assert!(!p.splits());
        assert!(p.split(2, 16, 0), "so does new work (other substeps)");
        let mut p = Payoff::default();
        run(&mut p, 20, 1.0, f64::NAN);
        assert!(p.splits());
        // Bad times of the split decide nothing either: one worker's finite times do not
        // win against them.
        let mut p = Payoff::default();
        run(&mut p, 20, -1.0, 5.0);
        assert!(p.splits());
    }

    #[test]
    fn a_gap_in_the_steps_drops_the_times_and_keeps_the_choice() {
        let mut p = Payoff::default();
        run(&mut p, 10, 0.38, 0.19);
        assert!(!p.splits());
        // Untimed steps in between (one thread, say): the next probe waits for two fresh
        // times of the choice, however fast the split was before.
        let step = p.last_step.unwrap() + 100;
        assert!(!p.split(2, 8, step));
        assert_eq!(p.recent_count, 0);
        p.record(false, 0.19);
        assert_eq!(p.recent_count, 1);
        assert!(!p.splits());
    }
}
