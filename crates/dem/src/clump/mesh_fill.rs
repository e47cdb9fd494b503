//! A clump that fills a closed triangle mesh: spheres inscribed in the body, added greedily
//! until they cover all but a stated fraction of its volume (docs/physics.md §11.6).
//!
//! The body is sampled on a grid of cubic cells; each cell centre inside the mesh (by its
//! winding number, the sum of the triangles' solid angles over 4π, Van Oosterom and Strackee
//! 1983, IEEE Trans. Biomed. Eng. 30, 125) gets its distance to the surface, the radius of the
//! largest sphere centred there that stays inside. Then, as in the inscribed-sphere methods of
//! Ferellec and McDowell (2010, Granular Matter 12, 459), the uncovered centre farthest from
//! the surface takes a sphere of that radius, which covers every centre within it, until the
//! covered centres make up the asked fraction of the inside ones. Every sphere lies inside
//! the mesh, so the clump never bulges out of the body; it falls short of it by the uncovered
//! fraction and by the grid's resolution, and [`FilledMesh`] reports the shortfall measured
//! exactly: the union's volume (§11.2) against the mesh's (the divergence theorem).

use glam::DVec3;

use super::{union_moments, ClumpError, ClumpShape};
use crate::wall::triangle::closest_point;

/// A mesh filled with spheres, and how well.
#[derive(Debug, Clone, PartialEq)]
pub struct FilledMesh {
    /// The spheres, as a clump in the mesh's frame.
    pub shape: ClumpShape,
    /// The volume the mesh encloses [m³].
    pub mesh_volume: f64,
    /// The volume of the spheres' union [m³].
    pub union_volume: f64,
}

/// The most spheres a filled mesh may take.
pub const MAX_FILL_SPHERES: usize = 512;

/// Fills the closed mesh `triangles` (counter-clockwise seen from outside) on a grid of
/// `cells` cells along its longest side, until the spheres cover at least `1 − shortfall` of
/// the inside cell centres (`shortfall` in (0, 1)) or [`MAX_FILL_SPHERES`] are placed.
pub fn fill_mesh(
    triangles: &[[DVec3; 3]],
    cells: usize,
    shortfall: f64,
) -> Result<FilledMesh, ClumpError> {
    let lo = triangles
        .iter()
        .flatten()
        .fold(DVec3::splat(f64::INFINITY), |m, &v| m.min(v));
    let hi = triangles
        .iter()
        .flatten()
        .fold(DVec3::splat(f64::NEG_INFINITY), |m, &v| m.max(v));
    let h = (hi - lo).max_element() / cells.max(1) as f64;
    if triangles.is_empty() || !(h > 0.0 && h.is_finite()) {
        return Err(ClumpError::Empty);
    }
    let counts = ((hi - lo) / h).ceil().max(DVec3::ONE);
    let (nx, ny, nz) = (counts.x as usize, counts.y as usize, counts.z as usize);
    // Inside cell centres and their distances to the surface.
    let mut inside: Vec<(DVec3, f64)> = Vec::new();
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                let x = lo + DVec3::new(i as f64 + 0.5, j as f64 + 0.5, k as f64 + 0.5) * h;
                if winding_number(triangles, x) > 0.5 {
                    let d = triangles
                        .iter()
                        .map(|&t| x.distance(closest_point(x, t).0))
                        .fold(f64::INFINITY, f64::min);
                    inside.push((x, d));
                }
            }
        }
    }
    if inside.is_empty() {
        return Err(ClumpError::Empty);
    }
    let mut covered = vec![false; inside.len()];
    let mut left = inside.len();
    let wanted = ((1.0 - shortfall.clamp(0.0, 1.0)) * inside.len() as f64).ceil() as usize;
    let mut spheres = Vec::new();
    while inside.len() - left < wanted && spheres.len() < MAX_FILL_SPHERES {
        // The uncovered centre farthest from the surface (the first of equals, in grid order).
        let Some((best, _)) = inside
            .iter()
            .enumerate()
            .filter(|(k, _)| !covered[*k])
            .max_by(|a, b| a.1 .1.total_cmp(&b.1 .1).then(b.0.cmp(&a.0)))
        else {
            break;
        };
        let (c, r) = inside[best];
        for (k, &(x, _)) in inside.iter().enumerate() {
            if !covered[k] && x.distance_squared(c) <= r * r {
                covered[k] = true;
                left -= 1;
            }
        }
        if !covered[best] {
            // A centre on the surface (distance 0) covers only itself.
            covered[best] = true;
            left -= 1;
        }
        if r > 0.0 {
            spheres.push((c, r));
        }
    }
    let union_volume = union_moments(&spheres).volume;
    let shape = ClumpShape::new(spheres)?;
    Ok(FilledMesh {
        shape,
        mesh_volume: mesh_volume(triangles),
        union_volume,
    })
}

