//! The report's analysis of silos with circular orifices (geometry kind `cylinder`):
//! the 3D Beverloo law per series and hopper angle, and the self-similar radial profiles
//! of each case against its measured rate (docs/physics.md §7.6, §8.4).

use analysis::beverloo3d::{fit_beverloo_3d, Beverloo3dConstants, Beverloo3dFit};
use analysis::Estimate;
use serde_json::json;

use super::comparison::ComparisonItem;
use super::data::GridPoint;
use super::{common_gravity, errors_if_known, Fitted};

/// Confidence level of the intervals of C and k.
pub const BEVERLOO_CONFIDENCE: f64 = 0.95;
/// The classic ranges for spheres through circular orifices: C about 0.55–0.65 and k about
/// 1.3–1.6 (Beverloo, Leniger and van de Velde 1961; Nedderman 1992, ch. 10).
pub const CLASSIC_C: (f64, f64) = (0.55, 0.65);
/// See [`CLASSIC_C`].
pub const CLASSIC_K: (f64, f64) = (1.3, 1.6);
/// Largest relative difference accepted between W from the fitted profiles and the
/// measured W (the 5 %).
pub const PROFILE_RATE_TOLERANCE: f64 = 0.05;

/// The 3D Beverloo fit of one series at one hopper angle.
#[derive(Debug, Clone)]
pub struct Beverloo3dGroup {
    /// Series name.
    pub series: String,
    /// Hopper (cone) half-angle [°].
    pub hopper_angle_deg: f64,
    /// Orifice diameters D [m] and their rates W [kg/s] (replica means).
    pub points: Vec<(f64, Estimate)>,
    /// Bulk density ρ_b = φ_B ρ_p [kg/m³], the mean over the points.
    pub bulk_density: f64,
    /// Particle diameter d [m].
    pub particle_diameter: f64,
    /// The fit, or why there is none.
    pub fit: Fitted<Beverloo3dFit>,
}

/// One case's profile fits against its measured rate.
#[derive(Debug, Clone)]
pub struct ProfileCheck {
    /// The grid point's key.
    pub key: String,
    /// Series name.
    pub series: String,
    /// Orifice diameter D [m].
    pub outlet_diameter: f64,
    /// Measured W [kg/s].
    pub rate: Estimate,
    /// The first replica's fits (v_c, a, φ_c, b and W from the profiles).
    pub fit: files::RadialFit,
}

impl ProfileCheck {
    /// (W_profiles − W)/W [-].
    pub fn relative_difference(&self) -> f64 {
        self.fit.profile_rate[0] / self.rate.value - 1.0
    }
}

/// All fits of a study's silo cases.
#[derive(Debug, Clone, Default)]
pub struct SiloAnalysis {
    /// 3D Beverloo per (series, angle).
    pub beverloo: Vec<Beverloo3dGroup>,
    /// Profile fits per grid point that has them.
    pub profiles: Vec<ProfileCheck>,
}

/// Fits the silo points of a study.
pub fn analyse_silos(points: &[GridPoint]) -> SiloAnalysis {
    let silos: Vec<&GridPoint> = points.iter().filter(|p| p.kind == "cylinder").collect();
    let mut groups: Vec<(String, f64)> = Vec::new();
    for p in &silos {
        let key = (p.series.clone(), p.hopper_angle_deg);
        if !groups.contains(&key) {
            groups.push(key);
        }
    }
    let beverloo = groups
        .into_iter()
        .map(|(series, angle)| {
            let mut members: Vec<&&GridPoint> = silos
                .iter()
                .filter(|p| p.series == series && p.hopper_angle_deg == angle)
                .collect();
            members.sort_by(|a, b| a.outlet_width.total_cmp(&b.outlet_width));
            let d = members[0].particle_diameter;
            let phi: Vec<f64> = members
                .iter()
                .map(|p| p.bulk_volume_fraction)
                .filter(|f| f.is_finite())
                .collect();
            let bulk_density = if phi.is_empty() {
                f64::NAN
            } else {
                members[0].particle_density * phi.iter().sum::<f64>() / phi.len() as f64
            };
            let points: Vec<(f64, Estimate)> = members
                .iter()
                .map(|p| (p.outlet_width, p.discharge_rate))
                .collect();
            let gravity = common_gravity(members.iter().map(|p| **p));
            let fit = fit_group(&points, d, bulk_density, gravity);
            Beverloo3dGroup {
                series,
                hopper_angle_deg: angle,
                points,
                bulk_density,
                particle_diameter: d,
                fit,
            }
        })
        .collect();
    let profiles = silos
        .iter()
        .filter_map(|p| {
            Some(ProfileCheck {
                key: p.key.clone(),
                series: p.series.clone(),
                outlet_diameter: p.outlet_width,
                rate: p.discharge_rate,
                fit: p.radial_fit?,
            })
        })
        .collect();
    SiloAnalysis { beverloo, profiles }
}

