//! Running many steps: plain runs, and runs watched between steps by a callback on another
//! thread while the next steps go on.

use super::*;
use crate::contacts::ContactSource;

impl Simulation {
    /// Takes `n` steps, each one's second half kick fused with the next one's first.
    ///
    /// Bit-identical to `n` calls of [`Simulation::step`]. If a step fails, every kick
    /// before the failing step was applied, as with `step`; a non-finite velocity is
    /// reported half a step later than `step` reports it, by the next step's pass.
    pub fn run(&mut self, n: u64) -> Result<(), DemError> {
        // `run_watched` with one stretch of n steps and a look that does nothing.
        self.run_watched(n, n, |_| Ok::<(), DemError>(()))
    }

    /// The simulation's team of threads, if it has one, for callers that alternate short
    /// [`Simulation::run`]s with work of their own (a run protocol measuring the outlet every
    /// few steps). Such a caller does better to run its whole loop inside the team
    /// ([`Team::install`]): each `run` then starts on a team thread at once, instead of
    /// handing its steps over to one and waiting for them. Changes no result, only which
    /// thread does the work.
    pub fn pool_handle(&self) -> Option<Arc<Team>> {
        self.pool.clone()
    }

    /// Takes `n` steps and calls `watch` after every `every` of them and after the last,
    /// with a view of the bodies at that step ([`Watched`]: positions, and velocities at
    /// the full step). Stops at the first error, of a step or of `watch`.
    ///
    /// Bit-identical to [`Simulation::run`]`(every)` repeated, with a look at
    /// [`Simulation::watched`] after each, and cheaper: `run` ends with its last step's
    /// second half kick, a pass over every body, so that velocities are at the full step;
    /// here that kick stays pending into the next step's pass (as it does between the steps
    /// of one `run`), and the view adds it to each velocity it is asked for (the same
    /// product and sum, so the same bits). A run protocol that looks at the outlet every
    /// ten steps would spend about 1 % of its time on those passes. After the call, as
    /// after `run`, every kick is done.
    pub fn run_watched<E: From<DemError> + Send>(
        &mut self,
        n: u64,
        every: u64,
        watch: impl FnMut(&Watched<'_>) -> Result<(), E> + Send,
    ) -> Result<(), E> {
        match self.pool.clone() {
            // The steps are driven from one of the pool's own threads, so that each step's
            // parallel evaluation starts inside the pool. Called from outside, every step
            // would hand its work to a sleeping worker and sleep until it came back: two
            // thread wake-ups per step, which cost more than the evaluation of a
            // few-thousand-particle system gains from a second thread.
            Some(pool) => pool.install(|| self.run_watched_here(n, every, watch)),
            None => self.run_watched_here(n, every, watch),
        }
    }

    /// The loop of [`Simulation::run_watched`], on the calling thread.
    pub(super) fn run_watched_here<E: From<DemError>>(
        &mut self,
        n: u64,
        every: u64,
        mut watch: impl FnMut(&Watched<'_>) -> Result<(), E>,
    ) -> Result<(), E> {
        let every = every.max(1);
        let (mut done, mut pending) = (0, false);
        while done < n {
            let m = every.min(n - done);
            let mut drifted = None;
            for k in 0..m {
                let end = match (k + 1 == m, done + m == n) {
                    (false, _) => StepEnd::Fused,
                    (true, true) => StepEnd::Kick,
                    (true, false) => StepEnd::Pending,
                };
                drifted = self.advance(pending, end, drifted)?;
                pending = end != StepEnd::Kick;
            }
            done += m;
            if let Err(e) = watch(&self.watched_with(pending)) {
                // Leave the state as `run` leaves it: every kick done.
                if pending {
                    self.finish_kick()?;
                }
                return Err(e);
            }
        }
        Ok(())
    }

    /// The bodies as [`Simulation::run_watched`] shows them, for a caller that looks at a
    /// simulation between runs, whose velocities are at the full step.
    pub fn watched(&self) -> Watched<'_> {
        self.watched_with(false)
    }

    /// The view, with this step's second half kick still to add (`pending`) or not.
    pub(super) fn watched_with(&self, pending: bool) -> Watched<'_> {
        let half = 0.5 * self.state.config.time_step;
        Watched::new(
            (&self.state.particles, &self.state.clumps),
            self.state.time,
            (
                &self.state.walls,
                &self.wall_loads,
                &self.state.wall_impulses,
            ),
            pending.then_some((half, self.uniform_free)),
            (self.prepared && !self.state.needs_rebuild).then_some(ContactSource {
                laws: self.state.config.laws,
                pair_coeffs: &self.pair_coeffs,
                wall_coeffs: &self.wall_coeffs,
                materials: self.state.materials.len(),
                pairs: &self.state.pairs,
                wall_pairs: &self.state.wall_pairs,
                reach: self.state.list_reach,
                kicked: (!pending).then_some(half),
            }),
        )
    }
}
