//! The shape of a component's grains (`particles.shape`, or a component's `shape`): rigid
//! clumps of spheres (docs/physics.md §11) given as a list of member spheres, as a rod of
//! an aspect ratio, or as a closed STL body filled with spheres. The component's diameter (or
//! size distribution) gives each grain's size as the diameter of the sphere of equal volume,
//! so that grains of different shapes and the spheres they are compared with have the same
//! mass.

use std::path::PathBuf;

use dem::clump::{ClumpShape, MAX_FILL_SPHERES, MAX_ROD_BEADS};
use dem::DVec3;
use serde::{Deserialize, Serialize};

/// Largest aspect ratio of a rod (length over width).
pub const MAX_ASPECT_RATIO: f64 = 20.0;

/// Most member spheres of a shape given as a list.
pub const MAX_SHAPE_SPHERES: usize = MAX_FILL_SPHERES;

/// Grid cells along an STL grain's longest side: default and allowed range.
pub const DEFAULT_FILL_CELLS: usize = 40;
/// See [`DEFAULT_FILL_CELLS`].
pub const FILL_CELLS_RANGE: (usize, usize) = (8, 200);

/// Share of an STL grain's inside left uncovered by its spheres: default and allowed range.
pub const DEFAULT_FILL_SHORTFALL: f64 = 0.05;
/// See [`DEFAULT_FILL_SHORTFALL`] (open interval ends).
pub const FILL_SHORTFALL_RANGE: (f64, f64) = (0.001, 0.5);

/// How the case file gives a shape.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum ShapeGiven {
    /// Member spheres as (x, y, z, r) in any unit of length (the shape is scaled to the
    /// component's size).
    Spheres {
        /// The members (x, y, z, r).
        spheres: Vec<[f64; 4]>,
    },
    /// Equal beads in a row ([`ClumpShape::rod`]).
    Rod {
        /// Length over width, end to end [-].
        aspect_ratio: f64,
        /// Beads in the row.
        beads: usize,
    },
    /// A closed STL surface filled with inscribed spheres (`dem::clump::fill_mesh`).
    Stl {
        /// The STL file, absolute (a relative path is taken from the case file's folder).
        file: PathBuf,
        /// Hex SHA-256 of the file's bytes when the case was read.
        sha256: String,
        /// Grid cells along the body's longest side.
        cells: usize,
        /// The share of the body's inside the spheres may leave uncovered [-].
        shortfall: f64,
    },
}

/// A grain shape, resolved: as given, and as the member spheres of a grain of unit
/// equal-volume diameter.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct GrainShape {
    /// How the case file gave it.
    pub given: ShapeGiven,
    /// The members (x, y, z, r) of a grain whose union has the volume of a sphere of
    /// diameter 1, in the frame they were given in (lengths in units of the equal-volume
    /// diameter).
    pub unit_members: Vec<[f64; 4]>,
    /// The farthest reach of a unit grain from its centre of mass: max |c − x_cm| + r over
    /// the members [in equal-volume diameters].
    pub unit_reach: f64,
    /// The unit grain's centre of mass in the frame of `unit_members` [equal-volume
    /// diameters].
    pub unit_centre: [f64; 3],
    /// For an STL grain, the union's volume over the body's [-] (1 − the shortfall measured
    /// exactly); 1 for the other kinds, whose members are the shape.
    pub filled_fraction: f64,
}

impl GrainShape {
    /// The shape of `members` (any frame, any unit), scaled to unit equal-volume diameter;
    /// `given` is how the case file gave it.
    pub fn from_members(
        given: ShapeGiven,
        members: &ClumpShape,
        filled_fraction: f64,
    ) -> GrainShape {
        let volume = members.body(1.0).volume;
        let scale = (std::f64::consts::PI / 6.0 / volume).cbrt();
        let unit: Vec<[f64; 4]> = members
            .members()
            .iter()
            .map(|&(c, r)| [c.x * scale, c.y * scale, c.z * scale, r * scale])
            .collect();
        let centre = unit_clump(&unit).body(1.0).centre;
        let unit_reach = unit
            .iter()
            .map(|m| (DVec3::new(m[0], m[1], m[2]) - centre).length() + m[3])
            .fold(0.0, f64::max);
        GrainShape {
            given,
            unit_members: unit,
            unit_reach,
            unit_centre: centre.to_array(),
            filled_fraction,
        }
    }

