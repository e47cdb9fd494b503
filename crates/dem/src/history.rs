//! Contact histories of a candidate list, one array per quantity.
//!
//! The paper's laws keep only the tangential displacement ξ; the EPSD rolling torque is kept
//! in its own array, which those laws never touch, so the gather of a touching contact moves
//! 24 bytes instead of 48 and the rolling array stays out of the cache. A third array holds
//! a byte per contact that says whether its history is still its own (see
//! [`HistoryArrays`]): the per-step filter over every candidate writes that byte, not ξ.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::capacity::reserve_total;
use crate::contact::ContactHistory;

/// Bit of [`HistoryArrays::live`]: the stored history is the contact's own.
pub(crate) const LIVE: u8 = 1;
/// Bit of [`HistoryArrays::live`]: [`LIVE`] as it was before this evaluation's filter, which
/// the gather of a touching contact reads.
pub(crate) const WAS_LIVE: u8 = 2;
/// Bit of [`HistoryArrays::live`]: the pair is bonded by a cohesion that acts beyond contact
/// ([`ContactHistory::bonded`]); meaningful only with [`LIVE`].
pub(crate) const BONDED: u8 = 4;
/// An entry of [`HistoryArrays::carry_from`]'s sources: no earlier contact, no history.
pub(crate) const NO_SOURCE: u32 = u32::MAX;

/// The histories of a candidate list, index-aligned with it.
///
/// A contact that opens forgets its history (docs/physics.md §3.1). Rather than rewriting ξ of
/// every separated candidate at every step, which moved 48 bytes a candidate for the two
/// thirds of candidates that do not touch, the per-step filters clear one byte, the
/// contact's [`LIVE`] bit: while it is clear, the history is zero whatever the arrays hold.
/// Every reader outside the force loops ([`HistoryArrays::get`], [`HistoryArrays::iter`],
/// serialisation, equality, [`HistoryArrays::split_mut`]) sees those zeros, so the lists'
/// contents, checkpoints and list rebuilds are what the eager clearing gave, bit for bit.
///
/// Serialised as a sequence of [`ContactHistory`], the layout checkpoints have always had;
/// written straight from the arrays, so that a checkpoint holds no second copy of them.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(from = "Vec<ContactHistory>")]
pub struct HistoryArrays {
    /// Tangential displacement ξ of each contact [m].
    pub(crate) tangential: Vec<DVec3>,
    /// EPSD spring torque on i of each contact [N m].
    pub(crate) rolling: Vec<DVec3>,
    /// Per contact: [`LIVE`] when the stored history is the contact's (otherwise it is zero),
    /// and [`WAS_LIVE`], the force loops' note of [`LIVE`] before their filter.
    pub(crate) live: Vec<u8>,
}

impl HistoryArrays {
    /// Number of contacts.
    pub fn len(&self) -> usize {
        self.tangential.len()
    }

    /// True when there are none.
    pub fn is_empty(&self) -> bool {
        self.tangential.is_empty()
    }

    /// Removes every contact, keeping the allocations.
    pub(crate) fn clear(&mut self) {
        self.tangential.clear();
        self.rolling.clear();
        self.live.clear();
    }

    /// Makes room for `len` contacts in all ([`reserve_total`]).
    pub(crate) fn reserve_total(&mut self, len: usize) {
        reserve_total(&mut self.tangential, len);
        reserve_total(&mut self.rolling, len);
        reserve_total(&mut self.live, len);
    }

    /// Appends one contact's history.
    #[inline]
    pub(crate) fn push(&mut self, h: ContactHistory) {
        self.tangential.push(h.tangential);
        self.rolling.push(h.rolling);
        self.live.push(if h.bonded { LIVE | BONDED } else { LIVE });
    }

    /// Appends contact `k` of `from` as stored, live flags included: a copy that the force
    /// loops read exactly as they would read the original.
    #[inline]
    pub(crate) fn push_stored(
        &mut self,
        (tangential, rolling, live): (&[DVec3], &[DVec3], &[u8]),
        k: usize,
    ) {
        self.tangential.push(tangential[k]);
        self.rolling.push(rolling[k]);
        self.live.push(live[k]);
    }

