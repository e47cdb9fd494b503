//! What the engine asks of a wall shape: the one trait every shape implements in its own
//! file, and the two ways to reach it through [`WallShape`](super::WallShape).
//!
//! The neighbour search, the force loops, the surface pass and the wall's motion use a
//! shape only through [`WallGeometry`]. [`WallShape::visit`](super::WallShape::visit) hands
//! the concrete shape to a [`ShapeVisitor`], so a loop written generically over the trait is
//! compiled once per shape and calls no method through a pointer; the cold uses (moving a
//! wall, counting its elements) take `&dyn WallGeometry` instead. Both are one exhaustive
//! `match` over the shapes, in `wall/mod.rs`: a shape left out does not compile.

use glam::{DQuat, DVec3};

use super::mesh::{MeshContact, MeshScratch, NearTriangle};

/// The parts of a wall its element loads are booked to (docs/physics.md §5.5).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum SurfaceElements {
    /// None: only the wall's total load is summed (a plane, a polygon).
    None,
    /// One per triangle, this many (a mesh).
    Triangles(usize),
    /// Bands of equal length along an axis, as many as the user sets, one at first (a
    /// cylinder or cone).
    Bands,
}

/// The triangles of a mesh found near a sphere on an earlier step and where the sphere was
/// then, kept with the sphere's contacts so that the mesh's index is searched again only
/// after the sphere has moved (`Mesh`'s [`WallGeometry::surface_contacts`]). Unused by the
/// other shapes.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct NearCache {
    /// Triangles within reach plus the margin of `anchor`.
    pub near: Vec<NearTriangle>,
    /// Where the sphere's centre was, in the mesh's frame, when `near` was found [m]; none
    /// until then.
    pub anchor: Option<DVec3>,
}

/// One wall shape's geometry: every operation the engine needs of a shape. A new shape is a
/// file implementing this trait and a variant of [`WallShape`](super::WallShape) with its
/// arm in `WallShape::visit` and `WallShape::geometry_mut`.
///
/// The methods without a default are the ones a shape cannot leave out without being
/// wrong; the defaults are correct for every shape and only slower than a shape's own test.
pub(crate) trait WallGeometry {
    /// Closest point of the shape to `x` and the distance to it [m]: Euclidean, or signed
    /// along the normal (negative on the solid side) for a one-sided shape (a plane).
    fn closest_point(&self, x: DVec3) -> (DVec3, f64);

    /// Contact normal (wall to particle) for a particle at `x` whose closest point of the
    /// shape is `p` at distance `dist`.
    fn contact_normal(&self, x: DVec3, p: DVec3, dist: f64) -> DVec3;

    /// True when `x` is certainly farther than `reach` [m] from the shape, by a test cheaper
    /// than [`WallGeometry::closest_point`]. Default: false, no such test.
    #[inline(always)]
    fn certainly_beyond(&self, _x: DVec3, _reach: f64) -> bool {
        false
    }

    /// True when the shape comes closer than `reach` [m] to `x`: the neighbour search's
    /// test. Default: the closest point's distance.
    #[inline(always)]
    fn comes_within(&self, x: DVec3, reach: f64) -> bool {
        self.closest_point(x).1 < reach
    }

    /// True when the shape is unbounded, so that nearly every body may be its neighbour and
    /// the search tests each without a branch on the outcome (`neighbour::walls`).
    fn is_unbounded(&self) -> bool;

    /// The shape as a plane x·n = offset (unit normal n, offset [m]) when it is an infinite
    /// plane, which the batched wall loop filters with one dot product per candidate.
    /// Default: none.
    #[inline(always)]
    fn as_plane(&self) -> Option<(DVec3, f64)> {
        None
    }

    /// True when the batched wall loop cannot take the shape: its contacts are resolved
    /// after the other walls' by the surface pass (`forces::surfaces`), through
    /// [`WallGeometry::surface_contacts`]; false when [`WallGeometry::closest_point`] and
    /// [`WallGeometry::contact_normal`] give its one contact with a sphere.
    fn needs_surface_pass(&self) -> bool;

    /// The parts the shape's element loads are booked to.
    fn elements(&self) -> SurfaceElements;

    /// The contacts of a sphere at `x` with radius `r` [m], into `out` (cleared first) in a
    /// fixed order, each with the element it is booked to, of `bands` for a banded shape.
    /// `near` is the sphere's own cache, `scratch` shared working memory. Default: the one
    /// contact at the closest point, if nearer than `r`, booked to element 0.
    #[inline]
    fn surface_contacts(
        &self,
        (x, r): (DVec3, f64),
        _bands: usize,
        _near: &mut NearCache,
        _scratch: &mut MeshScratch,
        out: &mut Vec<MeshContact>,
    ) {
        out.clear();
        let (point, distance) = self.closest_point(x);
        if distance < r {
            out.push(MeshContact {
                point,
                normal: self.contact_normal(x, point, distance),
                distance,
                triangle: 0,
            });
        }
    }

    /// Moves the shape rigidly by `offset` [m].
    fn translate(&mut self, offset: DVec3);

    /// Turns the shape rigidly by `rotation` about the world point `centre` [m].
    fn rotate_about(&mut self, centre: DVec3, rotation: DQuat);
}

/// An operation generic over the shape, which [`WallShape::visit`](super::WallShape::visit)
/// runs on the concrete shape: compiled once per shape, with static calls. A loop over many
/// bodies is written inside `visit`, so that the shape is matched once per loop.
pub(crate) trait ShapeVisitor<'a> {
    /// What the operation returns.
    type Output;
    /// Runs the operation on `shape`.
    fn visit<S: WallGeometry>(self, shape: &'a S) -> Self::Output;
}
