//! Hertz normal contact (paper Eq. 6 elastic part; docs/physics.md §2.1) and its closed forms.

/// Elastic Hertz force and tangent stiffness for overlap `delta` [m].
///
/// F_ne = (4/3) E* √R* δ^{3/2} [N] and S_n = dF_ne/dδ = 2 E* √(R* δ) [N/m].
/// Written with a = √(R* δ): F_ne = (4/3) E* a δ, which avoids `powf` (δ^{3/2} = δ√δ).
#[inline(always)]
pub fn hertz(e_star: f64, r_eff: f64, delta: f64) -> HertzForce {
    let a = (r_eff * delta).sqrt();
    HertzForce {
        force: (4.0 / 3.0) * e_star * a * delta,
        stiffness: 2.0 * e_star * a,
        contact_radius: a,
    }
}

/// The elastic part of a Hertz contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzForce {
    /// Elastic normal force F_ne [N].
    pub force: f64,
    /// Tangent normal stiffness S_n [N/m].
    pub stiffness: f64,
    /// Contact radius a = √(R* δ) [m].
    pub contact_radius: f64,
}

/// Elastic energy stored in a Hertz contact, ∫F_ne dδ = (8/15) E* √R* δ^{5/2} [J].
#[inline]
pub fn hertz_energy(e_star: f64, r_eff: f64, delta: f64) -> f64 {
    (8.0 / 15.0) * e_star * r_eff.sqrt() * delta * delta * delta.sqrt()
}

/// Maximum overlap of an elastic head-on impact at relative speed `v` [m/s]:
/// δ_max = (15 m* v² / (16 E* √R*))^{2/5} [m] (docs/physics.md §9 CO1).
pub fn max_overlap(e_star: f64, r_eff: f64, m_eff: f64, v: f64) -> f64 {
    (15.0 * m_eff * v * v / (16.0 * e_star * r_eff.sqrt())).powf(0.4)
}

/// Duration of an elastic Hertz impact at relative speed `v` [m/s]:
/// t_c = 2.868 (m*² / (R* E*² v))^{1/5} [s] (docs/physics.md §9 CO1; Johnson 1985 §11.4).
///
/// The constant is 2 ∫₀¹ dx/√(1−x^{5/2}) (15/16)^{2/5} = 2.8683; δ_max/v times 2.9432 is the same.
pub fn hertz_contact_time(e_star: f64, r_eff: f64, m_eff: f64, v: f64) -> f64 {
    2.9432 * max_overlap(e_star, r_eff, m_eff, v) / v
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn stiffness_is_the_derivative_of_the_force() {
        // Central difference of F_ne; relative error O(h²) ≈ 1e-8 for h = 1e-4 δ.
        let (e, r, d) = (1.3333e8, 7.5e-4, 2.0e-5);
        let h = d * 1e-4;
        let slope = (hertz(e, r, d + h).force - hertz(e, r, d - h).force) / (2.0 * h);
        assert_relative_eq!(hertz(e, r, d).stiffness, slope, max_relative = 1e-7);
    }

    #[test]
    fn energy_is_the_integral_of_the_force() {
        // d(energy)/dδ = F_ne; same central-difference tolerance as above.
        let (e, r, d) = (1.3333e8, 7.5e-4, 2.0e-5);
        let h = d * 1e-4;
        let slope = (hertz_energy(e, r, d + h) - hertz_energy(e, r, d - h)) / (2.0 * h);
        assert_relative_eq!(hertz(e, r, d).force, slope, max_relative = 1e-7);
    }

    #[test]
    fn table1_head_on_impact_matches_closed_form() {
        // docs/physics.md §1.1: δ_max = 29.0 µm, t_c = 85.4 µs for pp at 1 m/s (3 significant digits).
        let m = 3.5343e-5;
        let d = max_overlap(1.3333e8, 7.5e-4, m / 2.0, 1.0);
        assert_relative_eq!(d, 29.0e-6, max_relative = 2e-3);
        let t = hertz_contact_time(1.3333e8, 7.5e-4, m / 2.0, 1.0);
        assert_relative_eq!(t, 85.4e-6, max_relative = 2e-3);
    }
}
