//! Rolling resistance (docs/physics.md §4): the paper's Eq. 8 constant directional torque
//! (default) and the elastic–plastic spring–dashpot law (EPSD, Ai et al. 2011), with the
//! stiffness, limits and dashpot they are built from.
//!
//! The batched kernel (`forces::kernel`) forms the default law's torques with
//! [`constant_torque_levers_lane`], the lane form of [`constant_torque_levers`], tested to
//! give the same bits.

use glam::DVec3;
use serde::{Deserialize, Serialize};

/// Which rolling law a contact uses. Chosen once at setup.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum RollingLaw {
    /// No rolling resistance.
    None,
    /// Paper Eq. 8: M_i = −μ_r R_i F_ne ω̂_rel, on the relative spin ω_i − ω_j (CDT, EDEM type A
    /// with the relative spin). With `limiter`, |M| ≤ I_red |ω_rel|/Δt stops the chatter at rest (§4.2).
    ConstantTorque {
        /// Cap the torque so that one step cannot reverse the relative spin.
        limiter: bool,
    },
    /// EPSD (Ai et al. 2011; LIGGGHTS `epsd`): spring k_r = 2.25 k_n μ_r² R*², capped at
    /// μ_r R* F_ne, with a dashpot η_r 2√(I_r k_r) below the cap.
    Epsd {
        /// Viscous damping ratio η_r [-]; Ai et al. suggest 0.3.
        viscous_damping: f64,
    },
}

impl Default for RollingLaw {
    fn default() -> Self {
        RollingLaw::ConstantTorque { limiter: false }
    }
}

/// The scale s = μ_r F_ne/|ω_rel| [N m s] of paper Eq. 8's torque −a s ω_rel on each body,
/// from μ_r `rolling_friction` [-], the elastic normal force `f_ne` [N] and |ω_rel|² `w2`
/// [rad²/s²]; zero without relative spin or rolling friction. Both contact paths form the
/// torques from it: one division instead of three and no second cross product.
#[inline(always)]
pub fn constant_torque_scale(rolling_friction: f64, f_ne: f64, w2: f64) -> f64 {
    if w2 > 0.0 && rolling_friction > 0.0 {
        rolling_friction * f_ne / w2.sqrt()
    } else {
        0.0
    }
}

/// The torques on i and j [N m] of the tangential force and paper Eq. 8's rolling torque
/// together, on the levers `arm_i` a_i and `arm_j` a_j [m]: M_i = −a_i (n × F_t + s ω_rel)
/// and M_j = −a_j (n × F_t − s ω_rel), from `n_cross_ft` n × F_t [N], the scale `scale` s of
/// [`constant_torque_scale`] [N m s] and `omega_rel` ω_i − ω_j [rad/s]. The lever from i's
/// centre to the contact point is −a_i n and from j's +a_j n with force −F_t on j, so one
/// cross product serves both; Eq. 8 gives M_i −μ_r a_i F_ne ω̂ and M_j +μ_r a_j F_ne ω̂, the
/// same levers. The law of [`constant_torque`] without a limiter, with one division instead
/// of three and no second cross product.
#[inline(always)]
pub fn constant_torque_levers(
    n_cross_ft: DVec3,
    scale: f64,
    omega_rel: DVec3,
    (arm_i, arm_j): (f64, f64),
) -> (DVec3, DVec3) {
    let roll = scale * omega_rel;
    (-arm_i * (n_cross_ft + roll), -arm_j * (n_cross_ft - roll))
}

/// [`constant_torque_levers`] on one contact's components (x, y, z), for the batched
/// kernel's loop over contacts.
#[inline(always)]
pub fn constant_torque_levers_lane(
    n_cross_ft: [f64; 3],
    scale: f64,
    omega_rel: [f64; 3],
    (arm_i, arm_j): (f64, f64),
) -> ([f64; 3], [f64; 3]) {
    let roll = [
        scale * omega_rel[0],
        scale * omega_rel[1],
        scale * omega_rel[2],
    ];
    (
        [
            -arm_i * (n_cross_ft[0] + roll[0]),
            -arm_i * (n_cross_ft[1] + roll[1]),
            -arm_i * (n_cross_ft[2] + roll[2]),
        ],
        [
            -arm_j * (n_cross_ft[0] - roll[0]),
            -arm_j * (n_cross_ft[1] - roll[1]),
            -arm_j * (n_cross_ft[2] - roll[2]),
        ],
    )
}

/// The limiter's cap I_red |ω_rel|/Δt [N m] on paper Eq. 8's torque, from the reduced moment
/// of inertia `inertia_reduced` [kg m²], |ω_rel| `spin` [rad/s] and the step `dt` [s]: the
/// torque that stops the relative spin in one step, so that it cannot reverse it and
/// chatter at rest (docs/physics.md §4.2).
#[inline(always)]
pub fn constant_torque_limit(inertia_reduced: f64, spin: f64, dt: f64) -> f64 {
    inertia_reduced * spin / dt
}

