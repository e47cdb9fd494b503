//! CO1 — elastic head-on impact of two identical spheres (Chung & Ooi 2011, test 1; docs/physics.md §9).
//!
//! Set-up: two spheres of R = 0.010 m, each at 10 m/s towards the other (v_rel = 20 m/s),
//! e = 1, no friction, no gravity. Materials: glass (E = 4.8e10 Pa, ν = 0.20, ρ = 2800 kg/m³)
//! and limestone (E = 2.0e10 Pa, ν = 0.25, ρ = 2500 kg/m³).
//!
//! Expected (Hertz theory, docs/physics.md §9 table, computed from δ_max = (15 m* v²/(16 E*√R*))^{2/5},
//! F_max = 4/3 E*√R* δ_max^{3/2}, t_c = 2.943 δ_max/v): glass 274.1 µm, 10.70 kN, 40.34 µs;
//! limestone 368.3 µm, 7.108 kN, 54.20 µs. Rebound speed 10 m/s each.
//!
//! Tolerance (docs/physics.md §9): 1 % on δ_max, F_max and t_c and 1e-4 relative on the rebound
//! speed at ≥ 100 steps per contact; the force–overlap curve must follow 4/3 E*√R* δ^{3/2}
//! within 0.5 % at every step.

use dem::{ContactLaws, DVec3, Interaction, Material};

use crate::impact::{hertz_rows, Impact, Target};
use crate::{Resolution, Row, VerifyError};

const TEST: &str = "CO1";

/// Frictionless, perfectly elastic contact.
const ELASTIC: Interaction = Interaction {
    friction: 0.0,
    rolling_friction: 0.0,
    restitution: 1.0,
    cohesion: dem::Cohesion::None,
};

/// Runs CO1 for glass and limestone.
pub fn run(resolution: Resolution) -> Result<Vec<Row>, VerifyError> {
    // (name, material, δ_max [m], F_max [N], t_c [s]) from the docs/physics.md §9 table.
    let cases = [
        (
            "glass",
            Material {
                density: 2800.0,
                youngs_modulus: 4.8e10,
                poisson_ratio: 0.20,
            },
            274.1e-6,
            10.70e3,
            40.34e-6,
        ),
        (
            "limestone",
            Material {
                density: 2500.0,
                youngs_modulus: 2.0e10,
                poisson_ratio: 0.25,
            },
            368.3e-6,
            7.108e3,
            54.20e-6,
        ),
    ];
    let speed = 10.0;
    let mut rows = Vec::new();
    for (name, material, overlap, force, duration) in cases {
        let record = Impact {
            material,
            radius: 0.010,
            interaction: ELASTIC,
            laws: ContactLaws::default(),
            target: Target::Twin,
            velocity: DVec3::new(speed, 0.0, 0.0),
            angular_velocity: DVec3::ZERO,
            steps_per_contact: resolution.steps_per_contact(),
        }
        .run()?;
        rows.extend(hertz_rows(TEST, name, &record, (overlap, force, duration)));
        rows.push(Row::relative(
            TEST,
            format!("{name}: rebound speed of each sphere [m/s]"),
            speed,
            record.velocity.x.abs(),
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
