//! Writing triangles [m] as ASCII or binary STL, refusing anything the reader would reject.

mod ascii;
mod binary;
mod error;

pub use ascii::write_ascii;
pub use binary::write_binary;
pub use error::WriteError;

use glam::DVec3;

use crate::check::{defect, first_non_finite};
use crate::mesh::{Format, Triangle};

/// Checks that there is a triangle, that every coordinate is finite and that no triangle is
/// repeated-vertex or degenerate once its coordinates are rounded by `round` (the precision
/// the format stores), so that reading the output back succeeds.
fn check_writable(
    triangles: &[Triangle],
    format: Format,
    round: impl Fn(DVec3) -> DVec3,
) -> Result<(), WriteError> {
    if triangles.is_empty() {
        return Err(WriteError::NoTriangles);
    }
    for (index, triangle) in triangles.iter().enumerate() {
        for (k, &point) in triangle.iter().enumerate() {
            if let Some((axis, i)) = first_non_finite(point) {
                return Err(WriteError::NonFinite {
                    triangle: index + 1,
                    vertex: k + 1,
                    axis,
                    value: point[i],
                });
            }
        }
        if let Some(defect) = defect(&triangle.map(&round)) {
            return Err(WriteError::Unreadable {
                triangle: index + 1,
                format,
                reason: defect.to_string(),
            });
        }
    }
    Ok(())
}
