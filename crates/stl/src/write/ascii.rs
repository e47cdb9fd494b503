//! ASCII STL output: coordinates in the shortest decimal form that reads back exactly.

use std::io::{BufWriter, Write};

use glam::DVec3;

use super::{check_writable, WriteError};
use crate::mesh::{Format, Triangle};

/// Writes `triangles` [m] as ASCII STL under the solid name `name` (may be empty).
///
/// Numbers are written in Rust's shortest round-trip exponent form (e.g. `1.5e-3`), so reading
/// the file back gives the same `f64` values exactly. Each facet's normal is the unit normal
/// from the vertex order (zero for a triangle too small to give one); the reader ignores it.
///
/// Fails, before writing anything, on an empty list, a non-finite coordinate, a
/// repeated-vertex or degenerate triangle (see [`crate::DEGENERACY_RATIO`]), or a name the
/// reader would not read back as written: one with a line break or other control character,
/// with a word `solid`, `facet` or `endsolid`, or with white space other than single spaces
/// between words.
pub fn write_ascii<W: Write>(
    writer: W,
    triangles: &[Triangle],
    name: &str,
) -> Result<(), WriteError> {
    check_name(name)?;
    check_writable(triangles, Format::Ascii, |p| p)?;
    let mut out = BufWriter::new(writer);
    writeln!(out, "solid {name}")?;
    for triangle in triangles {
        let n = unit_normal(triangle);
        writeln!(out, "  facet normal {:e} {:e} {:e}", n.x, n.y, n.z)?;
        writeln!(out, "    outer loop")?;
        for p in triangle {
            writeln!(out, "      vertex {:e} {:e} {:e}", p.x, p.y, p.z)?;
        }
        writeln!(out, "    endloop")?;
        writeln!(out, "  endfacet")?;
    }
    writeln!(out, "endsolid {name}")?;
    out.flush()?;
    Ok(())
}

/// The unit normal `(v1 − v0) × (v2 − v0)` normalised, or zero if it has no direction.
pub(super) fn unit_normal(triangle: &Triangle) -> DVec3 {
    (triangle[1] - triangle[0])
        .cross(triangle[2] - triangle[0])
        .normalize_or_zero()
}

/// Rejects a name that the reader would not return unchanged.
fn check_name(name: &str) -> Result<(), WriteError> {
    let reason = if name.chars().any(char::is_control) {
        Some("it holds a line break or another control character")
    } else if name.split(' ').any(|w| {
        ["solid", "facet", "endsolid"]
            .iter()
            .any(|k| w.eq_ignore_ascii_case(k))
    }) {
        Some("the words `solid`, `facet` and `endsolid` would be read as keywords")
    } else if name.split(' ').any(str::is_empty) && !name.is_empty() {
        Some("words must be separated by single spaces, without leading or trailing spaces")
    } else {
        None
    };
    match reason {
        Some(reason) => Err(WriteError::Name {
            name: name.into(),
            reason,
        }),
        None => Ok(()),
    }
}
