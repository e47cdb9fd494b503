//! RB1 — torque-free rotation of an asymmetric rigid body: energy and angular momentum kept to
//! round-off, and the flips of its unstable middle axis at the closed-form interval
//! (docs/physics.md §11.3, §9).
//!
//! Set-up: the clump of three touching glass beads (R = 1 mm, ρ = 2500 kg/m³) in an L
//! (centres (0, 0, 0), (2R, 0, 0), (0, 2R, 0)), whose principal moments I₁ < I₂ < I₃ the
//! engine computes. It spins at 100 rad/s about its middle axis, slightly off it: in the body
//! frame L = I₂ ω₀ (0.005, 1, 0.02). Δt = 1 µs (Fast: 2 µs), for four and a half flips.
//!
//! Expected (Landau and Lifshitz, *Mechanics*, §37): with M² > 2EI₂, the body-frame
//! ω₂ = B sn(τ, k), τ = t √((I₃ − I₂)(M² − 2EI₁)/(I₁I₂I₃)),
//! k² = (I₂ − I₁)(2EI₃ − M²)/((I₃ − I₂)(M² − 2EI₁)), B = √((2EI₃ − M²)/(I₂(I₃ − I₂))). So ω₂
//! changes sign every 2K(k) in τ (the flip of the middle axis), with K the complete elliptic
//! integral of the first kind (by the arithmetic–geometric mean), and peaks at B. The energy
//! and the world-frame angular momentum are constant.
//!
//! The world angular momentum is the state the step keeps; the row on it checks that the
//! body's turns carry it: L̄ + W × L̄/2, from each step's turn W and L̄ = I W/Δt, turned into
//! the world, must be L.
//!
//! Tolerances. The implicit midpoint rule keeps the energy and L exactly but for round-off
//! (docs/physics.md §11.3). The energy's adds up as a random walk: the row allows 10 ε √N
//! relative over N steps. The turn of one step is read from two unit quaternions rounded to ε,
//! against its size ω Δt/2, so the momentum row allows 100 ε/(ω Δt), 2·10⁻¹⁰ at Δt = 1 µs. The flip interval is the mean of the intervals
//! between the zero crossings of ω₂ (interpolated linearly between steps, where sn is nearly
//! straight); the midpoint rule's phase error is of order (ω Δt)²/12, 10⁻⁹ here, so the rows
//! allow 10⁻⁶ relative on the interval and on the peak (the largest sampled |ω₂|, within
//! (ω₀ Δt)² of the peak).

use dem::clump::rotation::{angular_velocity, free_rotation, rotational_energy};
use dem::clump::ClumpShape;
use dem::{DQuat, DVec3};

use crate::{Resolution, Row, VerifyError};

const TEST: &str = "RB1";

/// The L-shaped clump's principal moments [kg m²], ascending.
pub fn l_clump_inertia() -> Result<DVec3, VerifyError> {
    let r = 0.001;
    let shape = ClumpShape::new(vec![
        (DVec3::ZERO, r),
        (DVec3::new(2.0 * r, 0.0, 0.0), r),
        (DVec3::new(0.0, 2.0 * r, 0.0), r),
    ])
    .map_err(|e| VerifyError::Measurement {
        what: "the L clump",
        reason: e.to_string(),
    })?;
    Ok(shape.body(2500.0).principal_inertia)
}

/// The complete elliptic integral of the first kind K(k) = π/(2 agm(1, √(1 − k²))).
pub fn elliptic_k(k: f64) -> f64 {
    let (mut a, mut b) = (1.0f64, (1.0 - k * k).sqrt());
    for _ in 0..64 {
        if (a - b).abs() <= f64::EPSILON * a {
            break;
        }
        (a, b) = ((a + b) / 2.0, (a * b).sqrt());
    }
    std::f64::consts::PI / (2.0 * a)
}

