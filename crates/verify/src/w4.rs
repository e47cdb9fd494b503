//! W4 — a closed mesh box with e = 1 and μ = 0 conserves energy (docs/physics.md §5.3, §9).
//!
//! Set-up: eight Table-1 spheres under gravity in a closed cube of 12 triangles, side
//! 12 R, with speeds of 0.3–0.5 m/s in all directions; e = 1 and no friction against the
//! walls and each other; 0.1 s (some hundred impacts on faces, edges and corners).
//!
//! Expected: the total energy (kinetic, rotational, gravitational, elastic) at the end
//! equals that at the start.
//! Tolerance: 1e-4 relative: without damping, velocity Verlet's energy error over one Hertz
//! contact resolved by ≈ 40 steps is of order (Δt/t_c)² ≈ 1e-3 of the impact's energy, and
//! it returns to zero after the contact up to a small part of that.

use dem::{DVec3, Interaction, Material, ParticleInit, Simulation, SimulationConfig};

use crate::meshes::{cube, mesh_wall, RADIUS, TIME_STEP};
use crate::{Resolution, Row, VerifyError};

const TEST: &str = "W4";
const TOLERANCE: f64 = 1e-4;

/// The rows of W4.
pub fn run(res: Resolution) -> Result<Vec<Row>, VerifyError> {
    let elastic = Interaction {
        friction: 0.0,
        rolling_friction: 0.0,
        restitution: 1.0,
        cohesion: dem::Cohesion::None,
    };
    let mut config = SimulationConfig::new(TIME_STEP);
    config.resort_every = 0;
    let mut sim = Simulation::new(config)?;
    let m = sim.add_material(Material::fan2023(), elastic)?;
    let side = 12.0 * RADIUS;
    sim.add_wall(mesh_wall(&cube(DVec3::ZERO, DVec3::splat(side)), elastic)?)?;
    for k in 0..8 {
        let corner = DVec3::new((k & 1) as f64, ((k >> 1) & 1) as f64, ((k >> 2) & 1) as f64);
        let position = DVec3::splat(3.0 * RADIUS) + corner * 6.0 * RADIUS;
        let dir = DVec3::new(
            (k as f64 * 1.3).sin(),
            (k as f64 * 2.1).cos(),
            (k as f64 * 0.7 + 0.4).sin(),
        )
        .normalize();
        sim.add_particle(ParticleInit {
            position,
            velocity: (0.3 + 0.025 * k as f64) * dir,
            angular_velocity: DVec3::ZERO,
            radius: RADIUS,
            material: m,
            flags: 0,
        })?;
    }
    let start = sim.energy().total();
    let steps: u64 = match res {
        Resolution::Full => 40_000,
        Resolution::Fast => 12_000,
    };
    let mut impacts = 0u64;
    let mut before = 0;
    for _ in 0..steps {
        sim.step()?;
        let c = sim.contacts().particle_wall + sim.contacts().particle_particle;
        impacts += u64::from(c > before);
        before = c;
    }
    // Finish outside any contact, where the elastic energy is exactly accounted.
    for _ in 0..100_000 {
        if sim.contacts().particle_wall + sim.contacts().particle_particle == 0 {
            break;
        }
        sim.step()?;
    }
    let end = sim.energy().total();
    let p = sim.particles();
    let inside = p
        .positions()
        .iter()
        .all(|x| x.min_element() > 0.0 && x.max_element() < side);
    Ok(vec![
        Row::absolute(
            TEST,
            format!("closed mesh box, e = 1, μ = 0: |ΔE|/E after {impacts} impacts"),
            0.0,
            (end - start).abs() / start.abs(),
            TOLERANCE,
        ),
        Row::absolute(
            TEST,
            "closed mesh box: spheres still inside (1 = all)",
            1.0,
            f64::from(u8::from(inside)),
            0.0,
        ),
    ])
}
