//! Walls (docs/physics.md §5): a wall is a body of infinite radius and mass, of one of the
//! shapes in [`WallShape`], each in a file of its own with the operations the neighbour
//! search and the force loops need of it (closest point, contact normal, a cheap test for
//! far points). A new shape is a new file and a new arm in each `match` of this file.

mod frustum;
mod mesh;
mod mesh_index;
mod plane;
mod polygon;
#[cfg(test)]
mod tests;
pub mod triangle;

use glam::{DQuat, DVec3};
use serde::{Deserialize, Serialize};

use crate::material::{Interaction, WallMaterial};
pub use frustum::Frustum;
pub use mesh::{Mesh, MeshContact, MeshScratch, NearTriangle};
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
    /// A cylinder or cone frustum, two-sided ([`Frustum`]).
    Frustum(Frustum),
    /// A surface of triangles, two-sided ([`Mesh`]).
    Mesh(Box<Mesh>),
}

impl WallShape {
    /// The shape as a plane x·n = offset (unit normal n, offset [m]) when it is an infinite
    /// plane, which the force loops filter with one dot product per candidate; `None` for
    /// shapes that need the general closest-point test.
    #[inline]
    pub fn as_plane(&self) -> Option<(DVec3, f64)> {
        match self {
            WallShape::Plane(p) => Some(p.normal_and_offset()),
            _ => None,
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
            WallShape::Frustum(f) => f.length().is_infinite(),
            WallShape::Polygon(_) | WallShape::Mesh(_) => false,
        }
    }

    /// True for the shapes the batched wall loop does not take (a frustum, a mesh): their
    /// contacts are resolved one at a time after the other walls' (`forces::surfaces`).
    #[inline]
    pub fn is_curved_or_meshed(&self) -> bool {
        matches!(self, WallShape::Frustum(_) | WallShape::Mesh(_))
    }
}

/// True when some wall of `walls` (by index, `None` where removed) is resolved one contact
/// at a time ([`Wall::resolved_one_by_one`]): the surface pass and its remembered contacts
/// are needed.
#[inline]
pub fn any_resolved_one_by_one(walls: &[Option<Wall>]) -> bool {
    walls.iter().flatten().any(Wall::resolved_one_by_one)
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
    /// A mesh without triangles.
    #[error("a wall mesh needs at least one triangle, got none")]
    EmptyMesh,
    /// A triangle of a mesh is unusable.
    #[error("wall mesh triangle {triangle} (counted from 0): {reason}")]
    BadTriangle {
        /// Index of the triangle in the list given.
        triangle: usize,
        /// What is wrong with it, with its numbers.
        reason: String,
    },
    /// A cylinder or cone setting out of range.
    #[error("cylinder/cone wall: {what}, got {value}")]
    BadAxisymmetric {
        /// The setting and its allowed range.
        what: String,
        /// The value given.
        value: String,
    },
    /// A wall motion setting out of range.
    #[error("wall motion: {0}")]
    BadMotion(String),
}

/// How a wall moves: a rigid motion, a translation velocity of the point `centre` and an
/// angular velocity about it. The contact uses the velocity of the wall's material point
/// at the contact, v + ω × (x − c) (docs/physics.md §5.4).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WallMotion {
    /// Velocity of `centre` [m/s].
    pub velocity: DVec3,
    /// Angular velocity about `centre` [rad/s].
    pub angular_velocity: DVec3,
    /// The point the wall turns about [m]; it moves with the wall when the wall is displaced.
    pub centre: DVec3,
    /// True: the wall is displaced by its motion every step (a sliding gate, a paddle).
    /// False: only its surface moves, the shape stays where it is (a conveyor belt, a drum
    /// turning about its own axis).
    pub displaced: bool,
}

impl Default for WallMotion {
    fn default() -> Self {
        Self {
            velocity: DVec3::ZERO,
            angular_velocity: DVec3::ZERO,
            centre: DVec3::ZERO,
            displaced: false,
        }
    }
}

impl WallMotion {
    /// Refuses non-finite settings.
    pub fn check(&self) -> Result<(), WallError> {
        for (what, v) in [
            ("velocity [m/s]", self.velocity),
            ("angular velocity [rad/s]", self.angular_velocity),
            ("centre [m]", self.centre),
        ] {
            if !v.is_finite() {
                return Err(WallError::BadMotion(format!(
                    "{what} must be finite, got {v}"
                )));
            }
        }
        Ok(())
    }
}

/// A wall as the engine stores it: its shape in a form ready for contact detection, its
/// motion and what it is made of.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "record::WallRecord", into = "record::WallRecord")]
pub struct Wall {
    shape: WallShape,
    /// Translational velocity used in the contact kinematics [m/s].
    pub velocity: DVec3,
    /// Angular velocity about `centre` used in the contact kinematics [rad/s].
    pub angular_velocity: DVec3,
    /// The point the wall turns about [m].
    pub centre: DVec3,
    /// Whether each step displaces the wall by its motion ([`WallMotion::displaced`]).
    pub displaced: bool,
    /// Whether the wall's total load is summed every step (`Simulation::wall_load`); on by
    /// default. It costs about 1.5 ns a contact (docs/performance.md), which a wall that
    /// every particle touches and no output reads (the faces of a quasi-2D slab) can spare.
    pub sums_load: bool,
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

