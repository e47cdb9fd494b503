//! The moments of a spherical cap and of the lens where two spheres overlap: the exact pieces
//! of a clump's mass properties (docs/physics.md §11.2).
//!
//! A cap of a ball of radius R is the part beyond a plane at signed distance d from the centre
//! (−R ≤ d ≤ R; d = −R is the whole ball). With z along the cap's axis from the centre and
//! ρ the distance from the axis, its cross-section at z is a disc of radius √(R² − z²), so
//! every moment is a polynomial integral over z ∈ [d, R]:
//!
//! - V  = π ∫ (R² − z²) dz     = π h² (3R − h)/3, h = R − d;
//! - M₁ = π ∫ z (R² − z²) dz   = π (R² − d²)²/4;
//! - M₂ = π ∫ z² (R² − z²) dz  = π (2R⁵/15 − R² d³/3 + d⁵/5);
//! - P  = ∫ ∫ ρ² dA dz = (π/2) ∫ (R² − z²)² dz = (π/2)(8R⁵/15 − R⁴ d + 2R² d³/3 − d⁵/5).

use glam::{DMat3, DVec3};

/// Volume, first and second moments of a solid of unit density [m³, m⁴, m⁵], about the
/// origin of the frame they are given in.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Moments {
    /// Volume V = ∫ dV [m³].
    pub volume: f64,
    /// First moment ∫ x dV [m⁴].
    pub first: DVec3,
    /// Second moment ∫ x xᵀ dV [m⁵].
    pub second: DMat3,
}

impl Moments {
    /// Nothing.
    pub const ZERO: Self = Self {
        volume: 0.0,
        first: DVec3::ZERO,
        second: DMat3::ZERO,
    };
}

/// The sum of two solids' moments (disjoint solids, or inclusion–exclusion terms).
impl std::ops::Add for Moments {
    type Output = Self;
    fn add(self, other: Self) -> Self {
        Self {
            volume: self.volume + other.volume,
            first: self.first + other.first,
            second: self.second + other.second,
        }
    }
}

/// One solid's moments less another's.
impl std::ops::Sub for Moments {
    type Output = Self;
    fn sub(self, other: Self) -> Self {
        Self {
            volume: self.volume - other.volume,
            first: self.first - other.first,
            second: self.second - other.second,
        }
    }
}

/// The moments of the cap of the ball of radius `r` centred at `centre` that lies beyond the
/// plane at signed distance `d` from the centre along the unit `axis` (d clamped to [−r, r]).
pub fn cap(centre: DVec3, r: f64, axis: DVec3, d: f64) -> Moments {
    use std::f64::consts::PI;
    let d = d.clamp(-r, r);
    let h = r - d;
    let (r2, d2) = (r * r, d * d);
    let volume = PI * h * h * (3.0 * r - h) / 3.0;
    let m1 = PI * (r2 - d2) * (r2 - d2) / 4.0;
    let m2 = PI * (2.0 * r2 * r2 * r / 15.0 - r2 * d2 * d / 3.0 + d2 * d2 * d / 5.0);
    let p = PI / 2.0
        * (8.0 * r2 * r2 * r / 15.0 - r2 * r2 * d + 2.0 * r2 * d2 * d / 3.0 - d2 * d2 * d / 5.0);
    axisymmetric(centre, axis, (volume, m1, m2, p))
}

/// The moments of a whole ball of radius `r` at `centre`.
pub fn ball(centre: DVec3, r: f64) -> Moments {
    cap(centre, r, DVec3::Z, -r)
}

/// The moments of the lens where the balls (`c1`, `r1`) and (`c2`, `r2`) overlap: nothing
/// when they do not; the smaller ball when it lies inside the other; otherwise the two caps
/// cut by the radical plane, where the two spheres' surfaces meet.
pub fn lens((c1, r1): (DVec3, f64), (c2, r2): (DVec3, f64)) -> Moments {
    let gap = c2 - c1;
    let dist = gap.length();
    if dist >= r1 + r2 {
        return Moments::ZERO;
    }
    if dist <= (r1 - r2).abs() {
        return if r1 <= r2 { ball(c1, r1) } else { ball(c2, r2) };
    }
    let axis = gap / dist;
    let d1 = (dist * dist + r1 * r1 - r2 * r2) / (2.0 * dist);
    cap(c1, r1, axis, d1) + cap(c2, r2, -axis, dist - d1)
}

