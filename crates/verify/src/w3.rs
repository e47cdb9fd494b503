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
//! Tolerance: 1e-9 of the impact speed: the closest point of the smooth surface is exact up
//! to round-off.

use dem::{DVec3, Wall, WallMaterial};

use crate::meshes::{no_rolling, plane_wall, rebound, RADIUS};
use crate::{Resolution, Row, VerifyError};

const TEST: &str = "W3";
const SPEED: f64 = 0.5;
const TOLERANCE: f64 = 1e-9;

/// The rows of W3.
pub fn run(_res: Resolution) -> Result<Vec<Row>, VerifyError> {
    let interaction = no_rolling();
    // Not a whole number of steps' travel (0.05 R would be 60 steps exactly), so round-off
    // of the start cannot move the first touching step.
    let gap = 0.0537 * RADIUS;
    let (plane, _) = rebound(
        vec![plane_wall(interaction)?],
        DVec3::new(0.0, 0.0, RADIUS + gap),
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
        let (v, _) = rebound(vec![wall], point + (RADIUS + gap) * n, -SPEED * n)?;
        rows.push(Row::absolute(
            TEST,
            format!("{what}: |v − e v n| / v_impact, normal rebound as on a plane"),
            0.0,
            v.distance(speed_out * n) / SPEED,
            TOLERANCE,
        ));
    }
    Ok(rows)
}
