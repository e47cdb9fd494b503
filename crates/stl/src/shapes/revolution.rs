//! Open surfaces of revolution: the side of a cylinder and of a cone frustum.

use std::f64::consts::TAU;

use glam::DVec3;

use super::error::{at_least, finite_point, nonzero_vector};
use super::{checked, triangle_count, ShapeError};
use crate::mesh::Triangle;

/// The side of a cylinder of `radius` [m] around the segment from `base_centre` to
/// `base_centre + axis` [m] (the axis vector's length is the height), tessellated into
/// `segments` flat strips of 2 triangles each. Open: no end caps. The ring vertices lie on the
/// circle, at angles `2π·i/segments` from a direction perpendicular to the axis; normals point
/// away from the axis (use [`super::flipped`] for inward).
///
/// Fails as [`frustum_side`] does, and on a radius that is not finite and > 0.
pub fn cylinder_side(
    base_centre: DVec3,
    axis: DVec3,
    radius: f64,
    segments: usize,
) -> Result<Vec<Triangle>, ShapeError> {
    const SHAPE: &str = "cylinder_side";
    if !(radius.is_finite() && radius > 0.0) {
        return Err(ShapeError::Length {
            shape: SHAPE,
            parameter: "radius",
            value: radius,
            allowed: "finite and > 0",
        });
    }
    revolution(SHAPE, base_centre, axis, [radius, radius], segments)
}

/// The side of a cone frustum around the segment from `base_centre` to `base_centre + axis`
/// [m], of radius `base_radius` at the base and `top_radius` at the top [m], tessellated into
/// `segments` strips: 2 triangles each, or 1 where a radius is zero (a cone's apex). Open: no
/// end caps. Normals point away from the axis (use [`super::flipped`] for inward); a conical
/// hopper narrowing downwards is a frustum with the outlet radius at the base.
///
/// Fails on a non-finite centre, a zero or non-finite axis, a radius that is not finite and
/// ≥ 0, both radii zero, fewer than 3 segments, more than [`super::MAX_TRIANGLES`] triangles,
/// or proportions so extreme that a triangle is degenerate.
pub fn frustum_side(
    base_centre: DVec3,
    axis: DVec3,
    base_radius: f64,
    top_radius: f64,
    segments: usize,
) -> Result<Vec<Triangle>, ShapeError> {
    const SHAPE: &str = "frustum_side";
    for (parameter, value) in [("base_radius", base_radius), ("top_radius", top_radius)] {
        if !(value.is_finite() && value >= 0.0) {
            return Err(ShapeError::Length {
                shape: SHAPE,
                parameter,
                value,
                allowed: "finite and ≥ 0",
            });
        }
    }
    if base_radius == 0.0 && top_radius == 0.0 {
        return Err(ShapeError::Length {
            shape: SHAPE,
            parameter: "base_radius and top_radius",
            value: 0.0,
            allowed: "> 0 for at least one of them",
        });
    }
    revolution(
        SHAPE,
        base_centre,
        axis,
        [base_radius, top_radius],
        segments,
    )
}

/// The strips between the base ring and the top ring; a ring of radius zero is a single point.
fn revolution(
    shape: &'static str,
    base_centre: DVec3,
    axis: DVec3,
    radii: [f64; 2],
    segments: usize,
) -> Result<Vec<Triangle>, ShapeError> {
    finite_point(shape, "base_centre", base_centre)?;
    nonzero_vector(shape, "axis", axis)?;
    let k = at_least(shape, "segments", segments, 3)?;
    let per_segment = if radii.contains(&0.0) { 1 } else { 2 };
    let count = triangle_count(shape, per_segment, k)?;
    let base = ring(base_centre, axis, radii[0], k);
    let top = ring(base_centre + axis, axis, radii[1], k);
    let mut triangles = Vec::with_capacity(count);
    for i in 0..k {
        let next = (i + 1) % k;
        let (b0, b1, t0, t1) = (base[i], base[next], top[i], top[next]);
        if radii[0] == 0.0 {
            triangles.push([b0, t1, t0]);
        } else if radii[1] == 0.0 {
            triangles.push([b0, b1, t0]);
        } else {
            triangles.push([b0, b1, t1]);
            triangles.push([b0, t1, t0]);
        }
    }
    checked(shape, triangles)
}

/// `k` points on the circle of `radius` around `centre` in the plane perpendicular to `axis`,
/// counter-clockwise seen from the tip of `axis`; all equal to `centre` when the radius is 0.
fn ring(centre: DVec3, axis: DVec3, radius: f64, k: usize) -> Vec<DVec3> {
    // Divided by its largest component first, so a tiny axis does not underflow to length 0.
    let direction = (axis / axis.abs().max_element()).normalize();
    let u = direction.any_orthonormal_vector();
    let w = direction.cross(u);
    (0..k)
        .map(|i| {
            let (sin, cos) = (TAU * i as f64 / k as f64).sin_cos();
            centre + radius * (cos * u + sin * w)
        })
        .collect()
}