/// EPSD rolling stiffness k_r = 2.25 k_n μ_r² R*² [N m/rad], with the secant normal
/// stiffness k_n = F_ne/δ_n of the elastic normal force `f_ne` [N] at overlap `overlap`
/// [m], the rolling friction `rolling_friction` μ_r [-] and the effective radius `r_eff`
/// R* [m] (J. Ai, J.-F. Chen, J. M. Rotter, J. Y. Ooi, "Assessment of rolling resistance
/// models in discrete element simulations", Powder Technol. 206 (2011) 269, model C;
/// LIGGGHTS `epsd`; docs/physics.md §4).
#[inline(always)]
pub fn epsd_stiffness(f_ne: f64, overlap: f64, rolling_friction: f64, r_eff: f64) -> f64 {
    let k_n = f_ne / overlap;
    let mu_r = rolling_friction;
    2.25 * k_n * mu_r * mu_r * r_eff * r_eff
}

/// EPSD limiting torque μ_r R* F_ne [N m] of the rolling spring, from the rolling friction
/// `rolling_friction` μ_r [-], the effective radius `r_eff` R* [m] and the elastic normal
/// force `f_ne` [N], beyond which the rolling is plastic (Ai et al. 2011, model C).
#[inline(always)]
pub fn epsd_limit(rolling_friction: f64, r_eff: f64, f_ne: f64) -> f64 {
    rolling_friction * r_eff * f_ne
}

/// EPSD rolling dashpot η_r 2√(I_r k_r) [N m s], from the damping ratio `viscous_damping`
/// η_r [-], the rolling inertia `rolling_inertia` I_r [kg m²] and the stiffness `stiffness`
/// k_r [N m/rad]: the rolling spring's critical damping scaled by η_r (Ai et al. 2011,
/// model C).
#[inline(always)]
pub fn epsd_dashpot(viscous_damping: f64, rolling_inertia: f64, stiffness: f64) -> f64 {
    viscous_damping * 2.0 * (rolling_inertia * stiffness).sqrt()
}

/// Constant directional torque of paper Eq. 8, returned as (torque on i, torque on j) [N m].
///
/// `omega_rel` = ω_i − ω_j [rad/s]; `magnitude_i` = μ_r a_i F_ne and `magnitude_j` = μ_r a_j F_ne [N m];
/// `limit` is the optional cap I_red|ω_rel|/Δt [N m] (pass `f64::INFINITY` for none).
#[inline]
pub fn constant_torque(
    omega_rel: DVec3,
    magnitude_i: f64,
    magnitude_j: f64,
    limit: f64,
) -> (DVec3, DVec3) {
    let w = omega_rel.length();
    if w == 0.0 {
        return (DVec3::ZERO, DVec3::ZERO);
    }
    let dir = omega_rel / w;
    (-magnitude_i.min(limit) * dir, magnitude_j.min(limit) * dir)
}

