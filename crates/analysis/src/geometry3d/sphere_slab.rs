//! Volume of a sphere inside a horizontal slab z₀ ≤ z ≤ z₁, whole and split into annular bins
//! about the silo axis, for radial packing fractions φ(r) over a circular orifice.
//!
//! The whole-slab volume is exact: the sphere's cross-section at height z is the disc of
//! radius a(z) = √(r² − (z − z_c)²), so with the limits clipped to the sphere,
//! u₀ = max(z₀, z_c − r) − z_c and u₁ = min(z₁, z_c + r) − z_c,
//!
//! V = ∫ π (r² − u²) du = π (u₁ − u₀) [r² − (u₀² + u₀u₁ + u₁²)/3],
//!
//! the difference of two spherical caps π h²(3r − h)/3 written without cancellation
//! (0 when the slab misses the sphere, 4πr³/3 when it holds it).
//!
//! The volume in the annulus ρ_i ≤ ρ < ρ_{i+1} is ∫ [A(a(z), ρ_{i+1}) − A(a(z), ρ_i)] dz with
//! A the lens area of `disc_overlap`. That integrand is not smooth: a(z) has a square-root
//! end at the poles z_c ± r, and A has a (Δa)^{3/2} kink where the section's circle touches
//! a bin circle (a = |ρ − s| or a = ρ + s, s the centre's distance from the axis; at the
//! equator, where a = r only touches such a value, it goes as |z − z_c|³). The z-range
//! is therefore cut at every such height, and each piece [z_a, z_b] is mapped by
//! z = z_m + h sin(πx/2) (z_m, h its midpoint and half-width), which makes z − z_a and z_b − z
//! quadratic in the distance to x = ∓1. Both kinds of singularity become analytic in x, and a
//! Gauss–Legendre rule converges geometrically on every piece. The pieces are cut from the
//! whole sphere, [z_c − r, z_c + r], and the slab keeps an x-subinterval of each: cutting at
//! the slab faces instead would leave a singularity just beyond a piece whenever a face falls
//! near a tangency height, and slow the convergence there by two orders of magnitude.

use crate::error::{ensure_finite, AnalysisError, AnalysisResult};

use super::disc_overlap::lens_area;
use super::gauss_legendre;

/// Spherical cap of height `height` h [m] cut from a sphere of radius `radius` r [m]:
/// π h²(3r − h)/3 [m³], for 0 ≤ h ≤ 2r.
pub fn spherical_cap_volume(radius: f64, height: f64) -> AnalysisResult<f64> {
    const CONTEXT: &str = "spherical cap";
    check_radius(CONTEXT, radius)?;
    if !(height.is_finite() && (0.0..=2.0 * radius).contains(&height)) {
        return Err(AnalysisError::InvalidArgument {
            context: CONTEXT,
            reason: format!(
                "cap height must lie in [0, 2r] = [0, {}] m, got {height}",
                2.0 * radius
            ),
        });
    }
    Ok(std::f64::consts::PI * height * height * (3.0 * radius - height) / 3.0)
}

fn check_radius(context: &'static str, radius: f64) -> AnalysisResult<()> {
    if radius.is_finite() && radius > 0.0 {
        Ok(())
    } else {
        Err(AnalysisError::InvalidArgument {
            context,
            reason: format!("sphere radius must be finite and > 0 m, got {radius}"),
        })
    }
}

fn check_slab(context: &'static str, lower: f64, upper: f64) -> AnalysisResult<()> {
    ensure_finite(context, &[lower, upper])?;
    if lower > upper {
        return Err(AnalysisError::InvalidArgument {
            context,
            reason: format!("slab bottom {lower} m lies above its top {upper} m"),
        });
    }
    Ok(())
}

/// The sphere's z-range inside the slab relative to its centre, (u₀, u₁), or `None` if empty.
fn clipped_range(centre_z: f64, radius: f64, lower: f64, upper: f64) -> Option<(f64, f64)> {
    let u0 = lower.max(centre_z - radius) - centre_z;
    let u1 = upper.min(centre_z + radius) - centre_z;
    (u1 > u0).then_some((u0, u1))
}

