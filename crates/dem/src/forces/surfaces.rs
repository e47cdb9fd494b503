//! The contacts of curved and meshed walls, and of spinning walls (docs/physics.md
//! §5.2–5.4): after every other contact, each wall's candidates in list order, so the sums
//! are the same bits at any thread count. Under the paper's laws the contacts found are
//! resolved in batches (`surface_batch`); other laws resolve them one at a time through
//! `ContactLaws::resolve`, the textbook form the batches are tested against.
//!
//! A sphere may touch such a wall in several places (a mesh's fold); each contact keeps
//! its own history, carried from step to step by its normal: a contact takes the history
//! of the remembered contact whose normal is nearest to its own, if that one is within
//! [`SAME_CONTACT_COS`]. So a sphere sliding across the triangles of a flat or gently
//! curved mesh keeps its tangential spring from one triangle to the next.

use glam::DVec3;

use super::loads::{add_load, LoadQuanta, LoadSum, SurfaceLoads};
use super::{walls, KernelInput, WorstOverlap};
use crate::contact::geometry::{sphere_wall, Sphere};
use crate::contact::{BodyMotion, ContactHistory};
use crate::history::{SurfaceContact, SurfaceSlot};
use crate::wall::{MeshContact, MeshScratch, Wall};

/// Cosine of the largest angle between the normals of a remembered contact and a new one
/// that continue each other (60°). A sliding contact's normal turns by far less in one
/// step; two simultaneous contacts of a fold differ by more.
const SAME_CONTACT_COS: f64 = 0.5;

/// Working arrays of the pass, reused from step to step.
#[derive(Debug, Default)]
pub(crate) struct SurfaceScratch {
    pub(super) mesh: MeshScratch,
    pub(super) contacts: Vec<MeshContact>,
    pub(super) previous: Vec<SurfaceContact>,
    pub(super) taken: Vec<bool>,
    /// The batched path's contacts found and not yet resolved, and their batch.
    pub(super) pending: Vec<super::surface_batch::Pending>,
    pub(super) batch: Box<super::kernel::Batch>,
    /// The batched path's contacts whose bond broke, as (candidate, contact within the
    /// candidate's slot), in the order found: removed from the slots after the stretch.
    pub(super) broken: Vec<(u32, u32)>,
}

/// Where the pass writes: the bodies' forces and torques, each wall's load in fixed point,
/// and the element loads of each curved or meshed wall (by wall index; empty where none).
pub(crate) struct SurfaceSinks<'a> {
    pub force: &'a mut [DVec3],
    pub torque: &'a mut [DVec3],
    pub loads: &'a mut [LoadSum],
    pub quanta: &'a LoadQuanta,
    pub elements: &'a mut [SurfaceLoads],
}

/// Resolves the candidates of the walls that [`Wall::resolved_one_by_one`] names whose
/// particles lie in `bodies`, from the wall-major list (`pi`, `pw`), with their remembered
/// contacts `slots` (index-aligned with the list); returns the worst overlap and the number
/// of contacts. Each wall's particles are visited in increasing index order, whether the
/// bodies come whole or chunk by chunk, so every sum sees its additions in the same order.
pub(crate) fn surface_pass(
    input: &KernelInput,
    (pi, pw): (&[u32], &[u32]),
    bodies: std::ops::Range<usize>,
    slots: &mut [SurfaceSlot],
    scratch: &mut SurfaceScratch,
    sinks: &mut SurfaceSinks,
) -> (WorstOverlap, usize) {
    let mut worst = WorstOverlap::default();
    let mut count = 0;
    for (w, run) in walls::wall_runs(pw) {
        let w = w as usize;
        let Some(wall) = input.walls[w].as_ref().filter(|w| w.resolved_one_by_one()) else {
            continue;
        };
        let mut sum = LoadSum::default();
        let bands = sinks.elements.get(w).map_or(1, |e| e.elements.len().max(1));
        // The run's particles are in increasing order: those in `bodies` are one stretch.
        let ids = &pi[run.clone()];
        let from = run.start + ids.partition_point(|&i| (i as usize) < bodies.start);
        let to = run.start + ids.partition_point(|&i| (i as usize) < bodies.end);
        let mut elements = sinks.elements.get_mut(w);
        let stretch = Stretch {
            wall,
            index: w,
            bands,
            ids: &pi[from..to],
            first: from,
            slots: &mut slots[from..to],
        };
        let mut target = StretchSinks {
            force: sinks.force,
            torque: sinks.torque,
            offset: 0,
            sum: &mut sum,
            quanta: sinks.quanta,
        };
        count += resolve_stretch(
            input,
            stretch,
            &mut target,
            scratch,
            &mut worst,
            &mut |triangle, normal, force| {
                if let Some(loads) = elements.as_deref_mut() {
                    loads.book(triangle as usize, normal, force, input.dt);
                }
            },
        );
        super::loads::merge_loads(&mut sinks.loads[w..=w], &[sum]);
    }
    (worst, count)
}

