//! Area of the intersection of two discs: a disc of radius a whose centre lies at distance s
//! from the silo axis, and the disc of radius ρ about the axis (the lens area).
//!
//! For |ρ − a| < s < ρ + a the lens is two circular segments cut by the common chord. The
//! chord lies at signed distances d₁ = (s² + ρ² − a²)/(2s) from the axis and
//! d₂ = (s² + a² − ρ²)/(2s) from the disc centre, with half-length
//! h = √((s + a + ρ)(−s + a + ρ)(s − a + ρ)(s + a − ρ))/(2s); with the half-angles
//! α = atan2(h, d₁), β = atan2(h, d₂) the area is
//!
//! A = ρ²(2α − sin 2α)/2 + a²(2β − sin 2β)/2,
//!
//! the textbook a² acos(d₂/a) + ρ² acos(d₁/ρ) − s h written with atan2 and a series for
//! x − sin x, so that a small disc straddling a large circle keeps its relative accuracy
//! (acos near 1 and the difference of two nearly equal terms would lose it). A = π min(a, ρ)²
//! for s ≤ |ρ − a| (one disc inside the other) and 0 for s ≥ ρ + a.

use crate::error::{AnalysisError, AnalysisResult};

/// x − sin x without cancellation: its Taylor series Σ_{k≥1} (−1)^{k+1} x^{2k+1}/(2k+1)!
/// below |x| = 0.5 (ten terms leave an error below 0.5²³/23! ≈ 5e-30, far under round-off),
/// the direct difference above (where it loses at most a factor 1/(1 − sin 0.5/0.5) ≈ 25 ulp).
fn x_minus_sin(x: f64) -> f64 {
    if x.abs() >= 0.5 {
        return x - x.sin();
    }
    let x2 = x * x;
    let mut term = x * x2 / 6.0;
    let mut sum = term;
    for k in 2..=10 {
        let k = k as f64;
        term *= -x2 / ((2.0 * k) * (2.0 * k + 1.0));
        sum += term;
    }
    sum
}

/// The lens area without input checks; `offset` s ≥ 0, `disc_radius` a ≥ 0 and `axis_radius`
/// ρ ≥ 0 are assumed finite. Used in the quadrature loops of `sphere_slab`.
pub(crate) fn lens_area(offset: f64, disc_radius: f64, axis_radius: f64) -> f64 {
    let (s, a, rho) = (offset, disc_radius, axis_radius);
    if s >= a + rho {
        return 0.0;
    }
    if s <= (rho - a).abs() {
        let smaller = a.min(rho);
        return std::f64::consts::PI * smaller * smaller;
    }
    // Differences of squares as products, so s ≈ ρ or a ≈ ρ do not cancel.
    let d1 = ((rho - a) * (rho + a) + s * s) / (2.0 * s);
    let d2 = ((s - rho) * (s + rho) + a * a) / (2.0 * s);
    let product = (s + a + rho) * (a + rho - s) * (s - a + rho) * (s + a - rho);
    let h = product.max(0.0).sqrt() / (2.0 * s);
    let alpha = h.atan2(d1);
    let beta = h.atan2(d2);
    0.5 * (rho * rho * x_minus_sin(2.0 * alpha) + a * a * x_minus_sin(2.0 * beta))
}

fn check(context: &'static str, name: &str, value: f64) -> AnalysisResult<()> {
    if value.is_finite() && value >= 0.0 {
        Ok(())
    } else {
        Err(AnalysisError::InvalidArgument {
            context,
            reason: format!("{name} must be finite and ≥ 0, got {value}"),
        })
    }
}

/// Area [m²] of the disc of radius `disc_radius` a [m], centred at distance `offset` s [m]
/// from the axis, that lies within `axis_radius` ρ [m] of the axis (see the module formula).
pub fn disc_in_disc_area(offset: f64, disc_radius: f64, axis_radius: f64) -> AnalysisResult<f64> {
    const CONTEXT: &str = "disc-in-disc area";
    check(CONTEXT, "offset", offset)?;
    check(CONTEXT, "disc radius", disc_radius)?;
    check(CONTEXT, "axis radius", axis_radius)?;
    Ok(lens_area(offset, disc_radius, axis_radius))
}

