//! The simulation: one owner of the whole state, advanced by velocity Verlet (physics.md §6.2).

use std::ops::Range;
use std::sync::Arc;

use glam::DVec3;
use serde::{Deserialize, Serialize};

use crate::contact::{normal::hertz_energy, ContactLaws};
use crate::error::DemError;
use crate::forces::{self, ContactCount, ForceBuffers, KernelInput, WorstOverlap};
use crate::integrator::{
    displacement_box_diagonal, kick, kick_drift, kick_drift_measured, kick_drift_range,
    largest_displacement, merge_drift, uniform_free_body, NOTHING_MOVED,
};
use crate::material::{harmonic, Interaction, Material, PairCoefficients};
use crate::neighbour::{build_lists, Carry, CellGrid, ListScratch, PairList, WallPairList};
use crate::particles::{MaterialId, ParticleInit, ParticleSet, ParticleTag};
use crate::reach::ReachBound;
use crate::timescale::rayleigh_time;
use crate::timing::{Mark, PhaseTimes, StepClock};
use crate::wall::{Wall, WallId};
use crate::watch::Watched;

/// Settings fixed for a run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SimulationConfig {
    /// Time step Δt [s]. The paper's base case uses 2.5e-6 s = 0.097 t_R (physics.md §6.1).
    pub time_step: f64,
    /// Gravitational acceleration [m/s²]; z is vertical, so (0, 0, −9.81) on Earth.
    pub gravity: DVec3,
    /// Contact sub-models.
    pub laws: ContactLaws,
    /// Verlet skin [m]; 0 picks 0.2 × the largest radius when the first list is built.
    pub skin: f64,
    /// Largest accepted Δt / t_R [-]. EDEM's guidance is 0.1–0.4; the paper stays below 0.1.
    pub max_rayleigh_fraction: f64,
    /// Largest accepted overlap as a fraction of the smaller radius [-]; beyond it the run stops.
    pub max_overlap_fraction: f64,
    /// Worker threads for force evaluation; 0 uses every core, 1 runs without a pool.
    pub threads: usize,
    /// Re-sort particles into cell order every this many list rebuilds (0: never).
    pub resort_every: u32,
}

impl SimulationConfig {
    /// Defaults around a time step `time_step` [s]: Earth gravity along −z, the paper's laws.
    pub fn new(time_step: f64) -> Self {
        Self {
            time_step,
            gravity: DVec3::new(0.0, 0.0, -9.81),
            laws: ContactLaws::default(),
            skin: 0.0,
            // 0.25 t_R leaves room for verification runs at coarser steps while refusing the
            // clearly unstable ones; production runs use 0.097.
            max_rayleigh_fraction: 0.25,
            // Hopper impacts at 3 m/s overlap by ≈ 3 % of the radius (physics.md §1.1); 10 % means
            // something is wrong.
            max_overlap_fraction: 0.1,
            threads: 1,
            resort_every: 16,
        }
    }
}

/// Everything that defines the state of a run; serialisable for checkpoints, so that a
/// resumed run is bit-identical to an uninterrupted one.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SimulationState {
    config: SimulationConfig,
    materials: Vec<Material>,
    interactions: Vec<Option<Interaction>>,
    particles: ParticleSet,
    walls: Vec<Option<Wall>>,
    pairs: PairList,
    wall_pairs: WallPairList,
    /// Positions at the last list build [m].
    reference: Vec<DVec3>,
    /// Largest wall displacement since the last build [m].
    wall_drift: f64,
    skin: f64,
    time: f64,
    steps: u64,
    rebuilds: u64,
    needs_rebuild: bool,
    indices_changed: bool,
    contacts: ContactCount,
}

impl SimulationState {
    /// How far the walls have moved since the last list build [m], where there are walls:
    /// the wall branch of the list-build test (`Simulation::lists_may_miss`).
    fn walls_moved(&self) -> Option<f64> {
        self.walls
            .iter()
            .any(Option::is_some)
            .then_some(self.wall_drift)
    }
}