    /// The members as an engine clump shape of unit equal-volume diameter; the engine scales
    /// it to each grain's diameter (`Simulation::add_scaled_clump`).
    pub fn unit_clump(&self) -> ClumpShape {
        unit_clump(&self.unit_members)
    }

    /// The smallest member's diameter over the grain's equal-volume diameter [-] (a rod of
    /// aspect ratio 3 has beads 0.63 of it across).
    pub fn smallest_member_diameter(&self) -> f64 {
        2.0 * self
            .unit_members
            .iter()
            .map(|m| m[3])
            .fold(f64::INFINITY, f64::min)
    }

    /// Number of member spheres.
    pub fn members(&self) -> usize {
        self.unit_members.len()
    }

    /// A short description for messages and reports: "rod of aspect ratio 2 (3 beads)".
    pub fn describe(&self) -> String {
        match &self.given {
            ShapeGiven::Spheres { spheres } => format!("clump of {} spheres", spheres.len()),
            ShapeGiven::Rod {
                aspect_ratio,
                beads,
            } => format!("rod of aspect ratio {aspect_ratio} ({beads} beads)"),
            ShapeGiven::Stl { file, .. } => format!(
                "{} filled with {} spheres",
                file.file_name().map_or_else(
                    || file.display().to_string(),
                    |n| n.to_string_lossy().into_owned()
                ),
                self.members()
            ),
        }
    }
}

fn unit_clump(members: &[[f64; 4]]) -> ClumpShape {
    ClumpShape::new(
        members
            .iter()
            .map(|m| (DVec3::new(m[0], m[1], m[2]), m[3]))
            .collect(),
    )
    .expect("a resolved shape's members were checked when it was read")
}

/// The default bead count of a rod of `aspect` (≥ 1): neighbours half a width apart,
/// ⌈2 (aspect − 1)⌉ + 1 beads (one at aspect 1, three at 2, five at 3), within the rod's
/// limits. Half a width keeps the rod's sides within 7 % of a width of a smooth
/// spherocylinder's (the dip between two beads of radius w/2 half a width apart is
/// w/2 − √(w²/4 − w²/16) = 0.067 w).
pub fn default_beads(aspect: f64) -> usize {
    if aspect <= 1.0 {
        return 1;
    }
    ((2.0 * (aspect - 1.0)).ceil() as usize + 1)
        .max(aspect.ceil() as usize)
        .min(MAX_ROD_BEADS)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_unit_grain_has_the_volume_of_the_unit_sphere_and_its_reach() {
        // Two touching spheres of radius 1 (volume 8π/3) scale to volume π/6: by (1/16)^(1/3);
        // the reach from the centre of mass is 2 radii, 2 (1/16)^(1/3).
        let two = ClumpShape::new(vec![
            (DVec3::new(-1.0, 0.0, 0.0), 1.0),
            (DVec3::new(1.0, 0.0, 0.0), 1.0),
        ])
        .unwrap();
        let given = ShapeGiven::Spheres {
            spheres: vec![[-1.0, 0.0, 0.0, 1.0], [1.0, 0.0, 0.0, 1.0]],
        };
        let shape = GrainShape::from_members(given, &two, 1.0);
        let v = shape.unit_clump().body(1.0).volume;
        assert!(
            (v / (std::f64::consts::PI / 6.0) - 1.0).abs() < 1e-14,
            "{v}"
        );
        let s = (1.0f64 / 16.0).cbrt();
        assert!((shape.unit_reach - 2.0 * s).abs() < 1e-14);
        assert!((shape.unit_members[0][3] - s).abs() < 1e-15);
    }

    #[test]
    fn default_beads_are_half_a_width_apart_and_at_least_touching() {
        assert_eq!(default_beads(1.0), 1);
        assert_eq!(default_beads(1.5), 2);
        assert_eq!(default_beads(2.0), 3);
        assert_eq!(default_beads(3.0), 5);
        assert_eq!(default_beads(2.2), 4);
        // Each default makes a valid rod.
        for a in [1.0, 1.2, 1.5, 2.0, 2.7, 3.0, 5.0, 10.0, MAX_ASPECT_RATIO] {
            ClumpShape::rod(a, default_beads(a), 1.0).unwrap_or_else(|e| panic!("{a}: {e}"));
        }
    }
}
