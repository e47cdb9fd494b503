//! A closed axis-aligned box of 12 triangles with outward normals.

use glam::DVec3;

use super::error::finite_point;
use super::{checked, ShapeError};
use crate::mesh::Triangle;

const SHAPE: &str = "axis_aligned_box";

/// The closed box with opposite corners `min` and `max` [m]: 6 faces of 2 triangles each,
/// every normal pointing out of the box (so the divergence theorem gives its volume).
///
/// Fails if a corner is not finite or if `min` is not below `max` on every axis.
pub fn axis_aligned_box(min: DVec3, max: DVec3) -> Result<Vec<Triangle>, ShapeError> {
    finite_point(SHAPE, "min", min)?;
    finite_point(SHAPE, "max", max)?;
    let extents = ["max.x − min.x", "max.y − min.y", "max.z − min.z"];
    for (i, parameter) in extents.into_iter().enumerate() {
        if min[i] >= max[i] {
            return Err(ShapeError::Length {
                shape: SHAPE,
                parameter,
                value: max[i] - min[i],
                allowed: "> 0",
            });
        }
    }
    // Corner with bits (x, y, z): 0 takes min, 1 takes max along that axis.
    let p = |x: usize, y: usize, z: usize| {
        DVec3::new([min.x, max.x][x], [min.y, max.y][y], [min.z, max.z][z])
    };
    // Each face counter-clockwise seen from outside.
    let faces = [
        [p(0, 0, 0), p(0, 0, 1), p(0, 1, 1), p(0, 1, 0)], // x = min, normal −x
        [p(1, 0, 0), p(1, 1, 0), p(1, 1, 1), p(1, 0, 1)], // x = max, normal +x
        [p(0, 0, 0), p(1, 0, 0), p(1, 0, 1), p(0, 0, 1)], // y = min, normal −y
        [p(0, 1, 0), p(0, 1, 1), p(1, 1, 1), p(1, 1, 0)], // y = max, normal +y
        [p(0, 0, 0), p(0, 1, 0), p(1, 1, 0), p(1, 0, 0)], // z = min, normal −z
        [p(0, 0, 1), p(1, 0, 1), p(1, 1, 1), p(0, 1, 1)], // z = max, normal +z
    ];
    let triangles = faces
        .iter()
        .flat_map(|&[a, b, c, d]| [[a, b, c], [a, c, d]])
        .collect();
    checked(SHAPE, triangles)
}
