//! The entry points: a file on disk or bytes in memory to a checked mesh in metres.

use std::path::Path;

use crate::ascii::parse_ascii;
use crate::binary::parse_binary;
use crate::detect::{detect, Detected};
use crate::error::StlError;
use crate::mesh::Mesh;
use crate::transform::Transform;

/// Reads the STL file at `path` (ASCII or binary), checks every triangle and maps it to metres
/// with `transform`. Errors name the file by `path` as given.
pub fn read(path: impl AsRef<Path>, transform: &Transform) -> Result<Mesh, StlError> {
    let path = path.as_ref();
    let file = path.display().to_string();
    let bytes = std::fs::read(path).map_err(|source| StlError::Io {
        file: file.clone(),
        source,
    })?;
    parse(&bytes, &file, transform)
}

/// Parses the bytes of an STL file (ASCII or binary), checks every triangle and maps it to
/// metres with `transform`. `source_name` names the bytes in error messages (a path, or a
/// description such as "wall mesh of case 3"). Never panics, whatever the bytes.
pub fn parse(bytes: &[u8], source_name: &str, transform: &Transform) -> Result<Mesh, StlError> {
    match detect(bytes, source_name)? {
        Detected::Binary { count } => parse_binary(bytes, count, source_name, transform),
        Detected::Ascii(text) => parse_ascii(text, source_name, transform),
    }
}
