//! Force evaluation: the contact kernel over candidate pairs, then accumulation in pair
//! order, so that sums are bit-identical at any thread count.
//!
//! One thread (this file): each contact force is added to its two bodies as soon as it is
//! computed. Several threads (`parallel`): each range of bodies, in one parallel pass,
//! resolves its own pairs, again the pairs that reach into it from earlier ranges, and its
//! wall contacts. Both paths run the same kernel and give every body the same sequence of
//! floating-point additions (gravity, pairs in list order, walls in list order).

use glam::{BVec3, DVec3};

use crate::contact::batch::{coefficient_row, Batch, BATCH};
use crate::contact::{BodyMotion, ContactForce, ContactGeometry, ContactHistory, ContactLaws};
use crate::history::{settle, LIVE, WAS_LIVE};
use crate::material::{harmonic, PairCoefficients};
use crate::neighbour::{PairList, WallPairList};
use crate::particles::ParticleSet;
use crate::wall::{Wall, WallShape};

mod chunked;
mod compact;
mod gather;
mod parallel;

pub(crate) use chunked::{chunk_bounds, evaluate_chunk};

/// Read-only inputs of the kernel.
pub(crate) struct KernelInput<'a> {
    pub particles: &'a ParticleSet,
    pub laws: &'a ContactLaws,
    pub pair_coeffs: &'a [PairCoefficients],
    pub materials: usize,
    pub walls: &'a [Option<Wall>],
    pub wall_coeffs: &'a [PairCoefficients],
    /// Radius [m] and mass [kg] of every particle, when all are alike (the batch is then
    /// filled with them once instead of per contact).
    pub uniform_body: Option<(f64, f64)>,
    pub dt: f64,
}

/// The largest overlap seen, as a fraction of the smaller radius, and where.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct WorstOverlap {
    pub fraction: f64,
    /// Index into the pair list (or wall pair list).
    pub index: usize,
}

impl WorstOverlap {
    #[inline]
    fn see(&mut self, fraction: f64, index: usize) {
        if fraction > self.fraction {
            *self = Self { fraction, index };
        }
    }

    /// Sees every contact of a resolved batch; `index` gives their list indices in order.
    ///
    /// The batch maximum is a branch-free reduction; the contacts are walked one by one only
    /// when it beats the worst so far, which after the first batches is rare.
    #[inline(always)]
    fn see_batch(&mut self, batch: &Batch, index: impl Iterator<Item = usize>) {
        let fractions = &batch.overlap_fraction[..batch.len.min(BATCH)];
        // The largest fraction's bits, sign cleared, as an integer maximum, which vectorises
        // (a float fold is a chain of dependent compares). For numbers ≥ 0 the integers
        // order as the numbers; a negative number or a NaN (whose bits exceed every
        // number's) can only cause a walk, and the walk below decides as before.
        let largest = fractions
            .iter()
            .fold(0u64, |a, &b| a.max(b.to_bits() & !(1 << 63)));
        if !(f64::from_bits(largest) <= self.fraction) {
            for (&f, k) in fractions.iter().zip(index) {
                self.see(f, k);
            }
        }
    }

    /// Deterministic merge: larger fraction wins, ties go to the lower index.
    fn merge(self, other: Self) -> Self {
        if other.fraction > self.fraction
            || (other.fraction == self.fraction && other.index < self.index)
        {
            other
        } else {
            self
        }
    }
}

/// Scratch of one pass of the pair and wall loops, reused from step to step.
#[derive(Debug, Default)]
struct KernelScratch {
    /// Indices (into the slice being filtered) of the touching pair candidates, in order.
    touching: Vec<u32>,
    /// The batch the contacts are resolved in.
    batch: Box<Batch>,
}

/// Reusable buffers.
#[derive(Debug, Default)]
pub(crate) struct ForceBuffers {
    /// Scratch of the one-thread pass.
    kernel: KernelScratch,
    /// Indices of the touching wall candidates.
    wall_hits: Vec<u32>,
    /// Whether each wall candidate touches (1) or not (0), for the split plane filter.
    wall_touch: Vec<u8>,
    wall_probes: Vec<WallProbe>,
    /// Scratch of the body ranges (several threads only).
    ranges: Vec<parallel::RangeScratch>,
    /// Forces [N] the contacts are added to: during a step's evaluation, the particles'
    /// own array (holding the weights the integrator wrote), lent by swapping and swapped
    /// back after.
    pub force: Vec<DVec3>,
    /// Torques [N m], lent the same way.
    pub torque: Vec<DVec3>,
}

/// Counts of contacts that carried force in the last evaluation.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct ContactCount {
    /// Particle–particle contacts.
    pub particle_particle: usize,
    /// Particle–wall contacts.
    pub particle_wall: usize,
}

/// What one evaluation found.
#[derive(Default)]
pub(crate) struct Evaluation {
    pub count: ContactCount,
    pub worst_pair: WorstOverlap,
    pub worst_wall: WorstOverlap,
}

/// Adds pair forces to the bodies in pair order, the one summation both evaluation paths share.
///
/// Each share is added to its body at once, i's as j's: every body receives its contacts
/// one by one, in pair-list order, onto gravity. (From the third to the twelfth session,
/// i's run of pairs was summed in registers and added once when the run ended. Runs are
/// about one contact long, so that saved almost no memory traffic, and keeping the run
/// branch-free cost twelve selects per contact: the plain additions are about 6 % faster
/// per step, docs/performance-log.md, thirteenth session.)
struct Accumulator<'a> {
    force: &'a mut [DVec3],
    torque: &'a mut [DVec3],
    /// Contacts added.
    contacts: usize,
}

impl<'a> Accumulator<'a> {
    fn new(force: &'a mut [DVec3], torque: &'a mut [DVec3]) -> Self {
        Self {
            force,
            torque,
            contacts: 0,
        }
    }

    /// j's share first: i ≠ j, so the order within a contact changes no sum, and a body
    /// that is j of this contact is often i of the next, whose load of its sums then
    /// waits less on this store (about 1 % of a step on the AMD host: the pair loop's
    /// share of a profile 31.4 % against 30.5 %, twenty-ninth session).
    #[inline(always)]
    fn add(&mut self, i: usize, j: usize, cf: &ContactForce) {
        self.contacts += 1;
        self.add_j(j, cf);
        self.add_i(i, cf);
    }

    /// Body i's share: F on i, and M_i.
    #[inline(always)]
    fn add_i(&mut self, i: usize, cf: &ContactForce) {
        self.force[i] += cf.force;
        self.torque[i] += cf.torque_i;
    }

    /// Body j's share: −F (Newton's third law), and M_j.
    #[inline(always)]
    fn add_j(&mut self, j: usize, cf: &ContactForce) {
        self.force[j] -= cf.force;
        self.torque[j] += cf.torque_j;
    }
}

