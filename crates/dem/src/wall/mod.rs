//! Walls (docs/physics.md §5): a wall is a body of infinite radius and mass, of one of the
//! shapes in [`WallShape`]. Each shape is a file of its own implementing
//! [`WallGeometry`](geometry::WallGeometry), every operation the neighbour search, the force
//! loops and the wall's motion need of it; [`WallShape::visit`] and
//! [`WallShape::geometry_mut`] are the only `match`es over the shapes, both exhaustive.
//!
//! A new shape: a file with its type, its construction checks and its `WallGeometry`
//! implementation (serialisable, for checkpoints), a variant of [`WallShape`], and its arm in
//! `visit` and in `geometry_mut`; a constructor on [`Wall`] if callers build it.

mod frustum;
pub(crate) mod geometry;
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
use geometry::{ShapeVisitor, SurfaceElements, WallGeometry};
pub use mesh::{Mesh, MeshContact, MeshScratch, NearTriangle};
pub use plane::Plane;
pub use polygon::Polygon;

/// Stable handle of a wall; survives the removal of other walls.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct WallId(pub u32);

/// The shape of a wall. Stored in checkpoints as the shape's own fields under the
/// variant's name (a mesh as its triangles and pose).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
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
    /// Runs `visitor` on the concrete shape: the one dispatch of the shapes' queries, so
    /// that each shape's code is compiled into the operation with static calls. Inlined, so
    /// that an operation on a known shape keeps only its arm.
    #[inline(always)]
    pub(crate) fn visit<'a, V: ShapeVisitor<'a>>(&'a self, visitor: V) -> V::Output {
        match self {
            WallShape::Plane(p) => visitor.visit(p),
            WallShape::Polygon(p) => visitor.visit(p),
            WallShape::Frustum(f) => visitor.visit(f),
            WallShape::Mesh(m) => visitor.visit(&**m),
        }
    }

    /// The shape as a trait object, for what is done once per wall rather than per body.
    pub(crate) fn geometry(&self) -> &dyn WallGeometry {
        struct AsDyn;
        impl<'a> ShapeVisitor<'a> for AsDyn {
            type Output = &'a dyn WallGeometry;
            fn visit<S: WallGeometry>(self, shape: &'a S) -> &'a dyn WallGeometry {
                shape
            }
        }
        self.visit(AsDyn)
    }

    /// The shape as a mutable trait object, to move it: the one dispatch of the shapes'
    /// changes.
    pub(crate) fn geometry_mut(&mut self) -> &mut dyn WallGeometry {
        match self {
            WallShape::Plane(p) => p,
            WallShape::Polygon(p) => p,
            WallShape::Frustum(f) => f,
            WallShape::Mesh(m) => &mut **m,
        }
    }

    /// The shape as a plane x·n = offset (unit normal n, offset [m]) when it is an infinite
    /// plane, which the force loops filter with one dot product per candidate; `None` for
    /// shapes that need the general closest-point test.
    #[inline]
    pub fn as_plane(&self) -> Option<(DVec3, f64)> {
        self.geometry().as_plane()
    }

    /// True when the shape is unbounded, so that nearly every body is a neighbour-list
    /// candidate of some such wall (the slab's faces) and the search tests every body
    /// without a branch on the outcome; a bounded shape is screened with
    /// [`Wall::certainly_beyond`] first.
    #[inline]
    pub fn is_unbounded(&self) -> bool {
        self.geometry().is_unbounded()
    }

    /// True for the shapes the batched wall loop does not take (a frustum, a mesh): their
    /// contacts are resolved one at a time after the other walls' (`forces::surfaces`).
    #[inline(always)]
    pub fn needs_surface_pass(&self) -> bool {
        struct Query;
        impl ShapeVisitor<'_> for Query {
            type Output = bool;
            #[inline(always)]
            fn visit<S: WallGeometry>(self, shape: &S) -> bool {
                shape.needs_surface_pass()
            }
        }
        self.visit(Query)
    }

    /// The parts the shape's element loads are booked to.
    pub(crate) fn elements(&self) -> SurfaceElements {
        self.geometry().elements()
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
        self.shape.needs_surface_pass() || self.angular_velocity != DVec3::ZERO
    }

    /// Turns the wall rigidly by `rotation` about the world point `centre` [m].
    pub fn rotate_about(&mut self, centre: DVec3, rotation: DQuat) {
        self.shape.geometry_mut().rotate_about(centre, rotation);
        self.centre = centre + rotation * (self.centre - centre);
    }

    /// The wall's shape.
    pub fn shape(&self) -> &WallShape {
        &self.shape
    }

    /// Moves the wall rigidly by `offset` [m].
    pub fn translate(&mut self, offset: DVec3) {
        self.shape.geometry_mut().translate(offset);
        self.centre += offset;
    }

    /// Closest point of the wall to `x` and the distance to it.
    ///
    /// For a plane the distance is signed along its normal (negative behind it, on the
    /// solid side). For a polygon it is the Euclidean distance to the face, an edge or a
    /// corner; for a frustum or a mesh, whose closest points are out of line, to the nearest
    /// point of the surface.
    #[inline(always)]
    pub fn closest_point(&self, x: DVec3) -> (DVec3, f64) {
        struct Query(DVec3);
        impl ShapeVisitor<'_> for Query {
            type Output = (DVec3, f64);
            #[inline(always)]
            fn visit<S: WallGeometry>(self, shape: &S) -> (DVec3, f64) {
                shape.closest_point(self.0)
            }
        }
        self.shape.visit(Query(x))
    }

    /// True when the wall comes closer than `reach` [m] to `x`: the neighbour search's test,
    /// which for a mesh looks only at the triangles in reach and stops at the first.
    #[inline]
    pub fn comes_within(&self, x: DVec3, reach: f64) -> bool {
        struct Query(DVec3, f64);
        impl ShapeVisitor<'_> for Query {
            type Output = bool;
            #[inline(always)]
            fn visit<S: WallGeometry>(self, shape: &S) -> bool {
                shape.comes_within(self.0, self.1)
            }
        }
        self.shape.visit(Query(x, reach))
    }

    /// True when `x` is certainly farther than `reach` [m] from the wall, by a test cheaper
    /// than [`Wall::closest_point`]; false when the shape has no such test (a plane).
    #[inline(always)]
    pub fn certainly_beyond(&self, x: DVec3, reach: f64) -> bool {
        struct Query(DVec3, f64);
        impl ShapeVisitor<'_> for Query {
            type Output = bool;
            #[inline(always)]
            fn visit<S: WallGeometry>(self, shape: &S) -> bool {
                shape.certainly_beyond(self.0, self.1)
            }
        }
        self.shape.visit(Query(x, reach))
    }

    /// Contact normal (wall to particle) for a particle at `x` whose closest wall point is `p`
    /// at distance `dist`.
    #[inline(always)]
    pub fn contact_normal(&self, x: DVec3, p: DVec3, dist: f64) -> DVec3 {
        struct Query(DVec3, DVec3, f64);
        impl ShapeVisitor<'_> for Query {
            type Output = DVec3;
            #[inline(always)]
            fn visit<S: WallGeometry>(self, shape: &S) -> DVec3 {
                shape.contact_normal(self.0, self.1, self.2)
            }
        }
        self.shape.visit(Query(x, p, dist))
    }

    /// The contacts of a sphere at `x` with radius `r` [m] with the wall on the surface pass,
    /// into `out`, each with the element it is booked to (of `bands` for a banded shape);
    /// `near` is the sphere's own cache of nearby triangles, `scratch` working memory
    /// ([`WallGeometry::surface_contacts`]).
    #[inline]
    pub(crate) fn surface_contacts(
        &self,
        sphere: (DVec3, f64),
        bands: usize,
        near: &mut geometry::NearCache,
        scratch: &mut MeshScratch,
        out: &mut Vec<MeshContact>,
    ) {
        struct Query<'b> {
            sphere: (DVec3, f64),
            bands: usize,
            near: &'b mut geometry::NearCache,
            scratch: &'b mut MeshScratch,
            out: &'b mut Vec<MeshContact>,
        }
        impl ShapeVisitor<'_> for Query<'_> {
            type Output = ();
            #[inline(always)]
            fn visit<S: WallGeometry>(self, shape: &S) {
                shape.surface_contacts(self.sphere, self.bands, self.near, self.scratch, self.out);
            }
        }
        self.shape.visit(Query {
            sphere,
            bands,
            near,
            scratch,
            out,
        });
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

    use super::{Interaction, Wall, WallError, WallMaterial, WallMotion, WallShape};
    use serde::{Deserialize, Serialize};

    /// A wall as stored.
    #[derive(Serialize, Deserialize)]
    pub(super) struct WallRecord {
        shape: WallShape,
        motion: WallMotion,
        sums_load: bool,
        material: WallMaterial,
        interaction: Interaction,
    }

    impl From<Wall> for WallRecord {
        fn from(w: Wall) -> Self {
            Self {
                motion: w.motion(),
                shape: w.shape,
                sums_load: w.sums_load,
                material: w.material,
                interaction: w.interaction,
            }
        }
    }

    impl TryFrom<WallRecord> for Wall {
        type Error = WallError;

        fn try_from(r: WallRecord) -> Result<Self, WallError> {
            let mut w = Wall::of(r.shape, r.material, r.interaction);
            w.set_motion(r.motion)?;
            w.sums_load = r.sums_load;
            Ok(w)
        }
    }
}
