//! Outlet summary: centre values and the flux check W = (2/3) ρ_p d ∫ φ v dx (docs/physics.md §7.4).
//!
//! A sphere of diameter d fills 2/3 of the cylinder of the same projected disc, so a monolayer
//! of 2D area fraction φ carries (2/3) ρ_p d φ v of mass per unit length per unit time
//! (paper Eqs. 13–14). The integral over the orifice is the bin sum Σ (bin value × Δx): since
//! every bin value is an average over its bin, the bin sum is the integral of the bin-averaged
//! field with no further quadrature error. All speeds are downward positive.

use serde::{Deserialize, Serialize};

use super::crossing::{CrossingRecord, VelocityProfile};
use super::error::MeasureError;
use super::snapshot::TimeWindow;
use super::strip::{AreaFractionProfile, StripRecord};

/// Centre values and the three discharge-rate estimates over one window.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OutletSummary {
    /// Averaging window.
    pub window: TimeWindow,
    /// v_c, the crossing speed of the central bins [m/s]; `None` without central crossings.
    pub centre_speed: Option<f64>,
    /// φ_c, the area fraction of the central bins.
    pub centre_area_fraction: Option<f64>,
    /// φ_max, the largest bin area fraction.
    pub max_area_fraction: Option<f64>,
    /// x* of the φ_max bin.
    pub max_area_fraction_position: Option<f64>,
    /// W counted from crossings inside the orifice span [kg/s].
    pub counted_rate: f64,
    /// W counted from all downward crossings [kg/s].
    pub counted_rate_all: f64,
    /// W from ⟨φ v⟩, (2/3) ρ_p d Σ ⟨φ v⟩ Δx [kg/s] — the cleanest flux estimator.
    pub flux_from_area_velocity: f64,
    /// W from φ(x) times the crossing v(x), (2/3) ρ_p d Σ φ v Δx [kg/s]; bins without
    /// crossings contribute zero.
    pub flux_from_profiles: f64,
    /// The crossing velocity profile used.
    pub velocity: VelocityProfile,
    /// The strip profile used.
    pub area_fraction: AreaFractionProfile,
}

/// (2/3) ρ_p d Σ ⟨φ v⟩ Δx [kg/s], with `particle_density` ρ_p [kg/m³].
pub fn flux_from_area_velocity(
    profile: &AreaFractionProfile,
    particle_density: f64,
    particle_diameter: f64,
) -> f64 {
    let integral: f64 = profile
        .entries
        .iter()
        .map(|e| e.area_fraction_speed)
        .sum::<f64>()
        * profile.bins.width();
    2.0 / 3.0 * particle_density * particle_diameter * integral
}

/// (2/3) ρ_p d Σ φ(x) v(x) Δx [kg/s] with the crossing v(x); the two profiles must share bins.
pub fn flux_from_profiles(
    velocity: &VelocityProfile,
    area_fraction: &AreaFractionProfile,
    particle_density: f64,
    particle_diameter: f64,
) -> Result<f64, MeasureError> {
    if !velocity.bins.matches(&area_fraction.bins) {
        return Err(MeasureError::BinsMismatch);
    }
    let integral: f64 = velocity
        .entries
        .iter()
        .zip(&area_fraction.entries)
        .map(|(v, phi)| v.mean_speed.unwrap_or(0.0) * phi.area_fraction)
        .sum::<f64>()
        * velocity.bins.width();
    Ok(2.0 / 3.0 * particle_density * particle_diameter * integral)
}

impl OutletSummary {
    /// Builds both profiles over `window` on the strip's bins and derives the summary;
    /// `particle_density` ρ_p [kg/m³].
    pub fn new(
        crossings: &CrossingRecord,
        strip: &StripRecord,
        window: TimeWindow,
        particle_density: f64,
    ) -> Result<Self, MeasureError> {
        if !(particle_density.is_finite() && particle_density > 0.0) {
            return Err(MeasureError::InvalidParameter {
                name: "particle_density",
                value: particle_density,
                reason: "must be finite and positive",
            });
        }
        let bins = strip.config.bins;
        let diameter = strip.config.geometry.particle_diameter;
        let velocity = crossings.velocity_profile(window, &bins);
        let area_fraction = strip.area_fraction_profile(window)?;
        let flux_from_profiles =
            flux_from_profiles(&velocity, &area_fraction, particle_density, diameter)?;
        let max = area_fraction.max_area_fraction();
        Ok(Self {
            window,
            centre_speed: velocity.centre_speed(),
            centre_area_fraction: area_fraction.centre_area_fraction(),
            max_area_fraction: max.map(|m| m.0),
            max_area_fraction_position: max.map(|m| m.1),
            counted_rate: crossings.mean_discharge_rate_inside(window),
            counted_rate_all: crossings.mean_discharge_rate(window),
            flux_from_area_velocity: flux_from_area_velocity(
                &area_fraction,
                particle_density,
                diameter,
            ),
            flux_from_profiles,
            velocity,
            area_fraction,
        })
    }
}
