//! The outline of a container's walls in a vertical plane y = const: what the frames of a
//! vertical cut draw (docs/physics.md §5.7–5.8).

/// Segments (x, z) [m] where the plane y = `y` cuts the convex planar `polygons` [m]: each
/// polygon that the plane crosses gives the segment between the two points where its edges
/// cross it. Polygons lying in the plane, or touching it at a corner only, give none.
pub fn vertical_cut(polygons: &[Vec<[f64; 3]>], y: f64) -> Vec<[(f64, f64); 2]> {
    let mut segments = Vec::new();
    for polygon in polygons {
        let mut points: Vec<(f64, f64)> = Vec::with_capacity(2);
        for (k, a) in polygon.iter().enumerate() {
            let b = polygon[(k + 1) % polygon.len()];
            let (da, db) = (a[1] - y, b[1] - y);
            // An edge crosses the plane when its ends lie on opposite sides; an end on the
            // plane counts for the edge that leaves it, so each crossing is found once.
            if (da <= 0.0 && db > 0.0) || (da > 0.0 && db <= 0.0) {
                let s = da / (da - db);
                points.push((a[0] + s * (b[0] - a[0]), a[2] + s * (b[2] - a[2])));
            }
        }
        if let [p, q] = points[..] {
            if p != q {
                segments.push([p, q]);
            }
        }
    }
    segments
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A square across the plane gives its chord; one beside it or in it gives nothing.
    #[test]
    fn squares_cut_by_the_plane() {
        let across = vec![
            [0.0, -1.0, 0.0],
            [1.0, -1.0, 0.0],
            [1.0, 1.0, 1.0],
            [0.0, 1.0, 1.0],
        ];
        let cut = vertical_cut(&[across], 0.0);
        assert_eq!(cut, vec![[(1.0, 0.5), (0.0, 0.5)]]);
        let beside = vec![[0.0, 1.0, 0.0], [1.0, 1.0, 0.0], [1.0, 2.0, 0.0]];
        let within = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 0.0, 1.0]];
        assert!(vertical_cut(&[beside, within], 0.0).is_empty());
    }
}
