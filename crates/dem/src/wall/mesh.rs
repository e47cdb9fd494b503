//! The triangle-mesh wall: a surface of triangles, two-sided, in a pose of its own
//! (docs/physics.md §5.3).
//!
//! A sphere near several triangles gets one contact per part of the surface it touches, not
//! one per triangle. Each triangle within reach reports the feature that holds its closest
//! point: its face, an edge or a corner. Triangles share welded edges and corners, and:
//! - a face contact always counts;
//! - an edge or corner contact counts once, and only where every triangle having that edge
//!   or corner reports it: then the sphere's centre lies in the feature's own region of
//!   space (its Voronoi region), off every face around it. A coplanar neighbour's edge seen
//!   past the face the sphere sits on, or an edge of the face it sits on, does not count.
//!
//! On a flat or convex region this leaves exactly one contact, the one an analytic plane or
//! a rounded edge would give; in a concave fold (a floor meeting a side) it leaves one per
//! face touched, as a sphere resting in the fold needs. Should round-off leave no feature
//! standing while some triangle is within reach (a centre exactly over a corner, seen as an
//! edge by one triangle), the nearest one counts, so a touching sphere always has a contact.

use glam::{DQuat, DVec3};
use serde::{Deserialize, Serialize};

use super::geometry::{NearCache, SurfaceElements, WallGeometry};
use super::mesh_index::TriangleGrid;
use super::triangle::{area2_and_normal, closest_point, Feature};
use super::WallError;

/// How far, as a fraction of its radius, a sphere may move relative to a mesh before the
/// triangles near it are looked up again: a triangle farther than R + margin when they were
/// found cannot have come within R since.
const NEAR_MARGIN: f64 = 0.02;

/// Smallest accepted ratio of a triangle's doubled area to the square of its longest edge:
/// below it the triangle is a sliver or a segment whose normal is round-off.
const MIN_ASPECT: f64 = 1e-10;

/// One triangle as the contact test needs it, in the mesh's own frame.
#[derive(Debug, Clone, PartialEq)]
struct Facet {
    /// Corners [m].
    corners: [DVec3; 3],
    /// Unit normal by the right-hand rule [-].
    normal: DVec3,
    /// Welded corner ids.
    vertex: [u32; 3],
    /// Edge ids, edge k from corner k to corner k + 1.
    edge: [u32; 3],
    /// Lowest and highest corner of the triangle's bounding box [m].
    bounds: (DVec3, DVec3),
}

impl Facet {
    /// True when `b` [m] is certainly farther than `reach` [m] from the triangle because it is
    /// that far from the triangle's plane, which no point of the triangle is nearer than.
    ///
    /// A cheap test before the closest point: the index offers every triangle whose bounding
    /// box comes within reach, and a long triangle slanting across the axes (a cone's side in
    /// one strip from the orifice to the cylinder, as CAD exports often give) has a box reaching
    /// far from its surface. The margin of 10⁻⁹ of the reach lets rounding in the plane
    /// distance refuse only what the closest point would refuse too, so the triangles found,
    /// and every contact, are the same as without the test.
    #[inline]
    fn plane_beyond(&self, b: DVec3, reach: f64) -> bool {
        (b - self.corners[0]).dot(self.normal).abs() > reach * (1.0 + 1e-9)
    }
}

/// A copy of one triangle's geometry, kept beside a sphere that is near it: the contact test
/// of every step then reads a few hundred bytes in a row instead of triangles scattered
/// through a large mesh, which cost a cache miss each.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NearTriangle {
    /// The triangle's index in the mesh.
    pub triangle: u32,
    /// Corners in the mesh's frame [m].
    corners: [DVec3; 3],
    /// Unit normal [-].
    normal: DVec3,
    /// Bounding box [m].
    bounds: (DVec3, DVec3),
}

/// A contact of a sphere with a mesh: where, along which normal and with which triangle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshContact {
    /// The closest point of the surface, in the world [m].
    pub point: DVec3,
    /// Unit normal from the surface to the sphere's centre, in the world [-].
    pub normal: DVec3,
    /// Distance from the sphere's centre to `point` [m].
    pub distance: f64,
    /// The triangle that holds the point (the lowest-numbered one where several share it),
    /// which its loads are booked to.
    pub triangle: u32,
}

