//! The arch that blocks a clogged orifice (docs/physics.md §7.9): the lowest grains over the
//! opening, which carry the bed above it.
//!
//! Over the orifice, every grain of the bed rests on grains below it, down to those of the
//! arch, below which lies the opening. So the arch is the lower envelope of the grains
//! over the opening: the footprint of the opening is cut into cells of width d/2 (along x
//! for a slot, in x and y for a circle or a rectangle), and in each cell the grain with the
//! lowest centre is an arch member. A grain whose centre is within r/2 of the opening's
//! edge can rest on the plate, so only centres more than r/2 inside count, as for the clog
//! test itself; and only grains within D + d above the outlet line, where an arch of
//! grains spanning the opening can stand.

use serde::{Deserialize, Serialize};

use super::geometry::{OutletGeometry, OutletShape};
use super::snapshot::Snapshot;

/// One grain of an arch.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ArchMember {
    /// The grain's stable identifier.
    pub id: u64,
    /// Its centre (x, y, z) [m].
    pub position: [f64; 3],
    /// Its radius [m].
    pub radius: f64,
}

/// The arch over a clogged orifice: its members in order of x, then y.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Arch {
    /// The members.
    pub members: Vec<ArchMember>,
    /// Height z_o of the outlet line the heights are measured from [m].
    pub outlet_height: f64,
}

impl Arch {
    /// The highest member's centre above the outlet line [m]: the arch's apex.
    pub fn apex_height(&self) -> f64 {
        self.heights().fold(f64::NEG_INFINITY, f64::max)
    }

    /// The lowest member's centre above the outlet line [m]: where it meets the plates.
    pub fn lowest_height(&self) -> f64 {
        self.heights().fold(f64::INFINITY, f64::min)
    }

    /// The members' mean centre height above the outlet line [m].
    pub fn mean_height(&self) -> f64 {
        self.heights().sum::<f64>() / self.members.len() as f64
    }

    /// The largest horizontal distance between two members' centres [m]: how far the arch
    /// reaches across the opening (0 for an arch of one grain).
    pub fn span(&self) -> f64 {
        let mut span: f64 = 0.0;
        for (k, a) in self.members.iter().enumerate() {
            for b in &self.members[k + 1..] {
                let (dx, dy) = (a.position[0] - b.position[0], a.position[1] - b.position[1]);
                span = span.max(dx.hypot(dy));
            }
        }
        span
    }

    fn heights(&self) -> impl Iterator<Item = f64> + '_ {
        self.members
            .iter()
            .map(|m| m.position[2] - self.outlet_height)
    }
}

