//! Analysis of centred outlets by hopper angle (paper §4.1, Table 2, Figs. 3–8): collapsed
//! profile exponents a and b, γ of v_c = √(2γgR), Eq. 12, Eq. 14 against the measured W,
//! and W(α)/W(90°) against Brown's Eq. 3 and Rose–Tanaka.

use analysis::flowrate::{
    brown_ratio, rose_tanaka_ratio, self_similar_discharge_rate, SelfSimilarFlowParameters,
};
use analysis::selfsimilar::{
    fit_centre_velocity, fit_collapsed_power_profile, fit_packing_saturation, CentreVelocityFit,
    PackingSaturationFit, PROFILE_FIT_HALF_WIDTH,
};
use analysis::Estimate;

use super::data::GridPoint;
use super::{errors_if_known, Fitted, GRAVITY};

/// Angle β_d [°] between the stagnant-zone boundary and the horizontal used for the
/// Rose–Tanaka curve. The paper does not state its value; 45° is the low end of the
/// usual 45–60° range (physics spec §8.4), where the law reduces to (cot α)^0.35.
pub const STAGNANT_ZONE_ANGLE_DEG: f64 = 45.0;

/// The fits of one hopper angle within one series (one row of Table 2).
#[derive(Debug, Clone)]
pub struct AngleFit {
    /// Series name.
    pub series: String,
    /// Hopper angle α [°].
    pub hopper_angle_deg: f64,
    /// The grid points (outlet widths), sorted by D.
    pub points: Vec<GridPoint>,
    /// Exponent a of v/v_c = (1 − x*²)^a over the collapsed profiles.
    pub velocity_exponent: Fitted<Estimate>,
    /// Exponent b of φ/φ_c = (1 − x*²)^b.
    pub packing_exponent: Fitted<Estimate>,
    /// γ of v_c = √(2γgR).
    pub centre_velocity: Fitted<CentreVelocityFit>,
    /// Eq. 12 over φ_c(R): φ∞, τ₁, τ₂ [1/mm].
    pub saturation: Fitted<PackingSaturationFit>,
    /// Eq. 14 at each point's R [kg/s], in the order of `points`.
    pub predicted_rates: Vec<Fitted<Estimate>>,
}

/// W(α)/W(90°) at one outlet width, with the two laws.
#[derive(Debug, Clone, PartialEq)]
pub struct AngleRatio {
    /// Series name.
    pub series: String,
    /// Hopper angle α [°].
    pub hopper_angle_deg: f64,
    /// Orifice width D [m].
    pub outlet_width: f64,
    /// Measured W(α)/W(90°).
    pub measured: Estimate,
    /// Brown's Eq. 3 ratio.
    pub brown: f64,
    /// Rose–Tanaka ratio at β_d = [`STAGNANT_ZONE_ANGLE_DEG`].
    pub rose_tanaka: f64,
}

/// Centred points of a series grouped by hopper angle, ascending.
fn by_angle(points: &[GridPoint]) -> Vec<(String, f64, Vec<GridPoint>)> {
    let mut groups: Vec<(String, f64, Vec<GridPoint>)> = Vec::new();
    for p in points.iter().filter(|p| p.is_centred()) {
        match groups
            .iter_mut()
            .find(|(s, a, _)| *s == p.series && (*a - p.hopper_angle_deg).abs() < 1e-9)
        {
            Some(group) => group.2.push(p.clone()),
            None => groups.push((p.series.clone(), p.hopper_angle_deg, vec![p.clone()])),
        }
    }
    for group in &mut groups {
        group
            .2
            .sort_by(|a, b| a.outlet_width.total_cmp(&b.outlet_width));
    }
    groups.sort_by(|a, b| a.0.cmp(&b.0).then(a.1.total_cmp(&b.1)));
    groups
}

/// Fits every (series, α) group of centred outlets.
pub fn fit_angles(points: &[GridPoint]) -> Vec<AngleFit> {
    by_angle(points)
        .into_iter()
        .map(|(series, angle, group)| fit_angle(series, angle, group))
        .collect()
}

