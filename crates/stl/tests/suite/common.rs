//! Shared fixtures: a small valid ASCII file, binary files built byte by byte (independently
//! of the crate's writer), and the error message of parsing some bytes.

#![allow(dead_code)]

use stl::{parse, Transform};

/// The source name every test gives to `parse`.
pub const FILE: &str = "walls.stl";

/// One right triangle in ASCII STL; line numbers: 1 `solid`, 2 `facet`, 3 `outer loop`,
/// 4–6 `vertex`, 7 `endloop`, 8 `endfacet`, 9 `endsolid`.
pub const ONE_TRIANGLE: &str = "solid wall
  facet normal 0 0 1
    outer loop
      vertex 0 0 0
      vertex 1 0 0
      vertex 0 1 0
    endloop
  endfacet
endsolid wall
";

/// `ONE_TRIANGLE` with line `line` (counted from 1) replaced by `text`.
pub fn with_line(line: usize, text: &str) -> String {
    let mut lines: Vec<&str> = ONE_TRIANGLE.lines().collect();
    lines[line - 1] = text;
    lines.join("\n") + "\n"
}

/// `ONE_TRIANGLE` without line `line` (counted from 1).
pub fn without_line(line: usize) -> String {
    let mut lines: Vec<&str> = ONE_TRIANGLE.lines().collect();
    lines.remove(line - 1);
    lines.join("\n") + "\n"
}

/// A binary STL file: `header_start` at the beginning of the 80-byte header (rest zero), the
/// count of `triangles`, then one record per triangle with a zero normal and attribute.
pub fn binary(header_start: &[u8], triangles: &[[[f32; 3]; 3]]) -> Vec<u8> {
    let mut bytes = vec![0u8; 80];
    bytes[..header_start.len()].copy_from_slice(header_start);
    bytes.extend_from_slice(&(triangles.len() as u32).to_le_bytes());
    for triangle in triangles {
        bytes.extend_from_slice(&[0u8; 12]);
        for value in triangle.iter().flatten() {
            bytes.extend_from_slice(&value.to_le_bytes());
        }
        bytes.extend_from_slice(&[0u8; 2]);
    }
    bytes
}

/// Two valid triangles for binary files.
pub const TWO_TRIANGLES: [[[f32; 3]; 3]; 2] = [
    [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
    [[1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]],
];

/// The message of the error that parsing `bytes` as [`FILE`] without transform gives; panics
/// (failing the test) if parsing succeeds.
pub fn message(bytes: &[u8]) -> String {
    match parse(bytes, FILE, &Transform::identity()) {
        Ok(mesh) => panic!("expected an error, got {} triangles", mesh.triangles.len()),
        Err(error) => error.to_string(),
    }
}
