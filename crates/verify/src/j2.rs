//! J2 — low-speed impacts of two JKR spheres: they stick below the sticking velocity and
//! part above it with the energy of the JKR loop taken (docs/physics.md §2.4, §9).
//!
//! Set-up (`adhesion::meeting`): two free spheres (R = 0.5 mm, E = 10⁸ Pa, ν = 0.3,
//! ρ = 2500 kg/m³) head-on, w = 0.1 J/m², no friction, e = 1, no gravity; the pair starts
//! |δ_c|/10 apart. Δt such that v_s Δt = |δ_c|/N (N = 4000; 1000 fast).
//!
//! Expected: with no damping, the contact is elastic along the JKR curve and loses only the
//! loop's energy W = ∫_{δ_c}^{0} (−F) dδ (J1's closed form, for E* = E/(2(1−ν²)) and
//! R* = R/2). Energy balance (Thornton & Ning 1998, Powder Technol. 99, 154, applied to the
//! JKR curve itself) gives the sticking velocity v_s = √(2W/m*) and, above it, the parting
//! speed √(v² − v_s²). So:
//! - at v = 0.9 v_s the spheres are still bonded after 20 oscillation periods of the bonded
//!   pair;
//! - at v = 1.1 v_s they part;
//! - at v = 2 v_s they part at √3 v_s: the sticking velocity measured as √(v² − v'²) is v_s.
//!
//! Tolerances. The force jumps by 8/9 F_c when the surfaces touch and by 5/9 F_c when the
//! bond breaks; velocity Verlet meets each jump between two steps and errs by at most the
//! jump times the distance of one step. At 2 v_s that is (8/9) F_c (2 v_s Δt) +
//! (5/9) F_c (√3 v_s Δt) ≤ 2.74 F_c |δ_c|/N in energy, while the smooth parts of the curve
//! err by O(Δt²). The closed forms give W = 0.9355 F_c |δ_c| for any material, so the
//! energy error is at most 2.9/N of W, and ½m*(v² − v'²) = ½m* v_s² (1 ± 2.9/N): the
//! measured v_s is within 1.5/N and v'/v_s within 2.9/(2√3 N) = 0.84/N. The rows allow twice
//! that, 3/N and 2/N, for the O(Δt²) rest. At 0.9 and 1.1 v_s the margin, 19 % of the
//! energy, is far above the error.

use std::f64::consts::PI;

use dem::Cohesion;

use crate::adhesion::{meeting, pair_mass, pair_modulus, JkrReference, RADIUS};
use crate::{Resolution, Row, VerifyError};

const TEST: &str = "J2";

/// Work of adhesion w [J/m²].
const WORK: f64 = 0.1;

/// Runs J2.
pub fn run(resolution: Resolution) -> Result<Vec<Row>, VerifyError> {
    let (e, r, m) = (pair_modulus(), 0.5 * RADIUS, pair_mass());
    // The loop's energy, the closed form of J1 for this pair.
    let reference = JkrReference::new(e, r, WORK);
    let (fc, dc) = (reference.pull_off, reference.breaking_overlap);
    let v_s = (2.0 * reference.loop_energy / m).sqrt();

    let n = match resolution {
        Resolution::Full => 4000.0,
        Resolution::Fast => 1000.0,
    };
    let dt = dc.abs() / (n * v_s);
    // A bonded pair oscillates in its well with a period of order √(m* |δ_c| / F_c); 20 of
    // those, over the steps each takes, bound the watch for a pair that stays.
    let period = (m * dc.abs() / fc).sqrt();
    let steps = (20.0 * 2.0 * PI * period / dt) as u64;
    let cohesion = Cohesion::Jkr {
        work_of_adhesion: WORK,
    };
    let gap = 0.1 * dc.abs();
    let apart = 1.01 * dc.abs();
    let slow = meeting(cohesion, 0.9 * v_s, (gap, apart), dt, steps)?;
    let above = meeting(cohesion, 1.1 * v_s, (gap, apart), dt, steps)?;
    let fast = meeting(cohesion, 2.0 * v_s, (gap, apart), dt, steps)?;
    let measured = ((2.0 * v_s).powi(2) - fast.separation_speed.powi(2)).sqrt();
    let flag = |b: bool| if b { 1.0 } else { 0.0 };
    Ok(vec![
        Row::absolute(
            TEST,
            "at 0.9 v_s the spheres part (1) or stick (0) [-]",
            0.0,
            flag(slow.parted),
            0.0,
        ),
        Row::absolute(
            TEST,
            "at 1.1 v_s the spheres part (1) or stick (0) [-]",
            1.0,
            flag(above.parted),
            0.0,
        ),
        Row::absolute(
            TEST,
            "at 2 v_s: the parting speed is √3 v_s, as a multiple of v_s [-]",
            3f64.sqrt(),
            fast.separation_speed / v_s,
            2.0 / n,
        ),
        Row::relative(
            TEST,
            format!("sticking velocity √(v² − v'²) at 2 v_s, v_s = {v_s:.4e} [m/s]"),
            v_s,
            measured,
            3.0 / n,
        ),
    ])
}
