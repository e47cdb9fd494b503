//! The paper's laws over particle–wall candidates: one run of equal wall at a time (the list
//! is wall-major), each wall's probe, velocity and coefficients looked up once per run.

use glam::DVec3;

use super::filter::{
    compact_touching, live_history, note_live, note_live_or_bonded, plane_touches, settle_bond,
};
use super::kernel::{Batch, BATCH};
use super::loads::{add_batch_loads, LoadSum};
use super::pairs::batch_force;
use super::{compact, gather, KernelInput, WorstOverlap};
use crate::contact::cohesion::{LAW_DRY, OUTCOME_APART};
use crate::contact::geometry::plane_distance;
use crate::contact::ContactForce;
use crate::wall::geometry::{ShapeVisitor, WallGeometry};
use crate::wall::Wall;

/// What the wall filter needs of one wall, flattened so that planes need no closest-point call.
#[derive(Debug, Clone, Copy)]
pub(super) enum WallProbe {
    /// The wall was removed.
    Absent,
    /// An infinite plane: signed distance x·n − offset [m], unit normal n towards the particles.
    Plane { normal: DVec3, offset: f64 },
    /// Any other shape the loop takes (a polygon): its closest-point test.
    ClosestPoint,
    /// A wall this loop leaves to the surface pass ([`Wall::resolved_one_by_one`]).
    Deferred,
}

/// The contact of a sphere at `x` with radius `r` [m] with wall `w`, if they overlap: the
/// normal from the wall to the sphere and the overlap δ [m]. A NaN distance counts as
/// touching (`!(≥)`), so that it reaches the NaN check.
#[inline(always)]
pub(super) fn wall_contact(
    input: &KernelInput,
    probe: &WallProbe,
    w: usize,
    x: DVec3,
    r: f64,
) -> Option<(DVec3, f64)> {
    match *probe {
        WallProbe::Plane { normal, offset } => {
            let s = plane_distance(x, normal, offset);
            (!(s >= r)).then_some((normal, r - s))
        }
        WallProbe::ClosestPoint => input.walls[w].as_ref()?.shape().visit(Touching { x, r }),
        WallProbe::Absent | WallProbe::Deferred => None,
    }
}

/// The normal from wall `w` (not a plane: [`WallProbe::ClosestPoint`]) to a sphere at `x` of
/// radius `r` [m] and their overlap δ [m], negative across a gap: a bonded contact's
/// geometry, touching or not.
#[inline(always)]
fn nearest(input: &KernelInput, w: usize, x: DVec3, r: f64) -> (DVec3, f64) {
    input.walls[w].as_ref().map_or((DVec3::ZERO, 0.0), |wall| {
        wall.shape().visit(Nearest { x, r })
    })
}

/// See [`nearest`].
struct Nearest {
    x: DVec3,
    r: f64,
}

impl ShapeVisitor<'_> for Nearest {
    type Output = (DVec3, f64);
    #[inline(always)]
    fn visit<S: WallGeometry>(self, shape: &S) -> (DVec3, f64) {
        let Self { x, r } = self;
        let (cp, dist) = shape.closest_point(x);
        (shape.contact_normal(x, cp, dist), r - dist)
    }
}

/// The contact of a sphere at `x` with radius `r` [m] with a shape whose closest point gives
/// its one contact ([`WallGeometry::needs_surface_pass`] false): the normal and the overlap,
/// if they overlap (NaN counts as touching, as in [`wall_contact`]).
struct Touching {
    x: DVec3,
    r: f64,
}

impl ShapeVisitor<'_> for Touching {
    type Output = Option<(DVec3, f64)>;
    #[inline(always)]
    fn visit<S: WallGeometry>(self, shape: &S) -> Option<(DVec3, f64)> {
        let Self { x, r } = self;
        let (cp, dist) = shape.closest_point(x);
        (!(dist >= r)).then(|| (shape.contact_normal(x, cp, dist), r - dist))
    }
}

