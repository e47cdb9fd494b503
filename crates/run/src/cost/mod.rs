//! What a run will cost before it starts: its steps, particle-steps, wall time on this
//! machine and peak memory (docs/user-guide.md, "What a run costs"), and the refusal of a
//! run that could not finish.
//!
//! The steps follow from the protocol ([`time_left`]): the fill as estimated from the first
//! batch the run itself inserts, the settling and the discharge at most as long as their
//! limits allow, so the figures are upper bounds where the run stops earlier. The wall time
//! is the particle-steps at the engine's speed measured on this machine just before, on a
//! dense block of the case's spheres ([`measure_speed`]).

mod limits;
mod memory;
mod speed;
mod steps;
mod words;

use serde::Serialize;

use crate::{CaseRun, Phase, RunError, Start};
use case::Case;

pub use limits::{cost_refusal, CostExcess, MAX_WALL_TIME};
pub use memory::{baseline_memory, peak_memory, physical_memory, BYTES_PER_SPHERE, OUTPUT_MEMORY};
pub use speed::{measure_speed, MeasuredSpeed};
pub use steps::{steps_of, time_left, PhaseTimes};
pub use words::{bytes_in_words, duration_in_words};

/// The cost of one run of a case, before it starts.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CostEstimate {
    /// Spheres of the run [-].
    pub particles: usize,
    /// Time step Δt [s].
    pub time_step: f64,
    /// Worker threads of the engine [-].
    pub threads: usize,
    /// Simulated time of each part of the protocol [s]: the fill estimated, the settling and
    /// the discharge at most.
    pub simulated: PhaseTimes,
    /// Steps of the whole protocol [-], at most.
    pub steps: f64,
    /// Particle-steps of each part [-]: the fill's spheres taken as half the count on
    /// average, the rest as the whole count; an upper bound, as the steps are.
    pub particle_steps: PhaseTimes,
    /// Predicted wall time of each part on this machine [s]: its particle-steps at the
    /// measured speed.
    pub wall_time: PhaseTimes,
    /// Peak resident memory of the run [bytes].
    pub peak_memory: f64,
    /// Particles the fill's first batch placed [-] (0 for a run that does not fill): the
    /// fill's rate.
    pub first_batch: usize,
    /// The engine's speed measured for this estimate.
    pub speed: MeasuredSpeed,
}

impl CostEstimate {
    /// The estimate of a run of `case` for `particles` spheres from the protocol's times
    /// `simulated` [s] at the measured `speed`, on a process holding `baseline` [bytes].
    pub fn from_parts(
        case: &Case,
        particles: usize,
        simulated: PhaseTimes,
        speed: MeasuredSpeed,
        (first_batch, baseline): (usize, f64),
    ) -> Self {
        let n = particles as f64;
        let steps = |t: f64| steps_of(case.time_step, t);
        let particle_steps = PhaseTimes {
            fill: 0.5 * n * steps(simulated.fill),
            settle: n * steps(simulated.settle),
            discharge: n * steps(simulated.discharge),
        };
        let seconds = |ps: f64| ps * speed.ns_per_particle_step * 1e-9;
        Self {
            particles,
            time_step: case.time_step,
            threads: speed.threads,
            simulated,
            steps: steps(simulated.fill) + steps(simulated.settle) + steps(simulated.discharge),
            particle_steps,
            wall_time: PhaseTimes {
                fill: seconds(particle_steps.fill),
                settle: seconds(particle_steps.settle),
                discharge: seconds(particle_steps.discharge),
            },
            peak_memory: peak_memory(particles, baseline),
            first_batch,
            speed,
        }
    }
}

/// Estimates the cost of running `case` from `start` on `threads` worker threads: times a
/// dense block of the case's spheres on this machine ([`measure_speed`], about 0.1 s on one
/// thread) and goes on as [`estimate_cost_at`].
pub fn estimate_cost(case: &Case, start: &Start, threads: usize) -> Result<CostEstimate, RunError> {
    let particles = match start {
        Start::Fill => case.particles.count,
        Start::Packing(packing) => packing.particles().len(),
        Start::Bed(bed) => bed.header().particles,
    };
    let speed = measure_speed(case, particles, threads)?;
    estimate_cost_at(case, start, speed)
}

/// The cost of running `case` from `start` at the engine's speed `speed` (measured for a
/// case of the same spheres and laws): inserts the fill's first batch as the run will (the
/// same random draws) to learn the fill's rate.
pub fn estimate_cost_at(
    case: &Case,
    start: &Start,
    speed: MeasuredSpeed,
) -> Result<CostEstimate, RunError> {
    let baseline = baseline_memory();
    let (particles, phase, first_batch) = match start {
        Start::Fill => {
            let mut run = CaseRun::new(case, 1)?;
            let first = run.insert_batch(case.particles.count)?;
            let phase = Phase::Fill {
                inserted: 0,
                last_insert: 0.0,
            };
            (case.particles.count, phase, first)
        }
        Start::Packing(packing) => (packing.particles().len(), Phase::Settle { since: 0.0 }, 0),
        Start::Bed(bed) => (
            bed.header().particles,
            Phase::Discharge {
                opened: 0.0,
                last_crossing: 0.0,
            },
            0,
        ),
    };
    let simulated = time_left(case, phase, 0.0, 0, first_batch);
    Ok(CostEstimate::from_parts(
        case,
        particles,
        simulated,
        speed,
        (first_batch, baseline),
    ))
}

