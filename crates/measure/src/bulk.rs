//! Settled bulk volume fraction φ_B and bed height (paper Sec. 2: φ_B = 0.59 for the angle
//! series, 0.57 for the eccentric series).
//!
//! Definitions used here:
//! - **Bed height** h_bed: the x-range of the container is cut into columns of width d; in
//!   each column holding particles, the highest centre plus its radius is the local surface;
//!   h_bed is the mean over occupied columns. This is the mean free-surface height, which for
//!   a heaped or sloped top is the level of an equal-volume flat surface to within the
//!   roughness of one layer.
//! - **Cut height** h_cut = h_bed − cut depth (default 2d), to keep the loose top layer out.
//! - **φ_B** = V_p(h_cut)/(A(h_cut) Z): V_p is the particle volume between the container floor
//!   and h_cut, counting each sphere's exact slice (spherical caps, no centre-counting bias);
//!   A(h) is the container's inner 2D cross-section area below h; Z is the slab thickness.
//! - **Mid-plane area fraction** φ_2D = Σ |disc ∩ {floor ≤ z ≤ h_cut}| / A(h_cut), with the
//!   particles' equatorial discs; φ_B ≈ (2/3)(d/Z) φ_2D in a monolayer (docs/physics.md §7.4),
//!   which is how 0.59 (3D) corresponds to ≈ 0.885 (2D).

use serde::{Deserialize, Serialize};

use super::disc_area::{overlap_area, Disc, Rectangle};
use super::error::MeasureError;
use super::geometry::OutletGeometry;
use super::snapshot::Snapshot;

/// The container's inner cross-section in the (x, z) plane.
pub trait CrossSection {
    /// Area of the container's inner (x, z) cross-section below height `height` [m], in m².
    fn area_below(&self, height: f64) -> f64;
}

impl<F: Fn(f64) -> f64> CrossSection for F {
    fn area_below(&self, height: f64) -> f64 {
        self(height)
    }
}

/// A simple polygon (x, z) [m] outlining the container's inside, e.g. the hopper walls closed
/// across the orifice at z_o and across the top.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ContainerOutline {
    /// Vertices in order (either orientation) [m].
    pub vertices: Vec<[f64; 2]>,
}

impl ContainerOutline {
    /// An outline from its vertices; needs at least three.
    pub fn new(vertices: Vec<[f64; 2]>) -> Result<Self, MeasureError> {
        if vertices.len() < 3 {
            return Err(MeasureError::DegenerateOutline(vertices.len()));
        }
        if vertices.iter().flatten().any(|c| !c.is_finite()) {
            return Err(MeasureError::InvalidParameter {
                name: "outline vertex",
                value: f64::NAN,
                reason: "coordinates must be finite",
            });
        }
        Ok(Self { vertices })
    }

    /// The hopper of Fig. 1: side walls at x = ±L/2 (`width` L [m]), bottom plates inclined at
    /// `hopper_angle` α [rad] to the vertical (π/2 = flat bottom), running from the side walls
    /// down to the orifice edges x_c ± R at z_o, and a lid at `top` [m].
    pub fn hopper(
        width: f64,
        outlet: &OutletGeometry,
        hopper_angle: f64,
        top: f64,
    ) -> Result<Self, MeasureError> {
        outlet.validate()?;
        if !(hopper_angle > 0.0 && hopper_angle <= std::f64::consts::FRAC_PI_2) {
            return Err(MeasureError::InvalidParameter {
                name: "hopper_angle",
                value: hopper_angle,
                reason: "must lie in (0, π/2] rad, measured from the vertical",
            });
        }
        let half = 0.5 * width;
        let left_edge = outlet.centre - outlet.half_width;
        let right_edge = outlet.centre + outlet.half_width;
        if !(width > 0.0 && left_edge >= -half && right_edge <= half) {
            return Err(MeasureError::InvalidParameter {
                name: "width",
                value: width,
                reason: "the orifice must fit between the side walls",
            });
        }
        // A plate at α to the vertical rises by run / tan α.
        let rise = |run: f64| run / hopper_angle.tan();
        let z_o = outlet.outlet_height;
        let z_left = z_o + rise(left_edge + half);
        let z_right = z_o + rise(half - right_edge);
        if !(top > z_left.max(z_right)) {
            return Err(MeasureError::InvalidParameter {
                name: "top",
                value: top,
                reason: "must lie above the bottom plates",
            });
        }
        Self::new(vec![
            [-half, top],
            [-half, z_left],
            [left_edge, z_o],
            [right_edge, z_o],
            [half, z_right],
            [half, top],
        ])
    }

