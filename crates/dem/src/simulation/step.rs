//! One step of velocity Verlet (docs/physics.md §6.2): kick, drift, rebuild when due, force
//! evaluation, kick; and the fused forms that do a step's second kick with the next step's
//! first kick and drift in one sweep over the bodies.

use super::*;

/// A step's second half kick ([`kick`], Δt/2 = `half` [s]), and the error for a velocity
/// it left non-finite at time `time` [s].
pub(super) fn second_kick(
    p: &mut ParticleSet,
    half: f64,
    uniform: Option<(f64, f64)>,
    time: f64,
) -> Result<(), DemError> {
    match kick(p, half, uniform) {
        true => Ok(()),
        false => non_finite_velocity(p, time).map_or(Ok(()), Err),
    }
}

/// The radius [m] and mass [kg] every particle shares, if they all do.
pub(super) fn uniform_body(p: &ParticleSet) -> Option<(f64, f64)> {
    let (&r, &m) = (p.radius.first()?, p.mass.first()?);
    (p.radius.iter().all(|&x| x == r) && p.mass.iter().all(|&x| x == m)).then_some((r, m))
}

/// Bodies beyond which a one-thread step does the next step's kicks and drift inside its
/// evaluation, chunk by chunk ([`Simulation::fuses_next_drift`]). Below it (the paper's
/// hopper) every body's numbers stay in the caches between the evaluation and a separate
/// pass, and the chunks would only add their fixed costs. Above it a separate pass would
/// stream every body from memory again, at the memory's full rate; done inside the
/// evaluation, it overlaps the evaluation's waits on partner bodies (docs/performance.md).
pub(super) const FUSE_BODIES: usize = 1 << 15;

/// What a kick-and-drift pass found ([`kick_drift`]).
#[derive(Debug, Clone, Copy)]
pub(super) struct Drift {
    /// Largest squared displacement since the last list build [m²], where it was measured.
    pub(super) max_disp2: Option<f64>,
    /// Every displacement was finite.
    pub(super) finite: bool,
    /// The deferred kick left every velocity and spin finite.
    pub(super) kicked_finite: bool,
}

impl From<(f64, bool, bool)> for Drift {
    fn from((max_disp2, finite, kicked_finite): (f64, bool, bool)) -> Self {
        Self {
            max_disp2: Some(max_disp2),
            finite,
            kicked_finite,
        }
    }
}

/// How a step ends ([`Simulation::advance`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum StepEnd {
    /// With its second half kick: velocities at the full step (the last step of a run).
    Kick,
    /// With its second half kick left to the next step's pass, and, where the engine fuses
    /// them ([`Simulation::fuses_next_drift`]), the next step's kicks and drift done inside
    /// this step's evaluation.
    Fused,
    /// With its second half kick left to the next step's pass, and the bodies at this step:
    /// for a caller that looks at them in between ([`Simulation::run_watched`]).
    Pending,
}

impl Simulation {
    /// Advances one step of velocity Verlet (docs/physics.md §6.2).
    pub fn step(&mut self) -> Result<(), DemError> {
        self.advance(false, StepEnd::Kick, None).map(|_| ())
    }

    /// One step. `kick_pending`: the previous step left its second half kick undone, to be
    /// done here in the same pass as this step's first half kick and drift. `end`: how the
    /// step ends ([`StepEnd`]; unless it kicks, the next call must be pending).
    /// `drifted`: the previous step already did this step's kicks and drift, body chunk by
    /// body chunk inside its evaluation, and this is what that pass found.
    ///
    /// The fused pass performs the same additions in the same order as two separate
    /// passes, so the trajectory is bit-identical; it only saves a sweep over the particles.
    /// Returns what the next step's kicks and drift found when this step did them (see
    /// [`Simulation::fuses_next_drift`]).
    pub(super) fn advance(
        &mut self,
        kick_pending: bool,
        end: StepEnd,
        drifted: Option<Drift>,
    ) -> Result<Option<Drift>, DemError> {
        if let Some(cause) = &self.failure {
            return Err(DemError::AfterFailure {
                time: self.state.time,
                cause: cause.clone(),
            });
        }
        // A set-up refused here (time step, materials) has changed nothing: the caller may
        // mend it and step again.
        if !self.prepared {
            self.prepare()?;
        }
        let stepped = self.advance_prepared(kick_pending, end, drifted);
        if let Err(e) = &stepped {
            self.failure = Some(Box::new(e.clone()));
        }
        stepped
    }

