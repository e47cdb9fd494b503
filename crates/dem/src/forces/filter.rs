//! Branch-free filters: which candidates touch, and which contacts keep their tangential
//! history (docs/physics.md §3.1: a contact that opens forgets it).

use glam::{BVec3, DVec3};

use super::{compact, gather, prefetch, PREFETCH_AHEAD, PREFETCH_BODIES};
use crate::contact::geometry::plane_distance;
use crate::history::{BONDED, LIVE, WAS_LIVE};
use crate::particles::ParticleSet;

/// Lists (in `touching[..count]`, count returned) the candidates of `pi`/`pj` whose spheres
/// overlap, and with `bonds` those bonded as well ([`note_live_or_bonded`]), without a
/// branch on the outcome, and marks the others' histories as not live (see [`note_live`]).
#[inline(never)]
pub(super) fn filter_touching(
    p: &ParticleSet,
    ids: (&[u32], &[u32]),
    live: &mut [u8],
    touching: &mut Vec<u32>,
    uniform_radius: Option<f64>,
    bonds: bool,
) -> usize {
    let radius = &p.radius[..p.len()];
    match uniform_radius {
        // Equal spheres: the contact distance is a constant, and (r + r)² is the same number
        // as the general branch computes for every pair.
        Some(r) => {
            let cut2 = (r + r) * (r + r);
            filter_touching_with(p, ids, live, touching, (Some(cut2), |_, _| cut2), bonds)
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
            bonds,
        ),
    }
}

/// The live flags of a listed contact after the laws, from its flags `old`: none if its bond
/// broke or it had none apart (`kept` false; its history is then zero), else [`LIVE`], with
/// [`BONDED`] where its pair's law bonds (`bonds`).
#[inline(always)]
pub(super) fn settle_bond(old: u8, kept: bool, bonds: bool) -> u8 {
    let base = old & WAS_LIVE;
    if kept {
        base | LIVE | (u8::from(bonds) * BONDED)
    } else {
        base
    }
}

/// [`filter_touching`] with `cut2(i, j)` the squared contact distance (R_i + R_j)² [m²],
/// and that distance alone where every pair shares it (equal spheres).
#[inline(always)]
pub(super) fn filter_touching_with(
    p: &ParticleSet,
    (pi, pj): (&[u32], &[u32]),
    live: &mut [u8],
    touching: &mut Vec<u32>,
    (shared, cut2): (Option<f64>, impl Fn(usize, usize) -> f64),
    bonds: bool,
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
    if bonds {
        note_live_or_bonded(flags, live);
    } else {
        note_live(flags, live);
    }
    compact::in_place(flags)
}

/// Pass 2 of the pair filter where pairs may bond (JKR, liquid bridges): a candidate is
/// listed while touching (`flags[k]` 1) or bonded, however far apart (the laws decide
/// whether its bond holds), and the live flags follow the listing ([`live_flags`]). A
/// listed bonded candidate keeps its [`BONDED`] bit; the pair loop sets the bits of every
/// listed one after the laws ([`settle_bond`]). Over bytes, with no count: vectorised.
/// The flags are bytes for the plane filter and 32-bit words for the pair filter.
#[inline(always)]
pub(super) fn note_live_or_bonded<T: Copy + Into<u32> + From<u8>>(
    flags: &mut [T],
    live: &mut [u8],
) {
    for (f, l) in flags.iter_mut().zip(live.iter_mut()) {
        let (listed, flags) = listed_or_bonded((*f).into() != 0, *l);
        *f = T::from(u8::from(listed));
        *l = flags;
    }
}

/// Whether a candidate that touches (`touch`) or not, with live flags `old`, is listed where
/// pairs may bond (touching, or bonded however far apart), and its live flags after the
/// filter ([`live_flags`], keeping [`BONDED`] where it is bonded).
#[inline(always)]
fn listed_or_bonded(touch: bool, old: u8) -> (bool, u8) {
    let bonded = old & (LIVE | BONDED) == LIVE | BONDED;
    let listed = touch | bonded;
    (
        listed,
        live_flags(u8::from(listed), old) | (u8::from(bonded) * BONDED),
    )
}

/// Pass 1 of the pair filter: `flags[k]` is 1 when candidate k's spheres overlap, with
/// `cut2(i, j)` the squared contact distance [m²]. With `FAR` (bodies beyond the caches,
/// [`PREFETCH_BODIES`]) it also asks for the position of the partner
/// [`PREFETCH_AHEAD`] candidates on, a hint that changes no result.
#[inline(always)]
pub(super) fn pair_flags<const FAR: bool>(
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
/// true, in order, and records in `live` which contacts keep their history (docs/physics.md §3.1:
/// a contact that opens forgets it; see [`note_live`]). With `BONDS` (contacts that may bond)
/// it lists the bonded candidates too, however far apart ([`listed_or_bonded`]).
/// Branch-free: every index is stored and the count advances only for a listed one, because
/// a branch on the outcome is mispredicted about as often as taken.
#[inline(always)]
pub(super) fn compact_touching<const BONDS: bool>(
    touches: impl Iterator<Item = bool>,
    live: &mut [u8],
    hits: &mut [u32],
) -> usize {
    let len = live.len();
    let mut count = 0;
    for (k, (touch, l)) in touches.zip(live.iter_mut()).enumerate() {
        let (listed, flags) = if BONDS {
            listed_or_bonded(touch, *l)
        } else {
            (touch, live_flags(u8::from(touch), *l))
        };
        hits[count.min(len - 1)] = k as u32;
        count += usize::from(listed);
        *l = flags;
    }
    count
}

/// The live flags of a contact after a filter that found it touching (`touch` = 1) or not
/// (0), from its flags before: [`LIVE`] becomes `touch`, and [`WAS_LIVE`] keeps the old
/// [`LIVE`] for the gather. A contact that does not touch forgets its history (§3.1) by
/// losing [`LIVE`]; its ξ is not rewritten.
#[inline(always)]
pub(super) fn live_flags(touch: u8, old: u8) -> u8 {
    touch | ((old & LIVE) << 1)
}

/// ξ of a touching contact as the laws see it: the stored one if it was live before this
/// step's filter, zero if it had opened since it was stored (§3.1). A select, not a branch.
#[inline(always)]
pub(super) fn live_history(flags: u8, xi: DVec3) -> DVec3 {
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
pub(super) fn plane_touches(
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
/// contact that opens forgets its history (docs/physics.md §3.1) by losing [`LIVE`], one byte per
/// candidate instead of rewriting ξ. Vectorised: no count. The flags are bytes for the plane
/// filter and 32-bit words for the pair filter, whose compaction then overwrites them in
/// place.
#[inline(always)]
pub(super) fn note_live<T: Copy + Into<u32>>(touch: &[T], live: &mut [u8]) {
    for (l, &t) in live.iter_mut().zip(touch) {
        // A flag is 0 or 1, so the narrowing keeps it.
        *l = live_flags(t.into() as u8, *l);
    }
}
