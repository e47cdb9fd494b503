//! Outlet geometry, the normalised coordinate x* and the x-bins across the orifice (docs/physics.md §7).

use serde::{Deserialize, Serialize};

use super::error::MeasureError;

/// Half-width in x* of the central region whose bins define centre values (docs/physics.md §7.2:
/// v_c is the mean of the bins with |x*| < 0.1).
pub const CENTRE_HALF_WIDTH: f64 = 0.1;

/// Where the orifice is and how big the grains are.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct OutletGeometry {
    /// Height z_o of the outlet line, the top surface of the bottom plates at the orifice [m].
    pub outlet_height: f64,
    /// Horizontal position x_c of the orifice centre, measured from the hopper axis [m].
    pub centre: f64,
    /// Orifice half-width R = D/2 [m].
    pub half_width: f64,
    /// Particle diameter d [m]; sets the default strip height and snapshot band.
    pub particle_diameter: f64,
    /// The orifice's shape: a slot across the slab, or a circle.
    #[serde(default)]
    pub shape: OutletShape,
}

/// The shape of an orifice in the outlet plane.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub enum OutletShape {
    /// A slot of half-width R about x = x_c, spanning the container in y.
    #[default]
    Slot,
    /// A circle of radius R about (x_c, `centre_y`).
    Circle {
        /// y of the orifice centre [m].
        centre_y: f64,
    },
    /// A rectangle x_c ± R by `centre_y` ± `half_depth` (a box's square orifice, the
    /// rectangle of STL walls); its profiles run along x.
    Rectangle {
        /// y of the orifice centre [m].
        centre_y: f64,
        /// Half its extent in y [m].
        half_depth: f64,
    },
}

impl OutletGeometry {
    /// Checks that the lengths are finite and positive.
    pub fn validate(&self) -> Result<(), MeasureError> {
        let checks = [
            (
                "outlet_height",
                self.outlet_height,
                self.outlet_height.is_finite(),
            ),
            ("centre", self.centre, self.centre.is_finite()),
            (
                "half_width",
                self.half_width,
                self.half_width.is_finite() && self.half_width > 0.0,
            ),
            (
                "particle_diameter",
                self.particle_diameter,
                self.particle_diameter.is_finite() && self.particle_diameter > 0.0,
            ),
        ];
        for (name, value, ok) in checks {
            if !ok {
                return Err(MeasureError::InvalidParameter {
                    name,
                    value,
                    reason: "must be finite (and positive for lengths)",
                });
            }
        }
        Ok(())
    }

    /// Normalised coordinate x* = (x − x_c)/R; x* < 0 lies toward the left (near) wall.
    pub fn normalised(&self, x: f64) -> f64 {
        (x - self.centre) / self.half_width
    }

    /// Whether a crossing at (x, y) [m] lies within the orifice: its span in x for a slot,
    /// the disc for a circle, both spans for a rectangle.
    pub fn contains(&self, x: f64, y: f64) -> bool {
        match self.shape {
            OutletShape::Slot => self.spans(x),
            OutletShape::Circle { centre_y } => {
                (x - self.centre).hypot(y - centre_y) <= self.half_width
            }
            OutletShape::Rectangle {
                centre_y,
                half_depth,
            } => self.spans(x) && (y - centre_y).abs() <= half_depth,
        }
    }

    /// Whether a centre at horizontal position `x` [m] lies within the orifice span
    /// [x_c − R, x_c + R].
    pub fn spans(&self, x: f64) -> bool {
        (x - self.centre).abs() <= self.half_width
    }
}

/// Equal-width bins covering the orifice span x* ∈ [−1, 1].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct OutletBins {
    /// Orifice centre x_c [m].
    pub centre: f64,
    /// Orifice half-width R [m].
    pub half_width: f64,
    /// Number of bins across the orifice.
    pub count: usize,
}

impl OutletBins {
    /// `count` equal bins across the orifice of `geometry`.
    pub fn across(geometry: &OutletGeometry, count: usize) -> Result<Self, MeasureError> {
        geometry.validate()?;
        if count == 0 {
            return Err(MeasureError::InvalidParameter {
                name: "bin count",
                value: 0.0,
                reason: "must be at least 1",
            });
        }
        Ok(Self {
            centre: geometry.centre,
            half_width: geometry.half_width,
            count,
        })
    }

    /// Bins of width close to `width` [m] (docs/physics.md §7.2 suggests d/2 or D/20): the count is
    /// round(D/width), at least one, so the bins tile the orifice exactly.
    pub fn with_width(geometry: &OutletGeometry, width: f64) -> Result<Self, MeasureError> {
        if !(width.is_finite() && width > 0.0) {
            return Err(MeasureError::InvalidParameter {
                name: "bin width",
                value: width,
                reason: "must be finite and positive",
            });
        }
        geometry.validate()?;
        let count = ((2.0 * geometry.half_width / width).round() as usize).max(1);
        Self::across(geometry, count)
    }

    /// Bin width Δx [m].
    pub fn width(&self) -> f64 {
        2.0 * self.half_width / self.count as f64
    }

    /// Left edge of bin `index` [m].
    pub fn left_edge(&self, index: usize) -> f64 {
        self.centre - self.half_width + index as f64 * self.width()
    }

    /// Centre of bin `index` in x [m].
    pub fn x_centre(&self, index: usize) -> f64 {
        self.left_edge(index) + 0.5 * self.width()
    }

    /// Centre of bin `index` in x* (dimensionless).
    pub fn x_star_centre(&self, index: usize) -> f64 {
        -1.0 + (2.0 * index as f64 + 1.0) / self.count as f64
    }

    /// Index of the bin holding position `x` [m], or `None` outside the orifice span.
    /// The right edge x_c + R belongs to the last bin.
    pub fn index_of(&self, x: f64) -> Option<usize> {
        let s = (x - (self.centre - self.half_width)) / self.width();
        if !(s >= 0.0 && s <= self.count as f64) {
            return None;
        }
        Some((s as usize).min(self.count - 1))
    }

    /// Bins that define centre values: those whose centre has |x*| < 0.1 (docs/physics.md §7.2).
    /// When the bins are too coarse for any centre to fall there, the bin(s) containing
    /// x* = 0 are used instead (two when x* = 0 is a bin edge).
    pub fn central_bins(&self) -> Vec<usize> {
        let inner: Vec<usize> = (0..self.count)
            .filter(|&i| self.x_star_centre(i).abs() < CENTRE_HALF_WIDTH)
            .collect();
        if !inner.is_empty() {
            return inner;
        }
        let middle = self.count / 2;
        if 2 * middle == self.count {
            vec![middle - 1, middle]
        } else {
            vec![middle]
        }
    }

    /// Whether two bin sets are the same (to round-off).
    pub fn matches(&self, other: &OutletBins) -> bool {
        let tol = 1e-12 * self.half_width.abs().max(1e-300);
        self.count == other.count
            && (self.centre - other.centre).abs() <= tol
            && (self.half_width - other.half_width).abs() <= tol
    }
}
