//! Why a file is not a usable STL mesh: every message begins with the file's name and gives the
//! line (ASCII) or record (binary), the triangle counted from 1, the value and what is allowed.

use std::fmt;

use glam::DVec3;
use thiserror::Error;

use crate::check::DEGENERACY_RATIO;

/// Where in the file a triangle or token is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Location {
    /// A line of an ASCII file, counted from 1.
    Line(usize),
    /// The 50-byte record of a binary file starting at this byte offset (0-based; the first
    /// record starts at byte 84).
    Record {
        /// Byte offset of the record from the start of the file.
        offset: u64,
    },
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Location::Line(line) => write!(f, "line {line}"),
            Location::Record { offset } => write!(f, "record at byte {offset}"),
        }
    }
}

/// A file that cannot be read as a mesh of valid triangles. Triangle and vertex numbers count
/// from 1; `file` is the source name given to [`crate::parse`] or the path given to
/// [`crate::read`].
#[derive(Debug, Error)]
pub enum StlError {
    /// The file could not be read from disk.
    #[error("{file}: cannot read the file: {source}")]
    Io {
        /// The file.
        file: String,
        /// The operating system's reason.
        #[source]
        source: std::io::Error,
    },
    /// The file has no bytes.
    #[error("{file}: the file is empty (0 bytes); an STL file holds at least one triangle")]
    Empty {
        /// The file.
        file: String,
    },
    /// Neither ASCII (no leading `solid`) nor long enough for a binary header.
    #[error(
        "{file}: not an STL file: it does not begin with `solid` (ASCII STL) and its {actual} bytes \
         are fewer than the 84 of a binary STL's header and triangle count"
    )]
    NotStl {
        /// The file.
        file: String,
        /// Size of the file [bytes].
        actual: u64,
    },
    /// A file taken for binary STL whose size disagrees with the triangle count in its header.
    #[error(
        "{file}: binary STL of the wrong size: the header declares {count} triangles, which need \
         84 + 50 × {count} = {expected} bytes, but the file has {actual} bytes \
         (truncated, or not an STL file)"
    )]
    BinarySize {
        /// The file.
        file: String,
        /// Triangle count in bytes 80..84.
        count: u32,
        /// Size the count implies, 84 + 50·count [bytes].
        expected: u64,
        /// Size of the file [bytes].
        actual: u64,
    },
    /// A file beginning with `solid` that holds a byte which is not text, and whose size does
    /// not fit binary STL either.
    #[error(
        "{file}, line {line}: byte {offset} (0x{byte:02x}) is not text, so the file is not ASCII \
         STL although it begins with `solid`; {}",
        binary_verdict(*.size)
    )]
    NotText {
        /// The file.
        file: String,
        /// Line of the offending byte, counted from 1.
        line: usize,
        /// Offset of the offending byte from the start of the file (0-based).
        offset: u64,
        /// The offending byte (a control character or the start of invalid UTF-8).
        byte: u8,
        /// Size of the file and, when it has a binary header, the count it declares.
        size: BinarySizeNote,
    },
    /// A binary file whose header declares no triangles.
    #[error("{file}: the binary STL header declares 0 triangles; a wall mesh needs at least one")]
    BinaryNoTriangles {
        /// The file.
        file: String,
    },
    /// An ASCII file without any facet.
    #[error(
        "{file}, line {line}: `endsolid` with no facet in the file; a wall mesh needs at least one \
         triangle"
    )]
    AsciiNoTriangles {
        /// The file.
        file: String,
        /// Line of the last `endsolid`.
        line: usize,
    },
    /// A token where the ASCII grammar allows other keywords.
    #[error("{file}, line {line}: expected {expected}, found `{found}`")]
    Unexpected {
        /// The file.
        file: String,
        /// Line of the token.
        line: usize,
        /// What the grammar allows here.
        expected: &'static str,
        /// The token found.
        found: String,
    },
    /// An ASCII file that ends inside a solid.
    #[error(
        "{file}, line {line}: the file ends where {expected} should follow \
         (truncated, or `endsolid` missing)"
    )]
    UnexpectedEnd {
        /// The file.
        file: String,
        /// Last line of the file.
        line: usize,
        /// What the grammar needs next.
        expected: &'static str,
    },
    /// A keyword after fewer than 3 numbers of a `vertex` or `normal`.
    #[error("{file}, line {line}: {item} needs 3 numbers, found {found} before `{next}`")]
    MissingNumbers {
        /// The file.
        file: String,
        /// Line of the keyword that cut the numbers short.
        line: usize,
        /// Which vertex or normal, e.g. "vertex 2 of triangle 5 (counting from 1)".
        item: String,
        /// How many numbers were read.
        found: usize,
        /// The keyword found instead of a number.
        next: String,
    },
    /// A fourth number after a `vertex` or `normal`.
    #[error("{file}, line {line}: {item} has more than 3 numbers: extra `{token}`")]
    ExtraNumber {
        /// The file.
        file: String,
        /// Line of the extra number.
        line: usize,
        /// Which vertex or normal.
        item: String,
        /// The extra number as written.
        token: String,
    },
    /// A token that should be a number and is not one.
    #[error("{file}, line {line}: `{token}` in {item} is not a number")]
    BadNumber {
        /// The file.
        file: String,
        /// Line of the token.
        line: usize,
        /// Which vertex or normal.
        item: String,
        /// The token as written.
        token: String,
    },
    /// A facet with other than 3 vertices.
    #[error(
        "{file}, line {line}: triangle {triangle} (counting from 1) has {count} vertices between \
         `outer loop` and `endloop`; a facet needs exactly 3"
    )]
    VertexCount {
        /// The file.
        file: String,
        /// Line of the facet's `endloop`.
        line: usize,
        /// The facet, counted from 1.
        triangle: usize,
        /// How many `vertex` lines it has.
        count: usize,
    },
    /// A vertex coordinate that is NaN or infinite.
    #[error(
        "{file}, triangle {triangle} (counting from 1), {location}: coordinate {axis} of vertex \
         {vertex} is {value}; allowed: finite numbers"
    )]
    NonFinite {
        /// The file.
        file: String,
        /// The triangle, counted from 1.
        triangle: usize,
        /// The vertex's line or the triangle's record.
        location: Location,
        /// The vertex, 1 to 3.
        vertex: usize,
        /// The coordinate: `x`, `y` or `z`.
        axis: char,
        /// The value as written (ASCII) or decoded (binary).
        value: String,
    },
    /// A triangle with two identical vertices.
    #[error(
        "{file}, triangle {triangle} (counting from 1), {location}: vertices {first} and {second} \
         are the same point ({}, {}, {}) [file units]; a triangle needs three distinct corners",
        .point.x, .point.y, .point.z
    )]
    RepeatedVertex {
        /// The file.
        file: String,
        /// The triangle, counted from 1.
        triangle: usize,
        /// The facet's first line or the triangle's record.
        location: Location,
        /// The first of the two equal vertices, 1 to 3.
        first: usize,
        /// The second of the two equal vertices, 1 to 3.
        second: usize,
        /// The shared point [file units].
        point: DVec3,
    },
    /// A triangle whose area is negligible against the square of its longest edge.
    #[error(
        "{file}, triangle {triangle} (counting from 1), {location}: degenerate, its corners lie on \
         one line: area / L² = {area_ratio:e} with longest edge L = {longest_edge} [file units]; \
         allowed: area / L² ≥ {DEGENERACY_RATIO:e}"
    )]
    Degenerate {
        /// The file.
        file: String,
        /// The triangle, counted from 1.
        triangle: usize,
        /// The facet's first line or the triangle's record.
        location: Location,
        /// Area over the square of the longest edge (dimensionless).
        area_ratio: f64,
        /// The longest edge [file units].
        longest_edge: f64,
    },
    /// A triangle with an edge beyond the double range (vertices of opposite sign near
    /// ±1.8e308), whose shape cannot be measured.
    #[error(
        "{file}, triangle {triangle} (counting from 1), {location}: an edge is beyond the double \
         range, so its shape cannot be measured; allowed: coordinate differences below 1.8e308 \
         file units"
    )]
    EdgeOverflow {
        /// The file.
        file: String,
        /// The triangle, counted from 1.
        triangle: usize,
        /// The facet's first line or the triangle's record.
        location: Location,
    },
    /// A vertex that the transform takes out of the finite numbers.
    #[error(
        "{file}, triangle {triangle} (counting from 1), {location}: vertex {vertex} is not finite \
         after the transform (scale {scale} m per file unit); allowed: coordinates that stay \
         finite in metres"
    )]
    Overflow {
        /// The file.
        file: String,
        /// The triangle, counted from 1.
        triangle: usize,
        /// The facet's first line or the triangle's record.
        location: Location,
        /// The vertex, 1 to 3.
        vertex: usize,
        /// The transform's scale [m per file unit].
        scale: f64,
    },
}

/// What the size of a non-text file beginning with `solid` says about it as binary STL.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BinarySizeNote {
    /// Size of the file [bytes].
    pub actual: u64,
    /// The triangle count in bytes 80..84; `None` when the file is shorter than 84 bytes.
    pub declared_count: Option<u32>,
}

/// The second half of a [`StlError::NotText`] message: why the file is not binary STL either.
fn binary_verdict(note: BinarySizeNote) -> String {
    match note.declared_count {
        Some(count) => format!(
            "nor is it binary STL: the header declares {count} triangles, which need {} bytes, \
             but the file has {} bytes",
            binary_size(count),
            note.actual
        ),
        None => format!(
            "nor is it binary STL: its {} bytes are fewer than the 84 of a binary header",
            note.actual
        ),
    }
}

/// The size of a binary STL file holding `count` triangles, 84 + 50·count [bytes].
pub(crate) fn binary_size(count: u32) -> u64 {
    84 + 50 * u64::from(count)
}
