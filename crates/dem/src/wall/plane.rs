//! The infinite plane: a wall whose solid side lies behind its unit normal (docs/physics.md §5).

use glam::{DQuat, DVec3};
use serde::{Deserialize, Serialize};

use super::geometry::{SurfaceElements, WallGeometry};
use super::WallError;

/// An infinite plane through `point` whose solid side lies behind `normal`; particles live
/// on the side `normal` points to and are pushed along it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Plane {
    /// A point of the plane [m].
    pub(super) point: DVec3,
    /// Unit normal towards the particles [-].
    pub(super) normal: DVec3,
}

impl Plane {
    /// The plane through `point` with normal `normal` (any finite non-zero length; stored
    /// as a unit vector).
    pub(super) fn new(point: DVec3, normal: DVec3) -> Result<Self, WallError> {
        let len = normal.length();
        if !(len.is_finite() && len > 0.0) || !point.is_finite() {
            return Err(WallError::BadNormal(normal));
        }
        Ok(Self {
            point,
            normal: normal / len,
        })
    }

    /// A point of the plane [m].
    pub fn point(&self) -> DVec3 {
        self.point
    }

    /// Unit normal towards the particles [-].
    pub fn normal(&self) -> DVec3 {
        self.normal
    }

    /// The plane as x·n = offset: its unit normal n and offset [m]. The force loop's filter
    /// tests every candidate of a plane with this one dot product.
    #[inline]
    pub fn normal_and_offset(&self) -> (DVec3, f64) {
        (self.normal, self.point.dot(self.normal))
    }
}

impl WallGeometry for Plane {
    /// The closest point and the distance signed along the normal (negative behind the
    /// plane).
    #[inline(always)]
    fn closest_point(&self, x: DVec3) -> (DVec3, f64) {
        let s = (x - self.point).dot(self.normal);
        (x - s * self.normal, s)
    }

    /// The plane's own normal, wherever the particle is.
    #[inline(always)]
    fn contact_normal(&self, _x: DVec3, _p: DVec3, _dist: f64) -> DVec3 {
        self.normal
    }

    #[inline(always)]
    fn is_unbounded(&self) -> bool {
        true
    }

    #[inline(always)]
    fn as_plane(&self) -> Option<(DVec3, f64)> {
        Some(self.normal_and_offset())
    }

    #[inline(always)]
    fn needs_surface_pass(&self) -> bool {
        false
    }

    fn elements(&self) -> SurfaceElements {
        SurfaceElements::None
    }

    fn translate(&mut self, offset: DVec3) {
        self.point += offset;
    }

    fn rotate_about(&mut self, centre: DVec3, rotation: DQuat) {
        self.point = centre + rotation * (self.point - centre);
        self.normal = (rotation * self.normal).normalize();
    }
}
