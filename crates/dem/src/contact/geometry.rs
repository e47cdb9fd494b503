//! The contact geometry of each shape pair (docs/physics.md §1, §5): normal, overlap,
//! effective radius and mass, and the levers from the centres to the contact point. Pure
//! functions; the one-contact path calls them whole, the batched kernel (`forces::kernel`)
//! calls the scalar pieces lane by lane.

use glam::DVec3;

use super::ContactGeometry;
use crate::material::harmonic;

/// One body of a contact as its geometry needs it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sphere {
    /// Radius R [m].
    pub radius: f64,
    /// Mass m [kg].
    pub mass: f64,
    /// Moment of inertia I [kg m²].
    pub inertia: f64,
}

/// Lever a = R − δ/2 [m] from a sphere's centre to the contact point, for radius `r` [m]
/// and overlap `overlap` [m] (docs/physics.md §1).
#[inline(always)]
pub fn lever_arm(r: f64, overlap: f64) -> f64 {
    r - 0.5 * overlap
}

/// Effective radius R* = R_i R_j/(R_i + R_j) [m], given the sum `sum` = R_i + R_j already
/// formed for the overlap (the same number as `harmonic(ri, rj)`).
#[inline(always)]
pub fn effective_radius(ri: f64, rj: f64, sum: f64) -> f64 {
    ri * rj / sum
}

/// Sphere–sphere: the geometry of spheres `i` and `j` whose centres are `d` = x_i − x_j
/// apart, at squared distance `dist2` = |d|² < (R_i + R_j)² [m²]. The normal points from j
/// to i.
#[inline(always)]
pub fn sphere_sphere(d: DVec3, dist2: f64, i: &Sphere, j: &Sphere) -> ContactGeometry {
    let (ri, rj) = (i.radius, j.radius);
    let sum = ri + rj;
    let dist = dist2.sqrt();
    let overlap = sum - dist;
    ContactGeometry {
        normal: d * (1.0 / dist),
        overlap,
        r_eff: effective_radius(ri, rj, sum),
        m_eff: harmonic(i.mass, j.mass),
        arm_i: lever_arm(ri, overlap),
        arm_j: lever_arm(rj, overlap),
        inertia: [i.inertia, j.inertia],
        mass_radius2: [i.mass * ri * ri, j.mass * rj * rj],
        radius: [ri, rj],
    }
}

/// Signed distance x·n − offset [m] of a point from the plane x·n = offset: the
/// sphere–plane test, a sphere of radius R touching where the distance is below R.
#[inline(always)]
pub fn plane_distance(x: DVec3, normal: DVec3, offset: f64) -> f64 {
    x.dot(normal) - offset
}

/// Sphere–wall, any wall shape: the geometry of sphere `i` whose closest wall point lies
/// at distance `dist` < R_i along the unit `normal` (wall to sphere). A wall is a body of
/// infinite radius and mass (docs/physics.md §5): R* = R_i, m* = m_i, no lever on its side.
#[inline(always)]
pub fn sphere_wall(normal: DVec3, dist: f64, i: &Sphere) -> ContactGeometry {
    let ri = i.radius;
    let overlap = ri - dist;
    ContactGeometry {
        normal,
        overlap,
        r_eff: ri,
        m_eff: i.mass,
        arm_i: lever_arm(ri, overlap),
        arm_j: 0.0,
        inertia: [i.inertia, f64::INFINITY],
        mass_radius2: [i.mass * ri * ri, f64::INFINITY],
        radius: [ri, f64::INFINITY],
    }
}
