//! RB4 — a clump on an incline slides or tips at the analytic angle, whichever comes first
//! (docs/physics.md §11.4, §9).
//!
//! Set-up: a "stool" clump of six beads (R = 1.5 mm): four feet at (±a, ±a, 0) with
//! a = 1.5R and a column of two touching beads at (0, 0, 2R) and (0, 0, 4R) on the feet, so
//! a/h = 0.75 (the engine's h = 2R) and the stool tips at 36.9°; of a stiff material (E = 10¹⁰ Pa, ν = 0.25,
//! ρ = 2500 kg/m³, so that its overlap at rest, under 2 µm, leaves its height as built),
//! no rolling friction, e = 0.5, standing on a plane. The incline is made by turning gravity
//! by θ about y: the clump stands still at first, then is watched for 0.05 s (0.1 s where it
//! should tip) at Δt = 0.25 µs.
//!
//! Expected (statics of a rigid body on an incline): with its centre of mass at height h
//! above the plane and the downhill feet's contacts a horizontal distance a from it (in the
//! incline's frame), the clump tips over its downhill edge once tan θ > a/h, and slides once
//! tan θ > μ, whichever is lower; sliding, it accelerates at g(sin θ − μ cos θ). h = R + z_c,
//! z_c the centre of mass above the feet's centres, computed by the engine's union of beads.
//! - μ = 0.3 < a/h: held at θ_s − 2°, with θ_s = atan μ (displacement under 10⁻⁶ m, A1's
//!   creep bound); sliding at θ_s + 2° at g(sin θ − μ cos θ) (1 %: the start of the slide,
//!   from rest through the tangential spring, is fitted out by timing from 0.01 s), without
//!   turning (under 10⁻³ rad);
//! - μ = 1.0 > a/h: held at θ_t − 2°, θ_t = atan(a/h) (turned by under 10⁻³ rad), and tipping
//!   at θ_t + 2°: turned by more than 0.1 rad in 0.1 s. Pivoting on its downhill edge, at a
//!   distance L = √(a² + h²) from the centre of mass, it turns as φ ≈ sin 2° (cosh kt − 1) with
//!   k² = M g L / I_edge, I_edge = I + M L²: k ≈ 40 /s here (L = 3.75 mm), so φ passes
//!   0.1 rad by about 0.06 s and the row's 0.1 s leaves room for the start from rest on Hertz
//!   springs. μ = 1 keeps it from sliding first: atan 1 = 45° against the 38.9° it is tilted to.

use dem::clump::ClumpShape;
use dem::{
    DQuat, DVec3, Interaction, Material, RollingLaw, Simulation, SimulationConfig, Wall,
    WallMaterial,
};

use crate::{Resolution, Row, VerifyError};

const TEST: &str = "RB4";
const R: f64 = 1.5e-3;
const DT: f64 = 2.5e-7;
const GRAVITY: f64 = 9.81;
/// The feet's distance from the axis, along x and y [m].
const FOOT: f64 = 1.5 * R;

/// The stool's members.
fn stool() -> Result<ClumpShape, VerifyError> {
    let a = FOOT;
    let mut members: Vec<(DVec3, f64)> = [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)]
        .iter()
        .map(|&(x, y)| (DVec3::new(x * a, y * a, 0.0), R))
        .collect();
    members.push((DVec3::new(0.0, 0.0, 2.0 * R), R));
    members.push((DVec3::new(0.0, 0.0, 4.0 * R), R));
    ClumpShape::new(members).map_err(|e| VerifyError::Measurement {
        what: "the stool clump",
        reason: e.to_string(),
    })
}

/// The height h [m] of the stool's centre of mass over the plane its feet stand on, and the
/// horizontal distance a [m] from it to the downhill feet.
pub fn stool_lever() -> Result<(f64, f64), VerifyError> {
    let shape = stool()?;
    let body = shape.body(2500.0);
    Ok((R + body.centre.z, FOOT))
}

/// What the stool did in `duration` [s] on an incline of `angle` [rad] with friction `friction`:
/// its displacement along the slope [m] at 0.01 s and at the end, and the largest angle
/// it turned by [rad].
struct Watch {
    early: f64,
    end: f64,
    turned: f64,
}

