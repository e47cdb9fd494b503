//! CO2 — elastic normal impact of a sphere on a rigid plane (Chung & Ooi 2011, test 2; docs/physics.md §9).
//!
//! Set-up: R = 0.10 m at 0.2 m/s onto a rigid plane (E* = E/(1−ν²)), e = 1, no friction, no
//! gravity. Materials: Al alloy (E = 7.0e10 Pa, ν = 0.30, ρ = 2699 kg/m³) and Mg alloy
//! (E = 4.0e10 Pa, ν = 0.35, ρ = 1800 kg/m³).
//!
//! Expected (Hertz theory, docs/physics.md §9 table): Al 49.72 µm, 11.37 kN, 731.6 µs;
//! Mg 52.12 µm, 7.233 kN, 767.0 µs; rebound speed 0.2 m/s.
//!
//! Tolerance: as CO1 (1 % on δ_max, F_max, t_c; 1e-4 relative on the rebound speed; the
//! force–overlap curve within 0.5 % of Hertz).

use dem::{ContactLaws, DVec3, Interaction, Material, WallMaterial};

use crate::impact::{hertz_rows, Impact, Target};
use crate::{Resolution, Row, VerifyError};

const TEST: &str = "CO2";

/// Runs CO2 for the Al and Mg alloys.
pub fn run(resolution: Resolution) -> Result<Vec<Row>, VerifyError> {
    let cases = [
        (
            "Al alloy",
            Material {
                density: 2699.0,
                youngs_modulus: 7.0e10,
                poisson_ratio: 0.30,
            },
            49.72e-6,
            11.37e3,
            731.6e-6,
        ),
        (
            "Mg alloy",
            Material {
                density: 1800.0,
                youngs_modulus: 4.0e10,
                poisson_ratio: 0.35,
            },
            52.12e-6,
            7.233e3,
            767.0e-6,
        ),
    ];
    let speed = 0.2;
    let mut rows = Vec::new();
    for (name, material, overlap, force, duration) in cases {
        let record = Impact {
            material,
            radius: 0.10,
            interaction: Interaction {
                friction: 0.0,
                rolling_friction: 0.0,
                restitution: 1.0,
                cohesion: dem::Cohesion::None,
            },
            laws: ContactLaws::default(),
            target: Target::Plane(WallMaterial::Rigid),
            velocity: DVec3::new(0.0, 0.0, -speed),
            angular_velocity: DVec3::ZERO,
            steps_per_contact: resolution.steps_per_contact(),
        }
        .run()?;
        rows.extend(hertz_rows(TEST, name, &record, (overlap, force, duration)));
        rows.push(Row::relative(
            TEST,
            format!("{name}: rebound speed [m/s]"),
            speed,
            record.velocity.z,
            1e-4,
        ));
        rows.push(Row::absolute(
            TEST,
            format!("{name}: largest |F - Hertz(δ)|/Hertz(δ) [-]"),
            0.0,
            record.hertz_deviation,
            0.005,
        ));
    }
    Ok(rows)
}