/// Particle-steps left, at most, of a run of `case` in `phase` at simulated time `t` [s]
/// (step `step`) with `particles` spheres in: the fill's at the mean of those in and the
/// case's count, the rest at the case's count or those in, whichever is more.
pub fn particle_steps_left(case: &Case, phase: Phase, t: f64, step: u64, particles: usize) -> f64 {
    let left = time_left(case, phase, t, step, case.particles.count);
    let steps = |t: f64| steps_of(case.time_step, t);
    let total = case.particles.count.max(particles) as f64;
    let filling = 0.5 * (particles as f64 + total);
    match phase {
        Phase::Fill { .. } => {
            filling * steps(left.fill) + total * (steps(left.settle) + steps(left.discharge))
        }
        _ => particles as f64 * (steps(left.settle) + steps(left.discharge)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A speed as the timed block would report it, without timing anything: 30 ns per
    /// particle-step, the paper's case on one thread (docs/performance.md).
    fn speed(ns: f64) -> MeasuredSpeed {
        MeasuredSpeed {
            spheres: 2000,
            steps: 1000,
            threads: 1,
            ns_per_particle_step: ns,
            contacts_per_particle: 6.0,
            seconds: 0.1,
        }
    }

    #[test]
    fn the_base_case_costs_its_protocol_limits_in_steps_at_the_measured_speed() {
        let case = Case::paper_base();
        let first_batch = 500;
        let simulated = time_left(
            &case,
            Phase::Fill {
                inserted: 0,
                last_insert: 0.0,
            },
            0.0,
            0,
            first_batch,
        );
        let e = CostEstimate::from_parts(&case, 3000, simulated, speed(30.0), (first_batch, 0.0));
        // The fill: the band 0.32-0.40 m clears when a sphere starting down at 1 m/s has
        // fallen 0.08 m under g, t = 2h / (v0 + √(v0² + 2gh)); the 2500 spheres after the
        // first batch go in at 500 per clearing, and the last chunk is 2.5 ms. Rounding of a
        // few operations only: 1e-12 relative.
        let (h, v0, g): (f64, f64, f64) = (0.08, 1.0, 9.81);
        let clear = 2.0 * h / (v0 + (v0 * v0 + 2.0 * g * h).sqrt());
        let fill = 5.0 * clear + 0.0025;
        assert!((e.simulated.fill - fill).abs() < 1e-12 * fill, "{e:?}");
        // The settling and the discharge at their limits, 3 s and 20 s, plus the chunk in
        // which each limit is seen: 1 201 000 and 8 001 000 steps of 2.5 µs. The quotient
        // of two decimals may round up by one step.
        let settle = steps_of(case.time_step, e.simulated.settle);
        let discharge = steps_of(case.time_step, e.simulated.discharge);
        assert!((settle - 1_201_000.0).abs() <= 1.0, "{settle}");
        assert!((discharge - 8_001_000.0).abs() <= 1.0, "{discharge}");
        // Particle-steps: the fill at half the count (it rises from none to all), the rest at
        // all 3000; the wall time is them at 30 ns each. Exact products: 1e-12 relative.
        let fill_steps = steps_of(case.time_step, fill);
        let expected = 1500.0 * fill_steps + 3000.0 * (settle + discharge);
        let ps = e.particle_steps.total();
        assert!(
            (ps - expected).abs() < 1e-12 * expected,
            "{ps} vs {expected}"
        );
        let wall = e.wall_time.total();
        assert!((wall - expected * 30e-9).abs() < 1e-12 * wall, "{wall}");
        assert_eq!(e.steps, fill_steps + settle + discharge);
        // Memory: the outputs' allowance and 3 kB a sphere over the baseline (0 here).
        let memory = OUTPUT_MEMORY + 3000.0 * BYTES_PER_SPHERE;
        assert!((e.peak_memory - memory).abs() < 1e-6, "{}", e.peak_memory);
        // About 14 minutes of wall time at most: within the limit, so no refusal.
        assert!(cost_refusal(&case, &e, Some(1e12)).is_none());
    }

    #[test]
    fn a_picosecond_step_with_a_long_time_limit_is_refused_naming_both_keys() {
        let mut case = Case::paper_base();
        case.time_step = 1e-12;
        case.protocol.time_limit = 1e9;
        let simulated = time_left(
            &case,
            Phase::Discharge {
                opened: 0.0,
                last_crossing: 0.0,
            },
            0.0,
            0,
            0,
        );
        // 10^21 steps of 3000 spheres at 30 ns: about 9·10^16 s, far over 30 days.
        let e = CostEstimate::from_parts(&case, 3000, simulated, speed(30.0), (0, 0.0));
        assert!(e.wall_time.total() > 1e16, "{}", e.wall_time.total());
        let why = cost_refusal(&case, &e, None).expect("refused");
        for key in [
            "time.time_step = 1e-12 s",
            "protocol.time_limit = 1000000000 s",
            "over the limit of 30.0 days",
        ] {
            assert!(why.contains(key), "{key:?} not in {why}");
        }
        // The memory check: the same run on a machine of 1 MB is refused for its memory too.
        let why = cost_refusal(&case, &e, Some(1e6)).expect("refused");
        assert!(why.contains("peak memory"), "{why}");
    }
}