    /// Replaces the contents with, for each entry of `source`, the history of contact
    /// `source[k]` of `old` (as [`HistoryArrays::get`] reads it), or none where it is
    /// [`NO_SOURCE`]; every entry is live, and bonded where its source was. Array by array,
    /// for the list rebuilds.
    ///
    /// Without a branch on the outcome: whether a history is kept (a source, and live
    /// there) varies from entry to entry, and a branch on it is mispredicted often enough
    /// to make this copy cost about 10 ns an entry. The kept value or +0.0 is chosen by masking its bits, so the copy is exact.
    pub(crate) fn carry_from(&mut self, old: &HistoryArrays, source: &[u32]) {
        self.clear();
        self.reserve_total(source.len());
        let n = old.len();
        if n == 0 {
            self.tangential.resize(source.len(), DVec3::ZERO);
            self.rolling.resize(source.len(), DVec3::ZERO);
            self.live.resize(source.len(), LIVE);
            return;
        }
        // All ones where contact `c` of `old` exists and is live, else zero; and the index
        // clamped so that the load needs no branch either.
        let keep = |c: u32| {
            let at = (c as usize).min(n - 1);
            let live = old.live[at] & LIVE & u8::from((c as usize) < n);
            (at, 0u64.wrapping_sub(u64::from(live)))
        };
        let masked = |v: DVec3, mask: u64| {
            let bits = |x: f64| f64::from_bits(x.to_bits() & mask);
            DVec3::new(bits(v.x), bits(v.y), bits(v.z))
        };
        self.tangential.extend(source.iter().map(|&c| {
            let (at, mask) = keep(c);
            masked(old.tangential[at], mask)
        }));
        self.rolling.extend(source.iter().map(|&c| {
            let (at, mask) = keep(c);
            masked(old.rolling[at], mask)
        }));
        self.live.extend(source.iter().map(|&c| {
            let (at, mask) = keep(c);
            LIVE | (old.live[at] & BONDED & mask as u8)
        }));
    }

    /// History of contact `k`.
    #[inline]
    pub fn get(&self, k: usize) -> ContactHistory {
        if self.live[k] & LIVE == 0 {
            return ContactHistory::default();
        }
        ContactHistory {
            tangential: self.tangential[k],
            rolling: self.rolling[k],
            bonded: self.live[k] & BONDED != 0,
        }
    }

    /// Every history, in list order.
    pub fn iter(&self) -> impl Iterator<Item = ContactHistory> + '_ {
        (0..self.len()).map(|k| self.get(k))
    }

    /// The three arrays, mutably, with every history that is not live written as zero and
    /// every flag live (bonded where it was), for the loops that clear separated contacts
    /// themselves (the scalar laws, tests).
    pub(crate) fn split_mut(&mut self) -> (&mut [DVec3], &mut [DVec3], &mut [u8]) {
        let (tangential, rolling, live) = self.parts_mut();
        settle(tangential, rolling, live);
        (tangential, rolling, live)
    }

    /// The three arrays as they are, for the force loops that read [`HistoryArrays::live`].
    pub(crate) fn parts_mut(&mut self) -> (&mut [DVec3], &mut [DVec3], &mut [u8]) {
        (&mut self.tangential, &mut self.rolling, &mut self.live)
    }
}

/// Writes zero into every history whose contact is not live and marks all live, keeping
/// [`BONDED`] where the contact was live: afterwards the arrays hold exactly what
/// [`HistoryArrays::get`] returns.
pub(crate) fn settle(tangential: &mut [DVec3], rolling: &mut [DVec3], live: &mut [u8]) {
    for ((t, r), l) in tangential
        .iter_mut()
        .zip(rolling.iter_mut())
        .zip(live.iter_mut())
    {
        if *l & LIVE == 0 {
            (*t, *r) = (DVec3::ZERO, DVec3::ZERO);
            *l = LIVE;
        } else {
            *l &= LIVE | BONDED;
        }
    }
}

/// Two lists are equal when every contact's history, as read, is.
impl PartialEq for HistoryArrays {
    fn eq(&self, other: &Self) -> bool {
        self.len() == other.len() && self.iter().eq(other.iter())
    }
}

impl Serialize for HistoryArrays {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_seq(self.iter())
    }
}