/// Sets `buffers` to the starting values of an evaluation: each body's weight m g [N]
/// (gravity `g` [m/s²]) and zero torque. The step does not call it: its integrator pass
/// writes the same products.
#[cfg(test)]
pub(crate) fn start(p: &ParticleSet, g: DVec3, buffers: &mut ForceBuffers) {
    buffers.force.clear();
    buffers.force.extend(p.mass.iter().map(|&m| m * g));
    buffers.torque.clear();
    buffers.torque.resize(p.len(), DVec3::ZERO);
}

/// Where the pair loops hand each contact's force, in pair order. A trait rather than a
/// closure so that the call is always inlined into the loop.
trait PairSink {
    fn contact(&mut self, i: usize, j: usize, cf: &ContactForce);
    /// Asks for body `j`'s sums to be brought into the cache ahead of its contact.
    #[inline(always)]
    fn prefetch(&self, _j: usize) {}
}

impl PairSink for Accumulator<'_> {
    #[inline(always)]
    fn contact(&mut self, i: usize, j: usize, cf: &ContactForce) {
        self.add(i, j, cf);
    }
    #[inline(always)]
    fn prefetch(&self, j: usize) {
        prefetch(&self.force[j]);
        prefetch(&self.torque[j]);
    }
}

/// Bodies beyond which the pair loops ask for the partner bodies' cache lines ahead of
/// use. Below it (the paper's hopper) the body arrays, about 120 bytes a body, stay in the
/// caches and the hints would only cost instructions. Above it a partner can lie far
/// behind in memory (the next layer of a 3D packing, 10^4 bodies on for 10^6 spheres): the
/// hints took the scaling benchmark's 10^6 spheres from about 73 to 70 ns per
/// particle-step, and left the hopper unchanged (twenty-third session).
const PREFETCH_BODIES: usize = 1 << 15;

/// Candidates ahead of the one being filtered whose partner's position is asked for.
const PREFETCH_AHEAD: usize = 32;

/// Asks for the cache line holding `x`; no effect on results.
#[inline(always)]
fn prefetch<T>(x: &T) {
    #[cfg(all(target_arch = "x86_64", target_feature = "sse"))]
    safe_arch::prefetch_t0(x);
    #[cfg(not(all(target_arch = "x86_64", target_feature = "sse")))]
    let _ = x;
}

/// Evaluates all contacts, updating histories, and adds their forces and torques to
/// `buffers.force` and `buffers.torque`, which must hold each body's starting values on
/// entry: its weight m g and zero torque ([`start`], or the integrator's pass, which writes
/// them while its cache lines are at hand).
pub(crate) fn evaluate(
    input: &KernelInput,
    pairs: &mut PairList,
    wall_pairs: &mut WallPairList,
    buffers: &mut ForceBuffers,
    pool: Option<&rayon::ThreadPool>,
) -> Evaluation {
    let n = input.particles.len();
    assert!(
        buffers.force.len() == n && buffers.torque.len() == n,
        "the force buffers hold one starting value per body"
    );
    if let Some(pool) = pool {
        return parallel::evaluate(input, pairs, wall_pairs, buffers, pool);
    }
    let mut count = ContactCount::default();
    let ids = (&pairs.i[..], &pairs.j[..]);

    let scratch = &mut buffers.kernel;
    let mut acc = Accumulator::new(&mut buffers.force, &mut buffers.torque);
    let worst_pair = pair_loop(
        input,
        ids,
        0,
        pairs.history.parts_mut(),
        (&mut scratch.touching, &mut scratch.batch),
        &mut acc,
    );
    count.particle_particle = acc.contacts;

    // Walls after pairs: each particle receives its wall forces in increasing wall order.
    // The sink holds the slices themselves, not references to the vectors, so that the
    // wall loop (not inlined) need not reload their addresses at every contact.
    let (force, torque) = (&mut buffers.force[..], &mut buffers.torque[..]);
    let sink = move |i: usize, cf: &ContactForce| {
        force[i] += cf.force;
        torque[i] += cf.torque_i;
    };
    let wall_ids = (&wall_pairs.particle[..], &wall_pairs.wall[..]);
    let (worst_wall, wall_contacts) = if *input.laws == ContactLaws::default() {
        let (tangential, _, live) = wall_pairs.history.parts_mut();
        batched_wall_loop(
            input,
            wall_ids,
            (tangential, live),
            (
                &mut buffers.wall_hits,
                &mut buffers.wall_touch,
                &mut buffers.wall_probes,
                &mut buffers.kernel.batch,
            ),
            sink,
        )
    } else {
        wall_loop(input, wall_ids, wall_pairs.history.split_mut(), sink)
    };
    count.particle_wall = wall_contacts;
    Evaluation {
        count,
        worst_pair,
        worst_wall,
    }
}

/// Runs the kernel over pairs `base..base + history.len()`, calling `sink(i, j, force)` for
/// each pair in contact, in order. `history` is ξ, the rolling history and the live flags
/// (`HistoryArrays`) of those pairs.
///
/// The paper's laws (the default) get their own copy of the loop in which the law choices are
/// constants, so the compiler drops the branches and code of the other laws.
#[inline(always)]
fn pair_loop(
    input: &KernelInput,
    ids: (&[u32], &[u32]),
    base: usize,
    (tangential, rolling, live): (&mut [DVec3], &mut [DVec3], &mut [u8]),
    scratch: (&mut Vec<u32>, &mut Batch),
    sink: &mut impl PairSink,
) -> WorstOverlap {
    if *input.laws == ContactLaws::default() {
        // The paper's laws keep no rolling history: only ξ is passed.
        batched_pair_loop(input, ids, base, (tangential, live), scratch, sink)
    } else {
        // The scalar laws clear separated histories themselves, from arrays that hold them.
        settle(tangential, rolling, live);
        pair_loop_with(input, *input.laws, ids, base, (tangential, rolling), sink)
    }
}

/// The coefficients every contact shares when there is one material, in [`Batch::coeff`] order.
fn uniform_coefficients(c: &[PairCoefficients], materials: usize) -> Option<[f64; 6]> {
    (materials == 1).then(|| coefficient_row(&c[0]))
}

/// The result of slot `m` of a resolved batch.
#[inline(always)]
fn batch_force(batch: &Batch, m: usize) -> ContactForce {
    let v = |a: &[[f64; BATCH]; 3]| DVec3::new(a[0][m], a[1][m], a[2][m]);
    ContactForce {
        force: v(&batch.force),
        torque_i: v(&batch.torque_i),
        torque_j: v(&batch.torque_j),
    }
}

