//! The clumps of a simulation as rigid bodies: their state, and their part of each step
//! (docs/physics.md §11.4).
//!
//! A clump's members are ordinary particles of the particle set, flagged
//! [`FLAG_CLUMP_MEMBER`]: the neighbour search, the contact laws and the walls treat them as
//! spheres, and the particle integrator leaves them alone. Each member carries the clump's
//! mass, which its contact laws see as the body's (the mass of the whole grain, as in
//! LIGGGHTS' multisphere and EDEM), so its weight in the force array, m g, is taken out again
//! when the members' forces are summed on the body.
//!
//! A step moves a clump as velocity Verlet moves a sphere (§6.2), with §11.3's rotation:
//! 1. half kick: v += (Δt/2) F/m, L += (Δt/2) τ, with the force and torque of the last
//!    evaluation;
//! 2. drift: x += Δt v, and the free rotation of q by Δt;
//! 3. the members placed: x_k = x + q r_k, v_k = v + ω × (q r_k), ω_k = ω;
//! 4. after the evaluation, the members' contact forces c_k = f_k − m g summed in member
//!    order: F = M g + Σ c_k, τ = Σ (τ_k + (x_k − x) × c_k); then the second half kick and
//!    the members' velocities again.
//!
//! The sums run over each clump's members in their fixed order, whatever the particles'
//! order, so a clump's motion has the same bits at any thread count.

use glam::{DMat3, DQuat, DVec3};
use serde::{Deserialize, Serialize};

use super::rotation::{angular_velocity, free_rotation_scaled};
use super::{ClumpBody, ClumpShape};
use crate::particles::{retain_by_mask, ParticleSet, ParticleTag, NO_CLUMP};
use crate::ranges::even_bounds;
use crate::team::Team;

/// Every clump of a simulation: the shapes they are made of, and each one's state.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
pub struct ClumpSet {
    /// The shapes as bodies of their material: mass [kg], principal moments [kg m²] and
    /// members in the principal frame.
    pub(crate) shapes: Vec<ClumpBody>,
    /// Per clump: its shape.
    pub(crate) shape: Vec<u32>,
    /// Per clump: the tag of its first member; member k has tag `first_tag + k`.
    pub(crate) first_tag: Vec<ParticleTag>,
    /// Per clump: centre of mass [m].
    pub(crate) position: Vec<DVec3>,
    /// Per clump: velocity of the centre of mass [m/s].
    pub(crate) velocity: Vec<DVec3>,
    /// Per clump: orientation, principal frame to world frame.
    pub(crate) orientation: Vec<DQuat>,
    /// Per clump: angular momentum about the centre of mass, world frame [kg m²/s].
    pub(crate) momentum: Vec<DVec3>,
    /// Per clump: force of the last evaluation, weight included [N].
    pub(crate) force: Vec<DVec3>,
    /// Per clump: torque about the centre of mass of the last evaluation [N m].
    pub(crate) torque: Vec<DVec3>,
    /// The members' particle indices, clump after clump, each clump's in member order; found
    /// again whenever the particles' indices change ([`ClumpSet::find_members`]).
    #[serde(skip)]
    pub(crate) members: Vec<u32>,
    /// Where each clump's members start in `members` (one more entry than clumps).
    #[serde(skip)]
    pub(crate) starts: Vec<usize>,
    /// Each member's new place and motion, in the order of `members`, as the clumps' pass
    /// computes them before they are copied into the particle arrays.
    #[serde(skip)]
    placed: Vec<Placed>,
    /// The member lists and densities [kg/m³] already made into bodies, with the index of
    /// their body in `unit`: a fill adds thousands of clumps of one shape, and a body whose
    /// members overlap three at a time takes a line integral to make (§11.2).
    #[serde(skip)]
    made: Vec<(ClumpShape, u64, u32)>,
    /// The bodies of `made`, at the members' own size.
    #[serde(skip)]
    unit: Vec<ClumpBody>,
    /// For a body of `unit` and a scale factor (its bits), the index of the scaled body in
    /// `shapes`: a fill of a size distribution scales one shape to each grain's size.
    #[serde(skip)]
    sized: std::collections::HashMap<(u32, u64), u32>,
}

/// What a pass needs of a shape, formed once a pass: 1/M [1/kg], 1/I [1/(kg m²)] and
/// Δt/(2I) [s/(kg m²)] per principal axis.
#[derive(Debug, Clone, Copy)]
struct ShapeConstants {
    inv_mass: f64,
    inv_inertia: DVec3,
    scale: DVec3,
}

/// [`ShapeConstants`] of every shape for a step of `dt` [s].
fn constants(shapes: &[ClumpBody], dt: f64) -> Vec<ShapeConstants> {
    shapes
        .iter()
        .map(|b| ShapeConstants {
            inv_mass: 1.0 / b.mass,
            inv_inertia: 1.0 / b.principal_inertia,
            scale: dt / (2.0 * b.principal_inertia),
        })
        .collect()
}

