//! Exact disc ∩ rectangle area against closed forms, additivity and Monte-Carlo sampling.

use measure::{overlap_area, section_radius, Disc, Rectangle};
use rand::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use std::f64::consts::PI;

const R: f64 = 1.5e-3;
// Closed-form comparisons: the routine sums a handful of asin/sqrt terms of size r², so
// round-off is a few ulps of r²; 1e-12 relative leaves three orders of magnitude of margin.
const EXACT: f64 = 1e-12;

fn disc() -> Disc {
    Disc {
        x: 0.02,
        z: -0.01,
        radius: R,
    }
}

fn relative_rectangle(x_min: f64, x_max: f64, z_min: f64, z_max: f64) -> Rectangle {
    let d = disc();
    Rectangle {
        x_min: d.x + x_min,
        x_max: d.x + x_max,
        z_min: d.z + z_min,
        z_max: d.z + z_max,
    }
}

#[test]
fn disc_fully_inside_rectangle_covers_its_whole_area() {
    let area = overlap_area(
        disc(),
        relative_rectangle(-2.0 * R, 3.0 * R, -1.1 * R, 1.0 * R),
    );
    assert!((area / (PI * R * R) - 1.0).abs() < EXACT, "{area}");
}

#[test]
fn half_plane_cut_gives_circular_segment_area() {
    for t in [-0.999, -0.7, -0.2, 0.0, 0.3, 0.5, 0.95, 0.999999] {
        let offset = t * R;
        // Everything above z = z_c + offset.
        let area = overlap_area(
            disc(),
            relative_rectangle(-5.0 * R, 5.0 * R, offset, 5.0 * R),
        );
        let segment = R * R * (offset / R).acos() - offset * (R * R - offset * offset).sqrt();
        assert!(
            (area - segment).abs() < EXACT * R * R,
            "t = {t}: {area} vs {segment}"
        );
        // The same cut along x.
        let area_x = overlap_area(
            disc(),
            relative_rectangle(offset, 5.0 * R, -5.0 * R, 5.0 * R),
        );
        assert!((area_x - segment).abs() < EXACT * R * R, "t = {t} along x");
    }
}

#[test]
fn rectangle_corner_at_centre_gives_a_quarter_disc() {
    for (x0, x1, z0, z1) in [
        (0.0, 9.0, 0.0, 9.0),
        (-9.0, 0.0, 0.0, 9.0),
        (-9.0, 0.0, -9.0, 0.0),
    ] {
        let area = overlap_area(disc(), relative_rectangle(x0 * R, x1 * R, z0 * R, z1 * R));
        assert!((area / (0.25 * PI * R * R) - 1.0).abs() < EXACT, "{area}");
    }
}

#[test]
fn rectangle_inside_disc_is_covered_entirely() {
    // Corners at distance √(0.5² + 0.6²) R = 0.78 R < R.
    let rectangle = relative_rectangle(-0.5 * R, 0.4 * R, -0.6 * R, 0.3 * R);
    let area = overlap_area(disc(), rectangle);
    assert!((area / rectangle.area() - 1.0).abs() < EXACT);
}

#[test]
fn corner_cut_matches_closed_form_of_the_quadrant_integral() {
    // Disc ∩ {x ≥ a, z ≥ b} for a, b > 0 with a² + b² < r²:
    // ∫_a^c (√(r² − x²) − b) dx, c = √(r² − b²), written out with the primitive
    // (x√(r² − x²) + r² asin(x/r))/2 — an independent evaluation of the corner area.
    let (a, b) = (0.3 * R, 0.45 * R);
    let c = (R * R - b * b).sqrt();
    let g = |x: f64| 0.5 * (x * (R * R - x * x).sqrt() + R * R * (x / R).asin());
    let expected = g(c) - g(a) - b * (c - a);
    let area = overlap_area(disc(), relative_rectangle(a, 4.0 * R, b, 4.0 * R));
    assert!(
        (area - expected).abs() < EXACT * R * R,
        "{area} vs {expected}"
    );
}