impl FromIterator<ContactHistory> for HistoryArrays {
    fn from_iter<I: IntoIterator<Item = ContactHistory>>(iter: I) -> Self {
        let iter = iter.into_iter();
        let mut out = Self::default();
        let (least, _) = iter.size_hint();
        out.tangential.reserve_exact(least);
        out.rolling.reserve_exact(least);
        out.live.reserve_exact(least);
        for h in iter {
            out.push(h);
        }
        out
    }
}

impl From<Vec<ContactHistory>> for HistoryArrays {
    fn from(v: Vec<ContactHistory>) -> Self {
        v.into_iter().collect()
    }
}

impl From<HistoryArrays> for Vec<ContactHistory> {
    fn from(h: HistoryArrays) -> Self {
        h.iter().collect()
    }
}

/// One contact of a sphere with a curved or meshed wall, as it is remembered from step to
/// step: its normal (wall to sphere) and its history. A sphere may touch such a wall in
/// several places at once (a fold of a mesh); the contacts of the next step take the
/// histories of the remembered ones whose normals are nearest (docs/physics.md §5.3).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub(crate) struct SurfaceContact {
    /// Unit normal, wall to sphere [-].
    pub normal: DVec3,
    /// ξ and the rolling history.
    pub history: ContactHistory,
}

/// What a candidate of a curved, meshed or spinning wall remembers: its contacts, and for
/// a mesh the triangles near the sphere, found once and reused while the sphere stays
/// within a margin of where they were found (docs/physics.md §5.3). The triangles are a
/// cache: any superset of those within reach gives the same contacts, so they are not
/// stored in checkpoints.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub(crate) struct SurfaceSlot {
    /// The contacts of the last step.
    pub contacts: Vec<SurfaceContact>,
    /// The triangles near the sphere and where it was when they were found.
    #[serde(skip)]
    pub near: crate::wall::geometry::NearCache,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn histories_serialise_as_the_records_checkpoints_always_held() {
        // A checkpoint written with `Vec<ContactHistory>` must load into the arrays and
        // back, byte for byte: the serialised form is the contract, not the layout.
        let records: Vec<ContactHistory> = (0..5)
            .map(|k| ContactHistory {
                tangential: DVec3::new(k as f64, -1.5, 2e-6),
                rolling: DVec3::new(0.0, k as f64 * 1e-3, -7.0),
                bonded: k % 2 == 1,
            })
            .collect();
        let old = postcard::to_allocvec(&records).unwrap();
        let arrays: HistoryArrays = postcard::from_bytes(&old).unwrap();
        assert_eq!(arrays.len(), 5);
        assert_eq!(arrays.get(3), records[3]);
        assert_eq!(postcard::to_allocvec(&arrays).unwrap(), old);
    }

    #[test]
    fn a_contact_that_is_not_live_reads_as_zero_everywhere() {
        // Clearing the live bit must be indistinguishable from writing zeros (docs/physics.md
        // §3.1), for every reader: get, iter, equality, serialisation and split_mut.
        let records: Vec<ContactHistory> = (1..=4)
            .map(|k| ContactHistory {
                tangential: DVec3::splat(k as f64),
                rolling: DVec3::splat(-(k as f64)),
                bonded: false,
            })
            .collect();
        let mut lazy: HistoryArrays = records.iter().copied().collect();
        lazy.live[2] = WAS_LIVE; // opened this step: live before, not now
        let mut eager = records.clone();
        eager[2] = ContactHistory::default();
        let eager: HistoryArrays = eager.into_iter().collect();
        assert_eq!(lazy.get(2), ContactHistory::default());
        assert_eq!(lazy.get(1), records[1]);
        assert_eq!(lazy, eager);
        assert_ne!(lazy, records.iter().copied().collect::<HistoryArrays>());
        assert_eq!(
            postcard::to_allocvec(&lazy).unwrap(),
            postcard::to_allocvec(&eager).unwrap()
        );
        let (t, r, _) = lazy.split_mut();
        assert_eq!((t[2], r[2]), (DVec3::ZERO, DVec3::ZERO));
        assert_eq!(t[3], records[3].tangential);
        assert!(lazy.live.iter().all(|&l| l == LIVE));
    }
}
