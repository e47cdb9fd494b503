//! The closest point of a triangle to a point, and which feature of the triangle holds it:
//! its face, one of its edges or one of its corners (docs/physics.md §5.3). A mesh wall
//! uses the feature to count a contact once where several triangles share an edge or a
//! corner.

use glam::DVec3;

/// The part of a triangle that holds a closest point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Feature {
    /// The open face: the closest point lies strictly inside the triangle.
    Face,
    /// Edge k, from corner k to corner (k + 1) mod 3, without its end points.
    Edge(u8),
    /// Corner k.
    Corner(u8),
}

/// Closest point of triangle `[a, b, c]` to `x`, and its feature.
///
/// Regions of the triangle's plane by barycentric coordinates (Ericson, *Real-Time
/// Collision Detection*, §5.1.5): the corner regions first, then the edge regions, then the
/// face. A point whose projection lies exactly on an edge line gets the edge, not the face,
/// so that two coplanar triangles sharing that edge report the same feature and the same
/// point, which the mesh then counts once. A degenerate triangle (refused at mesh
/// construction) would divide by zero; callers never pass one.
#[inline]
pub fn closest_point(x: DVec3, [a, b, c]: [DVec3; 3]) -> (DVec3, Feature) {
    let (ab, ac, ap) = (b - a, c - a, x - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, Feature::Corner(0));
    }
    let bp = x - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return (b, Feature::Corner(1));
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let t = d1 / (d1 - d3);
        return (a + t * ab, Feature::Edge(0));
    }
    let cp = x - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return (c, Feature::Corner(2));
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let t = d2 / (d2 - d6);
        return (a + t * ac, Feature::Edge(2));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (b + t * (c - b), Feature::Edge(1));
    }
    let denom = 1.0 / (va + vb + vc);
    let (v, w) = (vb * denom, vc * denom);
    (a + v * ab + w * ac, Feature::Face)
}

/// Twice the area of triangle `[a, b, c]` [m²], and its unit normal by the right-hand rule
/// (zero for a degenerate triangle).
pub fn area2_and_normal([a, b, c]: [DVec3; 3]) -> (f64, DVec3) {
    let n = (b - a).cross(c - a);
    let len = n.length();
    (len, if len > 0.0 { n / len } else { DVec3::ZERO })
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const T: [DVec3; 3] = [
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(1.0, 0.0, 0.0),
        DVec3::new(0.0, 1.0, 0.0),
    ];

    #[test]
    fn each_region_gives_its_feature_and_point() {
        // Exact coordinates: every case lands on representable numbers.
        let cases = [
            (
                DVec3::new(0.25, 0.25, 1.0),
                DVec3::new(0.25, 0.25, 0.0),
                Feature::Face,
            ),
            (
                DVec3::new(0.5, -1.0, 0.5),
                DVec3::new(0.5, 0.0, 0.0),
                Feature::Edge(0),
            ),
            (
                DVec3::new(1.0, 1.0, 0.0),
                DVec3::new(0.5, 0.5, 0.0),
                Feature::Edge(1),
            ),
            (
                DVec3::new(-1.0, 0.5, 0.0),
                DVec3::new(0.0, 0.5, 0.0),
                Feature::Edge(2),
            ),
            (DVec3::new(-1.0, -1.0, 2.0), DVec3::ZERO, Feature::Corner(0)),
            (DVec3::new(3.0, -0.5, 0.0), DVec3::X, Feature::Corner(1)),
            (DVec3::new(-0.5, 3.0, -1.0), DVec3::Y, Feature::Corner(2)),
        ];
        for (x, p, f) in cases {
            assert_eq!(closest_point(x, T), (p, f), "query {x}");
        }
    }

    #[test]
    fn a_projection_on_an_edge_line_is_the_edge_for_both_triangles_sharing_it() {
        // Two coplanar triangles on either side of the edge x + y = 1; a point straight
        // above the shared edge must give both the same point, so the mesh counts it once.
        let other = [DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
        let x = DVec3::new(0.5, 0.5, 0.3);
        let (p, f) = closest_point(x, T);
        let (q, g) = closest_point(x, other);
        assert_eq!(f, Feature::Edge(1));
        assert_eq!(g, Feature::Edge(2));
        assert_eq!(p, q);
    }

    fn brute(x: DVec3, [a, b, c]: [DVec3; 3]) -> f64 {
        // Dense barycentric sampling: the smallest distance over 200² points of the triangle.
        let n = 200;
        let mut best = f64::INFINITY;
        for i in 0..=n {
            for j in 0..=(n - i) {
                let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
                best = best.min((a + u * (b - a) + v * (c - a)).distance(x));
            }
        }
        best
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]
        #[test]
        fn the_closest_point_is_no_farther_than_any_sampled_point(
            x in prop::array::uniform3(-2.0f64..2.0),
            v in prop::array::uniform3(prop::array::uniform3(-1.0f64..1.0)),
        ) {
            let tri = v.map(DVec3::from_array);
            prop_assume!(area2_and_normal(tri).0 > 1e-3);
            let x = DVec3::from_array(x);
            let (p, _) = closest_point(x, tri);
            // The sample grid's spacing is 1/200 of the edges (< 0.02 here): the exact
            // point is never farther than the best sample and at most that much closer.
            let d = p.distance(x);
            let b = brute(x, tri);
            prop_assert!(d <= b + 1e-12);
            prop_assert!(d >= b - 0.02);
            // The point lies in the triangle's plane.
            let (_, n) = area2_and_normal(tri);
            prop_assert!((p - tri[0]).dot(n).abs() < 1e-12);
        }
    }
}
