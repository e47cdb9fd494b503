//! The one summation order both evaluation paths share: each contact's force and torques
//! added to its two bodies as it is resolved, in pair-list order.

use glam::DVec3;

use super::{prefetch, PairSink};
use crate::contact::ContactForce;

/// Adds pair forces to the bodies in pair order, the one summation both evaluation paths share.
///
/// Each share is added to its body at once, i's as j's: every body receives its contacts
/// one by one, in pair-list order, onto gravity. Summing i's run of pairs in registers and
/// adding it once would save almost no memory traffic, since runs are about one contact
/// long, and keeping such a run branch-free costs twelve selects per contact: the plain
/// additions are about 6 % faster per step.
pub(super) struct Accumulator<'a> {
    pub(super) force: &'a mut [DVec3],
    pub(super) torque: &'a mut [DVec3],
    /// Contacts added.
    pub(super) contacts: usize,
}

impl<'a> Accumulator<'a> {
    pub(super) fn new(force: &'a mut [DVec3], torque: &'a mut [DVec3]) -> Self {
        Self {
            force,
            torque,
            contacts: 0,
        }
    }

    /// j's share first: i ≠ j, so the order within a contact changes no sum, and a body
    /// that is j of this contact is often i of the next, whose load of its sums then
    /// waits less on this store (about 1 % of a step).
    #[inline(always)]
    pub(super) fn add(&mut self, i: usize, j: usize, cf: &ContactForce) {
        self.contacts += 1;
        self.add_j(j, cf);
        self.add_i(i, cf);
    }

    /// Body i's share: F on i, and M_i.
    #[inline(always)]
    pub(super) fn add_i(&mut self, i: usize, cf: &ContactForce) {
        self.force[i] += cf.force;
        self.torque[i] += cf.torque_i;
    }

    /// Body j's share: −F (Newton's third law), and M_j.
    #[inline(always)]
    pub(super) fn add_j(&mut self, j: usize, cf: &ContactForce) {
        self.force[j] -= cf.force;
        self.torque[j] += cf.torque_j;
    }
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
