//! The contacts of the current state, read-only: each particle–particle and particle–wall
//! contact with its force and contact point, for a caller that measures stresses
//! ([`crate::Watched::contacts`]).
//!
//! The engine does not keep per-contact forces: its force loops add each contact's force
//! to its two bodies and forget it. This module recomputes them on request, from the state
//! as it stands between steps, through the same laws as the step's one-contact path
//! ([`ContactLaws::resolve`] on `contact::geometry`'s spheres), with a copy of each
//! contact's history and a time step of zero, so that the history is not advanced again:
//!
//! - the tangential spring ξ stored after the step already holds the step's slip, so
//!   `resolve` with Δt = 0 gives the step's spring force −S_t ξ (and its Coulomb cap);
//! - the velocities are those the step's evaluation used, the half-step ones: as stored,
//!   where the view's second half kick is pending ([`crate::Simulation::run_watched`]);
//!   after a completed kick ([`crate::Simulation::watched`]), the stored full-step ones
//!   less that kick, v − (Δt/2) F/m and ω − (Δt/2) T/I (frozen and rotation-locked bodies
//!   as the kick treats them), equal to the step's to round-off.
//!
//! Nothing is written: the state, and so every later step, keeps its bits. The cost is one
//! pass of the scalar laws over the candidate lists (about the cost of one step's force
//! evaluation on one thread, unbatched), paid only when asked for.
//!
//! One adjustment: a contact that slid in the step has its spring truncated to the Coulomb
//! cap, S_t |ξ| = μ F_n, and the step dropped its tangential dashpot. Recomputed as stored,
//! S_t |ξ| lies on the cap to round-off, and the law's comparison with the cap could go
//! either way, adding back −γ_t v_t (in a collision's first step, many times the spring
//! force). So ξ is read stretched by [`SLIP_MARGIN`]: a sliding contact is then over the
//! cap, truncated to it again and given the step's force to a few ulps, and a sticking one's
//! spring force changes by 1e-12 of itself. With the half-step velocities, each body's
//! recomputed contacts sum to its force in the step to about 1e-12 of its largest contact
//! force (`crates/dem/tests/suite/watch.rs`).

use glam::DVec3;

use crate::contact::geometry::{sphere_sphere, sphere_wall, Sphere};
use crate::contact::{BodyMotion, ContactGeometry, ContactHistory, ContactLaws};
use crate::history::SurfaceContact;
use crate::material::PairCoefficients;
use crate::neighbour::{PairList, WallPairList};
use crate::particles::{ParticleSet, FLAG_HELD, FLAG_ROTATION_LOCKED};
use crate::wall::{MeshScratch, Wall, WallId};

/// One particle–particle contact carrying force.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairContact {
    /// Index of the first particle, i (in the view's order).
    pub i: usize,
    /// Index of the second particle, j.
    pub j: usize,
    /// Force on i [N]; the force on j is its negative.
    pub force: DVec3,
    /// The contact point, at lever R_i − δ/2 from i's centre along the line of centres [m].
    pub point: DVec3,
}

/// One particle–wall contact carrying force.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WallContact {
    /// Index of the particle (in the view's order).
    pub particle: usize,
    /// The wall.
    pub wall: WallId,
    /// Force on the particle [N]; the wall receives its negative.
    pub force: DVec3,
    /// The wall's closest point to the particle's centre [m].
    pub point: DVec3,
}

/// The contacts of one state.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Contacts {
    /// Particle–particle contacts, in candidate-list order.
    pub pairs: Vec<PairContact>,
    /// Particle–wall contacts, in candidate-list order.
    pub walls: Vec<WallContact>,
}

/// What the recomputation reads besides the particles and walls: the laws, the pair and
/// wall coefficients (by material pair), the candidate lists with their histories, and the
/// reach of cohesion beyond contact [m].
#[derive(Debug, Clone, Copy)]
pub(crate) struct ContactSource<'a> {
    pub laws: ContactLaws,
    pub pair_coeffs: &'a [PairCoefficients],
    pub wall_coeffs: &'a [PairCoefficients],
    pub materials: usize,
    pub pairs: &'a PairList,
    pub wall_pairs: &'a WallPairList,
    pub reach: f64,
    /// Δt/2 [s] where the step's second half kick has been done and must be taken off the
    /// stored velocities; `None` where it is pending (the stored ones are the step's).
    pub kicked: Option<f64>,
}

/// The factor the stored tangential spring ξ is read with, so that a contact that slid in
/// the step (its spring truncated to the Coulomb cap) is over the cap again, not on it to
/// round-off (see the module's notes): far above the few ulps of the truncation's
/// arithmetic, far below any physical difference.
pub const SLIP_MARGIN: f64 = 1.0 + 1e-12;

/// A stored history as the recomputation reads it: the spring stretched by [`SLIP_MARGIN`].
fn read(mut h: ContactHistory) -> ContactHistory {
    h.tangential *= SLIP_MARGIN;
    h
}

/// Body `k` as the contact geometry sees it.
fn sphere(p: &ParticleSet, k: usize) -> Sphere {
    Sphere {
        radius: p.radius[k],
        mass: p.mass[k],
        inertia: p.inertia[k],
    }
}

