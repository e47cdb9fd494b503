//! P1 — binary impacts of the project material, Table 1 of Fan et al. (2023) (docs/physics.md §1.1, §9).
//!
//! Set-up: d = 3 mm, ρ = 2500 kg/m³, G = 1e8 Pa, ν = 0.25, frictionless, no gravity.
//!
//! Expected (docs/physics.md §9, Hertz closed forms and the §2.3 damped ODE):
//! - head-on sphere–sphere at v_rel = 1 m/s, e = 1: δ_max = 29.02 µm, F_max = 0.7612 N, t_c = 85.41 µs;
//! - the same with e = 0.2: rebound v_rel' = 0.200 m/s and t_c = 110.8 µs;
//! - rigid wall at 1 m/s, e = 1: δ_max = 25.26 µm, t_c = 74.35 µs;
//! - same-material wall at 1 m/s, e = 1: δ_max = 33.34 µm, t_c = 98.11 µs;
//! - at the production step Δt = 2.5 µs, the sphere–sphere e = 0.2 impact still rebounds at e = 0.2.
//!
//! Tolerance (docs/physics.md §9): 1 %, and 0.01 in e at the production Δt (the half-step dashpot
//! bias of §2.3, ≈ 0.003 at 30–40 steps per contact).

use dem::{ContactLaws, DVec3, Interaction, Material, WallMaterial};

use crate::impact::{Impact, Target};
use crate::{Resolution, Row, VerifyError};

const TEST: &str = "P1";
/// Production time step of the paper's runs [s] (docs/physics.md §6.1).
const PRODUCTION_STEP: f64 = 2.5e-6;

fn impact(target: Target, restitution: f64, res: Resolution) -> Impact {
    let velocity = match target {
        Target::Twin => DVec3::new(0.5, 0.0, 0.0),
        Target::Plane(_) => DVec3::new(0.0, 0.0, -1.0),
        Target::Sphere(other) => DVec3::new(other.velocity.x + 1.0, 0.0, 0.0),
    };
    Impact {
        material: Material::fan2023(),
        radius: 1.5e-3,
        interaction: Interaction {
            friction: 0.0,
            rolling_friction: 0.0,
            restitution,
            cohesion: dem::Cohesion::None,
        },
        laws: ContactLaws::default(),
        target,
        velocity,
        angular_velocity: DVec3::ZERO,
        steps_per_contact: res.steps_per_contact(),
    }
}

/// Runs P1.
pub fn run(resolution: Resolution) -> Result<Vec<Row>, VerifyError> {
    let mut rows = Vec::new();
    let r = impact(Target::Twin, 1.0, resolution).run()?;
    rows.push(Row::relative(
        TEST,
        "sphere-sphere 1 m/s, e = 1: peak overlap [m]",
        29.02e-6,
        r.peak_overlap,
        0.01,
    ));
    rows.push(Row::relative(
        TEST,
        "sphere-sphere 1 m/s, e = 1: peak force [N]",
        0.7612,
        r.peak_force,
        0.01,
    ));
    rows.push(Row::relative(
        TEST,
        "sphere-sphere 1 m/s, e = 1: contact duration [s]",
        85.41e-6,
        r.duration,
        0.01,
    ));
    let r = impact(Target::Twin, 0.2, resolution).run()?;
    rows.push(Row::relative(
        TEST,
        "sphere-sphere 1 m/s, e = 0.2: rebound relative speed [m/s]",
        0.200,
        r.separation_speed,
        0.01,
    ));
    rows.push(Row::relative(
        TEST,
        "sphere-sphere 1 m/s, e = 0.2: contact duration [s]",
        110.8e-6,
        r.duration,
        0.01,
    ));
    let r = impact(Target::Plane(WallMaterial::Rigid), 1.0, resolution).run()?;
    rows.push(Row::relative(
        TEST,
        "rigid wall 1 m/s, e = 1: peak overlap [m]",
        25.26e-6,
        r.peak_overlap,
        0.01,
    ));
    rows.push(Row::relative(
        TEST,
        "rigid wall 1 m/s, e = 1: contact duration [s]",
        74.35e-6,
        r.duration,
        0.01,
    ));
    let r = impact(
        Target::Plane(WallMaterial::Elastic(Material::fan2023())),
        1.0,
        resolution,
    )
    .run()?;
    rows.push(Row::relative(
        TEST,
        "same-material wall 1 m/s, e = 1: peak overlap [m]",
        33.34e-6,
        r.peak_overlap,
        0.01,
    ));
    rows.push(Row::relative(
        TEST,
        "same-material wall 1 m/s, e = 1: contact duration [s]",
        98.11e-6,
        r.duration,
        0.01,
    ));
    // Same impact at Δt = 2.5 µs: choose steps per contact so that the harness lands on that step.
    let mut production = impact(Target::Twin, 0.2, resolution);
    production.steps_per_contact = 1.0;
    production.steps_per_contact = production.time_step() / PRODUCTION_STEP;
    let r = production.run()?;
    rows.push(Row::absolute(
        TEST,
        "sphere-sphere 1 m/s, e = 0.2, Δt = 2.5 µs: restitution [-]",
        0.2,
        r.restitution(),
        0.01,
    ));
    Ok(rows)
}
