//! A rectangular silo (`geometry.kind = "box"`, docs/physics.md §5.7): a box W wide (x) and
//! B deep (y) above a wedge of two plates meeting a slot, a pyramid of four plates narrowing to
//! a square orifice, or a flat bottom with a slot or a square orifice.
//!
//! The box is centred on the z axis: x ∈ [−W/2, W/2], y ∈ [−B/2, B/2], z up from the orifice
//! plane z = 0 to the top of the walls at H. The container is a convex polyhedron, the
//! intersection of half-spaces n·p ≤ d (unit outward normals), so its walls are the faces of
//! that polyhedron, exact planar polygons found by clipping each plane by all the others, and its
//! volume below a height is the divergence theorem's V = ⅓ Σ d_f A_f over those faces.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::wall_surface::WallSurface;

/// The orifice of a rectangular silo.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CuboidOutlet {
    /// A slot D wide in x spanning the whole depth B; under a wedge of two plates when the
    /// hopper angle is below 90°.
    Slot,
    /// A square of side D; under a pyramid of four plates when the hopper angle is below 90°.
    Square,
}

impl CuboidOutlet {
    /// The word of the case file's `geometry.outlet`.
    pub fn word(self) -> &'static str {
        match self {
            Self::Slot => "slot",
            Self::Square => "square",
        }
    }
}

/// One bounding plane of a rectangular silo: which wall it carries.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CuboidFace {
    /// The side wall x = −W/2.
    Left,
    /// The side wall x = +W/2.
    Right,
    /// The wall y = −B/2.
    Front,
    /// The wall y = +B/2.
    Back,
    /// The plate rising from the orifice's edge x = x_c − D/2 toward x = −W/2.
    PlateLeft,
    /// The plate rising from x = x_c + D/2 toward x = +W/2.
    PlateRight,
    /// The pyramid's plate rising from y = −D/2 toward y = −B/2.
    PlateFront,
    /// The pyramid's plate rising from y = +D/2 toward y = +B/2.
    PlateBack,
    /// The orifice plane z = 0: the gate under a hopper, the flat bottom otherwise.
    Bottom,
    /// The open top z = H (no wall).
    Top,
}

/// A half-space n·p ≤ d of the container, with n a unit outward normal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HalfSpace {
    /// The wall it carries.
    pub face: CuboidFace,
    /// Unit outward normal [-].
    pub normal: DVec3,
    /// Offset d [m]: the plane is n·p = d.
    pub offset: f64,
}

impl HalfSpace {
    fn new(face: CuboidFace, normal: DVec3, offset: f64) -> Self {
        Self {
            face,
            normal,
            offset,
        }
    }

    /// Signed distance of `p` outside the half-space's plane [m] (negative inside).
    pub fn outside(&self, p: DVec3) -> f64 {
        self.normal.dot(p) - self.offset
    }
}

/// A rectangular silo; see the module documentation for its conventions.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CuboidGeometry {
    /// Inner width W along x [m].
    pub width: f64,
    /// Inner depth B along y [m].
    pub depth: f64,
    /// Height H of the top of the walls above the orifice plane [m].
    pub height: f64,
    /// A slot across the depth or a square orifice.
    pub outlet: CuboidOutlet,
    /// D [m]: the slot's width or the square's side.
    pub outlet_width: f64,
    /// Angle α of the plates from the vertical [°], in (0, 90]; 90 is a flat bottom. Kept in
    /// degrees so that a resolved case writes back exactly what was read.
    pub hopper_angle_deg: f64,
    /// x of the orifice centre [m]; non-zero only with a flat bottom.
    pub outlet_offset: f64,
    /// Exact polygons (`smooth`) or one triangle mesh per wall (`meshed`).
    pub walls: WallSurface,
}

impl CuboidGeometry {
    /// A box 100 mm × 50 mm × 200 mm with a 60° wedge over a 20 mm slot.
    pub fn example() -> Self {
        Self {
            width: 0.1,
            depth: 0.05,
            height: 0.2,
            outlet: CuboidOutlet::Slot,
            outlet_width: 0.02,
            hopper_angle_deg: 60.0,
            outlet_offset: 0.0,
            walls: WallSurface::Smooth,
        }
    }

