//! J3 — a pendular liquid bridge: its force at contact, its force across a gap, where it
//! ruptures, and the energy it takes from an impact (Willett et al. 2000, Langmuir 16, 9396;
//! Lian, Thornton & Adams 1993, J. Colloid Interface Sci. 161, 138; docs/physics.md §2.6, §9).
//!
//! Set-up: water-like liquid, γ = 0.072 N/m, θ = 20°, V = 10⁻³ R³ per bridge, on spheres of
//! R = 0.5 mm (E = 10⁸ Pa, ν = 0.3), no friction, e = 1, no gravity.
//! - A held sphere and a rigid plane (`adhesion::pressed`): the plane starts S_c/2 away,
//!   presses to an overlap of 1 µm and pulls away to 1.2 S_c, Δs = S_c/N per step
//!   (N = 20 000; 2000 fast).
//! - Two free spheres head-on at v = 2 v_b (`adhesion::meeting`), v_b = √(2E_b/m*) the speed
//!   whose kinetic energy the bridge takes; v_b Δt = S_c/N (N = 4000; 1000 fast).
//!
//! Expected, written out here: the bridge radius R̃ = 2R* (2R against a plane, R between two
//! spheres), F(S) = 2πR̃γ cos θ/(1 + 2.1Ŝ + 10Ŝ²) with Ŝ = (S/2)√(R̃/V), S_c = (1 + θ/2)V^{1/3};
//! while the surfaces overlap, Hertz's (4/3)E*√R* δ^{3/2} less the contact value F(0). No force
//! across the gap before the surfaces touch. The energy the bridge takes is
//! E_b = ∫₀^{S_c} F dS = 2πR̃γ cos θ · 2√(V/R̃) · (2/√35.59) [atan((20Ŝ + 2.1)/√35.59)]₀^{Ŝ_c}.
//!
//! Tolerances: the forces to 10⁻¹² of F(0), round-off of the same closed forms (the engine
//! evaluates them in another order); the rupture to one step Δs; E_b: the force jumps by F(0)
//! when the surfaces touch and by F(S_c) when the bridge breaks, and velocity Verlet errs by
//! at most each jump times one step's travel (2 v_b Δt, then at most 2 v_b Δt), so the
//! energy is within 2(F(0) + F(S_c)) S_c/N and the measured v_b within half that relative to
//! E_b; the row allows twice that.

use std::f64::consts::PI;

use dem::Cohesion;

use crate::adhesion::{meeting, pair_mass, plane_modulus, pressed, RADIUS};
use crate::{Resolution, Row, VerifyError};

const TEST: &str = "J3";

/// Surface tension γ [N/m].
const TENSION: f64 = 0.072;

/// The bridge's liquid volume V [m³] and contact angle θ [rad].
fn liquid() -> (f64, f64) {
    (1e-3 * RADIUS.powi(3), 20f64.to_radians())
}

/// Willett et al.'s force [N] at surface separation `s` [m] for bridge radius `r_tilde` [m].
fn willett(r_tilde: f64, s: f64) -> f64 {
    let (v, theta) = liquid();
    let hat = 0.5 * s * (r_tilde / v).sqrt();
    2.0 * PI * r_tilde * TENSION * theta.cos() / (1.0 + 2.1 * hat + 10.0 * hat * hat)
}

/// Runs J3.
pub fn run(resolution: Resolution) -> Result<Vec<Row>, VerifyError> {
    let (volume, theta) = liquid();
    let cohesion = Cohesion::LiquidBridge {
        volume,
        surface_tension: TENSION,
        contact_angle: theta,
    };
    let s_c = (1.0 + 0.5 * theta) * volume.cbrt();
    let mut rows = Vec::new();

    // A sphere and a plane, quasi-statically: R̃ = 2R.
    let n = match resolution {
        Resolution::Full => 20_000.0,
        Resolution::Fast => 2_000.0,
    };
    let dt = 1e-7;
    let step = s_c / n;
    let samples = pressed(cohesion, (-0.5 * s_c, 1e-6, -1.2 * s_c), step / dt, dt)?;
    let (e, r) = (plane_modulus(), RADIUS);
    let f0 = willett(2.0 * r, 0.0);
    let (mut approach, mut pressed_dev, mut gap_dev) = (0.0f64, 0.0f64, 0.0f64);
    let mut last_bridged = f64::NAN;
    for s in &samples {
        if s.overlap > 0.0 {
            let hertz = 4.0 / 3.0 * e * r.sqrt() * s.overlap.powf(1.5);
            pressed_dev = pressed_dev.max((s.force - (hertz - f0)).abs() / f0);
        } else if !s.unloading {
            approach = approach.max(s.force.abs());
        } else if s.force != 0.0 {
            gap_dev = gap_dev.max((s.force + willett(2.0 * r, -s.overlap)).abs() / f0);
            last_bridged = -s.overlap;
        }
    }
    rows.push(Row::absolute(
        TEST,
        "largest |F| across the gap before touching [N]",
        0.0,
        approach,
        0.0,
    ));
    rows.push(Row::bounded(
        TEST,
        "sphere–plane, overlapping: largest |F − (F_Hertz − 4πRγ cos θ)|/F(0) [-]",
        pressed_dev,
        1e-12,
    ));
    rows.push(Row::bounded(
        TEST,
        "sphere–plane, across the gap: largest |F + F_Willett(S)|/F(0) [-]",
        gap_dev,
        1e-12,
    ));
    rows.push(Row::absolute(
        TEST,
        "sphere–plane: separation of the last bridged sample / S_c [-]",
        1.0,
        last_bridged / s_c,
        1.0 / n,
    ));

    // Two spheres meeting: R̃ = 2R* = R.
    let r_tilde = RADIUS;
    let root = (40.0f64 - 2.1 * 2.1).sqrt();
    let hat_c = 0.5 * s_c * (r_tilde / volume).sqrt();
    let integral = 2.0 / root * (((20.0 * hat_c + 2.1) / root).atan() - (2.1 / root).atan());
    let energy = willett(r_tilde, 0.0) * 2.0 * (volume / r_tilde).sqrt() * integral;
    let m = pair_mass();
    let v_b = (2.0 * energy / m).sqrt();
    let n = match resolution {
        Resolution::Full => 4000.0,
        Resolution::Fast => 1000.0,
    };
    let dt = s_c / (n * v_b);
    let period_bound = 200.0 * s_c / v_b;
    let met = meeting(
        cohesion,
        2.0 * v_b,
        (0.1 * s_c, 1.01 * s_c),
        dt,
        (period_bound / dt) as u64,
    )?;
    let measured = ((2.0 * v_b).powi(2) - met.separation_speed.powi(2)).sqrt();
    let jumps = willett(r_tilde, 0.0) + willett(r_tilde, s_c);
    let bound = 2.0 * jumps * s_c / n / energy;
    rows.push(Row::relative(
        TEST,
        format!("two spheres at 2 v_b: √(v² − v'²), v_b = {v_b:.4e} [m/s]"),
        v_b,
        measured,
        bound,
    ));
    Ok(rows)
}
