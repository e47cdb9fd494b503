//! The mesh builders: closed-form areas and volumes, orientation, and argument checks.

use std::collections::HashMap;
use std::f64::consts::PI;

use glam::DVec3;
use stl::shapes::{axis_aligned_box, cylinder_side, flipped, frustum_side, rectangle};
use stl::{parse, write_ascii, Transform, Triangle};

/// Relative tolerance of sums over at most a few thousand triangles: each term is exact to a
/// few ulps (1e-16), and their sum to a few hundred times that.
const SUM_TOLERANCE: f64 = 1e-12;

fn area(t: &Triangle) -> f64 {
    0.5 * (t[1] - t[0]).cross(t[2] - t[0]).length()
}

fn normal(t: &Triangle) -> DVec3 {
    (t[1] - t[0]).cross(t[2] - t[0])
}

/// Volume enclosed by a closed, outward-oriented surface (divergence theorem): Σ a·(b×c)/6.
fn signed_volume(triangles: &[Triangle]) -> f64 {
    triangles
        .iter()
        .map(|[a, b, c]| a.dot(b.cross(*c)))
        .sum::<f64>()
        / 6.0
}

/// How often each directed edge occurs, keyed by the bits of its two end points.
fn directed_edges(triangles: &[Triangle]) -> HashMap<([u64; 3], [u64; 3]), usize> {
    let key = |p: DVec3| p.to_array().map(f64::to_bits);
    let mut edges = HashMap::new();
    for t in triangles {
        for k in 0..3 {
            *edges.entry((key(t[k]), key(t[(k + 1) % 3]))).or_insert(0) += 1;
        }
    }
    edges
}

/// Checks consistent orientation: no directed edge twice; returns how many edges are on the
/// boundary (their reverse does not occur).
fn boundary_edges(triangles: &[Triangle]) -> usize {
    let edges = directed_edges(triangles);
    assert!(
        edges.values().all(|&n| n == 1),
        "a directed edge occurs twice"
    );
    edges
        .keys()
        .filter(|(a, b)| !edges.contains_key(&(*b, *a)))
        .count()
}

fn readable(triangles: &[Triangle]) -> bool {
    let mut bytes = Vec::new();
    write_ascii(&mut bytes, triangles, "shape").unwrap();
    parse(&bytes, "shape.stl", &Transform::identity())
        .unwrap()
        .triangles
        == triangles
}

#[test]
fn box_volume_by_the_divergence_theorem() {
    let (min, max) = (DVec3::new(-0.1, 0.2, 0.3), DVec3::new(0.4, 0.5, 0.9));
    let triangles = axis_aligned_box(min, max).unwrap();
    assert_eq!(triangles.len(), 12);
    let size = max - min;
    approx::assert_relative_eq!(
        signed_volume(&triangles),
        size.x * size.y * size.z,
        max_relative = SUM_TOLERANCE
    );
    // Reversing every triangle reverses the sign: the volume really depends on orientation.
    approx::assert_relative_eq!(
        signed_volume(&flipped(&triangles)),
        -size.x * size.y * size.z,
        max_relative = SUM_TOLERANCE
    );
}

#[test]
fn box_is_closed_with_outward_normals() {
    let (min, max) = (DVec3::ZERO, DVec3::new(1.0, 2.0, 3.0));
    let triangles = axis_aligned_box(min, max).unwrap();
    assert_eq!(
        boundary_edges(&triangles),
        0,
        "closed: every edge in both directions"
    );
    let centre = 0.5 * (min + max);
    for t in &triangles {
        let centroid = (t[0] + t[1] + t[2]) / 3.0;
        assert!(
            normal(t).dot(centroid - centre) > 0.0,
            "{t:?} points inward"
        );
    }
    let total: f64 = triangles.iter().map(area).sum();
    approx::assert_relative_eq!(total, 2.0 * (2.0 + 3.0 + 6.0), max_relative = SUM_TOLERANCE);
    assert!(readable(&triangles));
}

#[test]
fn floor_of_small_triangles() {
    let (u, v) = (DVec3::new(0.2, 0.0, 0.0), DVec3::new(0.0, 0.1, 0.0));
    let (n, m) = (20, 10);
    let triangles = rectangle(DVec3::new(0.0, 0.0, -0.05), u, v, n, m).unwrap();
    assert_eq!(triangles.len(), 2 * n * m);
    let total: f64 = triangles.iter().map(area).sum();
    approx::assert_relative_eq!(total, 0.2 * 0.1, max_relative = SUM_TOLERANCE);
    for t in &triangles {
        assert!(normal(t).dot(u.cross(v)) > 0.0);
        assert!(t.iter().all(|p| p.z == -0.05), "flat");
    }
    // Interior edges once in each direction; the outline's 2(n + m) edges once.
    assert_eq!(boundary_edges(&triangles), 2 * (n + m));
    assert!(readable(&triangles));
}

