//! Exact area of a disc ∩ an axis-aligned rectangle, and the section radius of a sphere.
//!
//! The strip area fraction of docs/physics.md §7.3 needs, per particle and x-bin, the area of the
//! bin rectangle covered by the particle's mid-plane disc. The area is the integral over x of
//! the vertical overlap between the rectangle [z_min, z_max] and the disc chord
//! [−h(x), h(x)], h(x) = √(ρ² − x²). Between the breakpoints where a rectangle edge meets the
//! circle the integrand is one of (z_max − z_min), (h − z_min), (z_max + h), 2h or 0, each with
//! the closed-form primitive ∫h dx = (x h + ρ² asin(x/ρ))/2. Integrating piecewise (instead of
//! inclusion–exclusion of quadrant areas) keeps small rectangles accurate.

use serde::{Deserialize, Serialize};

/// A disc in the (x, z) plane.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Disc {
    /// Centre x [m].
    pub x: f64,
    /// Centre z [m].
    pub z: f64,
    /// Radius ρ [m].
    pub radius: f64,
}

/// An axis-aligned rectangle [x_min, x_max] × [z_min, z_max] in the (x, z) plane.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Rectangle {
    /// Left edge [m].
    pub x_min: f64,
    /// Right edge [m].
    pub x_max: f64,
    /// Bottom edge [m].
    pub z_min: f64,
    /// Top edge [m].
    pub z_max: f64,
}

impl Rectangle {
    /// Area [m²]; zero for an empty or reversed rectangle.
    pub fn area(&self) -> f64 {
        (self.x_max - self.x_min).max(0.0) * (self.z_max - self.z_min).max(0.0)
    }
}

/// Radius [m] of the section of a sphere of radius `radius` [m] by a plane at distance
/// `offset` [m] from its centre: √(r² − offset²), zero when the plane misses the sphere.
pub fn section_radius(radius: f64, offset: f64) -> f64 {
    // (r − o)(r + o) keeps full relative precision when |o| is close to r.
    ((radius - offset.abs()) * (radius + offset.abs()))
        .max(0.0)
        .sqrt()
}

/// Exact area [m²] of `disc` ∩ `rectangle`. Zero for a non-positive radius or an empty
/// rectangle; infinite rectangle edges are allowed.
pub fn overlap_area(disc: Disc, rectangle: Rectangle) -> f64 {
    let r = disc.radius;
    if !(r > 0.0) {
        return 0.0;
    }
    // Work relative to the disc centre; clip x to the disc's extent.
    let x0 = (rectangle.x_min - disc.x).max(-r);
    let x1 = (rectangle.x_max - disc.x).min(r);
    let z0 = rectangle.z_min - disc.z;
    let z1 = rectangle.z_max - disc.z;
    if !(x1 > x0) || !(z1 > z0) || z0 >= r || z1 <= -r {
        return 0.0;
    }
    // Breakpoints: the interval ends and where the horizontal edges meet the circle.
    let mut breaks = [0.0_f64; 6];
    breaks[0] = x0;
    breaks[1] = x1;
    let mut n = 2;
    for z in [z0, z1] {
        if z.abs() < r {
            let c = section_radius(r, z);
            for b in [-c, c] {
                if b > x0 && b < x1 {
                    breaks[n] = b;
                    n += 1;
                }
            }
        }
    }
    let breaks = &mut breaks[..n];
    breaks.sort_by(|a, b| a.total_cmp(b));

    let mut area = 0.0;
    for pair in breaks.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        if !(b > a) {
            continue;
        }
        // Which bound is active is constant between breakpoints; decide at the midpoint.
        let h = section_radius(r, 0.5 * (a + b));
        let top_flat = z1 < h;
        let bottom_flat = z0 > -h;
        let top = if top_flat { z1 } else { h };
        let bottom = if bottom_flat { z0 } else { -h };
        if top <= bottom {
            continue;
        }
        let chord = chord_integral(r, a, b);
        let upper = if top_flat { z1 * (b - a) } else { chord };
        let lower = if bottom_flat { z0 * (b - a) } else { -chord };
        area += upper - lower;
    }
    area.max(0.0)
}

/// ∫_a^b √(r² − x²) dx for −r ≤ a ≤ b ≤ r.
fn chord_integral(r: f64, a: f64, b: f64) -> f64 {
    primitive(r, b) - primitive(r, a)
}

/// (x h + r² θ)/2 with h = √(r² − x²) and θ = atan2(x, h) (= asin(x/r)). Taking θ from the
/// accurately computed h, rather than asin(x/r), avoids the √ε blow-up of asin near ±1 that
/// would otherwise leave errors of ~1e-10 r² when a rectangle edge sits within an ulp of the
/// disc's side.
fn primitive(r: f64, x: f64) -> f64 {
    let x = x.clamp(-r, r);
    let h = section_radius(r, x);
    0.5 * (x * h + r * r * x.atan2(h))
}
