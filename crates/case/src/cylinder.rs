//! A cylindrical silo (`geometry.kind = "cylinder"`, docs/physics.md §5.6): a vertical
//! cylinder above a conical hopper or a flat bottom, with a circular orifice at z = 0 on the
//! z axis.

use std::f64::consts::PI;

use serde::{Deserialize, Serialize};

use super::fill_height::height_holding;
use super::wall_surface::{WallSurface, DEFAULT_MESH_SEGMENTS};

/// A cylindrical silo: a vertical cylinder of radius R above a conical hopper of half-angle
/// θ (or a flat bottom), with a circular orifice of diameter D in the orifice plane z = 0.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CylinderGeometry {
    /// Inner radius R of the cylinder [m] (benchmark silo: 0.1 m).
    pub radius: f64,
    /// Height H of the top of the cylinder above the orifice plane [m].
    pub height: f64,
    /// Orifice diameter D [m].
    pub outlet_diameter: f64,
    /// Half-angle θ of the conical hopper from the vertical [°], in (0, 90]; 90 is a flat
    /// bottom. Kept in degrees so that a resolved case writes back exactly what was read.
    pub hopper_angle_deg: f64,
    /// Offset e of the orifice centre from the axis along x [m]; non-zero only with a flat
    /// bottom.
    pub outlet_offset: f64,
    /// Smooth or meshed cylinder and cone.
    pub walls: WallSurface,
    /// Segments around the axis of meshed walls and of the orifice's polygon.
    pub mesh_segments: usize,
}

impl CylinderGeometry {
    /// The benchmark silo of Dosta et al. (2024) with its large orifice, moved so that the
    /// orifice plane is z = 0: R = 0.1 m, a 45° cone from the orifice of radius 0.03 m to the
    /// cylinder at z = 0.07 m, the top of the particle domain at H = 0.2354 m.
    pub fn dosta2024_large() -> Self {
        Self {
            radius: 0.1,
            height: 0.2354,
            outlet_diameter: 0.06,
            hopper_angle_deg: 45.0,
            outlet_offset: 0.0,
            walls: WallSurface::Smooth,
            mesh_segments: DEFAULT_MESH_SEGMENTS,
        }
    }

    /// Whether the bottom is flat (θ = 90°).
    pub fn is_flat(&self) -> bool {
        self.hopper_angle_deg >= 90.0
    }

    /// Half-angle θ of the cone from the vertical [rad].
    pub fn hopper_angle(&self) -> f64 {
        self.hopper_angle_deg.to_radians()
    }

    /// Orifice radius r_o = D/2 [m].
    pub fn outlet_radius(&self) -> f64 {
        0.5 * self.outlet_diameter
    }

    /// Height where the cone meets the cylinder, (R − r_o)/tan θ [m]; 0 for a flat bottom.
    pub fn cone_height(&self) -> f64 {
        if self.is_flat() {
            0.0
        } else {
            (self.radius - self.outlet_radius()) / self.hopper_angle().tan()
        }
    }

    /// Radius of the container at height `z` above the orifice plane [m]: the cone's
    /// r_o + z tan θ below the cone's top, R above it.
    pub fn radius_at(&self, z: f64) -> f64 {
        if z >= self.cone_height() {
            self.radius
        } else {
            self.outlet_radius() + z.max(0.0) * self.hopper_angle().tan()
        }
    }

    /// Volume of the container below height `h` above the orifice plane [m³]: a cone
    /// frustum π h (r_o² + r_o ρ + ρ²)/3 with ρ the radius at h, then a cylinder.
    pub fn volume_below(&self, h: f64) -> f64 {
        let h = h.clamp(0.0, self.height);
        let hc = self.cone_height();
        let cone = |z: f64| {
            let (a, b) = (self.outlet_radius(), self.radius_at(z));
            PI * z * (a * a + a * b + b * b) / 3.0
        };
        if h <= hc {
            cone(h)
        } else {
            cone(hc) + PI * self.radius * self.radius * (h - hc)
        }
    }

