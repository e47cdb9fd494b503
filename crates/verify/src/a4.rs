//! A4 — static checks of the two tangential laws (docs/physics.md §3.1–3.3, §9): the engine's pure
//! functions with the Table-1 sphere–sphere contact (E* = 1.333e8 Pa, G* = 2.857e7 Pa,
//! R* = 0.75 mm, δ_n = 20 µm, μ = 0.5, so δ_t,max = μ δ_n E*/(4G*) = 11.67 µm), and one run of
//! the engine with a static sphere–plane contact.
//!
//! Expected:
//! - Hertz–Mindlin no-slip: F_t = S_t ξ with S_t = 8G*√(R*δ), up to μF_ne, which it reaches at
//!   ξ = (2/3) δ_t,max, then constant;
//! - Mindlin–Deresiewicz: F_t = μF_ne (1 − (1 − ξ/δ_t,max)^{3/2}), reaching μF_ne at δ_t,max;
//! - both initial slopes equal S_t: for Mindlin–Deresiewicz through its finite-difference slope
//!   and its dashpot; for the no-slip law in the engine run below;
//! - engine run: a Table-1 sphere frozen at δ_n = 20 µm on a same-material plane (so
//!   R* = R = 1.5 mm) that slides under it at a constant speed u, so that δ_n stays fixed while ξ
//!   grows monotonically. The tangential force read from the engine grows with the tangential
//!   displacement ξ stored in the engine's contact history at the slope 8G*√(R*δ) (§3.1), with
//!   δ read from the sphere's position. The slope is the chord ΔF_t/Δξ between
//!   ξ ≈ δ_slip/8 and δ_slip/2 (δ_slip = μF_ne/S_t, where the cap starts), so the constant
//!   tangential dashpot force γ_t u drops out. And ξ must grow by the imposed relative
//!   displacement u Δt a step;
//! - rotating the normal by 90° in 900 steps with ξ held preserves |ξ| and keeps ξ·n = 0.
//!
//! Tolerance (docs/physics.md §9): 1e-10 relative. In the engine run only round-off remains: ξ is a
//! sum of a few hundred increments (≈ 1e-14 relative), δ = R − z loses the digits that R has
//! beyond δ (≈ 1e-14), and the force chord is a difference of two forces of similar size
//! (≈ 1e-15); a wrong stiffness (4G* for 8G*, R for R*, the Mindlin–Deresiewicz curve, whose
//! chord there is 0.889 S_t) misses by per cents or more. The one exception is the
//! finite-difference slope of the Mindlin–Deresiewicz curve at ξ = 1e-7 δ_t,max: its truncation
//! error is z/4 = 2.5e-8 and its round-off ≈ 1e-16/z = 1e-9, so it is held to 1e-7; the exact
//! initial stiffness is checked to 1e-10 through the law's dashpot, which is built on the same
//! k_t(0).

use dem::contact::normal::hertz;
use dem::contact::tangential::{mindlin_deresiewicz, mindlin_no_slip, rotate_into_plane};
use dem::material::{effective_shear_modulus, effective_youngs_modulus};
use dem::{
    ContactLaws, DVec3, Interaction, Material, ParticleInit, Simulation, SimulationConfig,
    TangentialLaw, Wall, WallMaterial, FLAG_FROZEN,
};

use crate::{Resolution, Row, VerifyError};

const TEST: &str = "A4";
const TIGHT: f64 = 1e-10;

/// What the run of the no-slip law measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeldContact {
    /// Overlap read from the sphere's position, R − z [m].
    pub overlap: f64,
    /// Chord slope −ΔF_t/Δξ of the tangential force against the stored ξ [N/m].
    pub slope: f64,
    /// Growth of the stored ξ over the chord divided by the imposed u·(t₂ − t₁) [-].
    pub displacement_ratio: f64,
}

