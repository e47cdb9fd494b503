//! J1 — a JKR contact pressed and pulled apart quasi-statically: its force–overlap curve, its
//! pull-off force, the overlap where it breaks and the energy of the loop (Johnson, Kendall &
//! Roberts 1971; Johnson 1985, *Contact Mechanics* §5.5; docs/physics.md §2.4, §9).
//!
//! Set-up (`adhesion::pressed`): a held sphere (R = 0.5 mm, E = 10⁸ Pa, ν = 0.3) and a rigid
//! plane, work of adhesion w = 0.1 J/m², no friction, e = 1. The plane starts |δ_c|/2 from
//! the sphere, moves in at a constant speed to an overlap of 4|δ_c|, and pulls away until the
//! overlap is 1.5 δ_c, Δδ = |δ_c|/N per step (N = 20 000; 2000 fast).
//!
//! Expected, from the closed forms written out here (E* = E/(1−ν²), R* = R):
//! δ(a) = a²/R* − √(2πwa/E*), F(a) = 4E*a³/(3R*) − √(8πwE*a³), F_c = (3/2)πwR*,
//! δ_c = −(3/4)(π²w²R*/E*²)^{1/3}:
//! - the force at each bonded sample on the curve, a found from δ by bisection (not the
//!   engine's Newton iteration);
//! - no force while loading across the gap (the contact forms on touching);
//! - the least force while unloading −F_c;
//! - the break at δ_c;
//! - the loop's energy ∮F dδ = ∫_{δ_c}^{0} (−F) dδ, the closed form of the area under the
//!   curve between its breaking and touching radii.
//!
//! Tolerances: the curve to 10⁻⁹ F_c (both sides solve δ(a) = δ to a few ulps; the forces
//! lose about |δ|/(a²/R*) of that in cancellation, far below 10⁻⁹); the least force to
//! 10⁻⁶ F_c (F is stationary there, so sampling costs (Δδ)², about 10⁻⁹ of F_c); the break to
//! one step Δδ; the loop's energy, summed by the trapezoidal rule, to (8/9 + 5/9) F_c Δδ/2 for
//! the two jumps the samples straddle (at touching and at the break) plus one Δδ F_c for the
//! step past the break, 1.25 F_c Δδ in all.

use std::f64::consts::PI;

use dem::Cohesion;

use crate::adhesion::{plane_modulus, pressed, JkrReference, RADIUS};
use crate::{Resolution, Row, VerifyError};

const TEST: &str = "J1";

/// Work of adhesion w [J/m²].
const WORK: f64 = 0.1;

/// Overlap δ(a) [m] of contact radius `a` [m].
fn overlap_of(e: f64, r: f64, a: f64) -> f64 {
    a * a / r - (2.0 * PI * WORK * a / e).sqrt()
}

/// Force F(a) [N] of contact radius `a` [m].
fn force_of(e: f64, r: f64, a: f64) -> f64 {
    4.0 * e * a.powi(3) / (3.0 * r) - (8.0 * PI * WORK * e * a.powi(3)).sqrt()
}

/// The contact radius of overlap `d` on the branch that holds the contact, by bisection
/// between the breaking radius (where δ is least) and a radius whose δ exceeds `d`.
fn radius_of(e: f64, r: f64, d: f64) -> f64 {
    let mut lo = (PI * WORK * r * r / (8.0 * e)).cbrt();
    let mut hi = lo;
    while overlap_of(e, r, hi) < d {
        hi *= 2.0;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if overlap_of(e, r, mid) < d {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Runs J1.
pub fn run(resolution: Resolution) -> Result<Vec<Row>, VerifyError> {
    let (e, r) = (plane_modulus(), RADIUS);
    let reference = JkrReference::new(e, r, WORK);
    let (fc, dc) = (reference.pull_off, reference.breaking_overlap);
    let n = match resolution {
        Resolution::Full => 20_000.0,
        Resolution::Fast => 2_000.0,
    };
    let step = dc.abs() / n;
    let dt = 1e-7;
    let samples = pressed(
        Cohesion::Jkr {
            work_of_adhesion: WORK,
        },
        (0.5 * dc, 4.0 * dc.abs(), 1.5 * dc),
        step / dt,
        dt,
    )?;

    let mut curve = 0.0f64;
    let mut loading_gap = 0.0f64;
    let mut least = f64::INFINITY;
    let mut last_bonded = f64::NAN;
    let mut work = 0.0;
    let mut previous: Option<(f64, f64)> = None;
    for s in &samples {
        if let Some((d0, f0)) = previous {
            work += 0.5 * (f0 + s.force) * (s.overlap - d0);
        }
        previous = Some((s.overlap, s.force));
        let bonded = s.overlap > 0.0 || (s.unloading && s.force != 0.0);
        if !s.unloading && s.overlap <= 0.0 {
            loading_gap = loading_gap.max(s.force.abs());
        }
        if bonded {
            let expected = force_of(e, r, radius_of(e, r, s.overlap));
            curve = curve.max((s.force - expected).abs() / fc);
        }
        if s.unloading {
            least = least.min(s.force);
            if s.force != 0.0 {
                last_bonded = s.overlap;
            }
        }
    }
    let loop_energy = reference.loop_energy;

    Ok(vec![
        Row::bounded(
            TEST,
            "largest |F − F_JKR(δ)|/F_c over the bonded samples [-]",
            curve,
            1e-9,
        ),
        Row::absolute(
            TEST,
            "largest |F| while loading across the gap [N]",
            0.0,
            loading_gap,
            0.0,
        ),
        Row::absolute(
            TEST,
            "least force while unloading / F_c [-]",
            -1.0,
            least / fc,
            1e-6,
        ),
        Row::absolute(
            TEST,
            "overlap of the last bonded sample / |δ_c| [-]",
            -1.0,
            last_bonded / dc.abs(),
            1.0 / n,
        ),
        Row::absolute(
            TEST,
            "energy of one loading–unloading cycle ∮F dδ [J]",
            loop_energy,
            work,
            1.25 * fc * step,
        ),
    ])
}
