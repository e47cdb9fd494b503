//! Rose & Tanaka (1959) hopper-angle factor as commonly cited (Nedderman 1992), physics spec §8.4:
//! W(α)/W(90°) = (tan α · tan β_d)^(−0.35) for α < 90° − β_d, and 1 otherwise.
//!
//! α is the hopper half-angle from the vertical; β_d is the angle between the stagnant-zone
//! boundary and the horizontal (45–60° for free-flowing grains). Below α = 90° − β_d the
//! hopper wall cuts into the flowing region and speeds the flow up; above it the stagnant
//! zone shields the wall and the flat-bottom rate is recovered. The exponent −0.35 is as
//! cited in secondary sources; it has not been checked against the 1959 paper.

use crate::error::{AnalysisError, AnalysisResult};

/// Rose–Tanaka ratio for `hopper_angle` α [rad] in (0, π/2] and `stagnant_zone_angle`
/// β_d [rad] in (0, π/2).
pub fn rose_tanaka_ratio(hopper_angle: f64, stagnant_zone_angle: f64) -> AnalysisResult<f64> {
    let half_pi = std::f64::consts::FRAC_PI_2;
    if !(hopper_angle > 0.0 && hopper_angle <= half_pi) {
        return Err(AnalysisError::InvalidArgument {
            context: "Rose–Tanaka ratio",
            reason: format!("hopper angle must lie in (0, π/2] rad, got {hopper_angle}"),
        });
    }
    if !(stagnant_zone_angle > 0.0 && stagnant_zone_angle < half_pi) {
        return Err(AnalysisError::InvalidArgument {
            context: "Rose–Tanaka ratio",
            reason: format!(
                "stagnant-zone angle must lie in (0, π/2) rad, got {stagnant_zone_angle}"
            ),
        });
    }
    if hopper_angle < half_pi - stagnant_zone_angle {
        Ok((hopper_angle.tan() * stagnant_zone_angle.tan()).powf(-0.35))
    } else {
        Ok(1.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_factor_is_continuous_at_the_stagnant_zone_limit() {
        // At α = 90° − β_d, tan α · tan β_d = 1, so the power-law branch equals 1; just below,
        // it may exceed 1 by only O(Δα) (1e-6 rad → < 1e-5).
        let beta = f64::to_radians(50.0);
        let limit = std::f64::consts::FRAC_PI_2 - beta;
        let below = rose_tanaka_ratio(limit - 1e-6, beta).unwrap();
        assert!(below > 1.0 && below - 1.0 < 1e-5);
        assert_eq!(rose_tanaka_ratio(limit + 1e-6, beta).unwrap(), 1.0);
    }

    #[test]
    fn steeper_hoppers_discharge_faster() {
        // With β_d = 45°, the factor reduces to (cot α)^0.35: 1.586 at 15°, 1.212 at 30°.
        let beta = f64::to_radians(45.0);
        let r15 = rose_tanaka_ratio(f64::to_radians(15.0), beta).unwrap();
        let r30 = rose_tanaka_ratio(f64::to_radians(30.0), beta).unwrap();
        let cot = |deg: f64| 1.0 / f64::to_radians(deg).tan();
        // β_d = 45° makes tan β_d = 1 up to rounding, so the two forms agree to 1e-12.
        assert!((r15 - cot(15.0).powf(0.35)).abs() < 1e-12);
        assert!((r30 - cot(30.0).powf(0.35)).abs() < 1e-12);
        assert!(r15 > r30 && r30 > 1.0);
        assert_eq!(
            rose_tanaka_ratio(std::f64::consts::FRAC_PI_2, beta).unwrap(),
            1.0
        );
    }

    #[test]
    fn angles_outside_their_ranges_are_rejected() {
        assert!(rose_tanaka_ratio(0.0, 0.8).is_err());
        assert!(rose_tanaka_ratio(0.5, std::f64::consts::FRAC_PI_2).is_err());
    }
}
