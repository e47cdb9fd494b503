//! Walls: infinite planes and finite convex planar polygons, with closest-point contact
//! (physics.md §5). A wall is a body of infinite radius and mass.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::material::{Interaction, WallMaterial};

/// Stable handle of a wall; survives the removal of other walls.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct WallId(pub u32);

/// The shape of a wall.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum WallShape {
    /// An infinite plane through `point` whose solid side lies behind `normal`; particles
    /// live on the side `normal` points to and are pushed along it.
    Plane {
        /// A point of the plane [m].
        point: DVec3,
        /// Unit normal towards the particles [-].
        normal: DVec3,
    },
    /// A finite convex planar polygon, two-sided; contacts with its face, edges and corners.
    Polygon {
        /// Vertices in order around the polygon [m]; at least three, coplanar and convex.
        vertices: Vec<DVec3>,
    },
}

/// Why a wall shape was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum WallError {
    /// The plane normal has zero or non-finite length.
    #[error("wall plane normal must be a finite non-zero vector, got {0:?}")]
    BadNormal(DVec3),
    /// Fewer than three vertices, or non-finite coordinates.
    #[error("a wall polygon needs at least three finite vertices, got {0}")]
    TooFewVertices(usize),
    /// The vertices are not coplanar and convex.
    #[error("wall polygon vertices must be coplanar and convex (vertex {0} is off)")]
    NotConvexPlanar(usize),
}

/// A wall as the engine stores it: its shape in a form ready for contact detection.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Wall {
    shape: WallShape,
    /// Unit normal of the plane or polygon [-].
    normal: DVec3,
    /// Inward edge normals of the polygon, in the polygon's plane (empty for a plane).
    edge_normals: Vec<DVec3>,
    /// Translational velocity used in the contact kinematics [m/s].
    pub velocity: DVec3,
    /// The wall's material.
    pub material: WallMaterial,
    /// Friction, rolling friction and restitution against particles.
    pub interaction: Interaction,
}

impl Wall {
    /// An infinite plane.
    pub fn plane(
        point: DVec3,
        normal: DVec3,
        material: WallMaterial,
        interaction: Interaction,
    ) -> Result<Self, WallError> {
        let len = normal.length();
        if !(len.is_finite() && len > 0.0) || !point.is_finite() {
            return Err(WallError::BadNormal(normal));
        }
        let normal = normal / len;
        Ok(Self {
            shape: WallShape::Plane { point, normal },
            normal,
            edge_normals: Vec::new(),
            velocity: DVec3::ZERO,
            material,
            interaction,
        })
    }

    /// A convex planar polygon (a rectangle, a triangle, …).
    pub fn polygon(
        vertices: Vec<DVec3>,
        material: WallMaterial,
        interaction: Interaction,
    ) -> Result<Self, WallError> {
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
            shape: WallShape::Polygon { vertices },
            normal,
            edge_normals,
            velocity: DVec3::ZERO,
            material,
            interaction,
        })
    }

    /// The wall's shape.
    pub fn shape(&self) -> &WallShape {
        &self.shape
    }

    /// Moves the wall rigidly by `offset` [m].
    pub fn translate(&mut self, offset: DVec3) {
        match &mut self.shape {
            WallShape::Plane { point, .. } => *point += offset,
            WallShape::Polygon { vertices } => vertices.iter_mut().for_each(|v| *v += offset),
        }
    }

    /// Closest point of the wall to `x` and the distance to it, or `None` when `x` is behind a plane.
    ///
    /// For a plane the distance is signed along its normal (the solid side is behind it).
    /// For a polygon it is the Euclidean distance to the face, an edge or a corner.
    #[inline(always)]
    pub fn closest_point(&self, x: DVec3) -> (DVec3, f64) {
        match &self.shape {
            WallShape::Plane { point, normal } => {
                let s = (x - *point).dot(*normal);
                (x - s * *normal, s)
            }
            WallShape::Polygon { vertices } => {
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
        }
    }

    /// True when `x` is certainly farther than `reach` [m] from a polygon, by its distance
    /// from the polygon's plane alone, which never exceeds the distance to the polygon.
    /// A cheap test to skip `closest_point`; always false for a plane.
    #[inline(always)]
    pub fn certainly_beyond(&self, x: DVec3, reach: f64) -> bool {
        match &self.shape {
            WallShape::Plane { .. } => false,
            WallShape::Polygon { vertices } => (x - vertices[0]).dot(self.normal).abs() >= reach,
        }
    }

    /// Contact normal (wall to particle) for a particle at `x` whose closest wall point is `p`
    /// at distance `dist`.
    #[inline(always)]
    pub fn contact_normal(&self, x: DVec3, p: DVec3, dist: f64) -> DVec3 {
        match &self.shape {
            WallShape::Plane { normal, .. } => *normal,
            WallShape::Polygon { .. } => {
                if dist > 0.0 {
                    (x - p) / dist
                } else {
                    self.normal
                }
            }
        }
    }
}

