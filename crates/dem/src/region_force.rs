//! An external force on the particles whose centres lie inside a region (docs/physics.md
//! §6.4): each such particle receives π r² τ [N], the traction τ [Pa] of a uniform stream
//! times its cross-section, as the drag of a gas stream at a high Reynolds number scales
//! (F = ½ ρ_f C_D π r² u², so τ = ½ ρ_f C_D u²). The engine applies it at every step while
//! it is set, at the positions the forces are evaluated at, on top of the weights; it knows
//! nothing of what the force stands for (an air jet through an orifice, a blower, a field).
//!
//! A clump's members share the force of its equal-volume sphere, π r_v² τ with r_v =
//! (3V/4π)^(1/3) for the union's volume V, member k taking the part r_k²/Σ r_j² of it: a
//! grain wholly inside receives the force of a sphere of its volume whatever its shape, so
//! grains of equal volume are pushed alike (their members' cross-sections overlap, and would
//! count the overlaps twice), and a grain partly inside is pushed where its members are.
//!
//! The force is not part of [`crate::SimulationState`]: a caller that checkpoints a run with
//! one set records it itself and sets it again on the restored simulation.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::clump::{ClumpBody, ClumpSet};
use crate::particles::{ParticleSet, FLAG_FROZEN, NO_CLUMP};

/// Where a [`RegionForce`] acts: the particles whose centres lie inside.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum ForceRegion {
    /// The axis-aligned box `min` ≤ x ≤ `max`, componentwise [m].
    Box {
        /// The corner of smallest coordinates [m].
        min: DVec3,
        /// The corner of largest coordinates [m].
        max: DVec3,
    },
    /// The upright cylinder of axis (x, y) = `axis` [m] and `radius` [m], from z = `bottom`
    /// to z = `top` [m].
    Cylinder {
        /// The axis's (x, y) [m].
        axis: [f64; 2],
        /// Radius [m].
        radius: f64,
        /// Lowest z [m].
        bottom: f64,
        /// Highest z [m].
        top: f64,
    },
}

impl ForceRegion {
    /// Whether the point `x` [m] lies inside (boundary included).
    pub fn contains(&self, x: DVec3) -> bool {
        match *self {
            Self::Box { min, max } => x.cmpge(min).all() && x.cmple(max).all(),
            Self::Cylinder {
                axis,
                radius,
                bottom,
                top,
            } => {
                let (dx, dy) = (x.x - axis[0], x.y - axis[1]);
                x.z >= bottom && x.z <= top && dx * dx + dy * dy <= radius * radius
            }
        }
    }

    /// Why the region is not a finite, non-empty one; `None` when it is.
    fn fault(&self) -> Option<String> {
        match *self {
            Self::Box { min, max } => {
                if !(min.is_finite() && max.is_finite()) {
                    Some(format!("box corners must be finite, got {min} and {max}"))
                } else if !max.cmpgt(min).all() {
                    Some(format!(
                        "box must have max > min on every axis, got {min} and {max}"
                    ))
                } else {
                    None
                }
            }
            Self::Cylinder {
                axis,
                radius,
                bottom,
                top,
            } => {
                if !(axis[0].is_finite() && axis[1].is_finite() && bottom.is_finite()) {
                    Some("cylinder axis and bottom must be finite".to_string())
                } else if !(radius > 0.0 && radius.is_finite()) {
                    Some(format!(
                        "cylinder radius must be > 0 and finite, got {radius}"
                    ))
                } else if !(top > bottom && top.is_finite()) {
                    Some(format!(
                        "cylinder top must be finite and above its bottom {bottom}, got {top}"
                    ))
                } else {
                    None
                }
            }
        }
    }
}

/// A force on every free particle whose centre lies in `region`: π r² `traction` [N] for a
/// particle of radius r [m].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RegionForce {
    /// Where it acts.
    pub region: ForceRegion,
    /// Force per unit of a particle's cross-section π r² [Pa = N/m²], a vector.
    pub traction: DVec3,
}

impl RegionForce {
    /// Why this force cannot be applied (a region that is not finite or is empty, a
    /// traction that is not finite); `None` when it can.
    pub fn fault(&self) -> Option<String> {
        if !self.traction.is_finite() {
            return Some(format!("traction must be finite, got {}", self.traction));
        }
        self.region.fault()
    }

    /// The force on a particle of radius `radius` [m] inside the region [N].
    pub fn force_on(&self, radius: f64) -> DVec3 {
        (std::f64::consts::PI * radius * radius) * self.traction
    }

    /// Adds the force to each free particle inside the region, in index order, a clump's
    /// members their shares of the grain's ([module docs](self)); returns how many it acted
    /// on.
    pub(crate) fn apply(&self, p: &mut ParticleSet, clumps: &ClumpSet) -> usize {
        let mut acted = 0;
        for k in 0..p.len() {
            if p.flags[k] & FLAG_FROZEN == 0 && self.region.contains(p.position[k]) {
                let force = self.force_on(p.radius[k]);
                p.force[k] += match p.clump[k] {
                    NO_CLUMP => force,
                    c => member_share(clumps.body(c as usize)) * force,
                };
                acted += 1;
            }
        }
        acted
    }
}

/// The part of its own cross-section's force that each member of `body` receives:
/// r_v²/Σ r_j², r_v the radius of the sphere of the body's volume, so that the members' forces
/// add up to the equal-volume sphere's [-].
pub(crate) fn member_share(body: &ClumpBody) -> f64 {
    let equal = (0.75 * body.volume / std::f64::consts::PI).cbrt();
    let squares: f64 = body.members.iter().map(|&(_, r)| r * r).sum();
    equal * equal / squares
}