/// A solid symmetric about the line through `centre` along the unit `axis`: from its volume
/// V, M₁ = ∫ z dV, M₂ = ∫ z² dV and P = ∫ ρ² dV (z along the axis from the centre, ρ the
/// distance from it). With x = c + z n + w, w ⊥ n, the symmetry gives ∫ w dV = 0 and
/// ∫ w wᵀ dV = (P/2)(1 − n nᵀ).
fn axisymmetric(centre: DVec3, axis: DVec3, (v, m1, m2, p): (f64, f64, f64, f64)) -> Moments {
    let outer = |a: DVec3, b: DVec3| DMat3::from_cols(a * b.x, a * b.y, a * b.z);
    let nn = outer(axis, axis);
    let second = outer(centre, centre) * v
        + (outer(centre, axis) + outer(axis, centre)) * m1
        + nn * m2
        + (DMat3::IDENTITY - nn) * (p / 2.0);
    Moments {
        volume: v,
        first: centre * v + axis * m1,
        second,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn worst(m: DMat3) -> f64 {
        m.to_cols_array().iter().fold(0.0f64, |a, x| a.max(x.abs()))
    }
    use std::f64::consts::PI;

    fn close(a: f64, b: f64, scale: f64) -> bool {
        // Round-off of a few dozen operations on numbers of size `scale`.
        (a - b).abs() <= 1e-13 * scale
    }

    #[test]
    fn a_whole_ball_has_the_textbook_volume_and_isotropic_second_moment() {
        // V = 4πr³/3 and ∫ x xᵀ = V c cᵀ + (4πr⁵/15) 1 (the inertia 2/5 m r² about its centre).
        let (c, r) = (DVec3::new(0.3, -0.2, 1.1), 0.7);
        let m = ball(c, r);
        let v = 4.0 * PI * r.powi(3) / 3.0;
        assert!(close(m.volume, v, v));
        assert!((m.first - c * v).abs().max_element() <= 1e-13);
        let iso = 4.0 * PI * r.powi(5) / 15.0;
        for a in 0..3 {
            for b in 0..3 {
                let want = v * c[a] * c[b] + if a == b { iso } else { 0.0 };
                assert!(close(m.second.col(b)[a], want, 1.0), "{a}{b}");
            }
        }
    }

    #[test]
    fn two_caps_of_one_plane_make_the_ball() {
        // The caps on either side of any plane add up to the whole ball: volume, first and
        // second moments, for cuts across the ball and an oblique axis.
        let (c, r) = (DVec3::new(-0.4, 0.9, 0.2), 1.3);
        let axis = DVec3::new(1.0, 2.0, -2.0).normalize();
        let whole = ball(c, r);
        for d in [-1.2, -0.5, 0.0, 0.31, 1.29] {
            let sum = cap(c, r, axis, d) + cap(c, r, -axis, -d);
            assert!(close(sum.volume, whole.volume, whole.volume), "{d}");
            assert!(
                (sum.first - whole.first).abs().max_element() <= 1e-12,
                "{d}"
            );
            assert!(worst(sum.second - whole.second) <= 1e-12, "{d}");
        }
    }

    #[test]
    fn the_lens_of_two_equal_balls_has_the_closed_form_volume() {
        // Two balls of radius r, centres s apart: V = π (4r + s)(2r − s)²/12, centred midway.
        let r = 0.5;
        for s in [0.01, 0.3, 0.77, 0.999] {
            let (a, b) = (DVec3::new(0.1, 0.2, 0.3), DVec3::new(0.1, 0.2 + s, 0.3));
            let m = lens((a, r), (b, r));
            let want = PI * (4.0 * r + s) * (2.0 * r - s).powi(2) / 12.0;
            assert!(close(m.volume, want, 1.0), "{s}: {} {want}", m.volume);
            let centroid = m.first / m.volume;
            assert!((centroid - (a + b) / 2.0).length() <= 1e-12, "{s}");
        }
        // Apart, they share nothing; one inside the other, the lens is the smaller ball.
        assert_eq!(lens((DVec3::ZERO, r), (DVec3::X, r)), Moments::ZERO);
        let inner = lens((DVec3::ZERO, 1.0), (DVec3::X * 0.2, 0.5));
        assert_eq!(inner, ball(DVec3::X * 0.2, 0.5));
    }
}