    /// Whether the bottom is flat (α = 90°).
    pub fn is_flat(&self) -> bool {
        self.hopper_angle_deg >= 90.0
    }

    /// Plate angle α from the vertical [rad].
    pub fn hopper_angle(&self) -> f64 {
        self.hopper_angle_deg.to_radians()
    }

    /// Half the orifice's width, D/2 [m].
    pub fn outlet_radius(&self) -> f64 {
        0.5 * self.outlet_width
    }

    /// Extent of the orifice in y [m]: the whole depth for a slot, D for a square.
    pub fn outlet_depth(&self) -> f64 {
        match self.outlet {
            CuboidOutlet::Slot => self.depth,
            CuboidOutlet::Square => self.outlet_width,
        }
    }

    /// Heights where the plates meet the walls [m]: (W − D)/2 · cot α for the x-plates, and
    /// (B − D)/2 · cot α for a pyramid's y-plates (0 where there are no such plates).
    pub fn plate_heights(&self) -> (f64, f64) {
        if self.is_flat() {
            return (0.0, 0.0);
        }
        let cot = 1.0 / self.hopper_angle().tan();
        let zx = 0.5 * (self.width - self.outlet_width) * cot;
        let zy = match self.outlet {
            CuboidOutlet::Slot => 0.0,
            CuboidOutlet::Square => 0.5 * (self.depth - self.outlet_width) * cot,
        };
        (zx, zy)
    }

    /// Height of the hopper's highest plate edge [m]; 0 for a flat bottom.
    pub fn hopper_height(&self) -> f64 {
        let (zx, zy) = self.plate_heights();
        zx.max(zy)
    }

    /// The half-spaces whose intersection is the container below `top` [m].
    pub fn half_spaces(&self, top: f64) -> Vec<HalfSpace> {
        let (hw, hb) = (0.5 * self.width, 0.5 * self.depth);
        let mut spaces = vec![
            HalfSpace::new(CuboidFace::Left, DVec3::NEG_X, hw),
            HalfSpace::new(CuboidFace::Right, DVec3::X, hw),
            HalfSpace::new(CuboidFace::Front, DVec3::NEG_Y, hb),
            HalfSpace::new(CuboidFace::Back, DVec3::Y, hb),
            HalfSpace::new(CuboidFace::Bottom, DVec3::NEG_Z, 0.0),
            HalfSpace::new(CuboidFace::Top, DVec3::Z, top),
        ];
        if !self.is_flat() {
            // A plate through the orifice edge x_c ± D/2 at z = 0, rising outward at α from
            // the vertical: its outward normal is (±cos α, 0, −sin α).
            let (sin, cos) = self.hopper_angle().sin_cos();
            let (c, r) = (self.outlet_offset, self.outlet_radius());
            spaces.push(HalfSpace::new(
                CuboidFace::PlateLeft,
                DVec3::new(-cos, 0.0, -sin),
                (r - c) * cos,
            ));
            spaces.push(HalfSpace::new(
                CuboidFace::PlateRight,
                DVec3::new(cos, 0.0, -sin),
                (r + c) * cos,
            ));
            if self.outlet == CuboidOutlet::Square {
                spaces.push(HalfSpace::new(
                    CuboidFace::PlateFront,
                    DVec3::new(0.0, -cos, -sin),
                    r * cos,
                ));
                spaces.push(HalfSpace::new(
                    CuboidFace::PlateBack,
                    DVec3::new(0.0, cos, -sin),
                    r * cos,
                ));
            }
        }
        spaces
    }

    /// The faces of the container below `top` [m]: each bounding plane's polygon, vertices
    /// counter-clockwise seen from outside; planes that touch the container in less than an
    /// area (a plate's plane beyond the other walls) are left out.
    pub fn faces(&self, top: f64) -> Vec<(CuboidFace, Vec<DVec3>)> {
        let spaces = self.half_spaces(top);
        let size = 4.0 * (self.width + self.depth + top.max(self.height));
        spaces
            .iter()
            .filter_map(|s| {
                let polygon = face_polygon(s, &spaces, size);
                (polygon.len() >= 3 && polygon_area(&polygon) > 1e-14 * size * size)
                    .then_some((s.face, polygon))
            })
            .collect()
    }

