//! The read-only snapshot every probe observes, and the time window analyses are taken over.
//!
//! Coordinates follow docs/physics.md §1/§7: x horizontal from the hopper axis, y normal to the
//! front/back walls (the slab direction), z vertical and up; gravity points along −z.

use serde::{Deserialize, Serialize};

use super::error::MeasureError;

/// A plain, borrowed view of the particles at one instant. Probes only read it.
///
/// The engine side fills it from its own storage; nothing here depends on the engine.
#[derive(Debug, Clone, Copy)]
pub struct Snapshot<'a> {
    /// Simulation time of the snapshot [s].
    pub time: f64,
    /// Stable particle identifiers; a removed particle's id is never reused.
    pub ids: &'a [u64],
    /// Centre positions (x, y, z) [m].
    pub positions: &'a [[f64; 3]],
    /// Centre velocities (v_x, v_y, v_z) [m/s].
    pub velocities: &'a [[f64; 3]],
    /// Radii [m].
    pub radii: &'a [f64],
    /// Particle material density ρ_p [kg/m³]; mass is ρ_p (4/3) π r³ (solid spheres).
    pub density: f64,
    /// Each particle's mass [kg], where the particles are of several materials (a mixture);
    /// `None`: every mass is ρ_p (4/3) π r³ with `density`.
    pub masses: Option<&'a [f64]>,
}

impl Snapshot<'_> {
    /// Number of particles in the frame.
    pub fn len(&self) -> usize {
        self.ids.len()
    }

    /// True when the frame holds no particle.
    pub fn is_empty(&self) -> bool {
        self.ids.is_empty()
    }

    /// Mass of particle `index` [kg]: its own where `masses` is given, else ρ_p (4/3) π r³.
    pub fn mass(&self, index: usize) -> f64 {
        if let Some(masses) = self.masses {
            return masses[index];
        }
        let r = self.radii[index];
        self.density * 4.0 / 3.0 * std::f64::consts::PI * r * r * r
    }

    /// Checks slice lengths, finiteness and a positive density; every probe calls this first
    /// so that a corrupt frame becomes an error instead of a silent NaN in the averages.
    pub fn validate(&self) -> Result<(), MeasureError> {
        let n = self.ids.len();
        let lengths = [
            ("positions", self.positions.len()),
            ("velocities", self.velocities.len()),
            ("radii", self.radii.len()),
            ("masses", self.masses.map_or(n, <[f64]>::len)),
        ];
        for (field, found) in lengths {
            if found != n {
                return Err(MeasureError::LengthMismatch {
                    field,
                    expected: n,
                    found,
                });
            }
        }
        if !self.time.is_finite() {
            return Err(MeasureError::NonFinite {
                field: "time",
                index: 0,
            });
        }
        if !(self.density.is_finite() && self.density > 0.0) {
            return Err(MeasureError::InvalidParameter {
                name: "density",
                value: self.density,
                reason: "must be finite and positive",
            });
        }
        for i in 0..n {
            if !self.positions[i].iter().all(|c| c.is_finite()) {
                return Err(MeasureError::NonFinite {
                    field: "positions",
                    index: i,
                });
            }
            if !self.velocities[i].iter().all(|c| c.is_finite()) {
                return Err(MeasureError::NonFinite {
                    field: "velocities",
                    index: i,
                });
            }
            if !(self.radii[i].is_finite() && self.radii[i] >= 0.0) {
                return Err(MeasureError::NonFinite {
                    field: "radii",
                    index: i,
                });
            }
            if self
                .masses
                .is_some_and(|m| !(m[i].is_finite() && m[i] > 0.0))
            {
                return Err(MeasureError::NonFinite {
                    field: "masses",
                    index: i,
                });
            }
        }
        Ok(())
    }
}

/// A half-open time interval [start, end) [s] over which averages are taken.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TimeWindow {
    /// Start time, included [s].
    pub start: f64,
    /// End time, excluded [s].
    pub end: f64,
}

impl TimeWindow {
    /// A window [start, end); fails unless start < end and both are finite.
    pub fn new(start: f64, end: f64) -> Result<Self, MeasureError> {
        if !(start.is_finite() && end.is_finite() && start < end) {
            return Err(MeasureError::EmptyWindow { start, end });
        }
        Ok(Self { start, end })
    }

    /// Whether time `t` [s] lies in [start, end).
    pub fn contains(&self, t: f64) -> bool {
        t >= self.start && t < self.end
    }

    /// Length of the window [s].
    pub fn duration(&self) -> f64 {
        self.end - self.start
    }
}