/// The paper's laws over structure-of-arrays batches, in two passes.
///
/// 1. A branch-free filter lists the touching candidates and marks which are live (physics.md
///    §3.1: a contact that opens forgets its ξ; `HistoryArrays` explains the flags). About
///    half the candidates are not touching, and a branch on it is mispredicted about as often.
/// 2. The touching pairs are gathered [`BATCH`] at a time (ξ, or zero for a contact that was
///    not live), resolved together, and handed to `sink` in pair order.
#[inline(always)]
fn batched_pair_loop(
    input: &KernelInput,
    (pi, pj): (&[u32], &[u32]),
    base: usize,
    (history, live): (&mut [DVec3], &mut [u8]),
    (touching, batch): (&mut Vec<u32>, &mut Batch),
    sink: &mut impl PairSink,
) -> WorstOverlap {
    let p = input.particles;
    // One common length lets the compiler check an index once for all the arrays.
    let n = p.len();
    let (pos, vel, omega) = (&p.position[..n], &p.velocity[..n], &p.omega[..n]);
    let (radius, mass, material) = (&p.radius[..n], &p.mass[..n], &p.material[..n]);
    let len = history.len();
    let (pi, pj) = (&pi[base..base + len], &pj[base..base + len]);

    let live = &mut live[..len];
    let count = filter_touching(
        p,
        (pi, pj),
        live,
        touching,
        input.uniform_body.map(|(r, _)| r),
    );
    let touching = &touching[..count];

    let uniform = uniform_coefficients(input.pair_coeffs, input.materials);
    if let Some(c) = uniform {
        batch.fill_coefficients(c);
    }
    if let Some((r, m)) = input.uniform_body {
        batch.radius[0].fill(r);
        batch.radius[1].fill(r);
        batch.mass[0].fill(m);
        batch.mass[1].fill(m);
    }
    let mut worst = WorstOverlap::default();
    let far = n > PREFETCH_BODIES;
    for (g, group) in touching.chunks(BATCH).enumerate() {
        if far {
            // The next batch's partners, far from their first bodies in memory: asked for
            // a whole batch (kernel and scatter included) before their gather.
            let next = touching.get((g + 1) * BATCH..).unwrap_or_default();
            for &k in next.iter().take(BATCH) {
                let j = pj[k as usize] as usize;
                prefetch(&pos[j]);
                prefetch(&vel[j]);
                prefetch(&omega[j]);
                sink.prefetch(j);
            }
        }
        let state = gather::PairState {
            position: pos,
            velocity: vel,
            omega,
            pi,
            pj,
            history,
            live,
        };
        gather::pair_motion(batch, group, &state);
        // Radii, masses and coefficients, where the contacts do not share them. (An `if`
        // around the loop instead of the `take` timed 1.4 % slower, A/B 0.986: layout.)
        let shared = input.uniform_body.is_some() && uniform.is_some();
        for (m, &k) in group
            .iter()
            .enumerate()
            .take(if shared { 0 } else { BATCH })
        {
            // `m < BATCH` already; the mask tells the compiler so.
            let m = m & (BATCH - 1);
            let k = k as usize;
            let (i, j) = (pi[k] as usize, pj[k] as usize);
            if input.uniform_body.is_none() {
                batch.radius[0][m] = radius[i];
                batch.radius[1][m] = radius[j];
                batch.mass[0][m] = mass[i];
                batch.mass[1][m] = mass[j];
            }
            if uniform.is_none() {
                let c = &input.pair_coeffs
                    [material[i] as usize * input.materials + material[j] as usize];
                for (a, v) in coefficient_row(c).into_iter().enumerate() {
                    batch.coeff[a][m] = v;
                }
            }
        }
        batch.len = group.len();
        match input.uniform_body {
            Some((r, m)) => batch.resolve_pairs_uniform(input.dt, r, m),
            None => batch.resolve_pairs(input.dt),
        }
        worst.see_batch(batch, group.iter().map(|&k| base + k as usize));
        for (m, &k) in group.iter().enumerate() {
            let m = m & (BATCH - 1);
            let k = k as usize;
            history[k] = DVec3::new(batch.xi[0][m], batch.xi[1][m], batch.xi[2][m]);
            sink.contact(pi[k] as usize, pj[k] as usize, &batch_force(batch, m));
        }
    }
    worst
}

/// Lists (in `touching[..count]`, count returned) the candidates of `pi`/`pj` whose spheres
/// overlap, without a branch on the outcome, and marks the others' histories as not live
/// (see [`note_live`]).
#[inline(never)]
fn filter_touching(
    p: &ParticleSet,
    ids: (&[u32], &[u32]),
    live: &mut [u8],
    touching: &mut Vec<u32>,
    uniform_radius: Option<f64>,
) -> usize {
    let radius = &p.radius[..p.len()];
    match uniform_radius {
        // Equal spheres: the contact distance is a constant, and (r + r)² is the same number
        // as the general branch computes for every pair.
        Some(r) => {
            let cut2 = (r + r) * (r + r);
            filter_touching_with(p, ids, live, touching, (Some(cut2), |_, _| cut2))
        }
        None => filter_touching_with(
            p,
            ids,
            live,
            touching,
            (None, |i, j| {
                let sum = radius[i] + radius[j];
                sum * sum
            }),
        ),
    }
}

/// [`filter_touching`] with `cut2(i, j)` the squared contact distance (R_i + R_j)² [m²],
/// and that distance alone where every pair shares it (equal spheres).
#[inline(always)]
fn filter_touching_with(
    p: &ParticleSet,
    (pi, pj): (&[u32], &[u32]),
    live: &mut [u8],
    touching: &mut Vec<u32>,
    (shared, cut2): (Option<f64>, impl Fn(usize, usize) -> f64),
) -> usize {
    let pos = &p.position[..p.len()];
    // Only grown, never cleared: see `batched_wall_loop`.
    if touching.len() < live.len() {
        touching.resize(live.len(), 0);
    }
    let len = live.len();
    // Three loops, as the plane filter: the flags, with no count carried from one candidate
    // to the next; the live flags, over bytes; then the listing, in place (`compact`).
    let flags = &mut touching[..len];
    if pos.len() > PREFETCH_BODIES {
        pair_flags::<true>(pos, (pi, pj), flags, &cut2);
    } else {
        // Equal spheres by fours where the build allows, the rest one at a time.
        let done = shared.map_or(0, |c| gather::pair_flags(pos, (pi, pj), flags, c));
        let rest = (&pi[done..], &pj[done..]);
        pair_flags::<false>(pos, rest, &mut flags[done..], &cut2);
    }
    note_live(flags, live);
    compact::in_place(flags)
}

/// Pass 1 of the pair filter: `flags[k]` is 1 when candidate k's spheres overlap, with
/// `cut2(i, j)` the squared contact distance [m²]. With `FAR` (bodies beyond the caches,
/// [`PREFETCH_BODIES`]) it also asks for the position of the partner
/// [`PREFETCH_AHEAD`] candidates on, a hint that changes no result.
#[inline(always)]
fn pair_flags<const FAR: bool>(
    pos: &[DVec3],
    (pi, pj): (&[u32], &[u32]),
    flags: &mut [u32],
    cut2: &impl Fn(usize, usize) -> f64,
) {
    for (k, (f, (&i, &j))) in flags.iter_mut().zip(pi.iter().zip(pj)).enumerate() {
        if FAR {
            if let Some(&ahead) = pj.get(k + PREFETCH_AHEAD) {
                prefetch(&pos[ahead as usize]);
            }
        }
        let (i, j) = (i as usize, j as usize);
        // `!(≥)` so that a NaN distance counts as touching and reaches the NaN check.
        *f = u32::from(!((pos[i] - pos[j]).length_squared() >= cut2(i, j)));
    }
}

