//! The smooth axisymmetric wall: a cylinder or a cone frustum about an axis, finite or (a
//! cylinder) infinite, not triangulated (docs/physics.md §5.2). The surface is a thin
//! two-sided shell: a sphere inside is pushed inwards and one outside outwards, so one shape
//! gives a silo's inner wall and a post's outer wall.
//!
//! The closest point lies in the meridian half-plane through the sphere's centre: there
//! the surface is the segment from (r₀, 0) to (r₁, L) in (distance from the axis, height
//! along it), and the closest point of a segment is exact.

use glam::{DQuat, DVec3};
use serde::{Deserialize, Serialize};

use super::geometry::{NearCache, SurfaceElements, WallGeometry};
use super::mesh::{MeshContact, MeshScratch};
use super::WallError;

/// A cylinder or cone frustum about an axis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Frustum {
    /// The axis point where the surface's radius is `radii[0]` [m].
    pub(super) base: DVec3,
    /// Unit axis [-], from `base` towards the other end.
    pub(super) axis: DVec3,
    /// Length along the axis [m]; infinite for an unbounded cylinder.
    pub(super) length: f64,
    /// Radius at `base` and at the other end [m].
    pub(super) radii: [f64; 2],
}

impl Frustum {
    /// The frustum from `base` along `axis` (any finite non-zero length) over `length` [m],
    /// with radii `radii` [m] at its two ends. `length` may be infinite for a cylinder
    /// (equal radii), which then extends both ways from `base`.
    pub(super) fn new(
        base: DVec3,
        axis: DVec3,
        length: f64,
        radii: [f64; 2],
    ) -> Result<Self, WallError> {
        let len = axis.length();
        let bad = |what: &str, value: String| WallError::BadAxisymmetric {
            what: what.to_string(),
            value,
        };
        if !base.is_finite() {
            return Err(bad("base point [m] must be finite", base.to_string()));
        }
        if !(len.is_finite() && len > 0.0) {
            return Err(bad(
                "axis must be a finite non-zero vector",
                axis.to_string(),
            ));
        }
        if !(length > 0.0) || (length.is_infinite() && radii[0] != radii[1]) {
            return Err(bad(
                "length [m] must be > 0 (infinite only for a cylinder)",
                length.to_string(),
            ));
        }
        if !radii.iter().all(|r| r.is_finite() && *r >= 0.0) || radii == [0.0, 0.0] {
            return Err(bad(
                "radii [m] must be finite, ≥ 0 and not both 0",
                format!("{radii:?}"),
            ));
        }
        Ok(Self {
            base,
            axis: axis / len,
            length,
            radii,
        })
    }

    /// The axis point at the first end [m].
    pub fn base(&self) -> DVec3 {
        self.base
    }

    /// The unit axis [-].
    pub fn axis(&self) -> DVec3 {
        self.axis
    }

    /// The length along the axis [m] (infinite for an unbounded cylinder).
    pub fn length(&self) -> f64 {
        self.length
    }

    /// The radii at the two ends [m].
    pub fn radii(&self) -> [f64; 2] {
        self.radii
    }

    /// Lateral area [m²] of band `band` (counted from 0 at the base) of `bands` bands of
    /// equal length along the axis, the elements the frustum's loads are booked to
    /// ([`WallGeometry::surface_contacts`]): the band is itself a cone frustum, between
    /// the heights a L and b L (a = band/bands, b = (band + 1)/bands) where the radii are
    /// r_a = r₀ + a (r₁ − r₀) and r_b = r₀ + b (r₁ − r₀), and its lateral area is
    /// π (r_a + r_b) s with the slant length s = √(L² + (r₁ − r₀)²)/bands. Infinite for an
    /// unbounded cylinder. What a wall pressure divides a band's normal force by.
    pub fn band_area(&self, band: usize, bands: usize) -> f64 {
        let (length, [r0, r1]) = (self.length, self.radii);
        let slant = length.hypot(r1 - r0) / bands as f64;
        let (a, b) = (band as f64 / bands as f64, (band + 1) as f64 / bands as f64);
        let (ra, rb) = (r0 + a * (r1 - r0), r0 + b * (r1 - r0));
        std::f64::consts::PI * (ra + rb) * slant
    }

    /// Height along the axis from the base and the unit radial direction of `x` (a fixed
    /// perpendicular of the axis when `x` lies on it), with the distance from the axis [m].
    #[inline]
    fn meridian(&self, x: DVec3) -> (f64, DVec3, f64) {
        let e = x - self.base;
        let s = e.dot(self.axis);
        let w = e - s * self.axis;
        let rho = w.length();
        let radial = if rho > 0.0 {
            w / rho
        } else {
            self.axis.any_orthonormal_vector()
        };
        (s, radial, rho)
    }