fn watch(angle: f64, friction: f64, duration: f64) -> Result<Watch, VerifyError> {
    let material = Material::from_shear_modulus(2500.0, 1e10 / 2.5, 0.25);
    let interaction = Interaction {
        friction,
        rolling_friction: 0.0,
        restitution: 0.5,
        ..Interaction::fan2023()
    };
    let mut config = SimulationConfig::new(DT);
    config.gravity = DVec3::new(-GRAVITY * angle.sin(), 0.0, -GRAVITY * angle.cos());
    config.laws.rolling = RollingLaw::None;
    let mut sim = Simulation::new(config)?;
    let id = sim.add_material(material, interaction)?;
    sim.add_wall(Wall::plane(
        DVec3::ZERO,
        DVec3::Z,
        WallMaterial::Elastic(material),
        interaction,
    )?)?;
    let shape = stool()?;
    let body = shape.body(material.density);
    // Feet just touching: their centres at R over the plane.
    let start = DVec3::new(0.0, 0.0, R + body.centre.z);
    sim.add_clump(
        &shape,
        id,
        (start, DQuat::IDENTITY),
        (DVec3::ZERO, DVec3::ZERO),
    )?;
    let q0 = sim.clumps().orientations()[0];
    let (mut early, mut turned) = (0.0, 0.0f64);
    let steps = (duration / DT).round() as u64;
    let early_step = (0.01 / DT).round() as u64;
    for step in 1..=steps {
        sim.step()?;
        let q = sim.clumps().orientations()[0];
        turned = turned.max((q0.inverse() * q).to_axis_angle().1.abs());
        if step == early_step {
            early = sim.clumps().positions()[0].x - start.x;
        }
    }
    let end = sim.clumps().positions()[0].x - start.x;
    Ok(Watch { early, end, turned })
}

/// Runs RB4 (the same at every resolution).
pub fn run(_resolution: Resolution) -> Result<Vec<Row>, VerifyError> {
    let (h, a) = stool_lever()?;
    let two = 2f64.to_radians();
    let mut rows = Vec::new();

    let mu: f64 = 0.3;
    let slide = mu.atan();
    let held = watch(slide - two, mu, 0.05)?;
    rows.push(Row::bounded(
        TEST,
        format!("μ = {mu}, 2° below atan μ: displacement along the slope [m]"),
        held.end.abs(),
        1e-6,
    ));
    let theta = slide + two;
    let sliding = watch(theta, mu, 0.05)?;
    // From 0.01 s on, x = x₁ + v₁ t + a t²/2: with the three-point form over 0.01 and 0.05 s
    // and the start, the acceleration from the end displacement less the early one's share.
    let want = GRAVITY * (theta.sin() - mu * theta.cos());
    let (t1, t2) = (0.01, 0.05);
    // Constant acceleration from rest after a short transient: x(t) ≈ a (t − t₀)²/2; two
    // readings give both a and t₀.
    let (s1, s2) = (sliding.early.abs().sqrt(), sliding.end.abs().sqrt());
    let t0 = (s2 * t1 - s1 * t2) / (s2 - s1);
    let measured = 2.0 * sliding.end.abs() / (t2 - t0).powi(2);
    rows.push(Row::relative(
        TEST,
        format!("μ = {mu}, 2° above atan μ: acceleration down the slope [m/s²]"),
        want,
        measured,
        0.01,
    ));
    rows.push(Row::bounded(
        TEST,
        format!("μ = {mu}, 2° above atan μ: largest turn while sliding [rad]"),
        sliding.turned,
        1e-3,
    ));

    let mu = 1.0;
    let tip = (a / h).atan();
    let standing = watch(tip - two, mu, 0.05)?;
    rows.push(Row::bounded(
        TEST,
        format!(
            "μ = {mu}, 2° below atan(a/h) = {:.2}°: largest turn [rad]",
            tip.to_degrees()
        ),
        standing.turned,
        1e-3,
    ));
    let tipping = watch(tip + two, mu, 0.1)?;
    rows.push(Row::absolute(
        TEST,
        format!("μ = {mu}, 2° above atan(a/h): turned > 0.1 rad in 0.1 s (1) or not (0) [-]"),
        1.0,
        if tipping.turned > 0.1 { 1.0 } else { 0.0 },
        0.0,
    ));
    Ok(rows)
}