/// A wall of triangles. Stored as [`MeshRecord`]: its triangles and pose; the index is
/// rebuilt on loading.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(into = "MeshRecord", try_from = "MeshRecord")]
pub struct Mesh {
    facets: Vec<Facet>,
    /// Welded corners, in the mesh's frame [m].
    vertices: Vec<DVec3>,
    /// Triangles having each edge.
    edge_faces: Vec<u32>,
    /// Triangles having each corner.
    vertex_faces: Vec<u32>,
    grid: TriangleGrid,
    /// Bounds of the mesh in its own frame [m].
    bounds: (DVec3, DVec3),
    /// Pose: a point b of the mesh's frame is at `rotation * b + translation` in the world.
    rotation: DQuat,
    /// Translation of the pose [m].
    translation: DVec3,
}

/// The stored form of a [`Mesh`]: its triangles in its own frame, as given, and its pose.
#[derive(Serialize, Deserialize)]
pub(super) struct MeshRecord {
    triangles: Vec<[DVec3; 3]>,
    rotation: DQuat,
    translation: DVec3,
}

impl From<Mesh> for MeshRecord {
    fn from(m: Mesh) -> Self {
        let (triangles, rotation, translation) = m.parts();
        Self {
            triangles,
            rotation,
            translation,
        }
    }
}

impl TryFrom<MeshRecord> for Mesh {
    type Error = WallError;

    fn try_from(r: MeshRecord) -> Result<Self, WallError> {
        let mut m = Mesh::new(&r.triangles)?;
        m.set_pose(r.rotation, r.translation);
        Ok(m)
    }
}

/// The triangles of a contact query before the claims, reused between queries.
#[derive(Debug, Default, Clone)]
pub struct MeshScratch {
    found: Vec<(Feature, u32, u32, DVec3, f64)>,
    near: Vec<NearTriangle>,
}

impl Mesh {
    /// A mesh of `triangles` [m], checked: at least one, finite corners, none degenerate.
    /// Corners with identical coordinates are welded, so that triangles sharing them share
    /// edges and corners.
    pub(super) fn new(triangles: &[[DVec3; 3]]) -> Result<Self, WallError> {
        if triangles.is_empty() {
            return Err(WallError::EmptyMesh);
        }
        let mut weld = std::collections::HashMap::new();
        let mut vertices = Vec::new();
        let mut edge_ids = std::collections::HashMap::new();
        let mut edge_faces: Vec<u32> = Vec::new();
        let mut vertex_faces: Vec<u32> = Vec::new();
        let mut facets = Vec::with_capacity(triangles.len());
        for (t, tri) in triangles.iter().enumerate() {
            if let Some(v) = tri.iter().find(|v| !v.is_finite()) {
                return Err(WallError::BadTriangle {
                    triangle: t,
                    reason: format!("corner {v} is not finite"),
                });
            }
            let (area2, normal) = area2_and_normal(*tri);
            let longest = (0..3)
                .map(|k| (tri[(k + 1) % 3] - tri[k]).length_squared())
                .fold(0.0, f64::max);
            if !(area2 > MIN_ASPECT * longest) {
                return Err(WallError::BadTriangle {
                    triangle: t,
                    reason: format!(
                        "degenerate: doubled area {area2:e} m² against longest edge² {longest:e} m² \
                         (at least {MIN_ASPECT:e} of it is needed)"
                    ),
                });
            }
            let vertex = tri.map(|v| {
                let key = v.to_array().map(f64::to_bits);
                let id = *weld.entry(key).or_insert_with(|| {
                    vertices.push(v);
                    vertex_faces.push(0);
                    vertices.len() as u32 - 1
                });
                vertex_faces[id as usize] += 1;
                id
            });
            let edge = [0, 1, 2].map(|k| {
                let (a, b) = (vertex[k], vertex[(k + 1) % 3]);
                let id = *edge_ids.entry((a.min(b), a.max(b))).or_insert_with(|| {
                    edge_faces.push(0);
                    edge_faces.len() as u32 - 1
                });
                edge_faces[id as usize] += 1;
                id
            });
            facets.push(Facet {
                corners: *tri,
                normal,
                vertex,
                edge,
                bounds: (
                    tri[0].min(tri[1]).min(tri[2]),
                    tri[0].max(tri[1]).max(tri[2]),
                ),
            });
        }
        let boxes: Vec<(DVec3, DVec3)> = triangles
            .iter()
            .map(|t| (t[0].min(t[1]).min(t[2]), t[0].max(t[1]).max(t[2])))
            .collect();
        let lo = boxes.iter().fold(DVec3::INFINITY, |a, b| a.min(b.0));
        let hi = boxes.iter().fold(DVec3::NEG_INFINITY, |a, b| a.max(b.1));
        Ok(Self {
            grid: TriangleGrid::new(&boxes, (lo, hi)),
            facets,
            vertices,
            edge_faces,
            vertex_faces,
            bounds: (lo, hi),
            rotation: DQuat::IDENTITY,
            translation: DVec3::ZERO,
        })
    }

