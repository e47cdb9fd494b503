//! The container of a case: the paper's slab hopper, a cylindrical silo with a flat or
//! conical bottom and a circular orifice (docs/physics.md §5.6), a rectangular silo
//! ([`CuboidGeometry`], §5.7), the user's own STL walls ([`MeshGeometry`], §5.8), or one of
//! the two calibration tests: the heap of a lifted cylinder ([`HeapGeometry`], §5.9) and the
//! draw-down box ([`DrawDownGeometry`], §5.10).
//!
//! Conventions shared by every kind: z is vertical, measured up from the orifice plane
//! z = 0 (the heap's plate); the silo's axis is the z axis (x = y = 0) for the cylinder, the
//! box, the heap and the draw-down box; the slab keeps its own x–z conventions (see
//! [`SlabGeometry`]).

use serde::{Deserialize, Serialize};

use super::cuboid::CuboidGeometry;
use super::cylinder::CylinderGeometry;
use super::draw_down::DrawDownGeometry;
use super::heap::HeapGeometry;
use super::mesh::MeshGeometry;
use super::slab::SlabGeometry;

/// The container of a case.
///
/// Serialised without a tag, so that the slab writes exactly the fields it always wrote.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Geometry {
    /// The paper's rectangular slab hopper (quasi-2D or thick).
    Slab(SlabGeometry),
    /// A cylindrical silo with a flat or conical bottom and a circular orifice.
    Cylinder(CylinderGeometry),
    /// A rectangular silo with a wedge, a pyramid or a flat bottom.
    Cuboid(CuboidGeometry),
    /// The user's STL walls, an orifice at z = 0 and a fill box.
    Mesh(MeshGeometry),
    /// The angle-of-repose test: a cylinder lifted off a plate, leaving a heap.
    Heap(HeapGeometry),
    /// The draw-down test: a flat-floored box discharging through a centred slot.
    DrawDown(DrawDownGeometry),
}

impl Geometry {
    /// The slab hopper, when this is one.
    pub fn slab(&self) -> Option<&SlabGeometry> {
        match self {
            Self::Slab(g) => Some(g),
            _ => None,
        }
    }

    /// The cylindrical silo, when this is one.
    pub fn cylinder(&self) -> Option<&CylinderGeometry> {
        match self {
            Self::Cylinder(g) => Some(g),
            _ => None,
        }
    }

    /// The rectangular silo, when this is one.
    pub fn cuboid(&self) -> Option<&CuboidGeometry> {
        match self {
            Self::Cuboid(g) => Some(g),
            _ => None,
        }
    }

    /// The container of STL walls, when this is one.
    pub fn mesh(&self) -> Option<&MeshGeometry> {
        match self {
            Self::Mesh(g) => Some(g),
            _ => None,
        }
    }

    /// The lifted-cylinder test, when this is one.
    pub fn heap(&self) -> Option<&HeapGeometry> {
        match self {
            Self::Heap(g) => Some(g),
            _ => None,
        }
    }

    /// The draw-down box, when this is one.
    pub fn draw_down(&self) -> Option<&DrawDownGeometry> {
        match self {
            Self::DrawDown(g) => Some(g),
            _ => None,
        }
    }

    /// The rectangular box of a `box` or a `draw_down` case, which are built, filled and
    /// discharged alike.
    pub fn rectangular(&self) -> Option<&CuboidGeometry> {
        match self {
            Self::Cuboid(g) | Self::DrawDown(DrawDownGeometry { container: g }) => Some(g),
            _ => None,
        }
    }

    /// The kind's name in the case file's `geometry.kind`.
    pub fn kind(&self) -> &'static str {
        match self {
            Self::Slab(_) => "slab",
            Self::Cylinder(_) => "cylinder",
            Self::Cuboid(_) => "box",
            Self::Mesh(_) => "mesh",
            Self::Heap(_) => "heap",
            Self::DrawDown(_) => "draw_down",
        }
    }

    /// Height H of the container's walls above the orifice plane [m]; for STL walls, the top
    /// of the fill box (the highest place a particle starts from).
    pub fn height(&self) -> f64 {
        match self {
            Self::Slab(g) => g.height,
            Self::Cylinder(g) => g.height,
            Self::Cuboid(g) => g.height,
            Self::Mesh(g) => g.fill_max[2],
            Self::Heap(g) => g.height,
            Self::DrawDown(g) => g.height(),
        }
    }

    /// Outlet size D [m]: the slot's width, the orifice's diameter, the square's side; for
    /// STL walls the disc's diameter or the rectangle's side along x; NaN for the heap, which
    /// has no outlet.
    pub fn outlet_size(&self) -> f64 {
        match self {
            Self::Slab(g) => g.outlet_width,
            Self::Cylinder(g) => g.outlet_diameter,
            Self::Cuboid(g) => g.outlet_width,
            Self::Mesh(g) => g.outlet.size(),
            Self::Heap(_) => f64::NAN,
            Self::DrawDown(g) => g.slot_width(),
        }
    }

    /// Hopper angle from the vertical [°] (90 is a flat bottom); NaN for STL walls and the
    /// heap, which have none.
    pub fn hopper_angle_deg(&self) -> f64 {
        match self {
            Self::Slab(g) => g.hopper_angle_deg,
            Self::Cylinder(g) => g.hopper_angle_deg,
            Self::Cuboid(g) => g.hopper_angle_deg,
            Self::Mesh(_) | Self::Heap(_) => f64::NAN,
            Self::DrawDown(_) => 90.0,
        }
    }
}