    /// Lowest and highest x [m].
    pub fn x_range(&self) -> (f64, f64) {
        let xs = self.vertices.iter().map(|v| v[0]);
        (
            xs.clone().fold(f64::INFINITY, f64::min),
            xs.fold(f64::NEG_INFINITY, f64::max),
        )
    }

    /// Lowest z [m], the container floor.
    pub fn floor(&self) -> f64 {
        self.vertices
            .iter()
            .map(|v| v[1])
            .fold(f64::INFINITY, f64::min)
    }
}

impl CrossSection for ContainerOutline {
    /// Clips the polygon to z ≤ height (Sutherland–Hodgman against one half-plane, exact for
    /// any simple polygon since degenerate edges add no area) and takes the shoelace area.
    fn area_below(&self, height: f64) -> f64 {
        let n = self.vertices.len();
        let mut clipped: Vec<[f64; 2]> = Vec::with_capacity(n + 4);
        for k in 0..n {
            let a = self.vertices[k];
            let b = self.vertices[(k + 1) % n];
            let (a_in, b_in) = (a[1] <= height, b[1] <= height);
            if a_in {
                clipped.push(a);
            }
            if a_in != b_in {
                let s = (height - a[1]) / (b[1] - a[1]);
                clipped.push([a[0] + s * (b[0] - a[0]), height]);
            }
        }
        let m = clipped.len();
        let twice: f64 = (0..m)
            .map(|k| {
                let (p, q) = (clipped[k], clipped[(k + 1) % m]);
                p[0] * q[1] - q[0] * p[1]
            })
            .sum();
        0.5 * twice.abs()
    }
}

/// Result of a bulk measurement.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BulkMeasurement {
    /// Mean free-surface height h_bed [m].
    pub bed_height: f64,
    /// Height below which φ_B is measured, h_bed − cut depth [m].
    pub cut_height: f64,
    /// Particle volume between the floor and the cut [m³].
    pub particle_volume: f64,
    /// Container volume A(h_cut)·Z below the cut [m³].
    pub container_volume: f64,
    /// Bulk (3D) volume fraction φ_B.
    pub volume_fraction: f64,
    /// Mid-plane 2D area fraction below the cut.
    pub area_fraction: f64,
    /// Number of occupied surface columns.
    pub columns: usize,
}

/// Measures φ_B and the bed height of a settled (or paused) packing.
#[derive(Debug, Clone)]
pub struct BulkProbe<C: CrossSection> {
    cross_section: C,
    slab_thickness: f64,
    x_min: f64,
    x_max: f64,
    floor: f64,
    column_width: f64,
    cut_depth: f64,
}

impl<C: CrossSection> BulkProbe<C> {
    /// A probe for a container with cross-section `cross_section`, slab thickness
    /// `slab_thickness` Z [m], inner x-range [x_min, x_max] [m] and floor height `floor` [m]
    /// (particles wholly below it, e.g. already discharged, are ignored). Columns are
    /// `particle_diameter` d wide and the cut depth is 2d; see [`Self::with_cut_depth`].
    pub fn new(
        cross_section: C,
        slab_thickness: f64,
        x_range: (f64, f64),
        floor: f64,
        particle_diameter: f64,
    ) -> Result<Self, MeasureError> {
        let positive = [
            ("slab_thickness", slab_thickness),
            ("particle_diameter", particle_diameter),
        ];
        for (name, value) in positive {
            if !(value.is_finite() && value > 0.0) {
                return Err(MeasureError::InvalidParameter {
                    name,
                    value,
                    reason: "must be finite and positive",
                });
            }
        }
        if !(x_range.0.is_finite() && x_range.1.is_finite() && x_range.1 > x_range.0) {
            return Err(MeasureError::InvalidParameter {
                name: "x_range",
                value: x_range.1,
                reason: "upper bound must be finite and above the lower one",
            });
        }
        if !floor.is_finite() {
            return Err(MeasureError::InvalidParameter {
                name: "floor",
                value: floor,
                reason: "must be finite",
            });
        }
        Ok(Self {
            cross_section,
            slab_thickness,
            x_min: x_range.0,
            x_max: x_range.1,
            floor,
            column_width: particle_diameter,
            cut_depth: 2.0 * particle_diameter,
        })
    }