/// The engine's stored tangential displacement ξ_x [m] of the only sphere–wall contact, read
/// from the state a checkpoint would write.
fn stored_tangential_displacement(sim: &Simulation) -> Result<f64, VerifyError> {
    let state = serde_json::to_value(sim.state()).map_err(|e| VerifyError::Measurement {
        what: "state of the held contact",
        reason: e.to_string(),
    })?;
    state["wall_pairs"]["history"][0]["tangential"][0]
        .as_f64()
        .ok_or(VerifyError::Measurement {
            what: "stored tangential displacement",
            reason: "no sphere-wall contact history in the state".into(),
        })
}

/// Runs the engine on a Table-1 sphere frozen at overlap `overlap` [m] on a same-material plane
/// z = 0 that shows the contact law a velocity −u x̂ (u chosen so that ξ reaches δ_slip/2 of
/// the no-slip law in 400 steps), with friction `friction`, restitution 0.2, no gravity and the
/// tangential law `law`; measures the chord slope between steps 100 and 400.
pub fn held_contact(
    overlap: f64,
    friction: f64,
    law: TangentialLaw,
) -> Result<HeldContact, VerifyError> {
    let material = Material::fan2023();
    let radius = 1.5e-3;
    let time_step = 2.5e-6;
    let interaction = Interaction {
        friction,
        rolling_friction: 0.0,
        restitution: 0.2,
        cohesion: dem::Cohesion::None,
    };
    let mut config = SimulationConfig::new(time_step);
    config.gravity = DVec3::ZERO;
    config.resort_every = 0;
    config.laws = ContactLaws {
        tangential: law,
        ..ContactLaws::default()
    };
    let mut sim = Simulation::new(config)?;
    let id = sim.add_material(material, interaction)?;
    let wall = sim.add_wall(Wall::plane(
        DVec3::ZERO,
        DVec3::Z,
        WallMaterial::Elastic(material),
        interaction,
    )?)?;
    sim.add_particle(ParticleInit {
        position: DVec3::new(0.0, 0.0, radius - overlap),
        velocity: DVec3::ZERO,
        angular_velocity: DVec3::ZERO,
        radius,
        material: id,
        flags: FLAG_FROZEN,
    })?;
    // δ_slip from the closed forms, only to pick u; the measurement does not use it.
    let e_star = effective_youngs_modulus(&material, Some(&material));
    let g_star = effective_shear_modulus(&material, Some(&material));
    let h = hertz(e_star, radius, overlap);
    let slip = friction * h.force / (8.0 * g_star * h.contact_radius);
    let (first, last) = (100, 400);
    let speed = 0.5 * slip / (last as f64 * time_step);
    sim.set_wall_velocity(wall, DVec3::new(-speed, 0.0, 0.0))?;
    sim.run(first)?;
    let (t1, f1, xi1) = (
        sim.time(),
        sim.particles().forces()[0].x,
        stored_tangential_displacement(&sim)?,
    );
    sim.run(last - first)?;
    let (t2, f2, xi2) = (
        sim.time(),
        sim.particles().forces()[0].x,
        stored_tangential_displacement(&sim)?,
    );
    Ok(HeldContact {
        overlap: radius - sim.particles().positions()[0].z,
        slope: -(f2 - f1) / (xi2 - xi1),
        displacement_ratio: (xi2 - xi1) / (speed * (t2 - t1)),
    })
}

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
    let held = held_contact(overlap, mu, TangentialLaw::MindlinNoSlip)?;
    let radius = 1.5e-3;
    rows.push(Row::relative(
        TEST,
        "no-slip law, engine run at δ = 20 µm: slope ΔF_t/Δξ over 8G*√(R*δ) [-]",
        1.0,
        held.slope / (8.0 * g_star * (radius * held.overlap).sqrt()),
        TIGHT,
    ));
    rows.push(Row::relative(
        TEST,
        "no-slip law, engine run at δ = 20 µm: growth of ξ over the imposed u Δt [-]",
        1.0,
        held.displacement_ratio,
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
