//! Tangential contact laws (docs/physics.md §3): Hertz–Mindlin no-slip (default) and the
//! corrected Mindlin–Deresiewicz law of paper Eq. 7.

use glam::DVec3;
use serde::{Deserialize, Serialize};

/// Which tangential law a contact uses. Chosen once at setup.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum TangentialLaw {
    /// EDEM/LIGGGHTS "Hertz–Mindlin (no slip)": linear spring S_t = 8G*√(R*δ) on the total
    /// tangential displacement, Coulomb cap μ_s F_ne, dashpot only while sticking (§3.1).
    #[default]
    MindlinNoSlip,
    /// The paper's Eq. 7 with its dimensional typo corrected and the history truncated at
    /// δ_t,max (§3.3): F_t = μ_s F_ne (1 − (1 − z)^{3/2}).
    MindlinDeresiewicz,
}

/// Rotates the history ξ into the tangent plane of `n`, keeping its length
/// (LAMMPS granular; Luding 2008 eq. 17; docs/physics.md §3.1 step 1).
#[inline]
pub fn rotate_into_plane(xi: DVec3, n: DVec3) -> DVec3 {
    let len2 = xi.length_squared();
    if len2 == 0.0 {
        return xi;
    }
    let projected = xi - xi.dot(n) * n;
    let p2 = projected.length_squared();
    if p2 == 0.0 {
        // ξ is parallel to n: no tangential direction survives.
        return DVec3::ZERO;
    }
    projected * (len2 / p2).sqrt()
}

/// Hertz–Mindlin no-slip tangential force on body i [N]; updates the history ξ [m].
///
/// `slip_velocity` is v_t [m/s] at the contact point, `stiffness` S_t [N/m],
/// `cap` the Coulomb limit μ_s F_ne [N], `dashpot` γ_t [kg/s] (docs/physics.md §3.1 steps 2–5).
#[inline]
pub fn mindlin_no_slip(
    xi: &mut DVec3,
    slip_velocity: DVec3,
    dt: f64,
    stiffness: f64,
    cap: f64,
    dashpot: f64,
) -> DVec3 {
    *xi += slip_velocity * dt;
    let spring2 = stiffness * stiffness * xi.length_squared();
    if spring2 > cap * cap {
        // Gross sliding: truncate the spring to the Coulomb limit; no dashpot while sliding.
        *xi *= cap / spring2.sqrt();
        -stiffness * *xi
    } else {
        -stiffness * *xi - dashpot * slip_velocity
    }
}

/// Corrected Mindlin–Deresiewicz tangential force on body i [N] (docs/physics.md §3.3).
///
/// `cap` is μ_s F_ne [N], `slip_distance` δ_t,max = μ_s δ_n E*/(4G*) [m],
/// `prefactor` 2C_t = 2√(5/6)|β| [-], `m_eff` m* [kg].
/// F_t = −μ_s F_ne (1 − (1−z)^{3/2}) ξ̂ − 2C_t √(m* k_t(z)) v_t,
/// k_t(z) = (3/2) μ_s F_ne √(1−z)/δ_t,max, z = |ξ|/δ_t,max.
#[inline]
pub fn mindlin_deresiewicz(
    xi: &mut DVec3,
    slip_velocity: DVec3,
    dt: f64,
    cap: f64,
    slip_distance: f64,
    prefactor: f64,
    m_eff: f64,
) -> DVec3 {
    if cap <= 0.0 || slip_distance <= 0.0 {
        // Frictionless contact: no tangential force and nothing to remember.
        *xi = DVec3::ZERO;
        return DVec3::ZERO;
    }
    *xi += slip_velocity * dt;
    let mut len = xi.length();
    if len > slip_distance {
        *xi *= slip_distance / len;
        len = slip_distance;
    }
    if len == 0.0 {
        let k0 = 1.5 * cap / slip_distance;
        return -prefactor * (m_eff * k0).sqrt() * slip_velocity;
    }
    let z = len / slip_distance;
    let one_minus = 1.0 - z;
    let root = one_minus.sqrt();
    let elastic = cap * (1.0 - one_minus * root);
    let k_t = 1.5 * cap * root / slip_distance;
    -elastic / len * *xi - prefactor * (m_eff * k_t).sqrt() * slip_velocity
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    // A4 (docs/physics.md §9): static contact, monotonic ξ; tolerance 1e-10 relative.
    const E_STAR: f64 = 1.3333e8;
    const G_STAR: f64 = 2.8571e7;
    const R: f64 = 7.5e-4;
    const DELTA: f64 = 2.0e-5;
    const MU: f64 = 0.5;

    fn setup() -> (f64, f64, f64) {
        let h = super::super::normal::hertz(E_STAR, R, DELTA);
        let s_t = 8.0 * G_STAR * h.contact_radius;
        let slip = MU * DELTA * E_STAR / (4.0 * G_STAR);
        (h.force, s_t, slip)
    }

    #[test]
    fn no_slip_law_is_linear_until_two_thirds_of_slip_distance_then_constant() {
        let (f_ne, s_t, slip) = setup();
        let cap = MU * f_ne;
        let x = DVec3::X;
        for k in 1..=40 {
            let target = slip * k as f64 / 30.0;
            let mut xi = target * x;
            let f = mindlin_no_slip(&mut xi, DVec3::ZERO, 0.0, s_t, cap, 0.0);
            let expected = (s_t * target).min(cap);
            assert_relative_eq!(f.length(), expected, max_relative = 1e-10);
        }
        // The linear spring reaches the cap at ξ = (2/3) δ_t,max (§3.2).
        assert_relative_eq!(cap / s_t, 2.0 / 3.0 * slip, max_relative = 1e-10);
    }

    #[test]
    fn deresiewicz_law_follows_the_three_halves_curve_and_matches_initial_stiffness() {
        let (f_ne, s_t, slip) = setup();
        let cap = MU * f_ne;
        for k in 1..=12 {
            let target = slip * k as f64 / 10.0;
            let mut xi = DVec3::new(0.0, target, 0.0);
            let f = mindlin_deresiewicz(&mut xi, DVec3::ZERO, 0.0, cap, slip, 0.0, 1.0);
            let z = (target / slip).min(1.0);
            let expected = cap * (1.0 - (1.0 - z).powf(1.5));
            assert_relative_eq!(f.length(), expected, max_relative = 1e-10);
        }
        // Slope at ξ → 0 equals S_t = 8G*√(R*δ); finite difference at ξ = 1e-9 δ_t,max
        // differs from the tangent by O(z) = 1e-9, far inside the 1e-7 tolerance.
        let h = slip * 1e-9;
        let mut xi = DVec3::new(h, 0.0, 0.0);
        let f = mindlin_deresiewicz(&mut xi, DVec3::ZERO, 0.0, cap, slip, 0.0, 1.0);
        assert_relative_eq!(f.length() / h, s_t, max_relative = 1e-7);
    }

    #[test]
    fn rotating_normal_by_ninety_degrees_preserves_history_length_and_tangency() {
        let mut xi = DVec3::new(1e-6, 0.0, 0.0);
        let steps = 900;
        for k in 1..=steps {
            let angle = std::f64::consts::FRAC_PI_2 * k as f64 / steps as f64;
            // The normal turns in the x–z plane from +z to −x; ξ starts along +x.
            let n = DVec3::new(-angle.sin(), 0.0, angle.cos());
            xi = rotate_into_plane(xi, n);
            assert!(xi.dot(n).abs() <= 1e-10 * xi.length(), "ξ·n must vanish");
        }
        assert_relative_eq!(xi.length(), 1e-6, max_relative = 1e-10);
    }
}
