//! Simplified JKR cohesion (docs/physics.md §2.5): an attraction k_c A, a cohesion energy
//! density k_c [J/m³] times the area A [m²] of the circle where the two undeformed surfaces
//! intersect, added to the dry contact while the bodies overlap. It is the `sjkr` cohesion of
//! LIGGGHTS and the "JKR" cohesion energy density of EDEM, so their parameter sets carry
//! over; unlike JKR it holds no tension beyond contact.

use std::f64::consts::PI;

/// The area π a² [m²] of the circle where spheres of radii `ri` and `rj` [m] whose centres lie
/// `ri + rj − overlap` apart intersect: a² = (d² − (R_i − R_j)²)((R_i + R_j)² − d²)/(4d²),
/// from the two spheres' equations. `rj` infinite stands for a wall (a plane through the
/// contact): a² = 2R_i δ − δ². Zero when the surfaces do not overlap.
#[inline]
pub fn intersection_area(ri: f64, rj: f64, overlap: f64) -> f64 {
    if rj.is_finite() {
        pair_intersection_area(ri, rj, overlap)
    } else {
        wall_intersection_area(ri, overlap)
    }
}

/// [`intersection_area`] of two spheres, without a branch (for the batched kernel's lanes).
#[inline(always)]
pub fn pair_intersection_area(ri: f64, rj: f64, overlap: f64) -> f64 {
    let sum = ri + rj;
    let d = sum - overlap;
    let diff = ri - rj;
    let a2 = (d * d - diff * diff) * (sum * sum - d * d) / (4.0 * d * d);
    touching_area(overlap, a2)
}

/// [`intersection_area`] of a sphere of radius `ri` [m] and a plane, without a branch.
#[inline(always)]
pub fn wall_intersection_area(ri: f64, overlap: f64) -> f64 {
    touching_area(overlap, overlap * (2.0 * ri - overlap))
}

/// π a² [m²] from a² [m²] where the surfaces overlap, else zero (and for a NaN overlap).
#[inline(always)]
fn touching_area(overlap: f64, a2: f64) -> f64 {
    let area = PI * a2.max(0.0);
    if overlap > 0.0 {
        area
    } else {
        0.0
    }
}

/// The attractive normal force k_c A [N] (to be subtracted from the repulsion) of energy
/// density `energy_density` [J/m³] over `area` [m²].
#[inline]
pub fn sjkr_force(energy_density: f64, area: f64) -> f64 {
    energy_density * area
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn the_area_is_the_circle_where_the_spheres_cross() {
        // Two equal spheres of R overlapping δ meet on the mid-plane at a² = R² − (R − δ/2)²;
        // exact up to round-off (1e-12).
        let (r, d): (f64, f64) = (2e-3, 1e-5);
        let expected = PI * (r * r - (r - d / 2.0).powi(2));
        assert_relative_eq!(intersection_area(r, r, d), expected, max_relative = 1e-9);
        // A sphere and a plane: a² = R² − (R − δ)².
        let expected = PI * (r * r - (r - d).powi(2));
        assert_relative_eq!(
            intersection_area(r, f64::INFINITY, d),
            expected,
            max_relative = 1e-12
        );
        // A very large partner tends to the plane: R_j = 10⁶ R_i within 1e-5.
        assert_relative_eq!(
            intersection_area(r, 1e6 * r, d),
            expected,
            max_relative = 1e-5
        );
        assert_eq!(intersection_area(r, r, 0.0), 0.0);
        assert_eq!(intersection_area(r, r, -1e-6), 0.0);
    }

    #[test]
    fn for_small_overlaps_the_area_is_two_pi_r_star_delta() {
        // To first order in δ, π a² = 2π R* δ for any pair (the relative error is O(δ/R)).
        let (ri, rj, d) = (1e-3, 3e-3, 1e-8);
        let r_star = ri * rj / (ri + rj);
        assert_relative_eq!(
            intersection_area(ri, rj, d),
            2.0 * PI * r_star * d,
            max_relative = 1e-4
        );
    }
}