/// One wall's candidates whose particles lie in one body range: the wall, its index and
/// element count (triangles or bands), the candidates' particles (increasing), the list
/// index of the first, and their remembered contacts (index-aligned with `ids`).
pub(super) struct Stretch<'a> {
    pub wall: &'a Wall,
    pub index: usize,
    pub bands: usize,
    pub ids: &'a [u32],
    pub first: usize,
    pub slots: &'a mut [SurfaceSlot],
}

/// Where a stretch's contacts go: the forces and torques of bodies `offset..` (indexed by
/// particle − `offset`) and the wall's fixed-point load.
pub(super) struct StretchSinks<'a> {
    pub force: &'a mut [DVec3],
    pub torque: &'a mut [DVec3],
    pub offset: usize,
    pub sum: &'a mut LoadSum,
    pub quanta: &'a LoadQuanta,
}

/// Resolves the candidates of `stretch` in order into `sinks`; `book` receives each
/// contact's element, normal and force on the particle, in the same order. Returns the
/// number of contacts. The paper's laws go through the batches of `surface_batch`; the
/// forces agree with the one-at-a-time path to a few ulps, and each particle receives its
/// contacts in the same order on both.
pub(super) fn resolve_stretch(
    input: &KernelInput,
    stretch: Stretch,
    sinks: &mut StretchSinks,
    scratch: &mut SurfaceScratch,
    worst: &mut WorstOverlap,
    book: &mut impl FnMut(u32, DVec3, DVec3),
) -> usize {
    if input.batched() {
        return super::surface_batch::resolve_batched(input, stretch, sinks, scratch, worst, book);
    }
    resolve_one_by_one(input, stretch, sinks, scratch, worst, book)
}

/// [`resolve_stretch`] through `ContactLaws::resolve`, one contact at a time: any laws.
pub(super) fn resolve_one_by_one(
    input: &KernelInput,
    stretch: Stretch,
    sinks: &mut StretchSinks,
    scratch: &mut SurfaceScratch,
    worst: &mut WorstOverlap,
    book: &mut impl FnMut(u32, DVec3, DVec3),
) -> usize {
    let Stretch {
        wall,
        index: w,
        bands,
        ids,
        first,
        slots,
    } = stretch;
    let mut count = 0;
    for (offset, (&i, slot)) in ids.iter().zip(slots.iter_mut()).enumerate() {
        let i = i as usize;
        let local = i - sinks.offset;
        let target = Target {
            force: &mut sinks.force[local],
            torque: &mut sinks.torque[local],
            sum: sinks.sum,
            quanta: sinks.quanta,
        };
        count += resolve_candidate(
            input,
            (wall, w, bands),
            (i, first + offset),
            slot,
            scratch,
            target,
            worst,
            &mut *book,
        );
    }
    count
}

/// Where one candidate's contacts go: its particle's force and torque, and its wall's
/// fixed-point load.
struct Target<'a> {
    pub force: &'a mut DVec3,
    pub torque: &'a mut DVec3,
    pub sum: &'a mut LoadSum,
    pub quanta: &'a LoadQuanta,
}

