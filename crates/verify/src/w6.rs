//! W6 — the loads on a mesh: the sum of the per-triangle forces equals the wall's total
//! force, and a bed at rest weighs on its floor (docs/physics.md §5.5, §9).
//!
//! Set-up: 64 Table-1 spheres dropped into a box whose floor is a mesh of 2 × 12² triangles
//! and whose sides are planes; they settle for 0.15 s, then the loads are summed over
//! 0.05 s: each triangle's impulse from `Simulation::take_surface_loads`, and the wall's
//! total force `Simulation::wall_load` of every step.
//!
//! Expected: Σ per-triangle impulse / window = mean total force (the same contacts booked
//! twice); the floor's mean normal force = the bed's weight (the sides are frictionless, so
//! they carry none of it).
//! Tolerance: 1e-9 relative for the sum (the total is summed in fixed point with a quantum
//! of 2⁻³² of a sphere's weight, the triangles in floating point); 1 % for the weight (the
//! settling bed's residual motion).

use dem::{
    DVec3, Interaction, Material, ParticleInit, Simulation, SimulationConfig, Wall, WallMaterial,
};

use crate::meshes::{floor, mesh_wall, RADIUS, TIME_STEP};
use crate::{Resolution, Row, VerifyError};

const TEST: &str = "W6";

/// The rows of W6.
pub fn run(_res: Resolution) -> Result<Vec<Row>, VerifyError> {
    let interaction = Interaction::fan2023();
    let slippery = Interaction {
        friction: 0.0,
        rolling_friction: 0.0,
        ..interaction
    };
    let mut config = SimulationConfig::new(TIME_STEP);
    config.resort_every = 0;
    let mut sim = Simulation::new(config)?;
    let m = sim.add_material(Material::fan2023(), interaction)?;
    let half = 6.0 * RADIUS;
    let floor_id = sim.add_wall(mesh_wall(&floor(half, 12, 0.0), interaction)?)?;
    for (point, normal) in [
        (DVec3::new(-half, 0.0, 0.0), DVec3::X),
        (DVec3::new(half, 0.0, 0.0), -DVec3::X),
        (DVec3::new(0.0, -half, 0.0), DVec3::Y),
        (DVec3::new(0.0, half, 0.0), -DVec3::Y),
    ] {
        sim.add_wall(Wall::plane(point, normal, WallMaterial::Rigid, slippery)?)?;
    }
    for k in 0..64 {
        let (i, j, l) = (k % 4, (k / 4) % 4, k / 16);
        let position = DVec3::new(
            -half + (1.5 + 3.0 * i as f64) * RADIUS,
            -half + (1.5 + 3.0 * j as f64) * RADIUS,
            (1.5 + 2.5 * l as f64) * RADIUS,
        );
        sim.add_particle(ParticleInit {
            position,
            velocity: DVec3::ZERO,
            angular_velocity: DVec3::ZERO,
            radius: RADIUS,
            material: m,
            flags: 0,
        })?;
    }
    let weight: f64 = sim.particles().masses().iter().map(|m| m * 9.81).sum();
    for _ in 0..60_000 {
        sim.step()?;
    }
    sim.take_surface_loads(floor_id)?;
    let window = 20_000;
    let mut total = DVec3::ZERO;
    for _ in 0..window {
        sim.step()?;
        total += sim.wall_load(floor_id)?.force;
    }
    let mean = total / window as f64;
    let loads = sim.take_surface_loads(floor_id)?;
    let summed: DVec3 = loads.elements.iter().map(|e| e.impulse).sum::<DVec3>() / loads.duration;
    let normal: f64 = loads.elements.iter().map(|e| e.normal_impulse).sum::<f64>() / loads.duration;
    Ok(vec![
        Row::absolute(
            TEST,
            "mesh floor: |Σ triangle forces − total force| / total",
            0.0,
            summed.distance(mean) / mean.length(),
            1e-9,
        ),
        Row::relative(
            TEST,
            "mesh floor: mean normal force [N] = weight of the bed",
            weight,
            normal,
            0.01,
        ),
    ])
}