/// A DEM simulation of spheres and walls.
pub struct Simulation {
    state: SimulationState,
    pool: Option<Arc<rayon::ThreadPool>>,
    grid: CellGrid,
    buffers: ForceBuffers,
    pair_coeffs: Vec<PairCoefficients>,
    wall_coeffs: Vec<PairCoefficients>,
    /// Radius [m] and mass [kg] shared by every particle, when they are all alike; found at
    /// each list rebuild (which every addition or removal of a particle forces).
    uniform_body: Option<(f64, f64)>,
    /// 1/m [1/kg] and 1/I [1/(kg m²)] shared by every particle when all are alike and free
    /// (`integrator::uniform_free_body`); found with `uniform_body`, and after a change of flags.
    uniform_free: Option<(f64, f64)>,
    prepared: bool,
    /// Time per phase since timing was switched on; `None` while off.
    phase_times: Option<PhaseTimes>,
    /// The lists before the last build, kept for their allocations: the next build writes
    /// into them, instead of growing fresh vectors to some 10^4 candidates at every build.
    spare_lists: (PairList, WallPairList),
    /// Bounds on the displacements since the last build, which spare the exact measures
    /// where they rule a build out ([`ReachBound`]); not part of the state: a restored
    /// simulation measures until its first build.
    reach_bound: ReachBound,
    /// The list builds' working arrays, kept for their memory ([`ListScratch`]).
    list_scratch: ListScratch,
    /// The error that stopped a step after it had begun to move bodies: every later step is
    /// refused with [`DemError::AfterFailure`], since the state is no longer one instant's.
    /// Not part of the state: a simulation restored from a checkpoint starts without it.
    failure: Option<Box<DemError>>,
}

/// Energy budget of the system [J].
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Energy {
    /// Σ ½ m v² [J].
    pub translational: f64,
    /// Σ ½ I ω² [J].
    pub rotational: f64,
    /// Σ −m g·x [J] (zero at the origin).
    pub gravitational: f64,
    /// Elastic energy of the normal Hertz springs, Σ (8/15) E* √R* δ^{5/2} [J].
    pub elastic: f64,
}

impl Energy {
    /// Total mechanical energy [J].
    pub fn total(&self) -> f64 {
        self.translational + self.rotational + self.gravitational + self.elastic
    }
}

/// A particle taken out of the simulation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RemovedParticle {
    /// Its tag.
    pub tag: ParticleTag,
    /// Position when removed [m].
    pub position: DVec3,
    /// Velocity when removed [m/s].
    pub velocity: DVec3,
    /// Mass [kg].
    pub mass: f64,
}

fn make_pool(threads: usize) -> Result<Option<Arc<rayon::ThreadPool>>, DemError> {
    if threads == 1 {
        return Ok(None);
    }
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map(|pool| Some(Arc::new(pool)))
        .map_err(|_| DemError::ThreadPool(threads))
}

impl Simulation {
    /// An empty simulation.
    pub fn new(config: SimulationConfig) -> Result<Self, DemError> {
        if !(config.time_step.is_finite() && config.time_step > 0.0) {
            return Err(DemError::InvalidInput(format!(
                "time step must be positive and finite, got {}",
                config.time_step
            )));
        }
        if !config.gravity.is_finite() {
            return Err(DemError::InvalidInput(format!(
                "gravity must be finite, got {}",
                config.gravity
            )));
        }
        // `!(x >= 0)` and `!(x > 0)` also refuse NaN, which every comparison would let pass.
        if !(config.skin >= 0.0 && config.skin.is_finite()) {
            return Err(DemError::InvalidInput(format!(
                "skin must be finite and ≥ 0 (0 picks 0.2 × the largest radius), got {}",
                config.skin
            )));
        }
        if !(config.max_overlap_fraction > 0.0) {
            return Err(DemError::InvalidInput(format!(
                "overlap limit (max_overlap_fraction) must be > 0, got {}",
                config.max_overlap_fraction
            )));
        }
        if !(config.max_rayleigh_fraction > 0.0) {
            // A NaN limit would switch the Rayleigh guard off without a word.
            return Err(DemError::InvalidInput(format!(
                "time-step limit (max_rayleigh_fraction) must be > 0, got {}",
                config.max_rayleigh_fraction
            )));
        }
        let state = SimulationState {
            config,
            materials: Vec::new(),
            interactions: Vec::new(),
            particles: ParticleSet::default(),
            walls: Vec::new(),
            pairs: PairList::default(),
            wall_pairs: WallPairList::default(),
            reference: Vec::new(),
            wall_drift: 0.0,
            skin: config.skin,
            time: 0.0,
            steps: 0,
            rebuilds: 0,
            needs_rebuild: true,
            indices_changed: false,
            contacts: ContactCount::default(),
        };
        Self::from_state(state, config.threads)
    }

