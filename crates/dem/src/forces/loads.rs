//! The loads on the walls: the total force and torque on each wall every step, and for
//! curved and meshed walls the force on each triangle or band, summed over a window for
//! pressure maps (docs/physics.md §5.5).
//!
//! The totals are summed in fixed point: each contact's share is rounded to a multiple of a
//! quantum far below any contact force (2⁻³² of the lightest particle's weight) and added
//! as an integer. Integer addition does not depend on its order, so the totals are the
//! same bits whether one thread walks the contacts or several threads each walk a range of
//! bodies, which floating-point sums would not be.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::contact::ContactForce;

/// Binary orders of magnitude between the lightest particle's weight and the force quantum.
const QUANTUM_BITS: i32 = 32;

/// The total load on one wall in one step.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct WallLoad {
    /// Force the particles exert on the wall [N].
    pub force: DVec3,
    /// Torque the particles exert on the wall about the origin [N m].
    pub torque: DVec3,
}

/// The force and torque quanta of the fixed-point sums and their inverses.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct LoadQuanta {
    /// Force quantum [N] and torque quantum [N m].
    quantum: (f64, f64),
    inverse: (f64, f64),
}

impl Default for LoadQuanta {
    fn default() -> Self {
        Self::new(1.0, 1.0)
    }
}

impl LoadQuanta {
    /// Quanta for particles whose lightest weight is `weight` [N] (the mass times the
    /// gravity, or times 1 m/s² without gravity) and smallest radius `radius` [m]: powers of
    /// two, so the scaling itself is exact.
    pub(crate) fn new(weight: f64, radius: f64) -> Self {
        let pow2 = |x: f64| {
            if x.is_finite() && x > 0.0 {
                2f64.powi(x.log2().floor() as i32)
            } else {
                1.0
            }
        };
        let force = pow2(weight) * 2f64.powi(-QUANTUM_BITS);
        let torque = force * pow2(radius);
        Self {
            quantum: (force, torque),
            inverse: (1.0 / force, 1.0 / torque),
        }
    }
}

/// A wall's load in fixed point: force then torque, in quanta.
pub(crate) type LoadSum = [i128; 6];

/// Adds to `sum` the load on a wall of the contact `cf` with the particle at `x` [m]:
/// force −F, torque about the origin −(x × F + M_i), the reaction of what the particle got.
#[inline(always)]
pub(crate) fn add_load(sum: &mut LoadSum, q: &LoadQuanta, x: DVec3, cf: &ContactForce) {
    let f = cf.force;
    let m = x.cross(f) + cf.torque_i;
    let (a, b) = q.inverse;
    // `as i64` rounds towards zero and saturates; contact loads stay far below 2⁶³ quanta.
    for (s, v) in sum
        .iter_mut()
        .zip([f.x * a, f.y * a, f.z * a, m.x * b, m.y * b, m.z * b])
    {
        *s -= (v as i64) as i128;
    }
}

/// The load a sum stands for.
pub(crate) fn load_of(sum: &LoadSum, q: &LoadQuanta) -> WallLoad {
    let (a, b) = q.quantum;
    WallLoad {
        force: DVec3::new(sum[0] as f64 * a, sum[1] as f64 * a, sum[2] as f64 * a),
        torque: DVec3::new(sum[3] as f64 * b, sum[4] as f64 * b, sum[5] as f64 * b),
    }
}

/// Adds sum `b` into `a`.
#[inline]
pub(crate) fn merge_loads(a: &mut [LoadSum], b: &[LoadSum]) {
    for (x, y) in a.iter_mut().zip(b) {
        for (u, v) in x.iter_mut().zip(y) {
            *u += v;
        }
    }
}

/// What one triangle of a mesh, or one band of a cylinder or cone, received over a window.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct ElementLoad {
    /// Time integral of the force the particles exert on the element [N s].
    pub impulse: DVec3,
    /// Time integral of its normal part, pressing on the surface (≥ 0) [N s].
    pub normal_impulse: f64,
    /// Time integral of the magnitude of its tangential part [N s].
    pub shear_impulse: f64,
}

/// The loads on the elements of one curved or meshed wall, summed since the window began.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct SurfaceLoads {
    /// Length of the window [s].
    pub duration: f64,
    /// One entry per triangle (a mesh) or band (a cylinder or cone, equal lengths along
    /// its axis from its base).
    pub elements: Vec<ElementLoad>,
}

impl SurfaceLoads {
    /// Books a contact's force `force` on the particle [N] with contact normal `normal`
    /// (wall to particle) to `element` over a step `dt` [s].
    #[inline]
    pub(crate) fn book(&mut self, element: usize, normal: DVec3, force: DVec3, dt: f64) {
        let on_wall = -force;
        let pressing = -on_wall.dot(normal);
        let shear = (on_wall + pressing * normal).length();
        if let Some(e) = self.elements.get_mut(element) {
            e.impulse += on_wall * dt;
            e.normal_impulse += pressing * dt;
            e.shear_impulse += shear * dt;
        }
    }
}