    /// Number of triangles.
    pub fn len(&self) -> usize {
        self.facets.len()
    }

    /// True when the mesh has no triangles (never, for a constructed mesh).
    pub fn is_empty(&self) -> bool {
        self.facets.is_empty()
    }

    /// Triangle `t`'s corners in the world [m].
    pub fn triangle(&self, t: usize) -> [DVec3; 3] {
        self.facets[t].corners.map(|c| self.to_world(c))
    }

    /// Triangle `t`'s unit normal in the world (right-hand rule on its corners) [-].
    pub fn triangle_normal(&self, t: usize) -> DVec3 {
        self.rotation * self.facets[t].normal
    }

    /// Area of triangle `t` [m²].
    pub fn triangle_area(&self, t: usize) -> f64 {
        0.5 * area2_and_normal(self.facets[t].corners).0
    }

    /// The pose: rotation and translation [m] from the mesh's frame to the world.
    pub fn pose(&self) -> (DQuat, DVec3) {
        (self.rotation, self.translation)
    }

    /// The mesh's triangles in its own frame, as given, with its pose: what a checkpoint
    /// stores.
    fn parts(&self) -> (Vec<[DVec3; 3]>, DQuat, DVec3) {
        (
            self.facets.iter().map(|f| f.corners).collect(),
            self.rotation,
            self.translation,
        )
    }

    /// Sets the pose (checkpoints).
    fn set_pose(&mut self, rotation: DQuat, translation: DVec3) {
        self.rotation = rotation;
        self.translation = translation;
    }

    /// True while the mesh is where it was built: its frame is the world's, and no point
    /// needs transforming.
    #[inline]
    fn at_home(&self) -> bool {
        self.rotation == DQuat::IDENTITY && self.translation == DVec3::ZERO
    }

    #[inline]
    fn to_world(&self, b: DVec3) -> DVec3 {
        if self.at_home() {
            return b;
        }
        self.rotation * b + self.translation
    }

    #[inline]
    fn to_body(&self, x: DVec3) -> DVec3 {
        if self.at_home() {
            return x;
        }
        self.rotation.inverse() * (x - self.translation)
    }

    /// Distance from `x` to the nearest point of the mesh within `reach` [m], or `reach`
    /// when none is nearer.
    #[cfg(test)]
    pub(super) fn distance_within(&self, x: DVec3, reach: f64) -> f64 {
        let b = self.to_body(x);
        let mut best = reach * reach;
        self.grid.near(b, reach, |t| {
            let (p, _) = closest_point(b, self.facets[t as usize].corners);
            best = best.min((b - p).length_squared());
            false
        });
        best.sqrt()
    }

    /// A point of the world in the mesh's own frame [m].
    #[inline]
    pub fn to_mesh_frame(&self, x: DVec3) -> DVec3 {
        self.to_body(x)
    }

    /// The triangles closer than `reach` [m] to `b`, a point in the mesh's own frame, into
    /// `out` in increasing order.
    pub fn triangles_near(&self, b: DVec3, reach: f64, out: &mut Vec<NearTriangle>) {
        out.clear();
        let reach2 = reach * reach;
        self.grid.near(b, reach, |t| {
            let f = &self.facets[t as usize];
            if f.plane_beyond(b, reach) {
                return false;
            }
            let (p, _) = closest_point(b, f.corners);
            if (b - p).length_squared() < reach2 {
                out.push(NearTriangle {
                    triangle: t,
                    corners: f.corners,
                    normal: f.normal,
                    bounds: f.bounds,
                });
            }
            false
        });
        out.sort_unstable_by_key(|n| n.triangle);
    }

