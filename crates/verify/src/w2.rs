//! W2 — a sphere dropped on a mesh's edge, on its corner and on its face gives one contact
//! and the rebound of the analytic plane (docs/physics.md §5.3, §9).
//!
//! Set-up: no gravity; a Table-1 sphere falls at 0.5 m/s straight down onto a closed cube
//! mesh (12 triangles, side 10 R): above the midpoint of a top edge (a convex ridge between
//! two faces), above a top corner (three faces meet), and above a top face on the diagonal
//! that two of its triangles share. The reference is the same drop on the plane z = 0.
//!
//! Expected: the rebound velocity of the plane, straight up (the contact's normal at a
//! ridge or a corner is along the line from the closest point to the centre, which is
//! vertical here); a single contact throughout.
//! Tolerance: 1e-9 of the impact speed: the closest point of an edge or a corner is exact
//! up to coordinate round-off.

use dem::{DVec3, Interaction};

use crate::meshes::{cube, mesh_wall, motion, one_sphere, plane_wall, RADIUS};
use crate::{Resolution, Row, VerifyError};

/// Table 1's contact without rolling friction: Eq. 8's constant torque turns with the sign
/// of ω, which for a sphere that does not spin a round-off tilt of the normal (1e-16)
/// decides, and would make the shapes differ by that decision, not by their geometry.
fn no_rolling() -> Interaction {
    Interaction {
        rolling_friction: 0.0,
        ..Interaction::fan2023()
    }
}

const TEST: &str = "W2";
const SPEED: f64 = 0.5;
const TOLERANCE: f64 = 1e-9;

/// Drops the sphere from `start` (its centre R + gap above the target) at `SPEED` down
/// until it moves up and out of contact; returns its velocity and the most contacts seen.
fn drop(walls: Vec<dem::Wall>, start: DVec3) -> Result<(DVec3, usize), VerifyError> {
    let interaction = no_rolling();
    let v = DVec3::new(0.0, 0.0, -SPEED);
    let (mut sim, _) = one_sphere(walls, interaction, DVec3::ZERO, (start, v, DVec3::ZERO))?;
    let mut most = 0;
    let mut touched = false;
    for _ in 0..400_000 {
        sim.step()?;
        let c = sim.contacts().particle_wall;
        most = most.max(c);
        touched |= c > 0;
        if touched && c == 0 {
            return Ok((motion(&sim).1, most));
        }
    }
    Err(VerifyError::NoEvent {
        what: "the rebound",
        steps: 400_000,
    })
}

/// The rows of W2.
pub fn run(_res: Resolution) -> Result<Vec<Row>, VerifyError> {
    let interaction = no_rolling();
    // Not a whole number of steps' travel (0.05 R would be 60 steps exactly), so round-off
    // of the start cannot move the first touching step.
    let gap = 0.0537 * RADIUS;
    let side = 10.0 * RADIUS;
    let (plane_v, _) = drop(
        vec![plane_wall(interaction)?],
        DVec3::new(0.0, 0.0, RADIUS + gap),
    )?;
    let top = side;
    let box_tris = cube(DVec3::ZERO, DVec3::splat(side));
    let mut rows = Vec::new();
    for (place, x, y) in [
        ("a top edge", 0.5 * side, 0.0),
        ("a top corner", 0.0, 0.0),
        (
            "the shared diagonal of the top face",
            0.3 * side,
            0.3 * side,
        ),
    ] {
        let (v, most) = drop(
            vec![mesh_wall(&box_tris, interaction)?],
            DVec3::new(x, y, top + RADIUS + gap),
        )?;
        rows.push(Row::absolute(
            TEST,
            format!("drop on {place}: rebound (restitution) |v − v_plane| / v_impact"),
            0.0,
            v.distance(plane_v) / SPEED,
            TOLERANCE,
        ));
        rows.push(Row::absolute(
            TEST,
            format!("drop on {place}: most contacts in a step"),
            1.0,
            most as f64,
            0.0,
        ));
    }
    Ok(rows)
}
