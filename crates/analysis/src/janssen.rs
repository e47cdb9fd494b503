//! Janssen's law for the static pressure in a silo (Janssen 1895; Nedderman, *Statics and
//! Kinematics of Granular Materials*, 1992, ch. 3). A horizontal slice of cross-section A and
//! perimeter P at depth h below the free surface balances its weight against the gradient of
//! the mean vertical stress σ_v and the wall friction μ_w p_w on the perimeter, with the wall
//! normal pressure p_w = K σ_v (K the Janssen stress ratio):
//!
//! dσ_v/dh = ρ_b g − μ_w K σ_v / R_h,   R_h = A/P (hydraulic radius),
//!
//! so that, with σ_v(0) = 0,
//!
//! σ_v(h) = (ρ_b g R_h / (K μ_w)) (1 − exp(−K μ_w h / R_h)),
//! p_w(h) = K σ_v(h) = p_sat (1 − exp(−K μ_w h / R_h)),   p_sat = ρ_b g R_h / μ_w.
//!
//! For a cylinder of radius R, R_h = R/2: p_sat = ρ_b g R/(2μ_w) and the exponent is
//! −2Kμ_w h/R. A rectangular box of sides w × l has R_h = wl/(2(w + l)) (Janssen's slice
//! balance with the mean wall pressure; the corners carry less than the mid-walls).
//!
//! The fit of p_w(h) determines p_sat and the product Kμ_w; with ρ_b, g and R_h known, μ_w =
//! ρ_b g R_h/p_sat and K = Kμ_w/μ_w follow, their errors propagated to first order with the
//! fit's covariance of (p_sat, Kμ_w). ρ_b, g and R_h are taken as exact.

use serde::{Deserialize, Serialize};

use crate::error::{
    ensure_at_least, ensure_finite, ensure_positive, ensure_same_length, AnalysisError,
    AnalysisResult,
};
use crate::estimate::Estimate;
use crate::fit::{fit_curve, fit_proportional, CurveData, ParameterBounds};

/// The hydraulic radius R_h = A/P [m] of a silo cross-section of area `area` A [m²] and
/// perimeter `perimeter` P [m] (R/2 for a cylinder, wl/(2(w + l)) for a w × l box).
pub fn hydraulic_radius(area: f64, perimeter: f64) -> AnalysisResult<f64> {
    const CONTEXT: &str = "hydraulic radius";
    ensure_positive(CONTEXT, "cross-section area", area)?;
    ensure_positive(CONTEXT, "perimeter", perimeter)?;
    Ok(area / perimeter)
}

/// A silo's cross-section and fill, as Janssen's law needs them.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct JanssenSilo {
    /// Hydraulic radius R_h = A/P [m].
    pub hydraulic_radius: f64,
    /// Bulk density ρ_b of the fill [kg/m³].
    pub bulk_density: f64,
    /// Gravitational acceleration g [m/s²].
    pub gravity: f64,
}

impl JanssenSilo {
    /// A silo of hydraulic radius `hydraulic_radius` [m] (any cross-section).
    pub fn new(hydraulic_radius: f64, bulk_density: f64, gravity: f64) -> AnalysisResult<Self> {
        const CONTEXT: &str = "Janssen silo";
        ensure_positive(CONTEXT, "hydraulic radius", hydraulic_radius)?;
        ensure_positive(CONTEXT, "bulk density", bulk_density)?;
        ensure_positive(CONTEXT, "gravity", gravity)?;
        Ok(Self {
            hydraulic_radius,
            bulk_density,
            gravity,
        })
    }

    /// A cylindrical silo of radius `radius` R [m]: R_h = πR²/(2πR) = R/2.
    pub fn cylinder(radius: f64, bulk_density: f64, gravity: f64) -> AnalysisResult<Self> {
        ensure_positive("Janssen silo", "cylinder radius", radius)?;
        Self::new(0.5 * radius, bulk_density, gravity)
    }

