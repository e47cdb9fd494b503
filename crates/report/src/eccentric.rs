//! Analysis of off-centred outlets (paper §4.2, Table 3, Figs. 10–16): Eqs. 16–17 per
//! outlet gap s (pooled over D) and per grid point, σ_s1(s*), φ_max(R), corrected Eq. 18
//! against the measured W, and W/W0 against s*.

use analysis::eccentric::{
    eccentric_discharge_rate, fit_eccentric_packing_profiles, fit_eccentric_velocity_profiles,
    fit_exponential_approach, fit_maximum_packing, AsymmetricProfileFit, AsymmetricProfileOptions,
    EccentricFlowParameters, ExponentialApproachFit,
};
use analysis::selfsimilar::PackingSaturationFit;
use analysis::Estimate;

use super::data::GridPoint;
use super::{common_gravity, errors_if_known, Fitted};

/// Eq. 16–17 fits of one set of profiles.
#[derive(Debug, Clone)]
pub struct ProfileFits {
    /// Eq. 16: δ_s1, ε_s1, σ_s1 of v/√(2gR).
    pub velocity: Fitted<AsymmetricProfileFit>,
    /// Eq. 17: δ_s2, σ_s2 of φ/φ_max with ε_s2 held at 1 (as in Table 3).
    pub packing: Fitted<AsymmetricProfileFit>,
}

/// One grid point of an off-centre series with its own fits and rates.
#[derive(Debug, Clone)]
pub struct EccentricPoint {
    /// The grid point.
    pub point: GridPoint,
    /// Fits of this point's profiles alone (Figs. 11 and 14 against s*).
    pub fits: ProfileFits,
    /// Corrected Eq. 18 with the fits of its gap s [kg/s].
    pub predicted_rate: Fitted<Estimate>,
    /// W/W0 with W0 the centred flat-bottom rate of the same width and conditions.
    pub relative_rate: Fitted<Estimate>,
}

/// One outlet gap s of one series (one row of Table 3).
#[derive(Debug, Clone)]
pub struct GapFit {
    /// Series name.
    pub series: String,
    /// Gap s [m].
    pub outlet_gap: f64,
    /// Fits pooled over the outlet widths.
    pub fits: ProfileFits,
}

/// Everything measured on the off-centre outlets of the study.
#[derive(Debug, Clone, Default)]
pub struct EccentricAnalysis {
    /// Per gap, pooled over D.
    pub gaps: Vec<GapFit>,
    /// Per grid point.
    pub points: Vec<EccentricPoint>,
    /// σ_s1 = c₀ − c₁ e^{−c₂ s*} over the per-point σ_s1 (Fig. 11b), per series.
    pub exponent_fits: Vec<(String, Fitted<ExponentialApproachFit>)>,
    /// φ_max(R) per series: wall outlets (s = 0) and the rest (Fig. 13).
    pub maximum_packing_fits: Vec<(String, String, Fitted<PackingSaturationFit>)>,
}

fn fit_profiles(points: &[&GridPoint]) -> ProfileFits {
    let with_velocity: Vec<&GridPoint> = points
        .iter()
        .copied()
        .filter(|p| p.velocity_profile.is_some())
        .collect();
    let velocity = if with_velocity.is_empty() {
        Err("no velocity profiles were saved".to_string())
    } else {
        let profiles: Vec<_> = with_velocity
            .iter()
            .filter_map(|p| p.velocity_profile.clone())
            .collect();
        let radii: Vec<f64> = with_velocity.iter().map(|p| p.radius()).collect();
        common_gravity(with_velocity.iter().copied()).and_then(|g| {
            fit_eccentric_velocity_profiles(
                &profiles,
                &radii,
                g,
                &AsymmetricProfileOptions::default(),
            )
            .map_err(|e| e.to_string())
        })
    };
    let packing_profiles: Vec<_> = points
        .iter()
        .filter_map(|p| p.area_fraction_profile.clone())
        .collect();
    let packing = if packing_profiles.is_empty() {
        Err("no area-fraction profiles were saved".to_string())
    } else {
        let options = AsymmetricProfileOptions {
            fixed_amplitude: Some(1.0),
            ..AsymmetricProfileOptions::default()
        };
        fit_eccentric_packing_profiles(&packing_profiles, &options).map_err(|e| e.to_string())
    };
    ProfileFits { velocity, packing }
}

/// The centred flat-bottom point that is W0 for `p`.
fn reference<'a>(p: &GridPoint, all: &'a [GridPoint]) -> Option<&'a GridPoint> {
    all.iter().find(|q| {
        q.is_centred()
            && q.is_flat()
            && (q.outlet_width - p.outlet_width).abs() < 1e-12
            && q.same_conditions(p)
    })
}

