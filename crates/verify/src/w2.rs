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
//! Tolerance: round-off only, since the closest point of an edge or a corner is exact up to
//! the rounding of coordinates. The overlap is a difference of coordinates of size L of 17 to
//! 18 mm (the cube's top) against peak overlaps of 15 µm, so each run's rebound may carry
//! 6.1 × 2 ε L/δ_max (`meshes::rebound_round_off`, ε the machine epsilon): 3.4e-12 to
//! 3.7e-12 of the impact speed for both runs together. The drops part from the plane's by
//! 3.1e-13.

use dem::DVec3;

use crate::meshes::{cube, mesh_wall, no_rolling, plane_wall, rebound, rebound_round_off, RADIUS};
use crate::{Resolution, Row, VerifyError};

const TEST: &str = "W2";
const SPEED: f64 = 0.5;

/// The rows of W2.
pub fn run(_res: Resolution) -> Result<Vec<Row>, VerifyError> {
    let interaction = no_rolling();
    // Not a whole number of steps' travel (0.05 R would be 60 steps exactly), so round-off
    // of the start cannot move the first touching step.
    let gap = 0.0537 * RADIUS;
    let side = 10.0 * RADIUS;
    let down = DVec3::new(0.0, 0.0, -SPEED);
    let plane_start = DVec3::new(0.0, 0.0, RADIUS + gap);
    let (plane_v, _) = rebound(vec![plane_wall(interaction)?], plane_start, down)?;
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
        let start = DVec3::new(x, y, top + RADIUS + gap);
        let (v, most) = rebound(vec![mesh_wall(&box_tris, interaction)?], start, down)?;
        rows.push(Row::absolute(
            TEST,
            format!("drop on {place}: rebound (restitution) |v − v_plane| / v_impact"),
            0.0,
            v.distance(plane_v) / SPEED,
            rebound_round_off(start.length(), plane_start, SPEED),
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