/// The paper's laws for particle–wall candidates, one run of equal wall at a time (the list
/// is wall-major): the wall's probe, velocity and coefficients are looked up once per run,
/// planes are filtered with one dot product per candidate and no branch on the outcome, and
/// the touching candidates are resolved in batches.
///
/// Each particle still receives its wall forces in increasing wall order, as a
/// particle-major walk would give them, so the sums do not depend on the list's order.
#[inline(never)]
pub(super) fn batched_wall_loop(
    input: &KernelInput,
    (pi, pw): (&[u32], &[u32]),
    (history, live): (&mut [DVec3], &mut [u8]),
    (hits, touch, probes, batch): (&mut Vec<u32>, &mut Vec<u8>, &mut Vec<WallProbe>, &mut Batch),
    loads: &mut [LoadSum],
    mut sink: impl FnMut(usize, &ContactForce),
) -> (WorstOverlap, usize) {
    wall_probes(input.walls, probes);
    // Only grown, never cleared: the filters overwrite what they use, and refilling the whole
    // buffer every step would cost as much as the filter itself.
    if hits.len() < history.len() {
        hits.resize(history.len(), 0);
        touch.resize(history.len(), 0);
    }
    prepare_wall_batch(input, batch);
    let mut worst = WorstOverlap::default();
    let mut contacts = 0;
    for (w, run) in wall_runs(pw) {
        let len = run.len();
        let wall = WallRun {
            probe: probes[w as usize],
            index: w as usize,
            base: run.start,
        };
        contacts += wall_run(
            input,
            &wall,
            &pi[run.clone()],
            (&mut history[run.clone()], &mut live[run]),
            (&mut hits[..len], &mut touch[..len], batch),
            (&mut worst, &mut loads[w as usize]),
            &mut sink,
        );
    }
    (worst, contacts)
}

/// The runs of equal wall in a wall-major list of candidates' walls: each wall with the
/// index range of its candidates, in list order.
pub(super) fn wall_runs(pw: &[u32]) -> impl Iterator<Item = (u32, std::ops::Range<usize>)> + '_ {
    let mut start = 0;
    std::iter::from_fn(move || {
        let &w = pw.get(start)?;
        // The list is wall-major (`build_lists`, `Simulation::from_state`).
        let end = start + pw[start..].partition_point(|&x| x <= w);
        let run = start..end;
        start = end;
        Some((w, run))
    })
}

/// The filter's view of every wall, by wall index, into `probes`.
pub(super) fn wall_probes(walls: &[Option<Wall>], probes: &mut Vec<WallProbe>) {
    probes.clear();
    probes.extend(walls.iter().map(|w| match w {
        None => WallProbe::Absent,
        Some(w) if w.resolved_one_by_one() => WallProbe::Deferred,
        Some(w) => match w.shape().as_plane() {
            Some((normal, offset)) => WallProbe::Plane { normal, offset },
            None => WallProbe::ClosestPoint,
        },
    }));
}

/// Fills what every wall contact of a batch shares: the walls of this loop do not spin (a
/// spinning wall goes to the surface pass, §5.4), so ω_j = 0 in
/// every slot, and equal spheres share one radius and mass.
pub(super) fn prepare_wall_batch(input: &KernelInput, batch: &mut Batch) {
    for row in &mut batch.omega[1] {
        row.fill(0.0);
    }
    if let Some((r, m)) = input.uniform_body {
        batch.radius[0].fill(r);
        batch.mass[0].fill(m);
    }
}

/// One run of the wall-major candidate list: its wall and where it starts.
pub(super) struct WallRun {
    pub(super) probe: WallProbe,
    /// The wall's index.
    pub(super) index: usize,
    /// Index of the run's first candidate in the whole list.
    pub(super) base: usize,
}

/// The candidates of one wall whose particles lie in one body range.
pub(super) struct WallPiece<'a> {
    /// The wall's index.
    pub(super) wall: usize,
    /// Index of the piece's first candidate in the whole wall list.
    pub(super) base: usize,
    pub(super) particles: &'a [u32],
    /// Their ξ and live flags (`HistoryArrays`).
    pub(super) history: &'a mut [DVec3],
    pub(super) live: &'a mut [u8],
}

/// Filters and resolves the wall candidates of `pieces`, in their order, into `sink`, with
/// the filter buffers `hits` and `touch` (only grown, never cleared, as in
/// [`batched_wall_loop`]) and a batch that [`prepare_wall_batch`] has prepared.
pub(super) fn wall_pieces<'a>(
    input: &KernelInput,
    probes: &[WallProbe],
    pieces: impl IntoIterator<Item = WallPiece<'a>>,
    (hits, touch, batch): (&mut Vec<u32>, &mut Vec<u8>, &mut Batch),
    loads: &mut [LoadSum],
    sink: &mut impl FnMut(usize, &ContactForce),
) -> (WorstOverlap, usize) {
    let mut worst = WorstOverlap::default();
    let mut contacts = 0;
    for piece in pieces {
        let len = piece.particles.len();
        if hits.len() < len {
            hits.resize(len, 0);
            touch.resize(len, 0);
        }
        let run = WallRun {
            probe: probes[piece.wall],
            index: piece.wall,
            base: piece.base,
        };
        contacts += wall_run(
            input,
            &run,
            piece.particles,
            (piece.history, piece.live),
            (&mut hits[..len], &mut touch[..len], batch),
            (&mut worst, &mut loads[piece.wall]),
            sink,
        );
    }
    (worst, contacts)
}