    /// The contacts of a sphere at `x` with radius `r` [m] under the module's rule, into
    /// `out` in a fixed order (faces, then edges, then corners, each by triangle or feature
    /// id): the triangles are looked up in the index.
    pub fn contacts(
        &self,
        x: DVec3,
        r: f64,
        scratch: &mut MeshScratch,
        out: &mut Vec<MeshContact>,
    ) {
        let mut near = std::mem::take(&mut scratch.near);
        self.triangles_near(self.to_body(x), r, &mut near);
        self.contacts_among(x, r, &near, scratch, out);
        scratch.near = near;
    }

    /// [`Mesh::contacts`] among the triangles `near`, which must include every triangle
    /// within `r` of `x` (more do no harm: the result is the same).
    pub fn contacts_among(
        &self,
        x: DVec3,
        r: f64,
        near: &[NearTriangle],
        scratch: &mut MeshScratch,
        out: &mut Vec<MeshContact>,
    ) {
        out.clear();
        let b = self.to_body(x);
        let r2 = r * r;
        let found = &mut scratch.found;
        found.clear();
        for facet in near {
            let t = facet.triangle;
            // The bounding box's distance and the plane's bound the triangle's from below:
            // most triangles beside a sphere are out of reach of its section with their
            // plane, and are left after these few operations.
            let (lo, hi) = facet.bounds;
            let gap = (lo - b).max(b - hi).max(DVec3::ZERO);
            if gap.length_squared() >= r2 {
                continue;
            }
            let h = (b - facet.corners[0]).dot(facet.normal);
            if h * h >= r2 {
                continue;
            }
            let (p, feature) = closest_point(b, facet.corners);
            let d2 = (b - p).length_squared();
            if d2 < r2 {
                // The feature's id on the whole mesh: the triangle, the edge or the corner.
                let id = match feature {
                    Feature::Face => t,
                    Feature::Edge(k) => self.facets[t as usize].edge[k as usize],
                    Feature::Corner(k) => self.facets[t as usize].vertex[k as usize],
                };
                found.push((feature_class(feature), id, t, p, d2));
            }
        }
        match found[..] {
            [] => return,
            // One face: nothing to count or claim (the common case of a sphere on a surface).
            [(Feature::Face, _, t, p, d2)] => {
                out.push(self.contact(b, t, p, d2));
                return;
            }
            _ => {}
        }
        found.sort_unstable_by_key(|f| (f.0, f.1, f.2));
        // Runs of one feature: a face counts; an edge or corner when every triangle having
        // it reported it.
        let mut k = 0;
        while k < found.len() {
            let (class, id, t, p, d2) = found[k];
            let run = found[k..]
                .iter()
                .take_while(|f| (f.0, f.1) == (class, id))
                .count();
            let sharing = match class {
                Feature::Face => 1,
                Feature::Edge(_) => self.edge_faces[id as usize],
                Feature::Corner(_) => self.vertex_faces[id as usize],
            };
            if run as u32 == sharing {
                out.push(self.contact(b, t, p, d2));
            }
            k += run;
        }
        if out.is_empty() {
            let &(_, _, t, p, d2) = found
                .iter()
                .min_by(|a, b| a.4.total_cmp(&b.4))
                .expect("some triangle within reach");
            out.push(self.contact(b, t, p, d2));
        }
    }

    /// The contact of a sphere whose centre is `b` (mesh frame) with closest point `p` of
    /// triangle `t` at squared distance `d2`, in the world.
    #[inline]
    fn contact(&self, b: DVec3, t: u32, p: DVec3, d2: f64) -> MeshContact {
        let distance = d2.sqrt();
        let normal_b = if distance > 0.0 {
            (b - p) / distance
        } else {
            self.facets[t as usize].normal
        };
        MeshContact {
            point: self.to_world(p),
            normal: if self.at_home() {
                normal_b
            } else {
                self.rotation * normal_b
            },
            distance,
            triangle: t,
        }
    }