/// Volume [m³] of the sphere of centre height `centre_z` z_c [m] and radius `radius` r [m]
/// inside the slab `lower` z₀ ≤ z ≤ `upper` z₁ [m] (module formula).
pub fn sphere_slab_volume(
    centre_z: f64,
    radius: f64,
    lower: f64,
    upper: f64,
) -> AnalysisResult<f64> {
    const CONTEXT: &str = "sphere-slab volume";
    ensure_finite(CONTEXT, &[centre_z])?;
    check_radius(CONTEXT, radius)?;
    check_slab(CONTEXT, lower, upper)?;
    Ok(match clipped_range(centre_z, radius, lower, upper) {
        None => 0.0,
        Some((u0, u1)) => {
            std::f64::consts::PI
                * (u1 - u0)
                * (radius * radius - (u0 * u0 + u0 * u1 + u1 * u1) / 3.0)
        }
    })
}

/// Checks radial bin edges: at least two, finite, ≥ 0 and strictly increasing.
pub(crate) fn check_edges(context: &'static str, edges: &[f64]) -> AnalysisResult<()> {
    if edges.len() < 2 {
        return Err(AnalysisError::TooFewPoints {
            context,
            needed: 2,
            got: edges.len(),
        });
    }
    ensure_finite(context, edges)?;
    if edges[0] < 0.0 || edges.windows(2).any(|w| w[1] <= w[0]) {
        return Err(AnalysisError::InvalidArgument {
            context,
            reason: "bin edges must be ≥ 0 and strictly increasing".into(),
        });
    }
    Ok(())
}

/// Adds to `out[i]` the volume [m³] of the sphere of centre `centre` = [x, y, z] [m] (x, y
/// measured from the orifice axis) and radius `radius` [m] that lies in the slab
/// `lower` ≤ z ≤ `upper` [m] and in the annulus `edges[i]` ≤ ρ < `edges[i + 1]` [m] about the
/// axis. Volume inside `edges[0]` or beyond the last edge is not counted. `out` must have
/// `edges.len() − 1` entries; it is added to, not overwritten, so one buffer can accumulate
/// every particle of a snapshot.
///
/// Quadrature as in the module documentation; with the sum over bins that cover the sphere it
/// reproduces [`sphere_slab_volume`] to round-off.
pub fn sphere_slab_radial_volumes(
    centre: [f64; 3],
    radius: f64,
    lower: f64,
    upper: f64,
    edges: &[f64],
    out: &mut [f64],
) -> AnalysisResult<()> {
    const CONTEXT: &str = "sphere-slab radial volumes";
    ensure_finite(CONTEXT, &centre)?;
    check_radius(CONTEXT, radius)?;
    check_slab(CONTEXT, lower, upper)?;
    check_edges(CONTEXT, edges)?;
    if out.len() + 1 != edges.len() {
        return Err(AnalysisError::LengthMismatch {
            context: CONTEXT,
            left: edges.len() - 1,
            right: out.len(),
        });
    }
    accumulate(
        gauss_legendre::rule(),
        centre,
        radius,
        lower,
        upper,
        edges,
        out,
    );
    Ok(())
}

