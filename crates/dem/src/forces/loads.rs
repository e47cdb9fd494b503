//! The loads on the walls: the total force and torque on each wall every step, and for
//! curved and meshed walls the force on each triangle or band, summed over a window for
//! pressure maps (docs/physics.md §5.5).
//!
//! The totals are summed in fixed point: each contact's share is rounded to a multiple of a
//! quantum far below any contact force (2⁻³² of the lightest particle's weight) and added
//! as an integer. Integer addition does not depend on its order, so the totals are the
//! same bits whether one thread walks the contacts or several threads each walk a range of
//! bodies, which floating-point sums would not be.
//!
//! Range: one contact's share is clamped to ±2⁵⁰ quanta (2¹⁸ of the lightest weight for a
//! force), and a wall's sum holds ±2⁶³ quanta (2³¹ of the lightest weight): far above any
//! load a bed of spheres puts on a wall. The torque's quantum is the force's times a length
//! four times the particles' farthest distance from the origin at set-up, so that a
//! torque's share is in range wherever its force's is.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::kernel::{Batch, BATCH};
use crate::contact::ContactForce;

/// Binary orders of magnitude between the lightest particle's weight and the force quantum.
const QUANTUM_BITS: i32 = 32;

/// 1.5 · 2⁵²: added to a number of magnitude below 2⁵¹, it leaves that number rounded to an
/// integer in the low bits of the sum's mantissa, which the subtraction of its own bits
/// reads out as an integer: one addition in place of a conversion instruction and its
/// overflow checks.
const ROUNDING: f64 = 6_755_399_441_055_744.0;

/// Largest share of one contact in quanta, within the rounding trick's exact range.
const LARGEST_SHARE: f64 = (1u64 << 50) as f64;

/// The total load on one wall in one step.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct WallLoad {
    /// Force the particles exert on the wall [N].
    pub force: DVec3,
    /// Torque the particles exert on the wall about the origin [N m].
    pub torque: DVec3,
}

/// The force and torque quanta of the fixed-point sums and their inverses.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
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
    /// gravity, or times 1 m/s² without gravity) and whose farthest point from the origin is
    /// `reach` [m] away: powers of two, so the scaling itself is exact.
    pub(crate) fn new(weight: f64, reach: f64) -> Self {
        let pow2 = |x: f64| {
            if x.is_finite() && x > 0.0 {
                2f64.powi(x.log2().floor() as i32)
            } else {
                1.0
            }
        };
        let force = pow2(weight) * 2f64.powi(-QUANTUM_BITS);
        let torque = force * pow2(reach) * 8.0;
        Self {
            quantum: (force, torque),
            inverse: (1.0 / force, 1.0 / torque),
        }
    }
}

/// A wall's load in fixed point: force then torque, in quanta.
pub(crate) type LoadSum = [i64; 6];

/// Adds to `sum` the load on a wall of the contact `cf` with the particle at `x` [m]:
/// force −F, torque about the origin −(x × F + M_i), the reaction of what the particle got.
#[inline(always)]
pub(crate) fn add_load(sum: &mut LoadSum, q: &LoadQuanta, x: DVec3, cf: &ContactForce) {
    let share = shares(q, x.to_array(), cf.force.to_array(), cf.torque_i.to_array());
    for (s, v) in sum.iter_mut().zip(share) {
        *s = s.wrapping_sub(v);
    }
}

/// One contact's share in quanta, force F then torque x × F + M_i, for the particle at `x`
/// [m] receiving force `f` [N] and torque `t` [N m]: the particle's side, whose negative
/// the wall receives.
#[inline(always)]
fn shares(q: &LoadQuanta, x: [f64; 3], f: [f64; 3], t: [f64; 3]) -> [i64; 6] {
    let (a, b) = q.inverse;
    let moment = [
        x[1] * f[2] - f[1] * x[2] + t[0],
        x[2] * f[0] - f[2] * x[0] + t[1],
        x[0] * f[1] - f[0] * x[1] + t[2],
    ];
    [
        quanta(f[0] * a),
        quanta(f[1] * a),
        quanta(f[2] * a),
        quanta(moment[0] * b),
        quanta(moment[1] * b),
        quanta(moment[2] * b),
    ]
}

/// `v` rounded to the nearest integer (ties to even), clamped to ±[`LARGEST_SHARE`]; NaN
/// gives some integer (a NaN stops the run at the step's check anyway).
#[inline(always)]
fn quanta(v: f64) -> i64 {
    let v = v.clamp(-LARGEST_SHARE, LARGEST_SHARE);
    ((v + ROUNDING).to_bits() as i64).wrapping_sub(ROUNDING.to_bits() as i64)
}

/// [`add_load`] for the first `len` contacts of a resolved batch, whose particles' centres
/// are `centres` [m] (by axis, lane): the same integers, summed lane by lane in a loop the
/// compiler vectorises.
#[inline(always)]
pub(crate) fn add_batch_loads(
    sum: &mut LoadSum,
    q: &LoadQuanta,
    batch: &Batch,
    centres: &[[f64; BATCH]; 3],
    len: usize,
) {
    let (f, t, x) = (&batch.force, &batch.torque_i, centres);
    let lane = |a: &[[f64; BATCH]; 3], m: usize| [a[0][m], a[1][m], a[2][m]];
    let mut acc = [0i64; 6];
    for m in 0..len.min(BATCH) {
        let share = shares(q, lane(x, m), lane(f, m), lane(t, m));
        for (s, v) in acc.iter_mut().zip(share) {
            *s = s.wrapping_add(v);
        }
    }
    for (s, v) in sum.iter_mut().zip(acc) {
        *s = s.wrapping_sub(v);
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
            *u = u.wrapping_add(*v);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shares_round_to_the_nearest_quantum_and_sum_in_any_order() {
        // The rounding trick against the definition on integers and halves (ties to even),
        // and the clamp; then the same contacts summed in two orders give the same bits.
        for (v, q) in [
            (0.0, 0),
            (2.4, 2),
            (-2.6, -3),
            (2.5, 2),
            (3.5, 4),
            (-1e300, -(1 << 50)),
        ] {
            assert_eq!(quanta(v), q, "{v}");
        }
        let quanta = LoadQuanta::new(1e-4, 0.1);
        let contacts: Vec<(DVec3, ContactForce)> = (0..50)
            .map(|k| {
                let k = k as f64;
                let force = DVec3::new((k * 0.7).sin(), (k * 1.3).cos(), 1.0 + k) * 1e-3;
                let torque_i = DVec3::new(k, -k, 0.5) * 1e-7;
                let x = DVec3::new(0.01 * k, -0.02, 0.05);
                (
                    x,
                    ContactForce {
                        force,
                        torque_i,
                        torque_j: DVec3::ZERO,
                    },
                )
            })
            .collect();
        let mut forward = LoadSum::default();
        contacts
            .iter()
            .for_each(|(x, c)| add_load(&mut forward, &quanta, *x, c));
        let mut halves = [LoadSum::default(), LoadSum::default()];
        for (k, (x, c)) in contacts.iter().enumerate().rev() {
            add_load(&mut halves[k % 2], &quanta, *x, c);
        }
        let mut merged = halves[0];
        merge_loads(std::slice::from_mut(&mut merged), &halves[1..]);
        assert_eq!(merged, forward);
        // And the sum is the loads' total to within half a quantum per contact.
        let load = load_of(&forward, &quanta);
        let exact: DVec3 = contacts.iter().map(|(_, c)| -c.force).sum();
        let bound = 50.0 * quanta.quantum.0;
        assert!((load.force - exact).abs().max_element() <= bound);
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