    /// A cylinder (`radii` equal) or cone frustum about the axis from `base` along `axis`,
    /// `length` [m] long (infinite for an unbounded cylinder), with radii `radii` [m] at its
    /// two ends; two-sided.
    pub fn frustum(
        base: DVec3,
        axis: DVec3,
        length: f64,
        radii: [f64; 2],
        material: WallMaterial,
        interaction: Interaction,
    ) -> Result<Self, WallError> {
        Ok(Self::of(
            WallShape::Frustum(Frustum::new(base, axis, length, radii)?),
            material,
            interaction,
        ))
    }

    /// A cylinder of radius `radius` [m] about the axis from `base` along `axis`, `length`
    /// [m] long (infinite for an unbounded one); two-sided.
    pub fn cylinder(
        base: DVec3,
        axis: DVec3,
        length: f64,
        radius: f64,
        material: WallMaterial,
        interaction: Interaction,
    ) -> Result<Self, WallError> {
        Self::frustum(base, axis, length, [radius, radius], material, interaction)
    }

    /// A surface of `triangles` (corners [m]), two-sided; corners with equal coordinates
    /// are welded. Refused when empty, with a non-finite corner or with a degenerate
    /// triangle, naming the triangle.
    pub fn mesh(
        triangles: &[[DVec3; 3]],
        material: WallMaterial,
        interaction: Interaction,
    ) -> Result<Self, WallError> {
        Ok(Self::of(
            WallShape::Mesh(Box::new(Mesh::new(triangles)?)),
            material,
            interaction,
        ))
    }

    /// A wall of `shape` at rest.
    fn of(shape: WallShape, material: WallMaterial, interaction: Interaction) -> Self {
        Self {
            shape,
            velocity: DVec3::ZERO,
            angular_velocity: DVec3::ZERO,
            centre: DVec3::ZERO,
            displaced: false,
            sums_load: true,
            material,
            interaction,
        }
    }

    /// The wall's motion.
    pub fn motion(&self) -> WallMotion {
        WallMotion {
            velocity: self.velocity,
            angular_velocity: self.angular_velocity,
            centre: self.centre,
            displaced: self.displaced,
        }
    }

    /// Sets the wall's motion.
    pub fn set_motion(&mut self, motion: WallMotion) -> Result<(), WallError> {
        motion.check()?;
        self.velocity = motion.velocity;
        self.angular_velocity = motion.angular_velocity;
        self.centre = motion.centre;
        self.displaced = motion.displaced;
        Ok(())
    }

    /// True when the batched wall loop cannot take the wall: a curved or meshed shape, or
    /// a surface velocity that varies over the wall (a spin).
    #[inline]
    pub fn resolved_one_by_one(&self) -> bool {
        self.shape.is_curved_or_meshed() || self.angular_velocity != DVec3::ZERO
    }