/// Resolves candidate `k` (particle `i`) of wall `w`: finds where the sphere touches the
/// wall, continues each contact's history from `slot` by its normal, and adds each force to
/// `target`; `book` receives each contact's element (triangle or band), normal and force on
/// the particle. Returns the number of contacts.
#[allow(clippy::too_many_arguments)]
fn resolve_candidate(
    input: &KernelInput,
    (wall, w, bands): (&Wall, usize, usize),
    (i, k): (usize, usize),
    slot: &mut SurfaceSlot,
    scratch: &mut SurfaceScratch,
    target: Target,
    worst: &mut WorstOverlap,
    mut book: impl FnMut(u32, DVec3, DVec3),
) -> usize {
    let p = input.particles;
    let (x, r) = (p.position[i], p.radius[i]);
    // With cohesion, the places within its reach of the surface: a bonded contact may act
    // across a gap (docs/physics.md §2.4, §2.6).
    touching(
        wall,
        (x, r + input.reach),
        bands,
        slot,
        (&mut scratch.mesh, &mut scratch.contacts),
    );
    let slot = &mut slot.contacts;
    if scratch.contacts.is_empty() {
        slot.clear();
        return 0;
    }
    remember(slot, &mut scratch.previous, &mut scratch.taken);
    let sphere = Sphere {
        radius: r,
        mass: p.mass[i],
        inertia: p.inertia[i],
    };
    let c = &input.wall_coeffs[w * input.materials + p.material[i] as usize];
    let bi = BodyMotion {
        velocity: p.velocity[i],
        omega: p.omega[i],
    };
    let mut count = 0;
    for contact in &scratch.contacts {
        let g = sphere_wall(contact.normal, contact.distance, &sphere);
        let mut h = continued(contact.normal, &scratch.previous, &mut scratch.taken);
        if g.overlap <= 0.0 && !h.bonded {
            // Within the cohesion's reach but never touched: no bond.
            continue;
        }
        worst.see(g.overlap / r, k);
        let bw = BodyMotion {
            velocity: wall.velocity_at(contact.point),
            omega: wall.angular_velocity,
        };
        let cf = input.laws.resolve(&g, &bi, &bw, c, &mut h, input.dt);
        if g.overlap <= 0.0 && !h.bonded {
            // The bond broke this step.
            continue;
        }
        count += 1;
        *target.force += cf.force;
        *target.torque += cf.torque_i;
        add_load(target.sum, target.quanta, x, &cf);
        book(contact.triangle, contact.normal, cf.force);
        slot.push(SurfaceContact {
            normal: contact.normal,
            history: h,
        });
    }
    count
}

/// The contacts of a sphere at `x` with radius `r` [m] with `wall`, into
/// `scratch.contacts`, each with its element: for a frustum its band, of `bands` equal
/// lengths along the axis; for a mesh its triangle, the triangles near the sphere looked up
/// in the mesh's index only when it has left the margin about where `slot` last found them
/// ([`Wall::surface_contacts`]).
#[inline]
pub(super) fn touching(
    wall: &Wall,
    sphere: (DVec3, f64),
    bands: usize,
    slot: &mut SurfaceSlot,
    (mesh, out): (&mut MeshScratch, &mut Vec<MeshContact>),
) {
    wall.surface_contacts(sphere, bands, &mut slot.near, mesh, out);
}

/// Moves a candidate's remembered contacts `slot` into `previous`, none of them `taken`
/// yet, leaving `slot` empty for this step's contacts: what [`continued`] matches against.
pub(super) fn remember(
    slot: &mut Vec<SurfaceContact>,
    previous: &mut Vec<SurfaceContact>,
    taken: &mut Vec<bool>,
) {
    previous.clear();
    previous.extend_from_slice(slot);
    taken.clear();
    taken.resize(previous.len(), false);
    slot.clear();
}

/// The history a contact of normal `normal` continues: that of the nearest remembered
/// contact not yet taken, if within [`SAME_CONTACT_COS`]; otherwise none.
pub(super) fn continued(
    normal: DVec3,
    previous: &[SurfaceContact],
    taken: &mut [bool],
) -> ContactHistory {
    let best = previous
        .iter()
        .enumerate()
        .filter(|(m, _)| !taken[*m])
        .map(|(m, c)| (m, c.normal.dot(normal)))
        .filter(|&(_, cos)| cos >= SAME_CONTACT_COS)
        .max_by(|a, b| a.1.total_cmp(&b.1));
    match best {
        Some((m, _)) => {
            taken[m] = true;
            previous[m].history
        }
        None => ContactHistory::default(),
    }
}
