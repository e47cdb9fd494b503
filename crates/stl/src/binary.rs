//! Binary STL: 80-byte header, `u32` count, then 50-byte records of little-endian `f32`.

use glam::DVec3;

use crate::check::{accept, first_non_finite, Origin};
use crate::detect::PREAMBLE_BYTES;
use crate::error::{Location, StlError};
use crate::mesh::{Format, Mesh, Triangle};
use crate::transform::Transform;

/// Bytes of one triangle record: normal, three vertices, attribute.
pub(crate) const RECORD_BYTES: usize = 50;
/// Offset of the first vertex within a record (after the 12-byte normal).
const FIRST_VERTEX: usize = 12;

/// Reads the records of a binary file whose size detection has matched to `count`.
pub(crate) fn parse_binary(
    bytes: &[u8],
    count: u32,
    file: &str,
    transform: &Transform,
) -> Result<Mesh, StlError> {
    if count == 0 {
        return Err(StlError::BinaryNoTriangles { file: file.into() });
    }
    let records = bytes.get(PREAMBLE_BYTES..).unwrap_or_default();
    let mut triangles = Vec::with_capacity(records.len() / RECORD_BYTES);
    for (index, record) in records.chunks_exact(RECORD_BYTES).enumerate() {
        let origin = Origin {
            file,
            triangle: index + 1,
            location: Location::Record {
                offset: (PREAMBLE_BYTES + index * RECORD_BYTES) as u64,
            },
        };
        let vertices = record_vertices(record, origin)?;
        triangles.push(accept(origin, vertices, transform)?);
    }
    Ok(Mesh {
        triangles,
        name: None,
        format: Format::Binary,
    })
}

/// The three vertices of a record, widened to `f64`, or an error at the first non-finite one.
fn record_vertices(record: &[u8], origin: Origin<'_>) -> Result<Triangle, StlError> {
    let mut vertices = [DVec3::ZERO; 3];
    for (k, vertex) in vertices.iter_mut().enumerate() {
        let start = FIRST_VERTEX + 12 * k;
        let point = DVec3::new(
            f32_at(record, start),
            f32_at(record, start + 4),
            f32_at(record, start + 8),
        );
        if let Some((axis, i)) = first_non_finite(point) {
            return Err(StlError::NonFinite {
                file: origin.file.into(),
                triangle: origin.triangle,
                location: origin.location,
                vertex: k + 1,
                axis,
                value: (point[i] as f32).to_string(),
            });
        }
        *vertex = point;
    }
    Ok(vertices)
}

/// The little-endian `f32` at `offset` of the record, widened exactly to `f64`; NaN if the
/// record were too short (it never is: records come from `chunks_exact`).
fn f32_at(record: &[u8], offset: usize) -> f64 {
    record
        .get(offset..offset + 4)
        .and_then(|b| b.try_into().ok())
        .map_or(f64::NAN, |b: [u8; 4]| f64::from(f32::from_le_bytes(b)))
}
