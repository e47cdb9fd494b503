//! W5 — a moving wall drags a sphere at the right tangential speed (docs/physics.md §5.4, §9).
//!
//! Set-up: a Table-1 sphere at rest on a conveyor: the floor z = 0 whose surface moves at
//! u = 0.1 m/s along x without being displaced, as an analytic plane and as a mesh floor;
//! no rolling friction. Sliding friction drags the sphere until its contact point moves
//! with the belt, then it rolls.
//!
//! Expected (rigid-body impulse balance, m Δv = J and I Δω = R J with I = (2/5) m R²):
//! the contact point's velocity v − R ω_y ends at u, and the centre's at v = (2/7) u.
//! Tolerance: 1e-3 u: the tangential spring's elastic rebound after the slip stops makes
//! the centre speed ring by ~1e-4 u around its final value.

use dem::{DVec3, Wall, WallMotion};

use crate::meshes::{floor, mesh_wall, motion, no_rolling, one_sphere, plane_wall, RADIUS};
use crate::{Resolution, Row, VerifyError};

const TEST: &str = "W5";
const BELT: f64 = 0.1;
const TOLERANCE: f64 = 1e-3;

/// Runs the conveyor with floor `wall` for 0.02 s; returns the centre's velocity and the
/// contact point's, along x.
fn conveyor(wall: Wall) -> Result<(f64, f64), VerifyError> {
    let interaction = no_rolling();
    let g = DVec3::new(0.0, 0.0, -9.81);
    let start = (
        DVec3::new(0.0, 0.0, RADIUS - 1e-7),
        DVec3::ZERO,
        DVec3::ZERO,
    );
    let (mut sim, ids) = one_sphere(vec![wall], interaction, g, start)?;
    sim.set_wall_motion(
        ids[0],
        WallMotion {
            velocity: DVec3::new(BELT, 0.0, 0.0),
            ..WallMotion::default()
        },
    )?;
    for _ in 0..8000 {
        sim.step()?;
    }
    let (_, v, w) = motion(&sim);
    Ok((v.x, v.x - RADIUS * w.y))
}

/// The rows of W5.
pub fn run(_res: Resolution) -> Result<Vec<Row>, VerifyError> {
    let interaction = no_rolling();
    let mut rows = Vec::new();
    for (what, wall) in [
        ("plane", plane_wall(interaction)?),
        (
            "mesh",
            mesh_wall(&floor(10.0 * RADIUS, 20, 0.0), interaction)?,
        ),
    ] {
        let (centre, contact) = conveyor(wall)?;
        rows.push(Row::absolute(
            TEST,
            format!("conveyor {what}: contact point speed [m/s], = belt speed"),
            BELT,
            contact,
            TOLERANCE * BELT,
        ));
        rows.push(Row::absolute(
            TEST,
            format!("conveyor {what}: centre speed [m/s], = 2u/7"),
            2.0 * BELT / 7.0,
            centre,
            TOLERANCE * BELT,
        ));
    }
    Ok(rows)
}
