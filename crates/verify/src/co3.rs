//! CO3 — restitution reproduction (Chung & Ooi 2011, test 3, plus the paper's e = 0.2; docs/physics.md §2.3, §9).
//!
//! Set-up: normal impact on a rigid plane at 3.9 m/s, R = 2.5 mm, no gravity, no friction,
//! e_in ∈ {0.2, 0.4, 0.6, 0.8, 1.0}, for Al oxide (E = 3.8e11 Pa, ν = 0.23, ρ = 4000 kg/m³) and
//! cast iron (E = 1.0e11 Pa, ν = 0.25, ρ = 7000 kg/m³). Then the Table-1 material
//! (d = 3 mm, e = 0.2): sphere–sphere, sphere–same-material wall and sphere–rigid wall at
//! v_rel ∈ {0.1, 1, 3} m/s.
//!
//! Expected: without the force clamp, e_out = e_in for any speed and material (the 2√(5/6)β
//! dashpot is exact for the Hertz ODE, docs/physics.md §2.3). With the clamp F_n ≥ 0 (optional
//! mode), e_out follows the §2.3 table (0.253 … 0.902 for e_in = 0.1 … 0.9), checked here on Al oxide.
//!
//! Tolerance (docs/physics.md §9 table, by steps actually spent in contact, because the half-step
//! dashpot biases e_out by O(1/steps), §2.3): ≥ 400 steps → 0.002, ≥ 100 → 0.005, fewer → 0.01.
//! Clamped rows add 0.0005 for the three-decimal rounding of the §2.3 table.

use dem::{ContactLaws, DVec3, Interaction, Material, WallMaterial};

use crate::impact::{Impact, ImpactRecord, Target};
use crate::{Resolution, Row, VerifyError};

const TEST: &str = "CO3";

/// Al oxide of Chung & Ooi's tests 3–4.
pub const ALUMINA: Material = Material {
    density: 4000.0,
    youngs_modulus: 3.8e11,
    poisson_ratio: 0.23,
};
/// Cast iron of Chung & Ooi's test 3.
pub const CAST_IRON: Material = Material {
    density: 7000.0,
    youngs_modulus: 1.0e11,
    poisson_ratio: 0.25,
};

/// The clamped-force restitution table of docs/physics.md §2.3: (e_in, e_out).
const CLAMPED: [(f64, f64); 9] = [
    (0.1, 0.253),
    (0.2, 0.325),
    (0.3, 0.397),
    (0.4, 0.472),
    (0.5, 0.550),
    (0.6, 0.632),
    (0.7, 0.718),
    (0.8, 0.808),
    (0.9, 0.902),
];

/// The |e_out − e_in| tolerance of docs/physics.md §9 for a contact resolved by `steps` steps.
pub fn restitution_tolerance(steps: u64) -> f64 {
    if steps >= 400 {
        0.002
    } else if steps >= 100 {
        0.005
    } else {
        0.01
    }
}

fn frictionless(restitution: f64) -> Interaction {
    Interaction {
        friction: 0.0,
        rolling_friction: 0.0,
        restitution,
        cohesion: dem::Cohesion::None,
    }
}

fn normal_impact(
    material: Material,
    radius: f64,
    e: f64,
    target: Target,
    speed: f64,
    clamp: bool,
    res: Resolution,
) -> Result<ImpactRecord, VerifyError> {
    let velocity = match target {
        Target::Plane(_) => DVec3::new(0.0, 0.0, -speed),
        // Each twin moves at half the relative speed.
        Target::Twin => DVec3::new(0.5 * speed, 0.0, 0.0),
        // The first sphere approaches the other at the relative speed.
        Target::Sphere(other) => DVec3::new(other.velocity.x + speed, 0.0, 0.0),
    };
    Impact {
        material,
        radius,
        interaction: frictionless(e),
        laws: ContactLaws {
            normal_clamp: clamp,
            ..ContactLaws::default()
        },
        target,
        velocity,
        angular_velocity: DVec3::ZERO,
        steps_per_contact: res.steps_per_contact(),
    }
    .run()
}

/// Runs CO3.
pub fn run(resolution: Resolution) -> Result<Vec<Row>, VerifyError> {
    let mut rows = Vec::new();
    for (name, material) in [("Al oxide", ALUMINA), ("cast iron", CAST_IRON)] {
        for e_in in [0.2, 0.4, 0.6, 0.8, 1.0] {
            let r = normal_impact(
                material,
                2.5e-3,
                e_in,
                Target::Plane(WallMaterial::Rigid),
                3.9,
                false,
                resolution,
            )?;
            let tol = restitution_tolerance(r.steps_in_contact);
            rows.push(Row::absolute(
                TEST,
                format!("{name}, rigid plane, 3.9 m/s, e_in = {e_in}: e_out [-]"),
                e_in,
                r.restitution(),
                tol,
            ));
        }
    }
    let table1 = Material::fan2023();
    let targets = [
        ("sphere-sphere", Target::Twin),
        (
            "sphere-wall (same material)",
            Target::Plane(WallMaterial::Elastic(table1)),
        ),
        ("sphere-wall (rigid)", Target::Plane(WallMaterial::Rigid)),
    ];
    for (name, target) in targets {
        for speed in [0.1, 1.0, 3.0] {
            let r = normal_impact(table1, 1.5e-3, 0.2, target, speed, false, resolution)?;
            let tol = restitution_tolerance(r.steps_in_contact);
            rows.push(Row::absolute(
                TEST,
                format!("Table 1 {name}, {speed} m/s, e_in = 0.2: e_out [-]"),
                0.2,
                r.restitution(),
                tol,
            ));
        }
    }
    for (e_in, e_out) in CLAMPED {
        let r = normal_impact(
            ALUMINA,
            2.5e-3,
            e_in,
            Target::Plane(WallMaterial::Rigid),
            3.9,
            true,
            resolution,
        )?;
        let tol = restitution_tolerance(r.steps_in_contact) + 0.0005;
        rows.push(Row::absolute(
            TEST,
            format!("Al oxide, force clamp on, e_in = {e_in}: e_out [-]"),
            e_out,
            r.restitution(),
            tol,
        ));
    }
    Ok(rows)
}