fn fit_angle(series: String, hopper_angle_deg: f64, points: Vec<GridPoint>) -> AngleFit {
    let velocity: Vec<_> = points
        .iter()
        .filter_map(|p| p.velocity_profile.clone())
        .collect();
    let packing: Vec<_> = points
        .iter()
        .filter_map(|p| p.area_fraction_profile.clone())
        .collect();
    let velocity_exponent = if velocity.is_empty() {
        Err("no velocity profiles were saved".to_string())
    } else {
        fit_collapsed_power_profile(&velocity, PROFILE_FIT_HALF_WIDTH)
            .map(|f| f.exponent)
            .map_err(|e| e.to_string())
    };
    let packing_exponent = if packing.is_empty() {
        Err("no area-fraction profiles were saved".to_string())
    } else {
        fit_collapsed_power_profile(&packing, PROFILE_FIT_HALF_WIDTH)
            .map(|f| f.exponent)
            .map_err(|e| e.to_string())
    };
    let radii: Vec<f64> = points.iter().map(GridPoint::radius).collect();
    let vc: Vec<Estimate> = points.iter().map(|p| p.centre_velocity).collect();
    let centre_velocity = fit_centre_velocity(
        &radii,
        &vc.iter().map(|e| e.value).collect::<Vec<_>>(),
        errors_if_known(&vc).as_deref(),
        GRAVITY,
    )
    .map_err(|e| e.to_string());
    let phi: Vec<Estimate> = points.iter().map(|p| p.centre_area_fraction).collect();
    let saturation = fit_packing_saturation(
        &radii,
        &phi.iter().map(|e| e.value).collect::<Vec<_>>(),
        errors_if_known(&phi).as_deref(),
    )
    .map_err(|e| e.to_string());
    let predicted_rates = points
        .iter()
        .map(|p| {
            let a = velocity_exponent.as_ref().map_err(|e| format!("a: {e}"))?;
            let b = packing_exponent.as_ref().map_err(|e| format!("b: {e}"))?;
            let g = centre_velocity.as_ref().map_err(|e| format!("γ: {e}"))?;
            let s = saturation.as_ref().map_err(|e| format!("φ∞: {e}"))?;
            let parameters = SelfSimilarFlowParameters {
                velocity_exponent: *a,
                packing_exponent: *b,
                gamma: g.gamma,
                phi_infinity: s.phi_infinity,
                particle_diameter: p.particle_diameter,
                particle_density: p.particle_density,
                gravity: GRAVITY,
            };
            self_similar_discharge_rate(&parameters, p.radius()).map_err(|e| e.to_string())
        })
        .collect();
    AngleFit {
        series,
        hopper_angle_deg,
        points,
        velocity_exponent,
        packing_exponent,
        centre_velocity,
        saturation,
        predicted_rates,
    }
}

/// W(α)/W(90°) for every centred point whose series has a flat-bottomed point of the same
/// width and conditions.
pub fn angle_ratios(points: &[GridPoint]) -> Vec<AngleRatio> {
    let mut ratios = Vec::new();
    for p in points.iter().filter(|p| p.is_centred() && !p.is_flat()) {
        let reference = points.iter().find(|q| {
            q.is_centred()
                && q.is_flat()
                && q.series == p.series
                && (q.outlet_width - p.outlet_width).abs() < 1e-12
                && q.same_conditions(p)
        });
        let Some(reference) = reference else { continue };
        let (w, w0) = (p.discharge_rate, reference.discharge_rate);
        let ratio = w.value / w0.value;
        let relative = |e: Estimate| {
            if e.standard_error.is_finite() {
                e.standard_error / e.value
            } else {
                0.0
            }
        };
        let error = ratio * (relative(w).powi(2) + relative(w0).powi(2)).sqrt();
        let alpha = p.hopper_angle_deg.to_radians();
        ratios.push(AngleRatio {
            series: p.series.clone(),
            hopper_angle_deg: p.hopper_angle_deg,
            outlet_width: p.outlet_width,
            measured: Estimate::new(ratio, error),
            brown: brown_ratio(alpha).unwrap_or(f64::NAN),
            rose_tanaka: rose_tanaka_ratio(alpha, STAGNANT_ZONE_ANGLE_DEG.to_radians())
                .unwrap_or(f64::NAN),
        });
    }
    ratios
}