    /// Closest point of the surface to `x`, its distance and the position along the axis
    /// of the closest point as a fraction of the length (0 at the base; 0.5 for an infinite
    /// cylinder), which gives the contact's band.
    #[inline]
    pub fn closest_point_and_height(&self, x: DVec3) -> (DVec3, f64, f64) {
        let (s, radial, rho) = self.meridian(x);
        let [r0, r1] = self.radii;
        let (t, rc, sc) = if self.length.is_infinite() {
            (0.5, r0, s)
        } else {
            // Segment (r0, 0) → (r1, L) in the (ρ, s) half-plane.
            let (dr, dl) = (r1 - r0, self.length);
            let t = (((rho - r0) * dr + s * dl) / (dr * dr + dl * dl)).clamp(0.0, 1.0);
            (t, r0 + t * dr, t * dl)
        };
        let p = self.base + sc * self.axis + rc * radial;
        let d = ((rho - rc).powi(2) + (s - sc).powi(2)).sqrt();
        (p, d, t)
    }
}

impl WallGeometry for Frustum {
    /// [`Frustum::closest_point_and_height`] without the height; out of line, so that the
    /// loops of the shapes that call it through [`super::Wall`] inline none of its code.
    #[inline(never)]
    fn closest_point(&self, x: DVec3) -> (DVec3, f64) {
        let (p, d, _) = self.closest_point_and_height(x);
        (p, d)
    }

    /// Contact normal (surface to sphere) for a sphere at `x` whose closest point is `p` at
    /// distance `dist`: along x − p, or the surface's meridian normal when x lies on it.
    #[inline]
    fn contact_normal(&self, x: DVec3, p: DVec3, dist: f64) -> DVec3 {
        if dist > 0.0 {
            return (x - p) / dist;
        }
        let (_, radial, _) = self.meridian(x);
        let [r0, r1] = self.radii;
        let slope = if self.length.is_infinite() {
            0.0
        } else {
            (r1 - r0) / self.length
        };
        (radial - slope * self.axis).normalize()
    }

    /// True when `x` is certainly farther than `reach` [m] from the surface: beyond either
    /// end, or outside the widest or inside the narrowest radius, by more than `reach`.
    #[inline]
    fn certainly_beyond(&self, x: DVec3, reach: f64) -> bool {
        let (s, _, rho) = self.meridian(x);
        let [r0, r1] = self.radii;
        s < -reach
            || s > self.length + reach
            || rho > r0.max(r1) + reach
            || rho < r0.min(r1) - reach
    }

    #[inline]
    fn is_unbounded(&self) -> bool {
        self.length.is_infinite()
    }

    #[inline]
    fn needs_surface_pass(&self) -> bool {
        true
    }

    fn elements(&self) -> SurfaceElements {
        SurfaceElements::Bands
    }

    /// The one contact at the closest point, if nearer than `r`, booked to the band of
    /// `bands` equal lengths along the axis that holds the point.
    #[inline]
    fn surface_contacts(
        &self,
        (x, r): (DVec3, f64),
        bands: usize,
        _near: &mut NearCache,
        _scratch: &mut MeshScratch,
        out: &mut Vec<MeshContact>,
    ) {
        out.clear();
        let (point, distance, t) = self.closest_point_and_height(x);
        if distance < r {
            out.push(MeshContact {
                point,
                normal: self.contact_normal(x, point, distance),
                distance,
                triangle: ((t * bands as f64) as usize).min(bands - 1) as u32,
            });
        }
    }

    /// Moves the frustum by `offset` [m].
    fn translate(&mut self, offset: DVec3) {
        self.base += offset;
    }