/// The world angular momentum [kg m²/s] that the turn from `before` to `after` in `dt` [s]
/// carries, for a body of principal moments `inertia` [kg m²]. The turn is a Cayley rotation of
/// W = Δt ω̄ (docs/physics.md §11.3), read from the increment's quaternion as
/// W = 2 (x, y, z)/w; the midpoint momentum L̄ = I W/Δt and L̄ + W × L̄/2 is the body-frame
/// momentum at the start of the step, which the start orientation turns into the world.
pub fn carried_momentum(before: DQuat, after: DQuat, inertia: DVec3, dt: f64) -> DVec3 {
    let turn = before.inverse() * after;
    let w = DVec3::new(turn.x, turn.y, turn.z) * (2.0 / turn.w);
    let mean = inertia * w / dt;
    before * (mean + w.cross(mean) / 2.0)
}

/// Runs RB1.
pub fn run(resolution: Resolution) -> Result<Vec<Row>, VerifyError> {
    let inertia = l_clump_inertia()?;
    let (i1, i2, i3) = (inertia.x, inertia.y, inertia.z);
    let omega = 100.0;
    let body = DVec3::new(0.005, 1.0, 0.02) * (i2 * omega);
    let e = 0.5 * body.dot(body / inertia);
    let m2 = body.length_squared();
    if m2 <= 2.0 * e * i2 {
        return Err(VerifyError::Measurement {
            what: "the RB1 set-up",
            reason: format!("M² = {m2} must exceed 2EI₂ = {}", 2.0 * e * i2),
        });
    }
    let rate = ((i3 - i2) * (m2 - 2.0 * e * i1) / (i1 * i2 * i3)).sqrt();
    let k2 = (i2 - i1) * (2.0 * e * i3 - m2) / ((i3 - i2) * (m2 - 2.0 * e * i1));
    let interval = 2.0 * elliptic_k(k2.sqrt()) / rate;
    let peak = ((2.0 * e * i3 - m2) / (i2 * (i3 - i2))).sqrt();

    let dt = match resolution {
        Resolution::Full => 1e-6,
        Resolution::Fast => 2e-6,
    };
    let steps = (4.5 * interval / dt).ceil() as u64;
    // An arbitrary starting orientation: the world frame plays no part in the closed forms.
    let mut q = DQuat::from_axis_angle(DVec3::new(1.0, -2.0, 0.7).normalize(), 0.9);
    let l = q * body;
    let (mut worst_energy, mut worst_momentum, mut largest) = (0.0f64, 0.0f64, 0.0f64);
    let mut crossings = Vec::new();
    let mut last = body.y;
    for step in 1..=steps {
        let before = q;
        q = free_rotation(q, l, inertia, dt);
        let now = rotational_energy(q, l, inertia);
        worst_energy = worst_energy.max(((now - e) / e).abs());
        let carried = carried_momentum(before, q, inertia, dt);
        worst_momentum = worst_momentum.max((carried - l).length() / l.length());
        let w = q.inverse() * angular_velocity(q, l, inertia);
        largest = largest.max(w.y.abs());
        let y = (q.inverse() * l).y;
        if (y > 0.0) != (last > 0.0) {
            let t = (step - 1) as f64 * dt + dt * last / (last - y);
            crossings.push(t);
        }
        last = y;
    }
    if crossings.len() < 3 {
        return Err(VerifyError::NoEvent {
            what: "three flips of the middle axis",
            steps,
        });
    }
    let measured = (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
    let round_off = 10.0 * f64::EPSILON * (steps as f64).sqrt();
    // The turn of one step is read from two unit quaternions, each rounded to ε, against a
    // vector part of size ω Δt / 2.
    let turn_round_off = 100.0 * f64::EPSILON / (omega * dt);
    Ok(vec![
        Row::bounded(
            TEST,
            "largest relative change of the rotational energy [-]",
            worst_energy,
            round_off,
        ),
        Row::bounded(
            TEST,
            "largest relative change of the world angular momentum the turns carry [-]",
            worst_momentum,
            turn_round_off,
        ),
        Row::relative(
            TEST,
            "interval between flips of the middle axis, 2K(k)/rate [s]",
            interval,
            measured,
            1e-6,
        ),
        Row::relative(
            TEST,
            "peak of the middle-axis ω₂ [rad/s]",
            peak,
            largest,
            1e-6,
        ),
    ])
}