/// EPSD rolling torque on body i [N m] (on j it is the opposite); updates the spring torque history.
///
/// `omega_roll` is the rolling part of ω_i − ω_j (normal component removed) [rad/s];
/// `stiffness` k_r [N m/rad], `cap` μ_r R* F_ne [N m], `dashpot` η_r 2√(I_r k_r) [N m s].
#[inline]
pub fn epsd(
    history: &mut DVec3,
    omega_roll: DVec3,
    dt: f64,
    stiffness: f64,
    cap: f64,
    dashpot: f64,
) -> DVec3 {
    *history -= stiffness * omega_roll * dt;
    let m = history.length();
    if m > cap {
        // Fully mobilised: plastic rolling at the limiting torque, no dashpot (Ai et al. 2011, Eq. 14).
        *history *= cap / m;
        *history
    } else {
        *history - dashpot * omega_roll
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn constant_torque_opposes_relative_spin_with_equal_and_opposite_reaction() {
        let (ti, tj) = constant_torque(DVec3::new(0.0, 3.0, 4.0), 2.0, 2.0, f64::INFINITY);
        // Exact: magnitudes are copied, directions are ±ω̂.
        assert_relative_eq!(ti.length(), 2.0, max_relative = 1e-15);
        assert!(ti.dot(DVec3::new(0.0, 3.0, 4.0)) < 0.0);
        assert_relative_eq!((ti + tj).length(), 0.0, epsilon = 1e-15);
    }

    #[test]
    fn limiter_caps_the_torque() {
        let (ti, _) = constant_torque(DVec3::X * 1e-3, 5.0, 5.0, 0.1);
        assert_relative_eq!(ti.length(), 0.1, max_relative = 1e-15);
    }

    #[test]
    fn constant_torque_levers_give_eq8_and_the_tangential_lever() {
        // Without a tangential force the levers give Eq. 8 on each body: −μ_r a_i F_ne ω̂ on
        // i and +μ_r a_j F_ne ω̂ on j, as `constant_torque` does.
        let (mu_r, f_ne, w) = (0.3, 2.0, DVec3::new(0.0, 3.0, 4.0));
        let s = constant_torque_scale(mu_r, f_ne, w.length_squared());
        let (ti, tj) = constant_torque_levers(DVec3::ZERO, s, w, (1.5, 0.5));
        let (ei, ej) = constant_torque(w, mu_r * 1.5 * f_ne, mu_r * 0.5 * f_ne, f64::INFINITY);
        assert_relative_eq!(ti.distance(ei), 0.0, epsilon = 1e-15);
        assert_relative_eq!(tj.distance(ej), 0.0, epsilon = 1e-15);
        // Without spin, −a (n × F_t) on both.
        let nxf = DVec3::new(1.0, -2.0, 0.5);
        let (ti, tj) = constant_torque_levers(nxf, 0.0, DVec3::ZERO, (2.0, 4.0));
        assert_eq!((ti, tj), (-2.0 * nxf, -4.0 * nxf));
    }

    #[test]
    fn the_lane_form_of_the_levers_gives_the_scalar_bits() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(9);
        for k in 0..2000 {
            let mut u = || rng.gen::<f64>() - 0.5;
            let nxf = DVec3::new(u(), u(), u()) * 1e-3;
            let w = DVec3::new(u(), u(), u()) * 400.0;
            let s = constant_torque_scale(0.3 * (u() + 0.5), u() + 0.5, w.length_squared());
            let arms = (1.5e-3 * (u() + 1.0), 1.5e-3 * (u() + 1.0));
            let (ti, tj) = constant_torque_levers(nxf, s, w, arms);
            let (li, lj) = constant_torque_levers_lane(nxf.to_array(), s, w.to_array(), arms);
            let bits = |a: [f64; 3]| a.map(f64::to_bits);
            assert_eq!(bits(li), bits(ti.to_array()), "torque i {k}");
            assert_eq!(bits(lj), bits(tj.to_array()), "torque j {k}");
        }
    }

    #[test]
    fn the_limiter_stops_the_spin_in_one_step() {
        // A torque of I ω/Δt changes ω by exactly ω in one step.
        let (inertia, spin, dt) = (2.0e-9, 30.0, 1.0e-5);
        let cap = constant_torque_limit(inertia, spin, dt);
        assert_relative_eq!(cap * dt / inertia, spin, max_relative = 1e-15);
    }

    #[test]
    fn epsd_stiffness_limit_and_dashpot_follow_ai_et_al() {
        // k_r = 2.25 k_n μ_r² R*² with k_n = F/δ; exact binary numbers: F = 8, δ = 2 (k_n =
        // 4), μ_r = 0.5, R* = 2 → k_r = 2.25 × 4 × 0.25 × 4 = 9.
        assert_eq!(epsd_stiffness(8.0, 2.0, 0.5, 2.0), 9.0);
        // The limiting torque μ_r R* F = 0.5 × 2 × 8.
        assert_eq!(epsd_limit(0.5, 2.0, 8.0), 8.0);
        // Critical damping 2√(I k) scaled by η_r: 0.25 × 2 × √(4 × 9) = 3.
        assert_eq!(epsd_dashpot(0.25, 4.0, 9.0), 3.0);
        // The spring reaches the limit after a rotation of μ_r R* F/k_r = F δ/(2.25 F μ_r R*)
        // = δ/(2.25 μ_r R*), independent of the force.
        let (f, d, mu, r) = (3.7e-2, 2.0e-5, 0.1, 7.5e-4);
        assert_relative_eq!(
            epsd_limit(mu, r, f) / epsd_stiffness(f, d, mu, r),
            d / (2.25 * mu * r),
            max_relative = 1e-14
        );
    }

    #[test]
    fn epsd_spring_saturates_at_the_cap() {
        let mut h = DVec3::ZERO;
        let mut last = DVec3::ZERO;
        for _ in 0..1000 {
            last = epsd(&mut h, DVec3::Z, 1e-3, 10.0, 0.5, 0.0);
        }
        // 1000 steps × k_r ω Δt = 10 N m ≫ cap: fully mobilised at exactly the cap.
        assert_relative_eq!(last.length(), 0.5, max_relative = 1e-12);
        assert!(last.z < 0.0, "the torque must oppose the spin");
    }
}
