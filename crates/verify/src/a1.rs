//! A1 — block sliding with rotation locked (docs/physics.md §9).
//!
//! Set-up: a Table-1 sphere (d = 3 mm) on a same-material plane with its rotation locked,
//! launched at v0 = 0.5 m/s, μ = 0.5, e = 0.2, gravity on, Δt = 2.5 µs. Then the same block at
//! rest on inclines of 20° (tan θ < μ) and 35° (tan θ > μ).
//!
//! Expected (Coulomb friction on a block): v(t) = v0 − μ g t, so it stops at t = v0/(μg) =
//! 0.1019 s after s = v0²/(2μg) = 25.48 mm, and then stays: the truncated tangential spring
//! relaxes by only μ m g/S_t ≈ 0.05 µm and must not drift. On an incline it stays put for
//! tan θ ≤ μ (26.57°) and otherwise slides with a = g(sin θ − μ cos θ).
//!
//! Tolerance (docs/physics.md §9): 1 % on the stop time, distance and incline acceleration;
//! residual creep < 1e-6 m over the observation window after stopping (and on the 20° incline).
//! Fast observes the creep for 0.05 s, Full for 0.5 s.

use dem::{ContactLaws, Interaction, FLAG_ROTATION_LOCKED};

use crate::surface::{probe, run_until, Surface, GRAVITY, TIME_STEP};
use crate::{Resolution, Row, VerifyError};

const TEST: &str = "A1";
const FRICTION: f64 = 0.5;

fn block(incline_deg: f64, speed: f64) -> Surface {
    Surface {
        incline: incline_deg.to_radians(),
        interaction: Interaction {
            friction: FRICTION,
            rolling_friction: 0.0,
            restitution: 0.2,
            cohesion: dem::Cohesion::None,
        },
        laws: ContactLaws::default(),
        speed,
        flags: FLAG_ROTATION_LOCKED,
    }
}

/// Runs A1.
pub fn run(resolution: Resolution) -> Result<Vec<Row>, VerifyError> {
    let window = match resolution {
        Resolution::Full => 0.5,
        Resolution::Fast => 0.05,
    };
    let window_steps = (window / TIME_STEP) as u64;
    let v0 = 0.5;
    let mut rows = Vec::new();

    // Horizontal slide to rest; the stop instant is interpolated where v_x crosses zero.
    let mut sim = block(0.0, v0).build()?;
    let mut last = (0.0, v0);
    let mut stop = (0.0, 0.0);
    run_until(
        &mut sim,
        (1.0 / TIME_STEP) as u64,
        "stop of the sliding block",
        |s| {
            let (x, v, _, _) = probe(s);
            if v <= 0.0 {
                let f = last.1 / (last.1 - v);
                stop = (s.time() - TIME_STEP * (1.0 - f), last.0 + f * (x - last.0));
                return true;
            }
            last = (x, v);
            false
        },
    )?;
    rows.push(Row::relative(
        TEST,
        "stop time, v0 = 0.5 m/s [s]",
        v0 / (FRICTION * GRAVITY),
        stop.0,
        0.01,
    ));
    rows.push(Row::relative(
        TEST,
        "sliding distance, v0 = 0.5 m/s [m]",
        v0 * v0 / (2.0 * FRICTION * GRAVITY),
        stop.1,
        0.01,
    ));
    let mut creep: f64 = 0.0;
    for _ in 0..window_steps {
        sim.step()?;
        creep = creep.max((probe(&sim).0 - stop.1).abs());
    }
    rows.push(Row::bounded(
        TEST,
        format!("largest displacement in {window} s after stopping [m]"),
        creep,
        1e-6,
    ));

    // At rest on a 20° incline: tan 20° = 0.364 < μ, so the spring must hold it.
    let mut sim = block(20.0, 0.0).build()?;
    let x0 = probe(&sim).0;
    let mut creep: f64 = 0.0;
    for _ in 0..window_steps {
        sim.step()?;
        creep = creep.max((probe(&sim).0 - x0).abs());
    }
    rows.push(Row::bounded(
        TEST,
        format!("20° incline: largest displacement in {window} s [m]"),
        creep,
        1e-6,
    ));

    // Sliding down 35°: acceleration from the velocity change over [0.01, 0.05] s.
    let theta = 35.0_f64.to_radians();
    let mut sim = block(35.0, 0.0).build()?;
    sim.run((0.01 / TIME_STEP) as u64)?;
    let (t1, v1) = (sim.time(), probe(&sim).1);
    sim.run((0.04 / TIME_STEP) as u64)?;
    let (t2, v2) = (sim.time(), probe(&sim).1);
    let expected = GRAVITY * (theta.sin() - FRICTION * theta.cos());
    rows.push(Row::relative(
        TEST,
        "35° incline: sliding acceleration [m/s²]",
        expected,
        (v2 - v1) / (t2 - t1),
        0.01,
    ));
    Ok(rows)
}
