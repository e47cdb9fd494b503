//! What a run will cost before it starts: its steps, particle-steps, wall time on this
//! machine and peak memory (docs/user-guide.md, "What a run costs"), and the refusal of a
//! run that could not finish.
//!
//! The steps follow from the protocol ([`time_left`]): the fill as estimated from the first
//! batch the run itself inserts, the settling and the discharge at most as long as their
//! limits allow, so these figures are upper bounds where the run stops earlier. Beside them
//! stands the likely cost ([`LikelyCost`]): the settling until the last poured spheres have
//! landed, the discharge as the mass in the container over its Beverloo rate. The wall time
//! is the particle-steps at the engine's speed measured on this machine just before, on a
//! dense block of the case's spheres ([`measure_speed`]); a run short even at its bounds
//! ([`SHORT_RUN_PARTICLE_STEPS`]) is not timed.

mod likely;
mod limits;
mod memory;
mod speed;
mod steps;
mod words;

use serde::Serialize;

use crate::{CaseRun, Phase, RunError, Start};
use case::Case;

pub use likely::{
    DischargeModel, LikelyCost, BEVERLOO_C, BULK_FRACTION, MIN_ORIFICE_DIAMETERS, ORIFICE_K, SLOT_K,
};
pub use limits::{cost_refusal, CostExcess, MAX_WALL_TIME};
pub use memory::{baseline_memory, peak_memory, physical_memory, BYTES_PER_SPHERE, OUTPUT_MEMORY};
pub use speed::{measure_speed, MeasuredSpeed};
pub use steps::{steps_of, time_left, PhaseTimes};
pub use words::{bytes_in_words, duration_in_words};

/// A run of at most this many particle-steps is not timed before it starts [-]: at the
/// engine's 30-110 ns per particle-step on one thread (the dense block's range on 2-core
/// machines, docs/performance.md) it takes 6-22 s at most, and timing the block (0.1-0.3 s)
/// would add a few per cent to it for a figure nobody waits on.
pub const SHORT_RUN_PARTICLE_STEPS: f64 = 2.0e8;

/// The speed that the wall times of a run not timed are reckoned at [ns per particle-step]:
/// the slow end of the block's measured range, so that they err long.
pub const UNTIMED_NS_PER_PARTICLE_STEP: f64 = 110.0;

/// Whether [`estimate_cost`] times the engine.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Timing {
    /// Always: the user asked for the estimate.
    Always,
    /// Only for a run over [`SHORT_RUN_PARTICLE_STEPS`] at its bounds.
    UnlessShort,
}

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
    /// Predicted wall time of each part on this machine at most [s]: its particle-steps at
    /// [`CostEstimate::ns_per_particle_step`].
    pub wall_time: PhaseTimes,
    /// The likely simulated time, particle-steps and wall time of each part.
    pub likely: LikelyCost,
    /// Peak resident memory of the run [bytes].
    pub peak_memory: f64,
    /// Particles the fill's first batch placed [-] (0 for a run that does not fill): the
    /// fill's rate.
    pub first_batch: usize,
    /// The engine's speed measured for this estimate; `None` for a short run not timed.
    pub speed: Option<MeasuredSpeed>,
    /// The speed the wall times are reckoned at [ns per particle-step]: the measured one, or
    /// [`UNTIMED_NS_PER_PARTICLE_STEP`] for a run not timed.
    pub ns_per_particle_step: f64,
}