/// Area [m²] of the same disc inside the annulus `inner` ≤ ρ < `outer` about the axis [m]:
/// the difference of two lens areas.
pub fn disc_in_annulus_area(
    offset: f64,
    disc_radius: f64,
    inner: f64,
    outer: f64,
) -> AnalysisResult<f64> {
    const CONTEXT: &str = "disc-in-annulus area";
    check(CONTEXT, "offset", offset)?;
    check(CONTEXT, "disc radius", disc_radius)?;
    check(CONTEXT, "inner radius", inner)?;
    check(CONTEXT, "outer radius", outer)?;
    if inner > outer {
        return Err(AnalysisError::InvalidArgument {
            context: CONTEXT,
            reason: format!("inner radius {inner} m exceeds outer radius {outer} m"),
        });
    }
    Ok((lens_area(offset, disc_radius, outer) - lens_area(offset, disc_radius, inner)).max(0.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flowrate::integrate;
    use std::f64::consts::PI;

    #[test]
    fn two_unit_discs_a_radius_apart_overlap_by_the_textbook_lens() {
        // Equal discs of radius 1 with centres 1 apart: 2π/3 − √3/2 (each segment subtends
        // 120°). Double precision: 1e-14.
        let area = disc_in_disc_area(1.0, 1.0, 1.0).unwrap();
        assert!((area - (2.0 * PI / 3.0 - 3f64.sqrt() / 2.0)).abs() < 1e-14);
    }

    #[test]
    fn nested_and_disjoint_discs_and_the_tangencies_are_continuous() {
        let (a, rho) = (0.3, 1.0);
        // Inside: the whole small disc; disjoint: nothing.
        assert_eq!(disc_in_disc_area(0.5, a, rho).unwrap(), PI * a * a);
        assert_eq!(disc_in_disc_area(1.5, a, rho).unwrap(), 0.0);
        // Disc larger than the axis circle and covering it: the axis disc.
        assert_eq!(disc_in_disc_area(0.1, 2.0, rho).unwrap(), PI * rho * rho);
        // Near each tangency the partial branch joins the nested or disjoint value: the gap
        // grows as ε^{3/2} (a segment of height ε), so at ε = 1e-10 it is below 1e-13.
        let eps = 1e-10;
        let inner_touch = rho - a;
        let inside = disc_in_disc_area(inner_touch + eps, a, rho).unwrap();
        assert!(
            (inside - PI * a * a).abs() < 1e-13,
            "{}",
            inside - PI * a * a
        );
        let outside = disc_in_disc_area(rho + a - eps, a, rho).unwrap();
        assert!(outside.abs() < 1e-13, "{outside}");
    }

    #[test]
    fn the_lens_is_symmetric_in_the_two_radii() {
        // The intersection of two discs does not depend on which one is "about the axis".
        for (s, a, rho) in [(0.7, 0.4, 0.5), (0.2, 1.0, 0.9), (1.3, 0.5, 1.0)] {
            let one = disc_in_disc_area(s, a, rho).unwrap();
            let other = disc_in_disc_area(s, rho, a).unwrap();
            assert!((one - other).abs() < 1e-15, "{s} {a} {rho}");
        }
    }

    #[test]
    fn the_lens_equals_the_polar_integral_of_the_arcs_inside_the_disc() {
        // Independent route: A(ρ) = ∫₀^ρ 2θ(r) r dr, with 2θ(r) the angle of the circle of
        // radius r about the axis that lies inside the disc (cos θ = (r² + s² − a²)/(2rs)).
        // The integrand has square-root kinks at r = |s − a| and s + a, so the range is split
        // there and each piece integrated by adaptive Simpson to 1e-13; compare to 1e-10.
        let (s, a) = (0.8, 0.5);
        let arc = |r: f64| {
            if r <= 0.0 {
                return 0.0;
            }
            let c = ((r * r + s * s - a * a) / (2.0 * r * s)).clamp(-1.0, 1.0);
            2.0 * c.acos() * r
        };
        for rho in [0.35, 0.6, 0.8, 1.0, 1.25, 1.4] {
            let mut cuts = vec![0.0, (s - a).abs(), s + a, rho];
            cuts.retain(|&c| c <= rho);
            cuts.sort_by(f64::total_cmp);
            let polar: f64 = cuts
                .windows(2)
                .map(|w| integrate(arc, w[0], w[1], 1e-13).unwrap())
                .sum();
            let lens = disc_in_disc_area(s, a, rho).unwrap();
            assert!((lens - polar).abs() < 1e-10, "ρ = {rho}: {lens} vs {polar}");
        }
    }

    #[test]
    fn a_small_disc_on_a_large_circle_keeps_its_relative_accuracy() {
        // A disc of radius a centred on the circle ρ: A = πa²/2 − a³/(3ρ) − a⁵/(120ρ³) + …
        // (the circle bulges into the disc by x²/(2ρ)). At a/ρ = 1e-4 the a³ term is 2e-4 of
        // the area; it must come out to 0.1 %, which the plain acos form (error ≈ ε_mach ρ²/α
        // ≈ 2e-12 ≫ 3e-16) does not achieve.
        let (a, rho) = (1e-4, 1.0);
        let area = disc_in_disc_area(rho, a, rho).unwrap();
        let deficit = PI * a * a / 2.0 - area;
        assert!(
            (deficit - a.powi(3) / (3.0 * rho)).abs() < 1e-3 * a.powi(3) / (3.0 * rho),
            "{deficit}"
        );
    }

    #[test]
    fn annulus_areas_add_up_to_the_disc_and_bad_radii_are_rejected() {
        // Annuli that cover the disc partition it (conservation, to round-off).
        let (s, a) = (0.6, 0.45);
        let edges = [0.0, 0.2, 0.4, 0.55, 0.7, 0.9, 1.2];
        let total: f64 = edges
            .windows(2)
            .map(|w| disc_in_annulus_area(s, a, w[0], w[1]).unwrap())
            .sum();
        assert!((total - PI * a * a).abs() < 1e-14);
        assert!(disc_in_annulus_area(s, a, 0.5, 0.4).is_err());
        assert!(disc_in_disc_area(-0.1, a, 1.0).is_err());
        assert!(disc_in_disc_area(0.1, f64::NAN, 1.0).is_err());
    }
}