    /// [`Simulation::advance`] once the simulation is prepared. An error from here on comes
    /// after the first kick and drift, or after some chunks of bodies have moved on
    /// ([`Simulation::evaluate_and_drift`]): the step is left half done.
    pub(super) fn advance_prepared(
        &mut self,
        kick_pending: bool,
        end: StepEnd,
        drifted: Option<Drift>,
    ) -> Result<Option<Drift>, DemError> {
        let mut clock = StepClock::start(self.phase_times.is_some());
        let dt = self.state.config.time_step;
        let half = 0.5 * dt;
        // The walls move to the end of the step first: the forces are evaluated there.
        self.move_walls(dt);
        let p = &mut self.state.particles;

        // First half kick and drift, tracking the largest displacement since the last build.
        let reference_valid = self.state.reference.len() == p.len();
        let drift = match drifted {
            Some(drift) => {
                self.reach_bound.forget();
                drift
            }
            None => {
                if !reference_valid {
                    // The list is rebuilt below anyway; a reference is needed only to
                    // measure from.
                    self.state.reference.clear();
                    self.state.reference.extend_from_slice(&p.position);
                }
                match self.uniform_free {
                    // Bodies alike: the displacements are measured only where the bounds
                    // cannot rule a list build out.
                    Some(uniform) => {
                        let s = &mut self.state;
                        let ahead = self.reach_bound.next_reach();
                        let measure = !self.reach_bound.rules_out(s.skin, s.walls_moved(), ahead);
                        let moved = kick_drift_flat_tracked(
                            &mut s.particles,
                            &s.reference,
                            (half, dt),
                            kick_pending,
                            uniform,
                            (s.config.gravity, measure),
                            self.pool.as_deref(),
                        );
                        self.reach_bound.step(moved.reach);
                        Drift {
                            max_disp2: moved.max_disp2,
                            finite: moved.finite,
                            kicked_finite: moved.kicked_finite,
                        }
                    }
                    None => {
                        self.reach_bound.forget();
                        Drift::from(kick_drift(
                            p,
                            &self.state.reference,
                            (half, dt),
                            kick_pending,
                            self.uniform_free,
                            self.state.config.gravity,
                            self.pool.as_deref(),
                        ))
                    }
                }
            }
        };
        let drift = self.drift_clumps(drift, (half, dt));
        self.check_drift(drift)?;
        StepClock::mark(&mut clock, Mark::Drifted);
        if self.state.needs_rebuild || !reference_valid || self.lists_may_miss(drift.max_disp2) {
            self.rebuild(None);
        }
        StepClock::mark(&mut clock, Mark::Listed);
        // The external force of a region, onto the weights the drift left (docs/physics.md
        // §6.4); without one the step is the same arithmetic as ever.
        if let Some(force) = &self.region_force {
            force.apply(&mut self.state.particles, &self.state.clumps);
        }

        // Forces at the drifted positions with half-step velocities, summed onto the weights
        // and zero torques that the pass above left in the particles' arrays (a list build
        // permutes them with the particles).
        let next = if end == StepEnd::Fused && self.fuses_next_drift() {
            let next = self.evaluate_and_drift((half, dt))?;
            StepClock::mark(&mut clock, Mark::Forced);
            Some(next)
        } else {
            let eval = self.evaluate_forces(dt, None);
            let pool = self.pool.as_deref();
            let s = &mut self.state;
            StepClock::mark(&mut clock, Mark::Forced);
            check_overlaps(s, &eval)?;
            s.contacts = eval.count;
            // The clumps take their members' forces and their whole second kick now, whether
            // or not the spheres' kick waits for the next step.
            let gravity = s.config.gravity;
            if !s.clumps.is_empty() && !s.clumps.gather_kick(&mut s.particles, gravity, half, pool)
            {
                return Err(non_finite_velocity(&s.particles, s.time).unwrap_or(
                    DemError::InvalidInput("a clump's velocity is not finite".into()),
                ));
            }

            // Second half kick, unless the next step does it.
            if end == StepEnd::Kick {
                second_kick(&mut s.particles, half, self.uniform_free, s.time)?;
            }
            None
        };
        self.keep_wall_loads(dt);
        let s = &mut self.state;
        s.steps += 1;
        s.time = s.steps as f64 * dt;
        if let Some(times) = &mut self.phase_times {
            StepClock::finish(clock, times);
        }
        Ok(next)
    }

    /// The clumps' half kick, drift and turn, and their members placed (docs/physics.md
    /// §11.4), folded into what the spheres' pass found.
    fn drift_clumps(&mut self, drift: Drift, step: (f64, f64)) -> Drift {
        let s = &mut self.state;
        if s.clumps.is_empty() {
            return drift;
        }
        let pool = self.pool.as_deref();
        let (worst, finite) = s
            .clumps
            .kick_drift(&mut s.particles, &s.reference, step, pool);
        Drift {
            max_disp2: drift.max_disp2.map(|d| d.max(worst)),
            finite: drift.finite && finite,
            kicked_finite: drift.kicked_finite,
        }
    }

