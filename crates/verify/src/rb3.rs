//! RB3 — mass properties of clumps against closed forms (docs/physics.md §11.2, §9).
//!
//! Shapes, of glass beads (R = 1 mm, ρ = 2500 kg/m³; m the mass of one bead):
//! - one bead: V = 4πR³/3 and I = (2/5) m R² about every axis;
//! - a dumbbell of two touching beads along an oblique axis: I = 2 (2/5) m R² about the axis,
//!   2 ((2/5) m R² + m R²) across it (parallel axes);
//! - two beads overlapping, centres R apart: V = 2 (4πR³/3) − π(4R + s)(2R − s)²/12 with
//!   s = R (the lens of two equal spheres);
//! - a rod of eleven beads 0.2 R apart along an oblique axis, where up to eleven members
//!   overlap at a point: volume and the moments about and across its axis against the integral
//!   of its profile ([`crate::profile`]), a solid of revolution integrated in closed form.
//!
//! Tolerances: round-off (10⁻¹² relative) where no three beads overlap, as the engine's sums
//! of balls and lenses are closed forms too; 10⁻⁵ relative on the rod, the accuracy the
//! engine states for its integral of the triple overlaps (docs/physics.md §11.2).

use std::f64::consts::PI;

use dem::clump::{ClumpBody, ClumpShape};
use dem::DVec3;

use crate::profile::collinear_moments;
use crate::{Resolution, Row, VerifyError};

const TEST: &str = "RB3";
const R: f64 = 0.001;
const DENSITY: f64 = 2500.0;
const ROUND_OFF: f64 = 1e-12;

fn body(members: Vec<(DVec3, f64)>) -> Result<ClumpBody, VerifyError> {
    let shape = ClumpShape::new(members).map_err(|e| VerifyError::Measurement {
        what: "a clump of RB3",
        reason: e.to_string(),
    })?;
    Ok(shape.body(DENSITY))
}

/// Runs RB3 (the same at every resolution).
pub fn run(_resolution: Resolution) -> Result<Vec<Row>, VerifyError> {
    let bead_volume = 4.0 * PI * R.powi(3) / 3.0;
    let m = DENSITY * bead_volume;
    let axis = DVec3::new(0.2, -0.7, 0.4).normalize();
    let mut rows = Vec::new();

    let one = body(vec![(DVec3::new(0.3, 0.2, 0.1), R)])?;
    rows.push(Row::relative(
        TEST,
        "one bead: volume [m³]",
        bead_volume,
        one.volume,
        ROUND_OFF,
    ));
    rows.push(Row::relative(
        TEST,
        "one bead: largest principal moment [kg m²]",
        0.4 * m * R * R,
        one.principal_inertia.z,
        ROUND_OFF,
    ));

    let dumbbell = body(vec![(axis * R, R), (-axis * R, R)])?;
    rows.push(Row::relative(
        TEST,
        "touching dumbbell: moment about its axis [kg m²]",
        2.0 * 0.4 * m * R * R,
        dumbbell.principal_inertia.x,
        ROUND_OFF,
    ));
    rows.push(Row::relative(
        TEST,
        "touching dumbbell: moment across its axis [kg m²]",
        2.0 * (0.4 * m * R * R + m * R * R),
        dumbbell.principal_inertia.z,
        ROUND_OFF,
    ));

    let s = R;
    let overlapping = body(vec![(DVec3::ZERO, R), (axis * s, R)])?;
    let lens = PI * (4.0 * R + s) * (2.0 * R - s).powi(2) / 12.0;
    rows.push(Row::relative(
        TEST,
        "two beads R apart: volume less their lens [m³]",
        2.0 * bead_volume - lens,
        overlapping.volume,
        ROUND_OFF,
    ));

    let beads: Vec<(f64, f64)> = (0..11).map(|k| (k as f64 * 0.2 * R, R)).collect();
    let [v, m1, m2, p] = collinear_moments(&beads);
    let about = DENSITY * p;
    let across = DENSITY * ((m2 - m1 * m1 / v) + p / 2.0);
    let rod = body(beads.iter().map(|&(z, r)| (axis * z, r)).collect())?;
    rows.push(Row::relative(
        TEST,
        "rod of 11 beads 0.2 R apart: volume [m³]",
        v,
        rod.volume,
        1e-5,
    ));
    rows.push(Row::relative(
        TEST,
        "rod of 11 beads 0.2 R apart: moment about its axis [kg m²]",
        about,
        rod.principal_inertia.x,
        1e-5,
    ));
    rows.push(Row::relative(
        TEST,
        "rod of 11 beads 0.2 R apart: moment across its axis [kg m²]",
        across,
        rod.principal_inertia.z,
        1e-5,
    ));
    Ok(rows)
}