    /// Turns the wall rigidly by `rotation` about the world point `centre` [m].
    pub fn rotate_about(&mut self, centre: DVec3, rotation: DQuat) {
        match &mut self.shape {
            WallShape::Plane(p) => p.rotate_about(centre, rotation),
            WallShape::Polygon(p) => p.rotate_about(centre, rotation),
            WallShape::Frustum(f) => f.rotate_about(centre, rotation),
            WallShape::Mesh(m) => m.rotate_about(centre, rotation),
        }
        self.centre = centre + rotation * (self.centre - centre);
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
            WallShape::Frustum(f) => f.translate(offset),
            WallShape::Mesh(m) => m.translate(offset),
        }
        self.centre += offset;
    }

    /// Closest point of the wall to `x` and the distance to it.
    ///
    /// For a plane the distance is signed along its normal (negative behind it, on the
    /// solid side). For a polygon it is the Euclidean distance to the face, an edge or a
    /// corner. The polygon's arm is tested first and alone, so that the force loop of
    /// polygons inlines no other shape's code.
    #[inline(always)]
    pub fn closest_point(&self, x: DVec3) -> (DVec3, f64) {
        match &self.shape {
            WallShape::Plane(p) => p.closest_point(x),
            WallShape::Polygon(p) => p.closest_point(x),
            _ => self.closest_point_of_surface(x),
        }
    }

    /// [`Wall::closest_point`] of a frustum or a mesh (for a mesh the nearest point of all
    /// its triangles), kept out of line.
    #[inline(never)]
    fn closest_point_of_surface(&self, x: DVec3) -> (DVec3, f64) {
        match &self.shape {
            WallShape::Frustum(f) => {
                let (p, d, _) = f.closest_point(x);
                (p, d)
            }
            WallShape::Mesh(m) => {
                let mut scratch = MeshScratch::default();
                let mut out = Vec::new();
                // Reach: grown until some triangle is within it.
                let mut reach = 1e-3;
                loop {
                    m.contacts(x, reach, &mut scratch, &mut out);
                    if let Some(c) = out.iter().min_by(|a, b| a.distance.total_cmp(&b.distance)) {
                        return (c.point, c.distance);
                    }
                    if !reach.is_finite() {
                        return (x, f64::INFINITY);
                    }
                    reach *= 4.0;
                }
            }
            WallShape::Plane(_) | WallShape::Polygon(_) => unreachable!("handled inline"),
        }
    }

    /// True when the wall comes closer than `reach` [m] to `x`: the neighbour search's test,
    /// which for a mesh looks only at the triangles in reach and stops at the first.
    #[inline]
    pub fn comes_within(&self, x: DVec3, reach: f64) -> bool {
        match &self.shape {
            WallShape::Mesh(m) => m.comes_within(x, reach),
            _ => self.closest_point(x).1 < reach,
        }
    }

    /// True when `x` is certainly farther than `reach` [m] from the wall, by a test cheaper
    /// than [`Wall::closest_point`]; false when the shape has no such test (a plane).
    #[inline(always)]
    pub fn certainly_beyond(&self, x: DVec3, reach: f64) -> bool {
        match &self.shape {
            WallShape::Plane(_) => false,
            WallShape::Polygon(p) => p.certainly_beyond(x, reach),
            WallShape::Frustum(f) => f.certainly_beyond(x, reach),
            WallShape::Mesh(m) => m.certainly_beyond(x, reach),
        }
    }

    /// Contact normal (wall to particle) for a particle at `x` whose closest wall point is `p`
    /// at distance `dist`.
    #[inline(always)]
    pub fn contact_normal(&self, x: DVec3, p: DVec3, dist: f64) -> DVec3 {
        match &self.shape {
            WallShape::Plane(plane) => plane.contact_normal(),
            WallShape::Polygon(polygon) => polygon.contact_normal(x, p, dist),
            WallShape::Frustum(f) => f.contact_normal(x, p, dist),
            WallShape::Mesh(_) => {
                if dist > 0.0 {
                    (x - p) / dist
                } else {
                    DVec3::Z
                }
            }
        }
    }

    /// Velocity of the wall's material point at `x` [m/s]: v + ω × (x − c)
    /// (docs/physics.md §5.4).
    #[inline(always)]
    pub fn velocity_at(&self, x: DVec3) -> DVec3 {
        self.velocity + self.angular_velocity.cross(x - self.centre)
    }
}

mod record {
    //! The stored form of a wall: its shape by its defining numbers (a mesh by its triangles
    //! and pose, rebuilt with its index on loading), then its motion and material.

    use super::*;

    /// The shape as stored.
    #[derive(Serialize, Deserialize)]
    pub(super) enum ShapeRecord {
        Plane {
            point: DVec3,
            normal: DVec3,
        },
        Polygon {
            vertices: Vec<DVec3>,
            normal: DVec3,
            edge_normals: Vec<DVec3>,
        },
        Frustum(Frustum),
        Mesh {
            triangles: Vec<[DVec3; 3]>,
            rotation: DQuat,
            translation: DVec3,
        },
    }

    /// A wall as stored.
    #[derive(Serialize, Deserialize)]
    pub(super) struct WallRecord {
        shape: ShapeRecord,
        motion: WallMotion,
        sums_load: bool,
        material: WallMaterial,
        interaction: Interaction,
    }

    impl From<Wall> for WallRecord {
        fn from(w: Wall) -> Self {
            let motion = w.motion();
            let shape = match w.shape {
                WallShape::Plane(p) => ShapeRecord::Plane {
                    point: p.point,
                    normal: p.normal,
                },
                WallShape::Polygon(p) => ShapeRecord::Polygon {
                    vertices: p.vertices,
                    normal: p.normal,
                    edge_normals: p.edge_normals,
                },
                WallShape::Frustum(f) => ShapeRecord::Frustum(f),
                WallShape::Mesh(m) => {
                    let (triangles, rotation, translation) = m.parts();
                    ShapeRecord::Mesh {
                        triangles,
                        rotation,
                        translation,
                    }
                }
            };
            Self {
                shape,
                motion,
                sums_load: w.sums_load,
                material: w.material,
                interaction: w.interaction,
            }
        }
    }

    impl TryFrom<WallRecord> for Wall {
        type Error = WallError;

        fn try_from(r: WallRecord) -> Result<Self, WallError> {
            let shape = match r.shape {
                ShapeRecord::Plane { point, normal } => WallShape::Plane(Plane { point, normal }),
                ShapeRecord::Polygon {
                    vertices,
                    normal,
                    edge_normals,
                } => WallShape::Polygon(Polygon {
                    vertices,
                    normal,
                    edge_normals,
                }),
                ShapeRecord::Frustum(f) => WallShape::Frustum(f),
                ShapeRecord::Mesh {
                    triangles,
                    rotation,
                    translation,
                } => {
                    let mut m = Mesh::new(&triangles)?;
                    m.set_pose(rotation, translation);
                    WallShape::Mesh(Box::new(m))
                }
            };
            let mut w = Wall::of(shape, r.material, r.interaction);
            w.set_motion(r.motion)?;
            w.sums_load = r.sums_load;
            Ok(w)
        }
    }
}