/// A member's place [m], velocity [m/s] and angular velocity [rad/s].
#[derive(Debug, Clone, Copy, Default)]
struct Placed {
    position: DVec3,
    velocity: DVec3,
    omega: DVec3,
}

/// Clumps per thread, at least, before the clumps' pass is shared: a clump's part of a step
/// costs about 0.15 µs and a fork-join about 1.5 µs, so below some ten clumps a thread the
/// join costs more than it saves.
const MIN_CLUMPS: usize = 64;

/// `one` of each range on the `pool`'s threads where there are several, otherwise here.
fn on_clump_ranges<R: Send>(
    ranges: Vec<ClumpRange<'_>>,
    pool: Option<&Team>,
    one: impl Fn(ClumpRange<'_>) -> R + Sync + Send,
) -> Vec<R> {
    match pool {
        Some(pool) if ranges.len() > 1 => crate::timing::parallel_region(|| pool.map(ranges, one)),
        _ => ranges.into_iter().map(one).collect(),
    }
}

/// A contiguous range of clumps, with its slices of the clumps' arrays and of the members'
/// new places.
struct ClumpRange<'a> {
    /// Index of its first clump.
    first: usize,
    shapes: &'a [ClumpBody],
    members: &'a [u32],
    starts: &'a [usize],
    shape: &'a [u32],
    position: &'a mut [DVec3],
    velocity: &'a mut [DVec3],
    orientation: &'a mut [DQuat],
    momentum: &'a mut [DVec3],
    force: &'a mut [DVec3],
    torque: &'a mut [DVec3],
    placed: &'a mut [Placed],
}

impl ClumpRange<'_> {
    /// Steps 1–3 for the range's clumps, their members' places written to `placed`.
    fn kick_drift(
        &mut self,
        consts: &[ShapeConstants],
        reference: &[DVec3],
        (half, dt): (f64, f64),
    ) -> (f64, bool) {
        let (shapes, members) = (self.shapes, self.members);
        let mut worst = 0.0f64;
        let mut finite = true;
        let base = self.starts[self.first];
        for c in 0..self.shape.len() {
            let shape = self.shape[c] as usize;
            let (body, k) = (&shapes[shape], consts[shape]);
            let v = self.velocity[c] + (half * k.inv_mass) * self.force[c];
            let l = self.momentum[c] + half * self.torque[c];
            let x = self.position[c] + dt * v;
            let q = free_rotation_scaled(self.orientation[c], l, k.scale);
            (
                self.velocity[c],
                self.momentum[c],
                self.position[c],
                self.orientation[c],
            ) = (v, l, x, q);
            finite &= x.is_finite() && q.is_finite();
            // One rotation matrix for ω and every member (cheaper than a quaternion each).
            let turn = DMat3::from_quat(q);
            let w = turn * (turn.transpose() * l * k.inv_inertia);
            let slots = self.starts[self.first + c]..self.starts[self.first + c + 1];
            for (slot, &(offset, _)) in slots.zip(&body.members) {
                let arm = turn * offset;
                let at = x + arm;
                self.placed[slot - base] = Placed {
                    position: at,
                    velocity: v + w.cross(arm),
                    omega: w,
                };
                if let Some(r) = reference.get(members[slot] as usize) {
                    worst = worst.max((at - *r).length_squared());
                }
            }
        }
        (worst, finite)
    }

    /// Step 4 for the range's clumps, from the evaluation's forces in `p`, their members'
    /// motion written to `placed`.
    fn gather_kick(
        &mut self,
        consts: &[ShapeConstants],
        p: &ParticleSet,
        (gravity, half): (DVec3, f64),
    ) -> bool {
        let (shapes, members) = (self.shapes, self.members);
        let mut finite = true;
        let base = self.starts[self.first];
        for c in 0..self.shape.len() {
            let shape = self.shape[c] as usize;
            let (body, k) = (&shapes[shape], consts[shape]);
            let x = self.position[c];
            let (mut force, mut torque) = (DVec3::ZERO, DVec3::ZERO);
            let slots = self.starts[self.first + c]..self.starts[self.first + c + 1];
            for &m in &members[slots.clone()] {
                let m = m as usize;
                let contact = p.force[m] - p.mass[m] * gravity;
                force += contact;
                torque += p.torque[m] + (p.position[m] - x).cross(contact);
            }
            force += body.mass * gravity;
            let v = self.velocity[c] + (half * k.inv_mass) * force;
            let l = self.momentum[c] + half * torque;
            (
                self.velocity[c],
                self.momentum[c],
                self.force[c],
                self.torque[c],
            ) = (v, l, force, torque);
            finite &= v.is_finite() && l.is_finite();
            let turn = DMat3::from_quat(self.orientation[c]);
            let w = turn * (turn.transpose() * l * k.inv_inertia);
            for (slot, &(offset, _)) in slots.zip(&body.members) {
                let place = &mut self.placed[slot - base];
                place.velocity = v + w.cross(turn * offset);
                place.omega = w;
            }
        }
        finite
    }
}