    /// A box silo of horizontal sides `width` × `length` [m]: R_h = wl/(2(w + l)).
    pub fn rectangular(
        width: f64,
        length: f64,
        bulk_density: f64,
        gravity: f64,
    ) -> AnalysisResult<Self> {
        ensure_positive("Janssen silo", "box width", width)?;
        ensure_positive("Janssen silo", "box length", length)?;
        Self::new(
            hydraulic_radius(width * length, 2.0 * (width + length))?,
            bulk_density,
            gravity,
        )
    }

    /// The saturation wall pressure p_sat = ρ_b g R_h/μ_w [Pa] for wall friction `wall_friction`.
    pub fn saturation_pressure(&self, wall_friction: f64) -> f64 {
        self.bulk_density * self.gravity * self.hydraulic_radius / wall_friction
    }

    /// The wall normal pressure p_w(h) [Pa] at depth `depth` h [m] below the free surface, for
    /// the stress ratio `stress_ratio` K and wall friction `wall_friction` μ_w.
    pub fn wall_pressure(&self, depth: f64, stress_ratio: f64, wall_friction: f64) -> f64 {
        janssen_wall_pressure(
            depth,
            self.saturation_pressure(wall_friction),
            stress_ratio * wall_friction,
            self.hydraulic_radius,
        )
    }

    /// The mean vertical stress σ_v(h) = p_w(h)/K [Pa] at depth `depth` h [m].
    pub fn vertical_stress(&self, depth: f64, stress_ratio: f64, wall_friction: f64) -> f64 {
        self.wall_pressure(depth, stress_ratio, wall_friction) / stress_ratio
    }
}

/// p_w(h) = p_sat (1 − exp(−Kμ_w h/R_h)) [Pa] at depth `depth` h [m], with the saturation
/// pressure `saturation_pressure` [Pa], the product `k_mu` = Kμ_w and the hydraulic radius
/// `hydraulic_radius` R_h [m]. `exp_m1` keeps shallow depths accurate.
pub fn janssen_wall_pressure(
    depth: f64,
    saturation_pressure: f64,
    k_mu: f64,
    hydraulic_radius: f64,
) -> f64 {
    -saturation_pressure * (-k_mu * depth / hydraulic_radius).exp_m1()
}

/// Result of a Janssen fit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JanssenFit {
    /// Saturation wall pressure p_sat [Pa].
    pub saturation_pressure: Estimate,
    /// The product Kμ_w (dimensionless) that sets the decay length R_h/(Kμ_w).
    pub k_mu: Estimate,
    /// Covariance of p_sat and Kμ_w [Pa], from the fit.
    pub covariance: f64,
    /// Wall friction μ_w = ρ_b g R_h/p_sat (dimensionless).
    pub wall_friction: Estimate,
    /// Janssen stress ratio K = Kμ_w/μ_w = Kμ_w p_sat/(ρ_b g R_h) (dimensionless).
    pub stress_ratio: Estimate,
    /// Weighted sum of squared residuals.
    pub chi_squared: f64,
    /// Residual degrees of freedom (n − 2).
    pub degrees_of_freedom: usize,
    /// The silo the fit refers to.
    pub silo: JanssenSilo,
}

impl JanssenFit {
    /// Fitted wall pressure p_w(h) [Pa] at depth `depth` [m].
    pub fn wall_pressure(&self, depth: f64) -> f64 {
        janssen_wall_pressure(
            depth,
            self.saturation_pressure.value,
            self.k_mu.value,
            self.silo.hydraulic_radius,
        )
    }

    /// Fitted mean vertical stress σ_v(h) = p_w(h)/K [Pa] at depth `depth` [m].
    pub fn vertical_stress(&self, depth: f64) -> f64 {
        self.wall_pressure(depth) / self.stress_ratio.value
    }
}