/// Analyses every off-centre flat-bottomed point of `all`.
pub fn analyse_eccentric(all: &[GridPoint]) -> EccentricAnalysis {
    let off: Vec<&GridPoint> = all
        .iter()
        .filter(|p| !p.is_centred() && p.is_flat())
        .collect();
    let mut analysis = EccentricAnalysis::default();
    let mut series: Vec<&str> = off.iter().map(|p| p.series.as_str()).collect();
    series.sort();
    series.dedup();
    for name in series {
        let members: Vec<&GridPoint> = off.iter().copied().filter(|p| p.series == name).collect();
        let mut gaps: Vec<f64> = members.iter().map(|p| p.outlet_gap).collect();
        gaps.sort_by(f64::total_cmp);
        gaps.dedup();
        for gap in gaps {
            let group: Vec<&GridPoint> = members
                .iter()
                .copied()
                .filter(|p| p.outlet_gap == gap)
                .collect();
            analysis.gaps.push(GapFit {
                series: name.to_string(),
                outlet_gap: gap,
                fits: fit_profiles(&group),
            });
        }
        let mut maxima = |label: &str, keep: &dyn Fn(&GridPoint) -> bool| {
            let group: Vec<&GridPoint> = members.iter().copied().filter(|p| keep(p)).collect();
            let radii: Vec<f64> = group.iter().map(|p| p.radius()).collect();
            // Equal weights, as γ and φ∞ (`centred::fit_angle` says why).
            let phi: Vec<f64> = group.iter().map(|p| p.max_area_fraction.value).collect();
            let fit = fit_maximum_packing(&radii, &phi, None).map_err(|e| e.to_string());
            analysis
                .maximum_packing_fits
                .push((name.to_string(), label.to_string(), fit));
        };
        maxima("s = 0", &|p| p.outlet_gap == 0.0);
        maxima("s > 0", &|p| p.outlet_gap > 0.0);
    }
    for p in off {
        let fits = fit_profiles(&[p]);
        let gap_fit = analysis
            .gaps
            .iter()
            .find(|g| g.series == p.series && g.outlet_gap == p.outlet_gap);
        let phi_fit = analysis
            .maximum_packing_fits
            .iter()
            .find(|(s, label, _)| *s == p.series && (label == "s = 0") == (p.outlet_gap == 0.0));
        let predicted_rate = gap_fit
            .ok_or_else(|| "no fit for this gap".to_string())
            .and_then(|g| {
                let v = g
                    .fits
                    .velocity
                    .as_ref()
                    .map_err(|e| format!("Eq. 16: {e}"))?;
                let f = g
                    .fits
                    .packing
                    .as_ref()
                    .map_err(|e| format!("Eq. 17: {e}"))?;
                // φ_max from the Fig. 13 fit at this R, as the paper does; the measured
                // maximum when that fit is not available.
                let maximum_fraction = match phi_fit.map(|(_, _, fit)| fit) {
                    Some(Ok(fit)) => Estimate::new(fit.fraction(p.radius()), 0.0),
                    _ => p.max_area_fraction,
                };
                let parameters = EccentricFlowParameters {
                    velocity_asymmetry: v.asymmetry,
                    velocity_amplitude: v.amplitude,
                    velocity_exponent: v.exponent,
                    packing_asymmetry: f.asymmetry,
                    packing_amplitude: f.amplitude,
                    packing_exponent: f.exponent,
                    maximum_fraction,
                    particle_diameter: p.particle_diameter,
                    particle_density: p.particle_density,
                    gravity: p.gravity,
                };
                eccentric_discharge_rate(&parameters, p.radius()).map_err(|e| e.to_string())
            });
        let relative_rate = match reference(p, all) {
            None => Err("no centred flat-bottom case of the same width".to_string()),
            Some(r) => {
                let (w, w0) = (p.discharge_rate, r.discharge_rate);
                let ratio = w.value / w0.value;
                let rel = |e: Estimate| {
                    if e.standard_error.is_finite() {
                        e.standard_error / e.value
                    } else {
                        0.0
                    }
                };
                Ok(Estimate::new(ratio, ratio * rel(w).hypot(rel(w0))))
            }
        };
        analysis.points.push(EccentricPoint {
            point: p.clone(),
            fits,
            predicted_rate,
            relative_rate,
        });
    }
    let mut series: Vec<String> = analysis
        .points
        .iter()
        .map(|p| p.point.series.clone())
        .collect();
    series.dedup();
    for name in series {
        let (mut s, mut sigma, mut errors) = (vec![], vec![], vec![]);
        for p in analysis.points.iter().filter(|p| p.point.series == name) {
            if let Ok(fit) = &p.fits.velocity {
                s.push(p.point.dimensionless_gap);
                sigma.push(fit.exponent.value);
                errors.push(fit.exponent);
            }
        }
        let fit = fit_exponential_approach(&s, &sigma, errors_if_known(&errors).as_deref())
            .map_err(|e| e.to_string());
        analysis.exponent_fits.push((name, fit));
    }
    analysis
}