    /// Turns the frustum by `rotation` about the world point `centre` [m].
    fn rotate_about(&mut self, centre: DVec3, rotation: DQuat) {
        self.base = centre + rotation * (self.base - centre);
        self.axis = (rotation * self.axis).normalize();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;
    use proptest::prelude::*;

    /// Closest distance by dense sampling of the surface: 400 heights × 720 angles.
    fn sampled(f: &Frustum, x: DVec3) -> f64 {
        let u = f.axis.any_orthonormal_vector();
        let v = f.axis.cross(u);
        let mut best = f64::INFINITY;
        for i in 0..=400 {
            let t = i as f64 / 400.0;
            let r = f.radii[0] + t * (f.radii[1] - f.radii[0]);
            for j in 0..720 {
                let a = j as f64 * std::f64::consts::TAU / 720.0;
                let p = f.base + t * f.length * f.axis + r * (a.cos() * u + a.sin() * v);
                best = best.min(p.distance(x));
            }
        }
        best
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(48))]
        #[test]
        fn the_closest_point_is_on_the_surface_and_no_farther_than_any_sample(
            x in prop::array::uniform3(-1.5f64..1.5),
            r0 in 0.0f64..1.0, r1 in 0.05f64..1.0,
        ) {
            let f = Frustum::new(DVec3::new(0.1, -0.2, -0.5), DVec3::new(0.3, 0.1, 1.0), 1.0, [r0, r1]).unwrap();
            let x = DVec3::from_array(x);
            let (p, d, t) = f.closest_point_and_height(x);
            prop_assert!((p.distance(x) - d).abs() < 1e-12);
            // p lies on the surface: at height t L its distance from the axis is r(t).
            let (s, _, rho) = f.meridian(p);
            prop_assert!((s - t * f.length).abs() < 1e-12);
            prop_assert!((rho - (r0 + t * (r1 - r0))).abs() < 1e-12);
            // Sample spacing: 1/400 of the length and 2π/720 of the radius (< 0.01 here).
            let b = sampled(&f, x);
            prop_assert!(d <= b + 1e-12);
            prop_assert!(d >= b - 0.01);
            // The far test never rejects a point within reach.
            prop_assert!(!f.certainly_beyond(x, d + 1e-9));
        }
    }

    #[test]
    fn a_cylinder_from_inside_and_outside_and_an_infinite_one() {
        // Exact numbers: radius 1 about z; a point at ρ = 0.75 is 0.25 from it, one at 1.5
        // is 0.5 from it, and the normal points back to the point in both cases.
        let c = Frustum::new(DVec3::ZERO, DVec3::Z, 2.0, [1.0, 1.0]).unwrap();
        let (p, d, _) = c.closest_point_and_height(DVec3::new(0.75, 0.0, 1.0));
        assert_eq!((p, d), (DVec3::new(1.0, 0.0, 1.0), 0.25));
        assert_eq!(
            c.contact_normal(DVec3::new(0.75, 0.0, 1.0), p, d),
            -DVec3::X
        );
        let (p, d, _) = c.closest_point_and_height(DVec3::new(0.0, 1.5, 0.5));
        assert_eq!((p, d), (DVec3::new(0.0, 1.0, 0.5), 0.5));
        let inf = Frustum::new(DVec3::ZERO, DVec3::Z, f64::INFINITY, [1.0, 1.0]).unwrap();
        let (p, d, _) = inf.closest_point_and_height(DVec3::new(0.0, 0.5, -1e6));
        assert_eq!((p, d), (DVec3::new(0.0, 1.0, -1e6), 0.5));
        assert!(!inf.certainly_beyond(DVec3::new(0.0, 0.5, 1e9), 0.6));
    }

    #[test]
    fn a_band_has_the_lateral_area_of_its_cone_frustum_and_the_bands_add_up() {
        // Closed form of a cone frustum's lateral area: π (r_a + r_b) √(h² + (r_b − r_a)²).
        let lateral =
            |ra: f64, rb: f64, h: f64| std::f64::consts::PI * (ra + rb) * h.hypot(rb - ra);
        let cone = Frustum::new(DVec3::ZERO, DVec3::Z, 0.6, [0.05, 0.3]).unwrap();
        // One band is the whole frustum.
        assert_relative_eq!(
            cone.band_area(0, 1),
            lateral(0.05, 0.3, 0.6),
            max_relative = 1e-15
        );
        // Band 1 of 4 lies between the heights 0.15 and 0.3, radii 0.1125 and 0.175.
        assert_relative_eq!(
            cone.band_area(1, 4),
            lateral(0.1125, 0.175, 0.15),
            max_relative = 1e-14
        );
        let total: f64 = (0..7).map(|k| cone.band_area(k, 7)).sum();
        assert_relative_eq!(total, lateral(0.05, 0.3, 0.6), max_relative = 1e-14);
        // A cylinder's band is 2π r L/bands; a sharp cone's whole side is π r √(L² + r²).
        let cylinder = Frustum::new(DVec3::ZERO, DVec3::Z, 2.0, [0.5, 0.5]).unwrap();
        assert_relative_eq!(
            cylinder.band_area(3, 5),
            std::f64::consts::TAU * 0.5 * 2.0 / 5.0,
            max_relative = 1e-15
        );
        let sharp = Frustum::new(DVec3::ZERO, DVec3::Z, 1.0, [0.0, 0.75]).unwrap();
        assert_relative_eq!(
            sharp.band_area(0, 1),
            std::f64::consts::PI * 0.75 * 1.25,
            max_relative = 1e-15
        );
    }

    #[test]
    fn bad_frusta_are_refused_with_the_setting() {
        for (axis, length, radii, what) in [
            (DVec3::ZERO, 1.0, [1.0, 1.0], "axis"),
            (DVec3::Z, 0.0, [1.0, 1.0], "length"),
            (DVec3::Z, f64::INFINITY, [1.0, 0.5], "length"),
            (DVec3::Z, 1.0, [-1.0, 1.0], "radii"),
            (DVec3::Z, 1.0, [0.0, 0.0], "radii"),
            (DVec3::Z, 1.0, [f64::NAN, 1.0], "radii"),
        ] {
            let e = Frustum::new(DVec3::ZERO, axis, length, radii).unwrap_err();
            assert!(e.to_string().contains(what), "{e}");
        }
    }
}
