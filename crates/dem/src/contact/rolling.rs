//! Rolling resistance (docs/physics.md §4): the paper's Eq. 8 constant directional torque
//! (default) and the elastic–plastic spring–dashpot law (EPSD, Ai et al. 2011).

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
