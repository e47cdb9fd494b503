//! The angle-of-repose test by a lifted cylinder (`geometry.kind = "heap"`, docs/physics.md
//! §5.9): a vertical cylinder open at both ends stands on a flat circular plate, is filled and
//! settled, then lifted at a constant speed so that the material flows out under its lower edge
//! and forms a heap on the plate (Roessler & Katterfeld 2018, 2019).
//!
//! Coordinates: z up from the plate's top face z = 0, the cylinder and the plate centred on
//! the z axis.

use std::f64::consts::PI;

use serde::{Deserialize, Serialize};

use super::fill_height::height_holding;

/// The lifted-cylinder test: a cylinder of inner radius R_c and height H on a plate of radius
/// R_p, lifted at a speed v.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HeapGeometry {
    /// Inner radius R_c of the cylinder [m].
    pub cylinder_radius: f64,
    /// Height H of the cylinder's top above the plate [m]; the fill is poured below it.
    pub height: f64,
    /// Radius R_p of the base plate [m]; grains rolling past its edge fall and are removed.
    pub plate_radius: f64,
    /// Speed at which the cylinder is lifted once the fill has settled [m/s].
    pub lift_speed: f64,
}

impl HeapGeometry {
    /// The default test: a cylinder of 40 mm inner diameter and 80 mm height on a plate of
    /// 120 mm diameter, lifted at 50 mm/s.
    ///
    /// The cylinder is 13 diameters of the paper's 3 mm spheres across, wider than the 8–10
    /// particle diameters below which the wall visibly steepens a heap, and the default 3000
    /// spheres fill it to about 55 mm at a volume fraction of 0.64. Their heap (about 7·10⁻⁵
    /// m³ of bulk at 0.6) would reach a radius of 57 mm at 20°, so a 60 mm plate holds every
    /// heap steeper than that. The lift speed is a quarter of the speed √(g d) ≈ 0.17 m/s at
    /// which a grain falls through one diameter: the column empties by avalanches along its
    /// foot, not by a collapse, and a default run stays cheap.
    pub fn example() -> Self {
        Self {
            cylinder_radius: 0.02,
            height: 0.08,
            plate_radius: 0.06,
            lift_speed: 0.05,
        }
    }

    /// Volume inside the cylinder below height `h` above the plate [m³]: π R_c² h.
    pub fn volume_below(&self, h: f64) -> f64 {
        PI * self.cylinder_radius * self.cylinder_radius * h.clamp(0.0, self.height)
    }

    /// Volume inside the whole cylinder [m³].
    pub fn volume(&self) -> f64 {
        self.volume_below(self.height)
    }

    /// Height [m] below which the cylinder holds `volume` [m³], or `None` if it cannot.
    pub fn height_holding(&self, volume: f64) -> Option<f64> {
        height_holding(self.height, volume, |z| self.volume_below(z))
    }

    /// Whether a sphere of radius `r` [m] centred at (x, y, z) lies inside the cylinder with
    /// clearance `gap` [m]: above the plate, below the top and inside the wall.
    pub fn holds(&self, x: f64, y: f64, z: f64, r: f64, gap: f64) -> bool {
        let c = r + gap;
        z - c >= 0.0 && z + c <= self.height && x.hypot(y) + c <= self.cylinder_radius
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cylinder holds π R² h and height_holding inverts it; holds() respects the plate,
    /// the wall and the top.
    #[test]
    fn cylinder_volume_and_inside() {
        let g = HeapGeometry::example();
        assert!((g.volume_below(0.03) - PI * 4e-4 * 0.03).abs() < 1e-18);
        let back = g.height_holding(g.volume_below(0.03)).unwrap();
        assert!((back - 0.03).abs() < 1e-12);
        assert!(g.height_holding(1.01 * g.volume()).is_none());
        let r = 0.0015;
        assert!(g.holds(0.0185 - 1e-9, 0.0, 0.01, r, 0.0));
        assert!(!g.holds(0.0185 + 1e-9, 0.0, 0.01, r, 0.0));
        assert!(!g.holds(0.0, 0.0, 0.001, r, 0.0));
        assert!(!g.holds(0.0, 0.0, 0.0795, r, 0.0));
    }
}