/// The winding number of the closed mesh about `x`: 1 inside, 0 outside (Σ solid angles/4π,
/// each by Van Oosterom and Strackee's formula tan(Ω/2) = a·(b × c) / (|a||b||c| + (a·b)|c| +
/// (a·c)|b| + (b·c)|a|) with a, b, c the corners from x).
fn winding_number(triangles: &[[DVec3; 3]], x: DVec3) -> f64 {
    let mut total = 0.0;
    for &[p, q, s] in triangles {
        let (a, b, c) = (p - x, q - x, s - x);
        let (la, lb, lc) = (a.length(), b.length(), c.length());
        let num = a.dot(b.cross(c));
        let den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
        total += 2.0 * num.atan2(den);
    }
    total / (4.0 * std::f64::consts::PI)
}

/// The volume the closed mesh encloses [m³]: Σ a·(b × c)/6 over its triangles.
fn mesh_volume(triangles: &[[DVec3; 3]]) -> f64 {
    triangles
        .iter()
        .map(|&[a, b, c]| a.dot(b.cross(c)) / 6.0)
        .sum::<f64>()
        .abs()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The 12 triangles of the box [0, a] × [0, b] × [0, c], counter-clockwise from outside.
    fn cuboid(a: f64, b: f64, c: f64) -> Vec<[DVec3; 3]> {
        let v = |i: u8| {
            DVec3::new(
                if i & 1 != 0 { a } else { 0.0 },
                if i & 2 != 0 { b } else { 0.0 },
                if i & 4 != 0 { c } else { 0.0 },
            )
        };
        let quads = [
            [0, 2, 3, 1], // z = 0, normal −z
            [4, 5, 7, 6], // z = c
            [0, 1, 5, 4], // y = 0
            [2, 6, 7, 3], // y = b
            [0, 4, 6, 2], // x = 0
            [1, 3, 7, 5], // x = a
        ];
        quads
            .iter()
            .flat_map(|q| [[v(q[0]), v(q[1]), v(q[2])], [v(q[0]), v(q[2]), v(q[3])]])
            .collect()
    }

    #[test]
    fn the_winding_number_and_the_volume_of_a_box_are_exact() {
        let box3 = cuboid(3.0, 1.0, 2.0);
        assert!((mesh_volume(&box3) - 6.0).abs() <= 1e-12);
        assert!((winding_number(&box3, DVec3::new(1.0, 0.5, 1.0)) - 1.0).abs() <= 1e-12);
        assert!(winding_number(&box3, DVec3::new(4.0, 0.5, 1.0)).abs() <= 1e-12);
    }

    #[test]
    fn a_filled_box_stays_inside_covers_most_of_it_and_keeps_its_long_axis() {
        // A 3 × 1 × 1 box, 30 cells along its length, 85 % of its inside centres covered:
        // every sphere inside the box, the union at least 70 % of the box's volume (the corners
        // and edges that spheres cannot reach, and the grid), and the clump's smallest moment
        // about x, the box's long axis.
        let box3 = cuboid(3.0, 1.0, 1.0);
        let filled = fill_mesh(&box3, 30, 0.15).expect("filled");
        for &(c, r) in filled.shape.members() {
            let clearance = c
                .min_element()
                .min((DVec3::new(3.0, 1.0, 1.0) - c).min_element());
            assert!(clearance >= r - 1e-12, "{c} {r}");
        }
        let ratio = filled.union_volume / filled.mesh_volume;
        assert!((0.7..=1.0).contains(&ratio), "{ratio}");
        let body = filled.shape.body(1.0);
        let long = body.axes * DVec3::X;
        assert!(long.x.abs() > 0.999, "{long}");
        // Asking for more coverage takes more spheres and covers more.
        let finer = fill_mesh(&box3, 30, 0.05).expect("filled");
        assert!(finer.shape.members().len() > filled.shape.members().len());
        assert!(finer.union_volume > filled.union_volume);
    }
}
