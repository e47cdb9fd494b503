//! RB2 — the torque-free symmetric top: its spin axis precesses at the closed-form rates
//! (docs/physics.md §11.3, §9).
//!
//! Set-up: the dumbbell of two touching glass beads (R = 1 mm, ρ = 2500 kg/m³), whose
//! principal moments the engine computes: I_a about its axis (body x), I_b across it. Body-frame
//! ω = (200, 50, 0) rad/s; Δt = 1 µs (Fast: 2 µs), for 0.05 s.
//!
//! Expected (Goldstein, *Classical Mechanics*, §5.6): ω_x stays constant; in the body frame the
//! transverse ω (ω_y, ω_z) turns about the axis at Ω = (I_a − I_b) ω_x / I_b; in the world
//! frame the axis turns about the constant L at |L|/I_b. The rates are measured as the
//! unwrapped angle turned over the run, over its duration.
//!
//! Tolerances: the midpoint rule's phase error is of order (|ω| Δt)²/12, 10⁻⁸ here at Δt = 2 µs;
//! the rows allow 10⁻⁷ relative on both rates. ω_x must stay constant to round-off of the
//! steps (10 ε √N relative, as RB1's energy).

use dem::clump::rotation::{angular_velocity, free_rotation};
use dem::clump::ClumpShape;
use dem::{DQuat, DVec3};

use crate::{Resolution, Row, VerifyError};

const TEST: &str = "RB2";

/// Runs RB2.
pub fn run(resolution: Resolution) -> Result<Vec<Row>, VerifyError> {
    let r = 0.001;
    let shape = ClumpShape::new(vec![
        (DVec3::new(-r, 0.0, 0.0), r),
        (DVec3::new(r, 0.0, 0.0), r),
    ])
    .map_err(|e| VerifyError::Measurement {
        what: "the dumbbell",
        reason: e.to_string(),
    })?;
    let inertia = shape.body(2500.0).principal_inertia;
    let (ia, ib) = (inertia.x, inertia.y);
    let spin = DVec3::new(200.0, 50.0, 0.0);
    let body_rate = (ia - ib) * spin.x / ib;

    let dt = match resolution {
        Resolution::Full => 1e-6,
        Resolution::Fast => 2e-6,
    };
    let steps = (0.05f64 / dt).round() as u64;
    let mut q = DQuat::from_axis_angle(DVec3::new(0.4, 0.1, -1.0).normalize(), 2.1);
    let l = q * (inertia * spin);
    let world_rate = l.length() / ib;
    let across = |v: DVec3| {
        // The axis's direction in the plane normal to L, as an angle about L.
        let n = l.normalize();
        let e1 = n.any_orthonormal_vector();
        let e2 = n.cross(e1);
        let p = v - n * v.dot(n);
        p.dot(e2).atan2(p.dot(e1))
    };
    let (mut body_angle, mut world_angle) = (0.0f64, 0.0f64);
    let mut last_body = spin.z.atan2(spin.y);
    let mut last_world = across(q * DVec3::X);
    let mut worst_spin = 0.0f64;
    let unwrap = |from: f64, to: f64| {
        let mut d = to - from;
        d -= (d / std::f64::consts::TAU).round() * std::f64::consts::TAU;
        d
    };
    for _ in 0..steps {
        q = free_rotation(q, l, inertia, dt);
        let w = q.inverse() * angular_velocity(q, l, inertia);
        worst_spin = worst_spin.max(((w.x - spin.x) / spin.x).abs());
        let b = w.z.atan2(w.y);
        body_angle += unwrap(last_body, b);
        last_body = b;
        let a = across(q * DVec3::X);
        world_angle += unwrap(last_world, a);
        last_world = a;
    }
    let t = steps as f64 * dt;
    Ok(vec![
        Row::bounded(
            TEST,
            "largest relative change of the spin ω_x about the axis [-]",
            worst_spin,
            10.0 * f64::EPSILON * (steps as f64).sqrt(),
        ),
        Row::relative(
            TEST,
            "body-frame precession rate (I_a − I_b) ω_x / I_b [rad/s]",
            body_rate,
            body_angle / t,
            1e-7,
        ),
        Row::relative(
            TEST,
            "world precession rate of the axis about L, |L|/I_b [rad/s]",
            world_rate,
            world_angle.abs() / t,
            1e-7,
        ),
    ])
}
