//! The finite convex planar polygon: a two-sided wall whose contacts are with its face, an
//! edge or a corner, whichever holds the closest point (docs/physics.md §5).

use glam::{DQuat, DVec3};
use serde::{Deserialize, Serialize};

use super::geometry::{SurfaceElements, WallGeometry};
use super::WallError;

/// A finite convex planar polygon, two-sided.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Polygon {
    /// Vertices in order around the polygon [m]; at least three, coplanar and convex.
    pub(super) vertices: Vec<DVec3>,
    /// Unit normal of the polygon's plane [-].
    pub(super) normal: DVec3,
    /// Inward edge normals, in the polygon's plane: edge k runs from vertex k to k + 1.
    pub(super) edge_normals: Vec<DVec3>,
}

impl Polygon {
    /// The polygon of `vertices`, checked to be at least three finite, coplanar points
    /// around a convex outline.
    pub(super) fn new(vertices: Vec<DVec3>) -> Result<Self, WallError> {
        let n = vertices.len();
        if n < 3 || vertices.iter().any(|v| !v.is_finite()) {
            return Err(WallError::TooFewVertices(n));
        }
        // Newell's method: robust normal of a planar polygon.
        let mut normal = DVec3::ZERO;
        for k in 0..n {
            let (a, b) = (vertices[k], vertices[(k + 1) % n]);
            normal += DVec3::new(
                (a.y - b.y) * (a.z + b.z),
                (a.z - b.z) * (a.x + b.x),
                (a.x - b.x) * (a.y + b.y),
            );
        }
        let len = normal.length();
        if !(len > 0.0) {
            return Err(WallError::NotConvexPlanar(0));
        }
        let normal = normal / len;
        let size = (0..n)
            .map(|k| (vertices[(k + 1) % n] - vertices[k]).length())
            .fold(0.0, f64::max);
        let mut edge_normals = Vec::with_capacity(n);
        for k in 0..n {
            let (a, b) = (vertices[k], vertices[(k + 1) % n]);
            if ((a - vertices[0]).dot(normal)).abs() > 1e-9 * size {
                return Err(WallError::NotConvexPlanar(k));
            }
            let inward = normal.cross(b - a).normalize();
            // Convexity: every other vertex lies on the inner side of every edge.
            for (m, v) in vertices.iter().enumerate() {
                if (*v - a).dot(inward) < -1e-9 * size {
                    return Err(WallError::NotConvexPlanar(m));
                }
            }
            edge_normals.push(inward);
        }
        Ok(Self {
            vertices,
            normal,
            edge_normals,
        })
    }

    /// Vertices in order around the polygon [m].
    pub fn vertices(&self) -> &[DVec3] {
        &self.vertices
    }

    /// Unit normal of the polygon's plane [-] (the polygon is two-sided; this is the one
    /// Newell's method gives for the vertices' order).
    pub fn normal(&self) -> DVec3 {
        self.normal
    }
}

impl WallGeometry for Polygon {
    /// Moves the polygon by `offset` [m].
    fn translate(&mut self, offset: DVec3) {
        self.vertices.iter_mut().for_each(|v| *v += offset);
    }

    /// Turns the polygon by `rotation` about the world point `centre` [m].
    fn rotate_about(&mut self, centre: DVec3, rotation: DQuat) {
        for v in &mut self.vertices {
            *v = centre + rotation * (*v - centre);
        }
        self.normal = rotation * self.normal;
        for e in &mut self.edge_normals {
            *e = rotation * *e;
        }
    }

    /// Closest point of the polygon to `x` and the Euclidean distance to it: the foot of
    /// the perpendicular when it falls inside, otherwise the closest point of the nearest
    /// edge or corner.
    #[inline(always)]
    fn closest_point(&self, x: DVec3) -> (DVec3, f64) {
        let vertices = &self.vertices;
        let h = (x - vertices[0]).dot(self.normal);
        let q = x - h * self.normal;
        let n = vertices.len();
        let inside = vertices
            .iter()
            .zip(&self.edge_normals)
            .all(|(v, e)| (q - *v).dot(*e) >= 0.0);
        if inside {
            return (q, h.abs());
        }
        let mut best = (vertices[0], f64::INFINITY);
        for k in 0..n {
            let p = closest_on_segment(x, vertices[k], vertices[(k + 1) % n]);
            let d2 = (x - p).length_squared();
            if d2 < best.1 {
                best = (p, d2);
            }
        }
        (best.0, best.1.sqrt())
    }

    /// True when `x` is certainly farther than `reach` [m] from the polygon, by its distance
    /// from the polygon's plane alone, which never exceeds the distance to the polygon.
    #[inline(always)]
    fn certainly_beyond(&self, x: DVec3, reach: f64) -> bool {
        (x - self.vertices[0]).dot(self.normal).abs() >= reach
    }

    /// Contact normal (polygon to particle) for a particle at `x` whose closest point is `p`
    /// at distance `dist`: along x − p, or the plane's normal when x lies in the polygon.
    #[inline(always)]
    fn contact_normal(&self, x: DVec3, p: DVec3, dist: f64) -> DVec3 {
        if dist > 0.0 {
            (x - p) / dist
        } else {
            self.normal
        }
    }

    #[inline(always)]
    fn is_unbounded(&self) -> bool {
        false
    }

    #[inline(always)]
    fn needs_surface_pass(&self) -> bool {
        false
    }

    fn elements(&self) -> SurfaceElements {
        SurfaceElements::None
    }
}

/// Closest point of segment [a, b] to x.
#[inline]
fn closest_on_segment(x: DVec3, a: DVec3, b: DVec3) -> DVec3 {
    let ab = b - a;
    let t = ((x - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
    a + t * ab
}