/// [`compact_touching`], listing bonded candidates too where `bonds`.
#[inline(always)]
fn compact_listed(
    bonds: bool,
    touches: impl Iterator<Item = bool>,
    live: &mut [u8],
    hits: &mut [u32],
) -> usize {
    if bonds {
        compact_touching::<true>(touches, live, hits)
    } else {
        compact_touching::<false>(touches, live, hits)
    }
}

/// Filters and resolves the candidates `pi` of one wall; returns how many are contacts
/// (touching, or held by a bond).
#[inline(always)]
pub(super) fn wall_run(
    input: &KernelInput,
    wall: &WallRun,
    pi: &[u32],
    (history, live): (&mut [DVec3], &mut [u8]),
    (hits, touch, batch): (&mut [u32], &mut [u8], &mut Batch),
    (worst, load): (&mut WorstOverlap, &mut LoadSum),
    sink: &mut impl FnMut(usize, &ContactForce),
) -> usize {
    let p = input.particles;
    let n = p.len();
    let (pos, radius) = (&p.position[..n], &p.radius[..n]);
    // Pass 1: which candidates touch. A separated contact (or one with a removed wall)
    // forgets its history (§3.1): it loses its live flag. Where the wall's contacts may
    // bond, the bonded ones are listed too, however far apart.
    let bonds = input.wall_bonds;
    let count = match wall.probe {
        // `!(≥)` so that a NaN distance counts as touching and reaches the NaN check.
        WallProbe::Plane { normal, offset } => match input.uniform_body {
            Some((r, _)) => {
                let touch = &mut touch[..pi.len()];
                plane_touches(pos, pi, (normal, offset, r), touch);
                if bonds {
                    note_live_or_bonded(touch, live);
                } else {
                    note_live(touch, live);
                }
                compact::from_bytes(touch, hits)
            }
            None => {
                let touches = pi.iter().map(|&i| {
                    let i = i as usize;
                    !(plane_distance(pos[i], normal, offset) >= radius[i])
                });
                compact_listed(bonds, touches, live, hits)
            }
        },
        WallProbe::ClosestPoint => {
            let touches = pi.iter().map(|&i| {
                let i = i as usize;
                wall_contact(input, &wall.probe, wall.index, pos[i], radius[i]).is_some()
            });
            compact_listed(bonds, touches, live, hits)
        }
        WallProbe::Absent => {
            live.fill(0);
            return 0;
        }
        WallProbe::Deferred => return 0,
    };
    let hits = &hits[..count];

    // Pass 2: the touching ones, in batches. What the run shares is written once.
    let w = wall.index;
    let wall_velocity = input.walls[w].as_ref().map_or(DVec3::ZERO, |w| w.velocity);
    let uniform = (input.materials == 1).then(|| &input.wall_coeffs[w]);
    if let Some(c) = uniform {
        batch.fill_coefficients(c);
    }
    if bonds {
        if let Some(c) = uniform {
            batch.bond.fill(&input.bond_tables.wall[w], c.e_star);
        }
    }
    // Whether the wall's load is summed (`Wall::sums_load`).
    let sums_load = input.walls[w].as_ref().is_some_and(|w| w.sums_load);
    let plane = match wall.probe {
        WallProbe::Plane { normal, offset } => {
            for (row, v) in batch.d.iter_mut().zip(normal.to_array()) {
                row.fill(v);
            }
            Some((normal, offset))
        }
        _ => None,
    };
    let coefficients = uniform.is_none().then_some(w);
    // The centres of a batch's particles, for the torques on the wall.
    let mut centres = [[0.0; BATCH]; 3];
    // Listed candidates whose bond broke this step: not contacts.
    let mut apart = 0;
    for group in hits.chunks(BATCH) {
        let source = WallSource {
            input,
            velocity: wall_velocity,
            coefficients,
            pi,
            history,
            live,
        };
        // The plane's case apart, so that its loop carries no test of the wall's kind per
        // contact: the filter's expression, so the same overlap.
        match plane {
            Some((normal, offset)) => {
                // Equal spheres of one material by fours where the build allows: the batch
                // already holds their radius, mass and coefficients.
                let fours = match input.uniform_body {
                    Some((radius, _)) if coefficients.is_none() => {
                        gather::plane_motion(batch, group, &source, (normal, offset), radius)
                    }
                    _ => 0,
                };
                source.gather(group, fours, batch, |b, m, x, r| {
                    b.overlap[m] = r - plane_distance(x, normal, offset);
                })
            }
            None => source.gather(group, 0, batch, |b, m, x, r| {
                let (normal, overlap) = if bonds {
                    nearest(input, w, x, r)
                } else {
                    wall_contact(input, &wall.probe, w, x, r).unwrap_or_default()
                };
                for (a, v) in normal.to_array().into_iter().enumerate() {
                    b.d[a][m] = v;
                }
                b.overlap[m] = overlap;
            }),
        }
        batch.len = group.len();
        if bonds {
            batch.resolve_bonded_walls(input.dt);
        } else {
            batch.resolve_walls(input.dt);
        }
        if input.area_cohesion {
            super::area_cohesion::walls(
                batch,
                group.len(),
                (uniform, |m| {
                    let i = pi[group[m] as usize] as usize;
                    &input.wall_coeffs[w * input.materials + p.material[i] as usize]
                }),
            );
        }
        worst.see_batch(batch, group.iter().map(|&k| wall.base + k as usize));
        for (m, &k) in group.iter().enumerate() {
            let m = m & (BATCH - 1);
            let k = k as usize;
            history[k] = DVec3::new(batch.xi[0][m], batch.xi[1][m], batch.xi[2][m]);
            let i = pi[k] as usize;
            if sums_load {
                for (a, v) in pos[i].to_array().into_iter().enumerate() {
                    centres[a][m] = v;
                }
            }
            if bonds {
                // A broken bond's slot holds zero force (and adds nothing to the load).
                let kept = batch.bond.outcome[m] != OUTCOME_APART;
                live[k] = settle_bond(live[k], kept, batch.bond.law[m] != LAW_DRY);
                if !kept {
                    apart += 1;
                    continue;
                }
            }
            sink(i, &batch_force(batch, m));
        }
        if sums_load {
            add_batch_loads(load, &input.quanta, batch, &centres, group.len());
        }
    }
    count - apart
}