    /// The orifice in the plane z = 0 as a rectangle [m], counter-clockwise seen from above:
    /// x ∈ x_c ± D/2, y across the depth (slot) or ±D/2 (square).
    pub fn orifice(&self) -> Vec<DVec3> {
        let (c, r, hy) = (
            self.outlet_offset,
            self.outlet_radius(),
            0.5 * self.outlet_depth(),
        );
        vec![
            DVec3::new(c - r, -hy, 0.0),
            DVec3::new(c + r, -hy, 0.0),
            DVec3::new(c + r, hy, 0.0),
            DVec3::new(c - r, hy, 0.0),
        ]
    }

    /// Volume of the container below height `h` above the orifice plane [m³]:
    /// ⅓ Σ d_f A_f over the faces of the container cut at h (divergence theorem).
    pub fn volume_below(&self, h: f64) -> f64 {
        let h = h.clamp(0.0, self.height);
        if h <= 0.0 {
            return 0.0;
        }
        let spaces = self.half_spaces(h);
        let size = 4.0 * (self.width + self.depth + self.height);
        spaces
            .iter()
            .map(|s| s.offset * polygon_area(&face_polygon(s, &spaces, size)))
            .sum::<f64>()
            / 3.0
    }

    /// Volume of the whole container below H [m³].
    pub fn volume(&self) -> f64 {
        self.volume_below(self.height)
    }

    /// Height [m] below which the container holds `volume` [m³], or `None` if it cannot.
    pub fn height_holding(&self, volume: f64) -> Option<f64> {
        super::fill_height::height_holding(self.height, volume, |z| self.volume_below(z))
    }

    /// Whether a sphere of radius `r` [m] centred at (x, y, z) lies inside the container with
    /// clearance `gap` [m]: at least r + gap inside every bounding plane, the orifice plane and
    /// the top included.
    pub fn holds(&self, x: f64, y: f64, z: f64, r: f64, gap: f64) -> bool {
        let p = DVec3::new(x, y, z);
        let c = r + gap;
        self.half_spaces(self.height)
            .iter()
            .all(|s| s.outside(p) <= -c)
    }
}

/// The polygon of `space`'s plane inside all of `spaces`: a square of side `size` in the plane,
/// about its point nearest the origin, clipped by every other half-space (Sutherland–Hodgman),
/// with vertices closer than 1e-12 · size merged.
fn face_polygon(space: &HalfSpace, spaces: &[HalfSpace], size: f64) -> Vec<DVec3> {
    let n = space.normal;
    let u = n.any_orthonormal_vector();
    let v = n.cross(u);
    let centre = n * space.offset;
    let h = 0.5 * size;
    // Counter-clockwise seen from outside (from +n): u, v, n right-handed.
    let mut polygon = vec![
        centre - h * u - h * v,
        centre + h * u - h * v,
        centre + h * u + h * v,
        centre - h * u + h * v,
    ];
    for other in spaces {
        if other.face == space.face {
            continue;
        }
        polygon = clip(&polygon, other);
        if polygon.is_empty() {
            break;
        }
    }
    let tolerance = 1e-12 * size;
    let mut merged: Vec<DVec3> = Vec::with_capacity(polygon.len());
    for p in polygon {
        if merged.last().is_none_or(|q| q.distance(p) > tolerance) {
            merged.push(p);
        }
    }
    while merged.len() > 1 && merged[0].distance(merged[merged.len() - 1]) <= tolerance {
        merged.pop();
    }
    merged
}

/// The part of a convex polygon inside a half-space.
fn clip(polygon: &[DVec3], space: &HalfSpace) -> Vec<DVec3> {
    let mut out = Vec::with_capacity(polygon.len() + 1);
    for (k, &a) in polygon.iter().enumerate() {
        let b = polygon[(k + 1) % polygon.len()];
        let (da, db) = (space.outside(a), space.outside(b));
        if da <= 0.0 {
            out.push(a);
        }
        if (da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0) {
            out.push(a + (b - a) * (da / (da - db)));
        }
    }
    out
}