/// Lists in `hits` (count returned) the indices of the candidates for which `touches` yields
/// true, in order, and records in `live` which contacts keep their history (physics.md §3.1:
/// a contact that opens forgets it; see [`note_live`]). Branch-free: every index is stored
/// and the count advances only for a touching one, because a branch on the outcome is
/// mispredicted about as often as taken.
#[inline(always)]
fn compact_touching(
    touches: impl Iterator<Item = bool>,
    live: &mut [u8],
    hits: &mut [u32],
) -> usize {
    let len = live.len();
    let mut count = 0;
    for (k, (touch, l)) in touches.zip(live.iter_mut()).enumerate() {
        hits[count.min(len - 1)] = k as u32;
        count += touch as usize;
        *l = live_flags(u8::from(touch), *l);
    }
    count
}

/// The live flags of a contact after a filter that found it touching (`touch` = 1) or not
/// (0), from its flags before: [`LIVE`] becomes `touch`, and [`WAS_LIVE`] keeps the old
/// [`LIVE`] for the gather. A contact that does not touch forgets its history (§3.1) by
/// losing [`LIVE`]; its ξ is not rewritten.
#[inline(always)]
fn live_flags(touch: u8, old: u8) -> u8 {
    touch | ((old & LIVE) << 1)
}

/// ξ of a touching contact as the laws see it: the stored one if it was live before this
/// step's filter, zero if it had opened since it was stored (§3.1). A select, not a branch.
#[inline(always)]
fn live_history(flags: u8, xi: DVec3) -> DVec3 {
    DVec3::select(BVec3::splat(flags & WAS_LIVE != 0), xi, DVec3::ZERO)
}

/// Pass 1 of the plane filter for equal spheres of radius `r` [m]: `touch[k]` is 1 when
/// candidate `pi[k]` reaches the plane x·n = offset, 0 otherwise; a NaN distance counts as
/// touching (`!(≥)`), so that it reaches the NaN check.
///
/// Apart from compaction, so that it vectorises: with no count to carry from one candidate
/// to the next, the compiler evaluates eight distances at once. The slab faces have every
/// particle as a candidate, in index order, so their runs read the positions as one
/// contiguous stream with no index lookup.
#[inline(always)]
fn plane_touches(
    pos: &[DVec3],
    pi: &[u32],
    (normal, offset, r): (DVec3, f64, f64),
    touch: &mut [u8],
) {
    let Some(&first) = pi.first() else { return };
    // Exact test (not a short-circuit, so that it too vectorises): is `pi` first, first + 1, …?
    let contiguous = pi
        .iter()
        .zip(first..)
        .fold(true, |all, (&i, k)| all & (i == k));
    let flag = |x: DVec3| u8::from(!(plane_distance(x, normal, offset) >= r));
    if contiguous {
        let run = &pos[first as usize..first as usize + pi.len()];
        for (t, &x) in touch.iter_mut().zip(run) {
            *t = flag(x);
        }
    } else {
        for (t, &i) in touch.iter_mut().zip(pi) {
            *t = flag(pos[i as usize]);
        }
    }
}

/// Pass 2 of the plane and pair filters: the live flags after `touch` ([`live_flags`]); a
/// contact that opens forgets its history (physics.md §3.1) by losing [`LIVE`], one byte per
/// candidate instead of rewriting ξ. Vectorised: no count. The flags are bytes for the plane
/// filter and 32-bit words for the pair filter, whose compaction then overwrites them in
/// place.
#[inline(always)]
fn note_live<T: Copy + Into<u32>>(touch: &[T], live: &mut [u8]) {
    for (l, &t) in live.iter_mut().zip(touch) {
        // A flag is 0 or 1, so the narrowing keeps it.
        *l = live_flags(t.into() as u8, *l);
    }
}

/// What the wall filter needs of one wall, flattened so that planes need no closest-point call.
#[derive(Debug, Clone, Copy)]
enum WallProbe {
    /// The wall was removed.
    Absent,
    /// An infinite plane: signed distance x·n − offset [m], unit normal n towards the particles.
    Plane { normal: DVec3, offset: f64 },
    /// A polygon: the general closest-point test.
    Polygon,
}

/// The contact of a sphere at `x` with radius `r` [m] with wall `w`, if they overlap: the
/// normal from the wall to the sphere and the overlap δ [m]. A NaN distance counts as
/// touching (`!(≥)`), so that it reaches the NaN check.
#[inline(always)]
fn wall_contact(
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
        WallProbe::Polygon => {
            // Only polygons present in the simulation get this probe.
            let wall = input.walls[w].as_ref().expect("probe of a present wall");
            let (cp, dist) = wall.closest_point(x);
            (!(dist >= r)).then(|| (wall.contact_normal(x, cp, dist), r - dist))
        }
        WallProbe::Absent => None,
    }
}

/// The paper's laws for particle–wall candidates, one run of equal wall at a time (the list
/// is wall-major): the wall's probe, velocity and coefficients are looked up once per run,
/// planes are filtered with one dot product per candidate and no branch on the outcome, and
/// the touching candidates are resolved in batches.
///
/// Each particle still receives its wall forces in increasing wall order, the order of the
/// particle-major list this replaced, so the sums are unchanged.
#[inline(never)]
fn batched_wall_loop(
    input: &KernelInput,
    (pi, pw): (&[u32], &[u32]),
    (history, live): (&mut [DVec3], &mut [u8]),
    (hits, touch, probes, batch): (&mut Vec<u32>, &mut Vec<u8>, &mut Vec<WallProbe>, &mut Batch),
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
            &mut worst,
            &mut sink,
        );
    }
    (worst, contacts)
}

/// The runs of equal wall in a wall-major list of candidates' walls: each wall with the
/// index range of its candidates, in list order.
fn wall_runs(pw: &[u32]) -> impl Iterator<Item = (u32, std::ops::Range<usize>)> + '_ {
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
fn wall_probes(walls: &[Option<Wall>], probes: &mut Vec<WallProbe>) {
    probes.clear();
    probes.extend(walls.iter().map(|w| match w {
        None => WallProbe::Absent,
        Some(w) => match w.shape() {
            WallShape::Plane { point, normal } => WallProbe::Plane {
                normal: *normal,
                offset: point.dot(*normal),
            },
            WallShape::Polygon { .. } => WallProbe::Polygon,
        },
    }));
}

/// Fills what every wall contact of a batch shares: a wall does not spin (§5), so ω_j = 0 in
/// every slot, and equal spheres share one radius and mass.
fn prepare_wall_batch(input: &KernelInput, batch: &mut Batch) {
    for row in &mut batch.omega[1] {
        row.fill(0.0);
    }
    if let Some((r, m)) = input.uniform_body {
        batch.radius[0].fill(r);
        batch.mass[0].fill(m);
    }
}

