//! Engine errors. Every one says what went wrong, where, and the likely cause.

use glam::DVec3;

use crate::material::MaterialTableError;

/// Why the engine refused a set-up or stopped a run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DemError {
    /// Δt is above the allowed fraction of the Rayleigh time (paper Eq. 9).
    #[error(
        "time step {time_step:.3e} s is {fraction:.3} of the Rayleigh time {rayleigh_time:.4e} s; \
         the allowed maximum is {max_fraction} (reduce the time step to at most {:.3e} s)",
        max_fraction * rayleigh_time
    )]
    TimeStepTooLarge {
        /// Requested Δt [s].
        time_step: f64,
        /// Smallest Rayleigh time of the particles present [s].
        rayleigh_time: f64,
        /// Δt / t_R [-].
        fraction: f64,
        /// Allowed maximum of Δt / t_R [-].
        max_fraction: f64,
    },
    /// A position or velocity became NaN or infinite.
    #[error(
        "particle {tag} at ({:.6}, {:.6}, {:.6}) m has a non-finite {quantity} at t = {time:.6} s; \
         the likely cause is a time step too large for the contact stiffness, or a bad initial state",
        position.x, position.y, position.z
    )]
    NonFinite {
        /// Tag of the offending particle.
        tag: u64,
        /// Its last finite position, or the non-finite one [m].
        position: DVec3,
        /// Which quantity ("position", "velocity", "force").
        quantity: &'static str,
        /// Simulated time [s].
        time: f64,
    },
    /// An overlap exceeded the allowed fraction of the particle radius.
    #[error(
        "particle {tag} at ({:.6}, {:.6}, {:.6}) m overlaps {other} by {fraction:.3} of its radius \
         (limit {limit}) at t = {time:.6} s; the likely cause is a time step too large, \
         particles inserted overlapping, or a wall moved into particles",
        position.x, position.y, position.z
    )]
    ExcessiveOverlap {
        /// Tag of the offending particle.
        tag: u64,
        /// What it overlaps ("particle 12", "wall 3").
        other: String,
        /// Its position [m].
        position: DVec3,
        /// δ / R [-].
        fraction: f64,
        /// The allowed maximum [-].
        limit: f64,
        /// Simulated time [s].
        time: f64,
    },
    /// Two materials meet but no interaction was defined for them.
    #[error("no interaction defined between materials {0} and {1}")]
    MissingInteraction(u16, u16),
    /// A particle or setting is not physical.
    #[error("invalid input: {0}")]
    InvalidInput(String),
    /// A material table that cannot be installed; the inner error names the key.
    #[error("material table: {0}")]
    MaterialTable(#[from] MaterialTableError),
    /// A wall handle that does not exist.
    #[error("no wall with id {0}")]
    UnknownWall(u32),
    /// A step was asked of a simulation that an earlier step left half done: that step
    /// failed after it had begun to move bodies (a non-finite state or an excessive overlap),
    /// so positions, velocities and forces no longer belong to one instant.
    #[error(
        "the simulation stopped at t = {time:.6} s, in the middle of a step, on this error: \
         {cause}; restore it from a checkpoint (or build it again) before running on"
    )]
    AfterFailure {
        /// Simulated time of the last whole step [s].
        time: f64,
        /// The error that stopped it.
        cause: Box<DemError>,
    },
    /// Rayon could not start its thread pool.
    #[error("could not start {0} worker threads")]
    ThreadPool(usize),
}
