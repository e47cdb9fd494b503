//! A Table-1 sphere resting on a plane under (possibly tilted) gravity: the shared set-up of the
//! sliding, rolling and incline cases A1–A3.
//!
//! The plane is z = 0 with normal +z, made of the particle material (docs/physics.md §5 default).
//! An incline of angle θ is modelled by tilting gravity instead of the plane,
//! g = 9.81 (sin θ, 0, −cos θ) m/s², so that x is the downhill direction. The sphere starts
//! at the equilibrium overlap of its normal load, so no normal bounce disturbs the measurement.

use dem::contact::normal::hertz;
use dem::material::effective_youngs_modulus;
use dem::{
    ContactLaws, DVec3, Interaction, Material, ParticleInit, Simulation, SimulationConfig, Wall,
    WallMaterial,
};

use crate::VerifyError;

/// Standard gravity [m/s²] (docs/physics.md §6.2).
pub const GRAVITY: f64 = 9.81;
/// Table-1 particle radius [m].
pub const RADIUS: f64 = 1.5e-3;
/// Production time step [s] (docs/physics.md §6.1: 0.097 of the Rayleigh time).
pub const TIME_STEP: f64 = 2.5e-6;

/// One sphere on the plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Surface {
    /// Incline angle θ [rad] (0: horizontal).
    pub incline: f64,
    /// Friction, rolling friction and restitution of the sphere–plane contact.
    pub interaction: Interaction,
    /// Contact sub-models.
    pub laws: ContactLaws,
    /// Initial velocity along x (downhill) [m/s].
    pub speed: f64,
    /// Particle flags (`FLAG_ROTATION_LOCKED` for block sliding).
    pub flags: u8,
}

impl Surface {
    /// Builds the simulation; the sphere is particle index 0 and the only particle.
    pub fn build(&self) -> Result<Simulation, VerifyError> {
        let material = Material::fan2023();
        let mut config = SimulationConfig::new(TIME_STEP);
        config.gravity = GRAVITY * DVec3::new(self.incline.sin(), 0.0, -self.incline.cos());
        config.laws = self.laws;
        config.resort_every = 0;
        let mut sim = Simulation::new(config)?;
        let id = sim.add_material(material, self.interaction)?;
        sim.add_wall(Wall::plane(
            DVec3::ZERO,
            DVec3::Z,
            WallMaterial::Elastic(material),
            self.interaction,
        )?)?;
        // Equilibrium overlap: (4/3) E* √R δ^{3/2} = m g cos θ.
        let e_star = effective_youngs_modulus(&material, Some(&material));
        let mass = material.density * 4.0 / 3.0 * std::f64::consts::PI * RADIUS.powi(3);
        let load = mass * GRAVITY * self.incline.cos();
        let overlap = (3.0 * load / (4.0 * e_star * RADIUS.sqrt())).powf(2.0 / 3.0);
        debug_assert!((hertz(e_star, RADIUS, overlap).force - load).abs() <= 1e-9 * load);
        sim.add_particle(ParticleInit {
            position: DVec3::new(0.0, 0.0, RADIUS - overlap),
            velocity: DVec3::new(self.speed, 0.0, 0.0),
            angular_velocity: DVec3::ZERO,
            radius: RADIUS,
            material: id,
            flags: self.flags,
        })?;
        Ok(sim)
    }
}

/// Downhill position x [m], velocity v_x [m/s], spin ω_y [rad/s] and contact-point slip
/// v_x − R ω_y [m/s] of the only sphere.
pub fn probe(sim: &Simulation) -> (f64, f64, f64, f64) {
    let p = sim.particles();
    let (x, v, w) = (
        p.positions()[0].x,
        p.velocities()[0].x,
        p.angular_velocities()[0].y,
    );
    (x, v, w, v - RADIUS * w)
}

/// Steps until `event(sim)` turns true; returns the steps taken.
pub fn run_until(
    sim: &mut Simulation,
    max_steps: u64,
    what: &'static str,
    mut event: impl FnMut(&Simulation) -> bool,
) -> Result<u64, VerifyError> {
    for k in 0..max_steps {
        sim.step()?;
        if event(sim) {
            return Ok(k + 1);
        }
    }
    Err(VerifyError::NoEvent {
        what,
        steps: max_steps,
    })
}
