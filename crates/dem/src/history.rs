//! Contact histories of a candidate list, one array per quantity.
//!
//! The paper's laws keep only the tangential displacement ξ; the EPSD rolling torque is kept
//! in its own array, which those laws never touch. Split this way, the per-step passes over
//! every candidate (clearing ξ of separated contacts, gathering it for touching ones) move
//! 24 bytes a candidate instead of 48, and the rolling array stays out of the cache.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::contact::ContactHistory;

/// The histories of a candidate list, index-aligned with it.
///
/// Serialised as a sequence of [`ContactHistory`], the layout checkpoints have always had.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(from = "Vec<ContactHistory>", into = "Vec<ContactHistory>")]
pub struct HistoryArrays {
    /// Tangential displacement ξ of each contact [m].
    pub(crate) tangential: Vec<DVec3>,
    /// EPSD spring torque on i of each contact [N m].
    pub(crate) rolling: Vec<DVec3>,
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
    }

    /// Appends one contact's history.
    #[inline]
    pub(crate) fn push(&mut self, h: ContactHistory) {
        self.tangential.push(h.tangential);
        self.rolling.push(h.rolling);
    }

    /// History of contact `k`.
    #[inline]
    pub fn get(&self, k: usize) -> ContactHistory {
        ContactHistory {
            tangential: self.tangential[k],
            rolling: self.rolling[k],
        }
    }

    /// Every history, in list order.
    pub fn iter(&self) -> impl Iterator<Item = ContactHistory> + '_ {
        self.tangential
            .iter()
            .zip(&self.rolling)
            .map(|(&tangential, &rolling)| ContactHistory {
                tangential,
                rolling,
            })
    }

    /// Both arrays, mutably, for the force loops.
    pub(crate) fn split_mut(&mut self) -> (&mut [DVec3], &mut [DVec3]) {
        (&mut self.tangential, &mut self.rolling)
    }
}

impl FromIterator<ContactHistory> for HistoryArrays {
    fn from_iter<I: IntoIterator<Item = ContactHistory>>(iter: I) -> Self {
        let mut out = Self::default();
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
            })
            .collect();
        let old = postcard::to_allocvec(&records).unwrap();
        let arrays: HistoryArrays = postcard::from_bytes(&old).unwrap();
        assert_eq!(arrays.len(), 5);
        assert_eq!(arrays.get(3), records[3]);
        assert_eq!(postcard::to_allocvec(&arrays).unwrap(), old);
    }
}
