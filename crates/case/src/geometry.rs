//! The container of a case: the paper's slab hopper, a cylindrical silo with a flat or
//! conical bottom and a circular orifice (docs/physics.md §5.6), a rectangular silo
//! ([`CuboidGeometry`], §5.7) or the user's own STL walls ([`MeshGeometry`], §5.8).
//!
//! Conventions shared by every kind: z is vertical, measured up from the orifice plane
//! z = 0; the silo's axis is the z axis (x = y = 0) for the cylinder and the box; the slab
//! keeps its own x–z conventions (see [`SlabGeometry`]).

use serde::{Deserialize, Serialize};

use super::cuboid::CuboidGeometry;
use super::cylinder::CylinderGeometry;
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

    /// The kind's name in the case file's `geometry.kind`.
    pub fn kind(&self) -> &'static str {
        match self {
            Self::Slab(_) => "slab",
            Self::Cylinder(_) => "cylinder",
            Self::Cuboid(_) => "box",
            Self::Mesh(_) => "mesh",
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
        }
    }

    /// Outlet size D [m]: the slot's width, the orifice's diameter, the square's side; for
    /// STL walls the disc's diameter or the rectangle's side along x.
    pub fn outlet_size(&self) -> f64 {
        match self {
            Self::Slab(g) => g.outlet_width,
            Self::Cylinder(g) => g.outlet_diameter,
            Self::Cuboid(g) => g.outlet_width,
            Self::Mesh(g) => g.outlet.size(),
        }
    }

    /// Hopper angle from the vertical [°] (90 is a flat bottom); NaN for STL walls, which
    /// have none.
    pub fn hopper_angle_deg(&self) -> f64 {
        match self {
            Self::Slab(g) => g.hopper_angle_deg,
            Self::Cylinder(g) => g.hopper_angle_deg,
            Self::Cuboid(g) => g.hopper_angle_deg,
            Self::Mesh(_) => f64::NAN,
        }
    }
}
