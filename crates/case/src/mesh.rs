//! A container of the user's own STL walls (`geometry.kind = "mesh"`, docs/physics.md §5.8):
//! a list of STL files, each mapped to metres by a scale, a rotation and a translation; an
//! orifice in the plane z = 0 given as a disc or a rectangle; and a box the fill is poured into.
//!
//! Conventions: z is vertical and z = 0 is the orifice plane, where the crossings are counted and
//! the gate closes the orifice until the discharge; the walls stand above it. Nothing checks that
//! the walls enclose anything (an open mesh has no inside): the user's fill box must lie inside
//! the walls, and resolving the case refuses one that cuts any triangle.

use std::path::PathBuf;
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::wall_surface::{DEFAULT_MESH_SEGMENTS, MESH_SEGMENTS_RANGE};

/// Most STL files of one case (each is a wall with a row in `wall_forces.csv`).
pub const MAX_MESH_WALLS: usize = 64;

/// One STL file of a mesh container and the map from its units to metres:
/// p = translate + R(rotate_axis, rotate_deg) · (scale · p_file) (the `stl` crate's order).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MeshWall {
    /// The wall's name in `wall_forces.csv` (default: the file's stem).
    pub name: String,
    /// The STL file, absolute (a relative path in a case file is taken from the case file's
    /// folder when it is read, and written back absolute).
    pub file: PathBuf,
    /// Hex SHA-256 of the file's bytes when it was read; a case that gives one refuses a file
    /// that has changed since.
    pub sha256: String,
    /// Metres per file unit (0.001 for a file in millimetres).
    pub scale: f64,
    /// Rotation axis (any length, not zero), as given.
    pub rotate_axis: [f64; 3],
    /// Rotation angle about the axis [°], right-hand rule.
    pub rotate_deg: f64,
    /// Translation applied last [m].
    pub translate: [f64; 3],
    /// The triangles in metres, read from the file when the case was resolved (not part of the
    /// serialised case: the file is).
    #[serde(skip)]
    pub triangles: Arc<Vec<[glam::DVec3; 3]>>,
}

/// The orifice of a mesh container, in the plane z = 0.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", tag = "shape")]
pub enum MeshOutlet {
    /// A disc; the gate is the regular polygon of `segments` sides circumscribing it.
    Disc {
        /// Centre (x, y) [m].
        centre: [f64; 2],
        /// Radius [m].
        radius: f64,
        /// Sides of the gate's polygon.
        segments: usize,
    },
    /// A rectangle with sides along x and y; the gate is the rectangle itself.
    Rectangle {
        /// Centre (x, y) [m].
        centre: [f64; 2],
        /// Side lengths (along x, along y) [m].
        size: [f64; 2],
    },
}

impl MeshOutlet {
    /// The default number of sides of a disc's gate polygon.
    pub const DEFAULT_SEGMENTS: usize = DEFAULT_MESH_SEGMENTS;
    /// The allowed numbers of sides.
    pub const SEGMENTS_RANGE: (i64, i64) = MESH_SEGMENTS_RANGE;

    /// The orifice's centre (x, y) [m].
    pub fn centre(&self) -> [f64; 2] {
        match self {
            Self::Disc { centre, .. } | Self::Rectangle { centre, .. } => *centre,
        }
    }

    /// Its size D [m]: the disc's diameter, the rectangle's side along x (the profiles' axis).
    pub fn size(&self) -> f64 {
        match self {
            Self::Disc { radius, .. } => 2.0 * radius,
            Self::Rectangle { size, .. } => size[0],
        }
    }
}

/// A container of STL walls; see the module documentation.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MeshGeometry {
    /// The walls, in the order of the case file.
    pub walls: Vec<MeshWall>,
    /// The orifice in the plane z = 0.
    pub outlet: MeshOutlet,
    /// Lower corner of the fill box [m].
    pub fill_min: [f64; 3],
    /// Upper corner of the fill box [m]; its z is the case's H.
    pub fill_max: [f64; 3],
}