    /// Restores a saved state with `threads` worker threads (0 = every core).
    pub fn from_state(mut state: SimulationState, threads: usize) -> Result<Self, DemError> {
        // Checkpoints from before the wall-major candidate order hold particle-major lists.
        state.wall_pairs = std::mem::take(&mut state.wall_pairs).into_wall_major();
        Ok(Self {
            pool: make_pool(threads)?,
            state,
            grid: CellGrid::default(),
            buffers: ForceBuffers::default(),
            pair_coeffs: Vec::new(),
            wall_coeffs: Vec::new(),
            uniform_body: None,
            uniform_free: None,
            prepared: false,
            phase_times: None,
            spare_lists: Default::default(),
            reach_bound: ReachBound::default(),
            list_scratch: ListScratch::default(),
            failure: None,
        })
    }

    /// Switches the per-phase timing of steps on (from zero) or off. It reads the clock and
    /// changes nothing else: trajectories are bit-identical either way.
    pub fn time_phases(&mut self, on: bool) {
        self.phase_times = on.then(PhaseTimes::default);
    }

    /// Wall-clock time per phase of the steps taken since [`Simulation::time_phases`]
    /// switched timing on; `None` while it is off.
    pub fn phase_times(&self) -> Option<PhaseTimes> {
        self.phase_times
    }

    /// The complete state, for checkpoints.
    pub fn state(&self) -> &SimulationState {
        &self.state
    }

    /// Changes the number of worker threads (results do not depend on it).
    pub fn set_threads(&mut self, threads: usize) -> Result<(), DemError> {
        self.pool = make_pool(threads)?;
        self.state.config.threads = threads;
        Ok(())
    }

    /// Registers a material and how it interacts with itself.
    pub fn add_material(
        &mut self,
        material: Material,
        self_interaction: Interaction,
    ) -> Result<MaterialId, DemError> {
        let fault = if !(material.density > 0.0 && material.density.is_finite()) {
            Some((
                "density",
                material.density,
                "must be positive and finite [kg/m³]",
            ))
        } else if !(material.youngs_modulus > 0.0 && material.youngs_modulus.is_finite()) {
            Some((
                "Young's modulus",
                material.youngs_modulus,
                "must be positive and finite [Pa]",
            ))
        } else if !(material.poisson_ratio > -1.0 && material.poisson_ratio < 0.5) {
            Some((
                "Poisson ratio",
                material.poisson_ratio,
                "must be in (-1, 0.5)",
            ))
        } else {
            None
        };
        if let Some((what, value, range)) = fault {
            return Err(DemError::InvalidInput(format!(
                "unphysical material: {what} {value} {range}; got {material:?}"
            )));
        }
        check_interaction(&self_interaction)?;
        let s = &mut self.state;
        let old = s.materials.len();
        let n = old + 1;
        let mut table = vec![None; n * n];
        for a in 0..old {
            for b in 0..old {
                table[a * n + b] = s.interactions[a * old + b];
            }
        }
        table[old * n + old] = Some(self_interaction);
        s.materials.push(material);
        s.interactions = table;
        self.prepared = false;
        Ok(MaterialId(old as u16))
    }

    /// Sets how two different materials interact.
    pub fn set_interaction(
        &mut self,
        a: MaterialId,
        b: MaterialId,
        interaction: Interaction,
    ) -> Result<(), DemError> {
        check_interaction(&interaction)?;
        let n = self.state.materials.len();
        if let Some(unknown) = [a, b].into_iter().find(|m| m.0 as usize >= n) {
            return Err(DemError::InvalidInput(format!(
                "unknown material {}: {n} material(s) are registered",
                unknown.0
            )));
        }
        self.state.interactions[a.0 as usize * n + b.0 as usize] = Some(interaction);
        self.state.interactions[b.0 as usize * n + a.0 as usize] = Some(interaction);
        self.prepared = false;
        Ok(())
    }

