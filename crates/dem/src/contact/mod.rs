//! The contact model: geometry first, then the fixed pipeline
//! normal → damping → tangential (history, Coulomb cap) → rolling (docs/physics.md §1–4).
//!
//! Each stage is a pure function in its own file; this module only orders them.

pub mod cohesion;
pub mod cube_root;
pub mod damping;
pub mod geometry;
pub mod jkr;
pub mod liquid_bridge;
pub mod normal;
pub mod rolling;
pub mod sjkr;
pub mod tangential;

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::material::PairCoefficients;
pub use cohesion::Cohesion;
use cohesion::NormalOutcome;
pub use rolling::RollingLaw;
pub use tangential::TangentialLaw;

/// The choice of sub-models, fixed for a simulation.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub struct ContactLaws {
    /// Clamp the normal force to F_n ≥ 0 (off by default, as in the paper's Eq. 6 and LIGGGHTS;
    /// switching it on raises the effective restitution, docs/physics.md §2.3).
    pub normal_clamp: bool,
    /// Tangential law (§3).
    pub tangential: TangentialLaw,
    /// Rolling law (§4).
    pub rolling: RollingLaw,
}

/// Geometry of one contact, computed before and apart from the force laws.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactGeometry {
    /// Unit normal from j (or the wall point) to i [-].
    pub normal: DVec3,
    /// Normal overlap δ_n > 0 [m].
    pub overlap: f64,
    /// Effective radius R* [m] (R_i for a wall).
    pub r_eff: f64,
    /// Effective mass m* [kg] (m_i for a wall).
    pub m_eff: f64,
    /// Lever from the centre of i to the contact point, a_i = R_i − δ/2 [m].
    pub arm_i: f64,
    /// Lever from the centre of j to the contact point, a_j = R_j − δ/2 [m] (0 for a wall).
    pub arm_j: f64,
    /// Moments of inertia of i and j [kg m²] (j: infinite for a wall). Only the limiter and
    /// EPSD need them, so the reduced forms are derived there, not for every contact.
    pub inertia: [f64; 2],
    /// m R² of i and j [kg m²] (j: infinite for a wall), for EPSD's rolling inertia.
    pub mass_radius2: [f64; 2],
    /// Radii R_i and R_j [m] (j: infinite for a wall), for the simplified JKR's area.
    pub radius: [f64; 2],
}

impl ContactGeometry {
    /// Reduced moment of inertia I_i I_j/(I_i + I_j) [kg m²] (I_i for a wall).
    #[inline]
    pub fn inertia_reduced(&self) -> f64 {
        1.0 / (1.0 / self.inertia[0] + 1.0 / self.inertia[1])
    }

    /// LIGGGHTS' EPSD rolling inertia 1.4 m_i R_i² m_j R_j²/(m_i R_i² + m_j R_j²) [kg m²]
    /// (1.4 m_i R_i² for a wall).
    #[inline]
    pub fn rolling_inertia(&self) -> f64 {
        1.4 / (1.0 / self.mass_radius2[0] + 1.0 / self.mass_radius2[1])
    }
}

/// Velocities of one body at the current (half) step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BodyMotion {
    /// Centre velocity [m/s].
    pub velocity: DVec3,
    /// Angular velocity [rad/s].
    pub omega: DVec3,
}

/// Per-contact memory, kept apart from the material parameters (MercuryDPM's split).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct ContactHistory {
    /// Accumulated tangential displacement ξ of i relative to j [m].
    pub tangential: DVec3,
    /// EPSD spring torque on i [N m].
    pub rolling: DVec3,
    /// The pair is bonded by a cohesion that acts beyond contact (a JKR contact or a liquid
    /// bridge that formed on touching and has not broken).
    pub bonded: bool,
}

impl ContactHistory {
    /// True when the contact remembers nothing.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.tangential == DVec3::ZERO && self.rolling == DVec3::ZERO && !self.bonded
    }
}

/// The result of one contact: the force on i (on j it is −force) and the two torques.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ContactForce {
    /// Force on i [N].
    pub force: DVec3,
    /// Torque on i [N m].
    pub torque_i: DVec3,
    /// Torque on j [N m].
    pub torque_j: DVec3,
}