#[test]
fn touching_empty_and_degenerate_cases_give_zero() {
    let cases = [
        relative_rectangle(-R, R, R, 2.0 * R), // touches the top
        relative_rectangle(R, 2.0 * R, -R, R), // touches the right side
        relative_rectangle(0.8 * R, 2.0 * R, 0.8 * R, 2.0 * R), // corner outside the circle
        relative_rectangle(0.1 * R, 0.1 * R, -R, R), // zero width
        relative_rectangle(0.2 * R, 0.1 * R, -R, R), // reversed
    ];
    for rectangle in cases {
        // Edges placed at the circle by adding R to the centre carry one rounding of the
        // centre coordinate, which can leave a sliver of relative size ~1e-16 ⇒ area ~1e-30 r².
        let area = overlap_area(disc(), rectangle);
        assert!(
            (0.0..EXACT * R * R).contains(&area),
            "{rectangle:?}: {area}"
        );
    }
    let point = Disc {
        radius: 0.0,
        ..disc()
    };
    assert_eq!(overlap_area(point, relative_rectangle(-R, R, -R, R)), 0.0);
}

#[test]
fn grid_of_rectangles_partitions_the_disc_area_exactly() {
    // Additivity: an irregular 7 × 5 grid that covers the disc sums to π r².
    let xs = [-1.3, -0.71, -0.2, 0.0, 0.33, 0.9, 0.99, 1.4];
    let zs = [-1.2, -0.5, 0.05, 0.6, 0.97, 1.1];
    let mut total = 0.0;
    for i in 0..xs.len() - 1 {
        for j in 0..zs.len() - 1 {
            total += overlap_area(
                disc(),
                relative_rectangle(xs[i] * R, xs[i + 1] * R, zs[j] * R, zs[j + 1] * R),
            );
        }
    }
    assert!((total / (PI * R * R) - 1.0).abs() < EXACT, "{total}");
}

#[test]
fn random_rectangles_agree_with_monte_carlo_sampling() {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(7);
    let samples = 400_000;
    for _ in 0..12 {
        let mut edge = || rng.gen_range(-1.3 * R..1.3 * R);
        let (a, b, c, e) = (edge(), edge(), edge(), edge());
        let rectangle = relative_rectangle(a.min(b), a.max(b), c.min(e), c.max(e));
        let exact = overlap_area(disc(), rectangle);
        let d = disc();
        let mut hits = 0u64;
        for _ in 0..samples {
            let x = rng.gen_range(rectangle.x_min..rectangle.x_max);
            let z = rng.gen_range(rectangle.z_min..rectangle.z_max);
            if (x - d.x).powi(2) + (z - d.z).powi(2) < R * R {
                hits += 1;
            }
        }
        let p = hits as f64 / samples as f64;
        let estimate = p * rectangle.area();
        // Binomial standard error of the estimate; 5σ makes a false failure ~1e-6 per case.
        let sigma = rectangle.area() * (p * (1.0 - p) / samples as f64).sqrt();
        let tolerance = 5.0 * sigma + 1e-15 * R * R;
        assert!(
            (estimate - exact).abs() <= tolerance,
            "{rectangle:?}: exact {exact}, sampled {estimate} ± {sigma}"
        );
    }
}

#[test]
fn section_radius_is_pythagorean_and_zero_beyond_the_sphere() {
    // 3-4-5 triangle: exact in floating point to a few ulps.
    assert!((section_radius(5.0, 3.0) - 4.0).abs() < 1e-15);
    assert_eq!(section_radius(1.0, 1.5), 0.0);
    // The paper's slab: an out-of-plane offset of 15 µm changes r = 1.5 mm by < 1e-4 r.
    let r = section_radius(1.5e-3, 15e-6);
    assert!((1.5e-3 - r) / 1.5e-3 < 1e-4);
}

#[test]
fn rectangle_edges_within_an_ulp_of_the_disc_sides_do_not_inflate_the_area() {
    // Regression: with asin(x/r) in the primitive, an edge at x = r(1 − 1e-16) (as produced by
    // bin edges computed from a different origin than the disc centre) gave ≈ 1e-10 π r² too
    // much area, since asin has an infinite slope at 1. The inscribing rectangle must give π r²
    // to round-off.
    let d = Disc {
        x: -2.499_999_999_999_998_3e-3,
        z: 0.04,
        radius: R,
    };
    let rectangle = Rectangle {
        x_min: -3.999_999_999_999_998e-3,
        x_max: -9.999_999_999_999_992e-4,
        z_min: 0.04 - R,
        z_max: 0.04 + R,
    };
    let area = overlap_area(d, rectangle);
    assert!((area / (PI * R * R) - 1.0).abs() < EXACT, "{area}");
}
