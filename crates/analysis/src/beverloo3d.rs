//! The 3D Beverloo law for circular orifices, W = C ρ_b √g (D − k d)^{5/2} (Beverloo, Leniger &
//! van de Velde 1961; the Dim = 3 case of paper Eq. 1): a weighted straight-line fit of W^{2/5}
//! against D, W^{2/5} = (C ρ_b √g)^{2/5} (D − k d), gives k d as the x-intercept and C from the
//! slope m through C = m^{5/2}/(ρ_b √g). Same construction as the 2D fit in `beverloo`, with
//! the exponent 5/2 in place of 3/2 and no slab thickness.

use serde::{Deserialize, Serialize};

use crate::error::{
    ensure_finite, ensure_positive, ensure_same_length, AnalysisError, AnalysisResult,
};
use crate::estimate::{Estimate, Interval};
use crate::fit::{fit_line_weighted, LinearFit};

/// Material constants that turn the fitted line into k and C.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Beverloo3dConstants {
    /// Particle diameter d [m].
    pub particle_diameter: f64,
    /// Bulk density ρ_b [kg/m³] that normalises C (the textbook choice; C ≈ 0.58).
    pub bulk_density: f64,
    /// Gravitational acceleration g [m/s²].
    pub gravity: f64,
}

/// Result of a 3D Beverloo fit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Beverloo3dFit {
    /// k (dimensionless; 1.3–1.6 for spheres).
    pub k: Estimate,
    /// Confidence interval of k (the x-intercept interval divided by d).
    pub k_interval: Interval,
    /// k·d, the x-intercept [m].
    pub kd: Estimate,
    /// C (dimensionless) with its standard error σ_C = (5/2) C σ_m/m.
    pub coefficient: Estimate,
    /// Confidence interval of C (the slope interval mapped through C = m^{5/2}/(ρ_b√g)).
    pub coefficient_interval: Interval,
    /// The underlying fit of W^{2/5} [(kg/s)^{2/5}] against D [m].
    pub line: LinearFit,
}

/// Fits the 3D Beverloo law to mass rates `rates` W [kg/s] measured at orifice diameters
/// `diameters` D [m], with optional rate errors `rate_errors` σ_W [kg/s] (propagated to W^{2/5}
/// as σ_y = (2/5) y σ_W/W and used as weights). Intervals are two-sided Student-t at
/// `confidence_level` with n − 2 degrees of freedom. Needs at least 3 points (repeated fills at
/// one D count) and two distinct diameters.
pub fn fit_beverloo_3d(
    diameters: &[f64],
    rates: &[f64],
    rate_errors: Option<&[f64]>,
    constants: &Beverloo3dConstants,
    confidence_level: f64,
) -> AnalysisResult<Beverloo3dFit> {
    const CONTEXT: &str = "3D Beverloo fit";
    ensure_same_length(CONTEXT, diameters.len(), rates.len())?;
    ensure_finite(CONTEXT, rates)?;
    ensure_positive(CONTEXT, "particle diameter", constants.particle_diameter)?;
    ensure_positive(CONTEXT, "bulk density", constants.bulk_density)?;
    ensure_positive(CONTEXT, "gravity", constants.gravity)?;
    if let Some(w) = rates.iter().find(|w| **w <= 0.0) {
        return Err(AnalysisError::InvalidArgument {
            context: CONTEXT,
            reason: format!("mass rates must be > 0 kg/s, got {w}"),
        });
    }
    let linearised: Vec<f64> = rates.iter().map(|w| w.powf(0.4)).collect();
    let sigma: Option<Vec<f64>> = match rate_errors {
        None => None,
        Some(errors) => {
            ensure_same_length(CONTEXT, rates.len(), errors.len())?;
            Some(
                linearised
                    .iter()
                    .zip(rates.iter().zip(errors))
                    .map(|(y, (w, e))| 0.4 * y * e / w)
                    .collect(),
            )
        }
    };
    let line = fit_line_weighted(diameters, &linearised, sigma.as_deref(), confidence_level)?;
    let slope = line.slope;
    if slope.value.is_nan() || slope.value <= 0.0 {
        return Err(AnalysisError::Degenerate {
            context: CONTEXT,
            reason: format!("W^(2/5) does not grow with D (slope {})", slope.value),
        });
    }
    let d = constants.particle_diameter;
    let kd = line.x_intercept;
    let scale = constants.bulk_density * constants.gravity.sqrt();
    let coefficient = slope.value.powf(2.5) / scale;
    Ok(Beverloo3dFit {
        k: Estimate::new(kd.value / d, kd.standard_error / d),
        k_interval: Interval {
            lower: line.x_intercept_interval.lower / d,
            upper: line.x_intercept_interval.upper / d,
        },
        kd,
        // dC/dm = (5/2) m^{3/2}/(ρ_b√g), so σ_C = (5/2) C σ_m/m.
        coefficient: Estimate::new(
            coefficient,
            2.5 * coefficient * slope.standard_error / slope.value,
        ),
        coefficient_interval: Interval {
            lower: line.slope_interval.lower.max(0.0).powf(2.5) / scale,
            upper: line.slope_interval.upper.powf(2.5) / scale,
        },
        line,
    })
}