impl ClumpSet {
    /// Number of clumps.
    pub fn len(&self) -> usize {
        self.shape.len()
    }

    /// True when there are none.
    pub fn is_empty(&self) -> bool {
        self.shape.is_empty()
    }

    /// Centres of mass [m].
    pub fn positions(&self) -> &[DVec3] {
        &self.position
    }

    /// Velocities of the centres of mass [m/s].
    pub fn velocities(&self) -> &[DVec3] {
        &self.velocity
    }

    /// The tag of each clump's first member (member k has tag `first + k`): the clump's
    /// name in outputs that count bodies.
    pub fn first_tags(&self) -> &[ParticleTag] {
        &self.first_tag
    }

    /// Orientations (principal frame to world frame).
    pub fn orientations(&self) -> &[DQuat] {
        &self.orientation
    }

    /// Angular momenta about the centres of mass, world frame [kg m²/s].
    pub fn angular_momenta(&self) -> &[DVec3] {
        &self.momentum
    }

    /// The body of clump `c`: mass, principal moments, members.
    pub fn body(&self, c: usize) -> &ClumpBody {
        &self.shapes[self.shape[c] as usize]
    }

    /// Angular velocity of clump `c` [rad/s], world frame.
    pub fn angular_velocity(&self, c: usize) -> DVec3 {
        let b = self.body(c);
        angular_velocity(self.orientation[c], self.momentum[c], b.principal_inertia)
    }

    /// The index in `shapes` of the body of `shape` at `density` [kg/m³] scaled by `scale`
    /// ([`ClumpBody::scaled`]): the body of the members made once for each shape and density,
    /// each scale of it once, and equal bodies shared.
    pub(crate) fn shape_index(&mut self, shape: &ClumpShape, density: f64, scale: f64) -> usize {
        let bits = density.to_bits();
        let unit = match self.made.iter().find(|(s, d, _)| *d == bits && s == shape) {
            Some(&(_, _, k)) => k,
            None => {
                self.unit.push(shape.body(density));
                let k = (self.unit.len() - 1) as u32;
                self.made.push((shape.clone(), bits, k));
                k
            }
        };
        if let Some(&k) = self.sized.get(&(unit, scale.to_bits())) {
            return k as usize;
        }
        let body = self.unit[unit as usize].scaled(scale);
        // After a resume the caches are empty while `shapes` holds the bodies made before.
        let k = match self.shapes.iter().position(|b| *b == body) {
            Some(k) => k,
            None => {
                self.shapes.push(body);
                self.shapes.len() - 1
            }
        };
        self.sized.insert((unit, scale.to_bits()), k as u32);
        k
    }

    /// Finds each clump's members among `p` by their tags (after a list build, a re-sort or
    /// a removal changed the indices).
    pub(crate) fn find_members(&mut self, p: &ParticleSet) {
        self.starts.clear();
        self.starts.push(0);
        for c in 0..self.len() {
            let count = self.body(c).members.len();
            self.starts.push(self.starts[c] + count);
        }
        self.members.clear();
        self.members
            .resize(*self.starts.last().unwrap_or(&0), u32::MAX);
        for (k, (&c, &tag)) in p.clump.iter().zip(&p.tag).enumerate() {
            if c != NO_CLUMP {
                let c = c as usize;
                let member = (tag - self.first_tag[c]) as usize;
                self.members[self.starts[c] + member] = k as u32;
            }
        }
    }

    /// Steps 1–3 of a clump's step (module documentation) with Δt/2 = `half` and Δt = `dt`
    /// [s]: kick, drift and turn every clump, then place its members in `p`. Returns the
    /// largest squared displacement of a member from `reference` [m²] and whether every new
    /// position was finite. With a `pool`, ranges of clumps run on its threads: each clump's
    /// arithmetic is its own and the reductions do not depend on the order they are merged
    /// in, so the result has the same bits on any number of threads.
    pub(crate) fn kick_drift(
        &mut self,
        p: &mut ParticleSet,
        reference: &[DVec3],
        step: (f64, f64),
        pool: Option<&Team>,
    ) -> (f64, bool) {
        let consts = constants(&self.shapes, step.1);
        let found = on_clump_ranges(self.ranges(pool), pool, |mut r| {
            r.kick_drift(&consts, reference, step)
        });
        self.scatter(p, true);
        found
            .into_iter()
            .fold((0.0, true), |(d, f), (d2, f2)| (d.max(d2), f && f2))
    }

