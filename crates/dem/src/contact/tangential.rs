//! Tangential contact laws (docs/physics.md §3): Hertz–Mindlin no-slip (default) and the
//! corrected Mindlin–Deresiewicz law of paper Eq. 7, with the stiffness, the Coulomb limit,
//! the slip distance and the dashpot they are built from.
//!
//! The batched kernel (`forces::kernel`) evaluates the no-slip law over arrays of contacts;
//! it calls the `*_lane` forms here, the same operations on one contact's components written
//! without branches so that a loop over contacts vectorises. Tests hold each lane form to
//! its scalar form bit for bit.

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

/// Tangential stiffness S_t = 8 G* a [N/m] of a Hertz contact of contact radius
/// `contact_radius` a = √(R* δ) [m] and effective shear modulus `g_star` G* [Pa]: the
/// initial slope of the tangential load–displacement curve without micro-slip (R. D.
/// Mindlin, "Compliance of elastic bodies in contact", J. Appl. Mech. 16 (1949) 259;
/// docs/physics.md §3.1 step 3).
#[inline(always)]
pub fn mindlin_stiffness(g_star: f64, contact_radius: f64) -> f64 {
    8.0 * g_star * contact_radius
}

/// Coulomb limit μ_s F_ne [N] of the tangential force, from the sliding friction `friction`
/// μ_s [-] and the elastic normal force `f_ne` [N] (not the damped one, as in EDEM and the
/// paper's Eq. 7; docs/physics.md §3.1 step 4).
#[inline(always)]
pub fn coulomb_limit(friction: f64, f_ne: f64) -> f64 {
    friction * f_ne
}

/// Slip distance δ_t,max = μ_s δ_n E*/(4G*) [m]: the tangential displacement at which a
/// Hertz contact of overlap `overlap` δ_n [m] slides as a whole under a constant normal
/// force, with sliding friction `friction` μ_s [-] and effective moduli `e_star` E*,
/// `g_star` G* [Pa] (R. D. Mindlin, H. Deresiewicz, "Elastic spheres in contact under
/// varying oblique forces", J. Appl. Mech. 20 (1953) 327; δ_t,max = 3 μ_s F_n/(16 G* a),
/// docs/physics.md §3.2).
#[inline(always)]
pub fn slip_distance(friction: f64, overlap: f64, e_star: f64, g_star: f64) -> f64 {
    friction * overlap * e_star / (4.0 * g_star)
}

/// Tangential dashpot γ_t [kg/s] of the no-slip law from the normal one `gamma_n` γ_n
/// [kg/s]: γ_t = prefactor √(S_t m*) = γ_n √(S_t/S_n), and S_t/S_n = 4G*/E* is fixed per
/// pair of materials, so `stiffness_ratio_sqrt` √(4G*/E*) [-] is computed once per pair and
/// a square root is saved per contact (EDEM, LIGGGHTS; docs/physics.md §3.1 step 3).
#[inline(always)]
pub fn no_slip_dashpot(gamma_n: f64, stiffness_ratio_sqrt: f64) -> f64 {
    gamma_n * stiffness_ratio_sqrt
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
    no_slip_force(xi, slip_velocity, stiffness, cap, dashpot)
}

/// The no-slip force on body i [N] for a history ξ [m] that already holds this step's slip
/// (steps 4–5 of [`mindlin_no_slip`]): the spring −S_t ξ and the dashpot −γ_t v_t while
/// S_t |ξ| ≤ `cap`; beyond it ξ is truncated to the Coulomb limit and the dashpot is off.
#[inline]
pub fn no_slip_force(
    xi: &mut DVec3,
    slip_velocity: DVec3,
    stiffness: f64,
    cap: f64,
    dashpot: f64,
) -> DVec3 {
    let spring2 = stiffness * stiffness * xi.length_squared();
    if spring2 > cap * cap {
        // Gross sliding: truncate the spring to the Coulomb limit; no dashpot while sliding.
        *xi *= cap / spring2.sqrt();
        -stiffness * *xi
    } else {
        -stiffness * *xi - dashpot * slip_velocity
    }
}

/// [`rotate_into_plane`] followed by this step's slip v_t Δt (steps 1–2 of
/// [`mindlin_no_slip`]), on one contact's components (x, y, z): the history `xi` [m] turned
/// into the tangent plane of the unit normal `n` keeping its length (a zero history, or one
/// along n, becomes zero), plus `slip_velocity` [m/s] times `dt` [s]. Without branches, for
/// the batched kernel's loop over contacts.
#[inline(always)]
pub fn rotate_and_slip_lane(
    xi: [f64; 3],
    n: [f64; 3],
    slip_velocity: [f64; 3],
    dt: f64,
) -> [f64; 3] {
    let len2 = dot(xi, xi);
    let xn = dot(xi, n);
    let proj = [xi[0] - xn * n[0], xi[1] - xn * n[1], xi[2] - xn * n[2]];
    let p2 = dot(proj, proj);
    let keep = if p2 > 0.0 { (len2 / p2).sqrt() } else { 0.0 };
    [
        proj[0] * keep + slip_velocity[0] * dt,
        proj[1] * keep + slip_velocity[1] * dt,
        proj[2] * keep + slip_velocity[2] * dt,
    ]
}

