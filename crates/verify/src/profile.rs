//! The exact moments of balls whose centres lie on one line: the reference for clumps of
//! overlapping spheres (RB3), independent of the engine's inclusion–exclusion.
//!
//! The union of balls centred on the z axis is a solid of revolution whose cross-section at
//! height z is the disc of the largest radius √(rₖ² − (z − zₖ)²) there. Between the points
//! where that largest member changes (each ball's ends, and the heights where two balls'
//! profiles cross), the volume V = π ∫ s, the moments ∫ z dV = π ∫ z s, ∫ z² dV = π ∫ z² s and
//! ∫ ρ² dV = (π/2) ∫ s² are integrals of polynomials in z, with s(z) = rₖ² − (z − zₖ)², taken in
//! closed form.

use std::f64::consts::PI;

/// Volume [m³], ∫ z dV [m⁴], ∫ z² dV [m⁵] and ∫ ρ² dV [m⁵] (ρ the distance from the axis) of
/// the union of the balls (zₖ, rₖ) [m] centred on the z axis.
pub fn collinear_moments(balls: &[(f64, f64)]) -> [f64; 4] {
    let mut cuts: Vec<f64> = balls.iter().flat_map(|&(z, r)| [z - r, z + r]).collect();
    for (i, &(za, ra)) in balls.iter().enumerate() {
        for &(zb, rb) in &balls[i + 1..] {
            // ra² − (z − za)² = rb² − (z − zb)² is linear in z.
            if za != zb {
                cuts.push((rb * rb - ra * ra + za * za - zb * zb) / (2.0 * (za - zb)));
            }
        }
    }
    cuts.sort_by(f64::total_cmp);
    let mut m = [0.0f64; 4];
    for w in cuts.windows(2) {
        let (a, b) = (w[0], w[1]);
        if b <= a {
            continue;
        }
        let mid = (a + b) / 2.0;
        // The ball with the widest disc at mid holds the profile on the whole piece.
        let Some((s_mid, zc, r)) = balls
            .iter()
            .map(|&(z, r)| (r * r - (mid - z) * (mid - z), z, r))
            .max_by(|x, y| x.0.total_cmp(&y.0))
        else {
            continue;
        };
        if s_mid <= 0.0 {
            continue;
        }
        // s(z) = −z² + 2 zc z + (r² − zc²), and s² by the product of coefficients.
        let s = [r * r - zc * zc, 2.0 * zc, -1.0];
        let mut s2 = [0.0; 5];
        for (i, si) in s.iter().enumerate() {
            for (j, sj) in s.iter().enumerate() {
                s2[i + j] += si * sj;
            }
        }
        let integral = |poly: &[f64], shift: usize| -> f64 {
            poly.iter()
                .enumerate()
                .map(|(k, c)| {
                    let e = (k + shift + 1) as i32;
                    c * (b.powi(e) - a.powi(e)) / f64::from(e)
                })
                .sum()
        };
        m[0] += PI * integral(&s, 0);
        m[1] += PI * integral(&s, 1);
        m[2] += PI * integral(&s, 2);
        m[3] += PI / 2.0 * integral(&s2, 0);
    }
    m
}
