//! W1 — a sphere at rest and rolling on a mesh of many small triangles gives the motion of the
//! same analytic plane (docs/physics.md §5.3, §9).
//!
//! Set-up: a Table-1 sphere (R = 1.5 mm) under gravity on the plane z = 0, once as an
//! analytic plane and once as a floor of 2 × 40² triangles whose squares are R/2 wide, so
//! the sphere's contact crosses a triangle every few hundred steps.
//! - At rest (no rolling friction, see below), 0.02 s from just below the equilibrium height, placed over a triangle's face, over an
//!   edge along x, over a diagonal edge, and over a corner shared by eight triangles.
//! - Rolling at 0.2 m/s along a direction oblique to the mesh (it crosses faces, edges and
//!   corners) for 0.05 s, starting in rolling (no slip).
//!
//! Expected: the position, velocity and spin of the mesh run equal the plane run's, and at
//! every step the sphere has at most one contact with the mesh (no double force).
//! Tolerance: round-off only, relative to the motion's scales (position to R; velocity and
//! spin to 0.01 m/s and 0.01/R at rest, 0.2 m/s and 0.2/R rolling). The floor lies in z = 0
//! with exact vertices, so a closest point on a face, an edge or a corner has z = 0 exactly
//! and the overlap has the plane's bits. What differs is the normal's tilt, from the rounding
//! of the closest point's x and y, and the order of the sums in the mesh's surface pass and
//! the plane's kernel. A step can then part the two motions by one rounding of a coordinate of
//! up to 10 R (the floor's half-width), at most 10 ε relative to R (ε the machine epsilon),
//! and by the tilted force's push on velocity and spin, which is 2.5 g Δt/V < 0.01 of a
//! rounding of the force: 20 ε a step covers both twice over. Added over the N steps of the
//! run without any cancelling, that is 20 ε N: 8.9e-12 at rest and 2.7e-11 rolling at the fast
//! resolution, 3.6e-11 and 8.9e-11 at the full one. The runs part by less than 1e-15.

use dem::{DVec3, Interaction, Simulation};

use crate::meshes::{floor, mesh_wall, motion, motion_gap, one_sphere, plane_wall, RADIUS};
use crate::{Resolution, Row, VerifyError};

const TEST: &str = "W1";
const ROLL_SPEED: f64 = 0.2;

/// Largest relative gap between the mesh and plane runs after `steps` steps: 20 ε a step
/// (module documentation) [-].
fn round_off(steps: u64) -> f64 {
    20.0 * f64::EPSILON * steps as f64
}

/// Runs `steps` steps; returns the largest number of wall contacts seen in a step.
fn most_contacts(sim: &mut Simulation, steps: u64) -> Result<usize, VerifyError> {
    let mut most = 0;
    for _ in 0..steps {
        sim.step()?;
        most = most.max(sim.contacts().particle_wall);
    }
    Ok(most)
}

/// The plane run and the mesh run from one start; returns the gap of their final motions
/// and the mesh run's largest contact count.
fn compare(
    start: (DVec3, DVec3, DVec3),
    steps: u64,
    scale: [f64; 3],
    interaction: Interaction,
) -> Result<(f64, usize), VerifyError> {
    let g = DVec3::new(0.0, 0.0, -9.81);
    let (mut plane, _) = one_sphere(vec![plane_wall(interaction)?], interaction, g, start)?;
    // 40 squares of R/2: the floor spans ±10 R.
    let tiles = floor(10.0 * RADIUS, 40, 0.0);
    let (mut mesh, _) = one_sphere(vec![mesh_wall(&tiles, interaction)?], interaction, g, start)?;
    most_contacts(&mut plane, steps)?;
    let most = most_contacts(&mut mesh, steps)?;
    Ok((motion_gap(motion(&plane), motion(&mesh), scale), most))
}

/// The rows of W1.
pub fn run(res: Resolution) -> Result<Vec<Row>, VerifyError> {
    let a = RADIUS / 2.0;
    let rest = RADIUS - 1.0e-7;
    let rest_steps = match res {
        Resolution::Full => 8000,
        Resolution::Fast => 2000,
    };
    // At rest without rolling friction: Eq. 8's constant torque turns with the sign of ω,
    // which at rest a round-off tilt of the normal (1e-16) decides, so with it the two runs
    // would chatter apart by that decision, not by their geometry.
    let still = Interaction {
        rolling_friction: 0.0,
        ..Interaction::fan2023()
    };
    let mut rows = Vec::new();
    for (place, x, y) in [
        ("a face", 0.3 * a, 0.2 * a),
        ("an edge along x", 0.5 * a, 0.0),
        ("a diagonal edge", 0.5 * a, 0.5 * a),
        ("a corner of eight triangles", 0.0, 0.0),
    ] {
        let start = (DVec3::new(x, y, rest), DVec3::ZERO, DVec3::ZERO);
        let (gap, most) = compare(start, rest_steps, [RADIUS, 0.01, 0.01 / RADIUS], still)?;
        rows.push(Row::absolute(
            TEST,
            format!("at rest over {place}: |mesh − plane| motion, relative"),
            0.0,
            gap,
            round_off(rest_steps),
        ));
        rows.push(Row::absolute(
            TEST,
            format!("at rest over {place}: most contacts with the mesh in a step"),
            1.0,
            most as f64,
            0.0,
        ));
    }
    let roll_steps = match res {
        Resolution::Full => 20_000,
        Resolution::Fast => 6000,
    };
    let v = ROLL_SPEED * DVec3::new(0.8, 0.6, 0.0);
    let spin = DVec3::Z.cross(v) / RADIUS;
    let start = (DVec3::new(0.1 * a, 0.3 * a, rest), v, spin);
    let scale = [RADIUS, ROLL_SPEED, ROLL_SPEED / RADIUS];
    let (gap, most) = compare(start, roll_steps, scale, Interaction::fan2023())?;
    rows.push(Row::absolute(
        TEST,
        "rolling across faces, edges and corners: |mesh − plane| motion, relative",
        0.0,
        gap,
        round_off(roll_steps),
    ));
    rows.push(Row::absolute(
        TEST,
        "rolling: most contacts with the mesh in a step",
        1.0,
        most as f64,
        0.0,
    ));
    Ok(rows)
}