/// One run of the wall-major candidate list: its wall and where it starts.
struct WallRun {
    probe: WallProbe,
    /// The wall's index.
    index: usize,
    /// Index of the run's first candidate in the whole list.
    base: usize,
}

/// Signed distance x·n − offset [m] of a point from a plane.
#[inline(always)]
fn plane_distance(x: DVec3, normal: DVec3, offset: f64) -> f64 {
    x.dot(normal) - offset
}

/// The candidates of one wall whose particles lie in one body range.
struct WallPiece<'a> {
    /// The wall's index.
    wall: usize,
    /// Index of the piece's first candidate in the whole wall list.
    base: usize,
    particles: &'a [u32],
    /// Their ξ and live flags (`HistoryArrays`).
    history: &'a mut [DVec3],
    live: &'a mut [u8],
}

/// Filters and resolves the wall candidates of `pieces`, in their order, into `sink`, with
/// the filter buffers `hits` and `touch` (only grown, never cleared, as in
/// [`batched_wall_loop`]) and a batch that [`prepare_wall_batch`] has prepared.
fn wall_pieces<'a>(
    input: &KernelInput,
    probes: &[WallProbe],
    pieces: impl IntoIterator<Item = WallPiece<'a>>,
    (hits, touch, batch): (&mut Vec<u32>, &mut Vec<u8>, &mut Batch),
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
            &mut worst,
            sink,
        );
    }
    (worst, contacts)
}

/// Filters and resolves the candidates `pi` of one wall; returns how many touch.
#[inline(always)]
fn wall_run(
    input: &KernelInput,
    wall: &WallRun,
    pi: &[u32],
    (history, live): (&mut [DVec3], &mut [u8]),
    (hits, touch, batch): (&mut [u32], &mut [u8], &mut Batch),
    worst: &mut WorstOverlap,
    sink: &mut impl FnMut(usize, &ContactForce),
) -> usize {
    let p = input.particles;
    let n = p.len();
    let (pos, radius) = (&p.position[..n], &p.radius[..n]);
    // Pass 1: which candidates touch. A separated contact (or one with a removed wall)
    // forgets its history (§3.1): it loses its live flag.
    let count = match wall.probe {
        // `!(≥)` so that a NaN distance counts as touching and reaches the NaN check.
        WallProbe::Plane { normal, offset } => match input.uniform_body {
            Some((r, _)) => {
                let touch = &mut touch[..pi.len()];
                plane_touches(pos, pi, (normal, offset, r), touch);
                note_live(touch, live);
                compact::from_bytes(touch, hits)
            }
            None => {
                let touches = pi.iter().map(|&i| {
                    let i = i as usize;
                    !(plane_distance(pos[i], normal, offset) >= radius[i])
                });
                compact_touching(touches, live, hits)
            }
        },
        WallProbe::Polygon => {
            let touches = pi.iter().map(|&i| {
                let i = i as usize;
                wall_contact(input, &wall.probe, wall.index, pos[i], radius[i]).is_some()
            });
            compact_touching(touches, live, hits)
        }
        WallProbe::Absent => {
            live.fill(0);
            return 0;
        }
    };
    let hits = &hits[..count];

    // Pass 2: the touching ones, in batches. What the run shares is written once.
    let w = wall.index;
    let wall_velocity = input.walls[w].as_ref().map_or(DVec3::ZERO, |w| w.velocity);
    let uniform = (input.materials == 1).then(|| coefficient_row(&input.wall_coeffs[w]));
    if let Some(c) = uniform {
        batch.fill_coefficients(c);
    }
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
                let (normal, overlap) =
                    wall_contact(input, &wall.probe, w, x, r).unwrap_or_default();
                for (a, v) in normal.to_array().into_iter().enumerate() {
                    b.d[a][m] = v;
                }
                b.overlap[m] = overlap;
            }),
        }
        batch.len = group.len();
        batch.resolve_walls(input.dt);
        worst.see_batch(batch, group.iter().map(|&k| wall.base + k as usize));
        for (m, &k) in group.iter().enumerate() {
            let m = m & (BATCH - 1);
            let k = k as usize;
            history[k] = DVec3::new(batch.xi[0][m], batch.xi[1][m], batch.xi[2][m]);
            sink(pi[k] as usize, &batch_force(batch, m));
        }
    }
    count
}

/// Where one wall run's gather reads: the bodies, the wall's velocity and coefficients, the
/// run's candidates `pi` and their ξ and live flags.
struct WallSource<'a> {
    input: &'a KernelInput<'a>,
    /// The wall's velocity [m/s].
    velocity: DVec3,
    /// The wall's index, where the coefficients differ by particle material (none when the
    /// batch already holds the one material's).
    coefficients: Option<usize>,
    pi: &'a [u32],
    history: &'a [DVec3],
    live: &'a [u8],
}

impl WallSource<'_> {
    /// Copies the touching candidates `group` (indices into `pi`) into slots
    /// `0..group.len()` of `batch`, from slot `first` on (the ones before are filled);
    /// `geometry(batch, slot, x, r)` writes a contact's normal and overlap from the
    /// particle's position `x` [m] and radius `r` [m].
    #[inline(always)]
    fn gather(
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
                let c = &input.wall_coeffs[w * input.materials + material[i] as usize];
                for (a, v) in coefficient_row(c).into_iter().enumerate() {
                    batch.coeff[a][m] = v;
                }
            }
        }
    }
}

#[inline(always)]
fn pair_loop_with(
    input: &KernelInput,
    laws: ContactLaws,
    (pi, pj): (&[u32], &[u32]),
    base: usize,
    (tangential, rolling): (&mut [DVec3], &mut [DVec3]),
    sink: &mut impl PairSink,
) -> WorstOverlap {
    let p = input.particles;
    let mut worst = WorstOverlap::default();
    let pi = &pi[base..base + tangential.len()];
    let pj = &pj[base..base + tangential.len()];
    let history = tangential.iter_mut().zip(rolling.iter_mut());
    for (k, ((&i, &j), (t, r))) in pi.iter().zip(pj).zip(history).enumerate() {
        let (i, j) = (i as usize, j as usize);
        let d = p.position[i] - p.position[j];
        let (ri, rj) = (p.radius[i], p.radius[j]);
        let sum = ri + rj;
        let dist2 = d.length_squared();
        if dist2 >= sum * sum {
            // Separated: the contact forgets its history (physics.md §3.1).
            (*t, *r) = (DVec3::ZERO, DVec3::ZERO);
            continue;
        }
        let dist = dist2.sqrt();
        let overlap = sum - dist;
        worst.see(overlap / ri.min(rj), base + k);
        let (mi, mj) = (p.mass[i], p.mass[j]);
        let g = ContactGeometry {
            normal: d * (1.0 / dist),
            overlap,
            // harmonic(ri, rj), reusing the sum.
            r_eff: ri * rj / sum,
            m_eff: harmonic(mi, mj),
            arm_i: ri - 0.5 * overlap,
            arm_j: rj - 0.5 * overlap,
            inertia: [p.inertia[i], p.inertia[j]],
            mass_radius2: [mi * ri * ri, mj * rj * rj],
        };
        let c =
            &input.pair_coeffs[p.material[i] as usize * input.materials + p.material[j] as usize];
        let bi = BodyMotion {
            velocity: p.velocity[i],
            omega: p.omega[i],
        };
        let bj = BodyMotion {
            velocity: p.velocity[j],
            omega: p.omega[j],
        };
        let mut h = ContactHistory {
            tangential: *t,
            rolling: *r,
        };
        let cf = laws.resolve(&g, &bi, &bj, c, &mut h, input.dt);
        (*t, *r) = (h.tangential, h.rolling);
        sink.contact(i, j, &cf);
    }
    worst
}