#[test]
fn cylinder_side_area_and_outward_normals() {
    let (base, axis, r, k) = (
        DVec3::new(0.5, 0.0, 0.0),
        DVec3::new(0.0, 0.0, 0.3),
        0.05,
        24,
    );
    let triangles = cylinder_side(base, axis, r, k).unwrap();
    assert_eq!(triangles.len(), 2 * k);
    // k flat rectangles of chord 2r·sin(π/k) and height |axis|.
    let expected = k as f64 * 2.0 * r * (PI / k as f64).sin() * axis.length();
    let total: f64 = triangles.iter().map(area).sum();
    approx::assert_relative_eq!(total, expected, max_relative = SUM_TOLERANCE);
    for t in &triangles {
        let centroid = (t[0] + t[1] + t[2]) / 3.0;
        let radial = centroid - base - axis * (centroid - base).dot(axis) / axis.length_squared();
        assert!(
            normal(t).dot(radial) > 0.0,
            "normal points away from the axis"
        );
    }
    for p in triangles.iter().flatten() {
        let off_axis = (*p - base).reject_from(axis).length();
        // Points on the circle up to the rounding of r·(cos u + sin w).
        approx::assert_relative_eq!(off_axis, r, max_relative = 1e-14);
    }
    // Open: the two rings of k edges each are the boundary.
    assert_eq!(boundary_edges(&triangles), 2 * k);
    assert!(readable(&triangles));
}

#[test]
fn frustum_side_area() {
    let (h, rb, rt, k) = (0.4, 0.02, 0.15, 32);
    let triangles = frustum_side(DVec3::ZERO, DVec3::new(0.0, 0.0, h), rb, rt, k).unwrap();
    assert_eq!(triangles.len(), 2 * k);
    // k planar isosceles trapezoids: parallel chords 2r·sin(π/k), apart by the distance of
    // their midpoints, √(h² + ((rt − rb)·cos(π/k))²).
    let half = PI / k as f64;
    let slant = (h * h + ((rt - rb) * half.cos()).powi(2)).sqrt();
    let expected = k as f64 * (rb + rt) * half.sin() * slant;
    let total: f64 = triangles.iter().map(area).sum();
    approx::assert_relative_eq!(total, expected, max_relative = SUM_TOLERANCE);
    assert_eq!(boundary_edges(&triangles), 2 * k);
    assert!(readable(&triangles));
}

#[test]
fn cone_sides_have_one_triangle_per_segment() {
    let (h, r, k) = (0.3, 0.1, 12);
    let half = PI / k as f64;
    let expected = k as f64 * r * half.sin() * (h * h + (r * half.cos()).powi(2)).sqrt();
    for (rb, rt) in [(r, 0.0), (0.0, r)] {
        let triangles = frustum_side(DVec3::ZERO, DVec3::new(0.0, 0.0, h), rb, rt, k).unwrap();
        assert_eq!(triangles.len(), k);
        let total: f64 = triangles.iter().map(area).sum();
        approx::assert_relative_eq!(total, expected, max_relative = SUM_TOLERANCE);
        // Only the ring is boundary; the apex is shared by all.
        assert_eq!(boundary_edges(&triangles), k);
        for t in &triangles {
            let centroid = (t[0] + t[1] + t[2]) / 3.0;
            assert!(normal(t).dot(DVec3::new(centroid.x, centroid.y, 0.0)) > 0.0);
        }
    }
}

#[test]
fn bad_arguments_are_named() {
    let cases = [
        (
            cylinder_side(DVec3::ZERO, DVec3::Z, 0.1, 2),
            "cylinder_side: segments = 2: must be at least 3",
        ),
        (
            cylinder_side(DVec3::ZERO, DVec3::Z, -0.1, 8),
            "cylinder_side: radius = -0.1 m: must be finite and > 0",
        ),
        (
            frustum_side(DVec3::ZERO, DVec3::ZERO, 0.1, 0.2, 8),
            "frustum_side: axis = (0, 0, 0) m: must be finite and non-zero",
        ),
        (
            frustum_side(DVec3::ZERO, DVec3::Z, 0.0, 0.0, 8),
            "frustum_side: base_radius and top_radius = 0 m: must be > 0 for at least one of them",
        ),
        (
            rectangle(DVec3::ZERO, DVec3::X, DVec3::Y, 0, 4),
            "rectangle: divisions_u = 0: must be at least 1",
        ),
        (
            rectangle(DVec3::new(f64::NAN, 0.0, 0.0), DVec3::X, DVec3::Y, 1, 1),
            "rectangle: corner = (NaN, 0, 0) m: must be finite",
        ),
        (
            rectangle(DVec3::ZERO, DVec3::X, DVec3::X, 1, 1),
            "rectangle: triangle 1 (counting from 1) would be unusable: degenerate: area / L² = \
             0e0 with longest edge L = 2; allowed: area / L² ≥ 1e-12 (coordinates in m)",
        ),
        (
            rectangle(DVec3::ZERO, DVec3::X, DVec3::Y, 100_000, 100_000),
            "rectangle: 2 × 10000000000 triangles exceed the limit of 10000000 triangles",
        ),
        (
            axis_aligned_box(DVec3::ZERO, DVec3::new(1.0, 0.0, 1.0)),
            "axis_aligned_box: max.y − min.y = 0 m: must be > 0",
        ),
    ];
    for (result, expected) in cases {
        assert_eq!(result.unwrap_err().to_string(), expected);
    }
}