    /// Whether a step that defers its second half kick also does the next step's kicks and
    /// drift, inside its evaluation ([`Simulation::evaluate_and_drift`]): on one thread, for
    /// the paper's laws, and for systems of more than [`FUSE_BODIES`] bodies.
    pub(super) fn fuses_next_drift(&self) -> bool {
        self.pool.is_none()
            && self.state.clumps.is_empty()
            && self.state.particles.len() > FUSE_BODIES
            && self.state.config.laws == ContactLaws::default()
            && !self.wall_bonds
    }

    /// The evaluation of the step's forces cut into chunks of bodies
    /// ([`forces::evaluate_chunk`]), each chunk, once its forces are whole, given the
    /// next step's deferred and first half kicks and its drift
    /// ([`crate::integrator::kick_drift_range`]), while its numbers are in the cache.
    ///
    /// Every body gets the additions, and then the kicks and drift, of the separate
    /// evaluation and pass, in the same order: the trajectory is bit-identical to theirs and
    /// so to that on any number of threads. Each chunk's overlaps are checked before its
    /// bodies move, so an overlap error reports the positions it was found at; it names the
    /// worst contact of the first chunk that has one too deep, and the bodies of the
    /// chunks before it have then already moved on, which is why a failed step refuses
    /// every later one ([`DemError::AfterFailure`]).
    pub(super) fn evaluate_and_drift(&mut self, (half, dt): (f64, f64)) -> Result<Drift, DemError> {
        let n = self.state.particles.len();
        let mut eval = forces::Evaluation::default();
        let mut drift = NOTHING_MOVED;
        for bodies in forces::chunk_bounds(n) {
            let part = self.evaluate_forces(dt, Some(bodies.clone()));
            let s = &mut self.state;
            check_overlaps(s, &part)?;
            eval = eval.merge(part);
            let moved = kick_drift_range(
                &mut s.particles,
                &s.reference,
                bodies,
                (half, dt),
                true,
                self.uniform_free,
                s.config.gravity,
            );
            drift = merge_drift(drift, moved);
        }
        self.state.contacts = eval.count;
        Ok(Drift::from(drift))
    }

    /// The step's forces at the current positions, summed onto the weights and zero torques
    /// in the particles' arrays, which are lent to the evaluation and come back right after
    /// it: for every body ([`forces::evaluate`], on the pool if there is one), or only for
    /// the chunk `bodies` ([`forces::evaluate_chunk`]).
    pub(super) fn evaluate_forces(
        &mut self,
        dt: f64,
        bodies: Option<Range<usize>>,
    ) -> forces::Evaluation {
        let s = &mut self.state;
        std::mem::swap(&mut s.particles.force, &mut self.buffers.force);
        std::mem::swap(&mut s.particles.torque, &mut self.buffers.torque);
        let input = KernelInput {
            particles: &s.particles,
            laws: &s.config.laws,
            pair_coeffs: &self.pair_coeffs,
            materials: s.materials.len(),
            walls: &s.walls,
            wall_coeffs: &self.wall_coeffs,
            bond_tables: &self.bond_tables,
            uniform_body: self.uniform_body,
            dt,
            quanta: self.load_quanta,
            pair_bonds: self.pair_bonds,
            wall_bonds: self.wall_bonds,
            area_cohesion: self.area_cohesion,
            reach: s.list_reach,
        };
        let (pairs, walls, buffers) = (&mut s.pairs, &mut s.wall_pairs, &mut self.buffers);
        if bodies.as_ref().is_none_or(|b| b.start == 0) {
            forces::start_loads(buffers, s.walls.len());
        }
        let elements = &mut s.surface_loads;
        let eval = match bodies {
            None => forces::evaluate(
                &input,
                pairs,
                walls,
                buffers,
                self.pool.as_deref(),
                elements,
            ),
            Some(bodies) => forces::evaluate_chunk(&input, pairs, walls, buffers, bodies, elements),
        };
        std::mem::swap(&mut s.particles.force, &mut self.buffers.force);
        std::mem::swap(&mut s.particles.torque, &mut self.buffers.torque);
        eval
    }

    /// The second half kick that a watched step left pending, alone: what the last step of
    /// a `run` does.
    pub(super) fn finish_kick(&mut self) -> Result<(), DemError> {
        let half = 0.5 * self.state.config.time_step;
        let s = &mut self.state;
        let kicked = second_kick(&mut s.particles, half, self.uniform_free, s.time);
        if let Err(e) = &kicked {
            self.failure = Some(Box::new(e.clone()));
        }
        kicked
    }
}