    /// Welded corners in the mesh's frame [m] (tests).
    #[cfg(test)]
    pub(super) fn vertex_count(&self) -> usize {
        self.vertices.len()
    }
}

impl WallGeometry for Mesh {
    /// The nearest point of all the triangles and the distance to it, found by looking
    /// for triangles within a reach grown fourfold from 1 mm until one is found. Out of
    /// line: the force loops find a mesh's contacts with [`Mesh::contacts_among`].
    #[inline(never)]
    fn closest_point(&self, x: DVec3) -> (DVec3, f64) {
        let mut scratch = MeshScratch::default();
        let mut out = Vec::new();
        let mut reach = 1e-3;
        loop {
            self.contacts(x, reach, &mut scratch, &mut out);
            if let Some(c) = out.iter().min_by(|a, b| a.distance.total_cmp(&b.distance)) {
                return (c.point, c.distance);
            }
            if !reach.is_finite() {
                return (x, f64::INFINITY);
            }
            reach *= 4.0;
        }
    }

    /// Along x − p, or +z where x lies on the surface (the surface pass takes a contact's
    /// normal from its triangle instead, [`MeshContact::normal`]).
    #[inline]
    fn contact_normal(&self, x: DVec3, p: DVec3, dist: f64) -> DVec3 {
        if dist > 0.0 {
            (x - p) / dist
        } else {
            DVec3::Z
        }
    }

    /// Moves the mesh by `offset` [m].
    fn translate(&mut self, offset: DVec3) {
        self.translation += offset;
    }

    /// Turns the mesh by `rotation` about the world point `centre` [m].
    fn rotate_about(&mut self, centre: DVec3, rotation: DQuat) {
        self.translation = centre + rotation * (self.translation - centre);
        self.rotation = (rotation * self.rotation).normalize();
    }

    /// True when `x` is certainly farther than `reach` [m] from the mesh: outside its
    /// bounding box grown by `reach`.
    #[inline]
    fn certainly_beyond(&self, x: DVec3, reach: f64) -> bool {
        let b = self.to_body(x);
        let gap = (self.bounds.0 - b).max(b - self.bounds.1).max(DVec3::ZERO);
        !(gap.length_squared() < reach * reach)
    }

    /// True when some triangle is closer than `reach` [m] to `x`: the neighbour search's
    /// test, which stops at the first.
    fn comes_within(&self, x: DVec3, reach: f64) -> bool {
        let b = self.to_body(x);
        let reach2 = reach * reach;
        let mut found = false;
        self.grid.near(b, reach, |t| {
            let f = &self.facets[t as usize];
            if f.plane_beyond(b, reach) {
                return false;
            }
            let (p, _) = closest_point(b, f.corners);
            found = (b - p).length_squared() < reach2;
            found
        });
        found
    }

    #[inline]
    fn is_unbounded(&self) -> bool {
        false
    }

    #[inline]
    fn needs_surface_pass(&self) -> bool {
        true
    }

    fn elements(&self) -> SurfaceElements {
        SurfaceElements::Triangles(self.len())
    }

    /// [`Mesh::contacts_among`] the triangles of `near`, which are looked up in the mesh's
    /// index again only when the sphere has left the margin about where they were found.
    #[inline]
    fn surface_contacts(
        &self,
        (x, r): (DVec3, f64),
        _bands: usize,
        near: &mut NearCache,
        scratch: &mut MeshScratch,
        out: &mut Vec<MeshContact>,
    ) {
        let margin = NEAR_MARGIN * r;
        let here = self.to_mesh_frame(x);
        if near
            .anchor
            .is_none_or(|a| a.distance_squared(here) >= margin * margin)
        {
            self.triangles_near(here, r + margin, &mut near.near);
            near.anchor = Some(here);
        }
        self.contacts_among(x, r, &near.near, scratch, out);
    }
}

/// The feature's class alone, which orders faces before edges before corners.
#[inline]
fn feature_class(f: Feature) -> Feature {
    match f {
        Feature::Face => Feature::Face,
        Feature::Edge(_) => Feature::Edge(0),
        Feature::Corner(_) => Feature::Corner(0),
    }
}
