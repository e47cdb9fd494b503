//! How much simulated time, and so how many steps, the protocol of a case can take from a
//! given point: the fill as estimated from the rate of its insertions, the settling and the
//! discharge at most as long as their limits allow (`protocol.max_settle_time`,
//! `protocol.time_limit`). The discharge usually ends earlier, when the container is empty,
//! drained or clogged, or at `protocol.stop_fraction`; these figures are its upper bound.

use serde::Serialize;

use crate::protocol::{fill_band, CHECK_INTERVAL, INSERT_INTERVAL, WALL_SLIP_SPEED};
use crate::Phase;
use case::Case;

/// A fill whose band does not clear is refused after this long without an insertion [s]
/// (`RunError::CannotFill`): the longest a band can take to clear in a fill that ends.
const FILL_GIVES_UP_AFTER: f64 = 1.0;

/// Simulated time of each part of the protocol [s].
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct PhaseTimes {
    /// Pouring the particles in [s]: an estimate from the rate of the insertions.
    pub fill: f64,
    /// Settling, the wall slip and the settling after it [s]: at most, each settling ending
    /// at `protocol.max_settle_time` if the bed is not calm before.
    pub settle: f64,
    /// From the opening to the stop [s]: at most `protocol.time_limit` (the heap test's lift
    /// and rest included).
    pub discharge: f64,
}

impl PhaseTimes {
    /// The three together [s].
    pub fn total(&self) -> f64 {
        self.fill + self.settle + self.discharge
    }
}

/// Time for a particle starting down at `protocol.fill_speed` to fall `height` [m] under
/// gravity [s]; infinite where it never gets there.
pub(crate) fn fall_time(case: &Case, height: f64) -> f64 {
    let h = height.max(0.0);
    let (v0, g) = (case.protocol.fill_speed, case.gravity);
    // h = v0 t + g t²/2, in the form without cancellation for small g.
    let root = (v0 * v0 + 2.0 * g * h).sqrt();
    if v0 + root > 0.0 {
        2.0 * h / (v0 + root)
    } else {
        f64::INFINITY
    }
}

/// Time for a particle inserted at the top of the insertion band to fall out of its bottom
/// [s]: it starts downward at `protocol.fill_speed` under gravity `gravity`. The band holds
/// about one batch, so the fill inserts about one batch per clearing. Never more than a
/// fill may wait without inserting.
pub(crate) fn band_clear_time(case: &Case) -> f64 {
    let (bottom, top) = fill_band(case);
    fall_time(case, top - bottom).clamp(INSERT_INTERVAL, FILL_GIVES_UP_AFTER + INSERT_INTERVAL)
}

/// The fill's remaining time [s] with `inserted` of the case's particles in at time `t`
/// after the fill began [s]: the rest at the rate so far, counted over at least one clearing
/// of the band. Before the first batch (`inserted` = 0) it is `first_batch` that sets it.
pub(crate) fn fill_time_left(case: &Case, inserted: usize, t: f64, first_batch: usize) -> f64 {
    let total = case.particles.count;
    let inserted = if inserted == 0 { first_batch } else { inserted }.max(1);
    let left = total.saturating_sub(inserted) as f64;
    let per_particle = t.max(band_clear_time(case)) / inserted as f64;
    // The chunk in which the last batch goes in.
    left * per_particle + CHECK_INTERVAL
}

/// Simulated time of the wall slip (`protocol.wall_slip` at the slip's speed) [s].
pub(crate) fn slip_time(case: &Case) -> f64 {
    let steps = (case.protocol.wall_slip / (WALL_SLIP_SPEED * case.time_step)).ceil();
    if case.protocol.wall_slip > 0.0 {
        steps.max(1.0) * case.time_step
    } else {
        0.0
    }
}

/// The longest settling [s]: `protocol.max_settle_time`, plus the chunk in which it is seen.
fn settle_limit(case: &Case) -> f64 {
    case.protocol.max_settle_time + CHECK_INTERVAL
}

/// The longest discharge [s]: `protocol.time_limit`, plus the chunk in which it is seen.
fn discharge_limit(case: &Case) -> f64 {
    case.protocol.time_limit + CHECK_INTERVAL
}

/// What is left of the protocol of `case` in `phase` at simulated time `t` [s] (step
/// `step`), part by part [s]: the fill's estimate from `first_batch` (the particles its first
/// batch placed), the rest at most.
pub fn time_left(case: &Case, phase: Phase, t: f64, step: u64, first_batch: usize) -> PhaseTimes {
    let settle_once = settle_limit(case);
    // After a settling: the slip and a second settling when the walls slip.
    let slip = slip_time(case);
    let after_slip = if slip > 0.0 { slip + settle_once } else { 0.0 };
    let discharge = discharge_limit(case);
    match phase {
        Phase::Fill { inserted, .. } => PhaseTimes {
            fill: fill_time_left(case, inserted, t, first_batch),
            settle: settle_once + after_slip,
            discharge,
        },
        Phase::Settle { since } => PhaseTimes {
            fill: 0.0,
            settle: (since + settle_once - t).max(0.0) + after_slip,
            discharge,
        },
        Phase::Slip { until_step } => PhaseTimes {
            fill: 0.0,
            settle: until_step.saturating_sub(step) as f64 * case.time_step + settle_once,
            discharge,
        },
        Phase::Resettle { since } => PhaseTimes {
            fill: 0.0,
            settle: (since + settle_once - t).max(0.0),
            discharge,
        },
        Phase::Discharge { opened, .. }
        | Phase::Pulse { opened, .. }
        | Phase::Lift { opened }
        | Phase::Rest { opened, .. } => PhaseTimes {
            fill: 0.0,
            settle: 0.0,
            discharge: (opened + discharge - t).max(0.0),
        },
        Phase::Done { .. } => PhaseTimes::default(),
    }
}

/// Steps that `time` [s] of simulated time takes at the time step `time_step` [s], rounded
/// up; a count past 2⁵³ is the nearest representable one.
pub fn steps_of(time_step: f64, time: f64) -> f64 {
    (time / time_step).ceil().max(0.0)
}
