//! A3 — a sphere released on an incline: rolling and slipping accelerations, the roll/slip
//! threshold, and behaviour at rest (docs/physics.md §4.2, §9).
//!
//! Set-up: a Table-1 sphere (d = 3 mm) released at rest on a same-material plane tilted by θ
//! (gravity tilted, see `surface`), μ = 0.5, μ_r = 0.01, e = 0.2, Δt = 2.5 µs, constant
//! directional torque (paper Eq. 8) unless stated.
//!
//! Expected (rigid-body mechanics, I = 2/5 m R²):
//! - rolling without slip while tan θ ≤ 3.5 μ − 2.5 μ_r, i.e. θ ≤ 59.90°, with
//!   a = (5/7) g (sin θ − μ_r cos θ) (checked at 30°);
//! - above it, slipping with a = g (sin θ − μ cos θ) and angular acceleration
//!   5 (μ − μ_r) g cos θ/(2R) (checked at 70°);
//! - the threshold itself, found by bisection on θ ∈ [55°, 65°]: an angle counts as slipping when
//!   the contact-point slip speed still grows by more than 1e-5 m/s between 25 and 50 ms after
//!   release (above the threshold by Δθ it grows by ≈ 0.49 Δθ[rad] m/s over that interval, below
//!   it the tangential spring holds it at ≈ 0 once the release transient has decayed);
//! - at rest with tan θ < μ_r (θ = 0.3°): EPSD (η_r = 0.3) holds the sphere still; CDT cannot
//!   hold a static rolling equilibrium and chatters with |Δω| ≈ μ_r R F_n Δt/I (§4.2).
//!
//! Tolerance (docs/physics.md §9): 1 % on accelerations; threshold within ±0.5° (bisection resolves
//! it to 0.04°, Fast to 0.16°); EPSD: displacement < 1e-3 d over the observation window after a
//! 0.1 s settling period in which the springs take up the load (their elastic set-up alone is
//! ≈ 1e-3 d at this angle); CDT: docs/physics.md §9 asks to record the creep, not to match it. Here
//! it is bounded by 1 % of the distance a sphere without rolling resistance would roll in the
//! same window, ½ a_free ((t_s + w)² − t_s²) with a_free = (5/7) g sin θ, t_s = 0.1 s settling
//! and w the window: 1.47 mm at Fast and 22.0 mm at Full, so bounds of 14.7 µm and 220 µm. The
//! bound scales with the window, so the row can fail at either resolution: a sphere that CDT
//! does not hold rolls 100 times the bound, and a torque too weak to hold it (an effective μ_r'
//! below tan θ = 0.0052, e.g. half the lever) rolls the fraction 1 − μ_r'/tan θ of the free
//! distance. The chatter lets the held sphere creep at ≈ 0.3 µm/s, 0.07 µm at Fast (0.5 % of
//! the bound). The spin chatter is held below 2 |Δω|.
//! The observation window is 1 s at Full and 0.2 s at Fast.

use dem::{ContactLaws, Interaction, RollingLaw};

use crate::surface::{probe, Surface, GRAVITY, RADIUS, TIME_STEP};
use crate::{Resolution, Row, VerifyError};

const TEST: &str = "A3";
const FRICTION: f64 = 0.5;
const ROLLING_FRICTION: f64 = 0.01;

fn sphere(theta_deg: f64, rolling: RollingLaw) -> Surface {
    Surface {
        incline: theta_deg.to_radians(),
        interaction: Interaction {
            friction: FRICTION,
            rolling_friction: ROLLING_FRICTION,
            restitution: 0.2,
            cohesion: dem::Cohesion::None,
        },
        laws: ContactLaws {
            rolling,
            ..ContactLaws::default()
        },
        speed: 0.0,
        flags: 0,
    }
}

const CDT: RollingLaw = RollingLaw::ConstantTorque { limiter: false };

/// Steps in `seconds` [s] of simulated time.
fn steps(seconds: f64) -> u64 {
    (seconds / TIME_STEP).round() as u64
}

/// Linear and angular accelerations [m/s², rad/s²] over [0.01, 0.05] s after release at `theta_deg`.
fn accelerations(theta_deg: f64) -> Result<(f64, f64), VerifyError> {
    let mut sim = sphere(theta_deg, CDT).build()?;
    sim.run(steps(0.01))?;
    let (t1, (_, v1, w1, _)) = (sim.time(), probe(&sim));
    sim.run(steps(0.04))?;
    let (t2, (_, v2, w2, _)) = (sim.time(), probe(&sim));
    Ok(((v2 - v1) / (t2 - t1), (w2 - w1) / (t2 - t1)))
}

/// Whether the sphere is still slipping 25–50 ms after release at `theta_deg`.
fn slips(theta_deg: f64) -> Result<bool, VerifyError> {
    let mut sim = sphere(theta_deg, CDT).build()?;
    sim.run(steps(0.025))?;
    let early = probe(&sim).3;
    sim.run(steps(0.025))?;
    Ok(probe(&sim).3 - early > 1e-5)
}

/// Settling period before the rest behaviour is observed [s].
const SETTLING: f64 = 0.1;