impl CostEstimate {
    /// The estimate of a run of `case` for `particles` spheres from the protocol's times
    /// `simulated` [s] (at most) at the measured `speed` (`None`: not timed), on a process
    /// holding `baseline` [bytes].
    pub fn from_parts(
        case: &Case,
        particles: usize,
        simulated: PhaseTimes,
        speed: Option<MeasuredSpeed>,
        (first_batch, baseline): (usize, f64),
    ) -> Self {
        let steps = |t: f64| steps_of(case.time_step, t);
        let particle_steps = bound_particle_steps(case, particles, simulated);
        let ns = speed.map_or(UNTIMED_NS_PER_PARTICLE_STEP, |s| s.ns_per_particle_step);
        let seconds = |ps: f64| ps * ns * 1e-9;
        // A run that pours its spheres settles them after the fill; one from a packing
        // starts at rest.
        let filled = simulated.fill > 0.0;
        Self {
            particles,
            time_step: case.time_step,
            threads: speed.map_or(1, |s| s.threads),
            simulated,
            steps: steps(simulated.fill) + steps(simulated.settle) + steps(simulated.discharge),
            particle_steps,
            wall_time: PhaseTimes {
                fill: seconds(particle_steps.fill),
                settle: seconds(particle_steps.settle),
                discharge: seconds(particle_steps.discharge),
            },
            likely: likely::likely_cost(case, particles, simulated, filled, ns),
            // Memory is held per sphere: a shaped grain's members each.
            peak_memory: peak_memory(
                (particles as f64 * case.particles.mean_spheres_per_grain()).ceil() as usize,
                baseline,
            ),
            first_batch,
            speed,
            ns_per_particle_step: ns,
        }
    }

    /// Whether the run is short enough not to be timed: at most
    /// [`SHORT_RUN_PARTICLE_STEPS`] particle-steps at its bounds.
    pub fn is_short(&self) -> bool {
        self.particle_steps.total() <= SHORT_RUN_PARTICLE_STEPS
    }
}

/// Particle-steps of each part at most [-] for `particles` spheres over the times
/// `simulated` [s]: the fill's at half the count, the rest at the whole count.
fn bound_particle_steps(case: &Case, particles: usize, simulated: PhaseTimes) -> PhaseTimes {
    let n = particles as f64;
    let steps = |t: f64| steps_of(case.time_step, t);
    PhaseTimes {
        fill: 0.5 * n * steps(simulated.fill),
        settle: n * steps(simulated.settle),
        discharge: n * steps(simulated.discharge),
    }
}

/// Estimates the cost of running `case` from `start` on `threads` worker threads: with
/// [`Timing::Always`], or for a run over [`SHORT_RUN_PARTICLE_STEPS`] at its bounds, times a
/// dense block of the case's spheres on this machine ([`measure_speed`], about 0.1 s on one
/// thread) and goes on as [`estimate_cost_at`]; a short run is not timed.
pub fn estimate_cost(
    case: &Case,
    start: &Start,
    threads: usize,
    timing: Timing,
) -> Result<CostEstimate, RunError> {
    let parts = protocol_parts(case, start)?;
    let bound = bound_particle_steps(case, parts.particles, parts.simulated).total();
    let speed = if timing == Timing::UnlessShort && bound <= SHORT_RUN_PARTICLE_STEPS {
        None
    } else {
        Some(measure_speed(case, parts.particles, threads)?)
    };
    Ok(parts.estimate(case, speed))
}

/// The cost of running `case` from `start` at the engine's speed `speed` (measured for a
/// case of the same spheres and laws): inserts the fill's first batch as the run will (the
/// same random draws) to learn the fill's rate.
pub fn estimate_cost_at(
    case: &Case,
    start: &Start,
    speed: MeasuredSpeed,
) -> Result<CostEstimate, RunError> {
    Ok(protocol_parts(case, start)?.estimate(case, Some(speed)))
}

/// What an estimate needs besides the engine's speed.
struct ProtocolParts {
    particles: usize,
    simulated: PhaseTimes,
    first_batch: usize,
    baseline: f64,
}

impl ProtocolParts {
    fn estimate(&self, case: &Case, speed: Option<MeasuredSpeed>) -> CostEstimate {
        CostEstimate::from_parts(
            case,
            self.particles,
            self.simulated,
            speed,
            (self.first_batch, self.baseline),
        )
    }
}