/// The arch over the opening of `outlet` in `snapshot`, or `None` when no grain stands over
/// the opening (the orifice is open).
pub fn find_arch(snapshot: &Snapshot, outlet: &OutletGeometry) -> Option<Arch> {
    let o = outlet;
    let cell = 0.5 * o.particle_diameter;
    let cells = (2.0 * o.half_width / cell).ceil().max(1.0) as i64;
    let top = o.outlet_height + 2.0 * o.half_width + o.particle_diameter;
    // Each cell's lowest grain, by (z, id) so that ties go the same way at any order.
    let mut lowest: std::collections::BTreeMap<(i64, i64), (f64, u64, usize)> =
        std::collections::BTreeMap::new();
    for k in 0..snapshot.len() {
        let [x, y, z] = snapshot.positions[k];
        let r = snapshot.radii[k];
        if !(z > o.outlet_height && z < top) {
            continue;
        }
        let inside = |reach: f64, half: f64| reach < half - 0.5 * r;
        let dx = x - o.centre;
        let (over, cy) = match o.shape {
            OutletShape::Slot => (inside(dx.abs(), o.half_width), 0.0),
            OutletShape::Circle { centre_y } => {
                (inside(dx.hypot(y - centre_y), o.half_width), y - centre_y)
            }
            OutletShape::Rectangle {
                centre_y,
                half_depth,
            } => (
                inside(dx.abs(), o.half_width) && inside((y - centre_y).abs(), half_depth),
                y - centre_y,
            ),
        };
        if !over {
            continue;
        }
        let ix = (((dx + o.half_width) / cell).floor() as i64).clamp(0, cells - 1);
        let iy = match o.shape {
            OutletShape::Slot => 0,
            _ => (cy / cell).floor() as i64,
        };
        let id = snapshot.ids[k];
        let entry = lowest.entry((ix, iy)).or_insert((z, id, k));
        if (z, id) < (entry.0, entry.1) {
            *entry = (z, id, k);
        }
    }
    if lowest.is_empty() {
        return None;
    }
    let mut members: Vec<ArchMember> = lowest
        .values()
        .map(|&(_, id, k)| ArchMember {
            id,
            position: snapshot.positions[k],
            radius: snapshot.radii[k],
        })
        .collect();
    members.sort_by(|a, b| {
        (a.position[0], a.position[1], a.id)
            .partial_cmp(&(b.position[0], b.position[1], b.id))
            .unwrap_or(std::cmp::Ordering::Equal)
    });
    Some(Arch {
        members,
        outlet_height: o.outlet_height,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn slot(half_width: f64) -> OutletGeometry {
        OutletGeometry {
            outlet_height: 0.0,
            centre: 0.0,
            half_width,
            particle_diameter: 0.003,
            shape: OutletShape::Slot,
        }
    }

    fn snapshot<'a>(
        ids: &'a [u64],
        positions: &'a [[f64; 3]],
        radii: &'a [f64],
        velocities: &'a [[f64; 3]],
    ) -> Snapshot<'a> {
        Snapshot {
            time: 0.0,
            ids,
            positions,
            velocities,
            radii,
            density: 2500.0,
            masses: None,
        }
    }

    #[test]
    fn the_arch_is_the_lower_envelope_over_the_opening() {
        // An arch of five grains over a slot 12 mm wide, a grain on top of its apex, and two
        // grains beside the opening resting on the plates: the arch is the five, in order of
        // x, with its apex at 6 mm and its feet at 2 mm.
        let r = 0.0015;
        let arch = [
            [-0.0044, 0.0, 0.002],
            [-0.0022, 0.0, 0.0045],
            [0.0, 0.0, 0.006],
            [0.0022, 0.0, 0.0045],
            [0.0044, 0.0, 0.002],
        ];
        let mut positions = arch.to_vec();
        positions.push([0.0, 0.0, 0.009]); // on the apex
        positions.push([-0.009, 0.0, 0.0015]); // on the left plate
        positions.push([0.009, 0.0, 0.0015]); // on the right plate
        let ids: Vec<u64> = (10..10 + positions.len() as u64).rev().collect();
        let radii = vec![r; positions.len()];
        let velocities = vec![[0.0; 3]; positions.len()];
        let found = find_arch(
            &snapshot(&ids, &positions, &radii, &velocities),
            &slot(0.006),
        )
        .expect("an arch");
        let xs: Vec<f64> = found.members.iter().map(|m| m.position[0]).collect();
        assert_eq!(xs, [-0.0044, -0.0022, 0.0, 0.0022, 0.0044]);
        assert_eq!(found.apex_height(), 0.006);
        assert_eq!(found.lowest_height(), 0.002);
        assert!((found.mean_height() - 0.0038).abs() < 1e-15);
        // Its feet lie 8.8 mm apart: the span, to rounding.
        assert!((found.span() - 0.0088).abs() < 1e-15);
    }

    #[test]
    fn an_open_orifice_has_no_arch() {
        // Grains only on the plates, beside the opening, or already below the outlet line.
        let positions = [[-0.009, 0.0, 0.0015], [0.0, 0.0, -0.002]];
        let ids = [1, 2];
        let radii = [0.0015; 2];
        let velocities = [[0.0; 3]; 2];
        assert!(find_arch(
            &snapshot(&ids, &positions, &radii, &velocities),
            &slot(0.006)
        )
        .is_none());
    }

    #[test]
    fn a_circular_orifice_takes_the_lowest_grain_of_each_cell() {
        // Two grains stacked over the centre of a 12 mm disc: only the lower one is in the
        // arch; a grain over the disc's edge (centre within r/2 of it) is not.
        let o = OutletGeometry {
            shape: OutletShape::Circle { centre_y: 0.0 },
            ..slot(0.006)
        };
        let positions = [[0.0, 0.0, 0.004], [0.0, 0.0, 0.007], [0.0, 0.0055, 0.002]];
        let ids = [5, 6, 7];
        let radii = [0.0015; 3];
        let velocities = [[0.0; 3]; 3];
        let found = find_arch(&snapshot(&ids, &positions, &radii, &velocities), &o).expect("arch");
        let ids: Vec<u64> = found.members.iter().map(|m| m.id).collect();
        assert_eq!(ids, [5]);
    }
}
