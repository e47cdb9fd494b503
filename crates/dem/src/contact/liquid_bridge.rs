//! Pendular liquid bridges between wet grains (docs/physics.md §2.6): the capillary force of
//! Willett, Adams, Johnson & Seville (2000, Langmuir 16, 9396), their closed form for a
//! bridge of volume V [m³], surface tension γ [N/m] and contact angle θ [rad] at surface
//! separation S [m],
//!
//! F = 2π R γ cos θ / (1 + 2.1 Ŝ + 10 Ŝ²), Ŝ = (S/2) √(R/V),
//!
//! with R = 2R* (the Derjaguin radius 2R_iR_j/(R_i + R_j) Willett et al. use for unequal
//! spheres; 2R_i against a wall), and the rupture distance of Lian, Thornton & Adams (1993,
//! J. Colloid Interface Sci. 161, 138), S_c = (1 + θ/2) V^{1/3}.
//!
//! A bridge forms when the surfaces touch and breaks at S_c; while the surfaces overlap it
//! pulls with its contact value. Its volume is fixed: liquid is neither drained nor passed
//! on when a bridge breaks (no redistribution), and the bridge's viscous force is not
//! modelled.

use std::f64::consts::PI;

/// The largest bridge volume V/R³ [-] accepted, R the smaller radius of a wet pair: the upper
/// end of the volumes over which Willett et al. (2000) fitted the closed form, near where the
/// pendular bridges of a packing begin to merge.
pub const LARGEST_VOLUME_RATIO: f64 = 0.1;

/// The rupture distance S_c = (1 + θ/2) V^{1/3} [m] of a bridge of volume `volume` [m³] and
/// contact angle `contact_angle` [rad] (Lian et al. 1993).
#[inline]
pub fn rupture_distance(volume: f64, contact_angle: f64) -> f64 {
    (1.0 + 0.5 * contact_angle) * volume.cbrt()
}

/// The capillary force [N] (attractive, as a magnitude) of a bridge between surfaces
/// `separation` [m] apart (≤ 0 when they touch or overlap: the contact value
/// 2π R γ cos θ), for the pair's effective radius `r_eff` [m]; zero beyond the rupture
/// distance.
#[inline]
pub fn bridge_force(
    r_eff: f64,
    volume: f64,
    surface_tension: f64,
    contact_angle: f64,
    separation: f64,
) -> f64 {
    BridgePair::new(volume, surface_tension, contact_angle).force(r_eff, separation)
}

/// The numbers of one material pair's bridge that do not depend on R* or the separation,
/// formed once per pair (the cosine and the cube root), so that a contact's evaluation is
/// arithmetic only: [`bridge_force`] goes through it, and so does the batched kernel's
/// lane, with the same bits.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BridgePair {
    /// Bridge volume V [m³].
    pub volume: f64,
    /// Surface tension γ [N/m].
    pub surface_tension: f64,
    /// cos θ of the contact angle [-].
    pub cos_angle: f64,
    /// The rupture distance S_c [m] ([`rupture_distance`]).
    pub rupture: f64,
}

impl BridgePair {
    /// The bridge of volume `volume` [m³], surface tension `surface_tension` [N/m] and
    /// contact angle `contact_angle` [rad].
    pub fn new(volume: f64, surface_tension: f64, contact_angle: f64) -> Self {
        Self {
            volume,
            surface_tension,
            cos_angle: contact_angle.cos(),
            rupture: rupture_distance(volume, contact_angle),
        }
    }

    /// The force [N] at `separation` [m] for effective radius `r_eff` [m] ([`bridge_force`]),
    /// without a branch.
    #[inline(always)]
    pub fn force(&self, r_eff: f64, separation: f64) -> f64 {
        let r = 2.0 * r_eff;
        let s = 0.5 * separation.max(0.0) * (r / self.volume).sqrt();
        let f =
            2.0 * PI * r * self.surface_tension * self.cos_angle / (1.0 + 2.1 * s + 10.0 * s * s);
        // Zero beyond the rupture distance, by a factor of 0 or 1 rather than a select,
        // which the compiler would turn into a branch around the division, and so keep
        // the kernel's loop from vectorising.
        f * f64::from(u8::from(separation <= self.rupture))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    // Water (γ = 0.072 N/m) between 2 mm spheres, θ = 20°, V = 10⁻³ R³.
    const R: f64 = 1e-3;
    const GAMMA: f64 = 0.072;

    #[test]
    fn at_contact_the_force_is_two_pi_r_gamma_cos_theta() {
        // Equal spheres: R = 2R* = R_i; exact up to round-off (1e-15).
        let theta = 20f64.to_radians();
        let f = bridge_force(R / 2.0, 1e-3 * R.powi(3), GAMMA, theta, 0.0);
        assert_relative_eq!(f, 2.0 * PI * R * GAMMA * theta.cos(), max_relative = 1e-15);
        // Overlapping surfaces keep the contact value.
        assert_eq!(bridge_force(R / 2.0, 1e-9, GAMMA, theta, -1e-6), f);
    }

    #[test]
    fn the_force_falls_with_separation_and_stops_at_rupture() {
        let (v, theta) = (1e-3 * R.powi(3), 0.3);
        let sc = rupture_distance(v, theta);
        assert_relative_eq!(sc, 1.15 * v.cbrt(), max_relative = 1e-15);
        let f = |s: f64| bridge_force(R / 2.0, v, GAMMA, theta, s);
        let mut last = f(0.0);
        for k in 1..100 {
            let now = f(sc * k as f64 / 100.0);
            assert!(now < last && now > 0.0);
            last = now;
        }
        assert!(f(sc) > 0.0 && f(sc) < last);
        assert_eq!(f(sc * (1.0 + 1e-12)), 0.0);
        // At Ŝ = 0.5 the denominator is 1 + 1.05 + 2.5 = 4.55.
        let s_half = 1.0 / (R / v).sqrt();
        assert_relative_eq!(f(s_half), f(0.0) / 4.55, max_relative = 1e-14);
    }
}
