//! A flat horizontal ring: a disc with a circular hole, the flat bottom of a silo around its
//! orifice.

use std::f64::consts::TAU;

use glam::DVec3;

use super::error::at_least;
use super::{checked, triangle_count, ShapeError};
use crate::mesh::Triangle;

/// The disc of `outer_radius` [m] about the vertical axis in the plane z = `z` [m], less the
/// hole of `hole_radius` [m] centred at (`hole_centre[0]`, `hole_centre[1]`) [m], as
/// `segments` quadrilaterals of 2 triangles between the hole's ring and the outer ring.
///
/// Both rings have their i-th vertex at the angle 2π·i/segments from +x, on the circle (so
/// the hole is the regular polygon inscribed in its circle; a gate made of the same polygon
/// closes it without overlap). Normals point up (+z). Fails unless the hole lies inside the
/// disc with room to spare (|centre| + hole_radius < outer_radius), on non-finite or
/// non-positive lengths and on fewer than 3 segments.
pub fn flat_ring(
    z: f64,
    outer_radius: f64,
    hole_centre: [f64; 2],
    hole_radius: f64,
    segments: usize,
) -> Result<Vec<Triangle>, ShapeError> {
    const SHAPE: &str = "flat_ring";
    for (parameter, value) in [("outer_radius", outer_radius), ("hole_radius", hole_radius)] {
        if !(value.is_finite() && value > 0.0) {
            return Err(ShapeError::Length {
                shape: SHAPE,
                parameter,
                value,
                allowed: "finite and > 0",
            });
        }
    }
    if !z.is_finite() {
        return Err(ShapeError::Length {
            shape: SHAPE,
            parameter: "z",
            value: z,
            allowed: "finite",
        });
    }
    let offset = hole_centre[0].hypot(hole_centre[1]);
    if !(offset.is_finite() && offset + hole_radius < outer_radius) {
        return Err(ShapeError::Length {
            shape: SHAPE,
            parameter: "|hole_centre| + hole_radius",
            value: offset + hole_radius,
            allowed: "finite and < outer_radius",
        });
    }
    let k = at_least(SHAPE, "segments", segments, 3)?;
    let count = triangle_count(SHAPE, 2, k)?;
    let point = |centre: [f64; 2], radius: f64, i: usize| {
        let (sin, cos) = (TAU * i as f64 / k as f64).sin_cos();
        DVec3::new(centre[0] + radius * cos, centre[1] + radius * sin, z)
    };
    let mut triangles = Vec::with_capacity(count);
    for i in 0..k {
        let next = (i + 1) % k;
        let (h0, h1) = (
            point(hole_centre, hole_radius, i),
            point(hole_centre, hole_radius, next),
        );
        let (o0, o1) = (
            point([0.0, 0.0], outer_radius, i),
            point([0.0, 0.0], outer_radius, next),
        );
        triangles.push([h0, o0, o1]);
        triangles.push([h0, o1, h1]);
    }
    checked(SHAPE, triangles)
}

/// The `segments` vertices of the hole's polygon that [`flat_ring`] leaves, in the same
/// order (counter-clockwise seen from above): the outline of a gate that closes it.
pub fn ring_hole(z: f64, hole_centre: [f64; 2], hole_radius: f64, segments: usize) -> Vec<DVec3> {
    (0..segments)
        .map(|i| {
            let (sin, cos) = (TAU * i as f64 / segments as f64).sin_cos();
            DVec3::new(
                hole_centre[0] + hole_radius * cos,
                hole_centre[1] + hole_radius * sin,
                z,
            )
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(t: &Triangle) -> DVec3 {
        0.5 * (t[1] - t[0]).cross(t[2] - t[0])
    }

    /// The ring's area is the outer polygon's less the hole's (each a regular k-gon,
    /// k/2 · r² sin(2π/k)), every normal points up, and the hole's outline is the inner ring.
    #[test]
    fn ring_area_orientation_and_hole() {
        let k = 48;
        let tris = flat_ring(0.25, 0.1, [0.02, -0.01], 0.03, k).unwrap();
        assert_eq!(tris.len(), 2 * k);
        let polygon = |r: f64| 0.5 * k as f64 * r * r * (TAU / k as f64).sin();
        let total: f64 = tris.iter().map(|t| area(t).z).sum();
        // Sums of 96 products of lengths ~0.1 m: round-off far below 1e-15 m².
        assert!((total - (polygon(0.1) - polygon(0.03))).abs() < 1e-15);
        assert!(tris
            .iter()
            .all(|t| area(t).z > 0.0 && t.iter().all(|p| p.z == 0.25)));
        let hole = ring_hole(0.25, [0.02, -0.01], 0.03, k);
        for (i, p) in hole.iter().enumerate() {
            assert_eq!(*p, tris[2 * i][0], "vertex {i} of the hole is the ring's");
        }
    }

    /// A hole that reaches the outer edge, a zero radius or too few segments are refused.
    #[test]
    fn bad_arguments_are_refused() {
        assert!(flat_ring(0.0, 0.1, [0.08, 0.0], 0.03, 24).is_err());
        assert!(flat_ring(0.0, 0.1, [0.0, 0.0], 0.0, 24).is_err());
        assert!(flat_ring(f64::NAN, 0.1, [0.0, 0.0], 0.03, 24).is_err());
        assert!(flat_ring(0.0, 0.1, [0.0, 0.0], 0.03, 2).is_err());
    }
}
