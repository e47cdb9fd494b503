//! Where a step's wall-clock time goes: the three phases of velocity Verlet as the engine
//! runs them (docs/physics.md §6.2), for the benchmarks' breakdown, in the spirit of the timing
//! table LAMMPS prints after a run (Pair, Neigh, Modify, Other).
//!
//! Each phase is split further into the wall time spent inside the step's parallel regions
//! (the pool's passes, every thread at work) and the rest, which one thread runs while the
//! others wait: the serial share that bounds the speed-up on more cores (Amdahl's law;
//! docs/performance.md, *Scaling model*). On one thread there are no parallel regions.
//!
//! Off by default. When on, the clock is read five times a step and twice more around each
//! parallel region (about 200 ns in all, a few hundredths of a nanosecond per particle-step
//! for the paper's 3000 spheres) and nothing else changes: the same additions in the same
//! order, so trajectories are bit-identical either way.

use std::cell::Cell;
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
    /// The part of `integrate` spent in parallel regions [s].
    pub integrate_parallel: f64,
    /// The part of `neighbour` spent in parallel regions [s].
    pub neighbour_parallel: f64,
    /// The part of `forces` spent in parallel regions [s].
    pub forces_parallel: f64,
}

impl PhaseTimes {
    /// The three phases together [s].
    pub fn total(&self) -> f64 {
        self.integrate + self.neighbour + self.forces
    }

    /// The three phases' time in parallel regions [s]: the rest of [`PhaseTimes::total`]
    /// ran on one thread.
    pub fn parallel(&self) -> f64 {
        self.integrate_parallel + self.neighbour_parallel + self.forces_parallel
    }
}

thread_local! {
    /// Whether the step running on this thread is timed, so that its parallel regions time
    /// themselves.
    static TIMED: Cell<bool> = const { Cell::new(false) };
    /// Wall time spent in this thread's timed parallel regions so far [s].
    static PARALLEL: Cell<f64> = const { Cell::new(0.0) };
    /// Parallel regions open on this thread: only the outermost is timed.
    static DEPTH: Cell<u32> = const { Cell::new(0) };
}

/// Runs `region`, one of the step's parallel passes on the pool, and adds its wall time to
/// the calling thread's parallel time when that thread's step is timed. A region opened
/// inside another is part of it and is not counted twice.
#[inline]
pub(crate) fn parallel_region<R>(region: impl FnOnce() -> R) -> R {
    if !TIMED.with(Cell::get) {
        return region();
    }
    let depth = DEPTH.with(|d| {
        let outer = d.get();
        d.set(outer + 1);
        outer
    });
    let start = Instant::now();
    let result = region();
    if depth == 0 {
        let secs = start.elapsed().as_secs_f64();
        PARALLEL.with(|p| p.set(p.get() + secs));
    }
    DEPTH.with(|d| d.set(depth));
    result
}

/// The calling thread's parallel time so far [s].
fn parallel_so_far() -> f64 {
    PARALLEL.with(Cell::get)
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
    /// The thread's parallel time at the start [s].
    parallel_start: f64,
    /// When each [`Mark`] was passed, by its index, with the thread's parallel time then.
    marks: [Option<(Instant, f64)>; 3],
}

impl StepClock {
    /// Starts timing a step, if `on`.
    #[inline]
    pub(crate) fn start(on: bool) -> Option<Self> {
        TIMED.with(|t| t.set(on));
        on.then(|| Self {
            start: Instant::now(),
            parallel_start: parallel_so_far(),
            marks: [None; 3],
        })
    }

    /// Notes that the step has passed `mark`, if the clock runs.
    #[inline]
    pub(crate) fn mark(clock: &mut Option<Self>, mark: Mark) {
        if let Some(c) = clock {
            c.marks[mark as usize] = Some((Instant::now(), parallel_so_far()));
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
        let end = (Instant::now(), parallel_so_far());
        let start = (c.start, c.parallel_start);
        let secs = |a: (Instant, f64), b: (Instant, f64)| b.0.duration_since(a.0).as_secs_f64();
        let par = |a: (Instant, f64), b: (Instant, f64)| b.1 - a.1;
        times.integrate += secs(start, drifted) + secs(forced, end);
        times.neighbour += secs(drifted, listed);
        times.forces += secs(listed, forced);
        times.integrate_parallel += par(start, drifted) + par(forced, end);
        times.neighbour_parallel += par(drifted, listed);
        times.forces_parallel += par(listed, forced);
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

    #[test]
    fn time_in_a_parallel_region_counts_as_parallel_in_its_phase_and_once() {
        let mut times = PhaseTimes::default();
        let mut clock = StepClock::start(true);
        StepClock::mark(&mut clock, Mark::Drifted);
        StepClock::mark(&mut clock, Mark::Listed);
        // A region with a region inside it, holding a 50 ms sleep: the force phase's parallel
        // part holds the sleep once, not twice, and no more than the phase itself.
        parallel_region(|| {
            parallel_region(|| std::thread::sleep(std::time::Duration::from_millis(50)))
        });
        StepClock::mark(&mut clock, Mark::Forced);
        StepClock::finish(clock, &mut times);
        assert!(times.forces_parallel >= 0.050, "{times:?}");
        assert!(times.forces_parallel <= times.forces, "{times:?}");
        assert!(times.forces_parallel < 0.100, "counted twice: {times:?}");
        assert_eq!(times.integrate_parallel + times.neighbour_parallel, 0.0);
        // Outside a timed step a region adds nothing.
        StepClock::start(false);
        let before = parallel_so_far();
        parallel_region(|| std::thread::sleep(std::time::Duration::from_millis(5)));
        assert_eq!(parallel_so_far(), before);
    }
}
