//! STL triangle meshes for wall geometry: a reader for ASCII and binary STL whose errors name
//! the file, the triangle, the line or record and the offending value; writers for both formats;
//! and builders of simple tessellated surfaces.
//!
//! The DEM engine sees no files: it takes plain triangles, `Vec<[DVec3; 3]>` in metres. This
//! crate turns a file into such triangles ([`read`], [`parse`]) and triangles back into a file
//! ([`write_binary`], [`write_ascii`]).
//!
//! # Formats
//!
//! - **ASCII STL**: `solid [name]`, then facets
//!   `facet normal nx ny nz / outer loop / vertex x y z (three times) / endloop / endfacet`,
//!   then `endsolid [name]`. Keywords are matched without regard to case; tokens are separated
//!   by any ASCII white space. Several `solid … endsolid` blocks in one file are read one after
//!   the other, and the name kept is the first block's.
//! - **Binary STL**: an 80-byte header (ignored), a little-endian `u32` triangle count `n`, then
//!   `n` records of 50 bytes: normal (3 × `f32`), three vertices (9 × `f32`), a `u16` attribute
//!   (ignored). The file is exactly `84 + 50·n` bytes.
//!
//! **Which format.** A file whose size is exactly `84 + 50·n`, with `n` read from bytes 80..84,
//! is binary, even when its header begins with `solid` (many exporters write that). An ASCII
//! file cannot meet this rule below 7.5 GB: bytes 80..84 of ASCII text are printable characters
//! or white space, so `n ≥ 0x0909_0909` and the size rule would ask for more than 7.5·10⁹ bytes.
//! Any other file is ASCII if it begins with `solid` (after optional white space and a UTF-8
//! byte-order mark) and is text throughout (valid UTF-8 without control characters other than
//! white space); otherwise the error says why it is neither.
//!
//! **Normals are ignored.** The normal written in each facet plays no part in the geometry: the
//! vertex order defines the triangle's normal (right-hand rule, counter-clockwise seen from the
//! side it points to), and many exporters write zero or wrong normals. They are parsed only as
//! part of the syntax, any value is accepted, and nothing is reported about them.
//!
//! # Transform
//!
//! Coordinates in the file are in file units. A [`Transform`] maps them to metres in this
//! order: multiply by `scale` (e.g. 0.001 for a file in millimetres), rotate by `angle` radians
//! about `axis` (right-hand rule), then add `translation` [m]:
//! `p_m = translation + R(axis, angle) · (scale · p_file)`.
//!
//! # Validation
//!
//! Reading stops at the first problem with a [`StlError`]; none of them panics, whatever the
//! bytes. Triangles and vertices are counted from 1 in every message (the first triangle of the
//! file is "triangle 1"); ASCII problems give the line, binary ones the byte offset of the
//! 50-byte record. Rejected:
//!
//! - an empty file, a file that is neither format, a binary file whose size is not
//!   `84 + 50·n` (expected and actual sizes are given), a binary file declaring `n = 0`;
//! - ASCII syntax: an unexpected keyword, a missing keyword (`vertex`, `endloop`, …), fewer or
//!   more than 3 numbers after `vertex` or `normal`, an unreadable number (the token is quoted),
//!   a facet with other than 3 vertices, a file that ends before `endsolid`, a file with no
//!   facet;
//! - a vertex coordinate that is NaN or infinite (either format);
//! - a triangle with two equal vertices, or a degenerate one: with `L` its longest edge, the
//!   area must satisfy `area ≥ DEGENERACY_RATIO · L²` (1e-12; an equilateral triangle has
//!   `area/L² ≈ 0.433`). The criterion depends only on the triangle's shape, not its size or
//!   position, so it is applied to the coordinates as written in the file, which the message
//!   quotes; below it the normal computed from the vertices is dominated by rounding;
//! - a triangle with an edge beyond the double range (vertices of opposite sign near
//!   ±1.8e308), whose shape cannot be measured;
//! - a vertex that is no longer finite after the transform (an overflowing scale).
//!
//! # Writing and building
//!
//! [`write_ascii`] prints the shortest decimals that read back to the same `f64`;
//! [`write_binary`] rounds to `f32` (relative error ≤ 2⁻²⁴ ≈ 6e-8). Both refuse, before
//! writing, what the reader would reject, including triangles that `f32` rounding collapses.
//! [`shapes`] builds a floor of many triangles, a closed box and the sides of a cylinder and a
//! cone frustum, for engine tests and simple walls.

// Units are written in brackets, e.g. `[m]`, as the project style asks; rustdoc would
// otherwise read them as links.
#![allow(rustdoc::broken_intra_doc_links)]
#![warn(missing_docs)]

mod ascii;
mod binary;
mod check;
mod closed;
mod detect;
mod error;
mod mesh;
mod read;
pub mod shapes;
mod tokens;
mod transform;
mod write;

pub use check::DEGENERACY_RATIO;
pub use closed::{check_closed, enclosed_volume, NotClosed};
pub use error::{BinarySizeNote, Location, StlError};
pub use mesh::{Format, Mesh, Triangle};
pub use read::{parse, read};
pub use transform::{Transform, TransformError};
pub use write::{write_ascii, write_binary, WriteError};
