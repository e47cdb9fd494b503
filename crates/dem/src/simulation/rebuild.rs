//! When and how the neighbour lists are rebuilt: the bound on how far any body may have
//! moved since the last build (skin/2, docs/physics.md §6.3), and the rebuild itself, which
//! carries contact history over and re-sorts the bodies in cell order when due.

use super::*;

impl Simulation {
    /// Rebuilds the neighbour lists, carrying contact history over; `moved` says where the
    /// bodies came from when their indices changed since the last build (new body k was
    /// body `moved[k]`).
    pub(super) fn rebuild(&mut self, moved: Option<&[u32]>) {
        let s = &mut self.state;
        let r_max = s.particles.radius.iter().copied().fold(0.0, f64::max);
        if s.skin == 0.0 {
            s.skin = 0.2 * r_max;
        }
        let reach = self.cohesion_reach(r_max);
        let s = &mut self.state;
        s.list_reach = reach;
        // Pairs are listed out to the skin beyond their cohesion's reach: a bonded pair stays
        // in the list as long as it can interact (docs/physics.md §2.7).
        let search_skin = s.skin + reach;
        let cell = 2.0 * r_max + search_skin;
        let resort =
            s.config.resort_every > 0 && s.rebuilds.is_multiple_of(s.config.resort_every as u64);
        // A re-sort changes indices again: new body k was body `order[k]` before it.
        let origin = resort.then(|| {
            self.grid
                .rebuild(&s.particles.position, cell.max(f64::MIN_POSITIVE));
            let order = self.grid.cell_order();
            s.particles.permute(order);
            match moved {
                Some(moved) => order.iter().map(|&k| moved[k as usize]).collect(),
                None => order.to_vec(),
            }
        });
        let carry = match (origin.as_deref(), moved) {
            (Some(origin), _) | (None, Some(origin)) => Carry::Moved(origin),
            (None, None) => Carry::Same,
        };
        // A wide size distribution is searched by size class; otherwise one grid, sized by
        // the largest sphere, serves (and the re-sort above keeps its cell order either way).
        let search = if SizeClasses::pays_for(&s.particles.radius) {
            self.size_classes
                .rebuild(&s.particles.position, &s.particles.radius, search_skin);
            PairSearch::Classes(&self.size_classes)
        } else {
            self.grid
                .rebuild(&s.particles.position, cell.max(f64::MIN_POSITIVE));
            PairSearch::Cells(&self.grid)
        };
        // `build_lists` clears what it writes into; only the capacity of the spares is reused.
        let old_pairs = std::mem::replace(&mut s.pairs, std::mem::take(&mut self.spare_lists.0));
        let mut old_walls =
            std::mem::replace(&mut s.wall_pairs, std::mem::take(&mut self.spare_lists.1));
        build_lists(
            search,
            &s.particles,
            &s.walls,
            search_skin,
            &old_pairs,
            &mut old_walls,
            carry,
            (&mut s.pairs, &mut s.wall_pairs),
            &mut self.list_scratch,
        );
        if !s.clumps.is_empty() {
            s.clumps.find_members(&s.particles);
        }
        self.spare_lists = (old_pairs, old_walls);
        self.buffers.forget_lists();
        self.uniform_body = uniform_body(&s.particles);
        self.uniform_free = uniform_free_body(&s.particles);
        s.reference.clear();
        s.reference.extend_from_slice(&s.particles.position);
        let extent = s
            .reference
            .iter()
            .fold(0.0, |m: f64, x| m.max(x.abs().max_element()));
        self.reach_bound = ReachBound::at_build(extent);
        s.wall_drift = 0.0;
        s.rebuilds += 1;
        s.needs_rebuild = false;
    }

    /// How far beyond contact [m] the most far-reaching cohesive pair interacts, for the
    /// largest particle present, of radius `r_max` [m] (JKR's reach grows with R*): 0 without
    /// a bonding cohesion.
    pub(super) fn cohesion_reach(&self, r_max: f64) -> f64 {
        if !self.bonds {
            return 0.0;
        }
        self.pair_coeffs
            .iter()
            .chain(&self.wall_coeffs)
            .map(|c| c.cohesion.reach(c.e_star, r_max))
            .fold(0.0, f64::max)
    }

    /// Whether a contact may have formed that the lists, built with the skin s [m], do not
    /// hold, now that the bodies have moved from their places at the build (`reference`)
    /// and the walls by `wall_drift` [m]. Exact bounds, so a list kept is never short:
    ///
    /// - **Walls.** A wall candidate is any body closer than R_i + s (`build_lists`), so a
    ///   body–wall gap can have closed only if max |Δx| + wall drift > s (not s/2, the
    ///   pairs' bound). Without walls it has nothing to guard.
    /// - **Pairs.** A pair left out was farther apart than R_i + R_j + s, and its distance
    ///   has changed by at most |Δx_i − Δx_j| ≤ |Δx_i − u| + |Δx_j − u| for any vector u.
    ///   The usual test takes u = 0: 2 max |Δx| > s. Taking u at the centre of the box that
    ///   holds every Δx bounds it by the box's diagonal instead, which is smaller when the
    ///   bodies move the same way: in a hopper the fastest bodies all fall, and their fall
    ///   sets the usual test off at 0.6 of what the box allows (docs/performance.md). The box costs a pass over the bodies, so it is measured only
    ///   once the usual test has fired; the list is rebuilt when both exceed s.
    ///
    /// `max_disp2` is the largest squared displacement [m²], where the step's pass measured
    /// it. Where it did not, the bounds of [`ReachBound`] rule a build out, or else it is
    /// measured here. Either way the answer is the test's. Every measure taken without a
    /// build goes to the bounds.
    pub(super) fn lists_may_miss(&mut self, max_disp2: Option<f64>) -> bool {
        let s = &self.state;
        let max_disp2 = match max_disp2 {
            Some(d2) => d2,
            None if self.reach_bound.rules_out(s.skin, s.walls_moved(), 0.0) => return false,
            // The pass's guess of its reach fell short of it.
            None => largest_displacement(&s.particles.position, &s.reference).0,
        };
        let largest = max_disp2.sqrt();
        if s.walls_moved()
            .is_some_and(|drift| largest + drift > s.skin)
        {
            return true;
        }
        let diagonal = (2.0 * largest > s.skin)
            .then(|| displacement_box_diagonal(&s.particles.position, &s.reference));
        if diagonal.is_some_and(|b| b > s.skin) {
            return true;
        }
        self.reach_bound.measured(largest, diagonal);
        false
    }
}