    /// Sets the depth [m] below the free surface that is left out of φ_B.
    pub fn with_cut_depth(mut self, cut_depth: f64) -> Result<Self, MeasureError> {
        if !(cut_depth.is_finite() && cut_depth >= 0.0) {
            return Err(MeasureError::InvalidParameter {
                name: "cut_depth",
                value: cut_depth,
                reason: "must be finite and non-negative",
            });
        }
        self.cut_depth = cut_depth;
        Ok(self)
    }

    /// Measures the frame. Fails if no particle lies above the floor or the cut falls to or
    /// below the floor.
    pub fn measure(&self, frame: &Snapshot<'_>) -> Result<BulkMeasurement, MeasureError> {
        frame.validate()?;
        let columns = ((self.x_max - self.x_min) / self.column_width)
            .ceil()
            .max(1.0) as usize;
        let mut top = vec![f64::NEG_INFINITY; columns];
        for i in 0..frame.len() {
            let [x, _, z] = frame.positions[i];
            if z < self.floor || x < self.x_min || x > self.x_max {
                continue;
            }
            let c = (((x - self.x_min) / self.column_width) as usize).min(columns - 1);
            top[c] = top[c].max(z + frame.radii[i]);
        }
        let occupied: Vec<f64> = top.into_iter().filter(|t| t.is_finite()).collect();
        if occupied.is_empty() {
            return Err(MeasureError::InvalidParameter {
                name: "frame",
                value: frame.len() as f64,
                reason: "no particle lies inside the container",
            });
        }
        let bed_height = occupied.iter().sum::<f64>() / occupied.len() as f64;
        let cut_height = bed_height - self.cut_depth;
        let area = self.cross_section.area_below(cut_height);
        if !(cut_height > self.floor && area > 0.0) {
            return Err(MeasureError::InvalidParameter {
                name: "cut_depth",
                value: self.cut_depth,
                reason: "the cut falls to or below the container floor; the bed is too shallow",
            });
        }
        let mut particle_volume = 0.0;
        let mut disc_area = 0.0;
        for i in 0..frame.len() {
            let [x, _, z] = frame.positions[i];
            let r = frame.radii[i];
            if x < self.x_min || x > self.x_max {
                continue;
            }
            particle_volume +=
                sphere_volume_below(r, cut_height - z) - sphere_volume_below(r, self.floor - z);
            disc_area += overlap_area(
                Disc { x, z, radius: r },
                Rectangle {
                    x_min: x - r,
                    x_max: x + r,
                    z_min: self.floor,
                    z_max: cut_height,
                },
            );
        }
        let container_volume = area * self.slab_thickness;
        Ok(BulkMeasurement {
            bed_height,
            cut_height,
            particle_volume,
            container_volume,
            volume_fraction: particle_volume / container_volume,
            area_fraction: disc_area / area,
            columns: occupied.len(),
        })
    }
}

/// Volume [m³] of a sphere of radius `radius` [m] below a plane at height `offset` [m] above
/// its centre: the cap of height c = clamp(offset + r, 0, 2r), V = π c² (3r − c)/3.
pub fn sphere_volume_below(radius: f64, offset: f64) -> f64 {
    let c = (offset + radius).clamp(0.0, 2.0 * radius);
    std::f64::consts::PI * c * c * (3.0 * radius - c) / 3.0
}