    /// Adds a particle; its initial force is its weight.
    pub fn add_particle(&mut self, init: ParticleInit) -> Result<ParticleTag, DemError> {
        let Some(mat) = self.state.materials.get(init.material.0 as usize) else {
            return Err(DemError::InvalidInput(format!(
                "unknown material {}: {} material(s) are registered",
                init.material.0,
                self.state.materials.len()
            )));
        };
        if !(init.radius > 0.0 && init.radius.is_finite())
            || !init.position.is_finite()
            || !init.velocity.is_finite()
            || !init.angular_velocity.is_finite()
        {
            return Err(DemError::InvalidInput(format!(
                "particle radius must be positive and the state finite: {init:?}"
            )));
        }
        let density = mat.density;
        let g = self.state.config.gravity;
        let p = &mut self.state.particles;
        let tag = p.push(&init, density);
        let k = p.len() - 1;
        p.force[k] = p.mass[k] * g;
        self.state.needs_rebuild = true;
        self.prepared = false;
        Ok(tag)
    }

    /// Removes every particle for which `remove(index, particles)` is true and returns them.
    pub fn remove_particles(
        &mut self,
        mut remove: impl FnMut(usize, &ParticleSet) -> bool,
    ) -> Vec<RemovedParticle> {
        let p = &self.state.particles;
        let keep: Vec<bool> = (0..p.len()).map(|k| !remove(k, p)).collect();
        if keep.iter().all(|&k| k) {
            return Vec::new();
        }
        let removed = (0..p.len())
            .filter(|&k| !keep[k])
            .map(|k| RemovedParticle {
                tag: p.tag[k],
                position: p.position[k],
                velocity: p.velocity[k],
                mass: p.mass[k],
            })
            .collect();
        // The survivors' contact memory follows them across the change of indices: new
        // body k was body `origin[k]`.
        let origin: Vec<u32> = (0..keep.len() as u32)
            .filter(|&k| keep[k as usize])
            .collect();
        self.state.particles.retain_mask(&keep);
        self.rebuild(Some(&origin));
        removed
    }

    /// Adds a wall; returns its handle.
    pub fn add_wall(&mut self, wall: Wall) -> WallId {
        self.state.walls.push(Some(wall));
        self.state.needs_rebuild = true;
        self.prepared = false;
        WallId(self.state.walls.len() as u32 - 1)
    }

    /// Removes a wall (a hopper's gate, say).
    pub fn remove_wall(&mut self, id: WallId) -> Result<Wall, DemError> {
        let slot = self
            .state
            .walls
            .get_mut(id.0 as usize)
            .ok_or(DemError::UnknownWall(id.0))?;
        let wall = slot.take().ok_or(DemError::UnknownWall(id.0))?;
        self.state.needs_rebuild = true;
        Ok(wall)
    }

    /// Moves a wall rigidly by `offset` [m].
    pub fn translate_wall(&mut self, id: WallId, offset: DVec3) -> Result<(), DemError> {
        let wall = self
            .state
            .walls
            .get_mut(id.0 as usize)
            .and_then(Option::as_mut)
            .ok_or(DemError::UnknownWall(id.0))?;
        wall.translate(offset);
        self.state.wall_drift += offset.length();
        Ok(())
    }

    /// Sets the velocity a wall shows to the contact law [m/s] (it does not move it).
    pub fn set_wall_velocity(&mut self, id: WallId, velocity: DVec3) -> Result<(), DemError> {
        let wall = self
            .state
            .walls
            .get_mut(id.0 as usize)
            .and_then(Option::as_mut)
            .ok_or(DemError::UnknownWall(id.0))?;
        wall.velocity = velocity;
        Ok(())
    }

    /// A wall by handle.
    pub fn wall(&self, id: WallId) -> Option<&Wall> {
        self.state.walls.get(id.0 as usize).and_then(Option::as_ref)
    }

    /// The particles (read-only; probes observe, never mutate).
    pub fn particles(&self) -> &ParticleSet {
        &self.state.particles
    }

    /// Sets the velocity and spin of particle `index` (test set-ups).
    pub fn set_particle_motion(&mut self, index: usize, velocity: DVec3, angular_velocity: DVec3) {
        self.state.particles.velocity[index] = velocity;
        self.state.particles.omega[index] = angular_velocity;
    }

    /// Sets the flags of particle `index` (`FLAG_*`).
    pub fn set_particle_flags(&mut self, index: usize, flags: u8) {
        self.state.particles.flags[index] = flags;
        // The integrator's shared-body form holds only while no particle has flags.
        self.prepared = false;
    }

    /// The configuration.
    pub fn config(&self) -> &SimulationConfig {
        &self.state.config
    }

    /// Simulated time [s].
    pub fn time(&self) -> f64 {
        self.state.time
    }

    /// Steps taken.
    pub fn steps(&self) -> u64 {
        self.state.steps
    }

