//! Errors raised by the outlet and bulk measurements.

use thiserror::Error;

/// What can go wrong when a probe observes a frame or a record is analysed.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum MeasureError {
    /// A per-particle slice of a frame does not match the length of `ids`.
    #[error("frame field `{field}` has {found} entries but `ids` has {expected}; every per-particle slice must have one entry per id")]
    LengthMismatch {
        /// Name of the offending slice.
        field: &'static str,
        /// Number of ids in the frame.
        expected: usize,
        /// Length of the offending slice.
        found: usize,
    },
    /// A frame holds a NaN or infinite value.
    #[error("frame field `{field}` holds a non-finite value (particle index {index}); the engine state is corrupt")]
    NonFinite {
        /// Name of the offending field.
        field: &'static str,
        /// Index of the particle in the frame (0 for scalar fields).
        index: usize,
    },
    /// A configuration value is out of its valid range.
    #[error("parameter `{name}` = {value} is invalid: {reason}")]
    InvalidParameter {
        /// Parameter name.
        name: &'static str,
        /// Value given.
        value: f64,
        /// What the value must satisfy.
        reason: &'static str,
    },
    /// Frames must be observed in strictly increasing time.
    #[error("observation time {current} s is not after the previous one {previous} s; observe frames in time order")]
    TimeNotIncreasing {
        /// Time of the previous observation [s].
        previous: f64,
        /// Time of the rejected observation [s].
        current: f64,
    },
    /// A time window with end ≤ start.
    #[error("time window [{start}, {end}) s is empty or reversed")]
    EmptyWindow {
        /// Window start [s].
        start: f64,
        /// Window end [s].
        end: f64,
    },
    /// Nothing was recorded inside the requested window.
    #[error("no frames fall inside the time window [{start}, {end}) s")]
    NoFramesInWindow {
        /// Window start [s].
        start: f64,
        /// Window end [s].
        end: f64,
    },
    /// The cumulative discharged mass never reaches the requested value.
    #[error("the discharged mass never reaches {mass} kg (total recorded {recorded} kg)")]
    MassNotReached {
        /// Requested mass [kg].
        mass: f64,
        /// Mass recorded by the probe [kg].
        recorded: f64,
    },
    /// Two profiles that must share their bins do not.
    #[error("velocity and area-fraction profiles use different x-bins; build both from the same `OutletBins`")]
    BinsMismatch,
    /// A numerical routine of the analysis refused the frame's data.
    #[error("analysis of the frame: {0}")]
    Analysis(String),
    /// A polygon outline with fewer than three vertices.
    #[error("container outline needs at least 3 vertices, got {0}")]
    DegenerateOutline(usize),
}
