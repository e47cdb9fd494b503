//! Why triangles cannot be written as STL.

use thiserror::Error;

use crate::mesh::Format;

/// Triangles that cannot be written, or a writer that failed. Triangles and vertices count
/// from 1.
#[derive(Debug, Error)]
pub enum WriteError {
    /// The writer failed.
    #[error("cannot write the STL output: {0}")]
    Io(#[from] std::io::Error),
    /// An empty list: readers, this crate's included, reject an STL file without triangles.
    #[error("no triangles to write; an STL file needs at least one")]
    NoTriangles,
    /// More triangles than the binary count (`u32`) can hold.
    #[error(
        "{count} triangles exceed the binary STL limit of {} (a 32-bit count)",
        u32::MAX
    )]
    TooMany {
        /// The number of triangles given.
        count: usize,
    },
    /// A coordinate that is NaN or infinite.
    #[error(
        "triangle {triangle} (counting from 1): coordinate {axis} of vertex {vertex} is {value} m; \
         allowed: finite numbers"
    )]
    NonFinite {
        /// The triangle, counted from 1.
        triangle: usize,
        /// The vertex, 1 to 3.
        vertex: usize,
        /// The coordinate: `x`, `y` or `z`.
        axis: char,
        /// The value [m].
        value: f64,
    },
    /// A coordinate beyond the range of the binary format's 32-bit floats.
    #[error(
        "triangle {triangle} (counting from 1): coordinate {axis} of vertex {vertex} = {value} m \
         is beyond binary STL's 32-bit floats; allowed: |value| ≤ {} m",
        f32::MAX
    )]
    OutOfRange {
        /// The triangle, counted from 1.
        triangle: usize,
        /// The vertex, 1 to 3.
        vertex: usize,
        /// The coordinate: `x`, `y` or `z`.
        axis: char,
        /// The value [m].
        value: f64,
    },
    /// A triangle the reader would reject once stored at the format's precision (e.g. two
    /// vertices that differ by less than 32-bit rounding in a binary file).
    #[error(
        "triangle {triangle} (counting from 1) would be unreadable as {format:?} STL: {reason} \
         (coordinates in m)"
    )]
    Unreadable {
        /// The triangle, counted from 1.
        triangle: usize,
        /// The format being written.
        format: Format,
        /// The defect, as the reader would report it.
        reason: String,
    },
    /// A solid name the ASCII reader would not read back as written.
    #[error("solid name `{name}` cannot be written to ASCII STL: {reason}")]
    Name {
        /// The name given.
        name: String,
        /// Why not.
        reason: &'static str,
    },
}