impl MeshGeometry {
    /// Whether a sphere of radius `r` [m] centred at (x, y, z) lies in the fill box with
    /// clearance `gap` [m] on every side.
    pub fn holds(&self, x: f64, y: f64, z: f64, r: f64, gap: f64) -> bool {
        let c = r + gap;
        [x, y, z]
            .iter()
            .zip(self.fill_min.iter().zip(&self.fill_max))
            .all(|(&v, (&lo, &hi))| v - c >= lo && v + c <= hi)
    }

    /// The lowest and highest corners of all the walls' triangles [m].
    pub fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for t in self.walls.iter().flat_map(|w| w.triangles.iter()) {
            for p in t {
                for k in 0..3 {
                    lo[k] = lo[k].min(p[k]);
                    hi[k] = hi[k].max(p[k]);
                }
            }
        }
        (lo, hi)
    }
}

/// Whether the closed box [`lo`, `hi`] [m] and the triangle `t` [m] share a point: the
/// separating-axis test of Akenine-Möller (2001) on the box's three axes, the triangle's normal
/// and the nine cross products of their edges. Exact up to the rounding of the products; a
/// triangle that merely touches the box counts as overlapping.
pub fn box_meets_triangle(lo: [f64; 3], hi: [f64; 3], t: &[glam::DVec3; 3]) -> bool {
    use glam::DVec3;
    let centre = DVec3::from(lo).lerp(DVec3::from(hi), 0.5);
    let half = (DVec3::from(hi) - DVec3::from(lo)) * 0.5;
    let v = [t[0] - centre, t[1] - centre, t[2] - centre];
    let edges = [v[1] - v[0], v[2] - v[1], v[0] - v[2]];
    let separates = |axis: DVec3| {
        if axis.length_squared() == 0.0 {
            return false;
        }
        let p = v.map(|q| q.dot(axis));
        let reach = half.x * axis.x.abs() + half.y * axis.y.abs() + half.z * axis.z.abs();
        let (min, max) = (p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2]));
        min > reach || max < -reach
    };
    let axes = [DVec3::X, DVec3::Y, DVec3::Z];
    if axes.iter().any(|&a| separates(a)) {
        return false;
    }
    if separates(edges[0].cross(edges[1])) {
        return false;
    }
    !axes
        .iter()
        .any(|&a| edges.iter().any(|&e| separates(a.cross(e))))
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    /// A triangle inside, one crossing a face, one beside the box and one just off a corner
    /// along a diagonal (only an edge cross product separates it).
    #[test]
    fn box_triangle_overlap() {
        let (lo, hi) = ([0.0; 3], [1.0; 3]);
        let t = |a: [f64; 3], b: [f64; 3], c: [f64; 3]| [a, b, c].map(DVec3::from);
        assert!(box_meets_triangle(
            lo,
            hi,
            &t([0.2, 0.2, 0.5], [0.8, 0.2, 0.5], [0.5, 0.8, 0.5])
        ));
        assert!(box_meets_triangle(
            lo,
            hi,
            &t([-1.0, -1.0, 0.5], [3.0, -1.0, 0.5], [-1.0, 3.0, 0.5])
        ));
        assert!(!box_meets_triangle(
            lo,
            hi,
            &t([1.5, 0.0, 0.0], [2.5, 0.0, 0.0], [1.5, 1.0, 1.0])
        ));
        // The plane x + y = 2.1 misses the box's corner (1, 1): separated by the normal.
        assert!(!box_meets_triangle(
            lo,
            hi,
            &t([2.1, 0.0, -1.0], [0.0, 2.1, -1.0], [1.05, 1.05, 3.0])
        ));
        // An edge along x + y = 2.1 in z = 0.5, just off the box's edge x = y = 1, in a plane
        // rising away from it that cuts the box: neither the face axes nor the normal separate
        // it, the cross product of the z axis and that edge does.
        assert!(!box_meets_triangle(
            lo,
            hi,
            &t([2.0, 0.1, 0.5], [0.1, 2.0, 0.5], [3.0, 3.0, 10.0])
        ));
        // Touching a face counts.
        assert!(box_meets_triangle(
            lo,
            hi,
            &t([1.0, 0.2, 0.2], [1.0, 0.8, 0.2], [1.0, 0.5, 0.8])
        ));
    }
}