/// The spheres and the protocol's times at most of a run of `case` from `start`: inserts
/// the fill's first batch as the run will (the same random draws) to learn the fill's rate.
fn protocol_parts(case: &Case, start: &Start) -> Result<ProtocolParts, RunError> {
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
        // A bed counts its spheres, a shaped grain's members each; the estimate counts
        // grains.
        Start::Bed(bed) => (
            (bed.header().particles as f64 / case.particles.mean_spheres_per_grain()).round()
                as usize,
            Phase::Discharge {
                opened: 0.0,
                last_crossing: 0.0,
            },
            0,
        ),
    };
    Ok(ProtocolParts {
        particles,
        simulated: time_left(case, phase, 0.0, 0, first_batch),
        first_batch,
        baseline,
    })
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
            grains: 2000,
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
        let e = CostEstimate::from_parts(
            &case,
            3000,
            simulated,
            Some(speed(30.0)),
            (first_batch, 0.0),
        );
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
        // Memory: the outputs' allowance and 1 kB a sphere over the baseline (0 here).
        let memory = OUTPUT_MEMORY + 3000.0 * BYTES_PER_SPHERE;
        assert!((e.peak_memory - memory).abs() < 1e-6, "{}", e.peak_memory);
        // About 14 minutes of wall time at most: within the limit, so no refusal.
        assert!(cost_refusal(&case, &e, Some(1e12)).is_none());
        // 2.8·10¹⁰ particle-steps at its bounds: not short, so a run times the engine.
        assert!(!e.is_short());
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
        // 10^21 steps of 3000 spheres at 30 ns at most: about 9·10^16 s. Likely, the 0.106 kg
        // leave at 32.8 g/s in 3.2 s, and the clog timeout's 0.3 s follows: 3.5·10^12 steps,
        // still some 10^8 s, far over the 30 days that the refusal checks.
        let e = CostEstimate::from_parts(&case, 3000, simulated, Some(speed(30.0)), (0, 0.0));
        assert!(e.wall_time.total() > 1e16, "{}", e.wall_time.total());
        assert!(e.likely.wall_time.total() > 1e8, "{:?}", e.likely);
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

    /// The estimate of `case` from a fill whose first batch placed 500 spheres, at 30 ns per
    /// particle-step.
    fn from_fill(case: &Case) -> CostEstimate {
        let fill = Phase::Fill {
            inserted: 0,
            last_insert: 0.0,
        };
        let simulated = time_left(case, fill, 0.0, 0, 500);
        let n = case.particles.count;
        CostEstimate::from_parts(case, n, simulated, Some(speed(30.0)), (500, 0.0))
    }

    #[test]
    fn the_base_case_likely_drains_its_mass_at_the_slot_beverloo_rate() {
        let case = Case::paper_base();
        let e = from_fill(&case);
        let l = &e.likely;
        // The 2D law with the paper's C = 0.58, k = 1.55 and ρ_b = 0.59 · 2500 kg/m³ gives
        // 32.8 g/s at D = 30 mm (docs/physics.md §8.2, rounded to 0.1 g/s there).
        assert_eq!(l.discharge.law, Some("beverloo_2d"));
        assert!(
            (l.discharge.rate - 0.0328).abs() < 0.0001,
            "{:?}",
            l.discharge
        );
        // The run waits for the whole fill (stop_fraction = 1): the mass over the rate, then
        // the clog timeout that ends a drained flat bottom, and the chunk it is seen in.
        // Sums of a few roundings: 1e-12 relative.
        let mass = case.particles.total_mass();
        let expected = mass / l.discharge.rate + case.protocol.clog_timeout + 0.0025;
        assert!(
            (l.simulated.discharge - expected).abs() < 1e-12 * expected,
            "{l:?}"
        );
        // The measured run drained in 4.19 s (W = 51 g/s over its steady window, then its
        // stagnant zones slowly): the likely time must be within a factor 1.5 of it, and
        // far under the 20 s limit.
        assert!(
            (4.19 / 1.5..4.19 * 1.5).contains(&l.simulated.discharge),
            "{l:?}"
        );
        // The settling: the last batch's fall from the fill top (0.4 m) at 1 m/s down, then
        // the check's chunk; the quasi-2D slab calms as it lands. Closed form: 1e-12.
        let h: f64 = 0.4;
        let fall = 2.0 * h / (1.0 + (1.0 + 2.0 * 9.81 * h).sqrt());
        assert!(
            (l.simulated.settle - (fall + 0.0025)).abs() < 1e-12,
            "{l:?}"
        );
        // Particles leave at a steady rate, so the discharge holds half the count on average
        // while it flows and none during the timeout (an exact product of step counts).
        let flow = steps_of(case.time_step, l.discharge.flowing);
        let ps = 0.5 * 3000.0 * flow;
        assert!(
            (l.particle_steps.discharge - ps).abs() <= 1e-12 * ps,
            "{l:?}"
        );
        // Likely is never over the bound, and here well under it (23 s of simulated limits
        // against about 3.7 s).
        assert!(l.wall_time.total() < 0.2 * e.wall_time.total(), "{e:?}");
    }

    #[test]
    fn a_study_case_stops_at_its_fraction_and_a_narrow_orifice_keeps_its_bound() {
        let mut case = Case::paper_base();
        case.protocol.stop_fraction = 0.7;
        let e = from_fill(&case);
        let d = &e.likely.discharge;
        // 70 % of the fill at the rate, no clog timeout: the run stops at the fraction.
        // Rounding of a few operations: 1e-12 relative.
        let expected = 0.7 * d.mass / d.rate + 0.0025;
        let got = e.likely.simulated.discharge;
        assert!((got - expected).abs() < 1e-12 * expected, "{d:?}");
        // D = 15 mm = 5 d may clog: the discharge keeps its bound, and says why.
        if let case::Geometry::Slab(slab) = &mut case.geometry {
            *slab = case::SlabGeometry::centred(0.1, 0.4, 3.03e-3, 0.015, 90.0);
        }
        let e = from_fill(&case);
        let why = e.likely.discharge.bounded.clone().expect("bounded");
        assert!(why.contains("may clog"), "{why}");
        assert_eq!(e.likely.simulated.discharge, e.simulated.discharge);
    }

    #[test]
    fn the_reduced_benchmark_silo_likely_drains_at_the_orifice_beverloo_rate() {
        let text = include_str!("../../../../cases/dosta2024-silo-reduced.toml");
        let case = case::parse_case(text, "dosta2024-silo-reduced.toml", &[]).expect("case");
        let e = from_fill(&case);
        let d = &e.likely.discharge;
        assert_eq!(d.law, Some("beverloo_3d"));
        // Measured in docs/reproduction.md: W = 1.943 ± 0.023 kg/s through its 60 mm orifice
        // in a 45° cone. The flat-bottom law with C = 0.58, k = 1.5 leaves out the cone's
        // gain; within 15 % of the measurement.
        assert!((d.rate / 1.943 - 1.0).abs() < 0.15, "{d:?}");
        // The silo emptied 1.07 s after the opening: the mass over the rate lies within 20 %
        // of it (the rate falls as the cone empties, the law keeps it steady).
        assert!((d.flowing / 1.07 - 1.0).abs() < 0.2, "{d:?}");
        // Its settling: the last batch's fall from 0.235 m and the 3D bed's calming (0.3 s),
        // measured 0.3 s after the pour; within a factor 1.5.
        let settle = e.likely.simulated.settle;
        assert!((0.3 / 1.5..0.3 * 1.5).contains(&settle), "{settle}");
    }

    #[test]
    fn a_short_run_is_not_timed_and_a_picosecond_step_is() {
        // 250 spheres, 0.15 s of settling and 0.6 s of discharge at most: 7.5·10⁷
        // particle-steps, short; the estimate reckons its wall time at the untimed speed.
        let text = include_str!("../../tests/data/tiny.toml");
        let case = case::parse_case(text, "tiny.toml", &[]).expect("case");
        let e = estimate_cost(&case, &Start::Fill, 1, Timing::UnlessShort).expect("estimate");
        assert!(e.is_short(), "{e:?}");
        assert!(e.speed.is_none());
        assert_eq!(e.ns_per_particle_step, UNTIMED_NS_PER_PARTICLE_STEP);
        // Refusal does not depend on the timing: a picosecond step is far from short.
        let mut case = case;
        case.time_step = 1e-12;
        case.protocol.time_limit = 1e9;
        let fill = Phase::Fill {
            inserted: 0,
            last_insert: 0.0,
        };
        let simulated = time_left(&case, fill, 0.0, 0, 100);
        let e = CostEstimate::from_parts(&case, 250, simulated, None, (100, 0.0));
        assert!(!e.is_short());
        assert!(cost_refusal(&case, &e, None).is_some());
    }
}