    /// Step 4 (module documentation): the members' forces and torques of the evaluation in
    /// `p` summed on each clump with its weight (`gravity` g [m/s²]), the second half kick
    /// (Δt/2 = `half` [s]), and the members' velocities set from the kicked body. Returns
    /// whether every velocity is finite. With a `pool`, as [`ClumpSet::kick_drift`].
    pub(crate) fn gather_kick(
        &mut self,
        p: &mut ParticleSet,
        gravity: DVec3,
        half: f64,
        pool: Option<&Team>,
    ) -> bool {
        let particles = &*p;
        let consts = constants(&self.shapes, 2.0 * half);
        let found = on_clump_ranges(self.ranges(pool), pool, |mut r| {
            r.gather_kick(&consts, particles, (gravity, half))
        });
        self.scatter(p, false);
        found.into_iter().all(|f| f)
    }

    /// The members' new motion (and, with `positions`, their places) from `placed` into the
    /// particle arrays.
    fn scatter(&self, p: &mut ParticleSet, positions: bool) {
        for (&k, m) in self.members.iter().zip(&self.placed) {
            let k = k as usize;
            if positions {
                p.position[k] = m.position;
            }
            p.velocity[k] = m.velocity;
            p.omega[k] = m.omega;
        }
    }

    /// The clumps cut into contiguous ranges, one a thread of `pool` where there are enough
    /// of them to share, each with its slices of every per-clump array and of `placed`.
    fn ranges(&mut self, pool: Option<&Team>) -> Vec<ClumpRange<'_>> {
        let n = self.len();
        self.placed.resize(self.members.len(), Placed::default());
        let bounds = match pool {
            Some(pool) => even_bounds(n, pool.threads(), 1, MIN_CLUMPS),
            None => vec![0, n],
        };
        let mut out = Vec::with_capacity(bounds.len() - 1);
        let (mut shape, mut position, mut velocity) = (
            &self.shape[..],
            &mut self.position[..],
            &mut self.velocity[..],
        );
        let (mut orientation, mut momentum) = (&mut self.orientation[..], &mut self.momentum[..]);
        let (mut force, mut torque) = (&mut self.force[..], &mut self.torque[..]);
        let mut placed = &mut self.placed[..];
        for w in bounds.windows(2) {
            let len = w[1] - w[0];
            let slots = self.starts[w[1]] - self.starts[w[0]];
            let (a, rest) = shape.split_at(len);
            shape = rest;
            let (b, rest) = std::mem::take(&mut position).split_at_mut(len);
            position = rest;
            let (c, rest) = std::mem::take(&mut velocity).split_at_mut(len);
            velocity = rest;
            let (d, rest) = std::mem::take(&mut orientation).split_at_mut(len);
            orientation = rest;
            let (e, rest) = std::mem::take(&mut momentum).split_at_mut(len);
            momentum = rest;
            let (f, rest) = std::mem::take(&mut force).split_at_mut(len);
            force = rest;
            let (g, rest) = std::mem::take(&mut torque).split_at_mut(len);
            torque = rest;
            let (h, rest) = std::mem::take(&mut placed).split_at_mut(slots);
            placed = rest;
            out.push(ClumpRange {
                first: w[0],
                shapes: &self.shapes,
                members: &self.members,
                starts: &self.starts,
                shape: a,
                position: b,
                velocity: c,
                orientation: d,
                momentum: e,
                force: f,
                torque: g,
                placed: h,
            });
        }
        out
    }

    /// Drops the clumps for which `gone[c]` is true and renumbers the others' members in
    /// `clump_of` (the particles' clump indices, after the gone clumps' members were removed).
    pub(crate) fn drop_clumps(&mut self, gone: &[bool], clump_of: &mut [u32]) {
        let mut renumber = vec![NO_CLUMP; gone.len()];
        let mut next = 0u32;
        for (c, &g) in gone.iter().enumerate() {
            if !g {
                renumber[c] = next;
                next += 1;
            }
        }
        for c in clump_of.iter_mut() {
            if *c != NO_CLUMP {
                *c = renumber[*c as usize];
            }
        }
        let kept: Vec<bool> = gone.iter().map(|&g| !g).collect();
        retain_by_mask(&mut self.shape, &kept);
        retain_by_mask(&mut self.first_tag, &kept);
        retain_by_mask(&mut self.position, &kept);
        retain_by_mask(&mut self.velocity, &kept);
        retain_by_mask(&mut self.orientation, &kept);
        retain_by_mask(&mut self.momentum, &kept);
        retain_by_mask(&mut self.force, &kept);
        retain_by_mask(&mut self.torque, &kept);
    }
}
