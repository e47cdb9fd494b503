//! Carrying contact history over a rebuild: by index where the bodies kept theirs, through
//! the map from new to old indices where they moved, with the history negated where a pair's
//! order flipped.

use super::*;

/// A carried history as the bodies' identities define it: none when it reads as empty
/// (zero, whatever the signs of its zeros), and negated when the pair's order of bodies
/// turned round (ξ and the rolling torque of j relative to i are minus those of i
/// relative to j). This gives, bit for bit, what a store keyed by the bodies' tags gives,
/// which keeps only non-empty histories and orients them by tag.
#[inline]
pub(super) fn carried(h: ContactHistory, flipped: bool) -> ContactHistory {
    if h.is_empty() {
        ContactHistory::default()
    } else if flipped {
        negate(h)
    } else {
        h
    }
}

/// The histories of the new pairs `ids` (i < j, sorted) after the bodies' indices changed
/// (new body k was old body `origin[k]`), from the old pairs (i < j, sorted) and their
/// histories `old`. The old list's rows by i are found by counting, and each new pair's
/// old row, which holds a handful of entries, is scanned for its partner: no sort and no
/// search by tag, which would cost about 0.9 ms a build on the paper's hopper, where every
/// outflow of particles and every sixteenth build moves the indices.
pub(super) fn carry_moved_pairs(
    history: &mut HistoryArrays,
    ids: (&[u32], &[u32]),
    (old_i, old_j): (&[u32], &[u32]),
    old: &HistoryArrays,
    (origin, row): (&[u32], &mut Vec<u32>),
) {
    // Old bodies that appear in the old list: i < j, so the largest j bounds them.
    let bodies = old_j.iter().max().map_or(0, |&j| j as usize + 1);
    // Old entries with i = x are `row[x]..row[x + 1]`.
    row.clear();
    row.resize(bodies + 1, 0);
    for &x in old_i {
        row[x as usize + 1] += 1;
    }
    for x in 0..bodies {
        row[x + 1] += row[x];
    }
    history.clear();
    history.reserve_total(ids.0.len());
    for (&a, &b) in ids.0.iter().zip(ids.1) {
        let (x, y) = (origin[a as usize], origin[b as usize]);
        let (lo, hi) = (x.min(y) as usize, x.max(y));
        let h = match row.get(lo..lo + 2) {
            Some(&[start, end]) => {
                let run = start as usize..end as usize;
                old_j[run.clone()]
                    .iter()
                    .position(|&j| j == hi)
                    .map_or_else(ContactHistory::default, |k| old.get(run.start + k))
            }
            _ => ContactHistory::default(),
        };
        history.push(carried(h, x > y));
    }
}

/// As [`carry_moved_pairs`], for wall candidates (wall, particle), wall-major: each wall's
/// old run is spread into a table by old body index while the new run reads it. `source`
/// receives, where asked for, each new candidate's old index or [`NO_SOURCE`].
pub(super) fn carry_moved_walls(
    history: &mut HistoryArrays,
    (walls, bodies): (&[u32], &[u32]),
    (old_walls, old_bodies): (&[u32], &[u32]),
    old: &HistoryArrays,
    (origin, slot): (&[u32], &mut Vec<u32>),
    mut source: Option<&mut Vec<u32>>,
) {
    if let Some(source) = source.as_deref_mut() {
        source.clear();
    }
    let size = old_bodies.iter().max().map_or(0, |&x| x as usize + 1);
    slot.clear();
    slot.resize(size, NO_SOURCE);
    let mut current: Option<(u32, std::ops::Range<usize>)> = None;
    history.clear();
    history.reserve_total(walls.len());
    for (&w, &a) in walls.iter().zip(bodies) {
        if current.as_ref().is_none_or(|(v, _)| *v != w) {
            if let Some((_, run)) = current.take() {
                for &x in &old_bodies[run] {
                    slot[x as usize] = NO_SOURCE;
                }
            }
            let run = old_walls.partition_point(|&v| v < w)..old_walls.partition_point(|&v| v <= w);
            for (k, &x) in old_bodies[run.clone()].iter().enumerate() {
                slot[x as usize] = (run.start + k) as u32;
            }
            current = Some((w, run));
        }
        let from = slot
            .get(origin[a as usize] as usize)
            .copied()
            .unwrap_or(NO_SOURCE);
        if let Some(source) = source.as_deref_mut() {
            source.push(from);
        }
        let h = match from {
            NO_SOURCE => ContactHistory::default(),
            k => old.get(k as usize),
        };
        history.push(carried(h, false));
    }
}

/// For each entry of the list `new`, sorted by its two columns, the index of the same entry
/// in the list `old`, sorted the same way, or [`NO_SOURCE`]: one merge.
///
/// Without a branch on the comparisons: each round advances the new cursor, the old one,
/// or both on a match, and writes the new entry's source, which a later round overwrites
/// while the old cursor is still behind. The lists change in a scattered few entries
/// between builds, so a branch on each comparison was mispredicted at every change.
pub(super) fn matching(
    (a, b): (&[u32], &[u32]),
    (oa, ob): (&[u32], &[u32]),
    source: &mut Vec<u32>,
) {
    let key = |x: u32, y: u32| (u64::from(x) << 32) | u64::from(y);
    let (new_len, old_len) = (a.len().min(b.len()), oa.len().min(ob.len()));
    source.clear();
    source.resize(new_len, NO_SOURCE);
    let (mut k, mut c) = (0, 0);
    while k < new_len && c < old_len {
        let (here, there) = (key(a[k], b[k]), key(oa[c], ob[c]));
        source[k] = if here == there { c as u32 } else { NO_SOURCE };
        k += usize::from(here <= there);
        c += usize::from(there <= here);
    }
}

/// History of j relative to i is minus that of i relative to j (ξ and the rolling torque on i).
pub(super) fn negate(h: ContactHistory) -> ContactHistory {
    ContactHistory {
        tangential: -h.tangential,
        rolling: -h.rolling,
        bonded: h.bonded,
    }
}
