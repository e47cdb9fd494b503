//! Tessellated surfaces built in code, for engine tests and simple walls: a flat rectangle of
//! many small triangles, a closed axis-aligned box, a flat ring with a hole, and the sides of a cylinder and of a cone
//! frustum. All lengths are in metres [m]; every builder checks its arguments and returns only
//! triangles that the reader accepts (distinct vertices, area / L² ≥
//! [`crate::DEGENERACY_RATIO`]). Neighbouring triangles share bit-identical vertices, and each
//! surface is consistently oriented: an edge shared by two triangles is traversed once in each
//! direction.

mod axis_aligned_box;
mod error;
mod flat_ring;
mod rectangle;
mod revolution;

pub use axis_aligned_box::axis_aligned_box;
pub use error::ShapeError;
pub use flat_ring::{flat_ring, ring_hole};
pub use rectangle::rectangle;
pub use revolution::{cylinder_side, frustum_side};

use crate::check::defect;
use crate::mesh::Triangle;

/// The most triangles a builder makes (about 720 MB of vertices); more is certainly a mistake
/// in the arguments, and refusing it keeps the allocation from failing.
pub const MAX_TRIANGLES: usize = 10_000_000;

/// The same triangles with the opposite orientation: vertices 2 and 3 swapped, so every normal
/// points the other way (e.g. a hopper's side facing its axis rather than away from it).
pub fn flipped(triangles: &[Triangle]) -> Vec<Triangle> {
    triangles.iter().map(|&[a, b, c]| [a, c, b]).collect()
}

/// The number of triangles `per_unit × units`, or an error if it exceeds [`MAX_TRIANGLES`].
fn triangle_count(shape: &'static str, per_unit: usize, units: usize) -> Result<usize, ShapeError> {
    per_unit
        .checked_mul(units)
        .filter(|&n| n <= MAX_TRIANGLES)
        .ok_or(ShapeError::TooMany {
            shape,
            per_unit,
            units,
        })
}

/// Passes the triangles through if the reader would accept every one of them.
fn checked(shape: &'static str, triangles: Vec<Triangle>) -> Result<Vec<Triangle>, ShapeError> {
    for (index, triangle) in triangles.iter().enumerate() {
        if let Some(defect) = defect(triangle) {
            return Err(ShapeError::Degenerate {
                shape,
                triangle: index + 1,
                reason: defect.to_string(),
            });
        }
    }
    Ok(triangles)
}