/// Runs the kernel over the particle–wall candidates, calling `sink(i, force)` per contact;
/// returns the largest overlap and the number of contacts.
#[inline(always)]
fn wall_loop(
    input: &KernelInput,
    (pi, pw): (&[u32], &[u32]),
    (tangential, rolling): (&mut [DVec3], &mut [DVec3]),
    mut sink: impl FnMut(usize, &ContactForce),
) -> (WorstOverlap, usize) {
    let p = input.particles;
    let mut worst = WorstOverlap::default();
    let mut contacts = 0;
    let history = tangential.iter_mut().zip(rolling.iter_mut());
    for (k, ((&i, &w), (t, r))) in pi.iter().zip(pw).zip(history).enumerate() {
        let (i, w) = (i as usize, w as usize);
        let Some(wall) = &input.walls[w] else {
            (*t, *r) = (DVec3::ZERO, DVec3::ZERO);
            continue;
        };
        let x = p.position[i];
        let ri = p.radius[i];
        let (cp, dist) = wall.closest_point(x);
        if dist >= ri {
            (*t, *r) = (DVec3::ZERO, DVec3::ZERO);
            continue;
        }
        let overlap = ri - dist;
        worst.see(overlap / ri, k);
        // A wall has infinite radius and mass: R* = R_i, m* = m_i (physics.md §5).
        let g = ContactGeometry {
            normal: wall.contact_normal(x, cp, dist),
            overlap,
            r_eff: ri,
            m_eff: p.mass[i],
            arm_i: ri - 0.5 * overlap,
            arm_j: 0.0,
            inertia: [p.inertia[i], f64::INFINITY],
            mass_radius2: [p.mass[i] * ri * ri, f64::INFINITY],
        };
        let c = &input.wall_coeffs[w * input.materials + p.material[i] as usize];
        let bi = BodyMotion {
            velocity: p.velocity[i],
            omega: p.omega[i],
        };
        let bw = BodyMotion {
            velocity: wall.velocity,
            omega: DVec3::ZERO,
        };
        let mut h = ContactHistory {
            tangential: *t,
            rolling: *r,
        };
        let cf = input.laws.resolve(&g, &bi, &bw, c, &mut h, input.dt);
        (*t, *r) = (h.tangential, h.rolling);
        sink(i, &cf);
        contacts += 1;
    }
    (worst, contacts)
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::history::HistoryArrays;
    use crate::material::{Interaction, Material, WallMaterial};
    use crate::neighbour::{build_lists, CellGrid};
    use crate::particles::{MaterialId, ParticleInit};
    use rand::{Rng, SeedableRng};

    /// Keeps every contact, in order, for tests that sum them their own way.
    impl PairSink for Vec<(u32, u32, ContactForce)> {
        fn contact(&mut self, i: usize, j: usize, cf: &ContactForce) {
            self.push((i as u32, j as u32, *cf));
        }
    }

    /// A jumble of spheres in a box of planes with one tilted polygon, moving and spinning,
    /// with random tangential histories: every branch of both kernels is reached.
    pub(super) fn jumble(materials: usize, polydisperse: bool) -> (ParticleSet, Vec<Option<Wall>>) {
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(5);
        let mut set = ParticleSet::default();
        let mut v = |s: f64| {
            DVec3::new(
                rng.gen::<f64>() - 0.5,
                rng.gen::<f64>() - 0.5,
                rng.gen::<f64>() - 0.5,
            ) * s
        };
        for k in 0..600 {
            let r = if polydisperse {
                1.5e-3 * (1.0 + 0.3 * (k % 7) as f64 / 7.0)
            } else {
                1.5e-3
            };
            let mut init = ParticleInit::at_rest(
                DVec3::splat(0.0125) + v(0.025),
                r,
                MaterialId((k % materials) as u16),
            );
            init.velocity = v(2.0);
            init.angular_velocity = v(400.0);
            set.push(&init, 2500.0 * (1.0 + (k % materials) as f64));
        }
        let m = WallMaterial::Elastic(Material::fan2023());
        let i = Interaction::fan2023();
        let mut walls: Vec<Option<Wall>> = vec![
            Some(Wall::plane(DVec3::ZERO, DVec3::Z, m, i).unwrap()),
            Some(
                Wall::plane(
                    DVec3::new(0.025, 0.0, 0.0),
                    -DVec3::X,
                    WallMaterial::Rigid,
                    i,
                )
                .unwrap(),
            ),
            None,
            Some(
                Wall::polygon(
                    vec![
                        DVec3::new(0.0, 0.0, 0.02),
                        DVec3::new(0.02, 0.0, 0.01),
                        DVec3::new(0.02, 0.02, 0.01),
                        DVec3::new(0.0, 0.02, 0.02),
                    ],
                    m,
                    Interaction { friction: 0.3, ..i },
                )
                .unwrap(),
            ),
        ];
        walls[0].as_mut().unwrap().velocity = DVec3::new(0.1, 0.0, 0.0);
        (set, walls)
    }

    #[test]
    fn a_batch_finds_the_same_worst_overlap_as_one_contact_at_a_time() {
        // `see_batch` skips the walk when the bits' maximum says nothing beats the worst so
        // far; it must never skip a batch that holds a larger fraction. Random batches of
        // fractions, some negative, zero, NaN or tiny, against `see` on every contact: the
        // same fraction and index, exactly.
        use rand::{Rng, SeedableRng};
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(5);
        let mut batch = Batch::default();
        let (mut batched, mut single) = (WorstOverlap::default(), WorstOverlap::default());
        for b in 0..2000 {
            batch.len = rng.gen_range(0..=BATCH);
            for f in &mut batch.overlap_fraction[..batch.len] {
                *f = match rng.gen_range(0..8) {
                    0 => -rng.gen::<f64>(),
                    1 => 0.0,
                    2 => f64::NAN,
                    3 => 1e-300 * rng.gen::<f64>(),
                    // Growing slowly, so later batches still beat the worst now and then.
                    _ => 0.05 * rng.gen::<f64>() * (1.0 + b as f64 / 500.0),
                };
            }
            let base = BATCH * b;
            batched.see_batch(&batch, base..);
            for (m, &f) in batch.overlap_fraction[..batch.len].iter().enumerate() {
                single.see(f, base + m);
            }
            assert_eq!(
                batched.fraction.to_bits(),
                single.fraction.to_bits(),
                "batch {b}"
            );
            assert_eq!(batched.index, single.index, "batch {b}");
        }
        assert!(
            single.fraction > 0.05,
            "the worst grew past the first batches'"
        );
    }

    #[test]
    fn split_plane_filter_matches_the_per_candidate_test() {
        // The three passes of the equal-sphere plane filter against the one-candidate-at-a-
        // time definition: the same touching list, histories kept bit for bit or forgotten,
        // for a contiguous run (the slab faces' stream) and for a run with gaps (the
        // gathered path), with a NaN position counted as touching. Exact equality: both
        // evaluate the same expression on the same numbers.
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(3);
        let r = 1.5e-3;
        let mut pos: Vec<DVec3> = (0..200)
            .map(|_| DVec3::new(rng.gen(), rng.gen::<f64>() * 4e-3, rng.gen()))
            .collect();
        pos[17] = DVec3::new(0.5, f64::NAN, 0.5);
        let (normal, offset) = (DVec3::new(0.0, 1.0, 0.0), 0.0);
        let contiguous: Vec<u32> = (10..150).collect();
        let gapped: Vec<u32> = (0..200).filter(|k| k % 3 != 1).collect();
        for pi in [contiguous, gapped] {
            let old: Vec<DVec3> = (0..pi.len())
                .map(|k| DVec3::splat(k as f64 + 1.0))
                .collect();
            let expect_touch: Vec<bool> = pi
                .iter()
                .map(|&i| !(plane_distance(pos[i as usize], normal, offset) >= r))
                .collect();
            // Every third contact had already opened (not live) before this filter.
            let before: Vec<u8> = (0..pi.len()).map(|k| u8::from(k % 3 != 0)).collect();
            let (mut touch, mut hits, mut history) = (
                vec![9u8; pi.len()],
                vec![0u32; pi.len()],
                HistoryArrays::from(
                    old.iter()
                        .map(|&t| ContactHistory {
                            tangential: t,
                            rolling: DVec3::ZERO,
                        })
                        .collect::<Vec<_>>(),
                ),
            );
            history.live.copy_from_slice(&before);
            plane_touches(&pos, &pi, (normal, offset, r), &mut touch);
            note_live(&touch, &mut history.live);
            let count = compact::from_bytes(&touch, &mut hits);
            let expect_hits: Vec<u32> = (0..pi.len() as u32)
                .filter(|&k| expect_touch[k as usize])
                .collect();
            assert!(count > 10 && count < pi.len(), "both outcomes occur");
            assert_eq!(&hits[..count], &expect_hits[..]);
            let nan = pi
                .iter()
                .position(|&i| i == 17)
                .expect("both runs hold particle 17");
            assert!(
                hits[..count].contains(&(nan as u32)),
                "a NaN distance counts as touching"
            );
            for (k, o) in old.iter().enumerate() {
                // Touching: live, and the gather sees ξ only if it was live before.
                // Separated: the history reads as zero (§3.1).
                let was = before[k] == LIVE;
                let kept = if expect_touch[k] && was {
                    *o
                } else {
                    DVec3::ZERO
                };
                let flags = history.live[k];
                let seen = if expect_touch[k] {
                    live_history(flags, history.tangential[k])
                } else {
                    history.get(k).tangential
                };
                assert_eq!(flags & LIVE == LIVE, expect_touch[k]);
                assert_eq!(
                    seen.to_array().map(f64::to_bits),
                    kept.to_array().map(f64::to_bits)
                );
            }
        }
    }

    /// Everything an evaluation leaves behind, as bits.
    pub(super) fn bits(
        buffers: &ForceBuffers,
        pairs: &PairList,
        walls: &WallPairList,
        eval: &Evaluation,
    ) -> Vec<u64> {
        let histories = pairs.history.iter().chain(walls.history.iter());
        let vectors = buffers
            .force
            .iter()
            .copied()
            .chain(buffers.torque.iter().copied())
            .chain(histories.flat_map(|h| [h.tangential, h.rolling]));
        let mut out: Vec<u64> = vectors
            .flat_map(|v| v.to_array().map(f64::to_bits))
            .collect();
        out.extend([
            eval.count.particle_particle as u64,
            eval.count.particle_wall as u64,
            eval.worst_pair.index as u64,
            eval.worst_pair.fraction.to_bits(),
            eval.worst_wall.index as u64,
            eval.worst_wall.fraction.to_bits(),
        ]);
        out
    }

    /// The jumble with everything an evaluation needs: coefficients of its materials and
    /// walls, and gravity.
    pub(super) struct Jumble {
        pub set: ParticleSet,
        pub walls: Vec<Option<Wall>>,
        pub pair_coeffs: Vec<PairCoefficients>,
        pub wall_coeffs: Vec<PairCoefficients>,
        pub materials: usize,
        pub poly: bool,
        /// Gravitational acceleration [m/s²].
        pub gravity: DVec3,
    }

    impl Jumble {
        pub fn new(materials: usize, poly: bool) -> Self {
            let (set, walls) = jumble(materials, poly);
            let mats: Vec<Material> = (0..materials)
                .map(|k| Material {
                    density: 2500.0 * (1.0 + k as f64),
                    ..Material::fan2023()
                })
                .collect();
            let i = Interaction::fan2023();
            let mut pair_coeffs = Vec::new();
            for a in &mats {
                for b in &mats {
                    pair_coeffs.push(PairCoefficients::new(a, Some(b), &i));
                }
            }
            let mut wall_coeffs = Vec::new();
            for w in &walls {
                for a in &mats {
                    wall_coeffs.push(match w {
                        Some(w) => PairCoefficients::with_wall(a, &w.material, &w.interaction),
                        None => PairCoefficients::new(a, None, &i),
                    });
                }
            }
            Self {
                set,
                walls,
                pair_coeffs,
                wall_coeffs,
                materials,
                poly,
                gravity: DVec3::new(0.0, -9.81, 0.0),
            }
        }

        /// Candidate lists with random tangential histories (and rolling ones, for the
        /// laws that keep them).
        pub fn lists(&self) -> (PairList, WallPairList) {
            let skin = 3e-4;
            let grid = CellGrid::build(&self.set.position, 2.0 * 1.5e-3 * 1.3 + skin);
            let (mut pairs, mut wall_pairs) = (PairList::default(), WallPairList::default());
            build_lists(
                &grid,
                &self.set,
                &self.walls,
                skin,
                &PairList::default(),
                &WallPairList::default(),
                crate::neighbour::Carry::Same,
                (&mut pairs, &mut wall_pairs),
                &mut crate::neighbour::ListScratch::default(),
            );
            let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(9);
            let (t, r) = pairs.history.split_mut();
            let (wt, wr) = wall_pairs.history.split_mut();
            for h in t.iter_mut().chain(wt.iter_mut()) {
                *h = DVec3::new(rng.gen(), rng.gen(), rng.gen()) * 2e-6;
            }
            for h in r.iter_mut().chain(wr.iter_mut()) {
                *h = DVec3::new(rng.gen(), rng.gen(), rng.gen()) * 1e-9;
            }
            (pairs, wall_pairs)
        }
    }

    /// The kernel input of `jumble` under `laws`.
    pub(super) fn jumble_input<'a>(jumble: &'a Jumble, laws: &'a ContactLaws) -> KernelInput<'a> {
        KernelInput {
            particles: &jumble.set,
            laws,
            pair_coeffs: &jumble.pair_coeffs,
            materials: jumble.materials,
            walls: &jumble.walls,
            wall_coeffs: &jumble.wall_coeffs,
            uniform_body: (!jumble.poly).then(|| (jumble.set.radius[0], jumble.set.mass[0])),
            dt: 2.5e-6,
        }
    }

    /// The scalar path's pair contacts summed onto `n` bodies: F and M_i on i, −F and M_j
    /// on j.
    fn summed(n: usize, contacts: Vec<(u32, u32, ContactForce)>) -> (Vec<DVec3>, Vec<DVec3>) {
        let (mut force, mut torque) = (vec![DVec3::ZERO; n], vec![DVec3::ZERO; n]);
        for (a, b, cf) in contacts {
            let (a, b) = (a as usize, b as usize);
            force[a] += cf.force;
            force[b] -= cf.force;
            torque[a] += cf.torque_i;
            torque[b] += cf.torque_j;
        }
        (force, torque)
    }

    /// The batched path's sums in `buffers` against the scalar path's: the same formulas
    /// with a few operations regrouped, so agreement to 1e-12 of each body's own force or
    /// torque.
    fn assert_close(buffers: &ForceBuffers, force: &[DVec3], torque: &[DVec3]) {
        for k in 0..force.len() {
            let f = force[k].length().max(1e-30);
            let t = torque[k].length().max(1e-30);
            assert!(
                (buffers.force[k] - force[k]).length() <= 1e-12 * f,
                "force {k}"
            );
            assert!(
                (buffers.torque[k] - torque[k]).length() <= 1e-12 * t,
                "torque {k}"
            );
        }
    }

    #[test]
    fn bodies_beyond_the_prefetch_size_get_the_scalar_laws_forces() {
        // Copies of the jumble, far apart, hold more bodies than `PREFETCH_BODIES`, so the
        // pair filter and gather ask for lines ahead (hints, which must change nothing).
        // Forces must agree with the scalar laws as in
        // `batched_kernels_match_the_scalar_contact_laws` (to 1e-12, the same formulas with
        // a few operations regrouped), and two threads must give every bit of one.
        let jumble = Jumble::new(1, false);
        let one = &jumble.set;
        let copies = PREFETCH_BODIES / one.len() + 2;
        let mut set = ParticleSet::default();
        for c in 0..copies {
            for k in 0..one.len() {
                let mut init = ParticleInit::at_rest(
                    one.position[k] + DVec3::X * (0.05 * c as f64),
                    one.radius[k],
                    MaterialId(0),
                );
                init.velocity = one.velocity[k];
                init.angular_velocity = one.omega[k];
                set.push(&init, 2500.0);
            }
        }
        assert!(set.len() > PREFETCH_BODIES);
        let big = Jumble {
            set,
            walls: Vec::new(),
            wall_coeffs: Vec::new(),
            ..Jumble::new(1, false)
        };
        let (mut pairs, mut wall_pairs) = big.lists();
        let laws = ContactLaws::default();
        let input = jumble_input(&big, &laws);
        let mut p2 = pairs.clone();
        let mut buffers = ForceBuffers::default();
        start(&big.set, DVec3::ZERO, &mut buffers);
        let eval = evaluate(&input, &mut pairs, &mut wall_pairs, &mut buffers, None);
        assert!(eval.count.particle_particle > copies * 100);

        let ids = (&p2.i.clone()[..], &p2.j.clone()[..]);
        let mut contacts = Vec::new();
        pair_loop_with(&input, laws, ids, 0, p2.history.split_mut(), &mut contacts);
        let (force, torque) = summed(big.set.len(), contacts);
        assert_close(&buffers, &force, &torque);

        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        let (mut p3, mut w3) = big.lists();
        let mut two = ForceBuffers::default();
        start(&big.set, DVec3::ZERO, &mut two);
        evaluate(&input, &mut p3, &mut w3, &mut two, Some(&pool));
        let bits = |v: &[DVec3]| {
            v.iter()
                .map(|x| x.to_array().map(f64::to_bits))
                .collect::<Vec<_>>()
        };
        assert_eq!(bits(&two.force), bits(&buffers.force));
        assert_eq!(bits(&two.torque), bits(&buffers.torque));
    }

    #[test]
    fn batched_kernels_match_the_scalar_contact_laws() {
        // The batched path (the paper's laws) against the general scalar path over the same
        // lists: with one material and one size (the shared-coefficient fills), and with two
        // materials and seven sizes (the per-contact gathers). Same formulas with a few
        // operations regrouped: agreement to 1e-12 of each body's largest force or torque.
        for (materials, poly) in [(1, false), (2, true)] {
            let jumble = Jumble::new(materials, poly);
            let set = &jumble.set;
            let (mut pairs, mut wall_pairs) = jumble.lists();
            let laws = ContactLaws::default();
            let input = jumble_input(&jumble, &laws);
            let (mut p2, mut w2) = (pairs.clone(), wall_pairs.clone());
            let mut buffers = ForceBuffers::default();
            start(set, DVec3::ZERO, &mut buffers);
            let eval = evaluate(&input, &mut pairs, &mut wall_pairs, &mut buffers, None);
            assert!(eval.count.particle_particle > 100 && eval.count.particle_wall > 10);
            assert!(
                eval.count.particle_particle < p2.len(),
                "some candidates must be apart"
            );

            let ids = (&p2.i.clone()[..], &p2.j.clone()[..]);
            let mut contacts = Vec::new();
            let worst = pair_loop_with(&input, laws, ids, 0, p2.history.split_mut(), &mut contacts);
            let (mut force, mut torque) = summed(set.len(), contacts);
            let wids = (&w2.particle.clone()[..], &w2.wall.clone()[..]);
            wall_loop(&input, wids, w2.history.split_mut(), |a, cf| {
                force[a] += cf.force;
                torque[a] += cf.torque_i;
            });
            assert_eq!(eval.worst_pair.index, worst.index);
            assert_close(&buffers, &force, &torque);
            for (a, b) in pairs
                .history
                .iter()
                .zip(p2.history.iter())
                .chain(wall_pairs.history.iter().zip(w2.history.iter()))
            {
                assert!(
                    (a.tangential - b.tangential).length() <= 1e-12 * b.tangential.length(),
                    "history"
                );
            }
        }
    }
}
