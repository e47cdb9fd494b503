//! A4 — static checks of the two tangential laws (physics.md §3.1–3.3, §9), calling the engine's
//! pure functions with the Table-1 sphere–sphere contact: E* = 1.333e8 Pa, G* = 2.857e7 Pa,
//! R* = 0.75 mm, δ_n = 20 µm, μ = 0.5, so δ_t,max = μ δ_n E*/(4G*) = 11.67 µm.
//!
//! Expected:
//! - Hertz–Mindlin no-slip: F_t = S_t ξ with S_t = 8G*√(R*δ), up to μF_ne, which it reaches at
//!   ξ = (2/3) δ_t,max, then constant;
//! - Mindlin–Deresiewicz: F_t = μF_ne (1 − (1 − ξ/δ_t,max)^{3/2}), reaching μF_ne at δ_t,max;
//! - both initial slopes equal S_t;
//! - rotating the normal by 90° in 900 steps with ξ held preserves |ξ| and keeps ξ·n = 0.
//!
//! Tolerance (physics.md §9): 1e-10 relative. The one exception is the finite-difference slope of
//! the Mindlin–Deresiewicz curve at ξ = 1e-7 δ_t,max: its truncation error is z/4 = 2.5e-8 and its
//! round-off ≈ 1e-16/z = 1e-9, so it is held to 1e-7; the exact initial stiffness is checked to
//! 1e-10 through the law's dashpot, which is built on the same k_t(0).

use dem::contact::normal::hertz;
use dem::contact::tangential::{mindlin_deresiewicz, mindlin_no_slip, rotate_into_plane};
use dem::material::{effective_shear_modulus, effective_youngs_modulus};
use dem::{DVec3, Material};

use crate::{Resolution, Row, VerifyError};

const TEST: &str = "A4";
const TIGHT: f64 = 1e-10;

/// Runs A4 (static, so the resolution does not matter).
pub fn run(_resolution: Resolution) -> Result<Vec<Row>, VerifyError> {
    let m = Material::fan2023();
    let e_star = effective_youngs_modulus(&m, Some(&m));
    let g_star = effective_shear_modulus(&m, Some(&m));
    let (r_eff, overlap, mu) = (7.5e-4, 2.0e-5, 0.5);
    let h = hertz(e_star, r_eff, overlap);
    let s_t = 8.0 * g_star * h.contact_radius;
    let cap = mu * h.force;
    let slip = mu * overlap * e_star / (4.0 * g_star);
    let no_slip = |x: f64| {
        let mut xi = DVec3::new(x, 0.0, 0.0);
        mindlin_no_slip(&mut xi, DVec3::ZERO, 0.0, s_t, cap, 0.0).length()
    };
    let deresiewicz = |x: f64| {
        let mut xi = DVec3::new(0.0, x, 0.0);
        mindlin_deresiewicz(&mut xi, DVec3::ZERO, 0.0, cap, slip, 0.0, 1.0).length()
    };
    let mut rows = Vec::new();

    let worst = (1..=45)
        .map(|k| {
            let x = slip * k as f64 / 30.0;
            (no_slip(x) - (s_t * x).min(cap)).abs() / (s_t * x).min(cap)
        })
        .fold(0.0, f64::max);
    rows.push(Row::bounded(
        TEST,
        "no-slip law: largest |F - min(S_t ξ, μF_ne)|/F for ξ ≤ 1.5 δ_t,max [-]",
        worst,
        TIGHT,
    ));
    rows.push(Row::relative(
        TEST,
        "no-slip law: F_t at ξ = (2/3) δ_t,max over μF_ne [-]",
        1.0,
        no_slip(2.0 / 3.0 * slip) / cap,
        TIGHT,
    ));
    let tiny = 1e-6 * slip;
    rows.push(Row::relative(
        TEST,
        "no-slip law: initial slope over 8G*√(R*δ) [-]",
        1.0,
        no_slip(tiny) / tiny / s_t,
        TIGHT,
    ));

    let worst = (1..=15)
        .map(|k| {
            let z = (k as f64 / 10.0).min(1.0);
            let expected = cap * (1.0 - (1.0 - z).powf(1.5));
            (deresiewicz(slip * k as f64 / 10.0) - expected).abs() / expected
        })
        .fold(0.0, f64::max);
    rows.push(Row::bounded(
        TEST,
        "Mindlin-Deresiewicz law: largest relative deviation from μF_ne(1-(1-z)^1.5) [-]",
        worst,
        TIGHT,
    ));
    rows.push(Row::relative(
        TEST,
        "Mindlin-Deresiewicz law: F_t at δ_t,max over μF_ne [-]",
        1.0,
        deresiewicz(slip) / cap,
        TIGHT,
    ));
    let z = 1e-7;
    rows.push(Row::relative(
        TEST,
        "Mindlin-Deresiewicz law: finite-difference slope at z = 1e-7 over S_t [-]",
        1.0,
        deresiewicz(z * slip) / (z * slip) / s_t,
        1e-7,
    ));
    // With ξ = 0 the law returns only its dashpot, −√(m* k_t(0)) v_t for unit prefactor and v_t = x̂.
    let mut xi = DVec3::ZERO;
    let dashpot = mindlin_deresiewicz(&mut xi, DVec3::X, 0.0, cap, slip, 1.0, 1.0).length();
    rows.push(Row::relative(
        TEST,
        "Mindlin-Deresiewicz law: k_t(0) over S_t [-]",
        1.0,
        dashpot * dashpot / s_t,
        TIGHT,
    ));

    // Normal turning from +z to −x in 900 steps while ξ (along +x, 1 µm) is held.
    let length = 1e-6;
    let mut xi = DVec3::new(length, 0.0, 0.0);
    let mut worst_tangency: f64 = 0.0;
    let steps = 900;
    for k in 1..=steps {
        let angle = std::f64::consts::FRAC_PI_2 * k as f64 / steps as f64;
        let n = DVec3::new(-angle.sin(), 0.0, angle.cos());
        xi = rotate_into_plane(xi, n);
        worst_tangency = worst_tangency.max(xi.dot(n).abs() / xi.length());
    }
    rows.push(Row::relative(
        TEST,
        "history rotated by 90°: |ξ| after over before [-]",
        1.0,
        xi.length() / length,
        TIGHT,
    ));
    rows.push(Row::bounded(
        TEST,
        "history rotated by 90°: largest |ξ·n|/|ξ| [-]",
        worst_tangency,
        TIGHT,
    ));
    Ok(rows)
}
