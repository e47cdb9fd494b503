//! Walls (docs/physics.md §5): a wall is a body of infinite radius and mass, of one of the
//! shapes in [`WallShape`], each in a file of its own with the operations the neighbour
//! search and the force loops need of it (closest point, contact normal, a cheap test for
//! far points). A new shape is a new file and a new arm in each `match` of this file.

mod plane;
mod polygon;
#[cfg(test)]
mod tests;

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::material::{Interaction, WallMaterial};
pub use plane::Plane;
pub use polygon::Polygon;

/// Stable handle of a wall; survives the removal of other walls.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct WallId(pub u32);

/// The shape of a wall.
#[derive(Debug, Clone, PartialEq)]
pub enum WallShape {
    /// An infinite plane ([`Plane`]).
    Plane(Plane),
    /// A finite convex planar polygon, two-sided ([`Polygon`]).
    Polygon(Polygon),
}

impl WallShape {
    /// The shape as a plane x·n = offset (unit normal n, offset [m]) when it is an infinite
    /// plane, which the force loops filter with one dot product per candidate; `None` for
    /// shapes that need the general closest-point test.
    #[inline]
    pub fn as_plane(&self) -> Option<(DVec3, f64)> {
        match self {
            WallShape::Plane(p) => Some(p.normal_and_offset()),
            WallShape::Polygon(_) => None,
        }
    }

    /// True when the shape is unbounded, so that nearly every body is a neighbour-list
    /// candidate of some such wall (the slab's faces) and the search tests every body
    /// without a branch on the outcome; a bounded shape is screened with
    /// [`Wall::certainly_beyond`] first.
    #[inline]
    pub fn is_unbounded(&self) -> bool {
        match self {
            WallShape::Plane(_) => true,
            WallShape::Polygon(_) => false,
        }
    }
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

/// A wall as the engine stores it: its shape in a form ready for contact detection, its
/// motion and what it is made of.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(from = "record::WallRecord", into = "record::WallRecord")]
pub struct Wall {
    shape: WallShape,
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
        Ok(Self::of(
            WallShape::Plane(Plane::new(point, normal)?),
            material,
            interaction,
        ))
    }

    /// A convex planar polygon (a rectangle, a triangle, …).
    pub fn polygon(
        vertices: Vec<DVec3>,
        material: WallMaterial,
        interaction: Interaction,
    ) -> Result<Self, WallError> {
        Ok(Self::of(
            WallShape::Polygon(Polygon::new(vertices)?),
            material,
            interaction,
        ))
    }

    /// A wall of `shape` at rest.
    fn of(shape: WallShape, material: WallMaterial, interaction: Interaction) -> Self {
        Self {
            shape,
            velocity: DVec3::ZERO,
            material,
            interaction,
        }
    }

    /// The wall's shape.
    pub fn shape(&self) -> &WallShape {
        &self.shape
    }

    /// Moves the wall rigidly by `offset` [m].
    pub fn translate(&mut self, offset: DVec3) {
        match &mut self.shape {
            WallShape::Plane(p) => p.translate(offset),
            WallShape::Polygon(p) => p.translate(offset),
        }
    }

    /// Closest point of the wall to `x` and the distance to it.
    ///
    /// For a plane the distance is signed along its normal (negative behind it, on the
    /// solid side). For a polygon it is the Euclidean distance to the face, an edge or a
    /// corner.
    #[inline(always)]
    pub fn closest_point(&self, x: DVec3) -> (DVec3, f64) {
        match &self.shape {
            WallShape::Plane(p) => p.closest_point(x),
            WallShape::Polygon(p) => p.closest_point(x),
        }
    }

    /// True when `x` is certainly farther than `reach` [m] from the wall, by a test cheaper
    /// than [`Wall::closest_point`]; false when the shape has no such test (a plane).
    #[inline(always)]
    pub fn certainly_beyond(&self, x: DVec3, reach: f64) -> bool {
        match &self.shape {
            WallShape::Plane(_) => false,
            WallShape::Polygon(p) => p.certainly_beyond(x, reach),
        }
    }

    /// Contact normal (wall to particle) for a particle at `x` whose closest wall point is `p`
    /// at distance `dist`.
    #[inline(always)]
    pub fn contact_normal(&self, x: DVec3, p: DVec3, dist: f64) -> DVec3 {
        match &self.shape {
            WallShape::Plane(plane) => plane.contact_normal(),
            WallShape::Polygon(polygon) => polygon.contact_normal(x, p, dist),
        }
    }

    /// Velocity of the wall's material point at `_x` [m/s]: walls translate rigidly and do
    /// not spin (docs/physics.md §5), so it is the same everywhere.
    #[inline(always)]
    pub fn velocity_at(&self, _x: DVec3) -> DVec3 {
        self.velocity
    }
}

mod record {
    //! The stored form of a wall, field for field the layout checkpoints have always held,
    //! so that the shapes' types can change without changing a checkpoint's bytes.

    use super::*;

    /// The shape as stored.
    #[derive(Serialize, Deserialize)]
    pub(super) enum ShapeRecord {
        Plane { point: DVec3, normal: DVec3 },
        Polygon { vertices: Vec<DVec3> },
    }

    /// A wall as stored: its shape, the unit normal of the plane or polygon, the polygon's
    /// inward edge normals (empty for a plane), then its motion and material.
    #[derive(Serialize, Deserialize)]
    pub(super) struct WallRecord {
        shape: ShapeRecord,
        normal: DVec3,
        edge_normals: Vec<DVec3>,
        velocity: DVec3,
        material: WallMaterial,
        interaction: Interaction,
    }

    impl From<Wall> for WallRecord {
        fn from(w: Wall) -> Self {
            let (shape, normal, edge_normals) = match w.shape {
                WallShape::Plane(p) => (
                    ShapeRecord::Plane {
                        point: p.point,
                        normal: p.normal,
                    },
                    p.normal,
                    Vec::new(),
                ),
                WallShape::Polygon(p) => (
                    ShapeRecord::Polygon {
                        vertices: p.vertices,
                    },
                    p.normal,
                    p.edge_normals,
                ),
            };
            Self {
                shape,
                normal,
                edge_normals,
                velocity: w.velocity,
                material: w.material,
                interaction: w.interaction,
            }
        }
    }

    impl From<WallRecord> for Wall {
        fn from(r: WallRecord) -> Self {
            let shape = match r.shape {
                ShapeRecord::Plane { point, normal } => WallShape::Plane(Plane { point, normal }),
                ShapeRecord::Polygon { vertices } => WallShape::Polygon(Polygon {
                    vertices,
                    normal: r.normal,
                    edge_normals: r.edge_normals,
                }),
            };
            Self {
                shape,
                velocity: r.velocity,
                material: r.material,
                interaction: r.interaction,
            }
        }
    }
}