/// Fits p_w(h) = p_sat (1 − exp(−Kμ_w h/R_h)) to wall pressures `pressures` [Pa] at depths
/// `depths` [m] below the free surface, with optional errors `sigma` [Pa]; errors scaled by
/// √(χ²/ν) as every fit here. Needs at least 3 points; the depths should reach beyond the decay
/// length R_h/(Kμ_w), otherwise only the shallow slope Kρ_b g is determined and p_sat and Kμ_w
/// separately are not.
///
/// Start: for fixed Kμ_w the model is proportional in p_sat, so Kμ_w is scanned on a log grid
/// of decay lengths from 1 % to 100 times the deepest depth; Levenberg–Marquardt refines.
pub fn fit_janssen(
    depths: &[f64],
    pressures: &[f64],
    sigma: Option<&[f64]>,
    silo: &JanssenSilo,
) -> AnalysisResult<JanssenFit> {
    const CONTEXT: &str = "Janssen fit";
    ensure_same_length(CONTEXT, depths.len(), pressures.len())?;
    ensure_finite(CONTEXT, depths)?;
    ensure_finite(CONTEXT, pressures)?;
    ensure_at_least(CONTEXT, 3, depths.len())?;
    let silo = JanssenSilo::new(silo.hydraulic_radius, silo.bulk_density, silo.gravity)?;
    if let Some(h) = depths.iter().find(|h| **h < 0.0) {
        return Err(AnalysisError::InvalidArgument {
            context: CONTEXT,
            reason: format!("depths below the free surface must be ≥ 0 m, got {h}"),
        });
    }
    let deepest = depths.iter().cloned().fold(0.0, f64::max);
    if deepest <= 0.0 {
        return Err(AnalysisError::Degenerate {
            context: CONTEXT,
            reason: "all depths are at the free surface".into(),
        });
    }
    // Depth in hydraulic radii, x = h/R_h, so that Kμ_w is the rate in x.
    let scaled: Vec<f64> = depths.iter().map(|h| h / silo.hydraulic_radius).collect();
    let x_max = deepest / silo.hydraulic_radius;

    let mut best: Option<(f64, f64, f64)> = None; // (χ², p_sat, Kμ_w)
                                                  // 80 steps over four decades: neighbouring decay lengths differ by 12 %, close enough
                                                  // for Levenberg–Marquardt to finish from the best of them.
    for step in 0..=80 {
        let decay = 0.01 * x_max * 1e4f64.powf(step as f64 / 80.0);
        let k_mu = 1.0 / decay;
        let basis: Vec<f64> = scaled.iter().map(|x| -(-k_mu * x).exp_m1()).collect();
        let Ok(line) = fit_proportional(&basis, pressures, sigma, 0.95) else {
            continue;
        };
        let p_sat = line.slope.value;
        if p_sat.is_nan() || p_sat <= 0.0 {
            continue;
        }
        if !matches!(best, Some(b) if b.0 <= line.chi_squared) {
            best = Some((line.chi_squared, p_sat, k_mu));
        }
    }
    let Some((_, p0, k0)) = best else {
        return Err(AnalysisError::Degenerate {
            context: CONTEXT,
            reason: "no saturating pressure profile with p_sat > 0 fits the data".into(),
        });
    };
    let positive = ParameterBounds {
        lower: Some(0.0),
        upper: None,
        fixed: false,
    };
    // Fitted as p = A (1 − e^{−Kμ_w x})/(Kμ_w), A = p_sat Kμ_w the initial slope: a bed too
    // shallow to saturate (Kμ_w x ≪ 1) determines A well and p_sat poorly, and in (p_sat,
    // Kμ_w) the search then runs off along the valley p_sat Kμ_w = A without converging.
    let fit = fit_curve(
        |x, p| p[0] * saturating(x, p[1]),
        CurveData {
            x: &scaled,
            y: pressures,
            sigma,
        },
        &[p0 * k0, k0],
        Some(&[positive, positive]),
    )?;
    let (slope, k_mu) = (fit.parameters[0], fit.parameters[1]);
    let slope_k = fit.covariance[0][1];
    if !(slope.value > 0.0 && k_mu.value > 0.0) {
        return Err(AnalysisError::Degenerate {
            context: CONTEXT,
            reason: format!(
                "fit ended at p_sat Kμ_w = {}, Kμ_w = {}",
                slope.value, k_mu.value
            ),
        });
    }
    // p_sat = A/Kμ_w: (σ_p/p)² = (σ_A/A)² + (σ_k/k)² − 2 cov(A, k)/(A k); and
    // cov(p_sat, Kμ_w) = cov(A, k)/k − A σ_k²/k², both to first order.
    let p = slope.value / k_mu.value;
    let relative_variance = slope.relative_error().powi(2) + k_mu.relative_error().powi(2)
        - 2.0 * slope_k / (slope.value * k_mu.value);
    let p_sat = Estimate::new(p, p * relative_variance.max(0.0).sqrt());
    let covariance =
        slope_k / k_mu.value - slope.value * k_mu.standard_error.powi(2) / k_mu.value.powi(2);
    let weight = silo.bulk_density * silo.gravity * silo.hydraulic_radius;
    // μ_w = ρ_b g R_h/p_sat: σ_μ/μ = σ_p/p.
    let mu = weight / p_sat.value;
    let wall_friction = Estimate::new(mu, mu * p_sat.relative_error());
    // K = Kμ_w p_sat/(ρ_b g R_h) = A/(ρ_b g R_h): σ_K = σ_A/(ρ_b g R_h).
    let stress_ratio = Estimate::new(slope.value / weight, slope.standard_error / weight);
    Ok(JanssenFit {
        saturation_pressure: p_sat,
        k_mu,
        covariance,
        wall_friction,
        stress_ratio,
        chi_squared: fit.chi_squared,
        degrees_of_freedom: fit.degrees_of_freedom,
        silo,
    })
}