impl ContactLaws {
    /// Evaluates one contact, updating its history (docs/physics.md §1–4, in that order).
    #[inline(always)]
    pub fn resolve(
        &self,
        g: &ContactGeometry,
        i: &BodyMotion,
        j: &BodyMotion,
        c: &PairCoefficients,
        history: &mut ContactHistory,
        dt: f64,
    ) -> ContactForce {
        let n = g.normal;
        // Contact-point relative velocity of i with respect to j (§1).
        let v_rel = (i.velocity - j.velocity) - (g.arm_i * i.omega + g.arm_j * j.omega).cross(n);
        let v_n = v_rel.dot(n);
        let v_t = v_rel - v_n * n;

        // Normal (§2): Hertz (Eq. 6 elastic part), or the pair's cohesive law, then the
        // restitution dashpot (§2.1).
        let normal = match cohesion::normal_stage(g, c, history.bonded) {
            NormalOutcome::Contact(normal) => normal,
            NormalOutcome::BridgeOnly(pull) => {
                // A bridge across a gap: no solid contact, nothing for friction to remember.
                *history = ContactHistory {
                    bonded: true,
                    ..ContactHistory::default()
                };
                return ContactForce {
                    force: -pull * n,
                    ..ContactForce::default()
                };
            }
            NormalOutcome::Apart => {
                *history = ContactHistory::default();
                return ContactForce::default();
            }
        };
        history.bonded = c.cohesion.bonds();
        let gamma_n = damping::dashpot(c.damping, normal.stiffness, g.m_eff);
        let mut f_n = normal.elastic - gamma_n * v_n;
        if self.normal_clamp && f_n < normal.floor {
            f_n = normal.floor;
        }
        if normal.pull != 0.0 {
            f_n -= normal.pull;
        }

        // Tangential (§3): history rotated into the current tangent plane first.
        let cap = tangential::coulomb_limit(c.friction, normal.load);
        history.tangential = tangential::rotate_into_plane(history.tangential, n);
        let f_t = match self.tangential {
            TangentialLaw::MindlinNoSlip => {
                let s_t = tangential::mindlin_stiffness(c.g_star, normal.contact_radius);
                let gamma_t = tangential::no_slip_dashpot(gamma_n, c.stiffness_ratio_sqrt);
                tangential::mindlin_no_slip(&mut history.tangential, v_t, dt, s_t, cap, gamma_t)
            }
            TangentialLaw::MindlinDeresiewicz => {
                let slip =
                    tangential::slip_distance(c.friction, normal.overlap, c.e_star, c.g_star);
                tangential::mindlin_deresiewicz(
                    &mut history.tangential,
                    v_t,
                    dt,
                    cap,
                    slip,
                    c.damping,
                    g.m_eff,
                )
            }
        };
        // Torque of F_t about each centre. The lever from i's centre to the contact point is
        // −a_i n and from j's is +a_j n with force −F_t on j, so M_i = −a_i (n × F_t) and
        // M_j = −a_j (n × F_t): one cross product serves both.
        let n_cross_ft = n.cross(f_t);

        // Rolling (§4), on the relative spin and the normal load.
        let omega_rel = i.omega - j.omega;
        let (mut torque_i, mut torque_j) = match self.rolling {
            // Eq. 8 folded into the same levers: one division instead of three and no
            // second cross product.
            RollingLaw::ConstantTorque { limiter: false } => {
                let w2 = omega_rel.length_squared();
                let s = rolling::constant_torque_scale(c.rolling_friction, normal.load, w2);
                rolling::constant_torque_levers(n_cross_ft, s, omega_rel, (g.arm_i, g.arm_j))
            }
            RollingLaw::None
            | RollingLaw::ConstantTorque { limiter: true }
            | RollingLaw::Epsd { .. } => (-g.arm_i * n_cross_ft, -g.arm_j * n_cross_ft),
        };
        if c.rolling_friction > 0.0 {
            match self.rolling {
                RollingLaw::None | RollingLaw::ConstantTorque { limiter: false } => {}
                RollingLaw::ConstantTorque { limiter: true } => {
                    let limit =
                        rolling::constant_torque_limit(g.inertia_reduced(), omega_rel.length(), dt);
                    let m = c.rolling_friction * normal.load;
                    let (mi, mj) =
                        rolling::constant_torque(omega_rel, m * g.arm_i, m * g.arm_j, limit);
                    torque_i += mi;
                    torque_j += mj;
                }
                RollingLaw::Epsd { viscous_damping } => {
                    let omega_roll = omega_rel - omega_rel.dot(n) * n;
                    history.rolling = tangential::rotate_into_plane(history.rolling, n);
                    let mu_r = c.rolling_friction;
                    let k_r = rolling::epsd_stiffness(normal.load, normal.overlap, mu_r, g.r_eff);
                    let cap_r = rolling::epsd_limit(mu_r, g.r_eff, normal.load);
                    let eta = rolling::epsd_dashpot(viscous_damping, g.rolling_inertia(), k_r);
                    let m = rolling::epsd(&mut history.rolling, omega_roll, dt, k_r, cap_r, eta);
                    torque_i += m;
                    torque_j -= m;
                }
            }
        }

        ContactForce {
            force: f_n * n + f_t,
            torque_i,
            torque_j,
        }
    }
}
