//! Hopper geometry of a case and the lengths and areas derived from it.
//!
//! Conventions (physics spec §5 and §7): x is horizontal, measured from the hopper axis;
//! z is vertical, measured up from the outlet plane z_o = 0; y runs across the slab,
//! from the front wall at y = 0 to the back wall at y = Z. The side walls stand at
//! x = ±L/2 and reach up to z = H, so H is the height of the container above the outlet
//! plane. The two bottom plates make the angle α with the vertical and run from the
//! outlet edges up to the side walls; α = 90° is a flat bottom.

use serde::{Deserialize, Serialize};

/// Validated hopper geometry. Lengths in metres.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SlabGeometry {
    /// Hopper width L between the side walls [m] (paper: 100 mm).
    pub width: f64,
    /// Height H of the side walls above the outlet plane [m] (paper: 400 mm).
    pub height: f64,
    /// Slab thickness Z between front and back walls [m] (paper: 1.01 d = 3.03 mm).
    /// A slab several diameters thick makes a 3D rectangular hopper.
    pub thickness: f64,
    /// Outlet width D [m] (paper: 18, 30, 45, 60 mm).
    pub outlet_width: f64,
    /// Hopper angle α from the vertical [°] (paper: 15–90°, 90° = flat bottom).
    /// Kept in degrees so that a resolved case writes back exactly what was read.
    pub hopper_angle_deg: f64,
    /// Gap s between the left wall and the outlet's left edge [m];
    /// s = (L − D)/2 for a centred outlet (paper Fig. 1b).
    pub outlet_gap: f64,
}

impl SlabGeometry {
    /// The paper's base case: L = 100 mm, H = 400 mm, Z = 3.03 mm, D = 30 mm, flat
    /// bottom, centred outlet.
    pub fn paper() -> Self {
        Self::centred(0.100, 0.400, 3.03e-3, 0.030, 90.0)
    }

    /// A hopper whose outlet is centred on the axis (e = 0).
    pub fn centred(
        width: f64,
        height: f64,
        thickness: f64,
        outlet_width: f64,
        hopper_angle_deg: f64,
    ) -> Self {
        Self {
            width,
            height,
            thickness,
            outlet_width,
            hopper_angle_deg,
            outlet_gap: 0.5 * (width - outlet_width),
        }
    }

    /// Hopper angle α from the vertical [rad].
    pub fn hopper_angle(&self) -> f64 {
        self.hopper_angle_deg.to_radians()
    }

    /// Outlet radius R = D/2 [m].
    pub fn outlet_radius(&self) -> f64 {
        0.5 * self.outlet_width
    }

    /// Offset e of the outlet centre from the axis [m], from e + s = (L − D)/2.
    /// Positive e means the outlet is shifted toward the left wall.
    pub fn outlet_offset(&self) -> f64 {
        0.5 * (self.width - self.outlet_width) - self.outlet_gap
    }

    /// Horizontal position x_c of the outlet centre [m]: x_c = −e (physics spec §7).
    pub fn outlet_centre(&self) -> f64 {
        -self.outlet_offset()
    }

    /// Left and right outlet edges x_c ∓ R [m].
    pub fn outlet_edges(&self) -> (f64, f64) {
        let left = -0.5 * self.width + self.outlet_gap;
        (left, left + self.outlet_width)
    }

    /// Dimensionless eccentricity s* = 2s/(L − D): 0 at the wall, 1 when centred.
    pub fn dimensionless_gap(&self) -> f64 {
        2.0 * self.outlet_gap / (self.width - self.outlet_width)
    }

    /// Horizontal runs of the left and right bottom plates [m]: s and L − s − D.
    pub fn plate_runs(&self) -> (f64, f64) {
        (
            self.outlet_gap,
            self.width - self.outlet_gap - self.outlet_width,
        )
    }

    /// Height a plate of horizontal run `run` [m] climbs at the hopper angle [m].
    fn rise(&self, run: f64) -> f64 {
        if self.hopper_angle_deg >= 90.0 {
            0.0
        } else {
            run / self.hopper_angle().tan()
        }
    }

    /// Height of the funnel: where the higher bottom plate meets its side wall [m].
    pub fn funnel_height(&self) -> f64 {
        let (left, right) = self.plate_runs();
        self.rise(left).max(self.rise(right))
    }

    /// In-plane (x–z) area of the container below height `h` above the outlet [m²].
    ///
    /// The rectangle L·h minus the two triangles under the bottom plates; a plate of
    /// run r leaves a dead width r − z tan α at height z below its top.
    pub fn area_below(&self, h: f64) -> f64 {
        let h = h.clamp(0.0, self.height);
        let dead = |run: f64| {
            if self.hopper_angle_deg >= 90.0 || run <= 0.0 {
                return 0.0;
            }
            let top = self.rise(run).min(h);
            run * top - 0.5 * self.hopper_angle().tan() * top * top
        };
        let (left, right) = self.plate_runs();
        self.width * h - dead(left) - dead(right)
    }

    /// In-plane area of the whole container [m²].
    pub fn cross_section_area(&self) -> f64 {
        self.area_below(self.height)
    }

    /// Height [m] below which the container holds `area` [m²], or `None` if it cannot.
    pub fn height_holding(&self, area: f64) -> Option<f64> {
        if area > self.cross_section_area() {
            return None;
        }
        // area_below is continuous and increasing in h: bisection to 1e-9 of H.
        let (mut low, mut high) = (0.0, self.height);
        for _ in 0..60 {
            let mid = 0.5 * (low + high);
            if self.area_below(mid) < area {
                low = mid;
            } else {
                high = mid;
            }
        }
        Some(high)
    }
}