    /// Volume of the whole container below H [m³].
    pub fn volume(&self) -> f64 {
        self.volume_below(self.height)
    }

    /// Height [m] below which the container holds `volume` [m³], or `None` if it cannot.
    pub fn height_holding(&self, volume: f64) -> Option<f64> {
        height_holding(self.height, volume, |z| self.volume_below(z))
    }

    /// Whether a sphere of radius `r` [m] centred at (x, y, z) lies inside the container
    /// with clearance `gap` [m]: above the orifice plane, inside the cylinder, and on the
    /// inner side of the cone (its distance to the cone's meridian line, (ρ_cone(z) − ρ)·cos θ,
    /// at least r + gap).
    pub fn holds(&self, x: f64, y: f64, z: f64, r: f64, gap: f64) -> bool {
        let c = r + gap;
        let rho = x.hypot(y);
        if z - c < 0.0 || z + c > self.height || rho + c > self.radius {
            return false;
        }
        if self.is_flat() {
            return true;
        }
        let theta = self.hopper_angle();
        let cone = self.outlet_radius() + z * theta.tan();
        (cone - rho) * theta.cos() >= c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The benchmark's cone meets the cylinder at 0.070 m above the large orifice
    /// (docs: the orifice plane at −0.0554 m, the junction at 0.0146 m).
    #[test]
    fn benchmark_cone_height_matches_the_driver() {
        let s = CylinderGeometry::dosta2024_large();
        // tan 45° rounds to 1 − 1.1e-16: the height is 0.07 to a few ulps.
        assert!((s.cone_height() - 0.070).abs() < 1e-15);
        let small = CylinderGeometry {
            outlet_diameter: 0.04,
            ..s
        };
        assert!((small.cone_height() - 0.080).abs() < 1e-15);
    }

    /// The volume is the cone frustum's closed form below the junction and grows by πR² per
    /// metre above it; height_holding inverts it.
    #[test]
    fn volume_below_and_its_inverse() {
        let s = CylinderGeometry::dosta2024_large();
        let hc = s.cone_height();
        let frustum = PI * hc * (0.03f64.powi(2) + 0.03 * 0.1 + 0.01) / 3.0;
        assert!((s.volume_below(hc) - frustum).abs() < 1e-15);
        let above = s.volume_below(hc + 0.05) - s.volume_below(hc);
        assert!((above - PI * 0.01 * 0.05).abs() < 1e-15);
        for h in [0.01, 0.05, 0.1, 0.2] {
            let back = s.height_holding(s.volume_below(h)).unwrap();
            // Bisection to 2^-60 of H.
            assert!((back - h).abs() < 1e-12, "{h} -> {back}");
        }
        assert!(s.height_holding(s.volume() * 1.01).is_none());
    }

    /// A sphere touching the cone from inside is held with zero clearance and refused with
    /// more; the cylinder and the orifice plane bound it too.
    #[test]
    fn holds_respects_every_wall() {
        let s = CylinderGeometry::dosta2024_large();
        let r = 0.002;
        let z = 0.03;
        // On the meridian x > 0: the largest ρ whose distance to the cone is exactly r.
        let theta = s.hopper_angle();
        let rho = s.outlet_radius() + z * theta.tan() - r / theta.cos();
        assert!(s.holds(rho - 1e-9, 0.0, z, r, 0.0));
        assert!(!s.holds(rho + 1e-9, 0.0, z, r, 0.0));
        assert!(!s.holds(0.0, 0.0, r * 0.5, r, 0.0));
        assert!(!s.holds(0.0, 0.099, 0.2, r, 0.0));
        assert!(s.holds(0.0, 0.097, 0.2, r, 0.0));
        assert!(!s.holds(0.0, 0.0, s.height - 0.5 * r, r, 0.0));
    }
}