/// [`no_slip_force`] on one contact's components, without branches, for the batched
/// kernel's loop over contacts: truncates `xi` [m] to the Coulomb limit `cap` [N] when the
/// spring exceeds it and returns the force on body i [N].
#[inline(always)]
pub fn no_slip_force_lane(
    xi: &mut [f64; 3],
    slip_velocity: [f64; 3],
    stiffness: f64,
    cap: f64,
    dashpot: f64,
) -> [f64; 3] {
    let spring2 = stiffness * stiffness * dot(*xi, *xi);
    let sliding = spring2 > cap * cap;
    let scale = if sliding { cap / spring2.sqrt() } else { 1.0 };
    let dash = if sliding { 0.0 } else { dashpot };
    for x in xi.iter_mut() {
        *x *= scale;
    }
    [
        -stiffness * xi[0] - dash * slip_velocity[0],
        -stiffness * xi[1] - dash * slip_velocity[1],
        -stiffness * xi[2] - dash * slip_velocity[2],
    ]
}

/// a · b summed in glam's order (x, then y, then z), so that the lane forms round as the
/// scalar ones.
#[inline(always)]
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    (a[0] * b[0]) + (a[1] * b[1]) + (a[2] * b[2])
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
        let s_t = mindlin_stiffness(G_STAR, h.contact_radius);
        let slip = slip_distance(MU, DELTA, E_STAR, G_STAR);
        (h.force, s_t, slip)
    }

    #[test]
    fn mindlin_stiffness_is_eight_g_star_times_the_contact_radius() {
        // A4's contact: a = √(R* δ) = √(1.5e-8) m, S_t = 8 G* a.
        let a = (R * DELTA).sqrt();
        assert_relative_eq!(
            mindlin_stiffness(G_STAR, a),
            8.0 * G_STAR * a,
            max_relative = 1e-15
        );
        // Exact numbers: 8 × 2 × 0.5 = 8.
        assert_eq!(mindlin_stiffness(2.0, 0.5), 8.0);
    }

    #[test]
    fn slip_distance_is_three_mu_f_over_sixteen_g_star_a() {
        // Mindlin–Deresiewicz: δ_t,max = 3 μ F_n/(16 G* a) with the Hertz force F_n.
        let h = super::super::normal::hertz(E_STAR, R, DELTA);
        let expected = 3.0 * MU * h.force / (16.0 * G_STAR * h.contact_radius);
        assert_relative_eq!(
            slip_distance(MU, DELTA, E_STAR, G_STAR),
            expected,
            max_relative = 1e-14
        );
        // The initial Mindlin–Deresiewicz stiffness (3/2) μ F_n/δ_t,max is Mindlin's 8 G* a.
        let cap = coulomb_limit(MU, h.force);
        assert_relative_eq!(
            1.5 * cap / slip_distance(MU, DELTA, E_STAR, G_STAR),
            mindlin_stiffness(G_STAR, h.contact_radius),
            max_relative = 1e-14
        );
        assert_eq!(coulomb_limit(0.5, 3.0), 1.5);
    }

    #[test]
    fn no_slip_dashpot_is_the_normal_one_scaled_by_the_stiffness_ratio() {
        // γ_t = prefactor √(S_t m*) = γ_n √(S_t/S_n), S_t/S_n = 8G*a/(2E*a) = 4G*/E*.
        let (prefactor, m) = (0.9, 1.0e-5);
        let h = super::super::normal::hertz(E_STAR, R, DELTA);
        let s_t = mindlin_stiffness(G_STAR, h.contact_radius);
        let gamma_n = prefactor * (h.stiffness * m).sqrt();
        let ratio = (4.0 * G_STAR / E_STAR).sqrt();
        assert_relative_eq!(
            no_slip_dashpot(gamma_n, ratio),
            prefactor * (s_t * m).sqrt(),
            max_relative = 1e-14
        );
    }

    #[test]
    fn the_lane_forms_give_the_scalar_forms_bits() {
        // Random contacts, sticking and sliding, fresh (zero) and old histories: the lane
        // forms must give the same bits as `rotate_into_plane` then `mindlin_no_slip`.
        use rand::{Rng, SeedableRng};
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(5);
        let v = |rng: &mut rand_xoshiro::Xoshiro256PlusPlus, scale: f64| {
            DVec3::new(
                rng.gen::<f64>() - 0.5,
                rng.gen::<f64>() - 0.5,
                rng.gen::<f64>() - 0.5,
            ) * scale
        };
        let (mut slid, mut stuck) = (0, 0);
        for k in 0..4000 {
            let n = v(&mut rng, 1.0).normalize();
            let xi = if k % 5 == 0 {
                DVec3::ZERO
            } else {
                v(&mut rng, 4e-5)
            };
            let vt = v(&mut rng, 2.0);
            let (dt, s_t, cap, gamma) = (2.5e-6, 1.0e5, 2.0 * rng.gen::<f64>(), 0.01);
            let mut scalar = rotate_into_plane(xi, n);
            let f = mindlin_no_slip(&mut scalar, vt, dt, s_t, cap, gamma);
            let mut lane = rotate_and_slip_lane(xi.to_array(), n.to_array(), vt.to_array(), dt);
            let g = no_slip_force_lane(&mut lane, vt.to_array(), s_t, cap, gamma);
            let bits = |a: [f64; 3]| a.map(f64::to_bits);
            assert_eq!(bits(lane), bits(scalar.to_array()), "history {k}");
            assert_eq!(bits(g), bits(f.to_array()), "force {k}");
            if f.length() < 0.999_999 * cap {
                stuck += 1;
            } else {
                slid += 1;
            }
        }
        assert!(slid > 100 && stuck > 100, "{slid} slid, {stuck} stuck");
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