impl ContactSource<'_> {
    /// Body `k`'s velocities at the half step, those the step's evaluation used.
    fn motion(&self, p: &ParticleSet, k: usize) -> BodyMotion {
        let (mut velocity, mut omega) = (p.velocity[k], p.omega[k]);
        if let Some(half) = self.kicked {
            if p.flags[k] & FLAG_HELD == 0 {
                velocity -= (half * p.inv_mass[k]) * p.force[k];
                if p.flags[k] & FLAG_ROTATION_LOCKED == 0 {
                    omega -= (half * p.inv_inertia[k]) * p.torque[k];
                }
            }
        }
        BodyMotion { velocity, omega }
    }

    /// Recomputes every contact of `p` among themselves and with `walls` (see the module's
    /// notes). Candidates whose indices fall outside the particles are skipped, so a view
    /// never panics.
    pub(crate) fn contacts(&self, p: &ParticleSet, walls: &[Option<Wall>]) -> Contacts {
        let mut out = Contacts::default();
        let n = p.len();
        let m = self.materials;
        let coeff = |table: &[PairCoefficients], a: usize, b: usize| table.get(a * m + b).copied();
        let list = self.pairs;
        for k in 0..list.i.len().min(list.j.len()).min(list.history.len()) {
            let (i, j) = (list.i[k] as usize, list.j[k] as usize);
            if i >= n || j >= n {
                continue;
            }
            let mut h = read(list.history.get(k));
            let d = p.position[i] - p.position[j];
            let sum = p.radius[i] + p.radius[j];
            let dist2 = d.length_squared();
            if (dist2 >= sum * sum && !h.bonded) || dist2 == 0.0 {
                continue;
            }
            let Some(c) = coeff(
                self.pair_coeffs,
                p.material[i] as usize,
                p.material[j] as usize,
            ) else {
                continue;
            };
            let g = sphere_sphere(d, dist2, &sphere(p, i), &sphere(p, j));
            let cf = self
                .laws
                .resolve(&g, &self.motion(p, i), &self.motion(p, j), &c, &mut h, 0.0);
            if g.overlap <= 0.0 && !h.bonded {
                continue;
            }
            out.pairs.push(PairContact {
                i,
                j,
                force: cf.force,
                point: p.position[i] - g.arm_i * g.normal,
            });
        }
        let wl = self.wall_pairs;
        let mut scratch = MeshScratch::default();
        let mut found = Vec::new();
        for k in 0..wl.particle.len().min(wl.wall.len()).min(wl.history.len()) {
            let (i, w) = (wl.particle[k] as usize, wl.wall[k] as usize);
            let Some(Some(wall)) = walls.get(w) else {
                continue;
            };
            if i >= n {
                continue;
            }
            let Some(c) = coeff(self.wall_coeffs, w, p.material[i] as usize) else {
                continue;
            };
            let x = p.position[i];
            let r = p.radius[i];
            let id = WallId(w as u32);
            if wall.resolved_one_by_one() {
                // Curved, meshed and spinning walls: every place the sphere touches, each
                // with the remembered contact whose normal is nearest (the step's own).
                let remembered: &[SurfaceContact] =
                    wl.surfaces.get(k).map_or(&[], |s| &s.contacts[..]);
                let mut near = Default::default();
                found.clear();
                wall.surface_contacts((x, r + self.reach), 1, &mut near, &mut scratch, &mut found);
                for contact in &found {
                    let mut h = remembered
                        .iter()
                        .max_by(|a, b| {
                            a.normal
                                .dot(contact.normal)
                                .total_cmp(&b.normal.dot(contact.normal))
                        })
                        .filter(|s| s.normal.dot(contact.normal) >= 0.5)
                        .map_or(ContactHistory::default(), |s| read(s.history));
                    let g = sphere_wall(contact.normal, contact.distance, &sphere(p, i));
                    if g.overlap <= 0.0 && !h.bonded {
                        continue;
                    }
                    let bw = BodyMotion {
                        velocity: wall.velocity_at(contact.point),
                        omega: wall.angular_velocity,
                    };
                    let at = (i, id, contact.point);
                    out.walls
                        .extend(self.wall_contact(p, at, (&g, &bw, &c), &mut h));
                }
                continue;
            }
            let mut h = read(wl.history.get(k));
            let (cp, dist) = wall.closest_point(x);
            if dist >= r && !h.bonded {
                continue;
            }
            let g = sphere_wall(wall.contact_normal(x, cp, dist), dist, &sphere(p, i));
            let bw = BodyMotion {
                velocity: wall.velocity_at(x),
                omega: DVec3::ZERO,
            };
            out.walls
                .extend(self.wall_contact(p, (i, id, cp), (&g, &bw, &c), &mut h));
        }
        out
    }

    /// Particle `i`'s contact with wall `id` at `point` [m]: the laws for geometry `g`, the
    /// wall's motion `bw` and coefficients `c`, from history `h`; `None` where the sphere
    /// neither touches nor stays bonded after them.
    fn wall_contact(
        &self,
        p: &ParticleSet,
        (i, id, point): (usize, WallId, DVec3),
        (g, bw, c): (&ContactGeometry, &BodyMotion, &PairCoefficients),
        h: &mut ContactHistory,
    ) -> Option<WallContact> {
        let cf = self.laws.resolve(g, &self.motion(p, i), bw, c, h, 0.0);
        (g.overlap > 0.0 || h.bonded).then_some(WallContact {
            particle: i,
            wall: id,
            force: cf.force,
            point,
        })
    }
}
