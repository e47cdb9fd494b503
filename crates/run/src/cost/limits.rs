//! Runs that could not finish: a likely wall time beyond a month, or more memory than the
//! machine has. A front end refuses them unless told to run them anyway.
//!
//! The wall time checked is the likely one ([`super::LikelyCost`]), not the upper bound: a
//! generous `protocol.time_limit` only bounds a discharge that the orifice's law says ends
//! far sooner, and such a run is not refused. Where no law applies (the heap test, an orifice
//! that may clog) the likely discharge is its bound, so the bound is what is checked.

use super::words::{bytes_in_words, duration_in_words};
use super::CostEstimate;
use case::Case;

/// Longest predicted wall time of a run or a study [s]: 30 days. Longer work does not end
/// within any scheduler's time limit or a person's patience, and is nearly always a time
/// step or a time limit given in the wrong unit.
pub const MAX_WALL_TIME: f64 = 30.0 * 86_400.0;

/// What makes a run or a study too costly to start.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CostExcess {
    /// The likely wall time [s] is over [`MAX_WALL_TIME`].
    WallTime {
        /// Likely wall time [s].
        predicted: f64,
    },
    /// The predicted peak memory [bytes] is over the machine's physical memory [bytes].
    Memory {
        /// Predicted peak resident memory [bytes].
        predicted: f64,
        /// The machine's physical memory [bytes].
        physical: f64,
    },
}

impl CostExcess {
    /// The excesses of a predicted wall time `wall` [s] and peak memory `memory` [bytes] on
    /// a machine of `physical` bytes of memory (`None`: unknown, not checked).
    pub fn of(wall: f64, memory: f64, physical: Option<f64>) -> Vec<Self> {
        let mut found = Vec::new();
        if wall.is_nan() || wall > MAX_WALL_TIME {
            found.push(Self::WallTime { predicted: wall });
        }
        if let Some(physical) = physical {
            if memory > physical {
                found.push(Self::Memory {
                    predicted: memory,
                    physical,
                });
            }
        }
        found
    }
}

impl std::fmt::Display for CostExcess {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Self::WallTime { predicted } => write!(
                f,
                "its likely wall time, {} ({predicted:.3e} s), is over the limit of {}",
                duration_in_words(predicted),
                duration_in_words(MAX_WALL_TIME)
            ),
            Self::Memory {
                predicted,
                physical,
            } => write!(
                f,
                "its predicted peak memory, {}, is over this machine's {}",
                bytes_in_words(predicted),
                bytes_in_words(physical)
            ),
        }
    }
}

/// Why a run of `case` with the estimate `estimate` could not finish on a machine of
/// `physical` bytes of memory, naming the keys, their values and the estimate; `None` when
/// it can. The wall time checked is the likely one (module docs).
pub fn cost_refusal(case: &Case, estimate: &CostEstimate, physical: Option<f64>) -> Option<String> {
    let wall = estimate.likely.wall_time.total();
    let excesses = CostExcess::of(wall, estimate.peak_memory, physical);
    if excesses.is_empty() {
        return None;
    }
    let list: Vec<String> = excesses.iter().map(ToString::to_string).collect();
    let mut text = format!("this run could not finish: {}.", list.join("; "));
    if excesses
        .iter()
        .any(|e| matches!(e, CostExcess::WallTime { .. }))
    {
        let p = &case.protocol;
        let likely = &estimate.likely;
        let steps = |t: f64| super::steps_of(case.time_step, t);
        let discharge = match (&likely.discharge.bounded, likely.discharge.law) {
            (Some(why), _) => format!(
                "at most {:.3e} steps ({why})",
                steps(likely.simulated.discharge)
            ),
            (None, law) => format!(
                "about {:.3e} steps ({:.3} kg at {:.3e} kg/s by {}, at most protocol.time_limit)",
                steps(likely.simulated.discharge),
                likely.discharge.fraction * likely.discharge.mass,
                likely.discharge.rate,
                law.unwrap_or("the law"),
            ),
        };
        text += &format!(
            " time.time_step = {:e} s with protocol.time_limit = {} s (the discharge, {discharge}), \
             protocol.max_settle_time = {} s (the settling, about {:.3e} steps) and a fill of \
             about {:.3e} steps give about {:.3e} steps (at most {:.3e}); for {} spheres at \
             {:.1} ns per particle-step ({}, {} thread{}) that is about {:.3e} particle-steps. \
             A larger time.time_step, a shorter protocol.time_limit or fewer particles.count \
             make it shorter.",
            case.time_step,
            p.time_limit,
            p.max_settle_time,
            steps(likely.simulated.settle),
            steps(likely.simulated.fill),
            steps(likely.simulated.fill)
                + steps(likely.simulated.settle)
                + steps(likely.simulated.discharge),
            estimate.steps,
            estimate.particles,
            estimate.ns_per_particle_step,
            if estimate.speed.is_some() {
                "measured on this machine"
            } else {
                "not timed, the slow end of the engine's range"
            },
            estimate.threads,
            if estimate.threads == 1 { "" } else { "s" },
            likely.particle_steps.total(),
        );
    }
    if excesses
        .iter()
        .any(|e| matches!(e, CostExcess::Memory { .. }))
    {
        text += &format!(
            " particles.count = {} at about {:.0} bytes a sphere needs more memory than \
             the machine has.",
            estimate.particles,
            super::BYTES_PER_SPHERE
        );
    }
    Some(text)
}