/// (1 − e^{−k x})/k, the Janssen profile per unit initial slope; x at k = 0.
fn saturating(x: f64, k: f64) -> f64 {
    if k == 0.0 {
        x
    } else {
        -(-k * x).exp_m1() / k
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_support::{normal, seeded_rng, Coverage};

    /// A 10 cm cylinder of glass beads: R_h = 2.5 cm, ρ_b = 1500 kg/m³; μ_w = 0.4, K = 0.5 give
    /// p_sat = 920 Pa and a decay length R_h/(Kμ_w) = 12.5 cm.
    fn cylinder() -> JanssenSilo {
        JanssenSilo::cylinder(0.05, 1500.0, 9.81).unwrap()
    }

    #[test]
    fn shallow_fill_is_hydrostatic_and_deep_fill_saturates() {
        // With x = Kμ_w h/R_h, σ_v/(ρ_b g h) = (1 − e^{−x})/x = 1 − x/2 + x²/6 − …: hydrostatic
        // at the surface, with the first wall-friction correction −x/2 (x = 8e-3 at h = 1 mm);
        // the remainder must be the x²/6 term (next term x³/24 ≈ 2e-8). p_w = Kσ_v. Far
        // below, p_w → ρ_b g R/(2μ_w) for a cylinder.
        let silo = cylinder();
        let (k, mu) = (0.5, 0.4);
        let h = 1e-3;
        let rho_g = 1500.0 * 9.81;
        let x = k * mu * h / silo.hydraulic_radius;
        let ratio = silo.vertical_stress(h, k, mu) / (rho_g * h);
        assert!(
            (ratio - 1.0 + x / 2.0 - x * x / 6.0).abs() < 1e-7,
            "{ratio}"
        );
        let wall = silo.wall_pressure(h, k, mu) / (k * rho_g * h);
        assert!((wall - ratio).abs() < 1e-14);
        let deep = silo.wall_pressure(100.0, k, mu);
        assert!((deep / (rho_g * 0.05 / (2.0 * mu)) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn the_stress_satisfies_the_slice_force_balance() {
        // dσ_v/dh = ρ_b g − μ_w K σ_v/R_h at every depth: central differences (step 1e-5 m,
        // truncation ~ h²σ''' ≈ 1e-8 of ρ_b g) against the balance, to 1e-6 of ρ_b g.
        let silo = cylinder();
        let (k, mu) = (0.45, 0.35);
        let rho_g = silo.bulk_density * silo.gravity;
        for depth in [0.01, 0.05, 0.1, 0.3, 0.8] {
            let step = 1e-5;
            let gradient = (silo.vertical_stress(depth + step, k, mu)
                - silo.vertical_stress(depth - step, k, mu))
                / (2.0 * step);
            let balance =
                rho_g - mu * k * silo.vertical_stress(depth, k, mu) / silo.hydraulic_radius;
            assert!((gradient - balance).abs() < 1e-6 * rho_g, "h = {depth}");
        }
    }

    #[test]
    fn a_square_box_saturates_like_the_cylinder_inscribed_in_it() {
        // R_h = L²/(4L) = L/4 for a square of side L, πR²/(2πR) = L/4 for the cylinder of
        // diameter L: equal saturation pressures.
        let square = JanssenSilo::rectangular(0.1, 0.1, 1500.0, 9.81).unwrap();
        let round = cylinder();
        assert!((square.hydraulic_radius - round.hydraulic_radius).abs() < 1e-15);
        assert!((square.saturation_pressure(0.4) - round.saturation_pressure(0.4)).abs() < 1e-9);
        // A long narrow box tends to a slot: R_h → w/2.
        let slot = JanssenSilo::rectangular(0.01, 1e4, 1500.0, 9.81).unwrap();
        assert!((slot.hydraulic_radius / 0.005 - 1.0).abs() < 1e-5);
    }

    fn noisy_pressures(
        silo: &JanssenSilo,
        depths: &[f64],
        noise: f64,
        rng: &mut impl rand::Rng,
    ) -> Vec<f64> {
        depths
            .iter()
            .map(|&h| silo.wall_pressure(h, 0.5, 0.4) + noise * normal(rng))
            .collect()
    }

    #[test]
    fn friction_and_stress_ratio_are_recovered_from_noisy_wall_pressures() {
        // 20 depths to 40 cm (3.2 decay lengths), noise 1 % of p_sat (9.2 Pa) given as σ:
        // p_sat, Kμ_w, μ_w and K within 4σ, and μ_w and K to better than 10 %.
        let silo = cylinder();
        let depths: Vec<f64> = (1..=20).map(|i| 0.02 * i as f64).collect();
        let noise = 0.01 * silo.saturation_pressure(0.4);
        let mut rng = seeded_rng(61);
        let pressures = noisy_pressures(&silo, &depths, noise, &mut rng);
        let sigma = vec![noise; depths.len()];
        let fit = fit_janssen(&depths, &pressures, Some(&sigma), &silo).unwrap();
        assert_eq!(fit.degrees_of_freedom, 18);
        for (estimate, truth) in [
            (fit.saturation_pressure, silo.saturation_pressure(0.4)),
            (fit.k_mu, 0.2),
            (fit.wall_friction, 0.4),
            (fit.stress_ratio, 0.5),
        ] {
            assert!(
                (estimate.value - truth).abs() < 4.0 * estimate.standard_error,
                "{estimate:?}"
            );
        }
        assert!(fit.wall_friction.relative_error() < 0.1);
        assert!(fit.stress_ratio.relative_error() < 0.1);
        // p_sat and Kμ_w trade off along the data (a larger plateau with a slower rise).
        assert!(fit.covariance < 0.0);
        // The fitted curve and σ_v = p_w/K agree with the truth to the noise level.
        let h = 0.2;
        assert!((fit.wall_pressure(h) - silo.wall_pressure(h, 0.5, 0.4)).abs() < 4.0 * noise);
        assert!((fit.vertical_stress(h) / silo.vertical_stress(h, 0.5, 0.4) - 1.0).abs() < 0.1);
    }

    #[test]
    fn a_bed_too_shallow_to_saturate_still_gives_its_stress_ratio() {
        // 17 depths to 3 cm, a tenth of a decay length (K = 0.5, μ_w = 0.4: 12.5 cm): the
        // profile is nearly hydrostatic, p_w ≈ K ρ_b g h. Its slope fixes K (to 2 %), while
        // p_sat and μ_w stay loose; the fit converges, and K is within 4σ of the truth.
        let silo = cylinder();
        let depths: Vec<f64> = (1..=17).map(|i| 0.03 * i as f64 / 17.0).collect();
        let noise = 0.5;
        let mut rng = seeded_rng(7);
        let pressures = noisy_pressures(&silo, &depths, noise, &mut rng);
        let sigma = vec![noise; depths.len()];
        let fit = fit_janssen(&depths, &pressures, Some(&sigma), &silo).unwrap();
        assert!((fit.stress_ratio.value - 0.5).abs() < 4.0 * fit.stress_ratio.standard_error);
        assert!(
            fit.stress_ratio.relative_error() < 0.02,
            "{:?}",
            fit.stress_ratio
        );
        assert!(fit.wall_friction.relative_error() > fit.stress_ratio.relative_error());
    }

    #[test]
    fn one_sigma_errors_of_friction_and_stress_ratio_cover_the_truth_at_the_student_t_rate() {
        // The set-up above in 2000 data sets: ν = 18, so each ±1σ interval must hold the truth
        // at P(|t_18| ≤ 1) = 67.0 %, within the 4σ binomial band. K's error needs the
        // covariance term: p_sat and Kμ_w are anticorrelated (correlation ≈ −0.89 here), and
        // adding their relative errors in quadrature alone overstates σ_K (85 % coverage).
        let silo = cylinder();
        let depths: Vec<f64> = (1..=20).map(|i| 0.02 * i as f64).collect();
        let noise = 0.01 * silo.saturation_pressure(0.4);
        let sigma = vec![noise; depths.len()];
        let mut mu = Coverage::new("μ_w", 0.4);
        let mut k = Coverage::new("K", 0.5);
        let mut rng = seeded_rng(62);
        for _ in 0..2000 {
            let pressures = noisy_pressures(&silo, &depths, noise, &mut rng);
            let fit = fit_janssen(&depths, &pressures, Some(&sigma), &silo).unwrap();
            mu.record(fit.wall_friction);
            k.record(fit.stress_ratio);
        }
        mu.assert_nominal(18);
        k.assert_nominal(18);
    }

    #[test]
    fn bad_inputs_are_rejected() {
        let silo = cylinder();
        let depths = [0.1, 0.2, 0.3];
        let pressures = [300.0, 500.0, 650.0];
        assert!(matches!(
            fit_janssen(&depths[..2], &pressures[..2], None, &silo),
            Err(AnalysisError::TooFewPoints { .. })
        ));
        assert!(matches!(
            fit_janssen(&depths, &pressures[..2], None, &silo),
            Err(AnalysisError::LengthMismatch { .. })
        ));
        assert!(matches!(
            fit_janssen(&[-0.1, 0.2, 0.3], &pressures, None, &silo),
            Err(AnalysisError::InvalidArgument { .. })
        ));
        assert!(matches!(
            fit_janssen(&depths, &[300.0, f64::NAN, 650.0], None, &silo),
            Err(AnalysisError::NonFinite { .. })
        ));
        assert!(fit_janssen(&depths, &pressures, Some(&[1.0, 0.0, 1.0]), &silo).is_err());
        assert!(matches!(
            fit_janssen(&[0.0, 0.0, 0.0], &pressures, None, &silo),
            Err(AnalysisError::Degenerate { .. })
        ));
        assert!(fit_janssen(&depths, &[-1.0, -2.0, -3.0], None, &silo).is_err());
        assert!(JanssenSilo::cylinder(0.0, 1500.0, 9.81).is_err());
        assert!(JanssenSilo::rectangular(0.1, -0.1, 1500.0, 9.81).is_err());
        assert!(hydraulic_radius(1.0, 0.0).is_err());
        let broken = JanssenSilo {
            hydraulic_radius: 0.025,
            bulk_density: 0.0,
            gravity: 9.81,
        };
        assert!(fit_janssen(&depths, &pressures, None, &broken).is_err());
    }
}
