//! A flat parallelogram (a floor, a plate) tessellated into many small triangles.

use glam::DVec3;

use super::error::{at_least, finite_point, nonzero_vector};
use super::{checked, triangle_count, ShapeError};
use crate::mesh::Triangle;

const SHAPE: &str = "rectangle";

/// The parallelogram `corner + s·edge_u + t·edge_v`, `s, t ∈ [0, 1]` [m], cut into
/// `divisions_u × divisions_v` cells, each split along its diagonal into 2 triangles.
///
/// Triangles are oriented so that their normals point along `edge_u × edge_v`; cell (i, j)
/// gives triangles `2·(j·divisions_u + i)` and the next one. With perpendicular edges this is a
/// rectangle, e.g. a floor of 0.2 m × 0.1 m in 20 × 10 squares:
/// `rectangle(DVec3::ZERO, 0.2 * DVec3::X, 0.1 * DVec3::Y, 20, 10)`.
///
/// Fails on a non-finite corner, a zero or non-finite edge, zero divisions, more than
/// [`super::MAX_TRIANGLES`] triangles, or edges so nearly parallel that the cells are
/// degenerate.
pub fn rectangle(
    corner: DVec3,
    edge_u: DVec3,
    edge_v: DVec3,
    divisions_u: usize,
    divisions_v: usize,
) -> Result<Vec<Triangle>, ShapeError> {
    finite_point(SHAPE, "corner", corner)?;
    nonzero_vector(SHAPE, "edge_u", edge_u)?;
    nonzero_vector(SHAPE, "edge_v", edge_v)?;
    let n = at_least(SHAPE, "divisions_u", divisions_u, 1)?;
    let m = at_least(SHAPE, "divisions_v", divisions_v, 1)?;
    let cells = n.saturating_mul(m);
    let count = triangle_count(SHAPE, 2, cells)?;
    // One function for every grid point, so cells sharing a point share its exact bits.
    let point = |i: usize, j: usize| {
        corner + edge_u * (i as f64 / n as f64) + edge_v * (j as f64 / m as f64)
    };
    let mut triangles = Vec::with_capacity(count);
    for j in 0..m {
        for i in 0..n {
            let (a, b, c, d) = (
                point(i, j),
                point(i + 1, j),
                point(i + 1, j + 1),
                point(i, j + 1),
            );
            triangles.push([a, b, c]);
            triangles.push([a, c, d]);
        }
    }
    checked(SHAPE, triangles)
}