/// Area of a planar polygon [m²] (Newell's method).
pub(crate) fn polygon_area(polygon: &[DVec3]) -> f64 {
    let mut sum = DVec3::ZERO;
    for (k, &a) in polygon.iter().enumerate() {
        sum += a.cross(polygon[(k + 1) % polygon.len()]);
    }
    0.5 * sum.length()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn silo(outlet: CuboidOutlet, angle: f64) -> CuboidGeometry {
        CuboidGeometry {
            outlet,
            hopper_angle_deg: angle,
            ..CuboidGeometry::example()
        }
    }

    /// A flat box holds W·B·h; a wedge holds B(D h + h² tan α) up to its plates' top, then the
    /// full cross-section; height_holding inverts the volume.
    #[test]
    fn volumes_match_closed_forms() {
        let flat = silo(CuboidOutlet::Slot, 90.0);
        assert!((flat.volume_below(0.07) - 0.1 * 0.05 * 0.07).abs() < 1e-17);
        let wedge = silo(CuboidOutlet::Slot, 60.0);
        let t = wedge.hopper_angle().tan();
        let (zx, _) = wedge.plate_heights();
        // (W − D)/2 cot 60° = 0.04/√3.
        assert!((zx - 0.04 / 3f64.sqrt()).abs() < 1e-15);
        for h in [0.005, 0.02] {
            let exact = 0.05 * (0.02 * h + h * h * t);
            assert!((wedge.volume_below(h) - exact).abs() < 1e-17, "{h}");
        }
        let above = wedge.volume_below(zx + 0.05) - wedge.volume_below(zx);
        assert!((above - 0.1 * 0.05 * 0.05).abs() < 1e-16);
        for h in [0.01, 0.05, 0.15] {
            let back = wedge.height_holding(wedge.volume_below(h)).unwrap();
            assert!((back - h).abs() < 1e-12);
        }
        assert!(wedge.height_holding(wedge.volume() * 1.01).is_none());
    }

    /// A square pyramid in a square box is a frustum of a square pyramid below its plates:
    /// h (a² + a b + b²)/3 with a = D and b = D + 2 h tan α.
    #[test]
    fn pyramid_volume_is_a_frustum() {
        let s = CuboidGeometry {
            depth: 0.1,
            ..silo(CuboidOutlet::Square, 45.0)
        };
        let h = 0.03;
        let (a, b) = (0.02, 0.02 + 2.0 * h * s.hopper_angle().tan());
        let exact = h * (a * a + a * b + b * b) / 3.0;
        assert!((s.volume_below(h) - exact).abs() < 1e-17);
        // Four plates, four side walls above them, and the square gate at z = 0.
        let faces: Vec<CuboidFace> = s.faces(s.height).iter().map(|f| f.0).collect();
        for face in [
            CuboidFace::PlateLeft,
            CuboidFace::PlateRight,
            CuboidFace::PlateFront,
            CuboidFace::PlateBack,
            CuboidFace::Left,
            CuboidFace::Bottom,
        ] {
            assert!(faces.contains(&face), "{face:?} missing from {faces:?}");
        }
    }

    /// In a rectangular box a pyramid's long plates are hexagons: a trapezoid up to where the
    /// short plates end, then the full depth up to the walls.
    #[test]
    fn long_pyramid_plates_reach_past_the_short_ones() {
        let s = silo(CuboidOutlet::Square, 45.0);
        let faces = s.faces(s.height);
        let plate = &faces
            .iter()
            .find(|f| f.0 == CuboidFace::PlateRight)
            .unwrap()
            .1;
        assert_eq!(plate.len(), 6, "{plate:?}");
        let (zx, zy) = s.plate_heights();
        assert!((zx - 0.04).abs() < 1e-15 && (zy - 0.015).abs() < 1e-15);
        let top = plate.iter().map(|p| p.z).fold(f64::MIN, f64::max);
        assert!((top - zx).abs() < 1e-15);
    }

    /// A sphere touching a wedge's plate is held with zero clearance and refused with more.
    #[test]
    fn holds_respects_the_plates() {
        let s = silo(CuboidOutlet::Slot, 60.0);
        let (r, z) = (0.002, 0.01);
        let a = s.hopper_angle();
        let x = 0.01 + z * a.tan() - r / a.cos();
        assert!(s.holds(x - 1e-9, 0.0, z, r, 0.0));
        assert!(!s.holds(x + 1e-9, 0.0, z, r, 0.0));
        assert!(!s.holds(0.0, 0.0245, 0.1, r, 0.0));
        assert!(s.holds(0.0, 0.0225, 0.1, r, 0.0));
    }
}
