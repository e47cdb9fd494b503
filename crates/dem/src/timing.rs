//! Where a step's wall-clock time goes: the three phases of velocity Verlet as the engine
//! runs them (docs/physics.md §6.2), for the benchmarks' breakdown, in the spirit of the timing
//! table LAMMPS prints after a run (Pair, Neigh, Modify, Other).
//!
//! Off by default. When on, the clock is read five times a step (about 140 ns in all, a few
//! hundredths of a nanosecond per particle-step for the paper's 3000 spheres) and nothing else
//! changes: the same additions in the same order, so trajectories are bit-identical either way.

use std::time::Instant;

use serde::Serialize;

/// Wall-clock time spent in each phase of the step since timing was switched on.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct PhaseTimes {
    /// The half kicks and the drift, with the largest-displacement and finiteness checks [s].
    /// Past 2^15 bodies on one thread, a run's steps do the next step's kicks and drift
    /// inside their force evaluation, chunk by chunk: that time then counts as `forces`,
    /// and only a run's first kick and drift and its last half kick count here.
    pub integrate: f64,
    /// Neighbour-list rebuilds, re-sorting into cell order included [s].
    pub neighbour: f64,
    /// Gravity, the contact filters and kernels for particle pairs and walls, and the sums
    /// onto each body [s].
    pub forces: f64,
    /// Steps timed [-].
    pub steps: u64,
}

impl PhaseTimes {
    /// The three phases together [s].
    pub fn total(&self) -> f64 {
        self.integrate + self.neighbour + self.forces
    }
}

/// The marks that divide one step into its phases, in the order the step passes them.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Mark {
    /// The first half kick and the drift are done.
    Drifted,
    /// The neighbour lists are up to date.
    Listed,
    /// The forces are evaluated.
    Forced,
}

/// The instants that divide one step into its phases.
#[derive(Debug, Clone, Copy)]
pub(crate) struct StepClock {
    start: Instant,
    /// When each [`Mark`] was passed, by its index.
    marks: [Option<Instant>; 3],
}

impl StepClock {
    /// Starts timing a step, if `on`.
    #[inline]
    pub(crate) fn start(on: bool) -> Option<Self> {
        on.then(|| Self {
            start: Instant::now(),
            marks: [None; 3],
        })
    }

    /// Notes that the step has passed `mark`, if the clock runs.
    #[inline]
    pub(crate) fn mark(clock: &mut Option<Self>, mark: Mark) {
        if let Some(c) = clock {
            c.marks[mark as usize] = Some(Instant::now());
        }
    }

    /// Adds a completed step to `times`: whatever follows the forces (the second half kick)
    /// counts as integration. A step that failed before its forces is not added.
    #[inline]
    pub(crate) fn finish(clock: Option<Self>, times: &mut PhaseTimes) {
        let Some(c) = clock else { return };
        let [Some(drifted), Some(listed), Some(forced)] = c.marks else {
            return;
        };
        let end = Instant::now();
        let secs = |a: Instant, b: Instant| b.duration_since(a).as_secs_f64();
        times.integrate += secs(c.start, drifted) + secs(forced, end);
        times.neighbour += secs(drifted, listed);
        times.forces += secs(listed, forced);
        times.steps += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_clock_that_is_off_adds_nothing() {
        let mut times = PhaseTimes::default();
        let mut clock = StepClock::start(false);
        StepClock::mark(&mut clock, Mark::Drifted);
        StepClock::mark(&mut clock, Mark::Listed);
        StepClock::mark(&mut clock, Mark::Forced);
        StepClock::finish(clock, &mut times);
        assert_eq!(times, PhaseTimes::default());
    }

    #[test]
    fn an_unfinished_step_is_not_counted() {
        // A step that returns an error before its forces leaves the totals as they were.
        let mut times = PhaseTimes::default();
        let mut clock = StepClock::start(true);
        StepClock::mark(&mut clock, Mark::Drifted);
        StepClock::finish(clock, &mut times);
        assert_eq!(times, PhaseTimes::default());
    }

    #[test]
    fn each_phase_gets_the_time_between_its_marks() {
        let mut times = PhaseTimes::default();
        let mut clock = StepClock::start(true);
        StepClock::mark(&mut clock, Mark::Drifted);
        // Sleep inside the force phase only: it must carry at least that much (a sleep never
        // ends early). 100 ms is far above the clock's resolution, and above any pause a
        // loaded test machine could put between the other marks.
        StepClock::mark(&mut clock, Mark::Listed);
        std::thread::sleep(std::time::Duration::from_millis(100));
        StepClock::mark(&mut clock, Mark::Forced);
        StepClock::finish(clock, &mut times);
        assert_eq!(times.steps, 1);
        assert!(times.forces >= 0.100, "forces {}", times.forces);
        // The other two phases hold no sleep: the sleep must not have been counted there too.
        assert!(
            times.integrate + times.neighbour < times.forces,
            "{times:?}"
        );
    }
}