    /// Neighbour-list builds so far.
    pub fn rebuilds(&self) -> u64 {
        self.state.rebuilds
    }

    /// Contacts that carried force in the last step.
    pub fn contacts(&self) -> ContactCount {
        self.state.contacts
    }

    /// The smallest Rayleigh time of the particles present [s] (paper Eq. 9).
    pub fn rayleigh_time(&self) -> Option<f64> {
        let p = &self.state.particles;
        (0..p.len())
            .map(|k| rayleigh_time(&self.state.materials[p.material[k] as usize], p.radius[k]))
            .min_by(f64::total_cmp)
    }

    /// Mixes coefficients and checks Δt; runs before a step whenever the set-up changed.
    fn prepare(&mut self) -> Result<(), DemError> {
        let s = &self.state;
        let n = s.materials.len();
        self.pair_coeffs.clear();
        for a in 0..n {
            for b in 0..n {
                let c = match s.interactions[a * n + b] {
                    Some(i) => PairCoefficients::new(&s.materials[a], Some(&s.materials[b]), &i),
                    // Never read unless the two materials meet; checked below.
                    None => PairCoefficients::new(&s.materials[a], None, &Interaction::fan2023()),
                };
                self.pair_coeffs.push(c);
            }
        }
        let mut present = vec![false; n];
        for &m in &s.particles.material {
            present[m as usize] = true;
        }
        for a in 0..n {
            for b in 0..n {
                if present[a] && present[b] && s.interactions[a * n + b].is_none() {
                    return Err(DemError::MissingInteraction(a as u16, b as u16));
                }
            }
        }
        self.wall_coeffs.clear();
        for w in &s.walls {
            for m in &s.materials {
                self.wall_coeffs.push(match w {
                    Some(w) => PairCoefficients::with_wall(m, &w.material, &w.interaction),
                    None => PairCoefficients::new(m, None, &Interaction::fan2023()),
                });
            }
        }
        if let Some(t_r) = self.rayleigh_time() {
            let fraction = s.config.time_step / t_r;
            if fraction > s.config.max_rayleigh_fraction {
                return Err(DemError::TimeStepTooLarge {
                    time_step: s.config.time_step,
                    rayleigh_time: t_r,
                    fraction,
                    max_fraction: s.config.max_rayleigh_fraction,
                });
            }
        }
        self.uniform_body = uniform_body(&s.particles);
        self.uniform_free = uniform_free_body(&s.particles);
        self.prepared = true;
        Ok(())
    }

