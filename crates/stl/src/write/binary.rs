//! Binary STL output: coordinates rounded to 32-bit floats.

use std::io::{BufWriter, Write};

use glam::DVec3;

use super::{check_writable, WriteError};
use crate::detect::HEADER_BYTES;
use crate::mesh::{Format, Triangle};

/// Writes `triangles` [m] as binary STL.
///
/// The 80-byte header holds `name`, cut at a character boundary to fit and padded with zero
/// bytes; a name beginning with `solid` is written after the word `binary ` so that readers
/// which take any file beginning with `solid` for ASCII do not misread it. Each record holds
/// the unit normal from the vertex order (zero for a triangle too small to give one), the
/// vertices rounded to the nearest `f32` (relative error at most 2⁻²⁴ ≈ 6e-8) and a zero
/// attribute.
///
/// Fails, before writing anything, on an empty list, more than `u32::MAX` triangles, a
/// non-finite coordinate, one beyond `f32` range, or a triangle that `f32` rounding makes
/// repeated-vertex or degenerate (see [`crate::DEGENERACY_RATIO`]).
pub fn write_binary<W: Write>(
    writer: W,
    triangles: &[Triangle],
    name: &str,
) -> Result<(), WriteError> {
    let count = u32::try_from(triangles.len()).map_err(|_| WriteError::TooMany {
        count: triangles.len(),
    })?;
    check_range(triangles)?;
    check_writable(triangles, Format::Binary, round_to_f32)?;
    let mut out = BufWriter::new(writer);
    out.write_all(&header(name))?;
    out.write_all(&count.to_le_bytes())?;
    for triangle in triangles {
        out.write_all(&record(triangle))?;
    }
    out.flush()?;
    Ok(())
}

/// Rejects a finite coordinate that `f32` cannot hold (it would become infinite).
fn check_range(triangles: &[Triangle]) -> Result<(), WriteError> {
    for (index, triangle) in triangles.iter().enumerate() {
        for (k, point) in triangle.iter().enumerate() {
            for (i, axis) in ['x', 'y', 'z'].into_iter().enumerate() {
                let value = point[i];
                if value.is_finite() && value.abs() > f64::from(f32::MAX) {
                    return Err(WriteError::OutOfRange {
                        triangle: index + 1,
                        vertex: k + 1,
                        axis,
                        value,
                    });
                }
            }
        }
    }
    Ok(())
}

/// The point as the binary file stores it: each coordinate rounded to the nearest `f32`.
fn round_to_f32(point: DVec3) -> DVec3 {
    point.as_vec3().as_dvec3()
}

/// The 80-byte header: the name (prefixed by `binary ` if it begins with `solid`), cut at a
/// character boundary, padded with zeros.
fn header(name: &str) -> [u8; HEADER_BYTES] {
    let begins_with_solid = name
        .trim_start()
        .get(..5)
        .is_some_and(|w| w.eq_ignore_ascii_case("solid"));
    let text = if begins_with_solid {
        format!("binary {name}")
    } else {
        name.to_string()
    };
    let mut end = text.len().min(HEADER_BYTES);
    while !text.is_char_boundary(end) {
        end -= 1;
    }
    let mut header = [0u8; HEADER_BYTES];
    header[..end].copy_from_slice(&text.as_bytes()[..end]);
    header
}

/// One 50-byte record: normal, three vertices, zero attribute.
fn record(triangle: &Triangle) -> Vec<u8> {
    let normal = super::ascii::unit_normal(triangle);
    let mut bytes = Vec::with_capacity(50);
    for point in std::iter::once(normal).chain(triangle.iter().copied()) {
        for value in point.as_vec3().to_array() {
            bytes.extend_from_slice(&value.to_le_bytes());
        }
    }
    bytes.extend_from_slice(&0u16.to_le_bytes());
    bytes
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_name_beginning_with_solid_is_prefixed_in_the_header() {
        assert!(header("Solid floor").starts_with(b"binary Solid floor\0"));
        assert!(header("floor").starts_with(b"floor\0"));
    }

    #[test]
    fn a_long_name_is_cut_at_a_character_boundary() {
        // 79 ASCII bytes then a two-byte character: only the 79 bytes fit.
        let name = format!("{}é", "a".repeat(79));
        let header = header(&name);
        assert_eq!(&header[..79], "a".repeat(79).as_bytes());
        assert_eq!(header[79], 0);
    }
}
