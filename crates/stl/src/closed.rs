//! Whether a mesh bounds a solid: every edge shared by exactly two triangles that run along
//! it in opposite directions (a closed, consistently oriented surface, a 2-manifold without
//! boundary). A grain filled with spheres (`ClumpShape` from a mesh) needs an inside, which
//! an open or inconsistently wound surface does not have.

use std::collections::HashMap;

use glam::DVec3;

use super::mesh::Triangle;

/// The first defect that keeps a mesh from bounding a solid.
#[derive(Debug, Clone, PartialEq)]
pub enum NotClosed {
    /// No triangles at all.
    Empty,
    /// An edge that only one triangle has: the surface has a hole or a free border there.
    Border {
        /// The triangle, counting from 1 in file order.
        triangle: usize,
        /// The edge's two vertices [file units after the transform].
        edge: [DVec3; 2],
    },
    /// An edge run in the same direction by two triangles (one of them is wound the other
    /// way round) or shared by more than two.
    Unpaired {
        /// The second triangle that runs it, counting from 1 in file order.
        triangle: usize,
        /// The edge's two vertices.
        edge: [DVec3; 2],
    },
}

impl std::fmt::Display for NotClosed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let show = |e: &[DVec3; 2]| format!("({}) to ({})", e[0], e[1]);
        match self {
            Self::Empty => write!(f, "the mesh has no triangles"),
            Self::Border { triangle, edge } => write!(
                f,
                "not closed: the edge from {} of triangle {triangle} belongs to no other \
                 triangle (a hole or a free border)",
                show(edge)
            ),
            Self::Unpaired { triangle, edge } => write!(
                f,
                "not closed and consistently wound: triangle {triangle} runs the edge from {} \
                 in the direction another triangle already runs it (a triangle wound the \
                 wrong way, or an edge of more than two triangles)",
                show(edge)
            ),
        }
    }
}

/// Checks that `triangles` bound a solid: each directed edge run by exactly one triangle,
/// and its reverse by exactly one other. Vertices are matched exactly (by their bits), as
/// STL files repeat each shared vertex's coordinates.
pub fn check_closed(triangles: &[Triangle]) -> Result<(), NotClosed> {
    if triangles.is_empty() {
        return Err(NotClosed::Empty);
    }
    let key = |v: DVec3| [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()];
    // Each directed edge, with the triangle that runs it.
    let mut runs: HashMap<([u64; 3], [u64; 3]), usize> = HashMap::new();
    for (t, tri) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            if runs.insert((key(a), key(b)), t).is_some() {
                return Err(NotClosed::Unpaired {
                    triangle: t + 1,
                    edge: [a, b],
                });
            }
        }
    }
    for (t, tri) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            if !runs.contains_key(&(key(b), key(a))) {
                return Err(NotClosed::Border {
                    triangle: t + 1,
                    edge: [a, b],
                });
            }
        }
    }
    Ok(())
}

/// The volume a closed mesh encloses [unit³], by the divergence theorem: Σ a · (b × c) / 6
/// over its triangles; positive when they wind counter-clockwise seen from outside.
pub fn enclosed_volume(triangles: &[Triangle]) -> f64 {
    triangles
        .iter()
        .map(|[a, b, c]| a.dot(b.cross(*c)))
        .sum::<f64>()
        / 6.0
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit cube [0, 1]³ as twelve triangles wound counter-clockwise from outside.
    fn cube() -> Vec<Triangle> {
        let v = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
        let quad = |a: DVec3, b: DVec3, c: DVec3, d: DVec3| [[a, b, c], [a, c, d]];
        let (p000, p100, p110, p010) = (v(0., 0., 0.), v(1., 0., 0.), v(1., 1., 0.), v(0., 1., 0.));
        let (p001, p101, p111, p011) = (v(0., 0., 1.), v(1., 0., 1.), v(1., 1., 1.), v(0., 1., 1.));
        [
            quad(p000, p010, p110, p100), // bottom, normal −z
            quad(p001, p101, p111, p011), // top, +z
            quad(p000, p100, p101, p001), // front, −y
            quad(p010, p011, p111, p110), // back, +y
            quad(p000, p001, p011, p010), // left, −x
            quad(p100, p110, p111, p101), // right, +x
        ]
        .concat()
    }

    #[test]
    fn a_cube_is_closed_with_unit_volume_and_its_defects_are_named() {
        let closed = cube();
        assert_eq!(check_closed(&closed), Ok(()));
        assert!((enclosed_volume(&closed) - 1.0).abs() < 1e-15);
        // A face's two triangles taken away leave a hole.
        let open = closed[2..].to_vec();
        assert!(matches!(check_closed(&open), Err(NotClosed::Border { .. })));
        // One triangle wound the other way round runs its edges as its neighbours do.
        let mut flipped = closed.clone();
        flipped[5].swap(1, 2);
        assert!(matches!(
            check_closed(&flipped),
            Err(NotClosed::Unpaired { .. })
        ));
        // Wound inside out, it is closed with volume −1.
        let inverted: Vec<Triangle> = closed.iter().map(|&[a, b, c]| [a, c, b]).collect();
        assert_eq!(check_closed(&inverted), Ok(()));
        assert!((enclosed_volume(&inverted) + 1.0).abs() < 1e-15);
        assert_eq!(check_closed(&[]), Err(NotClosed::Empty));
    }
}
