//! Eccentric-outlet geometry (paper Fig. 1b): gap s to the left wall, offset e, and s* = 2s/(L − D).

use crate::error::{AnalysisError, AnalysisResult};

fn check(gap: f64, hopper_width: f64, orifice_width: f64) -> AnalysisResult<f64> {
    let free = hopper_width - orifice_width;
    if !(free > 0.0 && gap >= 0.0 && gap <= free / 2.0 && free.is_finite() && gap.is_finite()) {
        return Err(AnalysisError::InvalidArgument {
            context: "eccentric geometry",
            reason: format!(
                "need 0 ≤ s ≤ (L − D)/2 and L > D, got s = {gap} m, L = {hopper_width} m, D = {orifice_width} m"
            ),
        });
    }
    Ok(free)
}

/// s* = 2s/(L − D) (dimensionless; 0 at the wall, 1 for a centred outlet), with the gap `gap`
/// s, hopper width `hopper_width` L and orifice width `orifice_width` D in metres.
pub fn normalised_eccentricity(
    gap: f64,
    hopper_width: f64,
    orifice_width: f64,
) -> AnalysisResult<f64> {
    let free = check(gap, hopper_width, orifice_width)?;
    Ok(2.0 * gap / free)
}

/// Offset e of the outlet centre from the hopper axis [m], from e + s = (L − D)/2.
pub fn outlet_offset(gap: f64, hopper_width: f64, orifice_width: f64) -> AnalysisResult<f64> {
    let free = check(gap, hopper_width, orifice_width)?;
    Ok(free / 2.0 - gap)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wall_and_centred_outlets_map_to_zero_and_one() {
        // L = 100 mm, D = 30 mm: (L − D)/2 = 35 mm.
        assert_eq!(normalised_eccentricity(0.0, 0.1, 0.03).unwrap(), 0.0);
        assert!((normalised_eccentricity(0.035, 0.1, 0.03).unwrap() - 1.0).abs() < 1e-12);
        assert!((outlet_offset(0.006, 0.1, 0.03).unwrap() - 0.029).abs() < 1e-12);
        assert!(normalised_eccentricity(0.04, 0.1, 0.03).is_err());
        assert!(normalised_eccentricity(0.0, 0.03, 0.03).is_err());
    }
}