/// The 3D Beverloo fit of one series and angle: orifice diameters [m] with their rates,
/// the particle diameter d [m], the bulk density ρ_b [kg/m³] and the group's g [m/s²].
fn fit_group(
    points: &[(f64, Estimate)],
    d: f64,
    bulk_density: f64,
    gravity: Fitted<f64>,
) -> Fitted<Beverloo3dFit> {
    let gravity = gravity?;
    if points.len() < 3 {
        return Err(format!(
            "{} orifice diameter(s); the fit needs 3 or more",
            points.len()
        ));
    }
    if !bulk_density.is_finite() {
        return Err("no settled bulk fraction was measured".into());
    }
    let diameters: Vec<f64> = points.iter().map(|p| p.0).collect();
    let rates: Vec<Estimate> = points.iter().map(|p| p.1).collect();
    let values: Vec<f64> = rates.iter().map(|r| r.value).collect();
    let errors = errors_if_known(&rates);
    fit_beverloo_3d(
        &diameters,
        &values,
        errors.as_deref(),
        &Beverloo3dConstants {
            particle_diameter: d,
            bulk_density,
            gravity,
        },
        BEVERLOO_CONFIDENCE,
    )
    .map_err(|e| e.to_string())
}

fn range_item(
    item: String,
    classic: (f64, f64),
    value: Result<(Estimate, analysis::Interval), String>,
) -> ComparisonItem {
    let band = format!("[{}, {}]", classic.0, classic.1);
    let paper = json!(format!("{}–{} (spheres, classic)", classic.0, classic.1));
    match value {
        Err(why) => ComparisonItem {
            item,
            paper,
            measured: json!("not measured"),
            band,
            pass: None,
            note: why,
        },
        Ok((v, interval)) => {
            let pass = v.value >= classic.0 && v.value <= classic.1;
            ComparisonItem {
                item,
                paper,
                measured: json!(v.value),
                band,
                pass: Some(pass),
                note: format!(
                    "{:.3} ± {:.3}, 95 % interval [{:.3}, {:.3}]{}",
                    v.value,
                    v.standard_error,
                    interval.lower,
                    interval.upper,
                    if pass {
                        ""
                    } else {
                        "; outside the classic range"
                    }
                ),
            }
        }
    }
}

/// The silo items: C and k of each 3D Beverloo fit against the classic ranges, and W from
/// each case's fitted profiles against its measured W.
pub fn silo_items(analysis: &SiloAnalysis) -> Vec<ComparisonItem> {
    let mut items = Vec::new();
    for g in &analysis.beverloo {
        let label = format!("series '{}', θ = {}°", g.series, g.hopper_angle_deg);
        items.push(range_item(
            format!("3D Beverloo C ({label})"),
            CLASSIC_C,
            g.fit
                .as_ref()
                .map(|f| (f.coefficient, f.coefficient_interval))
                .map_err(Clone::clone),
        ));
        items.push(range_item(
            format!("3D Beverloo k ({label})"),
            CLASSIC_K,
            g.fit
                .as_ref()
                .map(|f| (f.k, f.k_interval))
                .map_err(Clone::clone),
        ));
    }
    for p in &analysis.profiles {
        let difference = p.relative_difference();
        items.push(ComparisonItem {
            item: format!("W from the fitted profiles / W measured ({})", p.key),
            paper: json!("1 (Janda et al. 2012, in 3D)"),
            measured: json!(1.0 + difference),
            band: format!("[{}, {}]", 1.0 - PROFILE_RATE_TOLERANCE, 1.0 + PROFILE_RATE_TOLERANCE),
            pass: Some(difference.abs() <= PROFILE_RATE_TOLERANCE),
            note: format!(
                "W = {:.4} kg/s measured, {:.4} ± {:.4} kg/s from v_c = {:.3} m/s, a = {:.2}, φ_c = {:.3}, b = {:.2}",
                p.rate.value,
                p.fit.profile_rate[0],
                p.fit.profile_rate[1],
                p.fit.centre_velocity[0],
                p.fit.velocity_exponent[0],
                p.fit.centre_volume_fraction[0],
                p.fit.packing_exponent[0]
            ),
        });
    }
    items
}
