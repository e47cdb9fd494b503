//! The result of reading an STL file: triangles in metres and what the file said about itself.

use glam::DVec3;

/// One triangle: three vertices [m] whose order defines the normal by the right-hand rule,
/// `(v1 − v0) × (v2 − v0)`.
pub type Triangle = [DVec3; 3];

/// Which of the two STL encodings a file used.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Text: `solid … facet … endsolid`.
    Ascii,
    /// 80-byte header, triangle count, 50-byte records.
    Binary,
}

/// A triangle mesh read from an STL file, after the [`crate::Transform`].
#[derive(Debug, Clone, PartialEq)]
pub struct Mesh {
    /// The triangles in file order, vertices in metres [m], vertex order as in the file.
    pub triangles: Vec<Triangle>,
    /// The name after `solid` in an ASCII file (the first block's); `None` when it is empty
    /// and for binary files, whose header is free-form bytes.
    pub name: Option<String>,
    /// The encoding the file used.
    pub format: Format,
}
