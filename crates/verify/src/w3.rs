//! W3 — contact with a cylinder and a cone, from inside and from outside
//! (docs/physics.md §5.2, §9).
//!
//! Set-up: no gravity; a Table-1 sphere moves at 0.5 m/s along the surface's normal onto a
//! cylinder of radius 20 R about z, and onto a cone frustum from radius 20 R at z = 0 to
//! 10 R at z = 20 R, at mid-height, once from inside and once from outside. The reference
//! is the same normal impact on the plane z = 0.
//!
//! Expected: the wall counts as flat at the contact (R* = R, docs/physics.md §5), so the
//! sphere leaves along the normal with the plane's rebound speed.
//! Tolerance: round-off only, since the closest point of the smooth surface is exact up to
//! the rounding of coordinates. The overlap is a difference of coordinates of size L, here
//! 25 to 44 mm from the origin, against peak overlaps of 15 µm, so each run's rebound may
//! carry 6.1 × 2 ε L/δ_max (`meshes::rebound_round_off`, ε the machine epsilon): 5.1e-12
//! to 8.4e-12 of the impact speed for both runs together. The impacts part from the plane's
//! by 0.9e-13 to 3.8e-13.

use dem::{DVec3, Wall, WallMaterial};

use crate::meshes::{no_rolling, plane_wall, rebound, rebound_round_off, RADIUS};
use crate::{Resolution, Row, VerifyError};

const TEST: &str = "W3";
const SPEED: f64 = 0.5;

/// The rows of W3.
pub fn run(_res: Resolution) -> Result<Vec<Row>, VerifyError> {
    let interaction = no_rolling();
    // Not a whole number of steps' travel (0.05 R would be 60 steps exactly), so round-off
    // of the start cannot move the first touching step.
    let gap = 0.0537 * RADIUS;
    let plane_start = DVec3::new(0.0, 0.0, RADIUS + gap);
    let (plane, _) = rebound(
        vec![plane_wall(interaction)?],
        plane_start,
        -SPEED * DVec3::Z,
    )?;
    let speed_out = plane.z;
    let r = 20.0 * RADIUS;
    let cylinder = || {
        Wall::cylinder(
            DVec3::ZERO,
            DVec3::Z,
            2.0 * r,
            r,
            WallMaterial::Rigid,
            interaction,
        )
    };
    let cone = || {
        Wall::frustum(
            DVec3::ZERO,
            DVec3::Z,
            r,
            [r, 0.5 * r],
            WallMaterial::Rigid,
            interaction,
        )
    };
    // The cone's outward meridian normal at mid-height: (2, 0, 1)/√5 in (x, y, z).
    let cone_normal = DVec3::new(2.0, 0.0, 1.0) / 5f64.sqrt();
    let cone_point = DVec3::new(0.75 * r, 0.0, 0.5 * r);
    let cyl_point = DVec3::new(r, 0.0, r);
    let cases = [
        (
            "cylinder, from inside",
            cylinder()?,
            cyl_point,
            DVec3::X,
            -1.0,
        ),
        (
            "cylinder, from outside",
            cylinder()?,
            cyl_point,
            DVec3::X,
            1.0,
        ),
        ("cone, from inside", cone()?, cone_point, cone_normal, -1.0),
        ("cone, from outside", cone()?, cone_point, cone_normal, 1.0),
    ];
    let mut rows = Vec::new();
    for (what, wall, point, normal, side) in cases {
        // The surface's normal towards the sphere's side.
        let n = side * normal;
        let start = point + (RADIUS + gap) * n;
        let (v, _) = rebound(vec![wall], start, -SPEED * n)?;
        rows.push(Row::absolute(
            TEST,
            format!("{what}: |v − e v n| / v_impact, normal rebound as on a plane"),
            0.0,
            v.distance(speed_out * n) / SPEED,
            rebound_round_off(start.length(), plane_start, SPEED),
        ));
    }
    Ok(rows)
}