/// Distance [m] a sphere without rolling resistance rolls down `theta_deg` in `window` [s]
/// after the settling period, both from rest at release: a = (5/7) g sin θ, so
/// s = ½ a ((t_s + w)² − t_s²).
fn free_rolling_distance(theta_deg: f64, window: f64) -> f64 {
    let a = 5.0 / 7.0 * GRAVITY * theta_deg.to_radians().sin();
    0.5 * a * ((SETTLING + window).powi(2) - SETTLING * SETTLING)
}

/// Largest accepted CDT creep at rest over `window` [s]: 1 % of the free-rolling distance.
fn cdt_creep_bound(theta_deg: f64, window: f64) -> f64 {
    0.01 * free_rolling_distance(theta_deg, window)
}

/// Creep [m] over `window` [s] after a 0.1 s settling period, and the largest |ω_y| [rad/s] seen
/// in that window, for a sphere released at `theta_deg`.
fn at_rest(theta_deg: f64, rolling: RollingLaw, window: f64) -> Result<(f64, f64), VerifyError> {
    let mut sim = sphere(theta_deg, rolling).build()?;
    sim.run(steps(SETTLING))?;
    let x0 = probe(&sim).0;
    let (mut creep, mut spin): (f64, f64) = (0.0, 0.0);
    for _ in 0..steps(window) {
        sim.step()?;
        let (x, _, w, _) = probe(&sim);
        creep = creep.max((x - x0).abs());
        spin = spin.max(w.abs());
    }
    Ok((creep, spin))
}

/// Runs A3.
pub fn run(resolution: Resolution) -> Result<Vec<Row>, VerifyError> {
    let (window, bisections) = match resolution {
        Resolution::Full => (1.0, 8),
        Resolution::Fast => (0.2, 6),
    };
    let mut rows = Vec::new();

    let theta = 30.0_f64.to_radians();
    let (a, _) = accelerations(30.0)?;
    let expected = 5.0 / 7.0 * GRAVITY * (theta.sin() - ROLLING_FRICTION * theta.cos());
    rows.push(Row::relative(
        TEST,
        "30° (rolling): acceleration [m/s²]",
        expected,
        a,
        0.01,
    ));

    let theta = 70.0_f64.to_radians();
    let (a, alpha) = accelerations(70.0)?;
    rows.push(Row::relative(
        TEST,
        "70° (slipping): acceleration [m/s²]",
        GRAVITY * (theta.sin() - FRICTION * theta.cos()),
        a,
        0.01,
    ));
    let expected = 5.0 * (FRICTION - ROLLING_FRICTION) * GRAVITY * theta.cos() / (2.0 * RADIUS);
    rows.push(Row::relative(
        TEST,
        "70° (slipping): angular acceleration [rad/s²]",
        expected,
        alpha,
        0.01,
    ));

    let (mut low, mut high) = (55.0, 65.0);
    for _ in 0..bisections {
        let mid = 0.5 * (low + high);
        if slips(mid)? {
            high = mid;
        } else {
            low = mid;
        }
    }
    let threshold = (3.5 * FRICTION - 2.5 * ROLLING_FRICTION)
        .atan()
        .to_degrees();
    rows.push(Row::absolute(
        TEST,
        "roll/slip threshold angle [°]",
        threshold,
        0.5 * (low + high),
        0.5,
    ));

    let diameter = 2.0 * RADIUS;
    let (creep, _) = at_rest(
        0.3,
        RollingLaw::Epsd {
            viscous_damping: 0.3,
        },
        window,
    )?;
    rows.push(Row::bounded(
        TEST,
        format!("0.3°, EPSD: displacement over {window} s at rest [m]"),
        creep,
        1e-3 * diameter,
    ));
    let (creep, spin) = at_rest(0.3, CDT, window)?;
    rows.push(Row::bounded(
        TEST,
        format!("0.3°, CDT: creep over {window} s (bound: 1 % of free rolling) [m]"),
        creep,
        cdt_creep_bound(0.3, window),
    ));
    let mass = 2500.0 * 4.0 / 3.0 * std::f64::consts::PI * RADIUS.powi(3);
    let inertia = 0.4 * mass * RADIUS * RADIUS;
    let chatter =
        ROLLING_FRICTION * RADIUS * mass * GRAVITY * 0.3_f64.to_radians().cos() * TIME_STEP
            / inertia;
    rows.push(Row::bounded(
        TEST,
        format!(
            "0.3°, CDT: largest |ω| at rest (bound 2|Δω| = {:.2e}) [rad/s]",
            2.0 * chatter
        ),
        spin,
        2.0 * chatter,
    ));
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cdt_creep_row_fails_for_a_sphere_without_rolling_resistance() {
        // The bound must be one the row can miss at the fast window: without rolling
        // resistance the sphere rolls the whole free distance, 100 times the bound (the
        // engine's rolling sphere matches ½ a t² to well under 1 %, see the 30° row).
        let window = 0.2;
        let (creep, _) = at_rest(0.3, RollingLaw::None, window).unwrap_or((0.0, 0.0));
        let free = free_rolling_distance(0.3, window);
        assert!((creep / free - 1.0).abs() < 0.01, "{creep} vs {free}");
        assert!(!Row::bounded(TEST, "q", creep, cdt_creep_bound(0.3, window)).pass);
    }
}
