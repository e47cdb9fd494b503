//! The draw-down test (`geometry.kind = "draw_down"`, docs/physics.md §5.10): a rectangular box
//! with a flat floor and a slot across its whole depth in the middle of the floor. The fill
//! settles and discharges through the slot until the flow stops; the material left on the two
//! shelves beside the slot slopes at the drained angle of repose (Grima & Wypych 2011;
//! Coetzee 2017, §4).
//!
//! It is the rectangular silo of `geometry.kind = "box"` with the floor held flat and the slot
//! centred, so it is built, filled and discharged as that box is ([`DrawDownGeometry::container`]).

use serde::{Deserialize, Serialize};

use super::cuboid::{CuboidGeometry, CuboidOutlet};
use super::wall_surface::WallSurface;

/// The draw-down box: W wide (x), B deep (y), H high, with a slot D wide centred in x.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DrawDownGeometry {
    /// The box it is: flat bottom (α = 90°), a slot centred at x = 0 across the whole depth.
    /// Built only by [`DrawDownGeometry::new`], which holds these fixed.
    pub container: CuboidGeometry,
}

impl DrawDownGeometry {
    /// A draw-down box W × B × H [m] with a centred slot D wide [m].
    pub fn new(width: f64, depth: f64, height: f64, slot_width: f64, walls: WallSurface) -> Self {
        Self {
            container: CuboidGeometry {
                width,
                depth,
                height,
                outlet: CuboidOutlet::Slot,
                outlet_width: slot_width,
                hopper_angle_deg: 90.0,
                outlet_offset: 0.0,
                walls,
            },
        }
    }

    /// The default test: a box 100 mm wide, 30 mm deep and 100 mm high over a 20 mm slot.
    ///
    /// With the paper's 3 mm spheres each shelf is (W − D)/2 = 40 mm, 13 diameters, long
    /// enough for a slope to form between the slot's edge and the wall and be fitted over
    /// several bins; the depth of 10 diameters keeps the front and back walls from holding the
    /// whole slope up; the slot, nearly 7 diameters wide, is wide enough that arches over it
    /// are rare. The default 3000 spheres stand about 30 mm high, above the slope that a
    /// 40 mm shelf holds below 35°.
    pub fn example() -> Self {
        Self::new(0.1, 0.03, 0.1, 0.02, WallSurface::Smooth)
    }

    /// Inner width W along x [m].
    pub fn width(&self) -> f64 {
        self.container.width
    }

    /// Inner depth B along y [m].
    pub fn depth(&self) -> f64 {
        self.container.depth
    }

    /// Height H of the walls' top above the floor [m].
    pub fn height(&self) -> f64 {
        self.container.height
    }

    /// Width D of the slot [m].
    pub fn slot_width(&self) -> f64 {
        self.container.outlet_width
    }

    /// Length of each shelf between the slot's edge and the wall, (W − D)/2 [m].
    pub fn shelf_length(&self) -> f64 {
        0.5 * (self.width() - self.slot_width())
    }
}
