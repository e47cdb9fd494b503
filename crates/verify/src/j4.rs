//! J4 — simplified JKR cohesion: an attraction k_c A over the area where the undeformed
//! surfaces intersect, only while they overlap (docs/physics.md §2.5, §9).
//!
//! Set-up: spheres of R = 0.5 mm (E = 10⁸ Pa, ν = 0.3), k_c = 10⁶ J/m³, no friction, e = 1,
//! no gravity.
//! - A held sphere and a rigid plane (`adhesion::pressed`): the plane starts 0.1 µm away,
//!   presses to an overlap of 1 µm and pulls away to a gap of 0.1 µm, 10⁻³ µm per step
//!   (10⁻² µm fast).
//! - Two free spheres head-on at 0.05 m/s (`adhesion::meeting`).
//!
//! Expected, written out here: against the plane, F = (4/3)E*√R δ^{3/2} − k_c π(2Rδ − δ²)
//! while δ > 0 and no force across the gap, on loading and unloading alike. The force is a
//! function of the overlap alone, zero at touching, so an impact of two spheres is elastic:
//! they part at the speed they met.
//!
//! Tolerances: the force to 10⁻¹² of k_c π 2R δ_max, round-off of the closed form; the
//! parting speed to the energy error of velocity Verlet over a smooth contact, (ω Δt)²/8 of
//! the energy at ω the contact's highest frequency: Δt is t_c/1000 here, so 10⁻⁵ relative.

use std::f64::consts::PI;

use dem::contact::normal::hertz_contact_time;
use dem::Cohesion;

use crate::adhesion::{meeting, pair_mass, pair_modulus, plane_modulus, pressed, RADIUS};
use crate::{Resolution, Row, VerifyError};

const TEST: &str = "J4";

/// Cohesion energy density k_c [J/m³].
const DENSITY: f64 = 1e6;

/// Runs J4.
pub fn run(resolution: Resolution) -> Result<Vec<Row>, VerifyError> {
    let cohesion = Cohesion::SimplifiedJkr {
        energy_density: DENSITY,
    };
    let step = match resolution {
        Resolution::Full => 1e-9,
        Resolution::Fast => 1e-8,
    };
    let dt = 1e-7;
    let deepest = 1e-6;
    let samples = pressed(cohesion, (-1e-7, deepest, -1e-7), step / dt, dt)?;
    let (e, r) = (plane_modulus(), RADIUS);
    let scale = DENSITY * PI * 2.0 * r * deepest;
    let (mut in_contact, mut across) = (0.0f64, 0.0f64);
    for s in &samples {
        if s.overlap > 0.0 {
            let d = s.overlap;
            let expected =
                4.0 / 3.0 * e * r.sqrt() * d.powf(1.5) - DENSITY * PI * (2.0 * r * d - d * d);
            in_contact = in_contact.max((s.force - expected).abs() / scale);
        } else {
            across = across.max(s.force.abs());
        }
    }
    let speed = 0.05;
    let t_c = hertz_contact_time(pair_modulus(), 0.5 * RADIUS, pair_mass(), speed);
    let dt = t_c / 1000.0;
    let met = meeting(
        cohesion,
        speed,
        (2.0 * speed * dt, 1e-6),
        dt,
        (100.0 * t_c / dt) as u64,
    )?;
    Ok(vec![
        Row::bounded(
            TEST,
            "sphere–plane, overlapping: largest |F − (F_Hertz − k_c π(2Rδ − δ²))|/(k_c π 2R δ_max) [-]",
            in_contact,
            1e-12,
        ),
        Row::absolute(
            TEST,
            "sphere–plane: largest |F| across the gap, loading and unloading [N]",
            0.0,
            across,
            0.0,
        ),
        Row::relative(
            TEST,
            "two spheres at 0.05 m/s: parting speed [m/s]",
            speed,
            met.separation_speed,
            1e-5,
        ),
    ])
}
