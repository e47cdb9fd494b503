//! CO-T — Thornton-type normalised oblique impacts of a sphere on a rigid plane, no initial spin
//! (physics.md §9, after Thornton et al.'s Ψ1–Ψ2 regime maps).
//!
//! Set-up: V_n = 1 m/s, V_t = Ψ1 μ(1+e) V_n, no gravity, Hertz–Mindlin no-slip. Three series:
//! e = 1 with ν = 0.30 and with ν = 0.25 (E = 7.0e10 Pa, ρ = 2700 kg/m³, R = 2.5 mm, μ = 0.3; for
//! e = 1 the normalised results depend on ν only), and the Table-1 material (R = 1.5 mm,
//! μ = 0.5, e = 0.2). Outputs: Ψ2 = V_t'/(μ(1+e)V_n), with V_t' the contact-point tangential
//! velocity after impact, and Ω = R|ω'|/(μ(1+e)V_n).
//!
//! Expected: the model-reference table of physics.md §9 (Appendix-B integrator). For Ψ1 ≥ 4 these
//! are the rigid-body sliding line Ψ2 = Ψ1 − 3.5 and the plateau Ω = 2.5.
//!
//! Tolerance (physics.md §9): 0.02 absolute on the sliding line and the Ω plateau (Ψ1 ≥ 4),
//! 0.05 elsewhere.

use dem::{ContactLaws, Interaction, Material};

use crate::impact::oblique_on_rigid_plane;
use crate::{Resolution, Row, VerifyError};

const TEST: &str = "CO-T";

/// Ψ1 values of the table.
const PSI1: [f64; 11] = [0.25, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0, 5.0, 6.0];
/// Ψ2 for e = 1, ν = 0.30.
const PSI2_NU30: [f64; 11] = [
    0.238, 0.333, -0.138, -0.501, -0.699, -0.718, -0.491, 0.000, 0.5, 1.5, 2.5,
];
/// Ω for e = 1, ν = 0.30.
const OMEGA_NU30: [f64; 11] = [
    0.009, 0.119, 0.813, 1.429, 1.928, 2.298, 2.493, 2.5, 2.5, 2.5, 2.5,
];
/// Ψ2 for e = 1, ν = 0.25.
const PSI2_NU25: [f64; 11] = [
    0.250, 0.373, -0.098, -0.465, -0.670, -0.700, -0.487, 0.000, 0.5, 1.5, 2.5,
];
/// Ψ2 for Table 1 (e = 0.2, μ = 0.5, V_n = 1 m/s).
const PSI2_TABLE1: [f64; 11] = [
    0.001, 0.002, 0.000, -0.014, -0.034, -0.057, -0.130, 0.002, 0.502, 1.502, 2.502,
];
/// Ω for Table 1.
const OMEGA_TABLE1: [f64; 11] = [
    0.178, 0.356, 0.714, 1.081, 1.453, 1.826, 2.235, 2.499, 2.5, 2.5, 2.5,
];

/// The tolerance of physics.md §9 at Ψ1.
fn tolerance(psi1: f64) -> f64 {
    if psi1 >= 4.0 {
        0.02
    } else {
        0.05
    }
}

/// One series: its label, particle, and the tabulated Ψ2 and (optionally) Ω.
struct Series {
    label: &'static str,
    material: Material,
    radius: f64,
    interaction: Interaction,
    psi2: [f64; 11],
    omega: Option<[f64; 11]>,
}

/// Runs CO-T.
pub fn run(resolution: Resolution) -> Result<Vec<Row>, VerifyError> {
    let elastic = |nu| Material {
        density: 2700.0,
        youngs_modulus: 7.0e10,
        poisson_ratio: nu,
    };
    let frictional = Interaction {
        friction: 0.3,
        rolling_friction: 0.0,
        restitution: 1.0,
    };
    let table1 = Interaction {
        rolling_friction: 0.0,
        ..Interaction::fan2023()
    };
    let series = [
        Series {
            label: "e = 1, ν = 0.30",
            material: elastic(0.30),
            radius: 2.5e-3,
            interaction: frictional,
            psi2: PSI2_NU30,
            omega: Some(OMEGA_NU30),
        },
        Series {
            label: "e = 1, ν = 0.25",
            material: elastic(0.25),
            radius: 2.5e-3,
            interaction: frictional,
            psi2: PSI2_NU25,
            omega: None,
        },
        Series {
            label: "Table 1",
            material: Material::fan2023(),
            radius: 1.5e-3,
            interaction: table1,
            psi2: PSI2_TABLE1,
            omega: Some(OMEGA_TABLE1),
        },
    ];
    let normal = 1.0;
    let mut rows = Vec::new();
    for s in &series {
        let scale = s.interaction.friction * (1.0 + s.interaction.restitution) * normal;
        for (k, &psi1) in PSI1.iter().enumerate() {
            let o = oblique_on_rigid_plane(
                s.material,
                s.radius,
                s.interaction,
                ContactLaws::default(),
                psi1 * scale,
                normal,
                0.0,
                resolution.steps_per_contact(),
            )?;
            let tol = tolerance(psi1);
            rows.push(Row::absolute(
                TEST,
                format!("{} Ψ1 = {psi1}: Ψ2 [-]", s.label),
                s.psi2[k],
                o.contact_tangential / scale,
                tol,
            ));
            if let Some(omega) = s.omega {
                rows.push(Row::absolute(
                    TEST,
                    format!("{} Ψ1 = {psi1}: Ω [-]", s.label),
                    omega[k],
                    s.radius * o.spin.abs() / scale,
                    tol,
                ));
            }
        }
    }
    Ok(rows)
}