/// Where one wall run's gather reads: the bodies, the wall's velocity and coefficients, the
/// run's candidates `pi` and their ξ and live flags.
pub(super) struct WallSource<'a> {
    pub(super) input: &'a KernelInput<'a>,
    /// The wall's velocity [m/s].
    pub(super) velocity: DVec3,
    /// The wall's index, where the coefficients differ by particle material (none when the
    /// batch already holds the one material's).
    pub(super) coefficients: Option<usize>,
    pub(super) pi: &'a [u32],
    pub(super) history: &'a [DVec3],
    pub(super) live: &'a [u8],
}

impl WallSource<'_> {
    /// Copies the touching candidates `group` (indices into `pi`) into slots
    /// `0..group.len()` of `batch`, from slot `first` on (the ones before are filled);
    /// `geometry(batch, slot, x, r)` writes a contact's normal and overlap from the
    /// particle's position `x` [m] and radius `r` [m].
    #[inline(always)]
    pub(super) fn gather(
        &self,
        group: &[u32],
        first: usize,
        batch: &mut Batch,
        geometry: impl Fn(&mut Batch, usize, DVec3, f64),
    ) {
        let Self {
            input,
            velocity,
            coefficients,
            pi,
            history,
            live,
        } = *self;
        let p = input.particles;
        let n = p.len();
        let (pos, vel, omega) = (&p.position[..n], &p.velocity[..n], &p.omega[..n]);
        let (radius, mass, material) = (&p.radius[..n], &p.mass[..n], &p.material[..n]);
        for (m, &k) in group.iter().enumerate().skip(first) {
            let m = m & (BATCH - 1);
            let k = k as usize;
            let i = pi[k] as usize;
            let (x, r) = (pos[i], radius[i]);
            geometry(batch, m, x, r);
            let dv = vel[i] - velocity;
            let (wi, xi) = (omega[i], live_history(live[k], history[k]));
            for (a, (v, u, z)) in [(dv.x, wi.x, xi.x), (dv.y, wi.y, xi.y), (dv.z, wi.z, xi.z)]
                .into_iter()
                .enumerate()
            {
                batch.dv[a][m] = v;
                batch.omega[0][a][m] = u;
                batch.xi[a][m] = z;
            }
            if input.uniform_body.is_none() {
                batch.radius[0][m] = r;
                batch.mass[0][m] = mass[i];
            }
            if let Some(w) = coefficients {
                let pair = w * input.materials + material[i] as usize;
                let c = &input.wall_coeffs[pair];
                batch.coeff.set(m, c);
                if input.wall_bonds {
                    batch.bond.set(m, &input.bond_tables.wall[pair], c.e_star);
                }
            }
        }
    }
}