    /// Rebuilds the neighbour lists, carrying contact history over; `moved` says where the
    /// bodies came from when their indices changed since the last build (new body k was
    /// body `moved[k]`).
    fn rebuild(&mut self, moved: Option<&[u32]>) {
        let s = &mut self.state;
        let r_max = s.particles.radius.iter().copied().fold(0.0, f64::max);
        if s.skin == 0.0 {
            s.skin = 0.2 * r_max;
        }
        let cell = 2.0 * r_max + s.skin;
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
        self.grid
            .rebuild(&s.particles.position, cell.max(f64::MIN_POSITIVE));
        // `build_lists` clears what it writes into; only the capacity of the spares is reused.
        let old_pairs = std::mem::replace(&mut s.pairs, std::mem::take(&mut self.spare_lists.0));
        let old_walls =
            std::mem::replace(&mut s.wall_pairs, std::mem::take(&mut self.spare_lists.1));
        build_lists(
            &self.grid,
            &s.particles,
            &s.walls,
            s.skin,
            &old_pairs,
            &old_walls,
            carry,
            (&mut s.pairs, &mut s.wall_pairs),
            &mut self.list_scratch,
        );
        self.spare_lists = (old_pairs, old_walls);
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

    /// Advances one step of velocity Verlet (physics.md §6.2).
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
    fn advance(
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
    fn advance_prepared(
        &mut self,
        kick_pending: bool,
        end: StepEnd,
        drifted: Option<Drift>,
    ) -> Result<Option<Drift>, DemError> {
        let mut clock = StepClock::start(self.phase_times.is_some());
        let dt = self.state.config.time_step;
        let half = 0.5 * dt;
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
                match self.uniform_free.filter(|_| self.pool.is_none()) {
                    // One thread, bodies alike: the displacements are measured only where
                    // the bounds cannot rule a list build out.
                    Some(uniform) => {
                        let s = &mut self.state;
                        let ahead = self.reach_bound.next_reach();
                        let measure = !self.reach_bound.rules_out(s.skin, s.walls_moved(), ahead);
                        let moved = kick_drift_measured(
                            &mut s.particles,
                            &s.reference,
                            (half, dt),
                            kick_pending,
                            uniform,
                            s.config.gravity,
                            measure,
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
        self.check_drift(drift)?;
        StepClock::mark(&mut clock, Mark::Drifted);
        if self.state.needs_rebuild || !reference_valid || self.lists_may_miss(drift.max_disp2) {
            self.rebuild(None);
        }
        StepClock::mark(&mut clock, Mark::Listed);

        // Forces at the drifted positions with half-step velocities, summed onto the weights
        // and zero torques that the pass above left in the particles' arrays (a list build
        // permutes them with the particles).
        let next = if end == StepEnd::Fused && self.fuses_next_drift() {
            let next = self.evaluate_and_drift((half, dt))?;
            StepClock::mark(&mut clock, Mark::Forced);
            Some(next)
        } else {
            let eval = self.evaluate_forces(dt, None);
            let s = &mut self.state;
            StepClock::mark(&mut clock, Mark::Forced);
            check_overlaps(s, &eval)?;
            s.contacts = eval.count;

            // Second half kick, unless the next step does it.
            if end == StepEnd::Kick {
                second_kick(&mut s.particles, half, self.uniform_free, s.time)?;
            }
            None
        };
        let s = &mut self.state;
        s.steps += 1;
        s.time = s.steps as f64 * dt;
        if let Some(times) = &mut self.phase_times {
            StepClock::finish(clock, times);
        }
        Ok(next)
    }

    /// Whether a contact may have formed that the lists, built with the skin s [m], do not
    /// hold, now that the bodies have moved from their places at the build (`reference`)
    /// and the walls by `wall_drift` [m]. Exact bounds, so a list kept is never short:
    ///
    /// - **Walls.** A wall candidate is any body closer than R_i + s (`build_lists`), so a
    ///   body–wall gap can have closed only if max |Δx| + wall drift > s. (This test used
    ///   s/2, the pairs' bound, until the twenty-sixth session.) Without walls it has nothing
    ///   to guard.
    /// - **Pairs.** A pair left out was farther apart than R_i + R_j + s, and its distance
    ///   has changed by at most |Δx_i − Δx_j| ≤ |Δx_i − u| + |Δx_j − u| for any vector u.
    ///   The usual test takes u = 0: 2 max |Δx| > s. Taking u at the centre of the box that
    ///   holds every Δx bounds it by the box's diagonal instead, which is smaller when the
    ///   bodies move the same way: in a hopper the fastest bodies all fall, and their fall
    ///   sets the usual test off at 0.6 of what the box allows (twenty-sixth session,
    ///   docs/performance.md). The box costs a pass over the bodies, so it is measured only
    ///   once the usual test has fired; the list is rebuilt when both exceed s.
    ///
    /// `max_disp2` is the largest squared displacement [m²], where the step's pass measured
    /// it. Where it did not, the bounds of [`ReachBound`] rule a build out, or else it is
    /// measured here. Either way the answer is the test's. Every measure taken without a
    /// build goes to the bounds.
    fn lists_may_miss(&mut self, max_disp2: Option<f64>) -> bool {
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

    /// Reports what a kick-and-drift pass found: a velocity made non-finite by the previous
    /// step's deferred kick, or a non-finite position.
    fn check_drift(&self, drift: Drift) -> Result<(), DemError> {
        let p = &self.state.particles;
        if !drift.kicked_finite {
            // The previous step's deferred kick: reported as `kick` would have.
            if let Some(e) = non_finite_velocity(p, self.state.time) {
                return Err(e);
            }
        }
        if !drift.finite {
            // The fast check flags a non-finite or absurdly distant (|Δx|² overflowing)
            // particle; only a truly non-finite one is an error.
            if let Some(k) = p.position.iter().position(|x| !x.is_finite()) {
                return Err(DemError::NonFinite {
                    tag: p.tag[k],
                    position: p.position[k],
                    quantity: "position",
                    time: self.state.time,
                });
            }
        }
        Ok(())
    }

    /// Whether a step that defers its second half kick also does the next step's kicks and
    /// drift, inside its evaluation ([`Simulation::evaluate_and_drift`]): on one thread, for
    /// the paper's laws, and for systems of more than [`FUSE_BODIES`] bodies.
    fn fuses_next_drift(&self) -> bool {
        self.pool.is_none()
            && self.state.particles.len() > FUSE_BODIES
            && self.state.config.laws == ContactLaws::default()
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
    fn evaluate_and_drift(&mut self, (half, dt): (f64, f64)) -> Result<Drift, DemError> {
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
    fn evaluate_forces(&mut self, dt: f64, bodies: Option<Range<usize>>) -> forces::Evaluation {
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
            uniform_body: self.uniform_body,
            dt,
        };
        let (pairs, walls, buffers) = (&mut s.pairs, &mut s.wall_pairs, &mut self.buffers);
        let eval = match bodies {
            None => forces::evaluate(&input, pairs, walls, buffers, self.pool.as_deref()),
            Some(bodies) => forces::evaluate_chunk(&input, pairs, walls, buffers, bodies),
        };
        std::mem::swap(&mut s.particles.force, &mut self.buffers.force);
        std::mem::swap(&mut s.particles.torque, &mut self.buffers.torque);
        eval
    }

    /// Takes `n` steps, each one's second half kick fused with the next one's first.
    ///
    /// Bit-identical to `n` calls of [`Simulation::step`]. If a step fails, every kick
    /// before the failing step was applied, as with `step`; a non-finite velocity is
    /// reported half a step later than `step` reports it, by the next step's pass.
    pub fn run(&mut self, n: u64) -> Result<(), DemError> {
        // `run_watched` with one stretch of n steps and a look that does nothing.
        self.run_watched(n, n, |_| Ok::<(), DemError>(()))
    }

    /// The simulation's thread pool, if it has one, for callers that alternate short
    /// [`Simulation::run`]s with work of their own (a run protocol measuring the outlet every
    /// few steps). Such a caller does better to run its whole loop inside the pool
    /// (`pool.install`): each `run` then starts on a pool thread at once, instead of handing
    /// its steps over to a sleeping one and waiting for them. Changes no result, only which
    /// thread does the work.
    pub fn pool_handle(&self) -> Option<Arc<rayon::ThreadPool>> {
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
    /// ten steps spent about 1 % of its time on those passes (thirtieth session). After
    /// the call, as after `run`, every kick is done.
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
    fn run_watched_here<E: From<DemError>>(
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
    fn watched_with(&self, pending: bool) -> Watched<'_> {
        let half = 0.5 * self.state.config.time_step;
        Watched::new(
            &self.state.particles,
            self.state.time,
            pending.then_some((half, self.uniform_free)),
        )
    }

    /// The second half kick that a watched step left pending, alone: what the last step of
    /// a `run` does.
    fn finish_kick(&mut self) -> Result<(), DemError> {
        let half = 0.5 * self.state.config.time_step;
        let s = &mut self.state;
        let kicked = second_kick(&mut s.particles, half, self.uniform_free, s.time);
        if let Err(e) = &kicked {
            self.failure = Some(Box::new(e.clone()));
        }
        kicked
    }

    /// The energy budget at the current positions and (full-step) velocities.
    pub fn energy(&self) -> Energy {
        let s = &self.state;
        let p = &s.particles;
        let mut e = Energy::default();
        for k in 0..p.len() {
            e.translational += 0.5 * p.mass[k] * p.velocity[k].length_squared();
            e.rotational += 0.5 * p.inertia[k] * p.omega[k].length_squared();
            e.gravitational -= p.mass[k] * s.config.gravity.dot(p.position[k]);
        }
        let n = s.materials.len();
        let coeffs = |a: u16, b: u16| match s
            .interactions
            .get(a as usize * n + b as usize)
            .copied()
            .flatten()
        {
            Some(i) => {
                PairCoefficients::new(&s.materials[a as usize], Some(&s.materials[b as usize]), &i)
                    .e_star
            }
            None => 0.0,
        };
        for k in 0..s.pairs.len() {
            let (i, j) = (s.pairs.i[k] as usize, s.pairs.j[k] as usize);
            let overlap = p.radius[i] + p.radius[j] - p.position[i].distance(p.position[j]);
            if overlap > 0.0 {
                e.elastic += hertz_energy(
                    coeffs(p.material[i], p.material[j]),
                    harmonic(p.radius[i], p.radius[j]),
                    overlap,
                );
            }
        }
        for k in 0..s.wall_pairs.particle.len() {
            let i = s.wall_pairs.particle[k] as usize;
            if let Some(w) = &s.walls[s.wall_pairs.wall[k] as usize] {
                let overlap = p.radius[i] - w.closest_point(p.position[i]).1;
                if overlap > 0.0 {
                    let c = PairCoefficients::with_wall(
                        &s.materials[p.material[i] as usize],
                        &w.material,
                        &w.interaction,
                    );
                    e.elastic += hertz_energy(c.e_star, p.radius[i], overlap);
                }
            }
        }
        e
    }
}

/// A step's second half kick ([`kick`], Δt/2 = `half` [s]), and the error for a velocity
/// it left non-finite at time `time` [s].
fn second_kick(
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

/// The error for the first particle with a non-finite velocity or spin, if any; `time` [s].
fn non_finite_velocity(p: &ParticleSet, time: f64) -> Option<DemError> {
    let k = (0..p.len()).find(|&k| !(p.velocity[k].is_finite() && p.omega[k].is_finite()))?;
    Some(DemError::NonFinite {
        tag: p.tag[k],
        position: p.position[k],
        quantity: "velocity",
        time,
    })
}

/// The radius [m] and mass [kg] every particle shares, if they all do.
fn uniform_body(p: &ParticleSet) -> Option<(f64, f64)> {
    let (&r, &m) = (p.radius.first()?, p.mass.first()?);
    (p.radius.iter().all(|&x| x == r) && p.mass.iter().all(|&x| x == m)).then_some((r, m))
}

fn check_interaction(i: &Interaction) -> Result<(), DemError> {
    let ok = i.friction >= 0.0
        && i.rolling_friction >= 0.0
        && i.restitution > 0.0
        && i.restitution <= 1.0
        && i.friction.is_finite()
        && i.rolling_friction.is_finite();
    if ok {
        Ok(())
    } else {
        Err(DemError::InvalidInput(format!(
            "friction ≥ 0, rolling friction ≥ 0 and restitution in (0, 1] required, got {i:?}"
        )))
    }
}

/// Bodies beyond which a one-thread step does the next step's kicks and drift inside its
/// evaluation, chunk by chunk ([`Simulation::fuses_next_drift`]). Below it (the paper's
/// hopper) every body's numbers stay in the caches between the evaluation and a separate
/// pass, and the chunks would only add their fixed costs. Above it the separate pass
/// streamed every body from memory again, at the memory's full rate; done inside the
/// evaluation, it overlaps the evaluation's waits on partner bodies (docs/performance.md,
/// twenty-fourth session).
const FUSE_BODIES: usize = 1 << 15;

/// What a kick-and-drift pass found ([`kick_drift`]).
#[derive(Debug, Clone, Copy)]
struct Drift {
    /// Largest squared displacement since the last list build [m²], where it was measured.
    max_disp2: Option<f64>,
    /// Every displacement was finite.
    finite: bool,
    /// The deferred kick left every velocity and spin finite.
    kicked_finite: bool,
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

/// The error for an overlap deeper than the configured limit, if `eval` found one.
fn check_overlaps(s: &SimulationState, eval: &forces::Evaluation) -> Result<(), DemError> {
    let limit = s.config.max_overlap_fraction;
    if eval.worst_pair.fraction > limit {
        let w = eval.worst_pair;
        let (i, j) = (s.pairs.i[w.index] as usize, s.pairs.j[w.index] as usize);
        return Err(overlap_error(
            &s.particles,
            i,
            format!("particle {}", s.particles.tag[j]),
            w,
            limit,
            s.time,
        ));
    }
    if eval.worst_wall.fraction > limit {
        let w = eval.worst_wall;
        let i = s.wall_pairs.particle[w.index] as usize;
        return Err(overlap_error(
            &s.particles,
            i,
            format!("wall {}", s.wall_pairs.wall[w.index]),
            w,
            limit,
            s.time,
        ));
    }
    Ok(())
}

fn overlap_error(
    p: &ParticleSet,
    i: usize,
    other: String,
    worst: WorstOverlap,
    limit: f64,
    time: f64,
) -> DemError {
    DemError::ExcessiveOverlap {
        tag: p.tag[i],
        other,
        position: p.position[i],
        fraction: worst.fraction,
        limit,
        time,
    }
}

/// How a step ends ([`Simulation::advance`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum StepEnd {
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