/// Closest point of segment [a, b] to x.
#[inline]
fn closest_on_segment(x: DVec3, a: DVec3, b: DVec3) -> DVec3 {
    let ab = b - a;
    let t = ((x - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
    a + t * ab
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn square() -> Wall {
        // Unit square in the z = 0 plane.
        let v = vec![
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
        ];
        Wall::polygon(v, WallMaterial::Rigid, Interaction::fan2023()).unwrap()
    }

    // Closest points are exact geometry; 1e-14 covers round-off of unit-sized coordinates.
    const GEOM_TOL: f64 = 1e-14;

    #[test]
    fn polygon_face_edge_and_corner_contacts_use_the_closest_point() {
        let w = square();
        let (p, d) = w.closest_point(DVec3::new(0.3, 0.4, 0.2));
        assert_relative_eq!(
            p.distance(DVec3::new(0.3, 0.4, 0.0)),
            0.0,
            epsilon = GEOM_TOL
        );
        assert_relative_eq!(d, 0.2, epsilon = GEOM_TOL);
        let (p, d) = w.closest_point(DVec3::new(1.3, 0.5, 0.4));
        assert_relative_eq!(
            p.distance(DVec3::new(1.0, 0.5, 0.0)),
            0.0,
            epsilon = GEOM_TOL
        );
        assert_relative_eq!(d, 0.5, epsilon = GEOM_TOL);
        let (p, d) = w.closest_point(DVec3::new(-0.3, -0.4, 0.0));
        assert_relative_eq!(p.distance(DVec3::ZERO), 0.0, epsilon = GEOM_TOL);
        assert_relative_eq!(d, 0.5, epsilon = GEOM_TOL);
        let n = w.contact_normal(DVec3::new(-0.3, -0.4, 0.0), p, d);
        assert_relative_eq!(
            n.distance(DVec3::new(-0.6, -0.8, 0.0)),
            0.0,
            epsilon = GEOM_TOL
        );
    }

    #[test]
    fn triangles_and_planes_are_accepted_and_non_convex_polygons_refused() {
        let tri = vec![DVec3::ZERO, DVec3::X, DVec3::Y];
        assert!(Wall::polygon(tri, WallMaterial::Rigid, Interaction::fan2023()).is_ok());
        let dart = vec![
            DVec3::ZERO,
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(1.0, 0.2, 0.0),
            DVec3::new(1.0, 2.0, 0.0),
        ];
        assert!(matches!(
            Wall::polygon(dart, WallMaterial::Rigid, Interaction::fan2023()),
            Err(WallError::NotConvexPlanar(_))
        ));
        assert!(Wall::plane(
            DVec3::ZERO,
            DVec3::ZERO,
            WallMaterial::Rigid,
            Interaction::fan2023()
        )
        .is_err());
        let plane = Wall::plane(
            DVec3::ZERO,
            DVec3::new(0.0, 0.0, 2.0),
            WallMaterial::Rigid,
            Interaction::fan2023(),
        )
        .unwrap();
        assert_relative_eq!(
            plane.closest_point(DVec3::new(5.0, 1.0, 0.25)).1,
            0.25,
            epsilon = GEOM_TOL
        );
    }

    #[test]
    fn translating_a_wall_moves_its_closest_point() {
        let mut w = square();
        w.translate(DVec3::new(0.0, 0.0, -0.5));
        assert_relative_eq!(
            w.closest_point(DVec3::new(0.5, 0.5, 0.0)).1,
            0.5,
            epsilon = GEOM_TOL
        );
    }

    #[test]
    fn the_plane_test_never_rejects_a_point_within_reach_of_a_polygon() {
        // `certainly_beyond` may only skip points whose true distance is at least `reach`;
        // points all around a tilted quadrilateral, at distances on both sides of the reach,
        // must each be skipped only when `closest_point` puts them that far. Some must be
        // skipped, or the test would pass with a test that never skips.
        use rand::{Rng, SeedableRng};
        let w = Wall::polygon(
            vec![
                DVec3::new(0.0, 0.0, 0.2),
                DVec3::new(1.0, 0.0, 0.0),
                DVec3::new(1.0, 1.0, 0.0),
                DVec3::new(0.0, 1.0, 0.2),
            ],
            WallMaterial::Rigid,
            Interaction::fan2023(),
        )
        .unwrap();
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(3);
        let mut skipped = 0;
        for _ in 0..20_000 {
            let x = DVec3::new(
                3.0 * rng.gen::<f64>() - 1.0,
                3.0 * rng.gen::<f64>() - 1.0,
                2.0 * rng.gen::<f64>() - 1.0,
            );
            let reach = 0.5 * rng.gen::<f64>();
            if w.certainly_beyond(x, reach) {
                skipped += 1;
                assert!(w.closest_point(x).1 >= reach, "{x} skipped within {reach}");
            }
        }
        assert!(skipped > 1000, "only {skipped} skipped");
        let plane = Wall::plane(
            DVec3::ZERO,
            DVec3::Z,
            WallMaterial::Rigid,
            Interaction::fan2023(),
        )
        .unwrap();
        assert!(!plane.certainly_beyond(DVec3::new(0.0, 0.0, 9.0), 1.0));
    }
}