/// The quadrature of [`sphere_slab_radial_volumes`] with the Gauss–Legendre `rule` on each
/// piece; inputs already checked.
fn accumulate(
    rule: &[(f64, f64)],
    centre: [f64; 3],
    radius: f64,
    lower: f64,
    upper: f64,
    edges: &[f64],
    out: &mut [f64],
) {
    let Some((u0, u1)) = clipped_range(centre[2], radius, lower, upper) else {
        return;
    };
    let s = centre[0].hypot(centre[1]);
    let r = radius;
    // Only edges in [first, last] can see the sphere: below s − r every lens is empty, above
    // s + r every lens is the whole section; bins outside that range get nothing.
    let first = edges.partition_point(|&e| e <= s - r).saturating_sub(1);
    let last = edges.partition_point(|&e| e < s + r).min(edges.len() - 1);
    if first >= last {
        return;
    }
    let relevant = &edges[first..=last];

    // The natural pieces: cut [−r, r] at the poles and wherever a(u) = c for a tangency
    // radius c ≤ r (c = r cuts at the equator, where a touches c without crossing and the
    // lens goes as |u|³). The pieces are cut independently of the slab, so that a slab face
    // near a cut does not leave a singularity just outside a piece.
    let mut cuts = vec![-r, r];
    for &rho in relevant {
        for c in [(rho - s).abs(), rho + s] {
            if c <= r {
                let u = ((r - c) * (r + c)).sqrt();
                cuts.extend([-u, u]);
            }
        }
    }
    cuts.sort_by(f64::total_cmp);
    cuts.dedup();

    let mut cumulative = vec![0.0; relevant.len()];
    let half_pi = std::f64::consts::FRAC_PI_2;
    for piece in cuts.windows(2) {
        let (start, end) = (piece[0].max(u0), piece[1].min(u1));
        if start >= end {
            continue;
        }
        // On the whole piece, u = mid + half·sin(πx/2) for x ∈ [−1, 1]; the slab keeps the
        // part x ∈ [x_a, x_b], integrated by the rule mapped onto it.
        let (mid, half) = (0.5 * (piece[0] + piece[1]), 0.5 * (piece[1] - piece[0]));
        let to_x = |u: f64| ((u - mid) / half).clamp(-1.0, 1.0).asin() / half_pi;
        let (xa, xb) = (to_x(start), to_x(end));
        let (x_mid, x_half) = (0.5 * (xa + xb), 0.5 * (xb - xa));
        for &(t, w) in rule {
            // du = half·(π/2)·cos(πx/2) dx, dx = x_half dt.
            let x = x_mid + x_half * t;
            let u = mid + half * (half_pi * x).sin();
            let a = ((r - u) * (r + u)).max(0.0).sqrt();
            for (area, &rho) in cumulative.iter_mut().zip(relevant) {
                *area = lens_area(s, a, rho);
            }
            let weight = w * x_half * half * half_pi * (half_pi * x).cos();
            for (i, pair) in cumulative.windows(2).enumerate() {
                out[first + i] += weight * (pair[1] - pair[0]);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::flowrate::integrate;
    use std::f64::consts::PI;

    #[test]
    fn slab_volumes_reduce_to_caps_the_whole_sphere_and_nothing() {
        let (zc, r): (f64, f64) = (0.3, 0.05);
        let whole = 4.0 / 3.0 * PI * r.powi(3);
        // Slab holding the sphere, and slabs that miss it (touching counts as missing).
        assert!((sphere_slab_volume(zc, r, 0.0, 1.0).unwrap() - whole).abs() < 1e-15);
        assert_eq!(sphere_slab_volume(zc, r, 0.4, 1.0).unwrap(), 0.0);
        assert_eq!(sphere_slab_volume(zc, r, 0.0, zc - r).unwrap(), 0.0);
        // A slab whose top cuts the sphere at height h above its bottom is a cap of height h,
        // and the bottom-cut slab the complementary cap (1e-15 ≈ 100 ulp of the volume).
        for h in [0.0, 0.013, 0.05, 0.081, 0.1] {
            let below = sphere_slab_volume(zc, r, -1.0, zc - r + h).unwrap();
            let above = sphere_slab_volume(zc, r, zc - r + h, 1.0).unwrap();
            assert!((below - spherical_cap_volume(r, h).unwrap()).abs() < 1e-15);
            assert!((above - spherical_cap_volume(r, 2.0 * r - h).unwrap()).abs() < 1e-15);
            assert!((below + above - whole).abs() < 1e-15);
        }
        // Mirror symmetry about the centre.
        let up = sphere_slab_volume(zc, r, zc + 0.01, zc + 0.04).unwrap();
        let down = sphere_slab_volume(zc, r, zc - 0.04, zc - 0.01).unwrap();
        assert!((up - down).abs() < 1e-17);
        // A hemisphere.
        let half = sphere_slab_volume(zc, r, zc, 2.0).unwrap();
        assert!((half - whole / 2.0).abs() < 1e-16);
    }

    #[test]
    fn bad_slabs_and_radii_are_rejected() {
        assert!(sphere_slab_volume(0.0, 0.0, -1.0, 1.0).is_err());
        assert!(sphere_slab_volume(0.0, 1.0, 1.0, -1.0).is_err());
        assert!(sphere_slab_volume(f64::NAN, 1.0, -1.0, 1.0).is_err());
        assert!(spherical_cap_volume(1.0, 2.5).is_err());
        let mut out = vec![0.0; 2];
        let centre = [0.0, 0.0, 0.0];
        assert!(sphere_slab_radial_volumes(centre, 1.0, -1.0, 1.0, &[0.0, 1.0], &mut out).is_err());
        assert!(
            sphere_slab_radial_volumes(centre, 1.0, -1.0, 1.0, &[0.0, 2.0, 1.0], &mut out).is_err()
        );
        assert!(
            sphere_slab_radial_volumes(centre, 1.0, -1.0, 1.0, &[-0.1, 1.0, 2.0], &mut out)
                .is_err()
        );
        assert!(sphere_slab_radial_volumes(centre, 1.0, -1.0, 1.0, &[0.0], &mut []).is_err());
    }

    /// Radial volumes of one sphere into fresh bins.
    fn radial(centre: [f64; 3], r: f64, lower: f64, upper: f64, edges: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; edges.len() - 1];
        sphere_slab_radial_volumes(centre, r, lower, upper, edges, &mut out).unwrap();
        out
    }

    #[test]
    fn bins_that_cover_the_sphere_sum_to_the_exact_slab_volume() {
        // Conservation: whatever the position, the bins from the axis past s + r partition the
        // slab part of the sphere. The sum is a Gauss–Legendre integral of π a(z)² through the
        // sine map, so 1e-12 relative tests the rule and the cuts, not just the telescoping.
        let r = 1.5e-3;
        let edges: Vec<f64> = (0..=12).map(|i| i as f64 * 1e-3).collect();
        let positions = [
            [0.0, 0.0, 0.0],
            [0.0004, 0.0003, 0.0002],
            [0.0031, -0.0027, -0.0011],
            [-0.006, 0.0, 0.0009],
            [0.002, 0.002, 0.0014],
        ];
        for centre in positions {
            for (lower, upper) in [(-1e-3, 1e-3), (-5e-3, 5e-3), (0.0005, 0.0021)] {
                let total: f64 = radial(centre, r, lower, upper, &edges).iter().sum();
                let exact = sphere_slab_volume(centre[2], r, lower, upper).unwrap();
                assert!(
                    (total - exact).abs() <= 1e-12 * exact.max(1e-30),
                    "{centre:?} [{lower}, {upper}]: {total} vs {exact}"
                );
            }
        }
    }

    #[test]
    fn a_sphere_on_the_axis_splits_into_the_analytic_annulus_volumes() {
        // Centred on the axis: the section at height u is the disc of radius a(u), so the
        // volume within ρ of the axis is ∫ π min(a(u), ρ)² du, exactly
        // πρ²·2u_ρ + [sphere slab beyond |u| > u_ρ] with u_ρ = √(r² − ρ²) (ρ < r). Each bin
        // must match the difference of that closed form to 1e-12 relative.
        let r = 1.0;
        let within = |rho: f64, lower: f64, upper: f64| -> f64 {
            if rho >= r {
                return sphere_slab_volume(0.0, r, lower, upper).unwrap();
            }
            let u = (r * r - rho * rho).sqrt();
            let (l, h) = (lower.max(-u), upper.min(u));
            let cylinder = PI * rho * rho * (h - l).max(0.0);
            let caps = sphere_slab_volume(0.0, r, lower, upper.min(-u)).unwrap_or(0.0)
                + sphere_slab_volume(0.0, r, lower.max(u), upper).unwrap_or(0.0);
            cylinder + caps
        };
        let edges = [0.0, 0.1, 0.35, 0.6, 0.8, 0.95, 1.0, 1.3];
        for (lower, upper) in [(-2.0, 2.0), (-0.3, 0.5), (0.2, 0.9)] {
            let bins = radial([0.0, 0.0, 0.0], r, lower, upper, &edges);
            for (i, v) in bins.iter().enumerate() {
                let expected = within(edges[i + 1], lower, upper) - within(edges[i], lower, upper);
                let scale = sphere_slab_volume(0.0, r, lower, upper).unwrap();
                assert!(
                    (v - expected).abs() < 1e-12 * scale,
                    "bin {i} of [{lower}, {upper}]: {v} vs {expected}"
                );
            }
        }
    }

    #[test]
    fn off_axis_bins_match_adaptive_quadrature_of_the_lens_areas() {
        // The accuracy of the Gauss–Legendre pieces: for spheres off the axis (kinks inside the
        // range), each bin equals an independent adaptive-Simpson integral of the lens-area
        // difference over z (tolerance 1e-15 on a unit sphere; they agree to 7e-16) to 1e-13
        // of the sphere volume.
        let r = 1.0;
        let edges = [0.0, 0.5, 1.0, 1.7, 2.2, 2.9];
        let whole = 4.0 / 3.0 * PI;
        for centre in [
            [1.2f64, 0.0, 0.0],
            [0.3, 0.4, 0.1],
            [1.0, 1.0, -0.2],
            [0.0, 1.7, 0.0],
        ] {
            let s = centre[0].hypot(centre[1]);
            for (lower, upper) in [(-3.0, 3.0), (-0.4, 0.7)] {
                let bins = radial(centre, r, lower, upper, &edges);
                let (z0, z1) = (lower.max(centre[2] - r), upper.min(centre[2] + r));
                for (i, v) in bins.iter().enumerate() {
                    let slice = |z: f64| {
                        let a = (r * r - (z - centre[2]).powi(2)).max(0.0).sqrt();
                        lens_area(s, a, edges[i + 1]) - lens_area(s, a, edges[i])
                    };
                    let reference = integrate(slice, z0, z1, 1e-15).unwrap();
                    assert!(
                        (v - reference).abs() < 1e-13 * whole,
                        "{centre:?} bin {i}: {v} vs {reference}"
                    );
                }
            }
        }
    }

    #[test]
    fn the_rule_has_converged_wherever_the_slab_faces_fall() {
        // Why `gauss_legendre::ORDER` points suffice: slab faces swept in 1000 steps across
        // spheres at five offsets (the faces pass every tangency height), each bin compared
        // with the same quadrature at 96 points. Over such sweeps the worst difference is
        // 1.4e-10 of the sphere volume at 12 points, 3e-13 at 16 and round-off (2e-15) from
        // 20 on, where the order is set; 1e-14 is the bar.
        let r = 1.0;
        let edges = [0.0, 0.5, 1.0, 1.7, 2.2, 2.9];
        let whole = 4.0 / 3.0 * PI;
        let reference_rule = gauss_legendre::compute(96);
        let mut worst: f64 = 0.0;
        for centre in [
            [1.2f64, 0.0, 0.0],
            [0.3, 0.4, 0.1],
            [1.0, 1.0, -0.2],
            [0.0, 1.7, 0.0],
            [0.5, 0.5, 0.0],
        ] {
            for k in 0..1000 {
                let upper = -1.0 + k as f64 / 500.0 + 1e-4;
                for lower in [-3.0, upper - 0.37] {
                    let mut bins = vec![0.0; 5];
                    let mut reference = vec![0.0; 5];
                    sphere_slab_radial_volumes(centre, r, lower, upper, &edges, &mut bins).unwrap();
                    accumulate(
                        &reference_rule,
                        centre,
                        r,
                        lower,
                        upper,
                        &edges,
                        &mut reference,
                    );
                    for (x, y) in bins.iter().zip(&reference) {
                        worst = worst.max((x - y).abs() / whole);
                    }
                }
            }
        }
        assert!(
            worst < 1e-14,
            "worst bin difference {worst:e} of the sphere volume"
        );
    }

    #[test]
    fn a_sphere_inside_one_annulus_fills_only_that_bin_and_rotation_changes_nothing() {
        // Sphere of radius 0.2 at distance 1.5 from the axis, inside the bin [1.2, 1.8).
        let edges = [0.0, 0.6, 1.2, 1.8, 2.4];
        let angle: f64 = 0.7;
        let a = radial([1.5, 0.0, 0.0], 0.2, -1.0, 1.0, &edges);
        let b = radial(
            [1.5 * angle.cos(), 1.5 * angle.sin(), 0.0],
            0.2,
            -1.0,
            1.0,
            &edges,
        );
        let whole = 4.0 / 3.0 * PI * 0.2f64.powi(3);
        assert!((a[2] - whole).abs() < 1e-14);
        assert!(a[0] == 0.0 && a[1] == 0.0 && a[3] == 0.0);
        for (x, y) in a.iter().zip(&b) {
            assert!((x - y).abs() < 1e-15);
        }
        // Accumulation: a second call adds.
        let mut out = a.clone();
        sphere_slab_radial_volumes([1.5, 0.0, 0.0], 0.2, -1.0, 1.0, &edges, &mut out).unwrap();
        assert!((out[2] - 2.0 * whole).abs() < 1e-14);
    }
}