/// The 3D Beverloo rate W = C ρ_b √g (D − k d)^{5/2} [kg/s] for orifice diameter `diameter` D
/// [m]; zero when D ≤ k d.
pub fn beverloo_3d_rate(
    coefficient: f64,
    bulk_density: f64,
    diameter: f64,
    k: f64,
    particle_diameter: f64,
    gravity: f64,
) -> f64 {
    let opening = (diameter - k * particle_diameter).max(0.0);
    coefficient * bulk_density * gravity.sqrt() * opening.powf(2.5)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_support::{normal, seeded_rng, Coverage};

    fn glass_beads() -> Beverloo3dConstants {
        // 2 mm glass beads poured to φ_B = 0.60: ρ_b = 0.60 · 2500 kg/m³.
        Beverloo3dConstants {
            particle_diameter: 2e-3,
            bulk_density: 1500.0,
            gravity: 9.81,
        }
    }

    const DIAMETERS: [f64; 5] = [0.010, 0.015, 0.020, 0.025, 0.030];

    fn clean_rates(n: &Beverloo3dConstants) -> Vec<f64> {
        DIAMETERS
            .iter()
            .flat_map(|&d| [d; 3])
            .map(|d| beverloo_3d_rate(0.58, n.bulk_density, d, 1.5, n.particle_diameter, n.gravity))
            .collect()
    }

    #[test]
    fn the_law_is_a_five_halves_power_of_the_effective_opening() {
        // Doubling D − kd multiplies W by 2^{5/2}; no flow at or below D = kd.
        let n = glass_beads();
        let w = |d| beverloo_3d_rate(0.58, n.bulk_density, d, 1.5, n.particle_diameter, n.gravity);
        let kd = 1.5 * n.particle_diameter;
        assert!((w(kd + 0.02) / w(kd + 0.01) - 2f64.powf(2.5)).abs() < 1e-12);
        assert_eq!(w(kd), 0.0);
        assert_eq!(w(0.5 * kd), 0.0);
    }

    #[test]
    fn exact_rates_give_back_c_and_k() {
        // Noise-free W lies exactly on the line W^{2/5} = m(D − kd), so C and k come back to
        // rounding (1e-9 relative; the t-intervals collapse onto them).
        let n = glass_beads();
        let widths: Vec<f64> = DIAMETERS.iter().flat_map(|&d| [d; 3]).collect();
        let fit = fit_beverloo_3d(&widths, &clean_rates(&n), None, &n, 0.95).unwrap();
        assert!(
            (fit.coefficient.value / 0.58 - 1.0).abs() < 1e-9,
            "{:?}",
            fit.coefficient
        );
        assert!((fit.k.value / 1.5 - 1.0).abs() < 1e-9, "{:?}", fit.k);
        assert!((fit.kd.value - 1.5 * n.particle_diameter).abs() < 1e-12);
    }

    #[test]
    fn c_and_k_are_recovered_within_their_95_percent_intervals_from_noisy_rates() {
        // C = 0.58, k = 1.5; five diameters (5–15 d), three fills each, 2 % noise on W given
        // as σ_W. The 95 % Student-t intervals (ν = 13) must hold the truth, and 4σ as well;
        // σ_k < 0.05 (0.023 with this seed) resolves the 1.3–1.6 range quoted for spheres.
        let n = glass_beads();
        let widths: Vec<f64> = DIAMETERS.iter().flat_map(|&d| [d; 3]).collect();
        let clean = clean_rates(&n);
        let errors: Vec<f64> = clean.iter().map(|w| 0.02 * w).collect();
        let mut rng = seeded_rng(41);
        let rates: Vec<f64> = clean
            .iter()
            .zip(&errors)
            .map(|(w, e)| w + e * normal(&mut rng))
            .collect();
        let fit = fit_beverloo_3d(&widths, &rates, Some(&errors), &n, 0.95).unwrap();
        assert_eq!(fit.line.degrees_of_freedom, 13);
        assert!(fit.k_interval.contains(1.5), "{:?}", fit.k_interval);
        assert!(
            fit.coefficient_interval.contains(0.58),
            "{:?}",
            fit.coefficient_interval
        );
        assert!((fit.k.value - 1.5).abs() < 4.0 * fit.k.standard_error);
        assert!((fit.coefficient.value - 0.58).abs() < 4.0 * fit.coefficient.standard_error);
        assert!(fit.k.standard_error < 0.05, "{:?}", fit.k);
        assert!(fit.coefficient_interval.contains(fit.coefficient.value));
    }

    #[test]
    fn one_sigma_errors_of_k_and_c_cover_the_truth_at_the_student_t_rate() {
        // The set-up above in 2000 data sets: with ν = 13 each ±1σ interval must hold the
        // truth at P(|t_13| ≤ 1) = 66.4 %, within the 4σ binomial band. k is a ratio of line
        // parameters and C a power of the slope, both with first-order errors, so this checks
        // the delta-method errors as well as the weights σ_y = (2/5) y σ_W/W.
        let n = glass_beads();
        let widths: Vec<f64> = DIAMETERS.iter().flat_map(|&d| [d; 3]).collect();
        let clean = clean_rates(&n);
        let errors: Vec<f64> = clean.iter().map(|w| 0.02 * w).collect();
        let mut k = Coverage::new("k", 1.5);
        let mut c = Coverage::new("C", 0.58);
        let mut rng = seeded_rng(42);
        for _ in 0..2000 {
            let rates: Vec<f64> = clean
                .iter()
                .zip(&errors)
                .map(|(w, e)| w + e * normal(&mut rng))
                .collect();
            let fit = fit_beverloo_3d(&widths, &rates, Some(&errors), &n, 0.95).unwrap();
            k.record(fit.k);
            c.record(fit.coefficient);
        }
        k.assert_nominal(13);
        c.assert_nominal(13);
    }

    #[test]
    fn too_few_non_positive_and_mismatched_inputs_are_rejected() {
        let n = glass_beads();
        assert!(matches!(
            fit_beverloo_3d(&[0.01, 0.02], &[0.01, 0.05], None, &n, 0.95),
            Err(AnalysisError::TooFewPoints { .. })
        ));
        assert!(matches!(
            fit_beverloo_3d(&[0.01, 0.02, 0.03], &[0.01, 0.0, 0.05], None, &n, 0.95),
            Err(AnalysisError::InvalidArgument { .. })
        ));
        assert!(matches!(
            fit_beverloo_3d(&[0.01, 0.02, 0.03], &[0.01, -0.02, 0.05], None, &n, 0.95),
            Err(AnalysisError::InvalidArgument { .. })
        ));
        assert!(matches!(
            fit_beverloo_3d(&[0.01, 0.02], &[0.01, 0.02, 0.05], None, &n, 0.95),
            Err(AnalysisError::LengthMismatch { .. })
        ));
        assert!(matches!(
            fit_beverloo_3d(
                &[0.01, 0.02, 0.03],
                &[0.01, 0.02, 0.05],
                Some(&[0.001]),
                &n,
                0.95
            ),
            Err(AnalysisError::LengthMismatch { .. })
        ));
        // Rates that fall with D have no Beverloo line.
        assert!(matches!(
            fit_beverloo_3d(&[0.01, 0.02, 0.03], &[0.05, 0.02, 0.01], None, &n, 0.95),
            Err(AnalysisError::Degenerate { .. })
        ));
    }
}
